//! Spatial RSSR: a rocker on a fixed axis joined to a moving point by a rod
//! with spherical ends (seed 000: the "ball arm" O2B of the MF-7923D take-up;
//! seed 003: rockers 15-14, 4-3, 10-9).

use super::NoAssembly;
use crate::geometry::V3;
use crate::scalar::Real;

/// Geometry of a rocker: centre `c` of the ball end's circle, orthonormal
/// `u, v` spanning the circle's plane, axis `w = u × v`, arm radius `r`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rocker<T: Real> {
    pub c: V3<T>,
    pub u: V3<T>,
    pub v: V3<T>,
    pub w: V3<T>,
    pub r: T,
}

/// A rocker and its rod, with the constants of [`rssr`] folded once.
#[derive(Debug, Clone, Copy)]
pub struct RockerRod<T: Real> {
    pub rocker: Rocker<T>,
    /// Rod length.
    pub l: T,
    /// `r² − l²`.
    c0: T,
    /// `1 / (2r)`.
    inv_2r: T,
}

impl<T: Real> RockerRod<T> {
    pub fn new(rocker: Rocker<T>, l: T) -> Self {
        let c0 = rocker.r * rocker.r - l * l;
        let inv_2r = rocker.r.times(2.0).recip();
        RockerRod { rocker, l, c0, inv_2r }
    }
}

/// Ball end `B = c + r(cos θ·u + sin θ·v)` with `|B − a| = l`.
/// With `a − c = (a_u, a_v, a_w)`, `K = (r² + |a−c|² − l²) / (2r)` and
/// `ρ² = a_u² + a_v²`: `cos(θ − ψ) = K/ρ`, ψ the direction of `(a_u, a_v)`,
/// so `(B−c)_{uv} = (r/ρ²)·(K·(a_u, a_v) ± √(ρ² − K²)·(−a_v, a_u))`.
/// `sign = +1` turns counter-clockwise about `w` from `a`'s direction.
#[inline(always)]
pub fn rssr<T: Real>(rod: &RockerRod<T>, a: V3<T>, sign: f64) -> Result<V3<T>, NoAssembly> {
    let (b, ok) = rssr_unchecked(rod, a, sign);
    if ok {
        return Ok(b);
    }
    let (k, l) = (&rod.rocker, rod.l);
    let q = a - k.c;
    let (au, av) = (q.dot(&k.u).re(), q.dot(&k.v).re());
    let (rho, aw, r, l) = ((au * au + av * av).sqrt(), q.dot(&k.w).re(), k.r.re(), l.re());
    let near = ((rho - r).powi(2) + aw * aw).sqrt();
    let far = ((rho + r).powi(2) + aw * aw).sqrt();
    Err(if l > far {
        NoAssembly::new(
            l - far,
            format!("the rod ({l:.4} mm) is longer than the farthest reach of the rocker circle ({far:.4} mm)"),
        )
    } else {
        NoAssembly::new(
            near - l,
            format!("the rod ({l:.4} mm) is shorter than the nearest reach of the rocker circle ({near:.4} mm)"),
        )
    })
}

/// [`rssr`] without a branch: the ball end and whether it exists (when it
/// does not, the point is not a number). A cycle's loop of it vectorises.
#[inline(always)]
pub fn rssr_unchecked<T: Real>(rod: &RockerRod<T>, a: V3<T>, sign: f64) -> (V3<T>, bool) {
    let k = &rod.rocker;
    let q = a - k.c;
    let (au, av) = (q.dot(&k.u), q.dot(&k.v));
    let rho2 = au * au + av * av;
    let kk = (q.norm_squared() + rod.c0).times_k(rod.inv_2r);
    let disc = rho2 - kk * kk;
    let ok = !((disc.re() < 0.0) | (rho2.re() <= 0.0));
    let s = disc.sqrt().signed(sign);
    let f = rho2.recip().times_k(k.r);
    let bu = f * (kk * au - s * av);
    let bv = f * (kk * av + s * au);
    (k.c + k.u * bu + k.v * bv, ok)
}

/// Transmission angle at the ball end: like the planar interior angle
/// between rod `B→a` and arm `B→c`, but counting only the rod's component
/// along the ball's path: `μ = atan2(|rod·t|, rod·n)`, rad.
#[inline]
#[cfg(test)] // the formula the mechanism's transmission angles are checked against
pub fn transmission<T: Real>(k: &Rocker<T>, a: V3<T>, b: V3<T>) -> T {
    let (y, x) = transmission_parts(k, a, b);
    y.angle_of(x)
}

/// [`transmission`] as the vector `(y ≥ 0, x)` whose angle it is.
#[inline]
pub fn transmission_parts<T: Real>(k: &Rocker<T>, a: V3<T>, b: V3<T>) -> (T, T) {
    let rod = (a - b).normalize();
    let n = (k.c - b) / k.r;
    let t = k.w.cross(&(b - k.c)) / k.r;
    (rod.dot(&t).abs(), rod.dot(&n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn planar_rocker(c: V3<f64>, r: f64) -> Rocker<f64> {
        Rocker {
            c,
            u: V3::x(),
            v: V3::y(),
            w: V3::z(),
            r,
        }
    }

    #[test]
    fn in_plane_it_is_the_rrr_dyad() {
        let k = planar_rocker(V3::new(5.0, 0.0, 0.0), 4.0);
        let b = rssr(&RockerRod::new(k, 3.0), V3::zeros(), -1.0).unwrap();
        // Same triangle as the RRR test, seen from the rocker centre.
        assert_relative_eq!(b, V3::new(1.8, 2.4, 0.0), epsilon = 1e-13);
        assert_relative_eq!(
            transmission(&k, V3::zeros(), b),
            std::f64::consts::FRAC_PI_2,
            epsilon = 1e-13
        );
    }

    #[test]
    fn out_of_plane_point_keeps_lengths() {
        let k = Rocker {
            c: V3::new(1.0, 2.0, 3.0),
            u: V3::y(),
            v: V3::z(),
            w: V3::x(),
            r: 20.0,
        };
        let a = V3::new(7.0, -10.0, 30.0);
        for sign in [1.0, -1.0] {
            let b = rssr(&RockerRod::new(k, 28.0), a, sign).unwrap();
            assert_relative_eq!((b - a).norm(), 28.0, epsilon = 1e-12);
            assert_relative_eq!((b - k.c).norm(), 20.0, epsilon = 1e-12);
            assert_relative_eq!((b - k.c).dot(&k.w), 0.0, epsilon = 1e-12);
            let turn = (a - k.c).cross(&(b - k.c)).dot(&k.w);
            assert_eq!(turn > 0.0, sign > 0.0);
        }
        let e = rssr(&RockerRod::new(k, 100.0), a, 1.0).unwrap_err();
        assert!(e.defect_mm > 0.0 && e.message.contains("longer"));
    }
}
