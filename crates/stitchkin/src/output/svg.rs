//! A tiny SVG chart builder: axes with "nice" ticks and unit-carrying
//! labels, polylines (solid or dashed), lightly shaded x-intervals,
//! horizontal bands, a legend and a title.
//!
//! Written by hand rather than with a plotting crate: plotters, for one,
//! rounds every coordinate to whole pixels, which blurs a take-up curve
//! whose interesting detail (a dwell, a guide engaging) is a fraction of a
//! pixel high; here coordinates keep two decimals. Text uses the generic
//! `sans-serif` family, so no font is needed to write a chart. Non-finite
//! data points are left out, so no coordinate is ever NaN.

use std::fmt::Write;

/// Line colours, distinguishable and print-safe (Tableau 10).
pub const PALETTE: [&str; 10] = ["#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"];

/// The palette colour for index `i` (cycling).
pub fn color(i: usize) -> &'static str {
    PALETTE[i % PALETTE.len()]
}

/// One axis: its label with the unit (`φ, deg`), an optional fixed range
/// and an optional tick step (otherwise both follow the data).
#[derive(Debug, Clone, Default)]
pub struct Axis {
    pub label: String,
    pub range: Option<(f64, f64)>,
    pub step: Option<f64>,
}

impl Axis {
    pub fn new(label: impl Into<String>) -> Axis {
        Axis { label: label.into(), range: None, step: None }
    }
}

/// A polyline through `points` (x, y in data units).
#[derive(Debug, Clone)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub color: String,
    pub dashed: bool,
    /// A dot marks the first point (where the cycle starts).
    pub mark_start: bool,
}

/// A lightly shaded stretch of x over the full plot height.
#[derive(Debug, Clone)]
pub struct XShade {
    pub from: f64,
    pub to: f64,
    pub color: String,
    /// Tooltip (`<title>`).
    pub label: String,
}

/// A shaded stretch of y over the full plot width.
#[derive(Debug, Clone)]
pub struct YBand {
    pub from: f64,
    pub to: f64,
    pub color: String,
    pub label: String,
}

/// A chart: build it, then [`Chart::render`].
#[derive(Debug, Clone)]
pub struct Chart {
    pub title: String,
    pub subtitle: Option<String>,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
    pub x_shades: Vec<XShade>,
    pub y_bands: Vec<YBand>,
    /// Dashed horizontal reference lines at these y.
    pub y_lines: Vec<f64>,
    /// One data unit is as long on x as on y (a path drawn to scale).
    pub equal_scale: bool,
    pub width: f64,
    pub height: f64,
}

impl Chart {
    pub fn new(title: impl Into<String>, x: Axis, y: Axis) -> Chart {
        Chart {
            title: title.into(),
            subtitle: None,
            x,
            y,
            series: Vec::new(),
            x_shades: Vec::new(),
            y_bands: Vec::new(),
            y_lines: Vec::new(),
            equal_scale: false,
            width: 900.0,
            height: 540.0,
        }
    }
}

/// A "nice" tick step for `span` split into about `target` parts: 1, 2 or
/// 5 times a power of ten.
pub fn nice_step(span: f64, target: usize) -> f64 {
    let raw = span.abs() / target.max(1) as f64;
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let nice = if f <= 1.0 + 1e-9 {
        1.0
    } else if f <= 2.0 + 1e-9 {
        2.0
    } else if f <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

/// The ticks at multiples of `step` inside [lo, hi] (ends included, within
/// a rounding tolerance).
pub fn ticks_in(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite() && step.is_finite() && step > 0.0) || hi < lo {
        return Vec::new();
    }
    let eps = step * 1e-9;
    let first = ((lo - eps) / step).ceil() as i64;
    let last = ((hi + eps) / step).floor() as i64;
    (first..=last.max(first - 1)).map(|k| k as f64 * step).collect()
}

/// A nice axis over the data [lo, hi]: the range widened to whole ticks,
/// the step and the ticks. A zero-width range is widened first.
pub fn nice_axis(lo: f64, hi: f64, target: usize) -> (f64, f64, f64, Vec<f64>) {
    let (mut lo, mut hi) = if lo.is_finite() && hi.is_finite() && lo <= hi { (lo, hi) } else { (0.0, 1.0) };
    if hi - lo < 1e-12 * (1.0 + lo.abs()) {
        let d = if lo.abs() > 0.0 { lo.abs() * 0.05 } else { 1.0 };
        lo -= d;
        hi += d;
    }
    let step = nice_step(hi - lo, target);
    let (a, b) = ((lo / step).floor() * step, (hi / step).ceil() * step);
    (a, b, step, ticks_in(a, b, step))
}

/// A tick label with as many decimals as the step needs; never `-0`.
pub fn tick_label(v: f64, step: f64) -> String {
    let decimals = (0..10usize).find(|&d| {
        let m = step.abs() * 10f64.powi(d as i32);
        (m - m.round()).abs() < 1e-6 * m.max(1.0)
    });
    let decimals = decimals.unwrap_or(10);
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') { s.trim_start_matches('-').to_string() } else { s }
}

/// Text escaped for SVG/XML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => {}
            c => out.push(c),
        }
    }
    out
}

/// A coordinate with two decimals (sub-pixel), never NaN (callers filter).
fn n(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() { "0".into() } else { s.to_string() }
}

const LEGEND_W: f64 = 170.0;
const MARGIN_L: f64 = 78.0;
const MARGIN_R: f64 = 20.0;
const MARGIN_B: f64 = 58.0;

impl Chart {
    /// Data extent of the finite points of every series.
    fn extent(&self) -> Option<(f64, f64, f64, f64)> {
        let mut it = self.series.iter().flat_map(|s| s.points.iter()).filter(|(x, y)| x.is_finite() && y.is_finite());
        let &(x0, y0) = it.next()?;
        Some(it.fold((x0, x0, y0, y0), |(a, b, c, d), &(x, y)| (a.min(x), b.max(x), c.min(y), d.max(y))))
    }

    /// The SVG document.
    pub fn render(&self) -> String {
        let (w, h) = (self.width, self.height);
        let top = if self.subtitle.is_some() { 62.0 } else { 44.0 };
        let (px0, px1) = (MARGIN_L, w - LEGEND_W - MARGIN_R);
        let (py0, py1) = (top, h - MARGIN_B);
        let (dx0, dx1, dy0, dy1) = self.extent().unwrap_or((0.0, 1.0, 0.0, 1.0));
        let fixed = |a: &Axis, lo: f64, hi: f64| a.range.map_or((lo, hi), |r| (r.0.min(lo), r.1.max(hi)));
        let (xlo, xhi) = self.x.range.unwrap_or((dx0, dx1));
        let (ylo, yhi) = fixed(&self.y, dy0, dy1);
        let ((x0, x1, xs, xt), (y0, y1, ys, yt));
        if self.equal_scale {
            // Same tick step and mm per pixel on both axes, the data centred.
            let pad = 0.04 * (xhi - xlo).max(yhi - ylo).max(1e-9);
            let (mut a0, mut a1, mut b0, mut b1) = (xlo - pad, xhi + pad, ylo - pad, yhi + pad);
            let scale = ((px1 - px0) / (a1 - a0)).min((py1 - py0) / (b1 - b0));
            let (cx, cy) = ((a0 + a1) / 2.0, (b0 + b1) / 2.0);
            let (hx, hy) = ((px1 - px0) / scale / 2.0, (py1 - py0) / scale / 2.0);
            (a0, a1, b0, b1) = (cx - hx, cx + hx, cy - hy, cy + hy);
            let step = self.x.step.unwrap_or_else(|| nice_step((a1 - a0).min(b1 - b0), 6));
            (x0, x1, xs, xt) = (a0, a1, step, ticks_in(a0, a1, step));
            (y0, y1, ys, yt) = (b0, b1, step, ticks_in(b0, b1, step));
        } else {
            (x0, x1, xs, xt) = match (self.x.range, self.x.step) {
                (Some(r), Some(s)) => (r.0, r.1, s, ticks_in(r.0, r.1, s)),
                _ => nice_axis(xlo, xhi, 8),
            };
            (y0, y1, ys, yt) = match self.y.step {
                Some(s) => {
                    let (a, b) = ((ylo / s).floor() * s, (yhi / s).ceil() * s);
                    let (a, b) = if b > a { (a, b) } else { (a - s, b + s) };
                    (a, b, s, ticks_in(a, b, s))
                }
                None => nice_axis(ylo, yhi, 6),
            };
        }
        let sx = |x: f64| px0 + (x - x0) / (x1 - x0) * (px1 - px0);
        let sy = |y: f64| py1 - (y - y0) / (y1 - y0) * (py1 - py0);
        let clamp_x = |x: f64| x.clamp(x0, x1);
        let clamp_y = |y: f64| y.clamp(y0, y1);

        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {} {}" font-family="sans-serif" font-size="12">"#,
            n(w),
            n(h),
            n(w),
            n(h)
        );
        let _ = writeln!(s, "<title>{}</title>", escape(&self.title));
        let _ = writeln!(s, r#"<rect x="0" y="0" width="{}" height="{}" fill="white"/>"#, n(w), n(h));
        let _ = writeln!(s, r#"<text class="title" x="{}" y="24" font-size="16" font-weight="bold">{}</text>"#, n(px0), escape(&self.title));
        if let Some(sub) = &self.subtitle {
            let _ = writeln!(s, r##"<text class="subtitle" x="{}" y="44" fill="#555">{}</text>"##, n(px0), escape(sub));
        }
        let _ = writeln!(
            s,
            r##"<rect class="plot-area" x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#999"/>"##,
            n(px0),
            n(py0),
            n(px1 - px0),
            n(py1 - py0)
        );
        // Shading under everything else.
        for b in &self.y_bands {
            let (a, c) = (clamp_y(b.from.min(b.to)), clamp_y(b.from.max(b.to)));
            if !(a.is_finite() && c.is_finite()) || c <= a {
                continue;
            }
            let _ = writeln!(
                s,
                r#"<rect class="band" x="{}" y="{}" width="{}" height="{}" fill="{}" fill-opacity="0.12"><title>{}</title></rect>"#,
                n(px0),
                n(sy(c)),
                n(px1 - px0),
                n(sy(a) - sy(c)),
                escape(&b.color),
                escape(&b.label)
            );
        }
        for sh in &self.x_shades {
            let (a, c) = (clamp_x(sh.from.min(sh.to)), clamp_x(sh.from.max(sh.to)));
            if !(a.is_finite() && c.is_finite()) || c < a {
                continue;
            }
            // An engaged stretch of one sample still shows, a pixel wide.
            let wpx = (sx(c) - sx(a)).max(1.0);
            let _ = writeln!(
                s,
                r#"<rect class="shade" x="{}" y="{}" width="{}" height="{}" fill="{}" fill-opacity="0.10"><title>{}</title></rect>"#,
                n(sx(a)),
                n(py0),
                n(wpx),
                n(py1 - py0),
                escape(&sh.color),
                escape(&sh.label)
            );
        }
        // Grid, ticks and tick labels.
        for &t in &xt {
            let x = sx(t);
            let _ = writeln!(s, r##"<line class="grid" x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#e4e4e4"/>"##, n(py0), n(py1), x = n(x));
            let _ = writeln!(s, r##"<text class="tick x" x="{}" y="{}" text-anchor="middle" fill="#333">{}</text>"##, n(x), n(py1 + 16.0), escape(&tick_label(t, xs)));
        }
        for &t in &yt {
            let y = sy(t);
            let _ = writeln!(s, r##"<line class="grid" x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="#e4e4e4"/>"##, n(px0), n(px1), y = n(y));
            let _ = writeln!(s, r##"<text class="tick y" x="{}" y="{}" text-anchor="end" fill="#333">{}</text>"##, n(px0 - 6.0), n(y + 4.0), escape(&tick_label(t, ys)));
        }
        for &v in &self.y_lines {
            if v.is_finite() && v >= y0 && v <= y1 {
                let _ = writeln!(
                    s,
                    r##"<line class="ref" x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="#c0392b" stroke-dasharray="2 3"/>"##,
                    n(px0),
                    n(px1),
                    y = n(sy(v))
                );
            }
        }
        let _ = writeln!(
            s,
            r#"<text class="axis-label x" x="{}" y="{}" text-anchor="middle">{}</text>"#,
            n((px0 + px1) / 2.0),
            n(h - 16.0),
            escape(&self.x.label)
        );
        let _ = writeln!(
            s,
            r#"<text class="axis-label y" x="{x}" y="{y}" text-anchor="middle" transform="rotate(-90 {x} {y})">{}</text>"#,
            escape(&self.y.label),
            x = n(22.0),
            y = n((py0 + py1) / 2.0)
        );
        // Data, clipped to the plot area.
        let _ = writeln!(s, r#"<clipPath id="plot"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>"#, n(px0), n(py0), n(px1 - px0), n(py1 - py0));
        for se in &self.series {
            let pts: Vec<String> = se.points.iter().filter(|(x, y)| x.is_finite() && y.is_finite()).map(|&(x, y)| format!("{},{}", n(sx(x)), n(sy(y)))).collect();
            let dash = if se.dashed { r#" stroke-dasharray="6 4""# } else { "" };
            let _ = writeln!(
                s,
                r#"<polyline class="series" data-name="{}" clip-path="url(#plot)" fill="none" stroke="{}" stroke-width="1.6"{dash} points="{}"/>"#,
                escape(&se.name),
                escape(&se.color),
                pts.join(" ")
            );
            if se.mark_start
                && let Some(&(x, y)) = se.points.iter().find(|(x, y)| x.is_finite() && y.is_finite())
            {
                let _ = writeln!(s, r#"<circle class="start" cx="{}" cy="{}" r="3" fill="{}"/>"#, n(sx(x)), n(sy(y)), escape(&se.color));
            }
        }
        // Legend, right of the plot.
        let lx = px1 + 16.0;
        for (i, se) in self.series.iter().enumerate() {
            let y = py0 + 8.0 + 18.0 * i as f64;
            let dash = if se.dashed { r#" stroke-dasharray="6 4""# } else { "" };
            let _ = writeln!(
                s,
                r#"<line class="legend-sample" x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{}" stroke-width="2"{dash}/>"#,
                n(lx),
                n(lx + 26.0),
                escape(&se.color),
                y = n(y)
            );
            let _ = writeln!(s, r#"<text class="legend" x="{}" y="{}">{}</text>"#, n(lx + 32.0), n(y + 4.0), escape(&se.name));
        }
        s.push_str("</svg>\n");
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_one_two_or_five_times_a_power_of_ten() {
        assert_eq!(nice_step(360.0, 8), 50.0);
        assert_eq!(nice_step(21.5, 6), 5.0);
        assert_eq!(nice_step(0.7, 6), 0.2);
        assert_eq!(nice_step(10.0, 10), 1.0);
        assert_eq!(nice_step(0.0, 5), 1.0);
        assert_eq!(nice_step(f64::NAN, 5), 1.0);
    }

    #[test]
    fn axes_cover_the_data_with_whole_ticks() {
        let (a, b, step, t) = nice_axis(-0.3, 61.239, 6);
        assert_eq!((a, b, step), (-20.0, 80.0, 20.0));
        assert_eq!(t, vec![-20.0, 0.0, 20.0, 40.0, 60.0, 80.0]);
        assert!(a <= -0.3 && b >= 61.239);
        // A constant series still gets a range.
        let (a, b, _, t) = nice_axis(5.0, 5.0, 6);
        assert!(a < 5.0 && b > 5.0 && t.len() >= 2);
        let (a, b, _, _) = nice_axis(0.0, 0.0, 6);
        assert!(a < 0.0 && b > 0.0);
        assert_eq!(ticks_in(90.6, 450.6, 45.0), vec![135.0, 180.0, 225.0, 270.0, 315.0, 360.0, 405.0, 450.0]);
        assert_eq!(ticks_in(0.0, 360.0, 45.0).len(), 9);
    }

    #[test]
    fn tick_labels_have_the_decimals_the_step_needs() {
        assert_eq!(tick_label(180.0, 45.0), "180");
        assert_eq!(tick_label(0.4, 0.2), "0.4");
        assert_eq!(tick_label(-0.0, 0.5), "0.0");
        assert_eq!(tick_label(-1e-17, 5.0), "0");
        assert_eq!(tick_label(0.05, 0.05), "0.05");
        assert_eq!(tick_label(0.25, 0.25), "0.25");
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(escape(r#"a<b & "c" 'd'>"#), "a&lt;b &amp; &quot;c&quot; &#39;d&#39;&gt;");
        assert_eq!(escape("P′(φ), mm"), "P′(φ), mm");
        assert_eq!(escape("bell\u{7}"), "bell");
    }

    #[test]
    fn a_chart_has_no_nan_and_one_polyline_per_series() {
        let mut c = Chart::new("t <1>", Axis::new("φ, deg"), Axis::new("P, mm"));
        c.series.push(Series { name: "a&b".into(), points: vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0)], color: color(0).into(), dashed: false, mark_start: true });
        c.series.push(Series { name: "empty".into(), points: vec![], color: color(1).into(), dashed: true, mark_start: false });
        c.x_shades.push(XShade { from: 0.5, to: 0.5, color: color(0).into(), label: "G".into() });
        let svg = c.render();
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
        assert_eq!(svg.matches("<polyline").count(), 2);
        assert!(svg.contains("t &lt;1&gt;") && svg.contains(">a&amp;b</text>"));
        assert_eq!(svg.matches("class=\"shade\"").count(), 1);
        assert_eq!(svg.matches("<svg").count(), svg.matches("</svg>").count());
    }
}
