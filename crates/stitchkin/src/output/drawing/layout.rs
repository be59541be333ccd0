//! Page placement and label layout: drawing mm to px, plate outlines,
//! dimension names, and where point labels go so they cover the fewest
//! other labels, links and points.

use crate::geometry::V2;

/// Screen placement: drawing mm → px.
#[derive(Debug, Clone, Copy)]
pub(super) struct Screen {
    pub(super) scale: f64,
    pub(super) cx_mm: f64,
    pub(super) cy_mm: f64,
    pub(super) cx_px: f64,
    pub(super) cy_px: f64,
}

impl Screen {
    pub(super) fn px(&self, q: V2<f64>) -> (f64, f64) {
        (
            self.cx_px + (q.x - self.cx_mm) * self.scale,
            self.cy_px - (q.y - self.cy_mm) * self.scale,
        )
    }
}

/// Convex hull (counter-clockwise in drawing coordinates) of `pts`, as
/// indices; collinear and repeated points left out.
pub(super) fn hull(pts: &[V2<f64>]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..pts.len()).collect();
    idx.sort_by(|&a, &b| pts[a].x.total_cmp(&pts[b].x).then(pts[a].y.total_cmp(&pts[b].y)));
    let cross = |o: usize, a: usize, b: usize| (pts[a] - pts[o]).perp(&(pts[b] - pts[o]));
    let mut lower: Vec<usize> = Vec::new();
    for &i in &idx {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], i) <= 1e-12 {
            lower.pop();
        }
        lower.push(i);
    }
    let mut upper: Vec<usize> = Vec::new();
    for &i in idx.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], i) <= 1e-12 {
            upper.pop();
        }
        upper.push(i);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// Link name for a dimension: `l_AB` for one-letter points, `l_O2–B` otherwise.
pub(super) fn dim_label(symbol: &str, a: &str, b: &str) -> String {
    if a.chars().count() == 1 && b.chars().count() == 1 {
        format!("{symbol}_{a}{b}")
    } else {
        format!("{symbol}_{a}–{b}")
    }
}

/// An axis-aligned box, px.
#[derive(Debug, Clone, Copy)]
pub(super) struct Rect {
    pub(super) x0: f64,
    pub(super) y0: f64,
    pub(super) x1: f64,
    pub(super) y1: f64,
}

impl Rect {
    fn overlap(&self, o: &Rect) -> f64 {
        let w = (self.x1.min(o.x1) - self.x0.max(o.x0)).max(0.0);
        let h = (self.y1.min(o.y1) - self.y0.max(o.y0)).max(0.0);
        w * h
    }
    pub(super) fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1
    }
    /// Whether the segment crosses the box (sampled: labels are small).
    fn hit_by(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        (0..=16).any(|j| {
            let t = j as f64 / 16.0;
            self.contains(a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t)
        })
    }
}

/// A text box turned by `ang` (rad, clockwise on screen) about its
/// baseline centre (x, y): half width `hw`, from `top` to `bottom` px
/// across the baseline.
#[derive(Debug, Clone, Copy)]
pub(super) struct RotBox {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) ang: f64,
    pub(super) hw: f64,
    pub(super) top: f64,
    pub(super) bottom: f64,
}

impl RotBox {
    pub(super) fn contains(&self, px: f64, py: f64) -> bool {
        let (s, c) = self.ang.sin_cos();
        let (dx, dy) = (px - self.x, py - self.y);
        let (lx, ly) = (dx * c + dy * s, -dx * s + dy * c);
        lx.abs() <= self.hw && ly >= self.top && ly <= self.bottom
    }

    /// Points spread over the box, on screen.
    pub(super) fn samples(&self) -> Vec<(f64, f64)> {
        let (s, c) = self.ang.sin_cos();
        let mut out = Vec::with_capacity(27);
        for i in 0..9 {
            for j in 0..3 {
                let lx = -self.hw + 2.0 * self.hw * i as f64 / 8.0;
                let ly = self.top + (self.bottom - self.top) * j as f64 / 2.0;
                out.push((self.x + lx * c - ly * s, self.y + lx * s + ly * c));
            }
        }
        out
    }
}

/// A point on the page, px.
pub(super) type Px = (f64, f64);
/// A straight piece of the drawing, px.
pub(super) type Segment = (Px, Px);

/// Where a label goes: its anchor point, alignment and the box it covers.
#[derive(Debug, Clone, Copy)]
pub(super) struct LabelSpot {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) anchor: &'static str,
    pub(super) rect: Rect,
}

/// Font size of point labels, px, and an estimate of a character's width.
const LABEL_PX: f64 = 11.0;
const CHAR_W: f64 = 6.3;

/// Places a label of `text` near the point (x, y): the free spot of eight
/// around it that covers the fewest labels, links and points. `None` when
/// `droppable` and every spot covers another label.
pub(super) fn place_label(
    text: &str,
    (x, y): Px,
    placed: &[Rect],
    segments: &[Segment],
    dots: &[Px],
    droppable: bool,
    clip: &Rect,
) -> Option<LabelSpot> {
    let w = CHAR_W * text.chars().count() as f64;
    let h = LABEL_PX;
    let gap = 6.0;
    // (dx, dy, anchor): right, upper right, up, upper left, left, …
    let spots: [(f64, f64, &str); 8] = [
        (gap, 4.0, "start"),
        (gap * 0.8, -gap * 0.8, "start"),
        (0.0, -gap - 2.0, "middle"),
        (-gap * 0.8, -gap * 0.8, "end"),
        (-gap, 4.0, "end"),
        (-gap * 0.8, gap * 0.8 + h, "end"),
        (0.0, gap + h, "middle"),
        (gap * 0.8, gap * 0.8 + h, "start"),
    ];
    let mut best: Option<(f64, LabelSpot)> = None;
    for (k, (dx, dy, anchor)) in spots.iter().enumerate() {
        let (tx, ty) = (x + dx, y + dy);
        let x0 = match *anchor {
            "start" => tx,
            "end" => tx - w,
            _ => tx - w / 2.0,
        };
        let r = Rect {
            x0,
            y0: ty - h + 2.0,
            x1: x0 + w,
            y1: ty + 2.0,
        };
        let label_hit: f64 = placed.iter().map(|p| r.overlap(p)).sum();
        let seg_hits = segments.iter().filter(|(a, b)| r.hit_by(*a, *b)).count() as f64;
        let dot_hits = dots.iter().filter(|(px, py)| r.contains(*px, *py)).count() as f64;
        let outside = if r.x0 < clip.x0 || r.x1 > clip.x1 || r.y0 < clip.y0 || r.y1 > clip.y1 {
            1.0e4
        } else {
            0.0
        };
        let score = label_hit * 10.0 + seg_hits * 40.0 + dot_hits * 60.0 + outside + k as f64 * 0.5;
        if droppable && label_hit > 0.0 {
            continue;
        }
        if best.as_ref().is_none_or(|(s, _)| score < *s) {
            let anchor: &'static str = match *anchor {
                "start" => "start",
                "end" => "end",
                _ => "middle",
            };
            best = Some((
                score,
                LabelSpot {
                    x: tx,
                    y: ty,
                    anchor,
                    rect: r,
                },
            ));
        }
    }
    best.map(|(_, b)| b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_drops_inner_and_collinear_points() {
        let p = [
            V2::new(0.0, 0.0),
            V2::new(2.0, 0.0),
            V2::new(1.0, 0.0),
            V2::new(1.0, 0.5),
            V2::new(1.0, 3.0),
            V2::new(0.0, 0.0),
        ];
        let h = hull(&p);
        assert_eq!(h.len(), 3, "{h:?}");
        assert!(h.contains(&1) && h.contains(&4));
        assert!(hull(&[V2::new(0.0, 0.0), V2::new(1.0, 1.0), V2::new(2.0, 2.0)]).len() < 3);
    }

    #[test]
    fn dimension_names() {
        assert_eq!(dim_label("l", "A", "B"), "l_AB");
        assert_eq!(dim_label("r", "O2", "B"), "r_O2–B");
    }
}
