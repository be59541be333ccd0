//! `stitchkin plot`'s SVG charts, checked for structure: well-formed, one
//! polyline per series, labelled axes with units, legends naming the
//! series, a y-axis covering the data, shading where guides engage, no NaN.

use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::model::Model;
use stitchkin::output::plots::{Plot, render};

/// Balanced tags, checked with a small stack (no text contains `<` or `>`:
/// the writer escapes them).
fn assert_well_formed(svg: &str) {
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""), "{}", &svg[..80.min(svg.len())]);
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
            assert!(["&amp;", "&lt;", "&gt;", "&quot;", "&#39;"].iter().any(|e| t.starts_with(e)), "unescaped & in {t}");
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
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "a non-finite number in the SVG");
    for pts in attrs(svg, "<polyline", "points") {
        assert!(!pts.is_empty(), "an empty polyline");
        for p in pts.split_whitespace() {
            let (x, y) = p.split_once(',').unwrap();
            assert!(x.parse::<f64>().unwrap().is_finite() && y.parse::<f64>().unwrap().is_finite(), "{p}");
        }
    }
    for a in ["x", "y", "width", "height"] {
        for v in attrs(svg, "<rect", a) {
            assert!(v.parse::<f64>().unwrap().is_finite(), "rect {a}={v}");
        }
    }
}

fn table(model: &Model, points: Option<Vec<usize>>) -> CycleTable {
    run_cycle(model, &model.defaults(), &CycleOptions { analogs: false, points, ..Default::default() }).unwrap()
}

fn min_max<'a>(cols: impl Iterator<Item = &'a [f64]>) -> (f64, f64) {
    cols.flatten().fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)))
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
    let dashed: Vec<&str> = svg.lines().filter(|l| l.starts_with("<polyline") && l.contains("stroke-dasharray")).collect();
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
        t.columns.iter().filter(|c| c.name.ends_with(".P_mm") || c.name.ends_with(".Pprime_mm")).map(|c| c.values.as_slice()),
    );
    let ticks = y_ticks(&svg);
    assert!(ticks.first().unwrap() <= &lo && ticks.last().unwrap() >= &hi, "{ticks:?} vs {lo}…{hi}");
    // x over one cycle from the model's start, ticks every 45°.
    assert_eq!(texts(&svg, "tick x"), ["0", "45", "90", "135", "180", "225", "270", "315", "360"]);
    // The guides engage 249°…111° (across the cycle's end): two shaded
    // stretches, shared by all six paths.
    assert!(t.paths.iter().all(|p| !p.engaged.is_empty() && !p.engaged[0].1.is_empty()));
    let shades: Vec<&str> = svg.lines().filter(|l| l.starts_with("<rect class=\"shade\"")).collect();
    assert_eq!(shades.len(), 2, "{shades:?}");
    assert!(shades[0].contains("engaged 249°…111°: n1_A G4_1"), "{}", shades[0]);
}

#[test]
fn needle876_transmission_angle_plot_marks_the_band() {
    let model = Model::preset("needle876").unwrap();
    let mut params = model.defaults();
    model.set_str(&mut params, "alpha=38").unwrap();
    let svg = render(&model, &params, &Plot::Mu, 2.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    let keys: Vec<String> = model.dyads.iter().map(|d| d.key.clone()).collect();
    assert_eq!(texts(&svg, "legend"), keys);
    assert_eq!(svg.matches("<polyline").count(), keys.len());
    assert_eq!(texts(&svg, "axis-label y"), ["μ, deg"]);
    assert_eq!(y_ticks(&svg), [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0]);
    assert_eq!(svg.matches("class=\"band\"").count(), 2);
    assert_eq!(svg.matches("class=\"ref\"").count(), 2);
    // φ from needle876's start, 90.6°.
    assert_eq!(texts(&svg, "tick x")[0], "135");
    // Each series closes the cycle: 180 steps and the first again.
    assert!(attrs(&svg, "<polyline", "points").iter().all(|p| p.split_whitespace().count() == 181));
}

#[test]
fn needle876_trajectories_are_to_scale() {
    let model = Model::preset("needle876").unwrap();
    let svg = render(&model, &model.defaults(), &Plot::Trajectory { points: vec!["G".into(), "E".into()], plane: None }, 5.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    assert_eq!(texts(&svg, "legend"), ["G", "E"]);
    assert_eq!(svg.matches("<polyline").count(), 2);
    assert_eq!(svg.matches("<circle class=\"start\"").count(), 2);
    assert_eq!((texts(&svg, "axis-label x"), texts(&svg, "axis-label y")), (vec!["x, mm"], vec!["y, mm"]));
    // Pixels per mm alike on both axes.
    let pos = |class: &str, a: &str| -> Vec<f64> {
        svg.lines().filter(|l| l.starts_with(&format!("<text class=\"{class}\""))).map(|l| {
            let k = format!(" {a}=\"");
            let i = l.find(&k).unwrap() + k.len();
            l[i..i + l[i..].find('"').unwrap()].parse().unwrap()
        }).collect()
    };
    let (xv, yv): (Vec<f64>, Vec<f64>) = (texts(&svg, "tick x").iter().map(|t| t.parse().unwrap()).collect(), y_ticks(&svg));
    let (xp, yp) = (pos("tick x", "x"), pos("tick y", "y"));
    let sx = (xp[1] - xp[0]) / (xv[1] - xv[0]);
    let sy = (yp[0] - yp[1]) / (yv[1] - yv[0]);
    assert!((sx - sy).abs() < 0.02, "{sx} vs {sy} px/mm");
    // The needle G's stroke (seed 002: 18.08 mm) fits in the y ticks' span.
    let t = table(&model, Some(vec![model.point_names.iter().position(|p| p == "G").unwrap()]));
    let (lo, hi) = min_max(std::iter::once(t.column("G.y_mm").unwrap()));
    assert!((hi - lo - 18.08).abs() < 0.01);
    assert!(yv.first().unwrap() - 10.0 <= lo && yv.last().unwrap() + 10.0 >= hi);
}

#[test]
fn trajectories_can_be_drawn_in_a_frame() {
    // The Altin needle runs along its 20° guide: in the guide frame its
    // path is nearly vertical (seed 004).
    let model = Model::preset("altin-needle").unwrap();
    let plot = Plot::Trajectory { points: vec!["E".into()], plane: Some("guide".into()) };
    let svg = render(&model, &model.defaults(), &plot, 5.0).unwrap();
    assert_well_formed(&svg);
    assert_no_nan(&svg);
    assert_eq!((texts(&svg, "axis-label x"), texts(&svg, "axis-label y")), (vec!["guide.x, mm"], vec!["guide.y, mm"]));
    let pts: Vec<(f64, f64)> = attrs(&svg, "<polyline", "points")[0]
        .split_whitespace()
        .map(|p| p.split_once(',').map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap())).unwrap())
        .collect();
    let span = |f: fn(&(f64, f64)) -> f64| pts.iter().map(f).fold(f64::MIN, f64::max) - pts.iter().map(f).fold(f64::MAX, f64::min);
    assert!(span(|p| p.0) < 0.1 * span(|p| p.1), "x span {} px, y span {} px", span(|p| p.0), span(|p| p.1));
    let e = render(&model, &model.defaults(), &Plot::Trajectory { points: vec!["E".into()], plane: Some("nope".into()) }, 5.0).unwrap_err().to_string();
    assert!(e.contains("no frame `nope`"), "{e}");
}

#[test]
fn bad_input_gets_a_clear_error() {
    let model = Model::preset("needle876").unwrap();
    let p = model.defaults();
    let e = render(&model, &p, &Plot::TakeUp, 1.0).unwrap_err().to_string();
    assert!(e.contains("no thread paths"), "{e}");
    let e = render(&model, &p, &Plot::Trajectory { points: vec!["Q".into()], plane: None }, 1.0).unwrap_err().to_string();
    assert!(e.contains("no point `Q`"), "{e}");
    let e = render(&model, &p, &Plot::Trajectory { points: vec![], plane: None }, 1.0).unwrap_err().to_string();
    assert!(e.contains("no points"), "{e}");
    let e = render(&model, &p, &Plot::Mu, 0.0).unwrap_err().to_string();
    assert!(e.contains("step"), "{e}");
}
