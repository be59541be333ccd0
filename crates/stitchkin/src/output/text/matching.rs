//! The match of the take-up P with the thread the stitch needs, P′
//! ([`crate::eval::stitch_process`]), as one screen of text: per thread the score
//! and the figures, P against P′ as sparklines, the physical checks,
//! measured curves, notes and, in detail, every metric.

use crate::eval::CycleTable;
use crate::eval::stitch_process::{StitchSummary, StitchThreadSummary};
use crate::format::{fmt_num, score};
use crate::model::Model;
use crate::output::text::{sparkline, window_marks};
use crate::stitch::checks::Check;
use crate::stitch::spec::EventKind;
use crate::study::measured::MeasuredMatch;
use crate::thread::SplitPoint;
use crate::thread::measured::CurveKind;

/// Columns of the sparklines: 6° each over a turn.
const SPARK_COLS: usize = 60;

/// The match on one screen: the setting, one row per thread, P against P′
/// as sparklines, the checks, the caveats; with `details` every metric.
pub fn screen(
    model: &Model,
    table: &CycleTable,
    st: &StitchSummary,
    measured: &[MeasuredMatch],
    details: bool,
) -> String {
    let mut s = format!(
        "{} — stitch {}, material m = {} mm, stitch length t = {} mm\n",
        model.title().unwrap_or(model.name()),
        st.stitch_type,
        st.m_mm,
        st.t_mm
    );
    if st.threads.iter().any(|t| t.split == SplitPoint::B) {
        s += &format!(
            "needle threads measured at B, the eye's top position ({} §2.3); ",
            crate::references::cite(4)
        );
    }
    s += &format!(
        "P = P′ = 0 at φ = {}°; needle BDC at φ = {}°\n",
        st.phi0_deg, st.cyclogram_zero_deg
    );
    s += &format!("regulator: {}\n", st.regulator);
    s += "D = P − P′: D > 0 thread given but not needed (slack), D < 0 needed but not given (strain)\n\n";

    s += &format!(
        "{:<8} {:<8} {:>6} {:>10} {:>10} {:>10} {:>11}  {}\n",
        "thread", "path", "score", "RMS(D)", "max P", "max P′", "per stitch", "checks"
    );
    for t in &st.threads {
        let mm = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.2} mm"));
        let max_p = t
            .path
            .as_ref()
            .and_then(|p| table.paths.iter().find(|q| &q.path == p))
            .map(|q| q.max_p_mm);
        let checks: Vec<&Check> = st.checks.iter().filter(|c| c.thread == t.thread).collect();
        let passed = checks.iter().filter(|c| c.ok).count();
        let verdict = match checks.len() {
            0 => "—".to_string(),
            n if passed == n => format!("{n} of {n} pass"),
            n => format!("{} of {n} FAIL", n - passed),
        };
        s += &format!(
            "{:<8} {:<8} {:>6} {:>10} {:>10} {:>10} {:>11}  {verdict}\n",
            t.thread,
            t.path.as_deref().unwrap_or("—"),
            score(t.mismatch.as_ref().and_then(|m| m.score)),
            mm(t.mismatch.as_ref().map(|m| m.rms_d_mm)),
            mm(max_p),
            mm(Some(t.max_pprime_mm)),
            mm(Some(t.per_stitch_mm)),
        );
    }
    s += &sparklines(table, st, measured);
    s += &tension_block(st);
    s += &checks_block(table, st, details);
    for mm in measured {
        s += &measured_line(mm);
    }
    s += &notes(table, st);
    if details {
        for t in &st.threads {
            s += &thread_details(t);
        }
        if !st.moments.is_empty() {
            s += "\nmoments (φ): ";
            s += &st
                .moments
                .iter()
                .map(|(n, p)| format!("{n} {p:.1}°"))
                .collect::<Vec<_>>()
                .join(", ");
            s += "\n";
        }
    } else {
        s += "\n(every metric, the jumps of P′ and the moments: stitchkin match --details; all of it: --format json)\n";
    }
    for c in model.caveats().iter().chain(&st.transfers) {
        s += &format!("note: {c}\n");
    }
    for w in &table.warnings {
        s += &format!("warning: {w}\n");
    }
    s
}

/// P against P′ of each thread as two sparklines on one scale, the
/// regulator window marked below.
fn sparklines(table: &CycleTable, st: &StitchSummary, measured: &[MeasuredMatch]) -> String {
    let Some(phis) = table.column("phi_deg") else {
        return String::new();
    };
    let start = phis.first().copied().unwrap_or(0.0);
    let mut s = format!(
        "\nP (upper line) against P′ (lower line) over one turn from φ = {start}°, {}° a character, each thread on its own scale\n",
        360 / SPARK_COLS
    );
    let axis: String = (0..SPARK_COLS)
        .map(|c| if c % (SPARK_COLS / 4) == 0 { '|' } else { ' ' })
        .collect();
    s += &format!(
        "{:<12}{axis}  ({}°, {}°, {}°, {}°)\n",
        "",
        start,
        start + 90.0,
        start + 180.0,
        start + 270.0
    );
    for t in &st.threads {
        let p = t
            .path
            .as_ref()
            .and_then(|p| table.paths.iter().find(|q| &q.path == p))
            .and_then(|q| table.column(&q.p_column));
        let pprime = table.column(&t.pprime_column());
        let Some(pprime) = pprime else { continue };
        let extra: Vec<&MeasuredMatch> = measured.iter().filter(|m| m.thread == t.thread).collect();
        let all = pprime
            .iter()
            .chain(p.into_iter().flatten())
            .chain(extra.iter().flat_map(|m| m.values_mm.iter()));
        let (lo, hi) = all.fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        // No "-0.0" in the scale.
        let (lo, hi) = (lo + 0.0, hi + 0.0);
        if let Some(p) = p {
            let scale = |x: f64| {
                if x.abs() < 0.05 {
                    "0.0".to_string()
                } else {
                    format!("{x:.1}")
                }
            };
            s += &format!(
                "{:<6}{:<6}{}  {}…{} mm\n",
                t.thread,
                "P",
                sparkline(p, lo, hi, SPARK_COLS),
                scale(lo),
                scale(hi)
            );
        }
        s += &format!(
            "{:<6}{:<6}{}\n",
            if p.is_some() { "" } else { t.thread.as_str() },
            "P′",
            sparkline(pprime, lo, hi, SPARK_COLS)
        );
        for m in extra {
            let what = match m.kind {
                CurveKind::TakeUp => "P meas",
                CurveKind::Required => "P′ meas",
            };
            s += &format!("{:<6}{:<6}{}\n", "", what, sparkline(&m.values_mm, lo, hi, SPARK_COLS));
        }
    }
    // The regulator windows, one line per distinct set of windows.
    let mut windows: Vec<(&[[f64; 2]], Vec<&str>)> = Vec::new();
    for t in st.threads.iter().filter(|t| !t.regulator_windows_deg.is_empty()) {
        let w = t.regulator_windows_deg.as_slice();
        let same = |v: &[[f64; 2]]| {
            v.len() == w.len()
                && v.iter()
                    .zip(w)
                    .all(|(a, b)| (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9)
        };
        match windows.iter_mut().find(|(v, _)| same(v)) {
            Some((_, names)) => names.push(&t.thread),
            None => windows.push((w, vec![&t.thread])),
        }
    }
    let computed = st.threads.iter().any(|t| t.regulator_computed);
    for (ws, names) in &windows {
        let whose = if windows.len() > 1 {
            format!(" of {}", names.join(", "))
        } else {
            String::new()
        };
        // Every window of the set on one line.
        let mut marks: Vec<char> = window_marks(start, SPARK_COLS, ws[0], '~').chars().collect();
        for w in &ws[1..] {
            for (m, c) in marks.iter_mut().zip(window_marks(start, SPARK_COLS, *w, '~').chars()) {
                if c == '~' {
                    *m = '~';
                }
            }
        }
        let plural = if ws.len() > 1 { "s" } else { "" };
        s += &format!(
            "{:<12}{}  regulator window{plural}{whose}{} (left out of the metrics)\n",
            "",
            marks.into_iter().collect::<String>(),
            if computed { ", computed" } else { "" }
        );
    }
    s
}

/// Each thread's tension, where it is solved: the peak and where, the
/// breaking margin, the thread drawn per cycle and the strain the stitch
/// keeps, the largest slack loop and the regulator's computed window.
fn tension_block(st: &StitchSummary) -> String {
    let with: Vec<_> = st
        .threads
        .iter()
        .filter_map(|t| t.tension.as_ref().map(|tn| (t, tn)))
        .collect();
    let Some((_, first)) = with.first() else {
        return String::new();
    };
    let mut s = format!(
        "\nthread tension ({}: EA {} N, breaking {} N; regulator {} N):\n",
        first.material.as_deref().unwrap_or("the thread"),
        fmt_num(first.ea_n),
        fmt_num(first.breaking_n),
        fmt_num(first.regulator_n)
    );
    s += &format!(
        "{:<8} {:>9} {:>8}  {:<16} {:>7} {:>11} {:>7} {:>10}  {}\n",
        "thread",
        "peak T",
        "at φ",
        "between",
        "margin",
        "drawn",
        "strain",
        "slack",
        "regulator window (where thread passes)"
    );
    for (t, tn) in &with {
        let windows: Vec<String> = tn
            .regulator_windows_deg
            .iter()
            .map(|&[a, b]| {
                format!(
                    "{a:.0}°…{:.0}°",
                    crate::eval::wrap_deg(b).max(if b >= 360.0 { 0.0 } else { b })
                )
            })
            .collect();
        s += &format!(
            "{:<8} {:>7.2} N {:>7.1}°  {:<16} {:>6.2}× {:>8.2} mm {:>6.2} % {:>7.2} mm  {}\n",
            t.thread,
            tn.peak_n,
            tn.peak_at_deg,
            tn.peak_span,
            tn.margin.min(999.0),
            tn.drawn_per_cycle_mm,
            100.0 * tn.lock_strain,
            tn.max_slack_mm,
            if windows.is_empty() {
                "none".into()
            } else {
                windows.join(", ")
            }
        );
        if !tn.settled {
            s += &format!(
                "         the thread does not settle: after {} cycles its state still moves {:.3} mm a cycle \
                 (the figures are the last cycle's)\n",
                tn.cycles, tn.change_mm
            );
        }
    }
    s += "(drawn: thread past the regulator per cycle, unstretched; strain: what the finished stitch keeps; slack: the \
          largest loop between the regulator and the eye)\n";
    s
}

/// The physical checks: one line each (several threads: one line per check
/// they all pass), in full when one fails (or with `details`); each value
/// is the figure its message speaks of, beside its allowed range.
fn checks_block(table: &CycleTable, st: &StitchSummary, details: bool) -> String {
    if table.all_checks().next().is_none() {
        return String::new();
    }
    let mut s = "\nchecks (what no machine can do):\n".to_string();
    if !details && st.threads.len() > 1 {
        s += &grouped_checks(table, st);
    } else {
        for c in &st.checks {
            s += &check_line(table, st, c, details);
        }
    }
    for c in table.cam_checks() {
        s += &cam_check_line(c, details);
    }
    s
}

/// A cam and follower's check: its group, its figure beside the allowed
/// range and where (the cam angle δ for the profile's checks, φ for the
/// follower's contact over the cycle).
fn cam_check_line(c: &Check, details: bool) -> String {
    let at = if c.name == "follower_contact" { "φ" } else { "cam δ" };
    check_row(c, at, "", details)
}

/// The checks of several threads, one line per check where every thread
/// passes it (each thread's figure side by side), each thread's own line
/// where one fails.
fn grouped_checks(table: &CycleTable, st: &StitchSummary) -> String {
    let mut s = String::new();
    for group in check_groups(&st.checks) {
        if group.iter().any(|c| !c.ok) {
            for c in group {
                s += &check_line(table, st, c, false);
            }
        } else {
            s += &format!(
                "  {:<5} {:<6} {:<19} {}\n",
                "ok",
                "all",
                group[0].name,
                group_figure(&group)
            );
        }
    }
    s
}

/// The checks by name, in the order they first appear.
pub(super) fn check_groups(checks: &[Check]) -> Vec<Vec<&Check>> {
    let mut out: Vec<Vec<&Check>> = Vec::new();
    for c in checks {
        match out.iter_mut().find(|g| g[0].name == c.name) {
            Some(g) => g.push(c),
            None => out.push(vec![c]),
        }
    }
    out
}

/// One check's figure for every thread side by side, with the allowed
/// range: `n1 3.84×, n2 3.89×  (allowed ≥ 3.00×)`; a thread where it does
/// not apply reads `n/a`.
pub(super) fn group_figure(group: &[&Check]) -> String {
    let figures = group
        .iter()
        .map(|c| format!("{} {}", c.thread, c.value_words()))
        .collect::<Vec<_>>()
        .join(", ");
    match group.iter().find(|c| c.limit != [None, None]) {
        Some(c) if group.iter().all(|g| g.limit == c.limit || g.limit == [None, None]) => {
            format!("{figures}  (allowed {})", c.limit_words())
        }
        // Limits of each thread's own (a share of its own P′).
        Some(_) => format!(
            "{figures}  (allowed {})",
            group
                .iter()
                .filter(|c| c.limit != [None, None])
                .map(|c| format!("{} {}", c.thread, c.limit_words()))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        None => format!("n/a  ({})", group[0].message),
    }
}

/// One check of one thread: its figure and allowed range, where it is
/// judged, and what it means where it fails (or always, with `details`).
fn check_line(table: &CycleTable, st: &StitchSummary, c: &Check, details: bool) -> String {
    // The thread bound beside P_B's peak, the thread given at its most.
    let peak = match c.name {
        "thread_bound" => st
            .threads
            .iter()
            .find(|t| t.thread == c.thread)
            .and_then(|t| t.path.as_ref())
            .and_then(|p| table.paths.iter().find(|s| &s.path == p))
            .map_or(String::new(), |s| format!("; P_B peaks at {:.2} mm", s.max_p_mm)),
        _ => String::new(),
    };
    check_row(c, "φ", &peak, details)
}

/// A check's line: its verdict, whose it is, its figure beside the allowed
/// range and where (`at` names the angle, `extra` follows it), then what
/// it means where it fails (or always, with `details`).
fn check_row(c: &Check, at: &str, extra: &str, details: bool) -> String {
    let figure = if c.limit == [None, None] || !c.at_deg.is_finite() {
        format!("{:>11}  ({})", c.value_words(), c.message)
    } else {
        format!(
            "{:>11}  (allowed {}; {at} = {:.1}°{extra})",
            c.value_words(),
            c.limit_words(),
            c.at_deg
        )
    };
    let mut s = format!(
        "  {:<5} {:<6} {:<19} {figure}\n",
        if c.ok { "ok" } else { "FAIL" },
        c.thread,
        c.name
    );
    if !c.ok || details {
        s += &format!("        {}\n", c.message);
    }
    s
}

/// A measured curve against the model's other curve and against the model's own.
fn measured_line(m: &MeasuredMatch) -> String {
    let (what, other) = match m.kind {
        CurveKind::TakeUp => ("measured P", "P′"),
        CurveKind::Required => ("measured P′", "the model's P"),
    };
    let split = if m.split_declared {
        format!("at {}", m.split)
    } else {
        format!("taken at {}", m.split)
    };
    let mut s = format!("\n{what} of {} ({}, {split}):\n", m.thread, m.source);
    if let Some(i) = &m.interval {
        let (lo, hi) = i
            .half_width_mm
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), h| (a.min(*h), b.max(*h)));
        s += &format!(
            "  the mean of up to {} readings per φ ({} §3.4): interval ± {:.3}…{:.3} mm at {} % \
             (resolution {} mm); the model's {} within it at {:.0} % of φ; {} reading(s) flagged as outliers\n",
            i.readings_per_phi,
            crate::references::cite(4),
            lo,
            hi,
            fmt_num(i.confidence * 100.0),
            fmt_num(i.resolution_mm),
            if m.kind == CurveKind::TakeUp { "P" } else { "P′" },
            i.model_within_pct,
            i.outliers
        );
    }
    if let Some(a) = &m.against_other {
        s += &format!(
            "  against {other}: RMS(D) {:.2} mm, max |D| {:.2} mm at φ = {:.1}°, score {}\n",
            a.rms_d_mm,
            a.max_abs_d_mm,
            a.max_abs_d_at_deg,
            score(a.score)
        );
    }
    if let Some(b) = &m.against_model {
        s += &format!(
            "  the model's {} against it: RMS {:.2} mm, max |difference| {:.2} mm at φ = {:.1}°, score {}\n",
            if m.kind == CurveKind::TakeUp { "P" } else { "P′" },
            b.rms_d_mm,
            b.max_abs_d_mm,
            b.max_abs_d_at_deg,
            score(b.score)
        );
    }
    s
}

/// A take-up that gives less than this share of the thread its stitch takes
/// at the peak (max P′ − max P over max P′) gets a note: the score rates how
/// P follows P′ where they are compared, and reads a take-up that gives
/// (nearly) nothing as a middling match.
const SHORTFALL_NOTE_SHARE: f64 = 0.25;
/// …and by at least this, mm.
const SHORTFALL_NOTE_MIN_MM: f64 = 1.0;

/// Notes that read the numbers for the user.
fn notes(table: &CycleTable, st: &StitchSummary) -> String {
    let mut s = String::new();
    let failed: Vec<&Check> = table.all_checks().filter(|c| !c.ok).collect();
    if !failed.is_empty() {
        s += &format!(
            "\nnote: {} physical check(s) fail: this setting cannot work on a real machine, whatever its score\n",
            failed.len()
        );
    }
    for t in &st.threads {
        let max_p = t
            .path
            .as_ref()
            .and_then(|p| table.paths.iter().find(|q| &q.path == p))
            .map(|q| q.max_p_mm);
        // Where `takeup_gives` fails, its message says it already.
        let gives_failed = failed.iter().any(|c| c.name == "takeup_gives" && c.thread == t.thread);
        if let Some(max_p) = max_p
            && !gives_failed
            && t.max_pprime_mm > 0.0
            && t.max_pprime_mm - max_p > (SHORTFALL_NOTE_SHARE * t.max_pprime_mm).max(SHORTFALL_NOTE_MIN_MM)
        {
            let short = t.max_pprime_mm - max_p;
            let makes_up = match &t.tension {
                Some(tn) => format!(
                    "the thread's stretch, slack{} and the regulator make up the rest, at a peak tension of {:.2} N",
                    if tn.spring.is_some() { ", the check spring" } else { "" },
                    tn.peak_n
                ),
                None => "slack and the regulator must make up the rest".into(),
            };
            s += &format!(
                "note: {}: the take-up gives at most {:.2} mm, {:.2} mm ({:.0} %) short of the {:.2} mm the stitch takes at its peak: {makes_up}; the score rates how P follows P′ where they are compared, not this shortfall\n",
                t.thread,
                max_p,
                short,
                100.0 * short / t.max_pprime_mm,
                t.max_pprime_mm
            );
        }
        if let Some(m) = &t.mismatch
            && m.score.is_some_and(|x| x < 20.0)
            && m.phase_shift_max_deg.abs() > 90.0
        {
            s += &format!(
                "note: {}: P peaks {:.0}° away from P′: the take-up works against the stitch; check the take-up's phase\n",
                t.thread,
                m.phase_shift_max_deg.abs()
            );
        }
    }
    s
}

/// Every metric of one thread.
fn thread_details(t: &StitchThreadSummary) -> String {
    let iv = |v: &[[f64; 2]]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.iter()
                .map(|i| format!("{:.0}–{:.0}°", i[0], i[1]))
                .collect::<Vec<_>>()
                .join(", ")
        }
    };
    // Seed 004 numbers the contours of its stitches; the lockstitch has none.
    let contour = if t.contour == 0 {
        "lockstitch".to_string()
    } else {
        format!("contour {}", t.contour)
    };
    let mut s = format!(
        "\n{} ({contour}){}, measured at {}\n",
        t.thread,
        t.path
            .as_ref()
            .map(|p| format!(", take-up path {p}"))
            .unwrap_or_default(),
        t.split
    );
    s += &format!(
        "  per stitch          {:>9.3} mm (cut from P′ at its lock, φ = {:.1}°: {:.3} mm)\n",
        t.per_stitch_mm, t.lock_phi_deg, t.locked_mm
    );
    if t.released_mm > 0.0 {
        s += &format!(
            "  loop released       {:>9.3} mm when it leaves the looper or hook (the lock)\n",
            t.released_mm
        );
    }
    s += &format!(
        "  max P′              {:>9.3} mm at φ = {:.1}°\n",
        t.max_pprime_mm, t.phi_at_max_pprime_deg
    );
    if let Some(b) = t.max_pprime_eye_mm {
        s += &format!("  max P′ at the eye   {b:>9.3} mm (the same thread measured at the moving eye)\n");
    }
    match &t.mismatch {
        Some(m) => {
            s += &format!(
                "  RMS(D)              {:>9.3} mm   (std {:.3} mm)\n",
                m.rms_d_mm, m.std_d_mm
            );
            s += &format!(
                "  max |D|             {:>9.3} mm at φ = {:.1}°   (max D {:.3}, min D {:.3} mm)\n",
                m.max_abs_d_mm, m.max_abs_d_at_deg, m.max_d_mm, m.min_d_mm
            );
            s += &format!(
                "  excess / deficit    {:>9.1} / {:.1} mm·deg\n",
                m.excess_area_mm_deg, m.deficit_area_mm_deg
            );
            s += &format!("  slack  (D > ε)      {}\n", iv(&m.excess_intervals_deg));
            s += &format!("  strain (D < −ε)     {}\n", iv(&m.deficit_intervals_deg));
            let lag = m
                .best_lag_deg
                .map_or(String::new(), |l| format!("  (best lag {l:.1}°)"));
            s += &format!("  phase of maxima     {:>9.1}°{lag}\n", m.phase_shift_max_deg);
            s += &format!(
                "  match score         {:>9}   (offset-free {}; scale: P′ swings {:.3} mm)\n",
                score(m.score),
                score(m.score_offset_free),
                m.range_pprime_mm
            );
        }
        None => s += "  no take-up path to compare (give `path` in [stitch])\n",
    }
    let jumps: Vec<String> = t
        .events
        .iter()
        .filter(|e| e.kind != EventKind::Cont)
        .map(|e| format!("{} at φ = {:.1}°: {:+.3} mm", e.name, e.phi_deg, e.jump_mm))
        .collect();
    if !jumps.is_empty() {
        s += &format!("  jumps of P′         {}\n", jumps.join("; "));
    }
    s
}

/// The match of a model without `[stitch]`: each thread path's take-up P
/// against the curves given for it (a required P′ from a file, or a
/// measured P), over the whole turn; the paths' P and the curves as
/// sparklines; the cams' checks.
pub fn paths_screen(model: &Model, table: &CycleTable, measured: &[MeasuredMatch], details: bool) -> String {
    let mut s = format!(
        "{} — no [stitch]: each thread path's take-up P against the curves given for it\n",
        model.title().unwrap_or(model.name())
    );
    s +=
        "compared over the whole turn (the model gives no regulator window); D = P − P′: D > 0 slack, D < 0 strain\n\n";
    s += &format!(
        "{:<10} {:<5} {:>6} {:>10} {:>10} {:>10}  {}\n",
        "path", "curve", "score", "RMS(D)", "max P", "max P′", "file"
    );
    let phis = table.column("phi_deg").unwrap_or(&[]);
    for m in measured {
        let path = table.paths.iter().find(|q| q.path == m.thread);
        let max_p = path.map_or("—".into(), |q| format!("{:.2} mm", q.max_p_mm));
        let (what, mismatch, max_pprime) = match m.kind {
            CurveKind::Required => (
                "P′",
                m.against_other.as_ref(),
                format!("{:.2} mm", m.values_mm.iter().fold(f64::MIN, |a, &v| a.max(v))),
            ),
            CurveKind::TakeUp => ("P", m.against_model.as_ref(), "—".to_string()),
        };
        s += &format!(
            "{:<10} {:<5} {:>6} {:>10} {:>10} {:>10}  {}\n",
            m.thread,
            what,
            score(mismatch.and_then(|a| a.score)),
            mismatch.map_or("—".into(), |a| format!("{:.3} mm", a.rms_d_mm)),
            max_p,
            max_pprime,
            m.source
        );
    }
    if let Some(&start) = phis.first() {
        s += &format!(
            "\nP (upper line) against the curve (lower line) over one turn from φ = {start}°, {}° a character\n",
            360 / SPARK_COLS
        );
        for m in measured {
            let Some(p) = table
                .paths
                .iter()
                .find(|q| q.path == m.thread)
                .and_then(|q| table.column(&q.p_column))
            else {
                continue;
            };
            let (lo, hi) = p
                .iter()
                .chain(&m.values_mm)
                .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
            let what = if m.kind == CurveKind::Required {
                "P′"
            } else {
                "P meas"
            };
            s += &format!(
                "{:<10}{:<7}{}  {:.1}…{:.1} mm\n",
                m.thread,
                "P",
                sparkline(p, lo, hi, SPARK_COLS),
                lo + 0.0,
                hi + 0.0
            );
            s += &format!("{:<10}{:<7}{}\n", "", what, sparkline(&m.values_mm, lo, hi, SPARK_COLS));
        }
    }
    if table.cam_checks().next().is_some() {
        s += "\nchecks (what no machine can do):\n";
        for c in table.cam_checks() {
            s += &cam_check_line(c, details);
        }
    }
    for m in measured {
        s += &measured_line(m);
    }
    for c in model.caveats() {
        s += &format!("note: {c}\n");
    }
    for w in &table.warnings {
        s += &format!("warning: {w}\n");
    }
    s
}
