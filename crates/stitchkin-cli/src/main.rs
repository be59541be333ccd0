//! `stitchkin`: the command line, a thin shell over the `stitchkin` library.
//!
//! Each subcommand is a module of `commands/` with its arguments (`Args`)
//! and its `run`, which parses, calls the library and prints; `common`
//! holds the arguments and helpers they share, `picture` writes SVG or PNG.
//! This file parses the command line and dispatches.

// The arguments' doc comments are the `--help` text, which names the model
// file's tables as a user writes them ([stitch], [[cams]]): not links.
#![allow(rustdoc::broken_intra_doc_links)]

mod commands;
mod common;
mod picture;

use clap::{Parser, Subcommand};

use crate::commands::*;

#[derive(Parser)]
#[command(
    name = "stitchkin",
    version,
    // Help is wrapped at the terminal's width, and at 100 columns at most
    // (or into a pipe) so long lines stay readable.
    max_term_width = 100,
    about = "Kinematics of sewing-machine mechanisms and the thread they move",
    long_about = "Kinematics of sewing-machine mechanisms and the thread they move.\n\n\
        Describe a machine in one TOML model file (docs/model-format.md) or pick a shipped preset, \
        and get every position, exact velocity/acceleration analog and transmission angle over a \
        main-shaft cycle.",
    after_help = "Examples:\n  stitchkin run                         # the default preset: a summary on a terminal, CSV into a pipe\n  \
        stitchkin run --preset needle876 --set alpha=30 --format json -o run.json\n  \
        stitchkin new rocking-takeup -o my-machine.toml   # a starting model of your own machine\n  \
        stitchkin check my-machine.toml\n  stitchkin presets\n\n\
        Every command shows readable text on a terminal, and writes its table into a pipe or\n\
        -o FILE (CSV; -o FILE.json JSON); --format always wins. A file written is said on\n\
        stderr: wrote FILE (SIZE)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Presets(presets::Args),
    New(new::Args),
    Run(run::Args),
    Check(check::Args),
    #[command(name = "compare-2d3d")]
    Compare2d3d(compare_2d3d::Args),
    Consumption(consumption::Args),
    #[command(name = "match")]
    Match(matching::Args),
    Measured(measured::Args),
    Sweep(sweep::Args),
    Tune(tune::Args),
    Nomogram(nomogram::Args),
    Sensitivity(sensitivity::Args),
    Fit(fit::Args),
    Stroke(stroke::Args),
    Straightness(straightness::Args),
    Tolerance(tolerance::Args),
    Cam(cam::Args),
    Plot(plot::Args),
    Draw(draw::Args),
    Serve(serve::Args),
    Report(report::Args),
    Schema(schema::Args),
}

fn main() -> miette::Result<()> {
    common::unwrapped_diagnostics_off_terminal();
    common::remove_temporaries_on_signal();
    let cli = Cli::try_parse().unwrap_or_else(|e| common::exit_on_bad_arguments(e));
    let result = match cli.command {
        Command::Presets(args) => presets::run(args),
        Command::New(args) => new::run(args),
        Command::Run(args) => run::run(args),
        Command::Check(args) => check::run(args),
        Command::Compare2d3d(args) => compare_2d3d::run(args),
        Command::Consumption(args) => consumption::run(args),
        Command::Match(args) => matching::run(args),
        Command::Measured(args) => measured::run(args),
        Command::Sweep(args) => sweep::run(args),
        Command::Tune(args) => tune::run(args),
        Command::Nomogram(args) => nomogram::run(args),
        Command::Sensitivity(args) => sensitivity::run(args),
        Command::Fit(args) => fit::run(args),
        Command::Stroke(args) => stroke::run(args),
        Command::Straightness(args) => straightness::run(args),
        Command::Tolerance(args) => tolerance::run(args),
        Command::Cam(args) => cam::run(args),
        Command::Plot(args) => plot::run(args),
        Command::Draw(args) => draw::run(args),
        Command::Serve(args) => serve::run(args),
        Command::Report(args) => report::run(args),
        Command::Schema(args) => schema::run(args),
    };
    result.map_err(common::diagnostic)
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;
    use stitchkin::Input;

    /// Every long flag of every subcommand, nested ones included.
    fn long_flags(cmd: &clap::Command, out: &mut Vec<String>) {
        out.extend(
            cmd.get_arguments()
                .filter_map(|a| a.get_long())
                .map(|l| format!("--{l}")),
        );
        for sub in cmd.get_subcommands() {
            long_flags(sub, out);
        }
    }

    /// A library error about an input names a flag the command line has.
    #[test]
    fn every_library_input_maps_to_a_flag() {
        let mut flags = Vec::new();
        long_flags(&super::Cli::command(), &mut flags);
        for input in Input::ALL {
            let flag = crate::common::flag(input);
            assert!(
                flags.iter().any(|f| f == flag),
                "{input:?} maps to `{flag}`, which no subcommand has"
            );
        }
    }
}
