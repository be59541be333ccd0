//! Points rigidly attached to a moving link.

use super::NoAssembly;
use crate::geometry::{V2, V3, perp};
use crate::scalar::Real;

/// Planar rigid point at distance `d` and angle `γ` (counter-clockwise) from
/// the link vector `a → b`: `P = a + (d cos γ · e + d sin γ · perp(e))`,
/// `e = (b − a)/|b − a|`. `dc = d cos γ`, `ds = d sin γ` are precomputed.
#[inline(always)]
pub fn rigid_point<T: Real>(a: V2<T>, b: V2<T>, dc: T, ds: T) -> Result<V2<T>, NoAssembly> {
    let e = b - a;
    let n2 = e.norm_squared();
    if n2.re() <= 0.0 {
        return Err(NoAssembly::coincident("the two points that define the link"));
    }
    let inv = n2.sqrt().recip();
    Ok(a + (e.map(|x| x.times_k(dc)) + perp(e).map(|x| x.times_k(ds))) * inv)
}

/// [`rigid_point`] on a link of known length `l = |b − a|`, with
/// `dcl = d cos γ / l`, `dsl = d sin γ / l`: `P = a + dcl·(b − a) + dsl·perp(b − a)`.
#[inline(always)]
pub fn rigid_point_on_link<T: Real>(a: V2<T>, b: V2<T>, dcl: T, dsl: T) -> V2<T> {
    let e = b - a;
    a + e.map(|x| x.times_k(dcl)) + perp(e).map(|x| x.times_k(dsl))
}

/// Spatial rigid point at local coordinates `p` in the frame with origin
/// `o`, `e1` toward `x`, `e3 = e1 × (y − o)` normalised and `e2 = e3 × e1`.
#[inline(always)]
pub fn rigid_point_3d<T: Real>(o: V3<T>, x: V3<T>, y: V3<T>, p: V3<T>) -> Result<V3<T>, NoAssembly> {
    let ex = x - o;
    let n1 = ex.norm_squared();
    if n1.re() <= 0.0 {
        return Err(NoAssembly::coincident("the frame's origin and x point"));
    }
    let e1 = ex / n1.sqrt();
    let c = e1.cross(&(y - o));
    let n3 = c.norm_squared();
    if n3.re() <= 1e-24 * n1.re() {
        return Err(NoAssembly::coincident("the frame's three points (they are collinear)"));
    }
    let e3 = c / n3.sqrt();
    let e2 = e3.cross(&e1);
    Ok(o + e1.map(|x| x.times_k(p.x)) + e2.map(|x| x.times_k(p.y)) + e3.map(|x| x.times_k(p.z)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn coupler_point_at_30_degrees() {
        let (d, g) = (20.0f64, 30f64.to_radians());
        let p = rigid_point(V2::new(1.0, 1.0), V2::new(1.0, 11.0), d * g.cos(), d * g.sin()).unwrap();
        // link along +y, 30° counter-clockwise from it points to (−sin30, cos30).
        assert_relative_eq!(p, V2::new(1.0 - 10.0, 1.0 + 20.0 * g.cos()), epsilon = 1e-12);
        // The same point with the link's length (10) known.
        let q = rigid_point_on_link(
            V2::new(1.0, 1.0),
            V2::new(1.0, 11.0),
            d * g.cos() / 10.0,
            d * g.sin() / 10.0,
        );
        assert_relative_eq!(q, p, epsilon = 1e-12);
    }

    #[test]
    fn frame_from_three_points() {
        let o = V3::new(1.0, 0.0, 0.0);
        let p = rigid_point_3d(
            o,
            V3::new(1.0, 5.0, 0.0),
            V3::new(1.0, 0.0, 7.0),
            V3::new(1.0, 2.0, 3.0),
        )
        .unwrap();
        // e1 = y, e2 = z (side of the third point), e3 = e1 × e2 = x.
        assert_relative_eq!(p, V3::new(1.0 + 3.0, 1.0, 2.0), epsilon = 1e-12);
        assert!(rigid_point_3d(o, V3::new(2.0, 0.0, 0.0), V3::new(3.0, 0.0, 0.0), V3::zeros()).is_err());
    }
}
