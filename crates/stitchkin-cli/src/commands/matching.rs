//! `stitchkin match`: the take-up P against the thread the stitch needs,
//! P′, per thread, with the match scores and the physical checks, in one
//! screen (`--details` for every metric, `--format json` for all of it).

use stitchkin::error::{Error, PhysicalError, StitchError};
use stitchkin::eval;
use stitchkin::output::text;

use crate::common::{ModelArgs, OutputArgs, TABLE_OR_JSON_HELP, TableOrJson, load, measured};

/// Compare the take-up P(φ) with the thread the stitch needs, P'(φ), for
/// every thread of the model's `[stitch]`: per-stitch consumption, the
/// mismatch D = P − P' and the match score.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin match\n  stitchkin match --preset mf7923d --thickness 4 --stitch 2.5\n  \
    stitchkin match --details\n  stitchkin match --measured n1=n1-measured.csv\n  \
    stitchkin match my-machine.toml --format json -o match.json\n  \
    stitchkin match examples/seed004-variants/variant1.toml --measured lower=examples/altin504-lower-pprime.csv\n\n\
    One screen: per thread the score, RMS(D), max P, max P', the thread per stitch and the physical checks\n\
    passed; P against P' as sparklines; the checks; the model's caveats. Needle threads are measured at B,\n\
    the eye's top position; each thread's regulator window is left out of the metrics.\n\
    D > 0 is thread given but not needed (slack), D < 0 thread needed but not given (strain).\n\
    Score s = 100·max(0, 1 − RMS(D)/range(P')): 100 is a perfect match (docs/stitch-formation.md §8).\n\
    The P' columns themselves come with `stitchkin run` (THR.Pprime_B_mm, THR.Pprime_mm, THR.D_mm, ...).\n\
    Exit status: 0 when every physical check passes; 1 when one fails (the screen or file is written in full\n\
    first: the setting evaluates, but no real machine can sew it) or on an error. A step coarser than 1° is\n\
    compared with 1° and a warning says by how much the scores move.\n\
    A model without [stitch] (a feed mechanism alone) is matched against the curves given with --measured\n\
    PATH=FILE: a required take-up (column Pprime_mm) against the path's P, over the whole turn."
)]
#[command(mut_arg("format", |a| a.help(TABLE_OR_JSON_HELP)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// A measured take-up P or required P′ to set beside the model: a CSV
    /// file with columns phi_deg and one of P_mm, P_B_mm, P_eye_mm,
    /// Pprime_mm, Pprime_B_mm, Pprime_eye_mm (optionally THREAD.P_B_mm), any
    /// φ step (docs/studies.md, "Measured curves"). THREAD=FILE names the
    /// thread. Repeatable.
    #[arg(long, value_name = "[THREAD=]FILE")]
    measured: Vec<String>,
    /// Every metric of every thread: areas, intervals, phase, best lag, the
    /// jumps of P′, the moments, each check in full.
    #[arg(long)]
    details: bool,
    #[command(flatten)]
    output: OutputArgs<TableOrJson>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let table = eval::run_match(&model, &params, args.step)?;
    let measured = measured(&args.measured, &table)?;
    let out = match (&table.stitch, args.output.format()) {
        (None, _) if measured.is_empty() => {
            return Err(Error::Stitch(StitchError::new(
                format!("model `{}`", model.name()),
                "it has no [stitch] table, so there is no required take-up to match; add one (docs/model-format.md, \
                 \"Stitch process\"), give the required take-up of a path as --measured PATH=FILE (a column \
                 Pprime_mm), or try --preset mf7923d",
            )));
        }
        (None, TableOrJson::Json) => {
            let cam_checks: Vec<_> = table.cam_checks().collect();
            crate::common::json(&serde_json::json!({
                "model": model.name(),
                "measured": measured,
                "checks": cam_checks,
            }))?
        }
        (None, TableOrJson::Table) => text::matching::paths_screen(&model, &table, &measured, args.details),
        (Some(st), TableOrJson::Json) => {
            // The match as every front end writes it, with the measured
            // curves beside it.
            let json_err = |e: serde_json::Error| Error::Internal(format!("cannot write JSON: {e}"));
            let mut json = stitchkin::output::match_json(&model, &table, st).map_err(json_err)?;
            json["measured"] = serde_json::to_value(&measured).map_err(json_err)?;
            crate::common::json(&json)?
        }
        (Some(st), TableOrJson::Table) => text::matching::screen(&model, &table, st, &measured, args.details),
    };
    args.output.emit(&out)?;
    // The screen in full, then a setting no machine can realise fails the
    // command, as `check` does.
    let failed: Vec<String> = table
        .all_checks()
        .filter(|c| !c.ok)
        .map(|c| format!("{} {}", c.thread, c.name))
        .collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(Error::Physical(PhysicalError { failed }))
    }
}
