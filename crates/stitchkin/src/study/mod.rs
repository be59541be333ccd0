//! Studies over a model: comparisons, parameter sweeps and (to come)
//! sensitivity and tuning.

pub mod compare2d3d;
pub mod sweep;
pub mod tune;
