//! Velocity and acceleration analogs over φ: of chosen points, or dP/dφ
//! and d²P/dφ² of the thread paths. Two panels, one per order.

use super::{closed, column, phi_axis, title};
use crate::error::Error;
use crate::eval::CycleTable;
use crate::model::Model;
use crate::output::svg::{Axis, Chart, Figure, Series, color};

/// Height of each of the two panels.
const PANEL_H: f64 = 330.0;

/// The analog chart of a cycle run with analogs. With `points`, the first
/// and second analogs of each point's coordinates (x, y and, for a spatial
/// model, z; mm/rad and mm/rad²); without, those of the take-up P of the
/// thread paths `paths`.
pub fn analogs(model: &Model, table: &CycleTable, points: &[String], paths: &[String]) -> Result<Figure, Error> {
    let phis = column(table, "phi_deg")?;
    let lines = analog_lines(table, points, paths);
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
            .push(Series::new(n1.clone(), closed(phis, column(table, c1)?), color(i)));
        second
            .series
            .push(Series::new(n2.clone(), closed(phis, column(table, c2)?), color(i)));
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

/// (first-analog legend, second-analog legend, first-analog column,
/// second-analog column) per line of the chart.
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
