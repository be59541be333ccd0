//! Parameter sweeps: evaluate a model over every setting of a
//! [`Sweep`] design and report the selected figures of merit for each.
//!
//! [`run`] evaluates settings in parallel (rayon), in chunks, handing rows
//! to a sink in setting order, so memory stays flat however many settings
//! there are. An [`Evaluator`] gives each worker the figures of one setting
//! after another without building a cycle table.

use rayon::prelude::*;

use super::design::Sweep;
use super::figures::{figures, max_pprime_figure};
use crate::error::Error;
use crate::eval::stitch_process::Prepared;
use crate::eval::{CycleOptions, not_finite, path_error, run_cycle_with};
use crate::mechanism::{Mechanism, Phi, Pose};
use crate::model::{Machine, Model, Params};
use crate::scalar::Real;
use crate::thread::{ThreadWork, Threads};

/// One evaluated setting.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Setting number.
    pub index: usize,
    /// Values of the varied parameters.
    pub values: Vec<f64>,
    /// The selected figures, `None` where this setting has none (a flat P'
    /// has no score) or did not evaluate.
    pub figures: Vec<Option<f64>>,
    /// `None` when the cycle evaluated; otherwise why not (no assembly, …).
    pub error: Option<String>,
}

/// Evaluates one setting (with P' from `shared` when given).
pub fn evaluate(
    model: &Model,
    base: &Params,
    sweep: &Sweep,
    names: &[String],
    opts: &CycleOptions,
    shared: Option<&Prepared>,
    index: usize,
) -> Row {
    let values = sweep.setting(index);
    let mut p = base.clone();
    let mut result = Ok(());
    for (v, x) in sweep.vary.iter().zip(&values) {
        if let Err(e) = model.set(&mut p, &v.name, *x) {
            result = Err(Error::Param(e));
            break;
        }
    }
    let table = result.and_then(|_| run_cycle_with(model, &p, opts, shared));
    match table {
        Ok(t) => {
            let all = figures(&t);
            let figures = names
                .iter()
                .map(|n| {
                    all.iter()
                        .find(|(m, _)| m == n)
                        .map(|(_, v)| *v)
                        .filter(|v| v.is_finite())
                })
                .collect();
            Row {
                index,
                values,
                figures,
                error: None,
            }
        }
        Err(e) => Row {
            index,
            values,
            figures: vec![None; names.len()],
            error: Some(e.to_string().replace('\n', " ")),
        },
    }
}

/// Evaluates settings one after another, computing only the figures asked
/// for and keeping the cycle's buffers (pose, thread pieces, take-up) from
/// one setting to the next: one per worker. It gives exactly the figures
/// [`evaluate`] gives (test `the_fast_figures_are_the_cycle_tables`), with
/// no cycle table, no columns and no heap allocation for the cycle itself.
/// A model whose stitch process changes with the swept parameters (no
/// shared P') is evaluated through the full cycle instead.
pub struct Evaluator<'a> {
    model: &'a Model,
    base: &'a Params,
    sweep: &'a Sweep,
    names: &'a [String],
    opts: &'a CycleOptions,
    shared: Option<&'a Prepared>,
    /// `None` when the fast path cannot give every requested figure.
    fast: Option<Fast>,
    /// Figure values of the last setting, and for each requested figure
    /// its place among them (known after the first setting that evaluates).
    out: Figures,
    pick: Option<Vec<Option<usize>>>,
}

/// The fast path's plan and buffers.
struct Fast {
    phis: Vec<f64>,
    table: Vec<Phi<f64>>,
    phi0: [Phi<f64>; 1],
    params: Params,
    pose: Pose<f64>,
    pose0: Pose<f64>,
    /// The last setting's machine where `pose` and `work` hold its whole
    /// solution: the next setting solves only what its change moves.
    before: Option<Machine<f64>>,
    /// Per point of the mechanism, whether it moved from `before`'s.
    moved: Vec<bool>,
    work: ThreadWork<f64>,
    work0: ThreadWork<f64>,
    /// Per path, its course over the cycle for the thread's tension where
    /// one was solved: kept from setting to setting while none of the
    /// path's pieces moves (a sweep over the stitch alone), else empty
    /// until a tension needs it.
    courses: Vec<crate::eval::PathCourse>,
    /// Take-up of every path over the cycle, mm.
    p: Vec<Vec<f64>>,
    /// Which kinds of figures are asked for.
    mu: bool,
    measures: bool,
    strokes: bool,
    /// A figure that judges the checks, and one of the bound's margin.
    checks: bool,
    margins: bool,
    stitch: Vec<StitchPlan>,
    /// When the swept parameters change the stitch (no shared P′): P′ is
    /// prepared for each setting, and its plans made again from the path
    /// names and whether a tension figure is asked for.
    own_stitch: Option<(Vec<String>, bool)>,
    buf: Vec<f64>,
    /// Per-φ values of the measures, one column each.
    cols: Vec<Vec<f64>>,
    /// Per-φ transmission angles as `(y, x)`, one column per dyad.
    parts: Vec<Vec<(f64, f64)>>,
    part_buf: Vec<(f64, f64)>,
}

/// One stitch thread's fixed part of its figures: what only P' decides.
struct StitchPlan {
    name: String,
    /// The path its P comes from (index into the thread paths).
    path: Option<usize>,
    /// P' over the cycle grid, mm.
    pprime: Vec<f64>,
    /// The compared positions (outside a regulator window), and each
    /// position's weight in the mismatch (1 compared, 0 not).
    ks: Vec<usize>,
    weight: Vec<f64>,
    /// Range of P' over them; the score's scale.
    range: f64,
    max_pprime_figure: &'static str,
    max_pprime_mm: f64,
    /// A needle thread with a path: the most thread the needle can take
    /// through B at each φ (`stitch::checks::bound_curve`).
    bound: Option<Vec<f64>>,
    /// φ0, deg: where P = P′ = 0, the start of the stitch's drawing phase.
    phi0_deg: f64,
    /// Whether the thread has physical checks, and whether those that do
    /// not depend on the take-up (catch, stab) pass.
    has_checks: bool,
    fixed_checks_ok: bool,
    /// Where its path carries thread physics: the tension solved each
    /// setting (and, with the regulator's window computed, P' with it).
    tension: Option<TensionPlan>,
}

/// A stitch thread whose tension is solved for each setting.
struct TensionPlan {
    /// Its index among the stitch's threads.
    thread: usize,
    /// Whether the regulator's window is computed (P' and the compared
    /// positions follow the tension).
    computed: bool,
    /// This setting's tension, P' and weights.
    solved: Option<crate::eval::tension::Solved>,
    pprime: Vec<f64>,
    weight: Vec<f64>,
    count: usize,
    range: f64,
}

/// What a sweep of a model needs besides its design, worked out once: the
/// cycle options (lean, no analogs), the figures it reports and P' when it
/// is shared by every setting.
#[derive(Debug, Clone)]
pub struct SweepPlan {
    pub opts: CycleOptions,
    /// The figures, in their order (`select_figures`).
    pub names: Vec<String>,
    pub shared: Option<Prepared>,
}

impl SweepPlan {
    /// Plans a sweep of `model` around `base` over `sweep`, at a φ step of
    /// `step_deg`, for the figures matching `patterns` (the default figures
    /// when `None`). The nominal setting says which figures the model has;
    /// a pattern that matches none is an error that lists them.
    pub fn new(
        model: &Model,
        base: &Params,
        sweep: &Sweep,
        patterns: Option<&[String]>,
        step_deg: f64,
    ) -> Result<SweepPlan, Error> {
        let opts = CycleOptions::for_figures(step_deg);
        let nominal = crate::eval::run_cycle(model, base, &opts)?;
        let available = figures(&nominal);
        let patterns = patterns.map_or_else(|| super::figures::default_figures(&available), <[String]>::to_vec);
        let names = super::figures::select_figures(&available, &patterns)?;
        let shared = super::figures::shared_stitch(model, base, sweep, step_deg)?;
        Ok(SweepPlan { opts, names, shared })
    }

    /// The job of this plan: `model` at `base` over `sweep`.
    pub fn job<'a>(&'a self, model: &'a Model, base: &'a Params, sweep: &'a Sweep) -> SweepJob<'a> {
        SweepJob {
            model,
            base,
            sweep,
            names: &self.names,
            opts: &self.opts,
            shared: self.shared.as_ref(),
        }
    }
}

/// What a sweep evaluates: `model` at `base` with each setting of `sweep`
/// applied, for the figures `names` (as
/// [`select_figures`](super::figures::select_figures) gives them), every
/// cycle run with `opts`, and P' from `shared` when the sweep leaves the
/// stitch alone ([`super::figures::shared_stitch`]).
#[derive(Debug, Clone, Copy)]
pub struct SweepJob<'a> {
    pub model: &'a Model,
    pub base: &'a Params,
    pub sweep: &'a Sweep,
    pub names: &'a [String],
    pub opts: &'a CycleOptions,
    pub shared: Option<&'a Prepared>,
}

impl<'a> Evaluator<'a> {
    /// An evaluator of the settings of `job`.
    pub fn new(job: SweepJob<'a>) -> Self {
        let SweepJob {
            model,
            base,
            sweep,
            names,
            opts,
            shared,
        } = job;
        let fast = Fast::plan(model, base, names, opts, shared);
        Evaluator {
            model,
            base,
            sweep,
            names,
            opts,
            shared,
            fast,
            out: Figures {
                vals: Vec::new(),
                names: None,
            },
            pick: None,
        }
    }

    /// Whether settings go through the fast path (else the full cycle).
    pub fn is_fast(&self) -> bool {
        self.fast.is_some()
    }

    /// The row of setting `index`: the same as [`evaluate`]'s.
    pub fn evaluate(&mut self, index: usize) -> Row {
        let Some(fast) = &mut self.fast else {
            return evaluate(
                self.model,
                self.base,
                self.sweep,
                self.names,
                self.opts,
                self.shared,
                index,
            );
        };
        let values = self.sweep.setting(index);
        fast.params.values.clone_from(&self.base.values);
        let mut result = Ok(());
        for (v, x) in self.sweep.vary.iter().zip(&values) {
            if let Err(e) = self.model.set(&mut fast.params, &v.name, *x) {
                result = Err(Error::Param(e));
                break;
            }
        }
        let out = &mut self.out;
        out.vals.clear();
        out.names = self.pick.is_none().then(Vec::new);
        match result.and_then(|_| fast.figures(self.model, self.opts, self.shared, out)) {
            Ok(()) => {
                if let Some(names) = out.names.take() {
                    self.pick = Some(self.names.iter().map(|n| names.iter().position(|m| m == n)).collect());
                }
                let pick = self.pick.as_ref().expect("set by the first setting that evaluates");
                let figures = pick
                    .iter()
                    .map(|i| i.map(|i| out.vals[i]).filter(|v| v.is_finite()))
                    .collect();
                Row {
                    index,
                    values,
                    figures,
                    error: None,
                }
            }
            Err(e) => Row {
                index,
                values,
                figures: vec![None; self.names.len()],
                error: Some(e.to_string().replace('\n', " ")),
            },
        }
    }
}

impl Fast {
    /// The plan, or `None` when a figure needs the full cycle (a shared P'
    /// is missing for a stitch figure, or a figure of another kind).
    fn plan(
        model: &Model,
        base: &Params,
        names: &[String],
        opts: &CycleOptions,
        shared: Option<&Prepared>,
    ) -> Option<Fast> {
        if opts.analogs || opts.rpm.is_some() || crate::eval::check_options(opts).is_err() {
            return None;
        }
        let Machine {
            mechanism: mech,
            threads,
        } = model.machine::<f64>(base).ok()?;
        // A cam's checks read the whole cycle (`eval::cams`).
        let cams = mech
            .steps
            .iter()
            .any(|s| matches!(s, crate::mechanism::Step::CamFollower(_)));
        if cams && names.iter().any(|n| n == "checks.ok" || n.ends_with(".checks_ok")) {
            return None;
        }
        let threads = threads.as_ref();
        let path_names: Vec<&str> = threads.map_or(Vec::new(), |t| t.paths.iter().map(|p| p.name.as_str()).collect());
        let kinds = Kinds::of(model, threads, &path_names, names)?;
        let phis = crate::eval::cycle_phis_deg(model.phi_start_deg(), opts.step_deg);
        let (plans, own_stitch) = match (kinds.stitch, shared) {
            (false, _) => (Vec::new(), None),
            (true, Some(shared)) => (
                StitchPlan::all(model, shared, &phis, threads, &path_names, kinds.tension)?,
                None,
            ),
            // The setting changes the stitch: its P′ each setting, planned as
            // the base setting's is (which must prepare).
            (true, None) => {
                let own = crate::eval::stitch_process::prepare_on(model, base, phis.clone()).ok()??;
                let plans = StitchPlan::all(model, &own, &phis, threads, &path_names, kinds.tension)?;
                let names = path_names.iter().map(|n| n.to_string()).collect();
                (plans, Some((names, kinds.tension)))
            }
        };
        let phi0 = [Phi::at_deg(threads.map_or(0.0, |t| t.phi0_deg))];
        // Only the paths a figure reads: those asked for and those the
        // stitch's threads are compared with.
        let mut wanted = kinds.paths.clone();
        for pi in plans.iter().filter_map(|p| p.path) {
            wanted[pi] = true;
        }
        Some(Fast {
            table: Phi::table(&phis),
            phis,
            phi0,
            params: base.clone(),
            pose: mech.new_pose(0),
            pose0: mech.new_pose(1),
            before: None,
            moved: Vec::new(),
            work: ThreadWork::only_paths(wanted),
            work0: ThreadWork::default(),
            courses: Vec::new(),
            p: Vec::new(),
            mu: kinds.mu,
            measures: kinds.measures,
            strokes: kinds.strokes,
            checks: kinds.checks,
            margins: kinds.margins,
            stitch: plans,
            own_stitch,
            buf: Vec::new(),
            cols: Vec::new(),
            parts: Vec::new(),
            part_buf: Vec::new(),
        })
    }

    /// Every figure of the kinds planned, by name, for `self.params`: what
    /// [`figures`] of the cycle table gives.
    fn figures(
        &mut self,
        model: &Model,
        opts: &CycleOptions,
        shared: Option<&Prepared>,
        out: &mut Figures,
    ) -> Result<(), Error> {
        let machine = model.machine::<f64>(&self.params)?;
        // What the last setting left is used once; it is kept again only
        // where this setting's solution is whole.
        let before = self.before.take();
        machine.mechanism.solve_since(
            before.as_ref().map(|b| &b.mechanism),
            &self.table,
            &mut self.pose,
            &mut self.moved,
        )?;
        if let Some(threads) = &machine.threads {
            let kept = match before.as_ref().and_then(|b| b.threads.as_ref()) {
                Some(t0) => {
                    threads.keep_unmoved(t0, &self.moved, &mut self.work);
                    true
                }
                None => false,
            };
            // A course stays only where every piece of its path does.
            self.courses.resize_with(threads.paths.len(), Default::default);
            for (course, path) in self.courses.iter_mut().zip(threads.paths.iter()) {
                if !(kept && threads.path_kept(path, &self.work)) {
                    course.clear();
                }
            }
            self.take_up_figures(&machine.mechanism, threads, out)?;
        }
        let rest = self.stitch_and_measures(model, opts, shared, &machine, out);
        self.before = Some(machine);
        rest
    }

    /// The figures past the take-up, from the setting's solved `machine`.
    fn stitch_and_measures(
        &mut self,
        model: &Model,
        opts: &CycleOptions,
        shared: Option<&Prepared>,
        machine: &Machine<f64>,
        out: &mut Figures,
    ) -> Result<(), Error> {
        let Machine {
            mechanism: mech,
            threads,
        } = machine;
        // This setting's own P′, where the sweep changes the stitch.
        let own;
        let shared = match &self.own_stitch {
            Some((names, tension)) => {
                let unplanned = || {
                    Error::Stitch(crate::error::StitchError::new(
                        "stitch",
                        "this setting's stitch cannot be planned as the base setting's; sweep without the stitch's figures",
                    ))
                };
                let prepared = crate::eval::stitch_process::prepare_on(model, &self.params, self.phis.clone())?
                    .ok_or_else(unplanned)?;
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                self.stitch = StitchPlan::all(model, &prepared, &self.phis, threads.as_ref(), &names, *tension)
                    .ok_or_else(unplanned)?;
                own = prepared;
                Some(&own)
            }
            None => shared,
        };
        if let (Some(threads), Some(shared)) = (&threads, shared) {
            self.tensions(model, threads, shared)?;
        }
        if self.mu && !model.dyads.is_empty() {
            self.transmission_figures(model, mech, out)?;
        }
        if self.measures && !model.measure_names.is_empty() {
            self.measure_figures(model, mech, out)?;
        }
        if self.strokes {
            self.stroke_figures(model, opts, out)?;
        }
        if !self.stitch.is_empty() && shared.is_some() {
            self.stitch_figures(out);
        }
        Ok(())
    }

    /// The tension of every stitch thread whose path carries thread
    /// physics, with this setting's P' and compared positions where the
    /// regulator's window is computed: what `eval::stitch_process` reads.
    fn tensions(&mut self, model: &Model, threads: &Threads<f64>, shared: &Prepared) -> Result<(), Error> {
        if self.stitch.iter().all(|p| p.tension.is_none()) {
            return Ok(());
        }
        let physics = model.thread_physics(&self.params)?;
        let n = self.phis.len();
        let cz = shared.setup.cyclogram_zero_deg;
        for plan in &mut self.stitch {
            let (Some(tp), Some(pi)) = (&mut plan.tension, plan.path) else {
                continue;
            };
            let Some(ph) = physics.get(pi).and_then(Option::as_ref) else {
                tp.solved = None;
                continue;
            };
            let th = &shared.required.threads[tp.thread];
            let course = &mut self.courses[pi];
            if course.gaps_mm.is_empty() {
                course.extend(threads, &threads.paths[pi], &self.pose, &self.work, n);
            }
            course.keep_capstan(&threads.paths[pi].friction);
            let input = crate::eval::tension::PathInput {
                physics: ph,
                path: &threads.paths[pi],
                course,
            };
            let solved = crate::eval::tension::solve_thread(th, input, &self.phis, cz)?;
            if tp.computed {
                let (pprime, compared) =
                    crate::eval::stitch_process::computed_pprime(th, &solved, &self.phis, shared.phi0_deg, cz);
                let (mut hi, mut lo) = (f64::MIN, f64::MAX);
                for k in (0..n).filter(|&k| compared[k]) {
                    (hi, lo) = (hi.max(pprime[k]), lo.min(pprime[k]));
                }
                tp.count = compared.iter().filter(|&&c| c).count();
                tp.range = hi - lo;
                tp.weight = compared.iter().map(|&c| if c { 1.0 } else { 0.0 }).collect();
                tp.pprime = pprime;
            }
            tp.solved = Some(solved);
        }
        Ok(())
    }

    /// The take-up P of every path over the cycle (kept in `self.p`) and
    /// its largest and smallest value.
    fn take_up_figures(
        &mut self,
        mech: &Mechanism<f64>,
        threads: &Threads<f64>,
        out: &mut Figures,
    ) -> Result<(), Error> {
        let n = self.phis.len();
        // ξ(φ0) as `run_cycle` takes it (a pose of its own at φ0),
        // unless φ0 is on the grid: the same arithmetic there gives
        // the same bits.
        let k0 = self.phis.iter().position(|&p| p == threads.phi0_deg);
        if k0.is_none() {
            mech.reset_pose(&mut self.pose0, 1);
            mech.solve(&self.phi0, &mut self.pose0)?;
            threads
                .evaluate_into(&self.pose0, None, &mut self.work0)
                .map_err(|e| path_error(e, threads.phi0_deg))?;
        }
        if let Err(e) = threads.evaluate_into(&self.pose, None, &mut self.work) {
            // `run_cycle` reports a path that fails at φ0 first.
            if k0.is_some() {
                mech.reset_pose(&mut self.pose0, 1);
                mech.solve(&self.phi0, &mut self.pose0)?;
                threads
                    .evaluate_into(&self.pose0, None, &mut self.work0)
                    .map_err(|e| path_error(e, threads.phi0_deg))?;
            }
            let phi = self.phis[e.k];
            return Err(path_error(e, phi));
        }
        self.p.resize_with(threads.paths.len(), Vec::new);
        for (i, (path, track)) in threads.paths.iter().zip(&self.work.tracks).enumerate() {
            if !self.work.wants(i) {
                continue;
            }
            let xi0 = match k0 {
                Some(k) => track.xi_at_split(k),
                None => self.work0.tracks[i].xi_at_split(0),
            };
            let p = &mut self.p[i];
            p.clear();
            p.extend((0..n).map(|k| threads.convention.take_up(track.xi_at_split(k), xi0)));
            let pn = crate::eval::take_up_name(!track.eye_up.is_empty());
            let (lo, hi) =
                finite_extremes(p).map_err(|k| not_finite(&format!("{}.{pn}_mm", path.name), p[k], self.phis[k]))?;
            out.push(|| format!("{}.max_{pn}_mm", path.name), hi);
            out.push(|| format!("{}.min_{pn}_mm", path.name), lo);
        }
        Ok(())
    }

    /// The extremes of every transmission angle, overall and per dyad, and
    /// whether all stay in the band.
    fn transmission_figures(&mut self, model: &Model, mech: &Mechanism<f64>, out: &mut Figures) -> Result<(), Error> {
        // The angles' parts (y, x) only; atan2 at the extremes alone.
        let pose = &self.pose;
        per_phi_columns(
            &mut self.parts,
            &mut self.part_buf,
            model.dyads.len(),
            self.phis.len(),
            |k, b| mech.transmission_parts(pose, k, b),
        );
        let mut all_ok = true;
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        let first = out.vals.len();
        out.push(|| "mu.min_deg".into(), 0.0);
        out.push(|| "mu.max_deg".into(), 0.0);
        out.push(|| "mu.ok".into(), 0.0);
        for (d, v) in model.dyads.iter().zip(&self.parts) {
            let (mu_min, mu_max) = transmission_extremes_deg(v)
                .map_err(|(k, mu)| not_finite(&format!("mu_{}_deg", d.key), mu, self.phis[k]))?;
            all_ok &= mu_min >= crate::eval::MU_MIN_DEG && mu_max <= crate::eval::MU_MAX_DEG;
            lo = lo.min(mu_min);
            hi = hi.max(mu_max);
            out.push(|| format!("mu_{}.min_deg", d.key), mu_min);
            out.push(|| format!("mu_{}.max_deg", d.key), mu_max);
        }
        out.vals[first..first + 3].copy_from_slice(&[lo, hi, if all_ok { 1.0 } else { 0.0 }]);
        Ok(())
    }

    /// The range, smallest and largest value of every measure.
    fn measure_figures(&mut self, model: &Model, mech: &Mechanism<f64>, out: &mut Figures) -> Result<(), Error> {
        let pose = &self.pose;
        per_phi_columns(
            &mut self.cols,
            &mut self.buf,
            model.measure_names.len(),
            self.phis.len(),
            |k, b| mech.measures(pose, k, b),
        );
        for (name, v) in model.measure_names.iter().zip(&self.cols) {
            if let Some(k) = v.iter().position(|x| !x.is_finite()) {
                return Err(not_finite(&format!("{name}_mm"), v[k], self.phis[k]));
            }
            let (i0, i1) = crate::eval::extremes(v);
            out.push(|| format!("{name}.range_mm"), v[i1] - v[i0]);
            out.push(|| format!("{name}.min_mm"), v[i0]);
            out.push(|| format!("{name}.max_mm"), v[i1]);
        }
        Ok(())
    }

    /// The stroke of every tabulated point along each axis.
    fn stroke_figures(&self, model: &Model, opts: &CycleOptions, out: &mut Figures) -> Result<(), Error> {
        let points = opts.points.clone().unwrap_or_else(|| model.output_points.clone());
        let axes = if model.planar { 2 } else { 3 };
        for &pt in &points {
            for (c, axis) in ["x", "y", "z"].iter().enumerate().take(axes) {
                let (lo, hi) = self
                    .pose
                    .track(pt)
                    .iter()
                    .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v[c]), b.max(v[c])));
                if !(lo.is_finite() && hi.is_finite()) {
                    return Err(not_finite(
                        &format!("{}.{axis}_mm", model.point_names[pt]),
                        f64::NAN,
                        self.phis[0],
                    ));
                }
                out.push(|| format!("{}.{axis}_stroke_mm", model.point_names[pt]), hi - lo);
            }
        }
        Ok(())
    }

    /// Every stitch thread's largest P', checks, bound margin and match of
    /// P (from `self.p`) against P', then the mean and worst score.
    fn stitch_figures(&self, out: &mut Figures) {
        let mut scores = Vec::new();
        let mut all_ok = true;
        let mut any_checks = false;
        for plan in &self.stitch {
            let solved = plan.tension.as_ref().and_then(|t| t.solved.as_ref());
            // With the window computed, P' and the compared positions are
            // this setting's.
            let (pprime, weight, count, range) = match &plan.tension {
                Some(t) if t.computed && t.solved.is_some() => (&t.pprime, &t.weight, t.count, t.range),
                _ => (&plan.pprime, &plan.weight, plan.ks.len(), plan.range),
            };
            let max_pprime = match &plan.tension {
                Some(t) if t.computed && t.solved.is_some() => t.pprime.iter().cloned().fold(f64::MIN, f64::max),
                _ => plan.max_pprime_mm,
            };
            out.push(|| format!("{}.{}", plan.name, plan.max_pprime_figure), max_pprime);
            let tension_ok = match solved {
                Some(sol) => {
                    let tn = &sol.summary;
                    out.push(|| format!("{}.max_T_N", plan.name), tn.peak_n);
                    out.push(|| format!("{}.tension_margin", plan.name), tn.margin);
                    out.push(|| format!("{}.max_slack_mm", plan.name), tn.max_slack_mm);
                    out.push(|| format!("{}.set_slack_mm", plan.name), tn.set_slack_mm);
                    !self.checks
                        || crate::eval::tension::tension_checks(&plan.name, tn)
                            .iter()
                            .all(|c| c.ok)
                }
                None => true,
            };
            // As `eval::stitch`: the thread bound where P comes
            // closest to it, that the take-up gives thread while the stitch
            // draws it, and every check of the thread; only where a figure
            // reads them (the order of the figures stays the plan's).
            let margin = match (plan.path, &plan.bound) {
                (Some(pi), Some(bound)) if self.checks || self.margins => {
                    Some(crate::stitch::checks::bound_margin_mm(&self.p[pi], bound))
                }
                _ => None,
            };
            if self.checks && (plan.has_checks || margin.is_some()) {
                let gives_ok = plan.path.is_none_or(|pi| {
                    crate::stitch::checks::Given::of(&self.phis, &self.p[pi], pprime, plan.phi0_deg)
                        .is_none_or(|g| g.ok())
                });
                let ok = plan.fixed_checks_ok && tension_ok && gives_ok && margin.is_none_or(|m| m >= -1e-9);
                all_ok &= ok;
                any_checks = true;
                out.push(|| format!("{}.checks_ok", plan.name), if ok { 1.0 } else { 0.0 });
            }
            if let Some(m) = margin {
                out.push(|| format!("{}.bound_margin_mm", plan.name), m);
            }
            let Some(pi) = plan.path else { continue };
            if count == 0 {
                continue;
            }
            // As `stitch::mismatch::mismatch`: D = P − P' over the
            // compared positions, in order.
            let p = &self.p[pi];
            let rms = (crate::stitch::mismatch::sum_sq_diff(p, pprime, weight) / count as f64).sqrt();
            let mut max_abs = 0.0f64;
            for ((a, b), w) in p.iter().zip(pprime).zip(weight) {
                max_abs = max_abs.max((a - b).abs() * w);
            }
            if range > 1e-12 {
                let score = 100.0 * (1.0 - rms / range).max(0.0);
                out.push(|| format!("{}.score", plan.name), score);
                scores.push(score);
            }
            out.push(|| format!("{}.rms_D_mm", plan.name), rms);
            out.push(|| format!("{}.max_abs_D_mm", plan.name), max_abs);
        }
        if !scores.is_empty() {
            out.push(|| "score.mean".into(), scores.iter().sum::<f64>() / scores.len() as f64);
            out.push(|| "score.min".into(), scores.iter().cloned().fold(f64::MAX, f64::min));
        }
        if any_checks {
            out.push(|| "checks.ok".into(), if all_ok { 1.0 } else { 0.0 });
        }
    }
}

/// Which kinds of figures beside the take-up extremes are asked for.
struct Kinds {
    /// Per thread path, whether a figure of its P is asked for.
    paths: Vec<bool>,
    mu: bool,
    measures: bool,
    strokes: bool,
    checks: bool,
    margins: bool,
    stitch: bool,
    /// A figure of the thread's tension, or one that judges its checks.
    tension: bool,
}

impl Kinds {
    /// The kinds of the figures `names`, or `None` when one is of a kind
    /// the fast path does not compute.
    fn of(model: &Model, threads: Option<&Threads<f64>>, path_names: &[&str], names: &[String]) -> Option<Kinds> {
        let path_figure = |p: &str, i: usize, n: &str| {
            let pn = crate::eval::take_up_name(threads.is_some_and(|t| t.split_up[i].is_some()));
            n == format!("{p}.max_{pn}_mm") || n == format!("{p}.min_{pn}_mm")
        };
        let mut kinds = Kinds {
            paths: vec![false; path_names.len()],
            mu: false,
            measures: false,
            strokes: false,
            checks: false,
            margins: false,
            stitch: false,
            tension: false,
        };
        for n in names {
            let path_fig = path_names.iter().enumerate().position(|(i, p)| path_figure(p, i, n));
            if let Some(i) = path_fig {
                kinds.paths[i] = true;
            } else if n.starts_with("mu.") || n.starts_with("mu_") {
                kinds.mu = true;
            } else if n.ends_with("_stroke_mm") {
                kinds.strokes = true;
            } else if model.measure_names.iter().any(|m| {
                [".range_mm", ".min_mm", ".max_mm"]
                    .iter()
                    .any(|s| n == &format!("{m}{s}"))
            }) {
                kinds.measures = true;
            } else if n.starts_with("score.")
                || n == "checks.ok"
                || [
                    ".score",
                    ".rms_D_mm",
                    ".max_abs_D_mm",
                    ".max_Pprime_mm",
                    ".max_Pprime_B_mm",
                    ".checks_ok",
                    ".bound_margin_mm",
                    ".max_T_N",
                    ".tension_margin",
                    ".max_slack_mm",
                    ".set_slack_mm",
                ]
                .iter()
                .any(|s| n.ends_with(s))
            {
                let judges = n == "checks.ok" || n.ends_with(".checks_ok");
                kinds.stitch = true;
                kinds.checks |= judges;
                kinds.margins |= n.ends_with(".bound_margin_mm");
                kinds.tension |= judges
                    || [".max_T_N", ".tension_margin", ".max_slack_mm", ".set_slack_mm"]
                        .iter()
                        .any(|s| n.ends_with(s));
            } else {
                return None;
            }
        }
        Some(kinds)
    }
}

impl StitchPlan {
    /// The plan of every stitch thread from the shared P' (`prepared`, on
    /// the grid `phis`), or `None` when the fast path cannot reproduce the
    /// full cycle's figures for one. The thread's tension is solved per
    /// setting where the regulator's window is computed from it, or where
    /// `tension_figures` (a figure of the tension or of the checks) is
    /// asked for; otherwise no figure asked for reads it.
    fn all(
        model: &Model,
        prepared: &Prepared,
        phis: &[f64],
        threads: Option<&Threads<f64>>,
        path_names: &[&str],
        tension_figures: bool,
    ) -> Option<Vec<StitchPlan>> {
        if prepared.phis != phis {
            return None;
        }
        let computed = prepared.setup.spec.regulator == crate::stitch::spec::Regulator::Computed;
        // Which paths' threads have their tension solved each setting: those
        // with thread physics, where something asked for reads the tension.
        let solve_tension: Vec<bool> = if model.has_thread_physics() && (computed || tension_figures) {
            model
                .thread_physics(&model.defaults())
                .map(|ps| ps.iter().map(Option::is_some).collect())
                .unwrap_or_default()
        } else {
            Vec::new()
        };
        let n = phis.len();
        let setup = &prepared.setup;
        let fixed_checks = prepared.needle_checks();
        let mut plans = Vec::new();
        for (i, (th, path)) in prepared.required.threads.iter().zip(&setup.paths).enumerate() {
            let compared = &prepared.compared[i];
            let pprime = crate::eval::stitch_process::pprime_at_split(th, n);
            let ks: Vec<usize> = (0..n).filter(|&k| compared[k]).collect();
            let (hi, lo) = ks.iter().fold((f64::MIN, f64::MAX), |(hi, lo), &k| {
                (hi.max(pprime[k]), lo.min(pprime[k]))
            });
            let kmax = (0..n)
                .max_by(|&a, &b| pprime[a].total_cmp(&pprime[b]).then(b.cmp(&a)))
                .unwrap_or(0);
            let path = match path {
                Some(name) => Some(path_names.iter().position(|p| p == name)?),
                None => None,
            };
            // The full cycle compares a needle thread at B only when its
            // path is split there; the fast path takes that case alone.
            let at_b = th.travel_mm.is_some();
            if at_b && path.is_some_and(|i| threads.is_none_or(|t| t.split_up[i].is_none())) {
                return None;
            }
            let bound = match (path, &th.travel_mm, &th.loop_mm) {
                (Some(_), Some(s), Some(lp)) => Some(crate::stitch::checks::bound_curve(
                    phis,
                    &s[..n],
                    &lp[..n],
                    prepared.phi0_deg,
                )),
                _ => None,
            };
            let weight = compared.iter().map(|&c| if c { 1.0 } else { 0.0 }).collect();
            let mine: Vec<_> = fixed_checks.iter().filter(|c| c.thread == th.name).collect();
            let tension = path
                .filter(|&pi| solve_tension.get(pi).copied().unwrap_or(false))
                .map(|_| TensionPlan {
                    thread: i,
                    computed,
                    solved: None,
                    pprime: Vec::new(),
                    weight: Vec::new(),
                    count: 0,
                    range: 0.0,
                });
            plans.push(StitchPlan {
                name: th.name.clone(),
                path,
                max_pprime_figure: max_pprime_figure(at_b),
                max_pprime_mm: pprime[kmax],
                pprime,
                ks,
                weight,
                range: hi - lo,
                bound,
                phi0_deg: prepared.phi0_deg,
                has_checks: !mine.is_empty() || tension.is_some() || path.is_some(),
                fixed_checks_ok: mine.iter().all(|c| c.ok),
                tension,
            });
        }
        Some(plans)
    }
}

/// `cols[j][k]` = the j-th of `width` values `fill(k, buf)` gives at the
/// k-th φ, for k < n (the columns keep their buffers).
fn per_phi_columns<X: Copy>(
    cols: &mut Vec<Vec<X>>,
    buf: &mut Vec<X>,
    width: usize,
    n: usize,
    mut fill: impl FnMut(usize, &mut Vec<X>),
) {
    cols.resize_with(width, Vec::new);
    cols.iter_mut().for_each(Vec::clear);
    for k in 0..n {
        fill(k, buf);
        for (c, x) in cols.iter_mut().zip(buf.iter()) {
            c.push(*x);
        }
    }
}

/// Smallest and largest transmission angle over a cycle, degrees, from
/// its parts `(y, x)` (μ = atan2(y, x), [`crate::mechanism::Mechanism::transmission_parts`]).
/// μ falls as cos μ = x/|(x, y)| rises, so the extremes are found on that
/// key and atan2 is taken only where the key is within rounding of its
/// extreme: the values the cycle table gives. On an angle that is not a
/// finite number, its position and value.
fn transmission_extremes_deg(v: &[(f64, f64)]) -> Result<(f64, f64), (usize, f64)> {
    let mu_deg = |(y, x): (f64, f64)| y.angle_of(x).to_degrees();
    if !v.iter().all(|(y, x)| y.is_finite() && x.is_finite()) {
        // A part that is not finite: every angle, as the table does.
        let all: Vec<f64> = v.iter().map(|yx| mu_deg(*yx)).collect();
        if let Some(k) = all.iter().position(|x| !x.is_finite()) {
            return Err((k, all[k]));
        }
        let (i0, i1) = crate::eval::extremes(&all);
        return Ok((all[i0], all[i1]));
    }
    let key = |(y, x): (f64, f64)| {
        let r = (x * x + y * y).sqrt();
        if r > 0.0 { x / r } else { 1.0 }
    };
    let (key_hi, key_lo) = v
        .iter()
        .fold((f64::MIN, f64::MAX), |(h, l), yx| (h.max(key(*yx)), l.min(key(*yx))));
    const WITHIN: f64 = 1e-12;
    let (mut mu_min, mut mu_max) = (f64::MAX, f64::MIN);
    for yx in v {
        let c = key(*yx);
        if c >= key_hi - WITHIN {
            mu_min = mu_min.min(mu_deg(*yx));
        }
        if c <= key_lo + WITHIN {
            mu_max = mu_max.max(mu_deg(*yx));
        }
    }
    Ok((mu_min, mu_max))
}

/// A setting's figures in a fixed order: values every time, their names
/// only until they are known (the order depends on the model and the plan
/// alone, never on the values).
struct Figures {
    vals: Vec<f64>,
    names: Option<Vec<String>>,
}

impl Figures {
    #[inline]
    fn push(&mut self, name: impl FnOnce() -> String, value: f64) {
        self.vals.push(value);
        if let Some(n) = &mut self.names {
            n.push(name());
        }
    }
}

/// The smallest and largest of `v` (the values `eval::extremes` points
/// at), or the index of the first value that is not a finite number. One
/// pass without branches.
fn finite_extremes(v: &[f64]) -> Result<(f64, f64), usize> {
    let (mut lo, mut hi, mut nan) = (f64::MAX, f64::MIN, false);
    for &x in v {
        lo = if x < lo { x } else { lo };
        hi = if x > hi { x } else { hi };
        // NaN never wins a comparison: it is marked apart; ±∞ shows in lo, hi.
        nan |= x.is_nan();
    }
    if nan || !lo.is_finite() || !hi.is_finite() {
        return Err(v.iter().position(|x| !x.is_finite()).unwrap_or(0));
    }
    Ok((lo, hi))
}

/// Settings evaluated together before their rows go to the sink.
pub const CHUNK: usize = 4096;

/// Evaluates the settings `range` of `job` on all cores, handing rows to
/// `sink` in setting order, `CHUNK` at a time; `progress` is told how many
/// settings are done. Stops at the first error the sink returns. The sink
/// takes one chunk while the workers compute the next, and each worker keeps
/// one [`Evaluator`] for its share of a chunk.
pub fn run<E: Send>(
    job: SweepJob<'_>,
    range: std::ops::Range<usize>,
    mut sink: impl FnMut(&Row) -> Result<(), E> + Send,
    progress: impl Fn(usize) + Sync,
) -> Result<(), E> {
    let compute = |chunk: std::ops::Range<usize>| -> Vec<Row> {
        // At least 64 settings per piece of work: each piece sets up one
        // evaluator (its buffers grow on the first setting).
        chunk
            .into_par_iter()
            .with_min_len(64)
            .map_init(|| Evaluator::new(job), |ev, i| ev.evaluate(i))
            .collect()
    };
    let mut pending: Vec<Row> = Vec::new();
    let mut start = range.start;
    while start < range.end {
        let end = (start + CHUNK).min(range.end);
        let (rows, sunk) = rayon::join(|| compute(start..end), || pending.iter().try_for_each(&mut sink));
        sunk?;
        progress(rows.len());
        pending = rows;
        start = end;
    }
    pending.iter().try_for_each(&mut sink)
}
