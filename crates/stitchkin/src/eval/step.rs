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
