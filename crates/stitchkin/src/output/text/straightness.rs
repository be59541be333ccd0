//! Straightness and tolerance studies ([`crate::study::straightness`]) as
//! text: the summary of a path's deviation from a line, its CSV per φ
//! sample, and the tolerance table with its Monte Carlo lines.

use crate::format::{fmt_num, mm5, mm5_signed};
use crate::output::text::columns;
use crate::study::straightness::{Distribution, Straightness, ToleranceStudy};

/// The deviation summary of model `model` at φ step `step_deg`: the line,
/// the travel along it, the largest, smallest, largest absolute and RMS
/// deviation, and the minimum zone when there is one.
pub fn summary(model: &str, s: &Straightness, step_deg: f64) -> String {
    let mut summary = format!(
        "{model}: straightness of {} from {}, {} (φ step {}°)\n",
        s.point,
        s.reference,
        s.window,
        fmt_num(step_deg)
    );
    let [px, py, pz] = s.line_point_mm;
    let [ux, uy, uz] = s.line_direction;
    let (point, dir) = if s.signed {
        (format!("({px:.4}, {py:.4}) mm"), format!("({ux:.6}, {uy:.6})"))
    } else {
        (
            format!("({px:.4}, {py:.4}, {pz:.4}) mm"),
            format!("({ux:.6}, {uy:.6}, {uz:.6})"),
        )
    };
    summary += &format!(
        "line: through {point}, direction {dir}, {:.3}° from +y\n\n",
        s.line_from_y_deg
    );
    let d = if s.signed { "deviation" } else { "distance" };
    let extreme = |x: f64| if s.signed { mm5_signed(x) } else { mm5(x) };
    let mut rows = vec![
        vec![
            "travel along the line".to_string(),
            format!("{:.4} mm", s.travel_mm),
            String::new(),
        ],
        vec![
            format!("largest {d}"),
            extreme(s.max_dev_mm),
            format!("at φ = {:.2}°", s.phi_at_max_deg),
        ],
        vec![
            format!("smallest {d}"),
            extreme(s.min_dev_mm),
            format!("at φ = {:.2}°", s.phi_at_min_deg),
        ],
        vec![format!("max |{d}|"), mm5(s.max_abs_dev_mm), String::new()],
        vec![
            format!("RMS {d}"),
            mm5(s.rms_dev_mm),
            format!("over {} φ samples", s.phi_deg.len()),
        ],
    ];
    if let Some(z) = s.zone_mm {
        rows.push(vec![
            "minimum zone (ISO 1101)".into(),
            mm5(z),
            "width of the narrowest band holding the path".into(),
        ]);
    }
    for r in &rows {
        summary += format!("{:<24} {:>13}  {}", r[0], r[1], r[2]).trim_end();
        summary += "\n";
    }
    if s.signed {
        summary += "deviation: + to the left of the line's direction\n";
    }
    summary
}

/// The deviation per φ sample: `phi_deg,P.along_mm,P.dev_mm`.
pub fn csv(s: &Straightness) -> String {
    let mut c = format!("phi_deg,{p}.along_mm,{p}.dev_mm\n", p = s.point);
    for k in 0..s.phi_deg.len() {
        c += &format!(
            "{},{},{}\n",
            fmt_num(s.phi_deg[k]),
            fmt_num(s.along_mm[k]),
            fmt_num(s.dev_mm[k])
        );
    }
    c
}

/// `text` with every line a comment (`# …`; an empty line `#`), to stand
/// beside CSV.
pub fn commented(text: &str) -> String {
    text.lines()
        .map(|l| {
            if l.is_empty() {
                "#\n".to_string()
            } else {
                format!("# {l}\n")
            }
        })
        .collect()
}

/// One row per parameter: its tolerance, the deviation at −tol and +tol,
/// the change from nominal, the largest tolerance alone and whether a
/// limit was found (1) or not (0).
pub fn tolerance_csv(t: &ToleranceStudy) -> String {
    let mut c = String::from("parameter,unit,tol,dev_minus_mm,dev_plus_mm,change_mm,largest_tol,bounded\n");
    let o = |x: Option<f64>| x.map_or(String::new(), fmt_num);
    for r in &t.one_at_a_time {
        c += &format!(
            "{},{},{},{},{},{},{},{}\n",
            r.name,
            r.unit,
            fmt_num(r.tol),
            o(r.dev_minus_mm),
            o(r.dev_plus_mm),
            o(r.change_mm),
            fmt_num(r.largest_tol),
            r.bounded as u8
        );
    }
    c
}

/// The Monte Carlo over every tolerance at once, three lines each starting
/// with `prefix` (empty without a Monte Carlo).
pub fn monte_carlo(t: &ToleranceStudy, prefix: &str) -> String {
    let Some(mc) = &t.monte_carlo else { return String::new() };
    let how = match mc.distribution {
        Distribution::Uniform => "uniform within ±tol",
        Distribution::Normal => "normal, σ = tol/3, truncated at ±tol",
    };
    let v = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x:.4}"));
    let mut s = format!(
        "{prefix}Monte Carlo, every tolerance at once: {} samples, {how}, seed {}\n",
        mc.samples, mc.seed
    );
    s += &format!(
        "{prefix}  max |deviation|  50 %: {} mm   90 %: {} mm   99 %: {} mm   (mean {} mm, largest {} mm)\n",
        v(mc.p50_mm),
        v(mc.p90_mm),
        v(mc.p99_mm),
        v(mc.mean_mm),
        v(mc.max_mm)
    );
    s += &format!(
        "{prefix}  over the {} mm limit: {:.1} % of the samples ({} did not assemble)\n",
        fmt_num(t.limit_mm),
        100.0 * mc.over_limit,
        mc.failed
    );
    s
}

/// The readable tolerance table of model `model` at φ step `step_deg`: each
/// parameter at ± its tolerance (`*` over the limit) and the largest
/// tolerance it may have alone, then the Monte Carlo.
pub fn tolerance_table(model: &str, t: &ToleranceStudy, step_deg: f64) -> String {
    let mut s = format!(
        "{model}: tolerances for the straightness of {} (max |deviation| from {}, {}; φ step {}°)\n",
        t.point,
        t.reference,
        t.window,
        fmt_num(step_deg)
    );
    s += &format!("nominal {:.5} mm; limit {} mm\n\n", t.nominal_mm, fmt_num(t.limit_mm));
    let head: Vec<String> = [
        "parameter",
        "tolerance",
        "at −tol",
        "at +tol",
        "change",
        "largest alone",
    ]
    .map(String::from)
    .to_vec();
    let dev = |x: Option<f64>| x.map_or("no assembly".to_string(), |x| format!("{x:.5} mm"));
    let rows: Vec<Vec<String>> = t
        .one_at_a_time
        .iter()
        .map(|r| {
            let largest = if r.bounded {
                format!("±{:.4} {}", r.largest_tol, r.unit)
            } else {
                format!("> ±{} {} (no limit found)", fmt_num(r.largest_tol), r.unit)
            };
            let over = |x: Option<f64>| if x.is_some_and(|x| x > t.limit_mm) { " *" } else { "" };
            vec![
                r.name.clone(),
                format!("±{} {}", fmt_num(r.tol), r.unit),
                dev(r.dev_minus_mm) + over(r.dev_minus_mm),
                dev(r.dev_plus_mm) + over(r.dev_plus_mm),
                r.change_mm.map_or("—".to_string(), |c| format!("{c:+.5} mm")),
                largest,
            ]
        })
        .collect();
    s += &columns::table(&head, &rows, true);
    s += "change: the worse of −tol and +tol minus the nominal; largest alone: the largest ± tolerance of that\n";
    s += "parameter alone with the deviation within the limit (bisection); * over the limit\n";
    if t.monte_carlo.is_some() {
        s += "\n";
        s += &monte_carlo(t, "");
    }
    s
}
