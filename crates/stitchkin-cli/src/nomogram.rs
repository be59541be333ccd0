//! `stitchkin nomogram`: the tuned setting over a grid of material thickness
//! and stitch length (stitchkin::study::nomogram).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stitchkin::error::Error;
use stitchkin::study::nomogram::{Axis, NomogramOptions, nomogram};

#[derive(Args)]
pub struct NomogramArgs {
    #[command(flatten)]
    model: crate::ModelArgs,
    /// Material thickness m, mm: LO:HI:N (N values, ends included), LO:HI
    /// (11 values) or one value (default: 5 values over the range of the
    /// parameter [stitch] m_mm names). Sets that parameter.
    #[arg(long, value_name = "LO:HI:N", allow_hyphen_values = true)]
    thickness: Option<String>,
    /// Stitch length t, mm, as LO:HI:N (default: the model's stitch length).
    #[arg(long, value_name = "LO:HI:N", allow_hyphen_values = true)]
    stitch: Option<String>,
    #[command(flatten)]
    search: crate::SearchArgs,
    /// Output format: a readable table, CSV or JSON.
    #[arg(long, value_enum, default_value_t = NomogramFormat::Table)]
    format: NomogramFormat,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum NomogramFormat {
    Table,
    Csv,
    Json,
}

pub fn run(args: NomogramArgs) -> Result<(), Error> {
    let (model, params) = crate::load(&args.model)?;
    // A bad -o is reported before the tuning, not after it.
    if let Some(path) = &args.output {
        stitchkin::output::check_folder(path)?;
    }
    let thickness = match &args.thickness {
        Some(t) => Axis::parse(t, "--thickness")?,
        None => stitchkin::study::nomogram::default_thickness(&model)?,
    };
    let stitch = args.stitch.as_deref().map(|s| Axis::parse(s, "--stitch")).transpose()?;
    let opts = NomogramOptions {
        thickness,
        stitch,
        tune: args.search.options(args.search.adjust.clone().unwrap_or_default()),
    };
    let points = thickness.n * stitch.map_or(1, |s| s.n);
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        let b = indicatif::ProgressBar::new(points as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} grid points tuned, ETA {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let started = std::time::Instant::now();
    let result = nomogram(&model, &params, &opts, || bar.inc(1));
    bar.finish_and_clear();
    let n = result?;
    let out = match args.format {
        NomogramFormat::Table => stitchkin::output::text::nomogram::table(&n),
        NomogramFormat::Csv => stitchkin::output::text::nomogram::csv(&n),
        NomogramFormat::Json => serde_json::to_string_pretty(&n).map_err(|e| Error::Io(e.to_string()))? + "\n",
    };
    crate::emit(out.as_bytes(), args.output.as_ref())?;
    let failed = n.points.iter().filter(|p| p.tuned.is_none()).count();
    let cycles: usize = n.tuned().map(|(_, r)| r.evaluations).sum();
    eprintln!(
        "# nomogram: {} grid points tuned ({failed} failed), {cycles} cycles in {:.1} s",
        n.points.len() - failed,
        started.elapsed().as_secs_f64()
    );
    if n.all_scores_zero() && !matches!(args.format, NomogramFormat::Table) {
        eprintln!(
            "warning: every match score is 0 at every grid point: no setting in the ranges fits this stitch (the recommendations only minimise J)"
        );
    }
    Ok(())
}
