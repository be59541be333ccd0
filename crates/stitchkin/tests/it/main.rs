//! Integration tests of the stitchkin library, in one test binary (one link
//! step instead of one per file).

mod altin504;
mod architecture;
mod cam_synthesis;
mod cams;
mod cross_check;
mod docs;
mod drawing;
mod facts;
mod fit_measured;
mod follower_synthesis;
mod fuzz_models;
mod fuzz_regressions;
mod history;
mod invariants;
mod kinds;
mod limits;
mod loading;
mod lockstitch;
mod measured;
mod mechgen;
#[path = "../fuzz/mutate.rs"]
mod mutate;
mod nomogram;
mod plots;
mod presets;
mod report;
mod required_take_up;
mod sensitivity;
mod stitch;
mod strokes;
mod studies;
mod support;
mod thread_physics;
mod threads;
mod units;
