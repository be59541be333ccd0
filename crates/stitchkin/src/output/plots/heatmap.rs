//! One figure of merit over a grid of two parameters, as a heat map with
//! a colour bar (the sweep of `stitchkin sweep`, drawn).

use super::{check_vary, number_text, param_error, param_unit, title, unit_label, value_text};
use crate::error::Error;
use crate::eval::{CycleOptions, run_cycle};
use crate::model::{Model, Params};
use crate::output::svg::{Axis, Chart, Heat, Marker, nice_step};
use crate::study::design::{Design, Sweep, Vary};
use crate::study::figures::{figures, select_figures, shared_stitch};
use crate::study::sweep;

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

/// Evaluates the grid of the two `vary` parameters (in parallel, as
/// `stitchkin sweep`) and draws the figure matching `figure` as a heat
/// map: the first parameter across, the second up. Cells that did not
/// evaluate are grey; the smallest and largest value are marked.
pub fn heatmap(model: &Model, params: &Params, vary: &[Vary], figure: &str, step_deg: f64) -> Result<Chart, Error> {
    let vary = ordered_pair(model, vary)?;
    let opts = CycleOptions {
        step_deg,
        analogs: false,
        points: None,
        lean: true,
        ..Default::default()
    };
    let name = one_figure(model, params, &opts, figure)?;
    let rows = grid_rows(model, params, &vary, &name, &opts)?;
    let (a, b) = (&vary[0], &vary[1]);
    let (ua, ub) = (param_unit(model, &a.name), param_unit(model, &b.name));
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
    let cell = |i: usize, j: usize| &rows[i * b.n + j];
    let z: Vec<Vec<f64>> = (0..b.n)
        .map(|j| (0..a.n).map(|i| cell(i, j).figures[0].unwrap_or(f64::NAN)).collect())
        .collect();
    let unit = figure_label(&name)
        .rsplit_once(", ")
        .map(|(_, u)| format!(" {u}"))
        .unwrap_or_default();
    let fmt = |v: f64| format!("{}{unit}", number_text(v, 0.001, ""));
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
    mark_extremes(&mut chart, &z, &xs, &ys, &fmt, &at);
    chart.heat = Some(Heat {
        xs,
        ys,
        z,
        label: figure_label(&name),
        tips,
        missing: "no value".into(),
    });
    let mut sub = format!(
        "{} × {} settings, φ every {step_deg}°, the rest as set; colour: {name}",
        a.n, b.n
    );
    if missing > 0 {
        sub += &format!("; grey: {missing} without a value");
    }
    chart.subtitle = Some(sub);
    Ok(chart)
}

/// The two varied parameters, distinct and each checked, their ranges
/// ordered low to high.
fn ordered_pair(model: &Model, vary: &[Vary]) -> Result<Vec<Vary>, Error> {
    if vary.len() != 2 {
        return Err(param_error(
            format!("`plot heatmap` needs exactly 2 --vary, got {}", vary.len()),
            "give two parameters, e.g. --vary z=-10:10:11 --vary dphi=-20:20:11 (the first across, the second up)"
                .into(),
        ));
    }
    if vary[0].name == vary[1].name {
        return Err(param_error(
            format!("`{}` is varied twice (in --vary)", vary[0].name),
            "vary two different parameters".into(),
        ));
    }
    let vary: Vec<Vary> = vary
        .iter()
        .map(|v| Vary {
            name: v.name.clone(),
            lo: v.lo.min(v.hi),
            hi: v.lo.max(v.hi),
            n: v.n,
        })
        .collect();
    for v in &vary {
        check_vary(model, v)?;
    }
    Ok(vary)
}

/// The one figure of merit `figure` names, at the nominal setting.
fn one_figure(model: &Model, params: &Params, opts: &CycleOptions, figure: &str) -> Result<String, Error> {
    let nominal = run_cycle(model, params, opts)?;
    let names = select_figures(&figures(&nominal), &[figure.to_string()]).map_err(|e| match e {
        Error::Param(mut p) => {
            p.message += " (in --figure)";
            Error::Param(p)
        }
        e => e,
    })?;
    match names.as_slice() {
        [one] => Ok(one.clone()),
        many => Err(param_error(
            format!(
                "--figure `{figure}` matches {} figures of merit; a heat map shows one",
                many.len()
            ),
            format!("name one of: {}", many.join(", ")),
        )),
    }
}

/// Figure `name` at every setting of the grid over `vary` (in parallel,
/// as `stitchkin sweep`), the last parameter fastest.
fn grid_rows(
    model: &Model,
    params: &Params,
    vary: &[Vary],
    name: &str,
    opts: &CycleOptions,
) -> Result<Vec<sweep::Row>, Error> {
    let sw = Sweep::new(vary.to_vec(), Design::Grid)?;
    let shared = shared_stitch(model, params, &sw, opts.step_deg)?;
    let mut rows = Vec::with_capacity(sw.len());
    sweep::run(
        model,
        params,
        &sw,
        &[name.to_string()],
        opts,
        shared.as_ref(),
        0..sw.len(),
        |r| -> Result<(), Error> {
            rows.push(r.clone());
            Ok(())
        },
        |_| {},
    )?;
    Ok(rows)
}

/// The smallest and largest value of the heat map `z`, marked.
fn mark_extremes(
    chart: &mut Chart,
    z: &[Vec<f64>],
    xs: &[f64],
    ys: &[f64],
    fmt: &dyn Fn(f64) -> String,
    at: &dyn Fn(usize, usize) -> String,
) {
    let (na, nb) = (xs.len(), ys.len());
    let cells = || {
        (0..na)
            .flat_map(|i| (0..nb).map(move |j| (i, j)))
            .filter(|&(i, j)| z[j][i].is_finite())
    };
    let lowest = cells().min_by(|p, q| z[p.1][p.0].total_cmp(&z[q.1][q.0]));
    let highest = cells().max_by(|p, q| z[p.1][p.0].total_cmp(&z[q.1][q.0]));
    for (what, c, colour) in [("max", highest, "#e15759"), ("min", lowest, "#ffffff")] {
        if let Some((i, j)) = c {
            let v = z[j][i];
            chart.markers.push(Marker {
                x: xs[i],
                y: ys[j],
                color: colour.into(),
                label: format!("{what}: {}, at {}", fmt(v), at(i, j)),
                legend: Some(format!("{what} {}", fmt(v))),
            });
        }
    }
}

/// The names of the figures of merit the model offers at `params` (what
/// `--figure` may name).
pub fn figure_names(model: &Model, params: &Params, step_deg: f64) -> Result<Vec<String>, Error> {
    let opts = CycleOptions {
        step_deg,
        analogs: false,
        points: None,
        lean: true,
        ..Default::default()
    };
    Ok(figures(&run_cycle(model, params, &opts)?)
        .into_iter()
        .map(|(n, _)| n)
        .collect())
}
