//! The plots of `stitchkin plot` (docs/plots.md), as SVG charts built with
//! [`super::svg`]: of one cycle, the take-up P(φ) of every thread path with
//! the stitch's P'(φ), every transmission angle against the 30°…150° band,
//! the trajectories of chosen points and the velocity and acceleration
//! analogs; the motion law of any point coordinate, angle or measure; over
//! a varied parameter, P(φ) or a motion law as a family of lines, a heat
//! map or a projected surface; a figure of merit over two parameters as a
//! heat map; a nomogram; and the 2D-vs-3D take-up difference.

use super::svg::{Axis, Chart, Series, XShade, YBand, color};
use crate::error::{Error, ParamError};
use crate::eval::{CycleOptions, CycleTable, MU_MAX_DEG, MU_MIN_DEG, run_cycle, wrap_deg};
use crate::geometry::{Plane, V3};
use crate::model::{Model, Params};
use crate::study::design::Vary;
use crate::study::measured::MeasuredMatch;
use crate::study::nomogram::NomogramOptions;
use crate::thread::measured::CurveKind;

pub mod analogs;
pub mod delta;
pub mod family;
pub mod heatmap;
pub mod motion;
pub mod nomogram;

pub use crate::study::nomogram::default_thickness;
pub use analogs::analogs;
pub use delta::delta_2d3d;
pub use family::{FamilyData, Quantity, VaryGrid, family, family_data, surface_heat, surface_wireframe};
pub use heatmap::{figure_label, figure_names, heatmap};
pub use motion::{MotionSeries, motion_chart, motion_cycle, motion_family, motion_family_chart};
pub use nomogram::nomogram_chart;

/// What to plot.
#[derive(Debug, Clone, PartialEq)]
pub enum Plot {
    /// P(φ) of every thread path, P'(φ) of every stitch thread (dashed),
    /// the one-sided guides' engaged intervals shaded.
    TakeUp,
    /// Every transmission angle over φ against the 30°…150° band.
    Mu,
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
    /// `plane` (seed 000 Fig. 9; [`crate::study::compare2d3d`]).
    Delta2d3d { plane: String, threads: Vec<String> },
}

impl Plot {
    /// The kind's name on the command line (`takeup`, `family`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            Plot::TakeUp => "takeup",
            Plot::Mu => "mu",
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

fn param_error(message: String, help: String) -> Error {
    Error::Param(ParamError {
        message,
        help: Some(help),
    })
}

/// Draws `plot` of the model at `params`, φ every `step_deg`, as an SVG
/// document. Bad input (an unknown point, path, parameter or figure, a
/// parameter range outside the adjustable one, …) is an error naming the
/// option at fault and what to do instead.
pub fn render(model: &Model, params: &Params, plot: &Plot, step_deg: f64) -> Result<String, Error> {
    crate::eval::check_options(&CycleOptions {
        step_deg,
        ..Default::default()
    })?;
    match plot {
        Plot::TakeUp | Plot::Mu | Plot::Trajectory { .. } => {
            cycle_chart(model, params, plot, step_deg).map(|c| c.render())
        }
        Plot::Analogs { points, threads } => analogs(model, params, points, threads, step_deg).map(|f| f.render()),
        Plot::Family { vary, thread } => {
            family(model, &family_data(model, params, vary, thread.as_deref(), step_deg)?).map(|c| c.render())
        }
        Plot::Surface {
            vary,
            thread,
            wireframe,
        } => {
            let data = family_data(model, params, vary, thread.as_deref(), step_deg)?;
            Ok(surface(model, &data.grid, &data.quantity(), &data.p, *wireframe))
        }
        Plot::Motion { series, vary: None } => {
            let (phis, series) = motion_cycle(model, params, series, step_deg)?;
            Ok(motion_chart(model, &phis, &series).render())
        }
        Plot::Motion {
            series,
            vary: Some(vary),
        } => {
            let (grid, series) = motion_family(model, params, series, vary, step_deg)?;
            Ok(motion_family_chart(model, &grid, &series).render())
        }
        Plot::MotionSurface {
            series: name,
            vary,
            wireframe,
        } => {
            let (grid, series) = motion_family(model, params, std::slice::from_ref(name), vary, step_deg)?;
            let s = series
                .first()
                .ok_or_else(|| Error::Io(format!("no rows for series `{name}` (a bug: please report it)")))?;
            Ok(surface(model, &grid, &s.quantity(), &s.rows, *wireframe))
        }
        Plot::Heatmap { vary, figure } => heatmap(model, params, vary, figure, step_deg).map(|c| c.render()),
        Plot::Nomogram(opts) => {
            let mut opts = opts.clone();
            opts.tune.step_deg = step_deg;
            nomogram_chart(model, params, &opts).map(|f| f.render())
        }
        Plot::Delta2d3d { plane, threads } => delta_2d3d(model, params, plane, threads, step_deg).map(|f| f.render()),
    }
}

/// The heat map or, with `wireframe`, the projected surface of a quantity
/// over φ and a varied parameter, as SVG.
fn surface(model: &Model, grid: &VaryGrid, q: &Quantity, rows: &[Option<Vec<f64>>], wireframe: bool) -> String {
    if wireframe {
        surface_wireframe(model, grid, q, rows).render()
    } else {
        surface_heat(model, grid, q, rows).render()
    }
}

/// The charts of one cycle: take-up, transmission angles, trajectories.
fn cycle_chart(model: &Model, params: &Params, plot: &Plot, step_deg: f64) -> Result<Chart, Error> {
    let mut opts = CycleOptions {
        step_deg,
        analogs: false,
        points: Some(Vec::new()),
        ..Default::default()
    };
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
        Plot::Mu => transmission(model, &table),
        Plot::Trajectory { points, plane } => {
            let frame = match plane {
                None => None,
                Some(name) => Some((
                    name.as_str(),
                    model.frame_index(name).ok_or_else(|| {
                        param_error(
                            format!("the model has no frame `{name}` (in --plane)"),
                            format!("its frames are: {}", model.frame_names().join(", ")),
                        )
                    })?,
                )),
            };
            let frame = match frame {
                Some((name, i)) => Some((name, model.mechanism::<f64>(params)?.frame_plane(i))),
                None => None,
            };
            trajectory(model, &table, points, frame)
        }
        _ => take_up(model, &table),
    }
}

/// The cycle slots of the named moving points (`--points`).
fn point_slots(model: &Model, points: &[String]) -> Result<Vec<usize>, Error> {
    if points.is_empty() {
        return Err(param_error(
            "no points to trace".into(),
            format!(
                "name them with --points A,B; the moving points are: {}",
                moving_points(model)
            ),
        ));
    }
    points
        .iter()
        .map(|p| model.moving_point_slot(p).map_err(|e| e.given_in("--points")))
        .collect()
}

/// The names of the model's thread paths, in order.
fn path_names(model: &Model) -> Vec<String> {
    model
        .file
        .thread
        .as_ref()
        .map_or_else(Vec::new, |t| t.paths.iter().map(|p| p.name.clone()).collect())
}

/// The thread paths `wanted` (`--thread`; empty: all), checked against the
/// model.
fn select_paths(model: &Model, wanted: &[String]) -> Result<Vec<String>, Error> {
    let all = path_names(model);
    if all.is_empty() {
        return Err(no_threads(model));
    }
    for w in wanted {
        if !all.contains(w) {
            return Err(param_error(
                format!("the model has no thread path `{w}` (in --thread)"),
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

/// An axis label `name, unit` (just `name` without a unit).
fn unit_label(name: &str, unit: &str) -> String {
    if unit.is_empty() {
        name.to_string()
    } else {
        format!("{name}, {unit}")
    }
}

/// `4.5 mm`: a value with the decimals a grid `step` needs (at most 3).
fn number_text(v: f64, step: f64, unit: &str) -> String {
    let decimals = (0..=3i32)
        .find(|&d| {
            let m = step.abs() * 10f64.powi(d);
            (m - m.round()).abs() < 1e-6 * m.max(1.0)
        })
        .unwrap_or(3);
    let text = super::svg::tick_label(
        (v * 10f64.powi(decimals)).round() / 10f64.powi(decimals),
        10f64.powi(-decimals),
    );
    if unit.is_empty() {
        text
    } else {
        format!("{text} {unit}")
    }
}

/// `r1 = 4.5 mm`: [`number_text`] with the parameter's name.
fn value_text(name: &str, v: f64, step: f64, unit: &str) -> String {
    format!("{name} = {}", number_text(v, step, unit))
}

/// Checks a varied parameter for a chart: at least two values, both ends
/// settable. Errors name `--vary` and the fix.
fn check_vary(model: &Model, vary: &Vary) -> Result<(), Error> {
    let spec = format!("{}={}:{}:{}", vary.name, vary.lo, vary.hi, vary.n);
    if vary.n < 2 {
        return Err(param_error(
            format!("--vary {spec} gives one value; a chart needs at least 2"),
            format!("give N ≥ 2, e.g. --vary {}={}:{}:5", vary.name, vary.lo, vary.hi),
        ));
    }
    if vary.n > 1001 {
        return Err(param_error(
            format!("--vary {spec} gives {} values", vary.n),
            "at most 1001 values per parameter in a chart".into(),
        ));
    }
    if !(vary.lo.is_finite() && vary.hi.is_finite()) || vary.lo == vary.hi {
        return Err(param_error(
            format!("--vary {spec}: the range is empty"),
            "give two different ends, LO:HI:N".into(),
        ));
    }
    let mut p = model.defaults();
    for v in [vary.lo, vary.hi] {
        model
            .set(&mut p, &vary.name, v)
            .map_err(|e| in_flag(e, &format!("--vary {spec}")))?;
    }
    Ok(())
}

/// The error with `(in FLAG)` added to its message.
fn in_flag(mut e: ParamError, flag: &str) -> Error {
    e.message = format!("{} (in {flag})", e.message);
    Error::Param(e)
}

/// Parses `--vary NAME=LO:HI[:N]` for a chart: N defaults to `default_n`;
/// unknown parameters and ends outside the adjustable range are errors
/// that name the flag.
pub fn parse_vary(model: &Model, spec: &str, default_n: usize) -> Result<Vary, Error> {
    let mut v = Vary::parse(model, spec).map_err(|e| match e {
        Error::Param(p) if !p.message.contains("--vary") => in_flag(p, &format!("--vary {spec}")),
        e => e,
    })?;
    if spec.split_once('=').is_some_and(|(_, r)| r.split(':').count() == 2) {
        v.n = default_n;
    }
    Ok(v)
}

fn moving_points(model: &Model) -> String {
    model.moving_point_names().join(", ")
}

fn no_threads(model: &Model) -> Error {
    param_error(
        format!(
            "model `{}` has no thread paths, so it has no take-up to plot",
            model.name()
        ),
        "add a [thread] table with [[thread.paths]] (docs/model-format.md §13), or plot a model with threads \
         (e.g. --preset mf7923d); `plot mu` and `plot trajectory --points …` work for any model"
            .into(),
    )
}

fn no_dyads(model: &Model) -> Error {
    param_error(
        format!("model `{}` has no dyads, so it has no transmission angles to plot", model.name()),
        "transmission angles come from rrr, rrp, rpr and rssr groups; plot this model's `trajectory --points …` instead".into(),
    )
}

fn column<'a>(table: &'a CycleTable, name: &str) -> Result<&'a [f64], Error> {
    table
        .column(name)
        .ok_or_else(|| Error::Io(format!("the cycle has no column `{name}` (a bug: please report it)")))
}

/// (φ, v) over the cycle, closed at φ_start + 360° (the motion is periodic).
fn closed(phis: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    let mut pts: Vec<(f64, f64)> = phis.iter().copied().zip(values.iter().copied()).collect();
    if let (Some(&p0), Some(&v0)) = (phis.first(), values.first()) {
        pts.push((p0 + 360.0, v0));
    }
    pts
}

fn phi_axis(model: &Model) -> Axis {
    let start = model.phi_start_deg();
    Axis {
        label: "φ, deg".into(),
        range: Some((start, start + 360.0)),
        step: Some(45.0),
    }
}

fn title(model: &Model, what: &str) -> String {
    format!("{}: {what}", model.name())
}

/// The take-up chart: P(φ) of every path, P'(φ) of every stitch thread
/// dashed in its path's colour, engaged intervals shaded in the path's
/// colour.
pub fn take_up(model: &Model, table: &CycleTable) -> Result<Chart, Error> {
    take_up_with_measured(model, table, &[])
}

/// [`take_up`] with measured curves drawn over it (a solid dark line each,
/// legend `THREAD P measured` or `THREAD P′ measured`).
pub fn take_up_with_measured(model: &Model, table: &CycleTable, measured: &[MeasuredMatch]) -> Result<Chart, Error> {
    if table.paths.is_empty() {
        return Err(no_threads(model));
    }
    let phis = column(table, "phi_deg")?;
    let start = model.phi_start_deg();
    let at_b = table.paths.iter().any(|p| p.split == crate::thread::SplitPoint::B);
    let mut chart = Chart::new(title(model, "thread take-up P(φ)"), phi_axis(model), Axis::new("P, mm"));
    let mut sub = table.take_up.clone().unwrap_or_default();
    if let Some(st) = &table.stitch {
        sub = format!(
            "solid: P (take-up), dashed: P′ (required, stitch {}, m = {} mm, t = {} mm); shaded: one-sided guide engaged",
            st.stitch_type, st.m_mm, st.t_mm
        );
        if at_b {
            sub += "; needle threads at B, the eye's top position";
        }
        if let Some([a, b]) = st.threads.iter().find_map(|t| t.regulator_window_deg) {
            let end = if b > 360.0 + 1e-9 { wrap_deg(b) } else { b };
            sub += &format!(
                "; regulator window {a:.0}°…{end:.0}° of {} left out of the match",
                st.threads
                    .iter()
                    .find(|t| t.regulator_window_deg.is_some())
                    .map_or("", |t| t.thread.as_str())
            );
        }
    } else if table.paths.iter().any(|p| !p.engaged.is_empty()) {
        sub += "; shaded: one-sided guide engaged";
    }
    chart.subtitle = Some(sub);
    let mut engaged = Vec::new();
    for (i, p) in table.paths.iter().enumerate() {
        let c = color(i).to_string();
        chart.series.push(Series {
            name: p.path.clone(),
            points: closed(phis, column(table, &p.p_column)?),
            color: c,
            dashed: false,
            mark_start: false,
        });
        for (guide, ivs) in &p.engaged {
            for iv in ivs {
                engaged.push((iv.from_deg, iv.to_deg, format!("{} {guide}", p.path), i));
            }
        }
    }
    // Paths sharing a guide share its intervals: one rect per distinct
    // interval (grey when shared), so the shading stays light.
    let mut merged: Vec<(f64, f64, Vec<String>, usize)> = Vec::new();
    for (a, b, who, i) in engaged {
        match merged
            .iter_mut()
            .find(|m| (m.0 - a).abs() < 1e-9 && (m.1 - b).abs() < 1e-9)
        {
            Some(m) => m.2.push(who),
            None => merged.push((a, b, vec![who], i)),
        }
    }
    for (a, b, who, i) in merged {
        let c = if who.len() == 1 {
            color(i).to_string()
        } else {
            "#7f7f7f".to_string()
        };
        let label = format!("engaged {:.0}°…{:.0}°: {}", wrap_deg(a), wrap_deg(b), who.join(", "));
        // A stretch past the cycle's end continues at its start.
        chart.x_shades.push(XShade {
            from: a,
            to: b.min(start + 360.0),
            color: c.clone(),
            label: label.clone(),
        });
        if b > start + 360.0 {
            chart.x_shades.push(XShade {
                from: start,
                to: b - 360.0,
                color: c,
                label,
            });
        }
    }
    if let Some(st) = &table.stitch {
        for (j, th) in st.threads.iter().enumerate() {
            let c = th
                .path
                .as_ref()
                .and_then(|p| table.paths.iter().position(|q| &q.path == p))
                .unwrap_or(table.paths.len() + j);
            chart.series.push(Series {
                // "n1 P′": a stitch thread may share its path's name
                // (altin504's `needle`, `lower`, `upper`).
                name: format!("{} P′", th.thread),
                points: closed(phis, column(table, &th.pprime_column())?),
                color: color(c).to_string(),
                dashed: true,
                mark_start: false,
            });
        }
    }
    for m in measured {
        let what = match m.kind {
            CurveKind::TakeUp => "P",
            CurveKind::Required => "P′",
        };
        chart.series.push(Series {
            name: format!("{} {what} measured", m.thread),
            points: closed(phis, &m.values_mm),
            color: "#222222".into(),
            dashed: false,
            mark_start: false,
        });
    }
    Ok(chart)
}

/// The transmission-angle chart: μ(φ) per dyad, the band 30°…150° marked
/// and the outside shaded.
pub fn transmission(model: &Model, table: &CycleTable) -> Result<Chart, Error> {
    if table.transmission.is_empty() {
        return Err(no_dyads(model));
    }
    let phis = column(table, "phi_deg")?;
    let mut chart = Chart::new(
        title(model, "transmission angles μ(φ)"),
        phi_axis(model),
        Axis {
            label: "μ, deg".into(),
            range: Some((0.0, 180.0)),
            step: Some(30.0),
        },
    );
    chart.subtitle = Some(format!(
        "shaded: outside {MU_MIN_DEG}°…{MU_MAX_DEG}°, where the mechanism risks jamming (seed 002 eq. 15)"
    ));
    for (i, t) in table.transmission.iter().enumerate() {
        chart.series.push(Series {
            name: t.key.clone(),
            points: closed(phis, column(table, &format!("mu_{}_deg", t.key))?),
            color: color(i).into(),
            dashed: false,
            mark_start: false,
        });
    }
    chart.y_bands.push(YBand {
        from: f64::NEG_INFINITY,
        to: MU_MIN_DEG,
        color: "#c0392b".into(),
        label: format!("μ < {MU_MIN_DEG}°"),
    });
    chart.y_bands.push(YBand {
        from: MU_MAX_DEG,
        to: f64::INFINITY,
        color: "#c0392b".into(),
        label: format!("μ > {MU_MAX_DEG}°"),
    });
    chart.y_lines = vec![MU_MIN_DEG, MU_MAX_DEG];
    Ok(chart)
}

/// The trajectory chart: each point's path over the cycle in the xy-plane
/// of `frame` (its name and plane; `None`: the world's), a spatial model's
/// paths projected onto it, equal scales, a dot where the cycle starts.
pub fn trajectory(
    model: &Model,
    table: &CycleTable,
    points: &[String],
    frame: Option<(&str, Plane<f64>)>,
) -> Result<Chart, Error> {
    let (ax, ay, on) = match &frame {
        Some((name, _)) if *name != "world" => (
            format!("{name}.x, mm"),
            format!("{name}.y, mm"),
            format!("the xy-plane of frame `{name}`"),
        ),
        _ => (
            "x, mm".to_string(),
            "y, mm".to_string(),
            "the world xy-plane".to_string(),
        ),
    };
    let plane = frame.map_or(Plane::WORLD, |f| f.1);
    let mut chart = Chart::new(
        title(model, format!("trajectories of {}", points.join(", ")).as_str()),
        Axis::new(ax),
        Axis::new(ay),
    );
    chart.equal_scale = true;
    let projected = !model.planar;
    chart.subtitle = Some(format!(
        "{} {on}, over one cycle to scale; dot: φ = {}°",
        if projected { "projected onto" } else { "in" },
        model.phi_start_deg()
    ));
    for (i, p) in points.iter().enumerate() {
        let xs = column(table, &format!("{p}.x_mm"))?;
        let ys = column(table, &format!("{p}.y_mm"))?;
        let zs = table.column(&format!("{p}.z_mm"));
        let mut pts: Vec<(f64, f64)> = (0..xs.len())
            .map(|k| {
                let q = plane.project(&V3::new(xs[k], ys[k], zs.map_or(0.0, |z| z[k])));
                (q.x, q.y)
            })
            .collect();
        if let Some(&first) = pts.first() {
            pts.push(first);
        }
        chart.series.push(Series {
            name: p.clone(),
            points: pts,
            color: color(i).into(),
            dashed: false,
            mark_start: true,
        });
    }
    Ok(chart)
}
