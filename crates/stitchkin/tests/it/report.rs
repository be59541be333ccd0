//! `jobs::report`: one self-contained, well-formed HTML file.

use stitchkin::jobs::report::{ReportOptions, render};
use stitchkin::model::Model;
use stitchkin::output::drawing::View;
use stitchkin::study::nomogram::{Axis, NomogramOptions};
use stitchkin::study::tune::TuneOptions;

/// Parses the report as XML (it is written to be both) and returns it.
fn parse(html: &str) -> roxmltree::Document<'_> {
    let opts = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    roxmltree::Document::parse_with_options(html, opts).unwrap_or_else(|e| panic!("the report is not well-formed: {e}"))
}

fn section_ids(doc: &roxmltree::Document) -> Vec<String> {
    doc.descendants()
        .filter(|n| n.has_tag_name("section"))
        .map(|n| n.attribute("id").unwrap().to_string())
        .collect()
}

fn rows(doc: &roxmltree::Document, class: &str) -> Vec<Vec<String>> {
    let table = doc
        .descendants()
        .find(|n| n.has_tag_name("table") && n.attribute("class") == Some(class))
        .unwrap_or_else(|| panic!("no table {class}"));
    table
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.parent().is_some_and(|p| p.has_tag_name("tbody")))
        .map(|tr| {
            tr.children()
                .filter(|c| c.has_tag_name("td"))
                .map(|td| {
                    td.descendants()
                        .filter(|d| d.is_text())
                        .filter_map(|d| d.text())
                        .collect::<String>()
                })
                .collect()
        })
        .collect()
}

fn self_contained(html: &str) {
    assert!(!html.contains("NaN") && !html.contains("inf\""), "no non-finite number");
    assert!(!html.contains("<script"), "no script");
    for attr in ["src=\"", "href=\"http", "@import"] {
        assert!(!html.contains(attr), "a reference to another file: {attr}");
    }
    // url(#id) refers inside the file (clip paths); nothing else may.
    assert!(
        html.match_indices("url(").all(|(i, _)| html[i + 4..].starts_with('#')),
        "a url() to another file"
    );
}

#[test]
fn mf7923d_report_has_every_section_and_is_self_contained() {
    let model = Model::preset("mf7923d").unwrap();
    let mut params = model.defaults();
    model.set(&mut params, "r1", 5.0).unwrap();
    let html = render(
        &model,
        &params,
        &ReportOptions {
            step_deg: 2.0,
            ..Default::default()
        },
    )
    .unwrap();
    self_contained(&html);
    let doc = parse(&html);
    let ids = section_ids(&doc);
    assert_eq!(
        ids[..7],
        [
            "parameters",
            "mechanism",
            "takeup",
            "mismatch",
            "checks",
            "caveats",
            "transmission"
        ]
    );
    // Pictures: still and animated mechanism, P/P′, μ — all inline SVG.
    let svgs = doc.descendants().filter(|n| n.tag_name().name() == "svg").count();
    assert_eq!(svgs, 4);
    assert!(
        doc.descendants().any(|n| n.tag_name().name() == "animate"),
        "the animated drawing"
    );
    // The parameters with units and ranges; the changed one marked.
    let p = rows(&doc, "parameters");
    let r1 = p.iter().find(|r| r[0] == "r1").unwrap();
    assert_eq!(r1[1], "5 (set)");
    assert_eq!(r1[2], "mm");
    assert_eq!(r1[3], "4…6");
    assert!(html.contains("set: r1 = 5 mm"));
    // Mismatch per needle thread, with a score.
    let m = rows(&doc, "mismatch");
    assert_eq!(m.iter().map(|r| r[0].as_str()).collect::<Vec<_>>(), ["n1", "n2", "n3"]);
    for r in &m {
        let score: f64 = r[11].parse().unwrap();
        assert!((0.0..=100.0).contains(&score));
    }
    assert_eq!(rows(&doc, "paths").len(), 6);
    assert!(
        rows(&doc, "paths").iter().all(|r| r[2] == "B"),
        "needle-eye paths are measured at B"
    );
    assert_eq!(rows(&doc, "transmission").len(), 2);
    // The physical checks, eight per needle thread (three of the stitch,
    // the take-up's, four of the thread's tension), with what each means;
    // at r1 = 5 mm the take-up gives needle 3 next to nothing (0.5 of its
    // 9.8 mm), and every other check passes.
    let c = rows(&doc, "checks");
    assert_eq!(c.len(), 24);
    assert!(c.iter().all(|r| !r[6].is_empty()), "{c:?}");
    let failed: Vec<_> = c
        .iter()
        .filter(|r| r[2] != "ok")
        .map(|r| (r[0].as_str(), r[1].as_str()))
        .collect();
    assert_eq!(failed, [("n3", "takeup_gives")], "{c:?}");
    assert!(
        html.contains("Regulator: n1 φ = ") && html.contains("(computed)"),
        "the regulator window is stated"
    );
    // Every caveat of the model and every rule carried over from another
    // stitch type is listed, papers cited by authors and year.
    for c in model.caveats().iter() {
        let cited = stitchkin::references::cited(c);
        assert!(html.contains(&stitchkin::output::svg::escape(&cited)), "{cited}");
    }
    assert!(!html.contains("seed 00"), "a paper cited by its seed number");
    assert!(html.contains("401 two-thread chain stitch"));
}

#[test]
fn the_alternative_take_up_phase_fails_the_thread_bound_in_the_report() {
    let model = Model::preset("mf7923d").unwrap();
    let mut params = model.defaults();
    model.set(&mut params, "t1_phase", 0.0).unwrap();
    let html = render(
        &model,
        &params,
        &ReportOptions {
            step_deg: 5.0,
            animate: false,
            ..Default::default()
        },
    )
    .unwrap();
    let doc = parse(&html);
    let bound: Vec<Vec<String>> = rows(&doc, "checks")
        .into_iter()
        .filter(|r| r[1] == "thread_bound")
        .collect();
    assert_eq!(bound.len(), 3);
    assert!(
        bound.iter().all(|r| r[2] == "FAIL" && r[6].contains("hangs slack")),
        "{bound:?}"
    );
}

#[test]
fn a_planar_model_without_threads_reports_what_it_has() {
    let model = Model::preset("needle876").unwrap();
    let opts = ReportOptions {
        step_deg: 2.0,
        animate: false,
        view: Some(View::parse("xy").unwrap()),
        ..Default::default()
    };
    let html = render(&model, &model.defaults(), &opts).unwrap();
    self_contained(&html);
    let doc = parse(&html);
    let ids = section_ids(&doc);
    assert!(
        ids.starts_with(&["parameters".to_string(), "mechanism".to_string()]),
        "{ids:?}"
    );
    assert!(!ids.contains(&"takeup".to_string()) && !ids.contains(&"mismatch".to_string()));
    assert!(ids.contains(&"transmission".to_string()));
    assert!(!html.contains("<animate"), "no animation when not asked");
}

#[test]
fn tuning_and_nomogram_sections_when_asked() {
    let model = Model::preset("mf7923d").unwrap();
    let params = model.defaults();
    let tune = TuneOptions {
        objective: Default::default(),
        adjust: vec!["dphi".into()],
        samples: 8,
        seed: 1,
        step_deg: 4.0,
    };
    let opts = ReportOptions {
        step_deg: 4.0,
        animate: false,
        tune: Some(tune.clone()),
        nomogram: Some(NomogramOptions {
            thickness: Axis::parse("2:4:2", stitchkin::Input::Thickness).unwrap(),
            stitch: None,
            tune,
        }),
        ..Default::default()
    };
    let html = render(&model, &params, &opts).unwrap();
    self_contained(&html);
    let doc = parse(&html);
    let ids = section_ids(&doc);
    assert!(
        ids.contains(&"tuning".to_string()) && ids.contains(&"nomogram".to_string()),
        "{ids:?}"
    );
    let t = rows(&doc, "tuning");
    assert_eq!(t.len(), 1);
    assert_eq!(t[0][0], "dphi");
    let after: f64 = t[0][3].parse().unwrap();
    assert!(
        (-20.0..=20.0).contains(&after),
        "the recommendation stays in dphi's range: {after}"
    );
    assert!(
        doc.descendants()
            .any(|n| n.attribute("id") == Some("tuned-takeup-chart"))
    );
    assert!(doc.descendants().any(|n| n.attribute("id") == Some("nomogram-chart")));
}

#[test]
fn bad_options_are_errors_not_reports() {
    let model = Model::preset("mf7923d").unwrap();
    let err = render(
        &model,
        &model.defaults(),
        &ReportOptions {
            step_deg: 0.0,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("step"), "{err}");
    let err = render(
        &model,
        &model.defaults(),
        &ReportOptions {
            view: Some(View::Frame("nowhere".into())),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("nowhere"), "{err}");
}
