//! The material and the threads around its edge (`docs/stitch-formation.md`
//! §4.3).
//!
//! The compressed material is the open slab `x < x_edge, 0 < z < m`
//! (infinite in −x and in y). A thread between two points that may not cut
//! through it takes W(P, Q), the shortest path outside it: straight, over
//! one corner line (x = x_edge, z = m or z = 0), or over both (around the
//! edge face). Points on the faces (holes, corners, edge points) are
//! allowed.

use crate::geometry::V3;

/// Tolerance of "inside the material" for an organ point, mm.
const INSIDE_TOL: f64 = 1e-7;
/// Faces are moved in by this much when a segment is tested, so that a
/// segment along a face does not count as cutting the material, mm.
const FACE_TOL: f64 = 1e-9;

/// The material slab `x < x_edge, 0 < z < m`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slab {
    /// x of the edge face: the needle line plus the overedge width a_e, mm.
    pub x_edge: f64,
    /// Compressed thickness m, mm.
    pub m: f64,
}

/// The shortest path outside the slab: its length and its nodes (the two
/// ends and up to two contact points on the corner lines).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WPath {
    pub length: f64,
    nodes: [V3<f64>; 4],
    n: usize,
}

impl WPath {
    fn new(length: f64, nodes: &[V3<f64>]) -> WPath {
        let mut all = [V3::zeros(); 4];
        all[..nodes.len()].copy_from_slice(nodes);
        WPath {
            length,
            nodes: all,
            n: nodes.len(),
        }
    }

    /// P, the contact points in order, Q.
    pub fn nodes(&self) -> &[V3<f64>] {
        &self.nodes[..self.n]
    }
}

impl Slab {
    /// Is `p` strictly inside the material (beyond 1e-7 mm)? An organ point
    /// there is an error (§4.3).
    pub fn inside(&self, p: &V3<f64>) -> bool {
        p.x < self.x_edge - INSIDE_TOL && INSIDE_TOL < p.z && p.z < self.m - INSIDE_TOL
    }

    /// Does the open segment p–q pass through the open slab? (Clip the
    /// segment's parameter s ∈ [0, 1] by x < x_edge and 0 < z < m.)
    pub fn hits(&self, p: &V3<f64>, q: &V3<f64>) -> bool {
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        let dx = q.x - p.x;
        if dx.abs() < 1e-12 {
            if p.x >= self.x_edge - FACE_TOL {
                return false;
            }
        } else {
            let s = (self.x_edge - FACE_TOL - p.x) / dx;
            if dx > 0.0 {
                hi = hi.min(s);
            } else {
                lo = lo.max(s);
            }
        }
        let dz = q.z - p.z;
        if dz.abs() < 1e-12 {
            if !(FACE_TOL < p.z && p.z < self.m - FACE_TOL) {
                return false;
            }
        } else {
            let s0 = (FACE_TOL - p.z) / dz;
            let s1 = (self.m - FACE_TOL - p.z) / dz;
            lo = lo.max(s0.min(s1));
            hi = hi.min(s0.max(s1));
        }
        hi - lo > FACE_TOL
    }

    /// ρ: distance of `p` from the corner line x = x_edge, z = `z_line`
    /// (in the x–z plane).
    fn rho(&self, p: &V3<f64>, z_line: f64) -> f64 {
        (p.x - self.x_edge).hypot(p.z - z_line)
    }

    /// W(P, Q) with its polyline (§4.3). Unfolding the planes about the
    /// corner lines makes each candidate a straight line:
    /// - straight: |PQ| when the segment misses the slab;
    /// - one corner: √((ρ_P + ρ_Q)² + Δy²), contact at y_P + Δy·ρ_P/(ρ_P + ρ_Q);
    /// - two corners: √((ρ_P + m + ρ_Q)² + Δy²).
    ///
    /// The least candidate whose legs stay outside is taken. `None` when no
    /// candidate stays outside (an end point inside the material).
    pub fn path(&self, p: &V3<f64>, q: &V3<f64>) -> Option<WPath> {
        if !self.hits(p, q) {
            return Some(WPath::new((q - p).norm(), &[*p, *q]));
        }
        let mut best: Option<WPath> = None;
        let mut consider = |cand: WPath| {
            if best.is_none_or(|b| cand.length < b.length) {
                best = Some(cand);
            }
        };
        let dy = q.y - p.y;
        // One corner line.
        for z_line in [self.m, 0.0] {
            let (rp, rq) = (self.rho(p, z_line), self.rho(q, z_line));
            if rp + rq < 1e-12 {
                continue;
            }
            let c = V3::new(self.x_edge, p.y + dy * rp / (rp + rq), z_line);
            if self.hits(p, &c) || self.hits(&c, q) {
                continue;
            }
            consider(WPath::new((rp + rq).hypot(dy), &[*p, c, *q]));
        }
        // Both corner lines, around the edge face.
        for (z1, z2) in [(self.m, 0.0), (0.0, self.m)] {
            let (rp, rq) = (self.rho(p, z1), self.rho(q, z2));
            let total = rp + self.m + rq;
            let c1 = V3::new(self.x_edge, p.y + dy * rp / total, z1);
            let c2 = V3::new(self.x_edge, p.y + dy * (rp + self.m) / total, z2);
            if self.hits(p, &c1) || self.hits(&c2, q) {
                continue;
            }
            consider(WPath::new(total.hypot(dy), &[*p, c1, c2, *q]));
        }
        best
    }

    /// W(P, Q), mm (`None`: no path outside the material).
    pub fn w(&self, p: &V3<f64>, q: &V3<f64>) -> Option<f64> {
        self.path(p, q).map(|w| w.length)
    }
}

/// Nearest point of a polyline to `x`: (distance, point). The first nearest
/// segment wins a tie. `None` for an empty polyline.
pub fn polyline_nearest(poly: &[V3<f64>], x: &V3<f64>) -> Option<(f64, V3<f64>)> {
    if poly.len() == 1 {
        return Some(((poly[0] - x).norm(), poly[0]));
    }
    let mut best: Option<(f64, V3<f64>)> = None;
    for w in poly.windows(2) {
        let ab = w[1] - w[0];
        let l2 = ab.norm_squared();
        let s = if l2 < 1e-18 {
            0.0
        } else {
            ((x - w[0]).dot(&ab) / l2).clamp(0.0, 1.0)
        };
        let c = w[0] + ab * s;
        let d = (c - x).norm();
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The altin504 slab: edge at x = 4, m = 2.5.
    const SLAB: Slab = Slab { x_edge: 4.0, m: 2.5 };

    #[test]
    fn straight_when_the_segment_misses_the_material() {
        // Both below the plate, and one along the bottom face (allowed).
        let (p, q) = (V3::new(0.0, 0.0, -5.5), V3::new(6.0, 3.0, -1.0));
        assert_relative_eq!(SLAB.w(&p, &q).unwrap(), (36.0f64 + 9.0 + 20.25).sqrt(), epsilon = 1e-12);
        let (h, k) = (V3::new(0.0, 1.0, 0.0), V3::new(4.0, 3.8, 0.0));
        assert!(!SLAB.hits(&h, &k));
        assert_relative_eq!(SLAB.w(&h, &k).unwrap(), 4.0f64.hypot(2.8), epsilon = 1e-12);
        assert_eq!(SLAB.path(&h, &k).unwrap().nodes().len(), 2);
    }

    #[test]
    fn one_corner_by_hand() {
        // P beyond the edge and below the plate, Q on the top face: over the
        // top corner line (over the bottom one the leg to Q would cut the
        // material; around the edge face is longer).
        let p = V3::new(7.0, 0.0, -1.0); // ρ_top = √(9 + 12.25), outside
        let q = V3::new(1.0, 2.0, 2.5); // on the top face, ρ_top = 3
        let rp = 3.0f64.hypot(3.5);
        let w = SLAB.path(&p, &q).unwrap();
        assert_relative_eq!(w.length, (rp + 3.0).hypot(2.0), epsilon = 1e-12);
        let c = w.nodes()[1];
        assert_relative_eq!(c.x, 4.0);
        assert_relative_eq!(c.z, 2.5);
        assert_relative_eq!(c.y, 2.0 * rp / (rp + 3.0), epsilon = 1e-12);
        assert_eq!(w.nodes().len(), 3);
    }

    #[test]
    fn two_corners_around_the_edge_face() {
        // Hole top to hole bottom of the same stitch, on different faces:
        // a_e over the top, m down the edge, a_e back under.
        let p = V3::new(0.0, 0.0, 2.5);
        let q = V3::new(0.0, 3.0, 0.0);
        let w = SLAB.path(&p, &q).unwrap();
        assert_eq!(w.nodes().len(), 4);
        assert_relative_eq!(w.length, (4.0f64 + 2.5 + 4.0).hypot(3.0), epsilon = 1e-12);
        // The contact points split Δy in proportion 4 : 2.5 : 4.
        assert_relative_eq!(w.nodes()[1].y, 3.0 * 4.0 / 10.5, epsilon = 1e-12);
        assert_relative_eq!(w.nodes()[2].y, 3.0 * 6.5 / 10.5, epsilon = 1e-12);
    }

    #[test]
    fn inside_points_have_no_path() {
        let inside = V3::new(1.0, 0.0, 1.0);
        assert!(SLAB.inside(&inside));
        assert!(!SLAB.inside(&V3::new(1.0, 0.0, 2.5)));
        assert!(SLAB.path(&inside, &V3::new(1.0, 0.0, 10.0)).is_none());
    }

    #[test]
    fn nearest_point_of_a_polyline() {
        let poly = [V3::new(0.0, 0.0, 0.0), V3::new(4.0, 0.0, 0.0), V3::new(4.0, 4.0, 0.0)];
        let (d, c) = polyline_nearest(&poly, &V3::new(2.0, 1.0, 0.0)).unwrap();
        assert_relative_eq!(d, 1.0);
        assert_relative_eq!(c, V3::new(2.0, 0.0, 0.0));
        let (d, c) = polyline_nearest(&poly, &V3::new(5.0, 3.0, 1.0)).unwrap();
        assert_relative_eq!(d, 2.0f64.sqrt());
        assert_relative_eq!(c, V3::new(4.0, 3.0, 0.0));
        // Beyond an end: the end point.
        let (d, _) = polyline_nearest(&poly, &V3::new(-3.0, -4.0, 0.0)).unwrap();
        assert_relative_eq!(d, 5.0);
        assert!(polyline_nearest(&[], &V3::zeros()).is_none());
    }
}
