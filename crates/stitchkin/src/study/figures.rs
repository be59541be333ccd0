//! Figures of merit: the named numbers a study reads off a cycle table
//! (take-up extremes, transmission angles, measure ranges, point strokes,
//! match scores and checks), the patterns that select them, and the P' a
//! study can compute once when its varied parameters leave the stitch
//! process alone.

use super::design::Sweep;
use crate::error::{Error, ParamError};
use crate::eval::stitch_process::{Prepared, prepare};
use crate::eval::{CycleTable, glob_match};
use crate::model::{Model, Params};

/// Every figure of merit a cycle offers, by name (with its unit): take-up
/// extremes per path, transmission-angle extremes (per dyad and overall),
/// measure ranges, point strokes along each axis (`POINT.y_stroke_mm`),
/// and per stitch thread the match
/// score, RMS and largest |D|, plus the mean and worst score; where the
/// thread's tension is solved, its peak `THR.max_T_N`, breaking margin
/// `THR.tension_margin`, largest slack loop `THR.max_slack_mm` and the
/// slack left where the stitch is pulled tight `THR.set_slack_mm`.
pub fn figures(table: &CycleTable) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    for p in &table.paths {
        let pn = crate::eval::take_up_name(p.split == crate::thread::SplitPoint::B);
        out.push((format!("{}.max_{pn}_mm", p.path), p.max_p_mm));
        out.push((format!("{}.min_{pn}_mm", p.path), p.min_p_mm));
    }
    if !table.transmission.is_empty() {
        out.push((
            "mu.min_deg".into(),
            table.transmission.iter().map(|t| t.min_deg).fold(f64::MAX, f64::min),
        ));
        out.push((
            "mu.max_deg".into(),
            table.transmission.iter().map(|t| t.max_deg).fold(f64::MIN, f64::max),
        ));
        out.push((
            "mu.ok".into(),
            if table.transmission.iter().all(|t| t.ok) {
                1.0
            } else {
                0.0
            },
        ));
        for t in &table.transmission {
            out.push((format!("mu_{}.min_deg", t.key), t.min_deg));
            out.push((format!("mu_{}.max_deg", t.key), t.max_deg));
        }
    }
    for r in &table.ranges {
        out.push((format!("{}.range_mm", r.name), r.range));
        out.push((format!("{}.min_mm", r.name), r.min));
        out.push((format!("{}.max_mm", r.name), r.max));
    }
    for c in &table.columns {
        let coord = [".x_mm", ".y_mm", ".z_mm"]
            .iter()
            .find_map(|s| c.name.strip_suffix(s).map(|p| (p, &s[1..2])));
        if let Some((point, axis)) = coord
            && !c.name.contains("Pprime")
        {
            let (lo, hi) = c
                .values
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
            out.push((format!("{point}.{axis}_stroke_mm"), hi - lo));
        }
    }
    if let Some(st) = &table.stitch {
        let mut scores = Vec::new();
        for t in &st.threads {
            out.push((
                format!(
                    "{}.{}",
                    t.thread,
                    max_pprime_figure(t.split == crate::thread::SplitPoint::B)
                ),
                t.max_pprime_mm,
            ));
            if let Some(tn) = &t.tension {
                out.push((format!("{}.max_T_N", t.thread), tn.peak_n));
                out.push((format!("{}.tension_margin", t.thread), tn.margin));
                out.push((format!("{}.max_slack_mm", t.thread), tn.max_slack_mm));
                out.push((format!("{}.set_slack_mm", t.thread), tn.set_slack_mm));
            }
            let checks: Vec<_> = st.checks.iter().filter(|c| c.thread == t.thread).collect();
            if !checks.is_empty() {
                out.push((
                    format!("{}.checks_ok", t.thread),
                    if checks.iter().all(|c| c.ok) { 1.0 } else { 0.0 },
                ));
            }
            if let Some(c) = checks.iter().find(|c| c.name == "thread_bound") {
                out.push((format!("{}.bound_margin_mm", t.thread), c.value));
            }
            if let Some(m) = &t.mismatch {
                if let Some(s) = m.score {
                    out.push((format!("{}.score", t.thread), s));
                    scores.push(s);
                }
                out.push((format!("{}.rms_D_mm", t.thread), m.rms_d_mm));
                out.push((format!("{}.max_abs_D_mm", t.thread), m.max_abs_d_mm));
            }
        }
        if !scores.is_empty() {
            out.push(("score.mean".into(), scores.iter().sum::<f64>() / scores.len() as f64));
            out.push(("score.min".into(), scores.iter().cloned().fold(f64::MAX, f64::min)));
        }
    }
    // Each cam and follower's checks, and whether every check of the cycle
    // passes (the stitch's and the cams').
    for cam in &table.cams {
        out.push((
            format!("{}.checks_ok", cam.group),
            if cam.checks_ok() { 1.0 } else { 0.0 },
        ));
        for c in &cam.checks {
            let name = match c.name {
                "cam_pressure" => "max_pressure_deg",
                "cam_curvature" if c.limit[0].is_some() => "min_profile_radius_mm",
                "follower_contact" if c.limit[0].is_some() => "min_contact_force_n",
                _ => continue,
            };
            out.push((format!("{}.{name}", cam.group), c.value));
        }
        if let Some(rpm) = cam.limit_rpm {
            out.push((format!("{}.limit_rpm", cam.group), rpm));
        }
    }
    if table.all_checks().next().is_some() {
        out.push(("checks.ok".into(), if table.checks_ok() { 1.0 } else { 0.0 }));
    }
    out
}

/// The figure of a stitch thread's largest P': `max_Pprime_B_mm` for a
/// needle thread (at B), `max_Pprime_mm` for a looper thread.
pub(crate) fn max_pprime_figure(at_b: bool) -> &'static str {
    if at_b { "max_Pprime_B_mm" } else { "max_Pprime_mm" }
}

/// Figures a sweep writes by default (those the model has): every match
/// score and their mean and worst, the take-up maximum of every path (at B
/// for a needle-eye path), whether every physical check passes, the
/// transmission-angle extremes, the measures' ranges and the point strokes.
pub const DEFAULT_FIGURES: &[&str] = &[
    "*.score",
    "score.*",
    "*.max_P_B_mm",
    "*.max_P_mm",
    "checks.ok",
    "mu.min_deg",
    "mu.max_deg",
    "*.range_mm",
    "*_stroke_mm",
];

/// The [`DEFAULT_FIGURES`] patterns that match a figure of `available`.
pub fn default_figures(available: &[(String, f64)]) -> Vec<String> {
    DEFAULT_FIGURES
        .iter()
        .filter(|p| available.iter().any(|(n, _)| glob_match(p, n)))
        .map(|p| p.to_string())
        .collect()
}

/// The figure names matching `patterns` (`*` matches any run), in the order
/// [`figures`] gives them; an error lists what there is when a pattern
/// matches nothing.
pub fn select_figures(available: &[(String, f64)], patterns: &[String]) -> Result<Vec<String>, Error> {
    for p in patterns {
        if !available.iter().any(|(n, _)| glob_match(p, n)) {
            let names: Vec<&str> = available.iter().map(|(n, _)| n.as_str()).collect();
            return Err(Error::Param(ParamError::general(
                format!("no figure of merit matches `{p}`"),
                Some(format!("this model offers: {}", names.join(", "))),
            )));
        }
    }
    Ok(available
        .iter()
        .filter(|(n, _)| patterns.iter().any(|p| glob_match(p, n)))
        .map(|(n, _)| n.clone())
        .collect())
}

/// P' computed once for the whole sweep, when the varied parameters leave
/// the stitch process alone (they change only the take-up, as `z`, `dphi`,
/// `r1` of the MF-7923D do: [`Model::leaves_stitch_alone`] for every varied
/// parameter). `None` when the model has no stitch process or a varied
/// parameter changes it (P' is then computed per setting).
pub fn shared_stitch(model: &Model, base: &Params, sweep: &Sweep, step_deg: f64) -> Result<Option<Prepared>, Error> {
    let Some(nominal) = model.stitch_setup(base)? else {
        return Ok(None);
    };
    for v in &sweep.vary {
        if !model.leaves_stitch_alone(base, &nominal, &v.name, v.lo, v.hi)? {
            return Ok(None);
        }
    }
    prepare(model, base, step_deg)
}
