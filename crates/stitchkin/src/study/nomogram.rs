//! Nomograms: the tuned setting as a function of the technological
//! parameters.
//!
//! A technician reads a nomogram as "for 4 mm material set z = −4.7 mm".
//! [`nomogram`] runs [`super::tune::tune`] at every point of a grid of
//! the material thickness m and, optionally, the stitch length t (both set
//! through [`set_stitch_value`]). For each grid point it keeps the
//! recommended setting, how flat the optimum is, and the match before and
//! after (mean and per-thread scores, the objective J).
//!
//! Every grid point is tuned with the same seed, so a row equals
//! `stitchkin tune --thickness m --stitch t --seed S` at that point, and the
//! whole nomogram is the same on every run. Grid points run in parallel on
//! rayon's global pool. Each `tune` also uses that pool for its samples, and
//! rayon nests the two without starting more threads than cores, so the
//! cores stay busy while one point is in its sequential Nelder–Mead phase.

use rayon::prelude::*;
use serde::Serialize;

use super::design::parse_lo_hi_n;
use super::tune::{TuneOptions, TuneResult, set_stitch_value, tune};
use crate::error::{Error, Input, ParamError, StitchError};
use crate::format::fmt_num;
use crate::model::{Model, Params};

/// The most grid points a nomogram may have (each one is a full tuning).
pub const MAX_POINTS: usize = 10_000;

/// One axis of the grid: N values from LO to HI, both included.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub n: usize,
}

impl Axis {
    /// Parses `LO:HI:N`, `LO:HI` (11 values) or a single value `V`, given
    /// in `input` ([`Input::Thickness`] or [`Input::StitchLength`]).
    pub fn parse(spec: &str, input: Input) -> Result<Axis, Error> {
        const HELP: &str = "write LO:HI:N in mm, e.g. 0.5:5:10 (N values, ends included), or one value";
        let axis = match spec.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Axis { lo: v, hi: v, n: 1 },
            _ if !spec.contains(':') => {
                return Err(Error::Param(ParamError::new(
                    input,
                    format!("`{spec}` is not a number"),
                    Some(HELP.into()),
                )));
            }
            _ => {
                let (lo, hi, n) = parse_lo_hi_n(spec, spec, input, HELP, |lo| {
                    format!("give N ≥ 2 for values from LO to HI, or the one value {lo}")
                })?;
                Axis { lo, hi, n }
            }
        };
        Ok(axis)
    }

    /// The k-th value.
    pub fn value(&self, k: usize) -> f64 {
        if self.n == 1 {
            self.lo
        } else {
            self.lo + (self.hi - self.lo) * k as f64 / (self.n - 1) as f64
        }
    }
}

/// How to build a nomogram.
#[derive(Debug, Clone, PartialEq)]
pub struct NomogramOptions {
    /// Material thickness m, mm.
    pub thickness: Axis,
    /// Stitch length t, mm; `None` keeps the model's (or `--set`) value.
    pub stitch: Option<Axis>,
    /// The tuning at every grid point. An empty `adjust` means the default
    /// adjustables ([`Model::default_adjustables`]) at the nominal setting.
    pub tune: TuneOptions,
}

/// One grid point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NomogramPoint {
    pub m_mm: f64,
    pub t_mm: f64,
    /// The tuning, or `None` when it failed (see `error`).
    pub tuned: Option<TuneResult>,
    /// Why the tuning failed at this point (no assembly, a stitch that
    /// cannot be formed, …).
    pub error: Option<String>,
}

/// A nomogram: grid points in order, the thickness outermost and the stitch
/// length fastest.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Nomogram {
    pub model: String,
    /// The adjusted settings with their units.
    pub adjust: Vec<(String, &'static str)>,
    /// The compared threads, in the model's order.
    pub threads: Vec<String>,
    pub thickness: Axis,
    /// The stitch-length axis (one value when it was not varied).
    pub stitch: Axis,
    pub seed: u64,
    pub step_deg: f64,
    pub points: Vec<NomogramPoint>,
}

/// The parameter that the model's `[stitch] m_mm` (`which` = "m") or `t_mm`
/// ("t") names, if it names one.
fn stitch_param(model: &Model, which: &str) -> Option<String> {
    model.stitch_param(which).map(str::to_string)
}

/// Tunes `model` at every point of the grid. `progress` is called once per
/// finished grid point (from any thread).
///
/// Bad input (an axis outside the parameter's range, a model without a
/// stitch, nothing to adjust, adjusting m or t themselves) is an error
/// before anything runs. A grid point whose tuning fails is kept with its
/// reason; when every point fails, the first point's error is returned.
pub fn nomogram(
    model: &Model,
    base: &Params,
    opts: &NomogramOptions,
    progress: impl Fn() + Sync,
) -> Result<Nomogram, Error> {
    let bad = |message: String, help: String| Error::Param(ParamError::general(message, Some(help)));
    crate::eval::check_options(&crate::eval::CycleOptions {
        step_deg: opts.tune.step_deg,
        ..Default::default()
    })?;
    super::tune::check_samples(opts.tune.samples)?;
    let nominal = model.stitch_setup(base)?.ok_or_else(|| -> Error {
        StitchError::new(
            format!("model `{}`", model.name()),
            "it has no [stitch] table, so there is no match to tune; use a model with one, such as the presets mf7923d \
             and altin504",
        )
        .into()
    })?;
    // Both ends of each axis must be settable (a parameter, inside its range).
    for (which, input, axis) in [
        ("m", Input::Thickness, Some(&opts.thickness)),
        ("t", Input::StitchLength, opts.stitch.as_ref()),
    ] {
        if let Some(a) = axis {
            for v in [a.lo, a.hi] {
                set_stitch_value(model, &mut base.clone(), which, v).map_err(|e| match e {
                    Error::Param(p) => Error::Param(p.in_input(input)),
                    other => other,
                })?;
            }
        }
    }
    let stitch = opts.stitch.unwrap_or(Axis {
        lo: nominal.spec.t_mm,
        hi: nominal.spec.t_mm,
        n: 1,
    });
    let total = opts.thickness.n.saturating_mul(stitch.n);
    if total > MAX_POINTS {
        return Err(bad(
            format!(
                "the nomogram has {total} grid points ({} × {})",
                opts.thickness.n, stitch.n
            ),
            format!("at most {MAX_POINTS}: each point is a full tuning; use fewer values per axis"),
        ));
    }
    let tune_opts = tune_options(model, base, opts)?;
    let grid: Vec<(f64, f64)> = (0..opts.thickness.n)
        .flat_map(|i| (0..stitch.n).map(move |j| (i, j)))
        .map(|(i, j)| (opts.thickness.value(i), stitch.value(j)))
        .collect();
    let vary_t = opts.stitch.is_some();
    let results: Vec<Result<TuneResult, Error>> = grid
        .par_iter()
        .map(|&(m, t)| {
            let r = (|| {
                let mut p = base.clone();
                set_stitch_value(model, &mut p, "m", m)?;
                if vary_t {
                    set_stitch_value(model, &mut p, "t", t)?;
                }
                tune(model, &p, &tune_opts)
            })();
            progress();
            r
        })
        .collect();
    if let Some(Err(e)) = results.first()
        && results.iter().all(Result::is_err)
    {
        return Err(e.clone());
    }
    let first = results.iter().find_map(|r| r.as_ref().ok());
    let adjust = first.map(|r| r.names.clone()).unwrap_or_default();
    let threads = first
        .map(|r| r.after_figures.threads.iter().map(|t| t.0.clone()).collect())
        .unwrap_or_default();
    let points = grid
        .iter()
        .zip(results)
        .map(|(&(m_mm, t_mm), r)| grid_point(m_mm, t_mm, r))
        .collect();
    Ok(Nomogram {
        model: model.name().to_string(),
        adjust,
        threads,
        thickness: opts.thickness,
        stitch,
        seed: opts.tune.seed,
        step_deg: opts.tune.step_deg,
        points,
    })
}

/// The tuning of each grid point: `opts.tune` with the default settings
/// to adjust when it names none; never the thickness or stitch length the
/// nomogram is drawn over.
fn tune_options(model: &Model, base: &Params, opts: &NomogramOptions) -> Result<TuneOptions, Error> {
    let mut tune_opts = opts.tune.clone();
    if tune_opts.adjust.is_empty() {
        tune_opts.adjust = model.default_adjustables(base)?;
    }
    for (which, what) in [("m", "material thickness"), ("t", "stitch length")] {
        if let Some(p) = stitch_param(model, which)
            && tune_opts.adjust.contains(&p)
        {
            return Err(Error::Param(ParamError::new(
                Input::Adjust,
                format!("`{p}` is the {what} the nomogram is drawn over, so it cannot also be adjusted"),
                Some(format!(
                    "leave `{p}` out of the adjusted settings; the nomogram's {what} axis gives its values"
                )),
            )));
        }
    }
    Ok(tune_opts)
}

/// A grid point, tuned or with why it did not tune.
fn grid_point(m_mm: f64, t_mm: f64, r: Result<TuneResult, Error>) -> NomogramPoint {
    match r {
        Ok(r) => NomogramPoint {
            m_mm,
            t_mm,
            tuned: Some(r),
            error: None,
        },
        Err(e) => NomogramPoint {
            m_mm,
            t_mm,
            tuned: None,
            error: Some(e.to_string().replace('\n', " ")),
        },
    }
}

/// The default thickness axis: 5 values over the adjustable range of the
/// parameter the model's `[stitch] m_mm` names.
pub fn default_thickness(model: &Model) -> Result<Axis, Error> {
    let no_range = || {
        Error::Param(ParamError::new(
            Input::Thickness,
            format!(
                "model `{}` gives no thickness range to draw the nomogram over",
                model.name()
            ),
            Some("give one as LO:HI:N in mm, e.g. 1:5:5".into()),
        ))
    };
    if !model.has_stitch() {
        return Err(StitchError::new(
            format!("model `{}`", model.name()),
            "it has no [stitch] table, so there is no match to tune; use a model with one, such as the presets mf7923d \
             and altin504",
        )
        .into());
    }
    let name = model.stitch_param("m").ok_or_else(no_range)?;
    let i = model.param_index(name).ok_or_else(no_range)?;
    let p = &model.params[i];
    match p.range {
        Some([lo, hi]) if hi > lo => Ok(Axis {
            lo: p.to_result_unit(lo),
            hi: p.to_result_unit(hi),
            n: 5,
        }),
        _ => Err(no_range()),
    }
}

/// A thread's score at a point, before (`after` = false) or after tuning.
pub fn thread_score(r: &TuneResult, thread: &str, after: bool) -> Option<f64> {
    let f = if after { &r.after_figures } else { &r.before_figures };
    f.threads.iter().find(|t| t.0 == thread).and_then(|t| t.1)
}

impl Nomogram {
    /// Grid points that tuned.
    pub fn tuned(&self) -> impl Iterator<Item = (&NomogramPoint, &TuneResult)> {
        self.points.iter().filter_map(|p| p.tuned.as_ref().map(|r| (p, r)))
    }

    /// True when every tuned point has every thread's score 0 after tuning:
    /// no setting inside the ranges brings P within P's swing of P'.
    pub fn all_scores_zero(&self) -> bool {
        let mut any = false;
        for (_, r) in self.tuned() {
            any = true;
            if r.after_figures.threads.iter().any(|t| t.1.is_some_and(|s| s > 0.0)) {
                return false;
            }
        }
        any
    }

    /// Where the nomogram stands, gathered over its grid from each tuning's
    /// notes ([`TuneResult::notes`]): which settings sit on an end of their
    /// range and where, where the match does not improve, where a
    /// constraint is not met.
    pub fn notes(&self) -> Vec<String> {
        let r2 = |x: f64| fmt_num((x * 100.0).round() / 100.0);
        let at = |p: &NomogramPoint| {
            if self.stitch.n > 1 {
                format!("m = {} mm, t = {} mm", r2(p.m_mm), r2(p.t_mm))
            } else {
                format!("m = {} mm", r2(p.m_mm))
            }
        };
        let mut out = Vec::new();
        let tuned: Vec<(&NomogramPoint, &TuneResult)> = self.tuned().collect();
        for (name, unit) in &self.adjust {
            for end in ["lower", "upper"] {
                let key = format!("{name} = ");
                let wanted = format!("on the {end} end");
                let here: Vec<String> = tuned
                    .iter()
                    .filter(|(_, r)| r.notes.iter().any(|n| n.starts_with(&key) && n.contains(&wanted)))
                    .map(|(p, _)| at(p))
                    .collect();
                if !here.is_empty() {
                    out.push(format!(
                        "{name} ({unit}) is recommended on the {end} end of its adjustable range at {} of {} grid points ({}): \
                         the best match may lie beyond what the range allows",
                        here.len(),
                        tuned.len(),
                        here.join("; ")
                    ));
                }
            }
        }
        let flat: Vec<String> = tuned
            .iter()
            .filter(|(_, r)| r.notes.iter().any(|n| n.starts_with("the match does not improve")))
            .map(|(p, _)| at(p))
            .collect();
        if !flat.is_empty() {
            out.push(format!(
                "tuning does not raise the mean score at {} ({} of {} grid points)",
                flat.join("; "),
                flat.len(),
                tuned.len()
            ));
        }
        for (p, r) in &tuned {
            if !r.after_figures.failed_checks.is_empty() {
                out.push(format!(
                    "at {} no setting in the ranges passes every physical check ({} fail)",
                    at(p),
                    r.after_figures.failed_checks.join(", ")
                ));
            }
        }
        out
    }
}
