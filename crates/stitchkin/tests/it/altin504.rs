//! The `altin504` preset: Textima Altin overlock, stitch 504 (seed 004).
//! The published needle mechanism of altin-needle, illustrative looper
//! mechanisms and thread feed, and the required take-up P' of the needle,
//! lower- and upper-looper threads (docs/stitch-formation.md §10.2).
//!
//! The golden numbers were established with this preset (stitchkin check /
//! match, step 1°) and its design script; see the preset's header.

use stitchkin::eval::stitch_process::{StitchSummary, StitchThreadSummary};
use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::model::Model;

/// A cycle of the preset at `set`, step `step`, with the regulator's window
/// assumed (the stitch process's own figures; `support::assumed_window`).
fn run_with(set: &[(&str, f64)], step: f64) -> CycleTable {
    let model = super::support::assumed_window("altin504");
    let mut params = model.defaults();
    for (k, v) in set {
        model.set(&mut params, k, *v).unwrap();
    }
    run_cycle(
        &model,
        &params,
        &CycleOptions {
            step_deg: step,
            rpm: None,
            analogs: false,
            points: Some(Vec::new()),
            lean: false,
        },
    )
    .unwrap()
}

fn run() -> CycleTable {
    run_with(&[], 1.0)
}

fn col<'a>(t: &'a CycleTable, name: &str) -> &'a [f64] {
    t.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

fn stitch(t: &CycleTable) -> &StitchSummary {
    t.stitch.as_ref().expect("altin504 has a [stitch]")
}

fn thread<'a>(s: &'a StitchSummary, name: &str) -> &'a StitchThreadSummary {
    s.threads
        .iter()
        .find(|t| t.thread == name)
        .unwrap_or_else(|| panic!("no thread {name}"))
}

/// (min, φ at min, max, φ at max) of a column.
fn extremes(t: &CycleTable, name: &str) -> (f64, f64, f64, f64) {
    let (phi, v) = (col(t, "phi_deg"), col(t, name));
    let (mut lo, mut hi) = (0, 0);
    for k in 0..v.len() {
        if v[k] < v[lo] {
            lo = k;
        }
        if v[k] > v[hi] {
            hi = k;
        }
    }
    (v[lo], phi[lo].rem_euclid(360.0), v[hi], phi[hi].rem_euclid(360.0))
}

/// Circular distance of two angles, degrees.
fn dist_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

#[test]
fn loads_solves_and_keeps_every_transmission_angle_in_the_band() {
    let model = Model::preset("altin504").unwrap();
    assert_eq!(model.seed(), Some("004"));
    let t = run();
    assert_eq!(t.rows(), 360);
    for c in &t.columns {
        assert!(c.values.iter().all(|v| v.is_finite()), "{}", c.name);
    }
    for key in ["LM_AM", "BC_CD", "lower_rocker", "upper_rocker"] {
        let tr = t
            .transmission
            .iter()
            .find(|m| m.key == key)
            .unwrap_or_else(|| panic!("no μ of {key}"));
        assert!(tr.ok, "{key}: {tr:?}");
    }
    let mu = col(&t, "mu_upper_rocker_deg");
    assert!(
        mu.iter().all(|&m| (40.0..=145.0).contains(&m)),
        "upper rocker μ leaves 40…145°"
    );
    let mu = col(&t, "mu_lower_rocker_deg");
    assert!(
        mu.iter().all(|&m| (75.0..=105.0).contains(&m)),
        "lower rocker μ leaves 75…105°"
    );
    assert!(t.warnings.is_empty(), "{:?}", t.warnings);
    let s = stitch(&t);
    assert_eq!(s.stitch_type, 504);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let names: Vec<(&str, Option<&str>)> = s
        .threads
        .iter()
        .map(|t| (t.thread.as_str(), t.path.as_deref()))
        .collect();
    assert_eq!(
        names,
        [
            ("needle", Some("needle")),
            ("lower", Some("lower")),
            ("upper", Some("upper"))
        ]
    );
}

/// The needle is altin-needle's, unchanged: stroke 25.44 mm, BDC at φ = 0.
#[test]
fn needle_stroke_is_altin_needles() {
    let t = run_with(&[], 0.05);
    let (lo, phi_lo, hi, phi_hi) = extremes(&t, "needle_s_mm");
    assert!((hi - lo - 25.438).abs() < 1e-3, "stroke {}", hi - lo);
    assert!(dist_deg(phi_lo, 0.0) < 0.06, "BDC at {phi_lo}");
    assert!(dist_deg(phi_hi, 174.85) < 0.06, "TDC at {phi_hi}");
    assert!((stitch(&t).cyclogram_zero_deg - 0.0008).abs() < 1e-12);
    // The eye moves with the needle bar: the same stroke, along the 20° line.
    let (zlo, _, zhi, _) = extremes(&t, "eye_z_mm");
    assert!(
        (zhi - zlo - 25.438 * 20f64.to_radians().cos()).abs() < 2e-3,
        "eye z travel {}",
        zhi - zlo
    );
}

/// The eye stands 11.5 mm (seed S0) above 2.5 mm of material at TDC,
/// vertically: s_B = 14/cos 20° = 14.8985 mm along the needle, on the needle
/// line x = 0 of the stitch frame; the needle's up direction has a negative
/// y there, (0, −sin β, cos β).
#[test]
fn eye_stands_s0_above_the_material_at_tdc_in_the_stitch_frame() {
    let model = Model::preset("altin504").unwrap();
    let params = model.defaults();
    let t = run_cycle(
        &model,
        &params,
        &CycleOptions {
            step_deg: 1.0,
            rpm: None,
            analogs: false,
            points: None,
            lean: false,
        },
    )
    .unwrap();
    // Row 0 is φ = 174.85, the needle's TDC (phi_start_deg).
    let eye_z = col(&t, "eye_z_mm");
    let cos_b = 20f64.to_radians().cos();
    assert!(
        (eye_z[0] - 2.5 - 11.5).abs() < 2e-3,
        "eye {} mm above the plate",
        eye_z[0]
    );
    assert!(col(&t, "eye_x_mm").iter().all(|x| x.abs() < 1e-9));
    // World positions of the eye: the stitch frame's y is −world x, so the
    // eye's TDC is at a larger world x than its BDC (it leans toward −y).
    let ex = col(&t, "EYE.x_mm");
    let k_bdc = col(&t, "phi_deg")
        .iter()
        .position(|&p| (p.rem_euclid(360.0) - 359.85).abs() < 1e-6)
        .unwrap();
    assert!(ex[0] > ex[k_bdc]);
    let setup = model.stitch_setup(&params).unwrap().unwrap();
    let n = &setup.spec.needles[0];
    let (tdc, bdc) = (n.eye.at(174.85 - 0.0008), n.eye.at(0.0));
    let up = (tdc - bdc).normalize();
    assert!(up.y < 0.0 && (up.y + 20f64.to_radians().sin()).abs() < 1e-3, "{up:?}");
    assert!((tdc.z - 14.0).abs() < 1e-6, "{tdc:?}");
    let s_b = tdc.z / cos_b;
    assert!((s_b - 14.8985).abs() < 1e-4, "s_B = {s_b}");
}

/// Lower looper: stroke 17.3 mm across the seam, near extreme at the needle's
/// BDC, far extreme at 180°, catch (x = 0 going +x) at φ_c = 30, eye about
/// H = 5.5 mm below the plate.
#[test]
fn lower_looper_catches_at_30_with_a_17_3_mm_stroke() {
    let t = run_with(&[], 0.05);
    let (lo, phi_lo, hi, phi_hi) = extremes(&t, "lower_x_mm");
    assert!((hi - lo - 17.325).abs() < 0.01, "stroke {}", hi - lo);
    assert!(
        dist_deg(phi_lo, 0.0) < 1.0 && dist_deg(phi_hi, 180.0) < 1.0,
        "extremes at {phi_lo}, {phi_hi}"
    );
    assert!((lo + 0.993).abs() < 0.01 && (hi - 16.332).abs() < 0.01, "{lo} … {hi}");
    let (phi, x, z) = (col(&t, "phi_deg"), col(&t, "lower_x_mm"), col(&t, "lower_z_mm"));
    let n = x.len();
    let crossings: Vec<(f64, f64)> = (0..n)
        .filter(|&k| x[k] < 0.0 && x[(k + 1) % n] >= 0.0)
        .map(|k| {
            let s = -x[k] / (x[(k + 1) % n] - x[k]);
            ((phi[k] + 0.05 * s).rem_euclid(360.0), z[k])
        })
        .collect();
    assert_eq!(crossings.len(), 1, "{crossings:?}");
    let (catch, z_catch) = crossings[0];
    assert!((catch - 30.05).abs() < 0.1, "catch at {catch}");
    assert!((z_catch + 5.5).abs() < 0.05, "eye {z_catch} mm at the catch");
    assert!(z.iter().all(|&z| (-5.7..=-4.99).contains(&z)));
    let s = stitch(&t);
    let moment = |name: &str| {
        s.moments
            .iter()
            .find(|(n, _)| n.contains(name))
            .unwrap_or_else(|| panic!("no moment {name}: {:?}", s.moments))
            .1
    };
    assert!((moment("catch (derived)") - 30.05).abs() < 0.1);
    assert!((moment("drop (derived)") - 297.1).abs() < 0.3);
    assert!((moment("looper far extreme") - 180.0).abs() < 0.3);
}

/// Upper looper: low beyond the edge and below the plate, high over the
/// needle line at the stab, never inside the material, and it picks the
/// lower thread inside the window.
#[test]
fn upper_looper_goes_from_beyond_the_edge_over_the_needle() {
    let t = run_with(&[], 0.25);
    let (phi, x, z) = (col(&t, "phi_deg"), col(&t, "upper_x_mm"), col(&t, "upper_z_mm"));
    let (xlo, phi_high, xhi, phi_low) = extremes(&t, "upper_x_mm");
    assert!(dist_deg(phi_low, 130.0) < 1.0 && xhi > 14.5, "low {xhi} at {phi_low}");
    assert!(dist_deg(phi_high, 275.0) < 1.0 && xlo < 0.0, "high {xlo} at {phi_high}");
    let k270 = phi
        .iter()
        .position(|&p| (p.rem_euclid(360.0) - 270.1).abs() < 0.2)
        .unwrap();
    assert!(
        x[k270].abs() < 1.0 && (z[k270] - 4.2).abs() < 0.1,
        "at the stab ({}, {})",
        x[k270],
        z[k270]
    );
    let (a_e, m) = (4.0, 2.5);
    for k in 0..x.len() {
        assert!(
            !(x[k] < a_e && z[k] > 0.0 && z[k] < m),
            "inside the material at φ = {}",
            phi[k]
        );
        if z[k] < 0.0 {
            assert!(x[k] > 10.0, "below the plate at x = {} (φ = {})", x[k], phi[k]);
        }
    }
    let s = stitch(&t);
    let pick = s
        .moments
        .iter()
        .find(|(n, _)| n.contains("picks lower thread"))
        .unwrap()
        .1;
    assert!((pick - 160.7).abs() < 0.5, "pick-up at {pick}");
}

/// Thread per stitch (docs §6.3): 8.121 / 11.383 / 11.383 mm, and the P'
/// model locks exactly that.
#[test]
fn locked_thread_is_the_per_stitch_consumption() {
    let t = run();
    let s = stitch(&t);
    let (m, st, a_e): (f64, f64, f64) = (2.5, 2.8, 4.0);
    let l_m = m / 20f64.to_radians().cos();
    let l = (a_e * a_e + st * st).sqrt();
    for (name, want, rounded) in [
        ("needle", st + 2.0 * l_m, 8.121),
        ("lower", a_e + l + m, 11.383),
        ("upper", a_e + l + m, 11.383),
    ] {
        let th = thread(s, name);
        assert!((th.per_stitch_mm - want).abs() < 1e-12, "{name}: {}", th.per_stitch_mm);
        assert!(
            (th.per_stitch_mm - rounded).abs() < 5e-4,
            "{name}: {}",
            th.per_stitch_mm
        );
        assert!(
            (th.locked_mm - th.per_stitch_mm).abs() < 1e-9,
            "{name}: locked {} vs {}",
            th.locked_mm,
            th.per_stitch_mm
        );
    }
    // Locks at φ4 = 300 and φ5 = 330 of the cyclogram (model φ = φ_c + 0.0008).
    assert!((thread(s, "needle").lock_phi_deg - 300.0008).abs() < 1e-6);
    assert!((thread(s, "lower").lock_phi_deg - 330.0008).abs() < 1e-6);
    assert!((thread(s, "upper").lock_phi_deg - 330.0008).abs() < 1e-6);
}

#[test]
fn pprime_is_finite_and_zero_at_phi0() {
    let t = run();
    let s = stitch(&t);
    assert_eq!(s.phi0_deg, 174.85);
    assert_eq!(col(&t, "phi_deg")[0], 174.85);
    // The needle thread at B (its path ends at the needle's eye), the
    // looper threads at their eyes.
    for (name, at) in [("needle", "_B"), ("lower", ""), ("upper", "")] {
        let pp = col(&t, &format!("{name}.Pprime{at}_mm"));
        let p = col(&t, &format!("{name}.P{at}_mm"));
        let d = col(&t, &format!("{name}.D_mm"));
        assert!(
            pp[0].abs() < 1e-12 && p[0].abs() < 1e-12,
            "{name}: P'(φ0) = {}, P(φ0) = {}",
            pp[0],
            p[0]
        );
        for k in 0..pp.len() {
            assert!(pp[k].is_finite());
            assert!((d[k] - (p[k] - pp[k])).abs() < 1e-12);
        }
    }
    assert!(col(&t, "needle.Pprime_eye_mm")[0].abs() < 1e-9 && col(&t, "needle.P_eye_mm")[0].abs() < 1e-12);
}

/// Golden numbers of the preset (m = 2.5, t = 2.8, step 1°): the needle
/// thread at B, the looper threads at their eyes; each thread's stitch drawn
/// through its regulator in the 60° before it is pulled tight.
#[test]
fn golden_take_up_and_match() {
    let t = run();
    let s = stitch(&t);
    // (thread, its P column, max P', min P, max P, match score)
    for (name, p_col, max_pp, min_p, max_p, score) in [
        ("needle", "needle.P_B_mm", 15.156, 0.0, 8.227, 81.9),
        ("lower", "lower.P_mm", 7.327, -9.499, 6.285, 90.3),
        ("upper", "upper.P_mm", 3.491, -11.573, 2.600, 89.9),
    ] {
        let th = thread(s, name);
        assert!(
            (th.max_pprime_mm - max_pp).abs() < 0.02,
            "{name}: max P' {}",
            th.max_pprime_mm
        );
        let p = col(&t, p_col);
        let (lo, hi) = p.iter().fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(
            (lo - min_p).abs() < 0.02 && (hi - max_p).abs() < 0.02,
            "{name}: P {lo} … {hi}"
        );
        let mm = th.mismatch.as_ref().expect("compared with its path");
        let sc = mm.score.expect("P' varies");
        assert!((sc - score).abs() < 0.5, "{name}: score {sc}");
    }
    // The needle thread measured at the moving eye.
    let pe = col(&t, "needle.Pprime_eye_mm");
    let max_pe = pe.iter().fold(f64::MIN, |a, &v| a.max(v));
    assert!((max_pe - 2.776).abs() < 0.02, "max P'_eye {max_pe}");
    // The regulator windows: the needle thread's the 60° before the needle's
    // TDC (174.85°), the looper threads' the 60° before their draw-in (330°).
    let w = |name: &str| {
        thread(s, name)
            .regulator_windows_deg
            .first()
            .copied()
            .expect("a window")
    };
    assert!(
        (w("needle")[0] - 114.84).abs() < 0.02 && (w("needle")[1] - 174.84).abs() < 0.02,
        "{:?}",
        w("needle")
    );
    assert!((w("lower")[0] - 270.0008).abs() < 1e-6 && (w("upper")[1] - 330.0008).abs() < 1e-6);
    // The lock jumps of P': the stitch's own thread is drawn in the window,
    // so the needle's lock gives back only the loop −ρ, the looper threads'
    // the snap.
    let jump = |name: &str, kind: stitchkin::stitch::spec::EventKind| {
        thread(s, name)
            .events
            .iter()
            .find(|e| e.kind == kind)
            .map(|e| e.jump_mm)
            .unwrap()
    };
    use stitchkin::stitch::spec::EventKind::Lock;
    assert!((jump("needle", Lock) + 17.479).abs() < 0.01, "{}", jump("needle", Lock));
    assert!((jump("needle", Lock) + thread(s, "needle").released_mm).abs() < 1e-9);
    assert!((jump("lower", Lock) - 0.002).abs() < 0.01, "{}", jump("lower", Lock));
    assert!((jump("upper", Lock) - 0.183).abs() < 0.01, "{}", jump("upper", Lock));
    // Every physical check passes: the needle thread's three, the take-up's
    // and the tension's four of each thread.
    assert!(s.checks_ok() && s.checks.len() == 18, "{:?}", s.checks);
}

/// Seed 000/004: max P' grows with the thickness and the stitch length (the
/// needle thread, seed split at B).
#[test]
fn needle_pprime_b_grows_with_m_and_t() {
    let max_pb = |set: &[(&str, f64)]| {
        let t = run_with(set, 1.0);
        col(&t, "needle.Pprime_B_mm").iter().fold(f64::MIN, |a, &v| a.max(v))
    };
    let (m1, m25) = (max_pb(&[("m", 1.0)]), max_pb(&[("m", 2.5)]));
    assert!(m25 > m1 + 2.0, "m = 1: {m1}, m = 2.5: {m25}");
    let (t1, t28) = (max_pb(&[("stitch", 1.0)]), max_pb(&[("stitch", 2.8)]));
    assert!(t28 > t1 + 0.5, "t = 1: {t1}, t = 2.8: {t28}");
    // The thread per stitch follows the parameters.
    let t = run_with(&[("m", 1.0), ("stitch", 1.5)], 1.0);
    let th = thread(stitch(&t), "needle");
    let want = 1.5 + 2.0 / 20f64.to_radians().cos();
    assert!((th.per_stitch_mm - want).abs() < 1e-12 && (th.locked_mm - want).abs() < 1e-9);
}
