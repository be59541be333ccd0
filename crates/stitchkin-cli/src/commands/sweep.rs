//! `stitchkin sweep`: figures of merit over a grid or samples of the
//! adjustable parameters, streamed as CSV (stitchkin::study::sweep).

use std::path::PathBuf;
use std::str::FromStr;

use clap::ValueEnum;
use stitchkin::error::Error;
use stitchkin::output::{self, text};
use stitchkin::study::design::{Design, Sweep, Vary};
use stitchkin::study::sweep;
use stitchkin::study::sweep::SweepPlan;

use crate::common::{
    ModelArgs, TableOrCsv, emit_text, format_or_default, full_table_hint, load, note, note_written, progress_bar,
};

/// Sweep adjustable parameters over a grid or random / Latin-hypercube
/// samples, in parallel, and write figures of merit per setting (CSV,
/// streamed).
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin sweep --vary z=-10:10:21 --vary dphi=-20:20:21\n  \
    stitchkin sweep --preset mf7923d --vary r1=4:6 --vary z=-10:10 --samples 1000 --method lhs --seed 7 -o lhs.csv\n  \
    stitchkin sweep --preset needle876 --vary alpha=0:35:36 --figures 'needle_y.range_mm,mu.*'\n  \
    stitchkin sweep --vary z=-10:10:101 --vary dphi=-20:20:101 --shard 2/4 -o part2.csv\n\n\
    Figures of merit (--figures, patterns with *): PATH.max_P_mm, PATH.min_P_mm (PATH.max_P_B_mm,\n\
    PATH.min_P_B_mm for a needle thread split at B), THREAD.score, THREAD.rms_D_mm, THREAD.max_abs_D_mm,\n\
    THREAD.max_Pprime_B_mm (needle) or THREAD.max_Pprime_mm (looper), THREAD.checks_ok,\n\
    THREAD.bound_margin_mm, checks.ok, score.mean, score.min, mu.min_deg,\n\
    mu.max_deg, mu.ok, mu_KEY.min_deg, MEASURE.range_mm, POINT.y_stroke_mm, ... (the first setting's\n\
    list is printed when a pattern matches nothing). By default: *.score, score.*, *.max_P_B_mm,\n\
    *.max_P_mm, checks.ok, mu.min_deg, mu.max_deg, *.range_mm, *_stroke_mm. Columns: index, the varied parameters, the\n\
    figures, status (ok, or why the setting did not evaluate; its figures are then empty).\n\
    On a terminal (without --format or -o) sweep shows its summary; into a pipe or a file, the CSV\n\
    (the summary goes to stderr).\n\
    Shards are contiguous blocks and only shard 1 writes the header: `cat part*.csv` is the sweep.\n\
    Exit status 0 when the sweep ran, whatever its settings' checks say: a sweep maps where a machine can\n\
    work and where not, so each row carries THREAD.checks_ok and checks.ok (1 or 0) instead of failing the\n\
    command; `stitchkin match --set ...` on one setting exits 1 when a check fails."
)]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// A swept parameter: NAME=LO:HI:N (N values, ends included; default N
    /// 11). Repeatable: a grid over all of them, the last fastest.
    #[arg(long = "vary", value_name = "NAME=LO:HI:N", required = true)]
    vary: Vec<String>,
    /// Draw this many samples in the box instead of the grid.
    #[arg(long, value_name = "N")]
    samples: Option<usize>,
    /// How samples are drawn.
    #[arg(long, value_enum, default_value_t = Method::Lhs, requires = "samples")]
    method: Method,
    /// Seed of the samples (the same seed gives the same samples).
    #[arg(long, default_value_t = 1, requires = "samples")]
    seed: u64,
    /// Figures of merit, comma-separated patterns (default: every match
    /// score, the take-up extremes and the transmission-angle extremes).
    #[arg(long, value_delimiter = ',', value_name = "PATTERN,…")]
    figures: Option<Vec<String>>,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Evaluate only shard K of N (contiguous blocks, 1-based).
    #[arg(long, value_name = "K/N")]
    shard: Option<Shard>,
    /// Output format: table (the summary: how many settings, the largest
    /// and smallest figure, where) or CSV, one row per setting (default:
    /// the summary on a terminal, CSV into a pipe or a file).
    #[arg(long, value_enum)]
    format: Option<TableOrCsv>,
    /// Write to FILE instead of stdout (complete, or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum Method {
    Lhs,
    Random,
}

/// `--shard K/N`: the K-th of N contiguous blocks of the settings, 1-based.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Shard {
    k: usize,
    n: usize,
}

impl Shard {
    /// The whole sweep.
    const ALL: Shard = Shard { k: 1, n: 1 };
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Shard, String> {
        let parsed = s
            .split_once('/')
            .and_then(|(k, n)| Some((k.trim().parse::<usize>().ok()?, n.trim().parse::<usize>().ok()?)));
        match parsed {
            Some((k, n)) if n >= 1 && (1..=n).contains(&k) => Ok(Shard { k, n }),
            _ => Err(format!(
                "`{s}` is not a shard K/N with 1 ≤ K ≤ N (e.g. --shard 2/4 evaluates the second quarter)"
            )),
        }
    }
}

/// The sweep the arguments describe, on `model`.
fn design(args: &Args, model: &stitchkin::model::Model) -> Result<Sweep, Error> {
    let vary = args
        .vary
        .iter()
        .map(|v| Vary::parse(model, v))
        .collect::<Result<Vec<_>, _>>()?;
    let design = match (args.samples, args.method) {
        (None, _) => Design::Grid,
        (Some(samples), Method::Lhs) => Design::Lhs {
            samples,
            seed: args.seed,
        },
        (Some(samples), Method::Random) => Design::Random {
            samples,
            seed: args.seed,
        },
    };
    Sweep::new(vary, design)
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let sw = design(&args, &model)?;
    let plan = SweepPlan::new(&model, &params, &sw, args.figures.as_deref(), args.step)?;
    let names = &plan.names;
    let Shard { k, n } = args.shard.unwrap_or(Shard::ALL);
    let range = sw.shard(k, n);
    let total = range.len();
    let bar = progress_bar(total, "{bar:40} {pos}/{len} settings, {rate} settings/s, ETA {eta}");
    let table = matches!(format_or_default(args.format, args.output.as_deref()), TableOrCsv::Csv);
    // Stream to a temporary file next to the output (renamed at the end), or
    // to stdout; only the first shard writes the header. On a terminal the
    // rows are tallied, not printed.
    let mut sink = if table {
        Some(output::Sink::new(args.output.as_deref())?)
    } else {
        None
    };
    let header = if k == 1 {
        text::sweep::header(&model, &sw, names)
    } else {
        String::new()
    };
    let mut bytes = header.len();
    if let Some(sink) = &mut sink {
        sink.write(header.as_bytes())?;
    }
    let mut tally = text::sweep::Tally::new(names);
    sweep::run(
        plan.job(&model, &params, &sw),
        range,
        |row| {
            tally.add(row);
            match &mut sink {
                Some(sink) => {
                    let line = text::sweep::row(row);
                    bytes += line.len();
                    sink.write(line.as_bytes())
                }
                None => Ok(()),
            }
        },
        |d| bar.inc(d as u64),
    )?;
    bar.finish_and_clear();
    let summary = tally.summary(&sw, names, total, (k, n));
    match sink {
        Some(sink) => {
            sink.finish()?;
            note(&summary);
            if let Some(path) = &args.output {
                note_written(path, bytes);
            }
            Ok(())
        }
        None => emit_text(
            &(summary + &full_table_hint(&format!("one row per setting, {total} rows"))),
            args.output.as_ref(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_parses_k_of_n() {
        assert_eq!("2/4".parse::<Shard>(), Ok(Shard { k: 2, n: 4 }));
        assert_eq!(" 1 / 1 ".parse::<Shard>(), Ok(Shard::ALL));
        assert_eq!("3/3".parse::<Shard>(), Ok(Shard { k: 3, n: 3 }));
    }

    #[test]
    fn shard_refuses_what_is_not_k_of_n() {
        for bad in ["4/3", "0/3", "1/0", "2", "x/3", "2/y", "-1/3", "", "1/2/3"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert!(e.contains("is not a shard K/N") && e.contains(bad), "{bad}: {e}");
        }
    }
}
