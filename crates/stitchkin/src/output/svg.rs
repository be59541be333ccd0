//! A tiny SVG chart builder: axes with "nice" ticks and unit-carrying
//! labels, polylines (solid or dashed), lightly shaded x-intervals,
//! horizontal bands, filled areas between two curves, marked points, heat
//! maps with a colour bar, a legend and a title; charts stacked as panels
//! of one figure ([`Figure`]); and a projected wireframe surface
//! ([`Surface`]).
//!
//! Written by hand rather than with a plotting crate: plotters, for one,
//! rounds every coordinate to whole pixels, which blurs a take-up curve
//! whose interesting detail (a dwell, a guide engaging) is a fraction of a
//! pixel high; here coordinates keep two decimals. Text uses the generic
//! `sans-serif` family, so no font is needed to write a chart. Non-finite
//! data points are left out, so no coordinate is ever NaN.

use std::fmt::Write;

use crate::format::{push_svg_num, svg_num as n};

/// Line colours, distinguishable and print-safe (Tableau 10).
pub const PALETTE: [&str; 10] = [
    "#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac",
];

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
        Axis {
            label: label.into(),
            range: None,
            step: None,
        }
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
    /// A heat map under the lines, with its colour bar in the legend.
    pub heat: Option<Heat>,
    /// Filled areas between two curves (under the lines).
    pub areas: Vec<Area>,
    /// Marked points (over the lines).
    pub markers: Vec<Marker>,
    pub width: f64,
    pub height: f64,
}

/// A heat map: one cell per grid point, coloured by `z` on the
/// [`ramp`] from the smallest to the largest finite value; a non-finite
/// value (a setting that did not evaluate) is a grey cell. Cell edges lie
/// halfway between neighbouring grid values.
#[derive(Debug, Clone)]
pub struct Heat {
    /// Grid values along x, ascending.
    pub xs: Vec<f64>,
    /// Grid values along y, ascending.
    pub ys: Vec<f64>,
    /// `z[j][i]` is the value at (`xs[i]`, `ys[j]`).
    pub z: Vec<Vec<f64>>,
    /// The colour bar's label, with the unit (`P, mm`).
    pub label: String,
    /// Tooltips per cell, `tips[j][i]` (empty: none).
    pub tips: Vec<Vec<String>>,
    /// Legend text of the grey cells, shown when there are any.
    pub missing: String,
}

/// The region between `lower` and `upper` (x, y in data units), filled
/// lightly.
#[derive(Debug, Clone)]
pub struct Area {
    pub upper: Vec<(f64, f64)>,
    pub lower: Vec<(f64, f64)>,
    pub color: String,
    /// Tooltip.
    pub label: String,
}

/// A dot at (x, y) with a tooltip and, when `legend` is set, a legend entry.
#[derive(Debug, Clone)]
pub struct Marker {
    pub x: f64,
    pub y: f64,
    pub color: String,
    pub label: String,
    pub legend: Option<String>,
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
            heat: None,
            areas: Vec::new(),
            markers: Vec::new(),
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
    let (mut lo, mut hi) = if lo.is_finite() && hi.is_finite() && lo <= hi {
        (lo, hi)
    } else {
        (0.0, 1.0)
    };
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
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
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

/// The viridis colour map at `t` ∈ [0, 1] (dark violet → yellow),
/// perceptually uniform and readable in grey; linear between nine anchors.
pub fn ramp(t: f64) -> String {
    const VIRIDIS: [(u8, u8, u8); 9] = [
        (0x44, 0x01, 0x54),
        (0x47, 0x2d, 0x7b),
        (0x3b, 0x52, 0x8b),
        (0x2c, 0x72, 0x8e),
        (0x21, 0x91, 0x8c),
        (0x28, 0xae, 0x80),
        (0x5e, 0xc9, 0x62),
        (0xad, 0xdc, 0x30),
        (0xfd, 0xe7, 0x25),
    ];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let u = t * (VIRIDIS.len() - 1) as f64;
    let k = (u.floor() as usize).min(VIRIDIS.len() - 2);
    let f = u - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    let mix = |p: u8, q: u8| (p as f64 + (q as f64 - p as f64) * f).round() as u8;
    format!("#{:02x}{:02x}{:02x}", mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Colour `i` of a family of `n` lines: the dark three quarters of
/// [`ramp`] (its yellow end is too light for a line on white).
pub fn family_color(i: usize, n: usize) -> String {
    ramp(if n > 1 { 0.82 * i as f64 / (n - 1) as f64 } else { 0.0 })
}

impl Series {
    /// A solid line without a start mark.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>, color: impl Into<String>) -> Series {
        Series {
            name: name.into(),
            points,
            color: color.into(),
            dashed: false,
            mark_start: false,
        }
    }
}

/// Cell edges around grid values: halfway between neighbours, the ends
/// half a spacing out.
pub fn cell_edges(v: &[f64]) -> Vec<f64> {
    match v.len() {
        0 => Vec::new(),
        1 => vec![v[0] - 0.5, v[0] + 0.5],
        n => {
            let mut e = Vec::with_capacity(n + 1);
            e.push(v[0] - (v[1] - v[0]) / 2.0);
            e.extend(v.windows(2).map(|w| (w[0] + w[1]) / 2.0));
            e.push(v[n - 1] + (v[n - 1] - v[n - 2]) / 2.0);
            e
        }
    }
}

impl Heat {
    /// The smallest and largest finite value (widened when equal).
    pub fn z_range(&self) -> Option<(f64, f64)> {
        let (lo, hi) = self
            .z
            .iter()
            .flatten()
            .filter(|v| v.is_finite())
            .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        if lo > hi {
            return None;
        }
        if hi - lo < 1e-12 * (1.0 + lo.abs()) {
            let d = if lo.abs() > 0.0 { lo.abs() * 0.05 } else { 0.5 };
            return Some((lo - d, hi + d));
        }
        Some((lo, hi))
    }

    fn has_missing(&self) -> bool {
        self.z.iter().flatten().any(|v| !v.is_finite())
    }
}

const LEGEND_W: f64 = 170.0;
const MARGIN_L: f64 = 78.0;
const MARGIN_R: f64 = 20.0;
const MARGIN_B: f64 = 58.0;
/// Approximate advance of one 12 px sans-serif character.
const CHAR_W: f64 = 7.0;
const COLORBAR_W: f64 = 14.0;

/// The opening `<svg>` tag, the document title and a white background.
fn open_document(s: &mut String, w: f64, h: f64, title: &str) {
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {} {}" font-family="sans-serif" font-size="12">"#,
        n(w),
        n(h),
        n(w),
        n(h)
    );
    let _ = writeln!(s, "<title>{}</title>", escape(title));
    let _ = writeln!(
        s,
        r#"<rect x="0" y="0" width="{}" height="{}" fill="white"/>"#,
        n(w),
        n(h)
    );
}

/// The bold title and the grey subtitle under it, wrapped to the page's
/// `width`; returns the y where the content may start.
fn write_titles(s: &mut String, x: f64, width: f64, title: &str, subtitle: Option<&str>) -> f64 {
    let _ = writeln!(
        s,
        r#"<text class="title" x="{}" y="24" font-size="16" font-weight="bold">{}</text>"#,
        n(x),
        escape(title)
    );
    let Some(sub) = subtitle else { return 44.0 };
    let lines = wrap(sub, width - x - MARGIN_R);
    if let [line] = lines.as_slice() {
        let _ = writeln!(
            s,
            r##"<text class="subtitle" x="{}" y="44" fill="#555">{}</text>"##,
            n(x),
            escape(line)
        );
    } else {
        let spans: String = lines
            .iter()
            .enumerate()
            .map(|(k, l)| {
                format!(
                    r#"<tspan x="{}" y="{}">{}</tspan>"#,
                    n(x),
                    n(44.0 + SUBTITLE_LINE * k as f64),
                    escape(l)
                )
            })
            .collect();
        let _ = writeln!(
            s,
            r##"<text class="subtitle" x="{}" y="44" fill="#555">{spans}</text>"##,
            n(x)
        );
    }
    header_height(lines.len())
}

/// The height of the title and a subtitle of `lines` lines, px.
fn header_height(lines: usize) -> f64 {
    if lines == 0 {
        44.0
    } else {
        62.0 + SUBTITLE_LINE * (lines - 1) as f64
    }
}

/// A subtitle's lines on a page `width` wide, px.
fn subtitle_lines(subtitle: Option<&str>, width: f64) -> usize {
    subtitle.map_or(0, |sub| wrap(sub, width - MARGIN_L - MARGIN_R).len())
}

/// The distance between a subtitle's lines, px.
const SUBTITLE_LINE: f64 = 15.0;

/// `text` in lines at most `width` px wide (at [`CHAR_W`] a character):
/// broken after its clauses (`; `) where it can be, else between words.
fn wrap(text: &str, width: f64) -> Vec<String> {
    let max = ((width / CHAR_W).floor() as usize).max(20);
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    let clauses: Vec<&str> = text.split_inclusive("; ").collect();
    for clause in clauses {
        let clause_len = clause.trim_end().chars().count();
        if line.chars().count() + clause_len <= max {
            line.push_str(clause);
            continue;
        }
        if !line.is_empty() {
            lines.push(line.trim_end().to_string());
            line = String::new();
        }
        if clause_len <= max {
            line.push_str(clause);
            continue;
        }
        // A clause longer than a line: between its words.
        for word in clause.split_inclusive(' ') {
            if !line.is_empty() && line.chars().count() + word.trim_end().chars().count() > max {
                lines.push(line.trim_end().to_string());
                line = String::new();
            }
            line.push_str(word);
        }
    }
    if !line.trim().is_empty() {
        lines.push(line.trim_end().to_string());
    }
    lines
}

/// A vertical colour bar of [`ramp`] over [lo, hi] at (x, top), `height`
/// tall, with nice ticks and `label` (rotated) beside it. Returns the
/// width it takes.
fn colorbar(s: &mut String, id: &str, x: f64, top: f64, height: f64, (lo, hi): (f64, f64), label: &str) -> f64 {
    let _ = writeln!(s, r#"<defs><linearGradient id="{id}" x1="0" y1="1" x2="0" y2="0">"#);
    for k in 0..=8 {
        let t = k as f64 / 8.0;
        let _ = writeln!(s, r#"<stop offset="{}" stop-color="{}"/>"#, n(t), ramp(t));
    }
    s.push_str("</linearGradient></defs>\n");
    let _ = writeln!(
        s,
        r##"<rect class="colorbar" x="{}" y="{}" width="{}" height="{}" fill="url(#{id})" stroke="#999"/>"##,
        n(x),
        n(top),
        n(COLORBAR_W),
        n(height)
    );
    let step = nice_step(hi - lo, 6);
    let ticks = ticks_in(lo, hi, step);
    let mut widest = 0usize;
    for &t in &ticks {
        let y = top + height * (1.0 - (t - lo) / (hi - lo));
        let text = tick_label(t, step);
        widest = widest.max(text.chars().count());
        let _ = writeln!(
            s,
            r##"<line class="colorbar-mark" x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="#333"/>"##,
            n(x + COLORBAR_W),
            n(x + COLORBAR_W + 4.0),
            y = n(y)
        );
        let _ = writeln!(
            s,
            r##"<text class="colorbar-tick" x="{}" y="{}" fill="#333">{}</text>"##,
            n(x + COLORBAR_W + 7.0),
            n(y + 4.0),
            escape(&text)
        );
    }
    let lx = x + COLORBAR_W + 7.0 + CHAR_W * widest as f64 + 14.0;
    let _ = writeln!(
        s,
        r#"<text class="colorbar-label" x="{x}" y="{y}" text-anchor="middle" transform="rotate(-90 {x} {y})">{}</text>"#,
        escape(label),
        x = n(lx),
        y = n(top + height / 2.0)
    );
    lx + 6.0 - x
}

impl Chart {
    /// Data extent of every series, area, marker and heat-map cell.
    fn extent(&self) -> Option<(f64, f64, f64, f64)> {
        let areas = self.areas.iter().flat_map(|a| a.upper.iter().chain(&a.lower));
        let marks: Vec<(f64, f64)> = self.markers.iter().map(|m| (m.x, m.y)).collect();
        let cells: Vec<(f64, f64)> = match &self.heat {
            Some(h) => {
                let (ex, ey) = (cell_edges(&h.xs), cell_edges(&h.ys));
                match (ex.first(), ex.last(), ey.first(), ey.last()) {
                    (Some(&a), Some(&b), Some(&c), Some(&d)) => vec![(a, c), (b, d)],
                    _ => Vec::new(),
                }
            }
            None => Vec::new(),
        };
        let mut it = self
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .chain(areas)
            .chain(&marks)
            .chain(&cells)
            .filter(|(x, y)| x.is_finite() && y.is_finite());
        let &(x0, y0) = it.next()?;
        Some(it.fold((x0, x0, y0, y0), |(a, b, c, d), &(x, y)| {
            (a.min(x), b.max(x), c.min(y), d.max(y))
        }))
    }

    /// Width of the legend column: room for the longest entry.
    fn legend_width(&self) -> f64 {
        let names = self.series.iter().map(|s| s.name.chars().count()).chain(
            self.markers
                .iter()
                .filter_map(|m| m.legend.as_ref().map(|l| l.chars().count())),
        );
        let longest = names
            .chain(
                self.heat
                    .as_ref()
                    .filter(|h| h.has_missing())
                    .map(|h| h.missing.chars().count()),
            )
            .max()
            .unwrap_or(0);
        (40.0 + CHAR_W * longest as f64).clamp(LEGEND_W, 360.0)
    }

    /// The SVG document.
    pub fn render(&self) -> String {
        let mut s = String::new();
        open_document(&mut s, self.width, self.height, &self.title);
        let top = write_titles(&mut s, MARGIN_L, self.width, &self.title, self.subtitle.as_deref());
        self.draw(&mut s, top, self.height, self.legend_width(), "plot");
        s.push_str("</svg>\n");
        s
    }

    /// The plot area from `py0` down to `bottom` less the axis label, left
    /// of a legend column `legend_w` wide, and the axes' ranges and ticks:
    /// the data's (or the fixed ranges), or one scale for both axes.
    fn plot_area(&self, py0: f64, bottom: f64, legend_w: f64) -> Plot {
        let w = self.width;
        let (px0, px1) = (MARGIN_L, w - legend_w - MARGIN_R);
        let py1 = bottom - MARGIN_B;
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
            (y0, y1, ys, yt) = match (self.y.range, self.y.step) {
                // A fixed range with a step is kept as it is (widened only
                // to data outside it).
                (Some(_), Some(s)) if yhi > ylo => (ylo, yhi, s, ticks_in(ylo, yhi, s)),
                (_, Some(s)) => {
                    let (a, b) = ((ylo / s).floor() * s, (yhi / s).ceil() * s);
                    let (a, b) = if b > a { (a, b) } else { (a - s, b + s) };
                    (a, b, s, ticks_in(a, b, s))
                }
                (_, None) => nice_axis(ylo, yhi, 6),
            };
        }
        Plot {
            px0,
            px1,
            py0,
            py1,
            x0,
            x1,
            y0,
            y1,
            xs,
            xt,
            ys,
            yt,
        }
    }

    /// Draws the plot area from `py0` down to `bottom` (the x-axis label
    /// included) with a legend column `legend_w` wide; `id` names its clip
    /// path and gradient (unique within a document).
    fn draw(&self, s: &mut String, py0: f64, bottom: f64, legend_w: f64, id: &str) {
        let p = self.plot_area(py0, bottom, legend_w);
        let (px0, px1, py1) = (p.px0, p.px1, p.py1);
        let _ = writeln!(
            s,
            r##"<rect class="plot-area" x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#999"/>"##,
            n(px0),
            n(py0),
            n(px1 - px0),
            n(py1 - py0)
        );
        self.draw_shading(s, &p);
        self.draw_grid(s, &p);
        let _ = writeln!(
            s,
            r#"<clipPath id="{id}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>"#,
            n(px0),
            n(py0),
            n(px1 - px0),
            n(py1 - py0)
        );
        let z_range = self.heat.as_ref().and_then(Heat::z_range);
        self.draw_heat(s, &p, id, z_range);
        self.draw_areas(s, &p, id);
        self.draw_axis_labels(s, &p, bottom);
        self.draw_data(s, &p, id);
        self.draw_legend(s, &p, id, z_range);
    }

    /// Shading under everything else: y bands, then x stretches.
    fn draw_shading(&self, s: &mut String, p: &Plot) {
        let (px0, px1, py0, py1) = (p.px0, p.px1, p.py0, p.py1);
        let sx = |x: f64| p.sx(x);
        let sy = |y: f64| p.sy(y);
        let clamp_x = |x: f64| x.clamp(p.x0, p.x1);
        let clamp_y = |y: f64| y.clamp(p.y0, p.y1);
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
    }

    /// Grid lines, ticks and tick labels.
    fn draw_grid(&self, s: &mut String, p: &Plot) {
        let (px0, px1, py0, py1) = (p.px0, p.px1, p.py0, p.py1);
        let sx = |x: f64| p.sx(x);
        let sy = |y: f64| p.sy(y);
        for &t in &p.xt {
            let x = sx(t);
            let _ = writeln!(
                s,
                r##"<line class="grid" x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#e4e4e4"/>"##,
                n(py0),
                n(py1),
                x = n(x)
            );
            let _ = writeln!(
                s,
                r##"<text class="tick x" x="{}" y="{}" text-anchor="middle" fill="#333">{}</text>"##,
                n(x),
                n(py1 + 16.0),
                escape(&tick_label(t, p.xs))
            );
        }
        for &t in &p.yt {
            let y = sy(t);
            let _ = writeln!(
                s,
                r##"<line class="grid" x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="#e4e4e4"/>"##,
                n(px0),
                n(px1),
                y = n(y)
            );
            let _ = writeln!(
                s,
                r##"<text class="tick y" x="{}" y="{}" text-anchor="end" fill="#333">{}</text>"##,
                n(px0 - 6.0),
                n(y + 4.0),
                escape(&tick_label(t, p.ys))
            );
        }
    }

    /// The heat map, covering the grid.
    fn draw_heat(&self, s: &mut String, p: &Plot, id: &str, z_range: Option<(f64, f64)>) {
        let sx = |x: f64| p.sx(x);
        let sy = |y: f64| p.sy(y);
        if let (Some(h), Some((zlo, zhi))) = (&self.heat, z_range) {
            let (ex, ey) = (cell_edges(&h.xs), cell_edges(&h.ys));
            let _ = writeln!(s, r#"<g clip-path="url(#{id})" shape-rendering="crispEdges">"#);
            for (j, row) in h.z.iter().enumerate().take(h.ys.len()) {
                for (i, &v) in row.iter().enumerate().take(h.xs.len()) {
                    let (xa, xb, ya, yb) = (sx(ex[i]), sx(ex[i + 1]), sy(ey[j]), sy(ey[j + 1]));
                    let (class, fill) = if v.is_finite() {
                        ("cell", ramp((v - zlo) / (zhi - zlo)))
                    } else {
                        ("cell missing", "#d9d9d9".to_string())
                    };
                    let tip = h
                        .tips
                        .get(j)
                        .and_then(|r| r.get(i))
                        .map_or(String::new(), |t| format!("<title>{}</title>", escape(t)));
                    let _ = writeln!(
                        s,
                        r#"<rect class="{class}" x="{}" y="{}" width="{}" height="{}" fill="{fill}">{tip}</rect>"#,
                        n(xa.min(xb)),
                        n(ya.min(yb)),
                        n((xb - xa).abs()),
                        n((yb - ya).abs())
                    );
                }
            }
            s.push_str("</g>\n");
        }
    }

    /// Filled areas and the dashed reference lines.
    fn draw_areas(&self, s: &mut String, p: &Plot, id: &str) {
        let (px0, px1) = (p.px0, p.px1);
        let sx = |x: f64| p.sx(x);
        let sy = |y: f64| p.sy(y);
        for a in &self.areas {
            let (pts, count) = points_attr(
                a.upper
                    .iter()
                    .chain(a.lower.iter().rev())
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .map(|&(x, y)| (sx(x), sy(y))),
            );
            if count >= 3 {
                let _ = writeln!(
                    s,
                    r#"<polygon class="area" clip-path="url(#{id})" fill="{}" fill-opacity="0.15" stroke="none" points="{}"><title>{}</title></polygon>"#,
                    escape(&a.color),
                    pts,
                    escape(&a.label)
                );
            }
        }
        for &v in &self.y_lines {
            if v.is_finite() && v >= p.y0 && v <= p.y1 {
                let _ = writeln!(
                    s,
                    r##"<line class="ref" x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="#c0392b" stroke-dasharray="2 3"/>"##,
                    n(px0),
                    n(px1),
                    y = n(sy(v))
                );
            }
        }
    }

    /// The axes' labels.
    fn draw_axis_labels(&self, s: &mut String, p: &Plot, bottom: f64) {
        let (px0, px1, py0, py1) = (p.px0, p.px1, p.py0, p.py1);
        let _ = writeln!(
            s,
            r#"<text class="axis-label x" x="{}" y="{}" text-anchor="middle">{}</text>"#,
            n((px0 + px1) / 2.0),
            n(bottom - 16.0),
            escape(&self.x.label)
        );
        let _ = writeln!(
            s,
            r#"<text class="axis-label y" x="{x}" y="{y}" text-anchor="middle" transform="rotate(-90 {x} {y})">{}</text>"#,
            escape(&self.y.label),
            x = n(22.0),
            y = n((py0 + py1) / 2.0)
        );
    }

    /// Data, clipped to the plot area: the series, then the marked points.
    fn draw_data(&self, s: &mut String, p: &Plot, id: &str) {
        let sx = |x: f64| p.sx(x);
        let sy = |y: f64| p.sy(y);
        for se in &self.series {
            let (pts, _) = points_attr(
                se.points
                    .iter()
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .map(|&(x, y)| (sx(x), sy(y))),
            );
            let dash = if se.dashed { r#" stroke-dasharray="6 4""# } else { "" };
            let _ = writeln!(
                s,
                r#"<polyline class="series" data-name="{}" clip-path="url(#{id})" fill="none" stroke="{}" stroke-width="1.6"{dash} points="{}"/>"#,
                escape(&se.name),
                escape(&se.color),
                pts
            );
            if se.mark_start
                && let Some(&(x, y)) = se.points.iter().find(|(x, y)| x.is_finite() && y.is_finite())
            {
                let _ = writeln!(
                    s,
                    r#"<circle class="start" cx="{}" cy="{}" r="3" fill="{}"/>"#,
                    n(sx(x)),
                    n(sy(y)),
                    escape(&se.color)
                );
            }
        }
        for m in self.markers.iter().filter(|m| m.x.is_finite() && m.y.is_finite()) {
            let _ = writeln!(
                s,
                r#"<circle class="point" cx="{}" cy="{}" r="4" fill="{}" stroke="white" stroke-width="1.5"><title>{}</title></circle>"#,
                n(sx(m.x)),
                n(sy(m.y)),
                escape(&m.color),
                escape(&m.label)
            );
        }
    }

    /// Legend, right of the plot: the colour bar, then the entries.
    fn draw_legend(&self, s: &mut String, p: &Plot, id: &str, z_range: Option<(f64, f64)>) {
        let (px1, py0, py1) = (p.px1, p.py0, p.py1);
        let lx = px1 + 16.0;
        let mut ly = py0 + 8.0;
        let missing = self.heat.as_ref().filter(|h| h.has_missing());
        let entries = self.series.len()
            + self.markers.iter().filter(|m| m.legend.is_some()).count()
            + usize::from(missing.is_some());
        if let (Some(h), Some((zlo, zhi))) = (&self.heat, z_range) {
            let height = if entries > 0 {
                ((py1 - py0) * 0.6).max(60.0)
            } else {
                (py1 - py0) * 0.8
            };
            colorbar(
                s,
                &format!("{id}-ramp"),
                lx,
                py0,
                height.min(py1 - py0),
                (zlo, zhi),
                &h.label,
            );
            ly = py0 + height + 24.0;
        }
        let pitch = if entries > 1 {
            ((py1 + MARGIN_B * 0.5 - ly) / (entries - 1) as f64).clamp(10.0, 18.0)
        } else {
            18.0
        };
        for se in &self.series {
            let dash = if se.dashed { r#" stroke-dasharray="6 4""# } else { "" };
            let _ = writeln!(
                s,
                r#"<line class="legend-sample" x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{}" stroke-width="2"{dash}/>"#,
                n(lx),
                n(lx + 26.0),
                escape(&se.color),
                y = n(ly)
            );
            let _ = writeln!(
                s,
                r#"<text class="legend" x="{}" y="{}">{}</text>"#,
                n(lx + 32.0),
                n(ly + 4.0),
                escape(&se.name)
            );
            ly += pitch;
        }
        for m in &self.markers {
            if let Some(text) = &m.legend {
                let _ = writeln!(
                    s,
                    r##"<circle class="legend-sample" cx="{}" cy="{}" r="4" fill="{}" stroke="#555"/>"##,
                    n(lx + 13.0),
                    n(ly),
                    escape(&m.color)
                );
                let _ = writeln!(
                    s,
                    r#"<text class="legend" x="{}" y="{}">{}</text>"#,
                    n(lx + 32.0),
                    n(ly + 4.0),
                    escape(text)
                );
                ly += pitch;
            }
        }
        if let Some(h) = missing {
            let _ = writeln!(
                s,
                r##"<rect class="legend-sample" x="{}" y="{}" width="26" height="10" fill="#d9d9d9"/>"##,
                n(lx),
                n(ly - 5.0)
            );
            let _ = writeln!(
                s,
                r#"<text class="legend" x="{}" y="{}">{}</text>"#,
                n(lx + 32.0),
                n(ly + 4.0),
                escape(&h.missing)
            );
        }
    }
}

/// A chart's plot area on the page (px) and its axes: ranges, tick steps
/// and ticks (data units).
struct Plot {
    px0: f64,
    px1: f64,
    py0: f64,
    py1: f64,
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    xs: f64,
    xt: Vec<f64>,
    ys: f64,
    yt: Vec<f64>,
}

impl Plot {
    /// Data x to px.
    fn sx(&self, x: f64) -> f64 {
        self.px0 + (x - self.x0) / (self.x1 - self.x0) * (self.px1 - self.px0)
    }

    /// Data y to px (up).
    fn sy(&self, y: f64) -> f64 {
        self.py1 - (y - self.y0) / (self.y1 - self.y0) * (self.py1 - self.py0)
    }
}

/// Charts stacked as panels of one figure, under one title: each panel's
/// own title heads it, and the panels share the legend column's width so
/// their plot areas line up.
#[derive(Debug, Clone)]
pub struct Figure {
    pub title: String,
    pub subtitle: Option<String>,
    pub panels: Vec<Chart>,
}

impl Figure {
    pub fn new(title: impl Into<String>) -> Figure {
        Figure {
            title: title.into(),
            subtitle: None,
            panels: Vec::new(),
        }
    }

    /// The SVG document.
    pub fn render(&self) -> String {
        let w = self.panels.iter().map(|p| p.width).fold(0.0, f64::max).max(400.0);
        let legend_w = self.panels.iter().map(Chart::legend_width).fold(LEGEND_W, f64::max);
        let header = header_height(subtitle_lines(self.subtitle.as_deref(), w));
        let h = header + self.panels.iter().map(|p| p.height).sum::<f64>();
        let mut s = String::new();
        open_document(&mut s, w, h, &self.title);
        let mut y = write_titles(&mut s, MARGIN_L, w, &self.title, self.subtitle.as_deref());
        for (k, p) in self.panels.iter().enumerate() {
            let _ = writeln!(
                s,
                r#"<text class="panel-title" x="{}" y="{}" font-size="13" font-weight="bold">{}</text>"#,
                n(MARGIN_L),
                n(y + 16.0),
                escape(&p.title)
            );
            let mut panel = p.clone();
            panel.width = w;
            panel.draw(&mut s, y + 26.0, y + p.height, legend_w, &format!("plot{}", k + 1));
            y += p.height;
        }
        s.push_str("</svg>\n");
        s
    }
}

/// A surface z(x, y) over a grid, drawn as a projected wireframe: an
/// oblique view with x to the right, y going back and up to the right and
/// z up; the quadrilaterals are filled by z on [`ramp`] and painted from
/// the back to the front, so nearer parts hide farther ones. Grid lines
/// run along x at every y value and across at every `cross_every`-th x.
#[derive(Debug, Clone)]
pub struct Surface {
    pub title: String,
    pub subtitle: Option<String>,
    /// Across, at the front (`range`/`step` as for a chart).
    pub x: Axis,
    /// Into the depth.
    pub y: Axis,
    /// Up; its label also labels the colour bar.
    pub z: Axis,
    /// Grid values along x and y, ascending.
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    /// `z[j][i]` at (`xs[i]`, `ys[j]`).
    pub z_values: Vec<Vec<f64>>,
    /// Lines across the surface at every this-many x samples.
    pub cross_every: usize,
    pub width: f64,
    pub height: f64,
}

/// A surface's axis: its range, tick step and ticks.
type SurfaceAxis = (f64, f64, f64, Vec<f64>);

/// The oblique view of a surface's box [x0, x1]×[y0, y1]×[z0, z1]: x to
/// the right, y back and up to the right, z up, filling the page from
/// `left` to the colour bar and from the titles to `bottom`.
struct Oblique {
    x: SurfaceAxis,
    y: SurfaceAxis,
    z: SurfaceAxis,
    left: f64,
    bottom: f64,
    span_x: f64,
    span_z: f64,
    depth_x: f64,
    depth_y: f64,
}

impl Oblique {
    /// The page point of (x, y, z), px.
    fn at(&self, x: f64, y: f64, z: f64) -> (f64, f64) {
        let (x0, x1, y0, y1, z0, z1) = (self.x.0, self.x.1, self.y.0, self.y.1, self.z.0, self.z.1);
        let (u, v, t) = ((x - x0) / (x1 - x0), (y - y0) / (y1 - y0), (z - z0) / (z1 - z0));
        (
            self.left + u * self.span_x + v * self.depth_x,
            self.bottom - t * self.span_z - v * self.depth_y,
        )
    }
}

/// A page point as SVG `x,y`.
/// The `points` of a polyline or polygon through `pts` (px), `x,y x,y …`,
/// each number as [`n`] writes it, and how many points it holds.
fn points_attr(pts: impl IntoIterator<Item = (f64, f64)>) -> (String, usize) {
    let mut s = String::new();
    let mut count = 0;
    for (x, y) in pts {
        if count > 0 {
            s.push(' ');
        }
        push_svg_num(&mut s, x);
        s.push(',');
        push_svg_num(&mut s, y);
        count += 1;
    }
    (s, count)
}

/// A line from `a` to `b`, px.
fn line(s: &mut String, class: &str, a: (f64, f64), b: (f64, f64), stroke: &str) {
    let _ = writeln!(
        s,
        r#"<line class="{class}" x1="{}" y1="{}" x2="{}" y2="{}" stroke="{stroke}"/>"#,
        n(a.0),
        n(a.1),
        n(b.0),
        n(b.1)
    );
}

impl Surface {
    /// The SVG document.
    pub fn render(&self) -> String {
        let (w, h) = (self.width, self.height);
        let mut s = String::new();
        open_document(&mut s, w, h, &self.title);
        let top = write_titles(&mut s, MARGIN_L, w, &self.title, self.subtitle.as_deref()) + 10.0;
        let fin = |v: &[f64]| {
            v.iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)))
        };
        let all: Vec<f64> = self.z_values.iter().flatten().copied().collect();
        let (zl, zh) = fin(&all);
        // The projection: the box fills the area left of the colour bar.
        let (left, right, bottom) = (MARGIN_L + 10.0, w - 150.0 - 70.0, h - 50.0);
        let (depth_x, depth_y) = (0.30 * (right - left), 0.32 * (bottom - top));
        let (x, y, z) = self.axes((zl, zh), fin(&self.xs), fin(&self.ys));
        let o = Oblique {
            x,
            y,
            z,
            left,
            bottom,
            span_x: right - left - depth_x,
            span_z: bottom - top - depth_y,
            depth_x,
            depth_y,
        };
        self.draw_box(&mut s, &o);
        self.draw_tick_labels(&mut s, &o);
        self.draw_mesh(&mut s, &o, (zl, zh));
        if zh >= zl {
            let (lo, hi) = if zh - zl > 1e-12 {
                (zl, zh)
            } else {
                (zl - 0.5, zh + 0.5)
            };
            colorbar(
                &mut s,
                "surface-ramp",
                w - 150.0,
                top,
                (bottom - top) * 0.7,
                (lo, hi),
                &self.z.label,
            );
        }
        s.push_str("</svg>\n");
        s
    }

    /// The x, y and z axes over the data's ranges (or the fixed ones).
    fn axes(
        &self,
        (zl, zh): (f64, f64),
        (xl, xh): (f64, f64),
        (yl, yh): (f64, f64),
    ) -> (SurfaceAxis, SurfaceAxis, SurfaceAxis) {
        let axis = |a: &Axis, lo: f64, hi: f64, target: usize| match (a.range, a.step) {
            (Some(r), Some(s)) => (r.0, r.1, s, ticks_in(r.0, r.1, s)),
            (Some(r), None) => {
                let s = nice_step(r.1 - r.0, target);
                (r.0, r.1, s, ticks_in(r.0, r.1, s))
            }
            _ => nice_axis(lo, hi, target),
        };
        (
            axis(&self.x, xl, xh, 8),
            match self.y.range {
                Some(_) => axis(&self.y, yl, yh, 5),
                // The depth axis spans the grid exactly, ticks inside.
                None if yh > yl => {
                    let s = nice_step(yh - yl, 5);
                    (yl, yh, s, ticks_in(yl, yh, s))
                }
                None => nice_axis(yl, yh, 5),
            },
            axis(&self.z, zl, zh, 5),
        )
    }

    /// The floor and the two back walls, with grid lines.
    fn draw_box(&self, s: &mut String, o: &Oblique) {
        let (x0, x1, y0, y1, z0, z1) = (o.x.0, o.x.1, o.y.0, o.y.1, o.z.0, o.z.1);
        let p = |x: f64, y: f64, z: f64| o.at(x, y, z);
        let (x, y, z) = (&o.x, &o.y, &o.z);
        for (class, corners) in [
            ("floor", [p(x0, y0, z0), p(x1, y0, z0), p(x1, y1, z0), p(x0, y1, z0)]),
            ("wall", [p(x0, y1, z0), p(x1, y1, z0), p(x1, y1, z1), p(x0, y1, z1)]),
            ("wall", [p(x0, y0, z0), p(x0, y1, z0), p(x0, y1, z1), p(x0, y0, z1)]),
        ] {
            let _ = writeln!(
                s,
                r##"<polygon class="{class}" points="{}" fill="#fafafa" stroke="#999"/>"##,
                points_attr(corners).0
            );
        }
        for &t in &x.3 {
            line(s, "grid", p(t, y0, z0), p(t, y1, z0), "#e4e4e4");
            line(s, "grid", p(t, y1, z0), p(t, y1, z1), "#e4e4e4");
        }
        for &t in &y.3 {
            line(s, "grid", p(x0, t, z0), p(x1, t, z0), "#e4e4e4");
            line(s, "grid", p(x0, t, z0), p(x0, t, z1), "#e4e4e4");
        }
        for &t in &z.3 {
            line(s, "grid", p(x0, y0, t), p(x0, y1, t), "#e4e4e4");
            line(s, "grid", p(x0, y1, t), p(x1, y1, t), "#e4e4e4");
        }
    }

    /// Tick labels on the front edge (x), the right floor edge (y) and
    /// the front left edge (z), and the axis labels.
    fn draw_tick_labels(&self, s: &mut String, o: &Oblique) {
        let (x0, x1, y0, y1, z0, z1) = (o.x.0, o.x.1, o.y.0, o.y.1, o.z.0, o.z.1);
        let p = |x: f64, y: f64, z: f64| o.at(x, y, z);
        let (x, y, z) = (&o.x, &o.y, &o.z);
        for &t in &x.3 {
            let (a, b) = p(t, y0, z0);
            let _ = writeln!(
                s,
                r##"<text class="tick x" x="{}" y="{}" text-anchor="middle" fill="#333">{}</text>"##,
                n(a),
                n(b + 16.0),
                escape(&tick_label(t, x.2))
            );
        }
        for &t in &y.3 {
            let (a, b) = p(x1, t, z0);
            let _ = writeln!(
                s,
                r##"<text class="tick y" x="{}" y="{}" fill="#333">{}</text>"##,
                n(a + 14.0),
                n(b + 8.0),
                escape(&tick_label(t, y.2))
            );
        }
        for &t in &z.3 {
            let (a, b) = p(x0, y0, t);
            let _ = writeln!(
                s,
                r##"<text class="tick z" x="{}" y="{}" text-anchor="end" fill="#333">{}</text>"##,
                n(a - 6.0),
                n(b + 4.0),
                escape(&tick_label(t, z.2))
            );
        }
        let (ax, ay) = p((x0 + x1) / 2.0, y0, z0);
        let _ = writeln!(
            s,
            r#"<text class="axis-label x" x="{}" y="{}" text-anchor="middle">{}</text>"#,
            n(ax),
            n(ay + 36.0),
            escape(&self.x.label)
        );
        let (bx, by) = p(x1, (y0 + y1) / 2.0, z0);
        let _ = writeln!(
            s,
            r#"<text class="axis-label y" x="{}" y="{}">{}</text>"#,
            n(bx + 54.0),
            n(by + 8.0),
            escape(&self.y.label)
        );
        let (cx, cy) = (22.0, (p(x0, y0, z0).1 + p(x0, y0, z1).1) / 2.0);
        let _ = writeln!(
            s,
            r#"<text class="axis-label z" x="{x}" y="{y}" text-anchor="middle" transform="rotate(-90 {x} {y})">{}</text>"#,
            escape(&self.z.label),
            x = n(cx),
            y = n(cy)
        );
    }

    /// The surface, back to front: facets filled by z on [`ramp`] from
    /// `zl` to `zh`, with the mesh over them.
    fn draw_mesh(&self, s: &mut String, o: &Oblique, (zl, zh): (f64, f64)) {
        let p = |x: f64, y: f64, z: f64| o.at(x, y, z);
        let z = |i: usize, j: usize| self.z_values.get(j).and_then(|r| r.get(i)).copied().unwrap_or(f64::NAN);
        let (ni, nj) = (self.xs.len(), self.ys.len().min(self.z_values.len()));
        let edge = |s: &mut String, j: usize| {
            let mut run: Vec<(f64, f64)> = Vec::new();
            let flush = |s: &mut String, run: &mut Vec<(f64, f64)>| {
                if run.len() >= 2 {
                    let _ = writeln!(
                        s,
                        r##"<polyline class="mesh" fill="none" stroke="#333" stroke-width="0.8" points="{}"/>"##,
                        points_attr(run.iter().copied()).0
                    );
                }
                run.clear();
            };
            for i in 0..ni {
                let v = z(i, j);
                if v.is_finite() {
                    run.push(p(self.xs[i], self.ys[j], v));
                } else {
                    flush(s, &mut run);
                }
            }
            flush(s, &mut run);
        };
        let every = self.cross_every.max(1);
        if nj >= 2 && ni >= 2 {
            // Strip j lies between rows j and j + 1; its far edge (row
            // j + 1) is drawn over it, the nearer strips may hide both.
            for j in (0..nj - 1).rev() {
                for i in 0..ni - 1 {
                    let c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                    let vs: Vec<f64> = c.iter().map(|&(a, b)| z(a, b)).collect();
                    if vs.iter().any(|v| !v.is_finite()) {
                        continue;
                    }
                    let fill = ramp((vs.iter().sum::<f64>() / 4.0 - zl) / (zh - zl).max(1e-12));
                    let (pts, _) = points_attr(c.iter().zip(&vs).map(|(&(a, b), &v)| p(self.xs[a], self.ys[b], v)));
                    let _ = writeln!(
                        s,
                        r#"<polygon class="facet" points="{}" fill="{fill}" stroke="{fill}" stroke-width="0.5"/>"#,
                        pts
                    );
                }
                for i in (0..ni).step_by(every).chain(std::iter::once(ni - 1)) {
                    let (a, b) = (z(i, j), z(i, j + 1));
                    if a.is_finite() && b.is_finite() {
                        line(
                            s,
                            "mesh",
                            p(self.xs[i], self.ys[j], a),
                            p(self.xs[i], self.ys[j + 1], b),
                            "#333",
                        );
                    }
                }
                edge(s, j + 1);
            }
            edge(s, 0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_subtitle_wraps_after_its_clauses_inside_the_page() {
        let sub = "solid: P (take-up), dashed: P′ (required, stitch 407, m = 3 mm, t = 3 mm); shaded: one-sided guide \
                   engaged; needle threads at B, the eye's top position; regulator windows 19°…48°, 94°…113°, \
                   215°…237° of n1 (computed) left out of the match";
        let lines = wrap(sub, 900.0 - MARGIN_L - MARGIN_R);
        assert!(lines.len() >= 2, "{lines:?}");
        for l in &lines {
            assert!(MARGIN_L + CHAR_W * l.chars().count() as f64 <= 900.0 - MARGIN_R, "{l}");
        }
        assert_eq!(lines.join(" "), sub, "nothing lost");
        assert!(lines[0].ends_with(';'), "broken after a clause: {lines:?}");
        // A chart gives the subtitle's lines room: its plot area starts below them.
        let mut chart = Chart::new("t", Axis::new("x"), Axis::new("y"));
        chart
            .series
            .push(Series::new("a", vec![(0.0, 0.0), (1.0, 1.0)], "#000"));
        chart.subtitle = Some(sub.to_string());
        let svg = chart.render();
        assert_eq!(svg.matches("<tspan").count(), lines.len());
        let plot_top: f64 = svg
            .split("class=\"plot-area\"")
            .nth(1)
            .and_then(|r| r.split("y=\"").nth(1))
            .and_then(|r| r.split('"').next())
            .and_then(|y| y.parse().ok())
            .unwrap();
        assert!(
            plot_top >= 44.0 + SUBTITLE_LINE * (lines.len() - 1) as f64 + 12.0,
            "{plot_top}"
        );
        // A short one stays one line.
        assert_eq!(wrap("solid: P", 800.0), ["solid: P"]);
    }

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
        assert_eq!(
            ticks_in(90.6, 450.6, 45.0),
            vec![135.0, 180.0, 225.0, 270.0, 315.0, 360.0, 405.0, 450.0]
        );
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
        assert_eq!(
            escape(r#"a<b & "c" 'd'>"#),
            "a&lt;b &amp; &quot;c&quot; &#39;d&#39;&gt;"
        );
        assert_eq!(escape("P′(φ), mm"), "P′(φ), mm");
        assert_eq!(escape("bell\u{7}"), "bell");
    }

    #[test]
    fn a_chart_has_no_nan_and_one_polyline_per_series() {
        let mut c = Chart::new("t <1>", Axis::new("φ, deg"), Axis::new("P, mm"));
        c.series.push(Series {
            name: "a&b".into(),
            points: vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0)],
            color: color(0).into(),
            dashed: false,
            mark_start: true,
        });
        c.series.push(Series {
            name: "empty".into(),
            points: vec![],
            color: color(1).into(),
            dashed: true,
            mark_start: false,
        });
        c.x_shades.push(XShade {
            from: 0.5,
            to: 0.5,
            color: color(0).into(),
            label: "G".into(),
        });
        let svg = c.render();
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
        assert_eq!(svg.matches("<polyline").count(), 2);
        assert!(svg.contains("t &lt;1&gt;") && svg.contains(">a&amp;b</text>"));
        assert_eq!(svg.matches("class=\"shade\"").count(), 1);
        assert_eq!(svg.matches("<svg").count(), svg.matches("</svg>").count());
    }

    #[test]
    fn the_ramp_runs_from_violet_to_yellow_and_cells_tile_the_grid() {
        assert_eq!(ramp(0.0), "#440154");
        assert_eq!(ramp(1.0), "#fde725");
        assert_eq!(ramp(0.5), "#21918c");
        assert_eq!(ramp(f64::NAN), "#440154");
        assert_eq!(ramp(7.0), "#fde725");
        assert_eq!(cell_edges(&[0.0, 1.0, 3.0]), vec![-0.5, 0.5, 2.0, 4.0]);
        assert_eq!(cell_edges(&[2.0]), vec![1.5, 2.5]);
    }

    #[test]
    fn a_heat_map_has_one_cell_per_value_and_a_labelled_colour_bar() {
        let mut c = Chart::new("h", Axis::new("a, mm"), Axis::new("b, deg"));
        c.heat = Some(Heat {
            xs: vec![0.0, 1.0, 2.0],
            ys: vec![10.0, 20.0],
            z: vec![vec![1.0, 2.0, f64::NAN], vec![4.0, 5.0, 6.0]],
            label: "P, mm".into(),
            tips: Vec::new(),
            missing: "no value".into(),
        });
        let svg = c.render();
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
        assert_eq!(svg.matches("<rect class=\"cell\"").count(), 5);
        assert_eq!(svg.matches("<rect class=\"cell missing\"").count(), 1);
        assert!(svg.contains(">P, mm</text>") && svg.contains(">no value</text>"));
        assert!(svg.contains(r##"fill="#440154""##) && svg.contains(r##"fill="#fde725""##));
    }

    #[test]
    fn figure_panels_get_their_own_clip_paths() {
        let mut f = Figure::new("two");
        for k in 0..2 {
            let mut c = Chart::new(format!("panel {k}"), Axis::new("x"), Axis::new("y"));
            c.series.push(Series::new("s", vec![(0.0, 0.0), (1.0, 1.0)], color(0)));
            c.height = 300.0;
            f.panels.push(c);
        }
        let svg = f.render();
        assert!(svg.contains(r#"<clipPath id="plot1">"#) && svg.contains(r#"<clipPath id="plot2">"#));
        assert!(svg.contains(r#"height="644""#), "header 44 + 2 × 300");
        assert_eq!(svg.matches("class=\"panel-title\"").count(), 2);
    }
}
