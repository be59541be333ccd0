//! The φ step of a study that refines extremes below the cycle grid.

use super::{CycleOptions, check_options};
use crate::error::{Error, Input, ParamError};

/// The coarsest φ step of a study that refines extremes: each extremum must
/// lie between a grid sample's two neighbours, degrees.
pub const MAX_STEP_DEG: f64 = 45.0;

/// Checks a refining study's φ step: greater than 0 and at most
/// [`MAX_STEP_DEG`], and the cycle's own checks ([`check_options`]).
pub(crate) fn check_step(step_deg: f64) -> Result<(), Error> {
    if !(step_deg.is_finite() && step_deg > 0.0) {
        return Err(Error::Param(ParamError::new(
            Input::Step,
            format!("the step {step_deg} deg is out of range"),
            Some(format!(
                "give a step greater than 0 and at most {MAX_STEP_DEG} degrees, e.g. 1"
            )),
        )));
    }
    check_options(&CycleOptions {
        step_deg,
        ..Default::default()
    })?;
    if step_deg > MAX_STEP_DEG {
        return Err(Error::Param(ParamError::new(
            Input::Step,
            format!("the step {step_deg} deg is too coarse to bracket the extremes"),
            Some(format!(
                "give a step of at most {MAX_STEP_DEG} deg, e.g. 1 (extremes are refined below it)"
            )),
        )));
    }
    Ok(())
}

/// The φ step the stitch's metrics are judged against, degrees: the
/// presets' default. Finer steps still move a score where a computed
/// regulator window's edges fall on the grid: the MF-7923D's needle 3
/// scores 34.3 at 1°, 36.8 at 0.5° and 38.3 at 0.1° (its needles 1 and 2
/// and the lockstitch within 0.6 point); a step coarser than 1° moves them
/// by far more (needle 1: 35.5 at 30°, 75.0 at 1°).
pub const REFERENCE_STEP_DEG: f64 = 1.0;

/// A score that moves by more than this between a coarse step and
/// [`REFERENCE_STEP_DEG`] gets a warning, points.
pub const STEP_SCORE_POINTS: f64 = 1.0;

/// Where `coarse` (a stitch's summary at a step coarser than
/// [`REFERENCE_STEP_DEG`]) is run again at that step: a warning that says by
/// how much the scores move (when one moves by more than
/// [`STEP_SCORE_POINTS`]) and which checks turn; `None` when the step is
/// fine enough or nothing moves.
pub fn coarse_step_warning(
    model: &crate::model::Model,
    params: &crate::model::Params,
    coarse: &super::stitch_process::StitchSummary,
    opts: &CycleOptions,
) -> Result<Option<String>, Error> {
    if opts.step_deg <= REFERENCE_STEP_DEG {
        return Ok(None);
    }
    let fine_opts = CycleOptions {
        step_deg: REFERENCE_STEP_DEG,
        ..opts.clone()
    };
    let fine = super::run_cycle(model, params, &fine_opts)?;
    let Some(fine) = &fine.stitch else { return Ok(None) };
    let score = |st: &super::stitch_process::StitchSummary, thread: &str| {
        st.threads
            .iter()
            .find(|t| t.thread == thread)
            .and_then(|t| t.mismatch.as_ref())
            .and_then(|m| m.score)
    };
    // The thread whose score moves most.
    let moved = coarse
        .threads
        .iter()
        .filter_map(|t| Some((t.thread.as_str(), score(coarse, &t.thread)?, score(fine, &t.thread)?)))
        .max_by(|a, b| (a.1 - a.2).abs().total_cmp(&(b.1 - b.2).abs()));
    let turned: Vec<String> = coarse
        .checks
        .iter()
        .filter_map(|c| {
            let f = fine.checks.iter().find(|f| f.name == c.name && f.thread == c.thread)?;
            (f.ok != c.ok).then(|| {
                format!(
                    "{} {} {} at {REFERENCE_STEP_DEG}°",
                    c.thread,
                    c.name,
                    if f.ok { "passes" } else { "fails" }
                )
            })
        })
        .collect();
    let step = opts.step_deg;
    let mut parts = Vec::new();
    if let Some((thread, here, there)) = moved
        && (here - there).abs() > STEP_SCORE_POINTS
    {
        parts.push(format!(
            "the scores move by up to {:.1} points ({thread} {here:.1} at {step}°, {there:.1} at {REFERENCE_STEP_DEG}°)",
            (here - there).abs()
        ));
    }
    if !turned.is_empty() {
        parts.push(turned.join(", "));
    }
    Ok((!parts.is_empty()).then(|| {
        format!(
            "the φ step of {step}° is too coarse for the metrics: against a {REFERENCE_STEP_DEG}° step {}; use a step of {REFERENCE_STEP_DEG}° or finer",
            parts.join("; ")
        )
    }))
}

/// The cycle `match` judges (from the command line, Python and the page
/// alike): positions and paths at `step_deg`, no analogs or points, with
/// [`coarse_step_warning`] added to its warnings and its stitch's.
pub fn run_match(
    model: &crate::model::Model,
    params: &crate::model::Params,
    step_deg: f64,
) -> Result<super::CycleTable, Error> {
    let opts = CycleOptions {
        step_deg,
        rpm: None,
        analogs: false,
        points: Some(Vec::new()),
        lean: false,
    };
    let mut table = super::run_cycle(model, params, &opts)?;
    if let Some(st) = &table.stitch
        && let Some(w) = coarse_step_warning(model, params, st, &opts)?
    {
        table.warnings.push(w.clone());
        if let Some(st) = &mut table.stitch {
            st.warnings.push(w);
        }
    }
    Ok(table)
}
