//! The stitch process over a cycle: P'(φ) of every thread next to the
//! take-up P(φ) of the path it is compared with, and their mismatch
//! (`docs/stitch-formation.md` §5, §8).

use crate::error::StitchError;
use rayon::prelude::*;
use serde::Serialize;

use super::{Column, wrap_deg};
use crate::error::Error;
use crate::geometry::since_deg;
use crate::model::stitch_setup::StitchSetup;
use crate::model::{Model, Params};
use crate::stitch::checks::{Check, bound_curve, catch_and_stab, hook_clearance, takeup_gives, thread_bound};
use crate::stitch::mismatch::{Mismatch, mismatch};
use crate::stitch::required_take_up::required_take_up;
use crate::stitch::spec::{DEFAULT_REGULATOR_WIDTH_DEG, EventKind, Regulator, RequiredThread, StitchType, ThreadRole};
use crate::thread::SplitPoint;

use super::tension::{PathInput, Solved, solve_thread, tension_checks, tension_columns};

/// A moment of a thread's cyclogram, at the model's φ.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StitchEvent {
    pub name: String,
    pub phi_deg: f64,
    pub kind: EventKind,
    /// P' after minus P' before, mm (at a lock, with a regulator window:
    /// −ρ + σ_snap, the stitch's own thread being drawn in the window).
    pub jump_mm: f64,
}

/// One thread of the stitch: what it needs, and how the take-up gives it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StitchThreadSummary {
    pub thread: String,
    pub role: ThreadRole,
    /// The thread path P is taken from.
    pub path: Option<String>,
    /// Where P and P' are measured: B (a needle thread: the fixed point
    /// at the eye's top position, seed 004 §2.3) or the moving eye of a
    /// looper thread.
    pub split: SplitPoint,
    /// Contour of seed 004 §2.6.
    pub contour: u8,
    /// Thread per stitch by the contour formula, and as cut from the P'
    /// model at its lock (the two agree), mm.
    pub per_stitch_mm: f64,
    pub locked_mm: f64,
    /// The lock, model φ.
    pub lock_phi_deg: f64,
    /// ρ: thread released at the lock (the needle loop leaving the looper), mm.
    pub released_mm: f64,
    /// Where its per-stitch thread passes the regulator, model φ [from, to]
    /// deg (from in [0, 360), `to` may pass 360): left out of its metrics.
    /// Empty when the regulator passes it at the lock.
    pub regulator_windows_deg: Vec<[f64; 2]>,
    /// Whether those windows are computed from the thread's tension
    /// (otherwise assumed: `[stitch] regulator`).
    pub regulator_computed: bool,
    /// The largest P' at the split and where, mm and deg.
    pub max_pprime_mm: f64,
    pub phi_at_max_pprime_deg: f64,
    /// Needle threads: the largest P' measured at the moving eye, mm.
    pub max_pprime_eye_mm: Option<f64>,
    pub events: Vec<StitchEvent>,
    /// P − P' metrics (with a path).
    pub mismatch: Option<Mismatch>,
    /// The thread's tension over the cycle, when its path carries thread
    /// physics (`docs/thread-physics.md`).
    pub tension: Option<super::tension::ThreadTension>,
}

/// The stitch process of a cycle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StitchSummary {
    pub stitch_type: u16,
    pub m_mm: f64,
    pub t_mm: f64,
    /// The model's φ of the needle's BDC (φ_c = 0).
    pub cyclogram_zero_deg: f64,
    /// P' = 0 here, model φ.
    pub phi0_deg: f64,
    /// Where each thread's per-stitch length passes its tension regulator,
    /// in words, with how it was chosen (each thread's window:
    /// [`crate::stitch::spec::RequiredThread::regulator_window_deg`]).
    pub regulator: String,
    /// ε of the slack and strain intervals, mm.
    pub tolerance_mm: f64,
    pub threads: Vec<StitchThreadSummary>,
    /// The physical checks of every needle thread (`stitch::checks`).
    pub checks: Vec<Check>,
    /// Where the stitch model carries rules over from another stitch type.
    pub transfers: Vec<String>,
    /// Derived moments, model φ.
    pub moments: Vec<(String, f64)>,
    pub warnings: Vec<String>,
}

impl StitchThreadSummary {
    /// The column of its P′ at its split: `THR.Pprime_B_mm` for a needle
    /// thread, `THR.Pprime_mm` for a looper thread.
    pub fn pprime_column(&self) -> String {
        format!(
            "{}.{}",
            self.thread,
            if self.split == SplitPoint::B {
                "Pprime_B_mm"
            } else {
                "Pprime_mm"
            }
        )
    }
}

impl StitchSummary {
    /// Whether every physical check passes.
    pub fn checks_ok(&self) -> bool {
        self.checks.iter().all(|c| c.ok)
    }
}

/// Is model-φ `phi` inside the window [from, to] (which may wrap past 360°)?
pub(crate) fn in_window(phi: f64, w: [f64; 2]) -> bool {
    let (a, len) = (w[0].rem_euclid(360.0), (w[1] - w[0]).rem_euclid(360.0));
    (phi - a).rem_euclid(360.0) <= len
}

/// The stitch process of a model resolved for one φ grid: its setup and P'
/// of every thread. Depends on the parameters only through the stitch's
/// inputs (m, t, the organs' motions), so a study can compute it once for
/// many settings that leave those alone.
#[derive(Debug, Clone)]
pub struct Prepared {
    pub setup: StitchSetup,
    pub required: crate::stitch::spec::RequiredTakeUp,
    /// The model φ grid it was computed on, and φ0 (where P' = 0).
    pub phis: Vec<f64>,
    pub phi0_deg: f64,
    /// Each thread's regulator window, model φ [from, to] deg; `None` at
    /// the lock.
    pub windows_deg: Vec<Option<[f64; 2]>>,
    /// For each thread, whether each φ of the grid is compared (outside its
    /// regulator window).
    pub compared: Vec<Vec<bool>>,
}

impl Prepared {
    /// The catch clearance and stab checks of every needle thread: they
    /// depend on the stitch alone.
    pub fn needle_checks(&self) -> Vec<Check> {
        let from_c = |phi_c: f64| wrap_deg(phi_c + self.setup.cyclogram_zero_deg);
        self.required
            .threads
            .iter()
            .flat_map(|th| {
                let looper = th.needle_moments.map(|m| catch_and_stab(&th.name, &m, from_c));
                let hook = th.hook_moments.map(|m| hook_clearance(&th.name, &m, from_c));
                looper.into_iter().flatten().chain(hook)
            })
            .collect()
    }

    /// The regulator in words: each distinct window with its threads.
    pub fn regulator_words(&self) -> String {
        let mut windows: Vec<([f64; 2], Vec<&str>, ThreadRole)> = Vec::new();
        for (th, w) in self.required.threads.iter().zip(&self.windows_deg) {
            let Some(w) = *w else { continue };
            match windows
                .iter_mut()
                .find(|(v, ..)| (v[0] - w[0]).abs() < 1e-9 && (v[1] - w[1]).abs() < 1e-9)
            {
                Some((_, names, _)) => names.push(&th.name),
                None => windows.push((w, vec![&th.name], th.role)),
            }
        }
        if windows.is_empty() {
            return "each thread's stitch passes the regulator at its lock (nothing left out of the metrics)".into();
        }
        let parts: Vec<String> = windows
            .iter()
            .map(|([a, b], names, role)| {
                // The window's end as the turn reads it: 360° rather than 0°.
                let to = if *b > 360.0 + 1e-9 { wrap_deg(*b) } else { *b };
                let why = match self.setup.spec.regulator {
                    Regulator::BeforeTightening { width_deg } => {
                        let before = if *role == ThreadRole::Needle {
                            "the needle's TDC"
                        } else {
                            "the draw-in"
                        };
                        format!(
                            ", the last {width_deg}° before {before}{}",
                            if width_deg == DEFAULT_REGULATOR_WIDTH_DEG {
                                " (default)"
                            } else {
                                ""
                            }
                        )
                    }
                    _ => " (declared)".into(),
                };
                format!("{} φ = {a:.1}°…{to:.1}°{why}", names.join(", "))
            })
            .collect();
        format!(
            "{}: each stitch's thread is drawn through the regulator there, left out of the metrics",
            parts.join("; ")
        )
    }
}

/// Whether each φ of `phis` (model φ) is compared: outside the regulator
/// `window`, if any.
pub(crate) fn compared_outside(phis: &[f64], windows: &[[f64; 2]]) -> Vec<bool> {
    phis.iter()
        .map(|&p| !windows.iter().any(|&w| in_window(p, w)))
        .collect()
}

/// P' of the model's stitch process with `params` on the cycle grid of
/// `step_deg`; `None` when the model has no `[stitch]`.
pub fn prepare(model: &Model, params: &Params, step_deg: f64) -> Result<Option<Prepared>, Error> {
    super::check_options(&super::CycleOptions {
        step_deg,
        ..Default::default()
    })?;
    prepare_on(model, params, super::cycle_phis_deg(model.phi_start_deg(), step_deg))
}

/// [`prepare`] on any grid of model φ `phis` (a study's own sampling).
pub fn prepare_on(model: &Model, params: &Params, phis: Vec<f64>) -> Result<Option<Prepared>, Error> {
    let Some(setup) = model.stitch_setup(params)? else {
        return Ok(None);
    };
    prepare_setup(model, setup, phis)
}

/// [`prepare_on`] with the regulator's window assumed where the model
/// computes it from the thread's tension: the default window, the last 60°
/// before each thread's stitch is pulled tight. For a design that changes
/// the thread's path (a cam synthesised to give P'), whose target cannot
/// depend on the tension of the path it replaces.
pub fn prepare_assumed(model: &Model, params: &Params, phis: Vec<f64>) -> Result<Option<Prepared>, Error> {
    let Some(mut setup) = model.stitch_setup(params)? else {
        return Ok(None);
    };
    if setup.spec.regulator == Regulator::Computed {
        setup.spec.regulator = Regulator::default();
    }
    prepare_setup(model, setup, phis)
}

/// P' of `setup` on the model-φ grid `phis`.
fn prepare_setup(model: &Model, setup: StitchSetup, phis: Vec<f64>) -> Result<Option<Prepared>, Error> {
    let phi0_deg = model.take_up_phi0_deg();
    let to_c = |phi: f64| since_deg(phi, setup.cyclogram_zero_deg);
    // φ0 rides at the end of the grid, for S(φ0) of P'_B.
    let mut grid: Vec<f64> = phis.iter().map(|&p| to_c(p)).collect();
    grid.push(to_c(phi0_deg));
    let required = required_take_up(&setup.spec, &grid, to_c(phi0_deg))?;
    let windows_deg: Vec<Option<[f64; 2]>> = required
        .threads
        .iter()
        .map(|th| window_in_model_phi(th, setup.cyclogram_zero_deg))
        .collect();
    let compared = windows_deg
        .iter()
        .map(|w| compared_outside(&phis, w.as_slice()))
        .collect();
    Ok(Some(Prepared {
        setup,
        required,
        phis,
        phi0_deg,
        windows_deg,
        compared,
    }))
}

/// [`mismatch`] of `p` against `pprime` over a cycle of model φ `phis`,
/// with every angle it reports wrapped into [0°, 360°).
pub fn mismatch_on_cycle(
    phis: &[f64],
    p: &[f64],
    pprime: &[f64],
    compared: &[bool],
    eps_mm: f64,
    lag: bool,
) -> Option<Mismatch> {
    mismatch(phis, p, pprime, compared, eps_mm, lag).map(|mut m| {
        m.max_abs_d_at_deg = wrap_deg(m.max_abs_d_at_deg);
        for ivs in [&mut m.excess_intervals_deg, &mut m.deficit_intervals_deg] {
            for iv in ivs.iter_mut() {
                *iv = [wrap_deg(iv[0]), wrap_deg(iv[1])];
            }
            ivs.sort_by(|a, b| a[0].total_cmp(&b[0]));
        }
        m
    })
}

/// P' of a thread at its split on the first `n` positions of its grid:
/// for a needle thread at B, P'_B = P'_eye + S − S(φ0) (S(φ0) rides at
/// position `n`, as [`prepare`] lays the grid out); for a looper thread at
/// its eye.
pub fn pprime_at_split(th: &RequiredThread, n: usize) -> Vec<f64> {
    match &th.travel_mm {
        Some(s) => (0..n).map(|k| th.pprime_mm[k] + s[k] - s[n]).collect(),
        None => th.pprime_mm[..n].to_vec(),
    }
}

/// A thread's regulator window in the model's φ: [from, to] deg with from
/// in [0, 360).
pub fn window_in_model_phi(thread: &RequiredThread, cyclogram_zero_deg: f64) -> Option<[f64; 2]> {
    thread.regulator_window_deg.map(|[a, b]| {
        let from = wrap_deg(a + cyclogram_zero_deg);
        [from, from + (b - a)]
    })
}

/// Where the stitch model carries rules over from another stitch type.
fn transfers(ty: StitchType) -> Vec<String> {
    let source = format!(
        "the moments and period rules of {} §2.1 and Table 2 describe the 401 two-thread chain stitch",
        crate::references::cite(4)
    );
    match ty {
        StitchType::S301 => vec![format!(
            "{source}; the lockstitch takes its loop forming before the catch and the regulator's window from them \
             (the hook's loop and its cast-off are the lockstitch's own, docs/stitch-formation.md §13)"
        )],
        StitchType::S401 => Vec::new(),
        StitchType::S406 | StitchType::S407 => vec![format!(
            "{source}; they are applied to each needle of the {} (its catch and drop derived from the looper)",
            ty.number()
        )],
        StitchType::S503 | StitchType::S504 => vec![format!(
            "{source}; they are carried over to the {} overedge stitch (the 401 looper-thread events φ3 and φ5 become its \
             looper threads' stab and draw-in)",
            ty.number()
        )],
    }
}

/// What follows a stitch thread's name in the name of each column the
/// stitch process adds (`THREAD.SUFFIX`): its own (P′, η and γ),
/// D = P − P′ and the thread's tension ([`super::tension::tension_columns`]).
/// A test holds every preset's stitch columns to it.
pub const COLUMN_SUFFIXES: [&str; 16] = [
    "eta_B_mm",
    "Pprime_B_mm",
    "Pprime_eye_mm",
    "eta_mm",
    "Pprime_mm",
    "gamma_deg",
    "D_mm",
    "T_reg_N",
    "T_eye_N",
    "T_stitch_N",
    "T_max_N",
    "strain_max_pct",
    "drawn_mm",
    "slack_mm",
    "slack_stitch_mm",
    "spring_mm",
];

/// Whether the column pattern `pattern` can name a column of the stitch
/// process of a stitch whose threads may be named `threads`.
pub fn may_name_a_column(pattern: &str, threads: &[String]) -> bool {
    threads.iter().any(|t| {
        COLUMN_SUFFIXES
            .iter()
            .any(|s| super::glob_match(pattern, &format!("{t}.{s}")))
    })
}

/// A thread's columns: per needle thread (split at B) η_B, P'_B and
/// P'_eye; per looper thread η and P'; the needle loop's carry angle γ.
fn thread_columns(th: &RequiredThread, acc: &Accounting, n: usize, columns: &mut Vec<Column>) {
    let pprime = &acc.pprime_split[..];
    let push = |columns: &mut Vec<Column>, col: &str, values: Vec<f64>| {
        columns.push(Column {
            name: format!("{}.{col}", th.name),
            values,
        });
    };
    match &th.travel_mm {
        Some(s) => {
            push(columns, "eta_B_mm", (0..n).map(|k| th.eta_mm[k] + s[k]).collect());
            push(columns, "Pprime_B_mm", pprime.to_vec());
            push(columns, "Pprime_eye_mm", acc.pprime_eye[..n].to_vec());
        }
        None => {
            push(columns, "eta_mm", th.eta_mm[..n].to_vec());
            push(columns, "Pprime_mm", pprime.to_vec());
        }
    }
    if let Some(g) = &th.gamma_deg {
        push(columns, "gamma_deg", g[..n].to_vec());
    }
}

/// A thread's events at model φ (φ_c + `cyclogram_zero_deg`) with the jump
/// of η at each.
fn events(th: &RequiredThread, cyclogram_zero_deg: f64, drawn_apart: bool) -> Vec<StitchEvent> {
    // At the lock P' gives back the stitch's thread when the regulator
    // draws it apart from the lock (in an assumed or a computed window).
    let lock_back = if drawn_apart { th.per_stitch_mm } else { 0.0 };
    th.events
        .iter()
        .map(|e| StitchEvent {
            name: e.name.clone(),
            phi_deg: wrap_deg(e.phi_c_deg + cyclogram_zero_deg),
            kind: e.kind,
            jump_mm: e.eta_right_mm - e.eta_left_mm + if e.kind == EventKind::Lock { lock_back } else { 0.0 },
        })
        .collect()
}

/// Where a thread's stitch passes the regulator, and the P' and compared
/// positions that follow from it.
#[derive(Debug, Clone)]
struct Accounting {
    /// P' at the split (B for a needle thread) and at the moving eye (the
    /// first n positions).
    pprime_split: Vec<f64>,
    pprime_eye: Vec<f64>,
    /// Whether each φ is compared (no thread passes the regulator there).
    compared: Vec<bool>,
    windows: Vec<[f64; 2]>,
    computed: bool,
}

impl Accounting {
    /// The assumed accounting of `prepared` (`[stitch] regulator`).
    fn prepared(prepared: &Prepared, i: usize, n: usize) -> Accounting {
        let th = &prepared.required.threads[i];
        Accounting {
            pprime_split: pprime_at_split(th, n),
            pprime_eye: th.pprime_mm[..n].to_vec(),
            compared: prepared.compared[i].clone(),
            windows: prepared.windows_deg[i].into_iter().collect(),
            computed: false,
        }
    }

    /// Where the thread's tension draws the stitch's thread: P' = η − η(φ0)
    /// plus L_s·(H_L − w), w the share of the cycle's draw past the
    /// regulator since φ0 (§3.3 with the window computed), and the
    /// positions where thread passes left out. `th` was built at the lock
    /// (no window).
    fn computed(th: &RequiredThread, sol: &Solved, phis: &[f64], phi0_deg: f64, cz: f64) -> Accounting {
        let n = phis.len();
        let since = |phi: f64| since_deg(phi, phi0_deg);
        // The draw since φ0, in the cycle's order from φ0 (the step ending
        // at φ0 belongs to the end of the cycle).
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| since(phis[a]).total_cmp(&since(phis[b])));
        let steps = &sol.tensions.drawn_mm;
        let total = sol.summary.drawn_per_cycle_mm;
        let mut w = vec![0.0; n];
        let mut sum = 0.0;
        for (j, &k) in order.iter().enumerate() {
            if j > 0 || since(phis[k]) > 1e-9 {
                sum += steps[k];
            }
            w[k] = if total > 0.0 { (sum / total).min(1.0) } else { 0.0 };
        }
        let lock_since = match since(th.lock_deg + cz) {
            0.0 => 360.0,
            x => x,
        };
        let l_s = th.per_stitch_mm;
        let pprime_eye: Vec<f64> = (0..n)
            .map(|k| {
                let h_l = if since(phis[k]) >= lock_since { 1.0 } else { 0.0 };
                th.pprime_mm[k] + l_s * (h_l - w[k])
            })
            .collect();
        let pprime_split = match &th.travel_mm {
            Some(s) => (0..n).map(|k| pprime_eye[k] + s[k] - s[n]).collect(),
            None => pprime_eye.clone(),
        };
        Accounting {
            pprime_split,
            pprime_eye,
            compared: sol.passing.iter().map(|&p| !p).collect(),
            windows: sol.summary.regulator_windows_deg.clone(),
            computed: true,
        }
    }
}

/// A thread's P' at its split and the positions compared, with the
/// regulator's window computed from its tension `sol` (a sweep's fast path
/// reads its figures from these, as [`stitch_columns`] does).
pub(crate) fn computed_pprime(
    th: &RequiredThread,
    sol: &Solved,
    phis: &[f64],
    phi0_deg: f64,
    cz: f64,
) -> (Vec<f64>, Vec<bool>) {
    let a = Accounting::computed(th, sol, phis, phi0_deg, cz);
    (a.pprime_split, a.compared)
}

/// The regulator in words: each distinct window with its threads, computed
/// or assumed.
fn regulator_words(prepared: &Prepared, accounts: &[Accounting]) -> String {
    if !accounts.iter().any(|a| a.computed) {
        return prepared.regulator_words();
    }
    let parts: Vec<String> = prepared
        .required
        .threads
        .iter()
        .zip(accounts)
        .map(|(th, a)| {
            let ws: Vec<String> = a
                .windows
                .iter()
                .map(|[x, y]| {
                    let to = if *y > 360.0 + 1e-9 { wrap_deg(*y) } else { *y };
                    format!("{x:.0}°…{to:.0}°")
                })
                .collect();
            match (a.computed, ws.is_empty()) {
                (true, true) => format!("{} none (no thread passes)", th.name),
                (_, false) => format!("{} φ = {}", th.name, ws.join(", ")),
                (false, true) => format!("{} at the lock", th.name),
            }
        })
        .collect();
    format!(
        "{}: where each thread's tension draws thread through the regulator (computed), left out of the metrics",
        parts.join("; ")
    )
}

/// One thread's take-up P compared with its P': D = P − P', the mismatch,
/// and the checks of P: the thread bound where P is measured at B, and
/// that the take-up gives thread while the stitch draws it.
struct Compared {
    d_mm: Vec<f64>,
    mismatch: Option<Mismatch>,
    checks: Vec<Check>,
}

/// Compares thread `i` of `prepared`, whose P' at its split is
/// `pprime_split` ([`pprime_at_split`]), with the take-up of its `path` in
/// `columns`.
fn compare(
    prepared: &Prepared,
    i: usize,
    acc: &Accounting,
    path: &str,
    phis: &[f64],
    columns: &[Column],
    lean: bool,
) -> Result<Compared, Error> {
    let th = &prepared.required.threads[i];
    let pprime_split = &acc.pprime_split[..];
    let n = phis.len();
    let at_b = th.travel_mm.is_some();
    // The path's take-up at its split: B for a path that ends at this
    // needle's eye; a path split elsewhere is compared with P' at the
    // moving eye. A needle thread is measured at B: P'_B = P'_eye + S − S(φ0).
    let (p, pprime, p_at_b) = match columns.iter().find(|c| c.name == format!("{path}.P_B_mm")) {
        Some(c) if at_b => (&c.values, pprime_split, true),
        _ => {
            let p_name = format!("{path}.P_mm");
            let c = columns.iter().find(|c| c.name == p_name).ok_or_else(|| {
                Error::Stitch(StitchError::new(
                    format!("thread `{}`", th.name),
                    format!("the take-up column `{p_name}` of its path is missing"),
                ))
            })?;
            (&c.values, &acc.pprime_eye[..n], false)
        }
    };
    let d_mm = (0..n).map(|k| p[k] - pprime[k]).collect();
    let tolerance_mm = prepared.setup.tolerance_mm;
    let mismatch = mismatch_on_cycle(phis, p, pprime, &acc.compared, tolerance_mm, !lean);
    let bound = match (p_at_b, &th.travel_mm, &th.loop_mm) {
        (true, Some(s), Some(lp)) => {
            let curve = bound_curve(phis, &s[..n], &lp[..n], prepared.phi0_deg);
            Some(thread_bound(&th.name, phis, p, &curve, &lp[..n]))
        }
        _ => None,
    };
    let gives = takeup_gives(&th.name, phis, p, pprime, prepared.phi0_deg);
    let checks = bound.into_iter().chain([gives]).collect();
    Ok(Compared { d_mm, mismatch, checks })
}

/// Adds the stitch columns and returns the summary. Per needle thread THR
/// (split at B): `THR.eta_B_mm`, `THR.Pprime_B_mm`, `THR.Pprime_eye_mm`,
/// `THR.gamma_deg`; per looper thread: `THR.eta_mm`, `THR.Pprime_mm`; and
/// `THR.D_mm` = P − P' where the thread has a path. `phis` are the cycle's
/// model φ (uniform), the grid `prepared` was computed on.
pub(crate) fn stitch_columns(
    prepared: &Prepared,
    phis: &[f64],
    lean: bool,
    inputs: &[Option<PathInput<'_>>],
    columns: &mut Vec<Column>,
) -> Result<StitchSummary, Error> {
    if prepared.phis.len() != phis.len() || prepared.phis.first() != phis.first() {
        return Err(StitchError::new(
            "stitch process",
            "it was prepared for another φ grid; prepare it with the same step",
        )
        .into());
    }
    let (setup, req, phi0_deg) = (&prepared.setup, &prepared.required, prepared.phi0_deg);
    let from_c = |phi_c: f64| wrap_deg(phi_c + setup.cyclogram_zero_deg);
    let n = phis.len();
    // Each thread's tension stands alone: on every core.
    let solved: Vec<Option<Solved>> = req
        .threads
        .par_iter()
        .enumerate()
        .map(|(i, th)| {
            inputs
                .get(i)
                .copied()
                .flatten()
                .map(|input| solve_thread(th, input, phis, setup.cyclogram_zero_deg))
                .transpose()
        })
        .collect::<Result<_, Error>>()?;
    // Where each thread's stitch passes the regulator: computed from its
    // tension, or as prepared.
    let accounts: Vec<Accounting> = req
        .threads
        .iter()
        .enumerate()
        .map(|(i, th)| match (&solved[i], setup.spec.regulator) {
            (Some(sol), Regulator::Computed) => Accounting::computed(th, sol, phis, phi0_deg, setup.cyclogram_zero_deg),
            _ => Accounting::prepared(prepared, i, n),
        })
        .collect();
    // Each thread's comparison with its path stands alone (a best lag is
    // three FFTs of the cycle): on every core, read from the path columns.
    let compared_threads: Vec<Option<Compared>> = accounts
        .par_iter()
        .zip(&setup.paths)
        .enumerate()
        .map(|(i, (acc, path))| {
            path.as_ref()
                .map(|path| compare(prepared, i, acc, path, phis, columns, lean))
                .transpose()
        })
        .collect::<Result<_, Error>>()?;
    let mut threads = Vec::new();
    let mut checks = Vec::new();
    let needle_checks = prepared.needle_checks();
    let each = req
        .threads
        .iter()
        .zip(&setup.paths)
        .zip(&accounts)
        .zip(compared_threads);
    for (i, (((th, path), acc), c)) in each.enumerate() {
        let name = &th.name;
        let at_b = th.travel_mm.is_some();
        let split = if at_b { SplitPoint::B } else { SplitPoint::Eye };
        let pprime = &acc.pprime_split;
        thread_columns(th, acc, n, columns);
        let mut m = None;
        if let Some(c) = c {
            columns.push(Column {
                name: format!("{name}.D_mm"),
                values: c.d_mm,
            });
            m = c.mismatch;
            checks.extend(c.checks);
        }
        checks.extend(needle_checks.iter().filter(|c| &c.thread == name).cloned());
        let tension = solved[i].as_ref().map(|sol| {
            tension_columns(name, sol, sol.summary.ea_n, columns);
            checks.extend(tension_checks(name, &sol.summary));
            sol.summary.clone()
        });
        let kmax = (0..n)
            .max_by(|&a, &b| pprime[a].total_cmp(&pprime[b]).then(b.cmp(&a)))
            .unwrap_or(0);
        threads.push(StitchThreadSummary {
            thread: name.clone(),
            role: th.role,
            path: path.clone(),
            split,
            contour: th.contour,
            per_stitch_mm: th.per_stitch_mm,
            locked_mm: th.cut_mm,
            lock_phi_deg: from_c(th.lock_deg),
            released_mm: th.released_mm,
            regulator_windows_deg: acc.windows.clone(),
            regulator_computed: acc.computed,
            max_pprime_mm: pprime[kmax],
            phi_at_max_pprime_deg: wrap_deg(phis[kmax]),
            max_pprime_eye_mm: at_b.then(|| acc.pprime_eye[..n].iter().cloned().fold(f64::MIN, f64::max)),
            events: events(th, setup.cyclogram_zero_deg, !acc.windows.is_empty()),
            mismatch: m,
            tension,
        });
    }
    Ok(StitchSummary {
        stitch_type: setup.spec.stitch_type.number(),
        m_mm: setup.spec.m_mm,
        t_mm: setup.spec.t_mm,
        cyclogram_zero_deg: setup.cyclogram_zero_deg,
        phi0_deg: wrap_deg(phi0_deg),
        regulator: regulator_words(prepared, &accounts),
        tolerance_mm: setup.tolerance_mm,
        threads,
        checks,
        transfers: transfers(setup.spec.stitch_type),
        moments: req.moments.iter().map(|(s, p)| (s.clone(), from_c(*p))).collect(),
        warnings: req.warnings.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::in_window;

    #[test]
    fn windows_may_wrap() {
        assert!(in_window(10.0, [350.0, 20.0]));
        assert!(in_window(355.0, [350.0, 20.0]));
        assert!(!in_window(30.0, [350.0, 20.0]));
        assert!(in_window(100.0, [90.0, 120.0]));
        assert!(!in_window(89.0, [90.0, 120.0]));
    }
}
