//! `stitchkin straightness` and `stitchkin tolerance`: how straight a point
//! runs, and which dimensional tolerances keep it so
//! (stitchkin::study::straightness).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stitchkin::error::Error;
use stitchkin::format::fmt_num;
use stitchkin::model::Model;
use stitchkin::study::straightness::{
    Distribution, Reference, StraightnessOptions, ToleranceOptions, ToleranceStudy, Window, straightness,
    tolerance_study, tolerances,
};

use crate::TableFormat;
use crate::stroke::render_table;

/// The point, the line and the part of the cycle (shared by both commands).
#[derive(Args)]
struct PathArgs {
    /// The point whose path is measured (e.g. E, the needle of altin-needle).
    #[arg(long, value_name = "POINT")]
    point: String,
    /// Measure from the line through two model points H → T (e.g. a guide's N1,N2).
    #[arg(long, value_name = "H,T", conflicts_with = "fit")]
    line: Option<String>,
    /// Measure from the least-squares line of the path (the default).
    #[arg(long)]
    fit: bool,
    /// Part of the cycle: cycle, down (the working stroke, from the far dead
    /// centre along the line to the near one), up, or FROM:TO in degrees of φ.
    #[arg(long, default_value = "cycle", value_name = "PART")]
    over: String,
    /// Step of the main-shaft angle φ, degrees (the extremes are refined below it).
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
}

impl PathArgs {
    fn options(&self, model: &Model) -> Result<StraightnessOptions, Error> {
        Ok(StraightnessOptions {
            point: model
                .moving_point_slot(&self.point)
                .map_err(|e| e.given_in("--point"))?,
            reference: match &self.line {
                Some(l) => Reference::parse_line(model, l)?,
                None => Reference::Fit,
            },
            window: Window::parse(&self.over)?,
            step_deg: self.step,
        })
    }
}

#[derive(Args)]
pub struct StraightnessArgs {
    #[command(flatten)]
    model: crate::ModelArgs,
    #[command(flatten)]
    path: PathArgs,
    /// Output format: a readable summary, CSV (the deviation per φ sample) or JSON.
    #[arg(long, value_enum, default_value_t = TableFormat::Table)]
    format: TableFormat,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

#[derive(Clone, Copy, ValueEnum)]
enum Dist {
    Uniform,
    Normal,
}

#[derive(Args)]
pub struct ToleranceArgs {
    #[command(flatten)]
    model: crate::ModelArgs,
    #[command(flatten)]
    path: PathArgs,
    /// The largest max |deviation| allowed, mm (seed 004: ± 0.05 mm).
    #[arg(long, default_value_t = 0.05, value_name = "MM", allow_negative_numbers = true)]
    limit: f64,
    /// A parameter's tolerance NAME=±T in its unit (mm or deg); T = 0 holds
    /// it exact. Repeatable.
    #[arg(long = "tol", value_name = "NAME=±T", allow_hyphen_values = true)]
    tol: Vec<String>,
    /// Tolerance of every length parameter without a --tol, mm (seed 004:
    /// ± 0.05 mm); 0 studies only the --tol ones.
    #[arg(long, default_value_t = 0.05, value_name = "MM", allow_negative_numbers = true)]
    length_tol: f64,
    /// Monte Carlo samples, every tolerance at once (0: none).
    #[arg(long, default_value_t = 1000, value_name = "N")]
    samples: usize,
    /// Seed of the Monte Carlo (the same seed gives the same samples).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// How each dimension is drawn: uniform in ±T, or normal with σ = T/3
    /// truncated at ±T.
    #[arg(long, value_enum, default_value_t = Dist::Uniform)]
    distribution: Dist,
    /// Output format: a readable table, CSV (one row per parameter) or JSON.
    #[arg(long, value_enum, default_value_t = TableFormat::Table)]
    format: TableFormat,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

/// A deviation in mm, with its sign when it has one.
fn mm(x: f64, signed: bool) -> String {
    if signed {
        format!("{x:+.5} mm")
    } else {
        format!("{x:.5} mm")
    }
}

pub fn run(args: StraightnessArgs) -> Result<(), Error> {
    let (model, params) = crate::load(&args.model)?;
    let opts = args.path.options(&model)?;
    let s = straightness(&model, &params, &opts)?;
    let mut summary = format!(
        "{}: straightness of {} from {}, {} (φ step {}°)\n",
        model.name(),
        s.point,
        s.reference,
        s.window,
        fmt_num(opts.step_deg)
    );
    let [px, py, pz] = s.line_point_mm;
    let [ux, uy, uz] = s.line_direction;
    let (point, dir) = if s.signed {
        (format!("({px:.4}, {py:.4}) mm"), format!("({ux:.6}, {uy:.6})"))
    } else {
        (
            format!("({px:.4}, {py:.4}, {pz:.4}) mm"),
            format!("({ux:.6}, {uy:.6}, {uz:.6})"),
        )
    };
    summary += &format!(
        "line: through {point}, direction {dir}, {:.3}° from +y\n\n",
        s.line_from_y_deg
    );
    let d = if s.signed { "deviation" } else { "distance" };
    let mut rows = vec![
        vec![
            "travel along the line".to_string(),
            format!("{:.4} mm", s.travel_mm),
            String::new(),
        ],
        vec![
            format!("largest {d}"),
            mm(s.max_dev_mm, s.signed),
            format!("at φ = {:.2}°", s.phi_at_max_deg),
        ],
        vec![
            format!("smallest {d}"),
            mm(s.min_dev_mm, s.signed),
            format!("at φ = {:.2}°", s.phi_at_min_deg),
        ],
        vec![format!("max |{d}|"), mm(s.max_abs_dev_mm, false), String::new()],
        vec![
            format!("RMS {d}"),
            mm(s.rms_dev_mm, false),
            format!("over {} φ samples", s.phi_deg.len()),
        ],
    ];
    if let Some(z) = s.zone_mm {
        rows.push(vec![
            "minimum zone (ISO 1101)".into(),
            mm(z, false),
            "width of the narrowest band holding the path".into(),
        ]);
    }
    for r in &rows {
        summary += format!("{:<24} {:>13}  {}", r[0], r[1], r[2]).trim_end();
        summary += "\n";
    }
    if s.signed {
        summary += "deviation: + to the left of the line's direction\n";
    }
    let out = match args.format {
        TableFormat::Json => serde_json::to_string_pretty(&s).map_err(|e| Error::Io(e.to_string()))? + "\n",
        TableFormat::Table => summary.clone(),
        TableFormat::Csv => {
            let mut c = format!("phi_deg,{p}.along_mm,{p}.dev_mm\n", p = s.point);
            for k in 0..s.phi_deg.len() {
                c += &format!(
                    "{},{},{}\n",
                    fmt_num(s.phi_deg[k]),
                    fmt_num(s.along_mm[k]),
                    fmt_num(s.dev_mm[k])
                );
            }
            c
        }
    };
    crate::emit(out.as_bytes(), args.output.as_ref())?;
    if matches!(args.format, TableFormat::Csv) {
        eprint!(
            "{}",
            summary
                .lines()
                .map(|l| if l.is_empty() {
                    "#\n".to_string()
                } else {
                    format!("# {l}\n")
                })
                .collect::<String>()
        );
    }
    Ok(())
}

pub fn tolerance(args: ToleranceArgs) -> Result<(), Error> {
    let (model, params) = crate::load(&args.model)?;
    let opts = ToleranceOptions {
        straightness: args.path.options(&model)?,
        limit_mm: args.limit,
        tolerances: tolerances(&model, &args.tol, args.length_tol)?,
        samples: args.samples,
        seed: args.seed,
        distribution: match args.distribution {
            Dist::Uniform => Distribution::Uniform,
            Dist::Normal => Distribution::Normal,
        },
    };
    let t = tolerance_study(&model, &params, &opts)?;
    let out = match args.format {
        TableFormat::Json => serde_json::to_string_pretty(&t).map_err(|e| Error::Io(e.to_string()))? + "\n",
        TableFormat::Csv => {
            let mut c = String::from("parameter,unit,tol,dev_minus_mm,dev_plus_mm,change_mm,largest_tol,bounded\n");
            let o = |x: Option<f64>| x.map_or(String::new(), fmt_num);
            for r in &t.one_at_a_time {
                c += &format!(
                    "{},{},{},{},{},{},{},{}\n",
                    r.name,
                    r.unit,
                    fmt_num(r.tol),
                    o(r.dev_minus_mm),
                    o(r.dev_plus_mm),
                    o(r.change_mm),
                    fmt_num(r.largest_tol),
                    r.bounded as u8
                );
            }
            c
        }
        TableFormat::Table => tolerance_table(&model, &t, opts.straightness.step_deg),
    };
    crate::emit(out.as_bytes(), args.output.as_ref())?;
    if matches!(args.format, TableFormat::Csv) {
        eprint!("{}", monte_carlo_lines(&t, "# "));
    }
    Ok(())
}

fn monte_carlo_lines(t: &ToleranceStudy, prefix: &str) -> String {
    let Some(mc) = &t.monte_carlo else { return String::new() };
    let how = match mc.distribution {
        Distribution::Uniform => "uniform within ±tol",
        Distribution::Normal => "normal, σ = tol/3, truncated at ±tol",
    };
    let v = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.4}"));
    let mut s = format!(
        "{prefix}Monte Carlo, every tolerance at once: {} samples, {how}, seed {}\n",
        mc.samples, mc.seed
    );
    s += &format!(
        "{prefix}  max |deviation|  50 %: {} mm   90 %: {} mm   99 %: {} mm   (mean {} mm, largest {} mm)\n",
        v(mc.p50_mm),
        v(mc.p90_mm),
        v(mc.p99_mm),
        v(mc.mean_mm),
        v(mc.max_mm)
    );
    s += &format!(
        "{prefix}  over the {} mm limit: {:.1} % of the samples ({} did not assemble)\n",
        fmt_num(t.limit_mm),
        100.0 * mc.over_limit,
        mc.failed
    );
    s
}

fn tolerance_table(model: &Model, t: &ToleranceStudy, step: f64) -> String {
    let mut s = format!(
        "{}: tolerances for the straightness of {} (max |deviation| from {}, {}; φ step {}°)\n",
        model.name(),
        t.point,
        t.reference,
        t.window,
        fmt_num(step)
    );
    s += &format!("nominal {:.5} mm; limit {} mm\n\n", t.nominal_mm, fmt_num(t.limit_mm));
    let head: Vec<String> = [
        "parameter",
        "tolerance",
        "at −tol",
        "at +tol",
        "change",
        "largest alone",
    ]
    .map(String::from)
    .to_vec();
    let dev = |x: Option<f64>| x.map_or("no assembly".to_string(), |x| format!("{x:.5} mm"));
    let rows: Vec<Vec<String>> = t
        .one_at_a_time
        .iter()
        .map(|r| {
            let largest = if r.bounded {
                format!("±{:.4} {}", r.largest_tol, r.unit)
            } else {
                format!("> ±{} {} (no limit found)", fmt_num(r.largest_tol), r.unit)
            };
            let over = |x: Option<f64>| if x.is_some_and(|x| x > t.limit_mm) { " *" } else { "" };
            vec![
                r.name.clone(),
                format!("±{} {}", fmt_num(r.tol), r.unit),
                dev(r.dev_minus_mm) + over(r.dev_minus_mm),
                dev(r.dev_plus_mm) + over(r.dev_plus_mm),
                r.change_mm.map_or("—".to_string(), |c| format!("{c:+.5} mm")),
                largest,
            ]
        })
        .collect();
    s += &render_table(&head, &rows, true);
    s += "change: the worse of −tol and +tol minus the nominal; largest alone: the largest ± tolerance of that\n";
    s += "parameter alone with the deviation within the limit (bisection); * over the limit\n";
    if t.monte_carlo.is_some() {
        s += "\n";
        s += &monte_carlo_lines(t, "");
    }
    s
}
