//! A cycle ([`crate::eval`]) as text: the summary of a run (transmission
//! angles, measure ranges, take-up, the stitch's match and checks, notes and
//! warnings) and the report of a model check.

use crate::eval::{self, CycleTable};
use crate::format::score;
use crate::model::{Model, Params};
use crate::thread::{Interval, Span, SplitPoint, Threads};
use crate::verify::CrossCheck;

/// φ intervals for a summary line, each end within 0…360° (`none` when
/// there is none).
fn intervals(iv: &[Interval], none: &str) -> String {
    if iv.is_empty() {
        return none.to_string();
    }
    iv.iter()
        .map(|i| {
            if i.to_deg - i.from_deg >= 360.0 - 1e-9 {
                "the whole cycle".to_string()
            } else {
                format!("{:.0}°…{:.0}°", eval::wrap_deg(i.from_deg), eval::wrap_deg(i.to_deg))
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The summary of a cycle, one `# `-line per item: the transmission angles
/// with where they peak, the measure ranges, each thread path's take-up,
/// the stitch (P′, match, checks: one line per check every thread passes),
/// the model's caveats and the warnings.
pub fn summary(model: &Model, table: &CycleTable) -> String {
    summary_with(model, table, false)
}

/// The table's columns as a readable table of at most `max_rows` rows:
/// every row of a short table, else every k-th row from the first, and the
/// last (`run --columns` on a terminal). Values to 3 decimals, a column of
/// whole numbers (a guide's engagement 0/1) without decimals, φ as it is.
pub fn columns_table(table: &CycleTable, max_rows: usize) -> String {
    let rows = table.rows();
    let stride = if rows <= max_rows.max(2) {
        1
    } else {
        (rows - 1).div_ceil(max_rows.max(2) - 1)
    };
    let mut shown: Vec<usize> = (0..rows).step_by(stride).collect();
    if rows > 0 && shown.last() != Some(&(rows - 1)) {
        shown.push(rows - 1);
    }
    let header: Vec<String> = table.columns.iter().map(|c| c.name.clone()).collect();
    let whole: Vec<bool> = table
        .columns
        .iter()
        .map(|c| c.values.iter().all(|v| v.fract() == 0.0))
        .collect();
    let cells: Vec<Vec<String>> = shown
        .iter()
        .map(|&r| {
            table
                .columns
                .iter()
                .zip(&whole)
                .map(|(c, &w)| match c.values[r] {
                    v if !v.is_finite() => "–".to_string(),
                    v if c.name == "phi_deg" => crate::format::fmt_decimals(v, 3),
                    v => crate::format::decimals(v, if w { 0 } else { 3 }),
                })
                .collect()
        })
        .collect();
    let mut out = if stride > 1 {
        format!(
            "every {} row of {rows} (every {}°, and the last):\n",
            ordinal(stride),
            crate::format::fmt_decimals(stride as f64 * table.step_deg, 3)
        )
    } else {
        String::new()
    };
    out += &super::columns::table(&header, &cells, false);
    out
}

/// `2nd`, `3rd`, `10th`, …
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// [`summary`] with every check of every thread in full (`stitchkin
/// check`).
pub fn check_summary(model: &Model, table: &CycleTable) -> String {
    summary_with(model, table, true)
}

fn summary_with(model: &Model, table: &CycleTable, full_checks: bool) -> String {
    let mut s = format!(
        "# {} — {} rows, φ from {}° in steps of {}°{}\n",
        model.title().unwrap_or(model.name()),
        table.rows(),
        model.phi_start_deg(),
        table.step_deg,
        table.rpm.map(|r| format!(", {r} rpm")).unwrap_or_default()
    );
    let w = super::name_width(
        table
            .transmission
            .iter()
            .map(|t| t.key.len() + 3)
            .chain(table.ranges.iter().map(|r| r.name.len()))
            .chain(table.paths.iter().map(|p| p.path.len())),
        1,
    );
    for t in &table.transmission {
        s += &format!(
            "# {:<w$} {:>7.2}° (φ = {:>6.1}°) … {:>7.2}° (φ = {:>6.1}°)  {}  [{}]\n",
            format!("mu_{}", t.key),
            t.min_deg,
            t.phi_at_min_deg,
            t.max_deg,
            t.phi_at_max_deg,
            if t.ok { "ok" } else { "OUTSIDE 30°…150°" },
            t.group
        );
    }
    for r in &table.ranges {
        s += &format!(
            "# {:<w$} {:.4} … {:.4} {} (range {:.4} {}; min at φ = {:.1}°, max at φ = {:.1}°)\n",
            r.name, r.min, r.max, r.unit, r.range, r.unit, r.phi_at_min_deg, r.phi_at_max_deg
        );
    }
    if let Some(conv) = &table.take_up {
        s += &format!("# take-up: {conv}\n");
    }
    s += &take_up_lines(table, w);
    s += &cam_lines(table);
    s += &stitch_lines(model, table, w, full_checks);
    for c in model.caveats() {
        s += &format!("# note: {c}\n");
    }
    for w in &table.warnings {
        s += &format!("warning: {w}\n");
    }
    s
}

/// The checks of each cam and follower, one line each with its message.
pub fn cam_lines(table: &CycleTable) -> String {
    let mut s = String::new();
    for cam in &table.cams {
        for c in &cam.checks {
            s += &format!(
                "# cam {} {:<4} {:<16} {:>10}  (allowed {}): {}\n",
                cam.group,
                if c.ok { "ok" } else { "FAIL" },
                c.name,
                c.value_words(),
                c.limit_words(),
                c.message
            );
        }
    }
    s
}

/// One line per thread path: the extremes of P, the guides' engagement,
/// dwells and eye tension; names padded to `w`.
fn take_up_lines(table: &CycleTable, w: usize) -> String {
    let mut s = String::new();
    for p in &table.paths {
        let pn = eval::take_up_name(p.split == SplitPoint::B);
        s += &format!(
            "# {:<w$} max {pn} {:.3} mm at φ = {:.1}°, min {pn} {:.3} mm at φ = {:.1}°",
            p.path, p.max_p_mm, p.phi_at_max_deg, p.min_p_mm, p.phi_at_min_deg
        );
        if let Some(e) = p.max_p_eye_mm {
            s += &format!(" (max P_eye {e:.3} mm)");
        }
        for (pin, iv) in &p.engaged {
            s += &format!("; {pin} engaged {}", intervals(iv, "never"));
        }
        if !p.flat.is_empty() {
            s += &format!("; dwell {}", intervals(&p.flat, ""));
        }
        if let Some([lo, hi]) = p.eye_tension_n {
            s += &format!("; eye tension {lo:.3}…{hi:.3} N");
        }
        if let Some(t) = &p.thread {
            s += &format!("  [{t}]");
        }
        s += "\n";
    }
    s
}

/// The stitch: its setting, the regulator, P′ and the match per thread,
/// the physical checks and the transfers; names padded to `w`.
fn stitch_lines(model: &Model, table: &CycleTable, w: usize, full_checks: bool) -> String {
    let Some(st) = &table.stitch else {
        return if model.has_stitch() {
            "# stitch: not computed, no column asked for needs it (`stitchkin match` gives the match and the physical checks)\n"
                .into()
        } else {
            String::new()
        };
    };
    let mut s = format!(
        "# stitch {}: m = {} mm, t = {} mm; P' = 0 at φ = {}°, needle BDC at φ = {}°\n",
        st.stitch_type, st.m_mm, st.t_mm, st.phi0_deg, st.cyclogram_zero_deg
    );
    s += &format!("# regulator: {}\n", st.regulator);
    for t in &st.threads {
        let pn = if t.split == SplitPoint::B { "P'_B" } else { "P'" };
        s += &format!(
            "# {:<w$} max {pn} {:.3} mm at φ = {:.1}°; {:.3} mm per stitch (cut at its lock, φ = {:.1}°: {:.3} mm)",
            t.thread, t.max_pprime_mm, t.phi_at_max_pprime_deg, t.per_stitch_mm, t.lock_phi_deg, t.locked_mm
        );
        if let (Some(p), Some(m)) = (&t.path, &t.mismatch) {
            s += &format!("; vs {p}: RMS(P − P') {:.3} mm, score {}", m.rms_d_mm, score(m.score));
        }
        s += "\n";
    }
    // Every check in full for one thread (or with `full_checks`); for
    // several, one line per check they all pass.
    for group in super::matching::check_groups(&st.checks) {
        if full_checks || st.threads.len() < 2 || group.iter().any(|c| !c.ok) {
            for c in group {
                s += &format!(
                    "# check {:<4} {} {}: {}\n",
                    if c.ok { "ok" } else { "FAIL" },
                    c.thread,
                    c.name,
                    c.message
                );
            }
        } else {
            s += &format!(
                "# check ok   {}: {}\n",
                group[0].name,
                super::matching::group_figure(&group)
            );
        }
    }
    for t in &st.transfers {
        s += &format!("# note: {t}\n");
    }
    s
}

/// The report of a model check up to the cycle's summary: the title, every
/// parameter with its value, range, kind, label and provenance, the solve order, the
/// thread paths (`threads`, guides in brackets) and the φ range it
/// assembled over at `step_deg`.
pub fn model_check(model: &Model, params: &Params, threads: Option<&Threads<f64>>, step_deg: f64) -> String {
    let mut out = format!("{}: ok — {}\n", model.file_name, model.title().unwrap_or(model.name()));
    out += &format!("parameters ({}):\n", model.params.len());
    for (p, v) in model.params.iter().zip(&params.values) {
        let value = if p.is_derived() {
            "derived".to_string()
        } else {
            format!("{v} {}", p.unit_str())
        };
        let range = p
            .range
            .map(|[a, b]| format!("  range {a}…{b} {}", p.unit_str()))
            .unwrap_or_default();
        let prov = p
            .provenance
            .map(|p| format!("  [{p:?}]").to_lowercase())
            .unwrap_or_default();
        let label = p.label.as_deref().map(|l| format!(" — {l}")).unwrap_or_default();
        out += &format!("  {:<10} {value}{range}  {}{label}{prov}\n", p.name, p.kind.describe());
    }
    out += &format!("solve order ({} steps):\n", model.step_labels().len());
    for (k, l) in model.step_labels().iter().enumerate() {
        out += &format!("  {:>2}. {l}\n", k + 1);
    }
    if let Some(threads) = threads {
        out += &thread_paths(threads);
    }
    out += &format!(
        "assembles at every φ from {}° in steps of {}°\n",
        model.phi_start_deg(),
        step_deg
    );
    out
}

/// The thread paths of a check: the nodes of each, guides in brackets, and
/// how many of its pieces keep a constant length.
fn thread_paths(threads: &Threads<f64>) -> String {
    let mut out = format!(
        "thread paths ({}), {} distinct pieces:\n",
        threads.paths.len(),
        threads.spans.len()
    );
    for p in threads.paths.iter() {
        let nodes: Vec<String> = p
            .node_names
            .iter()
            .zip(&p.pin_span)
            .map(|(n, guide)| if guide.is_some() { format!("[{n}]") } else { n.clone() })
            .collect();
        let constant = p
            .spans
            .iter()
            .filter(|&&s| matches!(threads.spans[s], Span::Straight { constant: true, .. }))
            .count();
        out += &format!(
            "  {:<10} {}  ({} pieces, {constant} of constant length)\n",
            p.name,
            nodes.join(" "),
            p.spans.len()
        );
    }
    out
}

/// The line of a cross-check: how closely the closed-form groups and the
/// whole-system Newton solver agree, and where they differ most.
pub fn cross_check(c: &CrossCheck) -> String {
    format!(
        "cross-check: {} positions, closed-form groups and whole-system Newton agree to {:.2e} mm (largest at {} φ = {:.1}°)\n",
        c.positions,
        c.max_deviation_mm,
        c.at_point,
        eval::wrap_deg(c.at_phi_deg)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The MF-7923D's cycle at `step_deg` with the columns `patterns`.
    fn table(step_deg: f64, patterns: &[&str]) -> CycleTable {
        let model = Model::preset("mf7923d").unwrap();
        let opts = eval::CycleOptions {
            step_deg,
            ..Default::default()
        };
        let patterns: Vec<String> = patterns.iter().map(|p| p.to_string()).collect();
        eval::run_cycle_columns(&model, &model.defaults(), &opts, &patterns).unwrap()
    }

    #[test]
    fn a_long_table_shows_every_kth_row_and_the_last() {
        let t = columns_table(&table(1.0, &["n3_A.P_B_mm", "n1_A.G4_1_engaged"]), 37);
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines[0], "every 10th row of 360 (every 10°, and the last):");
        let header: Vec<&str> = lines[1].split_whitespace().collect();
        assert_eq!(header, ["phi_deg", "n1_A.G4_1_engaged", "n3_A.P_B_mm"], "{t}");
        // φ = 0, 10, …, 350 and the last row, 359.
        assert_eq!(lines.len(), 2 + 36 + 1, "{t}");
        assert!(lines[2].trim_start().starts_with("0 "), "{t}");
        assert!(lines.last().unwrap().trim_start().starts_with("359 "), "{t}");
        // Whole numbers without decimals, the rest to 3, no negative zero
        // (n3_A's P_B dips to −0.004 mm near φ = 0).
        for l in &lines[2..] {
            let cells: Vec<&str> = l.split_whitespace().collect();
            assert!(cells[1] == "0" || cells[1] == "1", "{l}");
            assert!(cells[2].split_once('.').is_some_and(|(_, d)| d.len() == 3), "{l}");
        }
        assert!(!t.contains("-0.000"), "{t}");
    }

    #[test]
    fn a_short_table_shows_every_row() {
        let t = columns_table(&table(30.0, &["n1_A.P_B_mm"]), 37);
        assert_eq!(t.lines().count(), 1 + 12, "{t}");
        assert!(t.starts_with("phi_deg"), "{t}");
        assert_eq!(ordinal(1), "1st");
        assert_eq!(ordinal(12), "12th");
        assert_eq!(ordinal(22), "22nd");
    }
}
