//! `stitchkin measured`: a bench's repeated readings of a take-up
//! processed as seed 004 §3.4 ([`stitchkin::thread::repeated`]).

use std::path::PathBuf;

use stitchkin::error::{Error, ParamError};
use stitchkin::output::text;
use stitchkin::{ReadingOptions, read_curve_with};

use crate::common::{OutputArgs, TableFormat, json};

/// Repeated readings of a take-up processed as Polyakov (2022) §3.4: per φ
/// the number of readings, the mean, the standard deviation, Student's t,
/// the interval, the random, systematic (the instrument's resolution),
/// total and relative errors, and the readings Grubbs' test flags.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  stitchkin measured bench.csv --resolution 0.05\n  \
    stitchkin measured bench.csv --confidence 0.99 -o bench-processed.csv\n  \
    stitchkin match --measured lower=bench.csv   # the mean curve and its interval beside the model\n\n\
    The file: a header `phi_deg,P_mm,P_mm,…` with one column per reading, or rows of the same φ one\n\
    after another (`phi_deg,P_mm`), or both; at least two readings at every φ. The resolution (the\n\
    instrument's largest error, the systematic error of each mean) comes from --resolution or a line\n\
    `# resolution_mm = 0.05` in the file; the confidence from --confidence, `# confidence = 0.95` or\n\
    0.95. Δ = √(Δr² + Δs²) with Δr = t·s/√n; the mean curve carries σ = √(s²/n + Δs²/3).\n\
    Outliers (Grubbs' test at α = 1 − confidence) are flagged, never removed (docs/studies.md,\n\
    \"Repeated readings\").")]
pub(crate) struct Args {
    /// The readings, a CSV file.
    #[arg(value_name = "FILE")]
    file: PathBuf,
    /// The instrument's resolution (its largest error), mm; stands for the
    /// file's `# resolution_mm` line.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    resolution: Option<f64>,
    /// The confidence of the intervals, 0…1 (default: the file's
    /// `# confidence` line, or 0.95).
    #[arg(long, value_name = "P", allow_negative_numbers = true)]
    confidence: Option<f64>,
    #[command(flatten)]
    output: OutputArgs,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let options = ReadingOptions {
        resolution_mm: args.resolution,
        confidence: args.confidence,
    };
    let curve = read_curve_with(&args.file, &options)?;
    let Some(p) = curve.readings() else {
        return Err(Error::Param(ParamError::general(
            format!("{}: one reading per φ, nothing to process", curve.source()),
            Some(
                "give several readings per φ (a column per reading, `phi_deg,P_mm,P_mm,…`, or rows of the same φ); \
                 a curve of one value per φ goes straight to `stitchkin match --measured`"
                    .into(),
            ),
        )));
    };
    let out = match args.output.format() {
        TableFormat::Json => json(&serde_json::json!({
            "source": curve.source(),
            "column": curve.column(),
            "confidence": p.confidence,
            "resolution_mm": p.resolution_mm,
            "points": p.points,
        }))?,
        TableFormat::Csv => text::readings::csv(p),
        TableFormat::Table => text::readings::table(p, curve.source()),
    };
    args.output.emit(&out)
}
