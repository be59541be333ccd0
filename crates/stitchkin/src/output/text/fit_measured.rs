//! A fit to measured take-up curves ([`crate::study::fit_measured`]) as a
//! readable screen: the setting the machine is at, with its intervals and
//! the correlation of the fitted parameters; how well the fitted model
//! reproduces each curve (residuals over φ as a sparkline); the warnings;
//! and, with the advice, the fitted machine's match against the stitch and
//! the adjustment from the fitted setting to the best one.

use crate::format::{decimals, fmt_num, sig_sci};
use crate::study::fit_measured::{Advice, CurveFit, MeasuredFit};
use crate::thread::measured::CurveKind;

use super::{name_width, sparkline};

/// The screen of a fit of model `model` (and its advice, when made).
pub fn screen(model: &str, fit: &MeasuredFit, advice: Option<&Advice>) -> String {
    let sources: Vec<String> = fit
        .curves
        .iter()
        .map(|c| format!("{} ({})", c.source, curve_name(c)))
        .collect();
    let mut s = format!("Fit of `{model}` to {}\n", sources.join(", "));
    s += &format!(
        "{} samples, {} parameter{}, {} degrees of freedom; {}\n",
        fit.samples,
        fit.params.len(),
        if fit.params.len() == 1 { "" } else { "s" },
        fit.dof,
        if fit.sigma_known {
            "weights 1/σ² from the readings' uncertainty".to_string()
        } else {
            format!(
                "one reading per φ: σ estimated from the residuals, s = {} mm",
                fit.sigma_estimated_mm.map_or("—".into(), |v| sig_sci(v, 3))
            )
        }
    );
    s += &super::fit::solver_line(fit.iterations, fit.cycles, fit.converged, &fit.stop);
    s += "\n";
    s += &params_table(fit);
    s += &correlation_table(fit);
    s += &format!(
        "\nχ²/dof = {} (S = {} at the start, {} fitted); condition of JᵀWJ {}\n",
        sig_sci(fit.chi2_per_dof, 3),
        sig_sci(fit.cost_start, 4),
        sig_sci(fit.cost, 4),
        if fit.condition.is_finite() {
            format!("{:.3e}", fit.condition)
        } else {
            "infinite (singular)".into()
        }
    );
    s += &residuals(fit);
    for w in &fit.warnings {
        s += &format!("warning: {w}\n");
    }
    // The weights' note is the header's second line.
    for n in fit
        .notes
        .iter()
        .filter(|n| !n.starts_with("weights 1/σ²") && !n.starts_with("one reading per φ"))
    {
        s += &format!("note: {n}\n");
    }
    if let Some(a) = advice {
        s += &advice_text(a);
    }
    s
}

/// `n1 P at B`: which curve of which thread a measured curve is.
fn curve_name(c: &CurveFit) -> String {
    let what = match c.kind {
        CurveKind::TakeUp => "P",
        CurveKind::Required => "P′",
    };
    format!("{} {what} of path {}", c.thread, c.path)
}

/// One row per fitted parameter: its plain label, start, fitted value,
/// standard error, interval and bounds.
fn params_table(fit: &MeasuredFit) -> String {
    let w = name_width(fit.params.iter().map(|p| p.name.len()), 9);
    let ci = format!("{} % interval", fmt_num(fit.confidence * 100.0));
    let mut s = format!(
        "{:<w$}  {:>12}  {:>12}  {:>14}  {:>26}  {}\n",
        "parameter", "start", "fitted", "± std error", ci, "bounds"
    );
    for p in &fit.params {
        let se = p
            .std_error
            .map_or("undetermined".into(), |e| format!("± {} {}", sig_sci(e, 2), p.unit));
        let iv = p.interval.map_or("—".into(), |[lo, hi]| {
            format!("{} … {} {}", decimals(lo, 4), decimals(hi, 4), p.unit)
        });
        s += &format!(
            "{:<w$}  {:>12}  {:>12}  {:>14}  {:>26}  {} … {} {}{}\n",
            p.name,
            format!("{} {}", fmt_num(p.start), p.unit),
            format!("{} {}", decimals(p.fitted, 4), p.unit),
            se,
            iv,
            fmt_num(p.lo),
            fmt_num(p.hi),
            p.unit,
            if p.at_bound { "  (at a bound)" } else { "" }
        );
        if p.label != p.name {
            s += &format!("{:<w$}  ({})\n", "", p.label);
        }
    }
    s += &format!(
        "intervals: fitted ± {} · std error ({})\n",
        sig_sci(fit.quantile, 4),
        fit.quantile_from
    );
    s
}

/// The correlation matrix ρ of the fitted parameters (two or more).
fn correlation_table(fit: &MeasuredFit) -> String {
    let n = fit.correlation.len();
    if n < 2 {
        return String::new();
    }
    let w = name_width(fit.params.iter().map(|p| p.name.len()), 6);
    let mut s = format!("\ncorrelation ρ\n{:<w$}", "");
    for p in &fit.params {
        s += &format!("  {:>8}", p.name);
    }
    s += "\n";
    for (p, row) in fit.params.iter().zip(&fit.correlation) {
        s += &format!("{:<w$}", p.name);
        for v in row {
            s += &format!("  {:>8}", format!("{v:+.3}"));
        }
        s += "\n";
    }
    s
}

/// Per curve: the RMS residual, the largest residual and where, the share
/// of samples whose interval holds the fitted model, and the residuals over
/// φ as a sparkline (around zero).
fn residuals(fit: &MeasuredFit) -> String {
    let mut s = String::from("\nresiduals (model − measured)\n");
    for c in &fit.curves {
        let (k, worst) =
            c.residual_mm.iter().enumerate().fold(
                (0, 0.0f64),
                |(k, m), (i, &r)| if r.abs() > m.abs() { (i, r) } else { (k, m) },
            );
        s += &format!(
            "  {}: RMS {} mm, largest {} mm at φ = {}°",
            curve_name(c),
            sig_sci(c.rms_residual_mm, 3),
            decimals(worst, 3),
            fmt_num(c.phi_deg.get(k).copied().unwrap_or(f64::NAN))
        );
        if let Some(sigma) = &c.sigma_mm {
            let q = fit.quantile;
            let within = c
                .residual_mm
                .iter()
                .zip(sigma)
                .filter(|(r, s)| r.abs() <= q * **s)
                .count();
            s += &format!(
                "; within ± {}·σ at {} of {} φ",
                sig_sci(q, 3),
                within,
                c.residual_mm.len()
            );
        }
        s += "\n";
        let top = c.residual_mm.iter().fold(0.0f64, |m, r| m.max(r.abs())).max(1e-9);
        s += &format!(
            "    {}  (from −{} to +{} mm, over φ {}°…{}°)\n",
            sparkline(&c.residual_mm, -top, top, c.residual_mm.len().min(72)),
            sig_sci(top, 2),
            sig_sci(top, 2),
            fmt_num(c.phi_deg.first().copied().unwrap_or(0.0)),
            fmt_num(c.phi_deg.last().copied().unwrap_or(0.0))
        );
    }
    s
}

/// The fitted machine against the stitch and the adjustment to the best
/// setting.
fn advice_text(a: &Advice) -> String {
    let mut s = String::from("\nThe fitted machine against the stitch\n");
    match &a.tune {
        Some(t) => {
            s += &format!(
                "match at the fitted setting: score {:.1} (mean over the threads)\n\n",
                t.before_figures.score_mean
            );
            s += &super::tune::table(t);
        }
        None => s += "no adjustment made\n",
    }
    for n in &a.notes {
        s += &format!("note: {n}\n");
    }
    s
}
