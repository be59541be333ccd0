//! `stitchkin plot`, run as a user would.

use super::{fails, ok, scratch};

#[test]
fn plot_writes_svg_to_stdout_or_a_file() {
    let (svg, _) = ok(&["plot", "takeup", "--step", "5"]);
    assert!(
        svg.starts_with("<svg ") && svg.trim_end().ends_with("</svg>"),
        "{}",
        &svg[..100.min(svg.len())]
    );
    assert!(svg.contains(">mf7923d: thread take-up P(φ)</text>") && !svg.contains("NaN"));
    assert_eq!(svg.matches("<polyline").count(), 9);
    let d = scratch("plot");
    let file = d.join("mu.svg");
    let (out, said) = ok(&[
        "plot",
        "mu",
        "--preset",
        "needle876",
        "--set",
        "alpha=38",
        "--step",
        "5",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(out.is_empty());
    assert!(
        said.contains("wrote ") && said.contains(file.to_str().unwrap()),
        "{said}"
    );
    let svg = std::fs::read_to_string(&file).unwrap();
    assert!(svg.contains("class=\"band\"") && svg.contains(">45</text>"));
    // Nothing but the file is left in the folder (the write is atomic).
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
    let (svg, _) = ok(&[
        "plot",
        "trajectory",
        "--preset",
        "needle876",
        "--points",
        "G,E",
        "--step",
        "10",
    ]);
    assert_eq!(svg.matches("<polyline").count(), 2);
    let (svg, _) = ok(&[
        "plot",
        "trajectory",
        "--preset",
        "altin-needle",
        "--points",
        "E",
        "--plane",
        "guide",
        "--step",
        "10",
    ]);
    assert!(svg.contains(">guide.y, mm</text>"));
}

#[test]
fn plot_rejects_bad_input_with_the_fix() {
    let e = fails(&["plot", "takeup", "--preset", "needle876"]);
    assert!(
        e.contains("has no thread paths") && e.contains("the preset mf7923d"),
        "{e}"
    );
    let e = fails(&["plot", "trajectory", "--preset", "needle876", "--points", "G,Q"]);
    assert!(e.contains("no point `Q`") && e.contains("its points are"), "{e}");
    let e = fails(&["plot", "trajectory", "--preset", "needle876"]);
    assert!(e.contains("no points to trace") && e.contains("--points"), "{e}");
    let e = fails(&["plot", "mu", "--points", "G"]);
    assert!(
        e.contains("--points is for `plot trajectory` and `plot analogs`, not `plot mu`"),
        "{e}"
    );
    let e = fails(&[
        "plot",
        "trajectory",
        "--preset",
        "altin-needle",
        "--points",
        "E",
        "--plane",
        "nope",
    ]);
    assert!(e.contains("no frame `nope`") && e.contains("guide"), "{e}");
    let e = fails(&["plot", "pie"]);
    assert!(
        e.contains("takeup") && e.contains("trajectory") && e.contains("heatmap") && e.contains("delta2d3d"),
        "{e}"
    );
}

#[test]
fn plot_draws_the_charts_over_parameters_sweeps_and_2d_3d() {
    let d = scratch("plot-kinds");
    let runs: [(&[&str], &str, usize); 7] = [
        (
            &["analogs", "--preset", "needle876", "--points", "G", "--step", "10"],
            ">velocity analog, mm/rad</text>",
            4,
        ),
        (
            &["analogs", "--thread", "n1_A", "--step", "10"],
            ">d²P/dφ², mm/rad²</text>",
            2,
        ),
        (
            &["family", "--vary", "r1=4:6", "--step", "10"],
            ">r1 = 6.0 mm</text>",
            // P and P′ per r1: the regulator's window, computed from the
            // thread's tension, moves P′ with the take-up.
            10,
        ),
        (
            &["surface", "--vary", "z=-10:10:3", "--step", "10"],
            "class=\"colorbar-label\"",
            0,
        ),
        (
            &["surface", "--vary", "dphi=-20:20:3", "--wireframe", "--step", "10"],
            "<polyline class=\"mesh\"",
            0,
        ),
        (
            &[
                "heatmap",
                "--vary",
                "z=-10:10:3",
                "--vary",
                "dphi=-20:20:3",
                "--figure",
                "n1_A.max_P_B_mm",
                "--step",
                "10",
            ],
            ">n1_A.max_P_B, mm</text>",
            0,
        ),
        (
            &["delta2d3d", "--plane", "uvw", "--thread", "n1_A,n1_B", "--step", "10"],
            ">ΔP, mm</text>",
            6,
        ),
    ];
    for (args, needle, polylines) in runs {
        let mut full = vec!["plot"];
        full.extend_from_slice(args);
        let (svg, _) = ok(&full);
        assert!(
            svg.starts_with("<svg ") && svg.trim_end().ends_with("</svg>"),
            "{args:?}"
        );
        assert!(svg.contains(needle), "{args:?}: no {needle}");
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{args:?}");
        assert_eq!(svg.matches("<polyline class=\"series\"").count(), polylines, "{args:?}");
    }
    // A nomogram into a file.
    let file = d.join("nomogram.svg");
    let (out, _) = ok(&[
        "plot",
        "nomogram",
        "--set",
        "t1_phase=180",
        "--thickness",
        "3:5:3",
        "--adjust",
        "z",
        "--step",
        "5",
        "-o",
        file.to_str().unwrap(),
    ]);
    assert!(out.is_empty());
    let svg = std::fs::read_to_string(&file).unwrap();
    assert!(
        svg.contains(">recommended z</text>")
            && svg.contains(">material thickness m, mm</text>")
            && svg.contains(">t = 3.0 mm</text>")
    );
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
}

#[test]
fn plot_rejects_bad_chart_options_with_the_fix() {
    let e = fails(&["plot", "family"]);
    assert!(
        e.contains("`plot family` needs the parameter to vary") && e.contains("r1 (4…6 mm)"),
        "{e}"
    );
    let e = fails(&["plot", "family", "--vary", "r1=4:7"]);
    assert!(
        e.contains("outside its adjustable range") && e.contains("(in --vary)") && e.contains("between 4 and 6"),
        "{e}"
    );
    let e = fails(&["plot", "surface", "--vary", "q=1:2"]);
    assert!(e.contains("no parameter `q`") && e.contains("--vary"), "{e}");
    let e = fails(&["plot", "family", "--vary", "r1=4:6:1"]);
    assert!(e.contains("at least 2") && e.contains("N ≥ 2"), "{e}");
    let e = fails(&["plot", "family", "--vary", "r1=4:6", "--vary", "z=-1:1"]);
    assert!(e.contains("varies one parameter") && e.contains("plot heatmap"), "{e}");
    let e = fails(&["plot", "family", "--vary", "r1=4:6", "--thread", "n1_A,n1_B"]);
    assert!(e.contains("draws one thread path"), "{e}");
    let e = fails(&["plot", "heatmap", "--vary", "z=-10:10:3", "--figure", "n1_A.max_P_B_mm"]);
    assert!(e.contains("exactly 2 --vary, got 1"), "{e}");
    let e = fails(&[
        "plot",
        "heatmap",
        "--vary",
        "z=-10:10:3",
        "--vary",
        "dphi=-20:20:3",
        "--step",
        "30",
    ]);
    assert!(
        e.contains("needs the figure of merit") && e.contains("n1_A.max_P_B_mm"),
        "{e}"
    );
    let e = fails(&[
        "plot",
        "heatmap",
        "--vary",
        "z=-10:10:3",
        "--vary",
        "dphi=-20:20:3",
        "--figure",
        "bogus",
        "--step",
        "30",
    ]);
    assert!(
        e.contains("no figure of merit matches `bogus`") && e.contains("--figure"),
        "{e}"
    );
    let e = fails(&["plot", "takeup", "--vary", "r1=4:6"]);
    assert!(
        e.contains("--vary is for `plot family`, `plot surface`, `plot heatmap` and `plot motion`, not `plot takeup`"),
        "{e}"
    );
    let e = fails(&["plot", "family", "--vary", "r1=4:6", "--figure", "score.mean"]);
    assert!(e.contains("--figure is for `plot heatmap`"), "{e}");
    // One thickness for a cycle's chart, an axis of them for a nomogram.
    let e = fails(&["plot", "mu", "--thickness", "3:5:3"]);
    assert!(
        e.contains("`3:5:3` is a range, and this command takes one thickness (in --thickness)")
            && e.contains("stitchkin plot nomogram"),
        "{e}"
    );
    let e = fails(&["plot", "nomogram", "--preset", "needle876"]);
    assert!(e.contains("no [stitch]"), "{e}");
    let e = fails(&["plot", "nomogram", "--thickness", "3"]);
    assert!(
        e.contains("one thickness (3 mm) is given") && e.contains("(in --thickness)"),
        "{e}"
    );
    let e = fails(&["plot", "nomogram", "--thickness", "0:9:3"]);
    assert!(e.contains("outside"), "{e}");
    let e = fails(&["plot", "delta2d3d", "--plane", "nope"]);
    assert!(e.contains("no frame `nope`") && e.contains("uvw"), "{e}");
    let e = fails(&["plot", "analogs", "--preset", "needle876"]);
    assert!(e.contains("needs points") && e.contains("G"), "{e}");
    let e = fails(&["plot", "analogs", "--thread", "n9"]);
    assert!(e.contains("no thread path `n9`") && e.contains("n3_B"), "{e}");
    let e = fails(&["plot", "surface", "--vary", "r1=4:6", "--step", "0"]);
    assert!(e.contains("step"), "{e}");
}

/// The y values a chart's polylines draw, back from pixels through the
/// y ticks (each label sits 4 px below its grid line).
fn drawn_y(svg: &str) -> Vec<Vec<f64>> {
    let attr = |l: &str, name: &str| -> String {
        let at = l.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        l[at..].split('"').next().unwrap().to_string()
    };
    let ticks: Vec<(f64, f64)> = svg
        .lines()
        .filter(|l| l.starts_with("<text class=\"tick y\""))
        .map(|l| {
            (
                attr(l, "y").parse::<f64>().unwrap() - 4.0,
                l[l.find('>').unwrap() + 1..l.rfind("</text>").unwrap()]
                    .parse()
                    .unwrap(),
            )
        })
        .collect();
    let ((p0, v0), (p1, v1)) = (ticks[0], ticks[ticks.len() - 1]);
    svg.lines()
        .filter(|l| l.starts_with("<polyline class=\"series\""))
        .map(|l| {
            attr(l, "points")
                .split_whitespace()
                .map(|q| v0 + (q.split_once(',').unwrap().1.parse::<f64>().unwrap() - p0) / (p1 - p0) * (v1 - v0))
                .collect()
        })
        .collect()
}

#[test]
fn plot_draws_motion_laws_and_their_families() {
    // The needle's height over one cycle: its stroke is needle876's 18.08 mm.
    let (svg, _) = ok(&["plot", "motion", "--preset", "needle876", "--series", "needle_y"]);
    assert!(svg.contains(">needle876: motion law needle_y</text>") && svg.contains(">needle_y, mm</text>"));
    let lines = drawn_y(&svg);
    assert_eq!(lines.len(), 1);
    let (lo, hi) = lines[0]
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(
        (hi - lo - 18.08).abs() < 0.01 && (lo - 107.475).abs() < 0.01,
        "{lo}…{hi}"
    );
    // mm and deg in two panels; short and full names alike.
    let (svg, _) = ok(&[
        "plot",
        "motion",
        "--preset",
        "needle876",
        "--series",
        "G.y_mm,angle_C_B,mu_23_deg",
        "--step",
        "10",
    ]);
    assert_eq!(svg.matches("class=\"panel-title\"").count(), 2);
    assert!(svg.contains(">G.y, mm</text>") && svg.contains(">angle_C_B, mu_23, deg</text>"));
    assert_eq!(svg.matches("<polyline class=\"series\"").count(), 3);
    // A family: N lines per series, legend as `plot family` writes it.
    let (svg, _) = ok(&[
        "plot",
        "motion",
        "--preset",
        "needle876",
        "--series",
        "G.y",
        "--vary",
        "alpha=0:35:3",
        "--step",
        "10",
    ]);
    assert_eq!(svg.matches("<polyline class=\"series\"").count(), 3);
    for v in ["alpha = 0.0 deg", "alpha = 17.5 deg", "alpha = 35.0 deg"] {
        assert!(svg.contains(&format!(">{v}</text>")), "no legend {v}");
    }
    let strokes: Vec<f64> = drawn_y(&svg)
        .iter()
        .map(|l| l.iter().fold(f64::MIN, |a, &b| a.max(b)) - l.iter().fold(f64::MAX, |a, &b| a.min(b)))
        .collect();
    assert!(
        strokes.windows(2).all(|w| w[1] > w[0] + 1.0) && (strokes[0] - 18.08).abs() < 0.05,
        "{strokes:?}"
    );
    // One series over φ and a parameter as a surface.
    let (svg, _) = ok(&[
        "plot",
        "surface",
        "--preset",
        "needle876",
        "--series",
        "G.y",
        "--vary",
        "alpha=0:35:4",
        "--wireframe",
        "--step",
        "10",
    ]);
    assert_eq!(svg.matches("<polyline class=\"mesh\"").count(), 4);
    assert!(svg.contains(">G.y, mm</text>") && svg.contains(">alpha, deg</text>"));
    let (svg, _) = ok(&[
        "plot",
        "surface",
        "--preset",
        "needle876",
        "--series",
        "angle_E_G",
        "--vary",
        "alpha=0:35:3",
        "--step",
        "30",
    ]);
    assert_eq!(svg.matches("<rect class=\"cell\"").count(), 3 * 13);
    assert!(svg.contains("class=\"colorbar-label\"") && svg.contains(">angle_E_G, deg</text>"));
}

#[test]
fn plot_motion_rejects_bad_input_with_the_fix() {
    let needle = ["plot", "motion", "--preset", "needle876", "--series", "G.y"];
    let with = |more: &[&'static str]| -> Vec<&'static str> { needle.iter().chain(more).copied().collect() };
    let cases: Vec<(Vec<&str>, &[&str])> = vec![
        (
            vec!["plot", "motion", "--preset", "needle876", "--series", "G.y,Q.y"],
            &[
                "no series `Q.y`",
                "(in --series)",
                "moving points A, B, D, E, G",
                "angle_C_B_deg",
            ],
        ),
        (
            vec!["plot", "motion", "--preset", "needle876"],
            &["no series to draw", "--series"],
        ),
        (
            vec!["plot", "mu", "--series", "G.y"],
            &["--series is for `plot motion` and `plot surface`, not `plot mu`"],
        ),
        (with(&["--thread", "n1_A"]), &["--thread is for", "not `plot motion`"]),
        (
            with(&["--vary", "alpha=0:50"]),
            &["outside its adjustable range", "(in --vary)"],
        ),
        (with(&["--vary", "alpha=0:35:1"]), &["at least 2"]),
        (
            with(&["--vary", "alpha=0:35", "--vary", "alpha=0:20"]),
            &["varies one parameter"],
        ),
        (
            vec![
                "plot",
                "surface",
                "--preset",
                "needle876",
                "--series",
                "G.y,E.y",
                "--vary",
                "alpha=0:35",
            ],
            &["draws one series; --series names 2"],
        ),
        (
            vec![
                "plot",
                "surface",
                "--series",
                "angle_O2_B",
                "--thread",
                "n1_A",
                "--vary",
                "r1=4:6",
            ],
            &["(--thread) or a motion law (--series), not both"],
        ),
        (
            vec!["plot", "surface", "--preset", "needle876", "--series", "G.y"],
            &["needs the parameter to vary"],
        ),
    ];
    for (args, needles) in cases {
        let e = fails(&args);
        for n in needles {
            assert!(e.contains(n), "{args:?}: no `{n}` in\n{e}");
        }
        assert!(!e.contains("panicked"), "{args:?}");
    }
}

// docs/plots.md's examples run in `picture_docs_examples_run` (cli.rs).

#[test]
fn plot_writes_png_of_the_same_drawing() {
    let dir = scratch("plot-png");
    let png = dir.join("takeup.png");
    let svg = dir.join("takeup.svg");
    ok(&["plot", "takeup", "--step", "5", "-o", png.to_str().unwrap()]);
    ok(&["plot", "takeup", "--step", "5", "-o", svg.to_str().unwrap()]);
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height are the SVG's times 2 px per unit.
    let text = std::fs::read_to_string(&svg).unwrap();
    let attr = |name: &str| -> u32 {
        let at = text.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        text[at..].split('"').next().unwrap().parse::<f64>().unwrap() as u32
    };
    assert_eq!(u32::from_be_bytes(bytes[16..20].try_into().unwrap()), 2 * attr("width"));
    assert_eq!(
        u32::from_be_bytes(bytes[20..24].try_into().unwrap()),
        2 * attr("height")
    );
    assert!(
        bytes.len() > 20_000,
        "a chart, not a blank picture: {} bytes",
        bytes.len()
    );
}

#[test]
fn plot_refuses_an_unknown_picture_format_before_computing() {
    let dir = scratch("plot-jpg");
    let jpg = dir.join("takeup.jpg");
    let err = fails(&["plot", "takeup", "-o", jpg.to_str().unwrap()]);
    assert!(err.contains(".svg") && err.contains(".png"), "{err}");
    assert!(!jpg.exists());
}

#[test]
fn plot_and_draw_refuse_a_missing_folder_before_computing() {
    let dir = scratch("plot-nofolder");
    for cmd in [&["plot", "nomogram"][..], &["draw"][..]] {
        let out = dir.join("no/such/folder/x.svg");
        let mut args = cmd.to_vec();
        args.extend(["-o", out.to_str().unwrap()]);
        assert!(fails(&args).contains("there is no folder"), "{cmd:?}");
    }
}
