//! A disc cam driving a follower: translating (with an offset) or rocking;
//! knife-edge, roller or flat-faced; closed by a spring or by a groove
//! (seed 004 §2.7, variants 1–6; §1.3's grooved cam).
//!
//! The cam is given as its follower's **lift** over the cam angle δ, as cam
//! makers give it: a lift table (a periodic cubic spline) or segments of
//! motion laws (dwell, cycloidal, simple harmonic, 3-4-5 polynomial). δ is
//! the angle of the direction from the cam's centre to a point turning with
//! it (`marker`), less `zero`. The profile the follower rides is what the
//! lift and the follower's geometry make of it (its pitch curve: the path
//! of the roller's centre, or the knife edge, in the cam's own frame), so
//! the follower's position is closed form at every φ:
//!
//! - translating, axis along `u` at `offset` e to the left of the cam's
//!   centre C: the roller centre `R = C + e·perp(u) + (y0 + s(δ))·u`,
//!   `y0 = √((r_b + r_r)² − e²)` (r_b the base circle, r_r the roller; a
//!   knife edge has r_r = 0; a flat face stands at `r_b + s` from C, its
//!   foot on the axis);
//! - rocking, arm `l` from the pivot O: at zero lift the roller centre
//!   touches the base circle (`|R0 − C| = r_b + r_r`, `|R0 − O| = l`, the
//!   branch picks the side); the arm turns from there by the lift, the way
//!   that takes the roller away from the cam.
//!
//! [`CamFollower::state`] gives the figures the cam checks read: the
//! pressure angle (between the contact normal and the follower's motion),
//! the radius of curvature of the working profile, and for a spring-closed
//! follower the force that keeps it on the cam.

use super::NoAssembly;
use super::rrr::rrr;
use crate::geometry::{V2, cross2, perp};
use crate::numeric::PeriodicCubic;
use crate::scalar::Real;
use nalgebra::ComplexField;
use num_dual::Dual2_64;
use std::f64::consts::TAU;
use std::sync::Arc;

/// A motion law of one rise or return: the fraction f(u) of the step done
/// at the fraction u of the segment's angle, with f(0) = 0, f(1) = 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Law {
    /// f = u − sin(2πu)/2π: zero velocity and acceleration at both ends.
    Cycloidal,
    /// f = (1 − cos πu)/2: zero velocity at both ends, acceleration jumps.
    Harmonic,
    /// f = 10u³ − 15u⁴ + 6u⁵: zero velocity and acceleration at both ends.
    Polynomial345,
}

impl Law {
    pub const NAMES: [&'static str; 3] = ["cycloidal", "harmonic", "polynomial_345"];

    pub fn from_name(s: &str) -> Option<Law> {
        match s {
            "cycloidal" => Some(Law::Cycloidal),
            "harmonic" => Some(Law::Harmonic),
            "polynomial_345" => Some(Law::Polynomial345),
            _ => None,
        }
    }

    /// f(u), generic.
    pub fn fraction<T: Real>(self, u: T) -> T {
        match self {
            Law::Cycloidal => u - (u * T::cst(TAU)).sin() / T::cst(TAU),
            Law::Harmonic => (T::one() - (u * T::cst(std::f64::consts::PI)).cos()).times(0.5),
            Law::Polynomial345 => {
                let u3 = u * u * u;
                u3 * (T::cst(10.0) + u * (T::cst(-15.0) + u * T::cst(6.0)))
            }
        }
    }
}

/// One segment of a lift over the cam angle: from `from` to `to` (rad) the
/// lift goes from `s0` to `s1` by `law` (a dwell when they are equal).
#[derive(Debug, Clone, PartialEq)]
pub struct Segment<T: Real> {
    pub from: f64,
    pub to: f64,
    pub s0: T,
    pub s1: T,
    pub law: Law,
}

/// The follower's lift over the cam angle δ (rad): mm for a translating
/// follower, rad for a rocking one.
#[derive(Debug, Clone, PartialEq)]
pub enum Lift<T: Real> {
    /// A periodic cubic spline through a lift table.
    Table(Arc<PeriodicCubic>),
    /// Segments covering one turn from δ = 0 in order.
    Segments(Vec<Segment<T>>),
}

impl<T: Real> Lift<T> {
    /// s(δ); `delta` may carry derivatives (with respect to φ, or to the cam
    /// angle itself).
    pub fn at(&self, delta: T) -> T {
        let turns = (delta.re() / TAU).floor();
        let d = delta - T::cst(turns * TAU);
        match self {
            Lift::Table(spline) => spline.eval(d),
            Lift::Segments(segs) => {
                let x = d.re();
                let seg = segs
                    .iter()
                    .find(|s| x < s.to)
                    .unwrap_or_else(|| segs.last().expect("a lift has segments"));
                let u = (d - T::cst(seg.from)) / T::cst(seg.to - seg.from);
                seg.s0 + (seg.s1 - seg.s0) * seg.law.fraction(u)
            }
        }
    }

    /// The same lift over another number type (`f` maps each number).
    pub fn map<U: Real>(&self, f: impl Fn(T) -> U) -> Lift<U> {
        match self {
            Lift::Table(s) => Lift::Table(s.clone()),
            Lift::Segments(segs) => Lift::Segments(
                segs.iter()
                    .map(|s| Segment {
                        from: s.from,
                        to: s.to,
                        s0: f(s.s0),
                        s1: f(s.s1),
                        law: s.law,
                    })
                    .collect(),
            ),
        }
    }
}

/// Where the follower touches the cam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Contact<T: Real> {
    Knife,
    /// A roller of this radius, mm.
    Roller(T),
    /// A flat face square to a translating follower's axis.
    Flat,
}

impl<T: Real> Contact<T> {
    fn roller(&self) -> T {
        match self {
            Contact::Roller(r) => *r,
            _ => T::zero(),
        }
    }
}

/// How the follower moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion<T: Real> {
    /// Along the unit direction `u` (in the plane), its axis `offset` mm to
    /// the left of the cam's centre.
    Translating { u: V2<T>, offset: T },
    /// On an arm of length `arm` mm about the pivot; `sign` +1 puts the
    /// roller left of the line from the pivot to the cam's centre. A flat
    /// face on the arm lies `face_offset` mm from the pivot (0 for a
    /// roller or knife edge), its point `arm` mm along the face from the
    /// foot of the pivot's perpendicular.
    Rocking { arm: T, sign: f64, face_offset: T },
}

/// The spring that holds a force-closed follower on its cam, and the
/// follower's mass it must hold against.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// Force at zero lift, N.
    pub preload_n: f64,
    /// Rate, N per mm of the follower's travel at the roller.
    pub rate_n_per_mm: f64,
    /// The follower's mass moved at the roller, kg (a rocking follower's
    /// moment of inertia over its arm squared).
    pub mass_kg: f64,
}

/// How the follower is kept on the cam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Closure {
    /// A spring (force closure); `None` when its figures are not given.
    Spring(Option<Spring>),
    /// A groove or conjugate cams (form closure): the roller is held both
    /// ways, and both flanks must be cut.
    Groove,
}

/// A cam and its follower, resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct CamFollower<T: Real> {
    /// Base circle radius r_b, mm: the profile's least radius.
    pub base: T,
    pub contact: Contact<T>,
    pub motion: Motion<T>,
    pub lift: Lift<T>,
    /// Cam angle 0: the direction from the centre to the marker, rad.
    pub zero: T,
    pub closure: Closure,
}

impl<T: Real> CamFollower<T> {
    /// The same cam and follower as plain numbers of another type (what it
    /// was resolved from is dropped: the checks differentiate over the cam
    /// angle alone).
    pub fn constant<U: Real>(&self) -> CamFollower<U> {
        let c = |x: T| U::cst(x.re());
        CamFollower {
            base: c(self.base),
            contact: match self.contact {
                Contact::Knife => Contact::Knife,
                Contact::Roller(r) => Contact::Roller(c(r)),
                Contact::Flat => Contact::Flat,
            },
            motion: match self.motion {
                Motion::Translating { u, offset } => Motion::Translating {
                    u: u.map(c),
                    offset: c(offset),
                },
                Motion::Rocking { arm, sign, face_offset } => Motion::Rocking {
                    arm: c(arm),
                    sign,
                    face_offset: c(face_offset),
                },
            },
            lift: self.lift.map(c),
            zero: c(self.zero),
            closure: self.closure,
        }
    }

    /// The cam angle δ (rad) with the cam's centre at `c` and its marker at `k`.
    pub fn cam_angle(&self, c: V2<T>, k: V2<T>) -> Result<T, NoAssembly> {
        let d = k - c;
        if d.norm_squared().re() <= 0.0 {
            return Err(NoAssembly::coincident("the cam's centre and its marker"));
        }
        Ok(d.y.angle_of(d.x) - self.zero)
    }

    /// The follower's point (roller centre, knife edge, or the flat face's
    /// foot on the axis) with the cam's centre at `c`, the cam angle `delta`
    /// and, for a rocking follower, its pivot at `o`.
    pub fn point_at(&self, c: V2<T>, delta: T, o: Option<V2<T>>) -> Result<V2<T>, NoAssembly> {
        let s = self.lift.at(delta);
        let rc = self.base + self.contact.roller();
        match (self.motion, o) {
            (Motion::Translating { u, offset }, _) => {
                if matches!(self.contact, Contact::Flat) {
                    return Ok(c + perp(u) * offset + u * (self.base + s));
                }
                let y0sq = rc * rc - offset * offset;
                if y0sq.re() <= 0.0 {
                    return Err(NoAssembly::new(
                        offset.re().abs() - rc.re(),
                        format!(
                            "the follower's axis passes {:.4} mm from the cam's centre, outside the base circle plus roller ({:.4} mm)",
                            offset.re().abs(),
                            rc.re()
                        ),
                    ));
                }
                Ok(c + perp(u) * offset + u * (y0sq.sqrt() + s))
            }
            (Motion::Rocking { arm, sign, face_offset }, Some(o)) if matches!(self.contact, Contact::Flat) => {
                let (n, e) = self.flat_face(c, o, s, sign, face_offset)?;
                Ok(o + n * face_offset + e * arm)
            }
            (Motion::Rocking { arm, sign, .. }, Some(o)) => {
                // Zero lift: the roller on the base circle (an RRR triangle).
                let r0 = rrr(o, c, arm * arm, rc * rc, sign).map_err(|e| {
                    let d = (o - c).norm().re();
                    NoAssembly::new(
                        e.defect_mm,
                        format!(
                            "the follower's arm ({:.4} mm) cannot put its roller on the base circle plus roller ({:.4} mm) from its pivot {d:.4} mm from the cam's centre",
                            arm.re(),
                            rc.re()
                        ),
                    )
                })?;
                let a0 = r0 - o;
                let beta0 = a0.y.angle_of(a0.x);
                // Turn the way that takes the roller away from the cam.
                let away = if cross2(a0, r0 - c).re() >= 0.0 { 1.0 } else { -1.0 };
                let beta = beta0 + s.times(away);
                let (sb, cb) = beta.sin_cos();
                Ok(o + V2::new(cb, sb) * arm)
            }
            (Motion::Rocking { .. }, None) => unreachable!("a rocking follower is resolved with its pivot"),
        }
    }

    /// A rocking flat face's unit normal n (from the cam toward the face)
    /// and its direction e along the face (toward the cam's side), at lift
    /// `s` (rad). The face is the line n·(X − O) = f, f = `face_offset`;
    /// the cam's centre lies p = f − n·(C − O) from it, on the −n side. At
    /// zero lift p = r_b: with D = C − O, n·D = f − r_b, so n's angle is
    /// γ ± acos((f − r_b)/|D|) (γ the angle of D, ± the `sign`), and a lift
    /// turns n by s the same way, taking the face away from the cam.
    fn flat_face(&self, c: V2<T>, o: V2<T>, s: T, sign: f64, face_offset: T) -> Result<(V2<T>, V2<T>), NoAssembly> {
        let d = c - o;
        let dist = d.norm();
        let cos_n = (face_offset - self.base) / dist;
        if cos_n.re().abs() > 1.0 {
            return Err(NoAssembly::new(
                cos_n.re().abs() - 1.0,
                format!(
                    "the flat face {:.4} mm from its pivot cannot rest on the base circle ({:.4} mm) of a cam {:.4} mm from the pivot",
                    face_offset.re(),
                    self.base.re(),
                    dist.re()
                ),
            ));
        }
        let gamma = d.y.angle_of(d.x);
        let beta_n0 = gamma + cos_n.acos().times(sign);
        let (sn0, cn0) = beta_n0.sin_cos();
        // e along the face, toward the side the cam is on at zero lift.
        let side = if (d.x * sn0 - d.y * cn0).re() >= 0.0 { 1.0 } else { -1.0 };
        let (sn, cn) = (beta_n0 + s.times(sign)).sin_cos();
        Ok((V2::new(cn, sn), V2::new(sn.times(side), cn.times(-side))))
    }

    /// The follower's point at one position of the mechanism.
    pub fn point(&self, c: V2<T>, k: V2<T>, o: Option<V2<T>>) -> Result<V2<T>, NoAssembly> {
        let delta = self.cam_angle(c, k)?;
        self.point_at(c, delta, o)
    }
}

/// A rocking flat face where it touches the cam ([`CamFollower::flat_support`]).
struct FlatSupport {
    /// The face's unit normal, from the cam toward the face.
    n: V2<f64>,
    /// The point of contact, mm.
    contact: V2<f64>,
    /// The profile's radius of curvature there, mm.
    rho: f64,
    /// The lift with its first and second analogs over the cam angle.
    s: Dual2_64,
}

/// A cam's outlines as it stands at cam angle 0, mm from its centre in
/// the plane of motion ([`CamFollower::outline`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CamOutline {
    /// The follower's point's path round the cam (empty for a flat face).
    pub pitch: Vec<V2<f64>>,
    /// The surface the follower rides.
    pub profile: Vec<V2<f64>>,
    /// A groove's outer flank (empty otherwise).
    pub outer: Vec<V2<f64>>,
}

/// The figures of the cam checks at one cam angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CamState {
    /// Between the contact normal and the follower's motion, deg.
    pub pressure_deg: f64,
    /// Radius of curvature of the pitch curve (the roller centre's path in
    /// the cam's frame), mm, positive where the cam is convex; for a flat
    /// face, of the profile itself.
    pub pitch_radius_mm: f64,
    /// The working profile's radius there (pitch less roller), mm.
    pub profile_radius_mm: f64,
    /// The lift's first and second derivatives over the cam angle (mm/rad,
    /// mm/rad²; a rocking follower's at the roller, arm × rad).
    pub ds_mm: f64,
    pub dds_mm: f64,
    /// The follower's travel at the roller from zero lift, mm.
    pub travel_mm: f64,
}

impl CamFollower<f64> {
    /// The direction in which a rocking follower's cam centre moves back
    /// when its base circle grows, the arm's angles kept: from the roller's
    /// (knife edge's) rest point R₀ through the cam's centre, so R₀ stays on
    /// the arm's circle and on the grown base circle plus roller, on the
    /// same branch (the triangle pivot–centre–R₀ keeps its orientation);
    /// for a flat face along −n₀, its normal at zero lift, which keeps
    /// n₀·(C − O) = f − r_b. `None` for a translating follower.
    pub fn rocking_retreat(&self, c: V2<f64>, o: V2<f64>) -> Result<Option<V2<f64>>, NoAssembly> {
        let Motion::Rocking { arm, sign, face_offset } = self.motion else {
            return Ok(None);
        };
        if matches!(self.contact, Contact::Flat) {
            let (n0, _) = self.flat_face(c, o, 0.0, sign, face_offset)?;
            return Ok(Some(-n0));
        }
        let rc = self.base + self.contact.roller();
        let r0 = rrr(o, c, arm * arm, rc * rc, sign).map_err(|e| {
            NoAssembly::new(
                e.defect_mm,
                "the follower's arm cannot put its roller on the base circle plus roller".to_string(),
            )
        })?;
        let d = c - r0;
        Ok(Some(d * (1.0 / d.norm())))
    }

    /// The checks' figures at cam angle `delta` (rad), the cam's centre at
    /// `c` and a rocking follower's pivot at `o`: the follower's point is
    /// differentiated over the cam angle (the follower's guide held fixed
    /// relative to the cam's shaft, as on a machine).
    pub fn state(&self, c: V2<f64>, delta: f64, o: Option<V2<f64>>) -> Result<CamState, NoAssembly> {
        if let (Contact::Flat, Motion::Rocking { arm, .. }, Some(o)) = (self.contact, self.motion, o) {
            let f = self.flat_support(c, delta, o)?;
            // The force acts along n at the contact; the arm moves the
            // contact point square to its radius from the pivot.
            let r = f.contact - o;
            let along = (f.n.dot(&perp(r)).abs() / r.norm()).min(1.0);
            return Ok(CamState {
                pressure_deg: along.acos().to_degrees(),
                pitch_radius_mm: f.rho,
                profile_radius_mm: f.rho,
                ds_mm: f.s.v1 * arm,
                dds_mm: f.s.v2 * arm,
                travel_mm: f.s.re * arm,
            });
        }
        let me = self.constant::<Dual2_64>();
        let d = Dual2_64::new(delta, 1.0, 0.0);
        let cd = c.map(Dual2_64::from_re);
        let od = o.map(|o| o.map(Dual2_64::from_re));
        let r = me.point_at(cd, d, od)?;
        let s = me.lift.at(d);
        // The pitch curve in the cam's frame: Q(δ) = Rot(−δ)(R − C).
        let (sn, cs) = d.sin_cos();
        let w = r - cd;
        let q = V2::new(w.x * cs + w.y * sn, w.y * cs - w.x * sn);
        let q1 = V2::new(q.x.v1, q.y.v1);
        let q2 = V2::new(q.x.v2, q.y.v2);
        let speed = q1.norm();
        // Q runs clockwise in the cam's frame as δ grows: a convex cam has
        // Q′ × Q″ < 0.
        let pitch = -speed.powi(3) / cross2(q1, q2);
        // The pitch curve's tangent back in the machine's frame, and the
        // way the follower's point can move.
        let t = V2::new(q1.x * cs.re - q1.y * sn.re, q1.x * sn.re + q1.y * cs.re);
        let (v, arm) = match (self.motion, o) {
            (Motion::Translating { u, .. }, _) => (u, 1.0),
            (Motion::Rocking { arm, .. }, Some(o)) => (perp(V2::new(r.x.re, r.y.re) - o), arm),
            (Motion::Rocking { .. }, None) => unreachable!("a rocking follower is resolved with its pivot"),
        };
        let (ds, dds) = (s.v1 * arm, s.v2 * arm);
        let (pressure, pitch, profile) = match self.contact {
            // A flat face square to the axis: the contact normal is the
            // axis; the profile's radius is r_b + s + s″.
            Contact::Flat => {
                let rho = self.base + s.re + s.v2;
                (0.0, rho, rho)
            }
            contact => {
                let along = t.dot(&v).abs();
                let across = cross2(t, v).abs();
                (along.atan2(across).to_degrees(), pitch, pitch - contact.roller())
            }
        };
        Ok(CamState {
            pressure_deg: pressure,
            pitch_radius_mm: pitch,
            profile_radius_mm: profile,
            ds_mm: ds,
            dds_mm: dds,
            travel_mm: s.re * arm,
        })
    }

    /// A rocking flat face on the cam at cam angle `delta` (rad): the
    /// cam's support function p(α), the distance from its centre to the
    /// face along the face's normal n at angle α in the cam's frame
    /// (α = β_n − δ), gives the contact C + p·n + p_α·n⊥ and the profile's
    /// radius of curvature ρ = p + p_αα, the derivatives over α from those
    /// over δ: p_α = p′/α′, p_αα = (p″α′ − p′α″)/α′³.
    fn flat_support(&self, c: V2<f64>, delta: f64, o: V2<f64>) -> Result<FlatSupport, NoAssembly> {
        let Motion::Rocking { sign, face_offset, .. } = self.motion else {
            unreachable!("a flat support is asked of a rocking flat face only")
        };
        let me = self.constant::<Dual2_64>();
        let d = Dual2_64::new(delta, 1.0, 0.0);
        let s = me.lift.at(d);
        let (cd, od) = (c.map(Dual2_64::from_re), o.map(Dual2_64::from_re));
        let f = Dual2_64::from_re(face_offset);
        let (n, _) = me.flat_face(cd, od, s, sign, f)?;
        let p = f - n.dot(&(cd - od));
        let alpha = n.y.angle_of(n.x) - d;
        let (a1, a2) = (alpha.v1, alpha.v2);
        if a1.abs() < 1e-9 {
            return Err(NoAssembly::new(
                0.0,
                format!(
                    "at cam angle {:.1}° the flat face turns with the cam, so it has no point of contact",
                    delta.to_degrees()
                ),
            ));
        }
        let p_a = p.v1 / a1;
        let p_aa = (p.v2 * a1 - p.v1 * a2) / a1.powi(3);
        let n0 = V2::new(n.x.re, n.y.re);
        Ok(FlatSupport {
            n: n0,
            contact: c + n0 * p.re + perp(n0) * p_a,
            rho: p.re + p_aa,
            s,
        })
    }

    /// The cam as made, as it stands at cam angle 0 (mm from its centre;
    /// at cam angle δ it is these turned by δ), `samples` points over its
    /// turn: the pitch curve (the follower's point, from
    /// [`CamFollower::point_at`], turned back by the cam angle; none for a
    /// flat face), the working profile (the pitch curve moved in along its
    /// normal by the roller; a flat face: the envelope of its lines) and a
    /// groove's outer flank (moved out by the roller). The follower's guide
    /// or pivot is held where `c` and `o` put it.
    pub fn outline(&self, c: V2<f64>, o: Option<V2<f64>>, samples: usize) -> Result<CamOutline, NoAssembly> {
        let me = self.constant::<Dual2_64>();
        let cd = c.map(Dual2_64::from_re);
        let od = o.map(|o| o.map(Dual2_64::from_re));
        let r_r = self.contact.roller();
        let n = samples.max(3);
        let mut out = CamOutline {
            pitch: Vec::with_capacity(n),
            profile: Vec::with_capacity(n),
            outer: Vec::new(),
        };
        for k in 0..n {
            let delta = k as f64 * TAU / n as f64;
            let d = Dual2_64::new(delta, 1.0, 0.0);
            let (sn, cs) = d.sin_cos();
            // Turned back into the cam's frame, at cam angle 0: Rot(−δ).
            let back = |w: V2<Dual2_64>| V2::new(w.x * cs + w.y * sn, w.y * cs - w.x * sn);
            if let (Contact::Flat, Motion::Translating { u, .. }) = (self.contact, self.motion) {
                // The face's line n·q = r_b + s; its envelope q = h·n + h′·n′.
                let h = me.base + me.lift.at(d);
                let nd = back(u.map(Dual2_64::from_re));
                let q = V2::new(h.re * nd.x.re + h.v1 * nd.x.v1, h.re * nd.y.re + h.v1 * nd.y.v1);
                out.profile.push(q);
                continue;
            }
            if let (Contact::Flat, Motion::Rocking { .. }, Some(o)) = (self.contact, self.motion, o) {
                // The envelope of the face's lines: the contact, turned back.
                let w = self.flat_support(c, delta, o)?.contact - c;
                let (sn, cs) = delta.sin_cos();
                out.profile.push(V2::new(w.x * cs + w.y * sn, w.y * cs - w.x * sn));
                continue;
            }
            let q = back(me.point_at(cd, d, od)? - cd);
            let (q0, t) = (V2::new(q.x.re, q.y.re), V2::new(q.x.v1, q.y.v1));
            let len = t.norm();
            // Q runs clockwise as δ grows: the cam is on its right.
            let inward = if len > 1e-12 {
                V2::new(t.y, -t.x) / len
            } else {
                -q0 / q0.norm().max(1e-12)
            };
            out.pitch.push(q0);
            out.profile.push(q0 + inward * r_r);
            if matches!(self.closure, Closure::Groove) && r_r > 0.0 {
                out.outer.push(q0 - inward * r_r);
            }
        }
        Ok(out)
    }

    /// A flat face as a segment to draw, its ends in the plane at cam angle
    /// `delta` (rad): a translating face across its axis, centred on its
    /// foot and wide enough for every contact (r_b + the lift's largest
    /// |s′| each side); a rocking face from the foot of the pivot's
    /// perpendicular past the contact by a fifth of the base circle.
    /// `None` for a roller or knife edge, or where the cam has no contact.
    pub fn face_segment(&self, c: V2<f64>, delta: f64, o: Option<V2<f64>>) -> Option<[V2<f64>; 2]> {
        match (self.contact, self.motion, o) {
            (Contact::Flat, Motion::Translating { u, .. }, _) => {
                let foot = self.point_at(c, delta, o).ok()?;
                let me = self.constant::<Dual2_64>();
                let widest = (0..72)
                    .map(|k| me.lift.at(Dual2_64::new(k as f64 * TAU / 72.0, 1.0, 0.0)).v1.abs())
                    .fold(0.0, f64::max);
                let w = perp(u) * (self.base + widest);
                Some([foot - w, foot + w])
            }
            (Contact::Flat, Motion::Rocking { face_offset, .. }, Some(o)) => {
                let f = self.flat_support(c, delta, o).ok()?;
                let foot = o + f.n * face_offset;
                let along = f.contact - foot;
                let len = along.norm();
                let dir = if len > 1e-12 { along / len } else { perp(f.n) };
                Some([foot, f.contact + dir * (0.2 * self.base)])
            }
            _ => None,
        }
    }

    /// The radius the roller's working flank has at a pitch radius: where
    /// the cam is convex (pitch > 0) the profile is the pitch less the
    /// roller (an undercut below zero); where it is concave, a groove's
    /// outer flank is the pitch's magnitude less the roller. `None` where
    /// the closure leaves that side uncut (a spring-closed cam's concave
    /// part has the roller on its outside, which always fits).
    pub fn flank_radius(&self, pitch_radius_mm: f64) -> Option<f64> {
        let r_r = self.contact.roller();
        if matches!(self.contact, Contact::Flat) {
            return Some(pitch_radius_mm);
        }
        if pitch_radius_mm > 0.0 {
            Some(pitch_radius_mm - r_r)
        } else if matches!(self.closure, Closure::Groove) && r_r > 0.0 {
            Some(-pitch_radius_mm - r_r)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn rise_return(law: Law) -> Lift<f64> {
        let r = |d: f64| d.to_radians();
        Lift::Segments(vec![
            Segment {
                from: 0.0,
                to: r(120.0),
                s0: 0.0,
                s1: 8.0,
                law,
            },
            Segment {
                from: r(120.0),
                to: r(180.0),
                s0: 8.0,
                s1: 8.0,
                law,
            },
            Segment {
                from: r(180.0),
                to: r(300.0),
                s0: 8.0,
                s1: 0.0,
                law,
            },
            Segment {
                from: r(300.0),
                to: TAU,
                s0: 0.0,
                s1: 0.0,
                law,
            },
        ])
    }

    fn translating(lift: Lift<f64>, offset: f64, contact: Contact<f64>) -> CamFollower<f64> {
        CamFollower {
            base: 20.0,
            contact,
            motion: Motion::Translating {
                u: V2::new(0.0, 1.0),
                offset,
            },
            lift,
            zero: 0.0,
            closure: Closure::Spring(None),
        }
    }

    #[test]
    fn motion_laws_start_and_end_at_rest_where_they_should() {
        for law in [Law::Cycloidal, Law::Harmonic, Law::Polynomial345] {
            let f = |u: f64| law.fraction(Dual2_64::new(u, 1.0, 0.0));
            assert_relative_eq!(f(0.0).re, 0.0, epsilon = 1e-15);
            assert_relative_eq!(f(1.0).re, 1.0, epsilon = 1e-15);
            assert_relative_eq!(f(0.0).v1, 0.0, epsilon = 1e-12);
            assert_relative_eq!(f(1.0).v1, 0.0, epsilon = 1e-12);
            if law != Law::Harmonic {
                assert_relative_eq!(f(0.0).v2, 0.0, epsilon = 1e-12);
                assert_relative_eq!(f(1.0).v2, 0.0, epsilon = 1e-12);
            }
            assert_relative_eq!(f(0.5).re, 0.5, epsilon = 1e-12);
        }
        // The 3-4-5 law's peak velocity is 15/8 of the mean, the cycloidal's 2.
        assert_relative_eq!(
            Law::Polynomial345.fraction(Dual2_64::new(0.5, 1.0, 0.0)).v1,
            1.875,
            epsilon = 1e-12
        );
        assert_relative_eq!(
            Law::Cycloidal.fraction(Dual2_64::new(0.5, 1.0, 0.0)).v1,
            2.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn a_translating_roller_rides_at_base_plus_roller_plus_lift() {
        let cf = translating(rise_return(Law::Cycloidal), 0.0, Contact::Roller(5.0));
        let c = V2::new(1.0, 2.0);
        // Cam angle 0: zero lift; 120°: full rise; 150°: the dwell.
        for (deg, s) in [(0.0f64, 0.0), (120.0, 8.0), (150.0, 8.0), (240.0, 4.0)] {
            let p = cf.point_at(c, deg.to_radians(), None).unwrap();
            assert_relative_eq!(p.x, 1.0, epsilon = 1e-12);
            assert_relative_eq!(p.y, 2.0 + 25.0 + s, epsilon = 1e-12);
        }
        // With an offset the axis moves over and y0 shrinks.
        let off = translating(rise_return(Law::Cycloidal), 7.0, Contact::Roller(5.0));
        let p = off.point_at(c, 0.0, None).unwrap();
        assert_relative_eq!(p.x, 1.0 - 7.0, epsilon = 1e-12);
        assert_relative_eq!(p.y, 2.0 + (25.0f64 * 25.0 - 49.0).sqrt(), epsilon = 1e-12);
        // An offset beyond the base circle plus roller has no assembly.
        let far = translating(rise_return(Law::Cycloidal), 26.0, Contact::Roller(5.0));
        let e = far.point_at(c, 0.0, None).unwrap_err();
        assert!(e.message.contains("outside the base circle"), "{}", e.message);
    }

    #[test]
    fn the_base_circle_dwell_has_zero_pressure_angle_and_its_own_radius() {
        let cf = translating(rise_return(Law::Cycloidal), 0.0, Contact::Roller(5.0));
        let st = cf.state(V2::zeros(), 330f64.to_radians(), None).unwrap();
        assert_relative_eq!(st.pressure_deg, 0.0, epsilon = 1e-9);
        assert_relative_eq!(st.pitch_radius_mm, 25.0, epsilon = 1e-9);
        assert_relative_eq!(st.profile_radius_mm, 20.0, epsilon = 1e-9);
        // On the dwell at full lift: the pitch radius is base + roller + rise.
        let top = cf.state(V2::zeros(), 150f64.to_radians(), None).unwrap();
        assert_relative_eq!(top.pitch_radius_mm, 33.0, epsilon = 1e-9);
    }

    #[test]
    fn the_pressure_angle_of_an_offset_translating_follower_is_the_textbook_one() {
        // tan α = (s′ − e) / (y0 + s) for an axis e to the left, the cam
        // turning counter-clockwise (δ growing).
        let cf = translating(rise_return(Law::Harmonic), 4.0, Contact::Roller(5.0));
        for deg in [20.0f64, 60.0, 100.0, 200.0, 260.0] {
            let d = deg.to_radians();
            let st = cf.state(V2::zeros(), d, None).unwrap();
            let s = cf.lift.map(Dual2_64::from_re).at(Dual2_64::new(d, 1.0, 0.0));
            let y0 = (25.0f64 * 25.0 - 16.0).sqrt();
            let want = ((s.v1 + 4.0) / (y0 + s.re)).atan().to_degrees().abs();
            let want2 = ((s.v1 - 4.0) / (y0 + s.re)).atan().to_degrees().abs();
            assert!(
                (st.pressure_deg - want).abs() < 1e-9 || (st.pressure_deg - want2).abs() < 1e-9,
                "{deg}: {} vs {want} or {want2}",
                st.pressure_deg
            );
        }
    }

    #[test]
    fn a_flat_face_needs_base_plus_lift_plus_its_second_derivative_positive() {
        let cf = translating(rise_return(Law::Harmonic), 0.0, Contact::Flat);
        let d = 60f64.to_radians();
        let st = cf.state(V2::zeros(), d, None).unwrap();
        let s = cf.lift.map(Dual2_64::from_re).at(Dual2_64::new(d, 1.0, 0.0));
        assert_relative_eq!(st.profile_radius_mm, 20.0 + s.re + s.v2, epsilon = 1e-12);
        assert_eq!(st.pressure_deg, 0.0);
        // A small base circle under a steep rise goes concave: a flat face
        // cannot follow it.
        let mut small = cf.clone();
        small.base = 0.5;
        let worst = (0..360)
            .map(|k| {
                small
                    .state(V2::zeros(), (k as f64).to_radians(), None)
                    .unwrap()
                    .profile_radius_mm
            })
            .fold(f64::MAX, f64::min);
        assert!(worst < 0.0, "{worst}");
    }

    #[test]
    fn a_rocking_roller_starts_on_the_base_circle_and_lifts_away() {
        let cf = CamFollower {
            base: 15.0,
            contact: Contact::Roller(4.0),
            motion: Motion::Rocking {
                arm: 30.0,
                sign: 1.0,
                face_offset: 0.0,
            },
            lift: rise_return(Law::Polynomial345),
            zero: 0.0,
            closure: Closure::Groove,
        };
        let (c, o) = (V2::new(0.0, 0.0), V2::new(40.0, 10.0));
        let r0 = cf.point_at(c, 0.0, Some(o)).unwrap();
        assert_relative_eq!((r0 - c).norm(), 19.0, epsilon = 1e-9);
        assert_relative_eq!((r0 - o).norm(), 30.0, epsilon = 1e-9);
        // Lifted by 8 (rad, as resolved) scaled down: use a real angle.
        let mut small = cf.clone();
        small.lift = Lift::Segments(vec![Segment {
            from: 0.0,
            to: TAU,
            s0: 0.0,
            s1: 0.0,
            law: Law::Cycloidal,
        }]);
        let same = small.point_at(c, 1.0, Some(o)).unwrap();
        assert_relative_eq!((same - r0).norm(), 0.0, epsilon = 1e-12);
        let up = {
            let mut lifted = cf.clone();
            lifted.lift = rise_return(Law::Polynomial345).scaled(0.2f64.to_radians() / 8.0 * 50.0);
            lifted.point_at(c, 120f64.to_radians(), Some(o)).unwrap()
        };
        assert!((up - c).norm() > 19.0, "the lift takes the roller away from the cam");
        assert_relative_eq!((up - o).norm(), 30.0, epsilon = 1e-9);
    }

    #[test]
    fn analogs_over_the_cam_angle_equal_finite_differences() {
        let cf = CamFollower {
            base: 15.0,
            contact: Contact::Roller(4.0),
            motion: Motion::Rocking {
                arm: 30.0,
                sign: -1.0,
                face_offset: 0.0,
            },
            lift: rise_return(Law::Cycloidal).scaled(20f64.to_radians() / 8.0),
            zero: 0.3,
            closure: Closure::Groove,
        };
        let o = V2::new(35.0, -12.0);
        let od = o.map(Dual2_64::from_re);
        let cfd = cf.constant::<Dual2_64>();
        let h = 1e-4;
        for deg in [30.0f64, 75.0, 200.0, 250.0] {
            let phi = deg.to_radians();
            // The marker on a unit crank at φ.
            let k = |p: f64| V2::new(p.cos(), p.sin());
            let pd = Dual2_64::new(phi, 1.0, 0.0);
            let rd = cfd.point(V2::zeros(), V2::new(pd.cos(), pd.sin()), Some(od)).unwrap();
            let r = |p: f64| cf.point(V2::zeros(), k(p), Some(o)).unwrap();
            let fd1 = (r(phi + h) - r(phi - h)) / (2.0 * h);
            let fd2 = (r(phi + h) - r(phi) * 2.0 + r(phi - h)) / (h * h);
            assert_relative_eq!(rd.x.v1, fd1.x, epsilon = 1e-6);
            assert_relative_eq!(rd.y.v1, fd1.y, epsilon = 1e-6);
            assert_relative_eq!(rd.x.v2, fd2.x, epsilon = 1e-3);
            assert_relative_eq!(rd.y.v2, fd2.y, epsilon = 1e-3);
        }
    }

    fn flat_rocking(sign: f64, face_offset: f64, rise_deg: f64) -> CamFollower<f64> {
        CamFollower {
            base: 20.0,
            contact: Contact::Flat,
            motion: Motion::Rocking {
                arm: 25.0,
                sign,
                face_offset,
            },
            lift: rise_return(Law::Cycloidal).scaled(rise_deg.to_radians() / 8.0),
            zero: 0.0,
            closure: Closure::Spring(None),
        }
    }

    #[test]
    fn a_rocking_flat_face_rests_on_the_base_circle_and_envelopes_the_profile() {
        let (c, o) = (V2::new(0.0, 0.0), V2::new(45.0, 30.0));
        for (sign, f) in [(1.0, 0.0), (-1.0, 0.0), (1.0, 6.0), (-1.0, -4.0)] {
            // At a dwell on the base circle the face is tangent to it.
            let dwell = flat_rocking(sign, f, 0.0);
            let st = dwell.state(c, 0.7, Some(o)).unwrap();
            assert_relative_eq!(st.profile_radius_mm, 20.0, epsilon = 1e-9);
            let fs = dwell.flat_support(c, 0.7, o).unwrap();
            assert_relative_eq!((fs.contact - c).norm(), 20.0, epsilon = 1e-9);
            // The contact lies on the face: n·(P − O) = f.
            assert_relative_eq!(fs.n.dot(&(fs.contact - o)), f, epsilon = 1e-9);
            // With a 12° rise: the profile is the envelope of the face's
            // lines, so every profile point lies on the cam's side of the
            // face, at most p from the centre along n, the contact on it.
            let cam = flat_rocking(sign, f, 12.0);
            let outline = cam.outline(c, Some(o), 720).unwrap();
            for deg in [10.0f64, 60.0, 100.0, 170.0, 250.0, 330.0] {
                let delta = deg.to_radians();
                let fs = cam.flat_support(c, delta, o).unwrap();
                // n and the contact turned back into the cam's frame.
                let back = |w: V2<f64>| {
                    V2::new(
                        w.x * delta.cos() + w.y * delta.sin(),
                        w.y * delta.cos() - w.x * delta.sin(),
                    )
                };
                let (n, q) = (back(fs.n), back(fs.contact - c));
                let p = n.dot(&q);
                let beyond = outline.profile.iter().map(|x| n.dot(x) - p).fold(f64::MIN, f64::max);
                assert!(beyond < 1e-3 && beyond > -1e-9, "{sign} {f} {deg}: {beyond}");
                assert!(fs.rho > 0.0);
            }
            // The face turns away from the cam as it lifts: the pivot's
            // point moves and its distance from the pivot stays.
            let r0 = cam.point_at(c, 0.0, Some(o)).unwrap();
            let r1 = cam.point_at(c, 120f64.to_radians(), Some(o)).unwrap();
            assert_relative_eq!((r0 - o).norm(), (r1 - o).norm(), epsilon = 1e-9);
            assert!((r1 - r0).norm() > 1.0);
        }
    }

    #[test]
    fn a_rocking_flat_faces_curvature_equals_the_outlines() {
        // ρ = p + p_αα against the outline's own curvature by finite
        // differences of its points (three points 0.1° of cam angle apart
        // give the contact's circle).
        let (c, o) = (V2::new(0.0, 0.0), V2::new(45.0, 30.0));
        let cam = flat_rocking(1.0, 3.0, 12.0);
        let h = 0.02f64.to_radians();
        for deg in [40.0f64, 80.0, 200.0, 300.0] {
            let pt = |d: f64| {
                let w = cam.flat_support(c, d, o).unwrap().contact - c;
                V2::new(w.x * d.cos() + w.y * d.sin(), w.y * d.cos() - w.x * d.sin())
            };
            let d = deg.to_radians();
            let (a, b, e) = (pt(d - h), pt(d), pt(d + h));
            // The circle through three points: R = |ab||be||ea| / (2|(b−a)×(e−a)|).
            let cross = ((b - a).x * (e - a).y - (b - a).y * (e - a).x).abs();
            let r = (b - a).norm() * (e - b).norm() * (a - e).norm() / (2.0 * cross);
            let rho = cam.flat_support(c, d, o).unwrap().rho;
            assert_relative_eq!(rho, r, max_relative = 1e-3);
        }
        // The analogs of the follower's point equal finite differences.
        let cfd = cam.constant::<Dual2_64>();
        let od = o.map(Dual2_64::from_re);
        for deg in [30.0f64, 75.0, 200.0] {
            let phi = deg.to_radians();
            let pd = Dual2_64::new(phi, 1.0, 0.0);
            let rd = cfd.point(V2::zeros(), V2::new(pd.cos(), pd.sin()), Some(od)).unwrap();
            let r = |p: f64| cam.point(V2::zeros(), V2::new(p.cos(), p.sin()), Some(o)).unwrap();
            let hh = 1e-4;
            let fd1 = (r(phi + hh) - r(phi - hh)) / (2.0 * hh);
            assert_relative_eq!(rd.x.v1, fd1.x, epsilon = 1e-6);
            assert_relative_eq!(rd.y.v1, fd1.y, epsilon = 1e-6);
        }
    }

    #[test]
    fn a_table_lift_is_a_smooth_periodic_spline() {
        let deg: Vec<f64> = (0..12).map(|k| (k * 30) as f64).collect();
        let mm: Vec<f64> = deg.iter().map(|d| 3.0 * (1.0 - d.to_radians().cos())).collect();
        let rad: Vec<f64> = deg.iter().map(|d| d.to_radians()).collect();
        let lift: Lift<f64> = Lift::Table(Arc::new(PeriodicCubic::new(&rad, &mm, TAU)));
        for (d, s) in rad.iter().zip(&mm) {
            assert_relative_eq!(lift.at(*d), *s, epsilon = 1e-12);
            assert_relative_eq!(lift.at(*d + TAU), *s, epsilon = 1e-12);
            assert_relative_eq!(lift.at(*d - TAU), *s, epsilon = 1e-12);
        }
        assert!((lift.at(1.0) - 3.0 * (1.0 - 1f64.cos())).abs() < 0.01);
    }

    impl Lift<f64> {
        fn scaled(&self, k: f64) -> Lift<f64> {
            self.map(|s| s * k)
        }
    }
}
