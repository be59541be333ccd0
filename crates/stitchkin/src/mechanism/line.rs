//! A point sliding on a line at a fixed distance from a moving point:
//! the spatial point-on-line group and, in a plane with an offset, the planar
//! dyad RRP (class II, type 2; seed 002 eq. 11–13).

use super::NoAssembly;
use nalgebra::SVector;

#[cfg(test)]
use crate::geometry::V3;
use crate::scalar::Real;

/// Point `P = h + s·u` on the line through `h` along the unit vector `u`
/// with `|P − a| = l`: `s = (a−h)·u ± √(l² − |(a−h)⊥|²)`.
/// `sign = +1` takes `P` ahead of `a`'s foot along `u`. Takes `l_sq = l²`.
#[inline(always)]
pub fn point_on_line<T: Real, const D: usize>(
    h: SVector<T, D>,
    u: SVector<T, D>,
    a: SVector<T, D>,
    l_sq: T,
    sign: f64,
) -> Result<SVector<T, D>, NoAssembly> {
    let (p, ok) = point_on_line_unchecked(h, u, a, l_sq, sign);
    if ok {
        return Ok(p);
    }
    let w = a - h;
    let along = w.dot(&u);
    let perp2 = w.norm_squared() - along * along;
    let (dist, l) = (perp2.re().max(0.0).sqrt(), l_sq.re().sqrt());
    Err(NoAssembly::new(
        dist - l,
        format!("the moving joint is {dist:.4} mm from the guide line but the rod is only {l:.4} mm long"),
    ))
}

/// [`point_on_line`] without a branch: the point and whether it exists
/// (when it does not, the point is not a number). A cycle's loop of it
/// vectorises.
#[inline(always)]
pub fn point_on_line_unchecked<T: Real, const D: usize>(
    h: SVector<T, D>,
    u: SVector<T, D>,
    a: SVector<T, D>,
    l_sq: T,
    sign: f64,
) -> (SVector<T, D>, bool) {
    let w = a - h;
    let along = w.dot(&u);
    let perp2 = w.norm_squared() - along * along;
    let disc = l_sq - perp2;
    (
        h + u * (along + disc.sqrt().signed(sign)),
        disc.re() >= 0.0 || disc.re().is_nan(),
    )
}

/// Transmission angle of a rod `a → p` driving a slider along `u`:
/// 90° minus the angle between rod and guide (seed 002 eq. 11, μ3), rad.
#[inline]
#[cfg(test)] // the formula the mechanism's transmission angles are checked against
pub fn transmission<T: Real, const D: usize>(u: SVector<T, D>, a: SVector<T, D>, p: SVector<T, D>) -> T {
    let (y, x) = transmission_parts(u, a, p);
    y.angle_of(x)
}

/// [`transmission`] as the vector `(y ≥ 0, x)` whose angle it is.
#[inline]
pub fn transmission_parts<T: Real, const D: usize>(u: SVector<T, D>, a: SVector<T, D>, p: SVector<T, D>) -> (T, T) {
    let rod = p - a;
    let along = rod.dot(&u).abs();
    let across = (rod.norm_squared() - along * along).max(T::zero()).sqrt();
    (along, across)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn slider_crank_dead_centres_give_stroke_2r() {
        // Central slider-crank, crank r = 10, rod 40, guide = x axis through O.
        let (h, u) = (V3::new(0.0, 0.0, 0.0), V3::new(1.0, 0.0, 0.0));
        let at = |phi: f64| {
            let a = V3::new(10.0 * phi.cos(), 10.0 * phi.sin(), 0.0);
            point_on_line(h, u, a, 1600.0, 1.0).unwrap().x
        };
        assert_relative_eq!(at(0.0), 50.0, epsilon = 1e-12);
        assert_relative_eq!(at(std::f64::consts::PI), 30.0, epsilon = 1e-12);
        // 3-4-5: A = (0, 3), rod 5 → slider at x = ±4.
        let p = point_on_line(h, u, V3::new(0.0, 3.0, 0.0), 25.0, -1.0).unwrap();
        assert_relative_eq!(p, V3::new(-4.0, 0.0, 0.0), epsilon = 1e-12);
        let mu = transmission(u, V3::new(0.0, 3.0, 0.0), p);
        assert_relative_eq!(mu, (4.0f64).atan2(3.0), epsilon = 1e-12);
    }

    #[test]
    fn spatial_line_and_defect() {
        let h = V3::new(1.0, 1.0, 1.0);
        let u = V3::new(0.0, 0.0, 1.0);
        let a = V3::new(4.0, 5.0, 3.0); // 5 mm from the line
        let p = point_on_line(h, u, a, 169.0, 1.0).unwrap();
        assert_relative_eq!(p, V3::new(1.0, 1.0, 15.0), epsilon = 1e-12);
        let e = point_on_line(h, u, a, 16.0, 1.0).unwrap_err();
        assert_relative_eq!(e.defect_mm, 1.0, epsilon = 1e-12);
    }
}
