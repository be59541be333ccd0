//! Thread consumption per stitch against the independent reference
//! (`tests/data/stitch/consumption_per_stitch.csv`, docs/stitch-formation.md §6).

use stitchkin::stitch::consumption::{StitchGeometry, consumption};

#[test]
fn consumption_matches_the_reference_table() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/stitch/consumption_per_stitch.csv")).unwrap();
    let altin = StitchGeometry { thickness_mm: 2.5, stitch_mm: 2.8, width_mm: 4.0, incline_deg: 20.0, edge_fraction: 0.5 };
    let mf = StitchGeometry { thickness_mm: 3.0, stitch_mm: 3.0, width_mm: 0.0, incline_deg: 0.0, edge_fraction: 0.5 };
    let mut checked = 0;
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.splitn(6, ',').collect();
        let (case, ty, thread, length) = (f[0], f[1], f[2], f[5]);
        let Ok(ty) = ty.parse::<u16>() else { continue };
        let g = if case == "altin504" { altin } else { mf };
        let c = consumption(ty, &g).unwrap();
        if thread == "TOTAL per stitch" {
            match length.parse::<f64>() {
                Ok(want) => assert!((c.total_mm.unwrap() - want).abs() < 1e-6, "{ty} total"),
                Err(_) => assert!(c.total_mm.is_none(), "{ty}: a total where the reference has none"),
            }
        } else {
            let ours = c.threads.iter().find(|t| t.thread == thread).unwrap_or_else(|| panic!("{ty}: no thread {thread}"));
            match length.parse::<f64>() {
                Ok(want) => assert!((ours.length_mm.unwrap() - want).abs() < 1e-6, "{ty} {thread}"),
                Err(_) => assert!(ours.length_mm.is_none(), "{ty} {thread}: a length where the reference has none"),
            }
        }
        checked += 1;
    }
    assert!(checked > 50, "only {checked} rows checked");
}

// ---------------------------------------------------------------------------
// The stitch process of a model: `[stitch]` loading, P' columns, the match.

use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::model::Model;

fn mf_run(set: &[(&str, f64)]) -> CycleTable {
    let model = Model::preset("mf7923d").unwrap();
    let mut params = model.defaults();
    for (k, v) in set {
        model.set(&mut params, k, *v).unwrap();
    }
    run_cycle(&model, &params, &CycleOptions { step_deg: 1.0, rpm: None, analogs: false, points: Some(Vec::new()) }).unwrap()
}

#[test]
fn mf7923d_locks_one_stitch_of_thread_per_needle() {
    let table = mf_run(&[]);
    let st = table.stitch.as_ref().expect("mf7923d has a [stitch]");
    assert_eq!(st.stitch_type, 407);
    assert_eq!(st.threads.len(), 3);
    for (j, t) in st.threads.iter().enumerate() {
        assert_eq!(t.thread, format!("n{}", j + 1));
        assert_eq!(t.path.as_deref(), Some(format!("n{}_A", j + 1).as_str()));
        // Contour 1: t + 2·l_m = 3 + 2·3 = 9 mm (β = 0), and the P' model
        // locks exactly that at the drop.
        assert!((t.per_stitch_mm - 9.0).abs() < 1e-12, "{t:?}");
        assert!((t.locked_mm - t.per_stitch_mm).abs() < 1e-9, "{}: locked {} vs {}", t.thread, t.locked_mm, t.per_stitch_mm);
        assert!(t.events.iter().any(|e| e.kind == stitchkin::stitch::spec::EventKind::Lock));
        let m = t.mismatch.as_ref().expect("compared with its path");
        assert!(m.rms_d_mm.is_finite() && m.rms_d_mm > 0.0);
        let pp = table.column(&format!("n{}.Pprime_mm", j + 1)).unwrap();
        let p = table.column(&format!("n{}_A.P_mm", j + 1)).unwrap();
        let d = table.column(&format!("n{}.D_mm", j + 1)).unwrap();
        // φ0 = 0 is the first row: P' = 0 there, and D = P − P'.
        assert!(pp[0].abs() < 1e-12, "P'(φ0) = {}", pp[0]);
        for k in 0..pp.len() {
            assert!(pp[k].is_finite());
            assert!((d[k] - (p[k] - pp[k])).abs() < 1e-12);
        }
        assert!(table.column(&format!("n{}.Pprime_B_mm", j + 1)).is_some());
        assert!(table.column(&format!("n{}.gamma_deg", j + 1)).is_some());
    }
}

#[test]
fn max_required_take_up_grows_with_thickness_and_stitch_length() {
    // Seed 000 (citing [5]): max P' is proportional to the stitch length and
    // the material thickness.
    let max_b = |set: &[(&str, f64)]| -> Vec<f64> {
        let table = mf_run(set);
        (1..=3).map(|j| table.column(&format!("n{j}.Pprime_B_mm")).unwrap().iter().cloned().fold(f64::MIN, f64::max)).collect()
    };
    let (thin, thick) = (max_b(&[("m", 2.0)]), max_b(&[("m", 4.0)]));
    let (short, long) = (max_b(&[("stitch", 2.0)]), max_b(&[("stitch", 4.0)]));
    for j in 0..3 {
        assert!(thick[j] > thin[j] + 1.0, "needle {}: m 2 → 4 gives {} → {}", j + 1, thin[j], thick[j]);
        assert!(long[j] > short[j] + 0.5, "needle {}: t 2 → 4 gives {} → {}", j + 1, short[j], long[j]);
    }
}

const STITCH_401: &str = r#"
[model]
name = "chain-401"
[parameters]
m = { value = 2, unit = "mm", range = [0.5, 5] }
[points]
O = [0, 0]
[[drivers]]
type = "crank"
center = "O"
out = "A"
radius = 10
[[groups]]
type = "rrp"
from = "A"
length = 40
through = "O"
direction_deg = 90
out = "N"
branch = "forward"
[thread]
phi0_deg = 0
[[thread.paths]]
name = "needle"
nodes = ["O", "A", "N"]
[stitch]
type = "401"
m_mm = "m"
t_mm = 2.5
cyclogram_zero_deg = 180
feed = { law = "harmonic", start_deg = 134, duration_deg = 100 }
[[stitch.needles]]
name = "thr"
law = { x_mm = 0, eye_above_plate_mm = 11, stroke_mm = 20 }
path = "needle"
[stitch.looper]
law = { stroke_mm = 17, far_deg = 180, catch_deg = 30, depth_mm = 5.5 }
k_mm = 4
a_mm = 1
b_mm = 2.5
gamma_max_deg = 23
"#;

fn stitch_err(from: &str, to: &str) -> String {
    let text = STITCH_401.replacen(from, to, 1);
    assert_ne!(text, STITCH_401, "`{from}` is not in the model");
    match Model::from_toml_str(&text, "bad.toml") {
        Ok(_) => panic!("expected an error after replacing `{from}` by `{to}`"),
        Err(e) => {
            assert!(e.line_col().is_some(), "no place: {e}");
            e.to_string()
        }
    }
}

#[test]
fn a_401_model_with_stand_in_laws_runs() {
    let model = Model::from_toml_str(STITCH_401, "chain.toml").unwrap();
    let table = run_cycle(&model, &model.defaults(), &CycleOptions::default()).unwrap();
    let st = table.stitch.clone().unwrap();
    let t = &st.threads[0];
    // l_m = m = 2, t = 2.5: 6.5 mm per stitch, locked exactly.
    assert!((t.per_stitch_mm - 6.5).abs() < 1e-12 && (t.locked_mm - 6.5).abs() < 1e-9, "{t:?}");
    assert!(t.mismatch.as_ref().unwrap().score.is_some());
    assert!(table.column("thr.D_mm").is_some());
}

#[test]
fn bad_stitch_tables_are_rejected_with_the_place_and_the_fix() {
    let e = stitch_err(r#"type = "401""#, r#"type = "301""#);
    assert!(e.contains("unknown or unsupported stitch type `301`") && e.contains("\"407\""), "{e}");
    let e = stitch_err(r#"type = "401""#, r#"type = "503""#);
    assert!(e.contains("503") && e.contains("not computed yet") && e.contains("consumption"), "{e}");
    let e = stitch_err(r#"type = "401""#, r#"type = "406""#);
    assert!(e.contains("has 2 needle(s), 1 given"), "{e}");
    let e = stitch_err(r#"name = "thr""#, "name = \"thr\"\neye = \"N\"");
    assert!(e.contains("exactly one of `eye`") , "{e}");
    let e = stitch_err(r#"path = "needle""#, r#"path = "neddle""#);
    assert!(e.contains("unknown thread path `neddle`") && e.contains("did you mean `needle`"), "{e}");
    let e = stitch_err("[stitch]\ntype", "[stitch]\nedge_split = 2\ntype");
    assert!(e.contains("edge_split = 2 is outside 0…1"), "{e}");
    let e = stitch_err(r#"law = "harmonic""#, r#"law = "cam""#);
    assert!(e.contains("unknown feed law `cam`"), "{e}");
    let e = stitch_err("m_mm = \"m\"", "m_mm = \"m + 1 deg\"");
    assert!(e.contains("m_mm"), "{e}");
    let e = stitch_err(r#"type = "401""#, r#"type = "504""#);
    assert!(e.contains("overedge width"), "{e}");
    let e = stitch_err("[stitch]\ntype = \"401\"", "[stitch]\ntype = \"504\"\noveredge_width_mm = 4");
    assert!(e.contains("upper looper"), "{e}");
    // A thickness the parameter range does not allow is refused on --set.
    let model = Model::from_toml_str(STITCH_401, "chain.toml").unwrap();
    let mut p = model.defaults();
    assert!(model.set(&mut p, "m", 9.0).is_err());
}
