//! Mechanism drawings (stitchkin::output::drawing): what is drawn for each
//! preset, to scale, the thread through its guides, the animation, and
//! clear errors.

use stitchkin::error::Error;
use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::jobs::drawing::render;
use stitchkin::model::Model;
use stitchkin::output::drawing::{DrawOptions, Plane, View};

fn draw(preset: &str, opts: &DrawOptions) -> String {
    let m = Model::preset(preset).unwrap();
    let svg = render(&m, &m.defaults(), opts).unwrap_or_else(|e| panic!("{preset}: {e}"));
    assert!(svg.starts_with("<svg ") && svg.trim_end().ends_with("</svg>"));
    assert!(
        !svg.contains("NaN") && !svg.contains("inf"),
        "{preset}: a non-finite number in the drawing"
    );
    svg
}

fn at(phi: f64) -> DrawOptions {
    DrawOptions {
        phi_deg: phi,
        ..Default::default()
    }
}

/// Elements whose class attribute is exactly `class`.
fn count(svg: &str, class: &str) -> usize {
    svg.matches(&format!("class=\"{class}\"")).count()
}

/// Elements whose class attribute starts with `prefix`.
fn count_prefix(svg: &str, prefix: &str) -> usize {
    svg.matches(&format!("class=\"{prefix}")).count()
}

/// The value of attribute `name` in the element starting at byte `from`.
fn attr<'a>(svg: &'a str, from: usize, name: &str) -> &'a str {
    let end = from + svg[from..].find('>').unwrap();
    let tag = &svg[from..end];
    let key = format!(" {name}=\"");
    let i = tag.find(&key).unwrap_or_else(|| panic!("no {name} in {tag}")) + key.len();
    &tag[i..i + tag[i..].find('"').unwrap()]
}

/// The px per mm the drawing states.
fn scale(svg: &str) -> f64 {
    attr(svg, 0, "data-px-per-mm").parse().unwrap()
}

/// Start of the element carrying `marker` (e.g. `data-points="A B"`).
fn element(svg: &str, marker: &str) -> usize {
    let i = svg.find(marker).unwrap_or_else(|| panic!("no element with {marker}"));
    svg[..i].rfind('<').unwrap()
}

fn points(list: &str) -> Vec<(f64, f64)> {
    list.split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

fn drawn_length(svg: &str, marker: &str) -> f64 {
    let p = points(attr(svg, element(svg, marker), "points"));
    assert_eq!(p.len(), 2, "{marker} is a bar");
    ((p[1].0 - p[0].0).powi(2) + (p[1].1 - p[0].1).powi(2)).sqrt()
}

/// Every name in the labels of one class.
fn label_names(svg: &str, class: &str) -> Vec<String> {
    let key = format!("class=\"{class}\" data-names=\"");
    svg.match_indices(&key)
        .flat_map(|(i, _)| {
            let rest = &svg[i + key.len()..];
            rest[..rest.find('"').unwrap()]
                .split(' ')
                .map(String::from)
                .collect::<Vec<_>>()
        })
        .collect()
}

#[test]
fn needle876_is_drawn_to_scale_at_any_phi() {
    let m = Model::preset("needle876").unwrap();
    for phi in [120.0, 300.0] {
        let svg = draw("needle876", &at(phi));
        // Crank OA, coupler AB, the bell crank C–B with D on it (one bar,
        // D lies on the line CB), DE, FE and the needle-bar rod EG.
        assert_eq!(count_prefix(&svg, "link "), 6, "{svg}");
        assert_eq!(count(&svg, "link crank"), 1);
        assert_eq!(count(&svg, "joint"), 5, "A, B, D, E, G");
        assert_eq!(count(&svg, "pivot"), 3, "O, C, F");
        assert_eq!(count(&svg, "slider"), 1);
        assert_eq!(count(&svg, "fixed-point"), 1, "H places the needle's guide line");
        assert_eq!(count(&svg, "label"), 5);
        assert_eq!(count(&svg, "label fixed"), 4);
        let mut moving = label_names(&svg, "label");
        moving.sort();
        assert_eq!(moving, ["A", "B", "D", "E", "G"]);
        // Links keep their lengths in the drawing: l·scale.
        let s = scale(&svg);
        assert!(
            (drawn_length(&svg, "data-points=\"A B\"") - 175.0 * s).abs() < 0.02,
            "AB at φ = {phi}"
        );
        assert!(
            (drawn_length(&svg, "data-points=\"O A\"") - 15.0 * s).abs() < 0.02,
            "OA at φ = {phi}"
        );
        assert!(
            (drawn_length(&svg, "data-points=\"E G\"") - 30.0 * s).abs() < 0.02,
            "EG at φ = {phi}"
        );
        // The crank is drawn at φ: A − O along (cos φ, sin φ), y up.
        let p = points(attr(&svg, element(&svg, "data-points=\"O A\""), "points"));
        let ang = (-(p[1].1 - p[0].1))
            .atan2(p[1].0 - p[0].0)
            .to_degrees()
            .rem_euclid(360.0);
        assert!((ang - phi).abs() < 0.2, "crank at {ang}° for φ = {phi}°");
    }
    // The model's own numbers: D is l_cd from C, opposite B.
    assert!(m.param_index("l_cd").is_some());
}

#[test]
fn dimensions_name_each_link_with_its_length() {
    let svg = draw(
        "needle876",
        &DrawOptions {
            dimensions: true,
            ..at(200.0)
        },
    );
    assert_eq!(count(&svg, "dimension"), 6, "r_OA, l_AB, l_CB, l_DE, l_FE, l_EG");
    for text in [
        "r_OA = 15 mm",
        "l_AB = 175 mm",
        "l_CB = 25 mm",
        "l_DE = 30 mm",
        "l_FE = 25 mm",
        "l_EG = 30 mm",
    ] {
        assert!(svg.contains(&format!(">{text}</text>")), "no {text}");
    }
    assert!(!draw("needle876", &at(200.0)).contains("class=\"dimension\""));
}

#[test]
fn takeup_lever_has_two_plates_and_its_thread_through_five_eyelets() {
    let svg = draw("takeup-lever", &at(45.0));
    assert_eq!(count(&svg, "link plate"), 2, "coupler P2P3P5 and rocker P4P3P6P7");
    assert_eq!(count(&svg, "link crank"), 1);
    assert_eq!(count(&svg, "thread"), 1);
    let t = element(&svg, "class=\"thread\"");
    assert_eq!(attr(&svg, t, "data-nodes"), "N1 P6 P5 P7 N2");
    assert_eq!(points(attr(&svg, t, "points")).len(), 5);
    assert_eq!(attr(&svg, t, "stroke"), stitchkin::output::svg::PALETTE[0]);
    assert_eq!(count(&svg, "guide eyelet"), 5);
    // The crank P1P2 is l1_2 = 13 mm long.
    assert!((drawn_length(&svg, "data-points=\"P1 P2\"") - 13.0 * scale(&svg)).abs() < 0.02);
}

/// Whether each pin of `path` bears on the thread at φ, from the cycle table.
fn engaged(model: &Model, path: &str, pin: &str, phi: f64) -> bool {
    let t = run_cycle(
        model,
        &model.defaults(),
        &CycleOptions {
            step_deg: 1.0,
            analogs: false,
            ..Default::default()
        },
    )
    .unwrap();
    let phis = t.column("phi_deg").unwrap();
    let k = phis.iter().position(|p| (p - phi).abs() < 1e-9).unwrap();
    t.column(&format!("{path}.{pin}_engaged")).unwrap()[k] == 1.0
}

#[test]
fn mf7923d_threads_run_through_the_guides_they_touch() {
    let m = Model::preset("mf7923d").unwrap();
    for phi in [0.0, 180.0] {
        let svg = draw("mf7923d", &at(phi));
        assert_eq!(count(&svg, "thread"), 6);
        let bearing = engaged(&m, "n1_A", "G4_1", phi);
        assert_eq!(bearing, phi == 0.0, "seed 000: G4 engaged 249°…111°");
        let want = if bearing { "guide pin engaged" } else { "guide pin free" };
        assert_eq!(count(&svg, want), 3, "G4_1, G4_2, G4_3 at φ = {phi}");
        let threads = m.machine::<f64>(&m.defaults()).unwrap().threads.unwrap();
        for (k, path) in threads.paths.iter().enumerate() {
            let t = element(&svg, &format!("data-path=\"{}\"", path.name));
            let nodes: Vec<&str> = attr(&svg, t, "data-nodes").split(' ').collect();
            // Every eyelet, and the pin only while the thread bears on it.
            let all = path.nodes.len();
            assert_eq!(
                nodes.len(),
                if bearing { all } else { all - 1 },
                "{} at φ = {phi}",
                path.name
            );
            assert_eq!(
                points(attr(&svg, t, "points")).len(),
                nodes.len(),
                "{} at φ = {phi}: one vertex per guide touched",
                path.name
            );
            assert_eq!(attr(&svg, t, "stroke"), stitchkin::output::svg::PALETTE[k]);
        }
        // The rocker T1 and the needle bar's eyelets carry labels; needles
        // 1–3 share their xy-positions, so one label names all three.
        let moving = label_names(&svg, "label");
        for p in ["A", "B", "D", "E", "T1_1", "T1_3", "T2_2", "N_1", "N_3"] {
            assert!(moving.iter().any(|n| n == p), "no label for {p}");
        }
        assert_eq!(count(&svg, "joint spherical"), 2, "the RSSR rod's ball ends A and B");
        assert!(count(&svg, "slider") == 1 && count(&svg, "link plate") == 1);
    }
}

#[test]
fn spatial_presets_in_every_view() {
    for preset in ["mf7923d", "altin504"] {
        let m = Model::preset(preset).unwrap();
        let mut views = vec![
            View::Plane(Plane::Xy),
            View::Plane(Plane::Xz),
            View::Plane(Plane::Yz),
            View::Isometric,
        ];
        views.extend(m.frame_names().into_iter().map(|f| View::Frame(f.to_string())));
        let mut sizes = Vec::new();
        for view in views {
            let svg = draw(
                preset,
                &DrawOptions {
                    view: view.clone(),
                    phi_deg: 30.0,
                    ..Default::default()
                },
            );
            assert!(count_prefix(&svg, "link ") >= 8, "{preset} {view:?}");
            sizes.push(scale(&svg));
        }
        assert!(sizes.iter().all(|s| *s > 0.5 && s.is_finite()), "{preset}: {sizes:?}");
    }
    // The isometric drawing is not a plane view.
    let a = draw(
        "mf7923d",
        &DrawOptions {
            view: View::Isometric,
            ..at(0.0)
        },
    );
    let b = draw("mf7923d", &at(0.0));
    assert!(a.contains("isometric") && !b.contains("isometric"));
}

#[test]
fn altin504_draws_its_cams_loopers_and_three_threads() {
    let svg = draw(
        "altin504",
        &DrawOptions {
            view: View::Isometric,
            ..at(90.0)
        },
    );
    assert_eq!(count(&svg, "thread"), 3, "needle, lower, upper");
    assert_eq!(count(&svg, "cam"), 2, "the two looper-thread feed cams");
    assert_eq!(count(&svg, "joint spherical"), 4, "two RSSR rods, two ball ends each");
    // The offset cam contact touches at one point: one vertex per node.
    for (path, n) in [("needle", 5), ("lower", 7), ("upper", 7)] {
        let t = element(&svg, &format!("data-path=\"{path}\""));
        assert_eq!(points(attr(&svg, t, "points")).len(), n, "{path}");
    }
    let moving = label_names(&svg, "label");
    for p in ["E", "LE", "UE", "EYE"] {
        assert!(moving.iter().any(|n| n == p), "no label for {p}");
    }
}

#[test]
fn trajectories_are_closed_thin_lines_over_the_cycle() {
    let svg = draw(
        "needle876",
        &DrawOptions {
            trajectories: vec!["G".into(), "E".into()],
            ..at(0.0)
        },
    );
    assert_eq!(count(&svg, "trajectory"), 2);
    let g = points(attr(&svg, element(&svg, "data-point=\"G\" fill"), "points"));
    assert_eq!(g.len(), 361, "360 positions, closed");
    // The needle moves on a vertical line: one x, a stroke of about 18 mm.
    let s = scale(&svg);
    let (lo, hi) = g
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    assert!(g.iter().all(|p| (p.0 - g[0].0).abs() < 0.02));
    let m = Model::preset("needle876").unwrap();
    let t = run_cycle(
        &m,
        &m.defaults(),
        &CycleOptions {
            step_deg: 1.0,
            analogs: false,
            points: Some(vec![m.point_names().iter().position(|p| p == "G").unwrap()]),
            ..Default::default()
        },
    )
    .unwrap();
    let y = t.column("G.y_mm").unwrap();
    let stroke = y.iter().cloned().fold(f64::MIN, f64::max) - y.iter().cloned().fold(f64::MAX, f64::min);
    assert!(
        ((hi - lo) / s - stroke).abs() < 0.02,
        "stroke drawn {} mm, computed {stroke} mm",
        (hi - lo) / s
    );
}

#[test]
fn an_animation_moves_every_part_over_one_turn() {
    let opts = DrawOptions {
        animate: true,
        frames: 24,
        duration_s: 3.0,
        trajectories: vec!["G".into()],
        ..at(90.6)
    };
    let svg = draw("needle876", &opts);
    assert!(svg.contains("data-frames=\"24\""));
    assert!(svg.contains("<animate ") && svg.contains("<animateTransform "));
    assert!(svg.contains("dur=\"3s\"") && svg.contains("repeatCount=\"indefinite\""));
    // The coupler's points: one value per frame, back to the first.
    let ab = element(&svg, "data-points=\"A B\"");
    let anim = ab + svg[ab..].find("<animate ").unwrap();
    let values: Vec<&str> = attr(&svg, anim, "values").split(';').collect();
    assert_eq!(values.len(), 25);
    assert_eq!(values[0], values[24]);
    let s = scale(&svg);
    for v in &values {
        let p = points(v);
        let l = ((p[1].0 - p[0].0).powi(2) + (p[1].1 - p[0].1).powi(2)).sqrt();
        assert!((l - 175.0 * s).abs() < 0.02, "AB drawn {l} px");
    }
    // Fixed pivots do not move.
    assert_eq!(count(&svg, "pivot"), 3);
    // A spatial preset with threads and one-sided guides.
    let svg = draw(
        "mf7923d",
        &DrawOptions {
            animate: true,
            frames: 36,
            ..Default::default()
        },
    );
    assert!(svg.contains("data-frames=\"36\""));
    let t = element(&svg, "data-path=\"n1_A\"");
    let anim = t + svg[t..].find("<animate ").unwrap();
    let frames: Vec<&str> = attr(&svg, anim, "values").split(';').collect();
    assert_eq!(frames.len(), 37);
    // The thread keeps its vertex count so it morphs smoothly.
    assert!(frames.iter().all(|f| points(f).len() == points(frames[0]).len()));
    // G4's fill follows the thread: engaged part of the turn only.
    assert!(svg.contains("attributeName=\"fill\"") && svg.contains("calcMode=\"discrete\""));
}

const JAMMING: &str = r#"
[model]
name = "jamming"

[points]
O1 = [0, 0]
O2 = [60, 0]

[[drivers]]
type = "crank"
center = "O1"
out = "A"
radius = 35

[[groups]]
type = "rrr"
name = "coupler_rocker"
joints = ["A", "O2"]
lengths = [50, 40]
out = "B"
branch = "left"
"#;

#[test]
fn no_assembly_is_the_usual_clear_error() {
    let m = Model::from_toml_str(JAMMING, "jamming.toml").unwrap();
    let p = m.defaults();
    // At φ = 0 the four-bar assembles and is drawn.
    let svg = render(&m, &p, &at(0.0)).unwrap();
    assert_eq!(count_prefix(&svg, "link "), 3);
    // At φ = 180° A is 95 mm from O2, beyond 50 + 40.
    let e = render(&m, &p, &at(180.0)).unwrap_err();
    assert!(matches!(e, Error::Assembly(_)), "{e:?}");
    let msg = e.to_string();
    assert!(msg.contains("φ = 180.000°") && msg.contains("coupler_rocker"), "{msg}");
    // An animation needs every φ of the turn, and says where it fails.
    let e = render(
        &m,
        &p,
        &DrawOptions {
            animate: true,
            ..at(0.0)
        },
    )
    .unwrap_err();
    assert!(
        matches!(e, Error::Assembly(_)) && e.to_string().contains("coupler_rocker"),
        "{e}"
    );
    // So do trajectories.
    let e = render(
        &m,
        &p,
        &DrawOptions {
            trajectories: vec!["B".into()],
            ..at(0.0)
        },
    )
    .unwrap_err();
    assert!(matches!(e, Error::Assembly(_)), "{e}");
}

#[test]
fn every_preset_draws_without_a_non_finite_number() {
    for preset in [
        "needle876",
        "overlock500",
        "altin-needle",
        "altin504",
        "mf7923d",
        "takeup-lever",
    ] {
        let m = Model::preset(preset).unwrap();
        for phi in [0.0, 77.0, 181.5, 300.0] {
            let svg = draw(
                preset,
                &DrawOptions {
                    view: View::default_for(&m),
                    dimensions: true,
                    ..at(phi)
                },
            );
            assert!(
                count_prefix(&svg, "link ") > 0 && count(&svg, "scale-bar") == 1,
                "{preset}"
            );
        }
    }
}

#[test]
fn bad_options_name_what_to_change() {
    let m = Model::preset("mf7923d").unwrap();
    let p = m.defaults();
    let full = |e: Error| match e {
        Error::Param(p) => format!("{p} / {}", p.help.clone().unwrap_or_default()),
        other => other.to_string(),
    };
    let e = full(
        render(
            &m,
            &p,
            &DrawOptions {
                view: View::Frame("uwv".into()),
                ..Default::default()
            },
        )
        .unwrap_err(),
    );
    assert!(e.contains("no frame `uwv`") && e.contains("uvw"), "{e}");
    let e = full(
        render(
            &m,
            &p,
            &DrawOptions {
                animate: true,
                frames: 0,
                ..Default::default()
            },
        )
        .unwrap_err(),
    );
    assert!(e.contains("(in `frames`)") && e.contains("72 frames"), "{e}");
    let e = full(
        render(
            &m,
            &p,
            &DrawOptions {
                phi_deg: f64::INFINITY,
                ..Default::default()
            },
        )
        .unwrap_err(),
    );
    assert!(e.contains("(in `phi`)"), "{e}");
    assert_eq!(View::parse("iso").unwrap(), View::Isometric);
    assert_eq!(View::parse("uvw").unwrap(), View::Frame("uvw".into()));
    assert!(View::parse(" ").is_err());
    assert_eq!(View::default_for(&m), View::Isometric);
    assert_eq!(
        View::default_for(&Model::preset("needle876").unwrap()),
        View::Plane(Plane::Xy)
    );
    assert!(View::choices(&m).contains(&"uvw".to_string()));
}

/// A model file of the repository's examples, drawn.
fn draw_example(text: &str, opts: &DrawOptions) -> String {
    let m = Model::from_toml_str(text, "cam.toml").unwrap();
    let svg = render(&m, &m.defaults(), opts).unwrap();
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
    svg
}

#[test]
fn a_cam_is_drawn_to_scale_with_its_roller_on_its_profile() {
    let text = include_str!("../../../../examples/cam-rocking-roller.toml");
    for phi in [0.0, 75.0, 200.0] {
        let svg = draw_example(text, &at(phi));
        let s = scale(&svg);
        let profile = points(attr(&svg, element(&svg, "class=\"cam-profile\""), "points"));
        let pitch = points(attr(&svg, element(&svg, "class=\"cam-pitch\""), "points"));
        let roller = points(attr(&svg, element(&svg, "class=\"cam-roller\""), "points"));
        assert_eq!(profile.len(), 360);
        assert_eq!(pitch.len(), 360);
        let o1 = points(attr(&svg, element(&svg, "data-points=\"O1 K\""), "points"))[0];
        let dist = |a: (f64, f64), b: (f64, f64)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt() / s;
        // The base circle (18 mm) is the profile's least radius, the pitch
        // curve's is it plus the roller (5 mm).
        let least = |c: &[(f64, f64)]| c.iter().map(|&p| dist(p, o1)).fold(f64::MAX, f64::min);
        assert!((least(&profile) - 18.0).abs() < 0.1, "φ = {phi}: {}", least(&profile));
        assert!((least(&pitch) - 23.0).abs() < 0.1, "φ = {phi}: {}", least(&pitch));
        // The roller (5 mm) round R touches the profile.
        let (xs, ys): (Vec<f64>, Vec<f64>) = roller.iter().cloned().unzip();
        let mid =
            |v: &[f64]| (v.iter().cloned().fold(f64::MAX, f64::min) + v.iter().cloned().fold(f64::MIN, f64::max)) / 2.0;
        let r = (mid(&xs), mid(&ys));
        assert!((dist(roller[0], r) - 5.0).abs() < 0.05);
        let gap = profile.iter().map(|&p| dist(p, r)).fold(f64::MAX, f64::min);
        assert!(
            (gap - 5.0).abs() < 0.15,
            "φ = {phi}: the roller is {gap} mm from the profile"
        );
    }
    // A groove has its outer flank drawn; an animation turns the cam.
    let groove = draw_example(
        include_str!("../../../../examples/cam-translating-groove.toml"),
        &at(0.0),
    );
    assert_eq!(count(&groove, "cam-groove"), 1);
    let svg = draw_example(
        text,
        &DrawOptions {
            animate: true,
            frames: 12,
            ..Default::default()
        },
    );
    let p = element(&svg, "class=\"cam-profile\"");
    let anim = p + svg[p..].find("<animate ").unwrap();
    let frames: Vec<&str> = attr(&svg, anim, "values").split(';').collect();
    assert_eq!(frames.len(), 13);
    assert_ne!(frames[0], frames[3]);
}
