//! `stitchkin cam`: cam synthesis from the command line (files written,
//! their formats, the summary, the errors).

use super::{fails, ok, scratch};

/// Tags open and close in order (an XML well-formedness check without an
/// XML parser): returns the element names in document order.
fn xml_elements(text: &str) -> Vec<String> {
    let mut stack: Vec<String> = Vec::new();
    let mut names = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find('<') {
        let j = rest[i..].find('>').expect("every < closes") + i;
        let tag = &rest[i + 1..j];
        rest = &rest[j + 1..];
        if tag.starts_with('?') || tag.starts_with('!') {
            continue;
        }
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop().as_deref(), Some(name.trim()), "mismatched </{name}>");
            continue;
        }
        let name = tag.split_whitespace().next().unwrap().trim_end_matches('/').to_string();
        names.push(name.clone());
        if !tag.ends_with('/') {
            stack.push(name);
        }
    }
    assert!(stack.is_empty(), "unclosed: {stack:?}");
    names
}

#[test]
fn cam_writes_csv_svg_dxf_and_a_toml_snippet() {
    let d = scratch("cam");
    let prefix = d.join("lower");
    let (out, summary) = ok(&[
        "cam",
        "--preset",
        "altin504",
        "--path",
        "lower",
        "--target",
        "required",
        "-o",
        prefix.to_str().unwrap(),
    ]);
    assert!(out.is_empty(), "files only with -o: {out}");
    for want in [
        "thread path `lower`, cam `cam_l`",
        "score 90.3 → 100.0",
        "at the knots",
        "TOO STEEP",
        "convex         NO",
        "wrote ",
    ] {
        assert!(summary.contains(want), "no `{want}` in\n{summary}");
    }
    let read = |ext: &str| {
        std::fs::read_to_string(d.join(format!("lower.{ext}"))).unwrap_or_else(|e| panic!("lower.{ext}: {e}"))
    };
    let csv = read("csv");
    assert!(csv.starts_with("theta_deg,radius_mm\n"));
    assert_eq!(csv.lines().count(), 361);
    let svg = read("svg");
    let names = xml_elements(&svg);
    assert_eq!(names.first().map(String::as_str), Some("svg"));
    assert!(
        names.iter().any(|n| n == "path") && names.iter().any(|n| n == "line") && names.iter().any(|n| n == "text"),
        "{names:?}"
    );
    assert!(svg.contains("width=\"") && svg.contains("mm\""), "drawn in mm");
    let dxf = read("dxf");
    let values: Vec<&str> = dxf.lines().skip(1).step_by(2).collect();
    for w in [
        "SECTION", "HEADER", "ENTITIES", "POLYLINE", "VERTEX", "SEQEND", "ENDSEC", "EOF",
    ] {
        assert!(values.contains(&w), "DXF without {w}");
    }
    assert_eq!(values.last(), Some(&"EOF"));
    let toml = read("toml");
    assert!(
        toml.contains("[[cams]]\nname = \"cam_l\"\ncenter = \"LCO\"\nmarker = \"LCM\"\npolar = { angle_deg = ["),
        "{}",
        &toml[..300]
    );
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        4,
        "four files, no temporary ones"
    );
}

#[test]
fn cam_writes_one_format_to_stdout_or_a_file() {
    let (csv, summary) = ok(&[
        "cam", "--preset", "altin504", "--path", "lower", "--target", "required", "--points", "72", "--smooth", "15",
    ]);
    assert!(
        csv.starts_with("theta_deg,radius_mm\n") && csv.lines().count() == 73,
        "{csv}"
    );
    assert!(
        summary.contains("moving average over 15°") && !summary.contains("wrote "),
        "{summary}"
    );
    let d = scratch("cam-svg");
    let f = d.join("upper.svg");
    let upper = |extra: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = ["cam", "--preset", "altin504", "--path", "upper", "--target", "required"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        a.extend(extra.iter().map(|s| s.to_string()));
        a.extend([
            "--format".into(),
            "svg".into(),
            "-o".into(),
            f.to_str().unwrap().to_string(),
        ]);
        a
    };
    // Unsmoothed, the spline between the steps' knots passes the cam's axis:
    // refused, and no file is written.
    let args = upper(&["--anchor-radius", "21"]);
    let e = fails(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(
        e.contains("pass through the cam's axis") && e.contains("raise the anchor radius"),
        "{e}"
    );
    assert!(!f.exists());
    let args = upper(&["--anchor-radius", "21", "--smooth", "20"]);
    let (_, summary) = ok(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(summary.contains("TOO SMALL"), "the spline dips below 3 mm: {summary}");
    xml_elements(&std::fs::read_to_string(&f).unwrap());
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
}

#[test]
fn cam_takes_a_csv_target() {
    // The lower thread's own take-up, from `stitchkin run`, as the target:
    // the cam comes back as the preset's disc (radius 6.8…17.2 mm).
    let d = scratch("cam-csv");
    let target = d.join("p.csv");
    ok(&[
        "run",
        "--preset",
        "altin504",
        "--columns",
        "lower.P_mm",
        "--no-analogs",
        "-o",
        target.to_str().unwrap(),
    ]);
    let (csv, summary) = ok(&[
        "cam",
        "--preset",
        "altin504",
        "--path",
        "lower",
        "--target",
        target.to_str().unwrap(),
        "--format",
        "toml",
    ]);
    assert!(csv.starts_with("# Cam `cam_l`"), "{csv}");
    assert!(
        summary.contains("radius 6.800…17.200 mm (the model's profile: 6.800…17.200 mm)"),
        "{summary}"
    );
    assert!(summary.contains("convex         yes"), "{summary}");
}

#[test]
fn cam_errors_are_clear() {
    let e = fails(&[
        "cam", "--preset", "altin504", "--path", "needle", "--target", "required",
    ]);
    assert!(e.contains("runs over no cam") && e.contains("lower, upper"), "{e}");
    let e = fails(&["cam", "--preset", "altin504", "--path", "lowr", "--target", "required"]);
    assert!(e.contains("no thread path `lowr`"), "{e}");
    let e = fails(&["cam", "--preset", "altin504", "--path", "upper", "--target", "required"]);
    assert!(
        e.contains("cannot be reached") && e.contains("an anchor radius of"),
        "{e}"
    );
    let e = fails(&[
        "cam", "--preset", "altin504", "--path", "lower", "--target", "required", "--format", "all",
    ]);
    assert!(e.contains("-o PREFIX"), "{e}");
    let e = fails(&[
        "cam",
        "--preset",
        "altin504",
        "--path",
        "lower",
        "--target",
        "/nonexistent/target.csv",
    ]);
    assert!(e.contains("cannot read the target"), "{e}");
    let e = fails(&[
        "cam", "--preset", "altin504", "--path", "lower", "--target", "required", "--points", "4",
    ]);
    assert!(e.contains("(in --points)") && e.contains("between 8 and 1440"), "{e}");
}

#[test]
fn cam_follower_writes_the_lift_the_profile_and_a_closed_dxf() {
    let ex = |f: &str| format!("{}/../../examples/{f}", env!("CARGO_MANIFEST_DIR"));
    let d = scratch("cam-follower");
    let prefix = d.join("pusher");
    let model = ex("cam-follower-thread.toml");
    let target = ex("altin504-lower-pprime.csv");
    let (out, summary) = ok(&[
        "cam",
        &model,
        "--follower",
        "pusher",
        "--path",
        "lower",
        "--target",
        &target,
        "--smooth",
        "10",
        "-o",
        prefix.to_str().unwrap(),
    ]);
    assert!(out.is_empty(), "files only with -o: {out}");
    for want in [
        "group `pusher` (translating follower), thread path `lower`",
        "score 99.6",
        "pressure angle  max 15.8°",
        "(limit 30°): ok",
        "curvature       least radius 5.95 mm",
        "wrote ",
    ] {
        assert!(summary.contains(want), "no `{want}` in\n{summary}");
    }
    let read = |ext: &str| std::fs::read_to_string(d.join(format!("pusher.{ext}"))).unwrap();
    let csv = read("csv");
    assert!(csv.starts_with("cam_deg,lift_mm,pitch_x_mm,pitch_y_mm,profile_x_mm,profile_y_mm\n"));
    assert_eq!(csv.lines().count(), 721);
    let toml = read("toml");
    assert!(
        toml.contains("base_radius = 24.97") && toml.contains("lift = { angle_deg = ["),
        "{toml}"
    );
    let dxf = read("dxf");
    assert!(dxf.contains("POLYLINE\n8\nPROFILE\n66\n1\n70\n1\n") && dxf.trim_end().ends_with("EOF"));
    assert_eq!(dxf.matches("VERTEX").count(), 720);
    // Without an unsmoothed profile to cut, the undercut is said.
    let (_, summary) = ok(&[
        "cam",
        &model,
        "--follower",
        "pusher",
        "--path",
        "lower",
        "--target",
        &target,
        "--format",
        "toml",
    ]);
    assert!(summary.contains("UNDERCUT"), "{summary}");
    // A group that is not there.
    let err = fails(&[
        "cam",
        &model,
        "--follower",
        "nope",
        "--path",
        "lower",
        "--target",
        &target,
    ]);
    assert!(
        err.contains("no cam_follower group `nope`") && err.contains("pusher"),
        "{err}"
    );
}

#[test]
fn check_judges_a_spring_at_the_speed_asked() {
    let model = format!("{}/../../examples/cam-rocking-roller.toml", env!("CARGO_MANIFEST_DIR"));
    // The model's own 1000 rpm passes and names the speed the spring holds.
    let (out, _) = ok(&["check", &model]);
    assert!(out.contains("the spring holds it up to 1285 rpm"), "{out}");
    // 3000 rpm: the follower jumps, the check fails and says where.
    let slow = super::run(&["check", &model, "--rpm", "3000"]);
    let (o, e) = (
        String::from_utf8_lossy(&slow.stdout),
        String::from_utf8_lossy(&slow.stderr),
    );
    assert!(!slow.status.success());
    assert!(
        o.contains("FAIL follower_contact") && o.contains("at 3000 rpm the follower leaves the cam"),
        "{o}"
    );
    assert!(e.contains("feed_arm follower_contact"), "{e}");
    // A speed that is no speed is refused, naming the option.
    let err = fails(&["check", &model, "--rpm", "-5"]);
    assert!(err.contains("--rpm") && err.contains("out of range"), "{err}");
}
