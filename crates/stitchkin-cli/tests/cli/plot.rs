//! `stitchkin plot`, run as a user would.

use super::{fails, ok, scratch};

#[test]
fn plot_writes_svg_to_stdout_or_a_file() {
    let (svg, _) = ok(&["plot", "takeup", "--step", "5"]);
    assert!(svg.starts_with("<svg ") && svg.trim_end().ends_with("</svg>"), "{}", &svg[..100.min(svg.len())]);
    assert!(svg.contains(">mf7923d: thread take-up P(φ)</text>") && !svg.contains("NaN"));
    assert_eq!(svg.matches("<polyline").count(), 9);
    let d = scratch("plot");
    let file = d.join("mu.svg");
    let (out, _) = ok(&["plot", "mu", "--preset", "needle876", "--set", "alpha=38", "--step", "5", "-o", file.to_str().unwrap()]);
    assert!(out.is_empty());
    let svg = std::fs::read_to_string(&file).unwrap();
    assert!(svg.contains("class=\"band\"") && svg.contains(">45</text>"));
    // Nothing but the file is left in the folder (the write is atomic).
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
    let (svg, _) = ok(&["plot", "trajectory", "--preset", "needle876", "--points", "G,E", "--step", "10"]);
    assert_eq!(svg.matches("<polyline").count(), 2);
    let (svg, _) = ok(&["plot", "trajectory", "--preset", "altin-needle", "--points", "E", "--plane", "guide", "--step", "10"]);
    assert!(svg.contains(">guide.y, mm</text>"));
}

#[test]
fn plot_rejects_bad_input_with_the_fix() {
    let e = fails(&["plot", "takeup", "--preset", "needle876"]);
    assert!(e.contains("has no thread paths") && e.contains("--preset mf7923d"), "{e}");
    let e = fails(&["plot", "trajectory", "--preset", "needle876", "--points", "G,Q"]);
    assert!(e.contains("no point `Q`") && e.contains("its points are"), "{e}");
    let e = fails(&["plot", "trajectory", "--preset", "needle876"]);
    assert!(e.contains("no points to trace") && e.contains("--points"), "{e}");
    let e = fails(&["plot", "mu", "--points", "G"]);
    assert!(e.contains("--points and --plane are for `plot trajectory`"), "{e}");
    let e = fails(&["plot", "trajectory", "--preset", "altin-needle", "--points", "E", "--plane", "nope"]);
    assert!(e.contains("no frame `nope`") && e.contains("guide"), "{e}");
    let e = fails(&["plot", "pie"]);
    assert!(e.contains("takeup") && e.contains("trajectory"), "{e}");
}
