//! Studies over a model: comparisons (2D against 3D, a measured curve
//! against the model), parameter sweeps, sensitivity, tuning and nomograms,
//! cam synthesis, calibration, strokes, straightness and tolerances.

pub mod cam_synthesis;
pub mod compare2d3d;
pub mod fit;
pub mod measured;
pub mod nomogram;
pub mod sensitivity;
pub mod straightness;
pub mod stroke;
pub mod sweep;
pub mod tune;
