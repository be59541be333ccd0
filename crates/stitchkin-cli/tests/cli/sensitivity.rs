//! `stitchkin sensitivity` and `stitchkin fit`, run as a user would.

use std::path::Path;

use super::{fails, ok, run_in, scratch};

fn repo() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

#[test]
fn sensitivity_ranks_the_parameters_of_each_figure() {
    let (out, _) = ok(&[
        "sensitivity",
        "--params",
        "r1,l_o2b,z",
        "--figures",
        "n1_A.max_P_B_mm,mu.max_deg",
        "--step",
        "5",
        "--format",
        "table",
    ]);
    assert!(
        out.starts_with("Sensitivity of `mf7923d` at r1 = 4 mm, l_o2b = 21.5 mm, z = 0 mm"),
        "{out}"
    );
    for line in [
        "n1_A.max_P_B_mm = ",
        "(ranked by |effect|)",
        "d/dp",
        "effect",
        "at lo",
        "span",
        "mu.max_deg = ",
    ] {
        assert!(out.contains(line), "`{line}` missing:\n{out}");
    }
    // r1 4 → 6 mm moves max P_B most, first in rank, in mm/mm: with T1 up
    // at TDC it lowers it (seed 000 states a rise; docs/published-facts.md),
    // and O2B raises it.
    let r1 = out
        .lines()
        .find(|l| l.trim_start().starts_with("1  r1"))
        .unwrap_or_else(|| panic!("r1 is not first:\n{out}"));
    assert!(r1.contains("mm/mm") && r1.contains("-1"), "{r1}");
    assert!(
        out.lines()
            .any(|l| l.trim_start().starts_with("2  l_o2b") && l.contains("+")),
        "{out}"
    );
    // mu.max in deg per mm.
    assert!(out.contains("deg/mm"), "{out}");
    // CSV: one row per figure and parameter, units in their own columns.
    let (csv, _) = ok(&[
        "sensitivity",
        "--params",
        "r1,l_o2b",
        "--figures",
        "n1_A.max_P_B_mm",
        "--step",
        "10",
        "--format",
        "csv",
    ]);
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("figure,figure_unit,nominal,rank,parameter,parameter_unit,range_lo,range_hi,derivative,derivative_unit,method,"), "{csv}");
    assert_eq!(lines.len(), 3, "{csv}");
    assert!(
        lines[1].starts_with("n1_A.max_P_B_mm,mm,")
            && lines[1].contains(",1,r1,mm,4,6,")
            && lines[1].contains(",mm/mm,exact,"),
        "{}",
        lines[1]
    );
    assert!(!csv.contains("NaN") && !csv.contains("inf"));
    // JSON, and -o writes the file whole.
    let d = scratch("sensitivity");
    let f = d.join("s.json");
    ok(&[
        "sensitivity",
        "--preset",
        "needle876",
        "--step",
        "5",
        "--format",
        "json",
        "-o",
        f.to_str().unwrap(),
    ]);
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&f).unwrap()).unwrap();
    assert_eq!(v["model"], "needle876");
    let stroke = v["figures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["figure"] == "needle_y.range_mm")
        .unwrap();
    assert_eq!(stroke["effects"][0]["param"], "alpha");
    assert_eq!(stroke["effects"][0]["method"], "exact");
    // Seed 002: the stroke grows from about 18 to about 26 mm over alpha 0…45°.
    assert!(stroke["effects"][0]["whole_range"].as_f64().unwrap() > 7.0);
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        1,
        "no temporary file left behind"
    );
}

#[test]
fn sensitivity_output_writes_the_file() {
    let d = scratch("sensitivity-output");
    let f = d.join("s.csv");
    let (out, _) = ok(&[
        "sensitivity",
        "--preset",
        "needle876",
        "--figures",
        "needle_y.range_mm",
        "--step",
        "10",
        "--format",
        "csv",
        "--output",
        f.to_str().unwrap(),
    ]);
    assert!(out.is_empty(), "the table went to stdout:\n{out}");
    let csv = std::fs::read_to_string(&f).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(
        lines[0].starts_with("figure,figure_unit,nominal,rank,parameter,"),
        "{csv}"
    );
    assert_eq!(lines.len(), 2, "{csv}");
    assert!(
        lines[1].starts_with("needle_y.range_mm,mm,") && lines[1].contains(",1,alpha,deg,0,45,"),
        "{csv}"
    );
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        1,
        "no temporary file left behind"
    );
}

#[test]
fn sensitivity_rejects_bad_requests_with_the_fix() {
    let e = fails(&["sensitivity", "--params", "t1_phase", "--step", "10"]);
    assert!(
        e.contains("`t1_phase` has no adjustable range") && e.contains("help"),
        "{e}"
    );
    let e = fails(&["sensitivity", "--params", "r1", "--figures", "nope", "--step", "10"]);
    assert!(
        e.contains("no figure of merit matches `nope`") && e.contains("n1_A.max_P_B_mm"),
        "{e}"
    );
    let e = fails(&["sensitivity", "--params", "r1", "--step", "0"]);
    assert!(e.contains("step"), "{e}");
    let e = fails(&["sensitivity", "--preset", "needle876", "--set", "alpha=99"]);
    assert!(e.contains("outside its adjustable range"), "{e}");
}

#[test]
fn fit_recovers_the_reconstructed_dimension_and_reports_residuals() {
    // From the repository root, as the docs show it.
    let facts = "examples/facts/needle876.toml";
    let out = run_in(
        &["fit", "--preset", "needle876", "--target", facts, "--set", "y_c=170"],
        repo(),
    );
    let (text, err) = (
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    );
    assert!(out.status.success(), "{err}");
    assert!(
        text.starts_with("Fit of `needle876` to examples/facts/needle876.toml"),
        "{text}"
    );
    assert!(text.contains("converged"), "{text}");
    let y_c = text
        .lines()
        .find(|l| l.starts_with("y_c "))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        y_c.contains("170 mm") && y_c.contains("174.99") && y_c.contains("± 0.03"),
        "{y_c}"
    );
    for line in [
        "needle_y.range_mm  alpha = 0 deg",
        "alpha = 35 deg minus alpha = 0 deg",
        "residual/tol",
        "cost Σ (residual/tolerance)²",
    ] {
        assert!(text.contains(line), "`{line}` missing:\n{text}");
    }
    // l_CF instead, from 41 mm, as JSON.
    let facts_abs = repo().join(facts);
    let (json, _) = ok(&[
        "fit",
        "--preset",
        "needle876",
        "--target",
        facts_abs.to_str().unwrap(),
        "--adjust",
        "l_cf=30:45",
        "--set",
        "l_cf=41",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(
        (v["params"][0]["fitted"].as_f64().unwrap() - 37.945).abs() < 0.01,
        "{json}"
    );
    assert_eq!(v["facts"].as_array().unwrap().len(), 3);
    assert!(v["facts"][2]["residual"].as_f64().unwrap().abs() < 1e-3);
    assert!(v["cost"].as_f64().unwrap() < v["cost_start"].as_f64().unwrap());
    // Bad requests.
    let e = fails(&["fit", "--preset", "needle876", "--target", "/nonexistent/facts.toml"]);
    assert!(e.contains("cannot read facts file"), "{e}");
    // The diagnostic wraps at the terminal width: compare its words.
    let e = flat(&fails(&[
        "fit",
        "--preset",
        "needle876",
        "--target",
        facts_abs.to_str().unwrap(),
        "--adjust",
        "alpha",
    ]));
    assert!(
        e.contains("sets `alpha`, which is being fitted") && e.contains("needle876.toml:"),
        "{e}"
    );
    let e = flat(&fails(&[
        "fit",
        "--preset",
        "needle876",
        "--target",
        facts_abs.to_str().unwrap(),
        "--adjust",
        "l_cf",
    ]));
    assert!(e.contains("no adjustable range") && e.contains("l_cf=LO:HI"), "{e}");
    let d = scratch("fit");
    let bad = d.join("bad.toml");
    std::fs::write(&bad, "[[fact]]\nfigure = \"needle_y.stroke_mm\"\nvalue = 18\n").unwrap();
    let e = flat(&fails(&[
        "fit",
        "--preset",
        "needle876",
        "--target",
        bad.to_str().unwrap(),
        "--adjust",
        "y_c=160:190",
    ]));
    assert!(
        e.contains("bad.toml:2:") && e.contains("no figure `needle_y.stroke_mm`") && e.contains("needle_y.range_mm"),
        "{e}"
    );
}

/// A diagnostic's words joined by single spaces, without miette's gutter
/// (it wraps long lines at the terminal's width, which differs between
/// machines).
fn flat(e: &str) -> String {
    e.split_whitespace()
        .filter(|w| !matches!(*w, "│" | "·"))
        .collect::<Vec<_>>()
        .join(" ")
}
