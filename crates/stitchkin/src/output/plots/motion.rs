//! Motion laws over φ: any column of the cycle table `stitchkin run`
//! writes (a point coordinate, a link or transmission angle, a measure, an
//! analog) against φ over one cycle, one panel per unit, as seed 002
//! Fig. 3 and seed 003 Fig. 8 draw positions against the crank angle; over
//! a varied parameter one panel per series with a line per value, or one
//! series as a heat map or a projected surface (seed 000 Fig. 6, drawn by
//! the surfaces of [`mod@super::family`]).

use super::family::{Quantity, VaryGrid};
use super::{phi_axis, title, unit_label};
use crate::model::Model;
use crate::output::svg::{Axis, Chart, Figure, Series, color, family_color};

/// The unit endings of the cycle table's column names, longest first.
const UNITS: [&str; 12] = [
    "mm_per_rad2",
    "mm_per_rad",
    "rad_per_rad2",
    "rad_per_rad",
    "mm_per_s2",
    "mm_per_s",
    "rad_per_s2",
    "rad_per_s",
    "mm",
    "deg",
    "rad",
    "N",
];

/// Height of a figure's only panel, and of each of several.
const ONE_PANEL_H: f64 = 480.0;
const PANEL_H: f64 = 330.0;

/// A y label names its series up to about this many characters.
const LABEL_CHARS: usize = 40;

/// One series: a column of the cycle table over φ.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionSeries {
    /// The column (`G.y_mm`), its name without the unit ending (`G.y`) and
    /// the unit as charts write it (`mm`, `mm/rad²`; empty for a plain
    /// number).
    pub column: String,
    pub name: String,
    pub unit: String,
    /// The values over φ, closed like the φ they are drawn against: one
    /// row for one cycle, or one per value of a varied parameter (`None`
    /// where that cycle failed).
    pub rows: Vec<Option<Vec<f64>>>,
    /// An angle shifted by whole turns to run continuously past ±180°:
    /// its values differ from the table's by multiples of 360°.
    pub unwrapped: bool,
}

impl MotionSeries {
    /// The series of `column` with its `rows` (closed like the φ they
    /// are drawn against): its name and unit read off the column's unit
    /// ending, an angle's wraps taken out.
    pub fn new(column: &str, mut rows: Vec<Option<Vec<f64>>>) -> MotionSeries {
        let (name, unit) = split_unit(column);
        let unwrapped = unit == "deg" && unwrap_rows(&mut rows);
        MotionSeries {
            column: column.to_string(),
            name: name.to_string(),
            unit: unit_text(unit),
            rows,
            unwrapped,
        }
    }

    /// The series as a surface draws it.
    pub fn quantity(&self) -> Quantity {
        Quantity {
            symbol: self.name.clone(),
            unit: self.unit.clone(),
            what: format!("motion law {}", self.name),
        }
    }
}

/// The chart of one cycle: the series against φ, one panel per unit (mm
/// and deg never share an axis) in the order the units first appear, each
/// series in its own colour.
pub fn motion_chart(model: &Model, phis: &[f64], series: &[MotionSeries]) -> Figure {
    let mut units: Vec<&str> = Vec::new();
    for s in series {
        if !units.contains(&s.unit.as_str()) {
            units.push(&s.unit);
        }
    }
    let panels = units
        .iter()
        .map(|u| {
            let members: Vec<(usize, &MotionSeries)> =
                series.iter().enumerate().filter(|(_, s)| s.unit == *u).collect();
            let names: Vec<&str> = members.iter().map(|(_, s)| s.name.as_str()).collect();
            let mut chart = Chart::new(
                names.join(", "),
                phi_axis(model),
                Axis::new(unit_label(&label_names(&names), u)),
            );
            for (i, s) in members {
                if let Some(Some(row)) = s.rows.first() {
                    chart
                        .series
                        .push(Series::new(s.name.clone(), pairs(phis, row), color(i)));
                }
            }
            chart
        })
        .collect();
    let mut fig = figure(model, &laws_of(series), panels);
    fig.subtitle = Some(format!(
        "over one cycle at the parameters as set, one panel per unit{}",
        unwrap_note(series)
    ));
    fig
}

/// The family chart: one panel per series, a line per value of the varied
/// parameter in a colour ramp (dark: the low end), legend `r1 = 4.5 mm`.
pub fn motion_family_chart(model: &Model, grid: &VaryGrid, series: &[MotionSeries]) -> Figure {
    let n = grid.values.len();
    let panels = series
        .iter()
        .map(|s| {
            let mut chart = Chart::new(s.name.clone(), phi_axis(model), Axis::new(unit_label(&s.name, &s.unit)));
            for (k, row) in s.rows.iter().enumerate() {
                if let Some(row) = row {
                    chart.series.push(Series::new(
                        grid.value_text(k),
                        pairs(&grid.phis, row),
                        family_color(k, n),
                    ));
                }
            }
            chart
        })
        .collect();
    let mut fig = figure(model, &format!("{} as {} varies", laws_of(series), grid.name), panels);
    fig.subtitle = Some(format!(
        "{n} values of {}, the rest as set; one panel per series{}{}",
        grid.range_text(),
        unwrap_note(series),
        grid.failure_note()
    ));
    fig
}

/// `motion law G.y`, `motion laws of G.y, E.y`: the title's words.
fn laws_of(series: &[MotionSeries]) -> String {
    let names: Vec<&str> = series.iter().map(|s| s.name.as_str()).collect();
    format!(
        "motion {} {}",
        if names.len() == 1 { "law" } else { "laws of" },
        names.join(", ")
    )
}

/// The figure of `panels` under the model's title.
fn figure(model: &Model, what: &str, mut panels: Vec<Chart>) -> Figure {
    let h = if panels.len() == 1 { ONE_PANEL_H } else { PANEL_H };
    for p in &mut panels {
        p.height = h;
    }
    let mut fig = Figure::new(title(model, what));
    fig.panels = panels;
    fig
}

/// (φ, v) pairs of a closed row.
fn pairs(phis: &[f64], row: &[f64]) -> Vec<(f64, f64)> {
    phis.iter().copied().zip(row.iter().copied()).collect()
}

/// The subtitle's note on the angles drawn continuously.
fn unwrap_note(series: &[MotionSeries]) -> String {
    let moved: Vec<&str> = series.iter().filter(|s| s.unwrapped).map(|s| s.name.as_str()).collect();
    if moved.is_empty() {
        String::new()
    } else {
        format!(
            "; {} drawn continuously past ±180° (whole turns added)",
            moved.join(", ")
        )
    }
}

/// The names a y label gives: all, or as many as fit in about
/// [`LABEL_CHARS`] characters and `…`.
fn label_names(names: &[&str]) -> String {
    let mut out = String::new();
    for (i, name) in names.iter().enumerate() {
        if i > 0 && out.chars().count() + name.chars().count() + 2 > LABEL_CHARS {
            return out + ", …";
        }
        if i > 0 {
            out += ", ";
        }
        out += name;
    }
    out
}

/// `G.y_mm` → (`G.y`, `mm`); a column without a unit ending is its own
/// name with an empty unit.
pub(crate) fn split_unit(column: &str) -> (&str, &'static str) {
    UNITS
        .iter()
        .find_map(|u| column.strip_suffix(u)?.strip_suffix('_').map(|base| (base, *u)))
        .unwrap_or((column, ""))
}

/// A unit ending as charts write it: `mm_per_rad2` → `mm/rad²`.
fn unit_text(unit: &str) -> String {
    let t = unit.replace("_per_", "/");
    match t.strip_suffix('2') {
        Some(base) => format!("{base}²"),
        None => t,
    }
}

/// Takes out the wraps of angles (deg) so they are drawn continuously: in
/// a row, a jump of more than 180° between neighbours is the angle leaving
/// its range −180°…180° and is undone by whole turns; then each row is
/// shifted by whole turns to start within 180° of the first row. True when
/// any value moved.
fn unwrap_rows(rows: &mut [Option<Vec<f64>>]) -> bool {
    let mut moved = false;
    let mut first: Option<f64> = None;
    for row in rows.iter_mut().flatten() {
        for k in 1..row.len() {
            let turns = ((row[k] - row[k - 1]) / 360.0).round();
            if turns != 0.0 {
                row[k] -= 360.0 * turns;
                moved = true;
            }
        }
        let Some(&start) = row.first() else { continue };
        let turns = ((start - *first.get_or_insert(start)) / 360.0).round();
        if turns != 0.0 {
            row.iter_mut().for_each(|v| *v -= 360.0 * turns);
            moved = true;
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_endings_split_off_and_read_as_charts_write_them() {
        assert_eq!(split_unit("G.y_mm"), ("G.y", "mm"));
        assert_eq!(split_unit("angle_O2_B_deg"), ("angle_O2_B", "deg"));
        assert_eq!(split_unit("G.d2y_dphi2_mm_per_rad2"), ("G.d2y_dphi2", "mm_per_rad2"));
        assert_eq!(
            split_unit("angle_A_B.d_dphi_rad_per_rad"),
            ("angle_A_B.d_dphi", "rad_per_rad")
        );
        assert_eq!(
            split_unit("angle_A_B.omega_rad_per_s"),
            ("angle_A_B.omega", "rad_per_s")
        );
        assert_eq!(split_unit("n1_A.tension_eye_N"), ("n1_A.tension_eye", "N"));
        assert_eq!(split_unit("n1_A.G4_1_engaged"), ("n1_A.G4_1_engaged", ""));
        assert_eq!(unit_text("mm_per_rad2"), "mm/rad²");
        assert_eq!(unit_text("mm_per_s"), "mm/s");
        assert_eq!(unit_text("deg"), "deg");
    }

    #[test]
    fn angles_run_on_past_the_wrap_and_rows_start_alike() {
        // A rocker swinging about 180°: atan2 jumps from +179 to −179.
        let mut rows = vec![
            Some(vec![170.0, 179.0, -179.0, -170.0, 179.0, 170.0]),
            None,
            Some(vec![-178.0, -175.0, 178.0, 170.0]),
        ];
        assert!(unwrap_rows(&mut rows));
        assert_eq!(
            rows[0].as_deref(),
            Some(&[170.0, 179.0, 181.0, 190.0, 179.0, 170.0][..])
        );
        // The third row began on the other side of the wrap: a turn up.
        assert_eq!(rows[2].as_deref(), Some(&[182.0, 185.0, 178.0, 170.0][..]));
        let mut calm = vec![Some(vec![-10.0, 0.0, 10.0, -10.0])];
        assert!(!unwrap_rows(&mut calm));
        assert_eq!(calm[0].as_deref(), Some(&[-10.0, 0.0, 10.0, -10.0][..]));
    }

    #[test]
    fn long_axis_labels_are_cut_with_an_ellipsis() {
        assert_eq!(label_names(&["G.y", "E.y"]), "G.y, E.y");
        let many = [
            "P20.x", "P20.y", "P20.z", "P6.x", "P6.y", "P6.z", "P11.x", "P11.y", "P11.z",
        ];
        let label = label_names(&many);
        assert!(
            label.starts_with("P20.x, P20.y") && label.ends_with(", …") && label.chars().count() <= LABEL_CHARS + 3,
            "{label}"
        );
    }
}
