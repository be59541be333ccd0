//! The stitch: thread consumption per stitch, and the required take-up
//! P'(φ) of `docs/stitch-formation.md`.

pub mod consumption;
pub mod mismatch;
pub mod spec;
pub mod feed; pub mod material; pub mod needle_thread; pub mod overedge; pub mod overedge503; pub mod pprime;
