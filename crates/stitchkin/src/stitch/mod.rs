//! The stitch: thread consumption per stitch, and the required take-up
//! P'(φ) of `docs/stitch-formation.md`.

pub mod consumption;
pub mod spec;
