//! The residuals of a fit to measured curves
//! ([`crate::study::fit_measured`]) over φ: per curve, model − measured at
//! each sample (a line through dots), with the band ± q·σ_i where the
//! readings carry their uncertainty (the fitted model inside it agrees with
//! the measurement at that φ), and zero as a dashed line.

use super::super::svg::{Area, Axis, Chart, Marker, Series, color};
use crate::format::fmt_num;
use crate::study::fit_measured::MeasuredFit;
use crate::thread::measured::CurveKind;

/// The residual chart of a fit of model `model`.
pub fn fit_residuals(model: &str, fit: &MeasuredFit) -> Chart {
    // φ from the 45° tick below the first sample to the one above the last.
    let (lo, hi) = fit
        .curves
        .iter()
        .flat_map(|c| c.phi_deg.iter().copied())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let range = (lo.is_finite() && hi > lo).then(|| ((lo / 45.0).floor() * 45.0, (hi / 45.0).ceil() * 45.0));
    let mut chart = Chart::new(
        format!("{model}: residuals of the fit (model − measured)"),
        Axis {
            label: "φ, deg".into(),
            range,
            step: Some(45.0),
        },
        Axis::new("model − measured, mm"),
    );
    let fitted: Vec<String> = fit
        .params
        .iter()
        .map(|p| format!("{} = {} {}", p.name, fmt_num((p.fitted * 1e4).round() / 1e4), p.unit))
        .collect();
    chart.subtitle = Some(format!(
        "fitted {}; χ²/dof = {:.2}{}",
        fitted.join(", "),
        fit.chi2_per_dof,
        if fit.sigma_known {
            format!(
                "; bands ± {:.2}·σ ({} %)",
                fit.quantile,
                fmt_num(fit.confidence * 100.0)
            )
        } else {
            String::new()
        }
    ));
    chart.y_lines.push(0.0);
    for (i, c) in fit.curves.iter().enumerate() {
        let what = match c.kind {
            CurveKind::TakeUp => "P",
            CurveKind::Required => "P′",
        };
        let col = color(i).to_string();
        let name = format!("{} {what} ({})", c.thread, c.source);
        let points: Vec<(f64, f64)> = c.phi_deg.iter().copied().zip(c.residual_mm.iter().copied()).collect();
        for &(phi, r) in &points {
            chart.markers.push(Marker {
                x: phi,
                y: r,
                color: col.clone(),
                label: format!("{name} at φ = {}°: {:+.3} mm", fmt_num(phi), r),
                legend: None,
            });
        }
        if let Some(sigma) = &c.sigma_mm {
            // Half the band's width along φ, deg.
            let w = 0.8;
            for (&(phi, _), s) in points.iter().zip(sigma) {
                let half = fit.quantile * s;
                chart.areas.push(Area {
                    upper: vec![(phi - w, half), (phi + w, half)],
                    lower: vec![(phi - w, -half), (phi + w, -half)],
                    color: col.clone(),
                    label: format!("{name} at φ = {}°: ± {:.3} mm", fmt_num(phi), half),
                });
            }
        }
        chart.series.push(Series {
            name,
            points,
            color: col,
            dashed: false,
            mark_start: false,
        });
    }
    chart
}
