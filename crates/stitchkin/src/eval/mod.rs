//! Evaluating a model over a main-shaft cycle: positions, exact analogs,
//! real velocities and accelerations, link and transmission angles, measures,
//! collected into a table of named, unit-carrying columns.

mod step;
pub mod stitch;

pub use step::MAX_STEP_DEG;
pub(crate) use step::check_step;

use num_dual::Dual2_64;
use serde::Serialize;

use crate::error::Error;
use crate::mechanism::{Mechanism, Phi, Pose};
use crate::model::{Model, Params};
use crate::scalar::Real;
use crate::thread::{Convention, PathError, PathTrack, SplitPoint, Threads};

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
    pub stitch: Option<stitch::StitchSummary>,
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
                return Err(Error::Param(crate::error::ParamError {
                    message: format!("no column matches `{p}`"),
                    help: Some(format!(
                        "columns are named like {} …; `*` matches any run of characters",
                        names.join(", ")
                    )),
                }));
            }
        }
        self.columns
            .retain(|c| c.name == "phi_deg" || patterns.iter().any(|p| glob_match(p, &c.name)));
        Ok(())
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
        return Err(Error::Param(crate::error::ParamError {
            message: format!("the step {} deg is out of range", opts.step_deg),
            help: Some("give a step between 0 and 360 degrees, e.g. --step 1".into()),
        }));
    }
    if opts.step_deg < 1e-3 {
        return Err(Error::Param(crate::error::ParamError {
            message: format!("the step {} deg would make over 360 000 rows", opts.step_deg),
            help: Some("use a step of at least 0.001 deg".into()),
        }));
    }
    if let Some(rpm) = opts.rpm
        && !(rpm.is_finite() && rpm > 0.0 && rpm <= 1.0e5)
    {
        return Err(Error::Param(crate::error::ParamError {
            message: format!("the speed {rpm} rpm is out of range"),
            help: Some("give a main-shaft speed between 0 and 100000 rev/min".into()),
        }));
    }
    Ok(())
}

struct Builder {
    columns: Vec<Column>,
}

impl Builder {
    fn col(&mut self, name: String, n: usize) -> usize {
        self.columns.push(Column {
            name,
            values: Vec::with_capacity(n),
        });
        self.columns.len() - 1
    }
}

/// Runs a full cycle of `model` with `params`. With analogs the mechanism
/// is solved in second-order dual numbers; without, in plain `f64` (about
/// four times faster, what studies use).
pub fn run_cycle(model: &Model, params: &Params, opts: &CycleOptions) -> Result<CycleTable, Error> {
    run_cycle_with(model, params, opts, None)
}

/// [`run_cycle`] with the stitch process's P' already computed for this
/// model and φ grid (see [`stitch::prepare`]): studies reuse it across
/// settings that do not change the stitch.
pub fn run_cycle_with(
    model: &Model,
    params: &Params,
    opts: &CycleOptions,
    prepared: Option<&stitch::Prepared>,
) -> Result<CycleTable, Error> {
    check_options(opts)?;
    if opts.analogs {
        cycle::<Dual2_64>(model, params, opts, prepared)
    } else {
        cycle::<f64>(model, params, opts, prepared)
    }
}

fn cycle<T: Real>(
    model: &Model,
    params: &Params,
    opts: &CycleOptions,
    prepared: Option<&stitch::Prepared>,
) -> Result<CycleTable, Error> {
    let mech = model.mechanism::<T>(params)?;
    let phis = cycle_phis_deg(model.phi_start_deg(), opts.step_deg);
    let n = phis.len();
    let omega = opts.rpm.map(|r| r * std::f64::consts::TAU / 60.0);
    let points: Vec<usize> = opts.points.clone().unwrap_or_else(|| model.output_points.clone());
    let axes: &[&str] = if model.planar { &["x", "y"] } else { &["x", "y", "z"] };

    let mut b = Builder { columns: Vec::new() };
    let phi_col = b.col("phi_deg".into(), n);
    // Column layout: per point, its coordinates, then analogs, then real
    // velocities and accelerations.
    let mut point_cols = Vec::new();
    for &p in &points {
        let name = &model.point_names[p];
        let pos: Vec<usize> = axes.iter().map(|a| b.col(format!("{name}.{a}_mm"), n)).collect();
        let (d1, d2) = if opts.analogs {
            (
                axes.iter()
                    .map(|a| b.col(format!("{name}.d{a}_dphi_mm_per_rad"), n))
                    .collect(),
                axes.iter()
                    .map(|a| b.col(format!("{name}.d2{a}_dphi2_mm_per_rad2"), n))
                    .collect(),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        let (v, acc) = if opts.analogs && omega.is_some() {
            (
                axes.iter().map(|a| b.col(format!("{name}.v{a}_mm_per_s"), n)).collect(),
                axes.iter()
                    .map(|a| b.col(format!("{name}.a{a}_mm_per_s2"), n))
                    .collect(),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        point_cols.push((p, pos, d1, d2, v, acc));
    }
    let scalar_cols = |b: &mut Builder, base: &str, unit: &str, d_unit: &str, v: (&str, &str)| -> [Option<usize>; 5] {
        let c0 = Some(b.col(format!("{base}_{unit}"), n));
        if !opts.analogs {
            return [c0, None, None, None, None];
        }
        let c1 = Some(b.col(format!("{base}.d_dphi_{d_unit}_per_rad"), n));
        let c2 = Some(b.col(format!("{base}.d2_dphi2_{d_unit}_per_rad2"), n));
        let (c3, c4) = if omega.is_some() {
            (
                Some(b.col(format!("{base}.{}", v.0), n)),
                Some(b.col(format!("{base}.{}", v.1), n)),
            )
        } else {
            (None, None)
        };
        [c0, c1, c2, c3, c4]
    };
    // Link angles are columns only (no summary or study figure reads
    // them): a lean run leaves them out.
    let angle_cols: Vec<[Option<usize>; 5]> = if opts.lean {
        Vec::new()
    } else {
        model
            .link_angle_names
            .iter()
            .map(|a| scalar_cols(&mut b, a, "deg", "rad", ("omega_rad_per_s", "eps_rad_per_s2")))
            .collect()
    };
    let mu_cols: Vec<usize> = model
        .dyads
        .iter()
        .map(|d| b.col(format!("mu_{}_deg", d.key), n))
        .collect();
    let measure_cols: Vec<[Option<usize>; 5]> = model
        .measure_names
        .iter()
        .map(|m| scalar_cols(&mut b, m, "mm", "mm", ("v_mm_per_s", "a_mm_per_s2")))
        .collect();

    let mut angles = Vec::new();
    let mut mus = Vec::new();
    let mut measures = Vec::new();
    let w = omega.unwrap_or(0.0);
    let cols = &mut b.columns;
    let push = |cols: &mut Vec<Column>, c: Option<usize>, v: f64| {
        if let Some(c) = c {
            cols[c].values.push(v);
        }
    };
    // Analogs in closed form where every group has one (mechanism::analogs):
    // about 2× faster than dual numbers for the four-bar and needle876. With
    // thread paths the dual pose feeds the paths' own analogs, and building
    // it from the closed form costs more than it saves (mf7923d: about 10 %
    // slower per cycle, docs/benchmarks.md), so those stay dual.
    let closed_form = opts.analogs && mech.threads.is_none();
    let plain = if closed_form {
        Some(model.mechanism::<f64>(params)?)
    } else {
        None
    };
    let pose = crate::mechanism::analogs::solve_cycle(&mech, plain.as_ref(), &phis)?;
    for (k, &phi_deg) in phis.iter().enumerate() {
        cols[phi_col].values.push(phi_deg);
        for (p, pos, d1, d2, v, acc) in &point_cols {
            let q = pose.point(*p, k);
            for k in 0..pos.len() {
                cols[pos[k]].values.push(q[k].re());
                if !d1.is_empty() {
                    cols[d1[k]].values.push(q[k].d1());
                    cols[d2[k]].values.push(q[k].d2());
                }
                if !v.is_empty() {
                    cols[v[k]].values.push(q[k].d1() * w);
                    cols[acc[k]].values.push(q[k].d2() * w * w);
                }
            }
        }
        if !angle_cols.is_empty() {
            mech.link_angles(&pose, k, &mut angles);
        }
        for (a, c) in angles.iter().zip(&angle_cols) {
            for (j, val) in [a.re().to_degrees(), a.d1(), a.d2(), a.d1() * w, a.d2() * w * w]
                .into_iter()
                .enumerate()
            {
                push(cols, c[j], val);
            }
        }
        mech.transmission_angles(&pose, k, &mut mus);
        for (m, &c) in mus.iter().zip(&mu_cols) {
            cols[c].values.push(m.re().to_degrees());
        }
        mech.measures(&pose, k, &mut measures);
        for (m, c) in measures.iter().zip(&measure_cols) {
            for (j, val) in [m.re(), m.d1(), m.d2(), m.d1() * w, m.d2() * w * w]
                .into_iter()
                .enumerate()
            {
                push(cols, c[j], val);
            }
        }
    }
    let (paths, take_up) = match &mech.threads {
        Some(threads) => thread_columns(&mech, threads, &pose, &phis, opts, omega, &mut b.columns)?,
        None => (Vec::new(), None),
    };
    let stitch = match prepared {
        Some(p) => Some(stitch::stitch_columns(p, &phis, opts.lean, &mut b.columns)?),
        None => match stitch::prepare(model, params, opts.step_deg)? {
            Some(p) => Some(stitch::stitch_columns(&p, &phis, opts.lean, &mut b.columns)?),
            None => None,
        },
    };
    let columns = b.columns;
    // Never NaN or infinity in output.
    for c in &columns {
        if let Some(k) = c.values.iter().position(|v| !v.is_finite()) {
            return Err(Error::NotFinite(format!(
                "`{}` is {} at φ = {:.3}°: the mechanism passes a dead point there, where analogs are infinite; \
                 change the geometry or the step so no position lands on the dead point",
                c.name,
                c.values[k],
                wrap_deg(phis[k])
            )));
        }
    }
    let mut warnings: Vec<String> = stitch.iter().flat_map(|s| s.warnings.iter().cloned()).collect();
    let transmission: Vec<TransmissionSummary> = model
        .dyads
        .iter()
        .zip(&mu_cols)
        .map(|(d, &c)| {
            let v = &columns[c].values;
            let (i0, i1) = extremes(v);
            let ok = v[i0] >= MU_MIN_DEG && v[i1] <= MU_MAX_DEG;
            if !ok {
                warnings.push(format!(
                    "transmission angle of {} leaves {MU_MIN_DEG}°…{MU_MAX_DEG}°: {:.2}° at φ = {:.1}° … {:.2}° at φ = {:.1}° (risk of jamming)",
                    d.label, v[i0], wrap_deg(phis[i0]), v[i1], wrap_deg(phis[i1])
                ));
            }
            TransmissionSummary {
                key: d.key.clone(),
                group: d.label.clone(),
                min_deg: v[i0],
                phi_at_min_deg: wrap_deg(phis[i0]),
                max_deg: v[i1],
                phi_at_max_deg: wrap_deg(phis[i1]),
                ok,
            }
        })
        .collect();
    let ranges = model
        .measure_names
        .iter()
        .zip(&measure_cols)
        .map(|(name, c)| {
            let v = &columns[c[0].expect("value column always present")].values;
            let (i0, i1) = extremes(v);
            RangeSummary {
                name: name.clone(),
                unit: "mm",
                min: v[i0],
                phi_at_min_deg: wrap_deg(phis[i0]),
                max: v[i1],
                phi_at_max_deg: wrap_deg(phis[i1]),
                range: v[i1] - v[i0],
            }
        })
        .collect();
    Ok(CycleTable {
        step_deg: opts.step_deg,
        rpm: opts.rpm,
        columns,
        transmission,
        ranges,
        paths,
        take_up,
        stitch,
        warnings,
    })
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

/// A thread path that cannot be formed, as an error naming path and φ.
pub fn path_error(e: PathError, phi_deg: f64) -> Error {
    Error::Thread(format!(
        "thread path `{}` at φ = {:.3}°: {}",
        e.path,
        wrap_deg(phi_deg),
        e.message
    ))
}

/// Adds each path's columns and returns its summary.
#[allow(clippy::too_many_arguments)]
fn thread_columns<T: Real>(
    mech: &Mechanism<T>,
    threads: &Threads<T>,
    pose: &Pose<T>,
    phis: &[f64],
    opts: &CycleOptions,
    omega: Option<f64>,
    columns: &mut Vec<Column>,
) -> Result<(Vec<PathSummary>, Option<String>), Error> {
    let at0 = tracks_at_phi0(mech, threads)?;
    let tracks = threads.evaluate(pose, None).map_err(|e| {
        let phi = phis[e.k];
        path_error(e, phi)
    })?;
    let mut summaries = Vec::new();
    for ((path, track), at0) in threads.paths.iter().zip(tracks).zip(at0) {
        let name = &path.name;
        let split = !track.eye_up.is_empty();
        let pn = take_up_name(split);
        let p: Vec<T> = (0..track.xi.len())
            .map(|k| threads.convention.take_up(track.xi_at_split(k), at0.xi_at_split(0)))
            .collect();
        let mut col = |n: String, v: Vec<f64>| {
            columns.push(Column {
                name: format!("{name}.{n}"),
                values: v,
            })
        };
        col("xi_mm".into(), track.xi.iter().map(|x| x.re()).collect());
        col(format!("{pn}_mm"), p.iter().map(|x| x.re()).collect());
        if opts.analogs {
            col(format!("d{pn}_dphi_mm_per_rad"), p.iter().map(|x| x.d1()).collect());
            col(format!("d2{pn}_dphi2_mm_per_rad2"), p.iter().map(|x| x.d2()).collect());
            if let Some(w) = omega {
                col(format!("v{pn}_mm_per_s"), p.iter().map(|x| x.d1() * w).collect());
            }
        }
        // The same thread measured at the moving eye (P_eye = P_B − S + S(φ0)).
        let p_eye: Option<Vec<f64>> = split.then(|| {
            track
                .xi
                .iter()
                .map(|x| threads.convention.take_up(*x, at0.xi[0]).re())
                .collect()
        });
        if let Some(v) = &p_eye {
            col("P_eye_mm".into(), v.clone());
        }
        // The angle the thread turns through at every node, per φ: a column
        // per guide between the ends, and the capstan tension from them.
        // (Left out of lean runs.)
        let wraps: Vec<Vec<f64>> = if opts.lean {
            Vec::new()
        } else {
            (0..phis.len()).map(|k| threads.wrap_angles(path, pose, k)).collect()
        };
        let pins = path.pin_names();
        let mut pin = 0;
        for i in 1..path.nodes.len().saturating_sub(1) {
            let node = &path.node_names[i];
            if path.pin_span[i].is_some() {
                col(
                    format!("{node}_engaged"),
                    track.engaged[pin].iter().map(|&e| if e { 1.0 } else { 0.0 }).collect(),
                );
                pin += 1;
            }
            if !opts.lean {
                col(
                    format!("{node}_wrap_deg"),
                    wraps.iter().map(|w| w[i].to_degrees()).collect(),
                );
            }
        }
        // Tension after each node at each φ; the eye's is the last.
        let tensions: Option<Vec<Vec<f64>>> = threads.tension_n.filter(|_| !opts.lean).map(|t0| {
            wraps
                .iter()
                .map(|theta| crate::thread::capstan(theta, &path.friction, t0))
                .collect()
        });
        let eye_tension: Option<Vec<f64>> = tensions
            .as_ref()
            .map(|t| t.iter().map(|row| *row.last().unwrap_or(&0.0)).collect());
        if let Some(t) = &eye_tension {
            col("tension_eye_N".into(), t.clone());
        }
        let max_tension: Vec<(String, f64)> = match &tensions {
            Some(t) => (0..path.nodes.len())
                .map(|i| {
                    (
                        path.node_names[i].clone(),
                        t.iter().map(|row| row[i]).fold(f64::MIN, f64::max),
                    )
                })
                .collect(),
            None => Vec::new(),
        };
        let p_re: Vec<f64> = p.iter().map(|x| x.re()).collect();
        let (imin, imax) = extremes(&p_re);
        // The slope dP/dφ: exact with analogs; otherwise the central
        // difference on the (periodic) grid, enough to classify dwells.
        let slope_mm_per_deg: Vec<f64> = if opts.analogs {
            p.iter().map(|x| x.d1() * std::f64::consts::PI / 180.0).collect()
        } else {
            let n = p_re.len();
            (0..n)
                .map(|k| (p_re[(k + 1) % n] - p_re[(k + n - 1) % n]) / (2.0 * opts.step_deg))
                .collect()
        };
        let flat_flags: Vec<bool> = slope_mm_per_deg
            .iter()
            .map(|s| s.abs() < FLAT_SLOPE_MM_PER_DEG)
            .collect();
        let flat = crate::thread::intervals(&flat_flags, phis)
            .into_iter()
            .filter(|iv| iv.to_deg - iv.from_deg >= FLAT_MIN_DEG)
            .collect();
        summaries.push(PathSummary {
            path: name.clone(),
            thread: path.label.clone(),
            split: if split { SplitPoint::B } else { SplitPoint::End },
            p_column: format!("{name}.{pn}_mm"),
            max_p_eye_mm: p_eye.as_ref().map(|v| v.iter().cloned().fold(f64::MIN, f64::max)),
            max_p_mm: p_re[imax],
            phi_at_max_deg: wrap_deg(phis[imax]),
            min_p_mm: p_re[imin],
            phi_at_min_deg: wrap_deg(phis[imin]),
            xi0_mm: at0.xi[0].re(),
            engaged: pins
                .iter()
                .enumerate()
                .map(|(j, pin)| (pin.to_string(), crate::thread::intervals(&track.engaged[j], phis)))
                .collect(),
            flat,
            max_tension_n: max_tension,
            eye_tension_n: eye_tension.map(|t| {
                [
                    t.iter().cloned().fold(f64::MAX, f64::min),
                    t.iter().cloned().fold(f64::MIN, f64::max),
                ]
            }),
        });
    }
    let mut words = match threads.convention {
        Convention::Release => format!(
            "P = xi(phi0) - xi(phi), phi0 = {} deg (seed 000 eq. 2)",
            threads.phi0_deg
        ),
        Convention::Feed { elongation_mm } => {
            format!(
                "P = xi(phi) - xi(phi0) + dP, dP = {elongation_mm} mm, phi0 = {} deg (seed 001 eq. 22-23)",
                threads.phi0_deg
            )
        }
    };
    if threads.split_up.iter().any(Option::is_some) {
        words += "; needle-eye paths split at B, the eye's top position: P_B = P_eye + S(phi) - S(phi0), S the needle's travel below B \
                  (seed 004 sec. 2.3)";
    }
    Ok((summaries, Some(words)))
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
