//! `stitchkin fit`: fit model dimensions to stated results
//! (stitchkin::study::fit), or the machine's setting to its measured
//! take-up (stitchkin::study::fit_measured) with the advice that follows.

use std::path::PathBuf;

use stitchkin::error::{Error, Input, ParamError};
use stitchkin::model::{Model, Params};
use stitchkin::output::text;
use stitchkin::study::fit::{Facts, FitOptions, fit};
use stitchkin::study::fit_measured::{CurveInput, FitMeasuredOptions, advise, fit_measured};

use crate::common::{ModelArgs, OutputArgs, TABLE_OR_JSON_HELP, TableOrJson, json, load, read_measured};

/// Fit model dimensions (figure-only, reconstructed ones) to stated
/// results, or the machine's setting to its measured take-up, by weighted
/// least squares within bounds; report the fitted values with their
/// uncertainty and the residuals.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin fit --preset needle876 --target examples/facts/needle876.toml --set y_c=170\n  \
    stitchkin fit --preset needle876 --target examples/facts/needle876.toml --set l_cf=41 --adjust l_cf=30:45\n  \
    stitchkin fit my-machine.toml --target facts.toml --adjust y_c=160:190,l_cf=30:45 --format json -o fit.json\n  \
    stitchkin fit --preset mf7923d --measured n1=examples/mf7923d-bench-n1.csv --adjust z,dphi\n  \
    stitchkin fit --preset mf7923d --measured n1=bench.csv --adjust z,dphi --chart residuals.svg --no-advice\n\n\
    With --target: facts.toml holds [[fact]] figure = \"needle_y.range_mm\", value = 18, set = { alpha = 0 },\n\
    tolerance = 0.25 (or weight = W; relative_to = { alpha = 0 } fits the difference to that setting; top-level\n\
    adjust = [\"l_cf=30:45\"] names the default parameters).\n\
    With --measured: the take-up measured on the machine (a CSV as `match --measured` reads it, one reading per\n\
    φ or repeated readings; docs/studies.md, \"Measured curves\"), one curve per thread, fitted by weighted least\n\
    squares (weights 1/σ² of the readings' uncertainty; with one reading per φ, σ estimated from the\n\
    residuals). Prints the setting the machine is at with its confidence intervals, the correlation of the\n\
    fitted parameters (a warning names two the data cannot tell apart), the residuals over φ, and, unless\n\
    --no-advice, the fitted machine's match against the stitch and the adjustment from the fitted setting to\n\
    the best one (the tune of the fitted machine settings).\n\
    --adjust NAME uses the parameter's range, NAME=LO:HI gives bounds. Levenberg-Marquardt with exact\n\
    Jacobians (dual numbers) where the figure is smooth; the start is the model with --set."
)]
#[command(mut_arg("format", |a| a.help(TABLE_OR_JSON_HELP)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// The facts file (TOML): [[fact]] tables with figure, value, set,
    /// relative_to, tolerance or weight, source.
    #[arg(long, value_name = "FILE", conflicts_with = "measured")]
    target: Option<PathBuf>,
    /// A take-up measured on the machine to fit: a CSV file with columns
    /// phi_deg and one of P_mm, P_B_mm, P_eye_mm (or THREAD.P_B_mm …; the
    /// column repeated for repeated readings). THREAD=FILE names the thread.
    /// Repeatable: several threads fit together.
    #[arg(long, value_name = "[THREAD=]FILE")]
    measured: Vec<String>,
    /// Parameters to fit, comma-separated: NAME (within its adjustable
    /// range) or NAME=LO:HI (default with --target: the facts file's
    /// `adjust`; with --measured: required). The start is the model's
    /// value, or --set.
    #[arg(long, value_delimiter = ',', value_name = "NAME[=LO:HI],…")]
    adjust: Option<Vec<String>>,
    /// Step of the main-shaft angle φ, degrees (default: the facts file's
    /// `step_deg`, else 1; with --measured: 1, or the largest step that
    /// holds every measured φ).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    step: Option<f64>,
    /// Levenberg–Marquardt iterations at most.
    #[arg(long, default_value_t = 100, value_name = "N")]
    max_iterations: usize,
    /// With --measured: the confidence of the intervals, 0 < P < 1.
    #[arg(long, default_value_t = 0.95, value_name = "P", requires = "measured")]
    confidence: f64,
    /// With --measured: only the fit, without the fitted machine's match and
    /// the adjustment to the best setting.
    #[arg(long, requires = "measured")]
    no_advice: bool,
    /// With --measured: draw the residuals over φ (model − measured, with
    /// the readings' interval) as an SVG chart into FILE.
    #[arg(long, value_name = "FILE.svg", requires = "measured")]
    chart: Option<PathBuf>,
    #[command(flatten)]
    output: OutputArgs<TableOrJson>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let Some(target) = &args.target else {
        if args.measured.is_empty() {
            return Err(Error::Param(ParamError::general(
                "nothing to fit to",
                Some(
                    "give --target FACTS.toml (stated figures to fit the model's dimensions to) or --measured \
                     [THREAD=]FILE (a take-up measured on the machine, to find its setting)"
                        .into(),
                ),
            )));
        }
        return run_measured(&args, &model, &params);
    };
    let facts = Facts::from_path(target)?;
    let opts = FitOptions {
        adjust: args.adjust.clone().unwrap_or_default(),
        step_deg: args.step,
        max_iterations: args.max_iterations,
    };
    let r = fit(&model, &params, &facts, &opts)?;
    let out = match args.output.format() {
        TableOrJson::Json => json(&r)?,
        TableOrJson::Table => text::fit::table(model.name(), &facts, &r),
    };
    args.output.emit(&out)
}

/// The fit to measured curves, its chart and its advice.
fn run_measured(args: &Args, model: &Model, params: &Params) -> Result<(), Error> {
    let Some(adjust) = args.adjust.clone() else {
        return Err(Error::Param(ParamError {
            input: Some(Input::Adjust),
            message: "a fit to measured curves needs the parameters to fit".into(),
            help: Some("name them: --adjust z,dphi (NAME within its range, or NAME=LO:HI)".into()),
        }));
    };
    if let Some(chart) = &args.chart {
        check_chart_path(chart)?;
    }
    let curves: Vec<CurveInput> = read_measured(&args.measured)?
        .into_iter()
        .map(|(thread, curve)| CurveInput { thread, curve })
        .collect();
    let opts = FitMeasuredOptions {
        adjust,
        step_deg: args.step,
        max_iterations: args.max_iterations,
        confidence: args.confidence,
    };
    let fit = fit_measured(model, params, &curves, &opts)?;
    let advice = if args.no_advice {
        None
    } else {
        Some(advise(model, params, &fit, 0, 1, 1.0)?)
    };
    let out = match args.output.format() {
        TableOrJson::Json => json(&serde_json::json!({ "fit": fit, "advice": advice }))?,
        TableOrJson::Table => text::fit_measured::screen(model.name(), &fit, advice.as_ref()),
    };
    if let Some(chart) = &args.chart {
        let svg = stitchkin::output::plots::fit_residuals(model.name(), &fit).render();
        crate::picture::emit_picture(&svg, Some(chart), false)?;
    }
    args.output.emit(&out)
}

/// `--chart FILE`: an .svg or .png name in a folder that exists, checked
/// before the fit.
fn check_chart_path(chart: &std::path::Path) -> Result<(), Error> {
    let ext = chart.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("svg" | "png")) {
        return Err(Error::Param(ParamError::general(
            format!("cannot tell the picture format of `{}` (in --chart)", chart.display()),
            Some("end the file name in .svg (vector, scalable) or .png (raster)".into()),
        )));
    }
    stitchkin::output::check_folder(chart)
}
