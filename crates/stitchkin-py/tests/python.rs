//! The Python package's tests, from `cargo test`: builds the wheel once in
//! release mode (maturin), installs it into a virtual environment under
//! `target/py-venv` with the pinned test requirements, and runs
//! `tests/python` with pytest against the command line of the same source
//! (`target/debug/stitchkin`).
//!
//! Needs `python3` (3.9 or later) with `venv`, and the package index for
//! the first run (later runs find the requirements installed).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The workspace's target folder (the parent of this test's scratch folder).
fn target_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("the scratch folder is inside the target folder")
        .to_path_buf()
}

/// Runs `command` and returns its standard output; panics with its output
/// when it fails.
#[track_caller]
fn run(command: &mut Command, what: &str) -> String {
    let out = command
        .output()
        .unwrap_or_else(|e| panic!("cannot {what}: {e} ({command:?})"));
    assert!(
        out.status.success(),
        "cannot {what} ({command:?}, {}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn python_package_tests_pass() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target = target_dir();
    let venv = target.join("py-venv");
    let python = venv.join("bin").join("python");
    if !python.exists() {
        run(
            Command::new("python3").args(["-m", "venv"]).arg(&venv),
            "create the virtual environment (python3 -m venv)",
        );
    }
    run(
        Command::new(&python)
            .args(["-m", "pip", "install", "--quiet", "--disable-pip-version-check", "-r"])
            .arg(crate_dir.join("requirements-test.txt")),
        "install the test requirements (pip)",
    );
    // The wheel, in a folder of its own so only this build's is installed.
    let wheels = target.join("py-wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    run(
        Command::new(venv.join("bin").join("maturin"))
            .args(["build", "--release", "--quiet", "-m"])
            .arg(crate_dir.join("Cargo.toml"))
            .arg("--out")
            .arg(&wheels)
            .arg("-i")
            .arg(&python),
        "build the wheel (maturin build --release)",
    );
    let wheel = std::fs::read_dir(&wheels)
        .expect("maturin wrote its folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "whl"))
        .expect("maturin wrote a wheel");
    run(
        Command::new(&python)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
                "--force-reinstall",
                "--no-deps",
            ])
            .arg(&wheel),
        "install the wheel",
    );
    // The command line of this source (already built by `cargo test
    // --workspace`: then this finds nothing to do).
    run(
        Command::new(env!("CARGO")).args(["build", "--quiet", "-p", "stitchkin-cli"]),
        "build the command line",
    );
    let cli = target.join("debug").join("stitchkin");
    let report = run(
        Command::new(&python)
            // `-rs`: each skipped test with its reason.
            .args(["-m", "pytest", "-q", "-rs", "-p", "no:cacheprovider"])
            .arg(crate_dir.join("tests").join("python"))
            .env("STITCHKIN_CLI", &cli)
            // Imported from the installed wheel, not from the source folder.
            .current_dir(&target),
        "pass the package's tests (pytest)",
    );
    // Every requirement a test can skip for (pandas, dask) is installed
    // above: here a skipped test is a test that did not run.
    let summary = report.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or_default();
    assert!(
        !summary.contains("skipped"),
        "some of the package's tests were skipped although their requirements are installed ({summary}):\n{report}"
    );
}
