//! Planar dyad RRR (class II, type 1): two links joined at `B`.

use super::NoAssembly;
use crate::geometry::{V2, perp};
use crate::scalar::Real;

/// How far below zero rounding can leave h² = (h/|d|)² where the links are
/// stretched straight or folded flat (dimensionless: h = 10⁻⁶·|d|).
const ROUNDING: f64 = 1e-12;

/// Joint `B` at distance `l1` from `p1` and `l2` from `p2` (seed 002 eq. 3–5,
/// written without angles): with `d = p2 − p1`,
/// `B = p1 + k·d ± h·perp(d)`, `k = (l1² − l2² + |d|²) / (2|d|²)`,
/// `h = √(l1²/|d|² − k²)`. `sign = +1` puts `B` left of `p1 → p2`.
/// Takes the squares `l1sq = l1²`, `l2sq = l2²` (constant over a cycle).
#[inline(always)]
pub fn rrr<T: Real>(p1: V2<T>, p2: V2<T>, l1sq: T, l2sq: T, sign: f64) -> Result<V2<T>, NoAssembly> {
    let d = p2 - p1;
    let d2 = d.norm_squared();
    if d2.re() <= 0.0 {
        return Err(NoAssembly::coincident("the two joints of the dyad"));
    }
    let inv_d2 = d2.recip();
    let k = ((l1sq - l2sq + d2) * inv_d2).times(0.5);
    let mut h2 = inv_d2.times_k(l1sq) - k * k;
    // Links stretched straight or folded flat (|d| = l1 + l2 or |l1 − l2|)
    // assemble with h = 0; rounding can leave h² a hair below zero there.
    if h2.re() < 0.0 && h2.re() >= -ROUNDING {
        h2 = T::zero();
    }
    if h2.re() < 0.0 {
        let (dist, l1, l2) = (d2.re().sqrt(), l1sq.re().sqrt(), l2sq.re().sqrt());
        // Too far apart (beyond l1 + l2) or too close (within |l1 − l2|):
        // the two gaps lie either side of the longer link.
        return Err(if dist > l1.max(l2) {
            NoAssembly::new(
                dist - (l1 + l2),
                format!(
                    "the joints are {dist:.4} mm apart but the two links reach only {:.4} mm",
                    l1 + l2
                ),
            )
        } else {
            NoAssembly::new(
                (l1 - l2).abs() - dist,
                format!(
                    "the joints are {dist:.4} mm apart, closer than the links' difference {:.4} mm",
                    (l1 - l2).abs()
                ),
            )
        });
    }
    Ok(p1 + d * k + perp(d) * h2.sqrt().signed(sign))
}

/// Transmission angle at `B` (seed 002 eq. 4, μ): the angle between the
/// links `B→p1` and `B→p2`, rad, in [0, π].
#[inline]
#[cfg(test)] // the formula the mechanism's transmission angles are checked against
pub fn transmission<T: Real>(p1: V2<T>, p2: V2<T>, b: V2<T>) -> T {
    let (y, x) = transmission_parts(p1, p2, b);
    y.angle_of(x)
}

/// [`transmission`] as the vector `(y ≥ 0, x)` whose angle it is.
#[inline]
pub fn transmission_parts<T: Real>(p1: V2<T>, p2: V2<T>, b: V2<T>) -> (T, T) {
    let (u, v) = (p1 - b, p2 - b);
    (crate::geometry::cross2(u, v).abs(), u.dot(&v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn right_triangle_3_4_5() {
        // p1 = (0,0), p2 = (5,0), l1 = 3, l2 = 4: B = (1.8, ±2.4).
        let b = rrr(V2::new(0.0, 0.0), V2::new(5.0, 0.0), 9.0, 16.0, 1.0).unwrap();
        assert_relative_eq!(b, V2::new(1.8, 2.4), epsilon = 1e-14);
        let b = rrr(V2::new(0.0, 0.0), V2::new(5.0, 0.0), 9.0, 16.0, -1.0).unwrap();
        assert_relative_eq!(b, V2::new(1.8, -2.4), epsilon = 1e-14);
        let mu = transmission(V2::new(0.0, 0.0), V2::new(5.0, 0.0), b);
        assert_relative_eq!(mu, std::f64::consts::FRAC_PI_2, epsilon = 1e-14);
    }

    #[test]
    fn left_is_counter_clockwise_for_any_base_direction() {
        let p1 = V2::new(2.0, 1.0);
        let p2 = V2::new(-3.0, 4.0);
        let b = rrr(p1, p2, 16.0, 25.0, 1.0).unwrap();
        assert!(crate::geometry::cross2(p2 - p1, b - p1) > 0.0);
        assert_relative_eq!((b - p1).norm(), 4.0, epsilon = 1e-12);
        assert_relative_eq!((b - p2).norm(), 5.0, epsilon = 1e-12);
    }

    #[test]
    fn no_assembly_reports_the_defect() {
        let e = rrr(V2::new(0.0, 0.0), V2::new(10.0, 0.0), 9.0, 16.0, 1.0).unwrap_err();
        assert_relative_eq!(e.defect_mm, 3.0, epsilon = 1e-12);
        let e = rrr(V2::new(0.0, 0.0), V2::new(1.0, 0.0), 9.0, 25.0, 1.0).unwrap_err();
        assert_relative_eq!(e.defect_mm, 1.0, epsilon = 1e-12);
        assert!(rrr(V2::new(1.0, 1.0), V2::new(1.0, 1.0), 9.0, 25.0, 1.0).is_err());
    }

    #[test]
    fn links_stretched_straight_or_folded_flat_assemble_and_failures_say_which_gap() {
        // |d| = l1 + l2 = 75 and |d| = l1 − l2 = 25: B on the line, h = 0.
        let b = rrr(V2::new(0.0, 0.0), V2::new(75.0, 0.0), 2500.0, 625.0, 1.0).unwrap();
        assert_relative_eq!(b, V2::new(50.0, 0.0), epsilon = 1e-9);
        let b = rrr(V2::new(0.0, 0.0), V2::new(25.0, 0.0), 2500.0, 625.0, 1.0).unwrap();
        assert_relative_eq!(b, V2::new(50.0, 0.0), epsilon = 1e-9);
        // Along a slanted base, where rounding does not cancel.
        let (p1, dir) = (V2::new(0.3, -1.7), V2::new(0.6, 0.8));
        let b = rrr(p1, p1 + dir * 75.0, 2500.0, 625.0, -1.0).unwrap();
        assert_relative_eq!(b, p1 + dir * 50.0, epsilon = 1e-9);
        // Just beyond either: the right message and a positive defect.
        let e = rrr(V2::new(0.0, 0.0), V2::new(75.001, 0.0), 2500.0, 625.0, 1.0).unwrap_err();
        assert!(e.message.contains("reach only"), "{}", e.message);
        assert_relative_eq!(e.defect_mm, 0.001, epsilon = 1e-9);
        let e = rrr(V2::new(0.0, 0.0), V2::new(24.999, 0.0), 2500.0, 625.0, 1.0).unwrap_err();
        assert!(e.message.contains("closer than the links' difference"), "{}", e.message);
        assert_relative_eq!(e.defect_mm, 0.001, epsilon = 1e-9);
    }
}
