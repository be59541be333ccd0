//! `stitchkin sensitivity`: how much each adjustable parameter moves each
//! figure of merit, ranked (stitchkin::study::sensitivity).

use clap::ValueEnum;
use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::study::sensitivity::{RankBy, SensitivityOptions, sensitivity};

use crate::common::{ModelArgs, OutputArgs, TableFormat, json, load};

/// Rank the adjustable parameters by their effect on each figure of
/// merit: the exact derivative (dual numbers) times the range width, and
/// the change over the whole range.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  stitchkin sensitivity\n  \
    stitchkin sensitivity --preset mf7923d --figures 'n1_A.max_P_B_mm,mu.*' --params r1,z\n  \
    stitchkin sensitivity --preset needle876 --step 0.5 --format csv -o needle876-sensitivity.csv\n  \
    stitchkin sensitivity --figures '*.score' --rank range --format json\n\n\
    Per figure (names as in `stitchkin sweep --figures`) and parameter: d/dp at the setting, exact by\n\
    dual numbers for smooth figures (take-up, measure, coordinate and transmission-angle extremes) and a\n\
    central difference (c) for the match figures; effect = d/dp × range width (figure unit); at lo, at hi\n\
    = the figure at the range's ends, the others nominal (Manoilenko et al. (2024) Fig. 7); span = its max − min over the\n\
    range (9 settings). Ranked by |effect| (by span for the match figures, or for all with --rank range).\n\
    Units: mm/mm, mm/deg, deg/mm, pts/mm (score points); CSV columns figure, figure_unit, nominal, rank,\n\
    parameter, parameter_unit, range_lo, range_hi, derivative, derivative_unit, method, ..., span, note.")]
#[command(mut_arg("format", |a| a.help(
    format!("{}{}", "Output format: a readable table, CSV (one row per figure and parameter) or JSON", crate::common::DEFAULT_FORMAT_HELP)
)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Figures of merit, comma-separated patterns with `*` (names as in
    /// `stitchkin sweep --figures`; default: max P per path, match score per
    /// thread, transmission-angle extremes, measure ranges, point strokes).
    #[arg(long, value_delimiter = ',', value_name = "FIGURE,…")]
    figures: Option<Vec<String>>,
    /// Parameters to study, comma-separated (default: every parameter with
    /// an adjustable range).
    #[arg(long, value_delimiter = ',', value_name = "NAME,…")]
    params: Option<Vec<String>>,
    /// Rank by the local effect |dF/dp| × range width (`local`; the match
    /// figures by their span) or by the span max − min of the figure over
    /// the parameter's range (`range`).
    #[arg(long, value_enum, default_value_t = Rank::Local)]
    rank: Rank,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    #[command(flatten)]
    output: OutputArgs,
}

#[derive(Clone, Copy, ValueEnum)]
enum Rank {
    Local,
    Range,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let opts = SensitivityOptions {
        params: args.params.clone().unwrap_or_default(),
        figures: args.figures.clone().unwrap_or_default(),
        step_deg: args.step,
        rank: match args.rank {
            Rank::Local => RankBy::Local,
            Rank::Range => RankBy::Range,
        },
    };
    let r = sensitivity(&model, &params, &opts)?;
    let out = match args.output.format() {
        TableFormat::Json => json(&r)?,
        TableFormat::Csv => text::sensitivity::csv(&r),
        TableFormat::Table => text::sensitivity::table(&r),
    };
    args.output.emit(&out)
}
