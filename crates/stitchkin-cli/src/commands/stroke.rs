//! `stitchkin stroke`: a point's stroke along an axis, both dead centres and
//! the transmission angles, per setting (stitchkin::study::stroke).

use stitchkin::error::{Error, Input};
use stitchkin::output::text;
use stitchkin::study::design::{Design, Sweep, Vary};
use stitchkin::study::stroke::{Axis, StrokeOptions, study};

use crate::common::{ModelArgs, OutputArgs, TableFormat, json, load, note};

/// A point's stroke along an axis, both dead centres (refined below the
/// φ step) and the range of every transmission angle, per setting, with
/// where an angle leaves 30°…150° (Kharzhevskyi et al. (n.d.) eq. 14, 15).
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin stroke --preset needle876 --point G --axis y\n  \
    stitchkin stroke --preset needle876 --point G --axis y --vary alpha=0:40:41\n  \
    stitchkin stroke --preset altin-needle --point E --axis guide.y --format json -o stroke.json\n  \
    stitchkin stroke my-machine.toml --point P --axis 0.34,0.94 --vary l_ef=20:30:11 --format csv\n\n\
    Axis: x, y, z (world), FRAME.x|y|z (from the frame's origin) or a world direction X,Y[,Z].\n\
    Dead centres: the zeros of the exact analog ds/dφ (dual numbers; Newton safeguarded by bisection).\n\
    Where an angle leaves the band between two settings, the setting is bisected to the crossing.\n\
    CSV columns: the varied parameters, P.AX_stroke_mm, P.AX_min_mm, P.AX_min_phi_deg, P.AX_max_mm,\n\
    P.AX_max_phi_deg, P.AX_min_to_max_deg, P_at_min.x_mm, ..., mu_KEY.min_deg, ..., mu_KEY.ok, status."
)]
#[command(mut_arg("format", |a| a.help(
    format!("{}{}", "Output format: a readable table, CSV (one row per setting) or JSON", crate::common::DEFAULT_FORMAT_HELP)
)))]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// The point whose stroke is measured (e.g. G, the needle of needle876).
    #[arg(long, value_name = "POINT")]
    point: String,
    /// The axis: x, y or z (world), FRAME.x|y|z (an axis of a model frame,
    /// measured from its origin, e.g. guide.y), or a world direction X,Y[,Z].
    #[arg(long, default_value = "y", value_name = "AXIS", allow_hyphen_values = true)]
    axis: String,
    /// A swept parameter: NAME=LO:HI:N (N values, ends included; default N
    /// 11). Repeatable: a grid, the last fastest; band crossings are found
    /// along the last.
    #[arg(long = "vary", value_name = "NAME=LO:HI:N")]
    vary: Vec<String>,
    /// Step of the main-shaft angle φ, degrees (dead centres and angle
    /// extremes are refined below it).
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    #[command(flatten)]
    output: OutputArgs,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let point = model
        .moving_point_slot(&args.point)
        .map_err(|e| e.given_in(Input::Point))?;
    let axis = Axis::parse(&model, &args.axis)?;
    let sweep = if args.vary.is_empty() {
        None
    } else {
        let vary = args
            .vary
            .iter()
            .map(|v| Vary::parse(&model, v))
            .collect::<Result<Vec<_>, _>>()?;
        Some(Sweep::new(vary, Design::Grid)?)
    };
    let opts = StrokeOptions {
        point,
        axis,
        step_deg: args.step,
    };
    let s = study(&model, &params, sweep.as_ref(), &opts)?;
    let out = match args.output.format() {
        TableFormat::Json => json(&s)?,
        TableFormat::Csv => text::stroke::csv(&s, model.is_planar()),
        TableFormat::Table => text::stroke::table(&s),
    };
    args.output.emit(&out)?;
    if !matches!(args.output.format(), TableFormat::Table) {
        note(&text::stroke::footer(&s, "# "));
    }
    Ok(())
}
