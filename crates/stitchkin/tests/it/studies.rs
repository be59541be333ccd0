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
