//! Cam synthesis for a follower: find the lift table of a `cam_follower`
//! group whose follower carries a thread path's point (its `out`, or a point
//! rigid with it) so that the path's take-up P(φ) equals a target (the
//! required P'(φ), or a curve: [`crate::study::cam_synthesis::Target`]).
//!
//! **The inverse, position by position.** At a knot φ_k the path's length
//! ξ depends on the lift s only through the follower (the rest of the
//! mechanism at φ_k stays where it is), and is monotonic in s near the
//! solution. The knots' cam angles δ(φ_k) are distinct (the cam turns once
//! per cycle), so a lift table through (δ_k, s_k) gives exactly s_k at φ_k,
//! whatever the other s: one cycle solved with that table evaluates every
//! ξ_k(s_k) at once, and the knots are solved together, each by its own
//! bracketed root finding (bracket by doubling steps, then the Illinois
//! variant of regula falsi) on ξ_k(s) − ξ_target(φ_k). The level: the
//! take-up fixes ξ only up to ξ(φ0), which is kept as the model's own lift
//! at φ0 gives it.
//!
//! **Lift and base circle.** The solved lift is smoothed (a periodic moving
//! average over the cam angle, applied twice, as the thread cam's profile
//! is), then shifted so its least value is 0; the base circle becomes what
//! puts the follower at zero lift where the least lift put it (translating:
//! √((r_b + r_r)² − e²) grows by the least lift; rocking: the arm at zero
//! lift turns by it), so the follower's positions are the solved ones.
//!
//! **Checks.** The group's own: the largest pressure angle and the working
//! profile's least radius of curvature over the cam's turn, every half
//! degree, as `eval::cams` reads them.

use std::sync::Arc;

use nalgebra::ComplexField;
use num_dual::Dual2_64;
use serde::Serialize;

use crate::error::Error;
use crate::eval::{self, wrap_deg};
use crate::geometry::{V2, perp};
use crate::mechanism::cam_follower::{CamFollower, Contact, Lift, Motion};
use crate::mechanism::{CamStep, Mechanism, Phi, Step};
use crate::model::{Machine, Model, Params};
use crate::numeric::PeriodicCubic;
use crate::stitch::mismatch::{Mismatch, mismatch};
use crate::study::cam_synthesis::{
    CamOptions, Knot, Target, UnsteadyTurn, Verification, bad, shift_note, smooth, steady_turn, take_up,
    target_on_grid, turn_deg, verification,
};
use crate::thread::{Convention, Threads};

const TAU: f64 = std::f64::consts::TAU;

/// Cam angles sampled for the checks and the profile, over one turn.
const PROFILE_SAMPLES: usize = 720;

/// How to synthesise a follower's lift.
#[derive(Debug, Clone, PartialEq)]
pub struct FollowerOptions {
    /// The `cam_follower` group whose lift is sought.
    pub group: String,
    /// The thread path that runs over a point the follower carries.
    pub path: String,
    pub target: Target,
    /// Lift points per turn (8…1440): the cam angles of as many positions φ.
    pub points: usize,
    /// Smoothing: a periodic moving average over this many degrees of cam
    /// angle, applied twice; 0 for none.
    pub smooth_deg: f64,
}

impl FollowerOptions {
    /// Defaults: 360 points, no smoothing.
    pub fn new(group: &str, path: &str, target: Target) -> FollowerOptions {
        FollowerOptions {
            group: group.to_string(),
            path: path.to_string(),
            target,
            points: 360,
            smooth_deg: 0.0,
        }
    }
}

/// The group's checks of the new cam: pressure angle and curvature.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FollowerChecks {
    pub max_pressure_deg: f64,
    pub max_pressure_at_cam_deg: f64,
    pub pressure_limit_deg: f64,
    pub pressure_ok: bool,
    /// The working profile's least radius of curvature, mm (> 0: no cusp,
    /// no undercut), and the cam angle where.
    pub min_curvature_radius_mm: f64,
    pub min_curvature_at_cam_deg: f64,
    pub curvature_ok: bool,
}

/// The least base circle that passes the group's checks with the
/// synthesised lift ([`least_passing_base`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BaseCircleAdvice {
    /// The base circle, mm, rounded up to 0.1 mm.
    pub base_radius_mm: f64,
    /// How far the cam's centre moves back, away from the follower, mm
    /// (along a translating follower's axis; for a rocking one from the
    /// roller's rest point through the centre, or along a flat face's
    /// normal at rest): the follower then keeps its positions, so the
    /// thread's take-up is the same.
    pub move_back_mm: f64,
    /// The same move as a vector in the model's plane, mm.
    pub move_mm: [f64; 2],
    /// The checks with that base circle.
    pub checks: FollowerChecks,
}

/// One point of the cam: its angle, the lift and the pitch and working
/// profiles in the cam's frame (x toward the cam angle 0), mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ProfilePoint {
    pub cam_deg: f64,
    /// mm (translating) or deg (rocking).
    pub lift: f64,
    pub pitch_mm: [f64; 2],
    pub profile_mm: [f64; 2],
}

/// A synthesised follower lift.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FollowerSynthesis {
    pub group: String,
    pub path: String,
    /// `translating` or `rocking`.
    pub motion: &'static str,
    /// The lift's unit: `mm` or `deg`.
    pub lift_unit: &'static str,
    pub target: String,
    pub thread: Option<String>,
    pub phi0_deg: f64,
    /// The lift table: cam angle (deg, increasing within a turn) and lift,
    /// least value 0, smoothed.
    pub lift: Vec<Knot>,
    pub smooth_deg: f64,
    /// The least lift solved (before the shift to 0), in the lift's unit.
    pub least_lift: f64,
    /// The model's base circle and the one the new lift needs, mm; the
    /// roller, mm (0 for a knife edge).
    pub base_radius_model_mm: f64,
    pub base_radius_mm: f64,
    pub roller_mm: f64,
    /// What touches the cam: `knife`, `roller` or `flat`.
    pub contact: &'static str,
    /// The lift's range, in its unit.
    pub lift_range: [f64; 2],
    pub checks: FollowerChecks,
    /// When the checks fail on a translating follower: the least base
    /// circle with which the same lift passes both, the cam's centre moved
    /// back along the follower's axis so every follower position stays.
    pub base_circle_needed: Option<BaseCircleAdvice>,
    pub verify: Verification,
    /// Score and RMS of the take-up against the target on the knots' φ,
    /// when no stitch thread is compared with the path (docs/stitch-formation.md §8,
    /// every φ compared, tolerance 0.5 mm).
    pub match_target: Option<Mismatch>,
    /// The cam over its turn, every half degree.
    pub profile: Vec<ProfilePoint>,
    pub notes: Vec<String>,
}

impl FollowerSynthesis {
    /// The match score that counts: against the stitch thread's P' when
    /// one is compared with the path, else against the target curve.
    pub fn score(&self) -> Option<f64> {
        self.verify
            .match_after
            .as_ref()
            .or(self.match_target.as_ref())
            .and_then(|m| m.score)
    }
}

/// The index of group `name` among the mechanism's steps.
fn cam_step_index(mech: &Mechanism<f64>, model: &Model, name: &str) -> Result<usize, Error> {
    let cams: Vec<(usize, &CamStep<f64>)> = mech
        .steps
        .iter()
        .enumerate()
        .filter_map(|(i, s)| match s {
            Step::CamFollower(c) => Some((i, &**c)),
            _ => None,
        })
        .collect();
    cams.iter()
        .find(|(_, c)| c.name == name)
        .map(|(i, _)| *i)
        .ok_or_else(|| {
            let all: Vec<&str> = cams.iter().map(|(_, c)| c.name.as_str()).collect();
            bad(
                format!("model `{}` has no cam_follower group `{name}`", model.name()),
                &if all.is_empty() {
                    "add a [[groups]] entry of type = \"cam_follower\" (docs/model-format.md §10.10)".to_string()
                } else {
                    format!("its cam_follower groups are: {}", all.join(", "))
                },
            )
        })
}

fn cam_step(mech: &Mechanism<f64>, i: usize) -> &CamStep<f64> {
    match &mech.steps[i] {
        Step::CamFollower(c) => c,
        _ => unreachable!("the index of a cam_follower step"),
    }
}

fn cam_step_mut(mech: &mut Mechanism<f64>, i: usize) -> &mut CamStep<f64> {
    match &mut mech.steps[i] {
        Step::CamFollower(c) => c,
        _ => unreachable!("the index of a cam_follower step"),
    }
}

/// A lift table through (cam angle rad, lift), sorted by angle.
fn table(angles: &[f64], values: &[f64]) -> Lift<f64> {
    Lift::Table(Arc::new(PeriodicCubic::new(angles, values, TAU)))
}

/// ξ of path `pi` at the knots' φ with the lift `s` at the knots' cam angles.
struct Knots<'a> {
    mech: Mechanism<f64>,
    threads: &'a Threads<f64>,
    ci: usize,
    pi: usize,
    phis: Vec<f64>,
    /// Knot order by cam angle, and the angles (rad, in [0, 2π)).
    order: Vec<usize>,
    angles: Vec<f64>,
}

impl Knots<'_> {
    fn xi(&mut self, s: &[f64]) -> Result<Vec<f64>, Error> {
        let vals: Vec<f64> = self.order.iter().map(|&k| s[k]).collect();
        cam_step_mut(&mut self.mech, self.ci).cam.lift = table(&self.angles, &vals);
        let mut pose = self.mech.new_pose(self.phis.len());
        self.mech.solve(&Phi::table(&self.phis), &mut pose)?;
        let phis = &self.phis;
        let tracks = self.threads.evaluate(&pose, None).map_err(|e| {
            let phi = phis[e.k];
            eval::path_error(e, phi)
        })?;
        Ok((0..phis.len()).map(|k| tracks[self.pi].xi_at_split(k)).collect())
    }
}

/// Every ξ_k(s_k) = want_k, starting from `s0`, one knot fixed (k = 0).
/// `h` is the first step (the lift's unit). An error names the worst knot
/// out of reach.
fn solve_lifts(kn: &mut Knots, want: &[f64], s0: &[f64], h: f64) -> Result<Vec<f64>, Error> {
    let n = want.len();
    let f = |xi: &[f64]| -> Vec<f64> { xi.iter().zip(want).map(|(x, w)| x - w).collect() };
    let mut a = s0.to_vec();
    let mut fa = f(&kn.xi(&a)?);
    let mut b: Vec<f64> = a.iter().map(|s| s + h).collect();
    let mut fb = f(&kn.xi(&b)?);
    // Bracket: step downhill, doubling, until the sign changes.
    let mut step: Vec<f64> = vec![h; n];
    for _ in 0..40 {
        let open: Vec<usize> = (1..n).filter(|&k| fa[k] * fb[k] > 0.0).collect();
        if open.is_empty() {
            break;
        }
        let mut c = b.clone();
        for &k in &open {
            let slope = (fb[k] - fa[k]) / (b[k] - a[k]);
            let dir = if slope * fb[k] > 0.0 { -1.0 } else { 1.0 };
            step[k] *= 2.0;
            c[k] = b[k] + dir * step[k];
        }
        let fc = f(&kn.xi(&c)?);
        for &k in &open {
            a[k] = b[k];
            fa[k] = fb[k];
            b[k] = c[k];
            fb[k] = fc[k];
        }
    }
    if let Some(k) = (1..n)
        .filter(|&k| fa[k] * fb[k] > 0.0)
        .max_by(|&x, &y| fb[x].abs().total_cmp(&fb[y].abs()))
    {
        return Err(bad(
            format!(
                "the target cannot be reached at φ = {:.3}°: no lift of the follower makes the thread path {:.4} mm long there \
                 (the nearest it came is {:.4} mm off)",
                wrap_deg(kn.phis[k]),
                want[k],
                fb[k].abs()
            ),
            "give the target less swing, or place the thread's guides so the follower's travel changes the path's length more",
        ));
    }
    // Illinois: regula falsi, halving the value of an end kept twice.
    for _ in 0..100 {
        if (1..n).all(|k| fa[k].abs().min(fb[k].abs()) < 1e-11 || (b[k] - a[k]).abs() < 1e-13) {
            break;
        }
        let c: Vec<f64> = (0..n)
            .map(|k| {
                if k == 0 || fb[k] == fa[k] {
                    b[k]
                } else {
                    b[k] - fb[k] * (b[k] - a[k]) / (fb[k] - fa[k])
                }
            })
            .collect();
        let fc = f(&kn.xi(&c)?);
        for k in 1..n {
            if fc[k] * fb[k] < 0.0 {
                a[k] = b[k];
                fa[k] = fb[k];
            } else {
                fa[k] *= 0.5;
            }
            b[k] = c[k];
            fb[k] = fc[k];
        }
    }
    Ok((0..n)
        .map(|k| {
            if k == 0 {
                s0[0]
            } else if fa[k].abs() < fb[k].abs() {
                a[k]
            } else {
                b[k]
            }
        })
        .collect())
}

/// What touches the cam, in words.
fn contact_name(contact: Contact<f64>) -> &'static str {
    match contact {
        Contact::Knife => "knife",
        Contact::Roller(_) => "roller",
        Contact::Flat => "flat",
    }
}

/// The roller's radius, mm (0 without a roller).
fn roller_of(contact: Contact<f64>) -> f64 {
    match contact {
        Contact::Roller(r) => r,
        _ => 0.0,
    }
}

/// The base circle that puts the follower at zero lift where the lift
/// `least` (in the lift's internal unit) put it with base `cam.base`.
fn shifted_base(cam: &CamFollower<f64>, c: V2<f64>, o: Option<V2<f64>>, least: f64) -> Result<f64, Error> {
    let r_r = roller_of(cam.contact);
    let base = match (cam.motion, cam.contact, o) {
        (Motion::Translating { .. }, Contact::Flat, _) => cam.base + least,
        (Motion::Translating { offset, .. }, _, _) => {
            let rc = cam.base + r_r;
            let y = (rc * rc - offset * offset).max(0.0).sqrt() + least;
            if y <= 0.0 {
                return Err(bad(
                    format!(
                        "at its least lift the follower would stand {:.4} mm behind the cam's centre along its axis: no base circle puts it there",
                        -y
                    ),
                    "place the thread's guides so the follower works further from the cam's centre, or move the cam's centre",
                ));
            }
            (y * y + offset * offset).sqrt() - r_r
        }
        (Motion::Rocking { .. }, contact, Some(o)) => {
            // The roller (or the face) where the least lift puts it: its
            // distance from C.
            let mut shifted = cam.clone();
            shifted.lift = Lift::Segments(vec![crate::mechanism::cam_follower::Segment {
                from: 0.0,
                to: TAU,
                s0: least,
                s1: least,
                law: crate::mechanism::cam_follower::Law::Cycloidal,
            }]);
            let why =
                |e: crate::mechanism::NoAssembly| bad(e.message, "move the follower's pivot or the thread's guides");
            if matches!(contact, Contact::Flat) {
                // A constant lift turns the face with nothing: the profile
                // is the circle the face stands off, p = ρ.
                shifted.state(c, 0.0, Some(o)).map_err(why)?.profile_radius_mm
            } else {
                (shifted.point_at(c, 0.0, Some(o)).map_err(why)? - c).norm() - r_r
            }
        }
        (Motion::Rocking { .. }, _, None) => unreachable!("a rocking follower is resolved with its pivot"),
    };
    if !(base.is_finite() && base > 0.0) {
        return Err(bad(
            format!(
                "the new lift would need a base circle of {base:.4} mm: the follower at its least lift reaches the cam's centre"
            ),
            "place the thread's guides so the follower works further from the cam's centre",
        ));
    }
    Ok(base)
}

/// The group's checks of a cam over its turn ([`PROFILE_SAMPLES`] cam
/// angles): the largest pressure angle against `limit` (deg) and the
/// working profile's least radius of curvature.
fn check_figures(cam: &CamFollower<f64>, c: V2<f64>, o: Option<V2<f64>>, limit: f64) -> Result<FollowerChecks, Error> {
    let mut worst = (f64::MIN, 0.0);
    let mut least: Option<(f64, f64)> = None;
    for k in 0..PROFILE_SAMPLES {
        let deg = k as f64 * 360.0 / PROFILE_SAMPLES as f64;
        let st = cam
            .state(c, deg.to_radians(), o)
            .map_err(|e| no_position(deg, e.message))?;
        if st.pressure_deg > worst.0 {
            worst = (st.pressure_deg, deg);
        }
        if let Some(r) = cam.flank_radius(st.pitch_radius_mm)
            && least.is_none_or(|(m, _)| r < m)
        {
            least = Some((r, deg));
        }
    }
    let (radius, at) = least.unwrap_or((f64::INFINITY, 0.0));
    Ok(FollowerChecks {
        max_pressure_deg: worst.0,
        max_pressure_at_cam_deg: worst.1,
        pressure_limit_deg: limit,
        pressure_ok: worst.0 <= limit,
        min_curvature_radius_mm: radius,
        min_curvature_at_cam_deg: at,
        curvature_ok: radius > 0.0,
    })
}

fn no_position(deg: f64, message: String) -> Error {
    bad(
        format!("at cam angle {deg:.1}° the new cam has no follower position: {message}"),
        "smooth the lift",
    )
}

/// The cam's pitch curve and working profile over its turn, every
/// 360°/[`PROFILE_SAMPLES`], in the cam's frame.
fn profile_points(
    cam: &CamFollower<f64>,
    c: V2<f64>,
    o: Option<V2<f64>>,
    lift_scale: f64,
) -> Result<Vec<ProfilePoint>, Error> {
    let me = cam.constant::<Dual2_64>();
    let r_r = roller_of(cam.contact);
    // A flat face's profile is the envelope of its lines, not an offset
    // of the follower point's path.
    let envelope = match cam.contact {
        Contact::Flat => Some(
            cam.outline(c, o, PROFILE_SAMPLES)
                .map_err(|e| no_position(0.0, e.message))?
                .profile,
        ),
        _ => None,
    };
    let mut profile = Vec::with_capacity(PROFILE_SAMPLES);
    for k in 0..PROFILE_SAMPLES {
        let deg = k as f64 * 360.0 / PROFILE_SAMPLES as f64;
        // The pitch curve in the cam's frame, Q = Rot(−δ)(R − C), and the
        // working profile the roller's radius inside it.
        let d = Dual2_64::new(deg.to_radians(), 1.0, 0.0);
        let r = me
            .point_at(c.map(Dual2_64::from_re), d, o.map(|o| o.map(Dual2_64::from_re)))
            .map_err(|e| no_position(deg, e.message))?;
        let (sn, cs) = d.sin_cos();
        let w = r - c.map(Dual2_64::from_re);
        let q = V2::new(w.x * cs + w.y * sn, w.y * cs - w.x * sn);
        let (q0, q1) = (V2::new(q.x.re, q.y.re), V2::new(q.x.v1, q.y.v1));
        let mut n = perp(q1) / q1.norm();
        if n.dot(&q0) < 0.0 {
            n = -n;
        }
        let p = envelope.as_ref().map_or(q0 - n * r_r, |e| e[k]);
        profile.push(ProfilePoint {
            cam_deg: deg,
            lift: cam.lift.at(deg.to_radians()) * lift_scale,
            pitch_mm: [q0.x, q0.y],
            profile_mm: [p.x, p.y],
        });
    }
    Ok(profile)
}

/// The checks of the new cam and, when one fails, the least base circle
/// that passes ([`least_passing_base`]).
fn checks_and_advice(
    cam: &CamFollower<f64>,
    c: V2<f64>,
    o: Option<V2<f64>>,
    limit: f64,
) -> Result<(FollowerChecks, Option<BaseCircleAdvice>), Error> {
    let checks = check_figures(cam, c, o, limit)?;
    let advice = if checks.pressure_ok && checks.curvature_ok {
        None
    } else {
        least_passing_base(cam, c, o, limit)?
    };
    Ok((checks, advice))
}

/// The largest base circle the search tries, mm.
const MAX_BASE_MM: f64 = 1000.0;

/// A cam with another base circle: the cam, its centre and the centre's
/// move, mm.
type MovedCam = (CamFollower<f64>, V2<f64>, V2<f64>);

/// The least base circle (to 0.1 mm, rounded up) with which a follower's
/// lift passes both checks, the cam's centre moved back so the follower
/// keeps its positions.
///
/// Translating: along the axis by Δ; with the axis offset e and roller
/// r_r, y0 = √((r_b + r_r)² − e²) grows by Δ and r_b′ = √((y0 + Δ)² + e²)
/// − r_r (a flat face: y0 = r_b, r_b′ = r_b + Δ, its profile's radius
/// r_b + s + s″ grows with Δ). The pressure angle, tan α = (s′ − e)/(y0 +
/// s) for an offset follower, falls as y0 grows, and the pitch curve's
/// radius grows with it.
///
/// Rocking: the arm's angle at zero lift is kept, so the roller's rest
/// point R₀ (pivot O, arm l) stays where it is and the centre moves from
/// R₀ through C by Δ = r_b′ − r_b ([`CamFollower::rocking_retreat`]); a
/// flat face's centre moves along −n₀ by Δ. The pressure angle's part from
/// the cam's turning falls as the centre moves off, toward the angle
/// between the line R₀C and the roller's path at rest, which no base
/// circle changes; a lift that fails there is not helped (`None`).
///
/// Passing is taken to be monotone in Δ and found by bisection. `Ok(None)`
/// when no base circle up to 1 000 mm passes.
pub fn least_passing_base(
    cam: &CamFollower<f64>,
    c: V2<f64>,
    o: Option<V2<f64>>,
    limit: f64,
) -> Result<Option<BaseCircleAdvice>, Error> {
    let no_pivot = || no_position(0.0, "a rocking follower needs its pivot".into());
    // For a base circle: the moved cam, its centre, and the move.
    let with_base = |base: f64| -> Result<MovedCam, Error> {
        let mut moved = cam.clone();
        moved.base = base;
        let shift = match cam.motion {
            Motion::Translating { u, offset } => {
                // Where the follower's point stands at zero lift along the
                // axis: a flat face at r_b.
                let stand = |base: f64| match cam.contact {
                    Contact::Flat => base,
                    Contact::Roller(r) => ((base + r).powi(2) - offset * offset).max(0.0).sqrt(),
                    Contact::Knife => (base * base - offset * offset).max(0.0).sqrt(),
                };
                u * -(stand(base) - stand(cam.base))
            }
            Motion::Rocking { .. } => {
                let o = o.ok_or_else(no_pivot)?;
                let d = cam
                    .rocking_retreat(c, o)
                    .map_err(|e| no_position(0.0, e.message))?
                    .ok_or_else(no_pivot)?;
                d * (base - cam.base)
            }
        };
        Ok((moved, c + shift, shift))
    };
    let passes = |base: f64| -> Result<(bool, FollowerChecks, V2<f64>), Error> {
        let (moved, c_moved, shift) = with_base(base)?;
        let checks = check_figures(&moved, c_moved, o, limit)?;
        Ok((checks.pressure_ok && checks.curvature_ok, checks, shift))
    };
    if passes(cam.base)?.0 {
        return Ok(None);
    }
    let (mut lo, mut hi) = (cam.base, (2.0 * cam.base).max(cam.base + 1.0));
    while !passes(hi)?.0 {
        if hi >= MAX_BASE_MM {
            return Ok(None);
        }
        (lo, hi) = (hi, (2.0 * hi).min(MAX_BASE_MM));
    }
    while hi - lo > 0.01 {
        let mid = 0.5 * (lo + hi);
        if passes(mid)?.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let rounded = (hi * 10.0).ceil() / 10.0;
    let base = if passes(rounded)?.0 { rounded } else { hi };
    let (_, checks, shift) = passes(base)?;
    Ok(Some(BaseCircleAdvice {
        base_radius_mm: base,
        move_back_mm: shift.norm(),
        move_mm: [shift.x, shift.y],
        checks,
    }))
}

/// Synthesises the lift of group `opts.group` (module docs).
pub fn synthesise_follower(model: &Model, params: &Params, opts: &FollowerOptions) -> Result<FollowerSynthesis, Error> {
    let copts = CamOptions {
        points: opts.points,
        smooth_deg: opts.smooth_deg,
        ..CamOptions::new(&opts.path, opts.target.clone())
    };
    crate::study::cam_synthesis::check_options(&copts)?;
    let Machine {
        mechanism: mech,
        threads,
    } = model.machine::<f64>(params)?;
    let threads = threads.as_ref().ok_or_else(|| {
        bad(
            format!(
                "model `{}` has no thread paths, so there is no take-up to match",
                model.name()
            ),
            "add [thread] paths over a point the follower carries (docs/model-format.md §13)",
        )
    })?;
    let (pi, ci) = path_and_group(model, &mech, threads, opts)?;
    let step = cam_step(&mech, ci).clone();
    let rocking = matches!(step.cam.motion, Motion::Rocking { .. });
    // Internally a rocking follower's lift is in rad; the table in deg.
    let (lift_scale, lift_unit, h) = if rocking {
        (180.0 / std::f64::consts::PI, "deg", 0.01)
    } else {
        (1.0, "mm", 0.5)
    };
    // --- the grid: knots at even j, midpoints at odd j, from φ0 --------------
    let n = opts.points;
    let phi0 = threads.phi0_deg;
    let phis: Vec<f64> = (0..2 * n).map(|j| phi0 + j as f64 * 180.0 / n as f64).collect();
    let mut pose = mech.new_pose(phis.len());
    mech.solve(&Phi::table(&phis), &mut pose)?;
    let at = |slot: usize, j: usize| step.plane.project(&pose.point(slot, j));
    let deltas = cam_angles(&step, &pose, phis.len())?;
    check_one_turn(&deltas, &phis, &opts.group)?;
    let knot_phis: Vec<f64> = phis.iter().step_by(2).copied().collect();
    let knot_angles: Vec<f64> = deltas.iter().step_by(2).map(|d| d.rem_euclid(TAU)).collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&x, &y| knot_angles[x].total_cmp(&knot_angles[y]));
    let angles: Vec<f64> = order.iter().map(|&k| knot_angles[k]).collect();
    // --- the target and the level ------------------------------------------------
    let (label, raw, stitch_thread) = target_on_grid(model, params, &copts, &phis)?;
    let xi0 = eval::tracks_at_phi0(&mech, threads)?[pi].xi_at_split(0);
    let p_conv0 = threads.convention.take_up(xi0, xi0);
    let shift = raw[0] - p_conv0;
    let target: Vec<f64> = raw.iter().map(|v| v - shift).collect();
    let mut notes = Vec::new();
    if shift.abs() > 1e-9 {
        notes.push(shift_note(raw[0], phi0, p_conv0));
    }
    let want: Vec<f64> = (0..n)
        .map(|k| match threads.convention {
            Convention::Release => xi0 - target[2 * k],
            Convention::Feed { elongation_mm } => xi0 + target[2 * k] - elongation_mm,
        })
        .collect();
    // --- lift by lift -------------------------------------------------------------
    let s_model: Vec<f64> = (0..n).map(|k| step.cam.lift.at(deltas[2 * k])).collect();
    let mut kn = Knots {
        mech: mech.clone(),
        threads,
        ci,
        pi,
        phis: knot_phis.clone(),
        order: order.clone(),
        angles: angles.clone(),
    };
    let solved = solve_lifts(&mut kn, &want, &s_model, h)?;
    let mut knots: Vec<Knot> = order
        .iter()
        .map(|&k| Knot {
            theta_deg: turn_deg(knot_angles[k].to_degrees()),
            radius_mm: solved[k],
            solved_mm: solved[k],
            phi_deg: wrap_deg(knot_phis[k]),
        })
        .collect();
    if opts.smooth_deg > 0.0 {
        smooth(&mut knots, opts.smooth_deg);
    }
    let least = knots.iter().map(|k| k.radius_mm).fold(f64::MAX, f64::min);
    // --- the new cam: lift from 0, base circle to match ---------------------------
    let c0 = at(step.center, 0);
    let o0 = step.pivot.map(|p| at(p, 0));
    let base = shifted_base(&step.cam, c0, o0, least)?;
    let shifted: Vec<f64> = knots.iter().map(|k| k.radius_mm - least).collect();
    let mut new_mech = mech.clone();
    let s = cam_step_mut(&mut new_mech, ci);
    (s.cam.lift, s.cam.base) = (table(&angles, &shifted), base);
    // --- verify: the model again with the new cam -------------------------------
    let p_after = take_up_on(&new_mech, threads, &phis, pi)?;
    let p_before = take_up(&mech, threads, &pose, &phis, pi)?;
    let verify = verification(phis.clone(), target, p_before, p_after, stitch_thread.as_ref());
    let match_target = stitch_thread.is_none().then(|| match_with_target(&verify)).flatten();
    // --- checks ----------------------------------------------------------------------
    let new_cam = &cam_step(&new_mech, ci).cam;
    let (checks, base_circle_needed) = checks_and_advice(new_cam, c0, o0, step.max_pressure_deg)?;
    let profile = profile_points(new_cam, c0, o0, lift_scale)?;
    let (lift, range) = lift_table(&knots, &shifted, least, lift_scale);
    Ok(FollowerSynthesis {
        group: opts.group.clone(),
        path: opts.path.clone(),
        motion: if rocking { "rocking" } else { "translating" },
        lift_unit,
        target: label,
        thread: stitch_thread.map(|t| t.name),
        phi0_deg: wrap_deg(phi0),
        lift,
        smooth_deg: opts.smooth_deg,
        least_lift: least * lift_scale,
        base_radius_model_mm: step.cam.base,
        base_radius_mm: base,
        contact: contact_name(step.cam.contact),
        roller_mm: roller_of(step.cam.contact),
        lift_range: range,
        checks,
        base_circle_needed,
        verify,
        match_target,
        profile,
        notes,
    })
}

/// The path's index and the group's step index, its follower one whose
/// lift can be synthesised.
fn path_and_group(
    model: &Model,
    mech: &Mechanism<f64>,
    threads: &Threads<f64>,
    opts: &FollowerOptions,
) -> Result<(usize, usize), Error> {
    let name = model.name();
    let pi = threads.paths.iter().position(|p| p.name == opts.path).ok_or_else(|| {
        let all: Vec<&str> = threads.paths.iter().map(|p| p.name.as_str()).collect();
        bad(
            format!("model `{name}` has no thread path `{}`", opts.path),
            &format!("its paths are: {}", all.join(", ")),
        )
    })?;
    let ci = cam_step_index(mech, model, &opts.group)?;
    Ok((pi, ci))
}

/// P of path `pi` at `phis` with the mechanism `mech`.
fn take_up_on(mech: &Mechanism<f64>, threads: &Threads<f64>, phis: &[f64], pi: usize) -> Result<Vec<f64>, Error> {
    let mut pose = mech.new_pose(phis.len());
    mech.solve(&Phi::table(phis), &mut pose)?;
    take_up(mech, threads, &pose, phis, pi)
}

/// The cam angle δ at every grid point, rad.
fn cam_angles(step: &CamStep<f64>, pose: &crate::mechanism::Pose<f64>, m: usize) -> Result<Vec<f64>, Error> {
    let at = |slot: usize, j: usize| step.plane.project(&pose.point(slot, j));
    (0..m)
        .map(|j| {
            step.cam
                .cam_angle(at(step.center, j), at(step.marker, j))
                .map_err(|e| bad(e.message, "check the group's centre and marker"))
        })
        .collect()
}

/// The take-up against the target on the knots' φ (even grid points):
/// every φ compared, tolerance 0.5 mm.
fn match_with_target(v: &Verification) -> Option<Mismatch> {
    let even = |v: &[f64]| v.iter().step_by(2).copied().collect::<Vec<f64>>();
    let phis = even(&v.phi_deg);
    mismatch(
        &phis,
        &even(&v.p_after_mm),
        &even(&v.target_mm),
        &vec![true; phis.len()],
        0.5,
        false,
    )
}

/// The knots with the lift shifted (`shifted`, internal unit) in the
/// table's unit, and its range.
fn lift_table(knots: &[Knot], shifted: &[f64], least: f64, scale: f64) -> (Vec<Knot>, [f64; 2]) {
    let lift: Vec<Knot> = knots
        .iter()
        .zip(shifted)
        .map(|(k, s)| Knot {
            radius_mm: s * scale,
            solved_mm: (k.solved_mm - least) * scale,
            ..*k
        })
        .collect();
    let range = lift.iter().fold([f64::MAX, f64::MIN], |m, k| {
        [m[0].min(k.radius_mm), m[1].max(k.radius_mm)]
    });
    (lift, range)
}

/// The cam must turn exactly once per cycle, one way, relative to the
/// follower, so each cam angle serves one position.
fn check_one_turn(deltas: &[f64], phis: &[f64], group: &str) -> Result<(), Error> {
    match steady_turn(deltas) {
        Ok(()) => Ok(()),
        Err(UnsteadyTurn::Stops(j)) => Err(bad(
            format!(
                "the cam of group `{group}` does not turn steadily (it stops or turns back near φ = {:.1}°), so one cam angle \
                 would have to serve two take-ups",
                wrap_deg(phis[j])
            ),
            "the lift can be synthesised only for a cam turning once per cycle (a cam on the main shaft)",
        )),
        Err(UnsteadyTurn::Turns(turns)) => Err(bad(
            format!(
                "the cam of group `{group}` turns {turns:.3} times per cycle; a lift can be synthesised only for exactly one"
            ),
            "the lift can be synthesised only for a cam turning once per main-shaft cycle",
        )),
    }
}
