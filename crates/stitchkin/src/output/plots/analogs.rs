//! Velocity and acceleration analogs over φ: of chosen points, or dP/dφ
//! and d²P/dφ² of the thread paths. Two panels, one per order.

use super::{closed, column, param_error, phi_axis, point_slots, select_paths, title};
use crate::error::Error;
use crate::eval::{CycleOptions, CycleTable, run_cycle};
use crate::model::{Model, Params};
use crate::output::svg::{Axis, Chart, Figure, Series, color};

/// Height of each of the two panels.
const PANEL_H: f64 = 330.0;

/// The analog chart. With `points`, the first and second analogs of each
/// point's coordinates (x, y and, for a spatial model, z; mm/rad and
/// mm/rad²); without, those of the take-up P of the thread paths
/// `threads` (empty: every path).
pub fn analogs(
    model: &Model,
    params: &Params,
    points: &[String],
    threads: &[String],
    step_deg: f64,
) -> Result<Figure, Error> {
    if !points.is_empty() && !threads.is_empty() {
        return Err(param_error(
            "`plot analogs` draws either points (--points) or thread paths (--thread), not both".into(),
            "leave out one of them: --points A,B for the points' analogs, --thread PATH for dP/dφ".into(),
        ));
    }
    if points.is_empty() && !model.has_threads() {
        return Err(param_error(
            format!(
                "model `{}` has no thread paths, so `plot analogs` needs points",
                model.name()
            ),
            format!(
                "name them with --points A,B; the moving points are: {}",
                super::moving_points(model)
            ),
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
    let table = run_cycle(
        model,
        params,
        &CycleOptions {
            step_deg,
            analogs: true,
            points: Some(slots),
            lean: true,
            ..Default::default()
        },
    )?;
    let phis = column(&table, "phi_deg")?;
    let lines = analog_lines(&table, points, &paths);
    let (what, y1, y2) = if points.is_empty() {
        (
            format!("take-up analogs of {}", paths.join(", ")),
            "dP/dφ, mm/rad",
            "d²P/dφ², mm/rad²",
        )
    } else {
        (
            format!("velocity and acceleration analogs of {}", points.join(", ")),
            "velocity analog, mm/rad",
            "acceleration analog, mm/rad²",
        )
    };
    let mut first = Chart::new(
        if points.is_empty() {
            "first analog dP/dφ (thread speed per unit shaft speed)"
        } else {
            "first analogs dx/dφ, dy/dφ, dz/dφ (velocity per unit shaft speed)"
        },
        phi_axis(model),
        Axis::new(y1),
    );
    let mut second = Chart::new(
        if points.is_empty() {
            "second analog d²P/dφ²"
        } else {
            "second analogs d²x/dφ², … (acceleration per unit shaft speed squared)"
        },
        phi_axis(model),
        Axis::new(y2),
    );
    for (i, (n1, n2, c1, c2)) in lines.iter().enumerate() {
        first
            .series
            .push(Series::new(n1.clone(), closed(phis, column(&table, c1)?), color(i)));
        second
            .series
            .push(Series::new(n2.clone(), closed(phis, column(&table, c2)?), color(i)));
    }
    first.height = PANEL_H;
    second.height = PANEL_H;
    let mut fig = Figure::new(title(model, &what));
    fig.subtitle = Some(
        "derivatives with respect to the main-shaft angle φ: times ω = πn/30 gives mm/s, times ω² gives mm/s²".into(),
    );
    fig.panels = vec![first, second];
    Ok(fig)
}

/// (legend of the first panel, of the second, first-analog column,
/// second-analog column) per line: each point's coordinates, then each
/// path's take-up.
fn analog_lines(table: &CycleTable, points: &[String], paths: &[String]) -> Vec<(String, String, String, String)> {
    let mut lines: Vec<(String, String, String, String)> = Vec::new();
    for p in points {
        for a in ["x", "y", "z"] {
            let d1 = format!("{p}.d{a}_dphi_mm_per_rad");
            if table.column(&d1).is_some() {
                lines.push((
                    format!("{p} d{a}/dφ"),
                    format!("{p} d²{a}/dφ²"),
                    d1,
                    format!("{p}.d2{a}_dphi2_mm_per_rad2"),
                ));
            }
        }
    }
    for p in paths {
        let pn = table
            .paths
            .iter()
            .find(|q| &q.path == p)
            .map_or("P", |q| q.take_up_name());
        lines.push((
            p.clone(),
            p.clone(),
            format!("{p}.d{pn}_dphi_mm_per_rad"),
            format!("{p}.d2{pn}_dphi2_mm_per_rad2"),
        ));
    }
    lines
}
