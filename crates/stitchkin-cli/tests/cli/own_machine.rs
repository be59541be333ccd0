//! `stitchkin presets --export` and `stitchkin new`: a model file of one's
//! own machine to start from, run as a user would.

use super::{PRESETS, fails, ok, run_in, scratch};

/// `args` run in `dir`, which must succeed: stdout and stderr.
fn ok_in(args: &[&str], dir: &std::path::Path) -> (String, String) {
    let out = run_in(args, dir);
    let (o, e) = (
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    );
    assert!(out.status.success(), "{args:?} failed:\n{e}");
    (o, e)
}

/// The shipped file of a preset, as the repository holds it.
fn shipped(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../presets/{name}.toml"));
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn every_exported_preset_is_the_shipped_file_and_gives_the_presets_results() {
    let d = scratch("export");
    for name in PRESETS {
        let file = format!("{name}.toml");
        let (stdout, _) = ok_in(&["presets", "--export", name], &d);
        assert_eq!(stdout, shipped(name), "{name} on stdout");
        let (nothing, note) = ok_in(&["presets", "--export", name, "-o", &file], &d);
        assert!(nothing.is_empty());
        assert!(note.starts_with(&format!("wrote {file} (")), "{note}");
        assert_eq!(
            std::fs::read_to_string(d.join(&file)).unwrap(),
            stdout,
            "{name} in {file}"
        );

        let run = ["run", "--step", "10", "--format", "csv"];
        let from_file = ok_in(&[&run[..], &[file.as_str()]].concat(), &d).0;
        let from_preset = ok_in(&[&run[..], &["--preset", name]].concat(), &d).0;
        assert!(from_file.lines().count() > 30, "{name}: {from_file}");
        assert!(
            from_file == from_preset,
            "{name}: `run` differs between the file and the preset"
        );

        if stdout.lines().any(|l| l.trim() == "[stitch]") {
            let from_file = ok_in(&["match", &file, "--format", "json"], &d).0;
            let from_preset = ok_in(&["match", "--preset", name, "--format", "json"], &d).0;
            assert!(from_file.contains("\"score\""), "{name}: {from_file}");
            assert!(
                from_file == from_preset,
                "{name}: `match` differs between the file and the preset"
            );
        }
    }
}

/// The families `new --list` names.
fn families() -> Vec<String> {
    let (list, _) = ok(&["new", "--list"]);
    assert!(list.starts_with("family "), "{list}");
    list.lines()
        .skip(1)
        .map(|l| l.split_whitespace().next().unwrap().to_string())
        .collect()
}

#[test]
fn every_family_gives_a_model_that_loads_runs_and_passes_its_checks() {
    let families = families();
    for needed in ["rocking-takeup", "lockstitch-lever", "takeup-lever", "needle-bar"] {
        assert!(
            families.iter().any(|f| f == needed),
            "no family {needed} in {families:?}"
        );
    }
    // Without a family, `new` lists them as --list does.
    assert_eq!(ok(&["new"]).0, ok(&["new", "--list"]).0);
    let d = scratch("new");
    for family in &families {
        let file = format!("{family}.toml");
        let (stdout, _) = ok_in(&["new", family], &d);
        let (_, note) = ok_in(&["new", family, "-o", &file], &d);
        assert!(note.starts_with(&format!("wrote {file} (")), "{note}");
        let text = std::fs::read_to_string(d.join(&file)).unwrap();
        assert_eq!(text, stdout, "{family}: the file and stdout differ");
        assert!(text.starts_with("# my-machine: "), "{family}: {}", &text[..200]);
        for words in [
            "mm",
            "deg",
            "kind = \"dimension\"",
            "kind = \"setting\"",
            "[model]",
            "name = \"my-machine\"",
            "MAKING IT YOUR MACHINE",
            "# 2. Fixed dimensions",
        ] {
            assert!(text.contains(words), "{family}: no `{words}` in the template");
        }
        let (report, _) = ok_in(&["check", &file], &d);
        assert!(
            report.contains("my-machine") || report.contains("My machine"),
            "{family}: {report}"
        );
        let (csv, _) = ok_in(&["run", &file, "--step", "30", "--format", "csv"], &d);
        assert_eq!(csv.lines().count(), 13, "{family}: {csv}");
    }
    // The template of the chain-stitch take-up matches as its preset does.
    ok_in(&["new", "rocking-takeup", "-o", "mine.toml"], &d);
    let mine = ok_in(&["match", "mine.toml", "--format", "json"], &d).0;
    let preset = ok_in(&["match", "--preset", "mf7923d", "--format", "json"], &d).0;
    let scores = |json: &str| -> Vec<String> {
        json.lines()
            .filter(|l| l.contains("\"score\""))
            .map(str::to_string)
            .collect()
    };
    assert!(!scores(&mine).is_empty());
    assert_eq!(scores(&mine), scores(&preset));
}

#[test]
fn an_unknown_family_or_preset_is_refused_with_the_closest_name() {
    let e = fails(&["new", "rocking-takup"]);
    assert!(e.contains("no mechanism family named `rocking-takup`"), "{e}");
    assert!(e.contains("did you mean `rocking-takeup`?"), "{e}");
    assert!(e.contains("the families are: rocking-takeup"), "{e}");
    let e = fails(&["presets", "--export", "lockstich"]);
    assert!(
        e.contains("no preset named `lockstich` (did you mean `lockstitch`?) (in --export)"),
        "{e}"
    );
    assert!(e.contains("the presets are:"), "{e}");
    let d = scratch("new-refused");
    let out = run_in(&["presets", "--export", "nosuch", "-o", "x.toml"], &d);
    assert!(!out.status.success());
    assert!(!d.join("x.toml").exists(), "a refused export wrote a file");
    let e = fails(&["new", "-o", "x.toml"]);
    assert!(e.contains("-o needs a family"), "{e}");
}

/// `new` keeps an existing file (perhaps a model already edited) unless
/// told to replace it; then, as every command's -o, it is replaced whole,
/// nothing is left beside it, and a read-only file is refused and kept.
#[test]
fn output_onto_an_existing_file_replaces_it_whole_and_refuses_a_read_only_one() {
    let d = scratch("new-existing");
    let file = d.join("mine.toml");
    std::fs::write(&file, "old contents\n").unwrap();
    let out = run_in(&["new", "needle-bar", "-o", "mine.toml"], &d);
    let e = String::from_utf8(out.stderr).unwrap();
    assert!(!out.status.success(), "an existing model was replaced");
    assert!(e.contains("`mine.toml` exists") && e.contains("--force"), "{e}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "old contents\n");
    ok_in(&["new", "needle-bar", "-o", "mine.toml", "--force"], &d);
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.starts_with("# my-machine: ") && !text.contains("old contents"));
    ok_in(&["presets", "--export", "needle876", "-o", "mine.toml"], &d);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), shipped("needle876"));
    let left: Vec<_> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 1, "files left beside the output: {left:?}");

    let mut perms = std::fs::metadata(&file).unwrap().permissions();
    perms.set_readonly(true);
    std::fs::set_permissions(&file, perms).unwrap();
    let out = run_in(&["new", "takeup-lever", "-o", "mine.toml", "--force"], &d);
    let e = String::from_utf8(out.stderr).unwrap();
    assert!(!out.status.success(), "a read-only file was replaced");
    assert!(e.contains("read-only"), "{e}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), shipped("needle876"));
}
