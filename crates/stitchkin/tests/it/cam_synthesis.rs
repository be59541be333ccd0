//! Cam synthesis (`stitchkin cam`): the inverse of seed 004
//! §2.5's cam feed, on the altin504 preset's lower-looper thread (a disc cam
//! with `contact = "offset"`) and on the looper cam of model-format
//! Example 11.

use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::{Model, Params};
use stitchkin::output::{drawing, text};
use stitchkin::study::cam_synthesis::{CamOptions, CamSynthesis, Target, synthesise, take_up_with_profile};
use stitchkin::thread::cam::Profile;
use stitchkin::thread::measured::parse_curve_csv;

fn altin504() -> (Model, Params) {
    let m = Model::preset("altin504").unwrap();
    let p = m.defaults();
    (m, p)
}

fn synth(model: &Model, opts: &CamOptions) -> CamSynthesis {
    synthesise(model, &model.defaults(), opts).unwrap_or_else(|e| panic!("synthesis failed: {e}"))
}

/// The error message and its help.
fn err(model: &Model, opts: &CamOptions) -> String {
    match synthesise(model, &model.defaults(), opts) {
        Ok(_) => panic!("should fail: {opts:?}"),
        Err(stitchkin::Error::Param(p)) => format!("{} | {}", p.message, p.help.unwrap_or_default()),
        Err(e) => e.to_string(),
    }
}

/// A path's own take-up P(φ) on the 1° grid of the model, as a target curve
/// (sorted within [0, 360)).
fn own_take_up(model: &Model, path: &str) -> Target {
    let t = run_cycle(
        model,
        &model.defaults(),
        &CycleOptions {
            step_deg: 1.0,
            rpm: None,
            analogs: false,
            points: Some(Vec::new()),
            lean: true,
        },
    )
    .unwrap();
    let mut v: Vec<(f64, f64)> = t
        .column("phi_deg")
        .unwrap()
        .iter()
        .map(|x| x.rem_euclid(360.0))
        .zip(t.column(&format!("{path}.P_mm")).unwrap().iter().copied())
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    Target::Curve {
        phi_deg: v.iter().map(|x| x.0).collect(),
        p_mm: v.iter().map(|x| x.1).collect(),
        source: format!("{path}.P_mm"),
    }
}

/// Model-format Example 11: a disc cam (r = 10, e = 6) on the main shaft
/// between two guides, fed by seed 004's offset contact (`seed`) and by the
/// exact one (`taut`); `extra` goes into [thread].
fn looper_cam(extra: &str) -> Model {
    let text = format!(
        r#"
[model]
name = "looper_cam"
[parameters]
r = {{ value = 10, unit = "mm" }}
e = {{ value = 6, unit = "mm" }}
[points]
O = [0, 0]
G1 = [-18, 6]
G2 = [18, 6]
[[drivers]]
type = "crank"
name = "cam_shaft"
center = "O"
out = "D"
radius = "e"
[[cams]]
name = "feed"
center = "O"
marker = "D"
disc = {{ radius_mm = "r", eccentricity_mm = "e" }}
[thread]
{extra}
[[thread.paths]]
name = "seed"
nodes = ["G1", {{ cam = "feed", contact = "offset", gamma_deg = 30 }}, "G2"]
[[thread.paths]]
name = "taut"
nodes = ["G1", {{ cam = "feed", wrap = "cw" }}, "G2"]
[[thread.paths]]
name = "straight"
nodes = ["G1", "G2"]
"#
    );
    Model::from_toml_str(&text, "looper_cam.toml").unwrap()
}

#[test]
fn round_trip_reproduces_the_disc() {
    // Target = the take-up altin504's disc cam gives its lower thread: the
    // synthesised profile must be that disc, and give back that take-up.
    let (m, p) = altin504();
    let s = synth(&m, &CamOptions::new("lower", own_take_up(&m, "lower")));
    let disc = Profile::disc(12.0, 5.2); // cam_r, e_l of the preset
    let radius_err = s
        .knots
        .iter()
        .map(|k| (k.radius_mm - disc.rho(k.theta_deg.to_radians())).abs())
        .fold(0.0, f64::max);
    println!(
        "round trip: max radius error {radius_err:.3e} mm, max |P - target| {:.3e} mm at the knots",
        s.verify.max_err_knots_mm
    );
    assert!(radius_err < 1e-9, "radius error {radius_err}");
    assert!(s.verify.max_err_knots_mm < 1e-9, "{}", s.verify.max_err_knots_mm);
    assert!(s.verify.max_err_between_mm < 1e-6, "{}", s.verify.max_err_between_mm);
    assert_eq!(s.knots.len(), 360);
    assert_eq!(s.target_shift_mm, 0.0);
    assert!((s.anchor_radius_mm - disc.rho(s.anchor_theta_deg.to_radians())).abs() < 1e-12);
    // Between the knots, against the disc's own take-up there.
    let mids: Vec<f64> = (0..360).map(|k| 175.35 + k as f64).collect();
    let want = take_up_with_profile(&m, &p, "lower", "cam_l", &disc, &mids).unwrap();
    let got = take_up_with_profile(&m, &p, "lower", "cam_l", &s.profile, &mids).unwrap();
    let between = want.iter().zip(&got).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    println!("round trip: max |P - P_disc| {between:.3e} mm between the knots");
    assert!(between < 1e-6, "{between}");
    // The disc is convex, its least radius r − e = 6.8 mm is above 3 mm, and
    // the upper thread's cam is shared by no other path.
    assert!(s.checks.convex && s.checks.min_radius_ok, "{:?}", s.checks);
    assert!(
        (s.checks.min_radius_mm - 6.8).abs() < 1e-3,
        "{}",
        s.checks.min_radius_mm
    );
    assert!(s.shared_with.is_empty() && s.notes.is_empty(), "{:?}", s.notes);
    // The disc's profile slope: atan(e sin θ / √(r² − e² sin² θ)) at most
    // asin(e/r) = 25.67°.
    assert!(
        (s.checks.max_slope_deg - (5.2f64 / 12.0).asin().to_degrees()).abs() < 0.05,
        "{}",
        s.checks.max_slope_deg
    );
}

#[test]
fn round_trip_under_the_feed_convention_with_a_coarse_grid() {
    // P = ξ − ξ(φ0) + ΔP (seed 001): the target's value at φ0 is ΔP, no shift.
    let m = looper_cam("convention = \"feed\"\nelongation_mm = 6");
    let mut o = CamOptions::new("seed", own_take_up(&m, "seed"));
    o.points = 72; // every 5°: the 1° target is interpolated between
    let s = synth(&m, &o);
    assert_eq!(s.knots.len(), 72);
    assert!(s.target_shift_mm.abs() < 1e-12, "{}", s.target_shift_mm);
    assert!(s.verify.max_err_knots_mm < 1e-9, "{}", s.verify.max_err_knots_mm);
    let disc = Profile::disc(10.0, 6.0);
    let radius_err = s
        .knots
        .iter()
        .map(|k| (k.radius_mm - disc.rho(k.theta_deg.to_radians())).abs())
        .fold(0.0, f64::max);
    assert!(radius_err < 1e-6, "{radius_err}");
    // A 5° spline through the disc is close to it between the knots too.
    assert!(s.verify.max_err_between_mm < 1e-2, "{}", s.verify.max_err_between_mm);
    // The cam also feeds `taut`, and that is said.
    assert_eq!(s.shared_with, vec!["taut".to_string()]);
}

#[test]
fn the_required_take_up_is_matched_and_the_checks_are_honest() {
    let (m, _) = altin504();
    let s = synth(&m, &CamOptions::new("lower", Target::Required));
    let (b, a, all) = (
        s.verify.match_before.as_ref().unwrap(),
        s.verify.match_after.as_ref().unwrap(),
        s.verify.match_after_all.as_ref().unwrap(),
    );
    println!(
        "altin504 lower: score {:.2} -> {:.2} (knots), {:.2} with the midpoints; RMS(P - P') {:.4} -> {:.2e} mm ({:.4}); max |P - P'| {:.2e} mm at the knots, {:.4} mm between (φ = {:.1}°); radius {:.3}..{:.3} mm",
        b.score.unwrap(),
        a.score.unwrap(),
        all.score.unwrap(),
        b.rms_d_mm,
        a.rms_d_mm,
        all.rms_d_mm,
        s.verify.max_err_knots_mm,
        s.verify.max_err_between_mm,
        s.verify.max_err_between_at_deg,
        s.radius_mm[0],
        s.radius_mm[1]
    );
    assert_eq!(s.thread.as_deref(), Some("lower"));
    // Before: the preset's 90.3 of `stitchkin match` (same 1° grid from φ0).
    assert!((b.score.unwrap() - 90.33).abs() < 0.1, "before {:?}", b.score);
    assert!((b.rms_d_mm - 1.5535).abs() < 2e-3, "{}", b.rms_d_mm);
    // After: exact at the knots (= the match grid).
    assert!(
        s.verify.max_err_knots_mm < 1e-9 && a.rms_d_mm < 1e-9,
        "{} {}",
        s.verify.max_err_knots_mm,
        a.rms_d_mm
    );
    assert!(a.score.unwrap() > 99.999);
    // P' has no step to follow: the lower thread's stitch is drawn through
    // its regulator over the 60° before its draw-in (270°…330°), so between
    // the knots the cam stays within a few hundredths of a mm.
    assert!(
        s.verify.max_err_between_mm < 0.05 && all.rms_d_mm < 1e-3,
        "{} {}",
        s.verify.max_err_between_mm,
        all.rms_d_mm
    );
    // The draw through the regulator starts at 270°: a kink of P' there
    // makes the profile steep and not convex; reported, not hidden. The
    // radius stays above 6 mm.
    let c = &s.checks;
    assert!(!c.convex && !c.not_convex_deg.is_empty());
    assert!(
        c.max_slope_deg > 60.0 && !c.contact_angle_ok && c.max_contact_angle_deg > 80.0,
        "{c:?}"
    );
    assert!((c.max_contact_angle_at_phi_deg - 270.9).abs() < 2.0, "{c:?}");
    assert!(c.min_radius_ok && c.min_radius_mm > 6.0);
    // The snippet pasted over the preset's disc gives the same match in a
    // plain model run (the loader's polar profile, `stitchkin match`), with
    // the regulator's window the synthesis assumed.
    let snippet = text::cam::toml_snippet(&s);
    let polar = &snippet[snippet.find("polar = ").unwrap()..];
    let text = super::support::assumed_text("altin504");
    let disc_line = "disc = { radius_mm = \"cam_r\", eccentricity_mm = \"e_l\" }\n";
    assert_eq!(text.matches(disc_line).count(), 1);
    let pasted = Model::from_toml_str(&text.replace(disc_line, polar), "altin504-synth.toml").unwrap();
    let t = run_cycle(
        &pasted,
        &pasted.defaults(),
        &CycleOptions {
            step_deg: 1.0,
            rpm: None,
            analogs: false,
            points: Some(Vec::new()),
            lean: true,
        },
    )
    .unwrap();
    let th = t
        .stitch
        .as_ref()
        .unwrap()
        .threads
        .iter()
        .find(|t| t.thread == "lower")
        .unwrap();
    let mm = th.mismatch.as_ref().unwrap();
    assert!(
        mm.rms_d_mm < 1e-6 && mm.score.unwrap() > 99.999,
        "{} {:?}",
        mm.rms_d_mm,
        mm.score
    );
    // The other threads are untouched.
    let up = t
        .stitch
        .as_ref()
        .unwrap()
        .threads
        .iter()
        .find(|t| t.thread == "upper")
        .unwrap();
    assert!((up.mismatch.as_ref().unwrap().score.unwrap() - 89.87).abs() < 0.1);
}

#[test]
fn smoothing_trades_the_match_for_a_gentler_profile() {
    let (m, _) = altin504();
    let mut prev: Option<CamSynthesis> = None;
    for sm in [0.0, 10.0, 30.0] {
        let mut o = CamOptions::new("lower", Target::Required);
        o.smooth_deg = sm;
        let s = synth(&m, &o);
        let a = s.verify.match_after.as_ref().unwrap();
        println!(
            "smooth {sm}°: score {:.2}, RMS {:.4} mm, slope {:.1}°, contact angle {:.1}°",
            a.score.unwrap(),
            a.rms_d_mm,
            s.checks.max_slope_deg,
            s.checks.max_contact_angle_deg
        );
        if let Some(p) = &prev {
            let pa = p.verify.match_after.as_ref().unwrap();
            assert!(a.rms_d_mm > pa.rms_d_mm, "smoothing more must cost match");
            assert!(
                s.checks.max_slope_deg < p.checks.max_slope_deg
                    && s.checks.max_contact_angle_deg < p.checks.max_contact_angle_deg
            );
            // The knots left the solved radii, and the verification says so.
            assert!(s.verify.max_err_knots_mm > 0.1);
            assert!(s.knots.iter().any(|k| (k.radius_mm - k.solved_mm).abs() > 0.1));
            // Still better than the disc.
            assert!(a.score.unwrap() > 92.0, "{:?}", a.score);
        }
        prev = Some(s);
    }
}

#[test]
fn a_shifted_target_and_an_anchor_radius() {
    // P = 1 + 1.5 sin φ: 1 mm at φ0 = 0, where every take-up is 0 under
    // `release`: matched up to that constant, and said so.
    let m = looper_cam("");
    let mut csv = String::from("phi_deg,P_mm\n");
    for k in (0..360).step_by(5) {
        csv += &format!("{k},{}\n", 1.0 + 1.5 * f64::from(k).to_radians().sin());
    }
    let target = Target::from_curve(&parse_curve_csv(&csv, "small.csv").unwrap()).unwrap();
    // The model's disc reaches only 0.09 mm beyond the straight thread along
    // φ0's contact radius, so it cannot give out 1.5 mm more: a clear error.
    let e = err(&m, &CamOptions::new("seed", target.clone()));
    assert!(
        e.contains("cannot be reached at") && e.contains("the worst is φ =") && e.contains("mm short"),
        "{e}"
    );
    // The anchor radius the error suggests makes it reachable, exactly at
    // the knots; a little less does not. (Reachable is not yet cuttable: at
    // that radius the spline between two knots dips through the cam's
    // axis, refused on its own terms.)
    let suggested: f64 = e
        .split("an anchor radius of ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("{e}"));
    let mut o = CamOptions::new("seed", target.clone());
    o.anchor_radius_mm = Some(suggested - 0.1);
    assert!(err(&m, &o).contains("cannot be reached"));
    o.anchor_radius_mm = Some(suggested);
    if let Err(e) = synthesise(&m, &m.defaults(), &o) {
        let e = e.to_string();
        assert!(e.contains("cam's axis") && !e.contains("cannot be reached"), "{e}");
    }
    let mut o = CamOptions::new("seed", target);
    o.anchor_radius_mm = Some(15.0);
    let s = synth(&m, &o);
    assert!((s.target_shift_mm + 1.0).abs() < 1e-12, "{}", s.target_shift_mm);
    assert!(
        s.notes.iter().any(|n| n.contains("matched up to that constant")),
        "{:?}",
        s.notes
    );
    assert!(
        s.verify.max_err_knots_mm < 1e-9 && s.verify.max_err_between_mm < 1e-6,
        "{:?}",
        s.verify.max_err_between_mm
    );
    assert!((s.anchor_radius_mm - 15.0).abs() < 1e-12);
    assert!(s.checks.convex && s.checks.contact_angle_ok, "{:?}", s.checks);
    assert!(s.verify.match_before.is_none(), "no [stitch] here");
}

#[test]
fn bad_inputs_give_clear_errors() {
    let (m, _) = altin504();
    let e = err(&m, &CamOptions::new("lowr", Target::Required));
    assert!(
        e.contains("no thread path `lowr`") && e.contains("needle, lower, upper"),
        "{e}"
    );
    let e = err(&m, &CamOptions::new("needle", Target::Required));
    assert!(
        e.contains("`needle` runs over no cam") && e.contains("lower, upper"),
        "{e}"
    );
    let mut o = CamOptions::new("lower", Target::Required);
    o.cam = Some("cam_u".into());
    let e = err(&m, &o);
    assert!(
        e.contains("does not run over cam `cam_u`") && e.contains("cam_l"),
        "{e}"
    );
    for (f, what) in [
        (
            Box::new(|o: &mut CamOptions| o.points = 4) as Box<dyn Fn(&mut CamOptions)>,
            "profile points",
        ),
        (Box::new(|o: &mut CamOptions| o.smooth_deg = f64::NAN), "smoothing"),
        (Box::new(|o: &mut CamOptions| o.min_radius_mm = -1.0), "minimum radius"),
        (
            Box::new(|o: &mut CamOptions| o.max_pressure_angle_deg = 90.0),
            "contact-angle limit",
        ),
        (
            Box::new(|o: &mut CamOptions| o.anchor_radius_mm = Some(0.0)),
            "anchor radius",
        ),
    ] {
        let mut o = CamOptions::new("lower", Target::Required);
        f(&mut o);
        assert!(err(&m, &o).contains(what), "{what}");
    }
    let ex = looper_cam("");
    // Exact contact: rejected with the reason.
    let e = err(&ex, &CamOptions::new("taut", Target::Required));
    assert!(
        e.contains("contact = \"exact\"") && e.contains("offset") && e.contains("whole wrapped arc"),
        "{e}"
    );
    // No [stitch]: no P'.
    let e = err(&ex, &CamOptions::new("seed", Target::Required));
    assert!(
        e.contains("no [stitch]") && e.contains("a CSV file with columns phi_deg,P_mm"),
        "{e}"
    );
    let e = err(&ex, &CamOptions::new("straight", Target::Required));
    assert!(e.contains("runs over no cam") && e.contains("seed, taut"), "{e}");
    // Unreachable: more thread than the cam can give, with the shortfall.
    let big = Target::Curve {
        phi_deg: (0..36).map(|k| 10.0 * k as f64).collect(),
        p_mm: (0..36).map(|k| 20.0 * f64::from(k * 10).to_radians().sin()).collect(),
        source: "big".into(),
    };
    let e = err(&ex, &CamOptions::new("seed", big));
    assert!(
        e.contains("cannot be reached at") && e.contains("never shorter than 36.0000 mm"),
        "{e}"
    );
    // A malformed curve.
    let bad = Target::Curve {
        phi_deg: vec![0.0, 90.0, 90.0, 180.0],
        p_mm: vec![0.0; 4],
        source: "dup".into(),
    };
    assert!(err(&ex, &CamOptions::new("seed", bad)).contains("not at least 4 finite points"));
}

#[test]
fn exports_are_well_formed() {
    let (m, _) = altin504();
    // The upper thread's P' needs a larger cam than the preset's; the error
    // says how large at φ0's contact (15.72 mm on this grid).
    let mut o = CamOptions::new("upper", Target::Required);
    o.points = 90;
    o.smooth_deg = 20.0;
    let e = err(&m, &o);
    assert!(e.contains("an anchor radius of 15.72 mm (or larger)"), "{e}");
    o.anchor_radius_mm = Some(21.0);
    let s = synth(&m, &o);
    let csv = text::cam::csv(&s);
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("theta_deg,radius_mm"));
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let (a, b) = l.split_once(',').unwrap();
            (a.parse().unwrap(), b.parse().unwrap())
        })
        .collect();
    assert_eq!(rows.len(), 90);
    assert!(rows.windows(2).all(|w| w[1].0 > w[0].0) && rows[0].0 >= 0.0 && rows[89].0 < 360.0);
    assert!(rows.iter().all(|r| r.1 > 0.0 && r.1.is_finite()));
    let svg = drawing::cam::svg(&s);
    assert!(
        svg.starts_with("<?xml")
            && svg.contains("<svg xmlns=\"http://www.w3.org/2000/svg\"")
            && svg.trim_end().ends_with("</svg>")
    );
    assert!(svg.contains("<path id=\"profile\" d=\"M") && svg.contains("mm\" height=") && svg.contains(" mm</text>"));
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
    let dxf = drawing::cam::dxf(&s);
    let codes: Vec<&str> = dxf.lines().collect();
    assert!(codes.len().is_multiple_of(2), "group code / value pairs");
    for w in ["SECTION", "ENTITIES", "POLYLINE", "VERTEX", "SEQEND", "ENDSEC", "EOF"] {
        assert!(codes.iter().skip(1).step_by(2).any(|v| *v == w), "no {w}");
    }
    assert_eq!(codes.last(), Some(&"EOF"));
    assert!(!dxf.contains("NaN"));
    // The [[cams]] snippet replaces the preset's entry and loads.
    let snippet = text::cam::toml_snippet(&s);
    let text = stitchkin::presets::find("altin504").unwrap().toml;
    let start = text.find("[[cams]]\nname = \"cam_u\"").unwrap();
    let end = start + text[start..].find("\n\n").unwrap();
    let model = Model::from_toml_str(&format!("{}{}{}", &text[..start], snippet, &text[end..]), "pasted.toml").unwrap();
    let cam = model.cam_spec("cam_u").unwrap();
    assert!(
        cam.disc.is_none()
            && cam.polar.as_ref().unwrap().angle_deg.len() == 90
            && cam.center == "UCO"
            && cam.marker == "UCM"
    );
}
