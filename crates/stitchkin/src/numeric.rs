//! Small dense linear algebra on the stack-sized systems the solvers meet:
//! LU with partial pivoting, in place, without allocation (the Newton groups
//! of `mechanism` and the cam contact of `thread` each solve a few unknowns
//! millions of times in a sweep).

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
    fn a_singular_matrix_is_refused() {
        let mut a = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!lu_factor(&mut a, 2, &mut [0; 2]));
    }
}
