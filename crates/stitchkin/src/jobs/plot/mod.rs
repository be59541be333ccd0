//! The plot job of `stitchkin plot` (docs/plots.md): a [`Plot`] request
//! checked, its cycles, sweep, tuning or comparison computed, and the chart
//! drawn by [`crate::output::plots`] as an SVG document.

use crate::error::{Error, Input};
use crate::eval::{CycleOptions, check_options};
use crate::model::{Model, Params};
use crate::output::plots::{self, no_threads, param_error};
use crate::study::compare_2d3d::{Comparison, compare_2d3d};
use crate::study::design::Vary;
use crate::study::nomogram::{Nomogram, NomogramOptions, nomogram};

mod cycle;
mod family;
mod heatmap;
mod motion;

pub use cycle::{analogs_cycle, render_take_up_with_measured};
pub use family::family_data;
pub use heatmap::{figure_grid, figure_names};
pub use motion::{motion_cycle, motion_family};

/// What to plot.
#[derive(Debug, Clone, PartialEq)]
pub enum Plot {
    /// P(φ) of every thread path, P'(φ) of every stitch thread (dashed),
    /// the one-sided guides' engaged intervals shaded.
    TakeUp,
    /// Every transmission angle over φ against the 30°…150° band.
    Mu,
    /// The thread's tension T(φ) at the eye and in the stitch of every
    /// stitch thread whose path carries thread physics, with the stretches
    /// where thread passes the regulator (docs/thread-physics.md).
    Tension,
    /// The path of each named point over the cycle, to scale, in the
    /// xy-plane of frame `plane` (`None`: the world's).
    Trajectory { points: Vec<String>, plane: Option<String> },
    /// Velocity and acceleration analogs over φ, in two panels: of each
    /// named point (dx/dφ, … in mm/rad; d²x/dφ², … in mm/rad²), or, with
    /// no points, dP/dφ and d²P/dφ² of the thread paths `threads` (empty:
    /// every path).
    Analogs { points: Vec<String>, threads: Vec<String> },
    /// P(φ) of one thread path (`None`: the model's first) for each of the
    /// N values of a parameter, as a family of lines, with the P'(φ) of
    /// the stitch thread on that path (seed 000 Fig. 7).
    Family { vary: Vary, thread: Option<String> },
    /// The same data as [`Plot::Family`] as a heat map of P over (φ, the
    /// parameter) with a colour bar, or with `wireframe` as a projected
    /// surface (seed 000 Fig. 7 a, c, e, g, i, the spatial charts).
    Surface {
        vary: Vary,
        thread: Option<String>,
        wireframe: bool,
    },
    /// The motion law of each series over φ: a column of the cycle table
    /// (`G.y_mm`, `angle_O2_B_deg`, `needle_y_mm`, `mu_23_deg`,
    /// `G.dy_dphi_mm_per_rad`; the unit ending may be left off), one panel
    /// per unit; with `vary`, one panel per series with a line per value
    /// of the parameter (seed 002 Fig. 3, seed 003 Fig. 8).
    Motion { series: Vec<String>, vary: Option<Vary> },
    /// One motion-law series over (φ, a varied parameter) as a heat map
    /// or, with `wireframe`, a projected surface (seed 000 Fig. 6).
    MotionSurface {
        series: String,
        vary: Vary,
        wireframe: bool,
    },
    /// One figure of merit of [`crate::study::figures::figures`] (a pattern
    /// matching exactly one) over the grid of two varied parameters, as a
    /// heat map with a colour bar.
    Heatmap { vary: Vec<Vary>, figure: String },
    /// The tuned setting(s) of [`crate::study::nomogram::nomogram`] against
    /// the material thickness m, one line per stitch length t, one panel
    /// per adjusted parameter. The plot's step replaces the options' φ step.
    Nomogram(NomogramOptions),
    /// P_2D and P_3D of each thread path (`threads`; empty: every path)
    /// and their difference ΔP(φ), the 2D model on the xy-plane of frame
    /// `plane` (seed 000 Fig. 9; [`crate::study::compare_2d3d`]).
    Delta2d3d { plane: String, threads: Vec<String> },
}

impl Plot {
    /// The kind's name on the command line (`takeup`, `family`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            Plot::TakeUp => "takeup",
            Plot::Mu => "mu",
            Plot::Tension => "tension",
            Plot::Trajectory { .. } => "trajectory",
            Plot::Analogs { .. } => "analogs",
            Plot::Family { .. } => "family",
            Plot::Surface { .. } | Plot::MotionSurface { .. } => "surface",
            Plot::Motion { .. } => "motion",
            Plot::Heatmap { .. } => "heatmap",
            Plot::Nomogram(_) => "nomogram",
            Plot::Delta2d3d { .. } => "delta2d3d",
        }
    }
}

/// Computes and draws `plot` of the model at `params`, φ every
/// `step_deg`, as an SVG document. Bad input (an unknown point, path,
/// parameter or figure, a parameter range outside the adjustable one, …)
/// is an error naming the option at fault and what to do instead.
pub fn render(model: &Model, params: &Params, plot: &Plot, step_deg: f64) -> Result<String, Error> {
    check_options(&CycleOptions {
        step_deg,
        ..Default::default()
    })?;
    match plot {
        Plot::TakeUp | Plot::Mu | Plot::Tension | Plot::Trajectory { .. } => {
            cycle::cycle_chart(model, params, plot, step_deg).map(|c| c.render())
        }
        Plot::Analogs { points, threads } => {
            let (table, paths) = analogs_cycle(model, params, points, threads, step_deg)?;
            plots::analogs(model, &table, points, &paths).map(|f| f.render())
        }
        Plot::Family { vary, thread } => {
            let data = family_data(model, params, vary, thread.as_deref(), step_deg)?;
            plots::family(model, &data).map(|c| c.render())
        }
        Plot::Surface {
            vary,
            thread,
            wireframe,
        } => {
            let data = family_data(model, params, vary, thread.as_deref(), step_deg)?;
            Ok(plots::surface(model, &data.grid, &data.quantity(), &data.p, *wireframe))
        }
        Plot::Motion { series, vary: None } => {
            let (phis, series) = motion_cycle(model, params, series, step_deg)?;
            Ok(plots::motion_chart(model, &phis, &series).render())
        }
        Plot::Motion {
            series,
            vary: Some(vary),
        } => {
            let (grid, series) = motion_family(model, params, series, vary, step_deg)?;
            Ok(plots::motion_family_chart(model, &grid, &series).render())
        }
        Plot::MotionSurface {
            series: name,
            vary,
            wireframe,
        } => {
            let (grid, series) = motion_family(model, params, std::slice::from_ref(name), vary, step_deg)?;
            let s = series
                .first()
                .ok_or_else(|| Error::Internal(format!("no rows for series `{name}`")))?;
            Ok(plots::surface(model, &grid, &s.quantity(), &s.rows, *wireframe))
        }
        Plot::Heatmap { vary, figure } => {
            let grid = figure_grid(model, params, vary, figure, step_deg)?;
            Ok(plots::heatmap(model, &grid).render())
        }
        Plot::Nomogram(opts) => {
            let mut opts = opts.clone();
            opts.tune.step_deg = step_deg;
            Ok(plots::nomogram_figure(&chart_nomogram(model, params, &opts)?).render())
        }
        Plot::Delta2d3d { plane, threads } => {
            let (c, paths) = comparison(model, params, plane, threads, step_deg)?;
            plots::delta_2d3d(model, &c, &paths).map(|f| f.render())
        }
    }
}

/// The nomogram of a chart: at least two thicknesses, then tuned over the
/// grid of `opts`.
fn chart_nomogram(model: &Model, params: &Params, opts: &NomogramOptions) -> Result<Nomogram, Error> {
    if opts.thickness.n < 2 {
        return Err(param_error(
            Input::Thickness,
            format!(
                "one thickness ({} mm) is given; a nomogram chart needs at least 2",
                opts.thickness.lo
            ),
            "give a range, e.g. 1:5:5 (or tune at one thickness)".into(),
        ));
    }
    nomogram(model, params, opts, || {})
}

/// The 2D-vs-3D comparison on the xy-plane of frame `plane` and the thread
/// paths to draw (`threads`; empty: every path).
fn comparison(
    model: &Model,
    params: &Params,
    plane: &str,
    threads: &[String],
    step_deg: f64,
) -> Result<(Comparison, Vec<String>), Error> {
    let paths = select_paths(model, threads)?;
    let c = compare_2d3d(model, params, plane, step_deg)?;
    Ok((c, paths))
}

/// The thread paths `wanted` (`--thread`; empty: all), checked against the
/// model.
fn select_paths(model: &Model, wanted: &[String]) -> Result<Vec<String>, Error> {
    let all: Vec<String> = model.thread_path_names().into_iter().map(String::from).collect();
    if all.is_empty() {
        return Err(no_threads(model));
    }
    for w in wanted {
        if !all.contains(w) {
            return Err(param_error(
                Input::Thread,
                format!("the model has no thread path `{w}`"),
                format!("its thread paths are: {}", all.join(", ")),
            ));
        }
    }
    Ok(if wanted.is_empty() { all } else { wanted.to_vec() })
}

/// The unit of parameter `name` as charts write it (`mm`, `deg`; empty for
/// a plain number).
fn param_unit(model: &Model, name: &str) -> &'static str {
    match model.param_index(name).map(|i| model.params[i].unit_str()) {
        Some("1") | None => "",
        Some(u) => u,
    }
}

/// Checks a varied parameter for a chart: at least two values, both ends
/// settable. Errors name the varied parameter and the fix.
fn check_vary(model: &Model, vary: &Vary) -> Result<(), Error> {
    let spec = format!("{}={}:{}:{}", vary.name, vary.lo, vary.hi, vary.n);
    if vary.n < 2 {
        return Err(param_error(
            Input::Vary,
            format!("`{spec}` gives one value; a chart needs at least 2"),
            format!("give N ≥ 2, e.g. {}={}:{}:5", vary.name, vary.lo, vary.hi),
        ));
    }
    if vary.n > 1001 {
        return Err(param_error(
            Input::Vary,
            format!("`{spec}` gives {} values", vary.n),
            "at most 1001 values per parameter in a chart".into(),
        ));
    }
    if !(vary.lo.is_finite() && vary.hi.is_finite()) || vary.lo == vary.hi {
        return Err(param_error(
            Input::Vary,
            format!("`{spec}`: the range is empty"),
            "give two different ends, LO:HI:N".into(),
        ));
    }
    let mut p = model.defaults();
    for v in [vary.lo, vary.hi] {
        model
            .set(&mut p, &vary.name, v)
            .map_err(|e| Error::Param(e.in_input(Input::Vary)))?;
    }
    Ok(())
}

/// Parses `--vary NAME=LO:HI[:N]` for a chart: N defaults to `default_n`;
/// unknown parameters and ends outside the adjustable range are errors
/// of [`Input::Vary`].
pub fn parse_vary(model: &Model, spec: &str, default_n: usize) -> Result<Vary, Error> {
    let mut v = Vary::parse(model, spec)?;
    if spec.split_once('=').is_some_and(|(_, r)| r.split(':').count() == 2) {
        v.n = default_n;
    }
    Ok(v)
}

/// The model's moving points, for a help text.
fn moving_points(model: &Model) -> String {
    model.moving_point_names().join(", ")
}
