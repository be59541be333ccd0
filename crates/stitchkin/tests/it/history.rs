//! The product speaks of what it does, never of how or when it was made.
//! README.md, docs/*.md, the presets, the examples and every crate's
//! sources, tests and benches are scanned for the words of a work diary:
//! work-item numbers, named sittings of work, notes addressed to whoever
//! builds the tool, numbered periods of work (an ordinal before "pass",
//! "round" or "period"), paths outside the repository and futures for
//! things that exist. CHANGELOG.md is where history belongs and is not scanned.
//! Every "seed NNN" the documents cite is listed in docs/references.md, and
//! every document that cites a seed links it.

use std::path::{Path, PathBuf};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// Ordinals that number periods of work ("the fourth round"), after one of
/// `DETERMINERS`: without it "first" is an adverb ("the thread first passes
/// G1", "the looper must first pass the needle").
const ORDINALS: [&str; 6] = ["first", "second", "third", "fourth", "fifth", "sixth"];
const DETERMINERS: [&str; 6] = ["the", "a", "an", "this", "that", "our"];

/// What an ordinal numbers when the text is a work diary.
/// The words of a note addressed to whoever builds the tool (written in two
/// pieces so this file does not hold the phrase it looks for).
const NOTE_TO_MAKER: &str = concat!("for the ", "developer");

const PERIODS: [&str; 5] = ["pass", "round", "session", "sitting", "period"];

/// Words after "first pass" or "first period" that make it part of a
/// method or of the stitch cycle, not a period of work: "the first pass over
/// the samples", "the first period of the stitch" (seed 004 §2.1 describes
/// stitch formation in periods). "of work" still counts as history.
const QUALIFIERS: [&str; 7] = ["over", "through", "of", "across", "along", "in", "trip"];

/// Text that only a work diary or a path outside the repository contains,
/// matched as written (case-sensitive).
const EXACT: [(&str, &str); 5] = [
    (
        "shared/seeds",
        "a path outside the repository (cite docs/references.md)",
    ),
    ("../shared/", "a path outside the repository"),
    ("SPEC.md", "a file outside the repository"),
    ("(to come)", "a future for something that exists or is decided"),
    ("OPEN QUESTION", "an open question instead of a decision"),
];

/// Lower-case words of `text`: letters, digits and `#`, the rest separates.
fn words(text: &str) -> Vec<String> {
    text.split(|c: char| !(c.is_alphanumeric() || c == '#'))
        .filter(|w| !w.is_empty())
        .map(str::to_lowercase)
        .collect()
}

fn is_number(word: &str) -> bool {
    let digits = word.trim_start_matches('#');
    !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit())
}

/// Why `line` reads as history, if it does. In source code (`code`) the
/// word "session" counts only in a comment: the browser test's DevTools
/// protocol has a `session` field.
fn history(line: &str, code: bool) -> Option<&'static str> {
    if let Some((_, why)) = EXACT.iter().find(|(s, _)| line.contains(s)) {
        return Some(why);
    }
    if line
        .split(|c: char| !c.is_alphanumeric() && c != '_')
        .any(|w| w == "SPEC")
    {
        return Some("a document outside the repository (SPEC)");
    }
    let lower = line.to_lowercase();
    if lower.contains(NOTE_TO_MAKER) {
        return Some("a note addressed to whoever builds the tool");
    }
    let w = words(line);
    let next = |i: usize| w.get(i).map(String::as_str).unwrap_or("");
    for i in 0..w.len() {
        if (w[i] == "issue" || w[i] == "issues") && is_number(next(i + 1)) {
            return Some("a work-item number (\"issue N\")");
        }
        let numbered = |x: &str| x.strip_prefix('q').is_some_and(is_number);
        if w[i] == "open" && next(i + 1).starts_with("question") && numbered(next(i + 2)) {
            return Some("an open question instead of a decision");
        }
        let noun = next(i + 1);
        let period = PERIODS
            .iter()
            .any(|p| noun.strip_prefix(p).is_some_and(|end| end.is_empty() || end == "s"));
        let numbered_period = i > 0 && DETERMINERS.contains(&w[i - 1].as_str()) && ORDINALS.contains(&w[i].as_str());
        if numbered_period && period {
            let after = next(i + 2);
            let of_work = after == "of" && next(i + 3) == "work";
            if of_work || !(QUALIFIERS.contains(&after) || is_number(after)) {
                return Some("an ordinal period of work (\"the third pass\")");
            }
        }
    }
    let prose = if code {
        line.split_once("//").map_or("", |(_, c)| c)
    } else {
        line
    };
    let pw = words(prose);
    let session = pw.iter().enumerate().any(|(i, x)| {
        (x == "session" || x == "sessions") && !(i > 0 && ["devtools", "cdp", "browser"].contains(&pw[i - 1].as_str()))
    });
    session.then_some("a work session")
}

/// Every file under `dir`, sorted, recursively.
fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files_under(&p, out);
        } else {
            out.push(p);
        }
    }
}

/// The product's text: README.md, docs/*.md but CHANGELOG.md, presets,
/// examples, and every crate's src, tests, benches and python (data tables, *.csv,
/// and this file, which spells the patterns out, left aside).
fn product_files() -> Vec<PathBuf> {
    let root = Path::new(ROOT);
    let mut files = vec![root.join("README.md")];
    for dir in ["docs", "presets", "examples"] {
        files_under(&root.join(dir), &mut files);
    }
    let mut crates = Vec::new();
    files_under(&root.join("crates"), &mut crates);
    files.extend(crates.into_iter().filter(|p| {
        let rel = p.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
        let part = rel.split('/').nth(2).unwrap_or("");
        ["src", "tests", "benches", "python"].contains(&part) && !rel.ends_with("tests/it/history.rs")
    }));
    files.retain(|p| {
        let name = p.file_name().unwrap().to_string_lossy();
        name != "CHANGELOG.md" && !name.ends_with(".csv")
    });
    files
}

fn relative(p: &Path) -> String {
    p.strip_prefix(Path::new(ROOT)).unwrap_or(p).display().to_string()
}

#[test]
fn the_product_does_not_speak_of_how_it_was_made() {
    let files = product_files();
    assert!(
        files.len() > 100,
        "the scan found only {} files under {ROOT}",
        files.len()
    );
    let mut hits = Vec::new();
    for file in &files {
        // Fonts and other binary files are not text.
        let Ok(text) = std::fs::read_to_string(file) else {
            continue;
        };
        let code = file.extension().is_some_and(|e| e == "rs");
        for (n, line) in text.lines().enumerate() {
            if let Some(why) = history(line, code) {
                hits.push(format!("{}:{}: {why}\n    {}", relative(file), n + 1, line.trim()));
            }
        }
    }
    assert!(
        hits.is_empty(),
        "write decisions as decisions, history goes to CHANGELOG.md:\n{}",
        hits.join("\n")
    );
}

#[test]
fn the_history_matcher_finds_history_and_only_history() {
    for diary in [
        concat!("study module docs end \"(iss", "ue 5, item 3)\""),
        "Goals (Issue #2):",
        concat!("measured in the third ", "session"),
        "the fourth pass made the take-up 3× faster",
        "after the first rounds the score rose",
        "two passes, then a third pass",
        concat!("## 12. Open questions for the ", "developer"),
        "The file is `shared/seeds/004_130f616db71991e6.txt`.",
        "The signs follow SPEC.md.",
        "SPEC: drawn from the bobbin",
        "//! Studies: comparisons and (to come) sensitivity",
        "# OPEN QUESTION (to settle when P' is computed)",
        "during the second period of work",
        "(open question Q1)",
        concat!("    // what this ", "session", " changed"),
    ] {
        assert!(history(diary, true).is_some(), "not found: {diary}");
    }
    for product in [
        "the looper meets the highest eye, needle 3, first",
        "seed = \"000\"",
        "seed 004 §2.1 period 1-2: the take-up does not work",
        "the first period of the stitch cycle",
        "a first pass over the samples finds the box",
        "the second derivatives are continuous all round",
        "an error would issue a warning",
        "    session: Option<String>,",
        "        msg[\"sessionId\"] = json!(s);",
        "    // attach to the page and keep the DevTools session",
        "use stitchkin::stitch::spec::StitchSpec;",
        "const STITCH_SPEC: &str = \"\";",
        "fuzz/seeds/minimal.toml",
        "open questions quickly become decisions",
        "the looper must first pass the needle line",
        "the thread first passes G1, then the eyelet",
        "the first round trip of the cam",
        "the needle thread's first catch",
    ] {
        assert_eq!(history(product, true), None, "{product}");
    }
    // Outside source code "session" counts wherever it stands.
    assert!(history("session: the second measurement", false).is_some());
}

/// The seed numbers `text` cites as "seed NNN" or "seeds NNN".
fn seeds_cited(text: &str) -> Vec<String> {
    let w = words(text);
    let mut seeds: Vec<String> = (1..w.len())
        .filter(|&i| (w[i - 1] == "seed" || w[i - 1] == "seeds") && w[i].len() == 3 && is_number(&w[i]))
        .map(|i| w[i].clone())
        .collect();
    seeds.sort();
    seeds.dedup();
    seeds
}

#[test]
fn every_cited_seed_resolves_in_references_md() {
    let root = Path::new(ROOT);
    let references = std::fs::read_to_string(root.join("docs/references.md")).expect("docs/references.md");
    let docs: Vec<PathBuf> = product_files()
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md") && !p.ends_with("docs/references.md"))
        .collect();
    assert!(
        docs.iter().any(|p| p.ends_with("docs/stitch-formation.md")),
        "the documents were not found"
    );
    let mut missing = Vec::new();
    for doc in &docs {
        let text = std::fs::read_to_string(doc).unwrap();
        let seeds = seeds_cited(&text);
        for seed in &seeds {
            if !references.contains(&format!("### Seed {seed}:")) {
                missing.push(format!(
                    "{}: seed {seed} has no entry in docs/references.md",
                    relative(doc)
                ));
            }
        }
        if !seeds.is_empty() && !text.contains("references.md") {
            missing.push(format!(
                "{}: cites seeds {seeds:?} but does not link docs/references.md",
                relative(doc)
            ));
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
    assert_eq!(
        seeds_cited("seed 000, seeds 004 and 003, seed 12, the seed"),
        ["000", "004"]
    );
}
