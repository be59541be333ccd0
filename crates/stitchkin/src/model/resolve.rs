//! One setting laid on the model: every expression's value placed into
//! frames, points, solve steps, measures and thread paths, giving the
//! [`Mechanism`] that is solved at any φ. Runs once per setting, so it
//! only looks values up; every name was checked when the model was loaded.

use super::file::ContactKind;
use super::load::cam_follower::{CamFollowerDef, LiftDef, MotionDef};
use super::{
    AxisDef, CamContactDef, CamDef, ClosureDef, ClosureRef, Machine, MeasureDef, Model, PathDef, PointKind, ProfileDef,
    SpanDef, StepDef, ThreadsDef, file, stitch_setup,
};
use crate::error::ModelError;
use crate::geometry::{Placement, Plane, V2, V3, axis_rotation};
use crate::mechanism::CamStep;
use crate::mechanism::cam_follower::{CamFollower, Contact, Lift, Motion, Segment};
use crate::mechanism::newton::{Closure, NewtonGroup, PointRef};
use crate::mechanism::rssr::Rocker;
use crate::mechanism::{MeasureStep, Mechanism, Step};
use crate::scalar::Real;
use crate::thread::cam::Profile;
use crate::thread::{Cam, CamModel, Convention, Span, ThreadPath, Threads};

type Resolved<T> = Result<T, Box<ModelError>>;

/// The mechanism of `model` with the values `q` of its expressions and,
/// with `with_threads` and a model that has them, its thread paths.
pub(super) fn machine<T: Real>(model: &Model, q: &[T], with_threads: bool) -> Resolved<Machine<T>> {
    let r = Resolver {
        model,
        q,
        deg: T::cst(std::f64::consts::PI / 180.0),
        frames: resolve_frames(model, q),
    };
    let fixed = r.resolve_points();
    let steps = r.resolve_steps(&fixed)?;
    let measures = r.resolve_measures()?;
    let threads = match &model.threads {
        Some(t) if with_threads => Some(r.resolve_threads(t, &fixed)?),
        _ => None,
    };
    let mechanism = Mechanism {
        fixed,
        steps,
        measures,
        n_points: model.point_names.len(),
        labels: model.labels.clone(),
        frames: r.frames,
    };
    Ok(Machine { mechanism, threads })
}

/// Every frame placed in the world, parents first.
fn resolve_frames<T: Real>(model: &Model, q: &[T]) -> Vec<Placement<T>> {
    let deg = T::cst(std::f64::consts::PI / 180.0);
    let mut frames: Vec<Option<Placement<T>>> = vec![None; model.frames.len()];
    frames[0] = Some(Placement::identity());
    while frames.iter().any(Option::is_none) {
        for (i, f) in model.frames.iter().enumerate() {
            if frames[i].is_some() {
                continue;
            }
            let parent = f.parent.unwrap_or(0);
            let Some(pp) = frames[parent] else { continue };
            let mut rot = nalgebra::Matrix3::identity();
            for (axis, a) in &f.rotate {
                rot *= axis_rotation(*axis, q[*a] * deg);
            }
            let origin = f.origin.map_or(V3::zeros(), |o| V3::new(q[o[0]], q[o[1]], q[o[2]]));
            frames[i] = Some(Placement { rot, origin }.within(&pp));
        }
    }
    frames.into_iter().map(|f| f.expect("parents resolved above")).collect()
}

/// The values of one setting and the frames they place.
struct Resolver<'a, T: Real> {
    model: &'a Model,
    /// Every expression's value.
    q: &'a [T],
    /// π/180: degrees to radians.
    deg: T,
    frames: Vec<Placement<T>>,
}

/// The canonical key of the link between two points.
fn link(a: usize, b: usize) -> [usize; 2] {
    [a.min(b), a.max(b)]
}

/// Lengths fixed by earlier steps: a rigid point on such a link needs no
/// square root per position.
struct KnownLengths<T: Real> {
    /// In-plane distances fixed by a link: (point, point), plane, length.
    links: Vec<([usize; 2], usize, T)>,
    /// Rocker arms of RSSR groups: (pivot, ball end), axis, radius. In a
    /// plane across the axis the arm's projection keeps its length.
    arms: Vec<([usize; 2], V3<T>, T)>,
}

impl<T: Real> KnownLengths<T> {
    /// The length of the link `base` in plane `pl` (normal `normal`), if an
    /// earlier step fixed it.
    fn of(&self, base: [usize; 2], pl: usize, normal: V3<T>) -> Option<T> {
        self.links
            .iter()
            .find(|(ab, p, l)| *ab == link(base[0], base[1]) && *p == pl && l.re() > 0.0)
            .map(|(_, _, l)| *l)
            .or_else(|| {
                self.arms
                    .iter()
                    .find(|(ab, w, r)| {
                        *ab == link(base[0], base[1]) && r.re() > 0.0 && normal.cross(w).norm().re() < 1e-12
                    })
                    .map(|(_, _, r)| *r)
            })
    }
}

impl<T: Real> Resolver<'_, T> {
    fn v3(&self, c: &[usize; 3]) -> V3<T> {
        V3::new(self.q[c[0]], self.q[c[1]], self.q[c[2]])
    }

    fn plane(&self, i: usize) -> Plane<T> {
        if i == 0 {
            Plane::WORLD
        } else {
            Plane(Some(self.frames[i]))
        }
    }

    /// A direction of frame `frame` in the world, unit length.
    fn dir(&self, a: &AxisDef, frame: usize) -> Resolved<V3<T>> {
        let local = match a {
            AxisDef::Named(i, s) => {
                let mut v = V3::zeros();
                v[*i] = T::cst(*s);
                v
            }
            AxisDef::Vector(c, path) => {
                let v = self.v3(c);
                if v.norm().re() <= 0.0 {
                    return Err(self.model.error_at(
                        path,
                        "the direction vector is zero",
                        Some("give a non-zero vector".into()),
                    ));
                }
                v
            }
        };
        Ok(self.frames[frame].dir_to_world(local).normalize())
    }

    /// The basis (u, v, w) of a turning axis: w along it, u its zero
    /// direction. Default zero direction: the next axis cyclically (x→y,
    /// y→z, z→x).
    fn basis(&self, axis: &AxisDef, zero: &Option<AxisDef>, frame: usize) -> Resolved<(V3<T>, V3<T>, V3<T>)> {
        let w = self.dir(axis, frame)?;
        let z0 = match (zero, axis) {
            (Some(z), _) => self.dir(z, frame)?,
            (None, AxisDef::Named(i, _)) => self.dir(&AxisDef::Named((i + 1) % 3, 1.0), frame)?,
            // Any perpendicular: the world axis least aligned with w.
            (None, AxisDef::Vector(..)) => {
                if w.x.re().abs() < 0.9 {
                    V3::x()
                } else {
                    V3::y()
                }
            }
        };
        let u = z0 - w * z0.dot(&w);
        if u.norm().re() < 1e-9 {
            let path = match (zero, axis) {
                (Some(AxisDef::Vector(_, p)), _) | (None, AxisDef::Vector(_, p)) => p.clone(),
                _ => super::KeyPath::root(),
            };
            return Err(self.model.error_at(
                &path,
                "the zero direction is parallel to the axis",
                Some("give a `zero_dir` perpendicular to the axis".into()),
            ));
        }
        let u = u.normalize();
        Ok((u, w.cross(&u), w))
    }

    /// The fixed points in the world: (slot, position).
    fn resolve_points(&self) -> Vec<(usize, V3<T>)> {
        self.model
            .point_kinds
            .iter()
            .enumerate()
            .filter_map(|(i, k)| match k {
                PointKind::Fixed { frame, coords } => Some((i, self.frames[*frame].to_world(self.v3(coords)))),
                PointKind::Moving => None,
            })
            .collect()
    }

    /// Every solve step with this setting's lengths, angles and axes.
    fn resolve_steps(&self, fixed: &[(usize, V3<T>)]) -> Resolved<Vec<Step<T>>> {
        let q = self.q;
        let mut steps = Vec::with_capacity(self.model.steps.len());
        let mut known = KnownLengths {
            links: Vec::new(),
            arms: Vec::new(),
        };
        for s in &self.model.steps {
            match s {
                StepDef::Rrr {
                    p1,
                    p2,
                    l1,
                    l2,
                    plane,
                    out,
                    ..
                } => {
                    known.links.push((link(*p1, *out), *plane, q[*l1]));
                    known.links.push((link(*p2, *out), *plane, q[*l2]));
                }
                StepDef::Rrp {
                    from, l, plane, out, ..
                } => known.links.push((link(*from, *out), *plane, q[*l])),
                _ => {}
            }
            let step = match s {
                StepDef::Rigid {
                    base,
                    d,
                    angle,
                    lift,
                    plane: pl,
                    out,
                } => {
                    let (sn, cs) = (q[*angle] * self.deg).sin_cos();
                    let normal = match &self.plane(*pl).0 {
                        None => V3::z(),
                        Some(f) => f.dir_to_world(V3::z()),
                    };
                    Step::Rigid {
                        base: *base,
                        dc: q[*d] * cs,
                        ds: q[*d] * sn,
                        base_len: known.of(*base, *pl, normal),
                        lift: q[*lift],
                        plane: self.plane(*pl),
                        out: *out,
                    }
                }
                StepDef::Rigid3 { frame, at, out } => Step::Rigid3 {
                    frame: *frame,
                    at: self.v3(at),
                    out: *out,
                },
                StepDef::Offset { from, by, frame, out } => Step::Offset {
                    from: *from,
                    by: self.frames[*frame].dir_to_world(self.v3(by)),
                    out: *out,
                },
                StepDef::Newton {
                    dim,
                    plane,
                    outs,
                    guess,
                    closures,
                } => Step::Newton(Box::new(self.newton_group(*dim, *plane, outs, guess, closures))),
                StepDef::CamFollower(c) => Step::CamFollower(Box::new(self.cam_follower(c))),
                dyad => self.resolve_planar(dyad, fixed)?,
            };
            if let (StepDef::Rssr { pivot, out, .. }, Step::Rssr { rocker, .. }) = (s, &step) {
                known.arms.push((link(*pivot, *out), rocker.w, rocker.r));
            }
            steps.push(step);
        }
        Ok(steps)
    }

    /// A cam and its follower with this setting's numbers: a rocking
    /// follower's lift from degrees to radians; each lift segment starts
    /// where the one before ends (the first where the last ends).
    fn cam_follower(&self, c: &CamFollowerDef) -> CamStep<T> {
        let (q, deg) = (self.q, self.deg);
        let rocking = matches!(c.motion, MotionDef::Rocking { .. });
        let lift = match &c.lift {
            LiftDef::Table(s) => Lift::Table(s.clone()),
            LiftDef::Segments(segs) => {
                let at = |k: usize| {
                    let v = q[segs[k].2];
                    if rocking { v * deg } else { v }
                };
                Lift::Segments(
                    (0..segs.len())
                        .map(|k| Segment {
                            from: segs[k].0,
                            to: segs[k].1,
                            s0: at((k + segs.len() - 1) % segs.len()),
                            s1: at(k),
                            law: segs[k].3,
                        })
                        .collect(),
                )
            }
        };
        let motion = match c.motion {
            MotionDef::Translating { direction, offset } => {
                let (sn, cs) = (q[direction] * deg).sin_cos();
                Motion::Translating {
                    u: V2::new(cs, sn),
                    offset: q[offset],
                }
            }
            MotionDef::Rocking { arm, sign, face_offset } => Motion::Rocking {
                arm: q[arm],
                sign,
                face_offset: q[face_offset],
            },
        };
        let contact = match (c.contact, c.roller) {
            (ContactKind::Roller, Some(r)) => Contact::Roller(q[r]),
            (ContactKind::Flat, _) => Contact::Flat,
            _ => Contact::Knife,
        };
        CamStep {
            name: c.name.clone(),
            center: c.center,
            marker: c.marker,
            pivot: c.pivot,
            cam: CamFollower {
                base: q[c.base],
                contact,
                motion,
                lift,
                zero: q[c.zero] * deg,
                closure: c.closure,
            },
            max_pressure_deg: c.max_pressure_deg,
            plane: self.plane(c.plane),
            out: c.out,
        }
    }

    /// A crank or a planar dyad (RRR, RRP, RPR); the spatial dyads go on to
    /// [`Self::resolve_spatial`].
    fn resolve_planar(&self, s: &StepDef, fixed: &[(usize, V3<T>)]) -> Resolved<Step<T>> {
        let (q, deg) = (self.q, self.deg);
        Ok(match s {
            StepDef::Crank {
                center,
                out,
                frame,
                axis,
                zero_dir,
                radius,
                phase,
                speed,
            } => {
                let (u, v, _) = self.basis(axis, zero_dir, *frame)?;
                let ph = q[*phase] * deg;
                let (sin_ph, cos_ph) = ph.sin_cos();
                Step::Crank {
                    center: *center,
                    out: *out,
                    r: q[*radius],
                    u,
                    v,
                    speed: *speed,
                    phase: ph,
                    cos_ph,
                    sin_ph,
                }
            }
            StepDef::Rrr {
                p1,
                p2,
                l1,
                l2,
                sign,
                plane: pl,
                out,
            } => Step::Rrr {
                p1: *p1,
                p2: *p2,
                l1: q[*l1],
                l2: q[*l2],
                sign: *sign,
                plane: self.plane(*pl),
                out: *out,
            },
            StepDef::Rrp {
                from,
                through,
                toward,
                dir: d,
                offset,
                l,
                sign,
                plane: pl,
                out,
            } => {
                let a = d.map_or(T::zero(), |d| q[d] * deg);
                Step::Rrp {
                    from: *from,
                    through: *through,
                    toward: *toward,
                    dir: V2::new(a.cos(), a.sin()),
                    offset: q[*offset],
                    l: q[*l],
                    sign: *sign,
                    plane: self.plane(*pl),
                    out: *out,
                }
            }
            StepDef::Rpr {
                from,
                pivot,
                e,
                d,
                plane: pl,
                out,
            } => Step::Rpr {
                from: *from,
                pivot: *pivot,
                e: q[*e],
                d: q[*d],
                plane: self.plane(*pl),
                out: *out,
            },
            spatial => self.resolve_spatial(spatial, fixed)?,
        })
    }

    /// A spatial dyad: RSSR or a point on a line.
    fn resolve_spatial(&self, s: &StepDef, fixed: &[(usize, V3<T>)]) -> Resolved<Step<T>> {
        let q = self.q;
        Ok(match s {
            StepDef::Rssr {
                from,
                l,
                pivot,
                frame,
                axis,
                r,
                offset,
                zero_dir,
                sign,
                out,
            } => {
                let (u, v, w) = self.basis(axis, zero_dir, *frame)?;
                let pivot_at = fixed
                    .iter()
                    .find(|(i, _)| i == pivot)
                    .map(|(_, p)| *p)
                    .unwrap_or_else(V3::zeros);
                Step::Rssr {
                    from: *from,
                    rocker: Rocker {
                        c: pivot_at + w * q[*offset],
                        u,
                        v,
                        w,
                        r: q[*r],
                    },
                    zero: u,
                    l: q[*l],
                    sign: *sign,
                    out: *out,
                }
            }
            StepDef::PointOnLine {
                from,
                through,
                toward,
                dir: d,
                frame,
                l,
                sign,
                out,
            } => Step::PointOnLine {
                from: *from,
                through: *through,
                toward: *toward,
                dir: match d {
                    Some(a) => self.dir(a, *frame)?,
                    None => V3::x(),
                },
                l: q[*l],
                sign: *sign,
                out: *out,
            },
            _ => unreachable!("resolved by resolve_steps and resolve_planar"),
        })
    }

    /// A numerical group with this setting's distances and start guess.
    fn newton_group(
        &self,
        dim: usize,
        pl: usize,
        outs: &[usize],
        guess: &[usize],
        closures: &[ClosureDef],
    ) -> NewtonGroup<T> {
        let conv = |r: &ClosureRef| match r {
            ClosureRef::Unknown(u) => PointRef::Unknown(*u),
            ClosureRef::Known(k) => PointRef::Known(*k),
        };
        NewtonGroup {
            dim,
            plane: self.plane(pl),
            outs: outs.to_vec(),
            guess: guess.iter().map(|g| self.q[*g].re()).collect(),
            closures: closures
                .iter()
                .map(|c| match c {
                    ClosureDef::Distance { a, b, l } => Closure::Distance {
                        a: conv(a),
                        b: conv(b),
                        l: self.q[*l],
                    },
                    ClosureDef::OnLine { p, h, t } => Closure::OnLine { p: *p, h: *h, t: *t },
                })
                .collect(),
        }
    }

    fn resolve_measures(&self) -> Resolved<Vec<MeasureStep<T>>> {
        let mut measures = Vec::with_capacity(self.model.measures.len());
        for m in &self.model.measures {
            measures.push(match m {
                MeasureDef::Distance { a, b } => MeasureStep::Distance { a: *a, b: *b },
                MeasureDef::LineDeviation { p, h, t, plane: pl } => MeasureStep::LineDeviation {
                    p: *p,
                    h: *h,
                    t: *t,
                    plane: pl.map(|i| self.plane(i)),
                },
                MeasureDef::Coordinate { p, from, frame, axis } => MeasureStep::Coordinate {
                    p: *p,
                    from: *from,
                    origin: self.frames[*frame].origin,
                    axis: self.dir(axis, *frame)?,
                },
            });
        }
        Ok(measures)
    }

    /// The thread paths with this setting's cams, pins and convention.
    fn resolve_threads(&self, t: &ThreadsDef, fixed: &[(usize, V3<T>)]) -> Resolved<Threads<T>> {
        let cams = t
            .cams
            .iter()
            .map(|c| self.resolve_cam(c))
            .collect::<Resolved<Vec<_>>>()?;
        // The paths' structure is the model's (ThreadsDef::layout); only
        // the distinct pieces take this setting's values.
        let mut still = vec![false; self.model.point_names.len()];
        for (slot, _) in fixed {
            still[*slot] = true;
        }
        let mut spans: Vec<Span<T>> = Vec::with_capacity(t.layout.pieces.len());
        for &(pi, si) in &t.layout.pieces {
            spans.push(self.resolve_span(&t.paths[pi], si, &still)?);
        }
        let paths = t.layout.paths.clone();
        let convention = match t.convention {
            file::TakeUpConvention::Release => Convention::Release,
            file::TakeUpConvention::Feed => Convention::Feed {
                elongation_mm: t.elongation.map_or(0.0, |e| self.q[e].re()),
            },
        };
        let split_up = paths.iter().map(|p| self.needle_direction(p)).collect();
        Ok(Threads {
            paths,
            spans,
            cams,
            convention,
            phi0_deg: t.phi0_deg.unwrap_or(self.model.phi_start_deg()),
            tension_n: t.tension_n,
            split_up,
        })
    }

    fn resolve_cam(&self, c: &CamDef) -> Resolved<Cam<T>> {
        let profile = match &c.profile {
            ProfileDef::Disc { r, e } => {
                let (r, e) = (self.q[*r].re(), self.q[*e].re());
                if e.abs() >= r {
                    return Err(self.model.error_at(
                        &c.path.key("disc"),
                        format!("the disc's eccentricity {e} mm must be smaller than its radius {r} mm"),
                        Some("the shaft must lie inside the disc".into()),
                    ));
                }
                Profile::disc(r, e)
            }
            ProfileDef::Polar { theta, rho } => Profile::spline(theta, rho),
        };
        Ok(Cam {
            name: c.name.clone(),
            center: c.center,
            marker: c.marker,
            axis: self.dir(&c.axis, c.frame)?,
            profile,
        })
    }

    /// Piece `si` of path `p`; `still[slot]`: whether the point is fixed.
    fn resolve_span(&self, p: &PathDef, si: usize, still: &[bool]) -> Resolved<Span<T>> {
        let q = self.q;
        Ok(match &p.spans[si] {
            SpanDef::Straight { a, b, constant } => Span::Straight {
                a: *a,
                b: *b,
                constant: *constant,
                fixed: [still[*a], still[*b]],
            },
            SpanDef::Pin {
                a,
                b,
                c,
                axis,
                frame,
                r,
                sense,
                node,
            } => {
                if q[*r].re() < 0.0 {
                    return Err(self.model.error_at(
                        &self.model.expr_paths[*r],
                        "a pin radius cannot be negative",
                        Some("give the radius in mm, 0 for a thin pin".into()),
                    ));
                }
                Span::Pin {
                    a: *a,
                    b: *b,
                    c: *c,
                    axis: self.dir(axis, *frame)?,
                    r: q[*r],
                    sense: *sense,
                    name: p.node_names[*node].clone(),
                }
            }
            SpanDef::Cam { a, b, cam, contact, .. } => Span::Cam {
                a: *a,
                b: *b,
                cam: *cam,
                contact: match contact {
                    CamContactDef::Exact { sense } => CamModel::Exact { sense: *sense },
                    CamContactDef::Offset { gamma } => CamModel::Offset {
                        gamma_rad: q[*gamma].re().to_radians(),
                    },
                },
            },
        })
    }

    /// A path that ends at the eye of a [[stitch.needles]] entry is split
    /// at B (seed 004 §2.3): its take-up is measured past the eye's top
    /// position, along the needle u_n = (0, −sin β, cos β) of the stitch
    /// frame. `None` for any other path.
    fn needle_direction(&self, p: &ThreadPath) -> Option<V3<T>> {
        let st = self.model.stitch.as_ref()?;
        let eye = *p.nodes.last()?;
        st.needles
            .iter()
            .any(|n| matches!(n.eye, stitch_setup::OrganDef::Point(s) if s == eye))
            .then(|| {
                let beta = st.tilt.map_or(T::zero(), |i| self.q[i] * self.deg);
                self.frames[st.frame]
                    .dir_to_world(V3::new(T::zero(), -beta.sin(), beta.cos()))
                    .normalize()
            })
    }
}
