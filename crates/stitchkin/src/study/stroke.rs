//! Stroke and dead centres of a point, with the transmission angles, over
//! one or more settings.
//!
//! Seed 002 eq. 14 defines the needle stroke as S = y_G(φ0') − y_G(φ0), the
//! difference of the needle's positions at the two extreme positions of the
//! mechanism. Here the coordinate is s(φ) = (P(φ) − O)·u, P the point, u a
//! unit axis (world or of a frame) and O that frame's origin:
//!
//! 1. s is sampled on the cycle grid (plain `f64`) and the grid samples of
//!    its smallest and largest value are found;
//! 2. each dead centre is then refined below the grid step as the zero of the
//!    exact first analog ds/dφ, computed through the same closed-form groups
//!    in second-order dual numbers (ds/dφ and d²s/dφ² together), by Newton's
//!    method safeguarded by bisection inside the two neighbouring grid
//!    intervals.
//!
//! The extremes of every transmission angle (seed 002 eq. 15: 30° < μ <
//! 150°) are refined the same way, and across a sweep of settings the value
//! where an angle leaves the band (where the mechanism starts to jam) is
//! found by bisection on the setting.

use num_dual::Dual2_64;
use rayon::prelude::*;
use serde::Serialize;

use super::design::Sweep;
use crate::error::{Error, Input, NotFiniteError, ParamError, did_you_mean};
use crate::eval::{MU_MAX_DEG, MU_MIN_DEG, check_step, cycle_phis_deg, wrap_deg};
use crate::geometry::V3;
use crate::mechanism::{Mechanism, Phi, Pose};
use crate::model::{Model, Params};
use crate::scalar::Real;

/// Degrees per radian: analogs are per radian of φ, the grid is in degrees.
const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;

/// A stroke shorter than this has no dead centres (the coordinate is
/// constant, e.g. a needle's x on a vertical guide), mm.
pub const NO_STROKE_MM: f64 = 1e-9;

/// Settings tabulated at most by one `stroke` study (all rows are kept in
/// memory; `stitchkin sweep` streams larger grids).
pub const MAX_SETTINGS: usize = 100_000;

/// A scalar function of the mechanism's pose at one φ, computable in any
/// scalar type: plain `f64` on the cycle grid, second-order dual numbers
/// where an extremum is refined.
pub(crate) trait PoseFn: Sync {
    fn at<T: Real>(&self, mech: &Mechanism<T>, pose: &Pose<T>, k: usize) -> T;
}

/// A fixed vector of plain numbers as constants of type `T`.
pub(crate) fn cst3<T: Real>(v: V3<f64>) -> V3<T> {
    v.map(T::cst)
}

/// s = (P − O)·u: a point's coordinate along a fixed unit axis.
struct Along {
    point: usize,
    origin: V3<f64>,
    dir: V3<f64>,
}

impl PoseFn for Along {
    fn at<T: Real>(&self, _: &Mechanism<T>, pose: &Pose<T>, k: usize) -> T {
        (pose.point(self.point, k) - cst3::<T>(self.origin)).dot(&cst3(self.dir))
    }
}

/// The transmission angle of dyad `j`, rad.
struct Mu(usize);

impl PoseFn for Mu {
    fn at<T: Real>(&self, mech: &Mechanism<T>, pose: &Pose<T>, k: usize) -> T {
        let mut out = Vec::new();
        mech.transmission_angles(pose, k, &mut out);
        out[self.0]
    }
}

/// Solves the mechanism at single φ values in dual numbers, for exact first
/// and second analogs of a [`PoseFn`].
pub(crate) struct Refiner {
    mech: Mechanism<Dual2_64>,
    pose: Pose<Dual2_64>,
}

impl Refiner {
    pub(crate) fn new(model: &Model, params: &Params) -> Result<Refiner, Error> {
        let mech = model.mechanism::<Dual2_64>(params)?;
        let pose = mech.new_pose(1);
        Ok(Refiner { mech, pose })
    }

    /// f(φ), df/dφ (per rad) and d²f/dφ² (per rad²).
    pub(crate) fn eval(&mut self, f: &impl PoseFn, phi_deg: f64) -> Result<(f64, f64, f64), Error> {
        self.mech.solve(&[Phi::at_deg(phi_deg)], &mut self.pose)?;
        let v = f.at(&self.mech, &self.pose, 0);
        Ok((v.re(), v.d1(), v.d2()))
    }

    /// World position of point `slot` at φ, mm.
    pub(crate) fn point(&mut self, slot: usize, phi_deg: f64) -> Result<[f64; 3], Error> {
        self.mech.solve(&[Phi::at_deg(phi_deg)], &mut self.pose)?;
        let p = self.pose.point(slot, 0);
        Ok([p.x.re(), p.y.re(), p.z.re()])
    }

    /// The extremum of f near the grid sample (`phi_deg`, `value`), whose
    /// grid neighbours are at `a` < `phi_deg` < `b`: the zero of the exact
    /// analog f'(φ) in [a, b], by Newton's method on f' (with f'' from the
    /// same dual-number run) safeguarded by bisection (rtsafe, Numerical
    /// Recipes §9.4). Returns φ (degrees, not wrapped) and f there. When f'
    /// does not change sign in [a, b] (a corner, or an extremum at a window
    /// end) or the refined value is no better than the grid sample, the grid
    /// sample is returned; at a corner (an infinite analog) the best point
    /// reached.
    pub(crate) fn refine(
        &mut self,
        f: &impl PoseFn,
        a: f64,
        b: f64,
        phi_deg: f64,
        value: f64,
        maximum: bool,
    ) -> Result<(f64, f64), Error> {
        let grid = (phi_deg, value);
        let (_, ga, _) = self.eval(f, a)?;
        let (_, gb, _) = self.eval(f, b)?;
        if !(ga.is_finite() && gb.is_finite()) || ga.signum() == gb.signum() || ga == 0.0 || gb == 0.0 {
            return Ok(grid);
        }
        // f'(lo) < 0 < f'(hi).
        let (mut lo, mut hi) = if ga < 0.0 { (a, b) } else { (b, a) };
        let mut x = phi_deg;
        let (mut v, mut g, mut gp) = self.eval(f, x)?;
        let mut dx_old = (b - a).abs();
        let mut dx = dx_old;
        for _ in 0..100 {
            // A corner (infinite analog) or an exact zero: stop here.
            if !(g.is_finite() && gp.is_finite()) || g == 0.0 {
                break;
            }
            if g < 0.0 {
                lo = x
            } else {
                hi = x
            }
            let newton = g / gp * DEG_PER_RAD;
            let xn = x - newton;
            if gp != 0.0 && (xn - lo) * (xn - hi) < 0.0 && 2.0 * newton.abs() <= dx_old.abs() {
                dx_old = dx;
                dx = newton;
                x = xn;
            } else {
                dx_old = dx;
                dx = 0.5 * (hi - lo);
                x = lo + dx;
            }
            (v, g, gp) = self.eval(f, x)?;
            if dx.abs() < 1e-10 {
                break;
            }
        }
        let better = if maximum { v >= value } else { v <= value };
        Ok(if better && v.is_finite() { (x, v) } else { grid })
    }
}

/// The grid neighbours of sample `k` on the periodic cycle grid `phis`.
pub(crate) fn neighbours(phis: &[f64], k: usize) -> (f64, f64) {
    let n = phis.len();
    let prev = if k == 0 { phis[n - 1] - 360.0 } else { phis[k - 1] };
    let next = if k + 1 == n { phis[0] + 360.0 } else { phis[k + 1] };
    (prev, next)
}

/// Indices of the smallest and the largest value.
pub(crate) use crate::eval::extremes as argminmax;

/// The axis a stroke is measured along.
#[derive(Debug, Clone, PartialEq)]
pub enum Axis {
    /// A world axis: 0 = x, 1 = y, 2 = z.
    World(usize),
    /// An axis of a model frame, the coordinate measured from its origin.
    Frame { frame: usize, name: String, axis: usize },
    /// A fixed world direction (normalised).
    Vector([f64; 3]),
}

impl Axis {
    /// `x`, `y`, `z`; `FRAME.x` (an axis of a model frame, e.g. `guide.y`);
    /// or a world direction `X,Y` or `X,Y,Z`.
    pub fn parse(model: &Model, spec: &str) -> Result<Axis, Error> {
        let bad = |message: String| {
            Error::Param(ParamError::general(
                message,
                Some(format!(
                    "write x, y or z (world axes), FRAME.x|y|z for an axis of a model frame ({}), or a direction X,Y[,Z]",
                    model.frame_names().join(", ")
                )),
            ))
        };
        let spec = spec.trim();
        let letter = |s: &str| match s {
            "x" => Some(0),
            "y" => Some(1),
            "z" => Some(2),
            _ => None,
        };
        if let Some(a) = letter(spec) {
            return Ok(Axis::World(a));
        }
        if spec.contains(',') {
            let parts: Vec<Option<f64>> = spec
                .split(',')
                .map(|s| s.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
                .collect();
            if !(2..=3).contains(&parts.len()) || parts.iter().any(Option::is_none) {
                return Err(bad(format!("`{spec}` is not a direction of two or three numbers")));
            }
            let v = V3::new(
                parts[0].unwrap_or(0.0),
                parts[1].unwrap_or(0.0),
                parts.get(2).copied().flatten().unwrap_or(0.0),
            );
            let n = v.norm();
            if n < 1e-12 {
                return Err(bad(format!("the direction `{spec}` has zero length")));
            }
            return Ok(Axis::Vector([v.x / n, v.y / n, v.z / n]));
        }
        if let Some((frame, a)) = spec.rsplit_once('.') {
            let Some(axis) = letter(a) else {
                return Err(bad(format!("`{a}` in `{spec}` is not x, y or z")));
            };
            let Some(f) = model.frame_index(frame) else {
                let hint = did_you_mean(frame, model.frame_names())
                    .map(|s| format!(" (did you mean `{s}`?)"))
                    .unwrap_or_default();
                return Err(bad(format!("the model has no frame `{frame}`{hint}")));
            };
            return Ok(if f == 0 {
                Axis::World(axis)
            } else {
                Axis::Frame {
                    frame: f,
                    name: frame.to_string(),
                    axis,
                }
            });
        }
        Err(bad(format!("`{spec}` is not an axis")))
    }

    /// Short label for column names: `y`, `guide_y`, `u`.
    pub fn label(&self) -> String {
        match self {
            Axis::World(a) => ["x", "y", "z"][*a].to_string(),
            Axis::Frame { name, axis, .. } => format!("{name}_{}", ["x", "y", "z"][*axis]),
            Axis::Vector(_) => "u".to_string(),
        }
    }

    /// In words, for headers.
    pub fn describe(&self) -> String {
        match self {
            Axis::World(a) => format!("{} (world)", ["x", "y", "z"][*a]),
            Axis::Frame { name, axis, .. } => format!("{} of frame `{name}` (from its origin)", ["x", "y", "z"][*axis]),
            Axis::Vector(v) => format!("u = ({:.4}, {:.4}, {:.4}) (world)", v[0], v[1], v[2]),
        }
    }

    /// Origin and unit direction in the world, for this mechanism (frames
    /// may move with parameters).
    fn resolve(&self, mech: &Mechanism<f64>) -> (V3<f64>, V3<f64>) {
        let e = |a: usize| V3::from_fn(|i, _| if i == a { 1.0 } else { 0.0 });
        match self {
            Axis::World(a) => (V3::zeros(), e(*a)),
            Axis::Frame { frame, axis, .. } => match mech.frame_plane(*frame).0 {
                Some(f) => (f.origin, f.dir_to_world(e(*axis))),
                None => (V3::zeros(), e(*axis)),
            },
            Axis::Vector(v) => (V3::zeros(), V3::new(v[0], v[1], v[2])),
        }
    }
}

/// One extreme position of the point along the axis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DeadCentre {
    /// Main-shaft angle, degrees in [0, 360); `None` when the point does not
    /// move along the axis.
    pub phi_deg: Option<f64>,
    /// The coordinate along the axis, mm.
    pub position_mm: f64,
    /// The point there, world x, y, z, mm.
    pub point_mm: [f64; 3],
}

/// A transmission angle over the cycle: its extremes (refined below the
/// grid step) and where it leaves 30°…150° (seed 002 eq. 15).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MuRange {
    #[serde(flatten)]
    pub range: crate::eval::TransmissionSummary,
    /// φ intervals (on the grid) where it is outside the band, degrees.
    pub outside_deg: Vec<[f64; 2]>,
}

impl std::ops::Deref for MuRange {
    type Target = crate::eval::TransmissionSummary;
    fn deref(&self) -> &Self::Target {
        &self.range
    }
}

/// The stroke at one setting.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stroke {
    /// max − min of the coordinate (seed 002 eq. 14), mm.
    pub stroke_mm: f64,
    /// The dead centre with the smallest coordinate (a needle's bottom dead
    /// centre along +y).
    pub min: DeadCentre,
    /// The dead centre with the largest coordinate.
    pub max: DeadCentre,
    /// φ from the min to the max dead centre (the rest of the turn goes back),
    /// degrees.
    pub min_to_max_deg: Option<f64>,
    /// Every dyad's transmission angle.
    pub mu: Vec<MuRange>,
}

/// Evaluates the stroke of `point` along `axis` at one setting, on the
/// cycle grid of `step_deg`, with the dead centres and angle extremes
/// refined (module docs).
pub fn stroke(model: &Model, params: &Params, point: usize, axis: &Axis, step_deg: f64) -> Result<Stroke, Error> {
    check_step(step_deg)?;
    let mech = model.mechanism::<f64>(params)?;
    let phis = cycle_phis_deg(model.phi_start_deg(), step_deg);
    let n = phis.len();
    let mut pose = mech.new_pose(n);
    mech.solve(&Phi::table(&phis), &mut pose)?;
    let mut refiner = Refiner::new(model, params)?;

    let (origin, dir) = axis.resolve(&mech);
    let along = Along { point, origin, dir };
    let s: Vec<f64> = (0..n).map(|k| along.at(&mech, &pose, k)).collect();
    let (kmin, kmax) = argminmax(&s);
    let moves = s[kmax] - s[kmin] >= NO_STROKE_MM;
    let mut dead_centre = |k: usize, maximum: bool| -> Result<DeadCentre, Error> {
        if !moves {
            let p = pose.point(point, k);
            return Ok(DeadCentre {
                phi_deg: None,
                position_mm: s[k],
                point_mm: [p.x, p.y, p.z],
            });
        }
        let (a, b) = neighbours(&phis, k);
        let (phi, v) = refiner.refine(&along, a, b, phis[k], s[k], maximum)?;
        Ok(DeadCentre {
            phi_deg: Some(wrap_deg(phi)),
            position_mm: v,
            point_mm: refiner.point(point, phi)?,
        })
    };
    let min = dead_centre(kmin, false)?;
    let max = dead_centre(kmax, true)?;
    let min_to_max_deg = match (min.phi_deg, max.phi_deg) {
        (Some(a), Some(b)) => Some((b - a).rem_euclid(360.0)),
        _ => None,
    };

    let mut mus: Vec<Vec<f64>> = vec![Vec::with_capacity(n); model.dyads.len()];
    let mut buf = Vec::new();
    for k in 0..n {
        mech.transmission_angles(&pose, k, &mut buf);
        for (j, m) in buf.iter().enumerate() {
            mus[j].push(*m);
        }
    }
    let mut mu = Vec::new();
    for (j, (d, v)) in model.dyads.iter().zip(&mus).enumerate() {
        let (i0, i1) = argminmax(v);
        let f = Mu(j);
        let (a, b) = neighbours(&phis, i0);
        let (phi_min, min_rad) = refiner.refine(&f, a, b, phis[i0], v[i0], false)?;
        let (a, b) = neighbours(&phis, i1);
        let (phi_max, max_rad) = refiner.refine(&f, a, b, phis[i1], v[i1], true)?;
        let (min_deg, max_deg) = (min_rad.to_degrees(), max_rad.to_degrees());
        let flags: Vec<bool> = v
            .iter()
            .map(|m| !(MU_MIN_DEG..=MU_MAX_DEG).contains(&m.to_degrees()))
            .collect();
        let outside_deg = crate::thread::intervals(&flags, &phis)
            .iter()
            .map(|i| [wrap_deg(i.from_deg), wrap_deg(i.to_deg)])
            .collect();
        mu.push(MuRange {
            range: crate::eval::TransmissionSummary {
                key: d.key.clone(),
                group: d.label.clone(),
                min_deg,
                phi_at_min_deg: wrap_deg(phi_min),
                max_deg,
                phi_at_max_deg: wrap_deg(phi_max),
                ok: min_deg >= MU_MIN_DEG && max_deg <= MU_MAX_DEG,
            },
            outside_deg,
        });
    }
    let out = Stroke {
        stroke_mm: max.position_mm - min.position_mm,
        min,
        max,
        min_to_max_deg,
        mu,
    };
    let finite = out.stroke_mm.is_finite()
        && out.min.point_mm.iter().chain(&out.max.point_mm).all(|x| x.is_finite())
        && out.mu.iter().all(|m| m.min_deg.is_finite() && m.max_deg.is_finite());
    if !finite {
        return Err(Error::NotFinite(NotFiniteError {
            quantity: "the stroke or a transmission angle".into(),
            phi_deg: None,
            cause: "the mechanism passes a dead point".into(),
        }));
    }
    Ok(out)
}

/// A varied parameter's name and unit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Varied {
    pub name: String,
    pub unit: &'static str,
}

/// One setting of a stroke study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StrokeRow {
    /// Values of the varied parameters, in `vary` order.
    pub setting: Vec<f64>,
    pub stroke: Option<Stroke>,
    /// Why the setting did not evaluate (no assembly, …).
    pub error: Option<String>,
}

/// Where a transmission angle crosses the band 30°…150° between two
/// neighbouring settings of the last varied parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BandCrossing {
    pub key: String,
    pub group: String,
    /// The parameter that moves (the last varied one) and where the angle
    /// reaches the band's edge, in its unit.
    pub parameter: String,
    pub value: f64,
    pub unit: &'static str,
    /// The other varied parameters, held.
    pub held: Vec<(String, f64)>,
    /// The edge reached: 30 (the minimum falls below) or 150 (the maximum
    /// rises above), degrees.
    pub bound_deg: f64,
    /// True when the angle is outside the band beyond `value` (the parameter
    /// growing), false when it comes back in.
    pub leaves: bool,
}

/// A stroke study: one row per setting, and the band crossings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StrokeStudy {
    pub model: String,
    pub point: String,
    /// Column label of the axis (`y`, `guide_y`, `u`) and the axis in words.
    pub axis: String,
    pub axis_words: String,
    pub step_deg: f64,
    pub vary: Vec<Varied>,
    pub rows: Vec<StrokeRow>,
    pub crossings: Vec<BandCrossing>,
}

/// How a stroke study is run.
#[derive(Debug, Clone, PartialEq)]
pub struct StrokeOptions {
    pub point: usize,
    pub axis: Axis,
    pub step_deg: f64,
}

fn at_setting(
    model: &Model,
    base: &Params,
    names: &[String],
    values: &[f64],
    opts: &StrokeOptions,
) -> Result<Stroke, Error> {
    let mut p = base.clone();
    for (n, x) in names.iter().zip(values) {
        model.set(&mut p, n, *x)?;
    }
    stroke(model, &p, opts.point, &opts.axis, opts.step_deg)
}

/// Runs the study: the base setting alone (`sweep` = `None`), or every
/// setting of a grid sweep, in parallel; then bisects on the last varied
/// parameter wherever a transmission angle enters or leaves the band
/// between neighbouring settings.
pub fn study(model: &Model, base: &Params, sweep: Option<&Sweep>, opts: &StrokeOptions) -> Result<StrokeStudy, Error> {
    check_step(opts.step_deg)?;
    let (names, settings) = grid_settings(sweep)?;
    let results: Vec<Result<Stroke, Error>> = settings
        .par_iter()
        .map(|x| at_setting(model, base, &names, x, opts))
        .collect();
    // A single setting that does not evaluate is an error, not a row.
    if sweep.is_none()
        && let Some(Err(e)) = results.first()
    {
        return Err(e.clone());
    }
    let rows: Vec<StrokeRow> = settings
        .iter()
        .zip(results)
        .map(|(x, r)| match r {
            Ok(s) => StrokeRow {
                setting: x.clone(),
                stroke: Some(s),
                error: None,
            },
            Err(e) => StrokeRow {
                setting: x.clone(),
                stroke: None,
                error: Some(e.to_string().replace('\n', " ")),
            },
        })
        .collect();
    let unit = |n: &str| model.param_index(n).map_or("", |i| model.params[i].unit_str());
    let crossings = match sweep {
        Some(s) => band_crossings(model, base, s, &names, &rows, opts),
        None => Vec::new(),
    };
    Ok(StrokeStudy {
        model: model.name().to_string(),
        point: model.point_names[opts.point].clone(),
        axis: opts.axis.label(),
        axis_words: opts.axis.describe(),
        step_deg: opts.step_deg,
        vary: names
            .iter()
            .map(|n| Varied {
                name: n.clone(),
                unit: unit(n),
            })
            .collect(),
        rows,
        crossings,
    })
}

/// The names of the varied parameters and every setting of the grid
/// `sweep` (one empty setting without a sweep).
fn grid_settings(sweep: Option<&Sweep>) -> Result<(Vec<String>, Vec<Vec<f64>>), Error> {
    Ok(match sweep {
        None => (Vec::new(), vec![Vec::new()]),
        Some(s) => {
            if s.design != super::design::Design::Grid {
                return Err(Error::Param(ParamError::new(
                    Input::Samples,
                    "a stroke study runs on a grid of settings, not a random sample",
                    Some("vary the parameters as NAME=LO:HI:N without a sample size".into()),
                )));
            }
            if s.len() > MAX_SETTINGS {
                return Err(Error::Param(ParamError::general(
                    format!(
                        "{} settings are more than a stroke table holds ({MAX_SETTINGS})",
                        s.len()
                    ),
                    Some(
                        "use fewer grid points, or a sweep with the figures `*_stroke_mm,mu.*`, which streams its rows"
                            .into(),
                    ),
                )));
            }
            (
                s.vary.iter().map(|v| v.name.clone()).collect(),
                (0..s.len()).map(|i| s.setting(i)).collect(),
            )
        }
    })
}

/// Where a transmission angle enters or leaves the band between
/// neighbouring settings of the grid `s` along its last parameter (the
/// others held), each found by bisection.
fn band_crossings(
    model: &Model,
    base: &Params,
    s: &Sweep,
    names: &[String],
    rows: &[StrokeRow],
    opts: &StrokeOptions,
) -> Vec<BandCrossing> {
    let unit = |n: &str| model.param_index(n).map_or("", |i| model.params[i].unit_str());
    let last = s.vary.len() - 1;
    let n_last = s.vary[last].n;
    // Neighbouring settings along the last parameter, the others held.
    let pairs: Vec<(usize, usize)> = (0..rows.len().saturating_sub(1))
        .filter(|i| (i + 1) % n_last != 0)
        .map(|i| (i, i + 1))
        .collect();
    let found: Vec<Vec<BandCrossing>> = pairs
        .par_iter()
        .map(|&(i, j)| {
            let (Some(a), Some(b)) = (&rows[i].stroke, &rows[j].stroke) else {
                return Vec::new();
            };
            let mut out = Vec::new();
            for (dyad, (ma, mb)) in a.mu.iter().zip(&b.mu).enumerate() {
                if ma.ok == mb.ok {
                    continue;
                }
                let (x, bound) = bisect_band(
                    model,
                    base,
                    names,
                    &rows[i].setting,
                    rows[i].setting[last],
                    rows[j].setting[last],
                    dyad,
                    ma.ok,
                    opts,
                );
                out.push(BandCrossing {
                    key: ma.key.clone(),
                    group: ma.group.clone(),
                    parameter: names[last].clone(),
                    value: x,
                    unit: unit(&names[last]),
                    held: names[..last]
                        .iter()
                        .cloned()
                        .zip(rows[i].setting[..last].iter().cloned())
                        .collect(),
                    bound_deg: bound,
                    leaves: ma.ok,
                });
            }
            out
        })
        .collect();
    found.into_iter().flatten().collect()
}

/// The value of the last varied parameter between `lo` (angle `dyad` in
/// the band when `ok_at_lo`) and `hi` where the angle reaches the band's
/// edge, by bisection (to 1e-9 of the interval; a setting that does not
/// assemble counts as outside the band), and that edge in degrees.
#[allow(clippy::too_many_arguments)]
fn bisect_band(
    model: &Model,
    base: &Params,
    names: &[String],
    setting: &[f64],
    lo: f64,
    hi: f64,
    dyad: usize,
    ok_at_lo: bool,
    opts: &StrokeOptions,
) -> (f64, f64) {
    let last = names.len() - 1;
    let eval = |x: f64| {
        let mut values = setting.to_vec();
        values[last] = x;
        at_setting(model, base, names, &values, opts)
            .ok()
            .map(|s| s.mu[dyad].clone())
    };
    let ok = |m: &Option<MuRange>| m.as_ref().is_some_and(|m| m.ok);
    let (mut a, mut b) = (lo, hi);
    let mut outside = eval(if ok_at_lo { hi } else { lo });
    for _ in 0..200 {
        if (b - a).abs() <= 1e-9 * (hi - lo).abs() {
            break;
        }
        let m = 0.5 * (a + b);
        let r = eval(m);
        if ok(&r) == ok_at_lo {
            a = m;
        } else {
            b = m;
            outside = r;
        }
    }
    let bound = match &outside {
        Some(m) if m.max_deg > MU_MAX_DEG && m.min_deg >= MU_MIN_DEG => MU_MAX_DEG,
        _ => MU_MIN_DEG,
    };
    (0.5 * (a + b), bound)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A central slider-crank along x: crank r = 10 about the origin, rod 40,
    /// slider on the x axis: dead centres at φ = 0° and 180°, stroke 2r.
    const SLIDER_CRANK: &str = r#"
        [model]
        name = "slider-crank"
        [parameters]
        r = { value = 10, unit = "mm" }
        [points]
        O = [0, 0]
        H = [0, 0]
        [[drivers]]
        type = "crank"
        center = "O"
        out = "A"
        radius = "r"
        [[groups]]
        type = "rrp"
        name = "slider"
        from = "A"
        length = 40
        through = "H"
        direction_deg = 0
        out = "S"
        branch = "forward"
    "#;

    #[test]
    fn slider_crank_dead_centres_are_exact_below_the_grid_step() {
        let m = Model::from_toml_str(SLIDER_CRANK, "slider.toml").unwrap();
        let s = m.moving_point_slot("S").unwrap();
        assert!(m.moving_point_slot("O").unwrap_err().to_string().contains("is fixed"));
        // A 7° grid misses both dead centres; refinement finds them.
        let r = stroke(&m, &m.defaults(), s, &Axis::World(0), 7.0).unwrap();
        assert!((r.stroke_mm - 20.0).abs() < 1e-12, "{r:?}");
        let (min, max) = (r.min.phi_deg.unwrap(), r.max.phi_deg.unwrap());
        assert!((max - 0.0).abs() < 1e-9 || (max - 360.0).abs() < 1e-9, "{max}");
        assert!((min - 180.0).abs() < 1e-9, "{min}");
        assert!((r.max.position_mm - 50.0).abs() < 1e-12 && (r.min.position_mm - 30.0).abs() < 1e-12);
        assert!((r.min_to_max_deg.unwrap() - 180.0).abs() < 1e-9);
        // Along y the slider does not move: no dead centres.
        let y = stroke(&m, &m.defaults(), s, &Axis::World(1), 7.0).unwrap();
        assert!(y.stroke_mm.abs() < 1e-12 && y.min.phi_deg.is_none() && y.min_to_max_deg.is_none());
        // The rod's transmission angle: 90° at the dead centres, 90° − asin(r/l) at its least.
        let mu = &r.mu[0];
        assert!((mu.max_deg - 90.0).abs() < 1e-9, "{mu:?}");
        assert!(
            (mu.min_deg - (90.0 - (10.0f64 / 40.0).asin().to_degrees())).abs() < 1e-9,
            "{mu:?}"
        );
    }

    #[test]
    fn axes_parse_with_clear_errors() {
        let m = Model::preset("altin-needle").unwrap();
        assert_eq!(Axis::parse(&m, "y").unwrap(), Axis::World(1));
        assert_eq!(Axis::parse(&m, "world.x").unwrap(), Axis::World(0));
        assert!(matches!(
            Axis::parse(&m, "guide.y").unwrap(),
            Axis::Frame { axis: 1, .. }
        ));
        let Axis::Vector(v) = Axis::parse(&m, "3,4").unwrap() else {
            panic!()
        };
        assert!((v[0] - 0.6).abs() < 1e-15 && (v[1] - 0.8).abs() < 1e-15);
        for (bad, says) in [
            ("w", "not an axis"),
            ("gide.y", "did you mean `guide`"),
            ("guide.q", "not x, y or z"),
            ("0,0", "zero length"),
            ("1,a", "two or three numbers"),
        ] {
            let e = Axis::parse(&m, bad).unwrap_err().to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }
}
