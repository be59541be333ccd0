//! Structure-aware mutation of model files, and the checks every mutant must
//! pass: shared by the fuzz test (`tests/it/fuzz_models.rs`, a few thousand
//! mutants on every test run) and `examples/fuzz_models.rs` (millions, on
//! demand).
//!
//! A mutant is a shipped preset with one to four edits that a person or a
//! broken tool could make: a number replaced (by 0, a negative, a huge or a
//! tiny value, NaN, a long integer), a line deleted, doubled or moved, a
//! name replaced by another of the file's or by a very long one, a table
//! header or a bracket inserted, the text cut short, a byte that is not
//! UTF-8. Each mutant is loaded from its bytes and, when it loads, run for a
//! cycle, and the match screen a user would see (`match --details`) is read
//! for a number that is not finite.

use std::time::{Duration, Instant};

use stitchkin::output::text;
use stitchkin::{CycleOptions, Model, Preset, run_cycle};

/// A small, fast, seeded generator (xorshift64*): the same seed gives the
/// same mutants on every machine.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1",
    "1e300",
    "-1e300",
    "1e-300",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "65536",
    "1e6",
    "1000001",
    "0.000001",
    "180",
    "360",
    "-360",
    "1e18",
    "3.5",
];
const TOKENS: &[&str] = &[
    "[[groups]]",
    "[[drivers]]",
    "[points]",
    "[parameters]",
    "[stitch]",
    "[thread]",
    "[[thread.paths]]",
    "[[cams]]",
    "[[frames]]",
    "[[measures]]",
    "[model]",
    "=",
    "\"",
    "[",
    "]",
    "{",
    "}",
    ",",
    "#",
    "\n",
    "\"expr\"",
    "type = \"rrr\"",
    "type = \"rssr\"",
    "branch = \"left\"",
    "x = [",
    "{ at = \"",
    "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[",
];

/// The shipped presets' texts: the seed corpus.
pub fn seeds() -> Vec<(&'static str, &'static str)> {
    stitchkin::presets::ALL
        .iter()
        .map(|p: &Preset| (p.name, p.toml))
        .collect()
}

/// One mutant of `text`: 1 to 4 edits.
pub fn mutate(text: &str, rng: &mut Rng) -> Vec<u8> {
    let mut s = text.to_string();
    for _ in 0..1 + rng.below(4) {
        s = edit(&s, rng);
    }
    let mut bytes = s.into_bytes();
    if rng.below(40) == 0 && !bytes.is_empty() {
        // A byte that is not UTF-8 somewhere.
        let k = rng.below(bytes.len());
        bytes[k] = 0xE6 ^ (rng.below(2) as u8);
    }
    bytes
}

fn edit(s: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = s.lines().collect();
    if lines.is_empty() {
        return s.to_string();
    }
    let k = rng.below(lines.len());
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    match rng.below(9) {
        0..=2 => out[k] = replace_number(&out[k], rng),
        3 => {
            out.remove(k);
        }
        4 => out.insert(k, lines[rng.below(lines.len())].to_string()),
        5 => {
            let j = rng.below(lines.len());
            out.swap(k, j);
        }
        6 => out[k] = replace_name(&out[k], &lines, rng),
        7 => {
            let t = TOKENS[rng.below(TOKENS.len())];
            let at = floor_boundary(&out[k], rng.below(out[k].len() + 1));
            out[k].insert_str(at, t);
        }
        _ => {
            let cut = floor_boundary(s, rng.below(s.len() + 1));
            return s[..cut].to_string();
        }
    }
    out.join("\n") + "\n"
}

fn floor_boundary(s: &str, mut i: usize) -> usize {
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// The line with one of its numbers replaced by a hostile one.
fn replace_number(line: &str, rng: &mut Rng) -> String {
    let spans: Vec<(usize, usize)> = number_spans(line);
    let Some(&(a, b)) = spans.get(rng.below(spans.len().max(1))) else {
        return line.to_string();
    };
    format!("{}{}{}", &line[..a], NUMBERS[rng.below(NUMBERS.len())], &line[b..])
}

fn number_spans(line: &str) -> Vec<(usize, usize)> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
        if starts {
            let j = (i..b.len())
                .find(|&j| !(b[j].is_ascii_digit() || b[j] == b'.' || b[j] == b'e'))
                .unwrap_or(b.len());
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// The line with a quoted name replaced by another quoted word of the file,
/// or rarely by a very long one.
fn replace_name(line: &str, lines: &[&str], rng: &mut Rng) -> String {
    let Some(a) = line.find('"') else {
        return line.to_string();
    };
    let Some(len) = line[a + 1..].find('"') else {
        return line.to_string();
    };
    let other = if rng.below(50) == 0 {
        "N".repeat(70_000)
    } else {
        let donor = lines[rng.below(lines.len())];
        donor.split('"').nth(1).unwrap_or("X").to_string()
    };
    format!("{}\"{other}\"{}", &line[..a], &line[a + 1 + len + 1..])
}

/// What a mutant did, when it did something wrong.
#[derive(Debug)]
pub enum Finding {
    /// A panic, with its message.
    Panic(String),
    /// A load error with no line and column.
    NoPosition(String),
    /// A run that gave Ok with a number that is not finite.
    NotFinite(String),
    /// Longer than the limit.
    Slow(Duration),
}

impl std::fmt::Display for Finding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Finding::Panic(m) => write!(f, "panic: {m}"),
            Finding::NoPosition(m) => write!(f, "load error without line:column: {m}"),
            Finding::NotFinite(c) => write!(f, "Ok with a non-finite `{c}`"),
            Finding::Slow(d) => write!(f, "slow: {:.1} s", d.as_secs_f64()),
        }
    }
}

/// What happened to one mutant.
#[derive(Debug, Default, Clone, Copy)]
pub struct Outcome {
    pub loaded: bool,
    pub ran: bool,
}

/// The first number on a screen of text that is not finite, as Rust
/// writes it (`NaN`, `inf`, `-inf`, with whatever unit follows), if any:
/// `inf` inside a word (information) is not one. The screen echoes the
/// model file's own words (its title, notes, the thread's name), where a
/// mutant may have written `inf` for a number (`tex inf`): `inf` counts
/// only where the file has no such word. The file writes NaN as TOML
/// does, `nan`, so `NaN` always counts.
pub fn non_finite_word<'a>(text: &'a str, file: &str) -> Option<&'a str> {
    let file_has_inf = words(file, "inf").next().is_some();
    words(text, "NaN")
        .next()
        .or_else(|| if file_has_inf { None } else { words(text, "inf").next() })
}

/// Each place `word` stands alone in `t` (no letter on either side), with
/// a minus sign before it taken along.
fn words<'t>(t: &'t str, word: &'static str) -> impl Iterator<Item = &'t str> {
    let letter = |c: Option<char>| c.is_some_and(char::is_alphabetic);
    t.match_indices(word).filter_map(move |(at, _)| {
        let end = at + word.len();
        let (before, after) = (t[..at].chars().next_back(), t[end..].chars().next());
        let start = if before == Some('-') { at - 1 } else { at };
        (!letter(before) && !letter(after)).then(|| &t[start..end])
    })
}

/// Loads `bytes` and, when they load, runs a cycle at a 10° step and reads
/// the match screen a user would see; checks every rule above.
pub fn check(bytes: &[u8], limit: Duration) -> Result<Outcome, Finding> {
    let started = Instant::now();
    let result = std::panic::catch_unwind(|| -> Result<Outcome, Finding> {
        let model = match Model::from_toml_bytes(bytes, "fuzz.toml") {
            Ok(m) => m,
            Err(e) => {
                return match e.line_col() {
                    Some(_) => Ok(Outcome::default()),
                    None => Err(Finding::NoPosition(e.to_string())),
                };
            }
        };
        let opts = CycleOptions {
            step_deg: 10.0,
            ..Default::default()
        };
        let ran = match run_cycle(&model, &model.defaults(), &opts) {
            Ok(table) => {
                if let Some(c) = table.columns.iter().find(|c| c.values.iter().any(|v| !v.is_finite())) {
                    return Err(Finding::NotFinite(c.name.clone()));
                }
                // What `match --details` shows: every metric, the tension,
                // the checks.
                let screen = match &table.stitch {
                    Some(st) => text::matching::screen(&model, &table, st, &[], true),
                    None => text::matching::paths_screen(&model, &table, &[], true),
                };
                if let Some(word) = non_finite_word(&screen, &String::from_utf8_lossy(bytes)) {
                    return Err(Finding::NotFinite(format!("`{word}` on the match screen")));
                }
                true
            }
            Err(_) => false,
        };
        Ok(Outcome { loaded: true, ran })
    });
    let elapsed = started.elapsed();
    match result {
        Err(p) => Err(Finding::Panic(
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default(),
        )),
        Ok(_) if elapsed > limit => Err(Finding::Slow(elapsed)),
        Ok(r) => r,
    }
}
