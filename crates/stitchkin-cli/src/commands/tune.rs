//! `stitchkin tune`: the machine settings that make the take-up match the
//! stitch best (stitchkin::study::tune).

use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::study::tune::tune;

use crate::common::{ModelArgs, OutputArgs, SearchArgs, TABLE_OR_JSON_HELP, TableOrJson, json, load};

/// Find the machine settings that make the take-up P match the stitch's
/// required P' best, for every thread together, with every transmission
/// angle inside 30°…150° and every physical check passing.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin tune\n  stitchkin tune --thickness 4 --stitch 2.5\n  \
    stitchkin tune --preset mf7923d --adjust z,dphi --seed 3\n  \
    stitchkin tune --preset altin504\n  \
    stitchkin tune --preset mf7923d --format json -o tuned.json\n\n\
    Default settings to adjust: the model's machine settings (kind = \"setting\" in [parameters], with a\n\
    range), except the thread's tension settings (regulator, clamp, check spring), which are adjusted\n\
    when named. A job input (the material thickness, the stitch length, the thread) or a fixed\n\
    dimension is refused unless --allow-inputs or --allow-dimensions says so. Constraints: the\n\
    transmission angles inside 30°…150° and every physical check passing. The search: a seeded\n\
    Latin-hypercube sample (global) and Nelder-Mead (local); the same seed gives the same answer.\n\
    Prints the recommended setting and how to make it on the machine (which part, which way, how far),\n\
    the match and the checks before and after, how far each setting may move with the match within one\n\
    score point of the optimum, and notes: a setting on an end of its range, a match that does not\n\
    improve, no setting that passes the checks.\n\
    Exit status 0 when the search ran, also when no setting in the ranges passes the checks: the answer\n\
    is then that the ranges hold none (the note says so; JSON `after_figures.feasible` is false and\n\
    `after_figures.failed_checks` names them), which is what a search is asked; `stitchkin match\n\
    --set ...` on the recommended setting exits 1 when one of its checks fails."
)]
#[command(mut_arg("format", |a| a.help(TABLE_OR_JSON_HELP)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    search: SearchArgs,
    #[command(flatten)]
    output: OutputArgs<TableOrJson>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    args.search.check()?;
    let (mut model, params) = load(&args.model)?;
    args.search.allow(&mut model);
    let adjust = match &args.search.adjust {
        Some(a) => a.clone(),
        None => model.default_adjustables(&params)?,
    };
    SearchArgs::check_kinds(&model, &adjust)?;
    let r = tune(&model, &params, &args.search.options(adjust))?;
    let out = match args.output.format() {
        TableOrJson::Json => json(&r)?,
        TableOrJson::Table => text::tune::table(&r),
    };
    args.output.emit(&out)
}
