//! The required take-up P'(φ) of every thread of a stitch
//! (`docs/stitch-formation.md` §3, §5, §7).
//!
//! Each thread's consumption contour η(φ_c) runs from its split point (the
//! needle eye, a looper eye) to its anchor, the last material point of the
//! newest finished stitch. P'(φ_c) = η(φ_c) − η(φ0) (seed 004 eq. 6). At the
//! thread's lock the anchor moves on by one stitch and η drops by the thread
//! cut off, which is exactly the per-stitch consumption of §6.

use crate::Error;
use crate::error::StitchError;
use crate::geometry::since_deg;

use super::consumption::{StitchGeometry, consumption};
use super::feed::Feed;
use super::lockstitch::LockstitchThread;
use super::needle_thread::{NeedleThread, SharedOrgans, Side, looper_far};
use super::overedge::Overedge;
use super::overedge::Overedge503;
use super::spec::{
    Event, EventKind, Motion, Regulator, RequiredTakeUp, RequiredThread, StitchSpec, StitchType, ThreadRole,
};

/// One thread's contour, for the common bookkeeping.
enum Contour<'a> {
    Needle(&'a NeedleThread),
    /// 301: the needle thread on the rotary hook.
    Lock(&'a LockstitchThread),
    Lower(&'a Overedge),
    Upper(&'a Overedge),
    /// 503: the needle thread drawn to the edge, and the looper thread.
    Needle503(&'a Overedge503),
    Looper503(&'a Overedge503),
}

impl Contour<'_> {
    fn eta(&self, phi: f64, side: Side) -> Result<f64, Error> {
        match self {
            Contour::Needle(n) => Ok(n.eta(phi, side)),
            Contour::Lock(n) => Ok(n.eta(phi, side)),
            Contour::Lower(o) => o.eta_lower(phi, side),
            Contour::Upper(o) => o.eta_upper(phi, side),
            Contour::Needle503(o) => o.eta_needle(phi, side),
            Contour::Looper503(o) => o.eta_looper(phi, side),
        }
    }

    fn piece(&self, phi: f64) -> &'static str {
        match self {
            Contour::Needle(n) => n.piece(phi, Side::Right).id(),
            Contour::Lock(n) => n.piece(phi, Side::Right).id(),
            Contour::Lower(o) => o.lower_piece(phi, Side::Right).id(),
            Contour::Upper(o) => o.upper_piece(phi, Side::Right).id(),
            Contour::Needle503(o) => o.needle_piece(phi, Side::Right).id(),
            Contour::Looper503(o) => o.looper_piece(phi, Side::Right).id(),
        }
    }

    fn events(&self) -> Vec<(String, f64, EventKind)> {
        match self {
            Contour::Needle(n) => n.events(),
            Contour::Lock(n) => n.events(),
            Contour::Lower(o) => o.lower_events(),
            Contour::Upper(o) => o.upper_events(),
            Contour::Needle503(o) => o.needle_events(),
            Contour::Looper503(o) => o.looper_events(),
        }
    }

    /// The lock φ_L, deg.
    fn lock(&self) -> f64 {
        match self {
            Contour::Needle(n) => n.phi_drop,
            Contour::Lock(n) => n.phi_cast,
            Contour::Lower(o) | Contour::Upper(o) => o.phi_draw_in,
            Contour::Needle503(o) | Contour::Looper503(o) => o.phi_draw_in,
        }
    }

    /// The thread cut at the lock, from the final nodes, mm.
    fn cut(&self) -> f64 {
        match self {
            Contour::Needle(n) => n.lock_cut(),
            Contour::Lock(n) => n.lock_cut(),
            Contour::Lower(o) => o.lower_cut(),
            Contour::Upper(o) => o.upper_cut(),
            Contour::Needle503(o) => o.needle_cut(),
            Contour::Looper503(o) => o.looper_cut(),
        }
    }

    /// ρ: thread released at the lock, mm (503: the needle loop leaves the
    /// looper at φ4, before the lock).
    fn released(&self) -> f64 {
        match self {
            Contour::Needle(n) => n.released(),
            Contour::Lock(n) => n.released(),
            Contour::Lower(_) | Contour::Upper(_) | Contour::Needle503(_) | Contour::Looper503(_) => 0.0,
        }
    }

    /// The needle of a needle thread (S(φ) and γ(φ) columns).
    fn needle(&self) -> Option<&NeedleThread> {
        match self {
            Contour::Needle(n) => Some(n),
            Contour::Needle503(o) => Some(&o.needle),
            _ => None,
        }
    }
}

/// φ wrapped into the cyclogram cycle [0, 360).
fn wrap(phi: f64) -> f64 {
    let w = phi.rem_euclid(360.0);
    if w >= 360.0 { 0.0 } else { w }
}

/// P'(φ) of every thread of the stitch, at the cyclogram angles `phis_c_deg`
/// (deg, 0 = needle BDC), with P' = η − η(phi0_c_deg).
///
/// Threads: for 401/406/407 one needle thread per `spec.needles` entry
/// (contour 1, locked at its drop); for 504 the needle thread (contour 1,
/// lock φ4), `lower` (contour 13) and `upper` (contour 10), both locked at
/// φ5; for 503 the needle thread (contour 3) and `looper` (contour 10), both
/// locked at φ5. At an event the right limit is given; the events list both
/// limits.
pub fn required_take_up(spec: &StitchSpec, phis_c_deg: &[f64], phi0_c_deg: f64) -> Result<RequiredTakeUp, Error> {
    check_spec(spec, phis_c_deg, phi0_c_deg)?;
    let ty = spec.stitch_type;
    let (m, t, tilt) = (spec.m_mm, spec.t_mm, spec.tilt_deg);
    let feed = Feed::new(&spec.feed, t)?;
    check_organs(spec)?;

    // Per-stitch consumption by the contour formulas (§6). Chain stitches
    // do not use the overedge width or the edge split.
    let overedge = matches!(ty, StitchType::S503 | StitchType::S504);
    let geometry = StitchGeometry {
        thickness_mm: m,
        stitch_mm: t,
        width_mm: if overedge { spec.a_e_mm } else { 0.0 },
        incline_deg: tilt,
        edge_fraction: if overedge { spec.edge_split } else { 0.5 },
        interlace_fraction: spec.interlace,
    };
    let per_stitch = consumption(ty.number(), &geometry)?;
    let formula = |thread: &str| {
        per_stitch
            .threads
            .iter()
            .find(|c| c.thread == thread)
            .and_then(|c| c.length_mm)
    };

    // 301: the needle thread on the hook (§13).
    if ty == StitchType::S301 {
        let per_stitch_mm = formula("needle 1").ok_or_else(|| {
            Error::Stitch(StitchError::new(
                "stitch 301",
                "no per-stitch formula for the needle thread",
            ))
        })?;
        return lockstitch_take_up(spec, feed, per_stitch_mm, phis_c_deg, phi0_c_deg);
    }
    let looper = spec.the_looper()?;
    let phi_far = looper_far(looper);
    let needles = spec
        .needles
        .iter()
        .map(|n| NeedleThread::with_looper_far(n, looper, phi_far, m, tilt, feed.clone()))
        .collect::<Result<Vec<_>, _>>()?;
    let ov = if ty == StitchType::S504 {
        Some(Overedge::new(spec, &needles[0])?)
    } else {
        None
    };
    let ov503 = if ty == StitchType::S503 {
        Some(Overedge503::new(spec, &needles[0])?)
    } else {
        None
    };

    // Needles in order, then the looper threads (the order of the model's
    // `StitchSetup::paths`).
    let mut contours: Vec<(String, ThreadRole, u8, Contour)> = match &ov503 {
        Some(o) => vec![
            (o.needle.name.clone(), ThreadRole::Needle, 3, Contour::Needle503(o)),
            ("looper".into(), ThreadRole::LowerLooper, 10, Contour::Looper503(o)),
        ],
        None => needles
            .iter()
            .map(|n| (n.name.clone(), ThreadRole::Needle, 1, Contour::Needle(n)))
            .collect(),
    };
    if let Some(o) = &ov {
        contours.push(("lower".into(), ThreadRole::LowerLooper, 13, Contour::Lower(o)));
        contours.push(("upper".into(), ThreadRole::UpperLooper, 10, Contour::Upper(o)));
    }

    let phis: Vec<f64> = phis_c_deg.iter().map(|&p| wrap(p)).collect();
    let phi0 = wrap(phi0_c_deg);
    let shared = SharedOrgans::new(&looper.eye, &feed, &phis);
    let mut threads = Vec::new();
    for entry in &contours {
        let (name, role, contour, c) = entry;
        let per_stitch_mm = match role {
            ThreadRole::Needle => formula("needle 1"),
            ThreadRole::LowerLooper => formula("lower looper"),
            ThreadRole::UpperLooper => formula("upper looper"),
        }
        .ok_or_else(|| {
            Error::Stitch(StitchError::new(
                format!("thread {name}"),
                format!("no per-stitch formula for contour {contour}"),
            ))
        })?;
        // A needle thread's stitch is pulled tight as the needle reaches
        // TDC, a looper thread's at its draw-in (its lock).
        let tight = if *role == ThreadRole::Needle {
            needles[0].line.phi_tdc
        } else {
            c.lock()
        };
        threads.push(required_thread(
            entry,
            per_stitch_mm,
            tight,
            spec.regulator,
            &phis,
            phi0,
            Some(&shared),
        )?);
    }

    let mut moments: Vec<(String, f64)> = match &ov503 {
        Some(o) => o.moments(),
        None => needles.iter().flat_map(|n| n.moments()).collect(),
    };
    let mut warnings: Vec<String> = feed.warning.iter().cloned().collect();
    warnings.extend(needles.iter().flat_map(|n| n.warnings.iter().cloned()));
    if let Some(o) = &ov {
        moments.push(("upper looper picks lower thread (φ_UC)".into(), o.phi_pick));
        warnings.extend(o.warnings.iter().cloned());
    }
    if let Some(o) = &ov503 {
        warnings.extend(o.warnings.iter().cloned());
    }
    Ok(RequiredTakeUp {
        threads,
        moments,
        warnings,
    })
}

/// P' of a lockstitch's needle thread (§13): one thread, on the hook.
fn lockstitch_take_up(
    spec: &StitchSpec,
    feed: Feed,
    per_stitch_mm: f64,
    phis_c_deg: &[f64],
    phi0_c_deg: f64,
) -> Result<RequiredTakeUp, Error> {
    let hook = spec.hook.as_ref().ok_or_else(|| {
        Error::Stitch(StitchError::new(
            "stitch 301",
            "it has no hook to take the needle loop; give [stitch.hook]",
        ))
    })?;
    let lock = LockstitchThread::new(&spec.needles[0], hook, spec.m_mm, spec.tilt_deg, spec.interlace, feed)?;
    let entry = (lock.name.clone(), ThreadRole::Needle, 0, Contour::Lock(&lock));
    let phis: Vec<f64> = phis_c_deg.iter().map(|&p| wrap(p)).collect();
    // The stitch is pulled tight as the needle reaches TDC.
    let thread = required_thread(
        &entry,
        per_stitch_mm,
        lock.line.phi_tdc,
        spec.regulator,
        &phis,
        wrap(phi0_c_deg),
        None,
    )?;
    let mut warnings: Vec<String> = lock.feed.warning.iter().cloned().collect();
    warnings.extend(lock.warnings.iter().cloned());
    Ok(RequiredTakeUp {
        threads: vec![thread],
        moments: lock.moments(),
        warnings,
    })
}

/// The spec's numbers in range (each refused with what to give instead).
fn check_spec(spec: &StitchSpec, phis_c_deg: &[f64], phi0_c_deg: f64) -> Result<(), Error> {
    let ty = spec.stitch_type;
    let (m, tilt) = (spec.m_mm, spec.tilt_deg);
    if !(m.is_finite() && m > 0.0) {
        return Err(StitchError::new("material", format!("the thickness m = {m} mm must be > 0 (e.g. 2.5)")).into());
    }
    if !(tilt.is_finite() && tilt.abs() < 80.0) {
        return Err(StitchError::new(
            "needle",
            format!("the tilt β = {tilt}° must be between −80° and 80° (Altin: 20°)"),
        )
        .into());
    }
    if let Some(bad) = phis_c_deg.iter().chain([&phi0_c_deg]).find(|p| !p.is_finite()) {
        return Err(StitchError::new(
            "cyclogram",
            format!("the angle φ_c = {bad} is not a number; give finite angles in degrees"),
        )
        .into());
    }
    if spec.needles.len() != ty.needles() {
        return Err(StitchError::new(
            format!("stitch {}", ty.number()),
            format!(
                "it has {} needle(s) but {} were given; give one [[stitch.needles]] entry per needle",
                ty.needles(),
                spec.needles.len()
            ),
        )
        .into());
    }
    Ok(())
}

/// The organs' motions usable, and an overedge stitch's width and edge
/// split in range.
fn check_organs(spec: &StitchSpec) -> Result<(), Error> {
    let ty = spec.stitch_type;
    for n in &spec.needles {
        check_motion(&format!("needle {}: the eye", n.name), &n.eye)?;
    }
    if let Some(looper) = &spec.looper {
        check_motion("the looper's catching point", &looper.eye)?;
    }
    if let Some(u) = spec.upper_looper.as_ref().filter(|_| ty == StitchType::S504) {
        check_motion("the upper looper's eye", &u.eye)?;
    }
    if let Some(sp) = spec.spreader.as_ref().filter(|_| ty == StitchType::S503) {
        check_motion("the spreader", &sp.eye)?;
    }
    // Chain stitches do not use the overedge width or the edge split.
    let overedge = matches!(ty, StitchType::S503 | StitchType::S504);
    if overedge && !(spec.a_e_mm.is_finite() && spec.a_e_mm > 0.0) {
        return Err(StitchError::new(
            format!("stitch {}", ty.number()),
            format!("the overedge width a_e = {} mm must be > 0 (e.g. 4)", spec.a_e_mm),
        )
        .into());
    }
    if overedge && !(0.0..=1.0).contains(&spec.edge_split) {
        return Err(StitchError::new(
            format!("stitch {}", ty.number()),
            format!(
                "the edge split e = {} must be in [0, 1] (0.5: the looper threads meet mid-edge)",
                spec.edge_split
            ),
        )
        .into());
    }
    Ok(())
}

/// A contour's columns over a φ_c grid: η (the right limit) and, for a
/// needle thread, the travel S, the carry angle γ (deg) and the loop on the
/// looper or the hook (mm).
struct Columns {
    eta_mm: Vec<f64>,
    travel_mm: Option<Vec<f64>>,
    gamma_deg: Option<Vec<f64>>,
    loop_mm: Option<Vec<f64>>,
}

impl Columns {
    /// The columns of `c` over `phis`: in one pass for a needle thread with
    /// its looper's organs `shared` and for the lockstitch's, point by
    /// point otherwise.
    fn of(c: &Contour, phis: &[f64], shared: Option<&SharedOrgans>) -> Result<Columns, Error> {
        Ok(match (c, shared) {
            (Contour::Needle(n), Some(shared)) => {
                let sr = n.series(phis, shared);
                Columns {
                    eta_mm: sr.eta_mm,
                    travel_mm: Some(sr.travel_mm),
                    gamma_deg: Some(sr.gamma_deg),
                    loop_mm: Some(sr.loop_mm),
                }
            }
            (Contour::Lock(n), _) => {
                let (eta_mm, travel, on_hook) = n.series(phis);
                Columns {
                    eta_mm,
                    travel_mm: Some(travel),
                    gamma_deg: None,
                    loop_mm: Some(on_hook),
                }
            }
            _ => {
                let eta_mm = phis
                    .iter()
                    .map(|&p| c.eta(p, Side::Right))
                    .collect::<Result<Vec<_>, _>>()?;
                let n = c.needle();
                Columns {
                    eta_mm,
                    travel_mm: n.map(|n| phis.iter().map(|&p| n.travel(p)).collect()),
                    gamma_deg: n.map(|n| phis.iter().map(|&p| n.carry.gamma(p).to_degrees()).collect()),
                    loop_mm: n.map(|n| phis.iter().map(|&p| n.loop_on_looper(p)).collect()),
                }
            }
        })
    }
}

/// One thread's required take-up over `phis` (φ_c, wrapped) from its
/// contour `c`: η, P' = η − η(φ0) shifted by the regulator's draw, the
/// events, and for a needle thread its travel, carry angle and loop.
fn required_thread(
    (name, role, contour, c): &(String, ThreadRole, u8, Contour),
    per_stitch_mm: f64,
    tight: f64,
    regulator: Regulator,
    phis: &[f64],
    phi0: f64,
    shared: Option<&SharedOrgans>,
) -> Result<RequiredThread, Error> {
    let Columns {
        eta_mm,
        travel_mm,
        gamma_deg,
        loop_mm,
    } = Columns::of(c, phis, shared)?;
    let eta0 = c.eta(phi0, Side::Right)?;
    let lock = c.lock();
    let window = regulator_window(regulator, tight, phi0)
        .map_err(|e| Error::Stitch(StitchError::new(format!("thread {name}"), e.to_string())))?;
    let pprime_mm: Vec<f64> = eta_mm
        .iter()
        .zip(phis)
        .map(|(e, &p)| e - eta0 + regulator_shift(window, per_stitch_mm, lock, phi0, p))
        .collect();
    let events = c
        .events()
        .into_iter()
        .map(|(ev, phi, kind)| {
            Ok(Event {
                name: ev,
                phi_c_deg: phi,
                kind,
                eta_left_mm: c.eta(phi, Side::Left)?,
                eta_right_mm: c.eta(phi, Side::Right)?,
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let (cut_mm, released_mm) = (c.cut(), c.released());
    // σ_snap: J_L = −L_s − ρ + σ_snap (§3.3).
    let snap_mm = c.eta(lock, Side::Right)? - c.eta(lock, Side::Left)? + cut_mm + released_mm;
    // The looper's catch and drop checks: not the lockstitch's hook.
    let needle_moments = c.needle().map(NeedleThread::moments_for_checks);
    // The eye is in the material from φ_in (entering) to φ_out (leaving),
    // across the needle's BDC (φ_c = 0).
    let in_material = |(out, inn): (f64, f64)| phis.iter().map(|&p| p < out || p > inn).collect();
    let eye_in_material = match c {
        Contour::Lock(n) => Some(in_material((n.phi_out, n.phi_in))),
        _ => c.needle().map(|n| in_material((n.phi_out, n.phi_in))),
    };
    let thread = RequiredThread {
        name: name.clone(),
        role: *role,
        contour: *contour,
        per_stitch_mm,
        lock_deg: lock,
        tight_deg: tight,
        eye_in_material,
        cut_mm,
        released_mm,
        snap_mm,
        piece: phis.iter().map(|&p| c.piece(p)).collect(),
        eta_mm,
        pprime_mm,
        travel_mm,
        gamma_deg,
        loop_mm,
        needle_moments,
        hook_moments: match c {
            Contour::Lock(n) => Some(n.moments_for_checks()),
            _ => None,
        },
        regulator_window_deg: window,
        events,
    };
    check_finite(&thread, phis)?;
    Ok(thread)
}

/// A thread's regulator window, φ_c [from, to] deg with from in [0, 360)
/// and to − from in (0, 360), for the moment its stitch is pulled tight
/// `tight` and φ0 (both φ_c); `None` at the lock. A window with φ0 strictly
/// inside is an error: P' is 0 at φ0 and the draw must not straddle it.
fn regulator_window(reg: Regulator, tight: f64, phi0: f64) -> Result<Option<[f64; 2]>, String> {
    let (from, width) = match reg {
        // A computed window is the thread's tension's, known per cycle: P'
        // is built at the lock here and drawn over it there.
        Regulator::AtLock | Regulator::Computed => return Ok(None),
        Regulator::BeforeTightening { width_deg } => (tight - width_deg, width_deg),
        Regulator::Window { from_deg, to_deg } => (from_deg, to_deg - from_deg),
    };
    if !(from.is_finite() && width.is_finite() && width > 0.0 && width < 360.0) {
        return Err(format!(
            "the regulator window must span between 0° and 360° (it spans {width}°); e.g. the last 60° before the stitch is pulled tight"
        ));
    }
    let from = wrap(from);
    if since_phi0(from, phi0) + width > 360.0 + 1e-9 {
        return Err(format!(
            "the regulator window φ_c {from:.2}°…{:.2}° contains φ0 = {phi0:.2}°, where P' = 0; end the window at φ0 or before \
             it, or move φ0 (`[thread] phi0_deg`) out of it",
            wrap(from + width)
        ));
    }
    Ok(Some([from, from + width]))
}

/// L_s·(H_L(φ) − w(φ)) (§3.3): the stitch's thread `l_s` given back at the
/// lock φ_L (H_L = 1 from the lock on) and drawn through the regulator over
/// `window` (w rising 0 → 1 across it), both counted from φ0 in the cycle's
/// order, so P' stays 0 at φ0 and periodic. 0 without a window (the
/// regulator passes L_s at the lock, where η already drops by it).
fn regulator_shift(window: Option<[f64; 2]>, l_s: f64, lock: f64, phi0: f64, phi: f64) -> f64 {
    let Some([from, to]) = window else { return 0.0 };
    let t = since_phi0(phi, phi0);
    // A lock at φ0 itself comes at the end of the cycle.
    let t_lock = match since_phi0(lock, phi0) {
        0.0 => 360.0,
        x => x,
    };
    let given_back = if t >= t_lock { 1.0 } else { 0.0 };
    let drawn = ((t - since_phi0(from, phi0)) / (to - from)).clamp(0.0, 1.0);
    l_s * (given_back - drawn)
}

/// φ − φ0 in [0, 360), deg: where φ comes in a cycle that starts at φ0 (an
/// angle within 1e-9° short of a whole turn counts as φ0 itself).
fn since_phi0(phi: f64, phi0: f64) -> f64 {
    let t = since_deg(phi, phi0);
    if t > 360.0 - 1e-9 { 0.0 } else { t }
}

/// A motion that can be evaluated over the whole cycle without a NaN or a
/// panic: finite numbers, a table covering one cycle, a polyline with points
/// and distinct low and high angles.
fn check_motion(organ: &str, motion: &Motion) -> Result<(), Error> {
    let bad = |what: String| Err(StitchError::new(organ, what).into());
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    match motion {
        Motion::Table {
            start_deg,
            step_deg,
            points,
            slopes,
        } => {
            if points.is_empty() || !(step_deg.is_finite() && *step_deg > 0.0) || !start_deg.is_finite() {
                return bad(format!(
                    "the motion table ({} points, step {step_deg}°) is empty or has no positive step",
                    points.len()
                ));
            }
            let span = points.len() as f64 * step_deg;
            if (span - 360.0).abs() > 1e-6 * 360.0 {
                return bad(format!(
                    "the motion table covers {span}° ({} points × {step_deg}°); it must cover one cycle, 360°",
                    points.len()
                ));
            }
            if let Some(m) = slopes
                && m.len() != points.len()
            {
                return bad(format!(
                    "the motion table has {} points but {} analogs; give one analog per point",
                    points.len(),
                    m.len()
                ));
            }
            let finite_at =
                |k: usize| finite(points[k].as_slice()) && slopes.as_ref().is_none_or(|m| finite(m[k].as_slice()));
            if let Some(k) = (0..points.len()).find(|&k| !finite_at(k)) {
                return bad(format!(
                    "the motion table has a non-finite point{} at φ_c = {}°",
                    if slopes.is_some() { " or analog" } else { "" },
                    start_deg + k as f64 * step_deg
                ));
            }
        }
        Motion::NeedleLaw {
            x_mm,
            eye_above_plate_mm,
            stroke_mm,
            bdc_deg,
            tilt_deg,
        } => {
            if !finite(&[*x_mm, *eye_above_plate_mm, *stroke_mm, *bdc_deg, *tilt_deg]) || *stroke_mm <= 0.0 {
                return bad("the needle law needs finite numbers and a positive stroke".into());
            }
        }
        Motion::LooperLaw {
            stroke_mm,
            far_deg,
            catch_deg,
            catch_x_mm,
            y0_mm,
            avoid_mm,
            depth_mm,
        } => {
            if !finite(&[
                *stroke_mm,
                *far_deg,
                *catch_deg,
                *catch_x_mm,
                *y0_mm,
                *avoid_mm,
                *depth_mm,
            ]) || *stroke_mm <= 0.0
            {
                return bad("the looper law needs finite numbers and a positive stroke".into());
            }
        }
        Motion::PolylineLaw {
            points,
            low_deg,
            high_deg,
        } => {
            let up = (high_deg - low_deg).rem_euclid(360.0);
            if points.is_empty() || !finite(&[*low_deg, *high_deg]) || up == 0.0 {
                return bad(format!(
                    "the polyline law needs points and distinct low and high angles (got {} points, low {low_deg}°, \
                     high {high_deg}°)",
                    points.len()
                ));
            }
            if !points.iter().all(|p| finite(p.as_slice())) {
                return bad("the polyline law has a non-finite point".into());
            }
        }
    }
    Ok(())
}

/// No NaN or infinity leaves: name the thread and φ instead.
fn check_finite(th: &RequiredThread, phis: &[f64]) -> Result<(), Error> {
    let series = [
        Some(&th.eta_mm),
        Some(&th.pprime_mm),
        th.travel_mm.as_ref(),
        th.gamma_deg.as_ref(),
        th.loop_mm.as_ref(),
    ];
    for s in series.into_iter().flatten() {
        if let Some(k) = s.iter().position(|v| !v.is_finite()) {
            return Err(StitchError::new(
                format!("thread {}", th.name),
                format!("η is not finite at φ_c = {:.2}°", phis[k]),
            )
            .into());
        }
    }
    let scalars = [th.per_stitch_mm, th.cut_mm, th.released_mm, th.snap_mm, th.lock_deg];
    let events = th
        .events
        .iter()
        .flat_map(|e| [e.eta_left_mm, e.eta_right_mm, e.phi_c_deg]);
    if scalars.into_iter().chain(events).any(|v| !v.is_finite()) {
        return Err(StitchError::new(format!("thread {}", th.name), "a lock or event value is not finite").into());
    }
    Ok(())
}

/// The reference cases of `tests/data/stitch` with their stand-in laws, for
/// the unit tests.
#[cfg(test)]
mod tests {
    use crate::stitch::reference::{altin503 as a503, altin504 as a504, mf7923d_407 as mf};
    fn altin504() -> StitchSpec {
        a504(2.5, 2.8)
    }
    fn altin503() -> StitchSpec {
        a503(2.5, 2.8)
    }
    fn mf7923d_407() -> StitchSpec {
        mf(3.0, 3.0)
    }
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn altin504_threads_locks_and_periodicity() {
        let s = altin504();
        let r = required_take_up(&s, &[0.0, 90.0, 359.999_999_999], 0.0).unwrap();
        let names: Vec<_> = r.threads.iter().map(|t| (t.name.as_str(), t.contour)).collect();
        assert_eq!(names, [("needle", 1), ("lower", 13), ("upper", 10)]);
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        for th in &r.threads {
            assert_eq!(th.pprime_mm[0], 0.0);
            // The cut recomputed from the nodes is the contour formula (§7a).
            assert_relative_eq!(th.cut_mm, th.per_stitch_mm, epsilon = 1e-12);
            // η(360⁻) = η(0⁺) (§7b).
            assert!((th.eta_mm[2] - th.eta_mm[0]).abs() < 1e-6, "{}", th.name);
            let lock = th.events.iter().find(|e| e.kind == EventKind::Lock).unwrap();
            assert_eq!(lock.phi_c_deg, th.lock_deg);
            assert!(th.snap_mm > -1e-9, "{}: snap {}", th.name, th.snap_mm);
        }
        let needle = &r.threads[0];
        assert_relative_eq!(needle.released_mm, 17.749, epsilon = 5e-4);
        assert_relative_eq!(needle.travel_mm.as_ref().unwrap()[0], 25.44, epsilon = 1e-12);
        assert_eq!(needle.piece, ["N1", "N2a", "N3b"]);
        assert!(
            r.moments
                .iter()
                .any(|(n, p)| n.contains("φ_UC") && (p - 126.6).abs() < 1e-9)
        );
    }

    #[test]
    fn the_407_has_three_needle_threads() {
        let r = required_take_up(&mf7923d_407(), &[180.0], 180.0).unwrap();
        assert_eq!(r.threads.len(), 3);
        assert!(
            r.threads
                .iter()
                .all(|t| t.role == ThreadRole::Needle && t.per_stitch_mm == 9.0)
        );
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    }

    #[test]
    fn altin503_has_a_needle_and_a_looper_thread_locked_at_the_draw_in() {
        let r = required_take_up(&altin503(), &[0.0, 315.0, 359.999_999_999], 0.0).unwrap();
        let names: Vec<_> = r.threads.iter().map(|t| (t.name.as_str(), t.role, t.contour)).collect();
        assert_eq!(
            names,
            [
                ("needle", ThreadRole::Needle, 3),
                ("looper", ThreadRole::LowerLooper, 10)
            ]
        );
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        for th in &r.threads {
            assert_relative_eq!(th.cut_mm, th.per_stitch_mm, epsilon = 1e-12);
            assert_relative_eq!(th.lock_deg, 330.0);
            assert!((th.eta_mm[2] - th.eta_mm[0]).abs() < 1e-6, "{}", th.name);
            assert_eq!(th.released_mm, 0.0);
            assert!(th.snap_mm > -1e-9, "{}: snap {}", th.name, th.snap_mm);
        }
        assert_eq!(r.threads[0].piece, ["N1", "N2d", "N3b"]);
        assert_eq!(r.threads[1].piece, ["S1", "S4", "S5"]);
        assert!(r.threads[0].travel_mm.is_some() && r.threads[1].travel_mm.is_none());
        // 18.621 + 11.383 = 30.004 mm per stitch (§6.3).
        assert_relative_eq!(
            r.threads[0].per_stitch_mm + r.threads[1].per_stitch_mm,
            30.0035111,
            epsilon = 1e-6
        );
        assert!(
            r.moments
                .iter()
                .any(|(n, p)| n.contains("φ_SC") && (p - 143.7).abs() < 1e-9)
        );
        assert!(r.moments.iter().any(|(n, p)| n.contains("lock (φ5)") && *p == 330.0));
        // A 503 without its spreader is an error that says what to add.
        let err = required_take_up(
            &StitchSpec {
                spreader: None,
                ..altin503()
            },
            &[0.0],
            0.0,
        )
        .unwrap_err();
        assert!(
            matches!(&err, Error::Stitch(_) if err.to_string().contains("503") && err.to_string().contains("[stitch.spreader]")),
            "{err}"
        );
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let s = altin504();
        assert!(required_take_up(&s, &[f64::NAN], 0.0).is_err());
        assert!(
            required_take_up(
                &StitchSpec {
                    m_mm: -1.0,
                    ..s.clone()
                },
                &[0.0],
                0.0
            )
            .is_err()
        );
        assert!(
            required_take_up(
                &StitchSpec {
                    needles: vec![],
                    ..s.clone()
                },
                &[0.0],
                0.0
            )
            .is_err()
        );
        let err = required_take_up(
            &StitchSpec {
                a_e_mm: 0.0,
                ..s.clone()
            },
            &[0.0],
            0.0,
        )
        .unwrap_err();
        assert!(matches!(&err, Error::Stitch(m) if m.message.contains("a_e")), "{err}");
        let err = required_take_up(
            &StitchSpec {
                edge_split: 1.5,
                ..s.clone()
            },
            &[0.0],
            0.0,
        )
        .unwrap_err();
        assert!(
            matches!(&err, Error::Stitch(m) if m.message.contains("edge split")),
            "{err}"
        );
        let mut empty_table = s.clone();
        empty_table.needles[0].eye = Motion::Table {
            start_deg: 0.0,
            step_deg: 0.01,
            points: Vec::new().into(),
            slopes: None,
        };
        let err = required_take_up(&empty_table, &[0.0], 0.0).unwrap_err().to_string();
        assert!(err.contains("needle needle: the eye") && err.contains("empty"), "{err}");
        let mut short_table = s.clone();
        short_table.needles[0].eye = Motion::Table {
            start_deg: 0.0,
            step_deg: 1.0,
            points: vec![crate::geometry::V3::zeros(); 90].into(),
            slopes: None,
        };
        let err = required_take_up(&short_table, &[0.0], 0.0).unwrap_err().to_string();
        assert!(err.contains("one cycle"), "{err}");
        let mut no_upper = s.clone();
        no_upper.upper_looper = None;
        let err = required_take_up(&no_upper, &[0.0], 0.0).unwrap_err().to_string();
        assert!(err.contains("upper looper"), "{err}");
    }
}
