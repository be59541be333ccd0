//! `stitchkin stroke`, `straightness` and `tolerance`, run as a user would.

use super::{fails, ok, scratch};

/// The column `name` of a CSV as numbers (empty cells are `None`).
fn column(csv: &str, name: &str) -> Vec<Option<f64>> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let i = header
        .iter()
        .position(|h| *h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    lines
        .map(|l| l.split(',').nth(i).unwrap().parse::<f64>().ok())
        .collect()
}

#[test]
fn stroke_tabulates_seed_002_and_finds_where_the_mechanism_jams() {
    let args = [
        "stroke",
        "--preset",
        "needle876",
        "--point",
        "G",
        "--axis",
        "y",
        "--vary",
        "alpha=0:40:41",
    ];
    let (table, _) = ok(&[&args[..], &["--format", "table"]].concat());
    assert!(
        table.starts_with("needle876: stroke of G along y (world), φ step 1°"),
        "{table}"
    );
    let row = |alpha: &str| {
        table
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("{alpha} ")))
            .unwrap_or_else(|| panic!("no row {alpha}:\n{table}"))
    };
    assert!(
        row("0").contains("18.0776") && row("0").contains("107.4750") && row("0").contains("90.61"),
        "{}",
        row("0")
    );
    assert!(row("35").contains("22.7682"), "{}", row("35"));
    assert!(row("38").contains(" *") && !row("37").contains(" *"), "{table}");
    assert!(
        table.contains("mu_45 (rrr group \"45\") leaves 30°…150° at alpha = 37.6"),
        "{table}"
    );
    assert!(table.contains("its minimum falls below 30°"), "{table}");
    // CSV: one row per setting, units in the header, the crossing on stderr.
    let mut csv_args = args.to_vec();
    csv_args.extend(["--format", "csv"]);
    let (csv, err) = ok(&csv_args);
    assert_eq!(csv.lines().count(), 42);
    let header = csv.lines().next().unwrap();
    for c in [
        "alpha_deg",
        "G.y_stroke_mm",
        "G.y_min_mm",
        "G.y_min_phi_deg",
        "G.y_max_phi_deg",
        "G_at_min.x_mm",
        "mu_45.min_deg",
        "mu_45.ok",
        "status",
    ] {
        assert!(header.split(',').any(|h| h == c), "no {c} in {header}");
    }
    let stroke = column(&csv, "G.y_stroke_mm");
    assert!((stroke[0].unwrap() - 18.08).abs() < 0.01 && (stroke[35].unwrap() - 22.77).abs() < 0.01);
    let low = column(&csv, "G.y_min_mm");
    assert!(low.iter().all(|y| (y.unwrap() - 107.475).abs() < 1e-3));
    assert!(!csv.contains("NaN") && !csv.contains("inf"));
    assert!(err.contains("# mu_45") && err.contains("37.6"), "{err}");
    // JSON, written atomically with -o.
    let d = scratch("stroke");
    let f = d.join("stroke.json");
    ok(&[
        "stroke",
        "--preset",
        "needle876",
        "--point",
        "G",
        "--vary",
        "alpha=30:40:3",
        "--format",
        "json",
        "-o",
        f.to_str().unwrap(),
    ]);
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&f).unwrap()).unwrap();
    assert_eq!(v["rows"].as_array().unwrap().len(), 3);
    assert!((v["rows"][0]["stroke"]["min"]["phi_deg"].as_f64().unwrap() - 90.6055).abs() < 1e-3);
    assert_eq!(v["crossings"][0]["key"], "45");
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1, "no temporary file left");
}

#[test]
fn stroke_along_a_frame_axis_and_settings_without_assembly() {
    // Along the Altin needle guide: 25.44 mm between BDC (φ = 0) and TDC.
    let (t, _) = ok(&[
        "stroke",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--axis",
        "guide.y",
        "--format",
        "table",
    ]);
    assert!(
        t.contains("along y of frame `guide`") && t.contains("25.4378") && t.contains("174.85"),
        "{t}"
    );
    // A setting that does not assemble is a row with its reason.
    let d = scratch("stroke-assembly");
    let model = "[model]\nname = \"fourbar\"\n[parameters]\nr = { value = 5, unit = \"mm\", range = [5, 15] }\n\
                 [points]\nO1 = [0, 0]\nO2 = [60, 0]\n[[drivers]]\ntype = \"crank\"\ncenter = \"O1\"\nout = \"A\"\nradius = \"r\"\n\
                 [[groups]]\ntype = \"rrr\"\nname = \"bc\"\njoints = [\"A\", \"O2\"]\nlengths = [50, 24]\nout = \"B\"\nbranch = \"left\"\n";
    let path = d.join("fourbar.toml");
    std::fs::write(&path, model).unwrap();
    let (csv, err) = ok(&[
        "stroke",
        path.to_str().unwrap(),
        "--point",
        "B",
        "--axis",
        "x",
        "--vary",
        "r=5:15:3",
        "--format",
        "csv",
    ]);
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert!(rows[0].ends_with(",ok") && rows[1].ends_with(",ok"), "{csv}");
    assert!(rows[2].starts_with("15,,") && rows[2].contains("no assembly"), "{csv}");
    assert!(err.contains("r = 15: no assembly"), "{err}");
    // A single setting that does not assemble is an error.
    let e = fails(&["stroke", path.to_str().unwrap(), "--point", "B", "--set", "r=15"]);
    assert!(e.contains("no assembly"), "{e}");
}

#[test]
fn stroke_rejects_bad_requests_with_the_fix() {
    let base = ["stroke", "--preset", "needle876"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> { base.iter().chain(extra).copied().collect() };
    for (extra, says) in [
        (
            &["--point", "Q"][..],
            "the model has no point `Q` (did you mean `O`?) (in --point)",
        ),
        (
            &["--point", "g"][..],
            "no point `g` (did you mean `G`?) (in --point)\n  help: its points are: O, C, F, H, A, B, D, E, G",
        ),
        (
            &["--point", "O"][..],
            "point `O` is fixed, so it has no path (in --point)\n  help: the moving points are: A, B, D, E, G",
        ),
        (&["--point", "G", "--axis", "w"][..], "FRAME.x|y|z"),
        (&["--point", "G", "--axis", "guide.y"][..], "no frame `guide`"),
        (&["--point", "G", "--axis", "0,0"][..], "zero length"),
        (
            &["--point", "G", "--vary", "alpha=0:50:3"][..],
            "outside its adjustable range",
        ),
        (&["--point", "G", "--vary", "alpha"][..], "NAME=LO:HI:N"),
        (&["--point", "G", "--step", "0"][..], "step"),
        (&["--point", "G", "--step", "90"][..], "at most 45 deg"),
    ] {
        let e = fails(&with(extra));
        assert!(e.contains(says), "{extra:?}: {e}");
    }
    let e = fails(&["stroke", "--preset", "needle876"]);
    assert!(e.contains("--point"), "{e}");
}

#[test]
fn straightness_of_the_altin_needle() {
    let (t, _) = ok(&[
        "straightness",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--line",
        "N1,N2",
        "--format",
        "table",
    ]);
    for s in [
        "from the line N1 → N2, over the cycle",
        "20.000° from +y",
        "travel along the line       25.4378 mm",
        "+0.00236 mm",
        "-0.00181 mm",
        "minimum zone (ISO 1101)     0.00408 mm",
    ] {
        assert!(t.contains(s), "`{s}` missing:\n{t}");
    }
    let (csv, summary) = ok(&[
        "straightness",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--fit",
        "--over",
        "down",
        "--step",
        "2",
        "--format",
        "csv",
    ]);
    assert!(csv.starts_with("phi_deg,E.along_mm,E.dev_mm\n"), "{csv}");
    let dev = column(&csv, "E.dev_mm");
    assert!(dev.iter().all(|d| d.unwrap().abs() < 0.003));
    assert!(
        summary.contains("# altin-needle: straightness of E from the least-squares line")
            && summary.contains("down, from φ = 174.85°"),
        "{summary}"
    );
    let (json, _) = ok(&[
        "straightness",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--over",
        "30:90",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["phi_deg"].as_array().unwrap().len(), 61);
    assert!(v["max_abs_dev_mm"].as_f64().unwrap() < 0.003 && v["signed"] == true);
    for (args, says) in [
        (&["--point", "E", "--line", "N1"][..], "H,T"),
        (&["--point", "E", "--line", "N1,N1"][..], "two different points"),
        (
            &["--point", "E", "--line", "N1,N9"][..],
            "the model has no point `N9` (did you mean `N1`?) (in --line)",
        ),
        (
            &["--point", "E", "--over", "sideways"][..],
            "cycle, down, up or FROM:TO",
        ),
        (&["--point", "A", "--over", "down"][..], "is fixed"),
    ] {
        let mut a = vec!["straightness", "--preset", "altin-needle"];
        a.extend(args);
        let e = fails(&a);
        assert!(e.contains(says), "{args:?}: {e}");
    }
}

#[test]
fn tolerance_table_bisection_and_reproducible_monte_carlo() {
    let args = [
        "tolerance",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--line",
        "N1,N2",
        "--length-tol",
        "0",
        "--tol",
        "l_ab=±0.05",
        "--tol",
        "l_cd=0.05",
        "--tol",
        "beta=0.02",
        "--samples",
        "40",
        "--seed",
        "3",
        "--step",
        "2",
    ];
    let table = |a: &[&str]| ok(&[a, &["--format", "table"]].concat()).0;
    let t = table(&args);
    for s in [
        "tolerances for the straightness of E",
        "limit 0.05 mm",
        "l_ab",
        "±0.05 mm",
        "beta",
        "±0.02 deg",
        "largest alone",
        "Monte Carlo",
        "40 samples",
        "seed 3",
        "50 %:",
        "99 %:",
    ] {
        assert!(t.contains(s), "`{s}` missing:\n{t}");
    }
    let l_ab = t.lines().find(|l| l.starts_with("l_ab")).unwrap();
    assert!(l_ab.contains(" *") && l_ab.contains("±0.042"), "{l_ab}");
    // The same seed, the same output; another seed, other samples.
    assert_eq!(table(&args), t);
    let mut other = args.to_vec();
    let seed = other.len() - 3;
    other[seed] = "4";
    assert_ne!(table(&other), t);
    let mut json_args = args.to_vec();
    json_args.extend(["--format", "json", "--distribution", "normal"]);
    let (json, _) = ok(&json_args);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["monte_carlo"]["distribution"], "normal");
    assert_eq!(v["one_at_a_time"].as_array().unwrap().len(), 3);
    let row = &v["one_at_a_time"][0];
    assert!(
        row["largest_tol"].as_f64().unwrap() < row["tol"].as_f64().unwrap(),
        "{row}"
    );
    let mut csv_args = args.to_vec();
    let samples = csv_args.iter().position(|a| *a == "--samples").unwrap() + 1;
    csv_args[samples] = "0";
    csv_args.extend(["--format", "csv"]);
    let (csv, err) = ok(&csv_args);
    assert!(
        csv.starts_with("parameter,unit,tol,dev_minus_mm,dev_plus_mm,change_mm,largest_tol,bounded\nl_ab,mm,0.05,"),
        "{csv}"
    );
    assert!(err.is_empty(), "{err}");
    for (extra, says) in [
        (&["--limit", "0.001"][..], "already deviates"),
        (&["--limit", "-1"][..], "positive"),
        (&["--tol", "alfa=1"][..], "`alpha`?"),
        (&["--tol", "rot_d=1"][..], "derived"),
        (&["--tol", "l_ab=x"][..], "≥ 0"),
        (&["--length-tol", "0"][..], "no parameter has a tolerance"),
    ] {
        let mut a = vec![
            "tolerance",
            "--preset",
            "altin-needle",
            "--point",
            "E",
            "--samples",
            "0",
        ];
        a.extend(extra);
        let e = fails(&a);
        assert!(e.contains(says), "{extra:?}: {e}");
    }
}
