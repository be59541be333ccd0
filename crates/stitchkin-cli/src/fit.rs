//! `stitchkin fit`: fit model dimensions to stated results
//! (stitchkin::study::fit).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stitchkin::error::Error;
use stitchkin::format::fmt_num;
use stitchkin::study::fit::{Facts, FitOptions, FitResult, fit};

#[derive(Args)]
pub struct FitArgs {
    #[command(flatten)]
    model: crate::ModelArgs,
    /// The facts file (TOML): [[fact]] tables with figure, value, set,
    /// relative_to, tolerance or weight, source.
    #[arg(long, value_name = "FILE")]
    target: PathBuf,
    /// Parameters to fit, comma-separated: NAME (within its adjustable
    /// range) or NAME=LO:HI (default: the facts file's `adjust`). The start
    /// is the model's value, or --set.
    #[arg(long, value_delimiter = ',', value_name = "NAME[=LO:HI],…")]
    adjust: Option<Vec<String>>,
    /// Step of the main-shaft angle φ, degrees (default: the facts file's
    /// `step_deg`, else 1).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    step: Option<f64>,
    /// Levenberg–Marquardt iterations at most.
    #[arg(long, default_value_t = 100, value_name = "N")]
    max_iterations: usize,
    /// Output format: a readable table or JSON.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum Format {
    Table,
    Json,
}

pub fn run(args: FitArgs) -> Result<(), Error> {
    let (model, params) = crate::load(&args.model)?;
    let facts = Facts::from_path(&args.target)?;
    let opts = FitOptions {
        adjust: args.adjust.clone().unwrap_or_default(),
        step_deg: args.step,
        max_iterations: args.max_iterations,
    };
    let r = fit(&model, &params, &facts, &opts)?;
    let out = match args.format {
        Format::Json => serde_json::to_string_pretty(&r).map_err(|e| Error::Io(e.to_string()))? + "\n",
        Format::Table => table(&model.name(), &facts, &r),
    };
    crate::emit(out.as_bytes(), args.output.as_ref())
}

/// `x` to `d` decimals, without a negative zero.
fn dec(x: f64, d: usize) -> String {
    let s = format!("{x:.d$}");
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// `n` significant digits, without an exponent.
fn sig(x: f64, n: i32) -> String {
    if x == 0.0 || !x.is_finite() || x.abs() < 1e-9 {
        return fmt_num(x);
    }
    let d = (n - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.d$}")
}

fn table(model: &str, facts: &Facts, r: &FitResult) -> String {
    let mut s = format!("Fit of `{model}` to {}", facts.file);
    if let Some(t) = &facts.title {
        s += &format!(" ({t})");
    }
    s += &format!(
        "\nLevenberg–Marquardt: {} iterations, {} cycles; {}: {}\n\n",
        r.iterations,
        r.cycles,
        if r.converged { "converged" } else { "NOT converged" },
        r.stop
    );
    let w = r.params.iter().map(|p| p.name.len()).max().unwrap_or(4).max(9);
    s += &format!(
        "{:<w$}  {:>14}  {:>14}  {:>16}  {}\n",
        "parameter", "start", "fitted", "± std error", "bounds"
    );
    for p in &r.params {
        let se = p
            .std_error
            .map_or("undetermined".into(), |e| format!("± {} {}", sig(e, 2), p.unit));
        s += &format!(
            "{:<w$}  {:>14}  {:>14}  {:>16}  {} … {} {}{}\n",
            p.name,
            format!("{} {}", fmt_num(p.start), p.unit),
            format!("{} {}", dec(p.fitted, 4), p.unit),
            se,
            fmt_num(p.lo),
            fmt_num(p.hi),
            p.unit,
            if p.at_bound { "  (at a bound)" } else { "" }
        );
    }
    let fw = r.facts.iter().map(|f| f.figure.len()).max().unwrap_or(6).max(6);
    let sw = r.facts.iter().map(|f| f.setting.len()).max().unwrap_or(7).max(7);
    s += &format!(
        "\n{:<fw$}  {:<sw$}  {:>12}  {:>12}  {:>12}  {:>12}  {:>11}\n",
        "figure", "setting", "target", "start", "fitted", "residual", "residual/tol"
    );
    for f in &r.facts {
        let u = f.unit;
        let scaled = match f.tolerance {
            Some(_) => dec(f.weighted, 3),
            None => format!("{} (w)", dec(f.weighted, 3)),
        };
        s += &format!(
            "{:<fw$}  {:<sw$}  {:>12}  {:>12}  {:>12}  {:>12}  {:>11}\n",
            f.figure,
            f.setting,
            format!("{} {u}", fmt_num(f.target)),
            format!("{} {u}", dec(f.start, 4)),
            format!("{} {u}", dec(f.fitted, 4)),
            format!("{} {u}", dec(f.residual, 4)),
            scaled
        );
    }
    let weighted = if r.facts.iter().any(|f| f.tolerance.is_none()) {
        " (weight × residual where a fact has a weight)"
    } else {
        ""
    };
    s += &format!(
        "\ncost Σ (residual/tolerance)²{weighted}: {} at the start, {} fitted\n",
        sig(r.cost_start, 4),
        sig(r.cost, 4)
    );
    for w in &r.warnings {
        s += &format!("warning: {w}\n");
    }
    s
}
