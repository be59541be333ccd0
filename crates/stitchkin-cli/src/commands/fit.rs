//! `stitchkin fit`: fit model dimensions to stated results
//! (stitchkin::study::fit).

use std::path::PathBuf;

use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::study::fit::{Facts, FitOptions, fit};

use crate::common::{ModelArgs, OutputArgs, TABLE_OR_JSON_HELP, TableOrJson, json, load};

/// Fit model dimensions (figure-only, reconstructed ones) to stated
/// results by weighted least squares within bounds, and report the
/// fitted values, the residual per fact and the cost.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin fit --preset needle876 --target examples/facts/needle876.toml --set y_c=170\n  \
    stitchkin fit --preset needle876 --target examples/facts/needle876.toml --set l_cf=41 --adjust l_cf=30:45\n  \
    stitchkin fit my-machine.toml --target facts.toml --adjust y_c=160:190,l_cf=30:45 --format json -o fit.json\n\n\
    facts.toml: [[fact]] figure = \"needle_y.range_mm\", value = 18, set = { alpha = 0 }, tolerance = 0.25\n\
    (or weight = W; relative_to = { alpha = 0 } fits the difference to that setting; top-level\n\
    adjust = [\"l_cf=30:45\"] names the default parameters). --adjust NAME uses the parameter's range,\n\
    NAME=LO:HI gives bounds. Levenberg-Marquardt with exact Jacobians (dual numbers) where the figure is\n\
    smooth; the start is the model with --set."
)]
#[command(mut_arg("format", |a| a.help(TABLE_OR_JSON_HELP)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
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
    #[command(flatten)]
    output: OutputArgs<TableOrJson>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let facts = Facts::from_path(&args.target)?;
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
