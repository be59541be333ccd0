//! Sensitivity of the figures of merit to each adjustable parameter.
//!
//! Two numbers per (figure F, parameter p):
//!
//! - **The local derivative dF/dp** at the nominal setting. Exact where F is
//!   a smooth function of the cycle: an extreme of a take-up P(φ), of a
//!   measure, of a point's coordinate or of a transmission angle. The model
//!   is resolved with p as the first-order dual number p + ε (num-dual
//!   `Dual64`, see [`Model::mechanism_with`]), the whole cycle is solved in
//!   dual arithmetic with φ a plain constant, and dF/dp is the ε part at the
//!   φ where the extreme lies. (The extreme's φ moves with p, but at an
//!   interior extreme dF/dφ = 0, so that motion changes F only to second
//!   order; on the φ grid the extreme simply stays on its grid point.) The
//!   match figures (score, RMS(D), max |D|, max P') involve P', a max and an
//!   RMS: they take a central difference. Every exact derivative is also
//!   checked against the central difference; where the two disagree (a
//!   kink: an extreme switching between two equal candidates, a guide
//!   engaging right there; or a value resolved as a plain number, which
//!   carries no derivative: cam profiles, the elongation allowance ΔP, a
//!   numerical group's starting guess) the central difference is reported
//!   and so marked.
//! - **The whole-range figures**, the parameter going over its adjustable
//!   range with the others nominal, as seed 000 Fig. 7 reports ΔP: F at the
//!   two ends, their difference F(hi) − F(lo), and the span max − min of F
//!   over the range (sampled at [`RANGE_SAMPLES`] settings), which also
//!   catches an even effect (max P of the MF-7923D rises 3.2 mm toward both
//!   ends of z = −10…10 mm, so F(hi) − F(lo) = 0 and dF/dz = 0 at z = 0).
//!
//! The normalised effect dF/dp × (hi − lo) puts parameters with different
//! units and ranges on one scale (the output's unit): the change a
//! technician can make with that setting, to first order.

use num_dual::Dual64;
use rayon::prelude::*;
use serde::Serialize;

use super::design::{Design, Sweep, Vary};
use super::figures::{figures, select_figures, shared_stitch};
use crate::error::ThreadError;
use crate::error::{Error, ParamError};
use crate::eval::stitch_process::Prepared;
use crate::eval::{
    CycleOptions, check_options, cycle_phis_deg, path_error, run_cycle_with, take_up_name, tracks_at_phi0,
};
use crate::mechanism::{Phi, Pose};
use crate::model::{Machine, Model, Params};

/// Central differences step, as a fraction of the parameter's range width.
pub const FD_REL_STEP: f64 = 1e-5;

/// Figures shown by default (those the model has): the match score per
/// stitch thread, max P per path, the transmission-angle extremes, the
/// measures' ranges and the point strokes.
pub const DEFAULT_FIGURES: &[&str] = &[
    "*.max_P_B_mm",
    "*.max_P_mm",
    "*.score",
    "mu.min_deg",
    "mu.max_deg",
    "*.range_mm",
    "*_stroke_mm",
];

/// How the parameters of one figure are ranked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RankBy {
    /// |dF/dp| × range width for smooth figures (exact derivatives), the
    /// span over the range for the others (match figures).
    Local,
    /// The span max − min of F over the range, for every figure.
    Range,
}

/// What to compute.
#[derive(Debug, Clone, PartialEq)]
pub struct SensitivityOptions {
    /// Parameters; empty: every parameter with an adjustable range.
    pub params: Vec<String>,
    /// Figure patterns (`*` matches any run); empty: [`DEFAULT_FIGURES`].
    pub figures: Vec<String>,
    /// φ step of the cycles, degrees.
    pub step_deg: f64,
    pub rank: RankBy,
}

/// How a derivative was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Dual numbers, confirmed by the central difference.
    Exact,
    /// Central difference (the figure is not smooth, or the exact value
    /// disagreed with it: a kink at the nominal setting).
    Central,
}

/// One parameter's effect on one figure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Effect {
    pub param: String,
    pub param_unit: &'static str,
    /// The adjustable range.
    pub lo: f64,
    pub hi: f64,
    /// 1 = the largest effect on this figure.
    pub rank: usize,
    /// dF/dp at the nominal setting, figure unit per parameter unit.
    pub derivative: Option<f64>,
    pub method: Method,
    /// The central difference, as a check of an exact derivative.
    pub central: Option<f64>,
    /// dF/dp × (hi − lo), figure unit.
    pub effect: Option<f64>,
    /// F with the parameter at its range ends, the others nominal.
    pub at_lo: Option<f64>,
    pub at_hi: Option<f64>,
    /// F(hi) − F(lo), figure unit: the change over the whole range.
    pub whole_range: Option<f64>,
    /// max − min of F over the range ([`RANGE_SAMPLES`] settings and the
    /// nominal one), figure unit: catches a figure that rises toward both
    /// ends, which F(hi) − F(lo) misses.
    pub span: Option<f64>,
    /// Why something is missing or was not exact.
    pub note: Option<String>,
}

/// Every parameter's effect on one figure, ranked.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FigureSensitivity {
    pub figure: String,
    /// `mm`, `deg`, `pts` (a match score) or `1`.
    pub unit: &'static str,
    pub nominal: f64,
    /// The figure has exact derivatives (dual numbers).
    pub exact: bool,
    /// What the rank is by: `effect` or `span`.
    pub ranked_by: &'static str,
    pub effects: Vec<Effect>,
}

/// A parameter studied: its nominal value (at the setting studied) and its
/// adjustable range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StudiedParam {
    pub name: String,
    pub unit: &'static str,
    pub nominal: f64,
    pub lo: f64,
    pub hi: f64,
}

/// The outcome.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SensitivityResult {
    pub model: String,
    pub step_deg: f64,
    /// The parameters studied.
    pub params: Vec<StudiedParam>,
    pub figures: Vec<FigureSensitivity>,
    /// Figures no parameter changes (a fixed point's stroke, a link length).
    pub insensitive: Vec<String>,
    /// Cycles evaluated.
    pub cycles: usize,
}

/// The unit of a figure, from its name: `mm`, `deg`, `pts` (a match score,
/// 0…100 points) or `1`.
pub fn figure_unit(name: &str) -> &'static str {
    if name.ends_with("_mm") {
        "mm"
    } else if name.ends_with("_deg") {
        "deg"
    } else if name.ends_with(".score") || name.starts_with("score.") {
        "pts"
    } else {
        "1"
    }
}

/// Every parameter with an adjustable range (lo < hi), in file order.
pub fn adjustable(model: &Model) -> Vec<String> {
    model
        .params
        .iter()
        .filter(|p| !p.is_derived() && p.range.is_some_and(|[lo, hi]| lo < hi))
        .map(|p| p.name.clone())
        .collect()
}

/// Indices (first occurrence) of the smallest and largest value part, as
/// the plain cycle picks them.
fn extremes(v: &[Dual64]) -> (usize, usize) {
    let (mut lo, mut hi) = (0, 0);
    for (k, x) in v.iter().enumerate() {
        if x.re < v[lo].re {
            lo = k;
        }
        if x.re > v[hi].re {
            hi = k;
        }
    }
    (lo, hi)
}

/// The cycle solved with parameter `param` seeded as p + ε: the mechanism,
/// its pose at every φ (value and d/dp), and the φ grid in degrees.
#[allow(clippy::type_complexity)]
fn seeded_cycle(
    model: &Model,
    base: &Params,
    param: usize,
    step_deg: f64,
) -> Result<(Machine<Dual64>, Pose<Dual64>, Vec<f64>), Error> {
    check_options(&CycleOptions {
        step_deg,
        ..Default::default()
    })?;
    if model.params.get(param).is_none_or(|p| p.is_derived()) {
        return Err(Error::Param(ParamError::general(
            format!("parameter #{param} cannot be seeded"),
            Some("seed a settable parameter".into()),
        )));
    }
    // ε = 1 on p; every other value is a constant.
    let seeded: Vec<Dual64> = base
        .values
        .iter()
        .enumerate()
        .map(|(i, &v)| Dual64::new(v, if i == param { 1.0 } else { 0.0 }))
        .collect();
    let machine = model.machine_with::<Dual64>(&seeded)?;
    let mech = &machine.mechanism;
    let phis = cycle_phis_deg(model.phi_start_deg(), step_deg);
    // φ is a plain constant here: the ε part is d/dp, not d/dφ.
    let table: Vec<Phi<Dual64>> = phis.iter().map(|p| Phi::new(Dual64::from_re(p.to_radians()))).collect();
    let mut pose = mech.new_pose(phis.len());
    mech.solve(&table, &mut pose)?;
    Ok((machine, pose, phis))
}

/// The smooth figures of a cycle with their exact derivatives with respect
/// to parameter `param` (index into `model.params`): `(name, value,
/// dvalue/dparam)`, named as [`figures`] names them, in the parameter's and
/// the figure's units (a transmission angle in deg per mm or per deg).
/// Take-up extremes, transmission-angle extremes, measure extremes and
/// ranges, point strokes; not the match figures.
pub fn figure_derivatives(
    model: &Model,
    base: &Params,
    param: usize,
    step_deg: f64,
) -> Result<Vec<(String, f64, f64)>, Error> {
    let (
        Machine {
            mechanism: mech,
            threads,
        },
        pose,
        phis,
    ) = seeded_cycle(model, base, param, step_deg)?;
    let n = phis.len();
    let mut out = Vec::new();
    // A derivative that is not finite (a square root at 0: a transmission
    // angle of exactly 90° at a slider's dead centre) is left out; the
    // figure then takes a central difference.
    let push = |out: &mut Vec<(String, f64, f64)>, name: String, x: Dual64| {
        if x.eps.is_finite() {
            out.push((name, x.re, x.eps));
        }
    };
    // Take-up extremes: P = ξ(φ0) − ξ(φ) (or the feed convention).
    if let Some(th) = &threads {
        let at0 = tracks_at_phi0(&mech, th)?;
        let tracks = th.evaluate(&pose, None).map_err(|e| {
            let phi = phis[e.k];
            path_error(e, phi)
        })?;
        for ((path, track), at0) in th.paths.iter().zip(tracks).zip(at0) {
            let p: Vec<Dual64> = (0..track.xi.len())
                .map(|k| th.convention.take_up(track.xi_at_split(k), at0.xi_at_split(0)))
                .collect();
            let (lo, hi) = extremes(&p);
            let pn = take_up_name(!track.eye_up.is_empty());
            push(&mut out, format!("{}.max_{pn}_mm", path.name), p[hi]);
            push(&mut out, format!("{}.min_{pn}_mm", path.name), p[lo]);
        }
    }
    // Transmission angles (rad → deg, value and derivative alike).
    let deg = |x: Dual64| Dual64::new(x.re.to_degrees(), x.eps.to_degrees());
    let mut buf = Vec::new();
    let nd = model.dyads.len();
    if nd > 0 {
        let mut mu: Vec<Vec<Dual64>> = vec![Vec::with_capacity(n); nd];
        for k in 0..n {
            mech.transmission_angles(&pose, k, &mut buf);
            for (j, m) in buf.iter().enumerate().take(nd) {
                mu[j].push(deg(*m));
            }
        }
        let ext: Vec<(Dual64, Dual64)> = mu
            .iter()
            .map(|v| {
                let (lo, hi) = extremes(v);
                (v[lo], v[hi])
            })
            .collect();
        // The overall extremes: the dyad whose extreme it is.
        let mut jmin = 0;
        let mut jmax = 0;
        for (j, e) in ext.iter().enumerate() {
            if e.0.re < ext[jmin].0.re {
                jmin = j;
            }
            if e.1.re > ext[jmax].1.re {
                jmax = j;
            }
        }
        push(&mut out, "mu.min_deg".into(), ext[jmin].0);
        push(&mut out, "mu.max_deg".into(), ext[jmax].1);
        for (d, e) in model.dyads.iter().zip(&ext) {
            push(&mut out, format!("mu_{}.min_deg", d.key), e.0);
            push(&mut out, format!("mu_{}.max_deg", d.key), e.1);
        }
    }
    // Measures: extremes and range.
    let nm = model.measure_names.len();
    if nm > 0 {
        let mut ms: Vec<Vec<Dual64>> = vec![Vec::with_capacity(n); nm];
        for k in 0..n {
            mech.measures(&pose, k, &mut buf);
            for (j, m) in buf.iter().enumerate().take(nm) {
                ms[j].push(*m);
            }
        }
        for (name, v) in model.measure_names.iter().zip(&ms) {
            let (lo, hi) = extremes(v);
            push(&mut out, format!("{name}.range_mm"), v[hi] - v[lo]);
            push(&mut out, format!("{name}.min_mm"), v[lo]);
            push(&mut out, format!("{name}.max_mm"), v[hi]);
        }
    }
    // Point strokes along each axis, for the model's output points.
    let axes: &[(usize, &str)] = if model.planar {
        &[(0, "x"), (1, "y")]
    } else {
        &[(0, "x"), (1, "y"), (2, "z")]
    };
    for &slot in &model.output_points {
        for &(a, name) in axes {
            let v: Vec<Dual64> = pose.track(slot).iter().map(|q| q[a]).collect();
            let (lo, hi) = extremes(&v);
            push(
                &mut out,
                format!("{}.{name}_stroke_mm", model.point_names[slot]),
                v[hi] - v[lo],
            );
        }
    }
    Ok(out)
}

/// The figures of a plain (f64, lean) cycle with parameter values `values`,
/// written directly (a central difference may step just past a range end).
/// With `shared`, P' of the stitch process is taken from it (see
/// [`super::figures::shared_stitch`]).
fn plain_figures(
    model: &Model,
    values: &[f64],
    step_deg: f64,
    shared: Option<&Prepared>,
) -> Result<Vec<(String, f64)>, Error> {
    let opts = CycleOptions::for_figures(step_deg);
    let t = run_cycle_with(
        model,
        &Params {
            values: values.to_vec(),
        },
        &opts,
        shared,
    )?;
    Ok(figures(&t))
}

fn lookup<T: Copy>(list: &[(String, T)], name: &str) -> Option<T> {
    list.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
}

/// Whether an exact derivative and its central-difference check agree:
/// to 1e-3 relative, or absolutely to what rounding allows for a figure of
/// size `scale` with a step `h`.
pub fn agrees(exact: f64, central: f64, scale: f64, h: f64) -> bool {
    (exact - central).abs() <= 1e-3 * exact.abs().max(central.abs()) + 1e-10 * (1.0 + scale.abs()) / h
}

/// Settings of each parameter, evenly over its range (ends included), for
/// the whole-range figures.
pub const RANGE_SAMPLES: usize = 9;

type Figures = Result<Vec<(String, f64)>, Error>;

/// The first line of an error, for a note.
fn why(r: &Figures) -> Option<String> {
    r.as_ref()
        .err()
        .map(|e| e.to_string().lines().next().unwrap_or("").to_string())
}

/// The sensitivity of `opts.figures` to `opts.params` at the setting `base`.
pub fn sensitivity(model: &Model, base: &Params, opts: &SensitivityOptions) -> Result<SensitivityResult, Error> {
    check_options(&CycleOptions {
        step_deg: opts.step_deg,
        ..Default::default()
    })?;
    let params = studied_params(model, opts)?;
    let nominal = plain_figures(model, &base.values, opts.step_deg, None)?;
    let patterns: Vec<String> = if opts.figures.is_empty() {
        DEFAULT_FIGURES
            .iter()
            .filter(|p| nominal.iter().any(|(n, _)| crate::eval::glob_match(p, n)))
            .map(|p| p.to_string())
            .collect()
    } else {
        opts.figures.clone()
    };
    let selected = select_figures(&nominal, &patterns)?;
    // Every plain cycle, in parallel: per parameter p0 ± h (the central
    // difference) and RANGE_SAMPLES settings over its range.
    let h: Vec<f64> = params.iter().map(|&(_, lo, hi)| FD_REL_STEP * (hi - lo)).collect();
    let mut jobs: Vec<(usize, f64)> = Vec::new();
    for (j, &(i, lo, hi)) in params.iter().enumerate() {
        let x0 = base.values[i];
        jobs.push((j, x0 + h[j]));
        jobs.push((j, x0 - h[j]));
        jobs.extend((0..RANGE_SAMPLES).map(|k| (j, lo + (hi - lo) * k as f64 / (RANGE_SAMPLES - 1) as f64)));
    }
    let shared = stitch_per_param(model, base, &params, &selected, opts.step_deg)?;
    let plain: Vec<Figures> = jobs
        .par_iter()
        .map(|&(j, x)| {
            let mut v = base.values.clone();
            v[params[j].0] = x;
            plain_figures(model, &v, opts.step_deg, shared[j].as_ref())
        })
        .collect();
    let exact: Vec<Vec<(String, f64, f64)>> = params
        .par_iter()
        .map(|&(i, ..)| figure_derivatives(model, base, i, opts.step_deg))
        .collect::<Result<_, _>>()?;
    let runs = Runs {
        model,
        base,
        params: &params,
        h,
        plain,
        exact,
    };
    let mut out = Vec::new();
    let mut insensitive = Vec::new();
    for fig in &selected {
        match runs.figure(fig, lookup(&nominal, fig).unwrap_or(f64::NAN), opts.rank) {
            Some(f) => out.push(f),
            None => insensitive.push(fig.clone()),
        }
    }
    Ok(SensitivityResult {
        model: model.name().to_string(),
        step_deg: opts.step_deg,
        params: params
            .iter()
            .map(|&(i, lo, hi)| StudiedParam {
                name: model.params[i].name.clone(),
                unit: model.params[i].unit_str(),
                nominal: base.values[i],
                lo,
                hi,
            })
            .collect(),
        figures: out,
        insensitive,
        cycles: 1 + params.len() * (2 + RANGE_SAMPLES + 1),
    })
}

/// The parameters studied (`opts.params`, else every one with an
/// adjustable range), each once: (index, lo, hi).
fn studied_params(model: &Model, opts: &SensitivityOptions) -> Result<Vec<(usize, f64, f64)>, Error> {
    let bad = |message: String, help: String| Error::Param(ParamError::general(message, Some(help)));
    let names = if opts.params.is_empty() {
        adjustable(model)
    } else {
        opts.params.clone()
    };
    if names.is_empty() {
        return Err(bad(
            format!("model `{}` has no parameter with an adjustable range", model.name()),
            "give a parameter `range = [lo, hi]` in [parameters] to study it".into(),
        ));
    }
    let mut params: Vec<(usize, f64, f64)> = Vec::new();
    for name in &names {
        let i = model.param_index(name).ok_or_else(|| {
            bad(
                format!("the model has no parameter `{name}`"),
                format!("parameters with a range: {}", adjustable(model).join(", ")),
            )
        })?;
        let p = &model.params[i];
        let Some([lo, hi]) = p.range.filter(|r| r[0] < r[1] && !p.is_derived()) else {
            return Err(bad(
                format!("`{name}` has no adjustable range, so it has no whole-range effect to report"),
                format!(
                    "study parameters with a range ({}), or give `{name}` `range = [lo, hi]` in [parameters]",
                    adjustable(model).join(", ")
                ),
            ));
        };
        if params.iter().any(|(j, ..)| *j == i) {
            return Err(bad(
                format!("`{name}` is named twice"),
                "name each parameter once".into(),
            ));
        }
        params.push((i, lo, hi));
    }
    Ok(params)
}

/// P' once per parameter that leaves the stitch process alone; once for
/// all when no selected figure involves P' (its figures are then unused).
fn stitch_per_param(
    model: &Model,
    base: &Params,
    params: &[(usize, f64, f64)],
    selected: &[String],
    step_deg: f64,
) -> Result<Vec<Option<Prepared>>, Error> {
    let stitch_figure = |f: &str| {
        f.starts_with("score.")
            || [".score", ".rms_D_mm", ".max_abs_D_mm", ".max_Pprime_mm"]
                .iter()
                .any(|s| f.ends_with(s))
    };
    if !selected.iter().any(|f| stitch_figure(f)) {
        return Ok(vec![
            crate::eval::stitch_process::prepare(model, base, step_deg)?;
            params.len()
        ]);
    }
    params
        .iter()
        .map(|&(i, lo, hi)| {
            let one = Sweep::new(
                vec![Vary {
                    name: model.params[i].name.clone(),
                    lo,
                    hi,
                    n: 2,
                }],
                Design::Grid,
            )?;
            shared_stitch(model, base, &one, step_deg)
        })
        .collect()
}

/// The cycles run for a sensitivity study: per parameter (in `params`'
/// order), p0 + h, p0 − h and the RANGE_SAMPLES settings over its range,
/// and the exact derivatives of every smooth figure.
struct Runs<'a> {
    model: &'a Model,
    base: &'a Params,
    params: &'a [(usize, f64, f64)],
    h: Vec<f64>,
    plain: Vec<Figures>,
    exact: Vec<Vec<(String, f64, f64)>>,
}

impl Runs<'_> {
    /// Figure `fig` (nominal value `f0`) with every parameter's effect,
    /// ranked; `None` when no parameter changes it.
    fn figure(&self, fig: &str, f0: f64, rank: RankBy) -> Option<FigureSensitivity> {
        let exact_figure = self.exact.iter().all(|e| e.iter().any(|(n, ..)| n == fig));
        let mut effects: Vec<Effect> = (0..self.params.len()).map(|j| self.effect(fig, f0, j)).collect();
        if effects.iter().all(|e| e.effect == Some(0.0) && e.span == Some(0.0)) {
            return None;
        }
        // Rank: the larger |key| first; what has no key goes last.
        let by_effect = exact_figure && rank == RankBy::Local;
        // (Ties, as between parameters with no local effect, go by the span.)
        let key = |e: &Effect| if by_effect { e.effect } else { e.span.or(e.effect) }.map_or(-1.0, f64::abs);
        let span = |e: &Effect| e.span.map_or(-1.0, f64::abs);
        effects.sort_by(|a, b| key(b).total_cmp(&key(a)).then(span(b).total_cmp(&span(a))));
        for (k, e) in effects.iter_mut().enumerate() {
            e.rank = k + 1;
        }
        Some(FigureSensitivity {
            figure: fig.to_string(),
            unit: figure_unit(fig),
            nominal: f0,
            exact: exact_figure,
            ranked_by: if by_effect { "effect" } else { "span" },
            effects,
        })
    }

    /// The effect of parameter `j` on figure `fig`: its derivative (exact,
    /// or the central difference where they disagree or only that exists),
    /// the figure at the range's ends and its span over the range.
    fn effect(&self, fig: &str, f0: f64, j: usize) -> Effect {
        let (i, lo, hi) = self.params[j];
        let p = &self.model.params[i];
        let per = 2 + RANGE_SAMPLES;
        let runs = &self.plain[j * per..(j + 1) * per];
        // Below this a change is rounding.
        let tiny = 1e-10 * (1.0 + f0.abs());
        let snap = |x: f64| if x.abs() <= tiny { 0.0 } else { x };
        let value = |r: &Figures| r.as_ref().ok().and_then(|v| lookup(v, fig)).filter(|x| x.is_finite());
        let mut notes = Vec::new();
        let d_exact = self.exact[j].iter().find(|(n, ..)| n == fig).map(|e| e.2);
        let central = value(&runs[0])
            .zip(value(&runs[1]))
            .map(|(a, b)| (a - b) / (2.0 * self.h[j]));
        let (derivative, method) = match (d_exact, central) {
            (Some(e), Some(c)) if !agrees(e, c, f0, self.h[j]) => {
                notes.push(format!(
                    "the exact slope {} disagrees with the central difference {}: a kink here, or a value the dual numbers do not carry \
                     (a cam profile, the elongation allowance); the central difference is used",
                    crate::format::fmt_num(e),
                    crate::format::fmt_num(c)
                ));
                (Some(c), Method::Central)
            }
            (Some(e), _) => (Some(e), Method::Exact),
            (None, c) => (c, Method::Central),
        };
        if derivative.is_none() {
            notes.extend(why(&runs[0]).or(why(&runs[1])).map(|w| format!("no derivative: {w}")));
        }
        let width = hi - lo;
        let derivative = derivative.map(|d| if (d * width).abs() <= tiny { 0.0 } else { d });
        let samples = &runs[2..];
        let (at_lo, at_hi) = (value(&samples[0]), value(&samples[RANGE_SAMPLES - 1]));
        for (k, r) in samples.iter().enumerate() {
            if let Some(w) = why(r) {
                let x = lo + width * k as f64 / (RANGE_SAMPLES - 1) as f64;
                notes.push(format!(
                    "at {} = {} {}: {w}",
                    p.name,
                    crate::format::fmt_num(x),
                    p.unit_str()
                ));
            }
        }
        // The span over the range: the samples and the nominal setting.
        let vals: Vec<f64> = samples
            .iter()
            .filter_map(value)
            .chain(std::iter::once(f0).filter(|_| (lo..=hi).contains(&self.base.values[i])))
            .collect();
        let span = if vals.len() >= 2 {
            Some(snap(
                vals.iter().cloned().fold(f64::MIN, f64::max) - vals.iter().cloned().fold(f64::MAX, f64::min),
            ))
        } else {
            None
        };
        Effect {
            param: p.name.clone(),
            param_unit: p.unit_str(),
            lo,
            hi,
            rank: 0,
            derivative,
            method,
            central,
            effect: derivative.map(|d| d * width),
            at_lo,
            at_hi,
            whole_range: at_lo.zip(at_hi).map(|(a, b)| snap(b - a)),
            span,
            note: if notes.is_empty() { None } else { Some(notes.join("; ")) },
        }
    }
}

/// P(φ) of every thread path and its exact derivative dP(φ)/dp over the
/// cycle: `(path, P mm, dP/dp)` per path, on the cycle's φ grid (returned
/// first, degrees).
#[allow(clippy::type_complexity)]
pub fn take_up_derivatives(
    model: &Model,
    base: &Params,
    param: usize,
    step_deg: f64,
) -> Result<(Vec<f64>, Vec<(String, Vec<f64>, Vec<f64>)>), Error> {
    let (
        Machine {
            mechanism: mech,
            threads,
        },
        pose,
        phis,
    ) = seeded_cycle(model, base, param, step_deg)?;
    let Some(th) = &threads else {
        return Err(Error::Thread(ThreadError {
            path: String::new(),
            phi_deg: None,
            message: format!("model `{}` has no thread paths", model.name()),
            help: Some("describe the thread paths in a [thread] table (docs/model-format.md §13)".into()),
        }));
    };
    let at0 = tracks_at_phi0(&mech, th)?;
    let tracks = th.evaluate(&pose, None).map_err(|e| {
        let phi = phis[e.k];
        path_error(e, phi)
    })?;
    let paths = th
        .paths
        .iter()
        .zip(tracks)
        .zip(at0)
        .map(|((path, track), at0)| {
            let p: Vec<Dual64> = (0..track.xi.len())
                .map(|k| th.convention.take_up(track.xi_at_split(k), at0.xi_at_split(0)))
                .collect();
            (
                path.name.clone(),
                p.iter().map(|x| x.re).collect(),
                p.iter().map(|x| x.eps).collect(),
            )
        })
        .collect();
    Ok((phis, paths))
}
