//! The `stitchkin` binary, run as a user would.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stitchkin"))
}

fn run(args: &[&str]) -> Output {
    run_in(args, Path::new("."))
}

fn run_in(args: &[&str], dir: &Path) -> Output {
    let out = bin()
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "panic for {args:?}:\n{stderr}");
    out
}

fn ok(args: &[&str]) -> (String, String) {
    let out = run(args);
    let (o, e) = (
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    );
    assert!(out.status.success(), "{args:?} failed:\n{e}");
    (o, e)
}

fn fails(args: &[&str]) -> String {
    let out = run(args);
    assert!(!out.status.success(), "{args:?} should fail");
    assert!(out.stdout.is_empty(), "{args:?} wrote to stdout despite failing");
    String::from_utf8(out.stderr).unwrap()
}

/// A fresh scratch folder.
fn scratch(name: &str) -> PathBuf {
    // Under the build folder (cargo clean removes it), not the system's /tmp.
    // One folder per test, emptied when the test starts again: runs do not
    // pile up folders.
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[path = "cli/examples.rs"]
mod examples;
#[path = "cli/fit_measured.rs"]
mod fit_measured;
#[path = "cli/limits.rs"]
mod limits;
#[path = "cli/measurement.rs"]
mod measurement;
#[path = "cli/nomogram.rs"]
mod nomogram;
#[path = "cli/output.rs"]
mod output;
#[path = "cli/own_machine.rs"]
mod own_machine;
#[path = "cli/sensitivity.rs"]
mod sensitivity;
#[path = "cli/strokes.rs"]
mod strokes;
#[path = "cli/tune.rs"]
mod tune;

#[path = "cli/cam.rs"]
mod cam;
#[path = "cli/draw.rs"]
mod draw;
#[path = "cli/plot.rs"]
mod plot;
#[path = "cli/report.rs"]
mod report;
#[path = "cli/serve.rs"]
mod serve;
#[path = "cli/variants.rs"]
mod variants;

const PRESETS: &[&str] = &[
    "needle876",
    "overlock500",
    "altin-needle",
    "altin504",
    "mf7923d",
    "takeup-lever",
    "lockstitch",
];

#[test]
fn run_without_arguments_uses_the_default_preset() {
    // The default preset is the Juki MF-7923D: P(φ) for three needles.
    let (csv, summary) = ok(&["run"]);
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for col in [
        "phi_deg",
        "T1_1.y_mm",
        "T1_1.dy_dphi_mm_per_rad",
        "E.d2y_dphi2_mm_per_rad2",
        "n1_A.P_B_mm",
        "n1_A.P_eye_mm",
        "n2_B.dP_B_dphi_mm_per_rad",
        "n3_A.G4_3_engaged",
        "mu_rod_AB_arm_O2B_deg",
        "n1.Pprime_B_mm",
        "n1.Pprime_eye_mm",
    ] {
        assert!(header.contains(&col), "no column {col} in {header:?}");
    }
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 360);
    assert!(rows.iter().all(|r| r.split(',').count() == header.len()));
    assert!(!csv.contains("NaN") && !csv.contains("inf"));
    for p in ["n1_A", "n2_A", "n3_A", "n1_B", "n2_B", "n3_B"] {
        assert!(summary.contains(&format!("# {p}")), "{summary}");
    }
    assert!(
        summary.contains("take-up: P = xi(phi0) - xi(phi)") && summary.contains("split at B"),
        "{summary}"
    );
    assert!(
        summary.contains("# check ok   thread_bound: n1 27.99 mm, n2 34.66 mm, n3 41.90 mm  (allowed ≥ 0.00 mm)")
            && !summary.contains("FAIL"),
        "{summary}"
    );
}

/// On a terminal `run` shows its summary, not hundreds of columns; the
/// table is one flag away (`--format csv`), and is what a pipe gets.
#[test]
fn run_on_a_terminal_shows_the_summary() {
    let exe = env!("CARGO_BIN_EXE_stitchkin");
    // `script` runs the command on a pseudo-terminal (util-linux, part of
    // every Debian system).
    let tty = |args: &str| {
        let out = Command::new("script")
            .args(["-qec", &format!("{exe} {args}"), "/dev/null"])
            .env("NO_COLOR", "1")
            .output()
            .expect("script runs");
        assert!(out.status.success(), "{args}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).replace('\r', "")
    };
    let screen = tty("run");
    assert!(screen.lines().count() < 40 && !screen.contains("phi_deg,"), "{screen}");
    assert!(
        screen.contains("# n1_A") && screen.contains("max P_B") && screen.contains("# check ok"),
        "{screen}"
    );
    assert!(
        screen.contains("the full table, 360 rows")
            && screen.contains("pipe it, `-o FILE.csv` (or .json), or `--format csv`"),
        "{screen}"
    );
    assert!(tty("run --format csv --step 30").contains("phi_deg,"));
}

#[test]
fn columns_can_be_selected_by_pattern() {
    let (csv, _) = ok(&["run", "--step", "30", "--columns", "*.P_B_mm,mu_*"]);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(header[0], "phi_deg");
    assert_eq!(header.iter().filter(|h| h.ends_with(".P_B_mm")).count(), 6);
    assert!(
        header
            .iter()
            .all(|h| *h == "phi_deg" || h.ends_with(".P_B_mm") || h.starts_with("mu_")),
        "{header:?}"
    );
    let e = fails(&["run", "--columns", "*.Q_mm"]);
    assert!(
        e.contains("no column matches `*.Q_mm`") && e.contains("columns are named like phi_deg"),
        "{e}"
    );
    // A near miss gets the closest name, as a misspelt parameter does.
    let e = fails(&["run", "--columns", "n1_A.P_B_m"]);
    assert!(e.contains("did you mean `n1_A.P_B_mm`?"), "{e}");
}

#[test]
fn consumption_of_a_lockstitch_seam_with_waste() {
    let args = ["consumption", "--type", "301", "--thickness", "2", "--stitch", "2.5"];
    let (out, _) = ok(&[&args[..], &["--seam", "2500", "--waste", "15", "--format", "table"]].concat());
    assert!(
        out.contains("bobbin") && out.contains("1000.0 stitches") && out.contains("10.3500"),
        "{out}"
    );
    assert!(out.contains("taut consumption"), "{out}");
    let (csv, _) = ok(&[&args[..], &["--interlace", "0.25", "--format", "csv"]].concat());
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(
        rows[0],
        "thread,contour,formula,length_mm,ratio_mm_per_mm,seam_m,seam_with_waste_m"
    );
    assert_eq!(rows[1], "needle 1,,\"t + 2·f·l_m\",3.5,1.4,1.4,1.4");
    assert_eq!(rows[2], "bobbin,,\"t + 2·(1 − f)·l_m\",5.5,2.2,2.2,2.2");
    assert_eq!(rows[3], "total,,\"sum of the threads\",9,3.6,3.6,3.6");
    for (flag, value, words) in [
        ("--interlace", "1.5", "interlacing depth"),
        ("--seam", "0", "seam length"),
        ("--waste", "-3", "waste allowance"),
    ] {
        let e = fails(&[&args[..], &[flag, value]].concat());
        assert!(e.contains(words) && e.contains(&format!("(in {flag})")), "{e}");
    }
}

#[test]
fn consumption_prints_the_thread_per_stitch() {
    let (out, _) = ok(&[
        "consumption",
        "--type",
        "504",
        "--thickness",
        "2.5",
        "--stitch",
        "2.8",
        "--width",
        "4",
        "--incline",
        "20",
    ]);
    assert!(out.contains("upper looper") && out.contains("30.8861"), "{out}");
    let (csv, _) = ok(&[
        "consumption",
        "--type",
        "407",
        "--thickness",
        "3",
        "--stitch",
        "3",
        "--format",
        "csv",
    ]);
    assert!(
        csv.starts_with("thread,contour,formula,length_mm") && csv.contains("needle 3,,\"t + 2·l_m\",9"),
        "{csv}"
    );
    let (json, _) = ok(&[
        "consumption",
        "--type",
        "503",
        "--thickness",
        "2.5",
        "--stitch",
        "2.8",
        "--width",
        "4",
        "--incline",
        "20",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!((v["total_mm"].as_f64().unwrap() - 30.0035111).abs() < 1e-6);
    let e = fails(&["consumption", "--type", "504", "--thickness", "2.5", "--stitch", "2.8"]);
    assert!(e.contains("needs the overedge width"), "{e}");
    let e = fails(&[
        "consumption",
        "--type",
        "999",
        "--thickness",
        "2.5",
        "--stitch",
        "2.8",
        "--width",
        "4",
    ]);
    assert!(e.contains("not covered") && e.contains("501"), "{e}");
    let e = fails(&[
        "consumption",
        "--type",
        "504",
        "--thickness",
        "2.5",
        "--stitch",
        "-1",
        "--width",
        "4",
    ]);
    assert!(e.contains("stitch length"), "{e}");
}

#[test]
fn match_prints_the_mismatch_per_thread() {
    let (out, _) = ok(&["match"]);
    assert!(out.lines().count() < 50, "one screen:\n{out}");
    assert!(
        out.starts_with("Juki MF-7923D") && out.contains("stitch 407, material m = 3 mm, stitch length t = 3 mm"),
        "{out}"
    );
    assert!(
        out.contains("needle threads measured at B, the eye's top position"),
        "{out}"
    );
    // The regulator's windows, computed from each thread's tension.
    assert!(
        out.contains("regulator: n1 φ = 19°…48°, 94°…113°, 215°…237°; n2 φ = ")
            && out.contains("where each thread's tension draws thread through the regulator (computed)"),
        "{out}"
    );
    // One row per needle thread: its score, and every check passes (the
    // stitch's three, the take-up's and the thread's four).
    for (j, want) in [(1, 75.0), (2, 57.6), (3, 34.3)] {
        let row = out
            .lines()
            .find(|l| l.starts_with(&format!("n{j} ")))
            .unwrap_or_else(|| panic!("no row n{j}:\n{out}"));
        let score: f64 = row.split_whitespace().nth(2).unwrap().parse().unwrap();
        assert!((score - want).abs() < 0.05 && row.ends_with("8 of 8 pass"), "{row}");
    }
    // The thread's tension: per needle its peak, where, the margin, the
    // thread drawn and the computed window.
    assert!(
        out.contains("thread tension (tex 30 spun polyester: EA 85 N, breaking 10.5 N; regulator 0.42 N):"),
        "{out}"
    );
    assert!(
        out.contains("n1          2.73 N   106.0°  N_1–stitch         3.84×     8.90 mm   1.10 %    3.20 mm  19°…48°, 94°…113°, 215°…237°"),
        "{out}"
    );
    // P against P′ as sparklines, the regulator window marked below them.
    assert_eq!(
        out.lines()
            .filter(|l| l.contains("P′    ") && l.chars().any(|c| ('▁'..='█').contains(&c)))
            .count(),
        3,
        "{out}"
    );
    assert!(out.contains("regulator windows of n1, computed"), "{out}");
    // Every check, one line for the three threads where all pass.
    for check in [
        "thread_bound",
        "takeup_gives",
        "catch_clearance",
        "stab_before_drop",
        "tension_margin",
        "slack_loop",
        "stitch_set",
        "spring_before_slip",
    ] {
        assert_eq!(out.matches(&format!(" {check} ")).count(), 1, "{check}:\n{out}");
    }
    assert!(!out.contains("FAIL") && !out.contains("note: P peaks"), "{out}");
    // The thread bound as the least to spare where the take-up gives thread
    // (at the drop, where the loop leaves the looper); each value the
    // figure of its message, beside its allowed range, in one column.
    assert!(
        out.contains("  ok    all    thread_bound        n1 27.99 mm, n2 34.66 mm, n3 41.90 mm  (allowed ≥ 0.00 mm)"),
        "{out}"
    );
    assert!(
        out.contains("  ok    all    stab_before_drop    n1 3.53 mm, n2 3.48 mm, n3 2.55 mm  (allowed ≥ 0.00 mm)"),
        "{out}"
    );
    assert!(
        out.contains("tension_margin      n1 3.84×, n2 3.89×, n3 3.14×  (allowed ≥ 3.00×)"),
        "{out}"
    );
    // The model's caveats and what the stitch model carries over.
    assert!(
        out.contains("note: Reconstruction:") && out.contains("401 two-thread chain stitch"),
        "{out}"
    );
    // Every metric with --details.
    let (details, _) = ok(&["match", "--details"]);
    for line in [
        "per stitch",
        "max P′",
        "max P′ at the eye",
        "RMS(D)",
        "max |D|",
        "slack  (D > ε)",
        "strain (D < −ε)",
        "match score",
        "jumps of P′",
        "moments (φ)",
    ] {
        assert!(details.contains(line), "`{line}` missing:\n{details}");
    }
    assert!(details.contains("9.000 mm (cut from P′ at its lock"), "{details}");
    // T1 down at TDC: the thread bound fails for every needle, and so does
    // the slack loop, and the match says what that means.
    let out = run(&["match", "--set", "t1_phase=0"]);
    assert_eq!(out.status.code(), Some(1), "a failing check fails the command");
    let other = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(other.matches("FAIL  n").count(), 6, "{other}");
    assert_eq!(other.matches(" slack_loop ").count(), 3, "{other}");
    assert!(
        other.contains("thread_bound          -30.82 mm  (allowed ≥ 0.00 mm; φ = 152.0°; P_B peaks at"),
        "{other}"
    );
    assert!(
        other.contains("hangs slack") && other.contains("note: 6 physical check(s) fail"),
        "{other}"
    );
}

/// Where the take-up gives far less than the stitch takes at its peak, the
/// match screen says so beside the score, which rates only how P follows P′.
#[test]
fn match_says_when_the_take_up_falls_short_of_the_stitch() {
    let (out, _) = ok(&["match"]);
    assert!(!out.contains("short of the"), "{out}");
    // At r1 = 6 mm, the end of its range, the take-up gives no needle
    // thread: a check fails for each (its message in place of the note),
    // after the screen the command fails.
    let out = run(&["match", "--set", "r1=6"]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("physical check(s) fail (n1 takeup_gives, n2 takeup_gives, n3 takeup_gives"),
        "{stderr}"
    );
    for j in 1..=3 {
        assert!(stdout.contains(&format!("  FAIL  n{j}     takeup_gives ")), "{stdout}");
    }
    assert!(
        stdout
            .contains("the take-up gives at most 0.00 mm, 0 % of it (at least 25 % wanted; P is -4.94 mm at the peak)")
            && stdout.contains("n2 n/a, n3 n/a"),
        "{stdout}"
    );
    assert!(!stdout.contains("short of the"), "{stdout}");
    // A coarse step: said, with by how much the scores move.
    let (out, _) = ok(&["match", "--step", "30"]);
    assert!(
        out.contains(
            "warning: the φ step of 30° is too coarse for the metrics: against a 1° step the scores move by up to 39.5 points"
        ),
        "{out}"
    );
    let (out, _) = ok(&["match"]);
    assert!(!out.contains("too coarse"), "{out}");
    let (out, _) = ok(&["match", "--preset", "lockstitch"]);
    assert!(
        out.contains("note: needle: the take-up gives at most 41.29 mm, 25.22 mm (38 %) short of the 66.51 mm")
            && out.contains("the check spring and the regulator make up the rest, at a peak tension of 2.72 N"),
        "{out}"
    );
}

/// `match --format json`: per thread the mismatch, the thread's tension and
/// its balance, and every check with its figures.
#[test]
fn match_gives_json_with_the_tension_and_the_checks() {
    let (json, _) = ok(&["match", "--preset", "mf7923d", "--set", "m=4", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["m_mm"], 4.0);
    assert_eq!(v["model"], "mf7923d");
    assert_eq!(v["threads"].as_array().unwrap().len(), 3);
    assert_eq!(v["threads"][0]["split"], "B");
    assert!(v["threads"][0]["mismatch"]["score"].is_number());
    // per stitch with m = 4: t + 2m = 11 mm.
    assert!((v["threads"][0]["per_stitch_mm"].as_f64().unwrap() - 11.0).abs() < 1e-9);
    // Per thread the thread's tension: its peak and where, the margin, the
    // thread drawn per cycle, the strain the finished stitch keeps, the
    // computed regulator windows and the largest slack loop.
    for th in v["threads"].as_array().unwrap() {
        let tn = &th["tension"];
        for key in [
            "peak_N",
            "peak_at_deg",
            "margin",
            "drawn_per_cycle_mm",
            "lock_strain",
            "max_slack_mm",
            "set_slack_mm",
        ] {
            assert!(tn[key].is_number(), "{key}: {tn}");
        }
        let windows = tn["regulator_windows_deg"].as_array().unwrap();
        assert!(
            !windows.is_empty() && windows.iter().all(|w| w.as_array().unwrap().len() == 2),
            "{tn}"
        );
        // The balance: drawn × (1 + strain) is one stitch's thread.
        let drawn = tn["drawn_per_cycle_mm"].as_f64().unwrap() * (1.0 + tn["lock_strain"].as_f64().unwrap());
        assert!((drawn / 11.0 - 1.0).abs() < 1e-3, "{drawn}");
    }
    // The checks: name, ok, value, limit, message; the stitch's three, the
    // take-up's and the thread's four per needle.
    let checks = v["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 24);
    for name in ["tension_margin", "slack_loop", "stitch_set", "spring_before_slip"] {
        assert_eq!(checks.iter().filter(|c| c["name"] == name).count(), 3, "{name}");
    }
    for c in checks {
        assert!(
            c["name"].is_string()
                && c["ok"].is_boolean()
                && c["value"].is_number()
                && c["limit"].is_array()
                && c["message"].is_string(),
            "{c}"
        );
    }
    assert!(v["caveats"].as_array().unwrap().len() >= 2 && v["transfers"].as_array().unwrap().len() == 1);
    // The P' columns come with `run`.
    let (csv, _) = ok(&["run", "--columns", "*.Pprime_B_mm,*.D_mm"]);
    assert!(csv.lines().next().unwrap().contains("n1.Pprime_B_mm"), "{csv}");
    // A model without [stitch] says so and fails cleanly.
    let e = fails(&["match", "--preset", "needle876"]);
    assert!(e.contains("has no [stitch] table"), "{e}");
    let e = fails(&["match", "--set", "m=9"]);
    assert!(e.contains("outside its adjustable range"), "{e}");
}

/// A measured curve (here the model's own P of needle 2, every 5°, as
/// `run` writes it) set beside the model by `match`, `plot takeup` and
/// `report`; a malformed file is refused with its line and the fix.
#[test]
fn match_plot_and_report_take_a_measured_curve() {
    let d = scratch("measured");
    let (csv, _) = ok(&["run", "--step", "5", "--columns", "n2_A.P_B_mm"]);
    std::fs::write(d.join("n2.csv"), &csv).unwrap();
    let file = d.join("n2.csv");
    let file = file.to_str().unwrap();
    let (out, _) = ok(&["match", "--measured", file]);
    assert!(out.contains("measured P of n2") && out.contains("at B"), "{out}");
    assert!(
        out.contains("the model's P against it: RMS 0.0"),
        "the model against itself, interpolated:\n{out}"
    );
    assert!(out.contains("P meas"), "a sparkline of the measured curve:\n{out}");
    let (json, _) = ok(&["match", "--measured", &format!("n2={file}"), "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["measured"][0]["thread"], "n2");
    // n2's own score against P′ with the regulator window computed (57.6).
    assert!(v["measured"][0]["against_other"]["score"].as_f64().unwrap() > 50.0);
    let svg = d.join("m.svg");
    ok(&["plot", "takeup", "--measured", file, "-o", svg.to_str().unwrap()]);
    assert!(
        std::fs::read_to_string(&svg)
            .unwrap()
            .contains("data-name=\"n2 P measured\"")
    );
    let html = d.join("m.html");
    ok(&[
        "report",
        "--measured",
        file,
        "--no-animation",
        "--step",
        "5",
        "-o",
        html.to_str().unwrap(),
    ]);
    assert!(std::fs::read_to_string(&html).unwrap().contains("id=\"measured\""));
    // A malformed curve: the line and the fix.
    std::fs::write(d.join("bad.csv"), "phi_deg,n2.P_B_mm\n0,0\n90,x\n").unwrap();
    let e = fails(&["match", "--measured", d.join("bad.csv").to_str().unwrap()]);
    assert!(e.contains("bad.csv:3"), "{e}");
    let e = fails(&["match", "--measured", d.join("missing.csv").to_str().unwrap()]);
    assert!(e.contains("missing.csv"), "{e}");
    let e = fails(&["plot", "mu", "--measured", file]);
    assert!(e.contains("--measured is for `plot takeup`"), "{e}");
}

#[test]
fn sweep_writes_one_row_per_setting_and_shards_concatenate() {
    let args = [
        "sweep",
        "--preset",
        "needle876",
        "--vary",
        "alpha=0:35:8",
        "--figures",
        "needle_y.range_mm,mu.min_deg",
    ];
    let (out, err) = ok(&args);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "index,alpha_deg,mu.min_deg,needle_y.range_mm,status");
    assert_eq!(lines.len(), 9, "{out}");
    // Seed 002: stroke 18.08 mm at α = 0, 22.77 mm at 35°.
    let stroke = |l: &str| l.split(',').nth(3).unwrap().parse::<f64>().unwrap();
    assert!(
        (stroke(lines[1]) - 18.08).abs() < 0.01 && (stroke(lines[8]) - 22.77).abs() < 0.01,
        "{out}"
    );
    assert!(lines[1..].iter().all(|l| l.ends_with(",ok")));
    assert!(err.contains("# sweep: 8 settings (8 evaluated"), "{err}");
    assert!(
        err.contains("largest mu.min_deg") && err.contains("at alpha = 0"),
        "{err}"
    );
    // Three shards, concatenated, are the sweep.
    let mut cat = String::new();
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let mut a = args.to_vec();
        a.extend(["--shard", shard.as_str()]);
        cat += &ok(&a).0;
    }
    assert_eq!(cat, out);
    // Samples are reproducible from the seed, and a setting without assembly
    // is a row with its reason, not a failure.
    let lhs = [
        "sweep",
        "--preset",
        "needle876",
        "--vary",
        "alpha=0:45",
        "--samples",
        "12",
        "--seed",
        "3",
        "--figures",
        "mu.min_deg",
    ];
    let (a, _) = ok(&lhs);
    let (b, _) = ok(&lhs);
    assert_eq!(a, b);
    assert_eq!(a.lines().count(), 13);
    // Bad requests fail before any work, naming the fix.
    let e = fails(&["sweep", "--preset", "needle876", "--vary", "alpha=0:99:3"]);
    assert!(e.contains("outside its adjustable range"), "{e}");
    let e = fails(&[
        "sweep",
        "--preset",
        "needle876",
        "--vary",
        "alpha=0:10:3",
        "--figures",
        "nope",
    ]);
    assert!(
        e.contains("no figure of merit matches `nope`") && e.contains("mu.min_deg"),
        "{e}"
    );
    let e = fails(&[
        "sweep",
        "--preset",
        "needle876",
        "--vary",
        "alpha=0:10:3",
        "--shard",
        "4/3",
    ]);
    assert!(e.contains("not a shard"), "{e}");
    let e = fails(&["sweep", "--preset", "needle876", "--vary", "alpha"]);
    assert!(e.contains("NAME=LO:HI:N"), "{e}");
    // With -o the file appears whole, and nothing else is left behind.
    let d = scratch("sweep");
    let f = d.join("s.csv");
    ok(&[
        "sweep",
        "--preset",
        "needle876",
        "--vary",
        "alpha=0:35:8",
        "--figures",
        "needle_y.range_mm,mu.min_deg",
        "-o",
        f.to_str().unwrap(),
    ]);
    assert_eq!(std::fs::read_to_string(&f).unwrap(), out);
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
}

#[test]
fn tune_recommends_a_setting_with_before_and_after() {
    let (out, _) = ok(&[
        "tune",
        "--set",
        "t1_phase=180",
        "--thickness",
        "4",
        "--adjust",
        "z,dphi",
        "--step",
        "2",
    ]);
    assert!(out.starts_with("Recommended setting: z = "), "{out}");
    assert!(out.contains("(from z = 0 mm, dphi = 0 deg)"), "{out}");
    for line in [
        "score before",
        "RMS(D) after",
        "mean",
        "transmission angles: before",
        "within one score point",
        "cycles evaluated",
    ] {
        assert!(out.contains(line), "`{line}` missing:\n{out}");
    }
    let (json, _) = ok(&[
        "tune",
        "--set",
        "t1_phase=180",
        "--adjust",
        "z",
        "--step",
        "3",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(v["after_figures"]["score_mean"].as_f64().unwrap() >= v["before_figures"]["score_mean"].as_f64().unwrap());
    let e = fails(&["tune", "--preset", "needle876", "--adjust", "alpha"]);
    assert!(e.contains("no [stitch]"), "{e}");
    let e = fails(&["tune", "--step", "0"]);
    assert!(e.contains("step 0 deg is out of range"), "{e}");
    let e = fails(&["tune", "--thickness", "9"]);
    assert!(e.contains("outside its adjustable range"), "{e}");
}

#[test]
fn compare_2d3d_reports_the_planar_error() {
    let (csv, summary) = ok(&["compare-2d3d", "--plane", "uvw", "--step", "10"]);
    let header = csv.lines().next().unwrap();
    assert!(
        header.starts_with("phi_deg,n1_A.P3D_mm,n1_A.P2D_mm,n1_A.dP_mm"),
        "{header}"
    );
    assert_eq!(csv.lines().count(), 37);
    assert!(summary.contains("n1_A max |ΔP|"), "{summary}");
    let (json, _) = ok(&["compare-2d3d", "--format", "json", "--step", "90"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["paths"].as_array().unwrap().len(), 6);
    let e = fails(&["compare-2d3d", "--plane", "nope"]);
    assert!(e.contains("no frame `nope`") && e.contains("uvw"), "{e}");
    let e = fails(&["compare-2d3d", "--preset", "needle876"]);
    assert!(e.contains("no thread paths"), "{e}");
}

#[test]
fn every_preset_runs_as_csv_and_json_and_checks() {
    for p in PRESETS {
        let (csv, _) = ok(&["run", "--preset", p, "--step", "5"]);
        assert_eq!(csv.lines().count(), 1 + 72, "{p}");
        let (json, _) = ok(&[
            "run", "--preset", p, "--step", "30", "--format", "json", "--rpm", "1000",
        ]);
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["model"], *p);
        assert_eq!(v["columns"][0]["name"], "phi_deg");
        assert_eq!(v["columns"][0]["values"].as_array().unwrap().len(), 12);
        assert!(v["transmission"].is_array() && v["parameters"].is_array());
        let (check, _) = ok(&["check", "--preset", p, "--cross-check", "--step", "10"]);
        assert!(
            check.contains("ok —") && check.contains("cross-check: 36 positions"),
            "{check}"
        );
        if *p == "mf7923d" {
            assert!(
                check.contains("thread paths (6)") && check.contains("[G4_1]"),
                "{check}"
            );
        }
    }
}

#[test]
fn presets_lists_name_machine_and_the_paper_by_authors_and_year() {
    let (out, _) = ok(&["presets"]);
    for (p, paper) in [
        ("needle876", "Kharzhevskyi et al. (n.d.)"),
        ("overlock500", "Dvorzhak et al. (2024)"),
        ("altin-needle", "Polyakov (2022)"),
        ("altin504", "Polyakov (2022)"),
        ("mf7923d", "Manoilenko et al. (2024)"),
        ("takeup-lever", "Dvorzhak et al. (n.d.)"),
        ("lockstitch", "Dvorzhak et al. (n.d.)"),
    ] {
        let line = out
            .lines()
            .find(|l| l.starts_with(p))
            .unwrap_or_else(|| panic!("{p} missing:\n{out}"));
        assert!(line.contains(paper), "{line}");
    }
    assert!(!out.contains("seed"), "{out}");
    assert!(out.contains("(default)"));
}

#[test]
fn overrides_are_applied_and_checked() {
    let n876 = ["run", "--preset", "needle876"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> { n876.iter().chain(extra).copied().collect() };
    let (a0, _) = ok(&with(&["--points", "G", "--step", "90"]));
    let (a30, warn30) = ok(&with(&["--points", "G", "--step", "90", "--set", "alpha=30"]));
    assert_ne!(a0, a30);
    assert!(!warn30.contains("warning"));
    let (_, warn40) = ok(&with(&["--step", "1", "--set", "alpha=40"]));
    assert!(
        warn40.contains("warning: transmission angle") && warn40.contains("45"),
        "{warn40}"
    );
    let e = fails(&with(&["--set", "alpha=50"]));
    assert!(e.contains("outside its adjustable range") && e.contains("help"), "{e}");
    let (_, sz) = ok(&["run", "--set", "z=-5", "--set", "dphi=10", "--step", "10"]);
    assert!(sz.contains("n1_A"));
    let e = fails(&["run", "--set", "z=-15"]);
    assert!(
        e.contains("z = -15 mm is outside its adjustable range -10…10 mm"),
        "{e}"
    );
    let e = fails(&with(&["--set", "alpah=5"]));
    assert!(e.contains("did you mean `alpha`"), "{e}");
    let e = fails(&with(&["--set", "alpha"]));
    assert!(e.contains("NAME=VALUE"), "{e}");
    let e = fails(&["run", "--step", "0"]);
    assert!(e.contains("greater than 0") && e.contains("(in --step)"), "{e}");
    let e = fails(&with(&["--set", "alpha=20", "--set", "alpha=30"]));
    assert!(e.contains("`alpha` is set twice (in --set)"), "{e}");
    let e = fails(&with(&["--set", "alpha=x"]));
    assert!(e.contains("`x` is not a number") && e.contains("(in --set)"), "{e}");
    let e = fails(&["run", "--rpm", "-5"]);
    assert!(e.contains("rpm"), "{e}");
    let e = fails(&["run", "--points", "Q"]);
    assert!(e.contains("no point `Q`"), "{e}");
    let e = fails(&["run", "--preset", "needle867"]);
    assert!(e.contains("did you mean `needle876`"), "{e}");
}

#[test]
fn malformed_files_name_file_line_column_and_fix() {
    let d = scratch("malformed");
    let cases: &[(&str, &str, &str)] = &[
        (
            "syntax.toml",
            "[model]\nname = \"x\"\n[points]\nO = [0, 0\n",
            "syntax.toml:4:",
        ),
        (
            "unknown.toml",
            "[model]\nname = \"x\"\n[points]\nO = [0, 0]\n[[drivers]]\ntype = \"crank\"\ncenter = \"Q\"\nout = \"A\"\nradius = 5\n",
            "syntax",
        ),
        (
            "units.toml",
            "[model]\nname = \"x\"\n[parameters]\na = { value = 5, unit = \"deg\" }\n[points]\nO = [0, 0]\n[[drivers]]\ntype = \"crank\"\ncenter = \"O\"\nout = \"A\"\nradius = \"a\"\n",
            "units.toml:11:",
        ),
    ];
    for (name, text, _) in cases {
        std::fs::write(d.join(name), text).unwrap();
    }
    let e = fails(&["check", d.join("syntax.toml").to_str().unwrap()]);
    assert!(e.contains("syntax.toml:4:"), "{e}");
    let e = fails(&["check", d.join("unknown.toml").to_str().unwrap()]);
    assert!(
        e.contains("unknown.toml:7:") && e.contains("unknown point `Q`") && e.contains("help"),
        "{e}"
    );
    let e = fails(&["run", d.join("units.toml").to_str().unwrap()]);
    assert!(
        e.contains("units.toml:11:") && e.contains("deg") && e.contains("mm"),
        "{e}"
    );
    let e = fails(&["run", d.join("missing.toml").to_str().unwrap()]);
    assert!(e.contains("cannot read model file"), "{e}");
}

/// A thread whose balance fails over coarse φ steps is told to take a
/// finer one.
#[test]
fn a_tension_lost_over_coarse_steps_names_the_finer_step() {
    let e = fails(&["run", "--preset", "altin504", "--step", "45"]);
    assert!(
        e.contains("thread path `upper`") && e.contains("at a φ step of 45.000°"),
        "{e}"
    );
    assert!(e.contains("a finer step, such as the default 1°"), "{e}");
}

#[test]
fn a_failed_run_leaves_no_output_file() {
    let d = scratch("atomic");
    // The rocker is too short for part of the cycle: no assembly there.
    let model = "[model]\nname = \"short\"\n[points]\nO1 = [0, 0]\nO2 = [60, 0]\n[[drivers]]\ntype = \"crank\"\ncenter = \"O1\"\nout = \"A\"\nradius = 15\n\
                 [[groups]]\ntype = \"rrr\"\nname = \"bc\"\njoints = [\"A\", \"O2\"]\nlengths = [50, 24]\nout = \"B\"\nbranch = \"left\"\n";
    std::fs::write(d.join("short.toml"), model).unwrap();
    let out = d.join("out.csv");
    let e = fails(&[
        "run",
        d.join("short.toml").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        e.contains("no assembly at φ =") && e.contains("rrr group \"bc\"") && e.contains("closure fails by"),
        "{e}"
    );
    assert!(!out.exists());
    // An existing file is left untouched by a failed run, replaced by a good one.
    std::fs::write(&out, "previous").unwrap();
    fails(&[
        "run",
        d.join("short.toml").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous");
    ok(&["run", "--step", "10", "-o", out.to_str().unwrap()]);
    assert!(std::fs::read_to_string(&out).unwrap().starts_with("phi_deg,"));
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        2,
        "no temporary files left behind"
    );
    let e = fails(&["run", "-o", "/nonexistent-dir/out.csv"]);
    assert!(e.contains("cannot"), "{e}");
}

#[test]
fn every_subcommand_has_help_with_an_example() {
    for sub in [
        vec!["--help"],
        vec!["run", "--help"],
        vec!["check", "--help"],
        vec!["presets", "--help"],
        vec!["schema", "--help"],
        vec!["compare-2d3d", "--help"],
        vec!["consumption", "--help"],
        vec!["match", "--help"],
        vec!["sweep", "--help"],
        vec!["tune", "--help"],
        vec!["sensitivity", "--help"],
        vec!["fit", "--help"],
        vec!["cam", "--help"],
        vec!["nomogram", "--help"],
        vec!["stroke", "--help"],
        vec!["straightness", "--help"],
        vec!["tolerance", "--help"],
        vec!["plot", "--help"],
    ] {
        let (out, _) = ok(&sub);
        assert!(out.contains("Example"), "{sub:?}:\n{out}");
    }
}

#[test]
fn schema_is_json_schema_of_the_format() {
    let (out, _) = ok(&["schema"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["$schema"].as_str().unwrap().contains("json-schema"));
    let text = out.as_str();
    for word in ["parameters", "drivers", "groups", "rrr", "rssr", "newton", "branch"] {
        assert!(text.contains(word), "schema lacks {word}");
    }
}

/// Starts `stitchkin ARGS --port 0` (a `serve`), reads the address it
/// prints, checks that `/api/model` answers, and stops it.
fn serve_answers(args: &[&str]) {
    use std::io::{BufRead, BufReader, Read, Write};
    let mut child = bin()
        .args(args)
        .args(["--port", "0"])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let url = line
        .split("open ")
        .nth(1)
        .and_then(|u| u.split_whitespace().next())
        .unwrap_or_else(|| panic!("no address in `{line}`"));
    let addr = url.trim_start_matches("http://").trim_end_matches('/');
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    write!(
        s,
        "GET /api/model HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut answer = String::new();
    s.read_to_string(&mut answer).unwrap();
    let _ = child.kill();
    let _ = child.wait();
    assert!(
        answer.starts_with("HTTP/1.1 200") && answer.contains("\"parameters\""),
        "{answer}"
    );
}

/// The `stitchkin …` commands of the ```sh blocks of a file of the
/// repository (comments and shell quoting taken off, as a shell would),
/// each with whether its comment says a check fails there (the command
/// then exits with status 1 after its output).
fn doc_commands(file: &str) -> Vec<(Vec<String>, bool)> {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(file)).unwrap();
    let mut in_sh = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with("```") {
            in_sh = line == "```sh";
            continue;
        }
        let (cmd, comment) = line.split_once('#').unwrap_or((line, ""));
        let cmd = cmd.trim();
        if in_sh && cmd.starts_with("stitchkin ") {
            out.push((
                cmd.split_whitespace()
                    .skip(1)
                    .map(|a| a.trim_matches('\'').to_string())
                    .collect(),
                comment.contains(" fails"),
            ));
        }
    }
    out
}

/// Runs every `stitchkin …` command of `file` in the scratch folder `d`
/// (a `serve` is started, asked and stopped); returns how many ran.
fn run_doc_commands(file: &str, d: &Path) -> usize {
    let commands = doc_commands(file);
    for (args, check_fails) in &commands {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        if args[0] == "serve" {
            serve_answers(&args);
            continue;
        }
        let out = run_in(&args, d);
        if *check_fails {
            assert!(
                out.status.code() == Some(1)
                    && String::from_utf8_lossy(&out.stderr).contains("physical check(s) fail")
                    && !out.stdout.is_empty(),
                "{file}: `stitchkin {}` should print its output and fail a check\n{}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr)
            );
            continue;
        }
        assert!(
            out.status.success(),
            "{file}: `stitchkin {}` failed\n{}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    commands.len()
}

/// Every `stitchkin …` command in the README's shell blocks runs.
#[test]
fn readme_examples_run() {
    let d = scratch("readme");
    let ran = run_doc_commands("README.md", &d);
    assert!(ran >= 4, "only {ran} README commands found");
    assert!(d.join("needle876-alpha30.json").exists());
}

/// And every one in the picture, report and web docs.
#[test]
fn picture_docs_examples_run() {
    let d = scratch("picture-docs");
    for (file, at_least) in [("docs/plots.md", 10), ("docs/drawing.md", 5), ("docs/report.md", 4)] {
        let ran = run_doc_commands(file, &d);
        assert!(ran >= at_least, "only {ran} commands in {file}");
    }
    assert!(d.join("tuned.html").exists() && d.join("takeup-lever.svg").exists());
}

/// The engine's cycle loops run on the widest vector unit the CPU has; plain
/// IEEE arithmetic gives the same bits at any width, so every unit prints
/// the same numbers (`STITCHKIN_SIMD` caps the unit).
#[test]
fn results_do_not_depend_on_the_vector_unit() {
    let sweep = ["sweep", "--vary", "z=-10:10:5", "--vary", "r1=4:6:3"];
    for args in [
        &["run"][..],
        &["run", "--preset", "takeup-lever"],
        &["run", "--preset", "needle876"],
        &sweep,
    ] {
        let with = |unit: &str| {
            let out = bin()
                .args(args)
                .env("NO_COLOR", "1")
                .env("STITCHKIN_SIMD", unit)
                .output()
                .expect("the binary runs");
            assert!(out.status.success(), "{args:?} with {unit} failed");
            out.stdout
        };
        let widest = with("avx512");
        assert!(widest.len() > 1000);
        for unit in ["baseline", "avx2"] {
            assert!(with(unit) == widest, "{args:?}: {unit} differs from the widest unit");
        }
    }
}

/// The library names the input at fault; the command line names its flag.
/// A command line that does not parse is reported in the same style, with
/// exit code 2.
#[test]
fn errors_name_the_flag_and_refuse_what_cannot_work() {
    let out = run(&["run", "--foo"]);
    let e = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(2), "{e}");
    assert!(
        e.starts_with("Error:") && e.contains("unexpected argument '--foo'") && e.contains("help:"),
        "{e}"
    );
    let e = fails(&["plot", "family", "--vary", "q=1:2:3", "-o", "x.svg"]);
    assert!(e.contains("no parameter `q`") && e.contains("(in --vary)"), "{e}");
    let e = fails(&["stroke", "--preset", "needle876", "--point", "Q"]);
    assert!(e.contains("no point `Q`") && e.contains("(in --point)"), "{e}");
    let e = fails(&["tune", "--preset", "altin504", "--adjust", "alpha"]);
    assert!(
        e.contains("fixed dimension") && e.contains("(in --adjust)") && e.contains("--allow-dimensions"),
        "{e}"
    );
    let e = fails(&[
        "consumption",
        "--type",
        "504",
        "--thickness",
        "1e308",
        "--stitch",
        "1e308",
        "--width",
        "1e308",
    ]);
    assert!(e.contains("overflow"), "{e}");
    let e = fails(&[
        "consumption",
        "--type",
        "504",
        "--stitch",
        "0",
        "--width",
        "4",
        "--thickness",
        "2",
    ]);
    assert!(e.contains("(in --stitch)"), "{e}");
}

/// `-o` never destroys what it points at: a device stays a device, a
/// read-only file is refused and kept, a stopped sweep leaves neither its
/// temporary file nor a half-written output.
#[cfg(unix)]
#[test]
fn outputs_keep_devices_read_only_files_and_stopped_runs_intact() {
    use std::os::unix::fs::{FileTypeExt, PermissionsExt};
    ok(&["run", "--step", "30", "-o", "/dev/null"]);
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
    let d = scratch("outputs");
    let locked = d.join("locked.csv");
    std::fs::write(&locked, "keep me").unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o444)).unwrap();
    let e = fails(&["run", "--step", "30", "-o", locked.to_str().unwrap()]);
    assert!(e.contains("read-only") && e.contains("chmod u+w"), "{e}");
    assert_eq!(std::fs::read_to_string(&locked).unwrap(), "keep me");
    let e = fails(&["run", "-o", d.join("nowhere/x.csv").to_str().unwrap()]);
    assert!(e.contains("there is no folder"), "{e}");

    // A long sweep stopped by SIGTERM while it streams its rows.
    let out = d.join("sweep.csv");
    let mut child = bin()
        .args(["sweep", "--vary", "z=-10:10:1001", "--vary", "dphi=-20:20:1001", "-o"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let temporary = || {
        std::fs::read_dir(&d)
            .unwrap()
            .filter_map(Result::ok)
            .any(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
    };
    let started = std::time::Instant::now();
    while !temporary() {
        assert!(started.elapsed().as_secs() < 120, "the sweep never opened its output");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(128 + 15), "{status:?}");
    assert!(!temporary(), "the temporary file outlived the signal");
    assert!(!out.exists(), "a stopped sweep wrote its output");
}

/// A repository example model's path.
fn example(name: &str) -> String {
    format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn cam_checks_count_in_sweeps_json_and_check() {
    let rocking = example("cam-rocking-roller.toml");
    // A 16° swing on a 12 mm base circle is too steep; on 18 mm it passes.
    let (csv, _) = ok(&["sweep", &rocking, "--set", "rise=16", "--vary", "r_b=12:18:2"]);
    let lines: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    let k = lines[0]
        .split(',')
        .position(|c| c == "checks.ok")
        .expect("a checks.ok column");
    let ok_col: Vec<&str> = lines[1..].iter().map(|l| l.split(',').nth(k).unwrap()).collect();
    assert_eq!(ok_col, ["0", "1"]);
    let (csv, _) = ok(&[
        "sweep",
        &rocking,
        "--vary",
        "rise=6:16:2",
        "--figures",
        "feed_arm.checks_ok",
    ]);
    assert!(csv.starts_with("index,rise_deg,feed_arm.checks_ok,status"), "{csv}");
    // run's JSON carries them; the spring fails at 3000 rpm.
    let (json, _) = ok(&["run", &rocking, "--rpm", "3000", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let checks = v["cams"][0]["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 3);
    assert_eq!(checks[2]["name"], "follower_contact");
    assert_eq!(checks[2]["ok"], false);
    // check passes at the model's 1000 rpm; match needs a stitch.
    let (text, _) = ok(&["check", &rocking]);
    assert!(text.contains("# cam feed_arm ok"), "{text}");
    let said = fails(&["match", &rocking]);
    assert!(said.contains("no [stitch]"), "{said}");
}
