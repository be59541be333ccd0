//! Planar dyad RPR (class II, type 3): a slotted lever.

use super::NoAssembly;
use crate::geometry::{V2, perp};
use crate::scalar::Real;

/// Unit direction `u` of a slot that turns about `c` and passes through the
/// pin `a`, the slot line lying at `e` to the left of `c`:
/// `a − c = s·u + e·perp(u)` with `s = √(|a−c|² − e²) > 0`, hence
/// `u = (s·d − e·perp(d)) / |d|²`, `d = a − c`. Returns `(u, s)`.
#[inline(always)]
pub fn rpr<T: Real>(a: V2<T>, c: V2<T>, e: T) -> Result<(V2<T>, T), NoAssembly> {
    let d = a - c;
    let d2 = d.norm_squared();
    let s2 = d2 - e * e;
    if s2.re() <= 0.0 {
        let dist = d2.re().sqrt();
        return Err(NoAssembly::new(
            e.re().abs() - dist,
            format!(
                "the pin is {dist:.4} mm from the pivot, within the slot offset {:.4} mm",
                e.re().abs()
            ),
        ));
    }
    let s = s2.sqrt();
    Ok(((d * s - perp(d) * e) / d2, s))
}

/// Transmission angle of the slotted lever: the force on the lever acts
/// across the slot, the lever point under the pin moves across `c → a`;
/// μ = 90° − their angle = `acos(|e| / |a − c|)`, rad (90° for `e = 0`).
#[inline]
#[cfg(test)] // the formula the mechanism's transmission angles are checked against
pub fn transmission<T: Real>(a: V2<T>, c: V2<T>, e: T) -> T {
    let (y, x) = transmission_parts(a, c, e);
    y.angle_of(x)
}

/// [`transmission`] as the vector `(y ≥ 0, x)` whose angle it is.
#[inline]
pub fn transmission_parts<T: Real>(a: V2<T>, c: V2<T>, e: T) -> (T, T) {
    let d = (a - c).norm();
    ((d * d - e * e).max(T::zero()).sqrt(), e.abs())
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn slot_through_pivot_points_at_pin() {
        let (u, s) = rpr(V2::new(3.0, 4.0), V2::new(0.0, 0.0), 0.0).unwrap();
        assert_relative_eq!(u, V2::new(0.6, 0.8), epsilon = 1e-15);
        assert_relative_eq!(s, 5.0, epsilon = 1e-15);
    }

    #[test]
    fn offset_slot_is_tangent_to_offset_circle() {
        let (a, c, e) = (V2::new(5.0, 0.0), V2::new(0.0, 0.0), 3.0);
        let (u, s) = rpr(a, c, e).unwrap();
        assert_relative_eq!(s, 4.0, epsilon = 1e-14);
        assert_relative_eq!(c + perp(u) * e + u * s, a, epsilon = 1e-14);
        assert_relative_eq!(u.norm(), 1.0, epsilon = 1e-14);
        assert_relative_eq!(transmission(a, c, e), (3.0f64 / 5.0).acos(), epsilon = 1e-14);
        assert!(rpr(V2::new(2.0, 0.0), c, 3.0).is_err());
    }
}
