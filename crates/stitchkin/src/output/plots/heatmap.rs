//! One figure of merit over a grid of two parameters, as a heat map with
//! a colour bar (the sweep of `stitchkin sweep`, drawn).

use super::{number_text, title, unit_label, value_text};
use crate::model::Model;
use crate::output::svg::{Axis, Chart, Heat, Marker, nice_step};
use crate::study::design::Vary;
use crate::study::sweep::Row;

/// One figure of merit evaluated over the grid of two varied parameters:
/// what a heat map draws.
#[derive(Debug, Clone)]
pub struct FigureGrid {
    /// The figure of merit (`n1_A.max_P_B_mm`).
    pub figure: String,
    /// The parameter across (x) and its unit (`mm`, `deg`, or empty), its
    /// values ascending.
    pub across: Vary,
    pub across_unit: &'static str,
    /// The parameter up (y) and its unit, its values ascending.
    pub up: Vary,
    pub up_unit: &'static str,
    /// The sweep's rows with the one figure, the parameter up running
    /// fastest: setting i·n_up + j is value i across and value j up.
    pub rows: Vec<Row>,
    /// The φ step of every cycle, degrees.
    pub step_deg: f64,
}

/// The colour-bar label of a figure of merit: its name with the unit split
/// off (`n1_A.max_P, mm`), a score's scale (`n1.score (0…100)`).
pub fn figure_label(name: &str) -> String {
    if let Some(base) = name.strip_suffix("_mm") {
        format!("{base}, mm")
    } else if let Some(base) = name.strip_suffix("_deg") {
        format!("{base}, deg")
    } else if name.ends_with(".score") || name.starts_with("score.") {
        format!("{name} (0…100)")
    } else if name == "mu.ok" {
        "mu.ok (1: every μ inside 30°…150°)".into()
    } else {
        name.to_string()
    }
}

/// The heat map of the grid: the first parameter across, the second up.
/// Cells that did not evaluate are grey; the smallest and largest value
/// are marked.
pub fn heatmap(model: &Model, g: &FigureGrid) -> Chart {
    let (a, b, name) = (&g.across, &g.up, &g.figure);
    let (ua, ub) = (g.across_unit, g.up_unit);
    let xs: Vec<f64> = (0..a.n).map(|i| a.grid_value(i)).collect();
    let ys: Vec<f64> = (0..b.n).map(|j| b.grid_value(j)).collect();
    let (da, db) = ((a.hi - a.lo) / (a.n - 1) as f64, (b.hi - b.lo) / (b.n - 1) as f64);
    let at = |i: usize, j: usize| {
        format!(
            "{}, {}",
            value_text(&a.name, xs[i], da, ua),
            value_text(&b.name, ys[j], db, ub)
        )
    };
    // The grid runs the last parameter fastest: setting i·n_b + j.
    let cell = |i: usize, j: usize| &g.rows[i * b.n + j];
    let z: Vec<Vec<f64>> = (0..b.n)
        .map(|j| (0..a.n).map(|i| cell(i, j).figures[0].unwrap_or(f64::NAN)).collect())
        .collect();
    let fmt = value_format(name);
    let tips = (0..b.n)
        .map(|j| {
            (0..a.n)
                .map(|i| match (cell(i, j).figures[0], &cell(i, j).error) {
                    (Some(v), _) => format!("{}: {name} = {}", at(i, j), fmt(v)),
                    (None, Some(e)) => format!("{}: no value ({e})", at(i, j)),
                    (None, None) => format!("{}: no value", at(i, j)),
                })
                .collect()
        })
        .collect();
    let half = |d: f64| d / 2.0;
    let x = Axis {
        label: unit_label(&a.name, ua),
        range: Some((a.lo - half(da), a.hi + half(da))),
        step: Some(nice_step(a.hi - a.lo, 8)),
    };
    let y = Axis {
        label: unit_label(&b.name, ub),
        range: Some((b.lo - half(db), b.hi + half(db))),
        step: Some(nice_step(b.hi - b.lo, 6)),
    };
    let mut chart = Chart::new(title(model, &format!("{name} over {} and {}", a.name, b.name)), x, y);
    let missing = z.iter().flatten().filter(|v| !v.is_finite()).count();
    chart.markers = extremes(&z, &xs, &ys, &fmt, &at);
    chart.heat = Some(Heat {
        xs,
        ys,
        z,
        label: figure_label(name),
        tips,
        missing: "no value".into(),
    });
    let mut sub = format!(
        "{} × {} settings, φ every {}°, the rest as set; colour: {name}",
        a.n, b.n, g.step_deg
    );
    if missing > 0 {
        sub += &format!("; grey: {missing} without a value");
    }
    chart.subtitle = Some(sub);
    chart
}

/// How a value of the figure `name` is written: three decimals and the
/// unit of its colour-bar label.
fn value_format(name: &str) -> impl Fn(f64) -> String {
    let unit = figure_label(name)
        .rsplit_once(", ")
        .map(|(_, u)| format!(" {u}"))
        .unwrap_or_default();
    move |v: f64| format!("{}{unit}", number_text(v, 0.001, ""))
}

/// The markers of the largest and the smallest value of `z` (rows up,
/// columns across), `at` naming the setting of a cell.
fn extremes(
    z: &[Vec<f64>],
    xs: &[f64],
    ys: &[f64],
    fmt: &impl Fn(f64) -> String,
    at: &impl Fn(usize, usize) -> String,
) -> Vec<Marker> {
    let cells = || {
        (0..xs.len())
            .flat_map(|i| (0..ys.len()).map(move |j| (i, j)))
            .filter(|&(i, j)| z[j][i].is_finite())
    };
    let lowest = cells().min_by(|p, q| z[p.1][p.0].total_cmp(&z[q.1][q.0]));
    let highest = cells().max_by(|p, q| z[p.1][p.0].total_cmp(&z[q.1][q.0]));
    let mut markers = Vec::new();
    for (what, c, colour) in [("max", highest, "#e15759"), ("min", lowest, "#ffffff")] {
        if let Some((i, j)) = c {
            let v = z[j][i];
            markers.push(Marker {
                x: xs[i],
                y: ys[j],
                color: colour.into(),
                label: format!("{what}: {}, at {}", fmt(v), at(i, j)),
                legend: Some(format!("{what} {}", fmt(v))),
            });
        }
    }
    markers
}
