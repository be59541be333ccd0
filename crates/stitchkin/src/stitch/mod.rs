//! The stitch: thread consumption per stitch (and, to come, the required
//! take-up P'(φ) of `docs/stitch-formation.md`).

pub mod consumption;
