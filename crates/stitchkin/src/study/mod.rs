//! Studies over a model: comparisons and (later) sweeps, sensitivity and
//! tuning.

pub mod compare2d3d;
