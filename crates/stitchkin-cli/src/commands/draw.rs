//! `stitchkin draw`: the mechanism drawn at a main-shaft angle, or animated
//! over the cycle, as SVG (stitchkin::output::drawing).

use std::path::PathBuf;

use stitchkin::error::{Error, ParamError};
use stitchkin::output::drawing::{self, DrawOptions, View};

use crate::common::{ModelArgs, load};

/// Draw the mechanism as SVG at a main-shaft angle, or animated over the cycle (docs/drawing.md).
#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Main-shaft angle φ to draw, degrees (the first frame of an animation).
    #[arg(long, default_value_t = 0.0, value_name = "DEG", allow_negative_numbers = true)]
    phi: f64,
    /// The view: xy, xz or yz (a world plane), iso (isometric, y up), or the
    /// name of a model frame (its xy-plane) [default: xy for a planar model,
    /// iso for a spatial one].
    #[arg(long, value_name = "xy|xz|yz|iso|FRAME")]
    view: Option<String>,
    /// Animate one turn of the main shaft (SMIL; plays in a browser).
    #[arg(long)]
    animate: bool,
    /// Frames per turn of an animation (at least 2) [default: 72].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    frames: Option<i64>,
    /// Seconds per turn of an animation [default: 4].
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    duration: Option<f64>,
    /// Moving points whose paths over the cycle are drawn, comma-separated.
    #[arg(long, value_delimiter = ',', value_name = "A,B,…")]
    trajectories: Vec<String>,
    /// Write each link's length beside it (l_AB = … mm, crank radii r_OA).
    #[arg(long)]
    dimensions: bool,
    /// Write the drawing to FILE instead of stdout: FILE.svg, or FILE.png
    /// for a still drawing rasterised (2 px per SVG unit). Written
    /// completely or not at all.
    #[arg(short, long, value_name = "FILE.svg|FILE.png")]
    output: Option<PathBuf>,
}

fn bad(message: String, help: &str) -> Error {
    Error::Param(ParamError::general(message, Some(help.into())))
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let defaults = DrawOptions::default();
    crate::picture::check_output(args.output.as_ref(), args.animate)?;
    if !args.animate && (args.frames.is_some() || args.duration.is_some()) {
        return Err(bad(
            "--frames and --duration are for an animation".into(),
            "add --animate, or leave them out for a drawing at one φ",
        ));
    }
    let frames = match args.frames {
        None => defaults.frames,
        Some(f) if f >= 2 => usize::try_from(f).unwrap_or(usize::MAX),
        Some(f) => {
            return Err(bad(
                format!("an animation needs at least 2 frames per turn, got {f} (in --frames)"),
                "give --frames 72 (5° per frame) or 120 (3°)",
            ));
        }
    };
    let opts = DrawOptions {
        phi_deg: args.phi,
        view: args
            .view
            .as_deref()
            .map(View::parse)
            .transpose()?
            .unwrap_or(View::Plane(drawing::Plane::Xy)),
        animate: args.animate,
        frames,
        duration_s: args.duration.unwrap_or(defaults.duration_s),
        trajectories: args.trajectories.clone(),
        dimensions: args.dimensions,
        ..defaults
    };
    let (model, params) = load(&args.model)?;
    let opts = DrawOptions {
        view: if args.view.is_none() {
            View::default_for(&model)
        } else {
            opts.view
        },
        ..opts
    };
    let svg = stitchkin::jobs::drawing::render(&model, &params, &opts)?;
    crate::picture::emit_picture(&svg, args.output.as_ref(), args.animate)
}
