//! The mechanism: drivers and structural groups, solved in order at each φ.
//!
//! A [`Mechanism`] is a model with every parameter resolved to a number of
//! type `T` (`f64` for positions, a dual number for exact analogs). Solving
//! at a batch of φ values (one, or a whole cycle) fills a preallocated
//! [`Pose`] group by group; nothing is allocated per step.

pub mod analogs;
pub mod cam_follower;
mod kernels;
pub(crate) mod line;
pub(crate) mod newton;
pub(crate) mod rigid;
pub(crate) mod rpr;
pub(crate) mod rrr;
pub(crate) mod rssr;

use std::sync::Arc;

pub use crate::error::AssemblyError;
use crate::geometry::{Plane, PlaneMap, V2, V3, perp};
use crate::scalar::Real;
use crate::with_plane;
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
        NoAssembly {
            defect_mm: 0.0,
            message: format!("{what} coincide, so the direction is undefined"),
        }
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

    /// φ (degrees) as the independent variable: analogs are d/dφ.
    pub fn at_deg(phi_deg: f64) -> Self {
        Phi::new(T::var(phi_deg.to_radians()))
    }

    /// A cycle's φ values, precomputed once (cos and sin included) so that
    /// solving the cycle does no trigonometry for the drivers.
    pub fn table(phis_deg: &[f64]) -> Vec<Phi<T>> {
        phis_deg.iter().map(|&p| Phi::at_deg(p)).collect()
    }
}

/// One solve step. Slots index the points of a [`Pose`].
#[derive(Debug, Clone, PartialEq)]
pub enum Step<T: Real> {
    /// Crank pin `out = center + r(cos θ·u + sin θ·v)`, θ = speed·φ + phase.
    Crank {
        center: usize,
        out: usize,
        r: T,
        u: V3<T>,
        v: V3<T>,
        speed: f64,
        phase: T,
        cos_ph: T,
        sin_ph: T,
    },
    Rrr {
        p1: usize,
        p2: usize,
        l1: T,
        l2: T,
        sign: f64,
        plane: Plane<T>,
        out: usize,
    },
    /// Planar RRP: slider on the line through `through` (toward `toward`, or
    /// along the fixed in-plane unit direction `dir`), offset `offset` left.
    Rrp {
        from: usize,
        through: usize,
        toward: Option<usize>,
        dir: V2<T>,
        offset: T,
        l: T,
        sign: f64,
        plane: Plane<T>,
        out: usize,
    },
    Rpr {
        from: usize,
        pivot: usize,
        e: T,
        d: T,
        plane: Plane<T>,
        out: usize,
    },
    Rssr {
        from: usize,
        rocker: Rocker<T>,
        zero: V3<T>,
        l: T,
        sign: f64,
        out: usize,
    },
    /// Spatial point on the line through `through` (toward `toward`, or along
    /// the fixed unit direction `dir`).
    PointOnLine {
        from: usize,
        through: usize,
        toward: Option<usize>,
        dir: V3<T>,
        l: T,
        sign: f64,
        out: usize,
    },
    /// Rigid point `dc`, `ds` along and left of `base[0] → base[1]`;
    /// `base_len` is that link's length when a group fixes it (the point
    /// then needs no square root).
    Rigid {
        base: [usize; 2],
        dc: T,
        ds: T,
        base_len: Option<T>,
        lift: T,
        plane: Plane<T>,
        out: usize,
    },
    Rigid3 {
        frame: [usize; 3],
        at: V3<T>,
        out: usize,
    },
    /// `out = from + by`: a point on the translating body of `from`.
    Offset {
        from: usize,
        by: V3<T>,
        out: usize,
    },
    Newton(Box<NewtonGroup<T>>),
    /// A disc cam turning about `center` with `marker`, driving a follower
    /// (a rocking one about `pivot`); `out` is the follower's point.
    CamFollower(Box<CamStep<T>>),
}

/// A cam-and-follower step: where the cam and the follower's pivot are,
/// and the cam with its follower.
#[derive(Debug, Clone, PartialEq)]
pub struct CamStep<T: Real> {
    /// The group's name (or its output point's).
    pub name: String,
    pub center: usize,
    pub marker: usize,
    pub pivot: Option<usize>,
    pub cam: cam_follower::CamFollower<T>,
    /// The largest pressure angle allowed, deg.
    pub max_pressure_deg: f64,
    pub plane: Plane<T>,
    pub out: usize,
}

impl<T: Real> Step<T> {
    /// The point a closed-form step places (`None` for a numerical group,
    /// which places several).
    pub fn out(&self) -> Option<usize> {
        match self {
            Step::Crank { out, .. }
            | Step::Rrr { out, .. }
            | Step::Rrp { out, .. }
            | Step::Rpr { out, .. }
            | Step::Rssr { out, .. }
            | Step::PointOnLine { out, .. }
            | Step::Rigid { out, .. }
            | Step::Rigid3 { out, .. }
            | Step::Offset { out, .. } => Some(*out),
            Step::CamFollower(c) => Some(c.out),
            Step::Newton(_) => None,
        }
    }

    /// Calls `f` with every point a closed-form step reads; false for a
    /// numerical group (its closures read points of their own).
    fn each_input(&self, mut f: impl FnMut(usize)) -> bool {
        match self {
            Step::Crank { center, .. } => f(*center),
            Step::Rrr { p1, p2, .. } => [*p1, *p2].into_iter().for_each(f),
            Step::Rrp {
                from, through, toward, ..
            }
            | Step::PointOnLine {
                from, through, toward, ..
            } => [Some(*from), Some(*through), *toward].into_iter().flatten().for_each(f),
            Step::Rpr { from, pivot, .. } => [*from, *pivot].into_iter().for_each(f),
            Step::Rssr { from, .. } | Step::Offset { from, .. } => f(*from),
            Step::Rigid { base, .. } => base.iter().copied().for_each(f),
            Step::Rigid3 { frame, .. } => frame.iter().copied().for_each(f),
            Step::CamFollower(c) => [Some(c.center), Some(c.marker), c.pivot]
                .into_iter()
                .flatten()
                .for_each(f),
            Step::Newton(_) => return false,
        }
        true
    }
}

/// A derived quantity, evaluated from a solved pose.
#[derive(Debug, Clone, PartialEq)]
pub enum MeasureStep<T: Real> {
    Distance {
        a: usize,
        b: usize,
    },
    /// Signed in-plane distance (`plane = Some`) or unsigned 3D distance.
    LineDeviation {
        p: usize,
        h: usize,
        t: usize,
        plane: Option<Plane<T>>,
    },
    Coordinate {
        p: usize,
        from: Option<usize>,
        origin: V3<T>,
        axis: V3<T>,
    },
}

/// Positions of every point at a batch of φ values (one φ, or a whole
/// cycle), plus the numerical groups' warm starts. Stored per point as a
/// track of `len()` positions so each group runs one tight loop over φ.
#[derive(Debug, Clone)]
pub struct Pose<T: Real> {
    n: usize,
    tracks: Vec<Vec<V3<T>>>,
    newton: Vec<NewtonState<T>>,
}

impl<T: Real> Pose<T> {
    /// Number of φ positions held.
    pub fn len(&self) -> usize {
        self.n
    }
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }
    /// Position of point `slot` at the `k`-th φ.
    #[inline]
    pub fn point(&self, slot: usize, k: usize) -> V3<T> {
        self.tracks[slot][k]
    }
    /// Every position of point `slot`, in φ order.
    pub fn track(&self, slot: usize) -> &[V3<T>] {
        &self.tracks[slot]
    }
    /// Keeps the first `n` positions (`n` ≤ [`Self::len`]) and the
    /// numerical groups' state, so a solve of `n` positions continues from
    /// the last one solved.
    pub fn truncate(&mut self, n: usize) {
        assert!(n <= self.n, "a pose only shrinks");
        self.n = n;
        self.tracks.iter_mut().for_each(|t| t.truncate(n));
    }
    /// A copy with every point projected onto `plane` (local z = 0).
    pub fn projected(&self, plane: &Plane<T>) -> Pose<T> {
        let tracks = self
            .tracks
            .iter()
            .map(|t| t.iter().map(|p| plane.lift(plane.project(p), T::zero())).collect())
            .collect();
        Pose {
            n: self.n,
            tracks,
            newton: self.newton.clone(),
        }
    }

    /// All points at the `k`-th φ, indexable by slot.
    pub fn at(&self, k: usize) -> PoseAt<'_, T> {
        PoseAt {
            tracks: &self.tracks,
            k,
        }
    }
}

/// The points of a [`Pose`] at one φ: `pose.at(k)[slot]`.
#[derive(Clone, Copy)]
pub struct PoseAt<'a, T: Real> {
    tracks: &'a [Vec<V3<T>>],
    k: usize,
}

impl<T: Real> std::ops::Index<usize> for PoseAt<'_, T> {
    type Output = V3<T>;
    #[inline]
    fn index(&self, slot: usize) -> &V3<T> {
        &self.tracks[slot][self.k]
    }
}

/// Fills `out[k] = f(k)` for every k, stopping at the first position with
/// no assembly.
#[inline(always)]
fn each<T: Real>(
    out: &mut [V3<T>],
    mut f: impl FnMut(usize) -> Result<V3<T>, NoAssembly>,
) -> Result<(), (usize, NoAssembly)> {
    for (k, o) in out.iter_mut().enumerate() {
        *o = f(k).map_err(|e| (k, e))?;
    }
    Ok(())
}

/// A model with every parameter resolved: ready to solve at any φ.
#[derive(Debug, Clone, PartialEq)]
pub struct Mechanism<T: Real> {
    pub(crate) fixed: Vec<(usize, V3<T>)>,
    pub(crate) steps: Vec<Step<T>>,
    pub(crate) measures: Vec<MeasureStep<T>>,
    pub(crate) n_points: usize,
    /// A label per step, for messages (`group "23" (rrr)`).
    pub(crate) labels: Arc<[String]>,
    /// Placements of the model's frames, by frame index (0 = world).
    pub(crate) frames: Vec<crate::geometry::Placement<T>>,
}

impl<T: Real> Mechanism<T> {
    /// A pose for `n` φ positions with the fixed points in place and the
    /// numerical groups at their starting guesses.
    pub fn new_pose(&self, n: usize) -> Pose<T> {
        let mut tracks = vec![vec![V3::zeros(); n]; self.n_points];
        for (slot, p) in &self.fixed {
            tracks[*slot].iter_mut().for_each(|q| *q = *p);
        }
        let newton = self
            .steps
            .iter()
            .filter_map(|s| {
                if let Step::Newton(g) = s {
                    Some(g.new_state())
                } else {
                    None
                }
            })
            .collect();
        Pose { n, tracks, newton }
    }

    /// Makes `pose` ready for [`Self::solve`] over `n` positions as
    /// [`Self::new_pose`] would, reusing its buffers: fixed points are
    /// rewritten only where they moved (a study's settings rarely move
    /// them) and numerical groups start afresh, so a result never depends
    /// on the setting solved before.
    pub fn reset_pose(&self, pose: &mut Pose<T>, n: usize) {
        if pose.n != n || pose.tracks.len() != self.n_points || pose.tracks.iter().any(|t| t.len() != n) {
            *pose = self.new_pose(n);
            return;
        }
        for (slot, p) in &self.fixed {
            let t = &mut pose.tracks[*slot];
            if t.first() != Some(p) || t.last() != Some(p) {
                t.iter_mut().for_each(|q| *q = *p);
            }
        }
        if !pose.newton.is_empty() {
            pose.newton = self
                .steps
                .iter()
                .filter_map(|s| {
                    if let Step::Newton(g) = s {
                        Some(g.new_state())
                    } else {
                        None
                    }
                })
                .collect();
        }
    }

    /// Solves every group at each φ of `phis` (as many as the pose holds),
    /// group by group, writing into `pose`. Numerical groups continue from
    /// the previous φ (and from the previous call).
    ///
    /// (Not compiled per vector unit as the thread paths are: most groups
    /// can fail at any φ, so their loops do not vectorise, and one copy
    /// keeps each group's loop body inlined.)
    pub fn solve(&self, phis: &[Phi<T>], pose: &mut Pose<T>) -> Result<(), AssemblyError> {
        self.solve_steps(phis, pose, None)
    }

    /// Solves `pose` as [`Self::reset_pose`] and [`Self::solve`] would,
    /// where it holds `before`'s solution over the same `phis` (a study's
    /// previous setting): a group whose definition is the same as
    /// `before`'s and whose points it reads did not move keeps its track,
    /// bit for bit what solving it again gives. `moved` says, per point,
    /// whether its track differs from `before`'s. Without a `before` (or one
    /// of another structure) everything is solved and has moved. On an
    /// error `pose` holds no whole solution: solve the next setting
    /// without a `before`.
    pub fn solve_since(
        &self,
        before: Option<&Mechanism<T>>,
        phis: &[Phi<T>],
        pose: &mut Pose<T>,
        moved: &mut Vec<bool>,
    ) -> Result<(), AssemblyError> {
        moved.clear();
        let comparable = before.filter(|b| {
            b.n_points == self.n_points
                && b.steps.len() == self.steps.len()
                && b.fixed.len() == self.fixed.len()
                && b.fixed.iter().zip(&self.fixed).all(|(p, q)| p.0 == q.0)
                && b.steps
                    .iter()
                    .zip(&self.steps)
                    .all(|(p, q)| std::mem::discriminant(p) == std::mem::discriminant(q))
                && pose.n == phis.len()
                && pose.tracks.len() == self.n_points
                && pose.tracks.iter().all(|t| t.len() == pose.n)
        });
        let Some(before) = comparable else {
            self.reset_pose(pose, phis.len());
            moved.resize(self.n_points, true);
            return self.solve(phis, pose);
        };
        moved.resize(self.n_points, false);
        for ((slot, p), (_, q)) in self.fixed.iter().zip(&before.fixed) {
            if p != q {
                moved[*slot] = true;
                pose.tracks[*slot].iter_mut().for_each(|t| *t = *p);
            }
        }
        self.solve_steps(phis, pose, Some((before, moved)))
    }

    /// [`Self::solve`], skipping (with `since`) the groups whose track
    /// stays `before`'s and marking the points that move.
    fn solve_steps(
        &self,
        phis: &[Phi<T>],
        pose: &mut Pose<T>,
        mut since: Option<(&Mechanism<T>, &mut Vec<bool>)>,
    ) -> Result<(), AssemblyError> {
        let n = pose.n;
        assert_eq!(phis.len(), n, "one φ per pose position");
        let tracks = &mut pose.tracks;
        let mut newton = 0;
        for (i, step) in self.steps.iter().enumerate() {
            if let Some((before, moved)) = &mut since {
                let mut inputs_moved = false;
                let closed_form = step.each_input(|s| inputs_moved |= moved[s]);
                if closed_form && !inputs_moved && *step == before.steps[i] {
                    continue;
                }
                match step {
                    Step::Newton(g) => {
                        // Numerical groups start afresh at every setting.
                        pose.newton[newton] = g.new_state();
                        g.outs.iter().for_each(|&s| moved[s] = true);
                    }
                    _ => moved[step.out().expect("a closed-form group has an output point")] = true,
                }
            }
            let r = match step {
                Step::Newton(g) => {
                    let st = &mut pose.newton[newton];
                    newton += 1;
                    g.solve_track(tracks, n, st)
                }
                _ => {
                    // Every closed-form group places one point; its track is
                    // taken out while the inputs are read.
                    let out_slot = step.out().expect("a closed-form group has an output point");
                    let mut o = std::mem::take(&mut tracks[out_slot]);
                    let r = self.solve_step(step, tracks, phis, &mut o[..n]);
                    tracks[out_slot] = o;
                    r
                }
            };
            if let Err((k, e)) = r {
                return Err(AssemblyError {
                    group: self.labels[i].clone(),
                    phi_deg: phis[k].phi.re().to_degrees(),
                    defect_mm: e.defect_mm,
                    message: e.message,
                });
            }
        }
        Ok(())
    }

    /// One closed-form group at every φ: its output track `o` from the
    /// tracks already solved; on failure, the first position without an
    /// assembly.
    #[inline(always)]
    fn solve_step(
        &self,
        step: &Step<T>,
        t: &[Vec<V3<T>>],
        phis: &[Phi<T>],
        o: &mut [V3<T>],
    ) -> Result<(), (usize, NoAssembly)> {
        let n = phis.len();
        let tr = |s: usize| &t[s][..n];
        match step {
            Step::Crank { .. } => self.solve_crank(step, t, phis, o),
            Step::Rrr {
                p1,
                p2,
                l1,
                l2,
                sign,
                plane,
                ..
            } => {
                let (a, b) = (tr(*p1), tr(*p2));
                let (l1sq, l2sq) = (*l1 * *l1, *l2 * *l2);
                match self.fixed_point(*p2) {
                    // A dyad on a fixed pivot (a four-bar's rocker): the
                    // pivot is projected once, not read at every φ.
                    Some(c) => with_plane!(plane, pl => {
                        let c = pl.project(&c);
                        each(o, |k| rrr::rrr(pl.project(&a[k]), c, l1sq, l2sq, *sign).map(|q| pl.lift(q, T::zero())))
                    }),
                    None => with_plane!(plane, pl => each(o, |k| {
                        rrr::rrr(pl.project(&a[k]), pl.project(&b[k]), l1sq, l2sq, *sign).map(|q| pl.lift(q, T::zero()))
                    })),
                }
            }
            Step::Rrp { .. } => self.solve_rrp(step, t, phis, o),
            Step::Rpr {
                from,
                pivot,
                e,
                d,
                plane,
                ..
            } => {
                let (a, c) = (tr(*from), tr(*pivot));
                with_plane!(plane, pl => each(o, |k| {
                    let ck = pl.project(&c[k]);
                    rpr::rpr(pl.project(&a[k]), ck, *e).map(|(u, _)| pl.lift(ck + perp(u) * *e + u * *d, T::zero()))
                }))
            }
            Step::Rssr {
                from, rocker, l, sign, ..
            } => {
                let a = tr(*from);
                let rod = rssr::RockerRod::new(*rocker, *l);
                // All positions at once; if one has no assembly, the
                // checked loop finds it and says why.
                if kernels::rssr(o, a, &rod, *sign) {
                    Ok(())
                } else {
                    each(o, |k| rssr::rssr(&rod, a[k], *sign))
                }
            }
            Step::PointOnLine { .. } => self.solve_point_on_line(step, t, phis, o),
            Step::Rigid { .. } => self.solve_rigid(step, t, phis, o),
            Step::Rigid3 { frame, at, .. } => {
                let (f0, f1, f2) = (tr(frame[0]), tr(frame[1]), tr(frame[2]));
                each(o, |k| rigid::rigid_point_3d(f0[k], f1[k], f2[k], *at))
            }
            Step::Offset { from, by, .. } => {
                kernels::offset(o, tr(*from), *by);
                Ok(())
            }
            Step::CamFollower(c) => {
                let (ce, mk) = (tr(c.center), tr(c.marker));
                let pv = c.pivot.map(tr);
                with_plane!(&c.plane, pl => each(o, |k| {
                    let pivot = pv.map(|p| pl.project(&p[k]));
                    c.cam.point(pl.project(&ce[k]), pl.project(&mk[k]), pivot).map(|q| pl.lift(q, T::zero()))
                }))
            }
            Step::Newton(_) => unreachable!("numerical groups are solved by `solve`"),
        }
    }

    /// An RRP dyad: a slider on a guide through `through`, at `l` from `from`.
    #[inline(always)]
    fn solve_rrp(
        &self,
        step: &Step<T>,
        t: &[Vec<V3<T>>],
        phis: &[Phi<T>],
        o: &mut [V3<T>],
    ) -> Result<(), (usize, NoAssembly)> {
        let n = phis.len();
        let tr = |s: usize| &t[s][..n];
        let Step::Rrp {
            from,
            through,
            toward,
            dir,
            offset,
            l,
            sign,
            plane,
            ..
        } = step
        else {
            unreachable!("solve_rrp is called on its own kind of step")
        };
        let (a, h) = (tr(*from), tr(*through));
        let l_sq = *l * *l;
        match toward.map(tr) {
            Some(t) => with_plane!(plane, pl => each(o, |k| {
                let hk = pl.project(&h[k]);
                let u = unit(pl.project(&t[k]) - hk)?;
                line::point_on_line(hk + perp(u) * *offset, u, pl.project(&a[k]), l_sq, *sign)
                    .map(|q| pl.lift(q, T::zero()))
            })),
            None => {
                // A guide of fixed direction: its offset is the same at every φ.
                let off = perp(*dir) * *offset;
                with_plane!(plane, pl => each(o, |k| {
                    line::point_on_line(pl.project(&h[k]) + off, *dir, pl.project(&a[k]), l_sq, *sign)
                        .map(|q| pl.lift(q, T::zero()))
                }))
            }
        }
    }

    /// A planar rigid point on the base `base[0]` → `base[1]`.
    #[inline(always)]
    fn solve_rigid(
        &self,
        step: &Step<T>,
        t: &[Vec<V3<T>>],
        phis: &[Phi<T>],
        o: &mut [V3<T>],
    ) -> Result<(), (usize, NoAssembly)> {
        let n = phis.len();
        let tr = |s: usize| &t[s][..n];
        let Step::Rigid {
            base,
            dc,
            ds,
            base_len,
            lift,
            plane,
            ..
        } = step
        else {
            unreachable!("solve_rigid is called on its own kind of step")
        };
        let (a, b) = (tr(base[0]), tr(base[1]));
        match base_len {
            // On a link of known length it cannot fail: a loop
            // without branches, which vectorises.
            Some(l) => {
                let (dcl, dsl) = (*dc / *l, *ds / *l);
                with_plane!(plane, pl => kernels::rigid_on_link(o, a, b, pl, dcl, dsl, *lift));
                Ok(())
            }
            None => with_plane!(plane, pl => each(o, |k| {
                rigid::rigid_point(pl.project(&a[k]), pl.project(&b[k]), *dc, *ds).map(|q| pl.lift(q, *lift))
            })),
        }
    }

    /// A spatial point on a line through `through`, at `l` from `from`.
    #[inline(always)]
    fn solve_point_on_line(
        &self,
        step: &Step<T>,
        t: &[Vec<V3<T>>],
        phis: &[Phi<T>],
        o: &mut [V3<T>],
    ) -> Result<(), (usize, NoAssembly)> {
        let n = phis.len();
        let tr = |s: usize| &t[s][..n];
        let Step::PointOnLine {
            from,
            through,
            toward,
            dir,
            l,
            sign,
            ..
        } = step
        else {
            unreachable!("solve_point_on_line is called on its own kind of step")
        };
        let (a, h) = (tr(*from), tr(*through));
        let t = toward.map(tr);
        let l_sq = *l * *l;
        // A guide of fixed direction: all positions at once, as
        // for RSSR; the checked loop only where one fails.
        if t.is_none() && kernels::point_on_line(o, h, a, *dir, l_sq, *sign) {
            Ok(())
        } else {
            each(o, |k| {
                let u = match t {
                    Some(t) => unit(t[k] - h[k])?,
                    None => *dir,
                };
                line::point_on_line(h[k], u, a[k], l_sq, *sign)
            })
        }
    }

    /// A crank's output track: planar cranks on a fixed shaft share
    /// cos φ, sin φ and the vectorised kernel; others turn at their speed.
    #[inline(always)]
    fn solve_crank(
        &self,
        step: &Step<T>,
        t: &[Vec<V3<T>>],
        phis: &[Phi<T>],
        o: &mut [V3<T>],
    ) -> Result<(), (usize, NoAssembly)> {
        let n = phis.len();
        let Step::Crank {
            center,
            r,
            u,
            v,
            speed,
            phase,
            cos_ph,
            sin_ph,
            ..
        } = step
        else {
            unreachable!("solve_crank is called on cranks")
        };
        let c0 = &t[*center][..n];
        let (ru, rv) = (*u * *r, *v * *r);
        if *speed != 1.0 {
            each(o, |k| {
                let (s, c) = (phis[k].phi * T::cst(*speed) + *phase).sin_cos();
                Ok(c0[k] + ru.map(|x| c.times_k(x)) + rv.map(|x| s.times_k(x)))
            })
        } else if u.z.re() == 0.0 && v.z.re() == 0.0 {
            // Shaft along z: a planar crank, cos(φ + ph) and
            // sin(φ + ph) from the shared cos φ, sin φ.
            let (cx, cy) = (ru.x * *cos_ph + rv.x * *sin_ph, ru.y * *cos_ph + rv.y * *sin_ph);
            let (sx, sy) = (rv.x * *cos_ph - ru.x * *sin_ph, rv.y * *cos_ph - ru.y * *sin_ph);
            match self.fixed_point(*center) {
                // A crank on a fixed shaft (every crank of the
                // presets): its centre is read once.
                Some(c0) => {
                    kernels::planar_crank(o, phis, c0, [cx, cy, sx, sy]);
                    Ok(())
                }
                None => each(o, |k| {
                    let (c, s) = (phis[k].cos, phis[k].sin);
                    Ok(V3::new(
                        c0[k].x + c.times_k(cx) + s.times_k(sx),
                        c0[k].y + c.times_k(cy) + s.times_k(sy),
                        c0[k].z,
                    ))
                }),
            }
        } else if let Some(c0) = self.fixed_point(*center) {
            kernels::crank(o, phis, c0, [ru, rv], [*cos_ph, *sin_ph]);
            Ok(())
        } else {
            each(o, |k| {
                let phi = &phis[k];
                let (c, s) = (
                    phi.cos * *cos_ph - phi.sin * *sin_ph,
                    phi.sin * *cos_ph + phi.cos * *sin_ph,
                );
                Ok(c0[k] + ru.map(|x| c.times_k(x)) + rv.map(|x| s.times_k(x)))
            })
        }
    }

    /// Transmission angle (rad) of every dyad, in the order of the model's dyads.
    pub fn transmission_angles(&self, pose: &Pose<T>, k: usize, out: &mut Vec<T>) {
        out.clear();
        self.each_transmission(pose, k, |y, x| out.push(y.angle_of(x)));
    }

    /// The transmission angles as the vectors `(y ≥ 0, x)` whose angles
    /// they are (μ = atan2(y, x) falls as x/|(x, y)| rises): a study finds
    /// the extremes over a cycle from these and takes atan2 there only.
    pub fn transmission_parts(&self, pose: &Pose<T>, k: usize, out: &mut Vec<(T, T)>) {
        out.clear();
        self.each_transmission(pose, k, |y, x| out.push((y, x)));
    }

    #[inline]
    fn each_transmission(&self, pose: &Pose<T>, k: usize, mut f: impl FnMut(T, T)) {
        let p = pose.at(k);
        for step in &self.steps {
            let (y, x) = match step {
                Step::Rrr {
                    p1, p2, plane, out: b, ..
                } => rrr::transmission_parts(plane.project(&p[*p1]), plane.project(&p[*p2]), plane.project(&p[*b])),
                Step::Rrp {
                    from,
                    through,
                    toward,
                    dir,
                    plane,
                    out: g,
                    ..
                } => {
                    let h = plane.project(&p[*through]);
                    let u = toward.map_or(*dir, |t| unit(plane.project(&p[t]) - h).unwrap_or(*dir));
                    line::transmission_parts(u, plane.project(&p[*from]), plane.project(&p[*g]))
                }
                Step::Rpr {
                    from, pivot, e, plane, ..
                } => rpr::transmission_parts(plane.project(&p[*from]), plane.project(&p[*pivot]), *e),
                Step::Rssr {
                    from, rocker, out: b, ..
                } => rssr::transmission_parts(rocker, p[*from], p[*b]),
                Step::PointOnLine {
                    from,
                    through,
                    toward,
                    dir,
                    out: q,
                    ..
                } => {
                    let u = toward.map_or(*dir, |t| unit(p[t] - p[*through]).unwrap_or(*dir));
                    line::transmission_parts(u, p[*from], p[*q])
                }
                _ => continue,
            };
            f(y, x);
        }
    }

    /// Link angles (rad) in [`Self::link_angles`] order: for RRR the two
    /// links into the output joint, for RRP the rod, for RPR the slot, for
    /// RSSR the rocker (about its axis from its zero direction).
    pub fn link_angles(&self, pose: &Pose<T>, k: usize, out: &mut Vec<T>) {
        out.clear();
        let p = pose.at(k);
        let ang = |plane: &Plane<T>, a: usize, b: usize| {
            let d = plane.project(&p[b]) - plane.project(&p[a]);
            d.y.angle_of(d.x)
        };
        for step in &self.steps {
            match step {
                Step::Rrr {
                    p1, p2, plane, out: b, ..
                } => {
                    out.push(ang(plane, *p1, *b));
                    out.push(ang(plane, *p2, *b));
                }
                Step::Rrp {
                    from, plane, out: g, ..
                } => out.push(ang(plane, *from, *g)),
                Step::Rpr {
                    from, pivot, plane, e, ..
                } => {
                    // Direction of the slot, from the pivot's foot toward the pin.
                    let u =
                        rpr::rpr(plane.project(&p[*from]), plane.project(&p[*pivot]), *e).map_or(V2::x(), |(u, _)| u);
                    out.push(u.y.angle_of(u.x));
                }
                Step::Rssr {
                    rocker, zero, out: b, ..
                } => {
                    let q = p[*b] - rocker.c;
                    let y = rocker.w.cross(zero);
                    out.push(q.dot(&y).angle_of(q.dot(zero)));
                }
                _ => {}
            }
        }
    }

    /// Values of the model's measures (mm).
    pub fn measures(&self, pose: &Pose<T>, k: usize, out: &mut Vec<T>) {
        out.clear();
        let p = pose.at(k);
        for m in &self.measures {
            out.push(match m {
                MeasureStep::Distance { a, b } => crate::geometry::norm_or_zero(p[*a] - p[*b]),
                MeasureStep::LineDeviation { p: q, h, t, plane } => match plane {
                    Some(pl) => {
                        let (h, t, q) = (pl.project(&p[*h]), pl.project(&p[*t]), pl.project(&p[*q]));
                        let u = unit(t - h).unwrap_or(V2::x());
                        crate::geometry::cross2(u, q - h)
                    }
                    None => {
                        let u = unit(p[*t] - p[*h]).unwrap_or(V3::x());
                        crate::geometry::norm_or_zero((p[*q] - p[*h]).cross(&u))
                    }
                },
                MeasureStep::Coordinate {
                    p: q,
                    from,
                    origin,
                    axis,
                } => {
                    let o = from.map_or(*origin, |f| p[f]);
                    (p[*q] - o).dot(axis)
                }
            });
        }
    }

    /// The position of point `slot` if it is fixed.
    fn fixed_point(&self, slot: usize) -> Option<V3<T>> {
        self.fixed.iter().find(|(s, _)| *s == slot).map(|(_, p)| *p)
    }

    /// Number of point slots.
    /// The slots of the fixed points, in order.
    pub fn fixed_slots(&self) -> Vec<usize> {
        self.fixed.iter().map(|(s, _)| *s).collect()
    }

    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// The xy-plane of frame `index` (see [`crate::model::Model::frame_index`]).
    pub fn frame_plane(&self, index: usize) -> Plane<T> {
        if index == 0 {
            Plane::WORLD
        } else {
            Plane(Some(self.frames[index]))
        }
    }
}

/// Unit direction of a guide line given by the difference `d` of its points.
fn unit<T: Real, const D: usize>(d: nalgebra::SVector<T, D>) -> Result<nalgebra::SVector<T, D>, NoAssembly> {
    let n = d.norm();
    if n.re() <= 0.0 {
        return Err(NoAssembly::coincident("the two points that define the guide line"));
    }
    Ok(d / n)
}
