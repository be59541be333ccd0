//! docs/model-format.md stays true: every complete model in it (a ```toml
//! block) loads and solves a full cycle, every fragment (```toml-fragment) is
//! valid TOML, and the numbers the text quotes are the numbers the examples
//! produce.

use stitchkin::eval::{CycleTable, run_cycle};
use stitchkin::model::Model;
use stitchkin::study::compare_2d3d::compare_2d3d;

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
    blocks(doc).into_iter().filter(|b| b.info == "toml").collect()
}

fn load(b: &Block) -> Result<Model, String> {
    Model::from_toml_str(&b.text, &format!("docs/model-format.md (block at line {})", b.line))
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
                        m.name(),
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
        .map(|m| m.name().to_string())
        .collect();
    let n = names.len();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), n, "two worked examples share a [model] name: {names:?}");
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
        if m.name() == name {
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
    assert!(m.is_planar());
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
    assert!(t.column("P.z_mm").is_none(), "a planar model has no z columns");
    let mut p = m.defaults();
    assert!(
        m.set(&mut p, "l_crank", 25.0).is_err(),
        "l_crank = 25 is outside its range"
    );
    m.set(&mut p, "l_crank", 18.0).unwrap();
    run_cycle(&m, &p, &Default::default()).unwrap();
    let mut p = m.defaults();
    m.set(&mut p, "l_coupler", 30.0).unwrap();
    let e = run_cycle(&m, &p, &Default::default()).unwrap_err().to_string();
    assert!(
        e.contains("no assembly at φ = 127.000°") && e.contains("coupler_rocker"),
        "{e}"
    );

    // Example 2: offset slider-crank, stroke √((l+r)² − e²) − √((l−r)² − e²).
    let (_, t) = example("slider_crank");
    let stroke = (57.0f64 * 57.0 - 36.0).sqrt() - (33.0f64 * 33.0 - 36.0).sqrt();
    close(t.ranges[0].range, stroke, 1e-3, "slider-crank stroke");
    close(stroke, 24.233, 5e-4, "slider-crank stroke formula");
    close(t.transmission[0].min_deg, 66.42, 0.005, "slider-crank μ min");
    close(t.transmission[0].phi_at_min_deg, 270.0, 1e-9, "slider-crank φ at μ min");

    // Example 3: spatial RSSR.
    let (m, t) = example("spatial_rssr");
    assert!(!m.is_planar() && t.column("N.z_mm").is_some());
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
    assert!(s.iter().all(|x| (x - 70.0).abs() < 1e-9), "the slider leaves its line");

    // Example 6: μ = acos(e / |A − C|) of the slotted lever.
    let (m, t) = example("slotted_lever");
    assert!(!m.is_planar(), "a lift makes the model spatial");
    let mu = col(&t, "mu_lever_deg");
    close(
        mu[90],
        (4.0f64 / 70.0).acos().to_degrees(),
        1e-9,
        "slotted lever μ at φ = 90°",
    );
    close(mu[90], 86.72, 0.005, "slotted lever μ at φ = 90° as quoted");
    close(mu[270], 82.34, 0.005, "slotted lever μ at φ = 270° as quoted");

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
        close(height[k], 5.0 + py[j] * 20f64.to_radians().sin(), 1e-9, "P_height");
        close(mu[k], mu_flat[j], 1e-9, "μ in the inclined plane");
        close(angle[k], angle_flat[j], 1e-9, "link angle in the inclined plane");
    }
}

fn path<'a>(t: &'a CycleTable, name: &str) -> &'a stitchkin::eval::PathSummary {
    t.paths
        .iter()
        .find(|p| p.path == name)
        .unwrap_or_else(|| panic!("no thread path `{name}`"))
}

/// A φ interval of a summary as (from, to), `to` wrapped past 360 when the
/// interval wraps.
fn spans(iv: &[stitchkin::thread::Interval]) -> Vec<(f64, f64)> {
    iv.iter().map(|i| (i.from_deg, i.to_deg)).collect()
}

#[test]
fn the_thread_numbers_quoted_in_the_doc_are_what_the_examples_give() {
    eyelet_crank_numbers();
    pin_and_roller_numbers();
    needle_bar_thread_numbers();
    mf7923d_thread_numbers();
    mf7923d_regulator_numbers();
}

/// Example 8: an eyelet on a crank, ξ(φ) in closed form.
fn eyelet_crank_numbers() {
    let (m, t) = example("eyelet_crank");
    assert!(m.is_planar(), "thread paths leave a planar model planar");
    let (r, h, a) = (10.0f64, 30.0f64, 40.0f64);
    let xi = |phi: f64| {
        let (x, y) = (r * phi.cos(), h + r * phi.sin());
        (a + x).hypot(y) + (a - x).hypot(y)
    };
    let phis = col(&t, "phi_deg");
    let (x, p) = (col(&t, "upper.xi_mm"), col(&t, "upper.P_mm"));
    for k in 0..phis.len() {
        let phi = phis[k].to_radians();
        close(x[k], xi(phi), 1e-12, "Example 8 ξ(φ) closed form");
        close(p[k], xi(0.0) - xi(phi), 1e-12, "Example 8 P = ξ(0) − ξ(φ)");
    }
    close(xi(0.0), 100.736, 5e-4, "Example 8 ξ(0)");
    close(x[90], 113.137, 5e-4, "Example 8 ξ(90°)");
    close(x[270], 89.443, 5e-4, "Example 8 ξ(270°)");
    let s = path(&t, "upper");
    close(s.max_p_mm, 11.293, 5e-4, "Example 8 max P");
    close(s.phi_at_max_deg, 270.0, 0.0, "Example 8 φ at max P");
    close(s.min_p_mm, -12.401, 5e-4, "Example 8 min P");
    close(s.phi_at_min_deg, 90.0, 0.0, "Example 8 φ at min P");
    assert_eq!(spans(&s.flat), vec![(77.0, 103.0), (254.0, 286.0)], "Example 8 dwells");
    let [lo, hi] = s.eye_tension_n.expect("Example 8 has tension_n");
    close(lo, 0.5 * (0.2 * 0.6f64.acos()).exp(), 1e-9, "Example 8 eye tension min");
    close(
        hi,
        0.5 * (0.2 * std::f64::consts::FRAC_PI_2).exp(),
        1e-9,
        "Example 8 eye tension max",
    );
    close(lo, 0.602, 5e-4, "Example 8 eye tension min as quoted");
    close(hi, 0.685, 5e-4, "Example 8 eye tension max as quoted");
    close(
        col(&t, "upper.d2P_dphi2_mm_per_rad2")[90],
        12.374,
        5e-4,
        "Example 8 d²P/dφ² at 90°",
    );
    close(
        col(&t, "upper.dP_dphi_mm_per_rad")[0],
        -12.216,
        5e-4,
        "Example 8 dP/dφ at 0",
    );
    let opts = stitchkin::eval::CycleOptions {
        rpm: m.rpm(),
        ..Default::default()
    };
    let with_rpm = run_cycle(&m, &m.defaults(), &opts).unwrap();
    close(
        col(&with_rpm, "upper.vP_mm_per_s")[0],
        -1279.26,
        5e-3,
        "Example 8 vP at 0 with its rpm",
    );
    assert!(
        t.take_up
            .as_deref()
            .unwrap()
            .contains("xi(phi0) - xi(phi), phi0 = 0 deg")
    );
}

/// Example 9: a thin pin and a roller.
fn pin_and_roller_numbers() {
    let (m, t) = example("pin_and_roller");
    assert!(m.is_planar());
    let beta = 30.0f64.atan2(40.0).to_degrees();
    close(beta, 36.87, 5e-3, "Example 9 β");
    let (x, on) = (col(&t, "thin.xi_mm"), col(&t, "thin.C_engaged"));
    let (x_thick, on_thick) = (col(&t, "thick.xi_mm"), col(&t, "thick.C_engaged"));
    for (k, phi) in col(&t, "phi_deg").iter().enumerate() {
        let (tx, ty) = (10.0 * phi.to_radians().cos(), 30.0 + 10.0 * phi.to_radians().sin());
        let engaged = (phi - beta).to_radians().sin() < 0.0;
        assert_eq!(on[k] == 1.0, engaged, "Example 9 thin pin engaged at φ = {phi}");
        let first = if engaged {
            25.0 + (tx + 20.0).hypot(ty - 15.0)
        } else {
            (tx + 40.0).hypot(ty)
        };
        close(
            x[k],
            first + (40.0 - tx).hypot(ty),
            1e-9,
            "Example 9 thin ξ closed form",
        );
        assert!(
            x_thick[k] >= x[k] - 1e-12,
            "Example 9: the roller's path is never shorter"
        );
        assert!(
            on_thick[k] >= on[k],
            "Example 9: the roller bears wherever the pin does"
        );
    }
    close(
        col(&t, "thin.C_wrap_deg")[270],
        36.87 - 14.04,
        0.01,
        "Example 9 wrap at 270°",
    );
    close(
        col(&t, "thin.C_wrap_deg")[270],
        22.83,
        5e-3,
        "Example 9 wrap at 270° as quoted",
    );
    let (thin, thick) = (path(&t, "thin"), path(&t, "thick"));
    assert_eq!(
        spans(&thin.engaged[0].1),
        vec![(217.0, 396.0)],
        "Example 9 thin engaged"
    );
    assert_eq!(
        spans(&thick.engaged[0].1),
        vec![(198.0, 425.0)],
        "Example 9 roller engaged"
    );
    close(thin.max_p_mm, 10.668, 5e-4, "Example 9 thin max P");
    close(thin.phi_at_max_deg, 264.0, 0.0, "Example 9 thin φ at max P");
    close(thin.min_p_mm, -12.170, 5e-4, "Example 9 thin min P");
    close(thick.max_p_mm, 10.224, 5e-4, "Example 9 thick max P");
    close(thick.phi_at_max_deg, 262.0, 0.0, "Example 9 thick φ at max P");
    close(thick.min_p_mm, -11.670, 5e-4, "Example 9 thick min P");
    assert_eq!(
        spans(&thin.flat),
        vec![(77.0, 103.0), (246.0, 285.0)],
        "Example 9 thin dwells"
    );
    assert_eq!(
        spans(&thick.flat),
        vec![(77.0, 103.0), (241.0, 286.0)],
        "Example 9 thick dwells"
    );
    assert!(thin.eye_tension_n.is_none(), "Example 9 has no tension_n");
    // Every node between the ends has a wrap column, the eyelet T too.
    col(&t, "thin.T_wrap_deg");
    assert!(thin.max_tension_n.is_empty(), "no tension_n, no tension maxima");
}

/// Example 10: offset points on a needle bar, the feed convention.
fn needle_bar_thread_numbers() {
    let (m, t) = example("needle_bar_thread");
    assert!(
        !m.is_planar() && t.column("N.z_mm").is_some(),
        "offset groups make the model spatial"
    );
    let (e, tt, n) = (col(&t, "E.y_mm"), col(&t, "T.y_mm"), col(&t, "N.y_mm"));
    for k in 0..e.len() {
        close(tt[k] - e[k], 20.0, 1e-12, "Example 10 T = E + l_t");
        close(n[k] - e[k], -90.0, 1e-12, "Example 10 N = E − l_n");
    }
    close(col(&t, "T.z_mm")[0], 10.0, 0.0, "Example 10 T.z");
    close(110.0f64.hypot(10.0), 110.454, 5e-4, "Example 10 |T N|");
    close(1909.0f64.sqrt(), 43.692, 5e-4, "Example 10 |G T| at TDC");
    close(3829.0f64.sqrt(), 61.879, 5e-4, "Example 10 |G T| at BDC");
    close(e[90], -28.0, 1e-9, "Example 10 E at TDC");
    close(e[270], -52.0, 1e-9, "Example 10 E at BDC");
    let p = col(&t, "needle.P_mm");
    let x = col(&t, "needle.xi_mm");
    for k in 0..p.len() {
        close(p[k], x[k] - x[90] + 6.0, 1e-12, "Example 10 feed convention");
    }
    close(
        x[90],
        1909.0f64.sqrt() + 110.0f64.hypot(10.0),
        1e-9,
        "Example 10 ξ(90°)",
    );
    let s = path(&t, "needle");
    close(s.min_p_mm, 6.0, 1e-12, "Example 10 min P");
    close(s.max_p_mm, 24.187, 5e-4, "Example 10 max P");
    close(s.phi_at_max_deg, 270.0, 0.0, "Example 10 φ at max P");
    assert_eq!(spans(&s.flat), vec![(61.0, 119.0), (258.0, 282.0)], "Example 10 dwells");
    assert!(t.take_up.as_deref().unwrap().contains("dP = 6 mm, phi0 = 90 deg"));
    let c = compare_2d3d(&m, &m.defaults(), "world", 1.0).unwrap();
    let cp = &c.paths[0];
    close(
        cp.p2d_mm[270],
        3604.0f64.sqrt() - 1684.0f64.sqrt() + 6.0,
        1e-9,
        "Example 10 P2D at 270°",
    );
    close(cp.p2d_mm[270], 24.997, 5e-4, "Example 10 P2D at 270° as quoted");
    close(cp.max_abs_dp_mm, 0.8099, 5e-5, "Example 10 max |ΔP|");
    close(cp.phi_at_max_deg, 270.0, 0.0, "Example 10 φ at max |ΔP|");
    close(cp.max_rel_percent, 3.35, 5e-3, "Example 10 max |ΔP| in %");
}

/// Section 13.10: the MF-7923D preset's paths, split at B.
fn mf7923d_thread_numbers() {
    // Section 13.10: the MF-7923D preset. Its paths end at the eyes of its
    // [[stitch.needles]], so they are split at B (P_B = P_eye + S − S(φ0))
    // and T1 is up at the needle's TDC (t1_phase = 180): the maxima, their
    // φ, the dwells, G4's contact and the tensions are those of P_B at that
    // reading. (They were 61.2/66.3 mm at BDC when P was taken at the
    // moving eye with T1 down at TDC, t1_phase = 0: a reading that passes
    // more thread through B than the needle can take.)
    let m = Model::preset("mf7923d").unwrap();
    let t = cycle(&m).unwrap();
    let (a, b) = (path(&t, "n1_A"), path(&t, "n1_B"));
    for s in [a, b] {
        assert_eq!(
            s.split,
            stitchkin::thread::SplitPoint::B,
            "mf7923d {} split at B",
            s.path
        );
        close(s.max_p_eye_mm.unwrap(), 0.0, 0.0, "mf7923d max P_eye");
        close(s.min_p_mm, 0.0, 0.0, "mf7923d min P_B");
        assert_eq!(spans(&s.engaged[0].1), vec![(256.0, 464.0)], "mf7923d G4_1 engaged");
    }
    close(a.max_p_mm, 17.475, 5e-4, "mf7923d n1_A max P_B");
    close(b.max_p_mm, 22.479, 5e-4, "mf7923d n1_B max P_B");
    close(b.max_p_mm - a.max_p_mm, 5.0, 0.05, "mf7923d B − A");
    close(a.phi_at_max_deg, 162.0, 0.0, "mf7923d n1_A φ at max P_B");
    close(b.phi_at_max_deg, 180.0, 0.0, "mf7923d n1_B φ at max P_B");
    assert_eq!(
        spans(&a.flat),
        vec![(151.0, 209.0), (325.0, 395.0)],
        "mf7923d n1_A dwells"
    );
    assert_eq!(
        spans(&b.flat),
        vec![(172.0, 188.0), (325.0, 395.0)],
        "mf7923d n1_B dwells"
    );
    // With thread physics the capstan estimate is not given.
    assert!(a.eye_tension_n.is_none() && b.eye_tension_n.is_none());
    // ΔP of the 2D model: S cancels, the percentage is of max P_B. With T1
    // up at TDC the w-steps G7→G8 and G3→T1 add at BDC (0.96 mm); the
    // other reading, t1_phase = 0, gives seed 000's size (0.11 mm).
    let c = compare_2d3d(&m, &m.defaults(), "uvw", 1.0).unwrap();
    for (name, dp, at, pct) in [("n1_A", 0.9580, 180.0, 5.48), ("n1_B", 0.3881, 205.0, 1.73)] {
        let cp = c.paths.iter().find(|p| p.path == name).unwrap();
        close(cp.max_abs_dp_mm, dp, 5e-5, "mf7923d max |ΔP|");
        close(cp.phi_at_max_deg, at, 0.0, "mf7923d φ at max |ΔP|");
        close(cp.max_rel_percent, pct, 5e-3, "mf7923d max |ΔP| in %");
    }
    let mut p0 = m.defaults();
    m.set(&mut p0, "t1_phase", 0.0).unwrap();
    let c0 = compare_2d3d(&m, &p0, "uvw", 1.0).unwrap();
    let cp = c0.paths.iter().find(|p| p.path == "n1_A").unwrap();
    close(cp.max_abs_dp_mm, 0.1084, 5e-5, "mf7923d t1_phase = 0 max |ΔP|");
    close(cp.max_rel_percent, 0.12, 5e-3, "mf7923d t1_phase = 0 max |ΔP| in %");
}

/// Section 13.11: the regulator's two accountings on the MF-7923D.
fn mf7923d_regulator_numbers() {
    let m = Model::preset("mf7923d").unwrap();
    let scores = |m: &Model| -> Vec<f64> {
        let t = cycle(m).unwrap();
        let st = t.stitch.expect("mf7923d has a [stitch]");
        assert!(st.checks.iter().all(|c| c.ok), "{:?}", st.checks);
        st.threads
            .iter()
            .map(|th| th.mismatch.as_ref().unwrap().score.unwrap())
            .collect()
    };
    let text = stitchkin::presets::find("mf7923d").unwrap().toml;
    let feed = "feed = { law = \"harmonic\", start_deg = 130, duration_deg = 100 }\n";
    let at_lock = Model::from_toml_str(
        &edit(text, feed, &format!("{feed}regulator = {{ at_lock = true }}\n")),
        "mf7923d-at-lock.toml",
    )
    .unwrap();
    for (got, want) in scores(&m).into_iter().zip([75.0, 57.6, 34.3]) {
        close(got, want, 0.05, "mf7923d score, regulator computed (the default)");
    }
    let assumed = super::support::assumed_window("mf7923d");
    for (got, want) in scores(&assumed).into_iter().zip([80.6, 82.2, 81.5]) {
        close(got, want, 0.05, "mf7923d score, regulator window assumed");
    }
    for (got, want) in scores(&at_lock).into_iter().zip([78.6, 78.7, 76.4]) {
        close(got, want, 0.05, "mf7923d score, regulator at the lock");
    }
}

/// The text of the worked example called `name` (a ```toml block).
fn example_text(name: &str) -> String {
    let doc = doc();
    models(&doc)
        .into_iter()
        .find(|b| b.text.contains(&format!("name = \"{name}\"")))
        .unwrap_or_else(|| panic!("docs/model-format.md has no example named `{name}`"))
        .text
}

/// `text` with `from` replaced once; `from` must occur in it.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "the example has no `{from}`");
    text.replacen(from, to, 1)
}

/// Example 11's disc cam: radius r and eccentricity e on the main shaft,
/// its marker D the disc's centre; guides G1, G2 = (∓a, h), mm.
const CAM: (f64, f64, f64, f64) = (10.0, 6.0, 18.0, 6.0);

/// The disc's polar profile ρ(θ) about the shaft.
fn disc_rho(theta: f64) -> f64 {
    let (r, e, ..) = CAM;
    e * theta.cos() + (r * r - e * e * theta.sin().powi(2)).sqrt()
}

/// The taut thread's turn over the disc at φ = 90°, rad.
fn taut_turn() -> f64 {
    let (r, _, a, _) = CAM;
    std::f64::consts::PI - 2.0 * (r / a).acos()
}

#[test]
fn the_cam_numbers_quoted_in_the_doc_are_what_the_example_gives() {
    // Example 11: a disc cam (r = 10, e = 6) on the main shaft, its marker
    // D the disc's centre; guides G1, G2 = (∓18, 6).
    let (m, t) = example("looper_cam");
    looper_cam_contours(&m, &t);
    looper_cam_taut_at_90(&t);
    looper_cam_seed_and_summary(&t);
    looper_cam_variants(&m);
}

/// Example 11, every φ: the taut contour free exactly while the disc is
/// below the guides, the offset one ξ = |G1 − A| + |A − G2|.
fn looper_cam_contours(m: &Model, t: &CycleTable) {
    let (r, e, a, h) = CAM;
    assert!(m.is_planar(), "cams leave a planar model planar");
    let rho = disc_rho;
    let phis = col(t, "phi_deg");
    let (xs, xt) = (col(t, "seed.xi_mm"), col(t, "taut.xi_mm"));
    let (on_s, on_t) = (col(t, "seed.feed_engaged"), col(t, "taut.feed_engaged"));
    let wrap_t = col(t, "taut.feed_wrap_deg");
    for k in 0..phis.len() {
        let phi = phis[k].to_radians();
        // Exact: free exactly when the disc's top e·sin φ + r is below h.
        let free = e * phi.sin() + r < h;
        assert_eq!(on_t[k] == 0.0, free, "Example 11 taut engaged at φ = {}", phis[k]);
        if free {
            close(xt[k], 2.0 * a, 1e-12, "Example 11 taut ξ while free");
            close(wrap_t[k], 0.0, 0.0, "Example 11 taut wrap while free");
        }
        // Offset: A at 120° from +x (the radius facing the guides, +y,
        // turned by γ = 30°), at profile angle 120° − φ.
        let beta = 120f64.to_radians();
        let (ax, ay) = (rho(beta - phi) * beta.cos(), rho(beta - phi) * beta.sin());
        close(
            xs[k],
            (ax + a).hypot(ay - h) + (ax - a).hypot(ay - h),
            1e-9,
            "Example 11 seed ξ = |G1 − A| + |A − G2|",
        );
        assert_eq!(on_s[k], 1.0, "the offset contact always bears");
    }
    let boundary = (-2.0f64 / 3.0).asin().to_degrees();
    close(180.0 - boundary, 221.81, 5e-3, "Example 11 free from");
    close(360.0 + boundary, 318.19, 5e-3, "Example 11 free to");
}

/// Example 11 at φ = 90°: tangents and the arc over the disc, and the taut
/// path as a roller of radius r about D.
fn looper_cam_taut_at_90(t: &CycleTable) {
    let (r, _, a, _) = CAM;
    let (xt, on_t, wrap_t) = (
        col(t, "taut.xi_mm"),
        col(t, "taut.feed_engaged"),
        col(t, "taut.feed_wrap_deg"),
    );
    // The taut thread at φ = 90°: tangents and the arc over the disc.
    let turn = taut_turn();
    close(2.0 * (a * a - r * r).sqrt(), 29.933, 5e-4, "Example 11 tangents");
    close(r * turn, 11.781, 5e-4, "Example 11 arc");
    close(
        xt[90],
        2.0 * (a * a - r * r).sqrt() + r * turn,
        1e-9,
        "Example 11 taut ξ(90°)",
    );
    close(xt[90], 41.714, 5e-4, "Example 11 taut ξ(90°) as quoted");
    close(turn.to_degrees(), 67.50, 5e-3, "Example 11 wrap at 90°");
    close(turn, 1.178, 5e-4, "Example 11 wrap at 90° in rad");
    close(wrap_t[90], turn.to_degrees(), 1e-6, "Example 11 taut wrap at 90°");
    let longest = (0..xt.len()).max_by(|&i, &j| xt[i].total_cmp(&xt[j])).unwrap();
    assert_eq!(longest, 90, "Example 11: the taut contour is longest at 90°");
    let widest = (0..wrap_t.len())
        .max_by(|&i, &j| wrap_t[i].total_cmp(&wrap_t[j]))
        .unwrap();
    assert_eq!(widest, 90, "Example 11: the taut wrap is largest at 90°");

    // The taut path is a roller of radius r about D.
    let text = example_text("looper_cam");
    let roller = Model::from_toml_str(
        &edit(
            &text,
            r#"{ cam = "feed", wrap = "cw" }"#,
            r#"{ pin = "D", axis = "z", wrap = "cw", radius = "r" }"#,
        ),
        "roller.toml",
    )
    .unwrap();
    let tr = cycle(&roller).unwrap();
    let (xr, on_r) = (col(&tr, "taut.xi_mm"), col(&tr, "taut.D_engaged"));
    for k in 0..xt.len() {
        close(xt[k], xr[k], 1e-9, "Example 11 taut = a roller about D");
        assert_eq!(on_t[k], on_r[k], "Example 11 taut engaged = roller engaged");
    }
}

/// Example 11: seed 004's contact at φ = 120°, and the summary lines.
fn looper_cam_seed_and_summary(t: &CycleTable) {
    let (_, _, a, h) = CAM;
    let turn = taut_turn();
    let (xs, xt) = (col(t, "seed.xi_mm"), col(t, "taut.xi_mm"));
    let (on_t, wrap_s) = (col(t, "taut.feed_engaged"), col(t, "seed.feed_wrap_deg"));
    // Seed 004's contact at φ = 120°: A = 16·(cos 120°, sin 120°).
    let (ax, ay) = (16.0 * 120f64.to_radians().cos(), 16.0 * 120f64.to_radians().sin());
    close(ax, -8.0, 1e-12, "Example 11 A.x");
    close(ay, 13.856, 5e-4, "Example 11 A.y");
    close((ax + a).hypot(ay - h), 12.717, 5e-4, "Example 11 |G1 − A|");
    close((ax - a).hypot(ay - h), 27.161, 5e-4, "Example 11 |A − G2|");
    close(xs[120], 39.878, 5e-4, "Example 11 seed ξ(120°)");
    let longest = (0..xs.len()).max_by(|&i, &j| xs[i].total_cmp(&xs[j])).unwrap();
    assert_eq!(longest, 120, "Example 11: the seed contour is longest at 120°");
    close(xs[300], 36.360, 5e-4, "Example 11 seed ξ(300°)");
    assert_eq!(on_t[300], 0.0, "Example 11: the taut thread is free at 300°");

    // The summary lines.
    let (s, tt) = (path(t, "seed"), path(t, "taut"));
    assert_eq!(s.thread.as_deref(), Some("looper thread, seed 004"));
    assert_eq!(tt.thread.as_deref(), Some("looper thread, exact"));
    close(s.max_p_mm, 0.082, 5e-4, "Example 11 seed max P");
    close(s.phi_at_max_deg, 19.0, 0.0, "Example 11 seed φ at max P");
    close(s.min_p_mm, -3.796, 5e-4, "Example 11 seed min P");
    close(s.phi_at_min_deg, 120.0, 0.0, "Example 11 seed φ at min P");
    close(tt.max_p_mm, xt[0] - 2.0 * a, 1e-12, "Example 11 taut max P = ξ(0) − 2a");
    close(tt.max_p_mm, 1.057, 5e-4, "Example 11 taut max P");
    close(tt.phi_at_max_deg, 222.0, 0.0, "Example 11 taut φ at max P");
    close(tt.min_p_mm, -4.656, 5e-4, "Example 11 taut min P");
    close(tt.phi_at_min_deg, 90.0, 0.0, "Example 11 taut φ at min P");
    close(s.max_p_mm - s.min_p_mm, 3.88, 5e-3, "Example 11 seed take-up per turn");
    close(
        tt.max_p_mm - tt.min_p_mm,
        5.71,
        5e-3,
        "Example 11 taut take-up per turn",
    );
    assert_eq!(spans(&s.engaged[0].1), vec![(0.0, 360.0)], "Example 11 seed engaged");
    assert_eq!(spans(&tt.engaged[0].1), vec![(319.0, 581.0)], "Example 11 taut engaged");
    assert_eq!(s.engaged[0].0, "feed");
    assert_eq!(
        spans(&s.flat),
        vec![(98.0, 142.0), (183.0, 417.0)],
        "Example 11 seed dwells"
    );
    assert_eq!(
        spans(&tt.flat),
        vec![(57.0, 123.0), (185.0, 355.0)],
        "Example 11 taut dwells"
    );
    let [lo, hi] = s.eye_tension_n.unwrap();
    close(lo, 0.300, 5e-4, "Example 11 seed eye tension min");
    close(hi, 0.363, 5e-4, "Example 11 seed eye tension max");
    close(
        col(t, "seed.tension_eye_N")[0],
        0.3 * (0.2 * wrap_s[0].to_radians()).exp(),
        1e-12,
        "Example 11 seed capstan at the cam",
    );
    let [lo, hi] = tt.eye_tension_n.unwrap();
    close(lo, 0.3, 1e-12, "Example 11 taut eye tension min (free)");
    close(hi, 0.3 * (0.2 * turn).exp(), 1e-9, "Example 11 taut eye tension max");
    close(hi, 0.380, 5e-4, "Example 11 taut eye tension max as quoted");
}

/// Example 11 with --set gamma=0, and the two cam errors of section 16
/// made from it.
fn looper_cam_variants(m: &Model) {
    let (_, _, a, h) = CAM;
    let text = example_text("looper_cam");
    // --set gamma=0: A on the line of symmetry, ξ = 2·|G1 − A| (seed 004).
    let mut p = m.defaults();
    m.set(&mut p, "gamma", 0.0).unwrap();
    let t0 = run_cycle(m, &p, &Default::default()).unwrap();
    let x0 = col(&t0, "seed.xi_mm");
    for (k, phi) in col(&t0, "phi_deg").iter().enumerate() {
        let rho_a = disc_rho(90f64.to_radians() - phi.to_radians());
        close(
            x0[k],
            2.0 * a.hypot(rho_a - h),
            1e-9,
            "Example 11 γ = 0: seed 004's 2·|O2 − A|",
        );
    }

    // Section 16: the two cam errors, made from Example 11 as described.
    let bad = |text: String, file: &str| Model::from_toml_str(&text, file).unwrap_err().to_string();
    let e = bad(edit(&text, r#", gamma_deg = "gamma" }"#, " }"), "bad8.toml");
    assert!(
        e.starts_with("bad8.toml:39:16: thread.paths[0].nodes[1]: an offset cam contact needs `gamma_deg`")
            && e.contains("help: Polyakov (2022) uses γ = 0.4–0.8 rad, i.e. 23–46 degrees"),
        "{e}"
    );
    let e = bad(
        edit(
            &text,
            r#"disc = { radius_mm = "r", eccentricity_mm = "e" }"#,
            "polar = { angle_deg = [0, 45, 90, 135, 180, 225, 270, 315], radius_mm = [10, 4, 10, 4, 10, 4, 10, 4] }",
        ),
        "bad9.toml",
    );
    assert!(
        e.starts_with("bad9.toml:45:24: thread.paths[1].nodes[1].cam: cam `feed` is not convex, so a taut thread does not follow its profile")
            && e.contains("help: use contact = \"offset\" or smooth the profile"),
        "{e}"
    );
}
