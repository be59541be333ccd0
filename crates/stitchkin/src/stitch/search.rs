//! The stitch's moments (TDC, catch, far extreme, drop, the eye's
//! crossings of the material top, the lowest needle point in the transport)
//! found on the organs' motions: each function of φ_c is scanned at
//! [`SCAN_STEP_DEG`] to bracket the moment, which is then found to about
//! 10⁻¹⁰° by regula falsi (a crossing) or Brent's search (an
//! extreme) on the motions themselves (`docs/stitch-formation.md` §4).
//!
//! Moments closer together than the scan step are not told apart: the
//! organs' motions are smooth over a degree of the shaft (a crossing that
//! comes and goes within one step, or two extremes within one, would be).

/// Step of the scans that bracket a moment, deg.
pub const SCAN_STEP_DEG: f64 = 1.0;
/// Scan points over one cycle.
const SCAN_N: usize = 360;
/// Width at which a bracket counts as found, deg.
const TOL_DEG: f64 = 1e-10;

/// The k-th scan angle, deg.
fn scan_deg(k: usize) -> f64 {
    k as f64 * SCAN_STEP_DEG
}

/// Which side of zero `v` is on: at or above (`true`) or below.
fn above(v: f64) -> bool {
    v >= 0.0
}

/// Where `f` changes side (below zero / at or above zero) in [a, b], f(a)
/// and f(b) on different sides: the first φ at or above zero if f rises,
/// found by the Illinois regula falsi to a bracket 10⁻¹⁰° wide.
pub fn crossing(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let (mut lo, mut hi) = (a, b);
    let (mut f_lo, mut f_hi) = (f(lo), f(hi));
    let side_lo = above(f_lo);
    debug_assert!(side_lo != above(f_hi), "a bracket of a crossing");
    // Which end stayed the last time (−1 lo, +1 hi): the Illinois rule.
    let mut kept = 0i8;
    for _ in 0..200 {
        if hi - lo <= TOL_DEG {
            break;
        }
        let mut mid = lo + (hi - lo) * f_lo / (f_lo - f_hi);
        if !(mid > lo && mid < hi) {
            mid = 0.5 * (lo + hi);
        }
        let f_mid = f(mid);
        if above(f_mid) == side_lo {
            (lo, f_lo) = (mid, f_mid);
            if kept == 1 {
                f_hi *= 0.5;
            }
            kept = 1;
        } else {
            (hi, f_hi) = (mid, f_mid);
            if kept == -1 {
                f_lo *= 0.5;
            }
            kept = -1;
        }
    }
    // The end on the far side of the crossing: the first φ past it.
    hi
}

/// The first φ in [from, to] where `f` crosses zero going up (`rising`:
/// from below to at or above) or down, scanned at [`SCAN_STEP_DEG`] from
/// `from` and found by [`crossing`]; `None` if it does not.
pub fn first_crossing(f: impl Fn(f64) -> f64, from: f64, to: f64, rising: bool) -> Option<f64> {
    if to < from {
        return None;
    }
    let mut a = from;
    let mut fa = f(a);
    loop {
        let b = (a + SCAN_STEP_DEG).min(to);
        let fb = f(b);
        let crosses = if rising {
            !above(fa) && above(fb)
        } else {
            above(fa) && !above(fb)
        };
        if crosses {
            return Some(crossing(&f, a, b));
        }
        if b >= to {
            return None;
        }
        (a, fa) = (b, fb);
    }
}

/// The scan angles of one cycle, k·[`SCAN_STEP_DEG`], deg.
pub fn scan_angles() -> impl Iterator<Item = f64> {
    (0..SCAN_N).map(scan_deg)
}

/// The first φ in [0, 360] where the periodic `f` crosses zero going down
/// and the first where it crosses going up ([`first_crossing`] of both
/// directions), from its values at the scan angles `scan`.
pub fn first_crossings_in(scan: &[f64], f: impl Fn(f64) -> f64) -> (Option<f64>, Option<f64>) {
    let (mut down, mut up) = (None, None);
    for k in 0..scan.len() {
        let (fa, fb) = (scan[k], scan[(k + 1) % scan.len()]);
        let (a, b) = (scan_deg(k), scan_deg(k + 1));
        if down.is_none() && above(fa) && !above(fb) {
            down = Some(crossing(&f, a, b));
        }
        if up.is_none() && !above(fa) && above(fb) {
            up = Some(crossing(&f, a, b));
        }
        if down.is_some() && up.is_some() {
            break;
        }
    }
    (down, up)
}

/// The largest `f` on [a, b]: (φ, f(φ)). Scanned at the scan angles inside
/// and at both ends, then polished by a Brent's search between the
/// best one's neighbours (a function linear between samples peaks at a
/// sample, which the search finds as well).
fn max_on(f: impl Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let (mut best, mut v_best) = (a, f(a));
    let k0 = (a / SCAN_STEP_DEG).floor() as i64 + 1;
    let mut k = k0;
    loop {
        let phi = k as f64 * SCAN_STEP_DEG;
        if phi >= b {
            break;
        }
        let v = f(phi);
        if v > v_best {
            (best, v_best) = (phi, v);
        }
        k += 1;
    }
    let v_b = f(b);
    if v_b > v_best {
        (best, v_best) = (b, v_b);
    }
    let (lo, hi) = ((best - SCAN_STEP_DEG).max(a), (best + SCAN_STEP_DEG).min(b));
    let (x, v) = brent_max(&f, lo, hi);
    if v > v_best { (x, v) } else { (best, v_best) }
}

/// The largest value of the periodic `f` over one cycle: (φ in [0, 360),
/// f(φ)), scanned at [`SCAN_STEP_DEG`] and polished by a Brent's search
/// between the best sample's neighbours, across 0° as well.
pub fn max_on_cycle(f: impl Fn(f64) -> f64) -> (f64, f64) {
    let (mut best, mut v_best) = (0.0, f(0.0));
    for k in 1..SCAN_N {
        let v = f(scan_deg(k));
        if v > v_best {
            (best, v_best) = (scan_deg(k), v);
        }
    }
    let (x, v) = brent_max(&f, best - SCAN_STEP_DEG, best + SCAN_STEP_DEG);
    if v > v_best {
        (x.rem_euclid(360.0), v)
    } else {
        (best, v_best)
    }
}

/// The largest and the smallest value of the periodic `f` over one cycle,
/// ((φ, f) at the largest, (φ, f) at the smallest), from its values at the
/// scan angles `scan`, each polished as [`max_on_cycle`] does.
pub fn extremes_in(scan: &[f64], f: impl Fn(f64) -> f64) -> ((f64, f64), (f64, f64)) {
    let v0 = scan[0];
    let (mut hi, mut lo) = ((0.0, v0), (0.0, v0));
    for (k, &v) in scan.iter().enumerate().skip(1) {
        if v > hi.1 {
            hi = (scan_deg(k), v);
        }
        if v < lo.1 {
            lo = (scan_deg(k), v);
        }
    }
    let polish = |(best, v_best): (f64, f64), sign: f64| {
        let (x, v) = brent_max(|phi| sign * f(phi), best - SCAN_STEP_DEG, best + SCAN_STEP_DEG);
        if v > sign * v_best {
            (x.rem_euclid(360.0), sign * v)
        } else {
            (best, v_best)
        }
    };
    (polish(hi, 1.0), polish(lo, -1.0))
}

/// The smallest `f` on [a, b]: (φ, f(φ)), scanned at the scan angles
/// inside and at both ends, then polished by a Brent's search.
pub fn min_on(f: impl Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let (x, v) = max_on(|phi| -f(phi), a, b);
    (x, -v)
}

/// The local maxima of `f` strictly inside (a, b), in order: where its
/// scan turns from rising to falling, polished by Brent's search.
pub fn local_maxima(f: impl Fn(f64) -> f64, a: f64, b: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut xs = vec![a];
    let mut k = (a / SCAN_STEP_DEG).floor() as i64 + 1;
    while (k as f64 * SCAN_STEP_DEG) < b {
        xs.push(k as f64 * SCAN_STEP_DEG);
        k += 1;
    }
    xs.push(b);
    let vs: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
    for i in 1..xs.len().saturating_sub(1) {
        if vs[i] >= vs[i - 1] && vs[i] > vs[i + 1] {
            let (x, v) = brent_max(&f, xs[i - 1], xs[i + 1]);
            out.push(if v > vs[i] { (x, v) } else { (xs[i], vs[i]) });
        }
    }
    out
}

/// Brent's search for the largest `f` on [a, b] (one peak there):
/// parabolic steps through the best three points, golden-section steps
/// when a parabola does not help; (φ, f(φ)) to about [`TOL_DEG`].
fn brent_max(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> (f64, f64) {
    // Minimises g = −f.
    let g = |x: f64| -f(x);
    let c_gold = 0.5 * (3.0 - 5f64.sqrt());
    let mut x = a + c_gold * (b - a);
    let mut fx = g(x);
    let (mut w, mut v) = (x, x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    for _ in 0..100 {
        let xm = 0.5 * (a + b);
        let tol1 = TOL_DEG * 0.5;
        let tol2 = 2.0 * tol1;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 {
            // A parabola through x, w, v.
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = tol1.copysign(xm - x);
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= xm { a - x } else { b - x };
            d = c_gold * e;
        }
        let u = if d.abs() >= tol1 { x + d } else { x + tol1.copysign(d) };
        let fu = g(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, -fx)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f` at the scan angles of one cycle, k·[`SCAN_STEP_DEG`].
    fn scan_cycle(f: impl Fn(f64) -> f64) -> Vec<f64> {
        (0..SCAN_N).map(|k| f(scan_deg(k))).collect()
    }

    #[test]
    fn crossings_are_found_to_the_tolerance_and_in_order() {
        // cos crosses zero going down at 90° and up at 270°.
        let f = |phi: f64| phi.to_radians().cos();
        let down = first_crossing(f, 0.0, 360.0, false).unwrap();
        let up = first_crossing(f, 0.0, 360.0, true).unwrap();
        assert!((down - 90.0).abs() < 1e-9, "{down}");
        assert!((up - 270.0).abs() < 1e-9, "{up}");
        // The first after 100°: the rising one; none before 80°.
        assert!((first_crossing(f, 100.0, 360.0, true).unwrap() - 270.0).abs() < 1e-9);
        assert_eq!(first_crossing(f, 0.0, 80.0, false), None);
        // A crossing exactly on a scan angle: the first φ at or above zero.
        let g = |phi: f64| phi - 42.0;
        assert_eq!(first_crossing(g, 0.0, 100.0, true), Some(42.0));
    }

    #[test]
    fn extremes_between_scan_angles_are_polished() {
        let f = |phi: f64| -(phi - 123.456_789).powi(2);
        let (x, v) = max_on_cycle(f);
        assert!((x - 123.456_789).abs() < 1e-8 && v > -1e-15, "{x} {v}");
        // Across 0°: a peak at 359.7° of a periodic function.
        let g = |phi: f64| (phi - 359.7).to_radians().cos();
        assert!((max_on_cycle(g).0 - 359.7).abs() < 1e-6);
        // On an interval: at an end, and inside.
        assert!((max_on(|p| p, 10.0, 20.5).0 - 20.5).abs() < 1e-12);
        let (x, v) = min_on(|p: f64| (p - 15.25).abs(), 10.0, 20.5);
        assert!((x - 15.25).abs() < 1e-8 && v < 1e-8, "{x}");
        let ((x_hi, _), (x_lo, v_lo)) = {
            let f = |p: f64| (p - 100.3).to_radians().cos();
            extremes_in(&scan_cycle(f), f)
        };
        assert!((x_hi - 100.3).abs() < 1e-6 && (x_lo - 280.3).abs() < 1e-6 && (v_lo + 1.0).abs() < 1e-12);
        let cos = |p: f64| p.to_radians().cos();
        let (down, up) = first_crossings_in(&scan_cycle(cos), cos);
        assert!((down.unwrap() - 90.0).abs() < 1e-9 && (up.unwrap() - 270.0).abs() < 1e-9);
        // Two humps: both local maxima, in order.
        let h = |p: f64| (2.0 * p.to_radians()).sin();
        let peaks = local_maxima(h, 0.0, 359.0);
        assert_eq!(peaks.len(), 2);
        assert!((peaks[0].0 - 45.0).abs() < 1e-6 && (peaks[1].0 - 225.0).abs() < 1e-6);
    }
}
