//! The nomogram drawn: the tuned setting against the material thickness,
//! one line per stitch length, the range within one score point shaded —
//! the chart a technician reads "for 4 mm material set z = −4.7 mm" off.

use super::{number_text, unit_label};
use crate::output::svg::{Area, Axis, Chart, Figure, Marker, Series, color, family_color};
use crate::study::nomogram::Nomogram;

/// Height of each panel (one per adjusted parameter).
const PANEL_H: f64 = 380.0;

/// The nomogram drawn: per adjusted parameter, its recommended value
/// against m, one line per t, with the range within one score point
/// shaded and each grid point marked (its tooltip gives the value, the
/// range and the match score).
pub fn nomogram_figure(n: &Nomogram) -> Figure {
    let dm = (n.thickness.hi - n.thickness.lo) / (n.thickness.n - 1).max(1) as f64;
    let dt = if n.stitch.n > 1 {
        (n.stitch.hi - n.stitch.lo) / (n.stitch.n - 1) as f64
    } else {
        0.1
    };
    let mut panels = Vec::new();
    for (k, (name, unit)) in n.adjust.iter().enumerate() {
        let mut chart = Chart::new(
            format!("recommended {name}"),
            Axis::new("material thickness m, mm"),
            Axis::new(unit_label(name, unit)),
        );
        chart.height = PANEL_H;
        for j in 0..n.stitch.n {
            let c = if n.stitch.n > 1 {
                family_color(j, n.stitch.n)
            } else {
                color(0).to_string()
            };
            let t = n.stitch.value(j);
            let (mut line, mut upper, mut lower) = (Vec::new(), Vec::new(), Vec::new());
            for i in 0..n.thickness.n {
                let p = &n.points[i * n.stitch.n + j];
                let Some(r) = &p.tuned else {
                    line.push((p.m_mm, f64::NAN));
                    continue;
                };
                let v = r.after[k];
                line.push((p.m_mm, v));
                let flat = r.flatness.iter().find(|f| &f.name == name);
                if let Some(f) = flat {
                    upper.push((p.m_mm, f.hi));
                    lower.push((p.m_mm, f.lo));
                }
                let within = flat.map_or(String::new(), |f| {
                    format!(
                        " (within one score point: {} … {})",
                        number_text(f.lo, 0.01, unit),
                        number_text(f.hi, 0.01, unit)
                    )
                });
                chart.markers.push(Marker {
                    x: p.m_mm,
                    y: v,
                    color: c.clone(),
                    label: format!(
                        "m = {}, t = {}: {name} = {}{within}; mean score {:.1} (before {:.1})",
                        number_text(p.m_mm, dm, "mm"),
                        number_text(t, dt, "mm"),
                        number_text(v, 0.01, unit),
                        r.after_figures.score_mean,
                        r.before_figures.score_mean
                    ),
                    legend: None,
                });
            }
            if upper.len() >= 2 {
                chart.areas.push(Area {
                    upper,
                    lower,
                    color: c.clone(),
                    label: format!("{name} within one score point, t = {}", number_text(t, dt, "mm")),
                });
            }
            chart
                .series
                .push(Series::new(format!("t = {}", number_text(t, dt, "mm")), line, c));
        }
        panels.push(chart);
    }
    let names: Vec<&str> = n.adjust.iter().map(|a| a.0.as_str()).collect();
    let mut fig = Figure::new(format!(
        "{}: nomogram, the tuned {} for the material",
        n.model,
        names.join(", ")
    ));
    let scores: Vec<f64> = n.tuned().map(|(_, r)| r.after_figures.score_mean).collect();
    let failed = n.points.iter().filter(|p| p.tuned.is_none()).count();
    let mut sub = if n.all_scores_zero() {
        "warning: every match score is 0, no setting in the ranges fits this stitch; the lines only minimise J"
            .to_string()
    } else {
        let (lo, hi) = scores
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &s| (a.min(s), b.max(s)));
        format!("shaded: within one point of the best match score; mean score after tuning {lo:.1}…{hi:.1}")
    };
    if failed > 0 {
        sub += &format!("; {failed} grid points did not tune");
    }
    fig.subtitle = Some(sub);
    fig.panels = panels;
    fig
}
