//! `stitchkin report`.

use super::{fails, ok, scratch};

#[test]
fn report_writes_one_html_file() {
    let dir = scratch("report");
    let out = dir.join("r.html");
    let (_, said) = ok(&["report", "--step", "3", "--no-animation", "-o", out.to_str().unwrap()]);
    assert!(said.contains("wrote ") && said.contains("kB"), "{said}");
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert!(html.contains("<section id=\"mismatch\">"));
    assert!(html.trim_end().ends_with("</html>"));
}

#[test]
fn report_refuses_bad_output_and_options() {
    let dir = scratch("report-bad");
    let txt = dir.join("r.txt");
    assert!(fails(&["report", "-o", txt.to_str().unwrap()]).contains(".html"));
    assert!(!txt.exists());
    let missing = dir.join("no/such/folder/r.html");
    assert!(fails(&["report", "-o", missing.to_str().unwrap()]).contains("no folder"));
    assert!(fails(&["report", "--view", "sideways"]).contains("sideways"));
    // The stitch axis of a nomogram needs its thickness axis.
    assert!(fails(&["report", "--nomogram-stitch", "2:3:2"]).contains("--nomogram-thickness"));
}
