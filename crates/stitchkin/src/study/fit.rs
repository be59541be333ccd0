//! Calibration: fit model dimensions (figure-only, reconstructed ones) to
//! stated results.
//!
//! A facts file lists results a source states, each a figure of merit (named
//! as [`super::figures::figures`] names them) at a setting, with a tolerance
//! or a weight:
//!
//! ```toml
//! adjust = ["l_cf=30:45"]          # default parameters to fit, with bounds
//! [[fact]]
//! figure = "needle_y.range_mm"
//! value = 18
//! set = { alpha = 0 }
//! tolerance = 0.25                 # residual / tolerance enters the cost
//! [[fact]]                         # a difference: F(set) − F(relative_to)
//! figure = "needle_y.min_mm"
//! value = 0
//! set = { alpha = 35 }
//! relative_to = { alpha = 0 }
//! tolerance = 0.01
//! ```
//!
//! The fit minimises the weighted sum of squares
//!
//! ```text
//! cost = Σ_i (w_i · (F_i(x) − v_i))²,   w_i = 1/tolerance_i (or the weight)
//! ```
//!
//! over the adjusted parameters x within their bounds, by Levenberg–
//! Marquardt: few parameters and few, smooth residuals make it the natural
//! choice (Gauss–Newton's quadratic convergence near the solution, gradient
//! descent's safety far from it), and every Jacobian column comes exact from
//! one dual-number cycle per setting ([`super::sensitivity::figure_derivatives`]),
//! a central difference only for the match figures. (argmin's Nelder–Mead
//! would need hundreds of cycles and stop at a tolerance in x it cannot
//! certify; its Gauss–Newton has neither damping nor bounds.) Bounds are kept
//! by projecting every step onto the box. At the optimum the linearised
//! standard error √((JᵀJ)⁻¹)_jj of each parameter is reported: with
//! tolerances as weights, how far the parameter may move with the facts
//! still met to their tolerances.

use std::sync::Arc;

use indexmap::IndexMap;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::figures::figures;
use super::least_squares::{invert_scaled, levenberg_marquardt, normal_matrix};
use super::sensitivity::{FD_REL_STEP, figure_derivatives, figure_unit};
use crate::error::{Error, Input, ModelError, ParamError};
use crate::eval::{CycleOptions, check_options, run_cycle_with};
use crate::model::spans::{KeyPath, SpanIndex};
use crate::model::{Model, Params};

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct FactsFileDef {
    title: Option<String>,
    model: Option<String>,
    #[serde(default)]
    adjust: Vec<String>,
    step_deg: Option<f64>,
    #[serde(default)]
    fact: Vec<FactDef>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct FactDef {
    figure: String,
    value: f64,
    #[serde(default)]
    set: IndexMap<String, f64>,
    relative_to: Option<IndexMap<String, f64>>,
    weight: Option<f64>,
    tolerance: Option<f64>,
    source: Option<String>,
}

/// One stated result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fact {
    /// A figure of merit, as `stitchkin sweep --figures` names it.
    pub figure: String,
    /// The stated value, in the figure's unit.
    pub value: f64,
    /// Parameter settings of this fact (on top of the model's and --set).
    pub set: Vec<(String, f64)>,
    /// When given, the fact is the difference F(set) − F(relative_to).
    pub relative_to: Option<Vec<(String, f64)>>,
    /// The residual's multiplier: 1/tolerance, or the weight (default 1).
    pub weight: f64,
    pub tolerance: Option<f64>,
    pub source: Option<String>,
}

/// A facts file.
#[derive(Debug, Clone)]
pub struct Facts {
    pub file: String,
    pub text: Arc<str>,
    pub title: Option<String>,
    /// The model the facts are about (a preset name or a file), if stated.
    pub model: Option<String>,
    /// Parameters to fit when the command line names none: `NAME` or
    /// `NAME=LO:HI`.
    pub adjust: Vec<String>,
    pub step_deg: Option<f64>,
    pub facts: Vec<Fact>,
}

impl Facts {
    /// Parses a facts file; `file` names it in messages.
    pub fn from_toml_str(text: &str, file: &str) -> Result<Facts, Error> {
        let text: Arc<str> = text.into();
        let err = |span: Option<std::ops::Range<usize>>, path: String, message: String, help: &str| {
            Error::Model(Box::new(ModelError {
                file: file.to_string(),
                text: text.clone(),
                span,
                path,
                message,
                help: Some(help.to_string()),
            }))
        };
        let def: FactsFileDef = toml::from_str(&text).map_err(|e| {
            err(
                e.span(),
                String::new(),
                e.message().to_string(),
                "write [[fact]] tables with figure = \"NAME\", value = NUMBER, and optionally set = { PARAM = VALUE }, \
                 relative_to = { PARAM = VALUE }, tolerance = NUMBER or weight = NUMBER, source = \"...\"",
            )
        })?;
        let spans = SpanIndex::new(&text);
        let at = |i: usize, key: &str| KeyPath::root().key("fact").index(i).key(key);
        let mut facts = Vec::new();
        for (i, f) in def.fact.iter().enumerate() {
            let fail = |key: &str, message: String, help: &str| {
                let p = at(i, key);
                err(
                    spans
                        .find(&p)
                        .or_else(|| spans.find(&KeyPath::root().key("fact").index(i))),
                    p.to_string(),
                    message,
                    help,
                )
            };
            if !f.value.is_finite() {
                return Err(fail(
                    "value",
                    "the stated value must be a finite number".into(),
                    "give the value in the figure's unit",
                ));
            }
            let weight = match (f.weight, f.tolerance) {
                (Some(_), Some(_)) => {
                    return Err(fail(
                        "tolerance",
                        "give a tolerance or a weight, not both".into(),
                        "tolerance = T weighs the residual by 1/T",
                    ));
                }
                (Some(w), None) if !(w.is_finite() && w > 0.0) => {
                    return Err(fail(
                        "weight",
                        format!("the weight must be positive, got {w}"),
                        "e.g. weight = 1",
                    ));
                }
                (None, Some(t)) if !(t.is_finite() && t > 0.0) => {
                    return Err(fail(
                        "tolerance",
                        format!("the tolerance must be positive, got {t}"),
                        "in the figure's unit, e.g. tolerance = 0.1",
                    ));
                }
                (Some(w), None) => w,
                (None, Some(t)) => 1.0 / t,
                (None, None) => 1.0,
            };
            let pairs = |m: &IndexMap<String, f64>| m.iter().map(|(k, v)| (k.clone(), *v)).collect::<Vec<_>>();
            facts.push(Fact {
                figure: f.figure.trim().to_string(),
                value: f.value,
                set: pairs(&f.set),
                relative_to: f.relative_to.as_ref().map(pairs),
                weight,
                tolerance: f.tolerance,
                source: f.source.clone(),
            });
        }
        if facts.is_empty() {
            return Err(err(
                None,
                String::new(),
                "the facts file states no fact".into(),
                "add [[fact]] tables: figure = \"needle_y.range_mm\", value = 18",
            ));
        }
        Ok(Facts {
            file: file.to_string(),
            text,
            title: def.title,
            model: def.model,
            adjust: def.adjust,
            step_deg: def.step_deg,
            facts,
        })
    }

    /// Reads and parses a facts file.
    pub fn from_path(path: &std::path::Path) -> Result<Facts, Error> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| Error::Io(crate::error::IoError::os("read facts file", Some(path), e)))?;
        Facts::from_toml_str(&text, &path.display().to_string())
    }

    /// An error at `fact[i].key` of the file.
    fn error_at(&self, i: usize, key: &str, message: String, help: String) -> Error {
        let spans = SpanIndex::new(&self.text);
        let p = KeyPath::root().key("fact").index(i).key(key);
        let span = spans
            .find(&p)
            .or_else(|| spans.find(&KeyPath::root().key("fact").index(i)));
        Error::Model(Box::new(ModelError {
            file: self.file.clone(),
            text: self.text.clone(),
            span,
            path: p.to_string(),
            message,
            help: Some(help),
        }))
    }
}

/// A fitted parameter: `NAME` (within its adjustable range) or
/// `NAME=LO:HI` (within these bounds).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bounded {
    pub name: String,
    #[serde(skip)]
    pub index: usize,
    pub unit: &'static str,
    pub lo: f64,
    pub hi: f64,
}

impl Bounded {
    pub fn parse(model: &Model, spec: &str) -> Result<Bounded, Error> {
        let bad = |message: String, help: String| Error::Param(ParamError::new(Input::Adjust, message, Some(help)));
        let (name, bounds) = match spec.split_once('=') {
            Some((n, b)) => (n.trim(), Some(b)),
            None => (spec.trim(), None),
        };
        let index = model.param_index(name).ok_or_else(|| {
            let names: Vec<&str> = model
                .params
                .iter()
                .filter(|p| !p.is_derived())
                .map(|p| p.name.as_str())
                .collect();
            let hint = crate::error::did_you_mean(name, names.iter().copied())
                .map_or(String::new(), |s| format!("did you mean `{s}`? "));
            bad(
                format!("the model has no parameter `{name}` to fit"),
                format!("{hint}its parameters are: {}", names.join(", ")),
            )
        })?;
        let p = &model.params[index];
        if p.is_derived() {
            return Err(bad(
                format!("`{name}` is derived from other parameters and cannot be fitted"),
                "fit the parameters its expression uses".into(),
            ));
        }
        let (lo, hi) = match bounds {
            Some(b) => {
                let parts: Vec<&str> = b.split(':').collect();
                let num = |s: &str| s.trim().parse::<f64>().ok().filter(|x| x.is_finite());
                match (
                    parts.len(),
                    parts.first().and_then(|s| num(s)),
                    parts.get(1).and_then(|s| num(s)),
                ) {
                    (2, Some(lo), Some(hi)) if lo < hi => (lo, hi),
                    _ => {
                        return Err(bad(
                            format!("`{spec}` does not give bounds LO:HI with LO < HI"),
                            format!("e.g. {name}=30:45"),
                        ));
                    }
                }
            }
            None => match p.range {
                Some([lo, hi]) if lo < hi => (lo, hi),
                _ => {
                    return Err(bad(
                        format!("`{name}` has no adjustable range to fit it in"),
                        format!("give bounds: {name}=LO:HI (in {})", p.unit_str()),
                    ));
                }
            },
        };
        if let Some([rlo, rhi]) = p.range
            && (lo < rlo || hi > rhi)
        {
            return Err(bad(
                format!(
                    "the bounds {lo}…{hi} {} of `{name}` leave its adjustable range {rlo}…{rhi}",
                    p.unit_str()
                ),
                format!("fit within {rlo}…{rhi}"),
            ));
        }
        Ok(Bounded {
            name: name.to_string(),
            index,
            unit: p.unit_str(),
            lo,
            hi,
        })
    }
}

/// How to fit.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// `NAME` or `NAME=LO:HI`; empty: the facts file's `adjust`.
    pub adjust: Vec<String>,
    /// φ step of the cycles, degrees; `None`: the facts file's, else 1.
    pub step_deg: Option<f64>,
    /// Levenberg–Marquardt iterations at most.
    pub max_iterations: usize,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            adjust: Vec::new(),
            step_deg: None,
            max_iterations: 100,
        }
    }
}

/// A parameter after a fit (to stated figures, or to measured curves in
/// [`super::fit_measured`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FittedParam {
    pub name: String,
    /// The part in plain words (the name when the model gives none).
    pub label: String,
    pub unit: &'static str,
    pub lo: f64,
    pub hi: f64,
    pub start: f64,
    pub fitted: f64,
    /// Linearised standard error √((JᵀJ)⁻¹)_jj, with J the weighted
    /// residuals' Jacobian; `None` when the data do not determine it.
    pub std_error: Option<f64>,
    /// The confidence interval fitted ± q·std_error, where the fit states
    /// a confidence (a fit to measured curves).
    pub interval: Option<[f64; 2]>,
    /// The fit stopped at a bound (an interval then assumes what the bound
    /// forbids).
    pub at_bound: bool,
}

/// A fact after the fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FactResult {
    pub figure: String,
    pub unit: &'static str,
    /// Its setting in words (`alpha = 35 deg`, or `alpha = 35 deg minus alpha = 0 deg`).
    pub setting: String,
    pub target: f64,
    pub tolerance: Option<f64>,
    pub weight: f64,
    pub start: f64,
    pub fitted: f64,
    /// fitted − target, in the figure's unit.
    pub residual: f64,
    /// weight × residual (residual / tolerance).
    pub weighted: f64,
    pub source: Option<String>,
}

/// The outcome of a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitResult {
    pub params: Vec<FittedParam>,
    pub facts: Vec<FactResult>,
    /// Σ (weight × residual)² at the start and at the end.
    pub cost_start: f64,
    pub cost: f64,
    pub iterations: usize,
    /// Cycles evaluated (plain and dual).
    pub cycles: usize,
    pub converged: bool,
    /// Why the iteration stopped.
    pub stop: String,
    pub warnings: Vec<String>,
}

/// The distinct settings the facts need, and for each fact its (setting,
/// relative-to setting) indices.
type Settings = (Vec<Vec<(usize, f64)>>, Vec<(usize, Option<usize>)>);

fn settings(model: &Model, facts: &Facts, adjusted: &[Bounded]) -> Result<Settings, Error> {
    let mut list: Vec<Vec<(usize, f64)>> = Vec::new();
    let mut index = |s: Vec<(usize, f64)>| match list.iter().position(|t| *t == s) {
        Some(k) => k,
        None => {
            list.push(s);
            list.len() - 1
        }
    };
    let mut of_fact = Vec::new();
    for (i, f) in facts.facts.iter().enumerate() {
        let resolve = |pairs: &[(String, f64)], key: &str| -> Result<Vec<(usize, f64)>, Error> {
            let mut out = Vec::new();
            for (name, v) in pairs {
                if adjusted.iter().any(|a| a.name == *name) {
                    return Err(facts.error_at(
                        i,
                        key,
                        format!("this fact sets `{name}`, which is being fitted"),
                        format!("fit other parameters, or drop `{name}` from this fact's {key}"),
                    ));
                }
                let mut p = model.defaults();
                model
                    .set(&mut p, name, *v)
                    .map_err(|e| facts.error_at(i, key, e.message.clone(), e.help.clone().unwrap_or_default()))?;
                out.push((model.param_index(name).unwrap_or(0), *v));
            }
            Ok(out)
        };
        let s = resolve(&f.set, "set")?;
        let r = match &f.relative_to {
            Some(r) => Some(resolve(r, "relative_to")?),
            None => None,
        };
        let a = index(s);
        let b = r.map(&mut index);
        of_fact.push((a, b));
    }
    Ok((list, of_fact))
}

/// Figures by name.
type Named = Vec<(String, f64)>;
/// A figure at one setting: name, value, d/dx_j for each adjusted x_j.
type Row = (String, f64, Vec<f64>);

/// What one evaluation gives: the facts' values and, when asked, their
/// derivatives with respect to each adjusted parameter.
struct Eval {
    values: Vec<f64>,
    jacobian: Option<Vec<Vec<f64>>>,
}

struct Problem<'a> {
    model: &'a Model,
    base: &'a Params,
    facts: &'a Facts,
    adjusted: &'a [Bounded],
    settings: Vec<Vec<(usize, f64)>>,
    of_fact: Vec<(usize, Option<usize>)>,
    step_deg: f64,
    cycles: std::sync::atomic::AtomicUsize,
}

impl Problem<'_> {
    fn params_at(&self, x: &[f64], setting: usize) -> Params {
        let mut p = self.base.clone();
        for (a, &v) in self.adjusted.iter().zip(x) {
            p.values[a.index] = v;
        }
        for &(i, v) in &self.settings[setting] {
            p.values[i] = v;
        }
        p
    }

    fn plain(&self, p: &Params) -> Result<Vec<(String, f64)>, Error> {
        self.cycles.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let opts = CycleOptions::for_figures(self.step_deg);
        Ok(figures(&run_cycle_with(self.model, p, &opts, None)?))
    }

    /// The figures each setting needs.
    fn needed(&self, setting: usize) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for (f, &(a, b)) in self.facts.facts.iter().zip(&self.of_fact) {
            if (a == setting || b == Some(setting)) && !out.contains(&f.figure.as_str()) {
                out.push(&f.figure);
            }
        }
        out
    }

    fn evaluate(&self, x: &[f64], jacobian: bool) -> Result<Eval, Error> {
        let ns = self.settings.len();
        let nx = self.adjusted.len();
        // Per setting: each needed figure's value and d/dx_j.
        let per: Vec<Result<Vec<Row>, Error>> = (0..ns)
            .into_par_iter()
            .map(|s| {
                let p = self.params_at(x, s);
                let plain = self.plain(&p)?;
                let needed = self.needed(s);
                let value = |list: &[(String, f64)], f: &str| list.iter().find(|(n, _)| n == f).map(|(_, v)| *v);
                let mut rows: Vec<Row> = Vec::new();
                for f in &needed {
                    let v = value(&plain, f).filter(|v| v.is_finite()).ok_or_else(|| {
                        Error::Param(ParamError::general(
                            format!("figure `{f}` is not available at this setting"),
                            None,
                        ))
                    })?;
                    rows.push((f.to_string(), v, vec![0.0; nx]));
                }
                if jacobian {
                    let cols: Vec<Result<Vec<f64>, Error>> = (0..nx)
                        .into_par_iter()
                        .map(|j| {
                            let a = &self.adjusted[j];
                            self.cycles.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                            let exact = figure_derivatives(self.model, &p, a.index, self.step_deg)?;
                            let mut col = Vec::with_capacity(needed.len());
                            let mut fd: Option<(Named, Named, f64)> = None;
                            for f in &needed {
                                match exact.iter().find(|(n, ..)| n == f) {
                                    Some(e) => col.push(e.2),
                                    None => {
                                        // A match figure: central difference.
                                        if fd.is_none() {
                                            let h = FD_REL_STEP * (a.hi - a.lo);
                                            let (mut up, mut dn) = (p.clone(), p.clone());
                                            up.values[a.index] += h;
                                            dn.values[a.index] -= h;
                                            fd = Some((self.plain(&up)?, self.plain(&dn)?, h));
                                        }
                                        let (up, dn, h) = fd.as_ref().expect("computed above");
                                        match (value(up, f), value(dn, f)) {
                                            (Some(u), Some(d)) => col.push((u - d) / (2.0 * h)),
                                            _ => {
                                                return Err(Error::Param(ParamError::general(
                                                    format!("figure `{f}` has no derivative here"),
                                                    None,
                                                )));
                                            }
                                        }
                                    }
                                }
                            }
                            Ok(col)
                        })
                        .collect();
                    for (j, c) in cols.into_iter().enumerate() {
                        for (row, d) in rows.iter_mut().zip(c?) {
                            row.2[j] = d;
                        }
                    }
                }
                Ok(rows)
            })
            .collect();
        let per = per.into_iter().collect::<Result<Vec<_>, _>>()?;
        let get = |s: usize, f: &str| {
            per[s]
                .iter()
                .find(|r| r.0 == f)
                .expect("every needed figure is evaluated")
        };
        let mut values = Vec::new();
        let mut jac = Vec::new();
        for (f, &(a, b)) in self.facts.facts.iter().zip(&self.of_fact) {
            let ra = get(a, &f.figure);
            let (mut v, mut d) = (ra.1, ra.2.clone());
            if let Some(b) = b {
                let rb = get(b, &f.figure);
                v -= rb.1;
                d.iter_mut().zip(&rb.2).for_each(|(x, y)| *x -= y);
            }
            values.push(v);
            jac.push(d);
        }
        Ok(Eval {
            values,
            jacobian: jacobian.then_some(jac),
        })
    }

    /// Weighted residuals w_i (v_i − F_i).
    fn residuals(&self, values: &[f64]) -> Vec<f64> {
        self.facts
            .facts
            .iter()
            .zip(values)
            .map(|(f, v)| f.weight * (v - f.value))
            .collect()
    }
}

/// Fits `opts.adjust` of `model` (starting from `base`) to `facts`.
pub fn fit(model: &Model, base: &Params, facts: &Facts, opts: &FitOptions) -> Result<FitResult, Error> {
    let step_deg = opts.step_deg.or(facts.step_deg).unwrap_or(1.0);
    check_options(&CycleOptions {
        step_deg,
        ..Default::default()
    })?;
    let adjusted = adjusted_params(model, facts, opts)?;
    let start: Vec<f64> = adjusted.iter().map(|a| base.values[a.index]).collect();
    check_start(&adjusted, &start)?;
    let (settings, of_fact) = settings(model, facts, &adjusted)?;
    let problem = Problem {
        model,
        base,
        facts,
        adjusted: &adjusted,
        settings,
        of_fact,
        step_deg,
        cycles: Default::default(),
    };
    check_figures(&problem, &start)?;
    let start_values = problem.evaluate(&start, false)?.values;
    let bounds: Vec<(f64, f64)> = adjusted.iter().map(|a| (a.lo, a.hi)).collect();
    // Weighted residuals r_i = w_i (v_i − F_i) and their Jacobian w_i ∂v_i/∂x_j.
    let weigh = |jac: &[Vec<f64>]| -> Vec<Vec<f64>> {
        jac.iter()
            .zip(&facts.facts)
            .map(|(row, f)| row.iter().map(|d| f.weight * d).collect())
            .collect()
    };
    let lm = levenberg_marquardt(&bounds, &start, opts.max_iterations, |x, jacobian| {
        let e = problem.evaluate(x, jacobian)?;
        Ok((problem.residuals(&e.values), e.jacobian.as_deref().map(weigh)))
    })?;
    // Standard errors at the optimum: √((JᵀJ)⁻¹)_jj of the weighted Jacobian.
    let n = lm.x.len();
    let end = problem.evaluate(&lm.x, true)?;
    let a = normal_matrix(&weigh(end.jacobian.as_deref().expect("asked for")));
    let std_error: Vec<Option<f64>> = match invert_scaled(&a).0 {
        Some(inv) => (0..n).map(|j| Some(inv[j][j].max(0.0).sqrt())).collect(),
        None => vec![None; n],
    };
    let warnings = fit_warnings(model, facts, &adjusted, &std_error);
    let params = adjusted
        .iter()
        .zip(&lm.x)
        .zip(&start)
        .zip(&std_error)
        .map(|(((b, &xf), &x0), s)| FittedParam {
            name: b.name.clone(),
            label: model.params[b.index].label_or_name().to_string(),
            unit: b.unit,
            lo: b.lo,
            hi: b.hi,
            start: x0,
            fitted: xf,
            std_error: *s,
            interval: None,
            at_bound: xf <= b.lo || xf >= b.hi,
        })
        .collect();
    Ok(FitResult {
        params,
        facts: fact_results(model, facts, &start_values, &end.values),
        cost_start: lm.cost_start,
        cost: lm.cost,
        iterations: lm.iterations,
        cycles: problem.cycles.into_inner(),
        converged: lm.converged,
        stop: lm.stop,
        warnings,
    })
}

/// The parameters to fit: `opts.adjust`, else the facts file's `adjust`,
/// each once.
fn adjusted_params(model: &Model, facts: &Facts, opts: &FitOptions) -> Result<Vec<Bounded>, Error> {
    let specs = if opts.adjust.is_empty() {
        &facts.adjust
    } else {
        &opts.adjust
    };
    if specs.is_empty() {
        let rec: Vec<&str> = model
            .params
            .iter()
            .filter(|p| p.provenance == Some(crate::model::Provenance::Reconstructed) && !p.is_derived())
            .map(|p| p.name.as_str())
            .collect();
        return Err(Error::Param(ParamError::new(
            Input::Adjust,
            "nothing to fit",
            Some(format!(
                "name the parameters to fit: NAME (within its range) or NAME=LO:HI, here or as `adjust = [...]` in the \
                 facts file{}",
                if rec.is_empty() {
                    String::new()
                } else {
                    format!(" (reconstructed in this model: {})", rec.join(", "))
                }
            )),
        )));
    }
    let adjusted = specs
        .iter()
        .map(|s| Bounded::parse(model, s))
        .collect::<Result<Vec<_>, _>>()?;
    for (k, a) in adjusted.iter().enumerate() {
        if adjusted[..k].iter().any(|b| b.name == a.name) {
            return Err(Error::Param(ParamError::new(
                Input::Adjust,
                format!("`{}` is fitted twice", a.name),
                Some("name each parameter once".into()),
            )));
        }
    }
    Ok(adjusted)
}

/// The start inside every parameter's bounds.
fn check_start(adjusted: &[Bounded], start: &[f64]) -> Result<(), Error> {
    for (a, &x) in adjusted.iter().zip(start) {
        if x < a.lo || x > a.hi {
            return Err(Error::Param(ParamError::new(
                Input::Adjust,
                format!(
                    "the start {} = {x} {} lies outside its bounds {}…{} {}",
                    a.name, a.unit, a.lo, a.hi, a.unit
                ),
                Some(format!(
                    "start inside them (set {} to a value within) or widen them ({}=LO:HI)",
                    a.name, a.name
                )),
            )));
        }
    }
    Ok(())
}

/// Every figure must exist (checked at the start setting, naming the fact).
fn check_figures(problem: &Problem, start: &[f64]) -> Result<(), Error> {
    let facts = problem.facts;
    let start_figures = problem.plain(&problem.params_at(start, 0))?;
    for (i, f) in facts.facts.iter().enumerate() {
        if !start_figures.iter().any(|(n, _)| *n == f.figure) {
            let hint = crate::error::did_you_mean(&f.figure, start_figures.iter().map(|(n, _)| n.as_str()));
            let names: Vec<&str> = start_figures.iter().map(|(n, _)| n.as_str()).collect();
            return Err(facts.error_at(
                i,
                "figure",
                format!(
                    "the model has no figure `{}`{}",
                    f.figure,
                    hint.map(|h| format!(" (did you mean `{h}`?)")).unwrap_or_default()
                ),
                format!("figures of this model: {}", names.join(", ")),
            ));
        }
    }
    Ok(())
}

/// What the fit cannot tell or was not asked: parameters the facts leave
/// undetermined, facts stated for another model, fewer facts than
/// parameters.
fn fit_warnings(model: &Model, facts: &Facts, adjusted: &[Bounded], std_error: &[Option<f64>]) -> Vec<String> {
    let mut warnings = Vec::new();
    for (b, s) in adjusted.iter().zip(std_error) {
        if s.is_none() {
            warnings.push(format!(
                "the facts do not determine `{}` (JᵀJ is singular): its fitted value is one of many",
                b.name
            ));
        }
    }
    if let Some(name) = &facts.model
        && *name != model.name()
    {
        warnings.push(format!(
            "the facts are stated for model `{name}`, the fit ran on `{}`",
            model.name()
        ));
    }
    let (m, n) = (facts.facts.len(), adjusted.len());
    if m < n {
        warnings.push(format!("{m} facts for {n} parameters: the fit is underdetermined"));
    }
    warnings
}

/// Each fact at the start and fitted, with its setting in words.
fn fact_results(model: &Model, facts: &Facts, start_values: &[f64], values: &[f64]) -> Vec<FactResult> {
    let words = |s: &[(String, f64)]| {
        if s.is_empty() {
            "nominal".to_string()
        } else {
            s.iter()
                .map(|(k, v)| {
                    format!(
                        "{k} = {} {}",
                        crate::format::fmt_num(*v),
                        model.param_index(k).map_or("", |i| model.params[i].unit_str())
                    )
                })
                .collect::<Vec<_>>()
                .join(", ")
        }
    };
    facts
        .facts
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let setting = match &f.relative_to {
                Some(rel) => format!("{} minus {}", words(&f.set), words(rel)),
                None => words(&f.set),
            };
            FactResult {
                figure: f.figure.clone(),
                unit: figure_unit(&f.figure),
                setting,
                target: f.value,
                tolerance: f.tolerance,
                weight: f.weight,
                start: start_values[i],
                fitted: values[i],
                residual: values[i] - f.value,
                weighted: f.weight * (values[i] - f.value),
                source: f.source.clone(),
            }
        })
        .collect()
}
