//! Studies: sweeps over adjustable parameters.

use stitchkin::eval::{CycleOptions, run_cycle, run_cycle_with};
use stitchkin::model::Model;
use stitchkin::study::design::{Design, Sweep, Vary};
use stitchkin::study::{figures, sweep};

fn opts(analogs: bool, lean: bool) -> CycleOptions {
    CycleOptions {
        step_deg: 2.0,
        rpm: None,
        analogs,
        points: None,
        lean,
    }
}

#[test]
fn plain_and_dual_cycles_agree_and_lean_keeps_the_figures() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let dual = run_cycle(&m, &p, &opts(true, false)).unwrap();
    let plain = run_cycle(&m, &p, &opts(false, false)).unwrap();
    let lean = run_cycle(&m, &p, &opts(false, true)).unwrap();
    for c in &plain.columns {
        let d = dual
            .column(&c.name)
            .unwrap_or_else(|| panic!("{} missing with analogs", c.name));
        let worst = c.values.iter().zip(d).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-9, "{}: f64 and dual differ by {worst}", c.name);
    }
    assert_eq!(plain.paths.len(), dual.paths.len());
    for (a, b) in plain.paths.iter().zip(&dual.paths) {
        assert_eq!(a.engaged, b.engaged);
        assert!((a.max_p_mm - b.max_p_mm).abs() < 1e-9);
    }
    // Lean drops the wrap and tension columns and the best lag, nothing else.
    assert!(lean.columns.len() < plain.columns.len());
    assert!(lean.column("n1_A.G4_1_wrap_deg").is_none() && plain.column("n1_A.G4_1_wrap_deg").is_some());
    assert_eq!(figures::figures(&lean), figures::figures(&plain));
    let st = lean.stitch.as_ref().unwrap();
    assert!(
        st.threads
            .iter()
            .all(|t| t.mismatch.as_ref().unwrap().best_lag_deg.is_none())
    );
}

#[test]
fn p_prime_is_shared_only_when_the_stitch_does_not_change() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let takeup = Sweep::new(
        vec![
            Vary::parse(&m, "z=-10:10:5").unwrap(),
            Vary::parse(&m, "dphi=-20:20:3").unwrap(),
        ],
        Design::Grid,
    )
    .unwrap();
    let shared = figures::shared_stitch(&m, &p, &takeup, 2.0)
        .unwrap()
        .expect("z and dphi leave the stitch alone");
    // The same rows with and without sharing.
    let names: Vec<String> = [
        "n1.score",
        "n2.rms_D_mm",
        "score.mean",
        "n3_A.max_P_B_mm",
        "checks.ok",
        "n2.bound_margin_mm",
    ]
    .map(String::from)
    .to_vec();
    for i in 0..takeup.len() {
        let a = sweep::evaluate(&m, &p, &takeup, &names, &opts(false, true), Some(&shared), i);
        let b = sweep::evaluate(&m, &p, &takeup, &names, &opts(false, true), None, i);
        assert_eq!(a, b, "setting {i}");
        assert!(a.error.is_none() && a.figures.iter().all(Option::is_some), "{a:?}");
    }
    // m changes P' (and the needle crank radius r2 the needle's motion).
    for v in ["m=2:4:3", "r2=15.5:16.5:3"] {
        let s = Sweep::new(vec![Vary::parse(&m, v).unwrap()], Design::Grid).unwrap();
        assert!(figures::shared_stitch(&m, &p, &s, 2.0).unwrap().is_none(), "{v}");
    }
    // Sharing with another grid is refused, not silently wrong.
    let other = run_cycle_with(
        &m,
        &p,
        &CycleOptions {
            step_deg: 1.0,
            ..opts(false, true)
        },
        Some(&shared),
    );
    assert!(other.unwrap_err().to_string().contains("another φ grid"));
}

#[test]
fn tuning_improves_the_match_within_the_ranges_and_is_repeatable() {
    use stitchkin::study::tune::{TuneOptions, set_stitch_value, tune};
    let m = Model::preset("mf7923d").unwrap();
    let mut p = m.defaults();
    m.set(&mut p, "t1_phase", 180.0).unwrap();
    set_stitch_value(&m, &mut p, "m", 4.0).unwrap();
    assert_eq!(p.values[m.param_index("m").unwrap()], 4.0);
    // The machine settings (seed 000 Table 3 and section 4.2), in file order:
    // not m, the stitch length, the thread, the reading switch t1_phase or
    // the thread's tension settings (the regulator and the clamp are tuned
    // when named).
    let adjust = m.default_adjustables(&p).unwrap();
    assert_eq!(
        adjust,
        ["r1", "l_o2b", "z", "r2", "R", "psi", "dphi", "g3_1", "g3_2", "g3_3"]
    );
    let opts = TuneOptions {
        objective: Default::default(),
        adjust: vec!["z".into(), "dphi".into()],
        samples: 0,
        seed: 5,
        step_deg: 2.0,
    };
    let r = tune(&m, &p, &opts).unwrap();
    assert!(r.after_figures.objective < r.before_figures.objective - 0.01, "{r:?}");
    assert!(r.after_figures.score_mean > r.before_figures.score_mean + 1.0);
    assert!(r.after_figures.feasible);
    assert!((-10.0..=10.0).contains(&r.after[0]) && (-20.0..=20.0).contains(&r.after[1]));
    for f in &r.flatness {
        let x = r.after[r.names.iter().position(|n| n.0 == f.name).unwrap()];
        assert!(f.lo <= x && x <= f.hi, "{f:?}");
    }
    // The same seed, the same answer.
    assert_eq!(tune(&m, &p, &opts).unwrap(), r);
    // Bad requests: a reading of the paper is no setting, and once fixed
    // dimensions are allowed, it still has no range to tune in.
    let reading = TuneOptions {
        objective: Default::default(),
        adjust: vec!["t1_phase".into()],
        ..opts.clone()
    };
    let e = tune(&m, &p, &reading).unwrap_err().to_string();
    assert!(e.contains("`t1_phase`") && e.contains("is a fixed dimension"), "{e}");
    let mut design = m.clone();
    design.allow_adjusting(stitchkin::model::ParamKind::Dimension);
    let e = tune(&design, &p, &reading).unwrap_err().to_string();
    assert!(e.contains("no adjustable range"), "{e}");
    let e = tune(
        &m,
        &p,
        &TuneOptions {
            objective: Default::default(),
            adjust: vec!["zz".into()],
            ..opts.clone()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no parameter `zz`"), "{e}");
    let n = Model::preset("needle876").unwrap();
    let e = tune(
        &n,
        &n.defaults(),
        &TuneOptions {
            objective: Default::default(),
            adjust: vec!["alpha".into()],
            ..opts
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no [stitch]"), "{e}");
}

/// The sweep's fast path (`sweep::Evaluator`: no cycle table, buffers kept
/// between settings) gives exactly the rows of the full cycle, for every
/// figure a preset offers, over settings across each ranged parameter,
/// including settings without assembly.
#[test]
fn the_fast_figures_are_the_cycle_tables() {
    use stitchkin::study::sweep::{Evaluator, SweepJob};
    let (mut fast_presets, mut failing) = (0, 0);
    for preset in stitchkin::presets::ALL {
        let m = Model::preset(preset.name).unwrap();
        let p = m.defaults();
        let o = opts(false, true);
        let nominal = run_cycle(&m, &p, &o).unwrap();
        let names: Vec<String> = figures::figures(&nominal).into_iter().map(|(n, _)| n).collect();
        // Every ranged parameter in turn, the last ones together.
        let ranged: Vec<&str> = m
            .params()
            .iter()
            .filter(|q| q.range.is_some_and(|[a, b]| a < b) && !q.is_derived())
            .map(|q| q.name.as_str())
            .collect();
        for name in ranged.iter().take(3) {
            let [lo, hi] = m.params()[m.param_index(name).unwrap()].range.unwrap();
            let sw = Sweep::new(
                vec![Vary::parse(&m, &format!("{name}={lo}:{hi}:6")).unwrap()],
                Design::Grid,
            )
            .unwrap();
            let shared = figures::shared_stitch(&m, &p, &sw, o.step_deg).unwrap();
            let mut ev = Evaluator::new(SweepJob {
                model: &m,
                base: &p,
                sweep: &sw,
                names: &names,
                opts: &o,
                shared: shared.as_ref(),
            });
            fast_presets += usize::from(ev.is_fast());
            for i in 0..sw.len() {
                let full = sweep::evaluate(&m, &p, &sw, &names, &o, shared.as_ref(), i);
                failing += usize::from(full.error.is_some());
                assert_eq!(ev.evaluate(i), full, "{} {name} setting {i}", preset.name);
            }
            // Again in reverse: nothing carries over from one setting to the next.
            for i in (0..sw.len()).rev() {
                assert_eq!(
                    ev.evaluate(i),
                    sweep::evaluate(&m, &p, &sw, &names, &o, shared.as_ref(), i),
                    "{} {name} setting {i} again",
                    preset.name
                );
            }
        }
    }
    // A four-bar whose longer cranks do not assemble: the same errors.
    let m = Model::from_toml_str(include_str!("../data/four-bar.toml"), "four-bar.toml").unwrap();
    let mut p = m.defaults();
    m.set(&mut p, "c", 26.0).unwrap();
    let o = opts(false, true);
    let names: Vec<String> = figures::figures(&run_cycle(&m, &p, &o).unwrap())
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    let sw = Sweep::new(vec![Vary::parse(&m, "r=10:20:11").unwrap()], Design::Grid).unwrap();
    let mut ev = Evaluator::new(SweepJob {
        model: &m,
        base: &p,
        sweep: &sw,
        names: &names,
        opts: &o,
        shared: None,
    });
    assert!(ev.is_fast());
    for i in 0..sw.len() {
        let full = sweep::evaluate(&m, &p, &sw, &names, &o, None, i);
        failing += usize::from(full.error.is_some());
        assert_eq!(ev.evaluate(i), full, "four-bar setting {i}");
    }
    // Sweeps that change the stitch (P′ prepared each setting): the same rows.
    for (preset, vary) in [("mf7923d", "m=1:5:4"), ("lockstitch", "catch_rise=1.8:2.8:4")] {
        let m = Model::preset(preset).unwrap();
        let p = m.defaults();
        let o = opts(false, true);
        let names: Vec<String> = figures::figures(&run_cycle(&m, &p, &o).unwrap())
            .into_iter()
            .map(|(n, _)| n)
            .collect();
        let sw = Sweep::new(vec![Vary::parse(&m, vary).unwrap()], Design::Grid).unwrap();
        assert!(figures::shared_stitch(&m, &p, &sw, o.step_deg).unwrap().is_none());
        let mut ev = Evaluator::new(SweepJob {
            model: &m,
            base: &p,
            sweep: &sw,
            names: &names,
            opts: &o,
            shared: None,
        });
        assert!(ev.is_fast(), "{preset} {vary}");
        for i in (0..sw.len()).chain((0..sw.len()).rev()) {
            assert_eq!(
                ev.evaluate(i),
                sweep::evaluate(&m, &p, &sw, &names, &o, None, i),
                "{preset} {vary} setting {i}"
            );
        }
    }
    assert!(fast_presets >= 6, "the fast path served only {fast_presets} sweeps");
    assert!(failing >= 3, "only {failing} settings without assembly were compared");
}

/// With the regulator's window assumed, a sweep of the kinematic match
/// alone reads nothing of the thread's tension, so the fast path does not
/// solve it, and its rows are still the full cycle's; asked for a check or
/// a tension figure it solves it.
#[test]
fn the_fast_match_with_the_window_assumed_gives_the_cycles_rows() {
    use stitchkin::study::sweep::{Evaluator, SweepJob};
    let text = stitchkin::presets::find("mf7923d").unwrap().toml.replacen(
        "[stitch]\n",
        "[stitch]\nregulator = { width_deg = 60 }\n",
        1,
    );
    let m = Model::from_toml_str(&text, "mf7923d-window60.toml").unwrap();
    let p = m.defaults();
    let o = opts(false, true);
    let sw = Sweep::new(vec![Vary::parse(&m, "z=-10:10:4").unwrap()], Design::Grid).unwrap();
    let shared = figures::shared_stitch(&m, &p, &sw, o.step_deg).unwrap();
    // Subsets read only some paths and some checks: the others are not
    // computed, and the rows are still the full cycle's.
    for figs in [
        &["score.mean", "n1.rms_D_mm"][..],
        &["score.mean", "checks.ok", "n3.max_T_N"][..],
        &["n2_B.max_P_B_mm", "n1.bound_margin_mm"][..],
        &["n3.checks_ok", "n1_A.min_P_B_mm"][..],
    ] {
        let names: Vec<String> = figs.iter().map(|s| s.to_string()).collect();
        let mut ev = Evaluator::new(SweepJob {
            model: &m,
            base: &p,
            sweep: &sw,
            names: &names,
            opts: &o,
            shared: shared.as_ref(),
        });
        assert!(ev.is_fast(), "{figs:?}");
        for i in 0..sw.len() {
            let row = ev.evaluate(i);
            assert_eq!(
                row,
                sweep::evaluate(&m, &p, &sw, &names, &o, shared.as_ref(), i),
                "{figs:?} setting {i}"
            );
            assert!(
                row.error.is_none() && row.figures.iter().all(|v| v.is_some_and(f64::is_finite)),
                "{row:?}"
            );
        }
    }
}
