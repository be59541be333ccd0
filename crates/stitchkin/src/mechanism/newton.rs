//! Numerical group: Newton's method on a group's closure equations,
//! continued from the previous φ, for groups without a closed form (class III
//! and higher Assur groups).
//!
//! Positions are solved in `f64`. Exact analogs then come from two more
//! Newton steps taken in the dual-number type `T` with the converged real
//! Jacobian: each step doubles the number of exact derivative orders
//! (implicit function theorem), so two steps make the first and second
//! derivatives exact to rounding.

use super::NoAssembly;
use crate::geometry::{Plane, V2, V3};
use crate::numeric::{lu_factor, lu_solve};
use crate::scalar::Real;

/// Where a constraint's point comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointRef {
    /// The i-th unknown of the group.
    Unknown(usize),
    /// A point already solved (pose slot).
    Known(usize),
}

#[derive(Debug, Clone, PartialEq)]
pub enum Closure<T: Real> {
    /// `|a − b| − l = 0`.
    Distance { a: PointRef, b: PointRef, l: T },
    /// `p` on the line through known points `h → t` (1 equation in a plane,
    /// 2 in space).
    OnLine { p: usize, h: usize, t: usize },
}

impl<T: Real> Closure<T> {
    pub fn equations(&self, dim: usize) -> usize {
        match self {
            Closure::Distance { .. } => 1,
            Closure::OnLine { .. } => dim - 1,
        }
    }
}

/// A resolved numerical group.
#[derive(Debug, Clone, PartialEq)]
pub struct NewtonGroup<T: Real> {
    /// 2 (planar, in `plane`) or 3.
    pub dim: usize,
    pub plane: Plane<T>,
    /// Pose slots of the unknown points, in unknown order.
    pub outs: Vec<usize>,
    /// Starting coordinates (in-plane for dim 2), the assembly guess.
    pub guess: Vec<f64>,
    pub closures: Vec<Closure<T>>,
}

/// Preallocated work space of one numerical group (kept between φ steps:
/// `x` is the continuation's warm start).
#[derive(Debug, Clone)]
pub struct NewtonState<T: Real> {
    pub x: Vec<f64>,
    started: bool,
    j: Vec<f64>,
    piv: Vec<usize>,
    r: Vec<f64>,
    dx: Vec<f64>,
    x0: Vec<f64>,
    xt: Vec<T>,
    rt: Vec<T>,
    known: Vec<V3<T>>,
}

impl<T: Real> NewtonGroup<T> {
    pub fn n(&self) -> usize {
        self.outs.len() * self.dim
    }

    pub fn new_state(&self) -> NewtonState<T> {
        let n = self.n();
        NewtonState {
            x: self.guess.clone(),
            started: false,
            j: vec![0.0; n * n],
            piv: vec![0; n],
            r: vec![0.0; n],
            dx: vec![0.0; n],
            x0: vec![0.0; n],
            xt: vec![T::zero(); n],
            rt: vec![T::zero(); n],
            known: Vec::new(),
        }
    }

    /// Point of `r` given unknowns `x` (plane coordinates padded with 0).
    fn point<S: Real>(&self, r: PointRef, x: &[S], known: &impl Fn(usize) -> V3<S>) -> V3<S> {
        match r {
            PointRef::Unknown(i) => {
                let k = i * self.dim;
                if self.dim == 2 {
                    V3::new(x[k], x[k + 1], S::zero())
                } else {
                    V3::new(x[k], x[k + 1], x[k + 2])
                }
            }
            PointRef::Known(slot) => known(slot),
        }
    }

    /// Residuals `F(x)` of the closure equations. `known(slot)` gives known
    /// points, already in plane coordinates (z = 0) for a planar group.
    fn residuals<S: Real>(&self, x: &[S], known: &impl Fn(usize) -> V3<S>, cst: impl Fn(T) -> S, out: &mut [S]) {
        let mut e = 0;
        for c in &self.closures {
            match c {
                Closure::Distance { a, b, l } => {
                    let d = self.point(*a, x, known) - self.point(*b, x, known);
                    out[e] = d.norm() - cst(*l);
                    e += 1;
                }
                Closure::OnLine { p, h, t } => {
                    let (h, t) = (known(*h), known(*t));
                    let w = self.point(PointRef::Unknown(*p), x, known) - h;
                    let u = (t - h).normalize();
                    if self.dim == 2 {
                        out[e] = u.x * w.y - u.y * w.x;
                        e += 1;
                    } else {
                        let (n1, n2) = normals(u);
                        out[e] = n1.dot(&w);
                        out[e + 1] = n2.dot(&w);
                        e += 2;
                    }
                }
            }
        }
    }

    /// Jacobian `∂F/∂x` at real `x` (row-major `n × n`).
    fn jacobian(&self, x: &[f64], known: &impl Fn(usize) -> V3<f64>, j: &mut [f64]) {
        let n = self.n();
        j.iter_mut().for_each(|v| *v = 0.0);
        let mut e = 0;
        let put = |row: usize, r: PointRef, g: V3<f64>, sign: f64, j: &mut [f64]| {
            if let PointRef::Unknown(i) = r {
                for k in 0..self.dim {
                    j[row * n + i * self.dim + k] += sign * g[k];
                }
            }
        };
        for c in &self.closures {
            match c {
                Closure::Distance { a, b, .. } => {
                    let d = self.point(*a, x, known) - self.point(*b, x, known);
                    let g = d / d.norm().max(1e-300);
                    put(e, *a, g, 1.0, j);
                    put(e, *b, g, -1.0, j);
                    e += 1;
                }
                Closure::OnLine { p, h, t } => {
                    let u = (known(*t) - known(*h)).normalize();
                    if self.dim == 2 {
                        put(e, PointRef::Unknown(*p), V3::new(-u.y, u.x, 0.0), 1.0, j);
                        e += 1;
                    } else {
                        let (n1, n2) = normals(u);
                        put(e, PointRef::Unknown(*p), n1, 1.0, j);
                        put(e + 1, PointRef::Unknown(*p), n2, 1.0, j);
                        e += 2;
                    }
                }
            }
        }
    }

    /// Solves the group at every φ of a pose's tracks in order, each from the
    /// previous solution, and writes its points.
    pub(crate) fn solve_track(
        &self,
        tracks: &mut [Vec<V3<T>>],
        n: usize,
        st: &mut NewtonState<T>,
    ) -> Result<(), (usize, NoAssembly)> {
        let mut pts = vec![V3::zeros(); tracks.len()];
        let slots = self.known_slots();
        for k in 0..n {
            for &s in &slots {
                pts[s] = tracks[s][k];
            }
            self.solve(&mut pts, st).map_err(|e| (k, e))?;
            for &s in &self.outs {
                tracks[s][k] = pts[s];
            }
        }
        Ok(())
    }

    fn known_slots(&self) -> Vec<usize> {
        let mut v = Vec::new();
        for c in &self.closures {
            match c {
                Closure::Distance { a, b, .. } => {
                    for r in [a, b] {
                        if let PointRef::Known(s) = r {
                            v.push(*s);
                        }
                    }
                }
                Closure::OnLine { h, t, .. } => v.extend([*h, *t]),
            }
        }
        v
    }

    /// Solves the group at one position and writes its points.
    /// `points` is the pose; `st` keeps the previous solution.
    pub fn solve(&self, points: &mut [V3<T>], st: &mut NewtonState<T>) -> Result<(), NoAssembly> {
        let n = self.n();
        // Known points in the group's coordinates.
        st.known.clear();
        st.known.resize(points.len(), V3::zeros());
        for c in &self.closures {
            let mut take = |r: PointRef| {
                if let PointRef::Known(s) = r {
                    st.known[s] = self.to_group(&points[s]);
                }
            };
            match c {
                Closure::Distance { a, b, .. } => {
                    take(*a);
                    take(*b);
                }
                Closure::OnLine { h, t, .. } => {
                    take(PointRef::Known(*h));
                    take(PointRef::Known(*t));
                }
            }
        }
        let known_t = &st.known;
        let known_re = |s: usize| known_t[s].map(|v| v.re());
        if !st.started {
            st.x.copy_from_slice(&self.guess);
            st.started = true;
        }
        // Real Newton with backtracking.
        let norm = |r: &[f64]| r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        self.residuals(&st.x, &known_re, |v: T| v.re(), &mut st.r);
        let mut res = norm(&st.r);
        let mut converged = res < 1e-11;
        for _ in 0..60 {
            if converged {
                break;
            }
            self.jacobian(&st.x, &known_re, &mut st.j);
            if !lu_factor(&mut st.j, n, &mut st.piv) {
                return Err(NoAssembly::new(
                    res,
                    "the closure equations are singular here (a dead point or a redundant constraint)".into(),
                ));
            }
            st.dx.copy_from_slice(&st.r);
            lu_solve(&st.j, n, &st.piv, &mut st.dx);
            st.x0.copy_from_slice(&st.x);
            let mut step = 1.0;
            loop {
                for k in 0..n {
                    st.x[k] = st.x0[k] - step * st.dx[k];
                }
                self.residuals(&st.x, &known_re, |v: T| v.re(), &mut st.r);
                let r1 = norm(&st.r);
                if r1.is_finite() && (r1 < res || step < 1e-3) {
                    res = r1;
                    break;
                }
                step *= 0.5;
            }
            let dmax = norm(&st.dx) * step;
            converged = res < 1e-11 || (dmax < 1e-13 && res < 1e-9);
        }
        if !converged || !res.is_finite() {
            return Err(NoAssembly::new(
                res,
                format!("Newton's method did not close the loop (largest closure residual {res:.3e} mm)"),
            ));
        }
        // Exact derivatives: two Newton steps in T with the real Jacobian.
        self.jacobian(&st.x, &known_re, &mut st.j);
        if !lu_factor(&mut st.j, n, &mut st.piv) {
            return Err(NoAssembly::new(
                0.0,
                "the group is at a singular position (its analogs are infinite)".into(),
            ));
        }
        for k in 0..n {
            st.xt[k] = T::cst(st.x[k]);
        }
        let known_t = |s: usize| known_t[s];
        for _ in 0..2 {
            self.residuals(&st.xt, &known_t, |v: T| v, &mut st.rt);
            lu_solve(&st.j, n, &st.piv, &mut st.rt);
            for k in 0..n {
                st.xt[k] -= st.rt[k];
            }
        }
        for (i, &slot) in self.outs.iter().enumerate() {
            let p = self.point(PointRef::Unknown(i), &st.xt, &known_t);
            points[slot] = self.group_to_space(p);
        }
        Ok(())
    }

    fn to_group(&self, p: &V3<T>) -> V3<T> {
        if self.dim == 2 {
            let q = self.plane.project(p);
            V3::new(q.x, q.y, T::zero())
        } else {
            *p
        }
    }

    fn group_to_space(&self, p: V3<T>) -> V3<T> {
        if self.dim == 2 {
            self.plane.lift(V2::new(p.x, p.y), T::zero())
        } else {
            p
        }
    }
}

/// Two unit normals of the unit vector `u`, chosen smoothly away from the
/// axis `u` is closest to.
fn normals<S: Real>(u: V3<S>) -> (V3<S>, V3<S>) {
    let (ax, ay, az) = (u.x.re().abs(), u.y.re().abs(), u.z.re().abs());
    let e = if ax <= ay && ax <= az {
        V3::x()
    } else if ay <= az {
        V3::y()
    } else {
        V3::z()
    };
    let n1 = u.cross(&e.map(S::cst)).normalize();
    let n2 = u.cross(&n1);
    (n1, n2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn newton_dyad_matches_closed_form() {
        // The 3-4-5 triangle as a numerical group.
        let g = NewtonGroup::<f64> {
            dim: 2,
            plane: Plane::WORLD,
            outs: vec![2],
            guess: vec![2.0, 2.0],
            closures: vec![
                Closure::Distance {
                    a: PointRef::Unknown(0),
                    b: PointRef::Known(0),
                    l: 3.0,
                },
                Closure::Distance {
                    a: PointRef::Unknown(0),
                    b: PointRef::Known(1),
                    l: 4.0,
                },
            ],
        };
        let mut pts = vec![V3::zeros(), V3::new(5.0, 0.0, 0.0), V3::zeros()];
        let mut st = g.new_state();
        g.solve(&mut pts, &mut st).unwrap();
        assert_relative_eq!(pts[2], V3::new(1.8, 2.4, 0.0), epsilon = 1e-12);
        // Unreachable: the residual is reported.
        pts[1] = V3::new(50.0, 0.0, 0.0);
        assert!(g.solve(&mut pts, &mut st).is_err());
    }
}
