//! `stitchkin run`: a model evaluated over one main-shaft cycle, as CSV or
//! JSON, with its summary.

use std::path::PathBuf;

use stitchkin::error::{Error, Input};
use stitchkin::eval::{self, CycleOptions};
use stitchkin::output::{self, text};

use crate::common::{
    ModelArgs, SinkWriter, TableFormat, emit_text, format_or_default, full_table_hint, load, note, note_written,
};

/// Evaluate a model over one main-shaft cycle: positions, analogs,
/// velocities, link and transmission angles, measures.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  stitchkin run\n  \
    stitchkin run --preset needle876 --set alpha=35 --step 0.5 --rpm 3000\n  \
    stitchkin run my-machine.toml --points G,E --format json -o out.json\n  \
    stitchkin run --columns '*.P_B_mm,*.G4_*_engaged'\n\n\
    Columns carry their units: phi_deg, G.y_mm, G.dy_dphi_mm_per_rad, G.d2y_dphi2_mm_per_rad2,\n\
    G.vy_mm_per_s (with --rpm), angle_A_B_deg, mu_23_deg, needle_y_mm, ...; a thread path's take-up\n\
    PATH.P_mm, or PATH.P_B_mm and PATH.P_eye_mm for a needle thread split at B (the eye's top position);\n\
    a stitch thread's THR.Pprime_B_mm (needle) or THR.Pprime_mm (looper) and THR.D_mm.\n\
    On a terminal (without --format or -o) run shows a readable summary (transmission angles, measure\n\
    ranges, take-up, match, physical checks, notes, warnings), or with --columns those columns every\n\
    few degrees; into a pipe or a file it writes the table (CSV, or JSON) and the summary goes to stderr.")]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Main-shaft speed, rev/min: adds real velocities and accelerations
    /// (default: the model's `rpm`, if any).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    rpm: Option<f64>,
    /// Points to tabulate, comma-separated (default: the model's output points).
    #[arg(long, value_delimiter = ',', value_name = "A,B,…")]
    points: Option<Vec<String>>,
    /// Columns to print, comma-separated patterns where `*` matches anything
    /// (e.g. `*.P_B_mm,mu_*`); phi_deg is always printed.
    #[arg(long, value_delimiter = ',', value_name = "PATTERN,…")]
    columns: Option<Vec<String>>,
    /// Positions only, without analogs.
    #[arg(long)]
    no_analogs: bool,
    /// Output format: table (a readable summary; with --columns, the
    /// columns every few degrees), CSV or JSON (default: the summary on a
    /// terminal, CSV into a pipe or a file; -o FILE.json JSON).
    #[arg(long, value_enum)]
    format: Option<TableFormat>,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let points = args
        .points
        .as_deref()
        .map(|p| model.point_slots(p, Input::Points))
        .transpose()?;
    let opts = CycleOptions {
        step_deg: args.step,
        rpm: args.rpm.or(model.rpm()),
        analogs: !args.no_analogs,
        points,
        lean: false,
    };
    // Only what the columns asked for need: without a column of the
    // stitch's, no stitch process and no thread tension.
    let table = match &args.columns {
        Some(patterns) => eval::run_cycle_columns(&model, &params, &opts, patterns)?,
        None => eval::run_cycle(&model, &params, &opts)?,
    };
    let format = format_or_default(args.format, args.output.as_deref());
    if let TableFormat::Table = format {
        // A person at a terminal gets the summary, or the asked columns
        // every few degrees: 360 rows of a few hundred columns read
        // nowhere but in a file or a pipe.
        let s = match &args.columns {
            Some(_) => {
                text::cycle::columns_table(&table, SHOWN_ROWS)
                    + &full_table_hint(&format!("every row, {} of them", table.rows()))
            }
            None => {
                text::cycle::summary(&model, &table)
                    + &full_table_hint(&format!(
                        "the full table, {} rows × {} columns; how P matches P′: `stitchkin match`",
                        table.rows(),
                        table.columns.len()
                    ))
            }
        };
        return emit_text(&s, args.output.as_ref());
    }
    // Streamed: a table of 0.001° steps is 700 MB of CSV. A file appears
    // whole when the sink finishes, or not at all.
    let mut sink = output::Sink::new(args.output.as_deref())?;
    let mut out = SinkWriter::new(&mut sink);
    match format {
        TableFormat::Json => output::write_json(&model, &params, &table, &mut out),
        _ => output::write_csv(&table, &mut out),
    }
    .map_err(|e| Error::Internal(format!("cannot format the cycle table: {e}")))?;
    let bytes = out.bytes;
    sink.finish()?;
    if matches!(format, TableFormat::Csv) || args.output.is_some() {
        note(&text::cycle::summary(&model, &table));
    }
    if let Some(path) = &args.output {
        note_written(path, bytes);
    }
    Ok(())
}

/// The most rows `run --columns` shows on a terminal: every 10° of a 1°
/// table (37 rows with both ends).
const SHOWN_ROWS: usize = 37;
