//! `stitchkin plot`'s SVG charts, checked for structure: well-formed, one
//! polyline per series, labelled axes with units, legends naming the
//! series, a y-axis covering the data, shading where guides engage, no NaN.

use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::jobs::plot::{Plot, render};
use stitchkin::model::Model;

/// Balanced tags, checked with a small stack (no text contains `<` or `>`:
/// the writer escapes them).
fn assert_well_formed(svg: &str) {
    assert!(
        svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""),
        "{}",
        &svg[..80.min(svg.len())]
    );
    let mut stack: Vec<String> = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find('<') {
        let j = rest[i..].find('>').expect("an unclosed tag") + i;
        let tag = &rest[i + 1..j];
        assert!(!tag.contains('<'), "`<` inside a tag: {tag}");
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop().as_deref(), Some(name.trim()), "mismatched </{name}>");
        } else if !tag.ends_with('/') {
            stack.push(tag.split_whitespace().next().unwrap().to_string());
        }
        // Text between tags has its `&` escaped.
        let text_end = rest[j..].find('<').map_or(rest.len(), |k| k + j);
        for (k, _) in rest[j + 1..text_end].match_indices('&') {
            let t = &rest[j + 1 + k..text_end];
            assert!(
                ["&amp;", "&lt;", "&gt;", "&quot;", "&#39;"]
                    .iter()
                    .any(|e| t.starts_with(e)),
                "unescaped & in {t}"
            );
        }
        rest = &rest[j + 1..];
    }
    assert!(stack.is_empty(), "unclosed: {stack:?}");
}

/// Every attribute value `name="…"` of the elements whose tag starts with `start`.
fn attrs<'a>(svg: &'a str, start: &str, name: &str) -> Vec<&'a str> {
    svg.lines()
        .filter(|l| l.starts_with(start))
        .filter_map(|l| {
            let key = format!(" {name}=\"");
            let i = l.find(&key)? + key.len();
            Some(&l[i..i + l[i..].find('"').unwrap()])
        })
        .collect()
}

/// The texts of `<text class="CLASS" …>TEXT</text>`.
fn texts<'a>(svg: &'a str, class: &str) -> Vec<&'a str> {
    svg.lines()
        .filter(|l| l.starts_with(&format!("<text class=\"{class}\"")))
        .map(|l| {
            let i = l.find('>').unwrap() + 1;
            &l[i..l.rfind("</text>").unwrap()]
        })
        .collect()
}

fn assert_no_nan(svg: &str) {
    assert!(
        !svg.contains("NaN") && !svg.contains("inf"),
        "a non-finite number in the SVG"
    );
    for pts in attrs(svg, "<polyline", "points") {
        assert!(!pts.is_empty(), "an empty polyline");
        for p in pts.split_whitespace() {
            let (x, y) = p.split_once(',').unwrap();
            assert!(
                x.parse::<f64>().unwrap().is_finite() && y.parse::<f64>().unwrap().is_finite(),
                "{p}"
            );
        }
    }
    for a in ["x", "y", "width", "height"] {
        for v in attrs(svg, "<rect", a) {
            assert!(v.parse::<f64>().unwrap().is_finite(), "rect {a}={v}");
        }
    }
}

fn table(model: &Model, points: Option<Vec<usize>>) -> CycleTable {
    run_cycle(
        model,
        &model.defaults(),
        &CycleOptions {
            analogs: false,
            points,
            ..Default::default()
        },
    )
    .unwrap()
}

fn min_max<'a>(cols: impl Iterator<Item = &'a [f64]>) -> (f64, f64) {
    cols.flatten()
        .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)))
}

fn y_ticks(svg: &str) -> Vec<f64> {
    texts(svg, "tick y").iter().map(|t| t.parse().unwrap()).collect()
}

#[test]
fn mf7923d_take_up_plot_shows_every_path_and_thread() {
    let model = Model::preset("mf7923d").unwrap();
    let svg = render(&model, &model.defaults(), &Plot::TakeUp, 1.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    let t = table(&model, Some(Vec::new()));
    let stitch = t.stitch.as_ref().unwrap();
    let mut names: Vec<String> = t.paths.iter().map(|p| p.path.clone()).collect();
    names.extend(stitch.threads.iter().map(|th| format!("{} P′", th.thread)));
    assert_eq!(names.len(), 9, "{names:?}");
    assert_eq!(texts(&svg, "legend"), names);
    assert_eq!(attrs(&svg, "<polyline", "data-name"), names);
    assert_eq!(svg.matches("<polyline").count(), names.len());
    // P' dashed, in its path's colour; P solid.
    let dashed: Vec<&str> = svg
        .lines()
        .filter(|l| l.starts_with("<polyline") && l.contains("stroke-dasharray"))
        .collect();
    assert_eq!(dashed.len(), 3);
    let colours = attrs(&svg, "<polyline", "stroke");
    for (j, th) in stitch.threads.iter().enumerate() {
        let k = t.paths.iter().position(|p| Some(&p.path) == th.path.as_ref()).unwrap();
        assert_eq!(colours[6 + j], colours[k], "{}", th.thread);
    }
    assert_eq!(texts(&svg, "axis-label x"), ["φ, deg"]);
    assert_eq!(texts(&svg, "axis-label y"), ["P, mm"]);
    assert!(texts(&svg, "title")[0].contains("mf7923d"));
    // The y axis covers every P and P'.
    let (lo, hi) = min_max(
        t.columns
            .iter()
            .filter(|c| c.name.ends_with(".P_B_mm") || c.name.ends_with(".Pprime_B_mm"))
            .map(|c| c.values.as_slice()),
    );
    let ticks = y_ticks(&svg);
    assert!(
        ticks.first().unwrap() <= &lo && ticks.last().unwrap() >= &hi,
        "{ticks:?} vs {lo}…{hi}"
    );
    // x over one cycle from the model's start, ticks every 45°.
    assert_eq!(
        texts(&svg, "tick x"),
        ["0", "45", "90", "135", "180", "225", "270", "315", "360"]
    );
    // The guides engage 256°…104° (across the cycle's end): two shaded
    // stretches, shared by all six paths.
    assert!(
        t.paths
            .iter()
            .all(|p| !p.engaged.is_empty() && !p.engaged[0].1.is_empty())
    );
    let shades: Vec<&str> = svg.lines().filter(|l| l.starts_with("<rect class=\"shade\"")).collect();
    assert_eq!(shades.len(), 2, "{shades:?}");
    assert!(shades[0].contains("engaged 256°…104°: n1_A G4_1"), "{}", shades[0]);
    // Needle threads are measured at B, and the subtitle says so and where
    // the regulator window is.
    let sub = &texts(&svg, "subtitle")[0];
    assert!(
        sub.contains("at B") && sub.contains("regulator windows 19°…48°, 94°…113°, 215°…237° of n1 (computed)"),
        "{sub}"
    );
}

#[test]
fn needle876_transmission_angle_plot_marks_the_band() {
    let model = Model::preset("needle876").unwrap();
    let mut params = model.defaults();
    model.set_str(&mut params, "alpha=38").unwrap();
    let svg = render(&model, &params, &Plot::Mu, 2.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    let keys: Vec<String> = model.dyads().iter().map(|d| d.key.clone()).collect();
    assert_eq!(texts(&svg, "legend"), keys);
    assert_eq!(svg.matches("<polyline").count(), keys.len());
    assert_eq!(texts(&svg, "axis-label y"), ["μ, deg"]);
    assert_eq!(y_ticks(&svg), [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0]);
    assert_eq!(svg.matches("class=\"band\"").count(), 2);
    assert_eq!(svg.matches("class=\"ref\"").count(), 2);
    // φ from needle876's start, 90.6°.
    assert_eq!(texts(&svg, "tick x")[0], "135");
    // Each series closes the cycle: 180 steps and the first again.
    assert!(
        attrs(&svg, "<polyline", "points")
            .iter()
            .all(|p| p.split_whitespace().count() == 181)
    );
}

#[test]
fn needle876_trajectories_are_to_scale() {
    let model = Model::preset("needle876").unwrap();
    let svg = render(
        &model,
        &model.defaults(),
        &Plot::Trajectory {
            points: vec!["G".into(), "E".into()],
            plane: None,
        },
        5.0,
    )
    .unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    assert_eq!(texts(&svg, "legend"), ["G", "E"]);
    assert_eq!(svg.matches("<polyline").count(), 2);
    assert_eq!(svg.matches("<circle class=\"start\"").count(), 2);
    assert_eq!(
        (texts(&svg, "axis-label x"), texts(&svg, "axis-label y")),
        (vec!["x, mm"], vec!["y, mm"])
    );
    // Pixels per mm alike on both axes.
    let pos = |class: &str, a: &str| -> Vec<f64> {
        svg.lines()
            .filter(|l| l.starts_with(&format!("<text class=\"{class}\"")))
            .map(|l| {
                let k = format!(" {a}=\"");
                let i = l.find(&k).unwrap() + k.len();
                l[i..i + l[i..].find('"').unwrap()].parse().unwrap()
            })
            .collect()
    };
    let (xv, yv): (Vec<f64>, Vec<f64>) = (
        texts(&svg, "tick x").iter().map(|t| t.parse().unwrap()).collect(),
        y_ticks(&svg),
    );
    let (xp, yp) = (pos("tick x", "x"), pos("tick y", "y"));
    let sx = (xp[1] - xp[0]) / (xv[1] - xv[0]);
    let sy = (yp[0] - yp[1]) / (yv[1] - yv[0]);
    assert!((sx - sy).abs() < 0.02, "{sx} vs {sy} px/mm");
    // The needle G's stroke (seed 002: 18.08 mm) fits in the y ticks' span.
    let t = table(
        &model,
        Some(vec![model.point_names().iter().position(|p| p == "G").unwrap()]),
    );
    let (lo, hi) = min_max(std::iter::once(t.column("G.y_mm").unwrap()));
    assert!((hi - lo - 18.08).abs() < 0.01);
    assert!(yv.first().unwrap() - 10.0 <= lo && yv.last().unwrap() + 10.0 >= hi);
}

#[test]
fn trajectories_can_be_drawn_in_a_frame() {
    // The Altin needle runs along its 20° guide: in the guide frame its
    // path is nearly vertical (seed 004).
    let model = Model::preset("altin-needle").unwrap();
    let plot = Plot::Trajectory {
        points: vec!["E".into()],
        plane: Some("guide".into()),
    };
    let svg = render(&model, &model.defaults(), &plot, 5.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    assert_eq!(
        (texts(&svg, "axis-label x"), texts(&svg, "axis-label y")),
        (vec!["guide.x, mm"], vec!["guide.y, mm"])
    );
    let pts: Vec<(f64, f64)> = attrs(&svg, "<polyline", "points")[0]
        .split_whitespace()
        .map(|p| {
            p.split_once(',')
                .map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap()))
                .unwrap()
        })
        .collect();
    let span = |f: fn(&(f64, f64)) -> f64| {
        pts.iter().map(f).fold(f64::MIN, f64::max) - pts.iter().map(f).fold(f64::MAX, f64::min)
    };
    assert!(
        span(|p| p.0) < 0.1 * span(|p| p.1),
        "x span {} px, y span {} px",
        span(|p| p.0),
        span(|p| p.1)
    );
    let e = render(
        &model,
        &model.defaults(),
        &Plot::Trajectory {
            points: vec!["E".into()],
            plane: Some("nope".into()),
        },
        5.0,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no frame `nope`"), "{e}");
}

#[test]
fn bad_input_gets_a_clear_error() {
    let model = Model::preset("needle876").unwrap();
    let p = model.defaults();
    let e = render(&model, &p, &Plot::TakeUp, 1.0).unwrap_err().to_string();
    assert!(e.contains("no thread paths"), "{e}");
    let e = render(
        &model,
        &p,
        &Plot::Trajectory {
            points: vec!["Q".into()],
            plane: None,
        },
        1.0,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no point `Q`"), "{e}");
    let e = render(
        &model,
        &p,
        &Plot::Trajectory {
            points: vec![],
            plane: None,
        },
        1.0,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no points"), "{e}");
    let e = render(&model, &p, &Plot::Mu, 0.0).unwrap_err().to_string();
    assert!(e.contains("step"), "{e}");
}

// ---- The charts over a varied parameter, a sweep, a nomogram, 2D/3D ----

use stitchkin::jobs::plot::parse_vary;
use stitchkin::study::design::Vary;
use stitchkin::study::nomogram::{Axis as GridAxis, NomogramOptions};
use stitchkin::study::tune::TuneOptions;

/// The panels of a stacked figure: the text from each `panel-title` to the next.
fn panels(svg: &str) -> Vec<&str> {
    let starts: Vec<usize> = svg
        .match_indices("<text class=\"panel-title\"")
        .map(|(i, _)| i)
        .collect();
    starts
        .iter()
        .enumerate()
        .map(|(k, &i)| &svg[i..starts.get(k + 1).copied().unwrap_or(svg.len())])
        .collect()
}

/// The points of every polyline, in pixels.
fn polylines(svg: &str) -> Vec<Vec<(f64, f64)>> {
    attrs(svg, "<polyline", "points")
        .iter()
        .map(|p| {
            p.split_whitespace()
                .map(|q| {
                    q.split_once(',')
                        .map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap()))
                        .unwrap()
                })
                .collect()
        })
        .collect()
}

fn numbers(texts: &[&str]) -> Vec<f64> {
    texts
        .iter()
        .map(|t| t.parse().unwrap_or_else(|_| panic!("`{t}` is not a number")))
        .collect()
}

/// An error's message and its help.
fn full(e: stitchkin::error::Error) -> String {
    match &e {
        stitchkin::error::Error::Param(p) => format!("{p} | {}", p.help.clone().unwrap_or_default()),
        e => e.to_string(),
    }
}

fn vary(name: &str, lo: f64, hi: f64, n: usize) -> Vary {
    Vary {
        name: name.into(),
        lo,
        hi,
        n,
    }
}

fn column_of(model: &Model, set: &[(&str, f64)], step: f64, name: &str) -> Vec<f64> {
    let mut p = model.defaults();
    for (k, v) in set {
        model.set(&mut p, k, *v).unwrap();
    }
    let t = run_cycle(
        model,
        &p,
        &CycleOptions {
            step_deg: step,
            ..Default::default()
        },
    )
    .unwrap();
    t.column(name).unwrap_or_else(|| panic!("no column {name}")).to_vec()
}

#[test]
fn analogs_of_points_come_in_two_panels_with_units() {
    let model = Model::preset("needle876").unwrap();
    let plot = Plot::Analogs {
        points: vec!["G".into(), "E".into()],
        threads: vec![],
    };
    let svg = render(&model, &model.defaults(), &plot, 5.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    let p = panels(&svg);
    assert_eq!(p.len(), 2);
    assert_eq!(texts(p[0], "legend"), ["G dx/dφ", "G dy/dφ", "E dx/dφ", "E dy/dφ"]);
    assert_eq!(
        texts(p[1], "legend"),
        ["G d²x/dφ²", "G d²y/dφ²", "E d²x/dφ²", "E d²y/dφ²"]
    );
    assert_eq!(
        texts(&svg, "axis-label y"),
        ["velocity analog, mm/rad", "acceleration analog, mm/rad²"]
    );
    assert_eq!(texts(&svg, "axis-label x"), ["φ, deg", "φ, deg"]);
    assert_eq!(svg.matches("<polyline").count(), 8);
    // 72 steps and the first again; each panel's y ticks cover its data.
    assert!(polylines(&svg).iter().all(|l| l.len() == 73));
    let pts: Vec<usize> = ["G", "E"]
        .iter()
        .map(|q| model.point_names().iter().position(|p| p == q).unwrap())
        .collect();
    for (panel, suffix) in p.iter().zip(["dy_dphi_mm_per_rad", "d2y_dphi2_mm_per_rad2"]) {
        let t = run_cycle(
            &model,
            &model.defaults(),
            &CycleOptions {
                step_deg: 5.0,
                points: Some(pts.clone()),
                ..Default::default()
            },
        )
        .unwrap();
        let (lo, hi) = min_max(["G", "E"].iter().map(|q| t.column(&format!("{q}.{suffix}")).unwrap()));
        let ticks = y_ticks(panel);
        assert!(ticks[0] <= lo && *ticks.last().unwrap() >= hi, "{ticks:?} vs {lo}…{hi}");
        assert!(hi - lo > 5.0, "{suffix}: {lo}…{hi}");
    }
}

#[test]
fn take_up_analogs_of_the_thread_paths() {
    let model = Model::preset("mf7923d").unwrap();
    let svg = render(
        &model,
        &model.defaults(),
        &Plot::Analogs {
            points: vec![],
            threads: vec![],
        },
        5.0,
    )
    .unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    let names = ["n1_A", "n1_B", "n2_A", "n2_B", "n3_A", "n3_B"];
    for p in panels(&svg) {
        assert_eq!(texts(p, "legend"), names);
    }
    assert_eq!(texts(&svg, "axis-label y"), ["dP/dφ, mm/rad", "d²P/dφ², mm/rad²"]);
    let one = render(
        &model,
        &model.defaults(),
        &Plot::Analogs {
            points: vec![],
            threads: vec!["n3_B".into()],
        },
        5.0,
    )
    .unwrap();
    assert_eq!(texts(&one, "legend"), ["n3_B", "n3_B"]);
    let e = full(
        render(
            &model,
            &model.defaults(),
            &Plot::Analogs {
                points: vec![],
                threads: vec!["n9".into()],
            },
            5.0,
        )
        .unwrap_err(),
    );
    assert!(
        e.contains("no thread path `n9` (in `thread`)") && e.contains("n1_A"),
        "{e}"
    );
    let e = full(
        render(
            &model,
            &model.defaults(),
            &Plot::Analogs {
                points: vec!["E".into()],
                threads: vec!["n1_A".into()],
            },
            5.0,
        )
        .unwrap_err(),
    );
    assert!(e.contains("not both"), "{e}");
    let needle = Model::preset("needle876").unwrap();
    let e = full(
        render(
            &needle,
            &needle.defaults(),
            &Plot::Analogs {
                points: vec![],
                threads: vec![],
            },
            5.0,
        )
        .unwrap_err(),
    );
    assert!(e.contains("needs points") && e.contains("(in `points`)"), "{e}");
}

#[test]
fn a_family_of_take_up_curves_over_r1_with_the_required_take_up() {
    // Seed 000 Fig. 7 b: r1 from 4 to 6 mm; with T1 up at the needle's TDC
    // the larger swing takes back more thread while the needle descends, so
    // max P_B falls (17.5 → 0.3 mm; seed 000 states a rise,
    // docs/published-facts.md); P' of needle 1 for comparison.
    let model = Model::preset("mf7923d").unwrap();
    let plot = Plot::Family {
        vary: vary("r1", 4.0, 6.0, 5),
        thread: None,
    };
    let svg = render(&model, &model.defaults(), &plot, 5.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    assert_eq!(
        texts(&svg, "legend"),
        [
            "r1 = 4.0 mm",
            "r1 = 4.5 mm",
            "r1 = 5.0 mm",
            "r1 = 5.5 mm",
            "r1 = 6.0 mm",
            // The regulator's window is computed for each setting, so P′
            // (which draws the stitch's thread across it) is each value's.
            "n1 P′, r1 = 4.0 mm",
            "n1 P′, r1 = 4.5 mm",
            "n1 P′, r1 = 5.0 mm",
            "n1 P′, r1 = 5.5 mm",
            "n1 P′, r1 = 6.0 mm"
        ]
    );
    assert_eq!(svg.matches("<polyline").count(), 10);
    assert_eq!(
        svg.lines()
            .filter(|l| l.starts_with("<polyline") && l.contains("stroke-dasharray"))
            .count(),
        5
    );
    assert_eq!(texts(&svg, "axis-label y"), ["P, mm"]);
    assert!(texts(&svg, "title")[0].contains("mf7923d") && texts(&svg, "title")[0].contains("n1_A"));
    // Five distinct colours of the ramp.
    let colours = attrs(&svg, "<polyline", "stroke");
    let mut distinct = colours[..5].to_vec();
    distinct.dedup();
    assert_eq!(distinct.len(), 5, "{colours:?}");
    // Larger r1, lower peak: the top of each curve (smallest pixel y) sinks.
    let tops: Vec<f64> = polylines(&svg)[..5]
        .iter()
        .map(|l| l.iter().map(|p| p.1).fold(f64::MAX, f64::min))
        .collect();
    assert!(tops.windows(2).all(|w| w[1] > w[0] + 5.0), "{tops:?}");
    // The y axis covers P at r1 = 4 and 6 and P'.
    let p4 = column_of(&model, &[("r1", 4.0)], 5.0, "n1_A.P_B_mm");
    let p6 = column_of(&model, &[("r1", 6.0)], 5.0, "n1_A.P_B_mm");
    let pp = column_of(&model, &[], 5.0, "n1.Pprime_B_mm");
    let (lo, hi) = min_max([p4.as_slice(), p6.as_slice(), pp.as_slice()].into_iter());
    let ticks = y_ticks(&svg);
    assert!(ticks[0] <= lo && *ticks.last().unwrap() >= hi, "{ticks:?} vs {lo}…{hi}");
    let peak = |v: &[f64]| v.iter().fold(f64::MIN, |a, &b| a.max(b));
    assert!(peak(&p4) - peak(&p6) > 15.0, "{} {}", peak(&p4), peak(&p6));
}

#[test]
fn a_family_over_the_thickness_draws_p_prime_per_value() {
    // m moves P' but not P: one dashed P' per value, in its colour.
    let model = Model::preset("mf7923d").unwrap();
    let plot = Plot::Family {
        vary: vary("m", 1.0, 5.0, 3),
        thread: Some("n3_A".into()),
    };
    let svg = render(&model, &model.defaults(), &plot, 10.0).unwrap();
    assert_no_nan(&svg);
    assert_eq!(
        texts(&svg, "legend"),
        [
            "m = 1 mm",
            "m = 3 mm",
            "m = 5 mm",
            "n3 P′, m = 1 mm",
            "n3 P′, m = 3 mm",
            "n3 P′, m = 5 mm"
        ]
    );
    let colours = attrs(&svg, "<polyline", "stroke");
    assert_eq!(colours[..3], colours[3..]);
    assert!(texts(&svg, "subtitle")[0].contains("P is the same for every value"));
}

#[test]
fn surface_heat_map_of_p_over_phi_and_z() {
    let model = Model::preset("mf7923d").unwrap();
    let plot = Plot::Surface {
        vary: vary("z", -10.0, 10.0, 5),
        thread: None,
        wireframe: false,
    };
    let svg = render(&model, &model.defaults(), &plot, 10.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    // One cell per (z, φ), φ closed at 360°.
    assert_eq!(svg.matches("<rect class=\"cell\"").count(), 5 * 37);
    assert_eq!(svg.matches("class=\"cell missing\"").count(), 0);
    assert_eq!(
        (texts(&svg, "axis-label x"), texts(&svg, "axis-label y")),
        (vec!["φ, deg"], vec!["z, mm"])
    );
    assert_eq!(
        texts(&svg, "tick x"),
        ["0", "45", "90", "135", "180", "225", "270", "315", "360"]
    );
    assert_eq!(numbers(&texts(&svg, "tick y")), [-10.0, -5.0, 0.0, 5.0, 10.0]);
    assert_eq!(texts(&svg, "colorbar-label"), ["P, mm"]);
    // The colour bar spans the P of every row; its ticks lie inside.
    let all: Vec<Vec<f64>> = [-10.0, -5.0, 0.0, 5.0, 10.0]
        .iter()
        .map(|&z| column_of(&model, &[("z", z)], 10.0, "n1_A.P_B_mm"))
        .collect();
    let (lo, hi) = min_max(all.iter().map(|v| v.as_slice()));
    let bar = numbers(&texts(&svg, "colorbar-tick"));
    assert!(
        bar.len() >= 3 && bar[0] >= lo && *bar.last().unwrap() <= hi,
        "{bar:?} vs {lo}…{hi}"
    );
    // The largest P is the bright end of the ramp, the smallest the dark.
    let cell = |v: f64| {
        svg.lines()
            .find(|l| l.contains(&format!("P = {v:.2} mm")))
            .map(|l| l.split("fill=\"").nth(1).unwrap()[..7].to_string())
            .unwrap()
    };
    assert_eq!(cell(hi), "#fde725");
    assert_eq!(cell(lo), "#440154");
}

#[test]
fn surface_wireframe_is_painted_back_to_front() {
    let model = Model::preset("mf7923d").unwrap();
    let plot = Plot::Surface {
        vary: vary("z", -10.0, 10.0, 4),
        thread: None,
        wireframe: true,
    };
    let svg = render(&model, &model.defaults(), &plot, 10.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    // 36 facets between each pair of rows; one line along φ per row.
    assert_eq!(svg.matches("class=\"facet\"").count(), 3 * 36);
    assert_eq!(svg.matches("<polyline class=\"mesh\"").count(), 4);
    assert_eq!(texts(&svg, "axis-label z"), ["P, mm"]);
    assert_eq!(texts(&svg, "axis-label y"), ["z, mm"]);
    assert_eq!(texts(&svg, "axis-label x"), ["φ, deg"]);
    assert_eq!(texts(&svg, "colorbar-label"), ["P, mm"]);
    let z = numbers(&texts(&svg, "tick z"));
    let (lo, hi) = min_max(std::iter::once(
        column_of(&model, &[("z", 10.0)], 10.0, "n1_A.P_B_mm").as_slice(),
    ));
    assert!(z[0] <= lo && *z.last().unwrap() >= hi, "{z:?}");
    // The rows go from the back (z = 10) to the front (z = -10): the first
    // facet drawn lies higher on the page than the last.
    let first_y = |l: &str| -> f64 {
        attrs(l, "<polygon", "points")[0]
            .split_whitespace()
            .map(|p| p.split_once(',').unwrap().1.parse::<f64>().unwrap())
            .sum::<f64>()
            / 4.0
    };
    let facets: Vec<&str> = svg.lines().filter(|l| l.contains("class=\"facet\"")).collect();
    assert!(first_y(facets[0]) < first_y(facets[facets.len() - 1]));
}

#[test]
fn heat_map_of_a_sweep_figure_over_two_parameters() {
    let model = Model::preset("mf7923d").unwrap();
    let plot = Plot::Heatmap {
        vary: vec![vary("z", -10.0, 10.0, 3), vary("dphi", -20.0, 20.0, 3)],
        figure: "n1_A.max_P_B_mm".into(),
    };
    let svg = render(&model, &model.defaults(), &plot, 10.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    assert_eq!(svg.matches("<rect class=\"cell\"").count(), 9);
    assert_eq!(
        (texts(&svg, "axis-label x"), texts(&svg, "axis-label y")),
        (vec!["z, mm"], vec!["dphi, deg"])
    );
    assert_eq!(texts(&svg, "colorbar-label"), ["n1_A.max_P_B, mm"]);
    let xt = numbers(&texts(&svg, "tick x"));
    assert!(xt.contains(&-10.0) && xt.contains(&10.0), "{xt:?}");
    let yt = numbers(&texts(&svg, "tick y"));
    assert!(yt.contains(&-20.0) && yt.contains(&20.0), "{yt:?}");
    // The marked extremes are those of the nine settings.
    let mut maxima = Vec::new();
    for z in [-10.0, 0.0, 10.0] {
        for d in [-20.0, 0.0, 20.0] {
            maxima.push(
                column_of(&model, &[("z", z), ("dphi", d)], 10.0, "n1_A.P_B_mm")
                    .iter()
                    .fold(f64::MIN, |a, &b| a.max(b)),
            );
        }
    }
    let (lo, hi) = min_max(std::iter::once(maxima.as_slice()));
    assert_eq!(
        texts(&svg, "legend"),
        [format!("max {hi:.3} mm"), format!("min {lo:.3} mm")]
    );
    assert_eq!(svg.matches("<circle class=\"point\"").count(), 2);
}

#[test]
fn heat_map_input_is_checked() {
    let model = Model::preset("mf7923d").unwrap();
    let p = model.defaults();
    let heat = |v: Vec<Vary>, f: &str| {
        full(
            render(
                &model,
                &p,
                &Plot::Heatmap {
                    vary: v,
                    figure: f.into(),
                },
                10.0,
            )
            .unwrap_err(),
        )
    };
    let e = heat(vec![vary("z", -10.0, 10.0, 3)], "n1_A.max_P_B_mm");
    assert!(
        e.contains("exactly 2 varied parameters, got 1") && e.contains("(in `vary`)"),
        "{e}"
    );
    let e = heat(
        vec![vary("z", -10.0, 10.0, 3), vary("dphi", -20.0, 20.0, 3)],
        "*.max_P_B_mm",
    );
    assert!(e.contains("matches 6 figures") && e.contains("n3_B.max_P_B_mm"), "{e}");
    let e = heat(vec![vary("z", -10.0, 10.0, 3), vary("dphi", -20.0, 20.0, 3)], "nope");
    assert!(
        e.contains("no figure of merit matches `nope` (in `figure`)") && e.contains("n1_A.max_P_B_mm"),
        "{e}"
    );
    let e = heat(
        vec![vary("z", -10.0, 10.0, 1), vary("dphi", -20.0, 20.0, 3)],
        "n1_A.max_P_B_mm",
    );
    assert!(
        e.contains("at least 2") && e.contains("(in `vary`)") && e.contains("e.g. z="),
        "{e}"
    );
    let e = heat(
        vec![vary("z", -10.0, 10.0, 3), vary("z", -5.0, 5.0, 3)],
        "n1_A.max_P_B_mm",
    );
    assert!(e.contains("varied twice"), "{e}");
}

#[test]
fn varied_parameters_are_checked_naming_the_input() {
    let model = Model::preset("mf7923d").unwrap();
    let v = parse_vary(&model, "r1=4:6", 5).unwrap();
    assert_eq!(v, vary("r1", 4.0, 6.0, 5));
    assert_eq!(parse_vary(&model, "r1=4:6:3", 5).unwrap().n, 3);
    let e = full(parse_vary(&model, "r1=4:7", 5).unwrap_err());
    assert!(
        e.contains("outside its adjustable range 4…6") && e.contains("(in `vary`)"),
        "{e}"
    );
    let e = full(parse_vary(&model, "q=1:2", 5).unwrap_err());
    assert!(e.contains("no parameter `q`") && e.contains("(in `vary`)"), "{e}");
    // A hand-made range outside the parameter's is caught by render too.
    let e = full(
        render(
            &model,
            &model.defaults(),
            &Plot::Family {
                vary: vary("r1", 3.0, 6.0, 3),
                thread: None,
            },
            10.0,
        )
        .unwrap_err(),
    );
    assert!(e.contains("outside") && e.contains("(in `vary`)"), "{e}");
    let e = full(
        render(
            &model,
            &model.defaults(),
            &Plot::Surface {
                vary: vary("r1", 4.0, 6.0, 1),
                thread: None,
                wireframe: false,
            },
            10.0,
        )
        .unwrap_err(),
    );
    assert!(e.contains("at least 2"), "{e}");
    let e = full(
        render(
            &model,
            &model.defaults(),
            &Plot::Family {
                vary: vary("r1", 4.0, 6.0, 3),
                thread: Some("n7".into()),
            },
            10.0,
        )
        .unwrap_err(),
    );
    assert!(e.contains("no thread path `n7`"), "{e}");
}

#[test]
fn nomogram_chart_reads_off_z_for_the_thickness() {
    // The tuned z for 3, 4 and 5 mm material (seed 000 says −2…−5 mm; with
    // each stitch drawn through the regulator before TDC this model puts it
    // near +2.4 mm for every thickness: docs/published-facts.md).
    let model = Model::preset("mf7923d").unwrap();
    let p = model.defaults();
    let opts = NomogramOptions {
        thickness: GridAxis { lo: 3.0, hi: 5.0, n: 3 },
        stitch: None,
        tune: TuneOptions {
            objective: Default::default(),
            adjust: vec!["z".into()],
            samples: 0,
            seed: 1,
            step_deg: 5.0,
        },
    };
    let svg = render(&model, &p, &Plot::Nomogram(opts.clone()), 5.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    assert_eq!(texts(&svg, "panel-title"), ["recommended z"]);
    assert_eq!(texts(&svg, "legend"), ["t = 3.0 mm"]);
    assert_eq!(
        (texts(&svg, "axis-label x"), texts(&svg, "axis-label y")),
        (vec!["material thickness m, mm"], vec!["z, mm"])
    );
    assert_eq!(svg.matches("<circle class=\"point\"").count(), 3);
    assert_eq!(svg.matches("<polygon class=\"area\"").count(), 1);
    let n = stitchkin::study::nomogram::nomogram(&model, &p, &opts, || {}).unwrap();
    let z: Vec<f64> = n.points.iter().map(|q| q.tuned.as_ref().unwrap().after[0]).collect();
    assert!(z.iter().all(|v| (-10.0..-7.0).contains(v)), "{z:?}");
    for v in &z {
        assert!(svg.contains(&format!("z = {v:.2} mm")), "no tooltip for z = {v:.2}");
    }
    // The line goes through the three tuned values: pixel y follows z.
    let line = &polylines(&svg)[0];
    assert_eq!(line.len(), 3);
    for k in 0..2 {
        assert_eq!(line[k + 1].1 < line[k].1, z[k + 1] > z[k], "{line:?} {z:?}");
    }
    let mut one = opts;
    one.thickness = GridAxis { lo: 3.0, hi: 3.0, n: 1 };
    let e = full(render(&model, &p, &Plot::Nomogram(one), 5.0).unwrap_err());
    assert!(
        e.contains("one thickness (3 mm) is given") && e.contains("(in `thickness`)"),
        "{e}"
    );
}

#[test]
fn delta_2d3d_shows_both_take_ups_and_their_difference() {
    // Seed 000 Fig. 9: needle 1, contour A; ΔP about 0.96 mm in this model
    // (T1 up at TDC; seed 000: about 0.2 mm, docs/published-facts.md).
    let model = Model::preset("mf7923d").unwrap();
    let plot = Plot::Delta2d3d {
        plane: "uvw".into(),
        threads: vec!["n1_A".into()],
    };
    let svg = render(&model, &model.defaults(), &plot, 5.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    let p = panels(&svg);
    assert_eq!(p.len(), 2);
    assert_eq!(texts(p[0], "legend"), ["n1_A 3D", "n1_A 2D"]);
    assert_eq!(texts(p[1], "legend"), ["n1_A ΔP"]);
    assert_eq!(texts(&svg, "axis-label y"), ["P, mm", "ΔP, mm"]);
    let c = stitchkin::study::compare_2d3d::compare_2d3d(&model, &model.defaults(), "uvw", 5.0).unwrap();
    let dp = c.paths.iter().find(|q| q.path == "n1_A").unwrap().max_abs_dp_mm;
    assert!((dp - 0.958).abs() < 0.02, "{dp}");
    assert!(
        texts(&svg, "subtitle")[0].contains(&format!("largest |ΔP| {dp:.3} mm (n1_A")),
        "{:?}",
        texts(&svg, "subtitle")
    );
    // ΔP's axis is scaled to ΔP (about a mm), not to P (tens of mm).
    let t = y_ticks(p[1]);
    let (lo, hi) = min_max(std::iter::once(
        c.paths.iter().find(|q| q.path == "n1_A").unwrap().dp_mm.as_slice(),
    ));
    assert!(
        t.last().unwrap() - t[0] < 2.0 && t[0] <= lo + 1e-9 && *t.last().unwrap() >= hi - 1e-9,
        "{t:?} vs {lo}…{hi}"
    );
    let e = full(
        render(
            &model,
            &model.defaults(),
            &Plot::Delta2d3d {
                plane: "nope".into(),
                threads: vec![],
            },
            5.0,
        )
        .unwrap_err(),
    );
    assert!(e.contains("no frame `nope`") && e.contains("(in `plane`)"), "{e}");
}

// ---- Motion laws: any column of the cycle over φ ----

/// Maps a panel's pixel y back to data with its y ticks (each tick label
/// sits 4 px below its grid line).
fn y_of_pixel(panel: &str) -> impl Fn(f64) -> f64 {
    let at: Vec<f64> = attrs(panel, "<text class=\"tick y\"", "y")
        .iter()
        .map(|v| v.parse::<f64>().unwrap() - 4.0)
        .collect();
    let values = y_ticks(panel);
    let (p0, p1, v0, v1) = (at[0], *at.last().unwrap(), values[0], *values.last().unwrap());
    move |py| v0 + (py - p0) / (p1 - p0) * (v1 - v0)
}

/// The data each polyline of a panel draws (y only, back from pixels).
fn drawn(panel: &str) -> Vec<Vec<f64>> {
    let to_data = y_of_pixel(panel);
    polylines(panel)
        .iter()
        .map(|l| l.iter().map(|p| to_data(p.1)).collect())
        .collect()
}

fn span(v: &[f64]) -> (f64, f64) {
    min_max(std::iter::once(v))
}

/// The chart at the model's defaults, checked well-formed and free of NaN.
fn checked(model: &Model, plot: &Plot, step: f64) -> String {
    let svg = render(model, &model.defaults(), plot, step).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    svg
}

fn motion(series: &[&str], vary: Option<Vary>) -> Plot {
    Plot::Motion {
        series: series.iter().map(|s| s.to_string()).collect(),
        vary,
    }
}

#[test]
fn the_needles_motion_law_has_the_stroke_the_model_gives() {
    // needle876 at α = 0: the needle bar G strokes 18.08 mm (seed 002).
    let model = Model::preset("needle876").unwrap();
    let svg = checked(&model, &motion(&["G.y_mm"], None), 1.0);
    assert_eq!(panels(&svg).len(), 1);
    assert_eq!(texts(&svg, "legend"), ["G.y"]);
    assert_eq!(texts(&svg, "axis-label y"), ["G.y, mm"]);
    assert_eq!(texts(&svg, "axis-label x"), ["φ, deg"]);
    assert!(texts(&svg, "title")[0].contains("needle876: motion law G.y"));
    let lines = drawn(&svg);
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0].len(), 361, "360 steps and the first again");
    // φ runs forward to the cycle's end, where the line closes.
    let xs: Vec<f64> = polylines(&svg)[0].iter().map(|p| p.0).collect();
    assert!(xs.windows(2).all(|w| w[1] > w[0]), "φ goes back somewhere");
    assert_eq!(lines[0][0], lines[0][360]);
    let g = column_of(&model, &[], 1.0, "G.y_mm");
    let ((lo, hi), (glo, ghi)) = (span(&lines[0]), span(&g));
    assert!((ghi - glo - 18.08).abs() < 0.01, "{}", ghi - glo);
    // Two decimals of a pixel: well inside 0.01 mm here.
    assert!(
        (hi - lo - (ghi - glo)).abs() < 0.01 && (lo - glo).abs() < 0.01,
        "drawn {lo}…{hi}, model {glo}…{ghi}"
    );
    // The short form names the same column.
    assert_eq!(
        render(&model, &model.defaults(), &motion(&["G.y"], None), 1.0).unwrap(),
        svg
    );
}

#[test]
fn millimetres_and_degrees_get_their_own_panels() {
    let model = Model::preset("needle876").unwrap();
    let svg = checked(
        &model,
        &motion(&["G.y", "angle_C_B", "needle_y_mm", "mu_23"], None),
        2.0,
    );
    let p = panels(&svg);
    assert_eq!(p.len(), 2);
    assert_eq!(texts(p[0], "legend"), ["G.y", "needle_y"]);
    assert_eq!(texts(p[1], "legend"), ["angle_C_B", "mu_23"]);
    assert_eq!(
        texts(&svg, "axis-label y"),
        ["G.y, needle_y, mm", "angle_C_B, mu_23, deg"]
    );
    // Four colours, one per series.
    let mut colours = attrs(&svg, "<polyline", "stroke");
    colours.dedup();
    assert_eq!(colours.len(), 4);
    // The rocker C-B swings about 180°, where atan2 wraps: the chart draws
    // it continuously (no jump of 360°), over the same swing as the table.
    let angle = &drawn(p[1])[0];
    assert!(
        angle.windows(2).all(|w| (w[1] - w[0]).abs() < 5.0),
        "a jump in angle_C_B"
    );
    let table = column_of(&model, &[], 2.0, "angle_C_B_deg");
    assert!(table.windows(2).any(|w| (w[1] - w[0]).abs() > 300.0), "the table wraps");
    let unwrapped: Vec<f64> = table.iter().map(|&a| if a < 0.0 { a + 360.0 } else { a }).collect();
    let ((lo, hi), (tlo, thi)) = (span(angle), span(&unwrapped));
    assert!(
        (lo - tlo).abs() < 0.05 && (hi - thi).abs() < 0.05,
        "drawn {lo}…{hi}, table {tlo}…{thi}"
    );
    assert!(texts(&svg, "subtitle")[0].contains("angle_C_B drawn continuously past ±180°"));
    // μ23 as the transmission-angle chart gives it: 52.28°…126.47°.
    let (mlo, mhi) = span(&drawn(p[1])[1]);
    assert!((mlo - 52.28).abs() < 0.2 && (mhi - 126.47).abs() < 0.2, "{mlo}…{mhi}");
}

#[test]
fn a_motion_family_over_alpha_raises_the_stroke_and_keeps_the_lowest_position() {
    // Seed 002 Fig. 3: as α (the hinge F) grows the needle's stroke grows,
    // its lowest position stays, and the velocity analog grows with it.
    let model = Model::preset("needle876").unwrap();
    let svg = checked(
        &model,
        &motion(&["G.y", "G.dy_dphi"], Some(vary("alpha", 0.0, 35.0, 6))),
        5.0,
    );
    let p = panels(&svg);
    assert_eq!(texts(&svg, "panel-title"), ["G.y", "G.dy_dphi"]);
    assert_eq!(texts(&svg, "axis-label y"), ["G.y, mm", "G.dy_dphi, mm/rad"]);
    let legend = [
        "alpha = 0 deg",
        "alpha = 7 deg",
        "alpha = 14 deg",
        "alpha = 21 deg",
        "alpha = 28 deg",
        "alpha = 35 deg",
    ];
    for panel in &p {
        assert_eq!(texts(panel, "legend"), legend);
        let mut colours = attrs(panel, "<polyline", "stroke");
        colours.dedup();
        assert_eq!(colours.len(), 6, "a ramp of six colours");
    }
    assert_eq!(svg.matches("<polyline").count(), 12);
    let (positions, speeds) = (drawn(p[0]), drawn(p[1]));
    for (k, alpha) in [0.0, 7.0, 14.0, 21.0, 28.0, 35.0].into_iter().enumerate() {
        let (glo, ghi) = span(&column_of(&model, &[("alpha", alpha)], 5.0, "G.y_mm"));
        let (lo, hi) = span(&positions[k]);
        assert!(
            (hi - lo - (ghi - glo)).abs() < 0.02 && (lo - glo).abs() < 0.02,
            "α = {alpha}: drawn {lo}…{hi}, model {glo}…{ghi}"
        );
        assert!((lo - 107.475).abs() < 0.02, "the lowest position moved: {lo}");
    }
    let strokes: Vec<f64> = positions.iter().map(|l| span(l).1 - span(l).0).collect();
    assert!(
        strokes.windows(2).all(|w| w[1] > w[0]) && strokes[5] > 22.5,
        "{strokes:?}"
    );
    let peak: Vec<f64> = speeds.iter().map(|l| span(l).1).collect();
    assert!(peak.windows(2).all(|w| w[1] > w[0]), "{peak:?}");
}

#[test]
fn a_motion_law_as_a_surface_over_a_parameter() {
    // Seed 000 Fig. 6 a: the eccentric r1 4 → 6 mm widens the swing of
    // the take-up shaft's arm O2B (±10.7° → ±16.2° in this model).
    let model = Model::preset("mf7923d").unwrap();
    let plot = Plot::MotionSurface {
        series: "angle_O2_B".into(),
        vary: vary("r1", 4.0, 6.0, 3),
        wireframe: false,
    };
    let svg = checked(&model, &plot, 10.0);
    assert_eq!(svg.matches("<rect class=\"cell\"").count(), 3 * 37);
    assert_eq!(
        (texts(&svg, "axis-label x"), texts(&svg, "axis-label y")),
        (vec!["φ, deg"], vec!["r1, mm"])
    );
    assert_eq!(texts(&svg, "colorbar-label"), ["angle_O2_B, deg"]);
    assert!(texts(&svg, "title")[0].contains("motion law angle_O2_B over φ and r1"));
    // Each row's swing, read from the tooltips, is the model's.
    let mut swings = Vec::new();
    for r1 in [4.0, 5.0, 6.0] {
        let row: Vec<f64> = svg
            .lines()
            .filter(|l| l.contains(&format!("r1 = {r1:.0} mm: angle_O2_B = ")))
            .map(|l| {
                l.split("angle_O2_B = ")
                    .nth(1)
                    .unwrap()
                    .split(' ')
                    .next()
                    .unwrap()
                    .parse()
                    .unwrap()
            })
            .collect();
        assert_eq!(row.len(), 37);
        let (lo, hi) = span(&column_of(&model, &[("r1", r1)], 10.0, "angle_O2_B_deg"));
        assert!(
            (span(&row).0 - lo).abs() < 0.006 && (span(&row).1 - hi).abs() < 0.006,
            "r1 = {r1}"
        );
        swings.push(hi - lo);
    }
    assert!(swings[2] > swings[0] + 9.0 && swings[1] > swings[0], "{swings:?}");
    let plot = Plot::MotionSurface {
        series: "G.y".into(),
        vary: vary("alpha", 0.0, 35.0, 4),
        wireframe: true,
    };
    let needle = Model::preset("needle876").unwrap();
    let svg = checked(&needle, &plot, 10.0);
    assert_eq!(svg.matches("<polyline class=\"mesh\"").count(), 4);
    assert_eq!(texts(&svg, "axis-label z"), ["G.y, mm"]);
    assert_eq!(texts(&svg, "axis-label y"), ["alpha, deg"]);
}

#[test]
fn motion_input_is_checked_and_the_error_lists_what_there_is() {
    let model = Model::preset("needle876").unwrap();
    let p = model.defaults();
    let e = full(render(&model, &p, &motion(&["G.y", "Q.y"], None), 5.0).unwrap_err());
    assert!(e.contains("no series `Q.y`") && e.contains("(in `series`)"), "{e}");
    assert!(
        e.contains("moving points A, B, D, E, G")
            && e.contains("angle_C_B_deg")
            && e.contains("mu_67_deg")
            && e.contains("needle_y_mm"),
        "{e}"
    );
    let e = full(render(&model, &p, &motion(&["G.yy"], None), 5.0).unwrap_err());
    assert!(e.contains("did you mean `G.y"), "{e}");
    // A fixed point has no motion law.
    let e = full(render(&model, &p, &motion(&["C.y"], None), 5.0).unwrap_err());
    assert!(e.contains("no series `C.y`"), "{e}");
    let e = full(render(&model, &p, &motion(&["G.y", ""], None), 5.0).unwrap_err());
    assert!(e.contains("an empty name (in `series`)"), "{e}");
    let e = full(render(&model, &p, &motion(&["phi"], None), 5.0).unwrap_err());
    assert!(e.contains("`phi` is φ itself"), "{e}");
    let e = full(render(&model, &p, &motion(&[], None), 5.0).unwrap_err());
    assert!(e.contains("no series to draw") && e.contains("(in `series`)"), "{e}");
    let e = full(render(&model, &p, &motion(&["G.y"], Some(vary("alpha", 0.0, 50.0, 3))), 5.0).unwrap_err());
    assert!(
        e.contains("outside its adjustable range") && e.contains("(in `vary`)"),
        "{e}"
    );
    let e = full(render(&model, &p, &motion(&["G.y"], Some(vary("alpha", 0.0, 35.0, 1))), 5.0).unwrap_err());
    assert!(e.contains("at least 2"), "{e}");
    let e = full(
        render(
            &model,
            &p,
            &Plot::MotionSurface {
                series: "nope".into(),
                vary: vary("alpha", 0.0, 35.0, 3),
                wireframe: false,
            },
            5.0,
        )
        .unwrap_err(),
    );
    assert!(e.contains("no series `nope`"), "{e}");
}
