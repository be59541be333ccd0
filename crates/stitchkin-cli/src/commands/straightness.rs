//! `stitchkin straightness`: how far a point's path strays from a straight
//! line (stitchkin::study::straightness).

use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::study::straightness::straightness;

use crate::common::{ModelArgs, OutputArgs, PathArgs, TableFormat, json, load, note};

/// How far a point's path strays from a straight line (two model points,
/// or the least-squares line): max and RMS deviation, minimum zone, over
/// the cycle or the working stroke.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin straightness --preset altin-needle --point E --line N1,N2\n  \
    stitchkin straightness --preset altin-needle --point E --fit --over down\n  \
    stitchkin straightness --preset altin-needle --point E --over 300:60 --step 0.25 --format csv -o dev.csv\n\n\
    Paths in the world xy-plane: the deviation is signed, + to the left of the line's direction (as\n\
    the line_deviation measure); spatial ones: the distance. --over down is the working stroke from the\n\
    far dead centre along the line to the near one. CSV: phi_deg, P.along_mm, P.dev_mm per sample."
)]
#[command(mut_arg("format", |a| a.help(
    format!("{}{}", "Output format: a readable summary, CSV (the deviation per φ sample) or JSON", crate::common::DEFAULT_FORMAT_HELP)
)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    path: PathArgs,
    #[command(flatten)]
    output: OutputArgs,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let opts = args.path.options(&model)?;
    let s = straightness(&model, &params, &opts)?;
    let summary = text::straightness::summary(model.name(), &s, opts.step_deg);
    let out = match args.output.format() {
        TableFormat::Json => json(&s)?,
        TableFormat::Table => summary.clone(),
        TableFormat::Csv => text::straightness::csv(&s),
    };
    args.output.emit(&out)?;
    if matches!(args.output.format(), TableFormat::Csv) {
        note(&text::straightness::commented(&summary));
    }
    Ok(())
}
