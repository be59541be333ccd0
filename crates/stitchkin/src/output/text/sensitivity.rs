//! A sensitivity study ([`crate::study::sensitivity`]) as text: the ranked
//! table per figure, and the CSV with one row per figure and parameter.

use crate::format::{fmt_num, per_unit, sig_sci};
use crate::study::sensitivity::{Method, SensitivityResult};

/// A signed value with 5 significant digits and its unit (`+1.2345 mm`),
/// or `—`.
fn signed(x: Option<f64>, unit: &str) -> String {
    x.map_or("—".into(), |x| {
        format!("{}{} {unit}", if x > 0.0 { "+" } else { "" }, sig_sci(x, 5))
    })
}

/// The readable table: the setting, then per figure its parameters in rank
/// order with d/dp, the effect over the range, the figure at the range's
/// ends and its span; parameters without effect on one line.
pub fn table(r: &SensitivityResult) -> String {
    let setting: Vec<String> = r
        .params
        .iter()
        .map(|p| format!("{} = {} {}", p.name, fmt_num(p.nominal), p.unit))
        .collect();
    let mut s = format!(
        "Sensitivity of `{}` at {} (φ step {}°)\n",
        r.model,
        setting.join(", "),
        r.step_deg
    );
    s += "d/dp: exact (dual numbers) unless marked (c), a central difference; effect = d/dp × the range width;\n";
    s += "at lo, at hi: the figure at the range's ends, the others nominal; span: its max − min over the range.\n";
    let w = super::name_width(r.params.iter().map(|p| p.name.len()), 9);
    let plain = |x: Option<f64>| x.map_or("—".into(), |x| sig_sci(x, 6));
    for f in &r.figures {
        let unit = f.unit;
        let by = if f.ranked_by == "effect" {
            "ranked by |effect|"
        } else {
            "ranked by span"
        };
        s += &format!("\n{} = {} {unit}   ({by})\n", f.figure, sig_sci(f.nominal, 6));
        s += &format!(
            "  {:>4}  {:<w$}  {:<18}  {:>22}  {:>14}  {:>12}  {:>12}  {:>12}\n",
            "rank", "parameter", "range", "d/dp", "effect", "at lo", "at hi", "span"
        );
        let mut none = Vec::new();
        for e in &f.effects {
            if e.effect == Some(0.0) && e.span == Some(0.0) && e.note.is_none() {
                none.push(e.param.as_str());
                continue;
            }
            let range = format!("{} … {} {}", fmt_num(e.lo), fmt_num(e.hi), e.param_unit);
            let d = e.derivative.map_or("—".into(), |d| {
                format!(
                    "{} {}{}",
                    sig_sci(d, 5),
                    per_unit(f.unit, e.param_unit),
                    if e.method == Method::Central { " (c)" } else { "" }
                )
            });
            s += &format!(
                "  {:>4}  {:<w$}  {:<18}  {:>22}  {:>14}  {:>12}  {:>12}  {:>12}\n",
                e.rank,
                e.param,
                range,
                d,
                signed(e.effect, unit),
                plain(e.at_lo),
                plain(e.at_hi),
                e.span.map_or("—".into(), |x| format!("{} {unit}", sig_sci(x, 5)))
            );
            if let Some(n) = &e.note {
                s += &format!("        {n}\n");
            }
        }
        if !none.is_empty() {
            s += &format!("        no effect: {}\n", none.join(", "));
        }
    }
    if !r.insensitive.is_empty() {
        s += &format!("\nno parameter changes: {}\n", r.insensitive.join(", "));
    }
    s += &format!("({} cycles evaluated)\n", r.cycles);
    s
}

/// One row per figure and parameter, every number by [`fmt_num`] (empty
/// where there is none), the note quoted.
pub fn csv(r: &SensitivityResult) -> String {
    let mut s = String::from(
        "figure,figure_unit,nominal,rank,parameter,parameter_unit,range_lo,range_hi,derivative,derivative_unit,method,central_difference,effect,at_lo,at_hi,whole_range,span,note\n",
    );
    let num = |x: Option<f64>| x.map_or(String::new(), fmt_num);
    for f in &r.figures {
        for e in &f.effects {
            let method = match e.method {
                Method::Exact => "exact",
                Method::Central => "central",
            };
            s += &format!(
                "{},{},{},{},{},{},{},{},{},{},{method},{},{},{},{},{},{},\"{}\"\n",
                f.figure,
                f.unit,
                fmt_num(f.nominal),
                e.rank,
                e.param,
                e.param_unit,
                fmt_num(e.lo),
                fmt_num(e.hi),
                num(e.derivative),
                per_unit(f.unit, e.param_unit),
                num(e.central),
                num(e.effect),
                num(e.at_lo),
                num(e.at_hi),
                num(e.whole_range),
                num(e.span),
                e.note.as_deref().unwrap_or("").replace('"', "'"),
            );
        }
    }
    s
}
