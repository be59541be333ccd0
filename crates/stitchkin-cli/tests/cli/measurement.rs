//! `stitchkin measured` and repeated readings beside the model: seed 004
//! §3.4's processing of a bench's readings, its table by destination, and
//! the mean curve with its interval in `match`, `plot takeup` and `report`.

use super::{fails, ok, scratch};

/// The illustrative bench file of examples/ (ten readings every 10°).
fn bench() -> String {
    format!("{}/../../examples/seed004-bench-lower.csv", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn measured_writes_the_processed_table_by_destination() {
    let file = bench();
    // Into a pipe: CSV with the columns of seed 004 §3.4, one row per φ.
    let (csv, _) = ok(&["measured", &file]);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "phi_deg,n,mean_mm,s_mm,s_mean_mm,t,ci_low_mm,ci_high_mm,random_mm,systematic_mm,total_mm,relative_pct,sigma_mm,outliers"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 36);
    assert!(!csv.contains("NaN") && !csv.contains("inf"));
    // φ = 174.85: n = 10, t(0.975, 9) = 2.262, resolution 0.05 mm as the file says.
    assert_eq!((rows[0][0], rows[0][1]), ("174.85", "10"));
    assert!(rows[0][5].starts_with("2.2621"), "{:?}", rows[0]);
    assert_eq!(rows[0][9], "0.05");
    // The slipped reading (the 7th at φ = 474.85) is flagged.
    let r = rows.iter().find(|r| r[0] == "474.85").unwrap();
    assert_eq!(r[13], "7");
    // Another resolution and confidence: wider intervals.
    let (wide, _) = ok(&["measured", &file, "--resolution", "0.2", "--confidence", "0.99"]);
    let w: Vec<&str> = wide.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(w[9], "0.2");
    assert!(w[5].starts_with("3.249"), "t(0.995, 9) = 3.250: {w:?}");
    // The readable table and JSON.
    let (table, _) = ok(&["measured", &file, "--format", "table"]);
    assert!(
        table.contains("Polyakov (2022) §3.4") && table.contains("flagged by Grubbs' test"),
        "{table}"
    );
    let (json, _) = ok(&["measured", &file, "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["points"].as_array().unwrap().len(), 36);
    assert_eq!(v["confidence"], 0.95);
    // -o FILE: written whole.
    let d = scratch("measured-table");
    let out = d.join("t.csv");
    ok(&["measured", &file, "-o", out.to_str().unwrap()]);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), csv);
}

#[test]
fn measured_refuses_bad_readings_with_the_place_and_the_fix() {
    let d = scratch("measured-bad");
    let write = |name: &str, text: &str| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let rows = |f: &dyn Fn(usize) -> String| (0..12).map(f).collect::<String>();
    // No resolution: the header line and the fix.
    let f = write(
        "nores.csv",
        &format!("phi_deg,P_mm,P_mm\n{}", rows(&|k| format!("{},1,1.1\n", 30 * k))),
    );
    let e = fails(&["measured", &f]);
    assert!(e.contains("nores.csv:1") && e.contains("# resolution_mm = 0.05"), "{e}");
    // The flag stands for the line; a resolution ≤ 0 is refused.
    ok(&["measured", &f, "--resolution", "0.05"]);
    let e = fails(&["measured", &f, "--resolution", "0"]);
    assert!(e.contains("the resolution 0 mm is not a length > 0"), "{e}");
    let e = fails(&["measured", &f, "--resolution", "0.05", "--confidence", "95"]);
    assert!(e.contains("the confidence 95 is not between 0 and 1"), "{e}");
    // A ragged row.
    let f = write(
        "ragged.csv",
        &format!(
            "# resolution_mm = 0.1\nphi_deg,P_mm,P_mm\n{}",
            rows(&|k| if k == 3 {
                "90,1\n".into()
            } else {
                format!("{},1,1.1\n", 30 * k)
            })
        ),
    );
    let e = fails(&["measured", &f]);
    assert!(
        e.contains("ragged.csv:6") && e.contains("the row has 2 field(s), the header 3"),
        "{e}"
    );
    // One reading per φ: nothing to process.
    let f = write(
        "plain.csv",
        &format!("phi_deg,P_mm\n{}", rows(&|k| format!("{},1\n", 30 * k))),
    );
    let e = fails(&["measured", &f]);
    assert!(e.contains("one reading per φ, nothing to process"), "{e}");
    // No half-written file after a failure.
    let out = d.join("never.csv");
    fails(&["measured", &f, "-o", out.to_str().unwrap()]);
    assert!(!out.exists());
}

#[test]
fn the_mean_curve_goes_beside_the_model_with_its_interval() {
    let file = format!("lower={}", bench());
    let (out, _) = ok(&["match", "--preset", "altin504", "--step", "5", "--measured", &file]);
    assert!(
        out.contains("the mean of up to 10 readings per φ (Polyakov (2022) §3.4): interval ±")
            && out.contains("at 95 % (resolution 0.05 mm)"),
        "{out}"
    );
    let (json, _) = ok(&[
        "match",
        "--preset",
        "altin504",
        "--step",
        "5",
        "--measured",
        &file,
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let i = &v["measured"][0]["interval"];
    assert_eq!(i["readings_per_phi"], 10);
    assert_eq!(i["readings_phi_deg"].as_array().unwrap().len(), 36);
    assert!(i["model_within_pct"].as_f64().unwrap() > 90.0, "{i}");
    let d = scratch("measured-interval");
    let svg = d.join("t.svg");
    ok(&[
        "plot",
        "takeup",
        "--preset",
        "altin504",
        "--step",
        "5",
        "--measured",
        &file,
        "-o",
        svg.to_str().unwrap(),
    ]);
    let svg = std::fs::read_to_string(&svg).unwrap();
    assert_eq!(
        svg.matches("(95 %, Polyakov (2022) §3.4)").count(),
        36,
        "one error bar per φ read"
    );
    let html = d.join("r.html");
    ok(&[
        "report",
        "--preset",
        "altin504",
        "--step",
        "5",
        "--no-animation",
        "--measured",
        &file,
        "-o",
        html.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(&html).unwrap();
    assert!(
        html.contains("at 95 % (10 readings per φ, Polyakov (2022) §3.4)"),
        "the interval in the report"
    );
}

/// A feed mechanism without [stitch] (seed 004's variant 1) matched against
/// a required take-up given as a file: its path's P against that P′, the
/// cam's checks, the exit status of the checks; without a curve, the error
/// names the way.
#[test]
fn a_model_without_a_stitch_matches_a_required_take_up_given_as_a_file() {
    let root = format!("{}/../..", env!("CARGO_MANIFEST_DIR"));
    let model = format!("{root}/examples/seed004-variants/variant1.toml");
    let target = format!("lower={root}/examples/altin504-lower-pprime.csv");
    let (screen, _) = ok(&["match", &model, "--measured", &target]);
    assert!(
        screen.contains("no [stitch]") && screen.contains("cam_pressure"),
        "{screen}"
    );
    let row = screen.lines().find(|l| l.starts_with("lower ")).unwrap();
    assert!(row.contains(" 99.0 "), "{row}");
    let (json, _) = ok(&["match", &model, "--measured", &target, "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let m = &v["measured"][0];
    assert_eq!(m["thread"], "lower");
    assert_eq!(m["kind"], "required");
    let rms = m["against_other"]["rms_d_mm"].as_f64().unwrap();
    assert!(rms > 0.0 && rms < 0.3, "{rms}");
    assert!(v["checks"].as_array().unwrap().iter().all(|c| c["ok"] == true));
    // Without a curve: what to give.
    let e = fails(&["match", &model]);
    assert!(e.contains("--measured PATH=FILE"), "{e}");
    // A path the model lacks.
    let e = fails(&[
        "match",
        &model,
        "--measured",
        &format!("upper={root}/examples/altin504-lower-pprime.csv"),
    ]);
    assert!(e.contains("no thread path `upper`") && e.contains("lower"), "{e}");
}
