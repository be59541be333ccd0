//! Input limits: each is checked before the work it limits, and a request
//! past it is refused with the limit and the fix.

use stitchkin::error::Error;
use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::Model;
use stitchkin::study::design::{Design, MAX_SETTINGS, Sweep, Vary};
use stitchkin::study::nomogram::{Axis, NomogramOptions, nomogram};
use stitchkin::study::tune::{MAX_SAMPLES, TuneOptions, tune};

/// An error as a user reads it: what is wrong, then the fix.
fn said(e: Error) -> String {
    format!("{e}; {}", e.help().unwrap_or_default())
}

fn tune_opts(samples: usize) -> TuneOptions {
    TuneOptions {
        objective: Default::default(),
        adjust: vec!["z".into(), "dphi".into()],
        samples,
        seed: 1,
        step_deg: 1.0,
    }
}

#[test]
fn samples_past_the_limits_are_refused_before_any_work() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let z = Vary::parse(&m, "z=-10:10:2").unwrap();
    // 2³² once wrapped to no strata in u32 and panicked.
    for samples in [1usize << 32, 1_000_000_000, MAX_SETTINGS + 1] {
        let e = said(
            Sweep::new(vec![z.clone()], Design::Lhs { samples, seed: 1 })
                .map(|_| ())
                .unwrap_err(),
        );
        assert!(e.contains("100 million"), "{e}");
    }
    for samples in [1usize << 32, 1_000_000_000, MAX_SAMPLES + 1] {
        let e = said(tune(&m, &p, &tune_opts(samples)).map(|_| ()).unwrap_err());
        assert!(e.contains(&format!("at most {MAX_SAMPLES}")), "{e}");
        let opts = NomogramOptions {
            thickness: Axis::parse("1:3:2", stitchkin::Input::Thickness).unwrap(),
            stitch: None,
            tune: tune_opts(samples),
        };
        let e = said(nomogram(&m, &p, &opts, || {}).map(|_| ()).unwrap_err());
        assert!(e.contains(&format!("at most {MAX_SAMPLES}")), "{e}");
    }
}

#[test]
fn one_value_from_a_range_is_ambiguous() {
    let m = Model::preset("mf7923d").unwrap();
    let e = said(Vary::parse(&m, "z=-10:10:1").map(|_| ()).unwrap_err());
    assert!(e.contains("N ≥ 2") && e.contains("z=-10:-10:1"), "{e}");
    let one = Vary::parse(&m, "z=5:5:1").unwrap();
    assert_eq!(Sweep::new(vec![one], Design::Grid).unwrap().len(), 1);
    let e = said(
        Axis::parse("1:3:1", stitchkin::Input::Thickness)
            .map(|_| ())
            .unwrap_err(),
    );
    assert!(e.contains("N ≥ 2"), "{e}");
    assert_eq!(Axis::parse("2", stitchkin::Input::Thickness).unwrap().n, 1);
}

#[test]
fn a_step_out_of_range_is_told_its_bounds() {
    let m = Model::preset("needle876").unwrap();
    for step_deg in [0.0, -1.0, 400.0, f64::NAN] {
        let opts = CycleOptions {
            step_deg,
            ..Default::default()
        };
        let e = said(run_cycle(&m, &m.defaults(), &opts).map(|_| ()).unwrap_err());
        assert!(e.contains("greater than 0 and at most 360 degrees"), "{e}");
    }
}

#[test]
fn a_refining_study_is_told_its_own_bounds() {
    use stitchkin::eval::MAX_STEP_DEG;
    use stitchkin::study::stroke::{Axis, stroke};
    let m = Model::preset("needle876").unwrap();
    let g = m.point_names().iter().position(|n| n == "G").unwrap();
    for step_deg in [0.0, -1.0, f64::NAN] {
        let e = said(
            stroke(&m, &m.defaults(), g, &Axis::World(1), step_deg)
                .map(|_| ())
                .unwrap_err(),
        );
        assert!(
            e.contains(&format!("greater than 0 and at most {MAX_STEP_DEG} degrees")),
            "{e}"
        );
    }
    let e = said(
        stroke(&m, &m.defaults(), g, &Axis::World(1), 90.0)
            .map(|_| ())
            .unwrap_err(),
    );
    assert!(e.contains(&format!("at most {MAX_STEP_DEG} deg")), "{e}");
}
