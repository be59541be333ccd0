//! `stitchkin tune`: the adjustable settings that make the take-up match
//! the stitch best (stitchkin::study::tune).

use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::study::tune::{set_stitch_value, tune};

use crate::common::{ModelArgs, OutputArgs, SearchArgs, TABLE_OR_JSON_HELP, TableOrJson, json, load};

/// Find the adjustable settings that make the take-up P match the
/// stitch's required P' best, for every thread together, with every
/// transmission angle inside 30°…150° and every physical check passing.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin tune\n  stitchkin tune --thickness 4 --stitch 2.5\n  \
    stitchkin tune --preset mf7923d --adjust z,dphi --seed 3\n  \
    stitchkin tune --preset mf7923d --format json -o tuned.json\n\n\
    Default settings to adjust: every parameter with an adjustable range that leaves the stitch\n\
    alone. Constraints: the transmission angles inside 30°…150° and every physical check passing.\n\
    The search: a seeded Latin-hypercube sample (global) and Nelder-Mead (local); the same\n\
    seed gives the same answer. Prints the recommended setting, the match and the checks before and\n\
    after, how far each setting may move with the match within one score point of the optimum, and\n\
    notes: a setting on an end of its range, a match that does not improve, no setting that passes\n\
    the checks."
)]
#[command(mut_arg("format", |a| a.help(TABLE_OR_JSON_HELP)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Material thickness m, mm (sets the parameter [stitch] m_mm names).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    thickness: Option<f64>,
    /// Stitch length t, mm (sets the parameter [stitch] t_mm names).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    stitch: Option<f64>,
    #[command(flatten)]
    search: SearchArgs,
    #[command(flatten)]
    output: OutputArgs<TableOrJson>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    args.search.check()?;
    let (model, mut params) = load(&args.model)?;
    if let Some(m) = args.thickness {
        set_stitch_value(&model, &mut params, "m", m)?;
    }
    if let Some(t) = args.stitch {
        set_stitch_value(&model, &mut params, "t", t)?;
    }
    let adjust = match &args.search.adjust {
        Some(a) => a.clone(),
        None => model.default_adjustables(&params)?,
    };
    let r = tune(&model, &params, &args.search.options(adjust))?;
    let out = match args.output.format {
        TableOrJson::Json => json(&r)?,
        TableOrJson::Table => text::tune::table(&r),
    };
    args.output.emit(&out)
}
