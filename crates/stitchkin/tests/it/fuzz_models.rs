//! A bounded fuzz run on every test run: mutants of every preset
//! (`tests/fuzz/mutate.rs`) load with an error that has a line and column,
//! or load and run, never panic, never give Ok with a non-finite number.
//! `cargo run --release -p stitchkin --example fuzz_models` runs millions.

use std::time::Duration;

use crate::mutate::{Rng, check, mutate, non_finite_word, seeds};

#[test]
fn mutants_of_the_presets_fail_cleanly_or_run() {
    let seeds = seeds();
    let mut rng = Rng::new(20_261_125);
    let (mut findings, mut loaded, mut ran) = (Vec::new(), 0, 0);
    let runs = 600;
    for i in 0..runs {
        let (name, text) = seeds[i % seeds.len()];
        let bytes = mutate(text, &mut rng);
        match check(&bytes, Duration::from_secs(60)) {
            Ok(o) => {
                loaded += o.loaded as usize;
                ran += o.ran as usize;
            }
            Err(f) => findings.push(format!("{name} #{i}: {f}\n{}", String::from_utf8_lossy(&bytes))),
        }
    }
    assert!(findings.is_empty(), "{}", findings.join("\n\n"));
    // The mutants are near misses: many still load.
    assert!(
        loaded > runs / 10 && ran > 0,
        "only {loaded} of {runs} loaded, {ran} ran"
    );
}

#[test]
fn a_number_that_is_not_finite_is_found_on_a_screen() {
    let file = "ea_n = 85";
    assert_eq!(non_finite_word("n3  NaN N  at 137.0°", file), Some("NaN"));
    assert_eq!(non_finite_word("margin inf×, slack 2 mm", file), Some("inf"));
    assert_eq!(non_finite_word("slack -inf mm", file), Some("-inf"));
    assert_eq!(non_finite_word("regulator window NaN°…48°", file), Some("NaN"));
    assert_eq!(
        non_finite_word("information: 3.84×, 2.73 N at 106.0°, infinite", file),
        None
    );
    // The file's own words echoed: a mutant's `tex inf` is not a result.
    let file = "thread = \"tex inf spun polyester\"";
    assert_eq!(non_finite_word("thread tension (tex inf spun polyester)", file), None);
    assert_eq!(non_finite_word("tex inf spun polyester: peak NaN N", file), Some("NaN"));
}
