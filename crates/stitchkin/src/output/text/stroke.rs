//! A stroke study ([`crate::study::stroke`]) as text: the table a person
//! reads, the CSV with one row per setting, and the band crossings.

use crate::format::fmt_num;
use crate::output::text::columns;
use crate::study::stroke::StrokeStudy;

/// A value or an empty cell.
fn cell(x: Option<f64>) -> String {
    x.map_or(String::new(), fmt_num)
}

/// One row per setting: the varied parameters, the stroke and both dead
/// centres (with the point's position at each, `x, y` for a planar model),
/// each transmission angle's extremes, and `ok` or why the setting failed.
pub fn csv(s: &StrokeStudy, planar: bool) -> String {
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

/// The band crossings (and a note on failed settings), one per line, each
/// line starting with `prefix` (`# ` beside a CSV).
pub fn footer(s: &StrokeStudy, prefix: &str) -> String {
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

/// The readable table: one row per setting with the stroke, both dead
/// centres and the range of each transmission angle (`*` outside
/// 30°…150°), then the crossings.
pub fn table(s: &StrokeStudy) -> String {
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
    out += &columns::table(&head, &rows, false);
    out += "\n";
    let any_out = s
        .rows
        .iter()
        .filter_map(|r| r.stroke.as_ref())
        .any(|st| st.mu.iter().any(|m| !m.ok));
    if any_out {
        out += &format!(
            "* outside 30°…150° somewhere in the cycle ({} eq. 15): risk of jamming\n",
            crate::references::cite(2)
        );
    } else if !keys.is_empty() {
        out += &format!(
            "every transmission angle stays inside 30°…150° ({} eq. 15)\n",
            crate::references::cite(2)
        );
    }
    out += &format!("({p}'s position at each dead centre and the φ of each angle's extremes: --format csv or json)\n");
    out + &footer(s, "")
}
