//! Invariants over random mechanisms: link lengths kept at every φ, exact
//! analogs equal to finite differences, no branch flip along a cycle,
//! periodicity.

use num_dual::Dual2_64;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::geometry::V3;
use stitchkin::mechanism::{Mechanism, Phi};
use stitchkin::model::Model;
use stitchkin::scalar::Real;

use crate::mechgen::{self, Generated};

fn slot(m: &Model, name: &str) -> usize {
    m.point_names().iter().position(|p| p == name).unwrap()
}

fn positions(mech: &Mechanism<f64>, phi: f64) -> Vec<V3<f64>> {
    let mut pose = mech.new_pose(1);
    mech.solve(&[Phi::new(phi)], &mut pose).unwrap();
    (0..mech.n_points()).map(|s| pose.point(s, 0)).collect()
}

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

fn check_lengths(g: &Generated) -> Result<(), TestCaseError> {
    let m = g.load();
    prop_assume!(assembles(&m));
    let mech = m.mechanism::<f64>(&m.defaults()).unwrap();
    for k in 0..72 {
        let p = positions(&mech, (k as f64 * 5.0).to_radians());
        for (a, b, l) in &g.links {
            let d = (p[slot(&m, a)] - p[slot(&m, b)]).norm();
            prop_assert!((d - l).abs() < 1e-9, "|{a}{b}| = {d}, want {l} at φ = {}°", k * 5);
        }
    }
    Ok(())
}

/// Exact analogs against central differences of positions.
fn check_analogs(g: &Generated) -> Result<(), TestCaseError> {
    let m = g.load();
    prop_assume!(assembles(&m));
    let exact = m.mechanism::<Dual2_64>(&m.defaults()).unwrap();
    let plain = m.mechanism::<f64>(&m.defaults()).unwrap();
    let h = 1e-4;
    for k in 0..24 {
        let phi = (k as f64 * 15.0 + 7.0).to_radians();
        let mut pose = exact.new_pose(1);
        exact.solve(&[Phi::new(Dual2_64::var(phi))], &mut pose).unwrap();
        let (pm, p0, pp) = (
            positions(&plain, phi - h),
            positions(&plain, phi),
            positions(&plain, phi + h),
        );
        for s in 0..exact.n_points() {
            for c in 0..3 {
                let d = pose.point(s, 0)[c];
                prop_assert!((d.re - p0[s][c]).abs() < 1e-12);
                let d1 = (pp[s][c] - pm[s][c]) / (2.0 * h);
                let d2 = (pp[s][c] - 2.0 * p0[s][c] + pm[s][c]) / (h * h);
                let scale = 1.0 + d.v1.abs() + d.v2.abs();
                prop_assert!((d.v1 - d1).abs() < 1e-6 * scale, "d/dφ {} vs {d1}", d.v1);
                prop_assert!((d.v2 - d2).abs() < 2e-3 * scale, "d²/dφ² {} vs {d2}", d.v2);
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, .. ProptestConfig::default() })]

    #[test]
    fn four_bar_keeps_lengths(g in mechgen::four_bar()) { check_lengths(&g)?; }
    #[test]
    fn slider_crank_keeps_lengths(g in mechgen::slider_crank()) { check_lengths(&g)?; }
    #[test]
    fn rssr_chain_keeps_lengths(g in mechgen::rssr_chain()) { check_lengths(&g)?; }

    #[test]
    fn four_bar_analogs_are_derivatives(g in mechgen::four_bar()) { check_analogs(&g)?; }
    #[test]
    fn slider_crank_analogs_are_derivatives(g in mechgen::slider_crank()) { check_analogs(&g)?; }
    #[test]
    fn rssr_chain_analogs_are_derivatives(g in mechgen::rssr_chain()) { check_analogs(&g)?; }

    /// The assembly stays on its declared side of the base line at every φ.
    #[test]
    fn four_bar_branch_never_flips(g in mechgen::four_bar()) {
        let m = g.load();
        let left = g.toml.contains("branch = \"left\"");
        let mech = m.mechanism::<f64>(&m.defaults()).unwrap();
        let (a, o2, b) = (slot(&m, "A"), slot(&m, "O2"), slot(&m, "B"));
        for k in 0..360 {
            let p = positions(&mech, (k as f64).to_radians());
            let (u, w) = (p[o2] - p[a], p[b] - p[a]);
            let cross = u.x * w.y - u.y * w.x;
            prop_assert_eq!(cross > 0.0, left, "flipped at φ = {}°", k);
        }
    }

    #[test]
    fn positions_are_periodic(g in mechgen::four_bar(), phi in 0.0..360.0f64) {
        let m = g.load();
        let mech = m.mechanism::<f64>(&m.defaults()).unwrap();
        let (p, q) = (positions(&mech, phi.to_radians()), positions(&mech, (phi + 360.0).to_radians()));
        for (x, y) in p.iter().zip(&q) {
            prop_assert!((x - y).norm() < 1e-9);
        }
    }
}

#[test]
fn rssr_branch_stays_on_its_side() {
    let g = mechgen::rssr_chain();
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut checked = 0;
    for _ in 0..40 {
        let g = g.new_tree(&mut runner).unwrap().current();
        let m = g.load();
        if !assembles(&m) {
            continue;
        }
        let left = g.toml.contains("branch = \"left\"");
        let mech = m.mechanism::<f64>(&m.defaults()).unwrap();
        let (a, b, c) = (slot(&m, "A"), slot(&m, "B"), slot(&m, "C"));
        // The rocker axis is the frame's x axis: turn from A's direction to B's about it.
        let cx = slot(&m, "Cx");
        for k in 0..72 {
            let p = positions(&mech, (k as f64 * 5.0).to_radians());
            let w = (p[cx] - p[c]).normalize();
            let turn = (p[a] - p[c]).cross(&(p[b] - p[c])).dot(&w);
            assert_eq!(turn > 0.0, left, "flipped at φ = {}°\n{}", k * 5, g.toml);
        }
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} generated chains assembled");
}

/// A setting solved from the one before (`Mechanism::solve_since`,
/// `Threads::keep_unmoved`: only what the change moves is solved again)
/// gives the bits of solving it afresh, for every preset and every ranged
/// parameter stepped across its range, forward and back; and what it says
/// did not move did not.
#[test]
fn a_setting_solved_from_the_last_is_the_setting_solved_afresh() {
    use stitchkin::thread::ThreadWork;
    let phis: Vec<f64> = (0..90).map(|k| 4.0 * k as f64).collect();
    let table = Phi::table(&phis);
    let mut still_points = 0;
    for preset in stitchkin::presets::ALL {
        let m = Model::preset(preset.name).unwrap();
        let base = m.defaults();
        let ranged: Vec<(String, [f64; 2])> = m
            .params()
            .iter()
            .filter(|q| q.range.is_some_and(|[a, b]| a < b) && !q.is_derived())
            .map(|q| (q.name.clone(), q.range.unwrap()))
            .collect();
        // Each parameter across its range and back, from the setting before.
        let mut settings = Vec::new();
        for (name, [lo, hi]) in &ranged {
            for f in [0.5, 0.0, 0.3, 1.0, 0.7, 0.5] {
                let mut p = base.clone();
                m.set(&mut p, name, lo + f * (hi - lo)).unwrap();
                settings.push((name.clone(), p));
            }
        }
        let mut before: Option<stitchkin::model::Machine<f64>> = None;
        let (mut pose, mut moved, mut work) = (None, Vec::new(), ThreadWork::<f64>::default());
        for (name, p) in &settings {
            let Ok(machine) = m.machine::<f64>(p) else {
                before = None;
                continue;
            };
            let mech = &machine.mechanism;
            let pose = pose.get_or_insert_with(|| mech.new_pose(phis.len()));
            let mut fresh = mech.new_pose(phis.len());
            let afresh = mech.solve(&table, &mut fresh);
            let since = mech.solve_since(before.as_ref().map(|b| &b.mechanism), &table, pose, &mut moved);
            assert_eq!(since.is_ok(), afresh.is_ok(), "{} {name}", preset.name);
            if since.is_err() {
                before = None;
                continue;
            }
            for slot in 0..mech.n_points() {
                assert_eq!(
                    pose.track(slot),
                    fresh.track(slot),
                    "{} {name} point {slot}",
                    preset.name
                );
            }
            if let Some(b) = &before {
                let mut was = b.mechanism.new_pose(phis.len());
                b.mechanism.solve(&table, &mut was).unwrap();
                for slot in 0..mech.n_points() {
                    if !moved[slot] {
                        assert_eq!(
                            was.track(slot),
                            fresh.track(slot),
                            "{} {name} point {slot} moved",
                            preset.name
                        );
                        still_points += 1;
                    }
                }
            }
            if let Some(threads) = &machine.threads {
                if let Some(t0) = before.as_ref().and_then(|b| b.threads.as_ref()) {
                    threads.keep_unmoved(t0, &moved, &mut work);
                }
                let kept = threads.evaluate_into(pose, None, &mut work);
                let afresh = threads.evaluate(&fresh, None);
                assert_eq!(kept.is_ok(), afresh.is_ok(), "{} {name} paths", preset.name);
                match afresh {
                    Ok(tracks) => assert_eq!(work.tracks, tracks, "{} {name} paths", preset.name),
                    Err(_) => {
                        before = None;
                        continue;
                    }
                }
            }
            before = Some(machine);
        }
    }
    assert!(still_points > 1000, "only {still_points} points stayed where they were");
}
