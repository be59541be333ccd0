//! `stitchkin tolerance`: which dimensional tolerances keep a path straight
//! (stitchkin::study::straightness).

use clap::ValueEnum;
use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::study::straightness::{Distribution, ToleranceOptions, tolerance_study, tolerances};

use crate::common::{ModelArgs, OutputArgs, PathArgs, TableFormat, json, load, note};

/// Which dimensional tolerances keep a path straight: each parameter
/// alone at ± its tolerance, the largest tolerance each may have alone
/// (bisection), and a seeded Monte Carlo over all at once.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin tolerance --preset altin-needle --point E --limit 0.05\n  \
    stitchkin tolerance --preset altin-needle --point E --line N1,N2 --tol beta=0.1 --tol l_lm=0 --samples 200\n  \
    stitchkin tolerance --preset altin-needle --point E --length-tol 0 --tol l_ab=0.05 --tol l_be=0.05 --format json\n\n\
    Every length parameter without a --tol gets ±0.05 mm (--length-tol; Polyakov (2022)); angles need an\n\
    explicit --tol NAME=±T in degrees, and T = 0 holds a parameter exact. The deviation is max |d| from\n\
    the line (--line H,T or the least-squares line, over --over). Monte Carlo: uniform in ±T, or\n\
    normal with σ = T/3 truncated at ±T; percentiles 50/90/99 %; the same --seed gives the same result."
)]
#[command(mut_arg("format", |a| a.help(
    format!("{}{}", "Output format: a readable table, CSV (one row per parameter) or JSON", crate::common::DEFAULT_FORMAT_HELP)
)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    path: PathArgs,
    /// The largest max |deviation| allowed, mm (Polyakov (2022): ± 0.05 mm).
    #[arg(long, default_value_t = 0.05, value_name = "MM", allow_negative_numbers = true)]
    limit: f64,
    /// A parameter's tolerance NAME=±T in its unit (mm, deg or N); T = 0 holds
    /// it exact. Repeatable.
    #[arg(long = "tol", value_name = "NAME=±T", allow_hyphen_values = true)]
    tol: Vec<String>,
    /// Tolerance of every length parameter without a --tol, mm (Polyakov (2022):
    /// ± 0.05 mm); 0 studies only the --tol ones.
    #[arg(long, default_value_t = 0.05, value_name = "MM", allow_negative_numbers = true)]
    length_tol: f64,
    /// Monte Carlo samples, every tolerance at once (0: none).
    #[arg(long, default_value_t = 1000, value_name = "N")]
    samples: usize,
    /// Seed of the Monte Carlo (the same seed gives the same samples).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// How each dimension is drawn: uniform in ±T, or normal with σ = T/3
    /// truncated at ±T.
    #[arg(long, value_enum, default_value_t = Dist::Uniform)]
    distribution: Dist,
    #[command(flatten)]
    output: OutputArgs,
}

#[derive(Clone, Copy, ValueEnum)]
enum Dist {
    Uniform,
    Normal,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let opts = ToleranceOptions {
        straightness: args.path.options(&model)?,
        limit_mm: args.limit,
        tolerances: tolerances(&model, &args.tol, args.length_tol)?,
        samples: args.samples,
        seed: args.seed,
        distribution: match args.distribution {
            Dist::Uniform => Distribution::Uniform,
            Dist::Normal => Distribution::Normal,
        },
    };
    let t = tolerance_study(&model, &params, &opts)?;
    let out = match args.output.format() {
        TableFormat::Json => json(&t)?,
        TableFormat::Csv => text::straightness::tolerance_csv(&t),
        TableFormat::Table => text::straightness::tolerance_table(model.name(), &t, opts.straightness.step_deg),
    };
    args.output.emit(&out)?;
    if matches!(args.output.format(), TableFormat::Csv) {
        note(&text::straightness::monte_carlo(&t, "# "));
    }
    Ok(())
}
