//! The thread's tension over a cycle (`thread::tension`,
//! `docs/thread-physics.md`) for every stitch thread whose path carries
//! thread physics: the solver's course built from the path's geometry and
//! the stitch's consumption contour, and the columns, summary and checks
//! read off the periodic steady state.

use serde::Serialize;

use super::paths::PathCourse;
use super::{Column, wrap_deg};
use crate::error::{Error, ThreadError};
use crate::geometry::since_deg;
use crate::mechanism::Phi;
use crate::model::{Machine, Model, Params};
use crate::stitch::checks::Check;
use crate::stitch::spec::RequiredThread;
use crate::thread::tension::{Chain, CheckSpring, Course, Tensions, ThreadPhysics, solve};
use crate::thread::{ThreadPath, ThreadWork, capstan_factor};

/// The least breaking margin (breaking force over the peak tension) the
/// check `tension_margin` asks for: what the published figures imply for
/// the finest industrial thread, tex 20 spun polyester breaking at 6.7 N
/// against needle-thread peaks of about 2 N while sewing (Mori & Niwa;
/// `docs/thread-physics.md`); tex 30 at 10.5 N has 5.
pub const TENSION_MARGIN_MIN: f64 = 3.0;

/// The largest slack loop the check `slack_loop` allows, mm: see
/// `docs/thread-physics.md` §3.
pub const SLACK_LOOP_MAX_MM: f64 = 10.0;

/// The most slack the check `stitch_set` allows between the regulator and
/// the stitch when the stitch is pulled tight, mm: see
/// `docs/thread-physics.md` §3.
pub const SET_SLACK_MAX_MM: f64 = 0.5;

/// Thread passing the regulator in a step by more than this counts as a
/// draw, mm (the solver balances to about 1e-9 mm).
const DRAW_MM: f64 = 1e-6;

/// A thread's tension over the cycle: the `tension` object of a stitch
/// thread in `match --format json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ThreadTension {
    /// The thread sewn, in words (`[thread.physics] thread`).
    pub material: Option<String>,
    /// Axial stiffness EA, breaking force and the regulator's hold, N.
    #[serde(rename = "ea_N")]
    pub ea_n: f64,
    #[serde(rename = "breaking_N")]
    pub breaking_n: f64,
    #[serde(rename = "regulator_N")]
    pub regulator_n: f64,
    /// The largest tension anywhere on the thread over the cycle, N, where
    /// (model φ, deg) and on which span (`G3_1–T1_1`, `N_1–stitch`).
    #[serde(rename = "peak_N")]
    pub peak_n: f64,
    pub peak_at_deg: f64,
    pub peak_span: String,
    /// Breaking force over the peak.
    pub margin: f64,
    /// The tension arriving at the eye: its least and largest, N.
    #[serde(rename = "eye_N")]
    pub eye_n: [f64; 2],
    /// Thread drawn past the regulator per cycle (unstretched), mm.
    pub drawn_per_cycle_mm: f64,
    /// The strain the finished stitch keeps (its thread's when it is
    /// pulled tight; the thread does not relax there, docs §3).
    pub lock_strain: f64,
    /// The thread one stitch consumes, mm: `drawn_per_cycle_mm · (1 +
    /// lock_strain)` equals it in the steady state.
    pub per_stitch_mm: f64,
    /// Where thread passes the regulator, model φ [from, to] deg (from in
    /// [0, 360), `to` may pass 360).
    pub regulator_windows_deg: Vec<[f64; 2]>,
    /// The largest slack loop on the path from the regulator to the eye
    /// (thread beyond the guides' reach that no check spring holds, where
    /// nothing controls it) and where, mm and deg.
    pub max_slack_mm: f64,
    pub max_slack_at_deg: f64,
    /// The largest slack below the eye, in the stitch's own contour (the
    /// loop released at the drop, which the stitch uses up), mm.
    pub max_stitch_slack_mm: f64,
    /// The least slack between the regulator and the stitch (path and
    /// stitch) from the release of the stitch's loop, past the moment the
    /// stitch is complete, until the needle enters the material for the
    /// next stitch (a looper thread: at its lock), and where,
    /// mm and deg: the take-up pulls the finished stitch tight there, or
    /// leaves it loose by this much.
    pub set_slack_mm: f64,
    pub set_at_deg: f64,
    /// The check spring, when the path has one.
    pub spring: Option<SpringSummary>,
    /// Cycles run to the periodic steady state, whether it settled, and the
    /// largest change of the state over the last cycle (mm).
    pub cycles: usize,
    pub settled: bool,
    pub change_mm: f64,
}

/// What a check spring did over the cycle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpringSummary {
    /// The node it follows.
    pub after: String,
    /// Its store, mm, and the tension at the start and end of its travel, N.
    pub take_up_mm: f64,
    #[serde(rename = "force_N")]
    pub force_n: [f64; 2],
    /// The most thread it gave out of its store, mm.
    pub max_travel_mm: f64,
    /// Thread it still held when thread first passed the regulator in a
    /// window, mm (0: it had reached the end of its travel, the makers'
    /// pull test); 0 when no thread passes.
    pub held_at_slip_mm: f64,
}

/// A stitch thread's tension, solved.
#[derive(Debug, Clone)]
pub struct Solved {
    pub summary: ThreadTension,
    pub tensions: Tensions,
    /// Thread drawn past the regulator at each φ since the grid's start
    /// (the draw of the step ending there included), mm.
    pub drawn_mm: Vec<f64>,
    /// Whether thread passes the regulator in the step ending at each φ.
    pub passing: Vec<bool>,
}

/// What a thread's tension is solved from besides its stitch.
#[derive(Debug, Clone, Copy)]
pub struct PathInput<'a> {
    pub physics: &'a ThreadPhysics,
    pub path: &'a ThreadPath,
    pub course: &'a PathCourse,
}

/// The solver's inputs for one stitch thread over a cycle, owned: the
/// chain and its course ([`Course`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TensionCourse {
    pub chain: Chain,
    /// n × S reaches, n × (S − 1) capstan factors and holds.
    pub len_mm: Vec<f64>,
    pub factor: Vec<f64>,
    pub hold_n: Vec<f64>,
    pub set_k: usize,
    pub set_mm: f64,
    /// Where the take-up may pull the finished stitch tight: the grid
    /// positions from the release (the lock) past the stitch's completion
    /// up to the needle's next entry into the material (a looper thread:
    /// its lock alone), in order.
    pub set_ks: Vec<usize>,
}

impl TensionCourse {
    /// The course as the solver reads it.
    pub fn course(&self) -> Course<'_> {
        Course {
            len_mm: &self.len_mm,
            factor: &self.factor,
            hold_n: &self.hold_n,
            set_k: self.set_k,
            set_mm: self.set_mm,
        }
    }
}

/// The course of the stitch thread `th` fed through `input` over the
/// model-φ grid `phis` (uniform, one cycle; `th` computed on it, cyclogram
/// zero `cz`).
pub fn tension_course(
    th: &RequiredThread,
    input: PathInput<'_>,
    phis: &[f64],
    cz: f64,
) -> Result<TensionCourse, Error> {
    let PathInput { physics, path, course } = input;
    let n = phis.len();
    let nodes = path.nodes.len();
    let s = nodes; // the path's node gaps and the stitch
    if course.gaps_mm.len() != n * (nodes - 1) || course.wraps_rad.len() != n * nodes || th.eta_mm.len() < n {
        return Err(Error::Internal(format!(
            "the course of path `{}` does not fit the cycle's {n} positions",
            path.name
        )));
    }
    let (lock, tight) = (th.lock_deg + cz, th.tight_deg + cz);
    let l_s = th.cut_mm;
    // Between the lock and the moment the stitch is pulled tight the
    // finished stitch's thread is still the stitch's (its final geometry):
    // the contour to the newest anchor plus L_s.
    let open_span = since_deg(tight, lock);
    let unset = |phi: f64| since_deg(phi, lock) < open_span;
    let set_k = (0..n)
        .min_by(|&a, &b| {
            let d = |k: usize| since_deg(phis[k], tight);
            d(a).total_cmp(&d(b))
        })
        .unwrap_or(0);
    // The first position at or after φ: the contour there is the one just
    // after an event on it.
    let from = |phi: f64| {
        (0..n)
            .min_by(|&a, &b| {
                let d = |k: usize| since_deg(phis[k], phi);
                d(a).total_cmp(&d(b))
            })
            .unwrap_or(0)
    };
    // A needle thread's finished stitch can be pulled tight from the release
    // of its loop (the lock), past the moment its stitch is complete (TDC),
    // until the needle takes the next stitch's thread into the material; a
    // looper thread's at its lock.
    let lock_k = from(lock);
    let set_ks: Vec<usize> = match &th.eye_in_material {
        Some(inside) if inside.len() >= n && th.tight_deg != th.lock_deg => {
            let mut ks = Vec::new();
            let mut past_tight = false;
            for j in 0..n {
                let k = (lock_k + j) % n;
                past_tight |= k == set_k;
                if past_tight && inside[k] && k != set_k {
                    break;
                }
                ks.push(k);
            }
            ks
        }
        _ => vec![lock_k],
    };
    let mut len_mm = Vec::with_capacity(n * s);
    let mut factor = Vec::with_capacity(n * (s - 1));
    let mut hold_n = vec![0.0; n * (s - 1)];
    // The eye's capstan factor where the thread turns back up through it.
    let eye_factor = capstan_factor(path.friction[nodes - 1], std::f64::consts::PI);
    for k in 0..n {
        len_mm.extend_from_slice(&course.gaps_mm[k * (nodes - 1)..(k + 1) * (nodes - 1)]);
        len_mm.push(th.eta_mm[k] + if unset(phis[k]) { l_s } else { 0.0 });
        // The guides between the regulator and the eye…
        match course.kept_capstan(&path.friction, k) {
            Some(kept) => factor.extend_from_slice(kept),
            None => {
                for j in 1..nodes - 1 {
                    factor.push(capstan_factor(path.friction[j], course.wraps_rad[k * nodes + j]));
                }
            }
        }
        // …and the eye: the thread turns back up through it toward the
        // stitch while the eye is in the material, and runs on down to the
        // material above it (a looper's eye: no turn).
        let in_material = th.eye_in_material.as_ref().is_some_and(|e| e[k]);
        factor.push(if in_material { eye_factor } else { 1.0 });
        for c in &physics.clamps {
            hold_n[k * (s - 1) + c.node - 1] = c.hold_at(phis[k]);
        }
    }
    Ok(TensionCourse {
        chain: Chain {
            ea_n: physics.ea_n,
            pass_n: physics.regulator_n,
            spring: physics.spring.map(|sp| CheckSpring {
                span: sp.node,
                take_up_mm: sp.take_up_mm,
                force_n: sp.force_n,
            }),
        },
        len_mm,
        factor,
        hold_n,
        set_k,
        set_mm: l_s,
        set_ks,
    })
}

/// A φ step coarser than this, deg, is named where the thread's balance
/// fails: the balance is followed step by step, and the stitch's events
/// last a few degrees (docs/thread-physics.md §5).
const COARSE_STEP_DEG: f64 = 5.0;

/// Solves the tension of the stitch thread `th` fed through `input` over
/// the model-φ grid `phis` ([`tension_course`]).
pub fn solve_thread(th: &RequiredThread, input: PathInput<'_>, phis: &[f64], cz: f64) -> Result<Solved, Error> {
    let tc = tension_course(th, input, phis, cz)?;
    let tensions = solve(&tc.chain, &tc.course()).map_err(|e| {
        // Over coarse steps the balance jumps across what happens between.
        let step_deg = phis.get(1).map_or(0.0, |p| p - phis[0]);
        let help = (step_deg > COARSE_STEP_DEG).then(|| {
            format!(
                "at a φ step of {step_deg:.3}° the thread's balance is followed in jumps past what happens between steps: a finer step, such as the default 1°, follows it"
            )
        });
        Error::Thread(ThreadError {
            path: input.path.name.clone(),
            phi_deg: Some(wrap_deg(phis[e.k.min(phis.len() - 1)])),
            message: e.message,
            help,
        })
    })?;
    Ok(read_off(th, input.physics, input.path, phis, tensions, &tc.set_ks))
}

/// The tension course of every stitch thread of `model` with `params` whose
/// path carries thread physics, on the cycle grid of `step_deg`, with the
/// thread's name: what [`solve_thread`] solves in a cycle, for a study or a
/// benchmark that runs the solver alone.
pub fn courses(model: &Model, params: &Params, step_deg: f64) -> Result<Vec<(String, TensionCourse)>, Error> {
    let Some(prepared) = super::stitch_process::prepare(model, params, step_deg)? else {
        return Ok(Vec::new());
    };
    let Machine {
        mechanism: mech,
        threads,
    } = model.machine::<f64>(params)?;
    let Some(threads) = threads else { return Ok(Vec::new()) };
    let phis = &prepared.phis;
    let mut pose = mech.new_pose(phis.len());
    mech.solve(&Phi::table(phis), &mut pose)?;
    let mut work = ThreadWork::default();
    threads.evaluate_into(&pose, None, &mut work).map_err(|e| {
        let phi = phis[e.k];
        super::path_error(e, phi)
    })?;
    let physics = model.thread_physics(params)?;
    let mut out = Vec::new();
    for (th, name) in prepared.required.threads.iter().zip(&prepared.setup.paths) {
        let Some(i) = threads.paths.iter().position(|p| Some(&p.name) == name.as_ref()) else {
            continue;
        };
        let Some(ph) = physics.get(i).and_then(Option::as_ref) else {
            continue;
        };
        let mut course = PathCourse::default();
        course.extend(&threads, &threads.paths[i], &pose, &work, phis.len());
        let input = PathInput {
            physics: ph,
            path: &threads.paths[i],
            course: &course,
        };
        out.push((
            th.name.clone(),
            tension_course(th, input, phis, prepared.setup.cyclogram_zero_deg)?,
        ));
    }
    Ok(out)
}

/// The summary and the per-φ series of a solved thread.
fn read_off(
    th: &RequiredThread,
    physics: &ThreadPhysics,
    path: &ThreadPath,
    phis: &[f64],
    t: Tensions,
    set_ks: &[usize],
) -> Solved {
    let n = phis.len();
    let s = t.spans;
    let span_name = |i: usize| {
        if i + 1 == s {
            format!("{}–stitch", path.node_names[s - 1])
        } else {
            format!("{}–{}", path.node_names[i], path.node_names[i + 1])
        }
    };
    let (mut peak, mut peak_k, mut peak_i) = (0.0f64, 0, 0);
    for k in 0..n {
        for i in 0..s {
            let v = t.tension(k, i);
            if v > peak {
                (peak, peak_k, peak_i) = (v, k, i);
            }
        }
    }
    let eye = (0..n).map(|k| t.tension(k, s - 2));
    let eye_n = [eye.clone().fold(f64::MAX, f64::min), eye.fold(0.0, f64::max)];
    // The path's slack: every span but the stitch's.
    let slack = |k: usize| t.slack_mm[k * s..(k + 1) * s - 1].iter().sum::<f64>();
    let slack_k = (0..n).max_by(|&a, &b| slack(a).total_cmp(&slack(b))).unwrap_or(0);
    let stitch_slack = (0..n).map(|k| t.slack_mm[k * s + s - 1]).fold(0.0, f64::max);
    // The tightest the thread runs from the regulator to the stitch while
    // the take-up may set the stitch.
    let total_slack = |k: usize| t.slack_mm[k * s..(k + 1) * s].iter().sum::<f64>();
    let set_k = set_ks
        .iter()
        .copied()
        .min_by(|&a, &b| total_slack(a).total_cmp(&total_slack(b)))
        .unwrap_or(0);
    let passing: Vec<bool> = t.drawn_mm.iter().map(|&d| d > DRAW_MM).collect();
    let windows = windows(phis, &passing);
    let mut drawn = Vec::with_capacity(n);
    let mut total = 0.0;
    for d in &t.drawn_mm {
        total += d;
        drawn.push(total);
    }
    let spring = physics.spring.map(|sp| {
        // The first φ of each window: what the spring still held there.
        let held = (0..n)
            .filter(|&k| passing[k] && !passing[if k == 0 { n - 1 } else { k - 1 }])
            .map(|k| sp.take_up_mm - t.spring_mm[k])
            .fold(0.0, f64::max);
        SpringSummary {
            after: path.node_names[sp.node].clone(),
            take_up_mm: sp.take_up_mm,
            force_n: sp.force_n,
            max_travel_mm: t.spring_mm.iter().cloned().fold(0.0, f64::max),
            held_at_slip_mm: held,
        }
    });
    let summary = ThreadTension {
        material: physics.thread.clone(),
        ea_n: physics.ea_n,
        breaking_n: physics.breaking_n,
        regulator_n: physics.regulator_n,
        peak_n: peak,
        peak_at_deg: wrap_deg(phis[peak_k]),
        peak_span: span_name(peak_i),
        margin: if peak > 0.0 {
            physics.breaking_n / peak
        } else {
            f64::INFINITY
        },
        eye_n,
        drawn_per_cycle_mm: t.drawn_per_cycle_mm,
        lock_strain: t.lock_strain,
        per_stitch_mm: th.per_stitch_mm,
        regulator_windows_deg: windows,
        max_slack_mm: slack(slack_k),
        max_slack_at_deg: wrap_deg(phis[slack_k]),
        max_stitch_slack_mm: stitch_slack,
        set_slack_mm: total_slack(set_k),
        set_at_deg: wrap_deg(phis[set_k]),
        spring,
        cycles: t.cycles,
        settled: t.settled,
        change_mm: t.change_mm,
    };
    Solved {
        summary,
        tensions: t,
        drawn_mm: drawn,
        passing,
    }
}

/// The stretches of the grid where thread passes (in the step ending at
/// φ_k), as [from, to] model φ of their first and last positions, from in
/// [0, 360); a stretch through the grid's end that goes on at its start is
/// one. A position is inside a stretch exactly when thread passes there, so
/// the positions a match leaves out are the stretches'.
fn windows(phis: &[f64], passing: &[bool]) -> Vec<[f64; 2]> {
    let n = phis.len();
    if n == 0 || !passing.iter().any(|&p| p) {
        return Vec::new();
    }
    let step = if n > 1 { phis[1] - phis[0] } else { 360.0 };
    if passing.iter().all(|&p| p) {
        let a = wrap_deg(phis[0]);
        return vec![[a, a + 360.0 - step]];
    }
    // Start where a stretch begins, so none is cut by the grid's end.
    let first = (0..n).find(|&k| passing[k] && !passing[(k + n - 1) % n]).unwrap_or(0);
    let mut out = Vec::new();
    let mut from: Option<f64> = None;
    for j in 0..=n {
        let k = (first + j) % n;
        // φ unwrapped from the first stretch's start.
        let phi = phis[first] + j as f64 * step;
        match (j < n && passing[k], from) {
            (true, None) => from = Some(phi),
            (false, Some(a)) => {
                out.push([a, phi - step]);
                from = None;
            }
            _ => {}
        }
    }
    out.into_iter()
        .map(|[a, b]| {
            let w = wrap_deg(a);
            [w, w + (b - a)]
        })
        .collect()
}

/// A thread's tension columns: `THR.T_reg_N` (just past the regulator),
/// `THR.T_eye_N` (arriving at the eye), `THR.T_stitch_N` (in the stitch),
/// `THR.T_max_N` (the largest on the thread), `THR.strain_max_pct`,
/// `THR.drawn_mm` (past the regulator since the cycle's start),
/// `THR.slack_mm` (the slack loop on the path to the eye),
/// `THR.slack_stitch_mm` (slack below the eye) and, with a check spring,
/// `THR.spring_mm` (the thread it has given out of its store).
pub fn tension_columns(thread: &str, solved: &Solved, ea_n: f64, columns: &mut Vec<Column>) {
    let t = &solved.tensions;
    let (n, s) = (solved.drawn_mm.len(), t.spans);
    let mut push = |col: &str, values: Vec<f64>| {
        columns.push(Column {
            name: format!("{thread}.{col}"),
            values,
        })
    };
    let row_max = |k: usize| t.tension_n[k * s..(k + 1) * s].iter().cloned().fold(0.0, f64::max);
    push("T_reg_N", (0..n).map(|k| t.tension(k, 0)).collect());
    push("T_eye_N", (0..n).map(|k| t.tension(k, s - 2)).collect());
    push("T_stitch_N", (0..n).map(|k| t.tension(k, s - 1)).collect());
    push("T_max_N", (0..n).map(row_max).collect());
    push("strain_max_pct", (0..n).map(|k| 100.0 * row_max(k) / ea_n).collect());
    push("drawn_mm", solved.drawn_mm.clone());
    push(
        "slack_mm",
        (0..n)
            .map(|k| t.slack_mm[k * s..(k + 1) * s - 1].iter().sum())
            .collect(),
    );
    push("slack_stitch_mm", (0..n).map(|k| t.slack_mm[k * s + s - 1]).collect());
    if !t.spring_mm.is_empty() {
        push("spring_mm", t.spring_mm.clone());
    }
}

/// The checks of a thread's tension: `tension_margin`, `slack_loop` and
/// `spring_before_slip`.
pub fn tension_checks(thread: &str, t: &ThreadTension) -> [Check; 4] {
    let check = |name, ok, value, limit, unit, at_deg, message| Check {
        name,
        thread: thread.to_string(),
        ok,
        value,
        limit,
        unit,
        at_deg,
        message,
    };
    let margin_ok = t.margin >= TENSION_MARGIN_MIN;
    let margin = check(
        "tension_margin",
        margin_ok,
        t.margin.min(1e9),
        [Some(TENSION_MARGIN_MIN), None],
        "1",
        t.peak_at_deg,
        if margin_ok {
            format!(
                "the thread's tension peaks at {:.2} N at φ = {:.1}° ({}), {:.1} times short of its {:.1} N breaking force \
                 (at least {TENSION_MARGIN_MIN} wanted)",
                t.peak_n, t.peak_at_deg, t.peak_span, t.margin, t.breaking_n
            )
        } else {
            format!(
                "the thread's tension peaks at {:.2} N at φ = {:.1}° ({}): only {:.1} times short of its {:.1} N breaking force, \
                 under the {TENSION_MARGIN_MIN} the thread makers' figures leave; expect breaks: lower the regulator's hold, \
                 give the take-up less to draw there, or sew a stronger thread",
                t.peak_n, t.peak_at_deg, t.peak_span, t.margin, t.breaking_n
            )
        },
    );
    let slack_ok = t.max_slack_mm <= SLACK_LOOP_MAX_MM;
    let slack = check(
        "slack_loop",
        slack_ok,
        t.max_slack_mm,
        [None, Some(SLACK_LOOP_MAX_MM)],
        "mm",
        t.max_slack_at_deg,
        if slack_ok {
            format!(
                "the largest slack loop between the regulator and the eye is {:.2} mm, at φ = {:.1}° (at most \
                 {SLACK_LOOP_MAX_MM} mm wanted)",
                t.max_slack_mm, t.max_slack_at_deg
            )
        } else {
            format!(
                "{:.2} mm of thread hangs slack between the regulator and the eye at φ = {:.1}°, more than \
                 {SLACK_LOOP_MAX_MM} mm: a loop no guide controls, that can catch and make loose stitches; the take-up \
                 gives more than the stitch takes there",
                t.max_slack_mm, t.max_slack_at_deg
            )
        },
    );
    let set_ok = t.set_slack_mm <= SET_SLACK_MAX_MM;
    let set = check(
        "stitch_set",
        set_ok,
        t.set_slack_mm,
        [None, Some(SET_SLACK_MAX_MM)],
        "mm",
        t.set_at_deg,
        if set_ok {
            format!(
                "the take-up pulls the thread taut from the regulator to the stitch at φ = {:.1}°, after the stitch's \
                 loop is released and before the needle takes the next stitch into the material: {:.2} mm of slack \
                 left (at most {SET_SLACK_MAX_MM} mm wanted)",
                t.set_at_deg, t.set_slack_mm
            )
        } else {
            format!(
                "the take-up never pulls the finished stitch tight: from the release of its loop until the needle takes \
                 the next stitch into the material at least {:.2} mm of thread stays slack (least at φ = {:.1}°), so \
                 the stitch is set loose and the loop shows under the seam; the take-up must draw back more thread \
                 after the release",
                t.set_slack_mm, t.set_at_deg
            )
        },
    );
    let spring = match &t.spring {
        None => check(
            "spring_before_slip",
            true,
            0.0,
            [None, None],
            "mm",
            0.0,
            "no check spring on this path: the makers' pull test does not apply".into(),
        ),
        Some(sp) => {
            let ok = sp.held_at_slip_mm <= 1e-3;
            check(
                "spring_before_slip",
                ok,
                sp.held_at_slip_mm,
                [None, Some(1e-3)],
                "mm",
                t.regulator_windows_deg.first().map_or(0.0, |w| w[0]),
                if ok {
                    format!(
                        "the check spring (after {}) reaches the end of its travel ({:.2} N) before thread slips through the \
                         regulator ({:.2} N): the makers' pull test passes",
                        sp.after, sp.force_n[1], t.regulator_n
                    )
                } else {
                    format!(
                        "thread slips through the regulator ({:.2} N) while the check spring (after {}) still holds {:.2} mm \
                         of its {:.2} mm: its tension is too high for the regulator ({:.2} N at the end of its travel); weaken \
                         the spring or tighten the regulator",
                        t.regulator_n, sp.after, sp.held_at_slip_mm, sp.take_up_mm, sp.force_n[1]
                    )
                },
            )
        }
    };
    [margin, slack, set, spring]
}

#[cfg(test)]
mod tests {
    use super::windows;

    #[test]
    fn windows_join_across_the_grids_end() {
        let phis: Vec<f64> = (0..36).map(|k| k as f64 * 10.0).collect();
        let mut passing = vec![false; 36];
        for k in [0, 1, 34, 35, 10, 11, 12] {
            passing[k] = true;
        }
        assert_eq!(windows(&phis, &passing), vec![[100.0, 120.0], [340.0, 370.0]]);
        // Inside a stretch exactly where thread passes.
        let ws = windows(&phis, &passing);
        let inside = crate::eval::stitch_process::compared_outside(&phis, &ws);
        for k in 0..36 {
            assert_eq!(inside[k], !passing[k], "φ = {}", phis[k]);
        }
        assert_eq!(windows(&phis, &[false; 36]), Vec::<[f64; 2]>::new());
    }
}
