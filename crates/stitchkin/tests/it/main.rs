//! Integration tests of the stitchkin library, in one test binary (one link
//! step instead of one per file).

mod cross_check;
mod facts;
mod mechgen;
mod docs;
mod fuzz_regressions;
mod invariants;
mod loading;
mod presets;
mod threads;
mod stitch;
mod studies;
mod sensitivity;
mod strokes;
mod nomogram;
mod pprime;
mod altin504;
mod cam_synthesis;
mod plots;
mod drawing;
mod report;
mod measured;
