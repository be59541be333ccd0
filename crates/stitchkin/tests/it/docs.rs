//! docs/model-format.md stays true: every complete model in it (a ```toml
//! block) loads and solves a full cycle, every fragment (```toml-fragment) is
//! valid TOML, and the numbers the text quotes are the numbers the examples
//! produce.

use stitchkin::eval::{CycleTable, run_cycle};
use stitchkin::model::Model;

const DOC_PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/model-format.md");

/// A fenced code block of the document.
struct Block {
    /// 1-based line of the opening fence.
    line: usize,
    /// Info string after the fence, e.g. `toml`.
    info: String,
    text: String,
}

fn doc() -> String {
    std::fs::read_to_string(DOC_PATH).unwrap_or_else(|e| panic!("cannot read {DOC_PATH}: {e}"))
}

/// Every fenced (```) code block, in order.
fn blocks(doc: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, line) in doc.lines().enumerate() {
        let t = line.trim_start();
        match open.as_mut() {
            None => {
                if let Some(info) = t.strip_prefix("```") {
                    open = Some(Block {
                        line: i + 1,
                        info: info.trim().to_string(),
                        text: String::new(),
                    });
                }
            }
            Some(b) => {
                if t.starts_with("```") && t.trim_start_matches('`').trim().is_empty() {
                    out.push(open.take().expect("a block is open"));
                } else {
                    b.text.push_str(line);
                    b.text.push('\n');
                }
            }
        }
    }
    if let Some(b) = open {
        panic!(
            "docs/model-format.md: the code block opened on line {} is never closed",
            b.line
        );
    }
    out
}

/// Complete models: blocks whose info string is exactly `toml`.
fn models(doc: &str) -> Vec<Block> {
    blocks(doc)
        .into_iter()
        .filter(|b| b.info == "toml")
        .collect()
}

fn load(b: &Block) -> Result<Model, String> {
    Model::from_toml_str(
        &b.text,
        &format!("docs/model-format.md (block at line {})", b.line),
    )
    .map_err(|e| e.to_string())
}

fn cycle(m: &Model) -> Result<CycleTable, String> {
    run_cycle(m, &m.defaults(), &Default::default()).map_err(|e| e.to_string())
}

#[test]
fn every_toml_block_in_the_model_format_doc_loads_and_runs() {
    let doc = doc();
    let models = models(&doc);
    assert!(
        models.len() >= 7,
        "expected the worked examples in docs/model-format.md, found {} toml blocks",
        models.len()
    );
    let mut failures = Vec::new();
    for b in &models {
        if !b.text.lines().any(|l| l.trim() == "[model]") {
            failures.push(format!(
                "line {}: a ```toml block must be a complete model with a [model] table (mark fragments ```toml-fragment)",
                b.line
            ));
            continue;
        }
        match load(b).and_then(|m| cycle(&m).map(|t| (m, t))) {
            Ok((m, t)) => {
                if t.rows() != 360 {
                    failures.push(format!(
                        "line {} ({}): {} rows instead of 360",
                        b.line,
                        m.file.model.name,
                        t.rows()
                    ));
                }
            }
            Err(e) => failures.push(format!("line {}: {e}", b.line)),
        }
    }
    assert!(
        failures.is_empty(),
        "docs/model-format.md has toml blocks that fail:\n\n{}",
        failures.join("\n\n")
    );
}

#[test]
fn model_names_in_the_doc_are_distinct() {
    let doc = doc();
    let mut names: Vec<String> = models(&doc)
        .iter()
        .filter_map(|b| load(b).ok())
        .map(|m| m.file.model.name)
        .collect();
    let n = names.len();
    names.sort();
    names.dedup();
    assert_eq!(
        names.len(),
        n,
        "two worked examples share a [model] name: {names:?}"
    );
}

#[test]
fn toml_fragments_in_the_doc_are_valid_toml() {
    let doc = doc();
    let mut failures = Vec::new();
    let mut n = 0;
    for b in blocks(&doc).iter().filter(|b| b.info == "toml-fragment") {
        n += 1;
        if let Err(e) = b.text.parse::<toml::Table>() {
            failures.push(format!("line {}: {e}", b.line));
        }
    }
    assert!(n > 0, "no ```toml-fragment blocks found");
    assert!(
        failures.is_empty(),
        "docs/model-format.md has fragments that are not valid TOML:\n\n{}",
        failures.join("\n\n")
    );
}

/// The worked example called `name`, solved over a cycle at 1° steps.
fn example(name: &str) -> (Model, CycleTable) {
    let doc = doc();
    for b in models(&doc) {
        let Ok(m) = load(&b) else { continue };
        if m.file.model.name == name {
            let t = cycle(&m).unwrap_or_else(|e| panic!("example `{name}` (line {}): {e}", b.line));
            return (m, t);
        }
    }
    panic!("docs/model-format.md has no example named `{name}`");
}

fn col<'a>(t: &'a CycleTable, name: &str) -> &'a [f64] {
    t.column(name).unwrap_or_else(|| {
        let names: Vec<&str> = t.columns.iter().map(|c| c.name.as_str()).collect();
        panic!("no column `{name}`; columns are {names:?}")
    })
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: the doc says {want}, the example gives {got}"
    );
}

#[test]
fn the_numbers_quoted_in_the_doc_are_what_the_examples_give() {
    // Example 1: four-bar with a coupler point.
    let (m, t) = example("fourbar");
    assert!(m.planar);
    let mu = &t.transmission[0];
    assert_eq!(mu.key, "coupler_rocker");
    close(mu.min_deg, 58.75, 0.005, "four-bar μ min");
    close(mu.max_deg, 112.41, 0.005, "four-bar μ max");
    close(col(&t, "B.x_mm")[0], 47.5, 1e-9, "four-bar B.x at φ = 0");
    close(col(&t, "B.y_mm")[0], 37.997, 5e-4, "four-bar B.y at φ = 0");
    close(col(&t, "P.x_mm")[0], 18.659, 5e-4, "four-bar P.x at φ = 0");
    close(col(&t, "P.y_mm")[0], 19.662, 5e-4, "four-bar P.y at φ = 0");
    close(t.ranges[0].min, 45.7787, 5e-5, "four-bar P_to_O2 min");
    close(t.ranges[0].max, 67.1137, 5e-5, "four-bar P_to_O2 max");
    assert!(
        t.column("P.z_mm").is_none(),
        "a planar model has no z columns"
    );
    let mut p = m.defaults();
    assert!(
        m.set(&mut p, "l_crank", 25.0).is_err(),
        "l_crank = 25 is outside its range"
    );
    m.set(&mut p, "l_crank", 18.0).unwrap();
    run_cycle(&m, &p, &Default::default()).unwrap();
    let mut p = m.defaults();
    m.set(&mut p, "l_coupler", 30.0).unwrap();
    let e = run_cycle(&m, &p, &Default::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no assembly at φ = 127.000°") && e.contains("coupler_rocker"),
        "{e}"
    );

    // Example 2: offset slider-crank, stroke √((l+r)² − e²) − √((l−r)² − e²).
    let (_, t) = example("slider_crank");
    let stroke = (57.0f64 * 57.0 - 36.0).sqrt() - (33.0f64 * 33.0 - 36.0).sqrt();
    close(t.ranges[0].range, stroke, 1e-3, "slider-crank stroke");
    close(stroke, 24.233, 5e-4, "slider-crank stroke formula");
    close(
        t.transmission[0].min_deg,
        66.42,
        0.005,
        "slider-crank μ min",
    );
    close(
        t.transmission[0].phi_at_min_deg,
        270.0,
        1e-9,
        "slider-crank φ at μ min",
    );

    // Example 3: spatial RSSR.
    let (m, t) = example("spatial_rssr");
    assert!(!m.planar && t.column("N.z_mm").is_some());
    let rod = t.ranges.iter().find(|r| r.name == "rod_check").unwrap();
    close(rod.min, 66.0, 1e-9, "rod_check min");
    close(rod.max, 66.0, 1e-9, "rod_check max");
    let mu = t.transmission.iter().find(|m| m.key == "rocker").unwrap();
    close(mu.min_deg, 78.0, 0.5, "RSSR μ min");
    close(mu.max_deg, 121.0, 0.6, "RSSR μ max");
    let needle = t.ranges.iter().find(|r| r.name == "needle_y").unwrap();
    close(needle.range, 16.5, 0.05, "needle stroke");

    // Example 4: the newton dyad agrees with the closed form, analogs too.
    let (_, t) = example("fourbar_newton");
    for c in ["gap_x", "gap_y"] {
        for suffix in ["_mm", ".d_dphi_mm_per_rad", ".d2_dphi2_mm_per_rad2"] {
            let v = col(&t, &format!("{c}{suffix}"));
            let worst = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!(worst < 1e-9, "{c}{suffix} reaches {worst}");
        }
    }
    let s = col(&t, "S.x_mm");
    assert!(
        s.iter().all(|x| (x - 70.0).abs() < 1e-9),
        "the slider leaves its line"
    );

    // Example 6: μ = acos(e / |A − C|) of the slotted lever.
    let (m, t) = example("slotted_lever");
    assert!(!m.planar, "a lift makes the model spatial");
    let mu = col(&t, "mu_lever_deg");
    close(
        mu[90],
        (4.0f64 / 70.0).acos().to_degrees(),
        1e-9,
        "slotted lever μ at φ = 90°",
    );
    close(mu[90], 86.72, 0.005, "slotted lever μ at φ = 90° as quoted");
    close(
        mu[270],
        82.34,
        0.005,
        "slotted lever μ at φ = 270° as quoted",
    );

    // Example 7: the inclined four-bar moves in its plane like Example 1.
    let (_, flat) = example("fourbar");
    let (_, t) = example("inclined_fourbar");
    let phi = col(&t, "phi_deg");
    close(phi[0], 90.0, 0.0, "inclined four-bar first φ");
    close(phi[359], 449.0, 1e-9, "inclined four-bar last φ");
    // Row k of the inclined run is φ = 90 + k, row (90 + k) mod 360 of the flat one.
    let dev = col(&t, "P_above_frame_line_mm");
    let height = col(&t, "P_height_mm");
    let py = col(&flat, "P.y_mm");
    let mu_flat = col(&flat, "mu_coupler_rocker_deg");
    let mu = col(&t, "mu_coupler_rocker_deg");
    let angle_flat = col(&flat, "angle_A_B_deg");
    let angle = col(&t, "angle_A_B_deg");
    for k in 0..360 {
        let j = (90 + k) % 360;
        close(dev[k], py[j], 1e-9, "in-plane deviation = flat P.y");
        close(
            height[k],
            5.0 + py[j] * 20f64.to_radians().sin(),
            1e-9,
            "P_height",
        );
        close(mu[k], mu_flat[j], 1e-9, "μ in the inclined plane");
        close(
            angle[k],
            angle_flat[j],
            1e-9,
            "link angle in the inclined plane",
        );
    }
}
