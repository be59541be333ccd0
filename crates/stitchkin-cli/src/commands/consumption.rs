//! `stitchkin consumption`: the thread one finished stitch consumes, from
//! the stitch's geometry ([`stitchkin::consumption`]).

use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::{Seam, StitchGeometry, consumption};

use crate::common::{OutputArgs, TableFormat, json};

/// Thread consumed by one finished stitch, per thread, from the stitch's
/// geometry (Polyakov (2022) §2.6; docs/stitch-formation.md §6): per stitch, per
/// length of seam, and for a seam with an allowance for waste. Taut
/// consumption: real seams take more.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin consumption --type 504 --thickness 2.5 --stitch 2.8 --width 4 --incline 20\n  \
    stitchkin consumption --type 301 --thickness 2 --stitch 2.5 --seam 2500 --waste 15\n  \
    stitchkin consumption --type 407 --thickness 3 --stitch 3 --format json\n\n\
    Types: 301, 401, 406, 407, 501–512, 514, 521, 602 and 605. Contours that cannot be derived\n\
    (drawings lost in the thesis, threads no source at hand describes) are reported as not\n\
    derivable, never guessed. The figures are taut consumption: zero-thickness threads pulled\n\
    straight; real seams take more (docs/stitch-formation.md §6)."
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
    /// Lockstitch 301: where needle and bobbin threads interlace, as a
    /// fraction of m below the top face (0.5: in the middle, balanced).
    #[arg(long, default_value_t = 0.5, value_name = "F", allow_negative_numbers = true)]
    interlace: f64,
    /// Seam length for the per-seam figures, mm.
    #[arg(long, default_value_t = 1000.0, value_name = "MM", allow_negative_numbers = true)]
    seam: f64,
    /// Allowance for waste on the seam's thread (chaining off, trimming,
    /// breaks), per cent; shown beside the taut figures, never inside them.
    #[arg(long, default_value_t = 0.0, value_name = "PCT", allow_negative_numbers = true)]
    waste: f64,
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
        interlace_fraction: args.interlace,
    };
    let seam = Seam {
        length_mm: args.seam,
        waste_pct: args.waste,
    };
    let c = consumption(args.stitch_type, &g)?.for_seam(&seam)?;
    let out = match args.output.format() {
        TableFormat::Json => json(&c)?,
        TableFormat::Csv => text::consumption::csv(&c),
        TableFormat::Table => text::consumption::table(&c, &g),
    };
    args.output.emit(&out)
}
