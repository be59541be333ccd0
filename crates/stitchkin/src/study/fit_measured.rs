//! The machine's setting from its measured take-up: the model fitted to
//! measured curves P(φ) (or P′(φ)) by weighted least squares, with
//! confidence intervals, the correlation of the fitted parameters and a
//! warning when the data cannot tell two of them apart.
//!
//! Each curve (a [`MeasuredCurve`], placed beside its stitch thread as
//! [`super::measured::measured_match`] places it) gives samples
//! (φ_i, y_i) with, when it comes from repeated readings (seed 004 §3.4),
//! a standard uncertainty σ_i. With m_i(x) the model's curve of the same
//! kind at φ_i and x the fitted parameters, the fit minimises
//!
//! ```text
//! S(x) = Σ_i r_i(x)²,   r_i = (m_i(x) − y_i) / σ_i
//! ```
//!
//! (σ_i = 1 mm when the curve carries no uncertainty) within the
//! parameters' bounds, by Levenberg–Marquardt projected onto the box. The
//! Jacobian J_ij = ∂r_i/∂x_j comes exact from one dual-number cycle per
//! parameter ([`super::sensitivity::take_up_derivatives`]) when the curve
//! is an actual take-up P at its thread's own split point; a required P′,
//! or a P measured at the moving eye of a thread split at B (moved to B by
//! the needle's travel, which the parameters may change), takes a central
//! difference of the whole residual.
//!
//! At the optimum x̂ (linearised, Bard 1974 §7; Seber & Wild 1989 §2.1):
//!
//! ```text
//! A = JᵀJ                            (JᵀWJ of the unweighted Jacobian, W = diag 1/σ_i²)
//! Cov(x̂) = A⁻¹                       σ_i known
//! Cov(x̂) = s² A⁻¹,  s² = S(x̂)/(n − p) σ_i unknown (one reading per φ)
//! x̂_j ± q · √Cov_jj                   q = z_(1+c)/2 (known) or t_(1+c)/2, n−p (estimated)
//! ρ_jk = Cov_jk / √(Cov_jj Cov_kk)
//! χ²/dof = S(x̂)/(n − p)
//! ```
//!
//! with n samples, p parameters and c the confidence. Two parameters whose
//! |ρ| exceeds [`INSEPARABLE_LIMIT`], or an A whose condition (scaled to a
//! unit diagonal) exceeds [`CONDITION_LIMIT`], are named in a warning: the
//! data shift the curve alike for both, so their values are not told apart.
//! Above [`CORRELATION_LIMIT`] a warning says they are strongly correlated
//! and by how much each interval is widened, √(1/(1 − ρ²)).

use crate::thread::repeated::student_t_quantile;
use rayon::prelude::*;
use serde::Serialize;

use super::fit::{Bounded, FittedParam};
use super::least_squares::{Eval, invert_scaled, levenberg_marquardt, normal_matrix};
use super::measured::{MeasuredMatch, measured_match};
use super::sensitivity::{FD_REL_STEP, take_up_derivatives};
use super::straightness::normal_quantile;
use super::tune::{KindRefusal, TuneOptions, TuneResult, tune};
use crate::error::{Error, Input, ParamError};
use crate::eval::{CycleOptions, CycleTable, check_options, run_cycle_with};
use crate::model::{Model, Params};
use crate::thread::measured::{CurveKind, MeasuredCurve};

/// |ρ| above which two fitted parameters are said to be strongly
/// correlated (a variance inflation 1/(1 − ρ²) above about 10, the usual
/// mark of collinearity).
pub const CORRELATION_LIMIT: f64 = 0.95;
/// |ρ| above which two fitted parameters are said not to be told apart
/// (variance inflation above 50: each interval at least 7 times as wide as
/// with the other known).
pub const INSEPARABLE_LIMIT: f64 = 0.99;
/// Condition number of JᵀWJ (scaled to a unit diagonal) above which the
/// fitted parameters are said not to be determined independently.
pub const CONDITION_LIMIT: f64 = 1e6;

/// How to fit.
#[derive(Debug, Clone, PartialEq)]
pub struct FitMeasuredOptions {
    /// `NAME` (within its adjustable range) or `NAME=LO:HI`.
    pub adjust: Vec<String>,
    /// φ step of the cycles, deg; `None`: 1° when every sample lies on the
    /// 1° grid, else the largest step that holds them all.
    pub step_deg: Option<f64>,
    /// Levenberg–Marquardt iterations at most.
    pub max_iterations: usize,
    /// Confidence of the intervals, 0 < c < 1 (0.95).
    pub confidence: f64,
}

impl Default for FitMeasuredOptions {
    fn default() -> Self {
        FitMeasuredOptions {
            adjust: Vec::new(),
            step_deg: None,
            max_iterations: 100,
            confidence: 0.95,
        }
    }
}

/// A measured curve to fit, with the stitch thread it belongs to when its
/// column does not say.
#[derive(Debug, Clone)]
pub struct CurveInput {
    pub thread: Option<String>,
    pub curve: MeasuredCurve,
}

/// One curve after the fit: its samples, the model there and the residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CurveFit {
    pub source: String,
    pub thread: String,
    pub path: String,
    pub kind: CurveKind,
    /// Whether the Jacobian of this curve's residuals was exact (dual
    /// numbers) or a central difference.
    pub exact_jacobian: bool,
    pub phi_deg: Vec<f64>,
    /// The measured values placed at the thread's split point, mm.
    pub measured_mm: Vec<f64>,
    /// Their standard uncertainty, mm, when the curve carries one.
    pub sigma_mm: Option<Vec<f64>>,
    /// The fitted model's curve at the samples, mm.
    pub model_mm: Vec<f64>,
    /// model − measured, mm.
    pub residual_mm: Vec<f64>,
    pub rms_residual_mm: f64,
}

/// The outcome of a fit to measured curves.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuredFit {
    pub params: Vec<FittedParam>,
    pub curves: Vec<CurveFit>,
    pub step_deg: f64,
    /// n, p and n − p.
    pub samples: usize,
    pub dof: usize,
    /// Whether every curve carries its uncertainty (weights 1/σ²) or σ is
    /// estimated from the residuals.
    pub sigma_known: bool,
    /// s = √(S/(n − p)), mm, when σ is estimated.
    pub sigma_estimated_mm: Option<f64>,
    /// S at the start and at the end.
    pub cost_start: f64,
    pub cost: f64,
    /// S/(n − p).
    pub chi2_per_dof: f64,
    pub confidence: f64,
    /// q of the intervals and what it is.
    pub quantile: f64,
    pub quantile_from: String,
    /// ρ_jk, in the order of `params`; empty when A is singular.
    pub correlation: Vec<Vec<f64>>,
    /// Condition of A scaled to a unit diagonal.
    pub condition: f64,
    pub iterations: usize,
    pub cycles: usize,
    pub converged: bool,
    pub stop: String,
    pub warnings: Vec<String>,
    /// How the fit was made (weights, Jacobians).
    pub notes: Vec<String>,
}

/// A parameter error of the fit's inputs.
fn bad(input: Option<Input>, message: String, help: String) -> Error {
    Error::Param(ParamError {
        input,
        message,
        help: Some(help),
    })
}

/// One placed curve: which model curve it is compared with and where its
/// samples sit on the cycle's grid.
struct Placed {
    thread: String,
    path: String,
    /// The model's column compared with it (P or P′ at the split).
    model_column: String,
    exact: bool,
    grid: Vec<usize>,
    /// The measured values at the samples as placed at the start, mm.
    measured: Vec<f64>,
    /// σ_i, mm (1 when unknown).
    sigma: Vec<f64>,
}

struct Problem<'a> {
    model: &'a Model,
    base: &'a Params,
    curves: &'a [CurveInput],
    adjusted: Vec<Bounded>,
    placed: Vec<Placed>,
    step_deg: f64,
    cycles: std::sync::atomic::AtomicUsize,
}

impl Problem<'_> {
    fn params_at(&self, x: &[f64]) -> Params {
        let mut p = self.base.clone();
        for (a, &v) in self.adjusted.iter().zip(x) {
            p.values[a.index] = v;
        }
        p
    }

    fn count(&self, k: usize) {
        self.cycles.fetch_add(k, std::sync::atomic::Ordering::Relaxed);
    }

    fn table(&self, p: &Params) -> Result<CycleTable, Error> {
        self.count(1);
        run_cycle_with(self.model, p, &cycle_options(self.step_deg), None)
    }

    /// (model, measured) at every curve's samples, from a full cycle.
    fn placed_values(&self, p: &Params) -> Result<Vec<ModelAndMeasured>, Error> {
        let t = self.table(p)?;
        self.curves
            .iter()
            .zip(&self.placed)
            .map(|(c, pl)| {
                let m = measured_match(&t, &c.curve, Some(&pl.thread))?;
                let col = t.column(&pl.model_column).unwrap_or(&[]);
                let model: Vec<f64> = pl
                    .grid
                    .iter()
                    .map(|&k| col.get(k).copied().unwrap_or(f64::NAN))
                    .collect();
                let meas: Vec<f64> = pl.grid.iter().map(|&k| m.values_mm[k]).collect();
                Ok((model, meas))
            })
            .collect()
    }

    /// The residuals r_i = (m_i − y_i)/σ_i of every curve, in order.
    fn residuals(&self, values: &[(Vec<f64>, Vec<f64>)]) -> Result<Vec<f64>, Error> {
        let mut r = Vec::new();
        for ((m, y), pl) in values.iter().zip(&self.placed) {
            for ((m, y), s) in m.iter().zip(y).zip(&pl.sigma) {
                r.push((m - y) / s);
            }
        }
        if r.iter().all(|v| v.is_finite()) {
            Ok(r)
        } else {
            Err(bad(
                None,
                "the model's curve is not defined at every measured φ here".into(),
                "start nearer the machine's setting".into(),
            ))
        }
    }

    /// The dual cycles seeded on each index of `seeds`: P of every path and
    /// dP/dx.
    fn duals(&self, p: &Params, seeds: &[usize]) -> Result<Vec<PathDerivatives>, Error> {
        self.count(seeds.len());
        seeds
            .par_iter()
            .map(|&i| Ok(take_up_derivatives(self.model, p, i, self.step_deg)?.1))
            .collect()
    }

    /// P and dP/dx of path `path` in a dual cycle's output.
    fn path_of<'b>(paths: &'b PathDerivatives, path: &str) -> Result<(&'b [f64], &'b [f64]), Error> {
        paths
            .iter()
            .find(|(name, ..)| name == path)
            .map(|(_, p, d)| (p.as_slice(), d.as_slice()))
            .ok_or_else(|| {
                bad(
                    None,
                    format!("thread path `{path}` has no take-up to fit"),
                    "fit a curve of a thread with a take-up path".into(),
                )
            })
    }

    fn evaluate(&self, x: &[f64], jacobian: bool) -> Result<Eval, Error> {
        let p = self.params_at(x);
        let all_exact = self.placed.iter().all(|pl| pl.exact);
        let seeds: Vec<usize> = if jacobian {
            self.adjusted.iter().map(|a| a.index).collect()
        } else if all_exact {
            vec![self.adjusted[0].index]
        } else {
            Vec::new()
        };
        let any_exact = self.placed.iter().any(|pl| pl.exact);
        let duals = if any_exact { self.duals(&p, &seeds)? } else { Vec::new() };
        // The values: from a dual cycle when every curve is a P at its
        // thread's split (its placement then does not move with x), else
        // from a full cycle with the stitch process.
        let values = if all_exact {
            self.placed
                .iter()
                .map(|pl| {
                    let (pv, _) = Self::path_of(&duals[0], &pl.path)?;
                    let model = pl.grid.iter().map(|&k| pv[k]).collect();
                    Ok((model, pl.measured.clone()))
                })
                .collect::<Result<Vec<_>, Error>>()?
        } else {
            self.placed_values(&p)?
        };
        let r = self.residuals(&values)?;
        if !jacobian {
            return Ok((r, None));
        }
        let n = r.len();
        // Column j of J: exact rows from the dual cycle seeded on x_j, the
        // rest by a central difference of the residuals.
        let cols: Vec<Result<Vec<f64>, Error>> = (0..self.adjusted.len())
            .into_par_iter()
            .map(|j| {
                let a = &self.adjusted[j];
                let fd = if all_exact {
                    None
                } else {
                    let h = FD_REL_STEP * (a.hi - a.lo);
                    let (mut up, mut dn) = (p.clone(), p.clone());
                    up.values[a.index] += h;
                    dn.values[a.index] -= h;
                    Some((self.placed_values(&up)?, self.placed_values(&dn)?, h))
                };
                let mut col = Vec::with_capacity(n);
                for (c, pl) in self.placed.iter().enumerate() {
                    for (s, &k) in pl.grid.iter().enumerate() {
                        col.push(if pl.exact {
                            let (_, dp) = Self::path_of(&duals[j], &pl.path)?;
                            dp[k] / pl.sigma[s]
                        } else {
                            let (up, dn, h) = fd.as_ref().expect("computed when a curve is not exact");
                            let d = |v: &[(Vec<f64>, Vec<f64>)]| v[c].0[s] - v[c].1[s];
                            (d(up) - d(dn)) / (2.0 * h) / pl.sigma[s]
                        });
                    }
                }
                Ok(col)
            })
            .collect();
        let cols = cols.into_iter().collect::<Result<Vec<_>, _>>()?;
        let jac = (0..n).map(|i| cols.iter().map(|c| c[i]).collect()).collect();
        Ok((r, Some(jac)))
    }
}

/// A curve's model and measured values at its samples, mm.
type ModelAndMeasured = (Vec<f64>, Vec<f64>);

/// P of every thread path and dP/dx over the cycle (one dual cycle).
type PathDerivatives = Vec<(String, Vec<f64>, Vec<f64>)>;

fn cycle_options(step_deg: f64) -> CycleOptions {
    CycleOptions {
        step_deg,
        rpm: None,
        analogs: false,
        points: Some(Vec::new()),
        lean: false,
    }
}

/// The φ step that holds every sample: 1° when all lie on whole degrees,
/// else the greatest common divisor of their angles (to 1e-6°).
fn default_step(curves: &[CurveInput], start_deg: f64) -> f64 {
    let micro = |phi: f64| ((phi - start_deg).rem_euclid(360.0) * 1e6).round() as u64;
    fn gcd(a: u64, b: u64) -> u64 {
        if b == 0 { a } else { gcd(b, a % b) }
    }
    let g = curves
        .iter()
        .flat_map(|c| c.curve.phi_deg().iter().map(|&p| micro(p)))
        .fold(360_000_000u64, gcd);
    if g % 1_000_000 == 0 { 1.0 } else { g as f64 / 1e6 }
}

/// The index of each sample on the cycle's φ grid.
fn grid_indices(phis: &[f64], curve: &MeasuredCurve, step_deg: f64) -> Result<Vec<usize>, Error> {
    curve
        .phi_deg()
        .iter()
        .map(|&phi| {
            phis.iter()
                .position(|&g| {
                    let d = (g - phi).rem_euclid(360.0);
                    d.min(360.0 - d) < 1e-6
                })
                .ok_or_else(|| {
                    bad(
                        Some(Input::Step),
                        format!(
                            "{}: the sample at φ = {} deg does not lie on the cycle's {} deg grid",
                            curve.source(),
                            crate::format::fmt_num(phi),
                            crate::format::fmt_num(step_deg)
                        ),
                        "give a φ step that divides the curve's angles (e.g. 1 deg for whole degrees)".into(),
                    )
                })
        })
        .collect()
}

/// Places every curve beside its thread at the start (which thread, which
/// model curve, where on the grid) and checks its uncertainties.
fn place(model: &Model, table: &CycleTable, curves: &[CurveInput], step_deg: f64) -> Result<Vec<Placed>, Error> {
    let phis = table.column("phi_deg").unwrap_or(&[]);
    let st = table.stitch.as_ref();
    curves
        .iter()
        .map(|c| {
            let m: MeasuredMatch = measured_match(table, &c.curve, c.thread.as_deref())?;
            let (path, model_column, exact) = match st {
                Some(st) => {
                    let th = st.threads.iter().find(|t| t.thread == m.thread).ok_or_else(|| {
                        bad(
                            Some(Input::Measured),
                            format!("{}: thread `{}` is not in the stitch", c.curve.source(), m.thread),
                            format!("use a model whose [stitch] has it ({})", model.name()),
                        )
                    })?;
                    let path = th.path.clone().unwrap_or_default();
                    let p_column = table
                        .paths
                        .iter()
                        .find(|q| q.path == path)
                        .map_or(format!("{path}.P_mm"), |q| q.p_column.clone());
                    let exact = m.kind == CurveKind::TakeUp && c.curve.split().is_none_or(|s| s == th.split);
                    let model_column = match m.kind {
                        CurveKind::TakeUp => p_column,
                        CurveKind::Required => th.pprime_column(),
                    };
                    (path, model_column, exact)
                }
                // A feed mechanism alone: a measured P against its path's P.
                None => {
                    if m.kind == CurveKind::Required {
                        return Err(bad(
                            Some(Input::Measured),
                            format!(
                                "{}: a required take-up P′ cannot be fitted on a model without [stitch] (it has \
                                 no P′ of its own)",
                                c.curve.source()
                            ),
                            "fit a measured take-up P (a column P_mm), or add a [stitch] to the model".into(),
                        ));
                    }
                    let q = table
                        .paths
                        .iter()
                        .find(|q| q.path == m.thread)
                        .expect("placed on a path");
                    (q.path.clone(), q.p_column.clone(), true)
                }
            };
            let sigma = match c.curve.sigma_mm() {
                Some(s) => {
                    if let Some(i) = s.iter().position(|&v| v <= 0.0) {
                        return Err(bad(
                            Some(Input::Measured),
                            format!(
                                "{}: the uncertainty at φ = {} deg is 0 mm, which would pin the fit to that sample",
                                c.curve.source(),
                                crate::format::fmt_num(c.curve.phi_deg()[i])
                            ),
                            "give every sample a standard uncertainty above 0 (at least the instrument's \
                             resolution)"
                                .into(),
                        ));
                    }
                    s.to_vec()
                }
                None => vec![1.0; c.curve.phi_deg().len()],
            };
            let grid = grid_indices(phis, &c.curve, step_deg)?;
            Ok(Placed {
                thread: m.thread,
                path,
                model_column,
                exact,
                measured: grid.iter().map(|&k| m.values_mm[k]).collect(),
                grid,
                sigma,
            })
        })
        .collect()
}

/// The fitted parameters, once each, after checking the curves and the
/// confidence.
fn checked_inputs(model: &Model, curves: &[CurveInput], opts: &FitMeasuredOptions) -> Result<Vec<Bounded>, Error> {
    if curves.is_empty() {
        return Err(bad(
            Some(Input::Measured),
            "no measured curve to fit".into(),
            "give a CSV `phi_deg,P_mm` of the take-up measured on the machine".into(),
        ));
    }
    if !(opts.confidence > 0.0 && opts.confidence < 1.0) {
        return Err(bad(
            None,
            format!("the confidence must lie between 0 and 1, got {}", opts.confidence),
            "e.g. 0.95 for 95 % intervals".into(),
        ));
    }
    if opts.adjust.is_empty() {
        return Err(bad(
            Some(Input::Adjust),
            "nothing to fit".into(),
            "name the parameters to fit: NAME (within its range) or NAME=LO:HI, e.g. z,dphi".into(),
        ));
    }
    let adjusted = opts
        .adjust
        .iter()
        .map(|s| Bounded::parse(model, s))
        .collect::<Result<Vec<_>, _>>()?;
    for (k, a) in adjusted.iter().enumerate() {
        if adjusted[..k].iter().any(|b| b.name == a.name) {
            return Err(bad(
                Some(Input::Adjust),
                format!("`{}` is fitted twice", a.name),
                "name each parameter once".into(),
            ));
        }
    }
    Ok(adjusted)
}

/// Each curve at the optimum: measured, model and residual at its samples.
fn curve_fits(
    curves: &[CurveInput],
    placed: &[Placed],
    values: Vec<ModelAndMeasured>,
    sigma_known: bool,
) -> Vec<CurveFit> {
    curves
        .iter()
        .zip(placed)
        .zip(values)
        .map(|((c, pl), (m, y))| {
            let res: Vec<f64> = m.iter().zip(&y).map(|(a, b)| a - b).collect();
            let rms = (res.iter().map(|v| v * v).sum::<f64>() / res.len().max(1) as f64).sqrt();
            CurveFit {
                source: c.curve.source().to_string(),
                thread: pl.thread.clone(),
                path: pl.path.clone(),
                kind: c.curve.kind(),
                exact_jacobian: pl.exact,
                phi_deg: c.curve.phi_deg().to_vec(),
                measured_mm: y,
                sigma_mm: if sigma_known { Some(pl.sigma.clone()) } else { None },
                model_mm: m,
                residual_mm: res,
                rms_residual_mm: rms,
            }
        })
        .collect()
}

/// ρ_jk = Cov_jk / √(Cov_jj Cov_kk).
fn correlation_of(c: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let p = c.len();
    (0..p)
        .map(|j| {
            (0..p)
                .map(|k| {
                    let d = (c[j][j] * c[k][k]).sqrt();
                    if d > 0.0 { (c[j][k] / d).clamp(-1.0, 1.0) } else { 0.0 }
                })
                .collect()
        })
        .collect()
}

/// q of the intervals and what it is: z_((1+c)/2) when σ is known, else
/// t_((1+c)/2, n−p).
fn interval_quantile(sigma_known: bool, confidence: f64, dof: usize) -> (f64, String) {
    let tail = 0.5 * (1.0 + confidence);
    if sigma_known {
        (
            normal_quantile(tail),
            "the normal quantile, σ known from the measurement".to_string(),
        )
    } else {
        (
            student_t_quantile(tail, dof as f64),
            format!("Student's t quantile with n − p = {dof} degrees of freedom, σ estimated"),
        )
    }
}

/// The start inside every parameter's bounds.
fn check_start(adjusted: &[Bounded], start: &[f64]) -> Result<(), Error> {
    for (a, &x) in adjusted.iter().zip(start) {
        if x < a.lo || x > a.hi {
            return Err(bad(
                Some(Input::Adjust),
                format!(
                    "the start {} = {x} {} lies outside its bounds {}…{} {}",
                    a.name, a.unit, a.lo, a.hi, a.unit
                ),
                format!("start inside them or widen them ({}=LO:HI)", a.name),
            ));
        }
    }
    Ok(())
}

/// Fits `opts.adjust` of `model` (starting from `base`) to the measured
/// `curves`.
pub fn fit_measured(
    model: &Model,
    base: &Params,
    curves: &[CurveInput],
    opts: &FitMeasuredOptions,
) -> Result<MeasuredFit, Error> {
    let adjusted = checked_inputs(model, curves, opts)?;
    let step_deg = opts
        .step_deg
        .unwrap_or_else(|| default_step(curves, model.phi_start_deg()));
    check_options(&CycleOptions {
        step_deg,
        ..Default::default()
    })?;
    let start: Vec<f64> = adjusted.iter().map(|a| base.values[a.index]).collect();
    check_start(&adjusted, &start)?;
    let table = run_cycle_with(model, base, &cycle_options(step_deg), None)?;
    let placed = place(model, &table, curves, step_deg)?;
    let (n, p) = (placed.iter().map(|pl| pl.grid.len()).sum::<usize>(), adjusted.len());
    if n <= p {
        return Err(bad(
            Some(Input::Measured),
            format!("{n} measured samples for {p} parameters: a fit needs more samples than parameters"),
            "measure at more φ, or fit fewer parameters".into(),
        ));
    }
    let sigma_known = curves.iter().all(|c| c.curve.sigma_mm().is_some());
    let mut notes = Vec::new();
    if !sigma_known && curves.iter().any(|c| c.curve.sigma_mm().is_some()) {
        notes.push(
            "some curves carry no uncertainty: every sample weighs alike and σ is estimated from the residuals".into(),
        );
    }
    let placed = if sigma_known {
        placed
    } else {
        placed
            .into_iter()
            .map(|pl| Placed {
                sigma: vec![1.0; pl.grid.len()],
                ..pl
            })
            .collect()
    };
    let problem = Problem {
        model,
        base,
        curves,
        adjusted,
        placed,
        step_deg,
        cycles: Default::default(),
    };
    let bounds: Vec<(f64, f64)> = problem.adjusted.iter().map(|a| (a.lo, a.hi)).collect();
    let lm = levenberg_marquardt(&bounds, &start, opts.max_iterations, |x, j| problem.evaluate(x, j))?;
    let (r, jac) = problem.evaluate(&lm.x, true)?;
    let jac = jac.expect("asked for");
    let cost: f64 = r.iter().map(|v| v * v).sum();
    let dof = n - p;
    let chi2_per_dof = cost / dof as f64;
    // A = JᵀJ (the weights are in J's rows).
    let a = normal_matrix(&jac);
    let (inv, condition) = invert_scaled(&a);
    let scale = if sigma_known { 1.0 } else { chi2_per_dof };
    let cov: Option<Vec<Vec<f64>>> = inv.map(|m| m.iter().map(|row| row.iter().map(|v| v * scale).collect()).collect());
    let (quantile, quantile_from) = interval_quantile(sigma_known, opts.confidence, dof);
    let params: Vec<FittedParam> = problem
        .adjusted
        .iter()
        .enumerate()
        .map(|(j, b)| {
            let se = cov.as_ref().map(|c| c[j][j].max(0.0).sqrt()).filter(|v| v.is_finite());
            let x = lm.x[j];
            FittedParam {
                name: b.name.clone(),
                label: model.params[b.index].label_or_name().to_string(),
                unit: b.unit,
                lo: b.lo,
                hi: b.hi,
                start: start[j],
                fitted: x,
                std_error: se,
                interval: se.map(|s| [x - quantile * s, x + quantile * s]),
                at_bound: x <= b.lo || x >= b.hi,
            }
        })
        .collect();
    let correlation = cov.as_ref().map_or_else(Vec::new, |c| correlation_of(c));
    let warnings = warnings(&params, &correlation, condition, sigma_known, chi2_per_dof, dof);
    // The curves at the optimum.
    let values = problem.placed_values(&problem.params_at(&lm.x))?;
    let curves_out = curve_fits(curves, &problem.placed, values, sigma_known);
    notes.push(if sigma_known {
        "weights 1/σ² from the measurement's standard uncertainty".to_string()
    } else {
        format!(
            "one reading per φ: σ estimated from the residuals, s² = S/(n − p), s = {} mm",
            crate::format::sig_sci(chi2_per_dof.sqrt(), 3)
        )
    });
    if curves_out.iter().all(|c| c.exact_jacobian) {
        notes.push("Jacobian exact (dual numbers)".into());
    } else {
        notes.push("Jacobian: exact for P at the thread's split, a central difference for the other curves".into());
    }
    Ok(MeasuredFit {
        params,
        curves: curves_out,
        step_deg,
        samples: n,
        dof,
        sigma_known,
        sigma_estimated_mm: (!sigma_known).then(|| chi2_per_dof.sqrt()),
        cost_start: lm.cost_start,
        cost,
        chi2_per_dof,
        confidence: opts.confidence,
        quantile,
        quantile_from,
        correlation,
        condition,
        iterations: lm.iterations,
        cycles: problem.cycles.into_inner(),
        converged: lm.converged,
        stop: lm.stop,
        warnings,
        notes,
    })
}

/// What the data cannot tell: pairs of parameters they do not separate, an
/// ill-conditioned or singular system, a bound reached, a model that does
/// not reproduce the measurement within its uncertainty.
fn warnings(
    params: &[FittedParam],
    correlation: &[Vec<f64>],
    condition: f64,
    sigma_known: bool,
    chi2_per_dof: f64,
    dof: usize,
) -> Vec<String> {
    let mut w = Vec::new();
    if correlation.is_empty() {
        w.push(
            "the data do not determine the fitted parameters (JᵀWJ is singular): their values are one of many and \
             have no interval; fit fewer parameters"
                .into(),
        );
    }
    for j in 0..correlation.len() {
        for k in j + 1..correlation.len() {
            let rho = correlation[j][k];
            let (a, b) = (&params[j], &params[k]);
            if rho.abs() > INSEPARABLE_LIMIT {
                w.push(format!(
                    "`{}` ({}) and `{}` ({}) cannot be told apart from these data: their correlation is {:+.3} \
                     (|ρ| > {INSEPARABLE_LIMIT}), so a change of one is almost undone by a change of the other \
                     (they shift the curve alike, as a phase and a length can); their intervals are wide and their \
                     values uncertain together. Fit one with the other held at its known value, or measure where \
                     their effects on P differ",
                    a.name, a.label, b.name, b.label, rho
                ));
            } else if rho.abs() > CORRELATION_LIMIT {
                w.push(format!(
                    "`{}` ({}) and `{}` ({}) are strongly correlated in these data ({:+.3}, |ρ| > \
                     {CORRELATION_LIMIT}): an error in one is largely made up by the other, so each interval holds \
                     with the other fitted too, and each is about {:.1} times as uncertain as it would be with the \
                     other known. Holding one at a known value narrows the other; readings where their effects on \
                     P differ separate them",
                    a.name,
                    a.label,
                    b.name,
                    b.label,
                    rho,
                    (1.0 / (1.0 - rho * rho)).sqrt()
                ));
            }
        }
    }
    if !correlation.is_empty() && condition > CONDITION_LIMIT {
        w.push(format!(
            "JᵀWJ is ill-conditioned (condition {:.1e} > {CONDITION_LIMIT:.0e} on a unit diagonal): some combination \
             of the fitted parameters is hardly seen in the data",
            condition
        ));
    }
    for p in params {
        if p.at_bound {
            w.push(format!(
                "`{}` stopped at a bound ({} {}): the best value may lie beyond it and its interval is not reliable",
                p.name,
                crate::format::fmt_num(p.fitted),
                p.unit
            ));
        }
    }
    if sigma_known && chi2_per_dof > 1.0 + 3.0 * (2.0 / dof as f64).sqrt() {
        w.push(format!(
            "χ²/dof = {:.2}: the fitted model misses the measurement by more than its uncertainty (about 1 expected); \
             another dimension differs from the model, or the uncertainty is understated, and the intervals are too \
             narrow",
            chi2_per_dof
        ));
    }
    w
}

/// What the fit means for the stitch: the fitted machine's match and the
/// tune from the fitted setting to the best one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Advice {
    /// The tuning from the fitted setting (its `before_figures` are the
    /// fitted machine's match, `adjustments` the advice in shop terms).
    pub tune: Option<TuneResult>,
    /// Why no tuning was done, or what it leaves out.
    pub notes: Vec<String>,
}

/// The fitted setting: `base` with every fitted value.
pub fn fitted_params(model: &Model, base: &Params, fit: &MeasuredFit) -> Result<Params, Error> {
    let mut p = base.clone();
    for f in &fit.params {
        model.set(&mut p, &f.name, f.fitted)?;
    }
    Ok(p)
}

/// The advice from a fit: the tuning of the fitted machine settings (the
/// fitted parameters that are settings; the others stay as fitted) from the
/// fitted setting, with `samples`, `seed` and `step_deg` as
/// [`super::tune::tune`] takes them.
pub fn advise(
    model: &Model,
    base: &Params,
    fit: &MeasuredFit,
    samples: usize,
    seed: u64,
    step_deg: f64,
) -> Result<Advice, Error> {
    let fitted = fitted_params(model, base, fit)?;
    let mut notes = Vec::new();
    if !model.has_stitch() {
        notes.push("the model has no [stitch]: there is no required take-up to tune the machine to".into());
        return Ok(Advice { tune: None, notes });
    }
    let mut adjust = Vec::new();
    for f in &fit.params {
        let p = &model.params[model.param_index(&f.name).unwrap_or(0)];
        if let Some(refusal) = KindRefusal::of(model, &f.name) {
            notes.push(format!("{}: kept as fitted", refusal.message()));
        } else if p.range.is_none() {
            notes.push(format!("`{}` has no adjustable range: kept as fitted", f.name));
        } else {
            adjust.push(f.name.clone());
        }
    }
    if adjust.is_empty() {
        notes.push("no fitted parameter is a machine setting to adjust".into());
        return Ok(Advice { tune: None, notes });
    }
    let t = tune(
        model,
        &fitted,
        &TuneOptions {
            adjust,
            samples,
            seed,
            step_deg,
            objective: Default::default(),
        },
    )?;
    Ok(Advice { tune: Some(t), notes })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_quantiles_match_tables() {
        // Student's t tables (two-sided 95 %): ν = 1, 2, 10, 30; large ν → z.
        for (nu, t) in [
            (1.0, 12.706_204_736),
            (2.0, 4.302_652_730),
            (10.0, 2.228_138_852),
            (30.0, 2.042_272_456),
        ] {
            assert!((student_t_quantile(0.975, nu) - t).abs() < 1e-6, "ν = {nu}");
        }
        assert!((student_t_quantile(0.975, 1e7) - 1.959_963_985).abs() < 1e-5);
        assert!((student_t_quantile(0.025, 10.0) + 2.228_138_852).abs() < 1e-6);
        assert!((crate::thread::repeated::ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
    }
}
