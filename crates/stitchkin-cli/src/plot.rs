//! `stitchkin plot`: SVG charts of a cycle (stitchkin::output::plots).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stitchkin::error::Error;
use stitchkin::output::plots::{self, Plot};

#[derive(Clone, Copy, ValueEnum)]
pub enum What {
    /// P(φ) of every thread path and P'(φ) of every stitch thread (dashed),
    /// one-sided guides' engaged intervals shaded.
    Takeup,
    /// Every transmission angle over φ, outside 30°…150° shaded.
    Mu,
    /// The path of each --points point over the cycle, in the xy-plane, to scale.
    Trajectory,
}

#[derive(Args)]
pub struct PlotArgs {
    /// What to plot.
    #[arg(value_enum)]
    what: What,
    #[command(flatten)]
    model: crate::ModelArgs,
    /// Points to trace (trajectory), comma-separated.
    #[arg(long, value_delimiter = ',', value_name = "A,B,…")]
    points: Vec<String>,
    /// Trajectory: draw in the xy-plane of this model frame (default: the
    /// world's).
    #[arg(long, value_name = "FRAME")]
    plane: Option<String>,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Write the SVG to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE.svg")]
    output: Option<PathBuf>,
}

pub fn run(args: PlotArgs) -> Result<(), Error> {
    let plot = match args.what {
        What::Takeup => Plot::TakeUp,
        What::Mu => Plot::Mu,
        What::Trajectory => Plot::Trajectory { points: args.points.clone(), plane: args.plane.clone() },
    };
    if !matches!(plot, Plot::Trajectory { .. }) && (!args.points.is_empty() || args.plane.is_some()) {
        return Err(Error::Param(stitchkin::error::ParamError {
            message: "--points and --plane are for `plot trajectory`".into(),
            help: Some("leave it out, or plot the points' paths with `stitchkin plot trajectory --points A,B`".into()),
        }));
    }
    let (model, params) = crate::load(&args.model)?;
    let svg = plots::render(&model, &params, &plot, args.step)?;
    crate::emit(svg.as_bytes(), args.output.as_ref())
}
