//! Small dense linear algebra on the stack-sized systems the solvers meet:
//! LU with partial pivoting, in place, without allocation (the Newton groups
//! of `mechanism` and the cam contact of `thread` each solve a few unknowns
//! millions of times in a sweep), and the periodic cubic spline that carries
//! a cam's profile or a follower's lift table over one turn.

use crate::scalar::Real;

/// LU factorisation with partial pivoting of the row-major `n × n` matrix `a`,
/// in place. Returns false when `a` is singular.
pub fn lu_factor(a: &mut [f64], n: usize, piv: &mut [usize]) -> bool {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs()))
            .unwrap_or(k);
        piv[k] = p;
        if a[p * n + k].abs() <= 1e-13 * scale {
            return false;
        }
        if p != k {
            for c in 0..n {
                a.swap(k * n + c, p * n + c);
            }
        }
        for i in k + 1..n {
            let f = a[i * n + k] / a[k * n + k];
            a[i * n + k] = f;
            for c in k + 1..n {
                a[i * n + c] -= f * a[k * n + c];
            }
        }
    }
    true
}

/// Solves `a x = b` in place with the factors of [`lu_factor`]; `b` may be
/// dual numbers (the matrix is real).
pub fn lu_solve<S: Real>(a: &[f64], n: usize, piv: &[usize], b: &mut [S]) {
    for k in 0..n {
        b.swap(k, piv[k]);
    }
    for i in 0..n {
        for c in 0..i {
            let bc = b[c];
            b[i] -= bc * S::cst(a[i * n + c]);
        }
    }
    for i in (0..n).rev() {
        for c in i + 1..n {
            let bc = b[c];
            b[i] -= bc * S::cst(a[i * n + c]);
        }
        b[i] /= S::cst(a[i * n + i]);
    }
}

/// A periodic cubic spline through `(x_i, y_i)` over one period: twice
/// continuously differentiable, closing smoothly on itself. Evaluated
/// generically, so a dual-number argument carries exact first and second
/// derivatives (a cam's profile ρ(θ), a follower's lift s(δ)).
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicCubic {
    /// Knots, strictly increasing within one period.
    pub x: Vec<f64>,
    /// Segment i: y(x_i + t) = c0 + c1 t + c2 t² + c3 t³.
    pub coef: Vec<[f64; 4]>,
    pub period: f64,
}

impl PeriodicCubic {
    /// Through the points (`x` strictly increasing, spanning less than one
    /// `period`; at least three points).
    pub fn new(x: &[f64], y: &[f64], period: f64) -> PeriodicCubic {
        let n = x.len();
        let h: Vec<f64> = (0..n)
            .map(|i| {
                if i + 1 < n {
                    x[i + 1] - x[i]
                } else {
                    x[0] + period - x[n - 1]
                }
            })
            .collect();
        let yv = |i: usize| y[i % n];
        // The periodic natural-cubic system for the second derivatives M_i
        // (cyclic tridiagonal; solved densely, tables have few points).
        let mut a = vec![0.0; n * n];
        let mut b = vec![0.0; n];
        for i in 0..n {
            let hp = h[(i + n - 1) % n];
            let hi = h[i];
            a[i * n + (i + n - 1) % n] += hp / 6.0;
            a[i * n + i] += (hp + hi) / 3.0;
            a[i * n + (i + 1) % n] += hi / 6.0;
            b[i] = (yv(i + 1) - yv(i)) / hi - (yv(i) - yv(i + n - 1)) / hp;
        }
        let mut piv = vec![0; n];
        let ok = lu_factor(&mut a, n, &mut piv);
        debug_assert!(ok, "the periodic spline system is diagonally dominant");
        lu_solve(&a, n, &piv, &mut b);
        let m = b;
        let coef = (0..n)
            .map(|i| {
                let (hi, m0, m1) = (h[i], m[i], m[(i + 1) % n]);
                let c1 = (yv(i + 1) - yv(i)) / hi - hi * (2.0 * m0 + m1) / 6.0;
                [yv(i), c1, m0 / 2.0, (m1 - m0) / (6.0 * hi)]
            })
            .collect();
        PeriodicCubic {
            x: x.to_vec(),
            coef,
            period,
        }
    }

    /// The segment holding `t` (reduced into the period that starts at the
    /// first knot) and `t` less that segment's knot.
    fn locate<T: Real>(&self, t: T) -> (usize, T) {
        let turns = ((t.re() - self.x[0]) / self.period).floor();
        let t0 = t - T::cst(turns * self.period);
        let i = self.x.iter().rposition(|&k| k <= t0.re()).unwrap_or(self.x.len() - 1);
        (i, t0 - T::cst(self.x[i]))
    }

    /// y(t), generic so `t` may carry derivatives.
    pub fn eval<T: Real>(&self, t: T) -> T {
        let (i, t) = self.locate(t);
        let [c0, c1, c2, c3] = self.coef[i];
        ((t * T::cst(c3) + T::cst(c2)) * t + T::cst(c1)) * t + T::cst(c0)
    }

    /// y'(t), generic.
    pub fn slope<T: Real>(&self, t: T) -> T {
        let (i, t) = self.locate(t);
        let [_, c1, c2, c3] = self.coef[i];
        (t * T::cst(3.0 * c3) + T::cst(2.0 * c2)) * t + T::cst(c1)
    }
}

/// Numbers in [0, 1) from `seed` (xorshift), the same on every run: the
/// random cases of the tests.
#[cfg(test)]
pub(crate) fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn lu_solves_a_small_system() {
        let mut a = vec![0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        let mut piv = vec![0; 3];
        assert!(lu_factor(&mut a, 3, &mut piv));
        let mut b = vec![5.0, 2.0, 7.0];
        lu_solve(&a, 3, &piv, &mut b);
        let x = b;
        assert_relative_eq!(0.0 * x[0] + 2.0 * x[1] + x[2], 5.0, epsilon = 1e-12);
        assert_relative_eq!(x[0] + x[1], 2.0, epsilon = 1e-12);
        assert_relative_eq!(3.0 * x[0] + x[2], 7.0, epsilon = 1e-12);
    }

    #[test]
    fn periodic_spline_interpolates_and_closes_with_two_continuous_derivatives() {
        let x = [0.0, 1.0, 2.5, 4.0];
        let y = [1.0, 3.0, 2.0, -1.0];
        let s = PeriodicCubic::new(&x, &y, 5.0);
        for (xi, yi) in x.iter().zip(y) {
            assert_relative_eq!(s.eval(*xi), yi, epsilon = 1e-12);
            assert_relative_eq!(s.eval(*xi + 5.0), yi, epsilon = 1e-12);
        }
        // Value, slope and curvature agree across the wrap at x = 5 ≡ 0.
        let d = |t: f64| {
            let v = s.eval(num_dual::Dual2_64::new(t, 1.0, 0.0));
            [v.re, v.v1, v.v2]
        };
        let (a, b) = (d(5.0 - 1e-9), d(1e-9));
        for k in 0..3 {
            assert_relative_eq!(a[k], b[k], epsilon = 1e-6);
        }
        assert_relative_eq!(s.slope(2.0), d(2.0)[1], epsilon = 1e-12);
    }

    #[test]
    fn a_singular_matrix_is_refused() {
        let mut a = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!lu_factor(&mut a, 2, &mut [0; 2]));
    }
}
