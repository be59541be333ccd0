//! The plots of `stitchkin plot` (docs/plots.md), as SVG charts built with
//! [`super::svg`]: the take-up P(φ) of every thread path with the stitch's
//! P'(φ), every transmission angle against the 30°…150° band, and the
//! trajectories of chosen points.

use super::svg::{Axis, Chart, Series, XShade, YBand, color};
use crate::error::{Error, ParamError};
use crate::geometry::{Plane, V3};
use crate::eval::{CycleOptions, CycleTable, MU_MAX_DEG, MU_MIN_DEG, run_cycle, wrap_deg};
use crate::model::{Model, Params};

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
}

fn param_error(message: String, help: String) -> Error {
    Error::Param(ParamError { message, help: Some(help) })
}

/// Runs the cycle the plot needs (positions only) and draws it.
pub fn render(model: &Model, params: &Params, plot: &Plot, step_deg: f64) -> Result<String, Error> {
    let mut opts = CycleOptions { step_deg, analogs: false, points: Some(Vec::new()), ..Default::default() };
    if let Plot::Trajectory { points, .. } = plot {
        if points.is_empty() {
            return Err(param_error("no points to trace".into(), format!("name them with --points A,B; the moving points are: {}", moving_points(model))));
        }
        let slots = points.iter().map(|p| crate::study::stroke::point_slot(model, p, "--points", true)).collect::<Result<Vec<_>, _>>()?;
        opts.points = Some(slots);
    }
    // Fail before the cycle when there is nothing to plot.
    match plot {
        Plot::TakeUp if model.file.thread.is_none() => return Err(no_threads(model)),
        Plot::Mu if model.dyads.is_empty() => return Err(no_dyads(model)),
        _ => {}
    }
    let table = run_cycle(model, params, &opts)?;
    let chart = match plot {
        Plot::TakeUp => take_up(model, &table)?,
        Plot::Mu => transmission(model, &table)?,
        Plot::Trajectory { points, plane } => {
            let frame = match plane {
                None => None,
                Some(name) => Some((
                    name.as_str(),
                    model.frame_index(name).ok_or_else(|| {
                        param_error(format!("the model has no frame `{name}` (in --plane)"), format!("its frames are: {}", model.frame_names().join(", ")))
                    })?,
                )),
            };
            let frame = match frame {
                Some((name, i)) => Some((name, model.mechanism::<f64>(params)?.frame_plane(i))),
                None => None,
            };
            trajectory(model, &table, points, frame)?
        }
    };
    Ok(chart.render())
}

fn moving_points(model: &Model) -> String {
    let names: Vec<&str> = (0..model.point_names.len()).filter(|&i| !model.is_fixed(i)).map(|i| model.point_names[i].as_str()).collect();
    names.join(", ")
}

fn no_threads(model: &Model) -> Error {
    param_error(
        format!("model `{}` has no thread paths, so it has no take-up to plot", model.file.model.name),
        "add a [thread] table with [[thread.paths]] (docs/model-format.md §13), or plot a model with threads \
         (e.g. --preset mf7923d); `plot mu` and `plot trajectory --points …` work for any model"
            .into(),
    )
}

fn no_dyads(model: &Model) -> Error {
    param_error(
        format!("model `{}` has no dyads, so it has no transmission angles to plot", model.file.model.name),
        "transmission angles come from rrr, rrp, rpr and rssr groups; plot this model's `trajectory --points …` instead".into(),
    )
}

fn column<'a>(table: &'a CycleTable, name: &str) -> Result<&'a [f64], Error> {
    table.column(name).ok_or_else(|| Error::Io(format!("the cycle has no column `{name}` (a bug: please report it)")))
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
    Axis { label: "φ, deg".into(), range: Some((start, start + 360.0)), step: Some(45.0) }
}

fn title(model: &Model, what: &str) -> String {
    format!("{}: {what}", model.file.model.name)
}

/// The take-up chart: P(φ) of every path, P'(φ) of every stitch thread
/// dashed in its path's colour, engaged intervals shaded in the path's
/// colour.
pub fn take_up(model: &Model, table: &CycleTable) -> Result<Chart, Error> {
    if table.paths.is_empty() {
        return Err(no_threads(model));
    }
    let phis = column(table, "phi_deg")?;
    let start = model.phi_start_deg();
    let mut chart = Chart::new(title(model, "thread take-up P(φ)"), phi_axis(model), Axis::new("P, mm"));
    let mut sub = table.take_up.clone().unwrap_or_default();
    if let Some(st) = &table.stitch {
        sub = format!("solid: P (take-up), dashed: P′ (required, stitch {}, m = {} mm, t = {} mm); shaded: one-sided guide engaged", st.stitch_type, st.m_mm, st.t_mm);
    } else if table.paths.iter().any(|p| !p.engaged.is_empty()) {
        sub += "; shaded: one-sided guide engaged";
    }
    chart.subtitle = Some(sub);
    let mut engaged = Vec::new();
    for (i, p) in table.paths.iter().enumerate() {
        let c = color(i).to_string();
        chart.series.push(Series { name: p.path.clone(), points: closed(phis, column(table, &format!("{}.P_mm", p.path))?), color: c, dashed: false, mark_start: false });
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
        match merged.iter_mut().find(|m| (m.0 - a).abs() < 1e-9 && (m.1 - b).abs() < 1e-9) {
            Some(m) => m.2.push(who),
            None => merged.push((a, b, vec![who], i)),
        }
    }
    for (a, b, who, i) in merged {
        let c = if who.len() == 1 { color(i).to_string() } else { "#7f7f7f".to_string() };
        let label = format!("engaged {:.0}°…{:.0}°: {}", wrap_deg(a), wrap_deg(b), who.join(", "));
        // A stretch past the cycle's end continues at its start.
        chart.x_shades.push(XShade { from: a, to: b.min(start + 360.0), color: c.clone(), label: label.clone() });
        if b > start + 360.0 {
            chart.x_shades.push(XShade { from: start, to: b - 360.0, color: c, label });
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
                points: closed(phis, column(table, &format!("{}.Pprime_mm", th.thread))?),
                color: color(c).to_string(),
                dashed: true,
                mark_start: false,
            });
        }
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
    let mut chart = Chart::new(title(model, "transmission angles μ(φ)"), phi_axis(model), Axis { label: "μ, deg".into(), range: Some((0.0, 180.0)), step: Some(30.0) });
    chart.subtitle = Some(format!("shaded: outside {MU_MIN_DEG}°…{MU_MAX_DEG}°, where the mechanism risks jamming (seed 002 eq. 15)"));
    for (i, t) in table.transmission.iter().enumerate() {
        chart.series.push(Series { name: t.key.clone(), points: closed(phis, column(table, &format!("mu_{}_deg", t.key))?), color: color(i).into(), dashed: false, mark_start: false });
    }
    chart.y_bands.push(YBand { from: f64::NEG_INFINITY, to: MU_MIN_DEG, color: "#c0392b".into(), label: format!("μ < {MU_MIN_DEG}°") });
    chart.y_bands.push(YBand { from: MU_MAX_DEG, to: f64::INFINITY, color: "#c0392b".into(), label: format!("μ > {MU_MAX_DEG}°") });
    chart.y_lines = vec![MU_MIN_DEG, MU_MAX_DEG];
    Ok(chart)
}

/// The trajectory chart: each point's path over the cycle in the xy-plane
/// of `frame` (its name and plane; `None`: the world's), a spatial model's
/// paths projected onto it, equal scales, a dot where the cycle starts.
pub fn trajectory(model: &Model, table: &CycleTable, points: &[String], frame: Option<(&str, Plane<f64>)>) -> Result<Chart, Error> {
    let (ax, ay, on) = match &frame {
        Some((name, _)) if *name != "world" => (format!("{name}.x, mm"), format!("{name}.y, mm"), format!("the xy-plane of frame `{name}`")),
        _ => ("x, mm".to_string(), "y, mm".to_string(), "the world xy-plane".to_string()),
    };
    let plane = frame.map_or(Plane::WORLD, |f| f.1);
    let mut chart = Chart::new(title(model, format!("trajectories of {}", points.join(", ")).as_str()), Axis::new(ax), Axis::new(ay));
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
        chart.series.push(Series { name: p.clone(), points: pts, color: color(i).into(), dashed: false, mark_start: true });
    }
    Ok(chart)
}
