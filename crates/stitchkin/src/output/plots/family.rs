//! P(φ) of one thread path as a parameter varies (seed 000 Fig. 6–7): a
//! family of lines with the required P'(φ) for comparison, a heat map of P
//! over (φ, parameter), or a projected surface.

use rayon::prelude::*;

use super::{check_vary, closed, column, number_text, param_unit, phi_axis, select_paths, title, unit_label, value_text};
use crate::error::Error;
use crate::eval::{CycleOptions, run_cycle};
use crate::model::{Model, Params};
use crate::output::svg::{Axis, Chart, Heat, Series, Surface, family_color, nice_step};
use crate::study::sweep::Vary;

/// P(φ) of one path over the values of a varied parameter.
#[derive(Debug, Clone)]
pub struct FamilyData {
    /// The varied parameter, its unit (`mm`, `deg`, or empty) and values
    /// (ascending).
    pub name: String,
    pub unit: &'static str,
    pub values: Vec<f64>,
    /// The thread path.
    pub path: String,
    /// φ over one cycle, closed (the start again at start + 360°).
    pub phis: Vec<f64>,
    /// P per value, closed like `phis`; `None` where the cycle failed.
    pub p: Vec<Option<Vec<f64>>>,
    /// The stitch thread on `path` and its P' per value, when the model
    /// has a `[stitch]` that compares a thread with this path.
    pub thread: Option<String>,
    pub pprime: Vec<Option<Vec<f64>>>,
    /// Why the cycle failed, per failed value.
    pub failures: Vec<(f64, String)>,
    /// The φ step, degrees.
    pub step_deg: f64,
}

impl FamilyData {
    /// The grid spacing of the values.
    fn spacing(&self) -> f64 {
        if self.values.len() > 1 { (self.values[self.values.len() - 1] - self.values[0]) / (self.values.len() - 1) as f64 } else { 1.0 }
    }

    /// `r1 = 4.5 mm` for value `k`.
    pub fn value_text(&self, k: usize) -> String {
        value_text(&self.name, self.values[k], self.spacing(), self.unit)
    }

    /// P' when it is the same for every value (the parameter leaves the
    /// stitch alone), else `None`.
    fn common_pprime(&self) -> Option<&Vec<f64>> {
        let mut it = self.pprime.iter().flatten();
        let first = it.next()?;
        it.all(|q| q.len() == first.len() && q.iter().zip(first).all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs()))).then_some(first)
    }

    fn failure_note(&self) -> String {
        if self.failures.is_empty() {
            return String::new();
        }
        let at: Vec<String> = self.failures.iter().map(|(v, _)| value_text(&self.name, *v, self.spacing(), self.unit)).collect();
        format!("; no cycle at {}", at.join(", "))
    }
}

/// Runs the cycle for each of the N values of `vary` (in parallel) and
/// keeps P of `path` (`None`: the model's first thread path) and the P' of
/// the stitch thread compared with it. A value whose cycle fails is kept
/// as a gap with its reason; when all fail, the first error is returned.
pub fn family_data(model: &Model, params: &Params, vary: &Vary, path: Option<&str>, step_deg: f64) -> Result<FamilyData, Error> {
    check_vary(model, vary)?;
    let wanted: Vec<String> = path.map(|p| vec![p.to_string()]).unwrap_or_default();
    let path = select_paths(model, &wanted)?.remove(0);
    let (lo, hi) = (vary.lo.min(vary.hi), vary.lo.max(vary.hi));
    let ascending = Vary { name: vary.name.clone(), lo, hi, n: vary.n };
    let values: Vec<f64> = (0..vary.n).map(|k| ascending.grid_value(k)).collect();
    let opts = CycleOptions { step_deg, analogs: false, points: Some(Vec::new()), lean: true, ..Default::default() };
    let runs: Vec<Result<crate::eval::CycleTable, Error>> = values
        .par_iter()
        .map(|&v| {
            let mut p = params.clone();
            model.set(&mut p, &vary.name, v)?;
            run_cycle(model, &p, &opts)
        })
        .collect();
    if let Some(Err(e)) = runs.first()
        && runs.iter().all(Result::is_err)
    {
        return Err(e.clone());
    }
    let thread = runs.iter().flatten().find_map(|t| t.stitch.as_ref()?.threads.iter().find(|th| th.path.as_deref() == Some(path.as_str())).map(|th| th.thread.clone()));
    let mut phis = Vec::new();
    let (mut p, mut pprime, mut failures) = (Vec::new(), Vec::new(), Vec::new());
    for (run, &v) in runs.iter().zip(&values) {
        match run {
            Ok(t) => {
                let ph = column(t, "phi_deg")?;
                let pts = closed(ph, column(t, &format!("{path}.P_mm"))?);
                phis = pts.iter().map(|q| q.0).collect();
                p.push(Some(pts.iter().map(|q| q.1).collect()));
                pprime.push(match &thread {
                    Some(th) => t.column(&format!("{th}.Pprime_mm")).map(|c| closed(ph, c).iter().map(|q| q.1).collect()),
                    None => None,
                });
            }
            Err(e) => {
                p.push(None);
                pprime.push(None);
                failures.push((v, e.to_string().replace('\n', " ")));
            }
        }
    }
    Ok(FamilyData { name: vary.name.clone(), unit: param_unit(model, &vary.name), values, path, phis, p, thread, pprime, failures, step_deg })
}

/// The line family: P(φ) per value in a colour ramp (dark: the low end),
/// and P'(φ) dashed: one grey line when the parameter leaves it alone,
/// else one per value in its colour.
pub fn family(model: &Model, d: &FamilyData) -> Result<Chart, Error> {
    let mut chart = Chart::new(title(model, &format!("take-up P(φ) of {} as {} varies", d.path, d.name)), phi_axis(model), Axis::new("P, mm"));
    let n = d.values.len();
    for k in 0..n {
        if let Some(p) = &d.p[k] {
            chart.series.push(Series::new(d.value_text(k), d.phis.iter().copied().zip(p.iter().copied()).collect(), family_color(k, n)));
        }
    }
    let range = format!("{} from {} to {}", d.name, number_text(d.values[0], d.spacing(), d.unit), number_text(d.values[n - 1], d.spacing(), d.unit));
    let mut sub = format!("{n} values of {range}, the rest as set");
    let rows: Vec<&Vec<f64>> = d.p.iter().flatten().collect();
    if rows.len() > 1 && rows.iter().all(|r| r.iter().zip(rows[0]).all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs()))) {
        sub += &format!(" (P is the same for every value: {} does not move the thread path)", d.name);
    }
    if let Some(th) = &d.thread {
        match d.common_pprime() {
            Some(q) => {
                let mut s = Series::new(format!("{th} P′ (required)"), d.phis.iter().copied().zip(q.iter().copied()).collect(), "#555555");
                s.dashed = true;
                chart.series.push(s);
                sub += &format!("; dashed: P′ of thread {th}, the same for every value");
            }
            None => {
                for k in 0..n {
                    if let Some(q) = &d.pprime[k] {
                        let mut s = Series::new(format!("{th} P′, {}", d.value_text(k)), d.phis.iter().copied().zip(q.iter().copied()).collect(), family_color(k, n));
                        s.dashed = true;
                        chart.series.push(s);
                    }
                }
                sub += &format!("; dashed: P′ of thread {th} per value");
            }
        }
    }
    chart.subtitle = Some(sub + &d.failure_note());
    Ok(chart)
}

/// P as a matrix over (value, φ), NaN where the cycle failed.
fn p_rows(d: &FamilyData) -> Vec<Vec<f64>> {
    d.p.iter().map(|p| p.clone().unwrap_or_else(|| vec![f64::NAN; d.phis.len()])).collect()
}

/// The heat map of P over φ (x) and the parameter (y), with a colour bar.
pub fn surface_heat(model: &Model, d: &FamilyData) -> Chart {
    let (lo, hi) = (d.values[0], d.values[d.values.len() - 1]);
    let half = d.spacing() / 2.0;
    let y = Axis { label: unit_label(&d.name, d.unit), range: Some((lo - half, hi + half)), step: Some(nice_step(hi - lo, 6)) };
    let mut chart = Chart::new(title(model, &format!("take-up P of {} over φ and {}", d.path, d.name)), phi_axis(model), y);
    let z = p_rows(d);
    let tips = z
        .iter()
        .enumerate()
        .map(|(k, row)| row.iter().zip(&d.phis).map(|(p, phi)| {
                    let v = if p.is_finite() { format!("P = {p:.2} mm") } else { "no cycle".into() };
                    format!("φ = {}°, {}: {v}", crate::output::fmt_num(*phi), d.value_text(k))
                }).collect())
        .collect();
    chart.heat = Some(Heat { xs: d.phis.clone(), ys: d.values.clone(), z, label: "P, mm".into(), tips, missing: "no cycle (does not assemble)".into() });
    chart.subtitle = Some(format!("colour: the take-up P; one row per value of {} ({} values), φ every {}°{}", d.name, d.values.len(), d.step_deg, d.failure_note()));
    chart
}

/// The projected wireframe surface P(φ, parameter).
pub fn surface_wireframe(model: &Model, d: &FamilyData) -> Surface {
    let x = phi_axis(model);
    Surface {
        title: title(model, &format!("take-up P of {} over φ and {}", d.path, d.name)),
        subtitle: Some(format!("surface P(φ, {}), one line along φ per value ({} values), across every 30°{}", d.name, d.values.len(), d.failure_note())),
        x,
        y: Axis::new(unit_label(&d.name, d.unit)),
        z: Axis::new("P, mm"),
        xs: d.phis.clone(),
        ys: d.values.clone(),
        z_values: p_rows(d),
        cross_every: ((30.0 / d.step_deg).round() as usize).max(1),
        width: 900.0,
        height: 600.0,
    }
}
