//! The checks of every cam and follower of a mechanism over a cycle
//! (`docs/model-format.md`, "Cams and followers"):
//!
//! - `cam_pressure`: the largest pressure angle over the cam's turn, within
//!   the group's limit (30° translating, 45° rocking by default): beyond it
//!   the cam pushes the follower more across its guide than along it, and
//!   the guide binds or the pivot wears;
//! - `cam_curvature`: the working profile's least radius of curvature where
//!   the roller rides it, above zero: at zero the profile is cut back to a
//!   cusp, below it the roller cannot follow the pitch curve (undercut); a
//!   groove's outer flank is checked where the cam is concave; a flat face
//!   needs a convex profile everywhere;
//! - `follower_contact`: for a spring-closed follower with its spring and
//!   mass given, the least force pressing it on the cam over the cycle at
//!   the model's speed, above zero: below it the follower leaves the cam
//!   (jumps) where it decelerates.
//!
//! The first two read the cam and follower as made (over the cam's whole
//! turn, every half degree, at the cycle's first position of the cam's
//! centre and the follower's pivot); the third reads the cycle, since it
//! depends on how fast the cam turns.

use num_dual::Dual2_64;
use serde::Serialize;

use crate::error::Error;
use crate::geometry::V2;
use crate::mechanism::cam_follower::{Closure, Contact, Motion};
use crate::mechanism::{CamStep, Phi, Step};
use crate::model::{Model, Params};
use crate::stitch::checks::Check;

/// Cam angles sampled for the profile checks, over one turn.
const PROFILE_SAMPLES: usize = 720;

/// One cam and follower's checks.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CamSummary {
    /// The group's name.
    pub group: String,
    /// `cam_pressure`, `cam_curvature` and, for a spring-closed follower,
    /// `follower_contact`; each check's `thread` is the group's name.
    pub checks: Vec<Check>,
    /// For a spring-closed follower with its spring and mass given: the
    /// highest main-shaft speed at which the spring keeps it on the cam,
    /// rpm ([`limit_rpm`]; 0 when the spring does not press everywhere).
    /// `None` otherwise, or when no speed loses it.
    pub limit_rpm: Option<f64>,
}

impl CamSummary {
    pub fn checks_ok(&self) -> bool {
        self.checks.iter().all(|c| c.ok)
    }
}

/// Every cam-and-follower group's checks at the cycle's `phis_deg`, the
/// main shaft at `rpm` (`None`: no speed, so the spring's check cannot be
/// judged and says so). Empty for a mechanism without cams.
pub fn cam_summaries(
    model: &Model,
    params: &Params,
    phis_deg: &[f64],
    rpm: Option<f64>,
) -> Result<Vec<CamSummary>, Error> {
    let mech = model.mechanism::<Dual2_64>(params)?;
    let cams: Vec<&CamStep<Dual2_64>> = mech
        .steps
        .iter()
        .filter_map(|s| match s {
            Step::CamFollower(c) => Some(&**c),
            _ => None,
        })
        .collect();
    if cams.is_empty() {
        return Ok(Vec::new());
    }
    let mut pose = mech.new_pose(phis_deg.len());
    mech.solve(&Phi::table(phis_deg), &mut pose)?;
    let plain = |v: V2<Dual2_64>| V2::new(v.x.re, v.y.re);
    cams.into_iter()
        .map(|c| {
            let at = |slot: usize, k: usize| c.plane.project(&pose.point(slot, k));
            let cam = c.cam.constant::<f64>();
            let centre = plain(at(c.center, 0));
            let pivot = c.pivot.map(|p| plain(at(p, 0)));
            let mut checks = profile_checks(c, &cam, centre, pivot)?;
            let mut limit = None;
            if let Closure::Spring(spring) = cam.closure {
                let (check, max_rpm) = contact_check(c, &cam, spring, phis_deg, rpm, |k| {
                    let centre = at(c.center, k);
                    let delta = c.cam.cam_angle(centre, at(c.marker, k))?;
                    Ok((plain(centre), delta, c.pivot.map(|p| plain(at(p, k)))))
                })?;
                checks.push(check);
                limit = max_rpm;
            }
            Ok(CamSummary {
                group: c.name.clone(),
                checks,
                limit_rpm: limit,
            })
        })
        .collect()
}

/// The pressure angle and curvature checks over the cam's turn.
fn profile_checks(
    c: &CamStep<Dual2_64>,
    cam: &crate::mechanism::cam_follower::CamFollower<f64>,
    centre: V2<f64>,
    pivot: Option<V2<f64>>,
) -> Result<Vec<Check>, Error> {
    let mut worst_pressure = (f64::MIN, 0.0);
    let mut least_radius: Option<(f64, f64)> = None;
    for k in 0..PROFILE_SAMPLES {
        let delta_deg = k as f64 * 360.0 / PROFILE_SAMPLES as f64;
        let st = cam
            .state(centre, delta_deg.to_radians(), pivot)
            .map_err(|e| no_state(c, delta_deg, &e.message))?;
        if st.pressure_deg > worst_pressure.0 {
            worst_pressure = (st.pressure_deg, delta_deg);
        }
        if let Some(r) = cam.flank_radius(st.pitch_radius_mm)
            && least_radius.is_none_or(|(m, _)| r < m)
        {
            least_radius = Some((r, delta_deg));
        }
    }
    let (pressure, at_pressure) = worst_pressure;
    let limit = c.max_pressure_deg;
    let kind = match cam.motion {
        Motion::Translating { .. } => "translating",
        Motion::Rocking { .. } => "rocking",
    };
    let pressure_check = Check {
        name: "cam_pressure",
        thread: c.name.clone(),
        ok: pressure <= limit,
        value: pressure,
        limit: [None, Some(limit)],
        unit: "deg",
        at_deg: at_pressure,
        message: if pressure <= limit {
            format!(
                "the cam pushes its {kind} follower at most {pressure:.1}° off the way it moves (at cam angle {at_pressure:.1}°), within {limit}°"
            )
        } else {
            format!(
                "at cam angle {at_pressure:.1}° the cam pushes its {kind} follower {pressure:.1}° off the way it moves, beyond {limit}°: the follower's guide or pivot takes more side load than lift and binds or wears; give the cam a larger base circle, spread the rise over a longer cam angle, or offset the follower"
            )
        },
    };
    // A profile the roller rides everywhere has a radius somewhere; only a
    // knife edge on a spring-closed cam that is concave all round has none.
    let (radius, at_radius) = least_radius.unwrap_or((f64::INFINITY, 0.0));
    let what = match cam.contact {
        Contact::Flat => "the profile under the flat face",
        Contact::Knife => "the profile under the knife edge",
        Contact::Roller(_) => "the profile the roller rides",
    };
    let ok = radius > 0.0;
    let curvature_check = Check {
        name: "cam_curvature",
        thread: c.name.clone(),
        ok,
        value: if radius.is_finite() { radius } else { 0.0 },
        limit: if radius.is_finite() {
            [Some(0.0), None]
        } else {
            [None, None]
        },
        unit: "mm",
        at_deg: at_radius,
        message: if !radius.is_finite() {
            format!("{what} has no convex part to check")
        } else if ok {
            format!("{what} bends no tighter than a radius of {radius:.2} mm (at cam angle {at_radius:.1}°)")
        } else if matches!(cam.contact, Contact::Flat) {
            format!(
                "at cam angle {at_radius:.1}° {what} would have to be concave (radius {radius:.2} mm): a flat face cannot follow it; enlarge the base circle or spread the rise over a longer cam angle"
            )
        } else {
            format!(
                "at cam angle {at_radius:.1}° {what} is undercut: the roller's path bends tighter than the roller itself, so the profile would need a radius of {radius:.2} mm there; no cutter makes that and the follower would not follow the lift; enlarge the base circle, use a smaller roller, or spread the rise over a longer cam angle"
            )
        },
    };
    Ok(vec![pressure_check, curvature_check])
}

/// The highest main-shaft speed at which a spring keeps its follower on
/// the cam, rpm, from the spring's force F_s(φ) = F0 + k·x (N) and the
/// follower's acceleration per ω², a(φ) = x″(φ) (m/rad²) at the cycle's
/// φ: N = F_s + m·a·ω² ≥ 0 wherever a < 0 holds while
/// ω² ≤ F_s/(m·|a|), so ω_max = min over a < 0 of √(F_s/(m·|a|)).
/// `Some(0)` when the spring does not press somewhere (F_s ≤ 0: no speed
/// keeps contact); `None` when the follower never decelerates or has no
/// mass (no speed loses it).
pub fn limit_rpm(mass_kg: f64, spring_n: &[f64], accel_per_omega2: &[f64]) -> Option<f64> {
    let mut omega2 = f64::INFINITY;
    for (&f, &a) in spring_n.iter().zip(accel_per_omega2) {
        if f <= 0.0 {
            return Some(0.0);
        }
        if a < 0.0 && mass_kg > 0.0 {
            omega2 = omega2.min(f / (mass_kg * -a));
        }
    }
    omega2.is_finite().then(|| omega2.sqrt() * 60.0 / std::f64::consts::TAU)
}

/// The force keeping a spring-closed follower on its cam, least over the
/// cycle: N = F0 + k·x + m·ẍ along the lift (the cam pushes, the spring
/// pulls back; where ẍ < 0 the spring alone must decelerate the follower),
/// and the speed up to which it stays above zero ([`limit_rpm`]).
fn contact_check(
    c: &CamStep<Dual2_64>,
    cam: &crate::mechanism::cam_follower::CamFollower<f64>,
    spring: Option<crate::mechanism::cam_follower::Spring>,
    phis_deg: &[f64],
    rpm: Option<f64>,
    place: impl Fn(usize) -> Result<(V2<f64>, Dual2_64, Option<V2<f64>>), crate::mechanism::NoAssembly>,
) -> Result<(Check, Option<f64>), Error> {
    let unjudged = |message: String| Check {
        name: "follower_contact",
        thread: c.name.clone(),
        ok: true,
        value: 0.0,
        limit: [None, None],
        unit: "N",
        at_deg: phis_deg.first().copied().unwrap_or(0.0),
        message,
    };
    let Some(spring) = spring else {
        return Ok((
            unjudged(
                "a spring holds the follower, but its preload, rate and the follower's mass are not given: whether it stays on the cam is not checked".into(),
            ),
            None,
        ));
    };
    // The spring's force (N) and the follower's acceleration per ω²
    // (m/rad²) at every φ.
    let mut spring_n = Vec::with_capacity(phis_deg.len());
    let mut accel = Vec::with_capacity(phis_deg.len());
    for (k, &phi) in phis_deg.iter().enumerate() {
        let (centre, delta, pivot) = place(k).map_err(|e| no_state(c, phi, &e.message))?;
        let st = cam
            .state(centre, delta.re, pivot)
            .map_err(|e| no_state(c, phi, &e.message))?;
        // Travel at the roller over φ: x″(φ) = x″(δ)·δ′² + x′(δ)·δ″, mm/rad².
        let x_phi2 = st.dds_mm * delta.v1 * delta.v1 + st.ds_mm * delta.v2;
        spring_n.push(spring.preload_n + spring.rate_n_per_mm * st.travel_mm);
        accel.push(x_phi2 * 1e-3);
    }
    let max_rpm = limit_rpm(spring.mass_kg, &spring_n, &accel);
    let holds = match max_rpm {
        Some(max) if max > 0.0 => format!("the spring holds it up to {max:.0} rpm"),
        Some(_) => "the spring does not press it everywhere, so it holds at no speed".to_string(),
        None => "the follower never decelerates, so no speed loses it".to_string(),
    };
    let Some(rpm) = rpm.filter(|r| *r > 0.0) else {
        return Ok((
            unjudged(format!(
                "the machine's speed is not given: whether the spring holds the follower on the cam is not checked ({holds})"
            )),
            max_rpm,
        ));
    };
    // Main-shaft angular speed, rad/s.
    let omega = rpm * std::f64::consts::TAU / 60.0;
    let mut least = (f64::MAX, 0.0);
    for ((&f, &a), &phi) in spring_n.iter().zip(&accel).zip(phis_deg) {
        let force = f + spring.mass_kg * a * omega * omega;
        if force < least.0 {
            least = (force, phi);
        }
    }
    let (force, at) = least;
    let ok = force > 0.0;
    let check = Check {
        name: "follower_contact",
        thread: c.name.clone(),
        ok,
        value: force,
        limit: [Some(0.0), None],
        unit: "N",
        at_deg: at,
        message: if ok {
            format!(
                "at {rpm} rpm the spring keeps at least {force:.2} N pressing the follower on the cam (at φ = {at:.1}°); {holds}"
            )
        } else {
            format!(
                "at {rpm} rpm the follower leaves the cam near φ = {at:.1}°: decelerating it needs {:.2} N more than the spring gives, so it jumps and hammers back ({holds}); a stiffer or more preloaded spring, a lighter follower, a gentler motion law, a groove (form closure) or a lower speed",
                -force
            )
        },
    };
    Ok((check, max_rpm))
}

fn no_state(c: &CamStep<Dual2_64>, at_deg: f64, why: &str) -> Error {
    Error::Assembly(crate::error::AssemblyError {
        group: format!("cam_follower group \"{}\"", c.name),
        phi_deg: at_deg,
        defect_mm: 0.0,
        message: why.to_string(),
    })
}
