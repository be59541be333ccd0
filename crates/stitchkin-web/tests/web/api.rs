//! `App::handle` on the presets and on bad requests.

use serde_json::Value;
use stitchkin::model::Model;
use stitchkin_web::{App, Reply};

fn app(preset: &str) -> App {
    let model = Model::preset(preset).unwrap();
    let base = model.defaults();
    App::new(model, base)
}

fn json(reply: &Reply) -> Value {
    assert!(
        reply.content_type.starts_with("application/json"),
        "{}",
        reply.content_type
    );
    serde_json::from_slice(&reply.body).unwrap()
}

fn get(app: &App, url: &str) -> Reply {
    app.handle("GET", url)
}

/// A 4xx whose JSON names what is wrong (`says`) and carries a help line.
fn assert_client_error(app: &App, url: &str, status: u16, says: &str) {
    let r = get(app, url);
    assert_eq!(r.status, status, "{url}: {}", r.text());
    let v = json(&r);
    let error = v["error"].as_str().unwrap();
    assert!(error.contains(says), "{url}: `{error}` should say `{says}`");
}

#[test]
fn page_is_html_with_its_script_inline() {
    let r = get(&app("mf7923d"), "/");
    assert_eq!(r.status, 200);
    assert!(r.content_type.starts_with("text/html"));
    let html = r.text();
    assert!(html.contains("<script>") && html.contains("/api/evaluate") && html.contains("/api/drawing"));
    assert!(!html.contains("src=\"http"), "the page loads nothing from elsewhere");
}

#[test]
fn model_lists_parameters_with_units_ranges_and_roles() {
    let v = json(&get(&app("mf7923d"), "/api/model"));
    assert_eq!(v["name"], "mf7923d");
    let params = v["parameters"].as_array().unwrap();
    let find = |n: &str| {
        params
            .iter()
            .find(|p| p["name"] == n)
            .unwrap_or_else(|| panic!("no {n}"))
    };
    assert_eq!(find("r1")["role"], "adjustable");
    assert_eq!(find("r1")["unit"], "mm");
    assert_eq!(find("r1")["range"], serde_json::json!([4.0, 6.0]));
    assert_eq!(find("dphi")["unit"], "deg");
    // The model's words for each part, as the library reads them.
    let model = Model::preset("mf7923d").unwrap();
    let r1 = &model.params()[model.param_index("r1").unwrap()];
    assert_eq!(find("r1")["kind"], r1.kind.as_str());
    assert_eq!(find("r1")["label"].as_str(), r1.label.as_deref());
    assert_eq!(find("r1")["what"].as_str(), r1.what.as_deref());
    assert!(find("r1")["label"].is_string(), "r1 has a plain label");
    assert_eq!(find("m")["kind"], "input");
    assert_eq!(find("m")["role"], "thickness");
    assert_eq!(find("stitch")["role"], "stitch_length");
    assert_eq!(v["stitch"]["type"], "407");
    assert_eq!(v["chart"], "takeup");
    assert_eq!(v["threads"].as_array().unwrap().len(), 6);
    assert!(!v["views"].as_array().unwrap().is_empty());
    // Derived parameters cannot be set, so the page does not offer them.
    let model = Model::preset("mf7923d").unwrap();
    for p in model.params().iter().filter(|p| p.is_derived()) {
        assert!(
            params.iter().all(|q| q["name"] != p.name.as_str()),
            "{} is derived",
            p.name
        );
    }
}

#[test]
fn evaluate_charts_and_sums_up_and_follows_the_sliders() {
    let app = app("mf7923d");
    let base = get(&app, "/api/evaluate");
    assert_eq!(base.status, 200, "{}", base.text());
    assert!(!base.text().contains("NaN"));
    let v = json(&base);
    let svg = v["chart_svg"].as_str().unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("polyline"));
    let threads = v["stitch"]["threads"].as_array().unwrap();
    assert_eq!(threads.len(), 3);
    for t in threads {
        assert!(t["rms_d_mm"].as_f64().unwrap() > 0.0);
        assert!((0.0..=100.0).contains(&t["score"].as_f64().unwrap()));
    }
    assert_eq!(v["values"]["r1"], 4.0);
    // The notes cite papers by authors and year, as the command line does.
    let caveats = v["caveats"].to_string();
    assert!(
        caveats.contains("Manoilenko et al. (2024)") && !caveats.contains("seed 00"),
        "{caveats}"
    );
    let max_p = |v: &Value| v["paths"][0]["max_p_mm"].as_f64().unwrap();

    // The eccentric's throw moves P: with T1 up at TDC a larger throw swings
    // T1 further down while the needle descends, so less thread passes B
    // (docs/published-facts.md MF05: seed 000 §6 states the opposite sign).
    let r1 = json(&get(&app, "/api/evaluate?p.r1=6"));
    assert_eq!(r1["values"]["r1"], 6.0);
    assert!(max_p(&r1) < max_p(&v) - 3.0, "{} vs {}", max_p(&r1), max_p(&v));
    assert_ne!(r1["chart_svg"], v["chart_svg"]);

    // Thickness and stitch length move P' (and so the mismatch), not P.
    let m = json(&get(&app, "/api/evaluate?p.m=5&p.stitch=4"));
    assert_eq!(m["stitch"]["m_mm"], 5.0);
    assert_eq!(m["stitch"]["t_mm"], 4.0);
    assert_eq!(max_p(&m), max_p(&v));
    let per_stitch = |v: &Value| v["stitch"]["threads"][0]["per_stitch_mm"].as_f64().unwrap();
    assert!(
        per_stitch(&m) > per_stitch(&v) + 1.0,
        "{} vs {}",
        per_stitch(&m),
        per_stitch(&v)
    );
    assert_ne!(m["chart_svg"], v["chart_svg"]);

    // A coarser step is accepted and reported.
    assert_eq!(json(&get(&app, "/api/evaluate?step=2"))["step_deg"], 2.0);
}

#[test]
fn the_lockstitch_page_follows_the_hook_timing() {
    let app = app("lockstitch");
    let v = json(&get(&app, "/api/evaluate"));
    assert!(!v.to_string().contains("NaN"));
    assert_eq!(v["stitch"]["type"], 301);
    let threads = v["stitch"]["threads"].as_array().unwrap();
    assert_eq!(threads.len(), 1);
    let max_pprime = |v: &Value| v["stitch"]["threads"][0]["max_pprime_mm"].as_f64().unwrap();
    // An earlier cast-off lets the loop go less far round the bobbin case.
    let early = json(&get(&app, "/api/evaluate?p.cast_off=130"));
    assert_eq!(early["values"]["cast_off"], 130.0);
    assert!(
        max_pprime(&early) < max_pprime(&v),
        "{} vs {}",
        max_pprime(&early),
        max_pprime(&v)
    );
    let r = get(&app, "/api/drawing?phi=200");
    assert_eq!(r.status, 200, "{}", r.text());
    assert!(r.text().starts_with("<svg"));
}

#[test]
fn a_model_without_threads_charts_its_transmission_angles() {
    let app = app("needle876");
    assert_eq!(json(&get(&app, "/api/model"))["chart"], "mu");
    let v = json(&get(&app, "/api/evaluate"));
    assert!(v["stitch"].is_null());
    let dyads = v["transmission"].as_array().unwrap().len();
    assert!(dyads > 0);
    let svg = v["chart_svg"].as_str().unwrap();
    assert_eq!(svg.matches("class=\"series\"").count(), dyads, "one μ line per dyad");
}

#[test]
fn drawing_is_svg_at_phi() {
    let app = app("mf7923d");
    let r = get(&app, "/api/drawing?phi=90");
    assert_eq!(r.status, 200, "{}", r.text());
    assert!(r.content_type.starts_with("image/svg+xml"));
    assert!(r.text().starts_with("<svg"));
    assert!(!r.text().contains("NaN"));
    let other = get(&app, "/api/drawing?phi=180");
    assert_ne!(r.body, other.body, "the mechanism moves with φ");
    let anim = get(&app, "/api/drawing?animate=1");
    assert_eq!(anim.status, 200, "{}", anim.text());
    assert!(anim.text().contains("<animate"), "an animation over the cycle");
}

#[test]
fn bad_requests_get_a_4xx_that_says_what_to_fix() {
    let app = app("mf7923d");
    assert_client_error(&app, "/api/evaluate?p.r1=99", 400, "outside its adjustable range 4…6");
    assert_client_error(&app, "/api/evaluate?p.zz=1", 400, "no parameter `zz`");
    assert_client_error(&app, "/api/evaluate?p.r1=abc", 400, "not a finite number");
    assert_client_error(&app, "/api/evaluate?p.r1=NaN", 400, "not a finite number");
    assert_client_error(&app, "/api/evaluate?p.r1=inf", 400, "not a finite number");
    assert_client_error(&app, "/api/evaluate?p.r1=", 400, "not a finite number");
    assert_client_error(&app, "/api/evaluate?p.r1=5&p.r1=6", 400, "given twice");
    assert_client_error(&app, "/api/evaluate?rpm=100", 400, "unknown query key `rpm`");
    assert_client_error(&app, "/api/evaluate?step=0", 400, "outside 0.25…10");
    assert_client_error(&app, "/api/evaluate?step=-1", 400, "outside 0.25…10");
    assert_client_error(&app, "/api/model?x=1", 400, "unknown query key");
    assert_client_error(&app, "/api/drawing?phi=north", 400, "not a finite number");
    assert_client_error(&app, "/api/drawing?animate=maybe", 400, "not a switch");
    assert_client_error(&app, "/api/drawing?view=sideways", 400, "sideways");
    assert_client_error(&app, "/nothing/here", 404, "nothing at /nothing/here");
    let long = format!("/api/evaluate?p.r1={}", "5".repeat(20_000));
    assert_eq!(get(&app, &long).status, 414);
    let post = app.handle("POST", "/api/evaluate");
    assert_eq!(post.status, 405);
    // Percent-encoded keys and values are decoded before the checks.
    assert_eq!(get(&app, "/api/evaluate?p.r1=5%2E5").status, 200);
}

#[test]
fn derived_parameters_cannot_be_set() {
    let model = Model::preset("mf7923d").unwrap();
    let Some(derived) = model.params().iter().find(|p| p.is_derived()) else {
        return;
    };
    let app = App::new(model.clone(), model.defaults());
    assert_client_error(&app, &format!("/api/evaluate?p.{}=1", derived.name), 400, "derived");
}

#[test]
fn a_setting_without_assembly_is_a_422_naming_the_group() {
    // r 15 mm, l 50 mm, c 40 mm, O1O2 60 mm: a crank-rocker (the library's
    // test four-bar).
    let model = Model::from_toml_str(
        include_str!("../../../stitchkin/tests/data/four-bar.toml"),
        "four-bar.toml",
    )
    .unwrap();
    let app = App::new(model.clone(), model.defaults());
    assert_eq!(get(&app, "/api/evaluate").status, 200);
    // With l = 10 mm the coupler reaches O2 near φ = 0 but not at φ = 180°.
    assert_eq!(get(&app, "/api/drawing?p.l=10&phi=0").status, 200);
    for url in [
        "/api/evaluate?p.l=10",
        "/api/drawing?p.l=10&phi=180",
        "/api/drawing?p.l=10&animate=1",
    ] {
        let r = get(&app, url);
        assert_eq!(r.status, 422, "{url}: {}", r.text());
        let v = json(&r);
        assert!(v["error"].as_str().unwrap().contains("bc"), "{v}");
        assert!(v["help"].as_str().unwrap().contains("dimensions"), "{v}");
    }
}

#[test]
fn repeated_trajectory_names_do_not_multiply_the_drawing() {
    let app = app("mf7923d");
    let points = json(&get(&app, "/api/model"))["moving_points"].clone();
    let point = points[0].as_str().unwrap().to_string();
    let one = get(&app, &format!("/api/drawing?trajectories={point}"));
    assert_eq!(one.status, 200, "{}", one.text());
    // As many times as a query holds.
    let times = 15_000 / (point.len() + 1);
    let many = get(
        &app,
        &format!("/api/drawing?trajectories={}", vec![point; times].join(",")),
    );
    assert_eq!(many.status, 200, "{}", many.text());
    assert_eq!(many.body.len(), one.body.len(), "each point drawn once");
    let names: Vec<String> = (0..33).map(|k| format!("x{k}")).collect();
    let url = format!("/api/drawing?trajectories={}", names.join(","));
    assert_client_error(&app, &url, 400, "more than 32 points");
}

#[test]
fn long_input_is_not_repeated_in_the_answer() {
    let app = app("mf7923d");
    let run = "b".repeat(100);
    for url in [
        format!("/{}", "b".repeat(200)),
        format!("/api/evaluate?{}=1", "b".repeat(10_000)),
        format!("/api/evaluate?p.{}=1", "b".repeat(10_000)),
        format!("/api/evaluate?p.r1={}", "b".repeat(10_000)),
        format!("/api/drawing?view={}", "b".repeat(10_000)),
        format!("/api/drawing?animate={}", "b".repeat(10_000)),
        format!("/api/drawing?trajectories={}", "b".repeat(10_000)),
    ] {
        let r = get(&app, &url);
        assert!((400..=404).contains(&r.status), "{}: {}", r.status, r.text());
        assert!(!r.text().contains(&run) && r.body.len() < 1000, "{}", r.text());
    }
    assert_client_error(&app, &format!("/{}", "b".repeat(300)), 414, "more than 256");
}

/// A model file sent as the page sends it.
fn post_file(app: &App, name: &str, text: &[u8]) -> Reply {
    app.handle_body(
        "POST",
        &format!("/api/models?name={name}"),
        Some("application/toml"),
        text,
    )
}

#[test]
fn every_preset_is_listed_with_its_title_and_can_be_asked_for() {
    let app = app("mf7923d");
    let v = json(&get(&app, "/api/models"));
    assert_eq!(v["started"]["preset"], "mf7923d");
    let listed = v["presets"].as_array().unwrap();
    assert_eq!(listed.len(), stitchkin::presets::ALL.len());
    for (entry, preset) in listed.iter().zip(stitchkin::presets::ALL) {
        let model = Model::preset(preset.name).unwrap();
        assert_eq!(entry["name"], preset.name);
        assert_eq!(entry["title"].as_str(), model.title(), "{}", preset.name);
        // Each one by name, without restarting anything.
        let m = json(&get(&app, &format!("/api/model?model={}", preset.name)));
        assert_eq!(m["name"], model.name());
        let e = get(&app, &format!("/api/evaluate?model={}&step=4", preset.name));
        assert_eq!(e.status, 200, "{}: {}", preset.name, e.text());
        let d = get(&app, &format!("/api/drawing?model={}", preset.name));
        assert_eq!(d.status, 200, "{}: {}", preset.name, d.text());
    }
    assert_client_error(&app, "/api/evaluate?model=needle877", 400, "not a preset");
    let r = json(&get(&app, "/api/evaluate?model=needle877"));
    assert!(r["help"].as_str().unwrap().contains("needle876"), "{r}");
}

#[test]
fn a_request_for_another_model_leaves_the_started_one_alone() {
    // Started with r1 = 5 (as `--set r1=5` does): not the preset as shipped.
    let model = Model::preset("mf7923d").unwrap();
    let mut base = model.defaults();
    model.set(&mut base, "r1", 5.0).unwrap();
    let app = App::new(model, base);
    let v = json(&get(&app, "/api/models"));
    assert!(v["started"]["preset"].is_null(), "{v}");
    assert_eq!(v["started"]["changed"]["r1"], 5.0);
    let needle = json(&get(&app, "/api/evaluate?model=needle876&p.alpha=20"));
    assert_eq!(needle["values"]["alpha"], 20.0);
    // A second tab without a model still sees the started one, with its r1.
    let started = json(&get(&app, "/api/evaluate"));
    assert_eq!(started["values"]["r1"], 5.0);
    assert!(started["values"].get("alpha").is_none());
    // The preset by name has its own values.
    assert_eq!(json(&get(&app, "/api/evaluate?model=mf7923d"))["values"]["r1"], 4.0);
    // Parameters are checked against the model named.
    assert_client_error(&app, "/api/evaluate?model=needle876&p.r1=5", 400, "no parameter `r1`");
}

#[test]
fn readouts_are_the_needle_stroke_and_the_thread_per_stitch_the_library_computes() {
    use stitchkin::study::stroke::{Axis, stroke};
    let app = app("mf7923d");
    let model = Model::preset("needle876").unwrap();
    for alpha in [0.0, 30.0] {
        let v = json(&get(&app, &format!("/api/evaluate?model=needle876&p.alpha={alpha}")));
        let r = &v["readouts"][0];
        assert_eq!(r["name"], "needle_y.stroke");
        assert_eq!(r["unit"], "mm");
        let mut params = model.defaults();
        model.set(&mut params, "alpha", alpha).unwrap();
        let g = model.moving_point_slot("G").unwrap();
        let s = stroke(&model, &params, g, &Axis::parse(&model, "y").unwrap(), 1.0).unwrap();
        assert!(
            (r["value"].as_f64().unwrap() - s.stroke_mm).abs() < 1e-9,
            "{r} vs {}",
            s.stroke_mm
        );
        assert!(r["what"].as_str().unwrap().contains("G along y"), "{r}");
    }
    // The stroke follows α (the point of the preset).
    let stroke_at = |a: f64| {
        json(&get(&app, &format!("/api/evaluate?model=needle876&p.alpha={a}")))["readouts"][0]["value"]
            .as_f64()
            .unwrap()
    };
    assert!((stroke_at(0.0) - stroke_at(30.0)).abs() > 1.0);
    // A stitch model: the thread per stitch of each stitch thread.
    let v = json(&get(&app, "/api/evaluate?p.m=5"));
    let threads = v["stitch"]["threads"].as_array().unwrap();
    let readouts = v["readouts"].as_array().unwrap();
    assert_eq!(readouts.len(), threads.len());
    for (r, t) in readouts.iter().zip(threads) {
        assert_eq!(r["value"], t["per_stitch_mm"]);
        assert!(r["label"].as_str().unwrap().contains(t["thread"].as_str().unwrap()));
    }
}

#[test]
fn a_model_file_loads_and_is_evaluated_by_its_key() {
    let app = app("mf7923d");
    let text = stitchkin::presets::find("needle876").unwrap().toml;
    let r = post_file(&app, "my-needle.toml", text.as_bytes());
    assert_eq!(r.status, 200, "{}", r.text());
    let v = json(&r);
    let key = v["model"].as_str().unwrap().to_string();
    assert!(key.starts_with("file:"), "{key}");
    assert_eq!(v["file"], "my-needle.toml");
    // The same text again is the same model.
    assert_eq!(
        json(&post_file(&app, "again.toml", text.as_bytes()))["model"],
        key.as_str()
    );
    let m = json(&get(&app, &format!("/api/model?model={key}")));
    assert_eq!(m["name"], "needle876");
    let e = json(&get(&app, &format!("/api/evaluate?model={key}&p.alpha=10")));
    assert_eq!(e["values"]["alpha"], 10.0);
    assert_eq!(get(&app, &format!("/api/drawing?model={key}&phi=30")).status, 200);
    // The started model is still the default.
    assert_eq!(json(&get(&app, "/api/model"))["name"], "mf7923d");
}

#[test]
fn a_bad_model_file_gets_the_library_message_with_its_place_and_fix() {
    let app = app("mf7923d");
    // A parameter used but not declared: the loader names the place.
    let text = stitchkin::presets::find("needle876")
        .unwrap()
        .toml
        .replace("radius = \"l_oa\"", "radius = \"l_oa2\"");
    let r = post_file(&app, "broken.toml", text.as_bytes());
    assert_eq!(r.status, 422, "{}", r.text());
    let v = json(&r);
    let expected = Model::from_toml_str(&text, "broken.toml").unwrap_err();
    let error = v["error"].as_str().unwrap();
    assert!(error.starts_with("broken.toml:"), "{error}");
    assert!(error.contains(&expected.message), "{error}");
    assert_eq!(v["help"].as_str(), expected.help.as_deref());
    let (line, column) = expected.line_col().unwrap();
    assert_eq!(v["line"], line);
    assert_eq!(v["column"], column);
    assert!(v["excerpt"].as_str().unwrap().contains("l_oa2"), "{v}");
    // TOML that does not parse, text that is not UTF-8, an empty file.
    let r = post_file(
        &app,
        "bad.toml",
        b"[model]\nname = \"x\"\n[parameters]\na = { value = 1 unit = \"mm\" }\n",
    );
    assert_eq!(r.status, 422);
    assert!(
        json(&r)["error"].as_str().unwrap().starts_with("bad.toml:4:"),
        "{}",
        r.text()
    );
    let r = post_file(&app, "latin1.toml", b"[model]\nname = \"caf\xe9\"\n");
    assert_eq!(r.status, 422);
    assert!(
        json(&r)["error"].as_str().unwrap().contains("not UTF-8"),
        "{}",
        r.text()
    );
    assert_eq!(post_file(&app, "empty.toml", b"").status, 400);
    // Folders in the name are not repeated.
    let r = post_file(&app, "%2Fhome%2Fme%2Fbad.toml", b"[model");
    assert!(
        json(&r)["error"].as_str().unwrap().starts_with("bad.toml:"),
        "{}",
        r.text()
    );
}

#[test]
fn model_files_are_limited_in_size_type_and_number() {
    let app = app("mf7923d");
    let big = vec![b'#'; stitchkin_web::api::MAX_FILE_BYTES + 1];
    let r = post_file(&app, "big.toml", &big);
    assert_eq!(r.status, 413);
    let error = json(&r)["error"].as_str().unwrap().to_string();
    assert!(
        error.contains("256 kB") && error.contains(&big.len().to_string()),
        "{error}"
    );
    let r = app.handle_body("POST", "/api/models", Some("text/plain"), b"[model]\nname = \"x\"\n");
    assert_eq!(r.status, 415, "{}", r.text());
    assert!(r.text().contains("application/toml"));
    assert_eq!(app.handle("POST", "/api/evaluate").status, 405);
    assert_eq!(app.handle("PUT", "/api/models").status, 405);
    // The least recently used file is forgotten past MAX_FILES.
    let base = stitchkin::presets::find("needle876").unwrap().toml;
    let keys: Vec<String> = (0..=stitchkin_web::api::MAX_FILES)
        .map(|k| {
            let text = format!("{base}\n# copy {k}\n");
            let r = post_file(&app, "copy.toml", text.as_bytes());
            assert_eq!(r.status, 200, "{}", r.text());
            json(&r)["model"].as_str().unwrap().to_string()
        })
        .collect();
    let first = get(&app, &format!("/api/model?model={}", keys[0]));
    assert_eq!(first.status, 404, "{}", first.text());
    assert!(first.text().contains("load the file again"));
    for key in &keys[1..] {
        assert_eq!(get(&app, &format!("/api/model?model={key}")).status, 200, "{key}");
    }
}

#[test]
fn a_cam_models_checks_are_in_the_evaluation_and_on_the_page() {
    let app = app("needle876");
    let text = include_str!("../../../../examples/cam-rocking-roller.toml");
    let r = post_file(&app, "cam.toml", text.as_bytes());
    assert_eq!(r.status, 200, "{}", r.text());
    let key = json(&r)["model"].as_str().unwrap().to_string();
    let e = json(&get(&app, &format!("/api/evaluate?model={key}")));
    assert!(e["stitch"].is_null());
    let checks = e["checks"].as_array().unwrap();
    let names: Vec<&str> = checks.iter().map(|c| c["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["cam_pressure", "cam_curvature", "follower_contact"]);
    assert!(checks.iter().all(|c| c["thread"] == "feed_arm" && c["ok"] == true));
    assert_eq!(e["cams"][0]["group"], "feed_arm");
    // The page builds its checks table from every check of the cycle.
    let page = get(&app, "/");
    assert!(page.text().contains("checksTable(b.checks)"));
    let svg = get(&app, &format!("/api/drawing?model={key}&phi=30"));
    assert!(svg.text().contains("class=\"cam-profile\""));
}

/// A measured curve sent as the page sends it.
fn post_curve(app: &App, name: &str, text: &[u8]) -> Reply {
    app.handle_body("POST", &format!("/api/measured?name={name}"), Some("text/csv"), text)
}

const SEED004_LOWER: &str = include_str!("../../../../examples/seed004-bench-lower.csv");
const MF7923D_N1: &str = include_str!("../../../../examples/mf7923d-bench-n1.csv");

#[test]
fn a_measured_curve_is_read_and_drawn_with_its_error_bars() {
    use stitchkin::eval::{CycleOptions, run_cycle};
    use stitchkin::study::measured::measured_match;
    use stitchkin::thread::measured::parse_curve_csv;
    for (preset, file, text, thread) in [
        ("altin504", "seed004-bench-lower.csv", SEED004_LOWER, "lower"),
        ("mf7923d", "mf7923d-bench-n1.csv", MF7923D_N1, "n1"),
    ] {
        let app = app(preset);
        let r = post_curve(&app, file, text.as_bytes());
        assert_eq!(r.status, 200, "{file}: {}", r.text());
        let v = json(&r);
        let key = v["key"].as_str().unwrap().to_string();
        assert!(key.starts_with("measured:"), "{v}");
        assert_eq!(v["kind"], "take_up", "{v}");
        assert_eq!(v["thread"], thread, "{v}");
        assert_eq!(v["readings"], 10, "{v}");
        let curve = parse_curve_csv(text, file).unwrap();
        assert_eq!(v["points"], curve.phi_deg().len());
        assert_eq!(v["resolution_mm"], 0.05);
        let [lo, hi] = [
            v["interval_mm"][0].as_f64().unwrap(),
            v["interval_mm"][1].as_f64().unwrap(),
        ];
        assert!(0.05 <= lo && lo <= hi && hi < 1.0, "{v}");
        // The same text again is the same curve.
        assert_eq!(
            json(&post_curve(&app, "again.csv", text.as_bytes()))["key"],
            key.as_str()
        );

        let e = get(&app, &format!("/api/evaluate?measured={key}"));
        assert_eq!(e.status, 200, "{file}: {}", e.text());
        assert!(!e.text().contains("NaN"));
        let e = json(&e);
        let svg = e["chart_svg"].as_str().unwrap();
        assert!(
            svg.contains(&format!("{thread} P measured")),
            "the mean curve in the legend"
        );
        // An error bar per φ read, each with the interval as its tooltip.
        let bars = svg.matches("Polyakov (2022) §3.4").count();
        assert!(bars >= curve.phi_deg().len() - 1, "{bars} error bars");
        let m = &e["measured"];
        assert_eq!(m["key"], key.as_str());
        assert_eq!(m["thread"], thread);
        assert_eq!(m["interval"]["readings_per_phi"], 10);
        let within = m["interval"]["model_within_pct"].as_f64().unwrap();
        assert!((0.0..=100.0).contains(&within), "{within}");
        assert!((0.0..=100.0).contains(&m["against_model"]["score"].as_f64().unwrap()));
        // The library's match on the same cycle.
        let model = Model::preset(preset).unwrap();
        let opts = CycleOptions {
            step_deg: 1.0,
            analogs: false,
            points: Some(Vec::new()),
            ..Default::default()
        };
        let table = run_cycle(&model, &model.defaults(), &opts).unwrap();
        let expected = measured_match(&table, &curve, None).unwrap();
        let expected_interval = expected.interval.as_ref().unwrap();
        assert!((within - expected_interval.model_within_pct).abs() < 1e-9, "{within}");
        assert_eq!(
            m["against_model"]["rms_d_mm"].as_f64().unwrap(),
            expected.against_model.as_ref().unwrap().rms_d_mm
        );
        // The curve follows the sliders: the model moves, the match with it.
        let param = if preset == "mf7923d" {
            "p.z=-3&p.dphi=5"
        } else {
            "p.timing_l=4"
        };
        let moved = get(&app, &format!("/api/evaluate?measured={key}&{param}"));
        assert_eq!(moved.status, 200, "{param}: {}", moved.text());
        let moved = json(&moved);
        let rms = |v: &Value| v["measured"]["against_model"]["rms_d_mm"].as_f64().unwrap();
        assert!((rms(&moved) - rms(&e)).abs() > 0.01, "{} vs {}", rms(&moved), rms(&e));
        assert!(moved["chart_svg"].as_str().unwrap().contains("Polyakov (2022) §3.4"));
        // Without `measured` the evaluation is as before: no measured curve.
        let plain = json(&get(&app, "/api/evaluate"));
        assert!(plain.get("measured").is_none());
        assert!(!plain["chart_svg"].as_str().unwrap().contains("measured"));
    }
}

#[test]
fn the_thread_of_a_measured_curve_is_the_columns_or_the_one_chosen() {
    let app = app("mf7923d");
    // The mf7923d readings without their thread in the column.
    let text = MF7923D_N1.replace("n1.P_B_mm", "P_B_mm");
    let key = json(&post_curve(&app, "bench.csv", text.as_bytes()))["key"]
        .as_str()
        .unwrap()
        .to_string();
    let r = get(&app, &format!("/api/evaluate?measured={key}"));
    assert_eq!(r.status, 400, "{}", r.text());
    let v = json(&r);
    assert!(
        v["error"].as_str().unwrap().contains("does not say which thread"),
        "{v}"
    );
    assert!(v["help"].as_str().unwrap().contains("n1.P_B_mm"), "{v}");
    let v = json(&get(&app, &format!("/api/evaluate?measured={key}&measured_thread=n1")));
    assert_eq!(v["measured"]["thread"], "n1", "{v}");
    // A thread the model does not have: the ones it compares.
    let r = get(&app, &format!("/api/evaluate?measured={key}&measured_thread=n7"));
    assert_eq!(r.status, 400, "{}", r.text());
    let v = json(&r);
    assert!(v["error"].as_str().unwrap().contains("`n7`"), "{v}");
    assert!(v["help"].as_str().unwrap().contains("n1, n2"), "{v}");
    // With the threads it can be set beside, for the page's menu.
    assert_eq!(v["threads"], serde_json::json!(["n1", "n2", "n3"]));
    // The thread names the curve, so it needs one.
    assert_client_error(
        &app,
        "/api/evaluate?measured_thread=n1",
        400,
        "no measured curve is given",
    );
}

#[test]
fn a_bad_measured_curve_gets_the_library_message_naming_the_line() {
    let app = app("altin504");
    // A reading that is not a number on line 13.
    let text = SEED004_LOWER.replacen("0.60,0.65", "0.60,O.65", 1);
    let r = post_curve(&app, "bench.csv", text.as_bytes());
    assert_eq!(r.status, 400, "{}", r.text());
    let v = json(&r);
    let expected = match stitchkin::thread::measured::parse_curve_csv(&text, "bench.csv").unwrap_err() {
        stitchkin::Error::Model(m) => m,
        other => panic!("{other}"),
    };
    let (line, column) = expected.line_col().unwrap();
    assert_eq!(line, 12);
    let error = v["error"].as_str().unwrap();
    assert!(error.starts_with(&format!("bench.csv:{line}:{column}: ")), "{error}");
    assert!(error.contains(&expected.message), "{error}");
    assert_eq!(v["help"].as_str(), expected.help.as_deref());
    assert_eq!(v["line"], line);
    assert!(v["excerpt"].as_str().unwrap().contains("O.65"), "{v}");
    // A header that says nothing of what the values are.
    let r = post_curve(&app, "plain.csv", b"phi_deg,length\n0,1\n90,2\n180,3\n270,2\n");
    assert_eq!(r.status, 400, "{}", r.text());
    assert!(
        json(&r)["error"].as_str().unwrap().starts_with("plain.csv:1:"),
        "{}",
        r.text()
    );
    // Empty, not CSV, too large.
    assert_eq!(post_curve(&app, "empty.csv", b"").status, 400);
    let r = app.handle_body(
        "POST",
        "/api/measured",
        Some("application/toml"),
        SEED004_LOWER.as_bytes(),
    );
    assert_eq!(r.status, 415, "{}", r.text());
    assert!(r.text().contains("text/csv"));
    let big = vec![b'#'; stitchkin_web::api::MAX_CURVE_BYTES + 1];
    let r = post_curve(&app, "big.csv", &big);
    assert_eq!(r.status, 413, "{}", r.text());
    assert!(json(&r)["error"].as_str().unwrap().contains("256 kB"), "{}", r.text());
    assert_eq!(app.handle("GET", "/api/measured").status, 405);
}

#[test]
fn an_unknown_measured_key_is_a_400_that_says_to_send_the_curve() {
    let app = app("mf7923d");
    for key in ["measured:0123456789abcdef", "file:0123456789abcdef", "lower.csv"] {
        let r = get(&app, &format!("/api/evaluate?measured={key}"));
        assert_eq!(r.status, 400, "{key}: {}", r.text());
        let v = json(&r);
        assert!(v["error"].as_str().unwrap().contains("not a measured curve"), "{v}");
        assert!(v["help"].as_str().unwrap().contains("POST /api/measured"), "{v}");
    }
    // A model file's key is not a curve's, nor the other way round.
    let key = json(&post_curve(&app, "n1.csv", MF7923D_N1.as_bytes()))["key"]
        .as_str()
        .unwrap()
        .to_string();
    let r = get(&app, &format!("/api/model?model={}", key.replace("measured:", "file:")));
    assert_eq!(r.status, 404, "{}", r.text());
    // The least recently used curve is forgotten past MAX_CURVES.
    let keys: Vec<String> = (0..=stitchkin_web::api::MAX_CURVES)
        .map(|k| {
            let text = format!("{MF7923D_N1}\n# copy {k}\n");
            json(&post_curve(&app, "copy.csv", text.as_bytes()))["key"]
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    assert_eq!(
        get(&app, &format!("/api/evaluate?measured={}&step=5", keys[0])).status,
        400
    );
    assert_eq!(
        get(&app, &format!("/api/evaluate?measured={}&step=5", keys[1])).status,
        200
    );
}
