//! Cam synthesis for a follower (`stitchkin cam --follower`): the lift of
//! a translating roller pusher that carries a looper thread between two
//! guides (examples/cam-follower-thread.toml), from the Altin lower
//! thread's required take-up P' written as a curve
//! (examples/altin504-lower-pprime.csv).

use stitchkin::model::Model;
use stitchkin::study::cam_synthesis::Target;
use stitchkin::study::follower_synthesis::{FollowerOptions, FollowerSynthesis, synthesise_follower};
use stitchkin::thread::measured::parse_curve_csv;

const MODEL: &str = include_str!("../../../../examples/cam-follower-thread.toml");
const PPRIME: &str = include_str!("../../../../examples/altin504-lower-pprime.csv");

fn model() -> Model {
    Model::from_toml_str(MODEL, "cam-follower-thread.toml").unwrap()
}

fn target() -> Target {
    Target::from_curve(&parse_curve_csv(PPRIME, "altin504-lower-pprime.csv").unwrap()).unwrap()
}

fn synth(smooth_deg: f64) -> FollowerSynthesis {
    let m = model();
    let mut o = FollowerOptions::new("pusher", "lower", target());
    o.smooth_deg = smooth_deg;
    synthesise_follower(&m, &m.defaults(), &o).unwrap_or_else(|e| panic!("synthesis failed: {e}"))
}

/// The example with the group's base_radius and lift replaced by `snippet`.
fn pasted(snippet: &str) -> Model {
    let start = MODEL.find("base_radius = \"r_b\"").unwrap();
    let lift = MODEL.find("lift = { angle_deg").unwrap();
    let end = lift + MODEL[lift..].find("}\n").unwrap() + 2;
    let text = format!(
        "{}{}{}",
        &MODEL[..start],
        MODEL[start..lift].replace("base_radius = \"r_b\"\n", ""),
        &MODEL[end..]
    )
    .replacen("out = \"R\"\n", &format!("out = \"R\"\n{snippet}"), 1);
    Model::from_toml_str(&text, "pasted.toml").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

#[test]
fn the_lift_gives_the_target_and_passes_the_checks() {
    // Unsmoothed: the take-up is the target at every knot, but the fall
    // after the draw-in bends the pitch curve tighter than the roller.
    let raw = synth(0.0);
    assert!(raw.verify.max_err_knots_mm < 1e-9, "{}", raw.verify.max_err_knots_mm);
    assert!(raw.score().unwrap() > 99.9);
    assert!(!raw.checks.curvature_ok && raw.checks.min_curvature_radius_mm < 0.0);
    let text = stitchkin::output::text::follower_cam::summary(&raw);
    assert!(text.contains("UNDERCUT"), "{text}");
    // Smoothed over 10°: score ≥ 90, both checks pass.
    let s = synth(10.0);
    let score = s.score().unwrap();
    assert!((90.0..100.0).contains(&score), "{score}");
    assert!(s.checks.pressure_ok && s.checks.curvature_ok, "{:?}", s.checks);
    assert!(s.checks.max_pressure_deg < 20.0 && s.checks.min_curvature_radius_mm > 3.0);
    // The lift starts at 0, and the base circle moves the follower's
    // zero-lift place to where the least lift put it: the pitch radius at
    // the least lift is the base circle plus the roller.
    assert_eq!(s.lift_range[0], 0.0);
    assert!(
        (s.base_radius_mm - (30.0 + s.least_lift)).abs() < 1e-9,
        "{}",
        s.base_radius_mm
    );
    let least_pitch = s
        .profile
        .iter()
        .map(|p| p.pitch_mm[0].hypot(p.pitch_mm[1]))
        .fold(f64::MAX, f64::min);
    assert!(
        (least_pitch - (s.base_radius_mm + s.roller_mm)).abs() < 1e-3,
        "{least_pitch}"
    );
    // Pasted into the model, the loader takes it and the model's own cam
    // checks and take-up agree with the synthesis.
    let m = pasted(&stitchkin::output::text::follower_cam::toml_snippet(&s));
    let t = stitchkin::eval::run_cycle(
        &m,
        &m.defaults(),
        &stitchkin::eval::CycleOptions {
            step_deg: 1.0,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(t.cams.iter().all(|c| c.checks_ok()), "{:?}", t.cams);
    let checks = &t.cams[0].checks;
    assert!((checks[0].value - s.checks.max_pressure_deg).abs() < 1e-6, "{checks:?}");
    assert!(
        (checks[1].value - s.checks.min_curvature_radius_mm).abs() < 1e-6,
        "{checks:?}"
    );
    // Its take-up over 1° of φ spans what the synthesis verified.
    let col = t.column("lower.P_mm").unwrap();
    let span = |v: &[f64]| v.iter().fold([f64::MAX, f64::MIN], |m, x| [m[0].min(*x), m[1].max(*x)]);
    let (a, b) = (span(col), span(&s.verify.p_after_mm));
    assert!((a[0] - b[0]).abs() < 0.05 && (a[1] - b[1]).abs() < 0.05, "{a:?} {b:?}");
}

#[test]
fn the_dxf_is_a_closed_profile() {
    let s = synth(10.0);
    let dxf = stitchkin::output::text::follower_cam::dxf(&s);
    let lines: Vec<&str> = dxf.lines().collect();
    let pairs: Vec<(&str, &str)> = lines.chunks(2).map(|c| (c[0].trim(), c[1].trim())).collect();
    let poly = pairs.iter().position(|p| *p == ("0", "POLYLINE")).unwrap();
    // The closed flag (70 = 1) on the polyline, and its vertices.
    let end = pairs.iter().position(|p| *p == ("0", "SEQEND")).unwrap();
    let head_end = poly + pairs[poly..].iter().position(|p| *p == ("0", "VERTEX")).unwrap();
    assert!(pairs[poly..head_end].contains(&("70", "1")));
    let xs: Vec<f64> = pairs[head_end..end]
        .iter()
        .filter(|p| p.0 == "10")
        .map(|p| p.1.parse().unwrap())
        .collect();
    let ys: Vec<f64> = pairs[head_end..end]
        .iter()
        .filter(|p| p.0 == "20")
        .map(|p| p.1.parse().unwrap())
        .collect();
    assert_eq!(xs.len(), 720);
    assert_eq!(ys.len(), 720);
    // Closing it back to the first vertex is a step like any other: the
    // outline goes round once without a gap.
    let step = |i: usize, j: usize| (xs[j] - xs[i]).hypot(ys[j] - ys[i]);
    let longest = (0..719).map(|i| step(i, i + 1)).fold(0.0, f64::max);
    assert!(
        step(719, 0) <= 1.5 * longest && longest < 1.0,
        "{} {longest}",
        step(719, 0)
    );
    let turn: f64 = (0..720)
        .map(|i| {
            let j = (i + 1) % 720;
            let d = ys[j].atan2(xs[j]) - ys[i].atan2(xs[i]);
            (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
        })
        .sum();
    assert!((turn.abs() - std::f64::consts::TAU).abs() < 1e-9, "{turn}");
}

#[test]
fn bad_input_is_refused_with_the_place_and_the_fix() {
    let m = model();
    let e = synthesise_follower(&m, &m.defaults(), &FollowerOptions::new("nope", "lower", target())).unwrap_err();
    assert!(
        e.to_string().contains("no cam_follower group `nope`") && e.help().unwrap().contains("pusher"),
        "{e}"
    );
    let e = synthesise_follower(&m, &m.defaults(), &FollowerOptions::new("pusher", "upper", target())).unwrap_err();
    assert!(e.to_string().contains("no thread path `upper`"), "{e}");
    let e = synthesise_follower(
        &m,
        &m.defaults(),
        &FollowerOptions::new("pusher", "lower", Target::Required),
    )
    .unwrap_err();
    assert!(e.to_string().contains("no [stitch]"), "{e}");
}

#[test]
fn a_rocking_arm_gets_its_own_lift_back() {
    // The rocking example with a thread over its eyelet E: the take-up its
    // own lift gives, as the target, gives back that lift (12° rise) and
    // the base circle (18 mm); with a flat face 3 mm from the pivot
    // instead of the roller, the same.
    let roller = include_str!("../../../../examples/cam-rocking-roller.toml")
        .replace("O3 = [45, 20]\n", "O3 = [45, 20]\nG1 = [60, 80]\nG2 = [100, 70]\n")
        .replace(
            "[output]",
            "[thread]\n[[thread.paths]]\nname = \"t\"\nnodes = [\"G1\", \"E\", \"G2\"]\n\n[output]",
        );
    let flat = roller
        .replace("contact = \"roller\"", "contact = \"flat\"\noffset = 3")
        .replace("roller_radius = \"r_r\"\n", "");
    for text in [roller, flat] {
        own_lift_back(&text);
    }
}

fn own_lift_back(text: &str) {
    let m = Model::from_toml_str(text, "rock.toml").unwrap();
    let t = stitchkin::eval::run_cycle(
        &m,
        &m.defaults(),
        &stitchkin::eval::CycleOptions {
            step_deg: 2.0,
            ..Default::default()
        },
    )
    .unwrap();
    let target = Target::Curve {
        phi_deg: t.column("phi_deg").unwrap().to_vec(),
        p_mm: t.column("t.P_mm").unwrap().to_vec(),
        source: "own".into(),
    };
    let mut o = FollowerOptions::new("feed_arm", "t", target);
    o.points = 180;
    let s = synthesise_follower(&m, &m.defaults(), &o).unwrap();
    assert_eq!(s.lift_unit, "deg");
    assert!((s.lift_range[1] - 12.0).abs() < 1e-4, "{:?}", s.lift_range);
    assert!((s.base_radius_mm - 18.0).abs() < 1e-4, "{}", s.base_radius_mm);
    assert!(s.verify.max_err_knots_mm < 1e-9 && s.score().unwrap() > 99.9);
    assert!(s.checks.pressure_ok && s.checks.curvature_ok);
}

#[test]
fn the_least_passing_base_circle_keeps_the_take_up_and_passes_the_checks() {
    // Unsmoothed, the lift undercuts a 24.9 mm base circle; the search
    // finds the base circle that passes, with the cam's centre moved back
    // along the follower's axis (here +y) so the follower keeps its place.
    let raw = synth(0.0);
    assert!(!raw.checks.curvature_ok);
    let advice = raw.base_circle_needed.clone().expect("a base circle is advised");
    assert!(advice.checks.pressure_ok && advice.checks.curvature_ok, "{advice:?}");
    // The axis passes through the centre (no offset): the centre moves
    // back by the growth of the base circle.
    assert!((advice.move_back_mm - (advice.base_radius_mm - raw.base_radius_mm)).abs() < 1e-9);
    let text = stitchkin::output::text::follower_cam::summary(&raw);
    assert!(text.contains("least base circle passing both"), "{text}");
    // Made so in the model (base circle and centre), the checks pass and
    // the take-up is the one synthesised; 0.1 mm less fails.
    let run = |base: f64| {
        cycle_of(
            &pasted(&snippet_with_base(&raw, base))
                .text()
                .replace("O1 = [0, 0]", &format!("O1 = [0, {}]", raw.base_radius_mm - base)),
        )
    };
    let t = run(advice.base_radius_mm);
    assert!(t.cams.iter().all(|c| c.checks_ok()), "{:?}", t.cams);
    assert_same_take_up(&t, &raw);
    let less = run(advice.base_radius_mm - 0.1);
    assert!(!less.cams.iter().all(|c| c.checks_ok()), "{:?}", less.cams);
}

#[test]
fn a_translating_flat_face_gets_a_lift_and_its_envelope() {
    // The pusher with a flat face (base circle 36 mm, where the roller's
    // centre stood): the target is met at the knots; the sharp fall after
    // the draw-in asks for a concave profile unless smoothed over 20°;
    // the profile is the envelope of the face (every profile point at
    // r_b + s from the centre along the axis at its cam angle, or within).
    let text = MODEL
        .replace("contact = \"roller\"", "contact = \"flat\"")
        .replace("roller_radius = \"r_r\"\n", "")
        .replace("r_b = { value = 30,", "r_b = { value = 36,");
    let m = Model::from_toml_str(&text, "flat.toml").unwrap();
    let synth = |smooth_deg: f64| {
        let mut o = FollowerOptions::new("pusher", "lower", target());
        o.smooth_deg = smooth_deg;
        synthesise_follower(&m, &m.defaults(), &o).unwrap()
    };
    let raw = synth(0.0);
    assert!(raw.verify.max_err_knots_mm < 1e-9 && raw.score().unwrap() > 99.9);
    assert_eq!(raw.contact, "flat");
    assert!(!raw.checks.curvature_ok);
    let text = stitchkin::output::text::follower_cam::summary(&raw);
    assert!(
        text.contains("a flat face cannot follow it") && text.contains("least base circle passing both"),
        "{text}"
    );
    let s = synth(20.0);
    assert!(
        s.checks.curvature_ok && s.checks.max_pressure_deg == 0.0,
        "{:?}",
        s.checks
    );
    assert!(s.score().unwrap() > 98.0);
    // The envelope: the face at cam angle δ is the line at r_b + s(δ)
    // along the axis (+y turned back by δ); no profile point lies beyond.
    for p in s.profile.iter().step_by(36) {
        let d = p.cam_deg.to_radians();
        let n = (d.sin(), d.cos()); // the axis (+y) turned back by δ
        let h = s.base_radius_mm + p.lift;
        let beyond = s
            .profile
            .iter()
            .map(|q| n.0 * q.profile_mm[0] + n.1 * q.profile_mm[1] - h)
            .fold(f64::MIN, f64::max);
        assert!(beyond < 1e-2 && beyond > -1e-6, "{}: {beyond}", p.cam_deg);
    }
}

/// Seed 004's variant 5 (a rocking roller arm) with an 8 mm roller: the
/// unsmoothed lift undercuts; the least base circle that passes comes with
/// the cam's centre moved back from the roller's rest point through the
/// centre, which keeps the arm's angles. Made so in the model, the checks
/// pass and the take-up is the one synthesised; 0.1 mm less fails.
#[test]
fn a_rocking_followers_least_passing_base_circle_keeps_the_arms_angles() {
    const V5: &str = include_str!("../../../../examples/seed004-variants/variant5.toml");
    let text = V5.replace("r_r = { value = 5,", "r_r = { value = 8,");
    let m = Model::from_toml_str(&text, "variant5-r8.toml").unwrap();
    let o = FollowerOptions::new("feed_arm", "lower", target());
    let raw = synthesise_follower(&m, &m.defaults(), &o).unwrap();
    assert!(!raw.checks.curvature_ok, "{:?}", raw.checks);
    let advice = raw.base_circle_needed.clone().expect("a base circle is advised");
    assert!(advice.checks.pressure_ok && advice.checks.curvature_ok, "{advice:?}");
    assert!(advice.base_radius_mm > raw.base_radius_mm);
    let [dx, dy] = advice.move_mm;
    assert!((dx.hypot(dy) - advice.move_back_mm).abs() < 1e-12);
    let text_out = stitchkin::output::text::follower_cam::summary(&raw);
    assert!(
        text_out.contains("from the roller's rest point through the centre"),
        "{text_out}"
    );
    // The model with the synthesised lift, the base circle `base` and the
    // cam's centre O1 moved by `shift`.
    let run = |base: f64, shift: [f64; 2]| {
        let start = text.find("base_radius = ").unwrap();
        let end = start + text[start..].find("] }\n").unwrap() + 4;
        cycle_of(
            &format!("{}{}{}", &text[..start], snippet_with_base(&raw, base), &text[end..])
                .replace("O1 = [0, 0]", &format!("O1 = [{}, {}]", shift[0], shift[1])),
        )
    };
    // The profile's checks (the unsmoothed lift's spring would still need
    // a groove: `follower_contact` is not the base circle's to mend).
    let profile_ok =
        |t: &stitchkin::eval::CycleTable| t.cam_checks().filter(|c| c.name != "follower_contact").all(|c| c.ok);
    let t = run(advice.base_radius_mm, advice.move_mm);
    assert!(profile_ok(&t), "{:?}", t.cams);
    assert_same_take_up(&t, &raw);
    let scale = (advice.base_radius_mm - 0.1 - raw.base_radius_mm) / (advice.base_radius_mm - raw.base_radius_mm);
    let less = run(advice.base_radius_mm - 0.1, [dx * scale, dy * scale]);
    assert!(!profile_ok(&less), "{:?}", less.cams);
}

/// The synthesised lift's TOML with the base circle `base`.
fn snippet_with_base(raw: &FollowerSynthesis, base: f64) -> String {
    stitchkin::output::text::follower_cam::toml_snippet(raw).replace(
        &format!("base_radius = {}", stitchkin::format::fmt_num(raw.base_radius_mm)),
        &format!("base_radius = {base}"),
    )
}

/// The cycle of the model `text` every 1°.
fn cycle_of(text: &str) -> stitchkin::eval::CycleTable {
    let m = Model::from_toml_str(text, "moved.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
    stitchkin::eval::run_cycle(
        &m,
        &m.defaults(),
        &stitchkin::eval::CycleOptions {
            step_deg: 1.0,
            ..Default::default()
        },
    )
    .unwrap()
}

/// The path `lower`'s take-up over the cycle spans what the synthesis
/// verified, to 0.05 mm.
fn assert_same_take_up(t: &stitchkin::eval::CycleTable, raw: &FollowerSynthesis) {
    let span = |v: &[f64]| v.iter().fold([f64::MAX, f64::MIN], |m, x| [m[0].min(*x), m[1].max(*x)]);
    let (a, b) = (span(t.column("lower.P_mm").unwrap()), span(&raw.verify.p_after_mm));
    assert!((a[0] - b[0]).abs() < 0.05 && (a[1] - b[1]).abs() < 0.05, "{a:?} {b:?}");
}
