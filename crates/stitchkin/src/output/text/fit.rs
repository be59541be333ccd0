//! A fit of model dimensions ([`crate::study::fit`]) as a readable table:
//! the fitted parameters with their standard errors, the residual per fact
//! and the cost.

use crate::format::{decimals, fmt_num, sig_fixed};
use crate::study::fit::{Facts, FitResult};

/// The fit of model `model` to `facts`: the solver's stop, one row per
/// parameter (start, fitted, ± standard error, bounds), one row per fact
/// (target, start, fitted, residual, residual/tolerance), the cost before
/// and after, and the warnings.
pub fn table(model: &str, facts: &Facts, r: &FitResult) -> String {
    let mut s = format!("Fit of `{model}` to {}", facts.file);
    if let Some(t) = &facts.title {
        s += &format!(" ({t})");
    }
    s += &format!("\n{}\n", solver_line(r.iterations, r.cycles, r.converged, &r.stop));
    s += &params_table(r);
    s += &facts_table(r);
    let weighted = if r.facts.iter().any(|f| f.tolerance.is_none()) {
        " (weight × residual where a fact has a weight)"
    } else {
        ""
    };
    s += &format!(
        "\ncost Σ (residual/tolerance)²{weighted}: {} at the start, {} fitted\n",
        sig_fixed(r.cost_start, 4),
        sig_fixed(r.cost, 4)
    );
    for w in &r.warnings {
        s += &format!("warning: {w}\n");
    }
    s
}

/// `Levenberg–Marquardt: 7 iterations, 24 cycles; converged: why` and a
/// blank line: how a fit's solver ended.
pub(crate) fn solver_line(iterations: usize, cycles: usize, converged: bool, stop: &str) -> String {
    format!(
        "Levenberg–Marquardt: {iterations} iterations, {cycles} cycles; {}: {stop}\n",
        if converged { "converged" } else { "NOT converged" }
    )
}

fn params_table(r: &FitResult) -> String {
    let w = super::name_width(r.params.iter().map(|p| p.name.len()), 9);
    let mut s = format!(
        "{:<w$}  {:>14}  {:>14}  {:>16}  {}\n",
        "parameter", "start", "fitted", "± std error", "bounds"
    );
    for p in &r.params {
        let se = p
            .std_error
            .map_or("undetermined".into(), |e| format!("± {} {}", sig_fixed(e, 2), p.unit));
        s += &format!(
            "{:<w$}  {:>14}  {:>14}  {:>16}  {} … {} {}{}\n",
            p.name,
            format!("{} {}", fmt_num(p.start), p.unit),
            format!("{} {}", decimals(p.fitted, 4), p.unit),
            se,
            fmt_num(p.lo),
            fmt_num(p.hi),
            p.unit,
            if p.at_bound { "  (at a bound)" } else { "" }
        );
    }
    s
}

fn facts_table(r: &FitResult) -> String {
    let fw = super::name_width(r.facts.iter().map(|f| f.figure.len()), 6);
    let sw = super::name_width(r.facts.iter().map(|f| f.setting.len()), 7);
    let mut s = format!(
        "\n{:<fw$}  {:<sw$}  {:>12}  {:>12}  {:>12}  {:>12}  {:>11}\n",
        "figure", "setting", "target", "start", "fitted", "residual", "residual/tol"
    );
    for f in &r.facts {
        let u = f.unit;
        let scaled = match f.tolerance {
            Some(_) => decimals(f.weighted, 3),
            None => format!("{} (w)", decimals(f.weighted, 3)),
        };
        s += &format!(
            "{:<fw$}  {:<sw$}  {:>12}  {:>12}  {:>12}  {:>12}  {:>11}\n",
            f.figure,
            f.setting,
            format!("{} {u}", fmt_num(f.target)),
            format!("{} {u}", decimals(f.start, 4)),
            format!("{} {u}", decimals(f.fitted, 4)),
            format!("{} {u}", decimals(f.residual, 4)),
            scaled
        );
    }
    s
}
