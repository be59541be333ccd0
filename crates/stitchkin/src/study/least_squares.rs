//! Bounded nonlinear least squares, shared by the fits
//! ([`super::fit`] to stated figures, [`super::fit_measured`] to measured
//! curves): Levenberg–Marquardt with Marquardt's scaling, each step
//! projected onto the box of the parameters' bounds, and the inverse of the
//! normal matrix JᵀJ with its condition for the covariance.
//!
//! The caller's `eval(x, jacobian)` gives the weighted residuals r(x) and,
//! when asked, their Jacobian J_ij = ∂r_i/∂x_j; the cost is S = Σ r_i².

use crate::error::Error;

/// The residual vector at x and, when asked, its Jacobian (rows: residuals).
pub(crate) type Eval = (Vec<f64>, Option<Vec<Vec<f64>>>);

/// JᵀJ of a Jacobian `jac` (rows: residuals).
pub(crate) fn normal_matrix(jac: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let p = jac.first().map_or(0, |row| row.len());
    (0..p)
        .map(|j| (0..p).map(|k| jac.iter().map(|row| row[j] * row[k]).sum()).collect())
        .collect()
}

/// The inverse of a small symmetric positive semidefinite matrix and its
/// condition scaled to a unit diagonal (`None` when singular to working
/// precision).
pub(crate) fn invert_scaled(a: &[Vec<f64>]) -> (Option<Vec<Vec<f64>>>, f64) {
    let n = a.len();
    let d: Vec<f64> = (0..n).map(|j| a[j][j].sqrt()).collect();
    if d.iter().any(|&x| !x.is_finite() || x <= 0.0) {
        return (None, f64::INFINITY);
    }
    let s = nalgebra::DMatrix::from_fn(n, n, |i, j| a[i][j] / (d[i] * d[j]));
    let eig = s.clone().symmetric_eigenvalues();
    let (min, max) = eig
        .iter()
        .fold((f64::MAX, 0.0f64), |(lo, hi), &e| (lo.min(e), hi.max(e)));
    let condition = if min > 0.0 { max / min } else { f64::INFINITY };
    if min <= max * 1e-12 {
        return (None, condition);
    }
    let Some(inv) = s.try_inverse() else {
        return (None, condition);
    };
    (
        Some(
            (0..n)
                .map(|i| (0..n).map(|j| inv[(i, j)] / (d[i] * d[j])).collect())
                .collect(),
        ),
        condition,
    )
}

/// Where Levenberg–Marquardt stopped.
pub(crate) struct Lm {
    pub x: Vec<f64>,
    /// S at `x` and at the start.
    pub cost: f64,
    pub cost_start: f64,
    pub iterations: usize,
    pub converged: bool,
    pub stop: String,
}

/// Levenberg–Marquardt with Marquardt's scaling, each step projected onto
/// the box: (JᵀJ + λ diag JᵀJ) δ = −Jᵀr, x ← clamp(x + δ).
pub(crate) fn levenberg_marquardt(
    bounds: &[(f64, f64)],
    start: &[f64],
    max_iterations: usize,
    eval: impl Fn(&[f64], bool) -> Result<Eval, Error>,
) -> Result<Lm, Error> {
    let p = start.len();
    let (r, jac) = eval(start, true)?;
    let mut jac = jac.expect("asked for");
    let mut x = start.to_vec();
    let mut cost: f64 = r.iter().map(|v| v * v).sum();
    let mut r = r;
    let cost_start = cost;
    let mut lambda = 1e-3;
    let (mut converged, mut stop) = (false, "the iteration limit was reached".to_string());
    let mut iterations = 0;
    'outer: while iterations < max_iterations {
        iterations += 1;
        let a: Vec<Vec<f64>> = (0..p)
            .map(|j| (0..p).map(|k| jac.iter().map(|row| row[j] * row[k]).sum()).collect())
            .collect();
        let g: Vec<f64> = (0..p)
            .map(|j| jac.iter().zip(&r).map(|(row, ri)| row[j] * ri).sum())
            .collect();
        if cost <= 1e-24
            || g.iter()
                .zip(bounds)
                .all(|(g, (lo, hi))| (g * (hi - lo)).abs() <= 1e-12 * (1.0 + cost))
        {
            (converged, stop) = (true, "the gradient vanishes".into());
            break;
        }
        loop {
            let floor = 1e-12 * (0..p).map(|j| a[j][j]).fold(0.0, f64::max).max(1e-300);
            let m = nalgebra::DMatrix::from_fn(p, p, |i, j| {
                a[i][j] + if i == j { lambda * a[j][j].max(floor) } else { 0.0 }
            });
            let rhs = nalgebra::DVector::from_iterator(p, g.iter().map(|v| -v));
            let delta = nalgebra::linalg::Cholesky::new(m).map(|c| c.solve(&rhs));
            let Some(delta) = delta.filter(|d| d.iter().all(|v| v.is_finite())) else {
                lambda *= 10.0;
                if lambda > 1e12 {
                    (converged, stop) = (false, "no step lowers the cost (the system is singular)".into());
                    break 'outer;
                }
                continue;
            };
            let trial: Vec<f64> = x
                .iter()
                .zip(delta.iter())
                .zip(bounds)
                .map(|((x, d), (lo, hi))| (x + d).clamp(*lo, *hi))
                .collect();
            let moved = trial
                .iter()
                .zip(&x)
                .zip(bounds)
                .map(|((t, x), (lo, hi))| (t - x).abs() / (hi - lo))
                .fold(0.0, f64::max);
            if moved <= 1e-12 {
                let pressed = x
                    .iter()
                    .zip(delta.iter())
                    .zip(bounds)
                    .any(|((x, d), (lo, hi))| (x <= lo && *d < 0.0) || (x >= hi && *d > 0.0));
                (converged, stop) = (
                    true,
                    if pressed {
                        "the step vanishes: pressed against a bound"
                    } else {
                        "the step vanishes"
                    }
                    .into(),
                );
                break 'outer;
            }
            let better = match eval(&trial, false) {
                Ok((rt, _)) => {
                    let ct: f64 = rt.iter().map(|v| v * v).sum();
                    (ct < cost).then_some((rt, ct))
                }
                // A setting that does not assemble counts as no better.
                Err(_) => None,
            };
            let Some((rt, ct)) = better else {
                lambda *= 10.0;
                if lambda > 1e12 {
                    (converged, stop) = (true, "no step lowers the cost (a local minimum)".into());
                    break 'outer;
                }
                continue;
            };
            let drop = (cost - ct) / cost.max(1e-300);
            (x, r, cost) = (trial, rt, ct);
            lambda = (lambda / 10.0).max(1e-12);
            if drop < 1e-12 || moved < 1e-10 {
                (converged, stop) = (true, "the cost no longer decreases".into());
                break 'outer;
            }
            jac = eval(&x, true)?.1.expect("asked for");
            continue 'outer;
        }
    }
    Ok(Lm {
        x,
        cost,
        cost_start,
        iterations,
        converged,
        stop,
    })
}
