//! A measured take-up curve set beside the model (study::measured), the
//! regulator's declarations, and where a tuning says it stands.

use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::model::Model;
use stitchkin::study::measured::measured_match;
use stitchkin::study::tune::{TuneOptions, tune};
use stitchkin::thread::measured::{CurveKind, parse_curve_csv};

fn mf7923d(step: f64) -> (Model, CycleTable) {
    let m = Model::preset("mf7923d").unwrap();
    let t = run_cycle(
        &m,
        &m.defaults(),
        &CycleOptions {
            step_deg: step,
            rpm: None,
            analogs: false,
            points: Some(Vec::new()),
            lean: false,
        },
    )
    .unwrap();
    (m, t)
}

/// A CSV of one column of the cycle, every `every`-th row, under `header`.
fn csv_of(t: &CycleTable, column: &str, header: &str, every: usize) -> String {
    let (phi, v) = (t.column("phi_deg").unwrap(), t.column(column).unwrap());
    let mut s = format!("phi_deg,{header}\n");
    for k in (0..phi.len()).step_by(every) {
        s += &format!("{},{}\n", phi[k], v[k]);
    }
    s
}

#[test]
fn a_measured_take_up_equal_to_the_model_matches_it_exactly() {
    let (_, t) = mf7923d(2.0);
    // "Measured" P of needle 2 at B, every 2°: the model's own.
    let curve = parse_curve_csv(&csv_of(&t, "n2_A.P_B_mm", "n2.P_B_mm", 1), "n2.csv").unwrap();
    let m = measured_match(&t, &curve, None).unwrap();
    assert_eq!(
        (m.thread.as_str(), m.kind, m.split, m.split_declared),
        ("n2", CurveKind::TakeUp, stitchkin::thread::SplitPoint::B, true)
    );
    let model = m.against_model.as_ref().unwrap();
    assert!(model.rms_d_mm < 1e-12 && model.max_abs_d_mm < 1e-12, "{model:?}");
    // Against P′ it is the model's own match.
    let own = t
        .stitch
        .as_ref()
        .unwrap()
        .threads
        .iter()
        .find(|x| x.thread == "n2")
        .unwrap()
        .mismatch
        .clone()
        .unwrap();
    let other = m.against_other.as_ref().unwrap();
    assert!(
        (other.rms_d_mm - own.rms_d_mm).abs() < 1e-12 && other.score == own.score,
        "{other:?} vs {own:?}"
    );
    // Sampled every 6° and interpolated back, it stays within a few
    // hundredths of a mm of the model where P is smooth.
    let coarse = parse_curve_csv(&csv_of(&t, "n2_A.P_B_mm", "P_B_mm", 3), "coarse.csv").unwrap();
    let m = measured_match(&t, &coarse, Some("n2")).unwrap();
    assert!(
        m.against_model.as_ref().unwrap().rms_d_mm < 0.1,
        "{:?}",
        m.against_model
    );
}

#[test]
fn a_curve_measured_at_the_moving_eye_is_moved_to_b() {
    let (_, t) = mf7923d(2.0);
    let eye = parse_curve_csv(&csv_of(&t, "n1_A.P_eye_mm", "n1.P_eye_mm", 1), "eye.csv").unwrap();
    let m = measured_match(&t, &eye, None).unwrap();
    assert_eq!(m.split, stitchkin::thread::SplitPoint::B);
    let at_b = t.column("n1_A.P_B_mm").unwrap();
    let worst = m
        .values_mm
        .iter()
        .zip(at_b)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "P_eye + S − S(φ0) = P_B: {worst}");
    // A measured P′ is set against the model's P: the thread's own D.
    let req = parse_curve_csv(&csv_of(&t, "n3.Pprime_B_mm", "Pprime_B_mm", 1), "req.csv").unwrap();
    let m = measured_match(&t, &req, Some("n3_A")).unwrap();
    assert_eq!((m.thread.as_str(), m.kind), ("n3", CurveKind::Required));
    let own = t
        .stitch
        .as_ref()
        .unwrap()
        .threads
        .iter()
        .find(|x| x.thread == "n3")
        .unwrap()
        .mismatch
        .clone()
        .unwrap();
    assert!((m.against_other.as_ref().unwrap().rms_d_mm - own.rms_d_mm).abs() < 1e-12);
    assert!(m.against_model.as_ref().unwrap().rms_d_mm < 1e-12);
}

#[test]
fn a_curve_that_does_not_fit_the_model_is_refused_with_the_fix() {
    let (_, t) = mf7923d(5.0);
    let text = csv_of(&t, "n1_A.P_B_mm", "P_B_mm", 1);
    let curve = parse_curve_csv(&text, "p.csv").unwrap();
    let e = measured_match(&t, &curve, None).unwrap_err().to_string();
    assert!(
        e.contains("does not say which thread") && e.contains("n1, n2, n3"),
        "{e}"
    );
    let e = measured_match(&t, &curve, Some("n7")).unwrap_err().to_string();
    assert!(e.contains("no stitch thread or thread path `n7`"), "{e}");
    // A looper thread is measured at its eye, never at B.
    let a = Model::preset("altin504").unwrap();
    let ta = run_cycle(
        &a,
        &a.defaults(),
        &CycleOptions {
            step_deg: 5.0,
            points: Some(Vec::new()),
            analogs: false,
            ..Default::default()
        },
    )
    .unwrap();
    let b = parse_curve_csv(&csv_of(&ta, "lower.P_mm", "lower.P_B_mm", 1), "lower.csv").unwrap();
    let e = measured_match(&ta, &b, None).unwrap_err().to_string();
    assert!(e.contains("looper thread measured at its eye"), "{e}");
    // A model without a stitch has nothing to compare with.
    let n = Model::preset("needle876").unwrap();
    let tn = run_cycle(
        &n,
        &n.defaults(),
        &CycleOptions {
            step_deg: 5.0,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        measured_match(&tn, &curve, None)
            .unwrap_err()
            .to_string()
            .contains("no [stitch]")
    );
}

/// The regulator declared three ways, and refused with the fix when wrong.
#[test]
fn the_regulator_is_declared_and_checked() {
    let text = stitchkin::presets::find("mf7923d").unwrap().toml;
    let with = |line: &str| {
        text.replacen(
            "cyclogram_zero_deg = 180\n",
            &format!("cyclogram_zero_deg = 180\n{line}\n"),
            1,
        )
    };
    let run = |src: &str| {
        let m = Model::from_toml_str(src, "r.toml").unwrap();
        run_cycle(
            &m,
            &m.defaults(),
            &CycleOptions {
                step_deg: 5.0,
                points: Some(Vec::new()),
                analogs: false,
                ..Default::default()
            },
        )
    };
    let st = |t: CycleTable| t.stitch.unwrap();
    let w = st(run(&with("regulator = { width_deg = 30 }")).unwrap()).threads[0].regulator_windows_deg[0];
    assert!((w[0] - 330.0).abs() < 1e-6 && (w[1] - 360.0).abs() < 1e-6, "{w:?}");
    let s = st(run(&with("regulator = { window_deg = [250, 310] }")).unwrap());
    assert!(
        s.threads
            .iter()
            .all(|t| t.regulator_windows_deg == vec![[250.0, 310.0]]),
        "{:?}",
        s.regulator
    );
    assert!(s.regulator.contains("declared"), "{}", s.regulator);
    let s = st(run(&with("regulator = { at_lock = true }")).unwrap());
    assert!(s.threads.iter().all(|t| t.regulator_windows_deg.is_empty()) && s.regulator.contains("at its lock"));
    // A window around φ0 (where P' = 0) cannot be.
    // Said in the model's φ, as the file gives it, where it stands in the
    // file, with a window that fits.
    for line in [
        "regulator = { window_deg = [340, 400] }",
        "regulator = { window_deg = [-30, 30] }",
    ] {
        let e = Model::from_toml_str(&with(line), "r.toml").unwrap_err();
        let w = &line[line.find('[').unwrap()..line.find(']').unwrap() + 1];
        let (text, help) = (e.to_string(), e.help.clone().unwrap_or_default());
        assert!(
            e.line_col().is_some() && text.contains(&format!("the window {w} contains φ0 = 0°")),
            "{text}"
        );
        assert!(help.contains("e.g. window_deg = [300, 360]"), "{help}");
    }
    // The needle threads are pulled tight at φ0: any width short of a turn
    // ends there.
    let s = st(run(&with("regulator = { width_deg = 300 }")).unwrap());
    assert!(
        s.threads.iter().all(|t| t.regulator_windows_deg == vec![[60.0, 360.0]]),
        "{:?}",
        s.regulator
    );
    for (line, says) in [
        (
            "regulator = { window_deg = [300, 200] }",
            "must run forward by less than a turn",
        ),
        ("regulator = { width_deg = 30, at_lock = true }", "exactly one of"),
        ("regulator = {}", "exactly one of"),
        ("regulator = { windows = [1, 2] }", "unknown field"),
    ] {
        let e = Model::from_toml_str(&with(line), "r.toml").unwrap_err();
        assert!(e.line_col().is_some() && e.to_string().contains(says), "{line}: {e}");
    }
}

/// A tuning whose optimum lies on a range end says so, and one that cannot
/// improve says that.
#[test]
fn tuning_says_where_it_stands() {
    // The kinematic match with the regulator's window assumed.
    let m = super::support::assumed_window("mf7923d");
    let p = m.defaults();
    // r1 wants to be smaller than its range allows.
    let r = tune(
        &m,
        &p,
        &TuneOptions {
            objective: Default::default(),
            adjust: vec!["r1".into()],
            samples: 16,
            seed: 1,
            step_deg: 5.0,
        },
    )
    .unwrap();
    assert!(r.after[0] - 4.0 < 0.01, "{:?}", r.after);
    assert!(
        r.notes
            .iter()
            .any(|n| n.starts_with("r1 = 4") && n.contains("lower end of its adjustable range (4…6 mm)")),
        "{:?}",
        r.notes
    );
    // At its best already: the match does not improve, and that is said.
    let mut q = p.clone();
    m.set(&mut q, "r1", r.after[0]).unwrap();
    let again = tune(
        &m,
        &q,
        &TuneOptions {
            objective: Default::default(),
            adjust: vec!["r1".into()],
            samples: 16,
            seed: 1,
            step_deg: 5.0,
        },
    )
    .unwrap();
    assert!(
        again.notes.iter().any(|n| n.contains("does not improve")),
        "{:?}",
        again.notes
    );
    // The reading with T1 down at TDC: no setting of z passes the checks.
    let mut q = p.clone();
    m.set(&mut q, "t1_phase", 0.0).unwrap();
    let r = tune(
        &m,
        &q,
        &TuneOptions {
            objective: Default::default(),
            adjust: vec!["z".into()],
            samples: 16,
            seed: 1,
            step_deg: 5.0,
        },
    )
    .unwrap();
    assert!(!r.after_figures.failed_checks.is_empty());
    assert!(
        r.notes.iter().any(|n| n.contains("passes every physical check")),
        "{:?}",
        r.notes
    );
}
