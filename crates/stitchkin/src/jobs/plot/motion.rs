//! The cycles of a motion-law chart: the series a request names resolved
//! to columns of the cycle table, over one cycle or over the values of a
//! varied parameter (seed 002 Fig. 3, seed 003 Fig. 8, seed 000 Fig. 6).

use super::check_vary;
use super::family::run_grid;
use crate::error::{Error, Input, did_you_mean};
use crate::eval::{CycleOptions, CycleTable, run_cycle};
use crate::model::{Model, Params};
use crate::output::plots::motion::split_unit;
use crate::output::plots::{MotionSeries, VaryGrid, closed, column, param_error};
use crate::study::design::Vary;

/// The series `wanted` over one cycle at `params`, φ every `step_deg`:
/// the closed φ and each series' one row. A series is a column name of
/// the cycle table (`G.y_mm`, `angle_C_B_deg`, `needle_y_mm`,
/// `G.dy_dphi_mm_per_rad`) or that name without its unit ending (`G.y`);
/// one named twice is drawn once. A name that matches nothing is an error
/// listing what the model offers.
pub fn motion_cycle(
    model: &Model,
    params: &Params,
    wanted: &[String],
    step_deg: f64,
) -> Result<(Vec<f64>, Vec<MotionSeries>), Error> {
    let (columns, _, table) = resolve(model, params, wanted, step_deg)?;
    let phis = column(&table, "phi_deg")?;
    let series = columns
        .iter()
        .map(|c| {
            Ok(MotionSeries::new(
                c,
                vec![Some(closed_values(phis, column(&table, c)?))],
            ))
        })
        .collect::<Result<_, Error>>()?;
    Ok((closed(phis, phis).into_iter().map(|q| q.0).collect(), series))
}

/// The series `wanted` (as for [`motion_cycle`]) over one cycle for each
/// of the N values of `vary`, the cycles run in parallel; a value whose
/// cycle fails is a gap (`None`) noted in the grid.
pub fn motion_family(
    model: &Model,
    params: &Params,
    wanted: &[String],
    vary: &Vary,
    step_deg: f64,
) -> Result<(VaryGrid, Vec<MotionSeries>), Error> {
    check_vary(model, vary)?;
    // The names are resolved on a one-row cycle at the parameters as set.
    let (columns, mut opts, _) = resolve(model, params, wanted, 360.0)?;
    opts.step_deg = step_deg;
    let (grid, runs) = run_grid(model, params, vary, &opts)?;
    let series = columns
        .iter()
        .map(|c| {
            let rows = runs
                .iter()
                .map(|run| {
                    run.as_ref()
                        .map(|t| Ok(closed_values(column(t, "phi_deg")?, column(t, c)?)))
                        .transpose()
                })
                .collect::<Result<_, Error>>()?;
            Ok(MotionSeries::new(c, rows))
        })
        .collect::<Result<_, Error>>()?;
    Ok((grid, series))
}

/// The values of `values` over the cycle, closed at φ_start + 360°.
fn closed_values(phis: &[f64], values: &[f64]) -> Vec<f64> {
    closed(phis, values).into_iter().map(|q| q.1).collect()
}

/// The column `wanted` names among `columns`: itself, or the one column
/// that is `wanted` with a unit ending (`G.y` → `G.y_mm`).
fn find_column<'a>(columns: &[&'a str], wanted: &str) -> Result<Option<&'a str>, Error> {
    if let Some(c) = columns.iter().find(|c| **c == wanted) {
        return Ok(Some(c));
    }
    let hits: Vec<&str> = columns
        .iter()
        .copied()
        .filter(|c| matches!(split_unit(c), (base, u) if !u.is_empty() && base == wanted))
        .collect();
    match hits.as_slice() {
        [] => Ok(None),
        [one] => Ok(Some(one)),
        many => Err(param_error(
            Input::Series,
            format!("`{wanted}` names {} columns: {}", many.len(), many.join(", ")),
            "give the whole name with its unit".into(),
        )),
    }
}

/// The cycle options to try, the cheapest first: every moving point's
/// coordinates, the link and transmission angles and the measures; then
/// also the analogs and, at the model's speed (`rpm`), the velocities and
/// accelerations, as `stitchkin run` writes them.
fn option_levels(model: &Model, step_deg: f64) -> [CycleOptions; 2] {
    let points: Vec<usize> = (0..model.point_names.len()).filter(|&i| !model.is_fixed(i)).collect();
    let plain = CycleOptions {
        step_deg,
        rpm: None,
        analogs: false,
        points: Some(points),
        lean: false,
    };
    let full = CycleOptions {
        rpm: model.rpm(),
        analogs: true,
        ..plain.clone()
    };
    [plain, full]
}

/// Runs the cycle at `params` with the cheapest options whose table has
/// every series of `wanted`; returns their columns (each once), those
/// options and the table.
fn resolve(
    model: &Model,
    params: &Params,
    wanted: &[String],
    step_deg: f64,
) -> Result<(Vec<String>, CycleOptions, CycleTable), Error> {
    let [plain, full] = option_levels(model, step_deg);
    if !wanted.is_empty() {
        let table = run_cycle(model, params, &plain)?;
        if let (found, None) = find_all(&table, wanted)? {
            return Ok((found, plain, table));
        }
    }
    let table = run_cycle(model, params, &full)?;
    match find_all(&table, wanted)? {
        _ if wanted.is_empty() => Err(param_error(
            Input::Series,
            "no series to draw".into(),
            format!("name them, e.g. {}; {}", example(model), offered(model, &table)),
        )),
        (found, None) => Ok((found, full, table)),
        (_, Some(missing)) => {
            let names: Vec<&str> = table
                .columns
                .iter()
                .map(|c| c.name.as_str())
                .filter(|n| *n != "phi_deg")
                .collect();
            let shorts: Vec<&str> = names.iter().map(|n| split_unit(n).0).collect();
            let hint = did_you_mean(missing, names.iter().chain(&shorts).copied())
                .map(|s| format!(" (did you mean `{s}`?)"))
                .unwrap_or_default();
            Err(param_error(
                Input::Series,
                format!("the model has no series `{missing}`{hint}"),
                offered(model, &table),
            ))
        }
    }
}

/// The columns of `table` that `wanted` names (each once, φ not among
/// them) and the first name that matches none.
fn find_all<'w>(table: &CycleTable, wanted: &'w [String]) -> Result<(Vec<String>, Option<&'w str>), Error> {
    let names: Vec<&str> = table
        .columns
        .iter()
        .map(|c| c.name.as_str())
        .filter(|n| *n != "phi_deg")
        .collect();
    let mut found: Vec<String> = Vec::new();
    for w in wanted {
        if w.trim().is_empty() {
            return Err(param_error(
                Input::Series,
                "an empty name".into(),
                "separate the names by single commas, e.g. G.y,E.y".into(),
            ));
        }
        if find_column(&["phi_deg"], w)?.is_some() {
            return Err(param_error(
                Input::Series,
                format!("`{w}` is φ itself, the x axis of every motion chart"),
                "name what to draw against φ, e.g. a point coordinate, an angle or a measure".into(),
            ));
        }
        match find_column(&names, w)? {
            Some(c) if found.iter().any(|f| f == c) => {}
            Some(c) => found.push(c.to_string()),
            None => return Ok((found, Some(w))),
        }
    }
    Ok((found, None))
}

/// `G.y`: a coordinate of the model's first moving point.
fn example(model: &Model) -> String {
    model
        .moving_point_names()
        .first()
        .map_or_else(|| "NAME".to_string(), |p| format!("{p}.y"))
}

/// What the model offers to draw, for an error's help.
fn offered(model: &Model, table: &CycleTable) -> String {
    let axes = if model.planar { "x_mm, y_mm" } else { "x_mm, y_mm, z_mm" };
    let scalars: Vec<&str> = table
        .columns
        .iter()
        .map(|c| c.name.as_str())
        .filter(|n| !n.contains('.') && *n != "phi_deg")
        .collect();
    let scalars = if scalars.is_empty() {
        String::new()
    } else {
        format!("; the angles and measures {}", scalars.join(", "))
    };
    let example = example(model);
    format!(
        "its series are the coordinates {axes} of the moving points {} (`{example}_mm`, or without the unit `{example}`){scalars}; and every other column of `stitchkin run` (analogs, thread and stitch columns)",
        model.moving_point_names().join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_names_find_their_column_once() {
        let cols = [
            "G.y_mm",
            "G.dy_dphi_mm_per_rad",
            "needle_y_mm",
            "needle_y.d_dphi_mm_per_rad",
            "twice_mm",
            "twice_deg",
        ];
        assert_eq!(find_column(&cols, "G.y").unwrap(), Some("G.y_mm"));
        assert_eq!(find_column(&cols, "G.y_mm").unwrap(), Some("G.y_mm"));
        assert_eq!(find_column(&cols, "G.dy_dphi").unwrap(), Some("G.dy_dphi_mm_per_rad"));
        assert_eq!(find_column(&cols, "needle_y").unwrap(), Some("needle_y_mm"));
        assert_eq!(find_column(&cols, "needle").unwrap(), None);
        assert_eq!(find_column(&cols, "G").unwrap(), None);
        let e = find_column(&cols, "twice").unwrap_err().to_string();
        assert!(e.contains("names 2 columns: twice_mm, twice_deg"), "{e}");
    }
}
