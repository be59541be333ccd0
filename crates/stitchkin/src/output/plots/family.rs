//! P(φ) of one thread path as a parameter varies (seed 000 Fig. 7): a
//! family of lines with the required P'(φ) for comparison, a heat map of P
//! over (φ, parameter), or a projected surface. The heat map and the
//! surface draw any quantity over φ and a parameter ([`Quantity`]): a
//! motion law's too (seed 000 Fig. 6, [`super::motion`]).

use super::{number_text, phi_axis, title, unit_label, value_text};
use crate::error::Error;
use crate::model::Model;
use crate::output::svg::{Axis, Chart, Heat, Series, Surface, family_color, nice_step};

/// The values of a varied parameter and the φ of one cycle: the grid the
/// lines of a family and the rows of a surface share.
#[derive(Debug, Clone)]
pub struct VaryGrid {
    /// The varied parameter, its unit (`mm`, `deg`, or empty) and values
    /// (ascending).
    pub name: String,
    pub unit: &'static str,
    pub values: Vec<f64>,
    /// φ over one cycle, closed (the start again at start + 360°).
    pub phis: Vec<f64>,
    /// Why the cycle failed, per failed value.
    pub failures: Vec<(f64, String)>,
    /// The φ step, degrees.
    pub step_deg: f64,
}

impl VaryGrid {
    /// The grid spacing of the values.
    fn spacing(&self) -> f64 {
        if self.values.len() > 1 {
            (self.values[self.values.len() - 1] - self.values[0]) / (self.values.len() - 1) as f64
        } else {
            1.0
        }
    }

    /// `r1 = 4.5 mm` for value `k`.
    pub fn value_text(&self, k: usize) -> String {
        value_text(&self.name, self.values[k], self.spacing(), self.unit)
    }

    /// `r1 from 4.0 to 6.0 mm`.
    pub(super) fn range_text(&self) -> String {
        let n = self.values.len();
        format!(
            "{} from {} to {}",
            self.name,
            number_text(self.values[0], self.spacing(), self.unit),
            number_text(self.values[n - 1], self.spacing(), self.unit)
        )
    }

    pub(super) fn failure_note(&self) -> String {
        if self.failures.is_empty() {
            return String::new();
        }
        let at: Vec<String> = self
            .failures
            .iter()
            .map(|(v, _)| value_text(&self.name, *v, self.spacing(), self.unit))
            .collect();
        format!("; no cycle at {}", at.join(", "))
    }
}

/// What the rows of a heat map or a surface hold: its symbol and unit
/// (`P`, `mm`), which label the colour bar and the z axis, and what it is
/// in words for the title (`take-up P of n1_A`).
#[derive(Debug, Clone, PartialEq)]
pub struct Quantity {
    pub symbol: String,
    pub unit: String,
    pub what: String,
}

/// P(φ) of one path over the values of a varied parameter.
#[derive(Debug, Clone)]
pub struct FamilyData {
    /// The varied parameter's values and the φ of the cycle.
    pub grid: VaryGrid,
    /// The thread path.
    pub path: String,
    /// P per value, closed like `grid.phis`; `None` where the cycle failed.
    pub p: Vec<Option<Vec<f64>>>,
    /// The stitch thread on `path` and its P' per value, when the model
    /// has a `[stitch]` that compares a thread with this path.
    pub thread: Option<String>,
    pub pprime: Vec<Option<Vec<f64>>>,
}

impl FamilyData {
    /// P' when it is the same for every value (the parameter leaves the
    /// stitch alone), else `None`.
    fn common_pprime(&self) -> Option<&Vec<f64>> {
        let mut it = self.pprime.iter().flatten();
        let first = it.next()?;
        it.all(|q| {
            q.len() == first.len()
                && q.iter()
                    .zip(first)
                    .all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs()))
        })
        .then_some(first)
    }

    /// The take-up P of the path, as a surface draws it.
    pub fn quantity(&self) -> Quantity {
        Quantity {
            symbol: "P".into(),
            unit: "mm".into(),
            what: format!("take-up P of {}", self.path),
        }
    }
}

/// The line family: P(φ) per value in a colour ramp (dark: the low end),
/// and P'(φ) dashed: one grey line when the parameter leaves it alone,
/// else one per value in its colour.
pub fn family(model: &Model, d: &FamilyData) -> Result<Chart, Error> {
    let g = &d.grid;
    let mut chart = Chart::new(
        title(model, &format!("take-up P(φ) of {} as {} varies", d.path, g.name)),
        phi_axis(model),
        Axis::new("P, mm"),
    );
    let n = g.values.len();
    for k in 0..n {
        if let Some(p) = &d.p[k] {
            chart.series.push(Series::new(
                g.value_text(k),
                g.phis.iter().copied().zip(p.iter().copied()).collect(),
                family_color(k, n),
            ));
        }
    }
    let mut sub = format!("{n} values of {}, the rest as set", g.range_text());
    let rows: Vec<&Vec<f64>> = d.p.iter().flatten().collect();
    if rows.len() > 1
        && rows.iter().all(|r| {
            r.iter()
                .zip(rows[0])
                .all(|(a, b)| (a - b).abs() <= 1e-9 * (1.0 + b.abs()))
        })
    {
        sub += &format!(
            " (P is the same for every value: {} does not move the thread path)",
            g.name
        );
    }
    if let Some(th) = &d.thread {
        match d.common_pprime() {
            Some(q) => {
                let mut s = Series::new(
                    format!("{th} P′ (required)"),
                    g.phis.iter().copied().zip(q.iter().copied()).collect(),
                    "#555555",
                );
                s.dashed = true;
                chart.series.push(s);
                sub += &format!("; dashed: P′ of thread {th}, the same for every value");
            }
            None => {
                for k in 0..n {
                    if let Some(q) = &d.pprime[k] {
                        let mut s = Series::new(
                            format!("{th} P′, {}", g.value_text(k)),
                            g.phis.iter().copied().zip(q.iter().copied()).collect(),
                            family_color(k, n),
                        );
                        s.dashed = true;
                        chart.series.push(s);
                    }
                }
                sub += &format!("; dashed: P′ of thread {th} per value");
            }
        }
    }
    chart.subtitle = Some(sub + &g.failure_note());
    Ok(chart)
}

/// The rows as a matrix over (value, φ), NaN where the cycle failed.
fn z_rows(g: &VaryGrid, rows: &[Option<Vec<f64>>]) -> Vec<Vec<f64>> {
    rows.iter()
        .map(|r| r.clone().unwrap_or_else(|| vec![f64::NAN; g.phis.len()]))
        .collect()
}

/// The heat map of a quantity over φ (x) and the parameter (y), with a
/// colour bar: `rows` holds it per value of the grid (`None`: no cycle).
pub fn surface_heat(model: &Model, g: &VaryGrid, q: &Quantity, rows: &[Option<Vec<f64>>]) -> Chart {
    let (lo, hi) = (g.values[0], g.values[g.values.len() - 1]);
    let half = g.spacing() / 2.0;
    let y = Axis {
        label: unit_label(&g.name, g.unit),
        range: Some((lo - half, hi + half)),
        step: Some(nice_step(hi - lo, 6)),
    };
    let mut chart = Chart::new(
        title(model, &format!("{} over φ and {}", q.what, g.name)),
        phi_axis(model),
        y,
    );
    let z = z_rows(g, rows);
    let tips = z
        .iter()
        .enumerate()
        .map(|(k, row)| {
            row.iter()
                .zip(&g.phis)
                .map(|(v, phi)| {
                    let v = if v.is_finite() {
                        format!("{} = {v:.2} {}", q.symbol, q.unit)
                    } else {
                        "no cycle".into()
                    };
                    format!("φ = {}°, {}: {v}", crate::format::fmt_num(*phi), g.value_text(k))
                })
                .collect()
        })
        .collect();
    chart.heat = Some(Heat {
        xs: g.phis.clone(),
        ys: g.values.clone(),
        z,
        label: unit_label(&q.symbol, &q.unit),
        tips,
        missing: "no cycle (does not assemble)".into(),
    });
    chart.subtitle = Some(format!(
        "colour: {}; one row per value of {} ({} values), φ every {}°{}",
        q.what,
        g.name,
        g.values.len(),
        g.step_deg,
        g.failure_note()
    ));
    chart
}

/// The projected wireframe surface of a quantity over (φ, parameter).
pub fn surface_wireframe(model: &Model, g: &VaryGrid, q: &Quantity, rows: &[Option<Vec<f64>>]) -> Surface {
    let x = phi_axis(model);
    Surface {
        title: title(model, &format!("{} over φ and {}", q.what, g.name)),
        subtitle: Some(format!(
            "surface {}(φ, {}), one line along φ per value ({} values), across every 30°{}",
            q.symbol,
            g.name,
            g.values.len(),
            g.failure_note()
        )),
        x,
        y: Axis::new(unit_label(&g.name, g.unit)),
        z: Axis::new(unit_label(&q.symbol, &q.unit)),
        xs: g.phis.clone(),
        ys: g.values.clone(),
        z_values: z_rows(g, rows),
        cross_every: ((30.0 / g.step_deg).round() as usize).max(1),
        width: 900.0,
        height: 600.0,
    }
}
