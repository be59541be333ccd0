//! A measured take-up curve against the model (seed 004 §3 measured P(φ)
//! on a Textima Altin): the match metrics of `docs/stitch-formation.md` §8
//! of the curve against the thread's other curve (a measured P against the
//! model's P′, a measured P′ against the model's P), and against the
//! model's own curve of the same kind (how well the model reproduces the
//! measurement).

use serde::Serialize;

use crate::error::{Error, Input, ParamError};
use crate::eval::CycleTable;
use crate::eval::stitch_process::{compared_outside, mismatch_on_cycle};
use crate::stitch::mismatch::Mismatch;
use crate::thread::measured::{CurveKind, MeasuredCurve, SplitPoint};

/// A measured curve set beside one thread of the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuredMatch {
    /// The file it came from.
    pub source: String,
    /// The stitch thread it belongs to.
    pub thread: String,
    pub kind: CurveKind,
    /// Where it is measured: the thread's own split (a curve
    /// measured at the moving eye of a needle thread is moved to B with the
    /// needle's travel: P_B = P_eye + S − S(φ0)).
    pub split: SplitPoint,
    /// Whether the file's column named the split (`P_B_mm`, `P_eye_mm`) or
    /// it was taken to be the thread's.
    pub split_declared: bool,
    /// The curve on the cycle's φ grid at the thread's split, mm.
    pub values_mm: Vec<f64>,
    /// A measured P against the model's P′, or the model's P against a
    /// measured P′: D = P − P′ as the stitch sees it.
    pub against_other: Option<Mismatch>,
    /// The model's curve of the same kind against the measured one:
    /// D = model − measured, the score scaled by the measured curve's swing.
    pub against_model: Option<Mismatch>,
    /// When the curve is the mean of repeated readings (seed 004 §3.4):
    /// how they were processed and what the interval says.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interval: Option<MeasuredInterval>,
}

/// The interval of a mean curve of repeated readings on the cycle's grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuredInterval {
    /// The confidence of the interval.
    pub confidence: f64,
    /// The most readings at any φ.
    pub readings_per_phi: usize,
    /// The instrument's resolution, the systematic error, mm.
    pub resolution_mm: f64,
    /// The half-width Δ (the total error) on the cycle's φ grid, mm.
    pub half_width_mm: Vec<f64>,
    /// The share of the cycle's φ at which the model's curve of the same
    /// kind lies within the interval, %.
    pub model_within_pct: f64,
    /// The number of readings Grubbs' test flags.
    pub outliers: usize,
    /// The φ of the readings, deg, and the half-width Δ there, mm (the
    /// error bars).
    pub readings_phi_deg: Vec<f64>,
    pub readings_half_width_mm: Vec<f64>,
}

fn bad(message: String, help: String) -> Error {
    Error::Param(ParamError::general(message, Some(help)))
}

/// A measured curve given that cannot be placed.
fn bad_input(message: String, help: String) -> Error {
    Error::Param(ParamError::new(Input::Measured, message, Some(help)))
}

/// Sets `curve` beside the stitch thread `thread` of the cycle `table`
/// (default: the thread the curve's column names, as a thread `n1` or its
/// path `n1_A`, or the only thread compared with a path).
pub fn measured_match(table: &CycleTable, curve: &MeasuredCurve, thread: Option<&str>) -> Result<MeasuredMatch, Error> {
    let source = curve.source();
    let Some(st) = &table.stitch else {
        return path_match(table, curve, thread);
    };
    let compared: Vec<&str> = st
        .threads
        .iter()
        .filter(|t| t.path.is_some())
        .map(|t| t.thread.as_str())
        .collect();
    let wanted = thread.or(curve.thread());
    let th = match wanted {
        Some(w) => st
            .threads
            .iter()
            .find(|t| t.thread == w || t.path.as_deref() == Some(w))
            .ok_or_else(|| {
                bad(
                    format!("{source}: the model has no stitch thread or thread path `{w}`"),
                    format!("its compared threads are: {}", compared.join(", ")),
                )
            })?,
        None => match compared.as_slice() {
            [one] => st.threads.iter().find(|t| t.thread == *one).expect("listed above"),
            _ => {
                return Err(bad_input(
                    format!(
                        "{source}: the curve does not say which thread it is, and the model compares {}",
                        compared.join(", ")
                    ),
                    format!(
                        "name the column after the thread (e.g. `{}.P_B_mm`) or give the curve as THREAD=FILE",
                        compared.first().unwrap_or(&"n1")
                    ),
                ));
            }
        },
    };
    let Some(path) = &th.path else {
        return Err(bad(
            format!("{source}: thread `{}` has no take-up path to compare", th.thread),
            "give it a `path` in [stitch]".into(),
        ));
    };
    let column = |name: String| -> Result<&[f64], Error> {
        table.column(&name).ok_or_else(|| {
            bad(
                format!("{source}: the cycle has no column `{name}`"),
                "run the full cycle (not a lean one)".into(),
            )
        })
    };
    let phis = column("phi_deg".into())?;
    let p = column(
        table
            .paths
            .iter()
            .find(|q| &q.path == path)
            .map_or(format!("{path}.P_mm"), |q| q.p_column.clone()),
    )?;
    let at_b = th.split == SplitPoint::B;
    let pprime = column(th.pprime_column())?;
    let mut values = curve.resample(phis);
    match (curve.split(), at_b) {
        (Some(SplitPoint::Eye), true) => {
            // S − S(φ0) = P'_B − P'_eye.
            let eye = column(format!("{}.Pprime_eye_mm", th.thread))?;
            for (k, v) in values.iter_mut().enumerate() {
                *v += pprime[k] - eye[k];
            }
        }
        (Some(SplitPoint::B), false) => {
            return Err(bad(
                format!(
                    "{source}: `{}` is measured at B, but thread `{}` is a looper thread measured at its eye",
                    curve.column(),
                    th.thread
                ),
                "give the curve at the looper eye (a column `P_mm` or `Pprime_mm`)".into(),
            ));
        }
        _ => {}
    }
    let compared_at = compared_outside(phis, &th.regulator_windows_deg);
    let eps = st.tolerance_mm;
    let (against_other, against_model) = match curve.kind() {
        CurveKind::TakeUp => (
            mismatch_on_cycle(phis, &values, pprime, &compared_at, eps, true),
            mismatch_on_cycle(phis, p, &values, &compared_at, eps, true),
        ),
        CurveKind::Required => (
            mismatch_on_cycle(phis, p, &values, &compared_at, eps, true),
            mismatch_on_cycle(phis, pprime, &values, &compared_at, eps, true),
        ),
    };
    let model = if curve.kind() == CurveKind::TakeUp { p } else { pprime };
    let interval = interval(curve, phis, &values, model);
    Ok(MeasuredMatch {
        interval,
        source: source.to_string(),
        thread: th.thread.clone(),
        kind: curve.kind(),
        split: th.split,
        split_declared: curve.split().is_some(),
        values_mm: values,
        against_other,
        against_model,
    })
}

/// A curve set beside a thread path of a model without `[stitch]`: a
/// required P′ (a target, e.g. another machine's P′ or a bench's) against
/// the path's take-up P, or a measured P against the model's P, over the
/// whole turn (no regulator window is known) with ε = the default
/// tolerance.
fn path_match(table: &CycleTable, curve: &MeasuredCurve, thread: Option<&str>) -> Result<MeasuredMatch, Error> {
    let source = curve.source();
    let names: Vec<&str> = table.paths.iter().map(|q| q.path.as_str()).collect();
    if names.is_empty() {
        return Err(bad(
            format!(
                "{source}: the model has no [stitch] and no thread path, so a measured curve has nothing to be compared with"
            ),
            "add a [thread] table with [[thread.paths]] (docs/model-format.md §13)".into(),
        ));
    }
    let path = match thread.or(curve.thread()) {
        Some(w) => table.paths.iter().find(|q| q.path == w).ok_or_else(|| {
            bad(
                format!("{source}: the model has no [stitch] and no thread path `{w}`"),
                format!("name one of its thread paths: {}", names.join(", ")),
            )
        })?,
        None => match table.paths.as_slice() {
            [one] => one,
            _ => {
                return Err(bad_input(
                    format!(
                        "{source}: the curve does not say which thread path it is, and the model has {}",
                        names.join(", ")
                    ),
                    format!(
                        "name the column after the path (e.g. `{}.Pprime_mm`) or give the curve as PATH=FILE",
                        names[0]
                    ),
                ));
            }
        },
    };
    if curve.split().is_some_and(|s| s != SplitPoint::End) {
        return Err(bad(
            format!(
                "{source}: `{}` is read at a needle's eye or at B, but the model has no [stitch] to place a needle \
                 thread's split",
                curve.column()
            ),
            "give the curve at the path's end (a column `P_mm` or `Pprime_mm`)".into(),
        ));
    }
    let column = |name: &str| -> Result<&[f64], Error> {
        table.column(name).ok_or_else(|| {
            bad(
                format!("{source}: the cycle has no column `{name}`"),
                "run the full cycle (not a lean one)".into(),
            )
        })
    };
    let phis = column("phi_deg")?;
    let p = column(&path.p_column)?;
    let values = curve.resample(phis);
    let compared = vec![true; phis.len()];
    let eps = crate::model::stitch_setup::DEFAULT_TOLERANCE_MM;
    let (against_other, against_model, interval) = match curve.kind() {
        CurveKind::Required => (mismatch_on_cycle(phis, p, &values, &compared, eps, true), None, None),
        CurveKind::TakeUp => (
            None,
            mismatch_on_cycle(phis, p, &values, &compared, eps, true),
            interval(curve, phis, &values, p),
        ),
    };
    Ok(MeasuredMatch {
        interval,
        source: source.to_string(),
        thread: path.path.clone(),
        kind: curve.kind(),
        split: SplitPoint::End,
        split_declared: curve.split().is_some(),
        values_mm: values,
        against_other,
        against_model,
    })
}

/// The interval of a mean curve of repeated readings on the grid `phis`
/// (`values` the curve there), and the share of φ at which `model` lies
/// within it; `None` for a curve of one value per φ.
fn interval(curve: &MeasuredCurve, phis: &[f64], values: &[f64], model: &[f64]) -> Option<MeasuredInterval> {
    let r = curve.readings()?;
    let half = curve.interval_at(phis)?;
    let within = values
        .iter()
        .zip(model)
        .zip(&half)
        .filter(|((v, m), h)| (*m - *v).abs() <= **h)
        .count();
    Some(MeasuredInterval {
        confidence: r.confidence,
        readings_per_phi: r.max_n(),
        resolution_mm: r.resolution_mm,
        model_within_pct: 100.0 * within as f64 / values.len().max(1) as f64,
        half_width_mm: half,
        outliers: r.outlier_count(),
        readings_phi_deg: r.points.iter().map(|q| q.phi_deg).collect(),
        readings_half_width_mm: r.points.iter().map(|q| q.total_mm).collect(),
    })
}
