//! Studies over a model, each answering one question by evaluating the
//! model at many settings or φ:
//!
//! - [`sweep`]: figures of merit over a grid or sample of settings;
//! - [`sensitivity`]: how much each parameter moves each figure;
//! - [`tune`] and [`nomogram`]: the settings that match the take-up P to the
//!   required P', for one stitch or over thickness and stitch length;
//! - [`fit`]: model dimensions calibrated against results a source states;
//! - [`fit_measured`]: the machine's setting fitted to its measured take-up,
//!   with confidence intervals, and the advice that follows;
//! - [`stroke`] and [`straightness`]: a point's stroke, dead centres and
//!   transmission angles, its straightness along a line, and the tolerance
//!   stack-up of both;
//! - [`compare_2d3d`]: how much a planar model of a spatial thread path errs;
//! - [`measured`]: a measured take-up curve against the model;
//! - [`cam_synthesis`]: the cam profile that gives a thread the take-up it
//!   needs.
//!
//! What they share: a [`design`] says what varies and how it is sampled
//! (grid, random, Latin hypercube), and [`figures`] names the numbers read
//! off a cycle (take-up, transmission angles, strokes, scores), selects them
//! by pattern, and computes P' once when the varied parameters leave the
//! stitch process alone.

pub mod cam_synthesis;
pub mod compare_2d3d;
pub mod design;
pub mod figures;
pub mod fit;
pub mod fit_measured;
pub mod follower_synthesis;
pub(crate) mod least_squares;
pub mod measured;
pub mod nomogram;
pub mod sensitivity;
pub mod straightness;
pub mod stroke;
pub mod sweep;
pub mod tune;
