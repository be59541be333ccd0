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
