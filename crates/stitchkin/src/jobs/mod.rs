//! Jobs: each is one thing a user asks for end to end — a chart, a
//! report. A job checks the request, computes with [`crate::eval`] and
//! [`crate::study`], and hands the results to [`crate::output`], which only
//! draws and formats them.

pub mod drawing;
pub mod plot;
pub mod report;

use crate::error::Error;
use crate::eval::{CycleOptions, CycleTable};
use crate::study::measured::{MeasuredMatch, measured_match};
use crate::thread::measured::MeasuredCurve;

/// The cycle a take-up or transmission-angle chart draws: thread paths,
/// stitch and transmission angles, φ every `step_deg`, no analogs and no
/// point columns.
fn chart_cycle(step_deg: f64) -> CycleOptions {
    CycleOptions {
        step_deg,
        analogs: false,
        points: Some(Vec::new()),
        ..Default::default()
    }
}

/// Each measured curve set beside its thread in `table`: the thread given
/// with the curve, else the one [`measured_match`] finds.
fn match_measured(table: &CycleTable, curves: &[(Option<String>, MeasuredCurve)]) -> Result<Vec<MeasuredMatch>, Error> {
    curves
        .iter()
        .map(|(thread, curve)| measured_match(table, curve, thread.as_deref()))
        .collect()
}
