//! Straightness of a point's path, and the tolerances that keep it straight.
//!
//! Seed 004 (section 2.2.1) studies the Textima Altin needle mechanism, a
//! linkage whose needle point E should run on a straight line inclined at
//! α = 20°: it changes "the accuracy of each parameter in turn, keeping the
//! others", and stops when "the trajectory deviates from straightness by
//! more than ± 0.05 mm"; most dimensions are held to ± 0.05 mm.
//!
//! [`straightness`] measures the deviation d(φ) of a point P from a line,
//! over the cycle or a part of it:
//! - the line through two model points H → T (unit u, at every φ), or the
//!   least-squares line of the sampled path (orthogonal regression: the
//!   centroid and the principal axis of the samples);
//! - paths in the world xy-plane: d = u × (P − H), signed, positive to the
//!   left of u (the `line_deviation` measure's convention); spatial ones:
//!   d = |(P − H) × u|;
//! - the largest and smallest d are refined below the grid step at the zero
//!   of the exact analog dd/dφ (dual numbers, as the dead centres of
//!   [`super::stroke`]); the RMS is over the φ samples;
//! - for paths in the xy-plane also the minimum-zone width (ISO 1101): the least
//!   distance between two parallel lines that enclose every sample.
//!
//! [`tolerance_study`] then varies the dimensions: one at a time at ± its
//! tolerance, the largest tolerance each may have alone before the largest
//! |d| exceeds a limit (bisection), and a seeded Monte Carlo over all
//! tolerances at once.

use nalgebra::Matrix3;
use rayon::prelude::*;
use serde::Serialize;

use super::design::{Design, Sweep, Vary};
use super::stroke::{NO_STROKE_MM, PoseFn, Refiner, argminmax, cst3, neighbours};
use crate::error::{Error, Input, NotFiniteError, ParamError, did_you_mean};
use crate::eval::{cycle_phis_deg, wrap_deg};
use crate::geometry::{V3, norm_or_zero};
use crate::mechanism::{Mechanism, Phi, Pose};
use crate::model::{Model, Params};
use crate::scalar::Real;

/// The line the deviation is measured from.
#[derive(Debug, Clone, PartialEq)]
pub enum Reference {
    /// Through point `through` toward point `toward` (e.g. a guide's two points).
    Line { through: usize, toward: usize },
    /// The least-squares line of the path's samples.
    Fit,
}

impl Reference {
    /// `H,T`: the line through model points H and T, directed H → T.
    pub fn parse_line(model: &Model, spec: &str) -> Result<Reference, Error> {
        let Some((h, t)) = spec.split_once(',') else {
            return Err(Error::Param(ParamError::new(
                Input::Line,
                format!("`{spec}` is not two points H,T"),
                Some("write H,T with two of the model's points, e.g. N1,N2".into()),
            )));
        };
        let (h, t) = (h.trim(), t.trim());
        if h == t {
            return Err(Error::Param(ParamError::new(
                Input::Line,
                format!("`{spec}`: a line needs two different points"),
                Some("e.g. N1,N2".into()),
            )));
        }
        Ok(Reference::Line {
            through: model.point_slot(h).map_err(|e| e.given_in(Input::Line))?,
            toward: model.point_slot(t).map_err(|e| e.given_in(Input::Line))?,
        })
    }
}

/// The part of the cycle measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Window {
    /// The whole cycle.
    Cycle,
    /// The working stroke down: from the dead centre farthest along the line
    /// (toward T; up for a fitted line) to the nearest.
    Down,
    /// Back up: from the nearest dead centre to the farthest.
    Up,
    /// From one φ to another, degrees (wrapping past 360° when `to < from`).
    Phi { from_deg: f64, to_deg: f64 },
}

impl Window {
    /// `cycle`, `down`, `up` or `FROM:TO` (degrees).
    pub fn parse(spec: &str) -> Result<Window, Error> {
        let bad = |message: String| {
            Error::Param(ParamError::new(
                Input::Over,
                message,
                Some("write cycle, down, up, or FROM:TO in degrees of φ, e.g. 300:60".into()),
            ))
        };
        match spec.trim() {
            "cycle" => Ok(Window::Cycle),
            "down" => Ok(Window::Down),
            "up" => Ok(Window::Up),
            s => {
                let (a, b) = s
                    .split_once(':')
                    .ok_or_else(|| bad(format!("`{s}` is not cycle, down, up or FROM:TO")))?;
                let num = |x: &str| x.trim().parse::<f64>().ok().filter(|v| v.is_finite());
                let (Some(from_deg), Some(to_deg)) = (num(a), num(b)) else {
                    return Err(bad(format!("the ends of `{s}` must be numbers (degrees)")));
                };
                if (to_deg - from_deg).rem_euclid(360.0) < 1e-9 {
                    return Err(bad(format!(
                        "`{s}` is empty or a whole turn; use `cycle` for the whole turn"
                    )));
                }
                Ok(Window::Phi { from_deg, to_deg })
            }
        }
    }
}

/// How to measure straightness.
#[derive(Debug, Clone, PartialEq)]
pub struct StraightnessOptions {
    pub point: usize,
    pub reference: Reference,
    pub window: Window,
    /// φ step of the samples, degrees.
    pub step_deg: f64,
}

/// The deviation of a point's path from a line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Straightness {
    pub point: String,
    /// The line and the window, in words.
    pub reference: String,
    pub window: String,
    /// The window in φ, degrees (`to_deg` − `from_deg` ≤ 360; `to_deg` may
    /// exceed 360).
    pub from_deg: f64,
    pub to_deg: f64,
    /// Path and line in the world xy-plane: d is signed (+ left of the
    /// line's direction); otherwise d is a distance.
    pub signed: bool,
    /// A point of the line and its unit direction (world; at the window's
    /// first sample when the line moves).
    pub line_point_mm: [f64; 3],
    pub line_direction: [f64; 3],
    /// Angle of the line's direction from the world +y axis, degrees (signed
    /// for paths in the xy-plane: + leaning toward +x).
    pub line_from_y_deg: f64,
    /// The point's travel along the line in the window, mm.
    pub travel_mm: f64,
    /// Largest and smallest d and where (φ in [0, 360)), mm.
    pub max_dev_mm: f64,
    pub phi_at_max_deg: f64,
    pub min_dev_mm: f64,
    pub phi_at_min_deg: f64,
    /// max |d|, mm: what a tolerance limit is compared with.
    pub max_abs_dev_mm: f64,
    /// √(mean d²) over the φ samples, mm.
    pub rms_dev_mm: f64,
    /// Minimum-zone (ISO 1101) width of the samples, mm (paths in the world
    /// xy-plane).
    pub zone_mm: Option<f64>,
    /// The samples: φ (degrees, not wrapped), position along the line from
    /// its point, and d, mm.
    pub phi_deg: Vec<f64>,
    pub along_mm: Vec<f64>,
    pub dev_mm: Vec<f64>,
}

/// The line at a sample: a fixed one (fitted), or through two model points.
#[derive(Debug, Clone, Copy)]
enum Line {
    Points(usize, usize),
    Fixed(V3<f64>, V3<f64>),
}

/// d(φ) of `point` from `line` (signed in the plane), or, with `along`,
/// the position along it, (P − H)·u.
struct Dev {
    point: usize,
    line: Line,
    signed: bool,
    along: bool,
}

impl PoseFn for Dev {
    fn at<T: Real>(&self, _: &Mechanism<T>, pose: &Pose<T>, k: usize) -> T {
        let (h, u) = match self.line {
            Line::Points(h, t) => {
                let h = pose.point(h, k);
                let d = pose.point(t, k) - h;
                (h, d / norm_or_zero(d))
            }
            Line::Fixed(c, u) => (cst3(c), cst3(u)),
        };
        let w = pose.point(self.point, k) - h;
        if self.along {
            w.dot(&u)
        } else if self.signed {
            u.x * w.y - u.y * w.x
        } else {
            norm_or_zero(w.cross(&u))
        }
    }
}

/// The least-squares line of `pts`: centroid and principal axis, pointing
/// up (+y; +x, then +z, when level).
fn fit_line(pts: &[V3<f64>]) -> (V3<f64>, V3<f64>) {
    let n = pts.len() as f64;
    let c = pts.iter().fold(V3::zeros(), |a, p| a + p) / n;
    let cov = pts
        .iter()
        .fold(Matrix3::zeros(), |a, p| a + (p - c) * (p - c).transpose());
    let eig = cov.symmetric_eigen();
    let (i, _) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .fold((0, f64::MIN), |b, (i, &l)| if l > b.1 { (i, l) } else { b });
    let mut u: V3<f64> = eig.eigenvectors.column(i).into_owned();
    let key = if u.y.abs() > 1e-12 {
        u.y
    } else if u.x.abs() > 1e-12 {
        u.x
    } else {
        u.z
    };
    if key < 0.0 {
        u = -u;
    }
    (c, u)
}

/// Minimum-zone straightness (ISO 1101) of planar points: the least
/// distance between two parallel lines enclosing them, i.e. the minimum
/// width of their convex hull, which is reached with one hull edge on one of
/// the lines (Toussaint's rotating calipers; here every edge against every
/// hull vertex).
pub fn zone_width(pts: &[[f64; 2]]) -> f64 {
    let mut p: Vec<[f64; 2]> = pts.to_vec();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return 0.0;
    }
    let hull = crate::geometry::convex_hull(&mut p);
    if hull.len() < 3 {
        return 0.0;
    }
    let h = hull.len();
    (0..h)
        .map(|i| {
            let (a, b) = (hull[i], hull[(i + 1) % h]);
            let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            hull.iter()
                .map(|&q| crate::geometry::turn(a, b, q).abs() / len)
                .fold(0.0, f64::max)
        })
        .fold(f64::MAX, f64::min)
}

/// Where an extreme is (φ, degrees) and its value.
type Extreme = (f64, f64);

/// The extremes of f over samples `phis` (with values `v`), refined with
/// the exact analog where they are interior (`periodic`: the samples are the
/// whole cycle): (min, max).
fn refined_extremes(
    refiner: &mut Refiner,
    f: &Dev,
    phis: &[f64],
    v: &[f64],
    periodic: bool,
) -> Result<(Extreme, Extreme), Error> {
    let (i0, i1) = argminmax(v);
    let n = phis.len();
    let mut one = |k: usize, maximum: bool| -> Result<Extreme, Error> {
        if periodic {
            let (a, b) = neighbours(phis, k);
            refiner.refine(f, a, b, phis[k], v[k], maximum)
        } else if k == 0 || k + 1 == n {
            Ok((phis[k], v[k]))
        } else {
            refiner.refine(f, phis[k - 1], phis[k + 1], phis[k], v[k], maximum)
        }
    };
    Ok((one(i0, false)?, one(i1, true)?))
}

/// Measures the straightness of the point's path (module docs).
pub fn straightness(model: &Model, params: &Params, opts: &StraightnessOptions) -> Result<Straightness, Error> {
    measure(model, params, opts, true)
}

/// [`straightness`]; without `detail` (for tolerance studies) the travel is
/// the grid's and the minimum zone is left out.
fn measure(model: &Model, params: &Params, opts: &StraightnessOptions, detail: bool) -> Result<Straightness, Error> {
    crate::eval::check_step(opts.step_deg)?;
    let mech = model.mechanism::<f64>(params)?;
    let mut refiner = Refiner::new(model, params)?;
    check_line(model, &mech, opts)?;

    // The window in φ.
    let cycle = cycle_phis_deg(model.phi_start_deg(), opts.step_deg);
    let (from_deg, to_deg) = match opts.window {
        Window::Cycle => (cycle[0], cycle[0] + 360.0),
        Window::Phi { from_deg, to_deg } => (from_deg, from_deg + (to_deg - from_deg).rem_euclid(360.0)),
        Window::Down | Window::Up => stroke_window(model, &mech, &mut refiner, opts, &cycle)?,
    };
    let periodic = opts.window == Window::Cycle;
    let phis: Vec<f64> = if periodic {
        cycle
    } else {
        let n = ((to_deg - from_deg) / opts.step_deg - 1e-9).ceil().max(2.0) as usize + 1;
        (0..n)
            .map(|j| from_deg + (to_deg - from_deg) * j as f64 / (n - 1) as f64)
            .collect()
    };
    let pose = solve_at(&mech, &phis)?;
    let pts = pose.track(opts.point).to_vec();
    // A path in the world xy-plane (a planar model, or one whose frames
    // turn only about z) has a signed deviation.
    let in_xy = |track: &[V3<f64>]| track.iter().all(|p| p.z.abs() < 1e-9);
    let signed = model.planar
        || (in_xy(&pts)
            && match opts.reference {
                Reference::Line { through, toward } => in_xy(pose.track(through)) && in_xy(pose.track(toward)),
                Reference::Fit => true,
            });
    let line = match opts.reference {
        Reference::Line { through, toward } => Line::Points(through, toward),
        Reference::Fit => {
            let (c, u) = fit_line(&pts);
            Line::Fixed(c, u)
        }
    };
    let dev = Dev {
        point: opts.point,
        line,
        signed,
        along: false,
    };
    let along = Dev { along: true, ..dev };
    let d: Vec<f64> = (0..phis.len()).map(|k| dev.at(&mech, &pose, k)).collect();
    let s: Vec<f64> = (0..phis.len()).map(|k| along.at(&mech, &pose, k)).collect();
    let ((phi_min, min), (phi_max, max)) = refined_extremes(&mut refiner, &dev, &phis, &d, periodic)?;
    let (s_lo, s_hi) = if detail {
        let ((_, lo), (_, hi)) = refined_extremes(&mut refiner, &along, &phis, &s, periodic)?;
        (lo, hi)
    } else {
        let (i0, i1) = argminmax(&s);
        (s[i0], s[i1])
    };
    let rms = (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt();
    let zone_mm = (signed && detail).then(|| zone_width(&pts.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>()));
    let (lp, ld) = match line {
        Line::Fixed(c, u) => (c, u),
        Line::Points(h, t) => {
            let (h, t) = (pose.point(h, 0), pose.point(t, 0));
            (h, (t - h).normalize())
        }
    };
    let line_from_y_deg = if signed {
        ld.x.atan2(ld.y).to_degrees()
    } else {
        ld.y.clamp(-1.0, 1.0).acos().to_degrees()
    };
    let (reference, window) = describe(model, opts, from_deg, to_deg);
    let out = Straightness {
        point: model.point_names[opts.point].clone(),
        reference,
        window,
        from_deg,
        to_deg,
        signed,
        line_point_mm: [lp.x, lp.y, lp.z],
        line_direction: [ld.x, ld.y, ld.z],
        line_from_y_deg,
        travel_mm: s_hi - s_lo,
        max_dev_mm: max,
        phi_at_max_deg: wrap_deg(phi_max),
        min_dev_mm: min,
        phi_at_min_deg: wrap_deg(phi_min),
        max_abs_dev_mm: if signed { max.max(-min) } else { max },
        rms_dev_mm: rms,
        zone_mm,
        phi_deg: phis,
        along_mm: s,
        dev_mm: d,
    };
    let finite = [
        out.max_dev_mm,
        out.min_dev_mm,
        out.rms_dev_mm,
        out.travel_mm,
        out.line_from_y_deg,
    ]
    .iter()
    .all(|x| x.is_finite())
        && out.dev_mm.iter().chain(&out.along_mm).all(|x| x.is_finite());
    if !finite {
        return Err(Error::NotFinite(NotFiniteError {
            quantity: format!("the deviation of `{}`", out.point),
            phi_deg: None,
            cause: "the line's two points coincide at some φ".into(),
        }));
    }
    Ok(out)
}

/// The mechanism solved at `phis`.
fn solve_at(mech: &Mechanism<f64>, phis: &[f64]) -> Result<Pose<f64>, Error> {
    let mut pose = mech.new_pose(phis.len());
    mech.solve(&Phi::table(phis), &mut pose)?;
    Ok(pose)
}

/// A reference line through two points that do not coincide.
fn check_line(model: &Model, mech: &Mechanism<f64>, opts: &StraightnessOptions) -> Result<(), Error> {
    if let Reference::Line { through, toward } = opts.reference {
        let pose = solve_at(mech, &[model.phi_start_deg()])?;
        if (pose.point(toward, 0) - pose.point(through, 0)).norm() < 1e-9 {
            return Err(Error::Param(ParamError::new(
                Input::Line,
                format!(
                    "points `{}` and `{}` coincide, so they give no direction",
                    model.point_names[through], model.point_names[toward]
                ),
                Some("choose two distinct points of the guide".into()),
            )));
        }
    }
    Ok(())
}

/// The working stroke (`--over down` or `up`): from one dead centre along
/// the line to the other, found over the whole `cycle` and refined.
fn stroke_window(
    model: &Model,
    mech: &Mechanism<f64>,
    refiner: &mut Refiner,
    opts: &StraightnessOptions,
    cycle: &[f64],
) -> Result<(f64, f64), Error> {
    // Dead centres along the line over the whole cycle.
    let pose = solve_at(mech, cycle)?;
    let line = match opts.reference {
        Reference::Line { through, toward } => Line::Points(through, toward),
        Reference::Fit => {
            let (c, u) = fit_line(pose.track(opts.point));
            Line::Fixed(c, u)
        }
    };
    let f = Dev {
        point: opts.point,
        line,
        signed: false,
        along: true,
    };
    let s: Vec<f64> = (0..cycle.len()).map(|k| f.at(mech, &pose, k)).collect();
    let ((phi_lo, lo), (phi_hi, hi)) = refined_extremes(refiner, &f, cycle, &s, true)?;
    if hi - lo < NO_STROKE_MM {
        return Err(Error::Param(ParamError::new(
            Input::Over,
            format!(
                "point `{}` does not move along the line, so it has no working stroke",
                model.point_names[opts.point]
            ),
            Some("measure over the whole cycle, or along a line of the point's motion".into()),
        )));
    }
    let (a, b) = if opts.window == Window::Down {
        (phi_hi, phi_lo)
    } else {
        (phi_lo, phi_hi)
    };
    Ok((a, a + (b - a).rem_euclid(360.0)))
}

/// The reference line and the window in words.
fn describe(model: &Model, opts: &StraightnessOptions, from_deg: f64, to_deg: f64) -> (String, String) {
    let words = |p: usize| model.point_names[p].as_str();
    let reference = match opts.reference {
        Reference::Line { through, toward } => format!("the line {} → {}", words(through), words(toward)),
        Reference::Fit => "the least-squares line of the path".to_string(),
    };
    let window = match opts.window {
        Window::Cycle => "over the cycle".to_string(),
        Window::Down => format!("down, from φ = {:.2}° to {:.2}°", wrap_deg(from_deg), wrap_deg(to_deg)),
        Window::Up => format!("up, from φ = {:.2}° to {:.2}°", wrap_deg(from_deg), wrap_deg(to_deg)),
        Window::Phi { .. } => format!("from φ = {:.2}° to {:.2}°", wrap_deg(from_deg), wrap_deg(to_deg)),
    };
    (reference, window)
}

/// A parameter's tolerance: the value may be anywhere in nominal ± `tol`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tolerance {
    pub name: String,
    pub unit: &'static str,
    pub tol: f64,
}

/// The tolerance of every parameter studied: those named in `specs`
/// (`NAME=±T`, `NAME=T`; T = 0 holds the parameter exact), and every other
/// length parameter at ± `length_tol` mm, in its own unit (seed 004: ± 0.05 mm). Angles and
/// dimensionless parameters need an explicit tolerance.
pub fn tolerances(model: &Model, specs: &[String], length_tol: f64) -> Result<Vec<Tolerance>, Error> {
    let help = || Some("write NAME=±T in the parameter's unit, e.g. l_ab=±0.05 (T = 0 holds it exact)".to_string());
    if !(length_tol.is_finite() && length_tol >= 0.0) {
        return Err(Error::Param(ParamError::new(
            Input::LengthTolerance,
            format!("the default length tolerance {length_tol} mm must be ≥ 0"),
            Some("e.g. 0.05".into()),
        )));
    }
    let mut explicit: Vec<(usize, f64)> = Vec::new();
    for spec in specs {
        let Some((name, value)) = spec.split_once('=') else {
            return Err(Error::Param(ParamError::new(
                Input::Tolerance,
                format!("`{spec}` is not NAME=±T"),
                help(),
            )));
        };
        let name = name.trim();
        let t = value.trim();
        let t = ["±", "+-", "+/-"].iter().find_map(|p| t.strip_prefix(p)).unwrap_or(t);
        let Some(tol) = t.trim().parse::<f64>().ok().filter(|x| x.is_finite() && *x >= 0.0) else {
            return Err(Error::Param(ParamError::new(
                Input::Tolerance,
                format!("the tolerance in `{spec}` must be a number ≥ 0"),
                help(),
            )));
        };
        let Some(i) = model.param_index(name) else {
            let hint = did_you_mean(name, model.params.iter().map(|p| p.name.as_str()))
                .map(|s| format!(" (did you mean `{s}`?)"))
                .unwrap_or_default();
            return Err(Error::Param(ParamError::new(
                Input::Tolerance,
                format!("`{spec}`: the model has no parameter `{name}`{hint}"),
                Some(format!(
                    "its parameters are: {}",
                    model
                        .params
                        .iter()
                        .filter(|p| !p.is_derived())
                        .map(|p| p.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
            )));
        };
        if model.params[i].is_derived() {
            return Err(Error::Param(ParamError::new(
                Input::Tolerance,
                format!("`{spec}`: `{name}` is derived from other parameters and has no tolerance of its own"),
                Some("give tolerances to the parameters its expression uses".into()),
            )));
        }
        if explicit.iter().any(|(j, _)| *j == i) {
            return Err(Error::Param(ParamError::new(
                Input::Tolerance,
                format!("`{name}` has two tolerances"),
                None,
            )));
        }
        explicit.push((i, tol));
    }
    let out: Vec<Tolerance> = model
        .params
        .iter()
        .enumerate()
        .filter(|(_, p)| !p.is_derived())
        .filter_map(|(i, p)| {
            let tol = match explicit.iter().find(|(j, _)| *j == i) {
                Some((_, t)) => *t,
                // `length_tol` is in mm; the parameter in the model's unit.
                None if p.unit.is_length() => p.from_result_unit(length_tol),
                None => 0.0,
            };
            (tol > 0.0).then(|| Tolerance {
                name: p.name.clone(),
                unit: p.unit_str(),
                tol,
            })
        })
        .collect();
    if out.is_empty() {
        return Err(Error::Param(ParamError::new(
            Input::Tolerance,
            "no parameter has a tolerance to study",
            help(),
        )));
    }
    Ok(out)
}

/// How the Monte Carlo draws each parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Distribution {
    /// Uniform in nominal ± tol.
    Uniform,
    /// Normal with σ = tol/3, truncated at ± tol (± 3σ: parts outside the
    /// tolerance are rejected by inspection).
    Normal,
}

/// How to run a tolerance study.
#[derive(Debug, Clone, PartialEq)]
pub struct ToleranceOptions {
    pub straightness: StraightnessOptions,
    /// The largest max |d| allowed, mm (seed 004: 0.05).
    pub limit_mm: f64,
    pub tolerances: Vec<Tolerance>,
    /// Monte Carlo samples (0: none), at most [`MAX_MONTE_CARLO_SAMPLES`].
    pub samples: usize,
    pub seed: u64,
    pub distribution: Distribution,
}

/// One parameter alone at ± its tolerance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OneAtATime {
    pub name: String,
    pub unit: &'static str,
    pub tol: f64,
    /// max |d| with the parameter at nominal − tol and + tol, mm (`None`:
    /// does not assemble).
    pub dev_minus_mm: Option<f64>,
    pub dev_plus_mm: Option<f64>,
    /// The worse of the two minus the nominal max |d|, mm (`None` when
    /// either side does not assemble).
    pub change_mm: Option<f64>,
    /// The largest tolerance this parameter may have alone with max |d|
    /// within the limit at both + and −, in its unit…
    pub largest_tol: f64,
    /// …or, when false, no limit was found up to `largest_tol`, the end of
    /// the search (64 × tol).
    pub bounded: bool,
}

/// Every tolerance at once, drawn at random.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MonteCarlo {
    pub samples: usize,
    pub seed: u64,
    pub distribution: Distribution,
    /// Samples that did not assemble (counted as over the limit).
    pub failed: usize,
    /// Percentiles of max |d| over the samples that assembled, mm.
    pub p50_mm: Option<f64>,
    pub p90_mm: Option<f64>,
    pub p99_mm: Option<f64>,
    pub mean_mm: Option<f64>,
    pub max_mm: Option<f64>,
    /// Share of all samples over the limit (or not assembling), 0…1.
    pub over_limit: f64,
}

/// The outcome of a tolerance study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToleranceStudy {
    pub point: String,
    pub reference: String,
    pub window: String,
    pub limit_mm: f64,
    /// max |d| at the nominal dimensions, mm.
    pub nominal_mm: f64,
    pub one_at_a_time: Vec<OneAtATime>,
    pub monte_carlo: Option<MonteCarlo>,
}

/// How far past a parameter's tolerance the search for its largest
/// tolerance goes.
pub const SEARCH_CAP: f64 = 64.0;

/// max |d| with parameters changed by `deltas` (index, change) from `base`,
/// bypassing the adjustable ranges (a manufacturing deviation is not an
/// adjustment); `None` when the mechanism does not assemble.
fn deviation(model: &Model, base: &Params, deltas: &[(usize, f64)], opts: &StraightnessOptions) -> Option<f64> {
    let mut p = base.clone();
    for &(i, d) in deltas {
        p.values[i] += d;
    }
    measure(model, &p, opts, false).ok().map(|s| s.max_abs_dev_mm)
}

/// Linear interpolation between order statistics (type 7) of sorted `v`.
fn percentile(v: &[f64], q: f64) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let h = q * (v.len() - 1) as f64;
    let (i, f) = (h.floor() as usize, h - h.floor());
    Some(if i + 1 < v.len() {
        v[i] + f * (v[i + 1] - v[i])
    } else {
        v[i]
    })
}

/// Φ⁻¹(p), the standard normal quantile, 0 < p < 1: Acklam's rational
/// approximation (relative error < 1.2e-9), enough for drawing samples.
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// Φ(−3): the normal draws are truncated at ± 3σ = ± tol.
const PHI_MINUS_3: f64 = 0.001_349_898_031_630_094_6;

/// The most Monte Carlo samples a tolerance study takes: each is a whole
/// straightness evaluation, and 1 000 already give the 99 % percentile to a
/// few per cent.
pub const MAX_MONTE_CARLO_SAMPLES: usize = 1_000_000;

/// Runs the tolerance study (module docs).
pub fn tolerance_study(model: &Model, base: &Params, opts: &ToleranceOptions) -> Result<ToleranceStudy, Error> {
    if !(opts.limit_mm.is_finite() && opts.limit_mm > 0.0) {
        return Err(Error::Param(ParamError::new(
            Input::Limit,
            format!("the limit {} mm must be a positive number", opts.limit_mm),
            Some(format!("e.g. 0.05 ({})", crate::references::cite(4))),
        )));
    }
    if opts.samples > MAX_MONTE_CARLO_SAMPLES {
        return Err(Error::Param(ParamError::new(
            Input::Samples,
            format!("{} Monte Carlo samples are too many", opts.samples),
            Some(format!(
                "up to {MAX_MONTE_CARLO_SAMPLES}; 1000 give the 99 % percentile to a few per cent"
            )),
        )));
    }
    let so = &opts.straightness;
    let nominal = straightness(model, base, so)?;
    let nominal_mm = nominal.max_abs_dev_mm;
    if nominal_mm > opts.limit_mm {
        return Err(Error::Param(ParamError::new(
            Input::Limit,
            format!(
                "at the nominal dimensions the path already deviates {nominal_mm:.4} mm, beyond the limit {} mm",
                opts.limit_mm
            ),
            Some("raise the limit, or measure over the working stroke (`down`)".into()),
        )));
    }
    let index: Vec<usize> = opts
        .tolerances
        .iter()
        .map(|t| model.param_index(&t.name).expect("tolerances name parameters"))
        .collect();
    let one_at_a_time: Vec<OneAtATime> = opts
        .tolerances
        .par_iter()
        .zip(&index)
        .map(|(t, &i)| one_at_a_time(model, base, opts, t, i, nominal_mm))
        .collect();
    let monte_carlo = monte_carlo(model, base, opts, &index)?;
    Ok(ToleranceStudy {
        point: nominal.point,
        reference: nominal.reference,
        window: nominal.window,
        limit_mm: opts.limit_mm,
        nominal_mm,
        one_at_a_time,
        monte_carlo,
    })
}

/// Parameter `t` (index `i`) alone at ± its tolerance, and the largest
/// tolerance it may have alone: grown from ± tol by doubling to the first
/// over the limit, then bisected.
fn one_at_a_time(
    model: &Model,
    base: &Params,
    opts: &ToleranceOptions,
    t: &Tolerance,
    i: usize,
    nominal_mm: f64,
) -> OneAtATime {
    let so = &opts.straightness;
    let at = |d: f64| deviation(model, base, &[(i, d)], so);
    let (minus, plus) = (at(-t.tol), at(t.tol));
    // Within the limit at both ends of ± tol.
    let within =
        |tol: f64| matches!((at(-tol), at(tol)), (Some(a), Some(b)) if a <= opts.limit_mm && b <= opts.limit_mm);
    // Largest tolerance: grow from ± tol by doubling to the first
    // tolerance over the limit, then bisect to 1e-3 of tol.
    let (mut ok, mut over) = (0.0, t.tol);
    while within(over) && over < SEARCH_CAP * t.tol {
        ok = over;
        over *= 2.0;
    }
    let bounded = !within(over);
    let largest_tol = if bounded {
        while over - ok > 1e-3 * t.tol {
            let m = 0.5 * (ok + over);
            if within(m) { ok = m } else { over = m }
        }
        ok
    } else {
        over
    };
    OneAtATime {
        name: t.name.clone(),
        unit: t.unit,
        tol: t.tol,
        dev_minus_mm: minus,
        dev_plus_mm: plus,
        change_mm: minus.zip(plus).map(|(a, b)| a.max(b) - nominal_mm),
        largest_tol,
        bounded,
    }
}

/// The Monte Carlo over every tolerance at once (`None` for 0 samples):
/// the deviation's percentiles and the share over the limit.
fn monte_carlo(
    model: &Model,
    base: &Params,
    opts: &ToleranceOptions,
    index: &[usize],
) -> Result<Option<MonteCarlo>, Error> {
    if opts.samples == 0 {
        return Ok(None);
    }
    let so = &opts.straightness;
    // Uniform numbers u in [0, 1) from the sweep's seeded SplitMix64
    // stream (fixed forever, as `sweep --method random` uses), one per
    // sample and parameter.
    let unit_box: Vec<Vary> = opts
        .tolerances
        .iter()
        .map(|t| Vary {
            name: t.name.clone(),
            lo: 0.0,
            hi: 1.0,
            n: 2,
        })
        .collect();
    let draws = Sweep::new(
        unit_box,
        Design::Random {
            samples: opts.samples,
            seed: opts.seed,
        },
    )?;
    let devs: Vec<Option<f64>> = (0..opts.samples)
        .into_par_iter()
        .map(|k| {
            let deltas: Vec<(usize, f64)> = draws
                .setting(k)
                .iter()
                .zip(&opts.tolerances)
                .zip(index)
                .map(|((&u, t), &i)| {
                    let d = match opts.distribution {
                        Distribution::Uniform => t.tol * (2.0 * u - 1.0),
                        Distribution::Normal => {
                            t.tol / 3.0 * normal_quantile(PHI_MINUS_3 + u * (1.0 - 2.0 * PHI_MINUS_3))
                        }
                    };
                    (i, d)
                })
                .collect();
            deviation(model, base, &deltas, so)
        })
        .collect();
    let mut ok: Vec<f64> = devs.iter().flatten().cloned().collect();
    ok.sort_by(f64::total_cmp);
    let failed = opts.samples - ok.len();
    let over = failed + ok.iter().filter(|d| **d > opts.limit_mm).count();
    Ok(Some(MonteCarlo {
        samples: opts.samples,
        seed: opts.seed,
        distribution: opts.distribution,
        failed,
        p50_mm: percentile(&ok, 0.5),
        p90_mm: percentile(&ok, 0.9),
        p99_mm: percentile(&ok, 0.99),
        mean_mm: (!ok.is_empty()).then(|| ok.iter().sum::<f64>() / ok.len() as f64),
        max_mm: ok.last().cloned(),
        over_limit: over as f64 / opts.samples as f64,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zone_of_a_rectangle_is_its_short_side() {
        let pts: Vec<[f64; 2]> = (0..=100)
            .flat_map(|i| [[i as f64 * 0.3, 0.0], [i as f64 * 0.3, 0.02]])
            .collect();
        assert!((zone_width(&pts) - 0.02).abs() < 1e-12);
        // Turned by 30°, with interior points: the same width.
        let (s, c) = 30f64.to_radians().sin_cos();
        let turned: Vec<[f64; 2]> = pts
            .iter()
            .chain(&[[5.0, 0.01]])
            .map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
            .collect();
        assert!((zone_width(&turned) - 0.02).abs() < 1e-12);
        assert_eq!(zone_width(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), 0.0);
    }

    #[test]
    fn normal_quantiles() {
        assert!(normal_quantile(0.5).abs() < 1e-12);
        assert!((normal_quantile(0.975) - 1.959_963_985).abs() < 1e-8);
        assert!((normal_quantile(PHI_MINUS_3) + 3.0).abs() < 1e-8);
        assert!((normal_quantile(0.01) + normal_quantile(0.99)).abs() < 1e-9);
    }

    #[test]
    fn fitted_line_points_up() {
        let pts: Vec<V3<f64>> = (0..10).map(|i| V3::new(-(i as f64) * 0.5, -(i as f64), 0.0)).collect();
        let (c, u) = fit_line(&pts);
        assert!((c - V3::new(-2.25, -4.5, 0.0)).norm() < 1e-12);
        assert!(u.y > 0.0 && (u.x / u.y - 0.5).abs() < 1e-12 && u.z.abs() < 1e-15);
    }

    #[test]
    fn windows_and_tolerances_parse() {
        assert_eq!(Window::parse("down").unwrap(), Window::Down);
        assert_eq!(
            Window::parse("300:60").unwrap(),
            Window::Phi {
                from_deg: 300.0,
                to_deg: 60.0
            }
        );
        for bad in ["sideways", "10:10", "a:3", "0:360"] {
            assert!(Window::parse(bad).is_err(), "{bad}");
        }
        let m = Model::preset("altin-needle").unwrap();
        let t = tolerances(&m, &["beta=±0.1".into(), "l_lm=0".into(), "l_ab=+-0.02".into()], 0.05).unwrap();
        let get = |n: &str| t.iter().find(|t| t.name == n).map(|t| t.tol);
        assert_eq!(get("beta"), Some(0.1));
        assert_eq!(get("l_ab"), Some(0.02));
        assert_eq!(get("l_bc"), Some(0.05));
        assert_eq!(get("l_lm"), None);
        assert_eq!(get("alpha"), None, "angles need an explicit tolerance");
        assert!(get("rot_d").is_none(), "derived");
        for (bad, says) in [
            ("l_ab", "NAME=±T"),
            ("l_abb=0.1", "did you mean `l_ab`"),
            ("l_ab=-1", "≥ 0"),
            ("rot_d=1", "derived"),
        ] {
            let e = tolerances(&m, &[bad.to_string()], 0.05).unwrap_err().to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
        assert!(
            tolerances(&m, &[], 0.0)
                .unwrap_err()
                .to_string()
                .contains("no parameter")
        );
    }
}
