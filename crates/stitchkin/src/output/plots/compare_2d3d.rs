//! The 2D-vs-3D take-up (seed 000 Fig. 9): P_3D and P_2D of each thread
//! path, and their difference ΔP(φ).

use super::{phi_axis, title};
use crate::error::Error;
use crate::model::Model;
use crate::output::svg::{Axis, Chart, Figure, Marker, Series, color};
use crate::study::compare_2d3d::Comparison;

/// Height of each of the two panels.
const PANEL_H: f64 = 330.0;

/// P_3D (solid) and P_2D (dashed) of the paths `paths` of the comparison
/// `c` (the 2D model on the xy-plane of frame `c.plane`), and ΔP = P_3D −
/// P_2D below, its largest |ΔP| marked.
pub fn delta_2d3d(model: &Model, c: &Comparison, paths: &[String]) -> Result<Figure, Error> {
    let start = model.phi_start_deg();
    let close = |v: &[f64]| -> Vec<(f64, f64)> {
        let mut pts: Vec<(f64, f64)> = c.phi_deg.iter().copied().zip(v.iter().copied()).collect();
        if let Some(&v0) = v.first() {
            pts.push((start + 360.0, v0));
        }
        pts
    };
    let mut top = Chart::new(
        "P_3D (solid, the spatial path) and P_2D (dashed, projected)",
        phi_axis(model),
        Axis::new("P, mm"),
    );
    let mut bottom = Chart::new("ΔP = P_3D − P_2D", phi_axis(model), Axis::new("ΔP, mm"));
    let mut worst: Option<(String, f64, f64)> = None;
    for (i, name) in paths.iter().enumerate() {
        let p = c
            .paths
            .iter()
            .find(|p| &p.path == name)
            .ok_or_else(|| Error::Internal(format!("no comparison for path `{name}`")))?;
        top.series
            .push(Series::new(format!("{name} 3D"), close(&p.p3d_mm), color(i)));
        let mut s2 = Series::new(format!("{name} 2D"), close(&p.p2d_mm), color(i));
        s2.dashed = true;
        top.series.push(s2);
        bottom
            .series
            .push(Series::new(format!("{name} ΔP"), close(&p.dp_mm), color(i)));
        let k = (0..p.dp_mm.len()).max_by(|&a, &b| p.dp_mm[a].abs().total_cmp(&p.dp_mm[b].abs()));
        if let Some(k) = k {
            bottom.markers.push(Marker {
                x: c.phi_deg[k],
                y: p.dp_mm[k],
                color: color(i).into(),
                label: format!(
                    "{name}: largest |ΔP| {:.4} mm at φ = {:.1}° ({:.2} % of max P)",
                    p.max_abs_dp_mm, p.phi_at_max_deg, p.max_rel_percent
                ),
                legend: None,
            });
        }
        if worst.as_ref().is_none_or(|w| p.max_abs_dp_mm > w.1) {
            worst = Some((name.clone(), p.max_abs_dp_mm, p.phi_at_max_deg));
        }
    }
    top.height = PANEL_H;
    bottom.height = PANEL_H;
    let mut fig = Figure::new(title(
        model,
        "take-up of the spatial and the planar model, P_3D and P_2D",
    ));
    let mut sub = format!(
        "2D model: every node projected onto the xy-plane of frame `{}`",
        c.plane
    );
    if let Some((name, dp, phi)) = worst {
        sub += &format!("; largest |ΔP| {dp:.3} mm ({name}, φ = {phi:.0}°), dots: each path's largest");
    }
    fig.subtitle = Some(sub);
    fig.panels = vec![top, bottom];
    Ok(fig)
}
