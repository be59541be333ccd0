//! The closed-form groups against an independent whole-mechanism Newton
//! solver: every preset and random mechanisms agree to 1e-9 mm.

use proptest::prelude::*;
use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::Model;
use stitchkin::verify::cross_check;

use crate::mechgen;

const TOL_MM: f64 = 1e-9;

#[test]
fn every_preset_agrees_with_the_newton_solver() {
    for p in stitchkin::presets::ALL {
        let m = Model::preset(p.name).unwrap();
        let c = cross_check(&m, &m.defaults(), 1.0).unwrap();
        assert_eq!(c.positions, 360, "{}", p.name);
        assert!(c.max_deviation_mm < TOL_MM, "{}: {c:?}", p.name);
    }
}

#[test]
fn needle876_agrees_across_its_adjustment_range() {
    let m = Model::preset("needle876").unwrap();
    for alpha in [0.0, 15.0, 35.0, 45.0] {
        let mut p = m.defaults();
        m.set(&mut p, "alpha", alpha).unwrap();
        let c = cross_check(&m, &p, 2.0).unwrap();
        assert!(c.max_deviation_mm < TOL_MM, "alpha {alpha}: {c:?}");
    }
}

/// Whether the generated model assembles over its whole cycle.
fn assembles(m: &Model) -> bool {
    run_cycle(
        m,
        &m.defaults(),
        &CycleOptions {
            step_deg: 5.0,
            analogs: false,
            ..Default::default()
        },
    )
    .is_ok()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]

    #[test]
    fn random_four_bars(g in mechgen::four_bar()) {
        let m = g.load();
        let c = cross_check(&m, &m.defaults(), 3.0).unwrap();
        prop_assert!(c.max_deviation_mm < TOL_MM, "{c:?}\n{}", g.toml);
    }

    #[test]
    fn random_slider_cranks(g in mechgen::slider_crank()) {
        let m = g.load();
        let c = cross_check(&m, &m.defaults(), 3.0).unwrap();
        prop_assert!(c.max_deviation_mm < TOL_MM, "{c:?}\n{}", g.toml);
    }

    #[test]
    fn random_rssr_chains(g in mechgen::rssr_chain()) {
        let m = g.load();
        prop_assume!(assembles(&m));
        let c = cross_check(&m, &m.defaults(), 3.0).unwrap();
        prop_assert!(c.max_deviation_mm < TOL_MM, "{c:?}\n{}", g.toml);
    }
}
