//! `stitchkin nomogram`: tune over a grid of material thickness and stitch
//! length.

use super::{fails, ok, scratch};

#[test]
fn nomogram_tabulates_the_tuned_setting_per_thickness() {
    let (out, err) = ok(&[
        "nomogram",
        "--thickness",
        "3:5:3",
        "--adjust",
        "z",
        "--step",
        "10",
        "--format",
        "table",
    ]);
    assert!(out.starts_with("Nomogram of `mf7923d`"), "{out}");
    assert!(out.contains("adjusting z (mm); seed 1, φ step 10°"), "{out}");
    let lines: Vec<&str> = out.lines().collect();
    let h = lines
        .iter()
        .position(|l| l.trim_start().starts_with("m mm"))
        .expect("a header row");
    for col in [
        "t mm",
        "z mm",
        "z within 1 pt",
        "score before",
        "score after",
        "n1",
        "n3",
        "J after",
    ] {
        assert!(lines[h].contains(col), "{col} missing: {}", lines[h]);
    }
    let rows: Vec<Vec<&str>> = lines[h + 1..h + 4]
        .iter()
        .map(|l| l.split_whitespace().collect())
        .collect();
    for (row, m) in rows.iter().zip(["3", "4", "5"]) {
        assert_eq!((row[0], row[1]), (m, "3"), "{row:?}");
        // z at about −8 to −10 mm at every thickness, with the regulator's
        // window computed (docs/published-facts.md, MF11).
        let z: f64 = row[2].parse().unwrap();
        assert!((-10.0..=-7.0).contains(&z), "m = {m}: z = {z}");
        let (before, after): (f64, f64) = (row[6].parse().unwrap(), row[7].parse().unwrap());
        assert!(after >= before, "{row:?}");
    }
    assert!(
        !out.contains("Every match score is 0") && !out.contains("note:"),
        "{out}"
    );
    assert!(err.contains("# nomogram: 3 grid points tuned (0 failed)"), "{err}");
    // Without --thickness: 5 values over the thickness parameter's range,
    // every setting tuned inside its range (with the regulator's window
    // computed no setting is pushed to a range end, so there is no note).
    let (out, err) = ok(&["nomogram", "--step", "10", "--samples", "24", "--format", "table"]);
    assert!(
        out.contains(
            "adjusting r1 (mm), l_o2b (mm), z (mm), r2 (mm), R (mm), psi (deg), dphi (deg), g3_1 (mm), g3_2 (mm), \
             g3_3 (mm)"
        ),
        "{out}"
    );
    assert!(err.contains("# nomogram: 5 grid points tuned (0 failed)"), "{err}");
    assert!(!out.contains("note:"), "{out}");
}

#[test]
fn nomogram_writes_csv_and_json() {
    let d = scratch("nomogram");
    let f = d.join("n.csv");
    let (stdout, _) = ok(&[
        "nomogram",
        "--thickness",
        "2:4:2",
        "--stitch",
        "2.5",
        "--adjust",
        "z",
        "--step",
        "15",
        "--seed",
        "7",
        "--format",
        "csv",
        "-o",
        f.to_str().unwrap(),
    ]);
    assert!(stdout.is_empty());
    let csv = std::fs::read_to_string(&f).unwrap();
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        1,
        "no temporary file left behind"
    );
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    assert!(
        lines[0].starts_with(
            "m_mm,t_mm,z_mm,z_lo_mm,z_hi_mm,score_mean_before,score_mean_after,J_before,J_after,n1.score_before"
        ),
        "{}",
        lines[0]
    );
    assert!(
        lines[0].ends_with(",mu_min_after_deg,mu_max_after_deg,status"),
        "{}",
        lines[0]
    );
    assert!(
        lines[1].starts_with("2,2.5,") && lines[2].starts_with("4,2.5,"),
        "{csv}"
    );
    assert!(
        lines[1..].iter().all(|l| l.ends_with(",ok") && !l.contains("NaN")),
        "{csv}"
    );
    let (json, _) = ok(&[
        "nomogram",
        "--thickness",
        "4",
        "--adjust",
        "z",
        "--step",
        "15",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["points"].as_array().unwrap().len(), 1);
    assert_eq!(v["adjust"][0][0], "z");
    assert_eq!(v["seed"], 1);
    let r = &v["points"][0]["tuned"];
    assert!(r["after_figures"]["score_mean"].as_f64().unwrap() >= r["before_figures"]["score_mean"].as_f64().unwrap());
    let e = fails(&[
        "nomogram",
        "--thickness",
        "4",
        "--adjust",
        "z",
        "-o",
        "/nonexistent-dir/n.csv",
    ]);
    assert!(e.contains("cannot write") && e.contains("no folder"), "{e}");
}

#[test]
fn nomogram_says_when_no_setting_fits() {
    // T1 down at the needle's TDC: no z gives a score or passes the checks.
    let (out, _) = ok(&[
        "nomogram",
        "--set",
        "t1_phase=0",
        "--thickness",
        "4",
        "--adjust",
        "z",
        "--step",
        "15",
        "--format",
        "table",
    ]);
    assert!(out.contains("Every match score is 0"), "{out}");
    assert!(out.contains("t1_phase = 0"), "{out}");
    assert!(
        out.contains("no setting in the ranges passes every physical check"),
        "{out}"
    );
}

#[test]
fn nomogram_refuses_bad_input_with_the_fix() {
    for (args, says, fix) in [
        (
            vec!["--thickness", "9"],
            "outside its adjustable range",
            "choose a value between",
        ),
        (
            vec!["--thickness", "1:x:3"],
            "must be numbers (in --thickness)",
            "LO:HI:N in mm",
        ),
        (
            vec!["--thickness", "1:5:0"],
            "whole number ≥ 1 (in --thickness)",
            "LO:HI:N in mm",
        ),
        (vec!["--thickness", "-1:5:3"], "outside its adjustable range", "between"),
        (
            vec!["--thickness", "3", "--stitch", "2:2:3"],
            "LO = HI gives 3 equal values; use N = 1 or widen the range (in --stitch)",
            "LO:HI:N in mm",
        ),
        (
            vec!["--thickness", "3", "--adjust", "z,m"],
            "`m` is the material thickness",
            "leave `m` out of the adjusted settings",
        ),
        (
            vec!["--thickness", "3", "--adjust", "zz"],
            "no parameter `zz` (did you mean `z`?) (in --adjust)",
            "adjustable parameters are",
        ),
        (
            vec!["--thickness", "3", "--step", "0"],
            "out of range (in --step)",
            "e.g. 1",
        ),
        (
            vec!["--preset", "needle876", "--thickness", "3"],
            "no [stitch]",
            "mf7923d",
        ),
        (
            vec![
                "--preset",
                "altin504",
                "--thickness",
                "1:2:2",
                "--adjust",
                "timing_l,alpha",
            ],
            "`alpha` (needle inclination alpha) is a fixed dimension",
            "--allow-dimensions",
        ),
    ] {
        let e = fails(&[&["nomogram"], &args[..]].concat());
        assert!(e.contains(says), "{args:?}: {e}");
        assert!(e.contains(fix), "{args:?} gives no fix: {e}");
    }
    let e = fails(&["nomogram", "--preset", "takeup-lever"]);
    assert!(e.contains("no [stitch]"), "{e}");
}
