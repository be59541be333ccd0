//! Sensitivity (exact derivatives by dual numbers, whole-range effects,
//! ranking) and calibration (`fit`).

use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::{Model, Params};
use stitchkin::study::figures::figures;
use stitchkin::study::fit::{Facts, FitOptions, fit};
use stitchkin::study::sensitivity::{
    Method, RankBy, SensitivityOptions, figure_derivatives, sensitivity, take_up_derivatives,
};

fn plain(m: &Model, p: &Params, step: f64) -> Vec<(String, f64)> {
    figures(
        &run_cycle(
            m,
            p,
            &CycleOptions {
                step_deg: step,
                rpm: None,
                analogs: false,
                points: None,
                lean: true,
            },
        )
        .unwrap(),
    )
}

/// The same with P' of the nominal setting (the figures compared with
/// exact derivatives do not involve it; this saves computing it).
fn plain_shared(
    m: &Model,
    p: &Params,
    step: f64,
    shared: Option<&stitchkin::eval::stitch_process::Prepared>,
) -> Vec<(String, f64)> {
    let opts = CycleOptions {
        step_deg: step,
        rpm: None,
        analogs: false,
        points: None,
        lean: true,
    };
    figures(&stitchkin::eval::run_cycle_with(m, p, &opts, shared).unwrap())
}

fn with(m: &Model, set: &[(&str, f64)]) -> Params {
    let mut p = m.defaults();
    for (k, v) in set {
        p.values[m.param_index(k).unwrap()] = *v;
    }
    p
}

/// Checks every exact derivative of `param` against a central difference
/// with step `h`: agreement to 1e-6 relative (1e-7 absolute near zero).
fn check_against_central(m: &Model, p: &Params, param: &str, h: f64, step: f64) -> usize {
    let i = m.param_index(param).unwrap();
    let exact = figure_derivatives(m, p, i, step).unwrap();
    let shared = stitchkin::eval::stitch_process::prepare(m, &m.defaults(), step).unwrap();
    let nominal = plain_shared(m, p, step, shared.as_ref());
    let (mut up, mut dn) = (p.clone(), p.clone());
    up.values[i] += h;
    dn.values[i] -= h;
    let (fu, fd) = (
        plain_shared(m, &up, step, shared.as_ref()),
        plain_shared(m, &dn, step, shared.as_ref()),
    );
    let get = |l: &[(String, f64)], n: &str| {
        l.iter()
            .find(|(k, _)| k == n)
            .unwrap_or_else(|| panic!("{n} missing"))
            .1
    };
    for (name, value, d) in &exact {
        // The dual cycle's values are the plain cycle's.
        assert!(
            (value - get(&nominal, name)).abs() < 1e-9,
            "{param}: {name} value {value} vs {}",
            get(&nominal, name)
        );
        let c = (get(&fu, name) - get(&fd, name)) / (2.0 * h);
        assert!(
            (d - c).abs() <= 1e-6 * d.abs().max(c.abs()) + 1e-7,
            "{}: d {name}/d {param}: exact {d} vs central {c}",
            m.name()
        );
    }
    exact.len()
}

#[test]
fn dual_derivatives_equal_central_differences() {
    let m = Model::preset("mf7923d").unwrap();
    // Off the symmetric nominal z = 0 and Δφ = 0, so no derivative is
    // trivially zero.
    let p = with(&m, &[("z", 3.0), ("dphi", 5.0), ("r1", 4.7)]);
    for param in ["r1", "l_o2b", "z", "r2", "dphi", "R"] {
        let n = check_against_central(&m, &p, param, 1e-5, 5.0);
        assert!(n >= 6 * 2 + 2, "{param}: only {n} exact figures");
    }
    // A planar mechanism, its adjustable angle and two figure-only
    // dimensions (the fit's Jacobian).
    let n876 = Model::preset("needle876").unwrap();
    let p = with(&n876, &[("alpha", 20.0)]);
    for param in ["alpha", "y_c", "l_cf", "l_ab"] {
        check_against_central(&n876, &p, param, 1e-5, 1.0);
    }
    // A spatial mechanism with measures.
    let a = Model::preset("altin504").unwrap();
    let params: Vec<String> = a
        .params()
        .iter()
        .filter(|p| !p.is_derived() && p.unit_str() == "mm")
        .map(|p| p.name.clone())
        .take(3)
        .collect();
    for param in &params {
        check_against_central(&a, &a.defaults(), param, 1e-5, 5.0);
    }
}

#[test]
fn take_up_derivatives_over_the_cycle_match_central_differences() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let i = m.param_index("r1").unwrap();
    let (phis, paths) = take_up_derivatives(&m, &p, i, 5.0).unwrap();
    assert_eq!(phis.len(), 72);
    assert_eq!(paths.len(), 6);
    let h = 1e-5;
    let (mut up, mut dn) = (p.clone(), p.clone());
    up.values[i] += h;
    dn.values[i] -= h;
    let opts = CycleOptions {
        step_deg: 5.0,
        analogs: false,
        ..Default::default()
    };
    let (tu, td, t0) = (
        run_cycle(&m, &up, &opts).unwrap(),
        run_cycle(&m, &dn, &opts).unwrap(),
        run_cycle(&m, &p, &opts).unwrap(),
    );
    for (name, pv, dp) in &paths {
        let col = format!("{name}.P_B_mm");
        let (a, b, c) = (
            tu.column(&col).unwrap(),
            td.column(&col).unwrap(),
            t0.column(&col).unwrap(),
        );
        for k in 0..phis.len() {
            assert!((pv[k] - c[k]).abs() < 1e-9);
            let central = (a[k] - b[k]) / (2.0 * h);
            assert!(
                (dp[k] - central).abs() <= 1e-6 * dp[k].abs().max(1.0),
                "{name} φ = {}: {} vs {central}",
                phis[k],
                dp[k]
            );
        }
        // P(φ0) = 0 whatever r1 is: dP/dr1 = 0 there; elsewhere a larger
        // eccentric swings the take-up lever further.
        assert_eq!(dp[0], 0.0);
        assert!(dp.iter().any(|d| d.abs() > 1.0));
    }
}

/// Seed 000 Fig. 7's parameters at the default reading (T1 up at the
/// needle's TDC, P past B), against the independent reference
/// (tests/data/mf7923d/reference_sensitivity.csv): r1 4 → 6 mm lowers max P_B
/// of contour A by 17.2, 14.0 and 11.0 mm for needles 1–3 (seed 000 states a
/// rise of about 10 mm for +2 mm: docs/published-facts.md); O2B 20 → 23 mm
/// raises it; z and Δφ raise it toward both ends of their ranges.
#[test]
fn mf7923d_sensitivity_agrees_with_the_reference() {
    let m = Model::preset("mf7923d").unwrap();
    let opts = SensitivityOptions {
        params: vec![],
        figures: vec!["*.max_P_B_mm".into()],
        step_deg: 1.0,
        rank: RankBy::Local,
    };
    let r = sensitivity(&m, &m.defaults(), &opts).unwrap();
    assert_eq!(r.figures.len(), 6);
    let by = |fig: &str, param: &str| {
        let f = r.figures.iter().find(|f| f.figure == fig).unwrap();
        f.effects.iter().find(|e| e.param == param).unwrap().clone()
    };
    for (j, d_r1, d_o2b, z_to_end) in [
        (1, -17.1817, 5.0255, 1.7152),
        (2, -13.9976, 5.4597, 2.4040),
        (3, -10.9633, 5.8352, 3.0555),
    ] {
        let fig = format!("n{j}_A.max_P_B_mm");
        let f = r.figures.iter().find(|f| f.figure == fig).unwrap();
        assert!(f.exact && f.ranked_by == "effect");
        // r1 first: the largest effect, negative, exact.
        let e = &f.effects[0];
        assert_eq!((e.param.as_str(), e.rank, e.method), ("r1", 1, Method::Exact));
        assert!(e.derivative.unwrap() < -8.0 && e.effect.unwrap() < 0.0, "{e:?}");
        // The whole-range change of the reference (its 0.1° grid against
        // this 1° grid: 1e-3 mm).
        assert!((e.whole_range.unwrap() - d_r1).abs() < 1e-3, "{fig}: {e:?}");
        let o = by(&fig, "l_o2b");
        assert!(
            o.derivative.unwrap() > 0.0 && (o.whole_range.unwrap() - d_o2b).abs() < 1e-3,
            "{o:?}"
        );
        // z: symmetric about z = 0 (P with +z at φ is P with −z at −φ), so
        // flat there, rising toward both ends.
        let z = by(&fig, "z");
        assert_eq!(z.derivative, Some(0.0));
        assert!((z.at_lo.unwrap() - z.at_hi.unwrap()).abs() < 1e-6);
        assert!((z.span.unwrap() - z_to_end).abs() < 2e-3, "{z:?}");
        // m and the stitch length move P' only, the thread's settings its
        // tension.
        for p in ["m", "ea", "breaking", "regulator", "clamp"] {
            assert_eq!(by(&fig, p).span, Some(0.0), "{p}");
        }
    }
    // Ranks follow |effect|, ties broken by the span.
    for f in &r.figures {
        let keys: Vec<(f64, f64)> = f
            .effects
            .iter()
            .map(|e| (e.effect.unwrap().abs(), e.span.unwrap()))
            .collect();
        assert!(keys.windows(2).all(|w| w[0] >= w[1]), "{}: {keys:?}", f.figure);
        // Twelve settings of the mechanism, the guides G3 and the stitch,
        // and four of the thread (EA, breaking force, the regulator's and
        // the clamp's holds), which move the tension only.
        assert_eq!(
            f.effects.iter().map(|e| e.rank).collect::<Vec<_>>(),
            (1..=16).collect::<Vec<_>>()
        );
        // The eccentric, the ball arm, then the take-up arm's eyelets R
        // (seed 000 section 4.2).
        let order: Vec<&str> = f.effects.iter().take(3).map(|e| e.param.as_str()).collect();
        assert_eq!(order, ["r1", "l_o2b", "R"], "{}", f.figure);
        // Each guide G3 moves its own needle's thread only.
        let j = &f.figure[1..2];
        for other in ["1", "2", "3"].iter().filter(|&&k| k != j) {
            assert_eq!(by(&f.figure, &format!("g3_{other}")).span, Some(0.0), "{}", f.figure);
        }
        assert!(by(&f.figure, &format!("g3_{j}")).span.unwrap() > 1.0, "{}", f.figure);
    }
    // Ranked by span instead, Δφ (5.1 mm) comes before O2B (5.0 mm) on
    // needle 1's contour A.
    let r = sensitivity(
        &m,
        &m.defaults(),
        &SensitivityOptions {
            rank: RankBy::Range,
            figures: vec!["n1_A.max_P_B_mm".into()],
            ..opts
        },
    )
    .unwrap();
    let order: Vec<&str> = r.figures[0].effects.iter().take(5).map(|e| e.param.as_str()).collect();
    assert_eq!(order, ["r1", "dphi", "l_o2b", "R", "psi"]);
    assert_eq!(r.figures[0].ranked_by, "span");
}

#[test]
fn match_scores_take_central_differences_and_rank_by_span() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let opts = SensitivityOptions {
        params: vec!["r1".into(), "z".into()],
        figures: vec!["n1.score".into(), "mu.*".into()],
        step_deg: 3.0,
        rank: RankBy::Local,
    };
    let r = sensitivity(&m, &p, &opts).unwrap();
    let score = r.figures.iter().find(|f| f.figure == "n1.score").unwrap();
    assert!(!score.exact && score.ranked_by == "span" && score.unit == "pts");
    assert!(
        score
            .effects
            .iter()
            .all(|e| e.method == Method::Central && e.derivative.is_some())
    );
    assert_eq!(score.effects[0].param, "r1");
    // The transmission angles are exact; mu.ok is not smooth, so it is not.
    assert!(
        r.figures
            .iter()
            .find(|f| f.figure == "mu.min_deg")
            .is_none_or(|f| f.exact)
    );
    assert!(
        r.figures
            .iter()
            .chain(r.insensitive.iter().map(|_| &r.figures[0]))
            .all(|f| f.figure != "mu.ok" || !f.exact)
    );
    assert_eq!(r.cycles, 1 + 2 * (2 + stitchkin::study::sensitivity::RANGE_SAMPLES + 1));
}

#[test]
fn sensitivity_rejects_bad_requests_with_the_fix() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let run = |params: &[&str], figures: &[&str], step: f64| {
        let opts = SensitivityOptions {
            params: params.iter().map(|s| s.to_string()).collect(),
            figures: figures.iter().map(|s| s.to_string()).collect(),
            step_deg: step,
            rank: RankBy::Local,
        };
        text(sensitivity(&m, &p, &opts).unwrap_err())
    };
    let e = run(&["t1_phase"], &[], 5.0);
    assert!(
        e.contains("`t1_phase` has no adjustable range") && e.contains("r1, l_o2b"),
        "{e}"
    );
    let e = run(&["rr1"], &[], 5.0);
    assert!(e.contains("no parameter `rr1`"), "{e}");
    let e = run(&["r1", "r1"], &[], 5.0);
    assert!(e.contains("named twice"), "{e}");
    let e = run(&["r1"], &["nope"], 5.0);
    assert!(e.contains("no figure of merit matches `nope`"), "{e}");
    let e = run(&["r1"], &[], 0.0);
    assert!(e.contains("step"), "{e}");
    let plain = Model::from_toml_str("[model]\nname = \"x\"\n[points]\nO = [0, 0]\n[[drivers]]\ntype = \"crank\"\ncenter = \"O\"\nout = \"A\"\nradius = 5\n", "x.toml").unwrap();
    let e = sensitivity(
        &plain,
        &plain.defaults(),
        &SensitivityOptions {
            params: vec![],
            figures: vec![],
            step_deg: 5.0,
            rank: RankBy::Local,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no parameter with an adjustable range"), "{e}");
}

/// An error's message with its help.
fn text(e: stitchkin::Error) -> String {
    match e {
        stitchkin::Error::Param(p) => format!("{p}\n  help: {}", p.help.clone().unwrap_or_default()),
        e => e.to_string(),
    }
}

fn needle_facts() -> Facts {
    Facts::from_path(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/facts/needle876.toml"))
        .unwrap()
}

/// examples/facts/needle876.toml: seed 002's strokes and the fixed lowest
/// position re-derive the reconstructed y_C = 175 mm (from φ0 in the
/// preset's header) and the published l_CF = 37.945 mm (Fig. 1) from
/// perturbed starts, each to 0.01 mm.
#[test]
fn fit_recovers_needle876_dimensions_from_perturbed_starts() {
    let m = Model::preset("needle876").unwrap();
    let facts = needle_facts();
    assert_eq!(facts.facts.len(), 3);
    assert_eq!(facts.adjust, ["y_c=160:190"]);
    for (name, start, want, bounds) in [
        ("y_c", 170.0, 175.0, "y_c=160:190"),
        ("y_c", 182.0, 175.0, "y_c=160:190"),
        ("l_cf", 41.0, 37.945, "l_cf=30:45"),
        ("l_cf", 34.0, 37.945, "l_cf=30:45"),
    ] {
        let p = with(&m, &[(name, start)]);
        let r = fit(
            &m,
            &p,
            &facts,
            &FitOptions {
                adjust: vec![bounds.into()],
                ..Default::default()
            },
        )
        .unwrap();
        let f = &r.params[0];
        assert!(r.converged, "{r:?}");
        assert_eq!((f.name.as_str(), f.start), (name, start));
        assert!((f.fitted - want).abs() < 0.01, "{name} from {start}: {}", f.fitted);
        let se = f.std_error.unwrap();
        assert!(se < 0.05 && (f.fitted - want).abs() < se, "{name}: ± {se}");
        assert!(!f.at_bound);
        // Residuals per fact: the preset's strokes 18.08 and 22.77 mm against
        // the stated 18 and ≈ 23 mm; the lowest position fixed to 0.1 µm.
        let res: Vec<f64> = r.facts.iter().map(|f| f.residual).collect();
        assert!(
            (res[0] - 0.077).abs() < 0.005 && (res[1] + 0.232).abs() < 0.005 && res[2].abs() < 1e-3,
            "{res:?}"
        );
        assert!(
            r.facts
                .iter()
                .all(|f| (f.weighted - f.residual / f.tolerance.unwrap()).abs() < 1e-12)
        );
        assert!(r.cost < 0.32 && r.cost_start > 1000.0, "{} → {}", r.cost_start, r.cost);
        assert!((r.cost - r.facts.iter().map(|f| f.weighted * f.weighted).sum::<f64>()).abs() < 1e-12);
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    }
    // The file's own `adjust` is the default.
    let r = fit(&m, &with(&m, &[("y_c", 170.0)]), &facts, &FitOptions::default()).unwrap();
    assert_eq!(r.params[0].name, "y_c");
    // Both together: the facts hardly tell them apart (standard errors of
    // tenths of a mm), though the optimum is near the preset.
    let r = fit(
        &m,
        &with(&m, &[("y_c", 170.0), ("l_cf", 40.0)]),
        &facts,
        &FitOptions {
            adjust: vec!["y_c=160:190".into(), "l_cf=30:45".into()],
            ..Default::default()
        },
    )
    .unwrap();
    assert!(r.params.iter().all(|p| p.std_error.unwrap() > 0.1), "{:?}", r.params);
}

/// Facts computed from the model at a known setting are met exactly: the
/// fit returns to that setting from a perturbed start.
#[test]
fn fit_recovers_a_known_setting_exactly() {
    let m = Model::preset("needle876").unwrap();
    let truth = with(&m, &[("l_ab", 176.5), ("b", 19.0)]);
    let at = |alpha: f64, fig: &str| {
        let mut p = truth.clone();
        p.values[m.param_index("alpha").unwrap()] = alpha;
        plain(&m, &p, 1.0).into_iter().find(|(n, _)| n == fig).unwrap().1
    };
    let text = format!(
        "[[fact]]\nfigure = \"needle_y.range_mm\"\nvalue = {}\nset = {{ alpha = 10 }}\ntolerance = 0.01\n\
         [[fact]]\nfigure = \"needle_y.max_mm\"\nvalue = {}\nset = {{ alpha = 30 }}\nweight = 100\n\
         [[fact]]\nfigure = \"mu_45.min_deg\"\nvalue = {}\nset = {{ alpha = 30 }}\ntolerance = 0.1\n",
        at(10.0, "needle_y.range_mm"),
        at(30.0, "needle_y.max_mm"),
        at(30.0, "mu_45.min_deg"),
    );
    let facts = Facts::from_toml_str(&text, "known.toml").unwrap();
    let start = with(&m, &[("l_ab", 172.0), ("b", 21.5)]);
    let r = fit(
        &m,
        &start,
        &facts,
        &FitOptions {
            adjust: vec!["l_ab=165:185".into(), "b=15:25".into()],
            ..Default::default()
        },
    )
    .unwrap();
    assert!(r.converged && r.cost < 1e-12, "{r:?}");
    assert!(
        (r.params[0].fitted - 176.5).abs() < 1e-5 && (r.params[1].fitted - 19.0).abs() < 1e-5,
        "{:?}",
        r.params
    );
    assert!(r.facts.iter().all(|f| f.residual.abs() < 1e-6));
    assert!(r.iterations < 20, "{}", r.iterations);
}

#[test]
fn facts_files_and_fit_requests_are_checked_with_the_fix() {
    let m = Model::preset("needle876").unwrap();
    let p = m.defaults();
    let parse = |t: &str| Facts::from_toml_str(t, "f.toml").unwrap_err().to_string();
    let e = parse("[[fact]]\nfigure = \"needle_y.range_mm\"\n");
    assert!(e.contains("f.toml:1:") && e.contains("missing field `value`"), "{e}");
    let e = parse("[[fact]]\nfigure = \"needle_y.range_mm\"\nvalue = 18\ntolerance = 0.1\nweight = 2\n");
    assert!(e.contains("f.toml:4:") && e.contains("not both"), "{e}");
    let e = parse("[[fact]]\nfigure = \"needle_y.range_mm\"\nvalue = 18\ntolerance = -1\n");
    assert!(e.contains("tolerance must be positive"), "{e}");
    let e = parse("[[fact]]\nfigure = \"x\"\nvalue = 1\nweigth = 2\n");
    assert!(e.contains("weigth"), "{e}");
    let e = parse("title = \"nothing\"\n");
    assert!(e.contains("states no fact"), "{e}");
    let good = |extra: &str| {
        Facts::from_toml_str(
            &format!("[[fact]]\nfigure = \"needle_y.range_mm\"\nvalue = 18\n{extra}"),
            "f.toml",
        )
        .unwrap()
    };
    let run = |facts: &Facts, adjust: &[&str]| {
        text(
            fit(
                &m,
                &p,
                facts,
                &FitOptions {
                    adjust: adjust.iter().map(|s| s.to_string()).collect(),
                    ..Default::default()
                },
            )
            .unwrap_err(),
        )
    };
    let e = run(&good(""), &[]);
    assert!(e.contains("nothing to fit") && e.contains("y_c"), "{e}");
    let e = run(&good(""), &["y_c"]);
    assert!(
        e.contains("no adjustable range") && e.contains("y_c=LO:HI") && e.contains("(in `adjust`)"),
        "{e}"
    );
    let e = run(&good(""), &["alpha=0:90"]);
    assert!(e.contains("leave its adjustable range"), "{e}");
    let e = run(&good(""), &["y_c=180:190"]);
    assert!(e.contains("start y_c = 175 mm lies outside"), "{e}");
    let e = run(&good("set = { alpha = 10 }\n"), &["alpha"]);
    assert!(
        e.contains("f.toml:4:") && e.contains("sets `alpha`, which is being fitted"),
        "{e}"
    );
    let e = run(&good("set = { alpha = 99 }\n"), &["y_c=160:190"]);
    assert!(e.contains("outside its adjustable range"), "{e}");
    let bad_fig = Facts::from_toml_str("[[fact]]\nfigure = \"needle_y.rnage_mm\"\nvalue = 18\n", "f.toml").unwrap();
    let e = run(&bad_fig, &["y_c=160:190"]);
    assert!(
        e.contains("f.toml:2:") && e.contains("did you mean `needle_y.range_mm`"),
        "{e}"
    );
    // One fact for two parameters: reported, not hidden.
    let r = fit(
        &m,
        &p,
        &good("tolerance = 0.1\n"),
        &FitOptions {
            adjust: vec!["y_c=160:190".into(), "l_cf=30:45".into()],
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        r.warnings.iter().any(|w| w.contains("underdetermined")),
        "{:?}",
        r.warnings
    );
    assert!(r.params.iter().all(|p| p.std_error.is_none()));
    assert!(r.facts[0].residual.abs() < 0.1);
}

/// The elongation allowance ΔP enters P as a plain number (the dual numbers
/// do not carry it): the check against the central difference catches the
/// zero slope and reports dP/dΔP = 1 from the central difference instead.
#[test]
fn values_the_dual_numbers_do_not_carry_fall_back_to_central_differences() {
    let text = stitchkin::presets::find("takeup-lever").unwrap().toml;
    let old = r#"dP     = { value = 6,   unit = "mm","#;
    assert!(text.contains(old));
    let m = Model::from_toml_str(
        &text.replace(old, r#"dP = { value = 6, unit = "mm", range = [4, 8],"#),
        "lever.toml",
    )
    .unwrap();
    let i = m.param_index("dP").unwrap();
    let exact = figure_derivatives(&m, &m.defaults(), i, 5.0).unwrap();
    assert!(exact.iter().filter(|e| e.0.ends_with(".max_P_mm")).all(|e| e.2 == 0.0));
    let opts = SensitivityOptions {
        params: vec!["dP".into()],
        figures: vec!["*.max_P_mm".into()],
        step_deg: 5.0,
        rank: RankBy::Local,
    };
    let r = sensitivity(&m, &m.defaults(), &opts).unwrap();
    let e = &r.figures[0].effects[0];
    assert_eq!(e.method, Method::Central);
    assert!(
        (e.derivative.unwrap() - 1.0).abs() < 1e-6 && (e.whole_range.unwrap() - 4.0).abs() < 1e-9,
        "{e:?}"
    );
    assert!(
        e.note
            .as_deref()
            .unwrap_or("")
            .contains("disagrees with the central difference"),
        "{e:?}"
    );
}
