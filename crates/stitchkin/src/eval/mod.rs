//! Evaluating a model over a main-shaft cycle: positions, exact analogs,
//! real velocities and accelerations, link and transmission angles, measures,
//! collected into a table of named, unit-carrying columns.

pub mod cams;
mod cycle;
mod paths;
mod step;
pub mod stitch_process;
pub mod tension;

pub use paths::PathCourse;
pub(crate) use step::check_step;
pub use step::{MAX_STEP_DEG, REFERENCE_STEP_DEG, STEP_SCORE_POINTS, coarse_step_warning, run_match};

use num_dual::Dual2_64;
use serde::Serialize;

use crate::error::{Error, Input, NotFiniteError, ParamError, ThreadError};
use crate::mechanism::{Mechanism, Phi};
use crate::model::{Model, Params};
use crate::scalar::Real;
use crate::thread::{PathError, PathTrack, SplitPoint, Threads};

/// The band a transmission angle must stay in (seed 002 eq. 15), degrees.
pub const MU_MIN_DEG: f64 = 30.0;
pub const MU_MAX_DEG: f64 = 150.0;

/// How to run a cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleOptions {
    /// φ step, degrees (0 < step ≤ 360).
    pub step_deg: f64,
    /// Main-shaft speed for velocities and accelerations; `None` prints
    /// analogs only.
    pub rpm: Option<f64>,
    /// Include first and second analogs.
    pub analogs: bool,
    /// Points to tabulate; `None`: the model's output points.
    pub points: Option<Vec<usize>>,
    /// Leave out what studies do not need: link-angle columns, the per-node
    /// wrap-angle and tension columns of thread paths and the best lag of
    /// the P–P' match.
    pub lean: bool,
}

impl CycleOptions {
    /// The cycle a study reads figures of merit from, at a φ step of
    /// `step_deg`: lean, without analogs or real velocities, the model's
    /// output points.
    pub fn for_figures(step_deg: f64) -> CycleOptions {
        CycleOptions {
            step_deg,
            rpm: None,
            analogs: false,
            points: None,
            lean: true,
        }
    }
}

impl Default for CycleOptions {
    fn default() -> Self {
        CycleOptions {
            step_deg: 1.0,
            rpm: None,
            analogs: true,
            points: None,
            lean: false,
        }
    }
}

/// One named column: `name` ends with its unit (`E.x_mm`, `mu_23_deg`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Column {
    pub name: String,
    pub values: Vec<f64>,
}

/// Extremes of a transmission angle over the cycle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransmissionSummary {
    /// Column key (`mu_{key}_deg`).
    pub key: String,
    pub group: String,
    pub min_deg: f64,
    pub phi_at_min_deg: f64,
    pub max_deg: f64,
    pub phi_at_max_deg: f64,
    /// Inside 30°…150° over the whole cycle.
    pub ok: bool,
}

/// Extremes of a measure or coordinate over the cycle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RangeSummary {
    pub name: String,
    pub unit: &'static str,
    pub min: f64,
    pub phi_at_min_deg: f64,
    pub max: f64,
    pub phi_at_max_deg: f64,
    /// max − min (a stroke, for a coordinate).
    pub range: f64,
}

/// A thread path over the cycle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathSummary {
    pub path: String,
    /// Which thread this is, in words.
    pub thread: Option<String>,
    /// Where the take-up is measured: B for a needle thread split at the
    /// eye's top position (seed 004 §2.3), else the path's last node.
    pub split: SplitPoint,
    /// The column of P: `PATH.P_B_mm` or `PATH.P_mm`.
    pub p_column: String,
    /// Largest take-up and where (at the split).
    pub max_p_mm: f64,
    pub phi_at_max_deg: f64,
    pub min_p_mm: f64,
    pub phi_at_min_deg: f64,
    /// A path split at B: its largest take-up measured at the moving eye,
    /// P_eye = P_B − S(φ) + S(φ0), mm.
    pub max_p_eye_mm: Option<f64>,
    /// Contour length at φ0 (to the last node).
    pub xi0_mm: f64,
    /// For each one-sided guide, the φ intervals where the thread bears on it.
    pub engaged: Vec<(String, Vec<crate::thread::Interval>)>,
    /// Dwell: where |dP/dφ| stays below [`FLAT_SLOPE_MM_PER_DEG`] for at
    /// least [`FLAT_MIN_DEG`].
    pub flat: Vec<crate::thread::Interval>,
    /// Thread tension at the eye (capstan law), N: min and max over the cycle.
    pub eye_tension_n: Option<[f64; 2]>,
    /// Largest tension after each node over the cycle, N (empty without a
    /// regulator tension).
    pub max_tension_n: Vec<(String, f64)>,
}

impl PathSummary {
    /// The name of its take-up columns: `P_B` split at B, else `P`
    /// ([`take_up_name`]).
    pub fn take_up_name(&self) -> &'static str {
        take_up_name(self.split == SplitPoint::B)
    }
}

/// A dwell of the take-up is a stretch where |dP/dφ| stays under this…
pub const FLAT_SLOPE_MM_PER_DEG: f64 = 0.05;
/// …for at least this many degrees.
pub const FLAT_MIN_DEG: f64 = 15.0;

/// A full cycle's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CycleTable {
    pub step_deg: f64,
    pub rpm: Option<f64>,
    pub columns: Vec<Column>,
    pub transmission: Vec<TransmissionSummary>,
    pub ranges: Vec<RangeSummary>,
    /// Thread paths, when the model has any (convention in `take_up`).
    pub paths: Vec<PathSummary>,
    /// How P is signed, in words.
    pub take_up: Option<String>,
    /// The stitch process: P' and the mismatch per thread, when the model
    /// has a `[stitch]`.
    pub stitch: Option<stitch_process::StitchSummary>,
    /// The checks of each cam and follower (empty without cams).
    pub cams: Vec<cams::CamSummary>,
    pub warnings: Vec<String>,
}

impl CycleTable {
    /// Keeps `phi_deg` and the columns matching any of `patterns` (`*`
    /// matches any run of characters: `*.P_mm`, `G.*`, `mu_*`). Errors when a
    /// pattern matches nothing, listing what there is.
    pub fn select(&mut self, patterns: &[String]) -> Result<(), Error> {
        for p in patterns {
            if !self.columns.iter().any(|c| glob_match(p, &c.name)) {
                let names: Vec<&str> = self.columns.iter().map(|c| c.name.as_str()).take(12).collect();
                // A name spelt nearly right gets the closest; a pattern the names.
                let near = (!p.contains('*'))
                    .then(|| crate::error::did_you_mean(p, self.columns.iter().map(|c| c.name.as_str())))
                    .flatten();
                let help = match near {
                    Some(near) => format!("did you mean `{near}`? `*` matches any run of characters"),
                    None => format!(
                        "columns are named like {} …; `*` matches any run of characters",
                        names.join(", ")
                    ),
                };
                return Err(Error::Param(ParamError::new(
                    Input::Columns,
                    format!("no column matches `{p}`"),
                    Some(help),
                )));
            }
        }
        self.columns
            .retain(|c| c.name == "phi_deg" || patterns.iter().any(|p| glob_match(p, &c.name)));
        Ok(())
    }

    /// Every check of the cycle, the one place front ends read them from:
    /// the stitch's physical checks, then each cam and follower's
    /// (`cam_pressure`, `cam_curvature`, `follower_contact`, their `thread`
    /// the group's name).
    pub fn all_checks(&self) -> impl Iterator<Item = &crate::stitch::checks::Check> {
        self.stitch
            .iter()
            .flat_map(|s| s.checks.iter())
            .chain(self.cams.iter().flat_map(|c| c.checks.iter()))
    }

    /// Whether every check of the cycle passes ([`CycleTable::all_checks`]).
    pub fn checks_ok(&self) -> bool {
        self.all_checks().all(|c| c.ok)
    }

    /// The checks of every cam and follower, in group order.
    pub fn cam_checks(&self) -> impl Iterator<Item = &crate::stitch::checks::Check> {
        self.cams.iter().flat_map(|c| c.checks.iter())
    }

    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.values.len())
    }
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.as_slice())
    }
}

/// Whether `name` matches `pattern`, where `*` matches any run of characters.
pub fn glob_match(pattern: &str, name: &str) -> bool {
    let parts: Vec<&str> = pattern.split('*').collect();
    if parts.len() == 1 {
        return pattern == name;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !name.starts_with(first) || !name[first.len()..].ends_with(last) || name.len() < first.len() + last.len() {
        return false;
    }
    let mut rest = &name[first.len()..name.len() - last.len()];
    for mid in &parts[1..parts.len() - 1] {
        match rest.find(mid) {
            Some(i) => rest = &rest[i + mid.len()..],
            None => return false,
        }
    }
    true
}

/// φ reduced to [0, 360) degrees, for reporting where something happens.
pub fn wrap_deg(phi_deg: f64) -> f64 {
    let w = phi_deg.rem_euclid(360.0);
    if w >= 360.0 - 1e-9 { 0.0 } else { w }
}

/// The φ values of a cycle starting at `start_deg` with `step_deg`.
pub fn cycle_phis_deg(start_deg: f64, step_deg: f64) -> Vec<f64> {
    let n = (360.0 / step_deg - 1e-9).ceil().max(1.0) as usize;
    (0..n).map(|k| start_deg + k as f64 * step_deg).collect()
}

/// Checks cycle options against the model.
pub fn check_options(opts: &CycleOptions) -> Result<(), Error> {
    if !(opts.step_deg.is_finite() && opts.step_deg > 0.0 && opts.step_deg <= 360.0) {
        return Err(Error::Param(ParamError::new(
            Input::Step,
            format!("the step {} deg is out of range", opts.step_deg),
            Some("give a step greater than 0 and at most 360 degrees, e.g. 1".into()),
        )));
    }
    if opts.step_deg < 1e-3 {
        return Err(Error::Param(ParamError::new(
            Input::Step,
            format!("the step {} deg would make over 360 000 rows", opts.step_deg),
            Some("use a step of at least 0.001 deg".into()),
        )));
    }
    if let Some(rpm) = opts.rpm
        && !(rpm.is_finite() && rpm > 0.0 && rpm <= 1.0e5)
    {
        return Err(Error::Param(ParamError::new(
            Input::Rpm,
            format!("the speed {rpm} rpm is out of range"),
            Some("give a main-shaft speed between 0 and 100000 rev/min".into()),
        )));
    }
    Ok(())
}

/// Runs a full cycle of `model` with `params`. With analogs the mechanism
/// is solved in second-order dual numbers; without, in plain `f64` (about
/// four times faster, what studies use).
pub fn run_cycle(model: &Model, params: &Params, opts: &CycleOptions) -> Result<CycleTable, Error> {
    run_cycle_with(model, params, opts, None)
}

/// [`run_cycle`] with the stitch process's P' already computed for this
/// model and φ grid (see [`stitch_process::prepare`]): studies reuse it across
/// settings that do not change the stitch.
pub fn run_cycle_with(
    model: &Model,
    params: &Params,
    opts: &CycleOptions,
    prepared: Option<&stitch_process::Prepared>,
) -> Result<CycleTable, Error> {
    cycle_of(model, params, opts, prepared, true)
}

/// [`run_cycle`] with only the columns `patterns` name (`*` matches any
/// run of characters; `phi_deg` is always kept), as `run --columns` and
/// Python's `run(columns=…)` ask for them: when no pattern can name a
/// column of the stitch process (`THREAD.Pprime_B_mm`, `THREAD.T_eye_N`,
/// … of a stitch thread), the stitch process and the thread's tension are
/// not computed, and the table has no stitch summary. An error names a
/// pattern that matches no column.
pub fn run_cycle_columns(
    model: &Model,
    params: &Params,
    opts: &CycleOptions,
    patterns: &[String],
) -> Result<CycleTable, Error> {
    let threads = model.stitch_thread_names();
    let with_stitch = patterns.iter().any(|p| stitch_process::may_name_a_column(p, &threads));
    // What no pattern can name is not computed: the analogs, the link
    // angles and the wrap angles of every guide.
    let mut opts = opts.clone();
    opts.analogs &= patterns.iter().any(|p| may_name_an_analog_column(p));
    opts.lean |= !patterns.iter().any(|p| may_name_a_lean_column(model, p));
    let mut table = cycle_of(model, params, &opts, None, with_stitch)?;
    table.select(patterns)?;
    Ok(table)
}

/// The last part of a column pattern (after its last `.`), and whether it
/// is a literal (no `*`).
fn pattern_tail(pattern: &str) -> (&str, bool) {
    let tail = pattern.rsplit('.').next().unwrap_or(pattern);
    (tail, !tail.contains('*'))
}

/// Whether the column pattern `pattern` can name a first or second analog,
/// a velocity or an acceleration (`…dphi…`, `…_per_s`, `…_per_s2`).
pub fn may_name_an_analog_column(pattern: &str) -> bool {
    let (tail, literal) = pattern_tail(pattern);
    !literal || tail.contains("dphi") || tail.ends_with("_per_s") || tail.ends_with("_per_s2")
}

/// Whether the column pattern `pattern` can name a column that a lean run
/// leaves out: a guide's wrap angle (`PATH.NODE_wrap_deg`), the eye's
/// tension by the capstan law (`PATH.tension_eye_N`) or a link angle
/// (`ANGLE_deg` and its analogs).
pub fn may_name_a_lean_column(model: &Model, pattern: &str) -> bool {
    let (tail, literal) = pattern_tail(pattern);
    !literal
        || tail.ends_with("_wrap_deg")
        || tail.starts_with("tension_")
        || model
            .link_angle_names
            .iter()
            .any(|a| glob_match(pattern, &format!("{a}_deg")) || pattern.starts_with(&format!("{a}.")))
}

fn cycle_of(
    model: &Model,
    params: &Params,
    opts: &CycleOptions,
    prepared: Option<&stitch_process::Prepared>,
    with_stitch: bool,
) -> Result<CycleTable, Error> {
    check_options(opts)?;
    if opts.analogs {
        cycle::cycle::<Dual2_64>(model, params, opts, prepared, with_stitch)
    } else {
        cycle::cycle::<f64>(model, params, opts, prepared, with_stitch)
    }
}

/// Every path at φ0 (ξ, and u·N for a path split at B), with φ0 a
/// constant: P = ξ(φ0) − ξ(φ) must carry no derivative of ξ(φ0) with
/// respect to φ.
pub fn tracks_at_phi0<T: Real>(mech: &Mechanism<T>, threads: &Threads<T>) -> Result<Vec<PathTrack<T>>, Error> {
    let mut p0 = mech.new_pose(1);
    mech.solve(&[Phi::new(T::cst(threads.phi0_deg.to_radians()))], &mut p0)?;
    threads.evaluate_at(&p0, 0).map_err(|e| path_error(e, threads.phi0_deg))
}

/// The name of a path's take-up columns: `P_B` for a path split at B (a
/// needle thread measured past the eye's top position, seed 004 §2.3), `P`
/// for one split at its last node.
pub fn take_up_name(split_at_b: bool) -> &'static str {
    if split_at_b { "P_B" } else { "P" }
}

/// The engine's own loop for a model's thread paths, without a table: the
/// mechanism solved over one turn and every path's length ξ(φ), with the
/// buffers kept between evaluations (what a sweep does for each setting,
/// and what the engine benchmark `mf7923d_take_up` times).
pub struct PathLengths {
    mechanism: Mechanism<f64>,
    threads: Threads<f64>,
    phis_deg: Vec<f64>,
    phis: Vec<Phi<f64>>,
    pose: crate::mechanism::Pose<f64>,
    work: crate::thread::ThreadWork<f64>,
}

impl PathLengths {
    /// The loop for `model` at `params`, φ from the model's start in steps
    /// of `step_deg`; an error if the model has no thread paths.
    pub fn new(model: &Model, params: &Params, step_deg: f64) -> Result<PathLengths, Error> {
        check_options(&CycleOptions::for_figures(step_deg))?;
        let mechanism = model.mechanism::<f64>(params)?;
        let Some(threads) = model.machine::<f64>(params)?.threads else {
            return Err(Error::Param(ParamError::general(
                format!("model `{}` has no thread paths", model.name()),
                Some("give a model with a [thread] table, e.g. the preset mf7923d".into()),
            )));
        };
        let phis_deg = cycle_phis_deg(model.phi_start_deg(), step_deg);
        let phis = Phi::table(&phis_deg);
        let pose = mechanism.new_pose(phis.len());
        Ok(PathLengths {
            mechanism,
            threads,
            phis_deg,
            phis,
            pose,
            work: Default::default(),
        })
    }

    /// Solves the mechanism and evaluates every path over the turn.
    pub fn evaluate(&mut self) -> Result<(), Error> {
        self.mechanism.solve(&self.phis, &mut self.pose)?;
        self.threads
            .evaluate_into(&self.pose, None, &mut self.work)
            .map_err(|e| {
                let phi_deg = self.phis_deg[e.k.min(self.phis_deg.len() - 1)];
                path_error(e, phi_deg)
            })
    }

    /// ξ(φ) of the `i`-th path (model order) from the last evaluation, mm.
    pub fn xi(&self, i: usize) -> Option<&[f64]> {
        self.work.tracks.get(i).map(|t| t.xi.as_slice())
    }
}

/// A thread path that cannot be formed, as an error naming path and φ.
pub fn path_error(e: PathError, phi_deg: f64) -> Error {
    Error::Thread(ThreadError {
        path: e.path,
        phi_deg: Some(wrap_deg(phi_deg)),
        message: e.message,
        help: None,
    })
}

/// A column value that is not a finite number, as `run_cycle` and the
/// sweeps report it.
pub(crate) fn not_finite(column: &str, value: f64, phi_deg: f64) -> Error {
    Error::NotFinite(NotFiniteError {
        quantity: format!("`{column}` ({value})"),
        phi_deg: Some(wrap_deg(phi_deg)),
        cause: "the mechanism passes a dead point there, where analogs are infinite; \
                change the geometry or the step so no position lands on the dead point"
            .into(),
    })
}

/// Indices of the smallest and largest value (the first of equals).
pub(crate) fn extremes(vals: &[f64]) -> (usize, usize) {
    let (mut imin, mut imax) = (0, 0);
    for (k, v) in vals.iter().enumerate() {
        if *v < vals[imin] {
            imin = k;
        }
        if *v > vals[imax] {
            imax = k;
        }
    }
    (imin, imax)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run asked for columns by name computes no analogs and no lean
    /// columns unless a name needs them: every column a full run has that
    /// a run without analogs (or a lean run) lacks is one the patterns'
    /// rules say needs them, on every preset.
    #[test]
    fn named_columns_need_analogs_and_wraps_exactly_when_the_rules_say() {
        let names = |model: &Model, analogs: bool, lean: bool| -> Vec<String> {
            let opts = CycleOptions {
                step_deg: 30.0,
                analogs,
                lean,
                rpm: Some(600.0),
                ..Default::default()
            };
            cycle_of(model, &model.defaults(), &opts, None, false)
                .unwrap()
                .columns
                .into_iter()
                .map(|c| c.name)
                .collect()
        };
        let mut seen = (0, 0);
        for preset in crate::presets::ALL {
            let model = Model::preset(preset.name).unwrap();
            let full = names(&model, true, false);
            let (plain, lean) = (names(&model, false, false), names(&model, true, true));
            for c in &full {
                if !plain.contains(c) {
                    assert!(may_name_an_analog_column(c), "{}: {c}", preset.name);
                    seen.0 += 1;
                } else {
                    assert!(
                        !may_name_an_analog_column(c) || c.contains("dphi"),
                        "{}: {c}",
                        preset.name
                    );
                }
                if !lean.contains(c) {
                    assert!(may_name_a_lean_column(&model, c), "{}: {c}", preset.name);
                    seen.1 += 1;
                } else {
                    assert!(!may_name_a_lean_column(&model, c), "{}: {c}", preset.name);
                }
            }
        }
        assert!(seen.0 > 100 && seen.1 > 20, "{seen:?}");
        assert!(!may_name_an_analog_column("*.P_B_mm") && may_name_an_analog_column("n1_A.*"));
    }

    #[test]
    fn path_lengths_are_the_tables_xi() {
        let model = Model::preset("mf7923d").unwrap();
        let params = model.defaults();
        let mut lengths = PathLengths::new(&model, &params, 5.0).unwrap();
        lengths.evaluate().unwrap();
        let table = run_cycle(&model, &params, &CycleOptions::for_figures(5.0)).unwrap();
        let xi = table.column("n2_B.xi_mm").unwrap();
        assert_eq!(lengths.xi(3).unwrap(), xi);
        assert!(lengths.xi(6).is_none());
        let bench = Model::preset("needle876").unwrap();
        let e = PathLengths::new(&bench, &bench.defaults(), 1.0).err().unwrap();
        assert!(e.to_string().contains("no thread paths"), "{e}");
        assert!(PathLengths::new(&model, &params, 0.0).is_err());
    }

    #[test]
    fn glob_patterns() {
        assert!(glob_match("*.P_mm", "n1_A.P_mm"));
        assert!(!glob_match("*.P_mm", "n1_A.dP_dphi_mm_per_rad"));
        assert!(glob_match("G.*", "G.y_mm") && !glob_match("G.*", "GG.y_mm"));
        assert!(glob_match("mu_*_deg", "mu_45_deg") && glob_match("*", "anything"));
        assert!(glob_match("n*_A.*_engaged", "n2_A.G4_2_engaged"));
        assert!(glob_match("phi_deg", "phi_deg") && !glob_match("phi", "phi_deg"));
        assert!(!glob_match("a*a", "a"));
    }

    #[test]
    fn phis_cover_one_cycle() {
        assert_eq!(cycle_phis_deg(0.0, 1.0).len(), 360);
        assert_eq!(cycle_phis_deg(90.6, 90.0), vec![90.6, 180.6, 270.6, 360.6]);
        assert_eq!(cycle_phis_deg(0.0, 7.0).len(), 52);
        assert_eq!(cycle_phis_deg(0.0, 360.0).len(), 1);
    }
}
