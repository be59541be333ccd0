//! Tuning: the adjustable settings that make the take-up P(φ) match the
//! required P'(φ) of every thread together, or that keep the thread's
//! tension lowest.
//!
//! The objective ([`TuneObjective`]) is the mean over the compared threads
//! of RMS(D)/range(P'), D = P − P' (docs/stitch-formation.md §8; the match
//! score is 100·max(0, 1 − that)), or on the thread's tension the highest
//! peak over the threads as a share of its breaking force; plus a penalty
//! for every physical check that fails, a penalty for every degree a transmission
//! angle leaves 30°…150° and a large one where the mechanism does not
//! assemble. The search runs in the box of the adjustable ranges: a seeded
//! Latin-hypercube sample on all cores (global), then Nelder–Mead (argmin)
//! from the best few samples (local). The same seed gives the same answer.

use std::sync::atomic::{AtomicUsize, Ordering};

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use rayon::prelude::*;
use serde::Serialize;

use super::design::{Design, Sweep, Vary};
use super::figures::shared_stitch;
use crate::error::{Error, Input, ParamError, StitchError};
use crate::eval::stitch_process::Prepared;
use crate::eval::{CycleOptions, CycleTable, MU_MAX_DEG, MU_MIN_DEG, run_cycle_with};
use crate::format::hundredths;
use crate::model::{Model, Params};

/// The most global samples of one tuning: each is a cycle of the model
/// (100 000 take the MF-7923D about 45 s on 2 cores), and every one is kept
/// until the local search picks its starts.
pub const MAX_SAMPLES: usize = 100_000;

/// How to tune.
#[derive(Debug, Clone, PartialEq)]
pub struct TuneOptions {
    /// Parameters to adjust (each needs an adjustable range).
    pub adjust: Vec<String>,
    /// Global samples (Latin hypercube), at most [`MAX_SAMPLES`]; 0: 32 per
    /// parameter, at least 64.
    pub samples: usize,
    pub seed: u64,
    /// φ step of the evaluation, degrees.
    pub step_deg: f64,
    /// What is minimised.
    pub objective: TuneObjective,
}

/// What a tuning minimises, with the transmission-angle band and every
/// physical check as constraints.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TuneObjective {
    /// The mismatch of P and P': the mean of RMS(D)/range(P') over the
    /// compared threads (the match score's complement).
    #[default]
    Match,
    /// The thread's tension: the largest peak over the threads, as a share
    /// of each thread's breaking force (`docs/thread-physics.md`); needs
    /// thread physics.
    PeakTension,
}

impl TuneObjective {
    /// Its name on the command line and in JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            TuneObjective::Match => "match",
            TuneObjective::PeakTension => "peak_tension",
        }
    }
}

/// The match at one setting.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MatchFigures {
    /// Mean match score of the compared threads (0…100).
    pub score_mean: f64,
    /// Per thread: name, score (None for a flat P'), RMS(D) mm, max |D| mm.
    pub threads: Vec<(String, Option<f64>, f64, f64)>,
    /// Transmission angles over the cycle, min and max, deg.
    pub mu_min_deg: Option<f64>,
    pub mu_max_deg: Option<f64>,
    /// All transmission angles inside 30°…150°.
    pub mu_ok: bool,
    /// The physical checks of the stitch's needle threads
    /// (`stitch::checks`) that fail here, as `thread check`.
    pub failed_checks: Vec<String>,
    /// Every constraint holds: the transmission angles and the checks.
    pub feasible: bool,
    /// The largest peak tension over the threads, N, where the thread's
    /// tension is solved.
    pub peak_tension_n: Option<f64>,
    /// The objective minimised (see the module docs).
    pub objective: f64,
}

/// How far one parameter may move from the optimum (the others held) with
/// the objective within 0.01 of its best (one point of match score) and the
/// transmission angles inside their band.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Flatness {
    pub name: String,
    pub lo: f64,
    pub hi: f64,
}

/// One adjusted parameter in shop terms: which part, which way and how
/// far, from the model's `label`, `what`, `increase` and `decrease`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Adjustment {
    pub name: String,
    pub unit: &'static str,
    /// `setting`, `input` or `dimension` (the last two only when allowed).
    pub kind: crate::model::ParamKind,
    /// The part in plain words (the name when the model gives none).
    pub label: String,
    /// What the part is and which way the value moves it, when the model
    /// says.
    pub what: Option<String>,
    pub before: f64,
    pub after: f64,
    /// after − before, in `unit`.
    pub change: f64,
    /// The advice, one line: "ball arm O2B on the take-up shaft: slide it
    /// along the shaft away from the take-up arm by 0.32 mm (z: 0 →
    /// -0.32 mm)".
    pub advice: String,
}

impl Adjustment {
    /// The adjustment of parameter `p` from `before` to `after`, worded
    /// to the hundredth the recommendation prints (the thousandth of an
    /// inch or a radian, whose hundredth is 0.25 mm or 0.57°).
    pub fn new(p: &crate::model::ParamDef, before: f64, after: f64) -> Adjustment {
        let unit = p.unit_str();
        let per = match p.unit {
            crate::model::Unit::In | crate::model::Unit::Rad => 1000.0,
            _ => 100.0,
        };
        let rounded = |x: f64| {
            if per == 100.0 {
                hundredths(x)
            } else {
                let r = (x * per).round() / per;
                if r == 0.0 { "0".to_string() } else { format!("{r}") }
            }
        };
        let with_unit = |x: f64| {
            let n = rounded(x);
            if unit == "1" { n } else { format!("{n} {unit}") }
        };
        let label = p.label_or_name().to_string();
        let (b, a) = (rounded(before), rounded(after));
        let advice = if a == b {
            format!("{label}: leave it as it is ({} = {})", p.name, with_unit(before))
        } else {
            let up = after > before;
            let way = match (up, &p.increase, &p.decrease) {
                (true, Some(w), _) | (false, _, Some(w)) => w.clone(),
                (true, None, _) => "increase it".into(),
                (false, _, None) => "decrease it".into(),
            };
            // The change between the two printed values.
            let by = ((after * per).round() - (before * per).round()).abs() / per;
            format!(
                "{label}: {way} by {} ({}: {b} → {})",
                with_unit(by),
                p.name,
                with_unit(after)
            )
        };
        Adjustment {
            name: p.name.clone(),
            unit,
            kind: p.kind,
            label,
            what: p.what.clone(),
            before,
            after,
            change: after - before,
            advice,
        }
    }
}

/// The outcome of a tuning.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TuneResult {
    /// The adjusted parameters with their units.
    pub names: Vec<(String, &'static str)>,
    pub before: Vec<f64>,
    pub after: Vec<f64>,
    /// The recommendation in shop terms, one per adjusted parameter.
    pub adjustments: Vec<Adjustment>,
    pub before_figures: MatchFigures,
    pub after_figures: MatchFigures,
    pub flatness: Vec<Flatness>,
    /// Where the result stands: a setting on the end of its range (the best
    /// may lie beyond what the range allows), a score that does not rise, a
    /// constraint no setting in the ranges meets.
    pub notes: Vec<String>,
    /// Cycles evaluated.
    pub evaluations: usize,
    /// What was minimised.
    pub objective: TuneObjective,
}

/// Objective penalty per degree a transmission angle leaves the band.
const MU_PENALTY_PER_DEG: f64 = 0.05;
/// Objective penalty per physical check that fails (more than any match
/// can gain: the objective of a match is at most 1 per thread on average)…
const CHECK_PENALTY: f64 = 1.0;
/// …and per mm of thread beyond the bound at B.
const CHECK_PENALTY_PER_MM: f64 = 0.05;
/// Objective of a setting that does not assemble or evaluate.
const FAILED: f64 = 1.0e3;

struct Problem<'a> {
    model: &'a Model,
    base: &'a Params,
    vary: &'a [Vary],
    opts: CycleOptions,
    shared: Option<&'a Prepared>,
    goal: TuneObjective,
}

impl Problem<'_> {
    /// The setting at u ∈ [0, 1]^d.
    fn values(&self, u: &[f64]) -> Vec<f64> {
        self.vary
            .iter()
            .zip(u)
            .map(|(v, &u)| v.lo + (v.hi - v.lo) * u.clamp(0.0, 1.0))
            .collect()
    }

    fn table(&self, x: &[f64]) -> Result<CycleTable, Error> {
        let mut p = self.base.clone();
        for (v, &x) in self.vary.iter().zip(x) {
            self.model.set(&mut p, &v.name, x)?;
        }
        run_cycle_with(self.model, &p, &self.opts, self.shared)
    }

    fn figures(&self, x: &[f64]) -> Option<MatchFigures> {
        let t = self.table(x).ok()?;
        let st = t.stitch.as_ref()?;
        let mut rel = Vec::new();
        let mut threads = Vec::new();
        for th in &st.threads {
            if let Some(m) = &th.mismatch {
                if m.range_pprime_mm > 1e-12 {
                    rel.push(m.rms_d_mm / m.range_pprime_mm);
                }
                threads.push((th.thread.clone(), m.score, m.rms_d_mm, m.max_abs_d_mm));
            }
        }
        if rel.is_empty() {
            return None;
        }
        let mean_rel = rel.iter().sum::<f64>() / rel.len() as f64;
        // The highest peak tension, and as a share of its thread's breaking
        // force.
        let tensions = st.threads.iter().filter_map(|th| th.tension.as_ref());
        let peak_tension_n = tensions.clone().map(|tn| tn.peak_n).reduce(f64::max);
        let peak_share = tensions.map(|tn| tn.peak_n / tn.breaking_n).reduce(f64::max);
        let goal = match self.goal {
            TuneObjective::Match => mean_rel,
            TuneObjective::PeakTension => peak_share?,
        };
        let scores: Vec<f64> = threads.iter().filter_map(|t| t.1).collect();
        let mu_min = t.transmission.iter().map(|m| m.min_deg).reduce(f64::min);
        let mu_max = t.transmission.iter().map(|m| m.max_deg).reduce(f64::max);
        let out_of_band =
            mu_min.map_or(0.0, |m| (MU_MIN_DEG - m).max(0.0)) + mu_max.map_or(0.0, |m| (m - MU_MAX_DEG).max(0.0));
        // The physical checks are constraints: a fixed penalty for each
        // that fails, plus the thread beyond the bound at B or short of
        // what the take-up must give, so the search is led back inside.
        let failed: Vec<&crate::stitch::checks::Check> = st.checks.iter().filter(|c| !c.ok).collect();
        let excess_mm: f64 = failed
            .iter()
            .filter(|c| matches!(c.name, "thread_bound" | "takeup_gives"))
            .map(|c| c.excess())
            .sum();
        Some(MatchFigures {
            score_mean: if scores.is_empty() {
                0.0
            } else {
                scores.iter().sum::<f64>() / scores.len() as f64
            },
            threads,
            mu_min_deg: mu_min,
            mu_max_deg: mu_max,
            mu_ok: out_of_band == 0.0,
            failed_checks: failed.iter().map(|c| format!("{} {}", c.thread, c.name)).collect(),
            feasible: out_of_band == 0.0 && failed.is_empty(),
            peak_tension_n,
            objective: goal
                + MU_PENALTY_PER_DEG * out_of_band
                + CHECK_PENALTY * failed.len() as f64
                + CHECK_PENALTY_PER_MM * excess_mm,
        })
    }

    /// The objective at u, with a penalty for leaving the box (Nelder–Mead
    /// is unconstrained: it is fed the clamped setting plus the distance).
    fn objective(&self, u: &[f64]) -> f64 {
        let outside: f64 = u.iter().map(|&u| (u - u.clamp(0.0, 1.0)).abs()).sum();
        self.figures(&self.values(u)).map_or(FAILED, |f| f.objective) + 10.0 * outside
    }

    /// Nelder–Mead from the best three starts of `scored` (objective and
    /// setting in u, best first): the best setting found, with its
    /// objective.
    fn local_search(&self, scored: &[(f64, Vec<f64>)], count: &AtomicUsize) -> Result<(f64, Vec<f64>), Error> {
        let d = self.vary.len();
        let starts: Vec<Vec<f64>> = scored.iter().take(3).map(|s| s.1.clone()).collect();
        let mut best = scored[0].clone();
        for s in starts {
            let mut simplex = vec![s.clone()];
            for k in 0..d {
                let mut v = s.clone();
                v[k] += if v[k] > 0.5 { -0.08 } else { 0.08 };
                simplex.push(v);
            }
            let solver = NelderMead::new(simplex)
                .with_sd_tolerance(1e-7)
                .map_err(|e| Error::Internal(format!("tuning: {e}")))?;
            let res = Executor::new(Cost(self, count), solver)
                .configure(|st| st.max_iters(60 * d as u64))
                .run()
                .map_err(|e| Error::Internal(format!("tuning: {e}")))?;
            let st = res.state();
            if let Some(p) = st.get_best_param()
                && st.get_best_cost() < best.0
            {
                best = (st.get_best_cost(), p.iter().map(|u| u.clamp(0.0, 1.0)).collect());
            }
        }
        Ok(best)
    }

    /// How flat the optimum `after` (with figures `best`) is: each
    /// parameter alone across its range (see [`Flatness`]).
    fn flatness(&self, after: &[f64], best: &MatchFigures, count: &AtomicUsize) -> Vec<Flatness> {
        self.vary
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let xs: Vec<f64> = (0..=40).map(|j| v.lo + (v.hi - v.lo) * j as f64 / 40.0).collect();
                let ok: Vec<bool> = xs
                    .par_iter()
                    .map(|&x| {
                        let mut s = after.to_vec();
                        s[k] = x;
                        self.figures(&s)
                            .is_some_and(|f| f.feasible && f.objective <= best.objective + 0.01)
                    })
                    .collect();
                count.fetch_add(xs.len(), Ordering::Relaxed);
                // The run of acceptable values around the optimum.
                let j0 = xs
                    .iter()
                    .enumerate()
                    .min_by(|a, b| (a.1 - after[k]).abs().total_cmp(&(b.1 - after[k]).abs()))
                    .map_or(0, |(j, _)| j);
                let (mut a, mut b) = (j0, j0);
                while a > 0 && ok[a - 1] {
                    a -= 1;
                }
                while b + 1 < xs.len() && ok[b + 1] {
                    b += 1;
                }
                Flatness {
                    name: v.name.clone(),
                    lo: xs[a].min(after[k]),
                    hi: xs[b].max(after[k]),
                }
            })
            .collect()
    }
}

struct Cost<'a, 'b>(&'b Problem<'a>, &'b AtomicUsize);

impl CostFunction for Cost<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Self::Param) -> Result<f64, argmin::core::Error> {
        self.1.fetch_add(1, Ordering::Relaxed);
        Ok(self.0.objective(u))
    }
}

/// Sets the stitch's thickness (`which` = "m") or length ("t"), `value_mm`
/// in mm, through the parameter its `[stitch]` value names (converted to
/// that parameter's unit, the model's length unit).
pub fn set_stitch_value(model: &Model, params: &mut Params, which: &str, value_mm: f64) -> Result<(), Error> {
    if !model.has_stitch() {
        return Err(StitchError::new(format!("model `{}`", model.name()), "it has no [stitch] table").into());
    }
    match model.stitch_param(which) {
        Some(name) => {
            let value = model
                .param_index(name)
                .map_or(value_mm, |i| model.params[i].from_result_unit(value_mm));
            model.set(params, name, value).map_err(Error::Param)
        }
        None => Err(Error::Param(ParamError::general(
            format!("[stitch] {which}_mm is not a parameter, so it cannot be set"),
            Some(format!(
                "write {which}_mm = \"NAME\" with NAME in [parameters] (with a range), or set the parameter it names"
            )),
        ))),
    }
}

/// Checks the number of global samples against [`MAX_SAMPLES`] (callers
/// check it before their own preparations; [`tune`] checks it too).
pub fn check_samples(samples: usize) -> Result<(), Error> {
    if samples > MAX_SAMPLES {
        return Err(Error::Param(ParamError::new(
            Input::Samples,
            format!("{samples} samples are too many for a tuning"),
            Some(format!(
                "at most {MAX_SAMPLES} per tuning: fewer samples (the default, 32 per adjusted setting and at least 64, \
                 is usually enough; the local search refines the best of them)"
            )),
        )));
    }
    Ok(())
}

/// Tunes `model` (with `base`, where the stitch's thickness and length are
/// already set) over `opts.adjust`.
pub fn tune(model: &Model, base: &Params, opts: &TuneOptions) -> Result<TuneResult, Error> {
    crate::eval::check_options(&CycleOptions {
        step_deg: opts.step_deg,
        ..Default::default()
    })?;
    check_samples(opts.samples)?;
    let vary = tuned_ranges(model, &opts.adjust)?;
    let cycle = CycleOptions {
        step_deg: opts.step_deg,
        rpm: None,
        analogs: false,
        points: Some(Vec::new()),
        lean: true,
    };
    let samples = if opts.samples == 0 {
        (32 * vary.len()).max(64)
    } else {
        opts.samples
    };
    let design = Sweep::new(
        vary.clone(),
        Design::Lhs {
            samples,
            seed: opts.seed,
        },
    )?;
    if opts.objective == TuneObjective::PeakTension && !model.has_thread_physics() {
        return Err(Error::Param(ParamError::new(
            Input::Adjust,
            format!(
                "model `{}` has no thread physics, so its thread's tension cannot be tuned",
                model.name()
            ),
            Some("give [thread.physics] in the model file (docs/thread-physics.md), or tune the match".into()),
        )));
    }
    let shared = shared_stitch(model, base, &design, opts.step_deg)?;
    let problem = Problem {
        model,
        base,
        vary: &vary,
        opts: cycle,
        shared: shared.as_ref(),
        goal: opts.objective,
    };
    let before: Vec<f64> = vary
        .iter()
        .map(|v| base.values[model.param_index(&v.name).unwrap_or(0)])
        .collect();
    let before_figures = problem.figures(&before).ok_or_else(|| match model.stitch_setup(base) {
        Ok(None) => StitchError::new(
            format!("model `{}`", model.name()),
            "it has no [stitch] with a take-up path to match",
        )
        .into(),
        _ => problem.table(&before).err().unwrap_or_else(|| {
            StitchError::new(
                "stitch process",
                "no thread of the stitch is compared with a take-up path (give `path` in [stitch])",
            )
            .into()
        }),
    })?;
    let count = AtomicUsize::new(0);
    // Global: the Latin-hypercube sample, in parallel.
    let unit = |i: usize| -> Vec<f64> {
        design
            .setting(i)
            .iter()
            .zip(&vary)
            .map(|(x, v)| (x - v.lo) / (v.hi - v.lo))
            .collect()
    };
    let mut scored: Vec<(f64, Vec<f64>)> = (0..samples)
        .into_par_iter()
        .map(|i| {
            let u = unit(i);
            count.fetch_add(1, Ordering::Relaxed);
            (problem.objective(&u), u)
        })
        .collect();
    // The nominal setting competes too.
    let u0: Vec<f64> = before
        .iter()
        .zip(&vary)
        .map(|(x, v)| (x - v.lo) / (v.hi - v.lo))
        .collect();
    scored.push((before_figures.objective, u0));
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    let best = problem.local_search(&scored, &count)?;
    let after = problem.values(&best.1);
    let after_figures = problem
        .figures(&after)
        .ok_or_else(|| Error::Internal("tuning: the optimum does not evaluate".into()))?;
    let flatness = problem.flatness(&after, &after_figures, &count);
    let names: Vec<(String, &'static str)> = vary
        .iter()
        .map(|v| {
            (
                v.name.clone(),
                model.params[model.param_index(&v.name).unwrap_or(0)].unit_str(),
            )
        })
        .collect();
    let notes = standing(&vary, &names, &after, &before_figures, &after_figures, opts.objective);
    let adjustments = vary
        .iter()
        .zip(before.iter().zip(&after))
        .map(|(v, (&b, &a))| Adjustment::new(&model.params[model.param_index(&v.name).unwrap_or(0)], b, a))
        .collect();
    Ok(TuneResult {
        names,
        before,
        after,
        adjustments,
        before_figures,
        after_figures,
        flatness,
        notes,
        evaluations: count.into_inner(),
        objective: opts.objective,
    })
}

/// The ranges of the parameters `adjust` names, each checked: a
/// parameter of the model with an adjustable range, a machine setting
/// unless the model allows its kind ([`Model::allow_adjusting`]).
fn tuned_ranges(model: &Model, adjust: &[String]) -> Result<Vec<Vary>, Error> {
    let bad = |message: String, help: &str| Error::Param(ParamError::new(Input::Adjust, message, Some(help.into())));
    let settings: Vec<&str> = model
        .params
        .iter()
        .filter(|p| p.is_adjustable_setting())
        .map(|p| p.name.as_str())
        .collect();
    if adjust.is_empty() {
        if !model.has_stitch() {
            return Err(StitchError::new(
                format!("model `{}`", model.name()),
                "it has no [stitch] table, so there is no match to tune; use a model with one, such as the presets \
                 mf7923d and altin504",
            )
            .into());
        }
        let help = if settings.is_empty() {
            format!(
                "model `{}` has no machine setting with a range: give the parts a technician sets `kind = \"setting\"` \
                 and `range = [lo, hi]` in [parameters] (docs/model-format.md §4), or name the parameters to search \
                 (a fixed dimension once the search allows them)",
                model.name()
            )
        } else {
            format!(
                "name the settings to adjust, e.g. {} (the thread's tension settings are adjusted only when named)",
                settings.join(",")
            )
        };
        return Err(bad("nothing to adjust".into(), &help));
    }
    let mut vary = Vec::new();
    for name in adjust {
        let i = model.param_index(name).ok_or_else(|| {
            let hint = crate::error::did_you_mean(name, model.params.iter().map(|p| p.name.as_str()))
                .map(|s| format!(" (did you mean `{s}`?)"))
                .unwrap_or_default();
            bad(
                format!("the model has no parameter `{name}`{hint}"),
                &format!("its adjustable parameters are: {}", settings.join(", ")),
            )
        })?;
        if let Some(r) = KindRefusal::of(model, name) {
            return Err(bad(r.message(), &r.help(None)));
        }
        let Some([lo, hi]) = model.params[i].range else {
            return Err(bad(
                format!("`{name}` has no adjustable range to tune in"),
                "give it `range = [lo, hi]` in [parameters]",
            ));
        };
        if lo >= hi {
            return Err(bad(
                format!("`{name}`'s adjustable range {lo}…{hi} is a single value, so there is nothing to tune"),
                "leave it out, or widen its `range` in [parameters]",
            ));
        }
        vary.push(Vary {
            name: name.clone(),
            lo,
            hi,
            n: 2,
        });
    }
    Ok(vary)
}

/// Why a tuning will not adjust a parameter it is asked to: a job input or
/// a fixed dimension, which the model does not allow searching
/// ([`Model::allow_adjusting`]).
#[derive(Debug, Clone, PartialEq)]
pub struct KindRefusal {
    pub name: String,
    pub label: Option<String>,
    pub kind: crate::model::ParamKind,
    /// The model's machine settings with room to move, which a tuning
    /// adjusts instead.
    pub settings: Vec<String>,
}

impl KindRefusal {
    /// The refusal of parameter `name`, if the model does not let a search
    /// adjust its kind (`None` for a setting, an allowed kind or an unknown
    /// name).
    pub fn of(model: &Model, name: &str) -> Option<KindRefusal> {
        let p = &model.params[model.param_index(name)?];
        (!model.may_adjust(p.kind)).then(|| KindRefusal {
            name: name.to_string(),
            label: p.label.clone(),
            kind: p.kind,
            settings: model
                .params
                .iter()
                .filter(|p| p.is_adjustable_setting())
                .map(|p| p.name.clone())
                .collect(),
        })
    }

    /// What the parameter is and why it is not tuned.
    pub fn message(&self) -> String {
        let (name, what) = (
            &self.name,
            self.label.as_deref().map(|l| format!(" ({l})")).unwrap_or_default(),
        );
        match self.kind {
            crate::model::ParamKind::Input => format!(
                "`{name}`{what} is a job input, not a machine setting: tuning recommends how to set the machine for \
                 a given job, never the job itself"
            ),
            _ => format!(
                "`{name}`{what} is a fixed dimension, not a machine setting: no technician adjusts it on the machine"
            ),
        }
    }

    /// What to do instead and how to search it anyway; `allow` is how the
    /// front end allows the kind (its option), or `None` for the library's
    /// own words.
    pub fn help(&self, allow: Option<&str>) -> String {
        let (name, settings) = (&self.name, self.settings.join(", "));
        let allow = allow.map_or_else(
            || match self.kind {
                crate::model::ParamKind::Input => "allow job inputs in the search".to_string(),
                _ => "allow fixed dimensions in the search".to_string(),
            },
            |a| format!("add {a}"),
        );
        match self.kind {
            crate::model::ParamKind::Input => format!(
                "give the job's value (the stitch's thickness and length, or the parameter itself) and adjust the \
                 machine settings ({settings}); a nomogram tunes them over the job's range; to search `{name}` \
                 anyway, {allow}"
            ),
            _ => format!(
                "adjust the machine settings ({settings}); to search `{name}` as a change to the machine's design, \
                 {allow}"
            ),
        }
    }
}

/// Where a tuning's result stands (see [`TuneResult::notes`]).
fn standing(
    vary: &[Vary],
    names: &[(String, &str)],
    after: &[f64],
    before: &MatchFigures,
    best: &MatchFigures,
    goal: TuneObjective,
) -> Vec<String> {
    let mut notes = Vec::new();
    let what = match goal {
        TuneObjective::Match => "the best match",
        TuneObjective::PeakTension => "the lowest peak tension",
    };
    for ((v, (name, unit)), &x) in vary.iter().zip(names).zip(after) {
        let tol = 1e-3 * (v.hi - v.lo);
        let end = if x <= v.lo + tol {
            "lower"
        } else if x >= v.hi - tol {
            "upper"
        } else {
            continue;
        };
        notes.push(format!(
            "{name} = {} {unit} lies on the {end} end of its adjustable range ({}…{} {unit}): {what} may lie beyond what \
             the range allows",
            crate::format::fmt_num((x * 1e6).round() / 1e6),
            crate::format::fmt_num(v.lo),
            crate::format::fmt_num(v.hi)
        ));
    }
    let no_gain = match goal {
        TuneObjective::Match => best.score_mean <= before.score_mean + 0.05,
        TuneObjective::PeakTension => best.objective >= before.objective - 1e-4,
    };
    if goal == TuneObjective::PeakTension && no_gain && best.failed_checks.len() >= before.failed_checks.len() {
        notes.push(format!(
            "the peak tension does not fall ({:.2} N → {:.2} N): within these ranges the starting setting is as good as any",
            before.peak_tension_n.unwrap_or(0.0),
            best.peak_tension_n.unwrap_or(0.0)
        ));
    } else if no_gain && best.failed_checks.len() >= before.failed_checks.len() {
        notes.push(format!(
            "the match does not improve (mean score {:.1} → {:.1}): within these ranges the starting setting is as good as any",
            before.score_mean, best.score_mean
        ));
    }
    if !best.failed_checks.is_empty() {
        notes.push(format!(
            "no setting found within the ranges passes every physical check ({} still fail): the machine cannot work this way; \
             see `stitchkin match` for what each check needs",
            best.failed_checks.join(", ")
        ));
    }
    if !best.mu_ok {
        notes.push(
            "a transmission angle stays outside 30°…150° at the best setting found: the mechanism risks jamming".into(),
        );
    }
    notes
}
