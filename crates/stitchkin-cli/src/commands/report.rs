//! `stitchkin report`: one self-contained HTML file about a model
//! (stitchkin::jobs::report).

use std::path::PathBuf;

use stitchkin::error::{Error, Input, ParamError};
use stitchkin::jobs::report::{self, ReportOptions};
use stitchkin::output::drawing::View;
use stitchkin::study::nomogram::{Axis, NomogramOptions};

use crate::common::{ModelArgs, SearchArgs, emit, in_flag, load, note_line};

/// One self-contained HTML report: parameters, mechanism drawing (still
/// and animated), P/P′ chart, mismatch, transmission angles and, when
/// asked, the tuning result and a nomogram.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  stitchkin report -o report.html\n  \
    stitchkin report --preset altin504 --thickness 2 -o altin504.html\n  \
    stitchkin report --tune --nomogram-thickness 1:5:3 -o tuned.html\n  \
    stitchkin report --measured n1=n1-measured.csv -o measured.html\n\n\
    The file holds everything (styles, every picture as inline SVG, no script) and opens in any browser (docs/report.md).")]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Main-shaft angle of the still mechanism drawing, degrees (default:
    /// the model's start).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    phi: Option<f64>,
    /// View of the mechanism drawings: xy, xz, yz, iso or a model frame
    /// (default: iso for a spatial model, xy for a planar one).
    #[arg(long, value_name = "VIEW")]
    view: Option<String>,
    /// Leave out the animated drawing (a smaller file).
    #[arg(long)]
    no_animation: bool,
    /// Tune the machine settings (as `stitchkin tune`) and report the
    /// recommended setting, how to make it on the machine, and its P/P′
    /// chart.
    #[arg(long)]
    tune: bool,
    /// Add a nomogram over this material thickness, mm: LO:HI:N (as
    /// `stitchkin nomogram --thickness`).
    #[arg(long, value_name = "LO:HI:N", allow_hyphen_values = true)]
    nomogram_thickness: Option<String>,
    /// The nomogram's stitch lengths, mm, LO:HI:N (default: the model's).
    #[arg(
        long,
        value_name = "LO:HI:N",
        allow_hyphen_values = true,
        requires = "nomogram_thickness"
    )]
    nomogram_stitch: Option<String>,
    /// A measured take-up P or required P′ to set beside the model (CSV:
    /// phi_deg and P_mm, P_B_mm, Pprime_B_mm, …; [THREAD=]FILE, as
    /// `stitchkin match --measured`). Repeatable.
    #[arg(long, value_name = "[THREAD=]FILE")]
    measured: Vec<String>,
    /// Tuning settings (--tune and the nomogram), and the φ step of every
    /// cycle in the report.
    #[command(flatten)]
    search: SearchArgs,
    /// Write the report to FILE.html (written completely or not at all)
    /// instead of stdout.
    #[arg(short, long, value_name = "FILE.html")]
    output: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    args.search.check()?;
    let (mut model, params) = load(&args.model)?;
    args.search.allow(&mut model);
    if let Some(path) = &args.output {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("html" | "htm")) {
            return Err(Error::Param(ParamError::general(
                format!(
                    "the report is HTML, but `{}` does not end in .html (in -o)",
                    path.display()
                ),
                Some("name it e.g. report.html".into()),
            )));
        }
        stitchkin::output::check_folder(path)?;
    }
    let adjust = args.search.adjust.clone().unwrap_or_default();
    let tune_opts = args.search.options(adjust.clone());
    SearchArgs::check_kinds(&model, &adjust)?;
    let tune = if args.tune {
        let mut t = tune_opts.clone();
        if t.adjust.is_empty() {
            t.adjust = model.default_adjustables(&params)?;
        }
        Some(t)
    } else {
        None
    };
    let nomogram = match &args.nomogram_thickness {
        None => None,
        Some(th) => Some(NomogramOptions {
            thickness: Axis::parse(th, Input::Thickness).map_err(|e| in_flag(e, "--nomogram-thickness"))?,
            stitch: args
                .nomogram_stitch
                .as_deref()
                .map(|s| Axis::parse(s, Input::StitchLength).map_err(|e| in_flag(e, "--nomogram-stitch")))
                .transpose()?,
            tune: tune_opts,
        }),
    };
    let opts = ReportOptions {
        step_deg: args.search.step,
        phi_deg: args.phi,
        view: args.view.as_deref().map(View::parse).transpose()?,
        animate: !args.no_animation,
        tune,
        nomogram,
        measured: crate::common::read_measured(&args.measured)?,
    };
    if opts.tune.is_some() || opts.nomogram.is_some() {
        note_line("# report: tuning (this takes a few seconds per tuning)…");
    }
    let html = report::render(&model, &params, &opts)?;
    emit(html.as_bytes(), args.output.as_ref())
}
