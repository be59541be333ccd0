//! `stitchkin cam`: synthesise a thread feed cam's profile from the take-up
//! it must give (stitchkin::study::cam_synthesis).

use std::ffi::OsString;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stitchkin::error::{Error, ParamError};
use stitchkin::study::cam_synthesis::{CamOptions, CamSynthesis, Target, synthesise};
use stitchkin::thread::measured::parse_curve_csv;

#[derive(Args)]
pub struct CamArgs {
    #[command(flatten)]
    model: crate::ModelArgs,
    /// The thread path whose take-up P(φ) the cam is to give.
    #[arg(long, value_name = "NAME")]
    path: String,
    /// The cam on that path (needed when it runs over several).
    #[arg(long, value_name = "NAME")]
    cam: Option<String>,
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
    /// Output: csv, svg, dxf, toml (the [[cams]] snippet), or all four
    /// (the default with -o).
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
    Csv,
    Svg,
    Dxf,
    Toml,
    All,
}

pub fn run(args: CamArgs) -> Result<(), Error> {
    let (model, params) = crate::load(&args.model)?;
    let target = if args.target == "required" {
        Target::Required
    } else {
        let text = std::fs::read_to_string(&args.target).map_err(|e| {
            Error::Param(ParamError {
                message: format!("cannot read the target `{}`: {e}", args.target),
                help: Some("give --target required (P' of the stitch) or a CSV file with columns phi_deg,P_mm".into()),
            })
        })?;
        Target::from_curve(&parse_curve_csv(&text, &args.target)?)?
    };
    let format = args.format.unwrap_or(if args.output.is_some() {
        CamFormat::All
    } else {
        CamFormat::Csv
    });
    if format == CamFormat::All && args.output.is_none() {
        return Err(Error::Param(ParamError {
            message: "--format all writes four files".into(),
            help: Some("give -o PREFIX (PREFIX.csv, .svg, .dxf, .toml), or one --format for stdout".into()),
        }));
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
        CamFormat::Csv => stitchkin::output::text::cam::csv(&s),
        CamFormat::Svg => stitchkin::output::drawing::cam::svg(&s),
        CamFormat::Dxf => stitchkin::output::drawing::cam::dxf(&s),
        CamFormat::Toml | CamFormat::All => stitchkin::output::text::cam::toml_snippet(&s),
    };
    let ext = |f: CamFormat| match f {
        CamFormat::Csv => "csv",
        CamFormat::Svg => "svg",
        CamFormat::Dxf => "dxf",
        CamFormat::Toml | CamFormat::All => "toml",
    };
    let mut written = Vec::new();
    match &args.output {
        None => crate::emit(render(format).as_bytes(), None)?,
        Some(prefix) => {
            let formats = if format == CamFormat::All {
                vec![CamFormat::Csv, CamFormat::Svg, CamFormat::Dxf, CamFormat::Toml]
            } else {
                vec![format]
            };
            for f in formats {
                // `-o cam.svg --format svg` writes cam.svg, not cam.svg.svg.
                let path = if format != CamFormat::All && prefix.extension().is_some_and(|e| e == ext(f)) {
                    prefix.clone()
                } else {
                    let mut p = OsString::from(prefix.as_os_str());
                    p.push(format!(".{}", ext(f)));
                    PathBuf::from(p)
                };
                stitchkin::output::write_atomic(&path, render(f).as_bytes())?;
                written.push(path.display().to_string());
            }
        }
    }
    eprint!("{}", report(&s, &written));
    Ok(())
}

/// A length for the summary: fixed point, or scientific when tiny.
fn mm(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-3 {
        format!("{x:.1e}")
    } else {
        format!("{x:.4}")
    }
}

/// The summary on stderr.
fn report(s: &CamSynthesis, written: &[String]) -> String {
    let v = &s.verify;
    let c = &s.checks;
    let n = s.knots.len();
    let mut r = format!(
        "# cam synthesis: thread path `{}`, cam `{}` (contact = \"offset\", γ = {:.2}°, seed 004 §2.5)\n# target: {}\n",
        s.path, s.cam, s.gamma_deg, s.target
    );
    r += &format!(
        "# {n} knots: the contact angles at φ = {}° + k·{}°; radius {:.3}…{:.3} mm (the model's profile: {:.3}…{:.3} mm)\n",
        stitchkin::format::fmt_num(s.phi0_deg),
        stitchkin::format::fmt_num(360.0 / n as f64),
        s.radius_mm[0],
        s.radius_mm[1],
        s.reference_radius_mm[0],
        s.reference_radius_mm[1]
    );
    r += &format!(
        "# anchor: ρ = {:.4} mm at θ = {:.2}°, the contact at φ0 = {}° where P is fixed by its convention\n",
        s.anchor_radius_mm,
        s.anchor_theta_deg,
        stitchkin::format::fmt_num(s.phi0_deg)
    );
    r += &if s.smooth_deg > 0.0 {
        format!(
            "# smoothing: moving average over {}° of profile angle, applied twice\n",
            stitchkin::format::fmt_num(s.smooth_deg)
        )
    } else {
        "# smoothing: none\n".to_string()
    };
    r += "# verify (the model evaluated again with the new profile as a polar cam):\n";
    r += &format!(
        "#   max |P − target| {} mm at the knots (φ = {:.1}°), {} mm between them (φ = {:.1}°); the model's own cam: {} mm\n",
        mm(v.max_err_knots_mm),
        v.max_err_knots_at_deg,
        mm(v.max_err_between_mm),
        v.max_err_between_at_deg,
        mm(v.max_err_before_mm)
    );
    if let (Some(t), Some(b), Some(a), Some(f)) = (&s.thread, &v.match_before, &v.match_after, &v.match_after_all) {
        let sc = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.1}"));
        r += &format!(
            "#   match of thread `{t}` (docs/stitch-formation.md §8, on the knots' φ): score {} → {}, RMS(P − P') {:.4} → {:.4} mm; with the midpoints: score {}, RMS {:.4} mm\n",
            sc(b.score),
            sc(a.score),
            b.rms_d_mm,
            a.rms_d_mm,
            sc(f.score),
            f.rms_d_mm
        );
    }
    r += "# checks (reported, not fixed):\n";
    r += &format!(
        "#   min radius     {:.3} mm at θ = {:.1}° (limit {} mm): {}\n",
        c.min_radius_mm,
        c.min_radius_at_theta_deg,
        stitchkin::format::fmt_num(c.min_radius_limit_mm),
        if c.min_radius_ok { "ok" } else { "TOO SMALL" }
    );
    if c.convex {
        r += "#   convex         yes (what contact = \"exact\" would need)\n";
    } else {
        let total: f64 = c.not_convex_deg.iter().map(|i| i[1] - i[0]).sum();
        let list: Vec<String> = c
            .not_convex_deg
            .iter()
            .take(4)
            .map(|i| format!("{:.1}°…{:.1}°", i[0], i[1].rem_euclid(360.0)))
            .collect();
        r += &format!(
            "#   convex         NO: {} stretch(es) of θ, {:.1}° in all ({}{}); the offset contact does not need it, a taut thread (contact = \"exact\") would bridge them\n",
            c.not_convex_deg.len(),
            total,
            list.join(", "),
            if c.not_convex_deg.len() > 4 { ", …" } else { "" }
        );
    }
    r += &format!(
        "#   profile slope  max {:.1}° at θ = {:.1}° (atan(|ρ'|/ρ): the angle between the radius and the profile normal)\n",
        c.max_slope_deg, c.max_slope_at_theta_deg
    );
    r += &format!(
        "#   contact angle  max {:.1}° at φ = {:.1}° (limit {}°): {}  (profile normal against the thread's pull on the cam; large: the thread slides along the profile)\n",
        c.max_contact_angle_deg,
        c.max_contact_angle_at_phi_deg,
        stitchkin::format::fmt_num(c.contact_angle_limit_deg),
        if c.contact_angle_ok { "ok" } else { "TOO STEEP" }
    );
    for note in &s.notes {
        r += &format!("# note: {note}\n");
    }
    if !(c.min_radius_ok && c.contact_angle_ok) && s.smooth_deg == 0.0 {
        r += "# hint: --smooth DEG rounds off steps of the target (such as the thread drawn in at a lock) at the cost of the match\n";
    }
    if !written.is_empty() {
        r += &format!("# written: {}\n", written.join(", "));
    }
    r
}
