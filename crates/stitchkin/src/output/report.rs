//! `stitchkin report`: one self-contained HTML file about a machine at one
//! setting — its parameters, the mechanism drawing (still and animated),
//! P(φ) with P′(φ), the mismatch per thread, the transmission angles and,
//! when asked, the tuning result and the nomogram (docs/report.md), written
//! from a [`Report`] of results already computed.
//!
//! Self-contained: styles inline, every picture an inline SVG, no script
//! and no reference to another file or site, so the file can be mailed or
//! archived as is. It is well-formed XML as well as HTML (every element
//! closed, every text escaped), which the tests check with an XML parser.

use std::fmt::Write;

use super::plots;
use super::svg::escape;
use crate::error::Error;
use crate::eval::{CycleTable, MU_MAX_DEG, MU_MIN_DEG};
use crate::model::{Model, ParamDef, Params};
use crate::study::measured::MeasuredMatch;
use crate::study::nomogram::Nomogram;
use crate::study::tune::{self, TuneResult};
use crate::thread::measured::CurveKind;

/// What a report shows, computed (the report job, `jobs::report`, computes
/// it): the cycle at the setting, the mechanism drawn, and what was asked
/// for beyond the fixed sections.
#[derive(Debug, Clone)]
pub struct Report {
    /// φ step of every cycle, degrees.
    pub step_deg: f64,
    /// The cycle at the setting: thread paths, stitch and transmission
    /// angles.
    pub table: CycleTable,
    /// The mechanism drawn at one angle and, when asked, animated.
    pub drawing: MechanismDrawing,
    /// Measured curves set beside the model.
    pub measured: Vec<MeasuredMatch>,
    /// The tuning of the adjustable settings, when asked.
    pub tuning: Option<Tuning>,
    /// The nomogram, when asked.
    pub nomogram: Option<Nomogram>,
}

/// The mechanism drawings of a report, as SVG documents.
#[derive(Debug, Clone)]
pub struct MechanismDrawing {
    /// Main-shaft angle of the still drawing, degrees.
    pub phi_deg: f64,
    /// The mechanism at `phi_deg`, dimensioned.
    pub still: String,
    /// One turn of the main shaft, animated.
    pub animated: Option<String>,
}

/// A tuning and the cycle at the setting it recommends.
#[derive(Debug, Clone)]
pub struct Tuning {
    /// The settings before and after, and their match figures.
    pub result: TuneResult,
    /// The cycle at the recommended setting (the tuned take-up).
    pub table: CycleTable,
}

/// Numbers as the report prints them: `d` decimals, `–` for none.
fn num(x: Option<f64>, d: usize) -> String {
    match x {
        // Never `-0.00`.
        Some(x) if x.is_finite() => crate::format::decimals(x, d),
        _ => "–".into(),
    }
}

/// Whether a settable parameter's `value` differs from the model's (a
/// `--set` changed it).
fn is_set(p: &ParamDef, value: f64) -> bool {
    !p.is_derived() && p.value.is_some_and(|nominal| nominal != value)
}

/// A table from a header and rows of cells (already escaped).
fn table(class: &str, head: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!("<table class=\"{class}\"><thead><tr>");
    for h in head {
        let _ = write!(s, "<th>{}</th>", escape(h));
    }
    s += "</tr></thead><tbody>";
    for r in rows {
        s += "<tr>";
        for c in r {
            let _ = write!(s, "<td>{c}</td>");
        }
        s += "</tr>";
    }
    s + "</tbody></table>"
}

/// An SVG as a figure with a caption.
fn figure(id: &str, svg: &str, caption: &str) -> String {
    // The XML declaration, if any, cannot stand inside HTML.
    let svg = svg
        .trim_start()
        .strip_prefix("<?xml")
        .map_or(svg, |rest| rest.split_once("?>").map_or(rest, |(_, s)| s));
    format!(
        "<figure id=\"{id}\">{svg}<figcaption>{}</figcaption></figure>",
        escape(caption)
    )
}

const STYLE: &str = "body{font:14px/1.45 system-ui,sans-serif;color:#222;max-width:1000px;margin:0 auto;padding:16px 20px}\
h1{font-size:22px;margin:0 0 4px}h2{font-size:18px;margin:28px 0 8px;border-bottom:1px solid #ddd;padding-bottom:3px}\
.meta{color:#666;font-size:12px}nav a{margin-right:12px}\
table{border-collapse:collapse;font-variant-numeric:tabular-nums;font-size:13px;margin:6px 0}\
th,td{padding:3px 8px;border-bottom:1px solid #ddd;text-align:right;vertical-align:top}\
th:first-child,td:first-child{text-align:left}td:has(> .text){text-align:left}td:not(:has(> .text)){white-space:nowrap}\
.bad{color:#b3261e;font-weight:600}.good{color:#2e7d32}.warn{color:#8a5a00}\
figure{margin:8px 0}figure svg{width:100%;height:auto}figcaption{color:#555;font-size:12px}\
@media print{nav{display:none}h2{break-after:avoid}figure{break-inside:avoid}}";

/// The whole report for `model` at `params`, from its computed results.
pub fn render(model: &Model, params: &Params, r: &Report) -> Result<String, Error> {
    let sections = sections(model, params, r)?;
    let title = match model.title() {
        Some(t) => format!("{} — {t}", model.name()),
        None => model.name().to_string(),
    };
    let mut html = String::with_capacity(1 << 20);
    html += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"/>";
    let _ = write!(
        html,
        "<title>stitchkin report · {}</title><style>{STYLE}</style></head><body>",
        escape(model.name())
    );
    let _ = write!(
        html,
        "<header><h1>{}</h1><p class=\"meta\">model {}",
        escape(&title),
        escape(&model.file_name)
    );
    if let Some(paper) = model.seed().and_then(crate::references::cite_seed) {
        let _ = write!(html, " · after {}", escape(paper));
    }
    let changed: Vec<String> = model
        .params
        .iter()
        .zip(&params.values)
        .filter(|(p, v)| is_set(p, **v))
        .map(|(p, v)| format!("{} = {} {}", p.name, super::fmt_num(*v), p.unit_str()))
        .collect();
    if !changed.is_empty() {
        let _ = write!(html, " · set: {}", escape(&changed.join(", ")));
    }
    let _ = write!(
        html,
        " · φ step {} deg · stitchkin {}</p>",
        super::fmt_num(r.step_deg),
        env!("CARGO_PKG_VERSION")
    );
    if let Some(notes) = model.notes() {
        let _ = write!(
            html,
            "<p class=\"meta\">{}</p>",
            escape(&crate::references::cited(notes))
        );
    }
    html += "<nav>";
    for (id, name, _) in &sections {
        let _ = write!(html, "<a href=\"#{id}\">{}</a>", escape(name));
    }
    html += "</nav></header>";
    for (k, (id, name, body)) in sections.iter().enumerate() {
        let _ = write!(
            html,
            "<section id=\"{id}\"><h2>{}. {}</h2>{body}</section>",
            k + 1,
            escape(name)
        );
    }
    html += "</body></html>\n";
    // No `-0.00` anywhere in the page, whatever formatted a number.
    Ok(crate::format::without_negative_zeros(&html).into_owned())
}

/// The report's sections in order: id, heading and body.
fn sections(model: &Model, params: &Params, r: &Report) -> Result<Vec<(&'static str, &'static str, String)>, Error> {
    let t = &r.table;
    let mut sections: Vec<(&str, &str, String)> = Vec::new();
    sections.push(("parameters", "Parameters", parameters(model, params)?));
    sections.push(("mechanism", "Mechanism", mechanism(&r.drawing)));
    if !t.paths.is_empty() {
        sections.push((
            "takeup",
            "Take-up P(φ) and required P′(φ)",
            take_up(model, t, &r.measured)?,
        ));
    }
    if t.stitch.is_some() {
        sections.push(("mismatch", "Mismatch P − P′", mismatch(t)));
    }
    if t.stitch.is_some() || !t.cams.is_empty() {
        sections.push(("checks", "Physical checks", checks(t)));
    }
    if !r.measured.is_empty() {
        sections.push(("measured", "Measured curves", measured_section(&r.measured)));
    }
    // Papers by authors and year, as the rest of the report cites them.
    let caveats: Vec<String> = model
        .caveats()
        .iter()
        .chain(t.stitch.iter().flat_map(|s| s.transfers.iter()))
        .map(|c| crate::references::cited(c).into_owned())
        .collect();
    if !caveats.is_empty() {
        sections.push((
            "caveats",
            "What this model reconstructs or carries over",
            list(&caveats, ""),
        ));
    }
    if !t.transmission.is_empty() {
        sections.push(("transmission", "Transmission angles", transmission(model, t)?));
    }
    if let Some(tuned) = &r.tuning {
        sections.push(("tuning", "Tuning", tuning(model, tuned)?));
    }
    if let Some(n) = &r.nomogram {
        sections.push(("nomogram", "Nomogram", nomogram_section(n)));
    }
    let mut warnings = t.warnings.clone();
    if let Some(s) = &t.stitch {
        warnings.extend(s.warnings.iter().cloned());
    }
    if !warnings.is_empty() {
        sections.push(("warnings", "Warnings", list(&warnings, " class=\"warn\"")));
    }
    Ok(sections)
}

/// A list `<ul>` of the texts (escaped), each `<li>` with `attrs`.
fn list(items: &[impl AsRef<str>], attrs: &str) -> String {
    let items: String = items
        .iter()
        .map(|c| format!("<li{attrs}>{}</li>", escape(c.as_ref())))
        .collect();
    format!("<ul>{items}</ul>")
}

/// The nomogram chart and its notes.
fn nomogram_section(n: &Nomogram) -> String {
    let mut body = figure(
        "nomogram-chart",
        &plots::nomogram_figure(n).render(),
        "The tuned setting against the material thickness, one line per stitch length.",
    );
    let notes = n.notes();
    if !notes.is_empty() {
        body += &list(&notes, " class=\"warn\"");
    }
    body
}

fn parameters(model: &Model, params: &Params) -> Result<String, Error> {
    let values = model.parameter_values(params)?;
    let rows: Vec<Vec<String>> = model
        .params
        .iter()
        .zip(&values)
        .map(|(p, v)| {
            let unit = if p.unit_str() == "1" { "" } else { p.unit_str() };
            let range = match p.range {
                Some([lo, hi]) => format!("{}…{}", super::fmt_num(lo), super::fmt_num(hi)),
                None if p.is_derived() => "derived".into(),
                None => String::new(),
            };
            let changed = is_set(p, *v);
            let value = format!(
                "{}{}",
                num(Some(*v), 4).trim_end_matches('0').trim_end_matches('.'),
                if changed { " (set)" } else { "" }
            );
            vec![
                escape(&p.name),
                escape(&value),
                unit.into(),
                escape(&range),
                p.kind.as_str().into(),
                p.provenance
                    .as_ref()
                    .map_or(String::new(), |pr| escape(&format!("{pr:?}").to_lowercase())),
                format!("<span class=\"text\">{}</span>", escape(&describe(p))),
            ]
        })
        .collect();
    Ok(table(
        "parameters",
        &[
            "parameter",
            "value",
            "unit",
            "range",
            "kind",
            "provenance",
            "what it is; source",
        ],
        &rows,
    ))
}

/// A parameter's label and `what` before its source, as one cell.
fn describe(p: &ParamDef) -> String {
    let text = [p.label.as_deref(), p.what.as_deref(), p.source.as_deref()]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join(" — ");
    crate::references::cited(&text).into_owned()
}

/// The mechanism drawings with their captions.
fn mechanism(d: &MechanismDrawing) -> String {
    let mut s = figure(
        "mechanism-still",
        &d.still,
        &format!(
            "The mechanism and its threads at φ = {} deg, dimensioned.",
            super::fmt_num(d.phi_deg)
        ),
    );
    if let Some(animated) = &d.animated {
        s += &figure(
            "mechanism-animated",
            animated,
            "One turn of the main shaft, animated (plays in any browser).",
        );
    }
    s
}

fn take_up(model: &Model, t: &CycleTable, measured: &[MeasuredMatch]) -> Result<String, Error> {
    let chart = plots::take_up_with_measured(model, t, measured)?.render();
    let rows: Vec<Vec<String>> = t
        .paths
        .iter()
        .map(|p| {
            vec![
                escape(&p.path),
                format!(
                    "<span class=\"text\">{}</span>",
                    escape(p.thread.as_deref().unwrap_or(""))
                ),
                if p.split == crate::thread::SplitPoint::B {
                    "B".into()
                } else {
                    "last node".into()
                },
                num(Some(p.max_p_mm), 2),
                num(Some(p.phi_at_max_deg), 1),
                num(Some(p.min_p_mm), 2),
                num(Some(p.xi0_mm), 2),
            ]
        })
        .collect();
    let mut s = figure(
        "takeup-chart",
        &chart,
        "P(φ) of every thread path (solid) and the required P′(φ) of every stitch thread (dashed), needle threads measured at B, the eye's top position; shaded: a one-sided guide engaged.",
    );
    s += &table(
        "paths",
        &[
            "thread path",
            "thread",
            "measured at",
            "max P, mm",
            "at φ, deg",
            "min P, mm",
            "length at φ0, mm",
        ],
        &rows,
    );
    if let Some(words) = &t.take_up {
        let _ = write!(s, "<p class=\"meta\">{}</p>", escape(words));
    }
    Ok(s)
}

fn score_cell(score: Option<f64>) -> String {
    let class = match score {
        Some(s) if s < 50.0 => "bad",
        Some(s) if s >= 80.0 => "good",
        _ => "",
    };
    format!("<span class=\"{class}\">{}</span>", num(score, 1))
}

fn mismatch(t: &CycleTable) -> String {
    let Some(st) = &t.stitch else { return String::new() };
    let rows: Vec<Vec<String>> = st
        .threads
        .iter()
        .map(|th| {
            let m = th.mismatch.as_ref();
            vec![
                escape(&th.thread),
                escape(th.path.as_deref().unwrap_or("–")),
                num(Some(th.per_stitch_mm), 2),
                num(Some(th.max_pprime_mm), 2),
                num(th.max_pprime_eye_mm, 2),
                num(m.map(|m| m.rms_d_mm), 2),
                num(m.map(|m| m.max_abs_d_mm), 2),
                num(m.map(|m| m.max_abs_d_at_deg), 1),
                num(m.map(|m| m.excess_area_mm_deg), 0),
                num(m.map(|m| m.deficit_area_mm_deg), 0),
                num(m.map(|m| m.phase_shift_max_deg), 1),
                score_cell(m.and_then(|m| m.score)),
            ]
        })
        .collect();
    let mut s = format!(
        "<p>Stitch {}, material thickness m = {} mm, stitch length t = {} mm; needle threads are measured at B, the eye's top \
         position ({} §2.3). D = P − P′: D &gt; 0 is thread given but not needed (slack), D &lt; 0 thread needed but not \
         given (strain). Score s = 100·max(0, 1 − RMS(D)/range(P′)).</p><p>Regulator: {}.</p>",
        st.stitch_type,
        num(Some(st.m_mm), 2),
        num(Some(st.t_mm), 2),
        crate::references::cite(4),
        escape(&st.regulator)
    );
    s += &table(
        "mismatch",
        &[
            "thread",
            "path",
            "per stitch, mm",
            "max P′, mm",
            "max P′ at the eye, mm",
            "RMS(D), mm",
            "max |D|, mm",
            "at φ, deg",
            "slack, mm·deg",
            "strain, mm·deg",
            "Δφ of maxima, deg",
            "score",
        ],
        &rows,
    );
    s
}

/// The physical checks of the threads and of each cam and follower
/// ([`CycleTable::all_checks`]), failures in red.
fn checks(t: &CycleTable) -> String {
    if t.all_checks().next().is_none() {
        return if t.stitch.is_some() {
            "<p>This stitch has no needle thread to check.</p>".into()
        } else {
            String::new()
        };
    }
    let rows: Vec<Vec<String>> = t
        .all_checks()
        .map(|c| {
            vec![
                escape(&c.thread),
                escape(c.name),
                if c.ok {
                    "<span class=\"good\">ok</span>".into()
                } else {
                    "<span class=\"bad\">FAIL</span>".into()
                },
                escape(&c.value_words()),
                escape(&c.limit_words()),
                match c.name {
                    "cam_pressure" | "cam_curvature" => format!("δ {}", num(Some(c.at_deg), 1)),
                    _ => num(Some(c.at_deg), 1),
                },
                format!("<span class=\"text\">{}</span>", escape(&c.message)),
            ]
        })
        .collect();
    let mut s = String::new();
    if t.stitch.as_ref().is_some_and(|st| !st.checks.is_empty()) {
        s += "<p>What no real machine can do: more thread through B than the needle can take (twice its deepest travel below B plus the \
         loop on the looper), a looper point that does not pass 1–3 mm above the eye at the catch, a loop that drops before the \
         needle has entered the looper thread's triangle; and, where the thread's tension is solved, a peak too close to the \
         thread's breaking force, a slack loop that can catch, a check spring still moving when thread slips through the \
         regulator.</p>";
    }
    if !t.cams.is_empty() {
        s += "<p>Each cam and follower: its largest pressure angle (at the cam angle δ), its working profile's least \
              radius of curvature (at δ; at or below 0 the profile is cut back to a cusp or undercut), the least force \
              keeping a spring-closed follower on the cam over the cycle (at φ; below 0 it jumps).</p>";
    }
    s += &table(
        "checks",
        &[
            "thread or cam",
            "check",
            "result",
            "value",
            "allowed",
            "at φ, deg",
            "what it means",
        ],
        &rows,
    );
    s
}

/// Each measured curve against the thread's other curve and the model's.
fn measured_section(measured: &[MeasuredMatch]) -> String {
    let rows: Vec<Vec<String>> = measured
        .iter()
        .map(|m| {
            let (what, other) = match m.kind {
                CurveKind::TakeUp => ("measured P", "the model's P′"),
                CurveKind::Required => ("measured P′", "the model's P"),
            };
            let a = m.against_other.as_ref();
            let b = m.against_model.as_ref();
            vec![
                escape(&m.source),
                escape(&m.thread),
                escape(what),
                escape(m.split.as_str()),
                escape(other),
                num(a.map(|a| a.rms_d_mm), 2),
                score_cell(a.and_then(|a| a.score)),
                num(b.map(|b| b.rms_d_mm), 2),
                num(b.map(|b| b.max_abs_d_mm), 2),
                interval_cell(m),
                num(m.interval.as_ref().map(|i| i.model_within_pct), 0),
            ]
        })
        .collect();
    table(
        "measured",
        &[
            "file",
            "thread",
            "curve",
            "at",
            "against",
            "RMS(D), mm",
            "score",
            "RMS vs the model, mm",
            "max |difference| vs the model, mm",
            "interval ± Δ, mm (repeated readings)",
            "the model within it, % of φ",
        ],
        &rows,
    )
}

/// A mean curve's interval (seed 004 §3.4): the range of its half-widths,
/// the confidence and the readings per φ; `—` for a curve of one value per φ.
fn interval_cell(m: &MeasuredMatch) -> String {
    match &m.interval {
        None => "—".into(),
        Some(i) => {
            let (lo, hi) = i
                .half_width_mm
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(a, b), h| (a.min(*h), b.max(*h)));
            escape(&format!(
                "{lo:.3}…{hi:.3} at {} % ({} readings per φ, {} §3.4)",
                crate::format::fmt_num(i.confidence * 100.0),
                i.readings_per_phi,
                crate::references::cite(4)
            ))
        }
    }
}

fn transmission(model: &Model, t: &CycleTable) -> Result<String, Error> {
    let chart = plots::transmission(model, t)?.render();
    let rows: Vec<Vec<String>> = t
        .transmission
        .iter()
        .map(|m| {
            vec![
                escape(&m.group),
                num(Some(m.min_deg), 1),
                num(Some(m.phi_at_min_deg), 1),
                num(Some(m.max_deg), 1),
                num(Some(m.phi_at_max_deg), 1),
                if m.ok {
                    "<span class=\"good\">inside</span>".into()
                } else {
                    "<span class=\"bad\">outside</span>".into()
                },
            ]
        })
        .collect();
    let mut s = figure(
        "mu-chart",
        &chart,
        &format!("Transmission angles μ(φ); outside {MU_MIN_DEG}°…{MU_MAX_DEG}° (shaded) the mechanism risks jamming."),
    );
    s += &table(
        "transmission",
        &[
            "group",
            "min μ, deg",
            "at φ, deg",
            "max μ, deg",
            "at φ, deg",
            &format!("{MU_MIN_DEG}°…{MU_MAX_DEG}°"),
        ],
        &rows,
    );
    Ok(s)
}

/// The tuning: the settings before and after, the scores, the tuned
/// take-up chart.
fn tuning(model: &Model, tuned: &Tuning) -> Result<String, Error> {
    let r = &tuned.result;
    let rows: Vec<Vec<String>> = r
        .names
        .iter()
        .zip(r.before.iter().zip(&r.after))
        .map(|((name, unit), (b, a))| {
            let flat = r.flatness.iter().find(|f| f.name == *name).map_or(String::new(), |f| {
                format!("{}…{}", num(Some(f.lo), 2), num(Some(f.hi), 2))
            });
            let advice = r
                .adjustments
                .iter()
                .find(|x| x.name == *name)
                .map_or(String::new(), |x| {
                    format!("<span class=\"text\">{}</span>", escape(&x.advice))
                });
            vec![
                escape(name),
                (*unit).into(),
                num(Some(*b), 3),
                format!("<b>{}</b>", num(Some(*a), 3)),
                num(Some(a - b), 3),
                flat,
                advice,
            ]
        })
        .collect();
    let mut s = String::from(
        "<p>The adjustable settings that make P match P′ best for every thread together, with the transmission angles inside their \
         band and every physical check passing (constraints of the search).</p>",
    );
    s += &table(
        "tuning",
        &[
            "setting",
            "unit",
            "before",
            "recommended",
            "change",
            "within one score point",
            "on the machine",
        ],
        &rows,
    );
    let threads: Vec<Vec<String>> = r
        .before_figures
        .threads
        .iter()
        .zip(&r.after_figures.threads)
        .map(|(b, a)| {
            vec![
                escape(&b.0),
                score_cell(b.1),
                score_cell(a.1),
                num(Some(b.2), 2),
                num(Some(a.2), 2),
            ]
        })
        .collect();
    s += &table(
        "tuning-scores",
        &[
            "thread",
            "score before",
            "score after",
            "RMS(D) before, mm",
            "RMS(D) after, mm",
        ],
        &threads,
    );
    let failed = |f: &tune::MatchFigures| {
        if f.failed_checks.is_empty() {
            "all pass".to_string()
        } else {
            format!("{} fail", f.failed_checks.join(", "))
        }
    };
    let _ = write!(
        s,
        "<p class=\"meta\">mean score {} → {}; physical checks before: {}, after: {}; {} cycles evaluated.</p>",
        num(Some(r.before_figures.score_mean), 1),
        num(Some(r.after_figures.score_mean), 1),
        escape(&failed(&r.before_figures)),
        escape(&failed(&r.after_figures)),
        r.evaluations
    );
    if !r.notes.is_empty() {
        s += &list(&r.notes, " class=\"warn\"");
    }
    let chart = plots::take_up(model, &tuned.table)?.render();
    s += &figure(
        "tuned-takeup-chart",
        &chart,
        "P(φ) and P′(φ) at the recommended setting.",
    );
    Ok(s)
}
