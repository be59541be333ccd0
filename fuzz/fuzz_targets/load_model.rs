//! Fuzz target: load arbitrary text as a model file and, when it loads,
//! evaluate a short cycle. Nothing may panic; errors are fine (and their
//! `Display` must not panic either).

#![no_main]

use libfuzzer_sys::fuzz_target;
use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::model::Model;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Model::from_toml_str(text, "fuzz.toml") {
        Ok(model) => {
            let opts = CycleOptions {
                step_deg: 45.0,
                ..Default::default()
            };
            match run_cycle(&model, &model.defaults(), &opts) {
                Ok(table) => {
                    std::hint::black_box(table.rows());
                }
                Err(e) => {
                    std::hint::black_box(e.to_string());
                }
            }
        }
        Err(e) => {
            std::hint::black_box(e.to_string());
        }
    }
});
