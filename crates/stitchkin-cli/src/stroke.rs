//! `stitchkin stroke`: a point's stroke along an axis, both dead centres and
//! the transmission angles, per setting (stitchkin::study::stroke).

use std::path::PathBuf;

use clap::Args;
use stitchkin::error::Error;
use stitchkin::format::fmt_num;
use stitchkin::study::design::{Design, Sweep, Vary};
use stitchkin::study::stroke::{Axis, StrokeOptions, StrokeStudy, study};

use crate::TableFormat;

#[derive(Args)]
pub struct StrokeArgs {
    #[command(flatten)]
    model: crate::ModelArgs,
    /// The point whose stroke is measured (e.g. G, the needle of needle876).
    #[arg(long, value_name = "POINT")]
    point: String,
    /// The axis: x, y or z (world), FRAME.x|y|z (an axis of a model frame,
    /// measured from its origin, e.g. guide.y), or a world direction X,Y[,Z].
    #[arg(long, default_value = "y", value_name = "AXIS", allow_hyphen_values = true)]
    axis: String,
    /// A swept parameter: NAME=LO:HI:N (N values, ends included; default N
    /// 11). Repeatable: a grid, the last fastest; band crossings are found
    /// along the last.
    #[arg(long = "vary", value_name = "NAME=LO:HI:N")]
    vary: Vec<String>,
    /// Step of the main-shaft angle φ, degrees (dead centres and angle
    /// extremes are refined below it).
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
    /// Output format: a readable table, CSV (one row per setting) or JSON.
    #[arg(long, value_enum, default_value_t = TableFormat::Table)]
    format: TableFormat,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

/// Columns under a header, widths in characters: the first left-aligned
/// when `names_first` (parameter names), the others right-aligned.
pub(crate) fn render_table(header: &[String], rows: &[Vec<String>], names_first: bool) -> String {
    let width = |c: usize| {
        rows.iter()
            .map(|r| r[c].chars().count())
            .chain([header[c].chars().count()])
            .max()
            .unwrap_or(0)
    };
    let widths: Vec<usize> = (0..header.len()).map(width).collect();
    let line = |cells: &[String]| {
        let s: Vec<String> = cells
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(i, (c, w))| {
                let pad = " ".repeat(w - c.chars().count());
                if i == 0 && names_first {
                    format!("{c}{pad}")
                } else {
                    format!("{pad}{c}")
                }
            })
            .collect();
        s.join("  ").trim_end().to_string() + "\n"
    };
    let mut out = line(header);
    for r in rows {
        out += &line(r);
    }
    out
}

pub fn run(args: StrokeArgs) -> Result<(), Error> {
    let (model, params) = crate::load(&args.model)?;
    let point = model
        .moving_point_slot(&args.point)
        .map_err(|e| e.given_in("--point"))?;
    let axis = Axis::parse(&model, &args.axis)?;
    let sweep = if args.vary.is_empty() {
        None
    } else {
        let vary = args
            .vary
            .iter()
            .map(|v| Vary::parse(&model, v))
            .collect::<Result<Vec<_>, _>>()?;
        Some(Sweep::new(vary, Design::Grid)?)
    };
    let s = study(
        &model,
        &params,
        sweep.as_ref(),
        &StrokeOptions {
            point,
            axis,
            step_deg: args.step,
        },
    )?;
    let planar = model.planar;
    let out = match args.format {
        TableFormat::Json => serde_json::to_string_pretty(&s).map_err(|e| Error::Io(e.to_string()))? + "\n",
        TableFormat::Csv => csv(&s, planar),
        TableFormat::Table => table(&s),
    };
    crate::emit(out.as_bytes(), args.output.as_ref())?;
    if !matches!(args.format, TableFormat::Table) {
        eprint!("{}", footer(&s, "# "));
    }
    Ok(())
}

/// A value or an empty cell.
fn cell(x: Option<f64>) -> String {
    x.map_or(String::new(), fmt_num)
}

fn csv(s: &StrokeStudy, planar: bool) -> String {
    let (p, a) = (&s.point, &s.axis);
    let axes: &[&str] = if planar { &["x", "y"] } else { &["x", "y", "z"] };
    let mut head: Vec<String> = s.vary.iter().map(|v| format!("{}_{}", v.name, v.unit)).collect();
    for c in [
        "stroke_mm",
        "min_mm",
        "min_phi_deg",
        "max_mm",
        "max_phi_deg",
        "min_to_max_deg",
    ] {
        head.push(format!("{p}.{a}_{c}"));
    }
    for end in ["min", "max"] {
        for x in axes {
            head.push(format!("{p}_at_{end}.{x}_mm"));
        }
    }
    let keys: Vec<&str> = s
        .rows
        .iter()
        .find_map(|r| r.stroke.as_ref())
        .map_or(Vec::new(), |st| st.mu.iter().map(|m| m.key.as_str()).collect());
    for k in &keys {
        for c in ["min_deg", "phi_min_deg", "max_deg", "phi_max_deg", "ok"] {
            head.push(format!("mu_{k}.{c}"));
        }
    }
    head.push("status".into());
    let mut out = head.join(",") + "\n";
    for r in &s.rows {
        let mut cells: Vec<String> = r.setting.iter().map(|x| fmt_num(*x)).collect();
        match &r.stroke {
            Some(st) => {
                cells.push(fmt_num(st.stroke_mm));
                cells.push(fmt_num(st.min.position_mm));
                cells.push(cell(st.min.phi_deg));
                cells.push(fmt_num(st.max.position_mm));
                cells.push(cell(st.max.phi_deg));
                cells.push(cell(st.min_to_max_deg));
                for d in [&st.min, &st.max] {
                    cells.extend(d.point_mm[..axes.len()].iter().map(|x| fmt_num(*x)));
                }
                for m in &st.mu {
                    cells.extend([
                        fmt_num(m.min_deg),
                        fmt_num(m.phi_at_min_deg),
                        fmt_num(m.max_deg),
                        fmt_num(m.phi_at_max_deg),
                        (m.ok as u8).to_string(),
                    ]);
                }
                cells.push("ok".into());
            }
            None => {
                cells.extend(std::iter::repeat_n(String::new(), head.len() - cells.len() - 1));
                cells.push(format!("\"{}\"", r.error.as_deref().unwrap_or("").replace('"', "'")));
            }
        }
        out += &(cells.join(",") + "\n");
    }
    out
}

/// The band crossings (and a note on failed settings), one per line.
fn footer(s: &StrokeStudy, prefix: &str) -> String {
    let mut out = String::new();
    for c in &s.crossings {
        let held: Vec<String> = c.held.iter().map(|(n, x)| format!("{n} = {}", fmt_num(*x))).collect();
        let held = if held.is_empty() {
            String::new()
        } else {
            format!(" (with {})", held.join(", "))
        };
        let (verb, why) = match (c.leaves, c.bound_deg < 90.0) {
            (true, true) => ("leaves", "its minimum falls below 30°"),
            (true, false) => ("leaves", "its maximum rises above 150°"),
            (false, true) => ("comes back into", "its minimum rises above 30°"),
            (false, false) => ("comes back into", "its maximum falls below 150°"),
        };
        out += &format!(
            "{prefix}mu_{} ({}) {verb} 30°…150° at {} = {:.3} {}{held}: {why}\n",
            c.key, c.group, c.parameter, c.value, c.unit
        );
    }
    let failed: Vec<String> = s
        .rows
        .iter()
        .filter_map(|r| {
            let setting: Vec<String> = s
                .vary
                .iter()
                .zip(&r.setting)
                .map(|(v, x)| format!("{} = {}", v.name, fmt_num(*x)))
                .collect();
            r.error
                .as_ref()
                .map(|e| format!("{prefix}{}: {e}\n", setting.join(", ")))
        })
        .collect();
    out + &failed.concat()
}

fn table(s: &StrokeStudy) -> String {
    let (p, a) = (&s.point, &s.axis);
    let mut out = format!(
        "{}: stroke of {p} along {}, φ step {}°\n",
        s.model,
        s.axis_words,
        fmt_num(s.step_deg)
    );
    out +=
        "dead centres and angle extremes: zeros of the exact first analog (dual numbers), refined below the step\n\n";
    let mut head: Vec<String> = s.vary.iter().map(|v| format!("{}_{}", v.name, v.unit)).collect();
    head.extend([
        format!("{a}_stroke_mm"),
        format!("{a}_min_mm"),
        "at φ_deg".into(),
        format!("{a}_max_mm"),
        "at φ_deg".into(),
    ]);
    let keys: Vec<String> = s.rows.iter().find_map(|r| r.stroke.as_ref()).map_or(Vec::new(), |st| {
        st.mu.iter().map(|m| format!("mu_{}_deg", m.key)).collect()
    });
    head.extend(keys.iter().cloned());
    let phi = |x: Option<f64>| x.map_or("—".to_string(), |v| format!("{v:.2}"));
    let rows: Vec<Vec<String>> = s
        .rows
        .iter()
        .map(|r| {
            let mut cells: Vec<String> = r.setting.iter().map(|x| fmt_num(*x)).collect();
            match &r.stroke {
                Some(st) => {
                    cells.extend([
                        format!("{:.4}", st.stroke_mm),
                        format!("{:.4}", st.min.position_mm),
                        phi(st.min.phi_deg),
                        format!("{:.4}", st.max.position_mm),
                        phi(st.max.phi_deg),
                    ]);
                    cells.extend(
                        st.mu
                            .iter()
                            .map(|m| format!("{:.2}…{:.2}{}", m.min_deg, m.max_deg, if m.ok { "  " } else { " *" })),
                    );
                }
                None => cells.extend(std::iter::repeat_n("—".to_string(), head.len() - cells.len())),
            }
            cells
        })
        .collect();
    out += &render_table(&head, &rows, false);
    out += "\n";
    let any_out = s
        .rows
        .iter()
        .filter_map(|r| r.stroke.as_ref())
        .any(|st| st.mu.iter().any(|m| !m.ok));
    if any_out {
        out += "* outside 30°…150° somewhere in the cycle (seed 002 eq. 15): risk of jamming\n";
    } else if !keys.is_empty() {
        out += "every transmission angle stays inside 30°…150° (seed 002 eq. 15)\n";
    }
    out += &format!("({p}'s position at each dead centre and the φ of each angle's extremes: --format csv or json)\n");
    out + &footer(s, "")
}
