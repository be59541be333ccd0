//! Exact first and second analogs (d/dφ, d²/dφ², per radian) of every
//! point, in closed form from the solved positions: each group's closure is
//! differentiated once and twice, which gives a small *linear* system for
//! the output's analogs in terms of its inputs' (the same matrix for both
//! orders). Cheaper than carrying second-order dual numbers through the
//! position formulas (no square root or division of duals), and exact:
//! the tests compare it with the dual-number solve to 1e-9.
//!
//! Groups covered: cranks, RRR, RRP and spatial point-on-line with a guide
//! of fixed direction, RSSR, planar rigid points and offsets. A mechanism
//! with any other step (RPR, a guide through two moving points, a spatial
//! rigid point, a numerical group) returns `None` from
//! [`Mechanism::analogs`], and its analogs come from the dual-number solve.
//!
//! With `d = B − A` of a link of constant length, `d·d = l²` differentiates
//! to `d·d′ = 0` and `d·d″ + d′·d′ = 0`: every formula below is that, or
//! the derivative of a point moving on a fixed line or circle.

use super::rssr::Rocker;
use super::{AssemblyError, Mechanism, Phi, Pose, Step};
use crate::geometry::{Plane, PlaneMap, V2, V3, perp};
use crate::scalar::Real;
use crate::with_plane;

/// d/dφ and d²/dφ² of every point over a cycle, per radian of φ.
#[derive(Debug, Clone)]
pub struct PoseAnalogs {
    n: usize,
    vel: Vec<Vec<V3<f64>>>,
    acc: Vec<Vec<V3<f64>>>,
}

impl PoseAnalogs {
    /// Zero analogs (fixed points keep them) for `n` positions of `points` points.
    pub fn new(points: usize, n: usize) -> PoseAnalogs {
        PoseAnalogs {
            n,
            vel: vec![vec![V3::zeros(); n]; points],
            acc: vec![vec![V3::zeros(); n]; points],
        }
    }
    /// Keeps the first `n` positions (`n` ≤ [`Self::len`]).
    pub fn truncate(&mut self, n: usize) {
        assert!(n <= self.n, "analogs only shrink");
        self.n = n;
        self.vel.iter_mut().chain(&mut self.acc).for_each(|t| t.truncate(n));
    }
    /// First analog of point `slot` at the `k`-th φ, mm/rad.
    pub fn vel(&self, slot: usize, k: usize) -> V3<f64> {
        self.vel[slot][k]
    }
    /// Second analog of point `slot` at the `k`-th φ, mm/rad².
    pub fn acc(&self, slot: usize, k: usize) -> V3<f64> {
        self.acc[slot][k]
    }
    pub fn len(&self) -> usize {
        self.n
    }
    /// Whether it holds `n` positions of `points` points.
    pub fn fits(&self, points: usize, n: usize) -> bool {
        self.n == n && self.vel.len() == points && self.vel.iter().all(|t| t.len() == n)
    }
    /// Makes `self` ready for [`Mechanism::analogs`] of `mech` over `n`
    /// positions as [`Self::new`] would, reusing its buffers: the fixed
    /// points' analogs are zeroed, every other point's is written by the
    /// solve.
    pub fn reset_for(&mut self, mech: &Mechanism<f64>, n: usize) {
        if !self.fits(mech.n_points(), n) {
            *self = PoseAnalogs::new(mech.n_points(), n);
            return;
        }
        for (slot, _) in &mech.fixed {
            self.vel[*slot].fill(V3::zeros());
            self.acc[*slot].fill(V3::zeros());
        }
    }
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }
    /// First analogs of point `slot` over the cycle.
    pub fn vel_track(&self, slot: usize) -> &[V3<f64>] {
        &self.vel[slot]
    }
    /// Second analogs of point `slot` over the cycle.
    pub fn acc_track(&self, slot: usize) -> &[V3<f64>] {
        &self.acc[slot]
    }
}

/// `x` with `m·x = rhs` for the 2×2 matrix of rows `r1`, `r2` (Cramer),
/// given `inv_det = 1/det m`. At a dead point (`det = 0`) the analogs are
/// infinite, and so is the answer: the caller reports non-finite analogs as
/// it does for the dual solve.
#[inline(always)]
fn solve2(r1: V2<f64>, r2: V2<f64>, inv_det: f64, rhs: V2<f64>) -> V2<f64> {
    V2::new(
        (rhs.x * r2.y - r1.y * rhs.y) * inv_det,
        (r1.x * rhs.y - rhs.x * r2.x) * inv_det,
    )
}

impl Mechanism<f64> {
    /// Whether every step has closed-form analogs (see the module docs).
    pub fn has_closed_form_analogs(&self) -> bool {
        self.steps.iter().all(|s| match s {
            Step::Crank { .. } | Step::Rrr { .. } | Step::Rssr { .. } | Step::Offset { .. } => true,
            Step::Rrp { toward, .. } | Step::PointOnLine { toward, .. } => toward.is_none(),
            Step::Rigid { .. } => true,
            Step::Rpr { .. } | Step::Rigid3 { .. } | Step::Newton(_) | Step::CamFollower(_) => false,
        })
    }

    crate::scalar::widest! {
        /// The analogs of a solved `pose` at `phis` (the φ it was solved at),
        /// into `out`; `None` when a step has no closed form (then nothing is
        /// written).
        pub fn analogs(&self, phis: &[Phi<f64>], pose: &Pose<f64>, out: &mut PoseAnalogs) -> Option<()> => analogs_in for Mechanism<f64>
    }

    /// [`Self::analogs`], inlined into each vector-unit variant.
    #[inline(always)]
    fn analogs_in(&self, phis: &[Phi<f64>], pose: &Pose<f64>, out: &mut PoseAnalogs) -> Option<()> {
        if !self.has_closed_form_analogs() {
            return None;
        }
        let n = pose.n;
        assert!(phis.len() == n && out.n == n, "one φ per pose position");
        for step in &self.steps {
            let o = step.out().expect("closed-form steps place one point");
            // The output's analogs are taken out while the inputs' are read.
            let (mut v, mut a) = (std::mem::take(&mut out.vel[o]), std::mem::take(&mut out.acc[o]));
            let inputs = Inputs {
                x: &pose.tracks,
                v: &out.vel,
                a: &out.acc,
                n,
            };
            step_analogs(step, &inputs, &pose.tracks[o][..n], &mut v[..n], &mut a[..n]);
            out.vel[o] = v;
            out.acc[o] = a;
        }
        Some(())
    }
}

/// The tracks a step reads: positions, analogs of the points before it, as
/// slices of the cycle's length (no bounds checks in the loops).
struct Inputs<'a> {
    x: &'a [Vec<V3<f64>>],
    v: &'a [Vec<V3<f64>>],
    a: &'a [Vec<V3<f64>>],
    n: usize,
}

impl<'a> Inputs<'a> {
    #[inline(always)]
    fn x(&self, s: usize) -> &'a [V3<f64>] {
        &self.x[s][..self.n]
    }
    #[inline(always)]
    fn v(&self, s: usize) -> &'a [V3<f64>] {
        &self.v[s][..self.n]
    }
    #[inline(always)]
    fn a(&self, s: usize) -> &'a [V3<f64>] {
        &self.a[s][..self.n]
    }
}

/// One closed-form step's output analogs `vo`, `ao` from its position `xo`
/// and its inputs.
#[inline(always)]
fn step_analogs(step: &Step<f64>, t: &Inputs, xo: &[V3<f64>], vo: &mut [V3<f64>], ao: &mut [V3<f64>]) {
    let n = t.n;
    match step {
        Step::Crank {
            center, speed, u, v: w, ..
        } => {
            // out = c + ρ(θ), ρ = r(cos θ·u + sin θ·w), θ = speed·φ + phase:
            // ρ′ = speed·(ρ·u·w − ρ·w·u), ρ″ = −speed²·ρ.
            let (c, cv, ca) = (t.x(*center), t.v(*center), t.a(*center));
            for k in 0..n {
                let rho = xo[k] - c[k];
                let (ru, rw) = (rho.dot(u), rho.dot(w));
                vo[k] = cv[k] + (w * ru - u * rw) * *speed;
                ao[k] = ca[k] - rho * (speed * speed);
            }
        }
        Step::Rrr { p1, p2, plane, .. } => rrr_analogs(t, [*p1, *p2], plane, xo, vo, ao),
        Step::Rrp {
            from,
            through,
            dir,
            plane,
            ..
        } => {
            // G = H + off + s·u on a guide of fixed direction u, |G − A| = l:
            // w = G − A, s′ = −w·(H′ − A′)/(w·u), s″ = −(|G′ − A′|² + w·(H″ − A″))/(w·u).
            let (xa, vh, va, ah, aa) = (t.x(*from), t.v(*through), t.v(*from), t.a(*through), t.a(*from));
            with_plane!(plane, pl => for k in 0..n {
                let w = pl.project(&xo[k]) - pl.project(&xa[k]);
                let (hv, av) = (pl.project_dir(&vh[k]), pl.project_dir(&va[k]));
                let inv_wu = 1.0 / w.dot(dir);
                let gv = hv - *dir * (w.dot(&(hv - av)) * inv_wu);
                let (ha, aa) = (pl.project_dir(&ah[k]), pl.project_dir(&aa[k]));
                let ga = ha - *dir * (((gv - av).norm_squared() + w.dot(&(ha - aa))) * inv_wu);
                vo[k] = pl.lift_dir(gv);
                ao[k] = pl.lift_dir(ga);
            })
        }
        Step::PointOnLine { from, through, dir, .. } => {
            // The spatial form of the RRP guide above.
            let (xa, vh, va, ah, aa) = (t.x(*from), t.v(*through), t.v(*from), t.a(*through), t.a(*from));
            for k in 0..n {
                let w = xo[k] - xa[k];
                let inv_wu = 1.0 / w.dot(dir);
                let gv = vh[k] - *dir * (w.dot(&(vh[k] - va[k])) * inv_wu);
                vo[k] = gv;
                ao[k] = ah[k] - *dir * (((gv - va[k]).norm_squared() + w.dot(&(ah[k] - aa[k]))) * inv_wu);
            }
        }
        Step::Rssr { from, rocker, .. } => rssr_analogs(t, *from, rocker, xo, vo, ao),
        Step::Rigid {
            base,
            dc,
            ds,
            base_len,
            plane,
            ..
        } => rigid_analogs(t, *base, [*dc, *ds], *base_len, plane, vo, ao),
        Step::Offset { from, .. } => {
            vo.copy_from_slice(t.v(*from));
            ao.copy_from_slice(t.a(*from));
        }
        Step::Rpr { .. } | Step::Rigid3 { .. } | Step::Newton(_) | Step::CamFollower(_) => {
            unreachable!("checked by has_closed_form_analogs")
        }
    }
}

/// RRR: d1 = B − P1, d2 = B − P2 of constant length:
/// d1·B′ = d1·P1′, d2·B′ = d2·P2′ (seed 002 eq. 3–5 differentiated);
/// d1·B″ = d1·P1″ − |B′ − P1′|², likewise for d2.
#[inline(always)]
fn rrr_analogs(
    t: &Inputs,
    [p1, p2]: [usize; 2],
    plane: &Plane<f64>,
    xo: &[V3<f64>],
    vo: &mut [V3<f64>],
    ao: &mut [V3<f64>],
) {
    let (x1, x2, v1s, v2s, a1s, a2s) = (t.x(p1), t.x(p2), t.v(p1), t.v(p2), t.a(p1), t.a(p2));
    with_plane!(plane, pl => for k in 0..t.n {
        let b = pl.project(&xo[k]);
        let (d1, d2) = (b - pl.project(&x1[k]), b - pl.project(&x2[k]));
        let (v1, v2) = (pl.project_dir(&v1s[k]), pl.project_dir(&v2s[k]));
        let inv_det = 1.0 / (d1.x * d2.y - d1.y * d2.x);
        let bv = solve2(d1, d2, inv_det, V2::new(d1.dot(&v1), d2.dot(&v2)));
        let (a1, a2) = (pl.project_dir(&a1s[k]), pl.project_dir(&a2s[k]));
        let rhs = V2::new(d1.dot(&a1) - (bv - v1).norm_squared(), d2.dot(&a2) - (bv - v2).norm_squared());
        vo[k] = pl.lift_dir(bv);
        ao[k] = pl.lift_dir(solve2(d1, d2, inv_det, rhs));
    })
}

/// RSSR: B = c + r(cos ψ u + sin ψ v) on the fixed rocker circle, |B − A| = l.
/// B_ψ = −q·v u + q·u v, B_ψψ = −q (q = B − c, in the rocker's plane);
/// w = B − A: ψ′ = w·A′/(w·B_ψ),
/// ψ″ = (w·A″ − |B′ − A′|² − w·B_ψψ ψ′²)/(w·B_ψ).
#[inline(always)]
fn rssr_analogs(t: &Inputs, from: usize, rocker: &Rocker<f64>, xo: &[V3<f64>], vo: &mut [V3<f64>], ao: &mut [V3<f64>]) {
    let (xa, va, aa) = (t.x(from), t.v(from), t.a(from));
    for k in 0..t.n {
        let q = xo[k] - rocker.c;
        let b_psi = rocker.v * q.dot(&rocker.u) - rocker.u * q.dot(&rocker.v);
        let w = xo[k] - xa[k];
        let inv = 1.0 / w.dot(&b_psi);
        let psi1 = w.dot(&va[k]) * inv;
        let bv = b_psi * psi1;
        let psi2 = (w.dot(&aa[k]) - (bv - va[k]).norm_squared() + w.dot(&q) * psi1 * psi1) * inv;
        vo[k] = bv;
        ao[k] = b_psi * psi2 - q * (psi1 * psi1);
    }
}

/// A planar rigid point P = A + dc·e + ds·perp(e) on the base A→B.
#[inline(always)]
fn rigid_analogs(
    t: &Inputs,
    base: [usize; 2],
    [dc, ds]: [f64; 2],
    base_len: Option<f64>,
    plane: &Plane<f64>,
    vo: &mut [V3<f64>],
    ao: &mut [V3<f64>],
) {
    let (x0, x1, v0s, v1s, a0s, a1s) = (
        t.x(base[0]),
        t.x(base[1]),
        t.v(base[0]),
        t.v(base[1]),
        t.a(base[0]),
        t.a(base[1]),
    );
    match base_len {
        // P = A + (dc/l)·d + (ds/l)·perp(d), d = B − A: linear in A and B.
        Some(l) => {
            let (dcl, dsl) = (dc / l, ds / l);
            let lin = |pa: V2<f64>, pb: V2<f64>| {
                let d = pb - pa;
                pa + d * dcl + perp(d) * dsl
            };
            with_plane!(plane, pl => for k in 0..t.n {
                vo[k] = pl.lift_dir(lin(pl.project_dir(&v0s[k]), pl.project_dir(&v1s[k])));
                ao[k] = pl.lift_dir(lin(pl.project_dir(&a0s[k]), pl.project_dir(&a1s[k])));
            })
        }
        // e = d/L: with L′ = e·d′ (l_1), e′ = (d′ − e L′)/L,
        // L″ = e′·d′ + e·d″ (l_2), e″ = (d″ − L″ e − 2L′ e′)/L.
        None => with_plane!(plane, pl => for k in 0..t.n {
            let d = pl.project(&x1[k]) - pl.project(&x0[k]);
            let (a0v, a0a) = (pl.project_dir(&v0s[k]), pl.project_dir(&a0s[k]));
            let dv = pl.project_dir(&v1s[k]) - a0v;
            let da = pl.project_dir(&a1s[k]) - a0a;
            let inv_l = 1.0 / d.norm();
            let e = d * inv_l;
            let l_1 = e.dot(&dv);
            let e1 = (dv - e * l_1) * inv_l;
            let l_2 = e1.dot(&dv) + e.dot(&da);
            let e2 = (da - e * l_2 - e1 * (2.0 * l_1)) * inv_l;
            vo[k] = pl.lift_dir(a0v + e1 * dc + perp(e1) * ds);
            ao[k] = pl.lift_dir(a0a + e2 * dc + perp(e2) * ds);
        }),
    }
}

impl<T: Real> Pose<T> {
    /// The pose of dual numbers that carries `pose`'s positions and `an`'s
    /// analogs (value, d/dφ, d²/dφ²), as the dual solve of `mech` would
    /// give it: the rest of a cycle (thread paths, angles, measures) then
    /// runs on it unchanged.
    pub fn from_analogs(mech: &Mechanism<T>, pose: &Pose<f64>, an: &PoseAnalogs) -> Pose<T> {
        let mut out = mech.new_pose(pose.n);
        out.set_analogs(pose, an);
        out
    }

    /// Overwrites this pose (of as many points and positions) with
    /// `pose`'s positions and `an`'s analogs.
    pub fn set_analogs(&mut self, pose: &Pose<f64>, an: &PoseAnalogs) {
        assert_eq!(self.n, pose.n);
        for (slot, track) in self.tracks.iter_mut().enumerate() {
            let (p, v, a) = (&pose.tracks[slot], &an.vel[slot], &an.acc[slot]);
            for (k, q) in track.iter_mut().enumerate() {
                let (p, v, a) = (p[k], v[k], a[k]);
                *q = V3::new(
                    T::from_parts(p.x, v.x, a.x),
                    T::from_parts(p.y, v.y, a.y),
                    T::from_parts(p.z, v.z, a.z),
                );
            }
        }
    }
}

/// Solves `mech` (any scalar) at the cycle `phis_deg`: for a dual scalar
/// whose mechanism has closed-form analogs, positions in `f64` (`plain`,
/// the same model and parameters) and analogs in closed form; otherwise
/// the solve in `T`.
pub fn solve_cycle<T: Real>(
    mech: &Mechanism<T>,
    plain: Option<&Mechanism<f64>>,
    phis_deg: &[f64],
) -> Result<Pose<T>, AssemblyError> {
    if let Some(m) = plain.filter(|m| m.has_closed_form_analogs()) {
        let phis = Phi::<f64>::table(phis_deg);
        let mut pose = m.new_pose(phis.len());
        m.solve(&phis, &mut pose)?;
        let mut an = PoseAnalogs::new(m.n_points(), phis.len());
        if m.analogs(&phis, &pose, &mut an).is_some() {
            return Ok(Pose::from_analogs(mech, &pose, &an));
        }
    }
    let mut pose = mech.new_pose(phis_deg.len());
    mech.solve(&Phi::table(phis_deg), &mut pose)?;
    Ok(pose)
}

/// [`solve_cycle`] a piece of the cycle at a time, into buffers of one
/// piece: the poses of consecutive pieces are the whole cycle's pose, piece
/// by piece (numerical groups continue from one piece to the next), while
/// memory holds one piece.
pub struct PieceSolver<'a, T: Real> {
    mech: &'a Mechanism<T>,
    /// The mechanism in `f64` with its pose and analogs, when the analogs
    /// have a closed form.
    plain: Option<(&'a Mechanism<f64>, Pose<f64>, PoseAnalogs)>,
    pose: Pose<T>,
}

impl<'a, T: Real> PieceSolver<'a, T> {
    /// A solver of pieces of at most `piece` positions (`plain` as for
    /// [`solve_cycle`]).
    pub fn new(mech: &'a Mechanism<T>, plain: Option<&'a Mechanism<f64>>, piece: usize) -> Self {
        let plain = plain
            .filter(|m| m.has_closed_form_analogs())
            .map(|m| (m, m.new_pose(piece), PoseAnalogs::new(m.n_points(), piece)));
        PieceSolver {
            mech,
            plain,
            pose: mech.new_pose(piece),
        }
    }

    /// The pose at `phis_deg`, the next piece of the cycle (at most the
    /// piece length; only the last piece may be shorter).
    pub fn solve(&mut self, phis_deg: &[f64]) -> Result<&Pose<T>, AssemblyError> {
        let n = phis_deg.len();
        self.pose.truncate(n);
        match &mut self.plain {
            Some((m, pose, an)) => {
                pose.truncate(n);
                an.truncate(n);
                let phis = Phi::<f64>::table(phis_deg);
                m.solve(&phis, pose)?;
                m.analogs(&phis, pose, an).expect("the closed form was checked");
                self.pose.set_analogs(pose, an);
            }
            None => self.mech.solve(&Phi::table(phis_deg), &mut self.pose)?,
        }
        Ok(&self.pose)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;
    use num_dual::Dual2_64;

    /// Closed-form analogs equal the dual-number solve's, for every preset
    /// whose groups all have a closed form, at every φ of a cycle.
    #[test]
    fn closed_form_analogs_equal_dual_numbers() {
        let mut covered = 0;
        for preset in crate::presets::ALL {
            let model = Model::preset(preset.name).unwrap();
            let params = model.defaults();
            let mech = model.mechanism::<f64>(&params).unwrap();
            if !mech.has_closed_form_analogs() {
                continue;
            }
            covered += 1;
            let phis_deg: Vec<f64> = (0..72).map(|k| model.phi_start_deg() + 5.0 * k as f64 + 0.37).collect();
            let phis = Phi::<f64>::table(&phis_deg);
            let mut pose = mech.new_pose(phis.len());
            mech.solve(&phis, &mut pose).unwrap();
            let mut an = PoseAnalogs::new(mech.n_points(), phis.len());
            mech.analogs(&phis, &pose, &mut an).unwrap();

            let dual = model.mechanism::<Dual2_64>(&params).unwrap();
            let mut dpose = dual.new_pose(phis.len());
            dual.solve(&Phi::table(&phis_deg), &mut dpose).unwrap();
            for slot in 0..mech.n_points() {
                for k in 0..phis.len() {
                    let q = dpose.point(slot, k);
                    for c in 0..3 {
                        let (v, a) = (an.vel(slot, k)[c], an.acc(slot, k)[c]);
                        let tol = |x: f64| 1e-9 * (1.0 + x.abs());
                        assert!(
                            (v - q[c].v1).abs() <= tol(v),
                            "{} point {slot} φ {} coord {c}: v {v} vs {}",
                            preset.name,
                            phis_deg[k],
                            q[c].v1
                        );
                        assert!(
                            (a - q[c].v2).abs() <= tol(a) * 10.0,
                            "{} point {slot} φ {} coord {c}: a {a} vs {}",
                            preset.name,
                            phis_deg[k],
                            q[c].v2
                        );
                    }
                }
            }
        }
        assert!(covered >= 3, "only {covered} presets have closed-form analogs");
    }

    /// `solve_cycle` with and without the closed form gives the same dual
    /// pose (the packing of positions and analogs into dual numbers).
    #[test]
    fn solve_cycle_packs_what_the_dual_solve_gives() {
        let model = Model::preset("needle876").unwrap();
        let params = model.defaults();
        let plain = model.mechanism::<f64>(&params).unwrap();
        let dual = model.mechanism::<Dual2_64>(&params).unwrap();
        let phis: Vec<f64> = (0..36).map(|k| 90.6 + 10.0 * k as f64).collect();
        let closed = solve_cycle(&dual, Some(&plain), &phis).unwrap();
        let reference = solve_cycle(&dual, None, &phis).unwrap();
        for slot in 0..plain.n_points() {
            for k in 0..phis.len() {
                let (a, b) = (closed.point(slot, k), reference.point(slot, k));
                for c in 0..3 {
                    assert!(
                        (a[c].re - b[c].re).abs() < 1e-9
                            && (a[c].v1 - b[c].v1).abs() < 1e-8
                            && (a[c].v2 - b[c].v2).abs() < 1e-7,
                        "{slot} {k} {c}: {a:?} vs {b:?}"
                    );
                }
            }
        }
    }
}
