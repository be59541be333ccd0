//! `stitchkin plot`: SVG charts of a cycle, of motion laws, of a varied
//! parameter, of a sweep, of a nomogram (stitchkin::jobs::plot).

use std::path::PathBuf;

use clap::ValueEnum;
use stitchkin::error::{Error, Input, ParamError};
use stitchkin::jobs::plot::{self as plots, Plot};
use stitchkin::model::{Model, Params};
use stitchkin::study::nomogram::{Axis, NomogramOptions};
use stitchkin::study::tune::TuneOptions;

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum What {
    /// P(φ) of every thread path and P'(φ) of every stitch thread (dashed),
    /// one-sided guides' engaged intervals shaded.
    Takeup,
    /// Every transmission angle over φ, outside 30°…150° shaded.
    Mu,
    /// The thread's tension over φ at the eye and in the stitch, where
    /// thread passes the regulator shaded (models with thread physics).
    Tension,
    /// The path of each --points point over the cycle, in the xy-plane, to scale.
    Trajectory,
    /// Velocity and acceleration analogs over φ of --points, or dP/dφ and
    /// d²P/dφ² of the thread paths.
    Analogs,
    /// The motion law of each --series (a point coordinate, angle or
    /// measure) over φ; with --vary, a family of lines per series.
    Motion,
    /// P(φ) of one thread path for N values of a --vary parameter, with P'(φ).
    Family,
    /// P (or one --series) over φ and a --vary parameter as a heat map
    /// (--wireframe: a surface).
    Surface,
    /// A --figure of merit over two --vary parameters as a heat map.
    Heatmap,
    /// The tuned setting against the material thickness, per stitch length.
    Nomogram,
    /// P_2D and P_3D of each thread path and ΔP(φ) (2D model on --plane).
    Delta2d3d,
}

impl What {
    fn name(self) -> &'static str {
        match self {
            What::Takeup => "takeup",
            What::Mu => "mu",
            What::Tension => "tension",
            What::Trajectory => "trajectory",
            What::Analogs => "analogs",
            What::Motion => "motion",
            What::Family => "family",
            What::Surface => "surface",
            What::Heatmap => "heatmap",
            What::Nomogram => "nomogram",
            What::Delta2d3d => "delta2d3d",
        }
    }
}

use crate::common::{ModelArgs, STITCH_AXIS_HELP, THICKNESS_AXIS_HELP, load, load_without_job};

/// Plot a cycle as SVG: the take-up P(φ) with the required P'(φ), the
/// transmission angles, the trajectories of points, the motion law of
/// any coordinate, angle or measure, and charts over varied parameters.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  stitchkin plot takeup -o mf7923d-takeup.svg\n  \
    stitchkin plot takeup --measured n1=n1-measured.csv -o measured.svg\n  \
    stitchkin plot takeup --preset altin504 --thickness 2 --step 2 -o altin504.svg\n  \
    stitchkin plot mu --preset needle876 --set alpha=38 -o mu.svg\n  \
    stitchkin plot trajectory --preset needle876 --points G,E -o paths.svg\n  \
    stitchkin plot trajectory --preset altin-needle --points E --plane guide -o altin-guide.svg\n  \
    stitchkin plot motion --preset needle876 --series G.y,angle_C_B --vary alpha=0:35:6 -o motion.svg\n  \
    stitchkin plot surface --series angle_O2_B --vary r1=4:6:9 --wireframe -o psi-r1.svg\n\n\
    takeup: P of every thread path (solid) and P' of every stitch thread (dashed, its path's colour),\n\
    needle threads at B, where a one-sided guide bears on the thread shaded lightly; --measured adds a\n\
    measured curve. mu: every transmission angle, the band 30°…150° marked and the outside shaded.\n\
    trajectory: each point's path in the world xy-plane (or --plane FRAME's), equal scales, a dot at the\n\
    cycle's start. motion: each --series (a column of `stitchkin run`, the unit ending optional) against φ,\n\
    one panel per unit; with --vary one panel per series, a line per value. φ runs over one cycle from the\n\
    model's start (docs/plots.md).")]
#[command(mut_arg("thickness", |a| a.value_name("MM | LO:HI:N").help(format!(
    "Material thickness m, mm: one value for every plot but nomogram, where it is the axis. {THICKNESS_AXIS_HELP}"
))))]
#[command(mut_arg("stitch", |a| a.value_name("MM | LO:HI:N").help(format!(
    "Stitch length t, mm: one value for every plot but nomogram, where it is the axis. {STITCH_AXIS_HELP}"
))))]
pub(crate) struct Args {
    /// What to plot.
    #[arg(value_enum)]
    what: What,
    #[command(flatten)]
    model: ModelArgs,
    /// Trajectory, analogs: points to draw, comma-separated.
    #[arg(long, value_delimiter = ',', value_name = "A,B,…")]
    points: Vec<String>,
    /// Trajectory: draw in the xy-plane of this model frame (default: the
    /// world's). Delta2d3d: the frame whose xy-plane is the 2D model's
    /// (default: world).
    #[arg(long, value_name = "FRAME")]
    plane: Option<String>,
    /// Motion: what to draw over φ, comma-separated columns as `stitchkin
    /// run` names them (G.y_mm, angle_O2_B_deg, needle_y_mm, mu_23_deg;
    /// the unit ending may be left off: G.y). Surface: the one series to
    /// draw instead of a thread path's take-up.
    #[arg(long, value_delimiter = ',', value_name = "NAME,…")]
    series: Vec<String>,
    /// Analogs, delta2d3d: thread paths to draw, comma-separated (default:
    /// all). Family, surface: the one path (default: the model's first).
    #[arg(long, value_delimiter = ',', value_name = "PATH,…")]
    thread: Vec<String>,
    /// Family, surface, motion: the varied parameter, NAME=LO:HI:N (N
    /// values, ends included; N default 5 for family and motion, 11 for
    /// surface). Heatmap: give it twice (N default 11), the first across,
    /// the second up.
    #[arg(long = "vary", value_name = "NAME=LO:HI:N")]
    vary: Vec<String>,
    /// Surface: draw a projected wireframe surface instead of the heat map.
    #[arg(long)]
    wireframe: bool,
    /// Heatmap: the figure of merit to draw (a name as in `stitchkin sweep
    /// --figures`, e.g. score.mean, n1_A.max_P_B_mm, mu.min_deg).
    #[arg(long, value_name = "NAME")]
    figure: Option<String>,
    /// Nomogram: settings to tune, comma-separated (default: the model's
    /// machine settings, as `stitchkin tune`).
    #[arg(long, value_delimiter = ',', value_name = "NAME,…")]
    adjust: Vec<String>,
    /// Nomogram: let --adjust name job inputs (as `stitchkin tune`).
    #[arg(long)]
    allow_inputs: bool,
    /// Nomogram: let --adjust name fixed dimensions (as `stitchkin tune`).
    #[arg(long)]
    allow_dimensions: bool,
    /// Nomogram: global samples of each tuning (default 32 per setting, at least 64).
    #[arg(long, value_name = "N")]
    samples: Option<usize>,
    /// Nomogram: seed of the search (the same seed, the same chart).
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// Takeup: a measured take-up P or required P′ drawn over the model's
    /// (CSV: phi_deg and P_mm, P_B_mm, Pprime_B_mm, …; [THREAD=]FILE, as
    /// `stitchkin match --measured`). Repeatable.
    #[arg(long, value_name = "[THREAD=]FILE")]
    measured: Vec<String>,
    /// Step of the main-shaft angle φ, degrees (default 1; 2 for family,
    /// surface, heatmap, nomogram and motion with --vary, which evaluate
    /// many cycles).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    step: Option<f64>,
    /// Write the chart to FILE instead of stdout: FILE.svg, or FILE.png for
    /// the same drawing rasterised (2 px per SVG unit). Written completely
    /// or not at all.
    #[arg(short, long, value_name = "FILE.svg|FILE.png")]
    output: Option<PathBuf>,
}

fn bad(message: String, help: String) -> Error {
    Error::Param(ParamError::general(message, Some(help)))
}

/// `plot family`, `plot surface` and `plot heatmap` (`a`, `a` and `b`).
fn list(kinds: &[What]) -> String {
    let names: Vec<String> = kinds.iter().map(|k| format!("`plot {}`", k.name())).collect();
    match names.as_slice() {
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
        [] => String::new(),
    }
}

/// Rejects options that belong to another kind of plot.
fn check_options(args: &Args) -> Result<(), Error> {
    use What::*;
    let nomogram_example = "stitchkin plot nomogram --set t1_phase=180 --thickness 3:5:3 --adjust z";
    let owners: [(&str, bool, &[What], &str); 13] = [
        (
            "--allow-inputs",
            args.allow_inputs,
            &[Nomogram],
            "stitchkin plot nomogram --adjust z,stitch --allow-inputs",
        ),
        (
            "--allow-dimensions",
            args.allow_dimensions,
            &[Nomogram],
            "stitchkin plot nomogram --adjust z,l_ab --allow-dimensions",
        ),
        (
            "--measured",
            !args.measured.is_empty(),
            &[Takeup],
            "stitchkin plot takeup --measured n1=n1-measured.csv",
        ),
        (
            "--points",
            !args.points.is_empty(),
            &[Trajectory, Analogs],
            "stitchkin plot trajectory --points A,B",
        ),
        (
            "--plane",
            args.plane.is_some(),
            &[Trajectory, Delta2d3d],
            "stitchkin plot delta2d3d --plane uvw",
        ),
        (
            "--thread",
            !args.thread.is_empty(),
            &[Analogs, Family, Surface, Delta2d3d],
            "stitchkin plot family --vary z=-10:10:5 --thread n3_A",
        ),
        (
            "--series",
            !args.series.is_empty(),
            &[Motion, Surface],
            "stitchkin plot motion --preset needle876 --series G.y,angle_C_B",
        ),
        (
            "--vary",
            !args.vary.is_empty(),
            &[Family, Surface, Heatmap, Motion],
            "stitchkin plot family --vary r1=4:6:5",
        ),
        (
            "--wireframe",
            args.wireframe,
            &[Surface],
            "stitchkin plot surface --vary r1=4:6:9 --wireframe",
        ),
        (
            "--figure",
            args.figure.is_some(),
            &[Heatmap],
            "stitchkin plot heatmap --vary z=-10:10:11 --vary dphi=-20:20:11 --figure n1_A.max_P_B_mm",
        ),
        ("--adjust", !args.adjust.is_empty(), &[Nomogram], nomogram_example),
        ("--samples", args.samples.is_some(), &[Nomogram], nomogram_example),
        ("--seed", args.seed.is_some(), &[Nomogram], nomogram_example),
    ];
    for (flag, given, kinds, example) in owners {
        if given && !kinds.contains(&args.what) {
            return Err(bad(
                format!("{flag} is for {}, not `plot {}`", list(kinds), args.what.name()),
                format!("leave it out, or use it as in `{example}`"),
            ));
        }
    }
    Ok(())
}

/// The ranged parameters with their ranges, for a missing --vary.
fn ranged(model: &Model) -> String {
    let v: Vec<String> = model
        .params()
        .iter()
        .filter(|p| !p.is_derived())
        .filter_map(|p| {
            p.range
                .filter(|r| r[1] > r[0])
                .map(|r| format!("{} ({}…{} {})", p.name, r[0], r[1], p.unit_str()))
        })
        .collect();
    if v.is_empty() {
        "the model has no parameter with an adjustable range".into()
    } else {
        format!("the ranged parameters are: {}", v.join(", "))
    }
}

/// The one path of a family or surface.
fn one_thread(args: &Args) -> Result<Option<String>, Error> {
    match args.thread.as_slice() {
        [] => Ok(None),
        [one] => Ok(Some(one.clone())),
        many => Err(bad(
            format!(
                "`plot {}` draws one thread path; --thread names {}",
                args.what.name(),
                many.len()
            ),
            format!("give one, e.g. --thread {}", many[0]),
        )),
    }
}

/// The one series of a surface (`None`: the take-up of a thread path).
fn one_series(args: &Args) -> Result<Option<String>, Error> {
    match args.series.as_slice() {
        [] => Ok(None),
        [_] if !args.thread.is_empty() => Err(bad(
            "`plot surface` draws a thread path's take-up (--thread) or a motion law (--series), not both".into(),
            "leave out one of them".into(),
        )),
        [one] => Ok(Some(one.clone())),
        many => Err(bad(
            format!("`plot surface` draws one series; --series names {}", many.len()),
            format!("give one, e.g. --series {}", many[0]),
        )),
    }
}

/// The one --vary of a family or surface, N defaulting to `default_n`.
fn one_vary(args: &Args, model: &Model, default_n: usize) -> Result<stitchkin::study::design::Vary, Error> {
    match args.vary.as_slice() {
        [] => Err(bad(
            format!(
                "`plot {}` needs the parameter to vary: --vary NAME=LO:HI:N",
                args.what.name()
            ),
            format!("e.g. --vary r1=4:6:{default_n}; {}", ranged(model)),
        )),
        [one] => plots::parse_vary(model, one, default_n),
        many => Err(bad(
            format!(
                "`plot {}` varies one parameter; --vary is given {} times",
                args.what.name(),
                many.len()
            ),
            "keep one, or draw two parameters with `plot heatmap --vary A=… --vary B=… --figure NAME`".into(),
        )),
    }
}

/// The plot the arguments ask for, its cycles at `step` degrees.
fn plot_of(args: &Args, model: &Model, params: &Params, step: f64) -> Result<Plot, Error> {
    Ok(match args.what {
        What::Takeup => Plot::TakeUp,
        What::Mu => Plot::Mu,
        What::Tension => Plot::Tension,
        What::Trajectory => Plot::Trajectory {
            points: args.points.clone(),
            plane: args.plane.clone(),
        },
        What::Analogs => Plot::Analogs {
            points: args.points.clone(),
            threads: args.thread.clone(),
        },
        What::Family => Plot::Family {
            vary: one_vary(args, model, 5)?,
            thread: one_thread(args)?,
        },
        What::Motion => {
            let vary = if args.vary.is_empty() {
                None
            } else {
                Some(one_vary(args, model, 5)?)
            };
            Plot::Motion {
                series: args.series.clone(),
                vary,
            }
        }
        What::Surface => match one_series(args)? {
            Some(series) => Plot::MotionSurface {
                series,
                vary: one_vary(args, model, 11)?,
                wireframe: args.wireframe,
            },
            None => Plot::Surface {
                vary: one_vary(args, model, 11)?,
                thread: one_thread(args)?,
                wireframe: args.wireframe,
            },
        },
        What::Heatmap => {
            let vary = args
                .vary
                .iter()
                .map(|v| plots::parse_vary(model, v, 11))
                .collect::<Result<Vec<_>, _>>()?;
            if vary.len() != 2 {
                return Err(bad(
                    format!("`plot heatmap` needs exactly 2 --vary, got {}", vary.len()),
                    format!(
                        "e.g. --vary z=-10:10:11 --vary dphi=-20:20:11 (the first across, the second up); {}",
                        ranged(model)
                    ),
                ));
            }
            let Some(figure) = args.figure.clone() else {
                let names = plots::figure_names(model, params, step)?;
                return Err(bad(
                    "`plot heatmap` needs the figure of merit to draw: --figure NAME".into(),
                    format!("this model offers: {}", names.join(", ")),
                ));
            };
            Plot::Heatmap { vary, figure }
        }
        What::Nomogram => {
            let thickness = match &args.model.thickness {
                Some(s) => Axis::parse(s, Input::Thickness)?,
                None => stitchkin::study::nomogram::default_thickness(model)?,
            };
            let stitch = args
                .model
                .stitch
                .as_deref()
                .map(|s| Axis::parse(s, Input::StitchLength))
                .transpose()?;
            let tune = TuneOptions {
                objective: Default::default(),
                adjust: args.adjust.clone(),
                samples: args.samples.unwrap_or(0),
                seed: args.seed.unwrap_or(1),
                step_deg: step,
            };
            Plot::Nomogram(NomogramOptions {
                thickness,
                stitch,
                tune,
            })
        }
        What::Delta2d3d => Plot::Delta2d3d {
            plane: args.plane.clone().unwrap_or_else(|| "world".into()),
            threads: args.thread.clone(),
        },
    })
}

pub(crate) fn run(args: Args) -> Result<(), Error> {
    check_options(&args)?;
    crate::picture::check_output(args.output.as_ref(), false)?;
    // A nomogram reads --thickness and --stitch as its axes; every other
    // plot takes one value of each.
    let (mut model, params) = if args.what == What::Nomogram {
        load_without_job(&args.model)?
    } else {
        load(&args.model)?
    };
    if args.allow_inputs {
        model.allow_adjusting(stitchkin::model::ParamKind::Input);
    }
    if args.allow_dimensions {
        model.allow_adjusting(stitchkin::model::ParamKind::Dimension);
    }
    if args.what == What::Nomogram {
        let axes = [model.stitch_param("m"), model.stitch_param("t")];
        let named: Vec<String> = args
            .adjust
            .iter()
            .filter(|n| !axes.contains(&Some(n.as_str())))
            .cloned()
            .collect();
        crate::common::SearchArgs::check_kinds(&model, &named)?;
    }
    let many_cycles = matches!(args.what, What::Family | What::Surface | What::Heatmap | What::Nomogram)
        || (args.what == What::Motion && !args.vary.is_empty());
    let step = args.step.unwrap_or(if many_cycles { 2.0 } else { 1.0 });
    let plot = plot_of(&args, &model, &params, step)?;
    let svg = if args.measured.is_empty() {
        plots::render(&model, &params, &plot, step)?
    } else {
        let measured = crate::common::read_measured(&args.measured)?;
        plots::render_take_up_with_measured(&model, &params, &measured, step)?
    };
    crate::picture::emit_picture(&svg, args.output.as_ref(), false)
}
