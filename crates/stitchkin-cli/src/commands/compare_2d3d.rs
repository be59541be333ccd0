//! `stitchkin compare-2d3d`: each thread path against its planar model
//! (stitchkin::study::compare_2d3d).

use stitchkin::error::Error;
use stitchkin::output::text;
use stitchkin::study::compare_2d3d::compare_2d3d;

use crate::common::{ModelArgs, OutputArgs, TableFormat, full_table_hint, load, note};

/// Compare each thread path with its planar model: project every node
/// onto a plane, recompute P and report ΔP = P3D − P2D (Manoilenko et al. (2024) §4.6).
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin compare-2d3d\n  stitchkin compare-2d3d --preset mf7923d --plane uvw --set z=-5 --format json -o dp.json\n\n\
    Columns: phi_deg, then per path PATH.P3D_mm, PATH.P2D_mm, PATH.dP_mm. On a terminal it shows the largest |ΔP| per path;\n\
    into a pipe or a file it writes the table and the largest |ΔP| goes to stderr."
)]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// Frame whose xy-plane is the plane of the 2D model.
    #[arg(long, default_value = "world", value_name = "FRAME")]
    plane: String,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    #[command(flatten)]
    output: OutputArgs,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let c = compare_2d3d(&model, &params, &args.plane, args.step)?;
    let summary = text::compare_2d3d::summary(&c);
    let out = match args.output.format() {
        // Pretty JSON without a final newline, as it always was written.
        TableFormat::Json => {
            serde_json::to_string_pretty(&c).map_err(|e| Error::Internal(format!("cannot write JSON: {e}")))?
        }
        TableFormat::Csv => text::compare_2d3d::csv(&c),
        TableFormat::Table => {
            return args.output.emit(&(summary + &full_table_hint("P3D, P2D and ΔP per φ")));
        }
    };
    args.output.emit(&out)?;
    note(&summary);
    Ok(())
}
