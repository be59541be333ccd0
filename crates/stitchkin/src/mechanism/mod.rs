//! The mechanism: drivers and structural groups, solved in order at each φ.
//!
//! A [`Mechanism`] is a model with every parameter resolved to a number of
//! type `T` (`f64` for positions, a dual number for exact analogs). Solving
//! at a φ fills a preallocated [`Pose`]; nothing is allocated per step.

pub mod line;
pub mod newton;
pub mod rigid;
pub mod rpr;
pub mod rrr;
pub mod rssr;

use std::sync::Arc;

use crate::geometry::{Plane, V2, V3, perp};
use crate::scalar::Real;
use newton::{NewtonGroup, NewtonState};
use rssr::Rocker;

/// A group that cannot be assembled at this position.
#[derive(Debug, Clone, PartialEq)]
pub struct NoAssembly {
    /// By how much the closure fails, mm (how far apart the two ends that
    /// should meet stay).
    pub defect_mm: f64,
    pub message: String,
}

impl NoAssembly {
    pub fn new(defect_mm: f64, message: String) -> Self {
        NoAssembly { defect_mm, message }
    }
    pub fn coincident(what: &str) -> Self {
        NoAssembly { defect_mm: 0.0, message: format!("{what} coincide, so the direction is undefined") }
    }
}

/// The main-shaft angle φ (rad) with its cosine and sine, precomputed once
/// per cycle step and shared by every driver.
#[derive(Debug, Clone, Copy)]
pub struct Phi<T: Real> {
    pub phi: T,
    pub cos: T,
    pub sin: T,
}

impl<T: Real> Phi<T> {
    pub fn new(phi: T) -> Self {
        let (sin, cos) = phi.sin_cos();
        Phi { phi, cos, sin }
    }
}

/// One solve step. Slots index [`Pose::points`].
#[derive(Debug, Clone, PartialEq)]
pub enum Step<T: Real> {
    /// Crank pin `out = center + r(cos θ·u + sin θ·v)`, θ = speed·φ + phase.
    Crank { center: usize, out: usize, r: T, u: V3<T>, v: V3<T>, speed: f64, phase: T, cos_ph: T, sin_ph: T },
    Rrr { p1: usize, p2: usize, l1: T, l2: T, sign: f64, plane: Plane<T>, out: usize },
    /// Planar RRP: slider on the line through `through` (toward `toward`, or
    /// along the fixed in-plane unit direction `dir`), offset `offset` left.
    Rrp { from: usize, through: usize, toward: Option<usize>, dir: V2<T>, offset: T, l: T, sign: f64, plane: Plane<T>, out: usize },
    Rpr { from: usize, pivot: usize, e: T, d: T, plane: Plane<T>, out: usize },
    Rssr { from: usize, rocker: Rocker<T>, zero: V3<T>, l: T, sign: f64, out: usize },
    /// Spatial point on the line through `through` (toward `toward`, or along
    /// the fixed unit direction `dir`).
    PointOnLine { from: usize, through: usize, toward: Option<usize>, dir: V3<T>, l: T, sign: f64, out: usize },
    Rigid { base: [usize; 2], dc: T, ds: T, lift: T, plane: Plane<T>, out: usize },
    Rigid3 { frame: [usize; 3], at: V3<T>, out: usize },
    Newton(Box<NewtonGroup<T>>),
}

/// A derived quantity, evaluated from a solved pose.
#[derive(Debug, Clone, PartialEq)]
pub enum MeasureStep<T: Real> {
    Distance { a: usize, b: usize },
    /// Signed in-plane distance (`plane = Some`) or unsigned 3D distance.
    LineDeviation { p: usize, h: usize, t: usize, plane: Option<Plane<T>> },
    Coordinate { p: usize, from: Option<usize>, origin: V3<T>, axis: V3<T> },
}

/// Positions of every point at one φ, plus the numerical groups' warm starts.
#[derive(Debug, Clone)]
pub struct Pose<T: Real> {
    pub points: Vec<V3<T>>,
    newton: Vec<NewtonState<T>>,
}

/// A model with every parameter resolved: ready to solve at any φ.
#[derive(Debug, Clone)]
pub struct Mechanism<T: Real> {
    pub(crate) fixed: Vec<(usize, V3<T>)>,
    pub(crate) steps: Vec<Step<T>>,
    pub(crate) measures: Vec<MeasureStep<T>>,
    pub(crate) n_points: usize,
    /// A label per step, for messages (`group "23" (rrr)`).
    pub(crate) labels: Arc<[String]>,
}

/// A position with no assembly: which group, where, and by how much.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("no assembly at φ = {phi_deg:.3}°: {group}: {message} (closure fails by {defect_mm:.4} mm)")]
pub struct AssemblyError {
    pub group: String,
    pub phi_deg: f64,
    pub defect_mm: f64,
    pub message: String,
}

impl<T: Real> Mechanism<T> {
    /// A pose with the fixed points in place and numerical groups at their
    /// starting guesses.
    pub fn new_pose(&self) -> Pose<T> {
        let mut points = vec![V3::zeros(); self.n_points];
        for (slot, p) in &self.fixed {
            points[*slot] = *p;
        }
        let newton = self
            .steps
            .iter()
            .filter_map(|s| if let Step::Newton(g) = s { Some(g.new_state()) } else { None })
            .collect();
        Pose { points, newton }
    }

    /// Solves every group at `phi`, in order, writing into `pose`.
    pub fn solve(&self, phi: &Phi<T>, pose: &mut Pose<T>) -> Result<(), AssemblyError> {
        let pts = &mut pose.points;
        let mut newton = 0;
        for (i, step) in self.steps.iter().enumerate() {
            let r = match step {
                Step::Crank { center, out, r, u, v, speed, phase, cos_ph, sin_ph } => {
                    let (c, s) = if *speed == 1.0 {
                        // cos(φ + ph), sin(φ + ph) from the shared cos φ, sin φ.
                        (phi.cos * *cos_ph - phi.sin * *sin_ph, phi.sin * *cos_ph + phi.cos * *sin_ph)
                    } else {
                        let (s, c) = (phi.phi * T::cst(*speed) + *phase).sin_cos();
                        (c, s)
                    };
                    pts[*out] = pts[*center] + (*u * c + *v * s) * *r;
                    Ok(())
                }
                Step::Rrr { p1, p2, l1, l2, sign, plane, out } => {
                    let (a, b) = (plane.project(&pts[*p1]), plane.project(&pts[*p2]));
                    rrr::rrr(a, b, *l1, *l2, *sign).map(|q| pts[*out] = plane.lift(q, T::zero()))
                }
                Step::Rrp { from, through, toward, dir, offset, l, sign, plane, out } => {
                    let h = plane.project(&pts[*through]);
                    let u = match toward {
                        Some(t) => unit2(plane.project(&pts[*t]) - h),
                        None => Ok(*dir),
                    };
                    u.and_then(|u| {
                        let a = plane.project(&pts[*from]);
                        line::point_on_line(h + perp(u) * *offset, u, a, *l, *sign)
                    })
                    .map(|q| pts[*out] = plane.lift(q, T::zero()))
                }
                Step::Rpr { from, pivot, e, d, plane, out } => {
                    let (a, c) = (plane.project(&pts[*from]), plane.project(&pts[*pivot]));
                    rpr::rpr(a, c, *e).map(|(u, _)| pts[*out] = plane.lift(c + perp(u) * *e + u * *d, T::zero()))
                }
                Step::Rssr { from, rocker, l, sign, out, .. } => {
                    rssr::rssr(rocker, pts[*from], *l, *sign).map(|b| pts[*out] = b)
                }
                Step::PointOnLine { from, through, toward, dir, l, sign, out } => {
                    let h = pts[*through];
                    let u = match toward {
                        Some(t) => unit3(pts[*t] - h),
                        None => Ok(*dir),
                    };
                    u.and_then(|u| line::point_on_line(h, u, pts[*from], *l, *sign)).map(|p| pts[*out] = p)
                }
                Step::Rigid { base, dc, ds, lift, plane, out } => {
                    let (a, b) = (plane.project(&pts[base[0]]), plane.project(&pts[base[1]]));
                    rigid::rigid_point(a, b, *dc, *ds).map(|q| pts[*out] = plane.lift(q, *lift))
                }
                Step::Rigid3 { frame, at, out } => {
                    rigid::rigid_point_3d(pts[frame[0]], pts[frame[1]], pts[frame[2]], *at).map(|p| pts[*out] = p)
                }
                Step::Newton(g) => {
                    let st = &mut pose.newton[newton];
                    newton += 1;
                    g.solve(pts, st)
                }
            };
            if let Err(e) = r {
                return Err(AssemblyError {
                    group: self.labels[i].clone(),
                    phi_deg: phi.phi.re().to_degrees(),
                    defect_mm: e.defect_mm,
                    message: e.message,
                });
            }
        }
        Ok(())
    }

    /// Transmission angle (rad) of every dyad, in [`Self::dyads`] order.
    pub fn transmission_angles(&self, pose: &Pose<T>, out: &mut Vec<T>) {
        out.clear();
        let p = &pose.points;
        for step in &self.steps {
            match step {
                Step::Rrr { p1, p2, plane, out: b, .. } => {
                    out.push(rrr::transmission(plane.project(&p[*p1]), plane.project(&p[*p2]), plane.project(&p[*b])));
                }
                Step::Rrp { from, through, toward, dir, plane, out: g, .. } => {
                    let h = plane.project(&p[*through]);
                    let u = toward.map_or(*dir, |t| unit2(plane.project(&p[t]) - h).unwrap_or(*dir));
                    out.push(line::transmission(u, plane.project(&p[*from]), plane.project(&p[*g])));
                }
                Step::Rpr { from, pivot, e, plane, .. } => {
                    out.push(rpr::transmission(plane.project(&p[*from]), plane.project(&p[*pivot]), *e));
                }
                Step::Rssr { from, rocker, out: b, .. } => out.push(rssr::transmission(rocker, p[*from], p[*b])),
                Step::PointOnLine { from, through, toward, dir, out: q, .. } => {
                    let u = toward.map_or(*dir, |t| unit3(p[t] - p[*through]).unwrap_or(*dir));
                    out.push(line::transmission(u, p[*from], p[*q]));
                }
                _ => {}
            }
        }
    }

    /// Link angles (rad) in [`Self::link_angles`] order: for RRR the two
    /// links into the output joint, for RRP the rod, for RPR the slot, for
    /// RSSR the rocker (about its axis from its zero direction).
    pub fn link_angles(&self, pose: &Pose<T>, out: &mut Vec<T>) {
        out.clear();
        let p = &pose.points;
        let ang = |plane: &Plane<T>, a: usize, b: usize| {
            let d = plane.project(&p[b]) - plane.project(&p[a]);
            d.y.atan2(d.x)
        };
        for step in &self.steps {
            match step {
                Step::Rrr { p1, p2, plane, out: b, .. } => {
                    out.push(ang(plane, *p1, *b));
                    out.push(ang(plane, *p2, *b));
                }
                Step::Rrp { from, plane, out: g, .. } => out.push(ang(plane, *from, *g)),
                Step::Rpr { pivot, plane, out: d, e, .. } => {
                    // Slot direction: from the pivot's foot toward `out`.
                    let (c, q) = (plane.project(&p[*pivot]), plane.project(&p[*d]));
                    let _ = e;
                    let dq = q - c;
                    out.push(dq.y.atan2(dq.x));
                }
                Step::Rssr { rocker, zero, out: b, .. } => {
                    let q = p[*b] - rocker.c;
                    let y = rocker.w.cross(zero);
                    out.push(q.dot(&y).atan2(q.dot(zero)));
                }
                _ => {}
            }
        }
    }

    /// Values of the model's measures (mm).
    pub fn measures(&self, pose: &Pose<T>, out: &mut Vec<T>) {
        out.clear();
        let p = &pose.points;
        for m in &self.measures {
            out.push(match m {
                MeasureStep::Distance { a, b } => crate::geometry::norm_or_zero(p[*a] - p[*b]),
                MeasureStep::LineDeviation { p: q, h, t, plane } => match plane {
                    Some(pl) => {
                        let (h, t, q) = (pl.project(&p[*h]), pl.project(&p[*t]), pl.project(&p[*q]));
                        let u = unit2(t - h).unwrap_or(V2::x());
                        crate::geometry::cross2(u, q - h)
                    }
                    None => {
                        let u = unit3(p[*t] - p[*h]).unwrap_or(V3::x());
                        crate::geometry::norm_or_zero((p[*q] - p[*h]).cross(&u))
                    }
                },
                MeasureStep::Coordinate { p: q, from, origin, axis } => {
                    let o = from.map_or(*origin, |f| p[f]);
                    (p[*q] - o).dot(axis)
                }
            });
        }
    }

    /// Number of point slots.
    pub fn n_points(&self) -> usize {
        self.n_points
    }
}

fn unit2<T: Real>(d: V2<T>) -> Result<V2<T>, NoAssembly> {
    let n = d.norm();
    if n.re() <= 0.0 {
        return Err(NoAssembly::coincident("the two points that define the guide line"));
    }
    Ok(d / n)
}

fn unit3<T: Real>(d: V3<T>) -> Result<V3<T>, NoAssembly> {
    let n = d.norm();
    if n.re() <= 0.0 {
        return Err(NoAssembly::coincident("the two points that define the guide line"));
    }
    Ok(d / n)
}
