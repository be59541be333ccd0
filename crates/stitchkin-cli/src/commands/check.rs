//! `stitchkin check`: a model file loaded, validated and solved over a full
//! cycle, with its report; a failed physical check fails the command.

use stitchkin::error::{Error, PhysicalError};
use stitchkin::eval::{self, CycleOptions};
use stitchkin::output::text;

use crate::common::{ModelArgs, emit_text, load};

/// Check a model file: load, validate, solve a full cycle, and report
/// its parameters, solve order, transmission angles and the stitch's
/// physical checks (a failed one makes the command fail).
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin check my-machine.toml\n  stitchkin check --preset needle876 --set alpha=30 --cross-check\n  stitchkin check examples/cam-rocking-roller.toml --rpm 3000"
)]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// φ step of the assembly check, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Also solve the whole mechanism's closure equations with an
    /// independent Newton solver and report the largest disagreement with
    /// the closed-form groups.
    #[arg(long)]
    cross_check: bool,
    /// Main-shaft speed, rev/min, at which a spring-closed cam follower's
    /// contact is judged (default: the model's `rpm`, if any).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    rpm: Option<f64>,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let opts = CycleOptions {
        step_deg: args.step,
        rpm: args.rpm,
        ..Default::default()
    };
    let table = eval::run_cycle(&model, &params, &opts)?;
    let machine = model.machine::<f64>(&params)?;
    let mut out = text::cycle::model_check(&model, &params, machine.threads.as_ref(), args.step);
    out += &text::cycle::check_summary(&model, &table);
    if args.cross_check {
        let c = stitchkin::verify::cross_check(&model, &params, args.step)?;
        out += &text::cycle::cross_check(&c);
    }
    emit_text(&out, None)?;
    // A setting no machine can realise does not pass the check.
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
