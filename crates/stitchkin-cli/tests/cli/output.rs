//! One convention for what every command prints (docs/architecture.md,
//! "Output for people and programs"): readable text on a terminal, the
//! table into a pipe or a file, `--format` first; every file written said
//! once; papers cited by authors and year; no negative zero.
//!
//! `STITCHKIN_TERMINAL=1` stands in for a terminal; `script` gives a real
//! one where it matters (util-linux, part of every Debian system).

use std::path::Path;
use std::process::{Command, Output};

use super::{bin, scratch};

/// Runs `args` in `dir` with stdout taken for a terminal (`terminal`) or a
/// pipe.
fn run_as(terminal: bool, args: &[&str], dir: &Path) -> Output {
    let out = bin()
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .env("STITCHKIN_TERMINAL", if terminal { "1" } else { "0" })
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{args:?} failed:\n{stderr}");
    assert!(!stderr.contains("panicked"), "panic for {args:?}:\n{stderr}");
    out
}

/// stdout and stderr of `args` on a terminal (`terminal`) or into a pipe.
fn texts(terminal: bool, args: &[&str]) -> (String, String) {
    let out = run_as(terminal, args, Path::new("."));
    (
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// `args` on a pseudo-terminal: stdout and stderr together.
fn on_a_tty(args: &str) -> String {
    let exe = env!("CARGO_BIN_EXE_stitchkin");
    let out = Command::new("script")
        .args(["-qec", &format!("{exe} {args}"), "/dev/null"])
        .env("NO_COLOR", "1")
        .env_remove("STITCHKIN_TERMINAL")
        .output()
        .expect("script runs");
    assert!(out.status.success(), "{args}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).replace('\r', "")
}

/// Whether `text` starts with a CSV header: a first line of names and
/// commas.
fn is_csv(text: &str) -> bool {
    let first = text.lines().next().unwrap_or("");
    first.contains(',') && !first.contains(' ')
}

/// The table commands, each with cheap arguments.
const TABLE_COMMANDS: &[&[&str]] = &[
    &["run", "--step", "30"],
    &["run", "--step", "30", "--columns", "*.P_B_mm"],
    &["compare-2d3d", "--step", "30"],
    &[
        "sweep",
        "--vary",
        "z=-5:5:3",
        "--figures",
        "n1_A.max_P_B_mm",
        "--step",
        "10",
    ],
    &[
        "stroke",
        "--preset",
        "needle876",
        "--point",
        "G",
        "--axis",
        "y",
        "--step",
        "10",
    ],
    &[
        "sensitivity",
        "--params",
        "r1,z",
        "--figures",
        "n1_A.max_P_B_mm",
        "--step",
        "10",
    ],
    &[
        "straightness",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--step",
        "5",
    ],
    &[
        "tolerance",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--samples",
        "20",
        "--step",
        "5",
    ],
    &["consumption", "--type", "301", "--thickness", "2", "--stitch", "2.5"],
    &[
        "cam", "--preset", "altin504", "--path", "lower", "--target", "required", "--points", "36",
    ],
];

#[test]
fn every_table_command_is_readable_on_a_terminal_and_a_table_in_a_pipe() {
    for args in TABLE_COMMANDS {
        let (screen, _) = texts(true, args);
        assert!(!is_csv(&screen), "{args:?} on a terminal printed CSV:\n{screen}");
        assert!(!screen.trim().is_empty(), "{args:?} printed nothing on a terminal");
        let (piped, _) = texts(false, args);
        assert!(is_csv(&piped), "{args:?} into a pipe is not CSV:\n{piped}");
        // --format wins either way.
        let mut csv = args.to_vec();
        csv.extend(["--format", "csv"]);
        assert!(is_csv(&texts(true, &csv).0), "{csv:?}");
        let mut table = args.to_vec();
        table.extend(["--format", "table"]);
        assert!(!is_csv(&texts(false, &table).0), "{table:?}");
    }
    // The commands read as a whole print the same text everywhere.
    for args in [
        &["match", "--step", "5"][..],
        &["tune", "--adjust", "z", "--samples", "8", "--step", "10"],
    ] {
        let (screen, _) = texts(true, args);
        let (piped, _) = texts(false, args);
        assert_eq!(screen, piped, "{args:?}");
        assert!(!is_csv(&piped), "{args:?}");
    }
}

/// On a real terminal: the summaries, and the way to the whole table.
#[test]
fn a_real_terminal_gets_the_summaries() {
    let compare = on_a_tty("compare-2d3d --step 30");
    assert!(
        compare.contains("max |ΔP|") && !compare.contains("phi_deg,") && compare.contains("pipe it, `-o FILE.csv`"),
        "{compare}"
    );
    let sweep = on_a_tty("sweep --vary z=-5:5:3 --figures n1_A.max_P_B_mm --step 10");
    assert!(
        sweep.contains("# sweep: 3 settings") && !sweep.contains("index,") && sweep.contains("3 rows"),
        "{sweep}"
    );
}

/// `run --columns` on a terminal shows the asked columns, every 10°, and
/// says how to get every row.
#[test]
fn run_columns_on_a_terminal_shows_the_columns() {
    let screen = on_a_tty("run --columns n1_A.P_B_mm,mu_*");
    let lines: Vec<&str> = screen.lines().collect();
    assert_eq!(lines[0], "every 10th row of 360 (every 10°, and the last):", "{screen}");
    let header: Vec<&str> = lines[1].split_whitespace().collect();
    assert_eq!(header[0], "phi_deg", "{screen}");
    assert!(
        header.contains(&"n1_A.P_B_mm") && header.iter().any(|h| h.starts_with("mu_")),
        "{screen}"
    );
    assert!(lines.iter().any(|l| l.trim_start().starts_with("180 ")), "{screen}");
    assert!(lines.len() < 45, "{screen}");
    assert!(
        screen.contains("every row, 360 of them: pipe it, `-o FILE.csv`"),
        "{screen}"
    );
    // A short table is shown whole.
    let (short, _) = texts(true, &["run", "--step", "30", "--columns", "n1_A.P_B_mm"]);
    assert_eq!(short.lines().count(), 1 + 12 + 1, "{short}");
}

/// A command of each kind with `-o`, and the file it writes.
const WRITERS: &[&[&str]] = &[
    &["run", "--step", "30", "-o", "run.csv"],
    &["run", "--step", "30", "-o", "run.json"],
    &["compare-2d3d", "--step", "30", "-o", "dp.csv"],
    &[
        "sweep",
        "--vary",
        "z=-5:5:3",
        "--figures",
        "n1_A.max_P_B_mm",
        "--step",
        "10",
        "-o",
        "sweep.csv",
    ],
    &[
        "stroke",
        "--preset",
        "needle876",
        "--point",
        "G",
        "--axis",
        "y",
        "--step",
        "10",
        "-o",
        "stroke.csv",
    ],
    &[
        "sensitivity",
        "--params",
        "r1",
        "--figures",
        "n1_A.max_P_B_mm",
        "--step",
        "10",
        "-o",
        "sens.csv",
    ],
    &[
        "straightness",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--step",
        "5",
        "-o",
        "straight.csv",
    ],
    &[
        "tolerance",
        "--preset",
        "altin-needle",
        "--point",
        "E",
        "--samples",
        "20",
        "--step",
        "5",
        "-o",
        "tol.csv",
    ],
    &[
        "consumption",
        "--type",
        "301",
        "--thickness",
        "2",
        "--stitch",
        "2.5",
        "-o",
        "cons.csv",
    ],
    &["match", "--step", "5", "-o", "match.txt"],
    &[
        "tune",
        "--adjust",
        "z",
        "--samples",
        "8",
        "--step",
        "10",
        "-o",
        "tune.json",
    ],
    &[
        "cam", "--preset", "altin504", "--path", "lower", "--target", "required", "--points", "36", "-o", "cam.csv",
        "--format", "csv",
    ],
    &["plot", "takeup", "--step", "10", "-o", "takeup.svg"],
    &["draw", "--phi", "30", "-o", "draw.svg"],
    &["report", "--step", "10", "--no-animation", "-o", "report.html"],
    &["presets", "--export", "needle876", "-o", "needle876.toml"],
    &["new", "needle-bar", "-o", "my-machine.toml"],
];

/// The file and what each command's `-o` writes, with how many files it
/// writes.
#[test]
fn every_file_written_is_said_once_the_same_way() {
    let d = scratch("output-wrote");
    let facts = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/facts/needle876.toml");
    let fit: &[&str] = &[
        "fit",
        "--preset",
        "needle876",
        "--target",
        facts.to_str().unwrap(),
        "--set",
        "y_c=170",
        "-o",
        "fit.txt",
    ];
    for args in WRITERS.iter().copied().chain([fit]) {
        let out = run_as(false, args, &d);
        let stderr = String::from_utf8_lossy(&out.stderr);
        let file = args[args.iter().position(|a| *a == "-o").unwrap() + 1];
        let said: Vec<&str> = stderr.lines().filter(|l| l.starts_with("wrote ")).collect();
        assert_eq!(said.len(), 1, "{args:?}:\n{stderr}");
        assert!(
            said[0].starts_with(&format!("wrote {file} ("))
                && (said[0].ends_with(" bytes)") || said[0].ends_with(" kB)")),
            "{args:?}: {}",
            said[0]
        );
        assert!(out.stdout.is_empty(), "{args:?} wrote to stdout too");
        let size = std::fs::metadata(d.join(file)).unwrap().len();
        assert!(size > 0, "{file}");
    }
    // The JSON of -o FILE.json, CSV else.
    let json = std::fs::read_to_string(d.join("run.json")).unwrap();
    assert!(json.trim_start().starts_with('{'), "{}", &json[..80]);
    assert!(is_csv(&std::fs::read_to_string(d.join("stroke.csv")).unwrap()));
    assert!(
        std::fs::read_to_string(d.join("tune.json"))
            .unwrap()
            .trim_start()
            .starts_with('{')
    );
    // cam's four files, each said.
    let out = run_as(
        false,
        &[
            "cam", "--preset", "altin504", "--path", "lower", "--target", "required", "--points", "36", "-o", "lower",
        ],
        &d,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    for ext in ["csv", "svg", "dxf", "toml"] {
        let said = stderr
            .lines()
            .filter(|l| l.starts_with(&format!("wrote lower.{ext} (")))
            .count();
        assert_eq!(said, 1, "lower.{ext}:\n{stderr}");
    }
}

/// Papers by authors and year in what a user reads: summaries, tables,
/// help, errors, the report, the presets' list.
#[test]
fn papers_are_cited_by_authors_and_year() {
    let d = scratch("output-papers");
    let (_, summary) = texts(false, &["run", "--step", "30"]);
    assert!(summary.contains("(Manoilenko et al. (2024) eq. 2)"), "{summary}");
    assert!(summary.contains("(Polyakov (2022) sec. 2.3)"), "{summary}");
    let (stroke, _) = texts(
        true,
        &[
            "stroke",
            "--preset",
            "needle876",
            "--point",
            "G",
            "--axis",
            "y",
            "--step",
            "10",
        ],
    );
    assert!(stroke.contains("(Kharzhevskyi et al. (n.d.) eq. 15)"), "{stroke}");
    let (screen, _) = texts(true, &["match", "--step", "5"]);
    assert!(screen.contains("Manoilenko et al. (2024)"), "{screen}");
    let (_, cam) = texts(
        false,
        &[
            "cam", "--preset", "altin504", "--path", "lower", "--target", "required", "--points", "36",
        ],
    );
    assert!(cam.contains("Polyakov (2022) §2.5"), "{cam}");
    // An error's help.
    let out = bin()
        .args(["tolerance", "--preset", "altin-needle", "--point", "E", "--limit", "0"])
        .env("NO_COLOR", "1")
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && e.contains("e.g. 0.05 (Polyakov (2022))"),
        "{e}"
    );
    // The report.
    run_as(false, &["report", "--step", "10", "--no-animation", "-o", "r.html"], &d);
    let html = std::fs::read_to_string(d.join("r.html")).unwrap();
    assert!(
        html.contains("after Manoilenko et al. (2024)"),
        "report without its paper"
    );
    for (what, text) in [
        ("run's summary", summary.as_str()),
        ("stroke", &stroke),
        ("match", &screen),
        ("cam", &cam),
        ("the error", &e),
        ("the report", &html),
    ] {
        assert!(!seed_cited(text), "{what} cites a seed by number:\n{text}");
    }
    // Every subcommand's help.
    for name in [
        "presets",
        "new",
        "run",
        "check",
        "compare-2d3d",
        "consumption",
        "match",
        "sweep",
        "tune",
        "nomogram",
        "sensitivity",
        "fit",
        "stroke",
        "straightness",
        "tolerance",
        "cam",
        "plot",
        "draw",
        "serve",
        "report",
        "schema",
    ] {
        let help = texts(false, &[name, "--help"]).0;
        assert!(
            !seed_cited(&help),
            "`stitchkin {name} --help` cites a seed by number:\n{help}"
        );
    }
}

/// Whether `text` cites a paper as "seed 000" … "seed 004".
fn seed_cited(text: &str) -> bool {
    (0..5).any(|n| text.contains(&format!("seed 00{n}")) || text.contains(&format!("Seed 00{n}")))
}

/// No `-0.00` in what a user reads, however the numbers fall.
#[test]
fn no_negative_zero_is_printed() {
    for args in [
        &["run", "--step", "10", "--format", "table"][..],
        &[
            "run",
            "--step",
            "10",
            "--columns",
            "*.P_B_mm,*.P_eye_mm,*.dP_B_dphi_mm_per_rad",
            "--format",
            "table",
        ],
        &["check", "--step", "10"],
        // The Altin needle's eye_x spans -0.00004 … 0 mm: `-0.0000` before.
        &["check", "--preset", "altin504", "--step", "5"],
        &["run", "--preset", "altin504", "--step", "5", "--format", "csv"],
        &["match", "--step", "5", "--details"],
        &[
            "stroke",
            "--preset",
            "needle876",
            "--point",
            "G",
            "--axis",
            "y",
            "--step",
            "10",
            "--format",
            "table",
        ],
        &["compare-2d3d", "--step", "10", "--format", "table"],
        &[
            "straightness",
            "--preset",
            "altin-needle",
            "--point",
            "E",
            "--step",
            "5",
            "--format",
            "table",
        ],
    ] {
        let (out, err) = texts(false, args);
        for text in [&out, &err] {
            assert!(!has_negative_zero(text), "{args:?} prints a negative zero:\n{text}");
        }
    }
}

/// Whether `text` holds a number such as `-0`, `-0.0`, `-0.000` (not
/// `-0.01`).
fn has_negative_zero(text: &str) -> bool {
    stitchkin::format::without_negative_zeros(text) != text
}
