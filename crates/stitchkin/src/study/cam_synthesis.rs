//! Cam synthesis: the inverse of the thread feed cam. Find
//! the polar profile ρ(θ) of a `[[cams]]` cam that makes a thread path's
//! take-up P(φ) equal a target: the required take-up P'(φ) of the stitch
//! thread compared with the path, or a given curve.
//!
//! Seed 004 §2.8 designs the new lower-thread cam the same way: the guides'
//! coordinates taken about the cam's centre, the contact turned by γ, and
//! "the cam's radius vector r determined from the given increment of the
//! thread contour" (its formulas are garbled in the text); the forward model
//! is §2.5's offset contact (`thread::cam::offset_contact`).
//!
//! **The inverse, radius by radius.** At one φ, seen in the cam's frame (u
//! toward the marker, v = w × u, w the shaft axis, origin C on the axis),
//! the contact is A = C + ρ·e_β, e_β = cos β·u + sin β·v, β = β₀(φ) + γ
//! with β₀ the bisector of the guides' directions (§13.5 of the format).
//! With the guides p, q before and after the cam,
//!
//! ```text
//! |A − p|² = ρ² − 2a_p ρ + c_p,   a_p = e_β·(p − C),   c_p = |p − C|²
//! ```
//!
//! (and the same for q), so the cam's piece of the path is explicit in ρ:
//!
//! ```text
//! L(ρ) = √(ρ² − 2a_p ρ + c_p) + √(ρ² − 2a_q ρ + c_q).
//! ```
//!
//! For seed 004 §2.5's symmetric guides (a_p = a_q = a, c_p = c_q = c) this
//! is ξ_cam = 2·|O₂ − A|, and L(ρ) = L gives the quadratic
//! ρ² − 2aρ + c − L²/4 = 0, ρ = a ± √(a² − c + L²/4). In general the points
//! with |A − p| + |A − q| = L form a prolate spheroid with foci p and q, and
//! the contact ray meets it where a quadratic in ρ vanishes: writing
//! s_p = |A − p|, s_q = |A − q|, s_p + s_q = L and s_p² − s_q² =
//! −2δa ρ + δc (δa = a_p − a_q, δc = c_p − c_q, linear in ρ), so
//! s_p = k + mρ with k = (L² + δc)/(2L), m = −δa/L, and squaring,
//!
//! ```text
//! (1 − m²) ρ² − 2(a_p + k m) ρ + (c_p − k²) = 0,   0 ≤ k + mρ ≤ L.
//! ```
//!
//! 1 − m² > 0 whenever L exceeds |δa| ≤ |p − q|, the straight thread. Of the
//! positive roots that keep both pieces non-negative, the one nearest the
//! model's own profile is taken (C inside the spheroid, the usual case,
//! leaves exactly one). No root means the target asks for a piece shorter
//! than min over ρ ≥ 0 of L(ρ) along that radius: an error naming φ and the
//! shortfall. Each root is polished by Newton on L(ρ) − L.
//!
//! **The rest of the path.** ξ(φ) = ξ_rest(φ) + L(φ), ξ_rest from
//! `Threads::evaluate` with the model's own profile minus its cam piece. The
//! take-up fixes ξ up to ξ(φ0): release P = ξ(φ0) − ξ(φ) (seed 000 eq. 2),
//! feed P = ξ(φ) − ξ(φ0) + ΔP (seed 001 eqs. 22–23). ξ(φ0) is the model's
//! own (the radius at φ0's contact angle kept), or set by an anchor radius
//! there. The knots are the contact angles of a uniform φ grid starting at
//! φ0, so φ0 is a knot and P(φ0) comes out exactly as the convention makes
//! it; a target that differs there is shifted by that constant (reported).
//!
//! **Exact contact** is not synthesised: the taut thread's length depends
//! on the whole wrapped arc (tangent points and the arc integral), not on
//! one radius, so there is no radius-by-radius inverse.

use num_dual::Dual2_64;
use serde::Serialize;

use crate::error::{Error, Input, NotFiniteError, ParamError};
use crate::eval::{self, wrap_deg};
use crate::format::fmt_num;
use crate::geometry::{V2, V3};
use crate::mechanism::{Mechanism, Phi, Pose};
use crate::model::{Machine, Model, Params};
use crate::numeric::PeriodicCubic;
use crate::stitch::mismatch::{Mismatch, mismatch};
use crate::thread::cam::{CamPlacement, Profile};
use crate::thread::measured::{MeasuredCurve, SplitPoint};
use crate::thread::{Cam, CamModel, Convention, Span, Threads};

const TAU: f64 = std::f64::consts::TAU;

/// What the take-up should be.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// P'(φ) of the `[stitch]` thread compared with the path.
    Required,
    /// A periodic curve P(φ) through points (φ in degrees, strictly
    /// increasing within one turn: last − first < 360°), the periodic cubic
    /// spline between them. [`Target::from_curve`] makes one from a curve
    /// file.
    Curve {
        phi_deg: Vec<f64>,
        p_mm: Vec<f64>,
        source: String,
    },
}

impl Target {
    /// The target a measured or wanted curve sets: its samples, as they
    /// are (a take-up P or a required P′ alike: what P should be). A curve
    /// split at B is refused: a path's P is taken at its last node, the
    /// eye, and P_B differs from it by the needle's travel S(φ) − S(φ0)
    /// (docs/stitch-formation.md §3.2).
    pub fn from_curve(curve: &MeasuredCurve) -> Result<Target, Error> {
        if curve.split() == Some(SplitPoint::B) {
            return Err(bad(
                format!(
                    "the target curve `{}` from {} is taken at B, the needle eye's top position; the path's take-up P is taken at its last node, the eye",
                    curve.column(),
                    curve.source()
                ),
                "give the curve at the eye (a column `P_mm`, `P_eye_mm`, `Pprime_mm` or `Pprime_eye_mm`): P_eye = P_B − (S(φ) − S(φ0)), docs/stitch-formation.md §3.2",
            ));
        }
        Ok(Target::Curve {
            phi_deg: curve.phi_deg().to_vec(),
            p_mm: curve.values_mm().to_vec(),
            source: curve.source().to_string(),
        })
    }
}

/// How to synthesise.
#[derive(Debug, Clone, PartialEq)]
pub struct CamOptions {
    /// The thread path whose take-up is to match.
    pub path: String,
    /// The cam on it (needed when the path runs over several).
    pub cam: Option<String>,
    pub target: Target,
    /// Profile points (knots) per turn, 8…1440.
    pub points: usize,
    /// Smoothing: a periodic moving average over this many degrees of
    /// profile angle, applied twice; 0 for none.
    pub smooth_deg: f64,
    /// Smallest acceptable radius, mm (checked, not enforced).
    pub min_radius_mm: f64,
    /// Largest acceptable thread contact angle, deg (checked).
    pub max_pressure_angle_deg: f64,
    /// Profile radius at the contact angle of φ0, mm (default: the model's).
    pub anchor_radius_mm: Option<f64>,
}

impl CamOptions {
    /// Defaults: 360 points, no smoothing, min radius 3 mm, contact angle
    /// at most 45°, the model's radius at φ0.
    pub fn new(path: &str, target: Target) -> CamOptions {
        CamOptions {
            path: path.to_string(),
            cam: None,
            target,
            points: 360,
            smooth_deg: 0.0,
            min_radius_mm: 3.0,
            max_pressure_angle_deg: 45.0,
            anchor_radius_mm: None,
        }
    }
}

/// One profile point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Knot {
    /// Profile angle from the marker direction, [0, 360), deg.
    pub theta_deg: f64,
    /// ρ, mm (after smoothing).
    pub radius_mm: f64,
    /// ρ solved from the target, before smoothing, mm.
    pub solved_mm: f64,
    /// The φ at which the thread bears at this angle, deg.
    pub phi_deg: f64,
}

/// The checks of a profile: reported, never fixed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Checks {
    pub min_radius_mm: f64,
    pub min_radius_at_theta_deg: f64,
    pub min_radius_limit_mm: f64,
    pub min_radius_ok: bool,
    /// ρ² + 2ρ'² − ρρ'' > 0 all round (what the exact contact needs).
    pub convex: bool,
    /// Its smallest value, mm².
    pub convexity_min_mm2: f64,
    /// Profile-angle intervals where it is not convex, deg.
    pub not_convex_deg: Vec<[f64; 2]>,
    /// Largest profile slope atan(|ρ'|/ρ): the angle between the radius and
    /// the profile normal, deg.
    pub max_slope_deg: f64,
    pub max_slope_at_theta_deg: f64,
    /// Largest thread contact angle: between the profile normal at the
    /// contact and the thread's pull on the cam (the sum of the unit
    /// vectors along its two pieces, seen along the shaft), deg.
    pub max_contact_angle_deg: f64,
    pub max_contact_angle_at_phi_deg: f64,
    pub contact_angle_limit_deg: f64,
    pub contact_angle_ok: bool,
}

/// The synthesised profile evaluated in the model again.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verification {
    /// The check grid: the knots' φ and the midpoints between them, from
    /// φ0, deg.
    pub phi_deg: Vec<f64>,
    /// Target, take-up with the model's own cam, and with the synthesised
    /// one, mm.
    pub target_mm: Vec<f64>,
    pub p_before_mm: Vec<f64>,
    pub p_after_mm: Vec<f64>,
    /// max |P − target| at the knots' φ and between them, with where.
    pub max_err_knots_mm: f64,
    pub max_err_knots_at_deg: f64,
    pub max_err_between_mm: f64,
    pub max_err_between_at_deg: f64,
    /// The same before synthesis (the model's own cam), over the grid.
    pub max_err_before_mm: f64,
    /// Match with the stitch thread's P' (docs/stitch-formation.md §8) on
    /// the knots' φ grid (every 360/N° from φ0: for N = 360 and φ0 on the
    /// model's φ grid, the grid of `stitchkin match`), before and after;
    /// `None` without a stitch thread on this path.
    pub match_before: Option<Mismatch>,
    pub match_after: Option<Mismatch>,
    /// After, on the whole check grid (knots and midpoints).
    pub match_after_all: Option<Mismatch>,
}

/// A synthesised cam.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CamSynthesis {
    pub path: String,
    pub cam: String,
    /// The cam's `center` and `marker` points, and its axis and frame as
    /// written in the model (for the `[[cams]]` snippet).
    pub center: String,
    pub marker: String,
    pub axis_toml: Option<String>,
    pub frame: Option<String>,
    pub gamma_deg: f64,
    /// What was matched, in words.
    pub target: String,
    /// The stitch thread compared with the path, if any.
    pub thread: Option<String>,
    pub phi0_deg: f64,
    /// Knots in profile-angle order.
    pub knots: Vec<Knot>,
    pub smooth_deg: f64,
    /// Constant taken off the target so that it has the convention's value
    /// at φ0, mm (0 for P').
    pub target_shift_mm: f64,
    /// Radius at the contact angle of φ0 and that angle, mm and deg.
    pub anchor_radius_mm: f64,
    pub anchor_theta_deg: f64,
    /// Radius range of the model's own profile and of the new one, mm.
    pub reference_radius_mm: [f64; 2],
    pub radius_mm: [f64; 2],
    pub checks: Checks,
    pub verify: Verification,
    /// Other paths over the same cam: their take-up changes too.
    pub shared_with: Vec<String>,
    pub notes: Vec<String>,
    #[serde(skip)]
    pub profile: Profile,
}

pub(crate) fn bad(message: String, help: &str) -> Error {
    Error::Param(ParamError::general(message, Some(help.to_string())))
}

/// A value given in `input` that cannot be used.
pub(crate) fn bad_input(input: Input, message: String, help: &str) -> Error {
    Error::Param(ParamError::new(input, message, Some(help.to_string())))
}

/// The contact ray of the offset model at one φ (seed 004 §2.5).
#[derive(Debug, Clone, Copy)]
struct Ray {
    /// Contact profile angle β = β₀ + γ, rad.
    beta: f64,
    /// a = e_β·(guide − C), c = |guide − C|², for p and q.
    ap: f64,
    cp: f64,
    aq: f64,
    cq: f64,
    /// The guides in the cam's frame: in-plane and height.
    pl: V2<f64>,
    ql: V2<f64>,
    hp: f64,
    hq: f64,
}

impl Ray {
    /// As `offset_contact` places it; `None` where it cannot.
    fn new(p: V3<f64>, q: V3<f64>, center: V3<f64>, marker: V3<f64>, axis: V3<f64>, gamma: f64) -> Option<Ray> {
        let at = CamPlacement::new(center, marker, axis)?;
        let local = |x: V3<f64>| {
            let d = x - at.center;
            (V2::new(d.dot(&at.u), d.dot(&at.v)), d.dot(&at.w))
        };
        let ((pl, hp), (ql, hq)) = (local(p), local(q));
        let (np, nq) = (pl.norm(), ql.norm());
        if np <= 0.0 || nq <= 0.0 {
            return None;
        }
        let bis = pl / np + ql / nq;
        if bis.norm() < 1e-9 {
            return None;
        }
        let beta = bis.y.atan2(bis.x) + gamma;
        let e = V2::new(beta.cos(), beta.sin());
        Some(Ray {
            beta,
            ap: pl.dot(&e),
            cp: pl.norm_squared() + hp * hp,
            aq: ql.dot(&e),
            cq: ql.norm_squared() + hq * hq,
            pl,
            ql,
            hp,
            hq,
        })
    }

    /// The two pieces |A − p|, |A − q| for radius ρ.
    fn pieces(&self, rho: f64) -> (f64, f64) {
        (
            (rho * rho - 2.0 * self.ap * rho + self.cp).max(0.0).sqrt(),
            (rho * rho - 2.0 * self.aq * rho + self.cq).max(0.0).sqrt(),
        )
    }

    /// L(ρ) = |A − p| + |A − q|.
    fn length(&self, rho: f64) -> f64 {
        let (a, b) = self.pieces(rho);
        a + b
    }

    /// The shortest L along the ray, ρ ≥ 0 (L is convex in ρ, least between
    /// the feet a_p and a_q): golden section.
    fn min_length(&self) -> f64 {
        let (mut lo, mut hi) = (self.ap.min(self.aq).max(0.0), self.ap.max(self.aq).max(0.0));
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..100 {
            let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if self.length(x1) < self.length(x2) {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        self.length(0.5 * (lo + hi))
    }

    /// ρ > 0 with L(ρ) = `l`: the spheroid quadratic (module docs), the root
    /// nearest `near`, polished by Newton. `None` when there is none.
    fn solve(&self, l: f64, near: f64) -> Option<f64> {
        let (da, dc) = (self.ap - self.aq, self.cp - self.cq);
        if !(l.is_finite() && l > da.abs()) {
            return None;
        }
        // s_p = k + mρ; (1 − m²)ρ² − 2(a_p + km)ρ + (c_p − k²) = 0.
        let k = (l * l + dc) / (2.0 * l);
        let m = -da / l;
        let (a2, b, c) = (1.0 - m * m, self.ap + k * m, self.cp - k * k);
        let disc = b * b - a2 * c;
        if disc < 0.0 {
            return None;
        }
        // Stable roots: q = b + sign(b)·√disc, ρ = q/a2 and c/q.
        let q = b + if b >= 0.0 { disc.sqrt() } else { -disc.sqrt() };
        let mut roots = vec![q / a2];
        if q != 0.0 {
            roots.push(c / q);
        }
        let tol = 1e-9 * l.max(1.0);
        roots
            .into_iter()
            .filter(|&r| r.is_finite() && r > 0.0 && (-tol..=l + tol).contains(&(k + m * r)))
            .map(|r| self.polish(r, l))
            .filter(|&r| r > 0.0 && (self.length(r) - l).abs() < 1e-6 * l.max(1.0))
            .min_by(|x, y| (x - near).abs().total_cmp(&(y - near).abs()))
    }

    /// Newton on L(ρ) − l, dL/dρ = (ρ − a_p)/s_p + (ρ − a_q)/s_q.
    fn polish(&self, mut rho: f64, l: f64) -> f64 {
        for _ in 0..4 {
            let (sp, sq) = self.pieces(rho);
            if sp <= 0.0 || sq <= 0.0 {
                break;
            }
            let d = (rho - self.ap) / sp + (rho - self.aq) / sq;
            if d.abs() < 1e-12 {
                break;
            }
            let step = (sp + sq - l) / d;
            if !step.is_finite() {
                break;
            }
            rho -= step;
        }
        rho
    }

    /// The thread contact angle at the contact for `profile`: between the
    /// profile normal at A and the in-plane part of the thread's pull on the
    /// cam (û toward p plus û toward q), deg; `None` when the thread runs
    /// straight through A.
    fn contact_angle_deg(&self, profile: &Profile) -> Option<f64> {
        let r = profile.rho(Dual2_64::new(self.beta, 1.0, 0.0));
        let (s, c) = self.beta.sin_cos();
        let a = V2::new(c, s) * r.re;
        let t = V2::new(c, s) * r.v1 + V2::new(-s, c) * r.re;
        let n = V2::new(t.y, -t.x);
        let unit = |g: V2<f64>, h: f64| {
            let d = V3::new(g.x - a.x, g.y - a.y, h);
            let len = d.norm();
            if len > 0.0 { d / len } else { V3::zeros() }
        };
        let pull = unit(self.pl, self.hp) + unit(self.ql, self.hq);
        let pull = V2::new(pull.x, pull.y);
        let (np, nn) = (pull.norm(), n.norm());
        if np < 1e-9 || nn <= 0.0 {
            return None;
        }
        Some((n.dot(&pull).abs() / (np * nn)).clamp(0.0, 1.0).acos().to_degrees())
    }
}

/// An angle reduced to [0, 360) degrees (`rem_euclid` may round up to 360).
pub(crate) fn turn_deg(x: f64) -> f64 {
    let w = x.rem_euclid(360.0);
    if w >= 360.0 { 0.0 } else { w }
}

/// P of path `pi` at every φ of `pose` with the mechanism's current cams.
pub(crate) fn take_up(
    mech: &Mechanism<f64>,
    threads: &Threads<f64>,
    pose: &Pose<f64>,
    phis: &[f64],
    pi: usize,
) -> Result<Vec<f64>, Error> {
    let tracks = threads.evaluate(pose, None).map_err(|e| {
        let phi = phis[e.k];
        eval::path_error(e, phi)
    })?;
    let xi0 = eval::tracks_at_phi0(mech, threads)?[pi].xi_at_split(0);
    Ok((0..tracks[pi].xi.len())
        .map(|k| threads.convention.take_up(tracks[pi].xi_at_split(k), xi0))
        .collect())
}

/// The take-up of path `path` over `phis` (deg) with the profile of cam
/// `cam` replaced by `profile`: the forward model the synthesis inverts.
pub fn take_up_with_profile(
    model: &Model,
    params: &Params,
    path: &str,
    cam: &str,
    profile: &Profile,
    phis: &[f64],
) -> Result<Vec<f64>, Error> {
    let Machine {
        mechanism: mech,
        mut threads,
    } = model.machine::<f64>(params)?;
    let threads = threads.as_mut().ok_or_else(|| {
        bad(
            format!("model `{}` has no thread paths", model.name()),
            "add [thread] paths",
        )
    })?;
    let pi = threads
        .paths
        .iter()
        .position(|p| p.name == path)
        .ok_or_else(|| bad(format!("unknown thread path `{path}`"), "see `stitchkin check`"))?;
    let ci = threads
        .cams
        .iter()
        .position(|c| c.name == cam)
        .ok_or_else(|| bad(format!("unknown cam `{cam}`"), "see the model's [[cams]]"))?;
    threads.cams[ci].profile = profile.clone();
    let mut pose = mech.new_pose(phis.len());
    mech.solve(&Phi::table(phis), &mut pose)?;
    take_up(&mech, threads, &pose, phis, pi)
}

/// The cam piece of the path being synthesised: the guides before and after
/// the cam (slots), the cam, and its contact angle γ, rad.
struct CamPiece {
    a: usize,
    b: usize,
    ci: usize,
    gamma: f64,
}

/// The stitch thread compared with the path: its name, P' over the grid
/// (mm), the compared mask and the tolerance of the match, mm.
pub(crate) struct StitchThread {
    pub(crate) name: String,
    pub(crate) pprime: Vec<f64>,
    pub(crate) compared: Vec<bool>,
    pub(crate) tolerance_mm: f64,
}

/// Synthesises the profile of the cam on `opts.path` (module docs).
pub fn synthesise(model: &Model, params: &Params, opts: &CamOptions) -> Result<CamSynthesis, Error> {
    // --- the inputs ---------------------------------------------------------
    check_options(opts)?;
    let name = &model.name();
    let Machine {
        mechanism: mech,
        threads,
    } = model.machine::<f64>(params)?;
    let threads = threads.as_ref().ok_or_else(|| {
        bad(
            format!("model `{name}` has no thread paths, so there is no cam to synthesise"),
            "add [thread] paths with a cam node (docs/model-format.md §13.5)",
        )
    })?;
    let pi = threads.paths.iter().position(|p| p.name == opts.path).ok_or_else(|| {
        let all: Vec<&str> = threads.paths.iter().map(|p| p.name.as_str()).collect();
        bad(
            format!("model `{name}` has no thread path `{}`", opts.path),
            &format!("its paths are: {}", all.join(", ")),
        )
    })?;
    let piece = cam_piece(threads, pi, opts)?;
    let (ci, cam) = (piece.ci, &threads.cams[piece.ci]);
    // --- the grid: knots at even j, midpoints at odd j, from φ0 -------------
    let n = opts.points;
    let phi0 = threads.phi0_deg;
    let phis: Vec<f64> = (0..2 * n).map(|j| phi0 + j as f64 * 180.0 / n as f64).collect();
    let mut pose = mech.new_pose(phis.len());
    mech.solve(&Phi::table(&phis), &mut pose)?;
    let rays = contact_rays(&pose, &phis, &piece, cam)?;
    check_single_sweep(&rays, &phis, &cam.name)?;
    // --- ξ_rest and the anchor ------------------------------------------------
    let tracks = threads.evaluate(&pose, None).map_err(|e| {
        let phi = phis[e.k];
        eval::path_error(e, phi)
    })?;
    let xi_ref: Vec<f64> = (0..tracks[pi].xi.len()).map(|k| tracks[pi].xi_at_split(k)).collect();
    let l_ref: Vec<f64> = rays.iter().map(|r| r.length(cam.profile.rho(r.beta))).collect();
    let xi_rest: Vec<f64> = xi_ref.iter().zip(&l_ref).map(|(x, l)| x - l).collect();
    let xi0_ref = eval::tracks_at_phi0(&mech, threads)?[pi].xi_at_split(0);
    let anchor_rho = opts.anchor_radius_mm.unwrap_or_else(|| cam.profile.rho(rays[0].beta));
    // ξ(φ0): the model's, or with the anchor radius at φ0's contact (j = 0 is φ0).
    let xi0 = match opts.anchor_radius_mm {
        None => xi0_ref,
        Some(r) => xi_rest[0] + rays[0].length(r),
    };
    let p_conv0 = threads.convention.take_up(xi0, xi0);
    // --- the target -------------------------------------------------------------
    let (label, raw, stitch_thread) = target_on_grid(model, params, opts, &phis)?;
    // Take-up is p_conv0 at φ0 by definition: shift the target to it.
    let shift = raw[0] - p_conv0;
    let target: Vec<f64> = raw.iter().map(|v| v - shift).collect();
    let mut notes = Vec::new();
    if shift.abs() > 1e-9 {
        notes.push(shift_note(raw[0], phi0, p_conv0));
    }
    // ξ the target asks for: release ξ = ξ0 − P, feed ξ = ξ0 + P − ΔP.
    let xi_of = |p: f64| match threads.convention {
        Convention::Release => xi0 - p,
        Convention::Feed { elongation_mm } => xi0 + p - elongation_mm,
    };
    // --- radius by radius --------------------------------------------------------
    let l_t: Vec<f64> = (0..n).map(|k| xi_of(target[2 * k]) - xi_rest[2 * k]).collect();
    let mut knots = solve_radii(&rays, &l_t, &phis, anchor_rho, cam)?;
    // --- smoothing: a periodic moving average over `smooth_deg`, twice -------
    if opts.smooth_deg > 0.0 {
        smooth(&mut knots, opts.smooth_deg);
    }
    let theta: Vec<f64> = knots.iter().map(|k| k.theta_deg.to_radians()).collect();
    let rho: Vec<f64> = knots.iter().map(|k| k.radius_mm).collect();
    let profile = Profile::spline(&theta, &rho);
    check_profile(&profile)?;
    // --- verify: the model again with the new profile --------------------------
    let p_after = take_up_with(&mech, threads, ci, &profile, &pose, &phis, pi)?;
    let p_before: Vec<f64> = xi_ref.iter().map(|x| threads.convention.take_up(*x, xi0_ref)).collect();
    let verify = verification(phis, target, p_before, p_after, stitch_thread.as_ref());
    // --- checks -------------------------------------------------------------
    let checks = check(&profile, &rays, &verify.phi_deg, opts);
    let shared_with = paths_sharing(threads, ci, &opts.path);
    if !shared_with.is_empty() {
        notes.push(format!(
            "cam `{}` also feeds path(s) {}: their take-up changes with the new profile too",
            cam.name,
            shared_with.join(", ")
        ));
    }
    let declared = model.cam_declaration(&cam.name);
    Ok(CamSynthesis {
        path: opts.path.clone(),
        cam: cam.name.clone(),
        center: declared
            .as_ref()
            .map_or_else(|| model.point_names[cam.center].clone(), |c| c.center.clone()),
        marker: declared
            .as_ref()
            .map_or_else(|| model.point_names[cam.marker].clone(), |c| c.marker.clone()),
        axis_toml: declared.as_ref().and_then(|c| c.axis_toml.clone()),
        frame: declared.and_then(|c| c.frame),
        gamma_deg: piece.gamma.to_degrees(),
        target: label,
        thread: stitch_thread.map(|t| t.name),
        phi0_deg: wrap_deg(phi0),
        knots,
        smooth_deg: opts.smooth_deg,
        target_shift_mm: -shift,
        anchor_radius_mm: anchor_rho,
        anchor_theta_deg: wrap_deg(rays[0].beta.to_degrees()),
        reference_radius_mm: radius_range(&cam.profile),
        radius_mm: radius_range(&profile),
        checks,
        verify,
        shared_with,
        notes,
        profile,
    })
}

/// P of path `pi` at every φ of `pose` with cam `ci`'s profile replaced.
fn take_up_with(
    mech: &Mechanism<f64>,
    threads: &Threads<f64>,
    ci: usize,
    profile: &Profile,
    pose: &Pose<f64>,
    phis: &[f64],
    pi: usize,
) -> Result<Vec<f64>, Error> {
    let mut threads = threads.clone();
    threads.cams[ci].profile = profile.clone();
    take_up(mech, &threads, pose, phis, pi)
}

/// The note on a target shifted to the convention's take-up at φ0.
pub(crate) fn shift_note(raw0: f64, phi0: f64, p_conv0: f64) -> String {
    format!(
        "the target is {} mm at φ0 = {}°, where every take-up is {} mm by definition: it is matched up to that constant (shifted by {} mm)",
        fmt_num(raw0),
        fmt_num(wrap_deg(phi0)),
        fmt_num(p_conv0),
        fmt_num(-(raw0 - p_conv0))
    )
}

/// The options in range, each refused naming the input that sets it.
pub(crate) fn check_options(opts: &CamOptions) -> Result<(), Error> {
    if !(8..=1440).contains(&opts.points) {
        return Err(bad_input(
            Input::ProfilePoints,
            format!("{} profile points is out of range", opts.points),
            "give between 8 and 1440, e.g. 360 (one per degree)",
        ));
    }
    if !(opts.smooth_deg.is_finite() && (0.0..=180.0).contains(&opts.smooth_deg)) {
        return Err(bad_input(
            Input::Smooth,
            format!("smoothing over {} deg is out of range", opts.smooth_deg),
            "give between 0 (none) and 180 degrees",
        ));
    }
    if !(opts.min_radius_mm.is_finite() && opts.min_radius_mm >= 0.0) {
        return Err(bad_input(
            Input::MinRadius,
            format!("the minimum radius {} mm is out of range", opts.min_radius_mm),
            "give a non-negative number of mm, e.g. 3",
        ));
    }
    if !(opts.max_pressure_angle_deg.is_finite()
        && opts.max_pressure_angle_deg > 0.0
        && opts.max_pressure_angle_deg < 90.0)
    {
        return Err(bad_input(
            Input::MaxPressureAngle,
            format!(
                "the contact-angle limit {} deg is out of range",
                opts.max_pressure_angle_deg
            ),
            "give between 0 and 90 degrees, e.g. 45",
        ));
    }
    if let Some(r) = opts.anchor_radius_mm
        && !(r.is_finite() && r > 0.0)
    {
        return Err(bad_input(
            Input::AnchorRadius,
            format!("the anchor radius {r} mm must be a positive number of mm"),
            "e.g. 12",
        ));
    }
    Ok(())
}

/// The cam piece of path `pi` to synthesise: its only one, or the one
/// `opts.cam` names; an offset contact.
fn cam_piece(threads: &Threads<f64>, pi: usize, opts: &CamOptions) -> Result<CamPiece, Error> {
    let cams: Vec<(usize, usize, usize, CamModel)> = threads.paths[pi]
        .spans
        .iter()
        .filter_map(|&s| match &threads.spans[s] {
            Span::Cam { a, b, cam, contact } => Some((*a, *b, *cam, *contact)),
            _ => None,
        })
        .collect();
    let cam_names = |v: &[(usize, usize, usize, CamModel)]| {
        v.iter()
            .map(|c| threads.cams[c.2].name.clone())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (a, b, ci, contact) = match (&opts.cam, cams.len()) {
        (_, 0) => {
            let with: Vec<&str> = threads
                .paths
                .iter()
                .filter(|p| p.spans.iter().any(|&s| matches!(threads.spans[s], Span::Cam { .. })))
                .map(|p| p.name.as_str())
                .collect();
            return Err(bad(
                format!(
                    "thread path `{}` runs over no cam, so there is no profile to synthesise",
                    opts.path
                ),
                &if with.is_empty() {
                    "give the path a cam node `{ cam = \"NAME\", contact = \"offset\", gamma_deg = 23 }` and a [[cams]] entry (docs/model-format.md §13.5)".to_string()
                } else {
                    format!("paths over a cam: {}", with.join(", "))
                },
            ));
        }
        (Some(c), _) => *cams.iter().find(|x| threads.cams[x.2].name == *c).ok_or_else(|| {
            bad(
                format!("thread path `{}` does not run over cam `{c}`", opts.path),
                &format!("its cams: {}", cam_names(&cams)),
            )
        })?,
        (None, 1) => cams[0],
        (None, _) => {
            return Err(bad_input(
                Input::Cam,
                format!(
                    "thread path `{}` runs over several cams ({})",
                    opts.path,
                    cam_names(&cams)
                ),
                "name the cam to synthesise",
            ));
        }
    };
    match contact {
        CamModel::Offset { gamma_rad } => Ok(CamPiece {
            a,
            b,
            ci,
            gamma: gamma_rad,
        }),
        CamModel::Exact { .. } => Err(bad(
            format!(
                "cam `{}` on path `{}` has contact = \"exact\": cam synthesis supports contact = \"offset\" only. Under the exact \
                 (taut-thread) contact the length depends on the whole wrapped arc of the profile, through its tangent points and \
                 the arc integral, not on one radius, so there is no radius-by-radius inverse",
                threads.cams[ci].name, opts.path
            ),
            "synthesise with the seed-004 model on this node, `contact = \"offset\", gamma_deg = 23` (0.4-0.8 rad), then check the profile",
        )),
    }
}

/// The contact ray at every φ of the grid.
fn contact_rays(pose: &Pose<f64>, phis: &[f64], piece: &CamPiece, cam: &Cam<f64>) -> Result<Vec<Ray>, Error> {
    let mut rays = Vec::with_capacity(phis.len());
    for (j, &phi) in phis.iter().enumerate() {
        let pt = |s: usize| pose.point(s, j);
        let r = Ray::new(pt(piece.a), pt(piece.b), pt(cam.center), pt(cam.marker), cam.axis, piece.gamma).ok_or_else(|| {
            bad(
                format!(
                    "at φ = {:.3}° the contact on cam `{}` is not defined: a guide on the shaft axis, the marker on the axis, or the two guides facing each other through the shaft",
                    wrap_deg(phi),
                    cam.name
                ),
                "check the cam's guides and marker",
            )
        })?;
        rays.push(r);
    }
    Ok(rays)
}

/// How a sequence of angles over one cycle fails to turn once, one way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum UnsteadyTurn {
    /// It stops or turns back between sample `j` and the next.
    Stops(usize),
    /// It turns this many times (not one) over the cycle.
    Turns(f64),
}

/// Whether `angles` (rad, one per φ of a cycle, the last followed by the
/// first) turn exactly once per cycle, one way: every step taken the short
/// way round has the same sign and the steps add up to ±2π.
pub(crate) fn steady_turn(angles: &[f64]) -> Result<(), UnsteadyTurn> {
    let pi = std::f64::consts::PI;
    let mut turn = 0.0;
    let mut sign = 0.0;
    for j in 0..angles.len() {
        let d = (angles[(j + 1) % angles.len()] - angles[j] + pi).rem_euclid(TAU) - pi;
        if d == 0.0 || (sign != 0.0 && d.signum() != sign) {
            return Err(UnsteadyTurn::Stops(j));
        }
        sign = d.signum();
        turn += d;
    }
    if (turn.abs() - TAU).abs() > 1e-6 {
        return Err(UnsteadyTurn::Turns(turn.abs() / TAU));
    }
    Ok(())
}

/// The contact must sweep the profile exactly once per cycle, one way.
fn check_single_sweep(rays: &[Ray], phis: &[f64], cam: &str) -> Result<(), Error> {
    let betas: Vec<f64> = rays.iter().map(|r| r.beta).collect();
    match steady_turn(&betas) {
        Ok(()) => Ok(()),
        Err(UnsteadyTurn::Stops(j)) => Err(bad(
            format!(
                "the contact on cam `{cam}` does not turn steadily over the profile (it stops or turns back near φ = {:.1}°), so one \
                 profile angle would have to serve two take-ups",
                wrap_deg(phis[j])
            ),
            "cam synthesis needs a cam turning once per cycle relative to its guides (a cam on the main shaft)",
        )),
        Err(UnsteadyTurn::Turns(turns)) => Err(bad(
            format!(
                "the contact sweeps cam `{cam}` {turns:.3} turns per cycle; a profile can be synthesised only for exactly one"
            ),
            "cam synthesis needs a cam turning once per main-shaft cycle relative to its guides",
        )),
    }
}

/// The target over the grid, unshifted, with what it is in words, and the
/// stitch thread compared with the path (for the match report).
pub(crate) fn target_on_grid(
    model: &Model,
    params: &Params,
    opts: &CamOptions,
    phis: &[f64],
) -> Result<(String, Vec<f64>, Option<StitchThread>), Error> {
    // The stitch process: needed for `required`; for a curve only for the
    // match report, so a stitch that does not evaluate just leaves it out.
    let required = matches!(opts.target, Target::Required);
    // The target cannot depend on the tension of the path the cam
    // replaces: a computed regulator window is assumed here.
    let prepared = match eval::stitch_process::prepare_assumed(model, params, phis.to_vec()) {
        Ok(p) => p,
        Err(e) if required => return Err(e),
        Err(_) => None,
    };
    let setup = prepared.as_ref().map(|p| &p.setup);
    // P' of the thread on this path over the grid, and the compared mask.
    let stitch_thread = prepared.as_ref().and_then(|s| {
        let t = s
            .setup
            .paths
            .iter()
            .position(|p| p.as_deref() == Some(opts.path.as_str()))?;
        let th = &s.required.threads[t];
        Some(StitchThread {
            name: th.name.clone(),
            pprime: eval::stitch_process::pprime_at_split(th, phis.len()),
            compared: s.compared[t].clone(),
            tolerance_mm: s.setup.tolerance_mm,
        })
    });
    let (label, raw) = match &opts.target {
        Target::Required => match &stitch_thread {
            Some(t) => (
                format!(
                    "required take-up P' of thread `{}`{}",
                    t.name,
                    if model.has_thread_physics() {
                        " (its stitch drawn through the regulator in the last 60° before it is pulled tight, \
                         assumed: the computed window depends on the path this cam replaces)"
                    } else {
                        ""
                    }
                ),
                t.pprime.clone(),
            ),
            None if setup.is_none() => {
                return Err(bad_input(
                    Input::Target,
                    format!(
                        "model `{}` has no [stitch], so there is no required take-up P' to match",
                        model.name()
                    ),
                    "give the target as a curve instead: a CSV file with columns phi_deg,P_mm",
                ));
            }
            None => {
                let listed: Vec<String> = setup.iter().flat_map(|s| s.paths.iter().flatten().cloned()).collect();
                return Err(bad_input(
                    Input::Target,
                    format!(
                        "no thread of [stitch] is compared with path `{}`, so it has no required take-up P'",
                        opts.path
                    ),
                    &format!(
                        "paths with a P': {}; or give the target as a CSV file",
                        if listed.is_empty() {
                            "none".into()
                        } else {
                            listed.join(", ")
                        }
                    ),
                ));
            }
        },
        Target::Curve { source, phi_deg, p_mm } => curve_on_grid(source, phi_deg, p_mm, phis)?,
    };
    Ok((label, raw, stitch_thread))
}

/// A target curve through its points, on the grid: the periodic spline.
fn curve_on_grid(source: &str, phi_deg: &[f64], p_mm: &[f64], phis: &[f64]) -> Result<(String, Vec<f64>), Error> {
    let ok = phi_deg.len() >= 4
        && phi_deg.len() == p_mm.len()
        && phi_deg.iter().chain(p_mm).all(|v| v.is_finite())
        && phi_deg.windows(2).all(|w| w[1] > w[0])
        && phi_deg[phi_deg.len() - 1] - phi_deg[0] < 360.0;
    if !ok {
        return Err(bad(
            format!("the target curve from {source} is not at least 4 finite points with φ increasing within one turn"),
            "read it with thread::measured::read_curve and make the target with Target::from_curve",
        ));
    }
    // The periodic cubic spline (C², as a polar profile) through the points.
    let sp = PeriodicCubic::new(phi_deg, p_mm, 360.0);
    Ok((
        format!("curve from {source} ({} points)", phi_deg.len()),
        phis.iter().map(|&p| sp.eval(p)).collect(),
    ))
}

/// One knot per contact ray at the knots' φ (even grid points), the radius
/// that makes the cam's piece `l_t[k]` long, sorted by profile angle. An
/// error when some are out of reach (naming the worst and the anchor
/// radius that reaches them all) or two fall on one angle.
fn solve_radii(rays: &[Ray], l_t: &[f64], phis: &[f64], anchor_rho: f64, cam: &Cam<f64>) -> Result<Vec<Knot>, Error> {
    let n = l_t.len();
    let mut knots = Vec::with_capacity(n);
    // Positions out of reach: (k, the shortest L along the radius).
    let mut short: Vec<(usize, f64)> = Vec::new();
    for (k, &l) in l_t.iter().enumerate() {
        let r = &rays[2 * k];
        let near = if k == 0 { anchor_rho } else { cam.profile.rho(r.beta) };
        match r.solve(l, near) {
            Some(rho) => knots.push(Knot {
                theta_deg: turn_deg(r.beta.to_degrees()),
                radius_mm: rho,
                solved_mm: rho,
                phi_deg: wrap_deg(phis[2 * k]),
            }),
            None => short.push((k, r.min_length())),
        }
    }
    if let Some(&(k, lmin)) = short
        .iter()
        .max_by(|a, b| (a.1 - l_t[a.0]).total_cmp(&(b.1 - l_t[b.0])))
    {
        // Every L grows with ξ(φ0) one for one: the worst shortfall (plus
        // 0.01 mm) is what φ0's contour must gain, and the anchor radius
        // that gives it lies on the rising side of L along φ0's radius.
        let need = lmin - l_t[k];
        let hint = match rays[0].solve(l_t[0] + need.max(0.0) + 0.01, 1e9) {
            Some(r) if r.is_finite() => format!(
                "the target gives out more thread there than this cam can release. ξ(φ0) sets the level: an anchor radius of {:.2} mm \
                 (or larger) reaches every position; or set the guides further apart, or give the target less swing",
                (r * 100.0).ceil() / 100.0
            ),
            _ => "the target gives out more thread there than this cam can release: set the guides further apart, or give the target less swing".to_string(),
        };
        return Err(bad(
            format!(
                "the target cannot be reached at {} of {n} positions; the worst is φ = {:.3}°, where the thread over cam `{}` would \
                 have to be {:.4} mm long, but along the contact radius (θ = {:.2}°) it is never shorter than {:.4} mm ({:.4} mm short)",
                short.len(),
                wrap_deg(phis[2 * k]),
                cam.name,
                l_t[k],
                wrap_deg(rays[2 * k].beta.to_degrees()),
                lmin,
                need
            ),
            &hint,
        ));
    }
    knots.sort_by(|x, y| x.theta_deg.total_cmp(&y.theta_deg));
    // Distinct within the turn, the last one short of the first a turn later.
    for k in 0..n {
        let (a, b) = (
            knots[k].theta_deg,
            if k + 1 < n {
                knots[k + 1].theta_deg
            } else {
                knots[0].theta_deg + 360.0
            },
        );
        if b - a < 1e-9 {
            return Err(bad_input(
                Input::ProfilePoints,
                format!("two knots fall on profile angle {:.6}°", a),
                "use fewer profile points",
            ));
        }
    }
    Ok(knots)
}

/// The take-up before and after against the target over the grid: the
/// largest errors at the knots and between them, and the match with the
/// stitch thread's P'.
pub(crate) fn verification(
    phis: Vec<f64>,
    target: Vec<f64>,
    p_before: Vec<f64>,
    p_after: Vec<f64>,
    stitch_thread: Option<&StitchThread>,
) -> Verification {
    let n2 = phis.len();
    let worst = |js: &mut dyn Iterator<Item = usize>, p: &[f64]| {
        js.map(|j| ((p[j] - target[j]).abs(), wrap_deg(phis[j])))
            .fold((0.0f64, phis[0]), |m, x| if x.0 > m.0 { x } else { m })
    };
    let (ek, ek_at) = worst(&mut (0..n2).step_by(2), &p_after);
    let (eb, eb_at) = worst(&mut (1..n2).step_by(2), &p_after);
    let (e0, _) = worst(&mut (0..n2), &p_before);
    let (match_before, match_after, match_after_all) = match stitch_thread {
        Some(t) => {
            let (pp, compared, tol) = (&t.pprime, &t.compared, t.tolerance_mm);
            let even = |v: &[f64]| v.iter().step_by(2).copied().collect::<Vec<f64>>();
            let ce: Vec<bool> = compared.iter().step_by(2).copied().collect();
            let (ph, ppe) = (even(&phis), even(pp));
            (
                mismatch(&ph, &even(&p_before), &ppe, &ce, tol, false),
                mismatch(&ph, &even(&p_after), &ppe, &ce, tol, false),
                mismatch(&phis, &p_after, pp, compared, tol, false),
            )
        }
        None => (None, None, None),
    };
    Verification {
        phi_deg: phis,
        target_mm: target,
        p_before_mm: p_before,
        p_after_mm: p_after,
        max_err_knots_mm: ek,
        max_err_knots_at_deg: ek_at,
        max_err_between_mm: eb,
        max_err_between_at_deg: eb_at,
        max_err_before_mm: e0,
        match_before,
        match_after,
        match_after_all,
    }
}

/// A profile a cam can be cut to: finite everywhere, and a polar radius
/// above zero (zero or less puts it through the cam's own axis).
fn check_profile(profile: &Profile) -> Result<(), Error> {
    if !(0..720).all(|i| profile.rho(i as f64 * TAU / 720.0).is_finite()) {
        return Err(Error::NotFinite(NotFiniteError {
            quantity: "the synthesised cam profile".into(),
            phi_deg: None,
            cause: "the target or the follower's geometry gives no finite radius somewhere; smooth the target or move the anchor".into(),
        }));
    }
    let [rho_min, _] = radius_range(profile);
    if rho_min <= 0.0 {
        let at = (0..3600)
            .map(|i| i as f64 / 10.0)
            .min_by(|a, b| profile.rho(a.to_radians()).total_cmp(&profile.rho(b.to_radians())))
            .unwrap_or(0.0);
        return Err(bad(
            format!(
                "the synthesised profile reaches a radius of {rho_min:.3} mm at θ = {at:.1}°: it would pass through the \
                 cam's axis, so no cam can be cut to it"
            ),
            "raise the anchor radius (the follower's radius at φ0) so the whole profile lies further out, smooth the \
             target, or set the guides further apart",
        ));
    }
    Ok(())
}

/// A profile's smallest and largest radius (3600 samples a turn), mm.
fn radius_range(p: &Profile) -> [f64; 2] {
    (0..3600)
        .map(|i| p.rho(i as f64 * TAU / 3600.0))
        .fold([f64::MAX, f64::MIN], |m, r| [m[0].min(r), m[1].max(r)])
}

/// The other paths over cam `ci`: their take-up changes too.
fn paths_sharing(threads: &Threads<f64>, ci: usize, path: &str) -> Vec<String> {
    threads
        .paths
        .iter()
        .filter(|p| {
            p.name != path
                && p.spans
                    .iter()
                    .any(|&s| matches!(threads.spans[s], Span::Cam { cam, .. } if cam == ci))
        })
        .map(|p| p.name.clone())
        .collect()
}

/// Periodic moving average of the knot radii over `width_deg` of profile
/// angle, applied twice: triangular weights reaching ±`width_deg`, each knot
/// weighted by the angle it stands for (the knots may be spaced unevenly).
pub(crate) fn smooth(knots: &mut [Knot], width_deg: f64) {
    let n = knots.len();
    let th: Vec<f64> = knots.iter().map(|k| k.theta_deg).collect();
    let gap = |i: usize, j: usize| (th[j] - th[i]).rem_euclid(360.0);
    let span: Vec<f64> = (0..n)
        .map(|i| 0.5 * (gap((i + n - 1) % n, i) + gap(i, (i + 1) % n)))
        .collect();
    let rho: Vec<f64> = knots.iter().map(|k| k.radius_mm).collect();
    for (i, k) in knots.iter_mut().enumerate() {
        let (mut sw, mut s) = (0.0, 0.0);
        for j in 0..n {
            let d = ((th[j] - th[i] + 180.0).rem_euclid(360.0) - 180.0).abs();
            let w = (1.0 - d / width_deg).max(0.0) * span[j];
            sw += w;
            s += w * rho[j];
        }
        if sw > 0.0 {
            k.radius_mm = s / sw;
        }
    }
}

/// Minimum radius, convexity, slope and thread contact angle of `profile`.
fn check(profile: &Profile, rays: &[Ray], phis: &[f64], opts: &CamOptions) -> Checks {
    let m = 3600;
    let mut min_r = (f64::MAX, 0.0);
    let mut slope = (0.0f64, 0.0);
    let mut conv_min = f64::MAX;
    let mut flags = Vec::with_capacity(m);
    let ths: Vec<f64> = (0..m).map(|i| i as f64 * 360.0 / m as f64).collect();
    for &t in &ths {
        let r = profile.rho(Dual2_64::new(t.to_radians(), 1.0, 0.0));
        if r.re < min_r.0 {
            min_r = (r.re, t);
        }
        let s = r.v1.abs().atan2(r.re.abs()).to_degrees();
        if s > slope.0 {
            slope = (s, t);
        }
        // The curvature numerator of a polar curve (cam.rs `convexity`).
        let c = r.re * r.re + 2.0 * r.v1 * r.v1 - r.re * r.v2;
        conv_min = conv_min.min(c);
        flags.push(c <= 0.0);
    }
    let not_convex: Vec<[f64; 2]> = crate::thread::intervals(&flags, &ths)
        .iter()
        .map(|i| [i.from_deg, i.to_deg.min(i.from_deg + 360.0)])
        .collect();
    let mut contact = (0.0f64, 0.0);
    for (r, &phi) in rays.iter().zip(phis) {
        if let Some(a) = r.contact_angle_deg(profile)
            && a > contact.0
        {
            contact = (a, wrap_deg(phi));
        }
    }
    Checks {
        min_radius_mm: min_r.0,
        min_radius_at_theta_deg: min_r.1,
        min_radius_limit_mm: opts.min_radius_mm,
        min_radius_ok: min_r.0 >= opts.min_radius_mm,
        convex: conv_min > 0.0,
        convexity_min_mm2: conv_min,
        not_convex_deg: not_convex,
        max_slope_deg: slope.0,
        max_slope_at_theta_deg: slope.1,
        max_contact_angle_deg: contact.0,
        max_contact_angle_at_phi_deg: contact.1,
        contact_angle_limit_deg: opts.max_pressure_angle_deg,
        contact_angle_ok: contact.0 <= opts.max_pressure_angle_deg,
    }
}

impl CamSynthesis {
    /// The profile sampled densely, at least 1440 points a turn from θ = 0:
    /// (x, y) in the cam frame (x toward the marker), mm.
    pub fn outline(&self) -> Vec<(f64, f64)> {
        let m = (4 * self.knots.len()).max(1440);
        (0..m)
            .map(|i| {
                let t = i as f64 * TAU / m as f64;
                let r = self.profile.rho(t);
                (r * t.cos(), r * t.sin())
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thread::cam::offset_contact;

    fn at(angle: f64) -> CamPlacement<f64> {
        CamPlacement {
            center: V3::zeros(),
            u: V3::new(angle.cos(), angle.sin(), 0.0),
            v: V3::new(-angle.sin(), angle.cos(), 0.0),
            w: V3::z(),
        }
    }

    #[test]
    fn a_steady_turn_is_one_turn_one_way() {
        let n = 36;
        let forward: Vec<f64> = (0..n).map(|k| k as f64 * TAU / n as f64).collect();
        assert_eq!(steady_turn(&forward), Ok(()));
        let backward: Vec<f64> = forward.iter().map(|a| -a).collect();
        assert_eq!(steady_turn(&backward), Ok(()));
        // Twice round: every step the same way, but two turns.
        let twice: Vec<f64> = forward.iter().map(|a| 2.0 * a).collect();
        assert!(matches!(steady_turn(&twice), Err(UnsteadyTurn::Turns(t)) if (t - 2.0).abs() < 1e-9));
        // A swing back and forth stops where it turns back.
        let swing: Vec<f64> = (0..n).map(|k| (k as f64 * TAU / n as f64).sin()).collect();
        assert!(matches!(steady_turn(&swing), Err(UnsteadyTurn::Stops(_))));
    }

    #[test]
    fn the_ray_length_is_the_offset_contact() {
        let prof = Profile::disc(10.0, 3.0);
        let (p, q) = (V3::new(-20.0, 30.0, 2.0), V3::new(25.0, 28.0, -3.0));
        for (ang, gamma) in [(0.0, 0.5), (1.3, -0.2), (4.0, 0.8)] {
            let pl = at(ang);
            let marker = pl.u * 5.0;
            let r = Ray::new(p, q, V3::zeros(), marker, V3::z(), gamma).unwrap();
            let want = offset_contact(&prof, &pl, p, q, gamma).unwrap().length;
            assert!((r.length(prof.rho(r.beta)) - want).abs() < 1e-12);
        }
    }

    #[test]
    fn the_quadratic_inverts_the_length() {
        // Unsymmetric guides: solve L(ρ) = L(ρ0) for ρ0 and get ρ0 back.
        let (p, q) = (V3::new(-20.0, 30.0, 2.0), V3::new(25.0, 28.0, -3.0));
        let r = Ray::new(p, q, V3::zeros(), V3::new(1.0, 0.0, 0.0), V3::z(), 0.4).unwrap();
        for rho0 in [2.0, 7.5, 15.0, 26.0] {
            let got = r.solve(r.length(rho0), rho0).unwrap();
            assert!((got - rho0).abs() < 1e-10, "{got} vs {rho0}");
        }
        // Symmetric guides: seed 004 §2.5's ξ = 2|O2 − A| and its closed-form root.
        let (p, q) = (V3::new(-18.0, 6.0, 0.0), V3::new(18.0, 6.0, 0.0));
        let r = Ray::new(p, q, V3::zeros(), V3::new(1.0, 0.0, 0.0), V3::z(), 0.0).unwrap();
        let l = 40.0;
        let (a, c) = (r.ap, r.cp);
        let want = a + (a * a - c + l * l / 4.0).sqrt();
        assert!((r.solve(l, 10.0).unwrap() - want).abs() < 1e-12);
        // Shorter than the thread can be along that radius: no root.
        assert!(r.solve(r.min_length() - 0.1, 10.0).is_none());
        assert!(
            r.solve(35.0, 10.0).is_none(),
            "shorter than the straight line between the guides"
        );
    }

    fn spline(t: &Target) -> PeriodicCubic {
        let Target::Curve { phi_deg, p_mm, .. } = t else {
            panic!("a curve")
        };
        PeriodicCubic::new(phi_deg, p_mm, 360.0)
    }

    /// The target of a curve file's text.
    fn target_csv(text: &str) -> Result<Target, Error> {
        Target::from_curve(&crate::thread::measured::parse_curve_csv(text, "t.csv")?)
    }

    #[test]
    fn csv_targets_are_periodic_splines_and_checked() {
        // Four points a quarter turn apart (given directly: a curve file
        // needs a row at least every 45°).
        let t = Target::Curve {
            phi_deg: vec![0.0, 90.0, 180.0, 270.0],
            p_mm: vec![0.0, 1.0, 2.0, 1.0],
            source: "t".into(),
        };
        let s = spline(&t);
        for (x, y) in [
            (0.0, 0.0),
            (90.0, 1.0),
            (180.0, 2.0),
            (270.0 + 360.0, 1.0),
            (-90.0, 1.0),
        ] {
            assert!((s.eval::<f64>(x) - y).abs() < 1e-12, "{x}");
        }
        // Symmetric about 180°, periodic.
        assert!(
            (s.eval::<f64>(45.0) - s.eval::<f64>(315.0)).abs() < 1e-12
                && (s.eval::<f64>(45.0) - s.eval::<f64>(405.0)).abs() < 1e-12
        );
        // Off-grid, the columns swapped, a column named as `stitchkin run`
        // writes it: a sinusoid through 10 points comes back to 1e-2
        // between them.
        let sine = |x: f64| 2.0 * x.to_radians().sin();
        let file = |from: f64| {
            let mut text = String::from("# comment\nlower.P_mm,phi_deg\n");
            for k in 0..10 {
                let x = from + 36.0 * k as f64;
                text += &format!("{},{x}\n", sine(x));
            }
            text
        };
        let s = spline(&target_csv(&file(5.0)).unwrap());
        for x in [0.0, 17.0, 100.0, 359.0] {
            assert!((s.eval::<f64>(x) - sine(x)).abs() < 1e-2, "{x}: {}", s.eval::<f64>(x));
        }
        // The same points written from 185° on (a turn may start anywhere,
        // as `stitchkin run` writes a cycle from φ0): the same spline.
        let late = spline(&target_csv(&file(185.0)).unwrap());
        for x in [0.0, 17.0, 100.0, 359.0] {
            assert!((late.eval::<f64>(x) - s.eval::<f64>(x)).abs() < 1e-12, "{x}");
        }
        for bad in [
            "",
            "phi,P_mm\n0,1\n",
            "phi_deg,P_mm\n0,1\n90,x\n",
            "phi_deg,P_mm\n0,1\n360,2\n90,1\n180,1\n",
            "phi_deg,P_mm\n0,1\n90,2\n",
            // Rows out of φ order.
            "phi_deg,P_mm\n0,0\n80,1\n40,1\n120,1\n160,1\n200,1\n240,1\n280,1\n320,1\n",
        ] {
            assert!(target_csv(bad).is_err(), "{bad:?}");
        }
        // A curve at B is not the path's take-up.
        let e = target_csv(&file(5.0).replace("lower.P_mm", "n1.Pprime_B_mm")).unwrap_err();
        assert!(
            e.to_string().contains("`n1.Pprime_B_mm` from t.csv is taken at B")
                && e.help().unwrap().contains("P_eye = P_B − (S(φ) − S(φ0))"),
            "{e}"
        );
        assert!(target_csv(&file(5.0).replace("lower.P_mm", "n1.Pprime_eye_mm")).is_ok());
    }

    #[test]
    fn smoothing_keeps_a_constant_and_flattens_a_spike() {
        let mut k: Vec<Knot> = (0..36)
            .map(|i| Knot {
                theta_deg: i as f64 * 10.0,
                radius_mm: 10.0,
                solved_mm: 10.0,
                phi_deg: 0.0,
            })
            .collect();
        smooth(&mut k, 30.0);
        assert!(k.iter().all(|k| (k.radius_mm - 10.0).abs() < 1e-12));
        k[0].radius_mm = 20.0;
        smooth(&mut k, 30.0);
        assert!(
            k[0].radius_mm < 14.0
                && k[1].radius_mm > 10.0
                && k[35].radius_mm > 10.0
                && (k[18].radius_mm - 10.0).abs() < 1e-12
        );
    }
}
