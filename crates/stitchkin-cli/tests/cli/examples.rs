//! The seed-study scripts in examples/ run: each one with this test build of
//! the binary (`STITCHKIN`) and coarse grids (`STITCHKIN_QUICK=1`), writing
//! its tables to a scratch folder (`STITCHKIN_OUT`). The scripts run at
//! once; every command in them runs, only on fewer points.

use std::path::Path;
use std::process::Command;

use super::scratch;

/// Each script with the tables it must write and a column each must have.
const SCRIPTS: &[(&str, &[(&str, &str)])] = &[
    (
        "seed000_z_sweep.sh",
        &[
            // Needle-eye paths are split at B: their take-up figure is
            // max_P_B_mm.
            ("seed000_z_max_P.csv", "n3_B.max_P_B_mm"),
            ("seed000_r1_max_P.csv", "r1_mm"),
            ("seed000_dphi_max_P.csv", "dphi_deg"),
            // The other reading of the take-up phase, with its checks.
            ("seed000_z_max_P_t1phase0.csv", "checks.ok"),
            ("seed000_r1_max_P_t1phase0.csv", "n1_A.max_P_B_mm"),
            ("seed000_dphi_max_P_t1phase0.csv", "dphi_deg"),
            ("seed000_z_match.csv", "score.mean"),
            ("seed000_r1_match.csv", "n1.score"),
            ("seed000_dphi_match.csv", "checks.ok"),
        ],
    ),
    (
        "seed000_nomogram.sh",
        &[
            ("seed000_nomogram_z.txt", "z within 1 pt"),
            // The preset with the window assumed, and its nomogram.
            ("mf7923d_window60.toml", "regulator = { width_deg = 60 }"),
            ("seed000_nomogram_z_window60.txt", "z within 1 pt"),
            // The preset with the whole stitch at the lock, and its nomogram.
            ("mf7923d_at_lock.toml", "regulator = { at_lock = true }"),
            ("seed000_nomogram_z_at_lock.txt", "z within 1 pt"),
            ("seed000_nomogram_z_t1phase0.txt", "Every match score is 0"),
            ("seed000_nomogram_z_dphi.csv", "dphi_lo_deg"),
        ],
    ),
    (
        "lockstitch_cam.sh",
        &[
            ("lockstitch_match.txt", "(lockstitch)"),
            ("lockstitch_tune.txt", "Recommended setting"),
            ("lockstitch_cam.csv", "theta_deg,radius_mm"),
            ("lockstitch_cam.toml", "[[cams]]"),
        ],
    ),
    (
        "seed002_stroke_table.sh",
        &[("seed002_stroke.csv", "needle_y.range_mm")],
    ),
    (
        "seed004_altin.sh",
        &[
            ("seed004_altin504_match.txt", "upper (contour 10)"),
            ("seed004_consumption_504.csv", "11.3826"),
            // The needle thread's P' at B, the looper threads' at their eyes.
            ("seed004_altin504_m_t.csv", "needle.max_Pprime_B_mm"),
        ],
    ),
    (
        "mf7923d_bench_fit.sh",
        &[
            ("mf7923d_bench_processed.csv", "phi_deg,n,mean_mm,s_mm"),
            ("mf7923d_bench_fit.txt", "95 % interval"),
            ("mf7923d_bench_fit.txt", "Recommended setting"),
            ("mf7923d_bench_fit.json", "\"correlation\""),
            ("mf7923d_bench_residuals.svg", "residuals of the fit"),
        ],
    ),
    (
        "seed004_experiment.sh",
        &[
            ("seed004_bench_processed.csv", "phi_deg,n,mean_mm,s_mm"),
            ("seed004_bench_processed.txt", "Polyakov (2022) §3.4"),
            ("seed004_bench_match.txt", "the mean of up to 10 readings per φ"),
            (
                "seed004_bench_takeup.svg",
                "0.015 ± 0.063 mm (95 %, Polyakov (2022) §3.4)",
            ),
        ],
    ),
];

#[test]
fn every_example_script_runs_and_writes_its_tables() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = scratch("examples");
    std::thread::scope(|s| {
        let runs: Vec<_> = SCRIPTS
            .iter()
            .map(|(script, _)| {
                let (root, out) = (&root, &out);
                s.spawn(move || {
                    let r = Command::new("bash")
                        .arg(Path::new("examples").join(script))
                        .current_dir(root)
                        .env("STITCHKIN", env!("CARGO_BIN_EXE_stitchkin"))
                        .env("STITCHKIN_QUICK", "1")
                        .env("STITCHKIN_OUT", out)
                        .env("NO_COLOR", "1")
                        .output()
                        .expect("bash runs");
                    (script, r)
                })
            })
            .collect();
        for run in runs {
            let (script, r) = run.join().unwrap();
            let stderr = String::from_utf8_lossy(&r.stderr);
            assert!(
                r.status.success() && !stderr.contains("panicked"),
                "examples/{script} failed:\n{stderr}"
            );
        }
    });
    for (script, tables) in SCRIPTS {
        for (table, has) in *tables {
            let text = std::fs::read_to_string(out.join(table))
                .unwrap_or_else(|e| panic!("examples/{script} did not write {table}: {e}"));
            assert!(text.contains(has), "examples/{script}: {table} lacks `{has}`:\n{text}");
            assert!(!text.contains("NaN"), "examples/{script}: {table}:\n{text}");
            if table.ends_with(".csv") {
                let mut lines = text.lines();
                let width = lines.next().unwrap().split(',').count();
                let rows: Vec<&str> = lines.collect();
                assert!(!rows.is_empty(), "{table} has no rows");
                assert!(
                    rows.iter().all(|l| l.split(',').count() == width),
                    "{table}: ragged rows:\n{text}"
                );
            }
        }
    }
}

/// examples/README.md describes every script, each script names the tables
/// it writes, and the scripts default to `cargo run --release --`.
#[test]
fn example_scripts_document_themselves() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
    for (script, tables) in SCRIPTS {
        let text = std::fs::read_to_string(dir.join(script)).unwrap();
        assert!(text.starts_with("#!/usr/bin/env bash\n"), "{script}");
        assert!(
            text.contains("set -euo pipefail") && text.contains("cargo run --release --quiet --"),
            "{script}"
        );
        assert!(
            readme.contains(&format!("## `{script}`")),
            "examples/README.md does not describe {script}"
        );
        for (table, _) in *tables {
            let stem = table.split('.').next().unwrap();
            assert!(text.contains(stem), "{script} does not name {table}");
        }
    }
}
