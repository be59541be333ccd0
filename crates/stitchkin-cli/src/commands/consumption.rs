//! `stitchkin consumption`: the thread one finished stitch consumes, from
//! the stitch's geometry ([`stitchkin::consumption`]).

use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::{StitchGeometry, consumption};

use crate::common::{OutputArgs, TableFormat, json};

/// Thread consumed by one finished stitch, per thread, from the stitch's
/// geometry (seed 004 §2.6; docs/stitch-formation.md §6).
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin consumption --type 504 --thickness 2.5 --stitch 2.8 --width 4 --incline 20\n  \
    stitchkin consumption --type 407 --thickness 3 --stitch 3 --format json\n\n\
    Types: 401, 406, 407 and 501–512, 514, 521. Contours whose drawings are lost in the thesis\n\
    are reported as not derivable, never guessed."
)]
pub(crate) struct Args {
    /// Stitch type (ISO 4915 number), e.g. 504.
    #[arg(long = "type", value_name = "N")]
    stitch_type: u16,
    /// Material thickness m (compressed), mm.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    thickness: f64,
    /// Stitch length t, mm.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    stitch: f64,
    /// Overedge width a (class 500), mm; required for class-500 types.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    width: Option<f64>,
    /// Needle inclination β from the normal to the material, degrees.
    #[arg(long, default_value_t = 0.0, value_name = "DEG", allow_negative_numbers = true)]
    incline: f64,
    /// Where the looper threads meet on the edge, as a fraction of m.
    #[arg(long, default_value_t = 0.5, value_name = "E", allow_negative_numbers = true)]
    edge: f64,
    #[command(flatten)]
    output: OutputArgs,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    // Without --width: none (a 500-class stitch is then refused, naming --width).
    let width = args.width.unwrap_or(0.0);
    let g = StitchGeometry {
        thickness_mm: args.thickness,
        stitch_mm: args.stitch,
        width_mm: width,
        incline_deg: args.incline,
        edge_fraction: args.edge,
    };
    let c = consumption(args.stitch_type, &g)?;
    let out = match args.output.format {
        TableFormat::Json => json(&c)?,
        TableFormat::Csv => text::consumption::csv(&c),
        TableFormat::Table => text::consumption::table(&c, &g),
    };
    args.output.emit(&out)
}
