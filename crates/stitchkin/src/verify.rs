//! An independent check of the closed-form groups: the whole mechanism's
//! loop-closure equations solved together by Newton's method, continued
//! from the previous φ (our stand-in for the SOLIDWORKS Motion check of
//! seed 002).
//!
//! Every moving point is an unknown (x, y, z); every step contributes the
//! equations its geometry imposes (distances, a point on a line or plane,
//! a point's place in a link frame) rather than its solution. The Jacobian
//! is taken by central differences and the linear systems are solved with
//! nalgebra's LU, so nothing is shared with the per-group solvers.

use nalgebra::{DMatrix, DVector};

use crate::error::Error;
use crate::error::NotFiniteError;
use crate::eval::cycle_phis_deg;
use crate::geometry::{Plane, V2, V3};
use crate::mechanism::newton::{Closure, NewtonGroup, PointRef};
use crate::mechanism::{Mechanism, Phi, Step};
use crate::model::{Model, Params};

/// Result of a cross-check over a cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct CrossCheck {
    /// Largest distance between the two solvers' positions of any point, mm.
    pub max_deviation_mm: f64,
    /// Where it occurs.
    pub at_phi_deg: f64,
    pub at_point: String,
    /// Positions compared.
    pub positions: usize,
}

/// Auxiliary unknowns: slotted levers (RPR) carry their slot angle.
struct Layout {
    moving: Vec<usize>,
    slot_of: Vec<Option<usize>>,
    aux: Vec<usize>,
    n: usize,
}

fn layout(mech: &Mechanism<f64>) -> Layout {
    let fixed: Vec<usize> = mech.fixed.iter().map(|(s, _)| *s).collect();
    let moving: Vec<usize> = (0..mech.n_points).filter(|s| !fixed.contains(s)).collect();
    let mut slot_of = vec![None; mech.n_points];
    for (k, &s) in moving.iter().enumerate() {
        slot_of[s] = Some(k);
    }
    let mut aux = vec![usize::MAX; mech.steps.len()];
    let mut n = 3 * moving.len();
    for (i, s) in mech.steps.iter().enumerate() {
        if matches!(s, Step::Rpr { .. }) {
            aux[i] = n;
            n += 1;
        }
    }
    Layout {
        moving,
        slot_of,
        aux,
        n,
    }
}

fn in_plane(plane: &Plane<f64>, p: &V3<f64>) -> (V2<f64>, f64) {
    match &plane.0 {
        None => (V2::new(p.x, p.y), p.z),
        Some(f) => {
            let q = f.to_local(*p);
            (q.xy(), q.z)
        }
    }
}

/// The unknowns `x` laid over the mechanism's points: a moving point's
/// position is three of them, a fixed point is where the mechanism puts it.
struct Unknowns<'a> {
    mech: &'a Mechanism<f64>,
    lay: &'a Layout,
    x: &'a DVector<f64>,
}

impl Unknowns<'_> {
    fn pt(&self, s: usize) -> V3<f64> {
        match self.lay.slot_of[s] {
            Some(k) => V3::new(self.x[3 * k], self.x[3 * k + 1], self.x[3 * k + 2]),
            None => self
                .mech
                .fixed
                .iter()
                .find(|(i, _)| *i == s)
                .map(|(_, p)| *p)
                .unwrap_or_else(V3::zeros),
        }
    }
}

/// Residuals of every closure equation at unknowns `x`.
fn residuals(mech: &Mechanism<f64>, lay: &Layout, phi: f64, x: &DVector<f64>, out: &mut Vec<f64>) {
    out.clear();
    let vars = Unknowns { mech, lay, x };
    for (i, step) in mech.steps.iter().enumerate() {
        step_residuals(step, i, &vars, phi, out);
    }
}

/// The equations of step `i`: a crank's place on its circle, the planar
/// dyads' distances and lines; the other steps go on to
/// [`spatial_residuals`].
fn step_residuals(step: &Step<f64>, i: usize, vars: &Unknowns, phi: f64, out: &mut Vec<f64>) {
    match step {
        Step::Crank {
            center,
            out: o,
            r,
            u,
            v,
            speed,
            phase,
            ..
        } => {
            let th = speed * phi + phase;
            let d = vars.pt(*o) - (vars.pt(*center) + (u * th.cos() + v * th.sin()) * *r);
            out.extend([d.x, d.y, d.z]);
        }
        Step::Rrr {
            p1,
            p2,
            l1,
            l2,
            plane,
            out: b,
            ..
        } => {
            let (q, h) = in_plane(plane, &vars.pt(*b));
            let (a, _) = in_plane(plane, &vars.pt(*p1));
            let (c, _) = in_plane(plane, &vars.pt(*p2));
            out.extend([(q - a).norm() - l1, (q - c).norm() - l2, h]);
        }
        Step::Rrp {
            from,
            through,
            toward,
            dir,
            offset,
            l,
            plane,
            out: g,
            ..
        } => {
            let (q, h) = in_plane(plane, &vars.pt(*g));
            let (a, _) = in_plane(plane, &vars.pt(*from));
            let (hh, _) = in_plane(plane, &vars.pt(*through));
            let u = match toward {
                Some(t) => (in_plane(plane, &vars.pt(*t)).0 - hh).normalize(),
                None => *dir,
            };
            // Signed distance of the slider from the guide line = offset.
            let side = u.x * (q - hh).y - u.y * (q - hh).x;
            out.extend([side - offset, (q - a).norm() - l, h]);
        }
        Step::Rpr {
            from,
            pivot,
            e,
            d,
            plane,
            out: o,
            ..
        } => {
            let th = vars.x[vars.lay.aux[i]];
            let (u, n) = (V2::new(th.cos(), th.sin()), V2::new(-th.sin(), th.cos()));
            let (a, _) = in_plane(plane, &vars.pt(*from));
            let (c, _) = in_plane(plane, &vars.pt(*pivot));
            let (q, h) = in_plane(plane, &vars.pt(*o));
            let dq = q - (c + n * *e + u * *d);
            // The slot line (through c + e·n along u) holds the pin, ahead of the foot.
            out.extend([n.dot(&(a - c)) - e, dq.x, dq.y, h]);
        }
        other => spatial_residuals(other, vars, out),
    }
}

/// The equations of the spatial dyads, the points carried by links and
/// the numerical groups.
fn spatial_residuals(step: &Step<f64>, vars: &Unknowns, out: &mut Vec<f64>) {
    match step {
        Step::Rssr {
            from,
            rocker,
            l,
            out: b,
            ..
        } => {
            let q = vars.pt(*b);
            out.extend([
                (q - vars.pt(*from)).norm() - l,
                (q - rocker.c).norm() - rocker.r,
                (q - rocker.c).dot(&rocker.w),
            ]);
        }
        Step::PointOnLine {
            from,
            through,
            toward,
            dir,
            l,
            out: p,
            ..
        } => {
            let h = vars.pt(*through);
            let u = match toward {
                Some(t) => (vars.pt(*t) - h).normalize(),
                None => *dir,
            };
            let [o1, o2] = off_line(u, vars.pt(*p) - h);
            out.extend([o1, o2, (vars.pt(*p) - vars.pt(*from)).norm() - l]);
        }
        Step::Rigid {
            base,
            dc,
            ds,
            lift,
            plane,
            out: o,
            ..
        } => {
            let (a, _) = in_plane(plane, &vars.pt(base[0]));
            let (b, _) = in_plane(plane, &vars.pt(base[1]));
            let (q, h) = in_plane(plane, &vars.pt(*o));
            let e = b - a;
            let n = e.norm();
            let w = q - a;
            // Projections of the point on the link and across it.
            out.extend([w.dot(&e) / n - dc, (e.x * w.y - e.y * w.x) / n - ds, h - lift]);
        }
        Step::Rigid3 { frame, at, out: o } => {
            let (o0, x1, y1) = (vars.pt(frame[0]), vars.pt(frame[1]), vars.pt(frame[2]));
            let e1 = (x1 - o0).normalize();
            let e3 = e1.cross(&(y1 - o0)).normalize();
            let e2 = e3.cross(&e1);
            let w = vars.pt(*o) - o0;
            out.extend([w.dot(&e1) - at.x, w.dot(&e2) - at.y, w.dot(&e3) - at.z]);
        }
        Step::Offset { from, by, out: o } => {
            let d = vars.pt(*o) - vars.pt(*from) - by;
            out.extend([d.x, d.y, d.z]);
        }
        Step::Newton(g) => newton_residuals(g, vars, out),
        // A follower's point is its lift by definition (the contact
        // geometry is checked against the textbook formulas in
        // `mechanism::cam_follower`): here, that the point sits where the
        // cam's and the pivot's solved places put it, in the plane.
        Step::CamFollower(c) => {
            let (q, h) = in_plane(&c.plane, &vars.pt(c.out));
            let (ce, _) = in_plane(&c.plane, &vars.pt(c.center));
            let (mk, _) = in_plane(&c.plane, &vars.pt(c.marker));
            let pivot = c.pivot.map(|p| in_plane(&c.plane, &vars.pt(p)).0);
            match c.cam.point(ce, mk, pivot) {
                Ok(r) => out.extend([q.x - r.x, q.y - r.y, h]),
                Err(e) => out.extend([e.defect_mm.abs().max(1.0), 0.0, h]),
            }
        }
        Step::Crank { .. } | Step::Rrr { .. } | Step::Rrp { .. } | Step::Rpr { .. } => {
            unreachable!("residuals of step_residuals")
        }
    }
}

/// A numerical group's closures, and for a planar one every unknown point
/// in its plane.
fn newton_residuals(g: &NewtonGroup<f64>, vars: &Unknowns, out: &mut Vec<f64>) {
    for c in &g.closures {
        let p = |r: &PointRef| match r {
            PointRef::Unknown(k) => vars.pt(g.outs[*k]),
            PointRef::Known(s) => vars.pt(*s),
        };
        match c {
            Closure::Distance { a, b, l } => {
                if g.dim == 2 {
                    let (pa, _) = in_plane(&g.plane, &p(a));
                    let (pb, _) = in_plane(&g.plane, &p(b));
                    out.push((pa - pb).norm() - l);
                } else {
                    out.push((p(a) - p(b)).norm() - l);
                }
            }
            Closure::OnLine { p: k, h, t } => {
                let q = vars.pt(g.outs[*k]);
                if g.dim == 2 {
                    let (q, _) = in_plane(&g.plane, &q);
                    let (h, _) = in_plane(&g.plane, &vars.pt(*h));
                    let (t, _) = in_plane(&g.plane, &vars.pt(*t));
                    let u = (t - h).normalize();
                    out.push(u.x * (q - h).y - u.y * (q - h).x);
                } else {
                    let (h, t) = (vars.pt(*h), vars.pt(*t));
                    let u = (t - h).normalize();
                    out.extend(off_line(u, q - h));
                }
            }
        }
    }
    if g.dim == 2 {
        for &o in &g.outs {
            out.push(in_plane(&g.plane, &vars.pt(o)).1);
        }
    }
}

/// The two components, across the unit direction `u`, of the offset `w` of a
/// point from a line (both zero when the point is on it), in a basis fixed
/// by `u`.
fn off_line(u: V3<f64>, w: V3<f64>) -> [f64; 2] {
    let across = w - u * w.dot(&u);
    let e = if u.x.abs() < 0.9 { V3::x() } else { V3::y() };
    let n1 = u.cross(&e).normalize();
    [across.dot(&n1), across.dot(&u.cross(&n1))]
}

/// Newton on the whole system from `x`; returns the final residual norm.
fn newton(mech: &Mechanism<f64>, lay: &Layout, phi: f64, x: &mut DVector<f64>) -> f64 {
    let n = lay.n;
    let mut r = Vec::with_capacity(n);
    let mut rp = Vec::with_capacity(n);
    let mut rm = Vec::with_capacity(n);
    let mut res = f64::INFINITY;
    for _ in 0..50 {
        residuals(mech, lay, phi, x, &mut r);
        res = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if res < 1e-13 {
            break;
        }
        let mut j = DMatrix::zeros(r.len(), n);
        for c in 0..n {
            let h = 1e-6 * (1.0 + x[c].abs());
            let keep = x[c];
            x[c] = keep + h;
            residuals(mech, lay, phi, x, &mut rp);
            x[c] = keep - h;
            residuals(mech, lay, phi, x, &mut rm);
            x[c] = keep;
            for row in 0..r.len() {
                j[(row, c)] = (rp[row] - rm[row]) / (2.0 * h);
            }
        }
        let Some(dx) = j.lu().solve(&DVector::from_vec(r.clone())) else {
            break;
        };
        *x -= dx;
        if x.iter().any(|v| !v.is_finite()) {
            return f64::INFINITY;
        }
    }
    res
}

/// Solves `model` over a cycle with both the closed-form groups and the
/// whole-system Newton solver, and reports the largest disagreement.
///
/// The Newton solver starts once from the closed-form pose at the cycle's
/// first φ, displaced by 0.05 mm, and then continues on its own from its
/// previous solution.
pub fn cross_check(model: &Model, params: &Params, step_deg: f64) -> Result<CrossCheck, Error> {
    let mech = model.mechanism::<f64>(params)?;
    let lay = layout(&mech);
    let phis = cycle_phis_deg(model.phi_start_deg(), step_deg);
    let mut pose = mech.new_pose(1);
    let mut x = DVector::zeros(lay.n);
    let mut worst = CrossCheck {
        max_deviation_mm: 0.0,
        at_phi_deg: phis[0],
        at_point: String::new(),
        positions: 0,
    };
    for (k, &phi_deg) in phis.iter().enumerate() {
        let phi = phi_deg.to_radians();
        mech.solve(&[Phi::new(phi)], &mut pose)?;
        let at = pose.at(0);
        if k == 0 {
            for (i, &s) in lay.moving.iter().enumerate() {
                for c in 0..3 {
                    x[3 * i + c] = at[s][c] + 0.05 * ((i + c) % 3) as f64 - 0.05;
                }
            }
            // Slot angles of slotted levers from the closed-form pose.
            for (i, s) in mech.steps.iter().enumerate() {
                if let Step::Rpr {
                    pivot,
                    out,
                    e,
                    d,
                    plane,
                    ..
                } = s
                {
                    let (c, _) = in_plane(plane, &at[*pivot]);
                    let (q, _) = in_plane(plane, &at[*out]);
                    let w = q - c;
                    // q − c = e·n + d·u: rotate back by the angle of (d, e).
                    x[lay.aux[i]] = w.y.atan2(w.x) - e.atan2(*d) + 0.01;
                }
            }
        }
        let res = newton(&mech, &lay, phi, &mut x);
        if res.is_nan() || res >= 1e-9 {
            return Err(Error::NotFinite(NotFiniteError {
                quantity: "the whole-system Newton solution".into(),
                phi_deg: Some(phi_deg),
                cause: format!("the solver did not converge (residual {res:.3e})"),
            }));
        }
        for (i, &s) in lay.moving.iter().enumerate() {
            let q = V3::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
            let d = (q - at[s]).norm();
            if d > worst.max_deviation_mm || worst.at_point.is_empty() {
                worst.max_deviation_mm = d;
                worst.at_phi_deg = phi_deg;
                worst.at_point = model.point_names[s].clone();
            }
        }
        worst.positions += 1;
    }
    Ok(worst)
}
