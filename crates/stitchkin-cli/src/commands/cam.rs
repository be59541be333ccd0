//! `stitchkin cam`: synthesise a thread feed cam's profile from the take-up
//! it must give (stitchkin::study::cam_synthesis).

use std::ffi::OsString;
use std::path::PathBuf;

use clap::ValueEnum;
use stitchkin::error::{Error, ParamError};
use stitchkin::output::text;
use stitchkin::parse_curve_csv;
use stitchkin::study::cam_synthesis::{CamOptions, Target, synthesise};
use stitchkin::study::follower_synthesis::{FollowerOptions, synthesise_follower};

use crate::common::{ByDestination, ModelArgs, emit, emit_text, format_or_default, full_table_hint, load, note};

/// Synthesise a thread feed cam: the polar profile ρ(θ) that makes a
/// path's take-up P(φ) equal the stitch's required P'(φ) or a given
/// curve (the inverse of Polyakov (2022) §2.5's cam feed, offset contact), with
/// checks, and CSV, SVG, DXF and a [[cams]] snippet to paste.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin cam --preset altin504 --path lower --target required -o lower-cam\n  \
    stitchkin cam --preset altin504 --path upper --target required --anchor-radius 21 --smooth 20 --format svg -o upper-cam.svg\n  \
    stitchkin cam my-machine.toml --path looper --target wanted.csv --points 72 --min-radius 5 --format toml\n  \
    stitchkin cam examples/cam-follower-thread.toml --follower pusher --path lower --target examples/altin504-lower-pprime.csv --smooth 10 -o pusher\n\n\
    The profile: one radius per position φ = φ0 + k·360/N, solved from the target by Polyakov (2022) §2.5's\n\
    offset contact (a quadratic in ρ); the rest of the path from the solved mechanism. Checks (reported,\n\
    not fixed): minimum radius, convexity, profile slope and the thread's contact angle. Files: PREFIX.csv\n\
    (theta_deg,radius_mm), PREFIX.svg (to scale, mm), PREFIX.dxf (R12, mm), PREFIX.toml ([[cams]] entry).\n\
    Target CSV: columns phi_deg,P_mm. On a terminal without --format or -o cam shows its summary;\n\
    into a pipe it writes the CSV, with -o the files, and the summary goes to stderr."
)]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// The thread path whose take-up P(φ) the cam is to give.
    #[arg(long, value_name = "NAME")]
    path: String,
    /// The cam on that path (needed when it runs over several).
    #[arg(long, value_name = "NAME")]
    cam: Option<String>,
    /// Synthesise the lift of this cam_follower group instead, whose
    /// follower carries a point of the path: files PREFIX.csv (lift and
    /// profile), PREFIX.dxf, PREFIX.toml (the group's base_radius and lift).
    #[arg(long, value_name = "GROUP", conflicts_with_all = ["cam", "anchor_radius", "min_radius", "max_pressure_angle"])]
    follower: Option<String>,
    /// What P(φ) should be: `required` (P' of the [stitch] thread compared
    /// with the path) or a CSV file with columns phi_deg,P_mm (periodic;
    /// the periodic cubic spline between its points).
    #[arg(long, value_name = "required|FILE.csv")]
    target: String,
    /// Smooth the profile: a periodic moving average over DEG degrees of
    /// profile angle, applied twice (0: none).
    #[arg(long, default_value_t = 0.0, value_name = "DEG", allow_negative_numbers = true)]
    smooth: f64,
    /// Smallest acceptable profile radius, mm (checked and reported).
    #[arg(
        long = "min-radius",
        default_value_t = 3.0,
        value_name = "MM",
        allow_negative_numbers = true
    )]
    min_radius: f64,
    /// Largest acceptable thread contact angle (profile normal against the
    /// thread's pull on the cam), degrees (checked and reported).
    #[arg(
        long = "max-pressure-angle",
        default_value_t = 45.0,
        value_name = "DEG",
        allow_negative_numbers = true
    )]
    max_pressure_angle: f64,
    /// Profile points per turn: the contact angles of N positions of φ,
    /// every 360/N degrees from φ0.
    #[arg(long, default_value_t = 360, value_name = "N")]
    points: usize,
    /// Profile radius at the contact angle of φ0, mm (default: the model's
    /// cam's). It sets the contour at φ0: a larger cam for a target that
    /// asks for more thread (an unreachable target's error suggests one).
    #[arg(long = "anchor-radius", value_name = "MM", allow_negative_numbers = true)]
    anchor_radius: Option<f64>,
    /// Output: table (the summary), csv, svg, dxf, toml (the [[cams]]
    /// snippet), or all four (the default with -o; without -o: the summary
    /// on a terminal, CSV into a pipe).
    #[arg(long, value_enum)]
    format: Option<CamFormat>,
    /// Write PREFIX.csv, PREFIX.svg, PREFIX.dxf and PREFIX.toml (as
    /// --format says), each completely or not at all; without it, the one
    /// format goes to stdout.
    #[arg(short, long, value_name = "PREFIX")]
    output: Option<PathBuf>,
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
enum CamFormat {
    Table,
    Csv,
    Svg,
    Dxf,
    Toml,
    All,
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    let (model, params) = load(&args.model)?;
    let target = if args.target == "required" {
        Target::Required
    } else {
        let text = std::fs::read_to_string(&args.target).map_err(|e| {
            Error::Param(ParamError::general(
                format!("cannot read the target `{}`: {e}", args.target),
                Some("give --target required (P' of the stitch) or a CSV file with columns phi_deg,P_mm".into()),
            ))
        })?;
        Target::from_curve(&parse_curve_csv(&text, &args.target)?)?
    };
    let format = format_or_default(args.format, args.output.as_deref());
    if format == CamFormat::All && args.output.is_none() {
        return Err(Error::Param(ParamError::general(
            if args.follower.is_some() {
                "--format all writes three files"
            } else {
                "--format all writes four files"
            },
            Some(if args.follower.is_some() {
                "give -o PREFIX (PREFIX.csv, .dxf, .toml), or one --format for stdout".into()
            } else {
                "give -o PREFIX (PREFIX.csv, .svg, .dxf, .toml), or one --format for stdout".into()
            }),
        )));
    }
    if let Some(group) = &args.follower {
        return run_follower(&args, (&model, &params), group, target, format);
    }
    let mut opts = CamOptions::new(&args.path, target);
    opts.cam = args.cam.clone();
    opts.points = args.points;
    opts.smooth_deg = args.smooth;
    opts.min_radius_mm = args.min_radius;
    opts.max_pressure_angle_deg = args.max_pressure_angle;
    opts.anchor_radius_mm = args.anchor_radius;
    let s = synthesise(&model, &params, &opts)?;
    let render = |f: CamFormat| match f {
        CamFormat::Csv => text::cam::csv(&s),
        CamFormat::Svg => stitchkin::output::drawing::cam::svg(&s),
        CamFormat::Dxf => stitchkin::output::drawing::cam::dxf(&s),
        CamFormat::Toml | CamFormat::All => text::cam::toml_snippet(&s),
        CamFormat::Table => text::cam_summary::summary(&s) + &full_table_hint("the profile, one radius per φ"),
    };
    let ext = |f: CamFormat| match f {
        CamFormat::Csv => "csv",
        CamFormat::Svg => "svg",
        CamFormat::Dxf => "dxf",
        CamFormat::Toml | CamFormat::All => "toml",
        CamFormat::Table => "txt",
    };
    let all = [CamFormat::Csv, CamFormat::Svg, CamFormat::Dxf, CamFormat::Toml];
    if !write_formats(args.output.as_ref(), format, &all, ext, render)? {
        return Ok(());
    }
    note(&text::cam_summary::summary(&s));
    Ok(())
}

/// Writes the result in `format`: without -o on stdout (the summary is
/// then the result, so `false`: nothing more to say on stderr); with -o
/// PREFIX one file per format (`all` for `--format all`), PREFIX.EXT, or
/// PREFIX itself when it already ends in the one format's extension
/// (`-o cam.svg --format svg` writes cam.svg, not cam.svg.svg).
fn write_formats(
    output: Option<&PathBuf>,
    format: CamFormat,
    all: &[CamFormat],
    ext: impl Fn(CamFormat) -> &'static str,
    render: impl Fn(CamFormat) -> String,
) -> Result<bool, Error> {
    match output {
        None if format == CamFormat::Table => {
            emit_text(&render(format), None)?;
            return Ok(false);
        }
        None => emit(render(format).as_bytes(), None)?,
        Some(prefix) => {
            let formats = if format == CamFormat::All {
                all.to_vec()
            } else {
                vec![format]
            };
            for f in formats {
                let path = if format != CamFormat::All && prefix.extension().is_some_and(|e| e == ext(f)) {
                    prefix.clone()
                } else {
                    let mut p = OsString::from(prefix.as_os_str());
                    p.push(format!(".{}", ext(f)));
                    PathBuf::from(p)
                };
                emit_text(&render(f), Some(&path))?;
            }
        }
    }
    Ok(true)
}

/// `--follower GROUP`: the lift of a cam_follower group.
fn run_follower(
    args: &Args,
    (model, params): (&stitchkin::model::Model, &stitchkin::model::Params),
    group: &str,
    target: Target,
    format: CamFormat,
) -> Result<(), Error> {
    if format == CamFormat::Svg {
        return Err(Error::Param(ParamError::general(
            "a follower's cam is written as csv, dxf or toml (or the summary), not svg",
            Some("give --format csv, dxf, toml or all".into()),
        )));
    }
    let mut opts = FollowerOptions::new(group, &args.path, target);
    opts.points = args.points;
    opts.smooth_deg = args.smooth;
    let s = synthesise_follower(model, params, &opts)?;
    let render = |f: CamFormat| match f {
        CamFormat::Csv => text::follower_cam::csv(&s),
        CamFormat::Dxf => text::follower_cam::dxf(&s),
        CamFormat::Table => {
            text::follower_cam::summary(&s) + &full_table_hint("the lift and the profile, every half degree")
        }
        _ => text::follower_cam::toml_snippet(&s),
    };
    let ext = |f: CamFormat| match f {
        CamFormat::Csv => "csv",
        CamFormat::Dxf => "dxf",
        CamFormat::Table => "txt",
        _ => "toml",
    };
    let all = [CamFormat::Csv, CamFormat::Dxf, CamFormat::Toml];
    if !write_formats(args.output.as_ref(), format, &all, ext, render)? {
        return Ok(());
    }
    note(&text::follower_cam::summary(&s));
    Ok(())
}

impl ByDestination for CamFormat {
    fn by_destination(output: Option<&std::path::Path>, is_terminal: bool) -> Self {
        match output {
            Some(_) => CamFormat::All,
            None if is_terminal => CamFormat::Table,
            None => CamFormat::Csv,
        }
    }
}
