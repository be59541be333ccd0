//! Cams and followers: the example models load, solve, give analogs equal to
//! finite differences, pass the independent cross-check, and the cam checks
//! catch what they are for (pressure angle, undercut, a follower leaving a
//! spring-closed cam).

use stitchkin::eval::{self, CycleOptions, CycleTable};
use stitchkin::model::Model;
use stitchkin::verify::cross_check;

const ROCKING: &str = include_str!("../../../../examples/cam-rocking-roller.toml");
const GROOVE: &str = include_str!("../../../../examples/cam-translating-groove.toml");

fn model(text: &str) -> Model {
    Model::from_toml_str(text, "cam.toml").unwrap()
}

fn cycle(m: &Model, set: &[(&str, f64)], rpm: Option<f64>) -> CycleTable {
    let mut p = m.defaults();
    for (k, v) in set {
        m.set(&mut p, k, *v).unwrap();
    }
    let opts = CycleOptions {
        step_deg: 0.5,
        rpm,
        ..Default::default()
    };
    eval::run_cycle(m, &p, &opts).unwrap()
}

fn check<'a>(t: &'a CycleTable, name: &str) -> &'a stitchkin::stitch::checks::Check {
    t.cams[0].checks.iter().find(|c| c.name == name).unwrap()
}

/// The rocking example with a flat face on its arm 3 mm from the pivot
/// instead of the roller.
fn flat_rocking() -> String {
    ROCKING
        .replace("contact = \"roller\"", "contact = \"flat\"\noffset = 3")
        .replace("roller_radius = \"r_r\"\n", "")
}

/// A steep rise on a small base circle: undercut and too steep.
fn steep() -> Model {
    let text = GROOVE
        .lines()
        .filter(|l| !l.trim_start().starts_with("mm = "))
        .map(|l| {
            if l.starts_with("lift = ") {
                "lift = { segments = [ { end_deg = 40, lift_mm = 15, law = \"cycloidal\" }, { end_deg = 80, lift_mm = 15 }, \
                 { end_deg = 200, lift_mm = 0, law = \"cycloidal\" }, { end_deg = 360, lift_mm = 0 } ] }"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    Model::from_toml_str(&text, "steep.toml").unwrap()
}

#[test]
fn both_examples_solve_and_their_analogs_equal_finite_differences() {
    for text in [ROCKING.to_string(), GROOVE.to_string(), flat_rocking()] {
        let m = model(&text);
        let t = cycle(&m, &[], None);
        let h = 0.5f64.to_radians();
        for axis in ["x", "y"] {
            let pos = t.column(&format!("R.{axis}_mm")).unwrap();
            let d1 = t.column(&format!("R.d{axis}_dphi_mm_per_rad")).unwrap();
            let d2 = t.column(&format!("R.d2{axis}_dphi2_mm_per_rad2")).unwrap();
            let n = pos.len();
            // Where a motion law starts, its third derivative jumps: a
            // central difference smears it over the step, so the second
            // analog is compared within 2 % of its largest value.
            let d2_scale = d2.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for k in 0..n {
                let (a, b) = (pos[(k + n - 1) % n], pos[(k + 1) % n]);
                let fd1 = (b - a) / (2.0 * h);
                let fd2 = (b - 2.0 * pos[k] + a) / (h * h);
                assert!(
                    (d1[k] - fd1).abs() < 2e-3 * (1.0 + fd1.abs()),
                    "{} {axis} at {k}: {} vs {fd1}",
                    m.name(),
                    d1[k]
                );
                assert!(
                    (d2[k] - fd2).abs() <= 0.02 * d2_scale + 1e-9,
                    "{} {axis} at {k}: {} vs {fd2}",
                    m.name(),
                    d2[k]
                );
            }
        }
        let c = cross_check(&m, &m.defaults(), 1.0).unwrap();
        assert!(c.max_deviation_mm < 1e-9, "{}: {c:?}", m.name());
    }
}

#[test]
fn a_rocking_flat_face_is_checked_like_a_roller() {
    // Its face rests on the cam's base circle at zero lift, and the checks
    // give a pressure angle and a convex profile; a steep swing on a small
    // base circle asks for a concave profile, which a flat face cannot
    // follow.
    let m = model(&flat_rocking());
    let t = cycle(&m, &[], None);
    assert!(t.cams[0].checks_ok(), "{:?}", t.cams);
    let p = check(&t, "cam_pressure");
    assert!(p.value > 0.0 && p.value < 45.0, "{p:?}");
    let c = check(&t, "cam_curvature");
    assert!(
        c.value > 0.0 && c.message.contains("the profile under the flat face"),
        "{c:?}"
    );
    let steep = cycle(&m, &[("rise", 16.0), ("r_b", 6.0)], None);
    let c = check(&steep, "cam_curvature");
    assert!(!c.ok && c.message.contains("a flat face cannot follow it"), "{c:?}");
    // A face too far from its pivot to reach the base circle: no assembly,
    // named.
    let far = flat_rocking().replace("offset = 3", "offset = 80");
    let e = eval::run_cycle(&model(&far), &model(&far).defaults(), &CycleOptions::default()).unwrap_err();
    assert!(e.to_string().contains("cannot rest on the base circle"), "{e}");
}

#[test]
fn the_follower_rides_the_lift_it_is_given() {
    // Translating roller, axis 5 mm to the left of the cam's centre along
    // +y: x stays −5, y = √(26² − 5²) + s(δ); the table's 8 mm at 150°.
    let m = model(GROOVE);
    let t = cycle(&m, &[], None);
    let (phi, x, y) = (
        t.column("phi_deg").unwrap(),
        t.column("R.x_mm").unwrap(),
        t.column("R.y_mm").unwrap(),
    );
    let y0 = (26.0f64 * 26.0 - 25.0).sqrt();
    for k in 0..phi.len() {
        assert!((x[k] + 5.0).abs() < 1e-9);
        if phi[k] == 150.0 || phi[k] == 180.0 {
            assert!((y[k] - y0 - 8.0).abs() < 1e-9, "{} {}", phi[k], y[k]);
        }
        if phi[k] == 0.0 {
            assert!((y[k] - y0).abs() < 1e-9);
        }
    }
    // Rocking: the arm keeps its length and the swing reaches the rise.
    let m = model(ROCKING);
    let t = cycle(&m, &[], None);
    let (x, y) = (t.column("R.x_mm").unwrap(), t.column("R.y_mm").unwrap());
    let angle: Vec<f64> = x
        .iter()
        .zip(y)
        .map(|(x, y)| (y - 20.0).atan2(x - 45.0).to_degrees())
        .collect();
    for (x, y) in x.iter().zip(y) {
        assert!((((x - 45.0).powi(2) + (y - 20.0).powi(2)).sqrt() - 35.0).abs() < 1e-9);
    }
    let swing = angle.iter().cloned().fold(f64::MIN, f64::max) - angle.iter().cloned().fold(f64::MAX, f64::min);
    assert!((swing - 12.0).abs() < 1e-6, "{swing}");
}

#[test]
fn the_examples_pass_their_cam_checks() {
    let t = cycle(&model(ROCKING), &[], None);
    assert_eq!(t.cams.len(), 1);
    assert!(t.cams[0].checks_ok(), "{:?}", t.cams);
    assert_eq!(check(&t, "cam_pressure").limit, [None, Some(45.0)]);
    // The model's own speed (1000 rpm) judges the spring.
    assert!(check(&t, "follower_contact").value > 0.0);
    let t = cycle(&model(GROOVE), &[], None);
    assert!(t.cams[0].checks_ok(), "{:?}", t.cams);
    assert_eq!(check(&t, "cam_pressure").limit, [None, Some(30.0)]);
    // A groove holds the roller: no spring to check.
    assert!(t.cams[0].checks.iter().all(|c| c.name != "follower_contact"));
}

#[test]
fn a_spring_too_weak_for_the_speed_lets_the_follower_jump() {
    let m = model(ROCKING);
    let slow = cycle(&m, &[], Some(1000.0));
    let fast = cycle(&m, &[], Some(3000.0));
    let (s, f) = (check(&slow, "follower_contact"), check(&fast, "follower_contact"));
    assert!(s.ok && !f.ok, "{s:?} {f:?}");
    assert!(f.message.contains("leaves the cam"), "{}", f.message);
    // The inertia force grows as the speed squared: N(3000) − F_spring =
    // 9 × (N(1000) − F_spring) at the same φ, so the least force falls.
    assert!(f.value < s.value - 40.0);
}

#[test]
fn the_spring_holds_up_to_the_speed_it_names() {
    // The message names the highest speed the spring holds; just under it
    // the check passes with little force left, just over it it fails.
    let m = model(ROCKING);
    let at_1000 = cycle(&m, &[], Some(1000.0));
    let c = check(&at_1000, "follower_contact");
    let limit: f64 = c
        .message
        .split("holds it up to ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("{}", c.message));
    assert!((1000.0..3000.0).contains(&limit), "{limit}");
    let (under, over) = (cycle(&m, &[], Some(limit * 0.99)), cycle(&m, &[], Some(limit * 1.01)));
    let (under, over) = (check(&under, "follower_contact"), check(&over, "follower_contact"));
    assert!(under.ok && !over.ok, "{under:?} {over:?}");
    assert!(under.value < 0.1 * c.value.max(1.0), "{under:?}");
    // Without a speed the check is not judged but still names the limit.
    let unset = cycle(&model(&ROCKING.replace("rpm = 1000\n", "")), &[], None);
    let none = check(&unset, "follower_contact");
    assert!(
        none.ok && none.message.contains(&format!("up to {limit:.0} rpm")),
        "{}",
        none.message
    );
}

#[test]
fn a_sweep_reads_each_cams_figures() {
    // The figures a sweep tabulates are the checks' values and the limit
    // speed, named after the group.
    let t = cycle(&model(ROCKING), &[], None);
    let figures = stitchkin::study::figures::figures(&t);
    let get = |name: &str| {
        figures
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| *v)
            .unwrap_or_else(|| panic!("{name} not in {figures:?}"))
    };
    let c = &t.cams[0];
    assert_eq!(
        get(&format!("{}.max_pressure_deg", c.group)),
        check(&t, "cam_pressure").value
    );
    assert_eq!(
        get(&format!("{}.min_profile_radius_mm", c.group)),
        check(&t, "cam_curvature").value
    );
    assert_eq!(
        get(&format!("{}.min_contact_force_n", c.group)),
        check(&t, "follower_contact").value
    );
    assert_eq!(get(&format!("{}.limit_rpm", c.group)), c.limit_rpm.unwrap());
    // A groove holds its roller at any speed: no contact figures.
    let g = cycle(&model(GROOVE), &[], None);
    let names: Vec<String> = stitchkin::study::figures::figures(&g)
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    assert!(
        names
            .iter()
            .all(|n| !n.ends_with("limit_rpm") && !n.ends_with("contact_force_n")),
        "{names:?}"
    );
}

#[test]
fn the_limit_speed_is_where_the_spring_just_decelerates_the_follower() {
    use stitchkin::eval::cams::limit_rpm;
    // F = 10 N, a = −0.01 m/rad², m = 0.1 kg: ω² = 10/(0.1·0.01) = 10⁴.
    let rpm = limit_rpm(0.1, &[10.0, 12.0], &[-0.01, 0.02]).unwrap();
    assert!((rpm - 100.0 * 60.0 / std::f64::consts::TAU).abs() < 1e-9, "{rpm}");
    assert_eq!(limit_rpm(0.1, &[0.0, 12.0], &[0.01, 0.02]), Some(0.0));
    assert_eq!(limit_rpm(0.1, &[5.0, 12.0], &[0.01, 0.02]), None);
    assert_eq!(limit_rpm(0.0, &[5.0], &[-1.0]), None);
}

#[test]
fn a_small_base_circle_under_a_steep_rise_is_undercut_and_too_steep() {
    let m = steep();
    let t = cycle(&m, &[("e", 0.0), ("r_b", 8.0)], None);
    let c = check(&t, "cam_curvature");
    assert!(!c.ok && c.value < 0.0, "{c:?}");
    assert!(
        c.message.contains("undercut") && c.message.contains("cam angle"),
        "{}",
        c.message
    );
    let p = check(&t, "cam_pressure");
    assert!(!p.ok && p.value > 30.0, "{p:?}");
    // A base circle large enough for the same rise passes the curvature.
    let t = cycle(&m, &[("e", 0.0), ("r_b", 60.0)], None);
    assert!(check(&t, "cam_curvature").ok, "{:?}", check(&t, "cam_curvature"));
}

#[test]
fn cam_follower_mistakes_are_named_with_their_fix() {
    let bad = |from: &str, to: &str| {
        let text = ROCKING.replacen(from, to, 1);
        assert_ne!(text, ROCKING, "{from}");
        match Model::from_toml_str(&text, "bad.toml") {
            Ok(_) => panic!("{to} loads"),
            Err(e) => format!("{} {}", e.message, e.help.clone().unwrap_or_default()),
        }
    };
    let e = bad("law = \"cycloidal\"", "law = \"cycloid\"");
    assert!(e.contains("unknown motion law") && e.contains("polynomial_345"), "{e}");
    let e = bad("roller_radius = \"r_r\"\n", "");
    assert!(e.contains("roller's radius"), "{e}");
    let e = bad("pivot = \"O3\"\n", "");
    assert!(e.contains("pivot"), "{e}");
    let e = bad("lift_deg = \"rise\", law", "lift_mm = 3, law");
    assert!(e.contains("lift is in deg"), "{e}");
    let e = bad("{ end_deg = 360, lift_deg = 0 }", "{ end_deg = 350, lift_deg = 0 }");
    assert!(e.contains("360"), "{e}");
    let e = bad("mass_kg = 0.05", "mass_kg = 0");
    assert!(e.contains("mass"), "{e}");
    let g = GROOVE.replacen("mm = [0, 0.5", "mm = [-1, 0.5", 1);
    let e = Model::from_toml_str(&g, "bad.toml").unwrap_err();
    assert!(e.message.contains("below the base circle"), "{}", e.message);
    // An axis offset beyond the base circle plus roller has no assembly.
    let m = model(GROOVE);
    let mut p = m.defaults();
    m.set(&mut p, "r_b", 1.0).unwrap();
    m.set(&mut p, "e", 8.0).unwrap();
    let e = eval::run_cycle(&m, &p, &CycleOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("outside the base circle"), "{e}");
}

#[test]
fn every_check_of_a_cycle_includes_the_cams_and_a_failed_one_fails_the_setting() {
    let m = model(ROCKING);
    let slow = cycle(&m, &[], None);
    let names: Vec<&str> = slow.all_checks().map(|c| c.name).collect();
    assert_eq!(names, ["cam_pressure", "cam_curvature", "follower_contact"]);
    assert!(slow.all_checks().all(|c| c.thread == "feed_arm"));
    assert!(slow.checks_ok());
    let fast = cycle(&m, &[], Some(3000.0));
    assert!(!fast.checks_ok());
    // A sweep's figures: the cam's own and the cycle's.
    let figure = |t: &CycleTable, n: &str| {
        stitchkin::study::figures::figures(t)
            .into_iter()
            .find(|(k, _)| k == n)
            .unwrap_or_else(|| panic!("no figure {n}"))
            .1
    };
    assert_eq!(figure(&slow, "checks.ok"), 1.0);
    assert_eq!(figure(&slow, "feed_arm.checks_ok"), 1.0);
    assert_eq!(figure(&fast, "checks.ok"), 0.0);
    assert_eq!(figure(&fast, "feed_arm.checks_ok"), 0.0);
    // The JSON of a cycle carries them.
    let json = serde_json::to_value(&fast).unwrap();
    assert_eq!(json["cams"][0]["group"], "feed_arm");
    assert_eq!(json["cams"][0]["checks"][2]["ok"], false);
}

#[test]
fn a_sweep_over_a_cam_judges_its_checks_in_checks_ok() {
    use stitchkin::study::design::{Design, Sweep, Vary};
    use stitchkin::study::sweep::{Evaluator, SweepPlan};
    let m = model(ROCKING);
    let mut base = m.defaults();
    m.set(&mut base, "rise", 16.0).unwrap();
    // A 16° swing on a 12 mm base circle is too steep; on 18 mm it passes.
    let sweep = Sweep::new(vec![Vary::parse(&m, "r_b=12:18:2").unwrap()], Design::Grid).unwrap();
    let plan = SweepPlan::new(&m, &base, &sweep, None, 1.0).unwrap();
    let k = plan
        .names
        .iter()
        .position(|n| n == "checks.ok")
        .expect("checks.ok is a default figure");
    let mut ev = Evaluator::new(plan.job(&m, &base, &sweep));
    let ok: Vec<Option<f64>> = (0..2).map(|i| ev.evaluate(i).figures[k]).collect();
    assert_eq!(ok, [Some(0.0), Some(1.0)]);
}

#[test]
fn the_report_lists_the_cam_checks() {
    use stitchkin::jobs::report::{ReportOptions, render};
    let m = model(&ROCKING.replace("rpm = 1000", "rpm = 3000"));
    let opts = ReportOptions {
        animate: false,
        ..Default::default()
    };
    let html = render(&m, &m.defaults(), &opts).unwrap();
    assert!(html.contains("id=\"checks\""), "no checks section");
    for name in ["cam_pressure", "cam_curvature", "follower_contact"] {
        assert!(html.contains(name), "the report does not list {name}");
    }
    assert!(html.contains("FAIL"));
}
