//! Studies over a model: comparisons, parameter sweeps and (to come)
//! sensitivity and tuning.

pub mod cam_synthesis;
pub mod compare2d3d;
pub mod fit;
pub mod nomogram;
pub mod sensitivity;
pub mod straightness;
pub mod stroke;
pub mod sweep;
pub mod tune;
