//! The stitch: thread consumption per stitch, and the required take-up
//! P'(φ) of `docs/stitch-formation.md`.
//!
//! - [`spec`]: what P' is computed from (the stitch, the organs' motions, the
//!   moments) and what comes out;
//! - [`feed`], [`material`], [`needle_thread`], [`overedge`] (with its stitches
//!   [`overedge::s504`] and [`overedge::s503`]):
//!   the building blocks and the pieces of §4–§5;
//! - [`lockstitch`]: the lockstitch's needle thread on a rotary hook (§13);
//! - [`required_take_up`]: [`required_take_up::required_take_up`], P' of every thread;
//! - [`consumption`]: thread per finished stitch (§6);
//! - [`mismatch`]: P against P' (§8);
//! - [`checks`]: what no real machine can do (the thread bound at B, the
//!   catch clearance, the stab before the drop);
//! - [`mod@reference`]: the stand-in cases of the independent numpy reference.

pub mod checks;
pub mod consumption;
pub mod feed;
pub mod lockstitch;
pub mod material;
pub mod mismatch;
pub mod needle_thread;
pub mod overedge;
pub mod required_take_up;
pub mod search;
// The stand-in cases shared by the unit tests and tests/it; not part of the
// library's documented surface.
#[doc(hidden)]
pub mod reference;
pub mod spec;
