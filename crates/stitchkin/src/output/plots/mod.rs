//! The charts of `stitchkin plot` (docs/plots.md), drawn as SVG with
//! [`super::svg`] from results already computed (the plot job,
//! `jobs::plot`, computes them): of one cycle, the take-up P(φ) of every
//! thread path with the stitch's P'(φ), every transmission angle against
//! the 30°…150° band, the trajectories of chosen points and the velocity
//! and acceleration analogs; the motion law of any point coordinate, angle
//! or measure; over a varied parameter, P(φ) or a motion law as a family
//! of lines, a heat map or a projected surface; a figure of merit over two
//! parameters as a heat map; a nomogram; and the 2D-vs-3D take-up
//! difference.

use super::svg::{Area, Axis, Chart, Series, XShade, YBand, color};
use crate::error::{Error, Input, ParamError};
use crate::eval::{CycleTable, MU_MAX_DEG, MU_MIN_DEG, wrap_deg};
use crate::geometry::{Plane, V3};
use crate::model::Model;
use crate::study::measured::{MeasuredInterval, MeasuredMatch};
use crate::thread::measured::CurveKind;

pub mod analogs;
pub mod compare_2d3d;
pub mod family;
pub mod heatmap;
pub mod motion;
pub mod nomogram;
pub mod residuals;

pub use analogs::analogs;
pub use compare_2d3d::delta_2d3d;
pub use family::{FamilyData, Quantity, VaryGrid, family, surface_heat, surface_wireframe};
pub use heatmap::{FigureGrid, figure_label, heatmap};
pub use motion::{MotionSeries, motion_chart, motion_family_chart};
pub use nomogram::nomogram_figure;
pub use residuals::fit_residuals;

/// A parameter error with its help.
pub(crate) fn param_error(input: impl Into<Option<Input>>, message: String, help: String) -> Error {
    Error::Param(ParamError {
        input: input.into(),
        message,
        help: Some(help),
    })
}

/// The heat map or, with `wireframe`, the projected surface of a quantity
/// over φ and a varied parameter, as SVG.
pub fn surface(model: &Model, grid: &VaryGrid, q: &Quantity, rows: &[Option<Vec<f64>>], wireframe: bool) -> String {
    if wireframe {
        surface_wireframe(model, grid, q, rows).render()
    } else {
        surface_heat(model, grid, q, rows).render()
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

pub(crate) fn no_threads(model: &Model) -> Error {
    param_error(
        None,
        format!(
            "model `{}` has no thread paths, so it has no take-up to plot",
            model.name()
        ),
        "add a [thread] table with [[thread.paths]] (docs/model-format.md §13), or plot a model with threads \
         (e.g. the preset mf7923d); the transmission-angle and trajectory charts work for any model"
            .into(),
    )
}

pub(crate) fn no_dyads(model: &Model) -> Error {
    param_error(
        None,
        format!(
            "model `{}` has no dyads, so it has no transmission angles to plot",
            model.name()
        ),
        "transmission angles come from rrr, rrp, rpr and rssr groups; plot the trajectories of its points instead"
            .into(),
    )
}

pub(crate) fn column<'a>(table: &'a CycleTable, name: &str) -> Result<&'a [f64], Error> {
    table
        .column(name)
        .ok_or_else(|| Error::Internal(format!("the cycle has no column `{name}`")))
}

/// (φ, v) over the cycle, closed at φ_start + 360° (the motion is periodic).
pub(crate) fn closed(phis: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
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
    let mut chart = Chart::new(title(model, "thread take-up P(φ)"), phi_axis(model), Axis::new("P, mm"));
    chart.subtitle = Some(take_up_subtitle(table));
    for (i, p) in table.paths.iter().enumerate() {
        chart.series.push(Series {
            name: p.path.clone(),
            points: closed(phis, column(table, &p.p_column)?),
            color: color(i).to_string(),
            dashed: false,
            mark_start: false,
        });
    }
    chart.x_shades = engaged_shades(table, model.phi_start_deg());
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
        if let Some(i) = &m.interval {
            error_bars(&mut chart, phis, &m.values_mm, i, &m.thread, what);
        }
    }
    Ok(chart)
}

/// The error bars of a mean curve of repeated readings (seed 004 §3.4):
/// at each φ read, a thin bar from x̄ − Δ to x̄ + Δ around the curve (on
/// the cycle's grid, so a needle thread read at its eye and moved to B is
/// moved with it), with the interval as its tooltip.
fn error_bars(chart: &mut Chart, phis: &[f64], values: &[f64], i: &MeasuredInterval, thread: &str, what: &str) {
    let (Some(&first), Some(&last)) = (phis.first(), phis.last()) else {
        return;
    };
    // Half the bar's width, deg.
    let w = 0.6;
    for (&phi, &half) in i.readings_phi_deg.iter().zip(&i.readings_half_width_mm) {
        let x = first + (phi - first).rem_euclid(360.0);
        if x > last || !half.is_finite() {
            continue;
        }
        let k = phis.partition_point(|&p| p < x).min(phis.len() - 1);
        let y = if k > 0 && phis[k] > x {
            let t = (x - phis[k - 1]) / (phis[k] - phis[k - 1]);
            values[k - 1] + t * (values[k] - values[k - 1])
        } else {
            values[k]
        };
        if !y.is_finite() {
            continue;
        }
        chart.areas.push(Area {
            upper: vec![(x - w, y + half), (x + w, y + half)],
            lower: vec![(x - w, y - half), (x + w, y - half)],
            color: "#222222".into(),
            label: format!(
                "{thread} {what} measured at φ = {:.1}°: {:.3} ± {:.3} mm ({} %, {} §3.4)",
                phi,
                y,
                half,
                crate::format::fmt_num(i.confidence * 100.0),
                crate::references::cite(4)
            ),
        });
    }
}

/// The thread's tension over the cycle (`docs/thread-physics.md`): per
/// stitch thread whose tension is solved, T arriving at the eye (solid) and
/// in the stitch (dashed), N; the stretches where thread passes the
/// regulator shaded in the thread's colour, the breaking force over the
/// margin the check asks for as a dotted line.
pub fn tension(model: &Model, table: &CycleTable) -> Result<Chart, Error> {
    let threads: Vec<_> = table
        .stitch
        .iter()
        .flat_map(|s| s.threads.iter())
        .filter_map(|t| t.tension.as_ref().map(|tn| (t, tn)))
        .collect();
    if threads.is_empty() {
        return Err(param_error(
            None,
            format!(
                "model `{}` has no thread physics, so there is no tension to chart",
                model.name()
            ),
            "give [thread.physics] in the model file (docs/thread-physics.md)".into(),
        ));
    }
    let phis = column(table, "phi_deg")?;
    let start = model.phi_start_deg();
    let mut chart = Chart::new(title(model, "thread tension T(φ)"), phi_axis(model), Axis::new("T, N"));
    let (_, first) = threads[0];
    chart.subtitle = Some(format!(
        "solid: at the eye, dashed: in the stitch; shaded: thread passes the regulator ({} N); dotted: a third of the \
         {} N breaking force",
        crate::format::fmt_num(first.regulator_n),
        crate::format::fmt_num(first.breaking_n),
    ));
    for (i, (t, tn)) in threads.iter().enumerate() {
        let c = color(i).to_string();
        for (col, dashed, what) in [("T_eye_N", false, "eye"), ("T_stitch_N", true, "stitch")] {
            chart.series.push(Series {
                name: format!("{} T at the {what}", t.thread),
                points: closed(phis, column(table, &format!("{}.{col}", t.thread))?),
                color: c.clone(),
                dashed,
                mark_start: false,
            });
        }
        for &[a, b] in &tn.regulator_windows_deg {
            let label = format!(
                "{}: thread passes the regulator {:.0}°…{:.0}°",
                t.thread,
                wrap_deg(a),
                wrap_deg(b)
            );
            // Unwrapped onto the chart's cycle from `start`.
            let (a, b) = (
                start + (a - start).rem_euclid(360.0),
                start + (a - start).rem_euclid(360.0) + (b - a),
            );
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
                    color: c.clone(),
                    label,
                });
            }
        }
    }
    chart
        .y_lines
        .push(first.breaking_n / crate::eval::tension::TENSION_MARGIN_MIN);
    Ok(chart)
}

/// The take-up chart's subtitle: what the lines and the shading are, where
/// needle threads are measured, the regulator window.
fn take_up_subtitle(table: &CycleTable) -> String {
    let at_b = table.paths.iter().any(|p| p.split == crate::thread::SplitPoint::B);
    let mut sub = table.take_up.clone().unwrap_or_default();
    if let Some(st) = &table.stitch {
        sub = format!(
            "solid: P (take-up), dashed: P′ (required, stitch {}, m = {} mm, t = {} mm); shaded: one-sided guide engaged",
            st.stitch_type, st.m_mm, st.t_mm
        );
        if at_b {
            sub += "; needle threads at B, the eye's top position";
        }
        if let Some(t) = st.threads.iter().find(|t| !t.regulator_windows_deg.is_empty()) {
            let ws: Vec<String> = t
                .regulator_windows_deg
                .iter()
                .map(|&[a, b]| {
                    let end = if b > 360.0 + 1e-9 { wrap_deg(b) } else { b };
                    format!("{a:.0}°…{end:.0}°")
                })
                .collect();
            sub += &format!(
                "; regulator window{} {} of {}{} left out of the match",
                if ws.len() > 1 { "s" } else { "" },
                ws.join(", "),
                t.thread,
                if t.regulator_computed { " (computed)" } else { "" }
            );
        }
    } else if table.paths.iter().any(|p| !p.engaged.is_empty()) {
        sub += "; shaded: one-sided guide engaged";
    }
    sub
}

/// The φ intervals where a one-sided guide bears on a path, shaded in the
/// path's colour; the cycle starts at `start` (deg).
fn engaged_shades(table: &CycleTable, start: f64) -> Vec<XShade> {
    let mut engaged = Vec::new();
    for (i, p) in table.paths.iter().enumerate() {
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
    let mut shades = Vec::new();
    for (a, b, who, i) in merged {
        let c = if who.len() == 1 {
            color(i).to_string()
        } else {
            "#7f7f7f".to_string()
        };
        let label = format!("engaged {:.0}°…{:.0}°: {}", wrap_deg(a), wrap_deg(b), who.join(", "));
        // A stretch past the cycle's end continues at its start.
        shades.push(XShade {
            from: a,
            to: b.min(start + 360.0),
            color: c.clone(),
            label: label.clone(),
        });
        if b > start + 360.0 {
            shades.push(XShade {
                from: start,
                to: b - 360.0,
                color: c,
                label,
            });
        }
    }
    shades
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
        "shaded: outside {MU_MIN_DEG}°…{MU_MAX_DEG}°, where the mechanism risks jamming ({} eq. 15)",
        crate::references::cite(2)
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
