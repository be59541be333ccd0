//! Studies: sweeps over adjustable parameters.

use stitchkin::eval::{CycleOptions, run_cycle, run_cycle_with};
use stitchkin::model::Model;
use stitchkin::study::sweep::{self, Design, Sweep, Vary};

fn opts(analogs: bool, lean: bool) -> CycleOptions {
    CycleOptions { step_deg: 2.0, rpm: None, analogs, points: None, lean }
}

#[test]
fn plain_and_dual_cycles_agree_and_lean_keeps_the_figures() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let dual = run_cycle(&m, &p, &opts(true, false)).unwrap();
    let plain = run_cycle(&m, &p, &opts(false, false)).unwrap();
    let lean = run_cycle(&m, &p, &opts(false, true)).unwrap();
    for c in &plain.columns {
        let d = dual.column(&c.name).unwrap_or_else(|| panic!("{} missing with analogs", c.name));
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
    assert_eq!(sweep::figures(&lean), sweep::figures(&plain));
    let st = lean.stitch.as_ref().unwrap();
    assert!(st.threads.iter().all(|t| t.mismatch.as_ref().unwrap().best_lag_deg.is_none()));
}

#[test]
fn p_prime_is_shared_only_when_the_stitch_does_not_change() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let takeup = Sweep::new(vec![Vary::parse(&m, "z=-10:10:5").unwrap(), Vary::parse(&m, "dphi=-20:20:3").unwrap()], Design::Grid).unwrap();
    let shared = sweep::shared_stitch(&m, &p, &takeup, 2.0).unwrap().expect("z and dphi leave the stitch alone");
    // The same rows with and without sharing.
    let names: Vec<String> = ["n1.score", "n2.rms_D_mm", "score.mean", "n3_A.max_P_mm"].map(String::from).to_vec();
    for i in 0..takeup.len() {
        let a = sweep::evaluate(&m, &p, &takeup, &names, &opts(false, true), Some(&shared), i);
        let b = sweep::evaluate(&m, &p, &takeup, &names, &opts(false, true), None, i);
        assert_eq!(a, b, "setting {i}");
        assert!(a.error.is_none() && a.figures.iter().all(Option::is_some), "{a:?}");
    }
    // m changes P' (and the needle crank radius r2 the needle's motion).
    for v in ["m=2:4:3", "r2=15.5:16.5:3"] {
        let s = Sweep::new(vec![Vary::parse(&m, v).unwrap()], Design::Grid).unwrap();
        assert!(sweep::shared_stitch(&m, &p, &s, 2.0).unwrap().is_none(), "{v}");
    }
    // Sharing with another grid is refused, not silently wrong.
    let other = run_cycle_with(&m, &p, &CycleOptions { step_deg: 1.0, ..opts(false, true) }, Some(&shared));
    assert!(other.unwrap_err().to_string().contains("another φ grid"));
}

#[test]
fn tuning_improves_the_match_within_the_ranges_and_is_repeatable() {
    use stitchkin::study::tune::{TuneOptions, default_adjustables, set_stitch_value, tune};
    let m = Model::preset("mf7923d").unwrap();
    let mut p = m.defaults();
    m.set(&mut p, "t1_phase", 180.0).unwrap();
    set_stitch_value(&m, &mut p, "m", 4.0).unwrap();
    assert_eq!(p.values[m.param_index("m").unwrap()], 4.0);
    // The technician's settings: not m, the stitch length, the needle crank r2
    // (it moves the needle, so P') or the reading switch t1_phase.
    let adjust = default_adjustables(&m, &p).unwrap();
    assert_eq!(adjust, ["r1", "l_o2b", "z", "dphi"]);
    let opts = TuneOptions { adjust: vec!["z".into(), "dphi".into()], samples: 0, seed: 5, step_deg: 2.0 };
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
    // Bad requests.
    let e = tune(&m, &p, &TuneOptions { adjust: vec!["t1_phase".into()], ..opts.clone() }).unwrap_err().to_string();
    assert!(e.contains("no adjustable range"), "{e}");
    let e = tune(&m, &p, &TuneOptions { adjust: vec!["zz".into()], ..opts.clone() }).unwrap_err().to_string();
    assert!(e.contains("no parameter `zz`"), "{e}");
    let n = Model::preset("needle876").unwrap();
    let e = tune(&n, &n.defaults(), &TuneOptions { adjust: vec!["alpha".into()], ..opts }).unwrap_err().to_string();
    assert!(e.contains("no [stitch]"), "{e}");
}
