//! Thread paths ("feed contours") and the actual take-up P(φ).
//!
//! A path runs from the tension regulator through fixed guides, eyelets on
//! moving links and one-sided guides to the needle (or looper) eye. Its
//! length is the contour length ξ(φ) = Σ |segment| (seed 000 eqs. 3–6);
//! the actual take-up is P(φ) = ξ(φ0) − ξ(φ) (seed 000 eq. 2) or, in the
//! convention of seed 001 (eqs. 22–23), P(φ) = ξ(φ) − ξ(φ0) + ΔP.
//!
//! Paths are evaluated over a whole [`Pose`] at once, segment by segment;
//! a segment whose two ends ride on one rigid body (two fixed guides, two
//! eyelets on the needle bar) is computed once per pose, not per φ.

pub mod wrap;

use crate::geometry::{Plane, V3};
use crate::mechanism::Pose;
use crate::scalar::Real;

/// One piece of a path between two nodes the thread passes through.
#[derive(Debug, Clone, PartialEq)]
pub enum Span<T: Real> {
    /// A straight segment `a → b`; `constant` when both ends ride on one
    /// rigid body.
    Straight { a: usize, b: usize, constant: bool },
    /// `a → b` over a one-sided cylindrical guide through point `c`.
    Pin { a: usize, b: usize, c: usize, axis: V3<T>, r: T, sense: f64, node: usize },
}

/// A thread path with every parameter resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct ThreadPath<T: Real> {
    pub name: String,
    /// Pose slots of the nodes, in thread order (pins included).
    pub nodes: Vec<usize>,
    /// The nodes' point names.
    pub node_names: Vec<String>,
    /// Friction coefficient at each node (the first node's is unused).
    pub friction: Vec<f64>,
    pub spans: Vec<Span<T>>,
}

/// How P(φ) is signed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Convention {
    /// `P = ξ(φ0) − ξ(φ)`.
    Release,
    /// `P = ξ(φ) − ξ(φ0) + ΔP`.
    Feed { elongation_mm: f64 },
}

impl Convention {
    /// P from ξ and ξ(φ0).
    #[inline]
    pub fn take_up<T: Real>(&self, xi: T, xi0: T) -> T {
        match self {
            Convention::Release => xi0 - xi,
            Convention::Feed { elongation_mm } => xi - xi0 + T::cst(*elongation_mm),
        }
    }
    /// Sign of dP/dξ.
    pub fn sign(&self) -> f64 {
        match self {
            Convention::Release => -1.0,
            Convention::Feed { .. } => 1.0,
        }
    }
}

/// The thread part of a resolved model.
#[derive(Debug, Clone, PartialEq)]
pub struct Threads<T: Real> {
    pub paths: Vec<ThreadPath<T>>,
    pub convention: Convention,
    /// φ0, degrees.
    pub phi0_deg: f64,
    /// Regulator tension, N.
    pub tension_n: Option<f64>,
}

/// A path evaluated over a pose.
#[derive(Debug, Clone, PartialEq)]
pub struct PathTrack<T: Real> {
    /// Contour length ξ at each φ, mm.
    pub xi: Vec<T>,
    /// For each pin (in node order): whether it is engaged at each φ.
    pub engaged: Vec<Vec<bool>>,
    /// For each pin: the capstan angle at each φ, rad.
    pub pin_wrap: Vec<Vec<f64>>,
}

/// A path whose contour cannot be formed: a node inside a guide.
#[derive(Debug, Clone, PartialEq)]
pub struct PathError {
    pub k: usize,
    pub message: String,
}

/// Where node positions come from: the pose, optionally projected onto a
/// plane (the 2D comparison of seed 000 §4.6).
struct Positions<'a, T: Real> {
    pose: &'a Pose<T>,
    plane: Option<&'a Plane<T>>,
}

impl<T: Real> Positions<'_, T> {
    #[inline]
    fn at(&self, slot: usize, k: usize) -> V3<T> {
        let p = self.pose.point(slot, k);
        match self.plane {
            None => p,
            Some(pl) => {
                let q = pl.project(&p);
                pl.lift(q, T::zero())
            }
        }
    }
}

impl<T: Real> ThreadPath<T> {
    /// Contour length and guide contacts at every φ of `pose`. With
    /// `project`, every node is first projected onto that plane and pins are
    /// taken perpendicular to it (the 2D model).
    pub fn evaluate(&self, pose: &Pose<T>, project: Option<&Plane<T>>) -> Result<PathTrack<T>, PathError> {
        let n = pose.len();
        let pos = Positions { pose, plane: project };
        let mut xi = vec![T::zero(); n];
        let mut engaged = Vec::new();
        let mut pin_wrap = Vec::new();
        for span in &self.spans {
            match span {
                Span::Straight { a, b, constant: true } if n > 0 => {
                    let l = (pos.at(*b, 0) - pos.at(*a, 0)).norm();
                    xi.iter_mut().for_each(|x| *x += l);
                }
                Span::Straight { a, b, .. } => {
                    for (k, x) in xi.iter_mut().enumerate() {
                        *x += (pos.at(*b, k) - pos.at(*a, k)).norm();
                    }
                }
                Span::Pin { a, b, c, axis, r, sense, node } => {
                    let axis = match project {
                        // In the 2D model every pin stands across the plane.
                        Some(pl) => normal_of(pl),
                        None => *axis,
                    };
                    let mut on = vec![false; n];
                    let mut wr = vec![0.0; n];
                    for k in 0..n {
                        let w = wrap::pin_wrap(pos.at(*a, k), pos.at(*b, k), pos.at(*c, k), axis, *r, *sense)
                            .ok_or_else(|| PathError {
                                k,
                                message: format!("a thread end lies inside the guide at `{}`", self.node_names[*node]),
                            })?;
                        xi[k] += w.length;
                        on[k] = w.engaged;
                        wr[k] = w.wrap_rad;
                    }
                    engaged.push(on);
                    pin_wrap.push(wr);
                }
            }
        }
        Ok(PathTrack { xi, engaged, pin_wrap })
    }

    /// Thread tension after each node at the `k`-th φ of `pose` by the
    /// capstan (Euler–Eytelwein) law with Amontons friction:
    /// `T_{i+1} = T_i · exp(μ_i · θ_i)`, θ_i the angle the thread turns
    /// through at node i, starting from `t0` (N) at the first node and
    /// assuming the thread is drawn toward the eye. Returns (tension after
    /// each node, wrap angle at each node in rad).
    pub fn tension(&self, pose: &Pose<T>, track: &PathTrack<T>, k: usize, t0: f64) -> (Vec<f64>, Vec<f64>) {
        let m = self.nodes.len();
        let mut theta = vec![0.0; m];
        // Eyelets: the angle between the incoming and outgoing segments.
        let pin_nodes: Vec<usize> =
            self.spans.iter().filter_map(|s| if let Span::Pin { node, .. } = s { Some(*node) } else { None }).collect();
        for i in 1..m.saturating_sub(1) {
            if pin_nodes.contains(&i) {
                continue;
            }
            let prev = self.contact_before(i);
            let next = self.contact_after(i);
            let p = pose.point(self.nodes[i], k).map(|v| v.re());
            let u = (p - pose.point(self.nodes[prev], k).map(|v| v.re())).normalize();
            let w = (pose.point(self.nodes[next], k).map(|v| v.re()) - p).normalize();
            let c = u.dot(&w).clamp(-1.0, 1.0);
            theta[i] = if c.is_finite() { c.acos() } else { 0.0 };
        }
        for (j, &i) in pin_nodes.iter().enumerate() {
            theta[i] = track.pin_wrap[j][k];
        }
        let mut t = vec![t0; m];
        for i in 1..m {
            t[i] = t[i - 1] * (self.friction[i] * theta[i]).exp();
        }
        (t, theta)
    }

    /// The node the thread last touched before node `i` (skipping
    /// disengaged pins is not needed for eyelets: a pin is never adjacent
    /// to a pin, and a pin's neighbours are eyelets).
    /// ξ at the `k`-th φ of `pose` alone.
    pub fn evaluate_at(&self, pose: &Pose<T>, k: usize) -> Result<T, PathError> {
        let mut xi = T::zero();
        for span in &self.spans {
            xi += match span {
                Span::Straight { a, b, .. } => (pose.point(*b, k) - pose.point(*a, k)).norm(),
                Span::Pin { a, b, c, axis, r, sense, node } => {
                    wrap::pin_wrap(pose.point(*a, k), pose.point(*b, k), pose.point(*c, k), *axis, *r, *sense)
                        .ok_or_else(|| PathError { k, message: format!("a thread end lies inside the guide at `{}`", self.node_names[*node]) })?
                        .length
                }
            };
        }
        Ok(xi)
    }

    /// Names of the path's pins, in order.
    pub fn pin_names(&self) -> Vec<&str> {
        self.spans
            .iter()
            .filter_map(|s| if let Span::Pin { node, .. } = s { Some(self.node_names[*node].as_str()) } else { None })
            .collect()
    }

    fn contact_before(&self, i: usize) -> usize {
        let mut j = i - 1;
        while j > 0 && self.is_pin(j) {
            j -= 1;
        }
        j
    }

    fn contact_after(&self, i: usize) -> usize {
        let mut j = i + 1;
        while j + 1 < self.nodes.len() && self.is_pin(j) {
            j += 1;
        }
        j
    }

    fn is_pin(&self, i: usize) -> bool {
        self.spans.iter().any(|s| matches!(s, Span::Pin { node, .. } if *node == i))
    }
}

fn normal_of<T: Real>(pl: &Plane<T>) -> V3<T> {
    match &pl.0 {
        None => V3::z(),
        Some(f) => f.dir_to_world(V3::z()),
    }
}

/// An interval of φ, degrees (`to` may exceed 360 when it wraps).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Interval {
    pub from_deg: f64,
    pub to_deg: f64,
}

/// Maximal runs where `flag[k]` holds, as φ intervals on the cycle grid
/// `phis` (step `step`), joining a run that wraps past the cycle's end.
pub fn intervals(flag: &[bool], phis: &[f64], step: f64) -> Vec<Interval> {
    let n = flag.len();
    if n == 0 {
        return Vec::new();
    }
    if flag.iter().all(|f| *f) {
        return vec![Interval { from_deg: phis[0], to_deg: phis[0] + 360.0 }];
    }
    // Start scanning just after a false entry so a wrapping run is whole.
    let start = (0..n).find(|&k| !flag[k]).unwrap_or(0);
    let mut out = Vec::new();
    let mut k = 0;
    while k < n {
        let i = (start + k) % n;
        if flag[i] {
            let first = k;
            while k < n && flag[(start + k) % n] {
                k += 1;
            }
            let a = phis[(start + first) % n];
            let b = phis[(start + k - 1) % n];
            let b = if b < a { b + 360.0 } else { b };
            out.push(Interval { from_deg: a, to_deg: b + step.min(0.0) });
        } else {
            k += 1;
        }
    }
    out.sort_by(|x, y| x.from_deg.total_cmp(&y.from_deg));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_join_a_run_that_wraps() {
        let phis: Vec<f64> = (0..12).map(|k| k as f64 * 30.0).collect();
        let flag = [true, true, false, false, true, true, true, false, false, false, true, true];
        let iv = intervals(&flag, &phis, 30.0);
        assert_eq!(iv.len(), 2);
        assert_eq!((iv[0].from_deg, iv[0].to_deg), (120.0, 180.0));
        assert_eq!((iv[1].from_deg, iv[1].to_deg), (300.0, 390.0));
        assert_eq!(intervals(&[true; 4], &phis[..4], 30.0)[0].to_deg, 360.0);
        assert!(intervals(&[false; 4], &phis[..4], 30.0).is_empty());
    }

    #[test]
    fn conventions() {
        assert_eq!(Convention::Release.take_up(90.0, 100.0), 10.0);
        assert_eq!(Convention::Feed { elongation_mm: 6.0 }.take_up(90.0, 100.0), -4.0);
    }
}
