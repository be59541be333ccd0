//! The invariants of docs/architecture.md, checked on the source: which of
//! the library's top-level modules may use which, and what the output layer
//! and the binaries must not do.
//!
//! The check reads `crate::…` paths (outside `#[cfg(test)]` blocks, since a
//! test may build a whole model to exercise a low-level function) and the
//! binaries' `stitchkin::…` paths.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's layers, lowest first. A module may use modules of its own
/// layer or below, never above (docs/architecture.md, "Code map").
const LAYERS: &[&[&str]] = &[
    &["scalar", "format", "numeric", "error", "presets", "references"],
    &["geometry"],
    &["mechanism"],
    &["thread", "stitch"],
    &["model"],
    &["eval"],
    &["study", "verify"],
    &["output"],
    &["jobs"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

fn src_dir(krate: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(krate).join("src")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The text of a source file without its `#[cfg(test)]` items and without
/// comments (a doc comment may name any module).
fn code_of(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("#[cfg(test)]") {
            // Skip the item that follows: up to its closing brace at the
            // same indentation, or its `;`.
            let indent = line.len() - trimmed.len();
            for next in lines.by_ref() {
                let t = next.trim_start();
                let ind = next.len() - t.len();
                if t.ends_with(';') && ind == indent && !t.starts_with("use") {
                    break;
                }
                if ind == indent && t.starts_with('}') {
                    break;
                }
                if t.starts_with("use ") && ind == indent {
                    break;
                }
                out.push('\n');
            }
            out.push_str("\n\n");
            continue;
        }
        if trimmed.starts_with("//") {
            out.push('\n');
            continue;
        }
        out.push_str(line.split(" // ").next().unwrap_or(line));
        out.push('\n');
    }
    out
}

/// Top-level modules named by `prefix::NAME` or inside `prefix::{…}`.
fn modules_used(code: &str, prefix: &str) -> BTreeSet<String> {
    let mut used = BTreeSet::new();
    let mut rest = code;
    while let Some(at) = rest.find(prefix) {
        let before = rest[..at].chars().last();
        rest = &rest[at + prefix.len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        if let Some(group) = rest.strip_prefix('{') {
            let end = matching_brace(group);
            for item in split_top_level(&group[..end]) {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if item.trim()[name.len()..].starts_with("::") && !name.is_empty() {
                    used.insert(name);
                }
            }
        } else {
            let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            if !name.is_empty() && rest[name.len()..].starts_with("::") || layer_of(&name).is_some() {
                used.insert(name);
            }
        }
    }
    used
}

fn matching_brace(s: &str) -> usize {
    let mut depth = 1;
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return i;
                }
            }
            _ => {}
        }
    }
    s.len()
}

fn split_top_level(s: &str) -> Vec<&str> {
    let (mut parts, mut depth, mut start) = (Vec::new(), 0, 0);
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&s[start..]);
    parts
}

/// For every top-level module of the library: the files it is made of.
fn library_modules() -> BTreeMap<String, Vec<(PathBuf, String)>> {
    let root = src_dir("stitchkin");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    let mut modules: BTreeMap<String, Vec<(PathBuf, String)>> = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(&root).unwrap();
        let top = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy()
            .trim_end_matches(".rs")
            .to_string();
        if top == "lib" {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(&f).unwrap());
        modules.entry(top).or_default().push((f, code));
    }
    modules
}

#[test]
fn the_matcher_reads_paths_and_groups() {
    let code = "use crate::{geometry::V3, scalar::Real};\nlet x = crate::eval::run_cycle(m);\nfoo_crate::model::X";
    let used = modules_used(code, "crate::");
    assert_eq!(used.into_iter().collect::<Vec<_>>(), ["eval", "geometry", "scalar"]);
    let code =
        code_of("use crate::a::B;\n#[cfg(test)]\nmod tests {\n    use crate::model::Model;\n}\nuse crate::c::D;\n");
    assert!(!code.contains("model") && code.contains("crate::c::D"), "{code}");
}

#[test]
fn every_library_module_has_a_layer() {
    for module in library_modules().keys() {
        assert!(
            layer_of(module).is_some(),
            "src/{module}: a new top-level module; give it a layer in docs/architecture.md and in this test"
        );
    }
}

#[test]
fn dependencies_point_down_only() {
    let mut wrong = Vec::new();
    for (module, files) in library_modules() {
        let Some(own) = layer_of(&module) else { continue };
        for (file, code) in files {
            for used in modules_used(&code, "crate::") {
                if let Some(theirs) = layer_of(&used)
                    && theirs > own
                {
                    wrong.push(format!(
                        "{} uses {used} (layer {theirs} above {module}, layer {own})",
                        file.display()
                    ));
                }
            }
        }
    }
    assert!(wrong.is_empty(), "arrows running up:\n{}", wrong.join("\n"));
}

#[test]
fn modules_of_one_layer_do_not_use_each_other_both_ways() {
    let modules = library_modules();
    let uses = |a: &str, b: &str| {
        modules[a]
            .iter()
            .any(|(_, code)| modules_used(code, "crate::").contains(b))
    };
    for layer in LAYERS {
        for a in layer.iter().filter(|m| modules.contains_key(**m)) {
            for b in layer.iter().filter(|m| modules.contains_key(**m) && *m > a) {
                assert!(!(uses(a, b) && uses(b, a)), "{a} and {b} use each other");
            }
        }
    }
}

/// `mechanism` knows nothing of threads or stitches; only `model` knows the
/// file's shape.
#[test]
fn mechanism_knows_no_thread_and_only_model_knows_the_file() {
    let mut wrong = Vec::new();
    for (module, files) in library_modules() {
        for (file, code) in files {
            if module == "mechanism" {
                for word in ["thread", "stitch", "Threads"] {
                    if code.contains(&format!("crate::{word}")) {
                        wrong.push(format!("{}: mechanism names {word}", file.display()));
                    }
                }
            }
            if module != "model" {
                for shape in ["model::file", "ModelFile", ".file()"] {
                    if code.contains(shape) {
                        wrong.push(format!(
                            "{}: reads the model file's shape ({shape}); use Model's accessors",
                            file.display()
                        ));
                    }
                }
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Calls that compute: the output layer is given their results.
const COMPUTING: &[&str] = &[
    "run_cycle(",
    "run_cycle_with(",
    "tune(",
    "nomogram(",
    "sweep::run(",
    "compare_2d3d(",
    ".solve(",
    ".mechanism(",
    ".mechanism::<",
    ".machine(",
    ".machine::<",
    "measured_match(",
];

#[test]
fn output_formats_what_it_is_given_and_runs_nothing() {
    let mut wrong = Vec::new();
    for (file, code) in &library_modules()["output"] {
        for call in COMPUTING {
            for (k, line) in code.lines().enumerate() {
                if line.contains(call)
                    && !line.trim_start().starts_with("pub fn")
                    && !line.trim_start().starts_with("fn ")
                {
                    wrong.push(format!("{} line {}: {}", file.display(), k + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "output computes instead of formatting:\n{}",
        wrong.join("\n")
    );
}

/// The binaries parse, route and print: they call the library's jobs,
/// studies and formatters, never its solvers.
#[test]
fn binaries_do_not_reach_into_solvers() {
    let mut wrong = Vec::new();
    for krate in ["stitchkin-cli", "stitchkin-web", "stitchkin-py"] {
        let mut files = Vec::new();
        rust_files(&src_dir(krate), &mut files);
        for file in files {
            let code = code_of(&std::fs::read_to_string(&file).unwrap());
            for used in modules_used(&code, "stitchkin::") {
                if ["mechanism", "geometry", "numeric", "thread", "stitch"].contains(&used.as_str()) {
                    wrong.push(format!(
                        "{}: uses stitchkin::{used}; binaries go through model, eval, study, output and jobs",
                        file.display()
                    ));
                }
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The library speaks of its inputs in its own words ([`stitchkin::Input`]);
/// the command line maps them to its flags. Only `output::text`, the text
/// the command line prints, may point at a flag.
#[test]
fn library_messages_name_no_command_line_flag() {
    let mut wrong = Vec::new();
    let mut files = Vec::new();
    rust_files(&src_dir("stitchkin"), &mut files);
    for file in files {
        if file.components().any(|c| c.as_os_str() == "text") {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(&file).unwrap());
        for (n, line) in code.lines().enumerate() {
            if line.trim_start().starts_with('#') {
                continue;
            }
            if let Some(f) = flag_in(line) {
                wrong.push(format!("{}:{}: names the flag `{f}`", file.display(), n + 1));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The first ` --word`, `"--word`, `(--word` or `` `--word `` in a line: a
/// flag written into a string.
fn flag_in(line: &str) -> Option<String> {
    let bytes = line.as_bytes();
    (0..bytes.len().saturating_sub(3)).find_map(|i| {
        let before = if i == 0 { b' ' } else { bytes[i - 1] };
        let starts = bytes[i] == b'-' && bytes[i + 1] == b'-' && bytes[i + 2].is_ascii_lowercase();
        (starts && matches!(before, b' ' | b'"' | b'(' | b'`')).then(|| {
            let end = line[i + 2..]
                .find(|c: char| !(c.is_ascii_lowercase() || c == '-'))
                .map_or(line.len(), |e| i + 2 + e);
            line[i..end].to_string()
        })
    })
}

#[test]
fn the_flag_matcher_finds_flags_in_strings_only() {
    assert_eq!(flag_in(r#"help: "give --vary z=1:2:3""#).as_deref(), Some("--vary"));
    assert_eq!(flag_in("(in --plane)").as_deref(), Some("--plane"));
    assert_eq!(flag_in("let x = a--b;"), None);
    assert_eq!(flag_in("x - -y"), None);
}
