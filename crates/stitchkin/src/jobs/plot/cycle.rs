//! The charts of one cycle: take-up, transmission angles, trajectories and
//! analogs; the take-up with measured curves over it.

use super::{Plot, moving_points, select_paths};
use crate::error::{Error, Input};
use crate::eval::{CycleOptions, CycleTable, run_cycle};
use crate::geometry::Plane;
use crate::jobs::{chart_cycle, match_measured};
use crate::model::{Model, Params};
use crate::output::plots::{self, no_dyads, no_threads, param_error};
use crate::output::svg::Chart;
use crate::thread::measured::MeasuredCurve;

/// The chart of [`Plot::TakeUp`], [`Plot::Mu`], [`Plot::Tension`] or [`Plot::Trajectory`]
/// from one cycle at `params`.
pub(super) fn cycle_chart(model: &Model, params: &Params, plot: &Plot, step_deg: f64) -> Result<Chart, Error> {
    let mut opts = chart_cycle(step_deg);
    if let Plot::Trajectory { points, .. } = plot {
        opts.points = Some(point_slots(model, points)?);
    }
    // Fail before the cycle when there is nothing to plot.
    match plot {
        Plot::TakeUp if !model.has_threads() => return Err(no_threads(model)),
        Plot::Mu if model.dyads.is_empty() => return Err(no_dyads(model)),
        _ => {}
    }
    let table = run_cycle(model, params, &opts)?;
    match plot {
        Plot::Mu => plots::transmission(model, &table),
        Plot::Tension => plots::tension(model, &table),
        Plot::Trajectory { points, plane } => {
            let frame = trajectory_frame(model, params, plane.as_deref())?;
            plots::trajectory(model, &table, points, frame)
        }
        _ => plots::take_up(model, &table),
    }
}

/// The frame a trajectory is drawn in: its name and xy-plane at `params`
/// (`None`: the world's).
fn trajectory_frame<'a>(
    model: &Model,
    params: &Params,
    plane: Option<&'a str>,
) -> Result<Option<(&'a str, Plane<f64>)>, Error> {
    let Some(name) = plane else { return Ok(None) };
    let i = model.frame_index(name).ok_or_else(|| {
        param_error(
            Input::Plane,
            format!("the model has no frame `{name}`"),
            format!("its frames are: {}", model.frame_names().join(", ")),
        )
    })?;
    Ok(Some((name, model.mechanism::<f64>(params)?.frame_plane(i))))
}

/// The cycle slots of the named moving points (`--points`).
fn point_slots(model: &Model, points: &[String]) -> Result<Vec<usize>, Error> {
    if points.is_empty() {
        return Err(param_error(
            Input::Points,
            "no points to trace".into(),
            format!("name them, e.g. A,B; the moving points are: {}", moving_points(model)),
        ));
    }
    points
        .iter()
        .map(|p| model.moving_point_slot(p).map_err(|e| e.given_in(Input::Points)))
        .collect()
}

/// The cycle of an analog chart, run with analogs: of the named `points`,
/// or without points of the thread paths `threads` (empty: every path);
/// and the thread paths drawn.
pub fn analogs_cycle(
    model: &Model,
    params: &Params,
    points: &[String],
    threads: &[String],
    step_deg: f64,
) -> Result<(CycleTable, Vec<String>), Error> {
    if !points.is_empty() && !threads.is_empty() {
        return Err(param_error(
            Input::Thread,
            "an analog chart draws either points or thread paths, not both".into(),
            "leave out one of them: the points for their analogs, or the thread paths for dP/dφ".into(),
        ));
    }
    if points.is_empty() && !model.has_threads() {
        return Err(param_error(
            Input::Points,
            format!(
                "model `{}` has no thread paths, so an analog chart needs points",
                model.name()
            ),
            format!("name them, e.g. A,B; the moving points are: {}", moving_points(model)),
        ));
    }
    let paths = if points.is_empty() {
        select_paths(model, threads)?
    } else {
        Vec::new()
    };
    let slots = if points.is_empty() {
        Vec::new()
    } else {
        point_slots(model, points)?
    };
    let opts = CycleOptions {
        step_deg,
        analogs: true,
        points: Some(slots),
        lean: true,
        ..Default::default()
    };
    Ok((run_cycle(model, params, &opts)?, paths))
}

/// The take-up chart of [`Plot::TakeUp`] with measured curves drawn over
/// it, each curve with the thread it belongs to (`None`: the one its file
/// names), as an SVG document.
pub fn render_take_up_with_measured(
    model: &Model,
    params: &Params,
    curves: &[(Option<String>, MeasuredCurve)],
    step_deg: f64,
) -> Result<String, Error> {
    let table = run_cycle(model, params, &chart_cycle(step_deg))?;
    let measured = match_measured(&table, curves)?;
    Ok(plots::take_up_with_measured(model, &table, &measured)?.render())
}
