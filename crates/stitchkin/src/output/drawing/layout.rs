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
    pub(super) fn overlap(&self, o: &Rect) -> f64 {
        let w = (self.x1.min(o.x1) - self.x0.max(o.x0)).max(0.0);
        let h = (self.y1.min(o.y1) - self.y0.max(o.y0)).max(0.0);
        w * h
    }
    pub(super) fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1
    }
    /// Whether the segment crosses the box (sampled: labels are small).
    pub(super) fn hit_by(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        if a.0.max(b.0) < self.x0 || a.0.min(b.0) > self.x1 || a.1.max(b.1) < self.y0 || a.1.min(b.1) > self.y1 {
            return false;
        }
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

/// Where a label goes: its anchor point, alignment and the box it covers,
/// and the leader line from its point when it stands off.
#[derive(Debug, Clone, Copy)]
pub(super) struct LabelSpot {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) anchor: &'static str,
    pub(super) rect: Rect,
    pub(super) leader: Option<Segment>,
}

/// Font size of point labels, px.
const LABEL_PX: f64 = 11.0;

/// The width a label's text takes, px: each character's advance in a
/// common sans-serif (DejaVu Sans, what `sans-serif` is on most Linux
/// desktops; others are narrower) at [`LABEL_PX`], bold 8 % wider, and a
/// pixel each side.
pub(super) fn label_width(text: &str, bold: bool) -> f64 {
    // Advances in thousandths of the font size.
    let em: f64 = text
        .chars()
        .map(|c| match c {
            'M' => 863.0,
            'W' => 989.0,
            'm' => 974.0,
            'w' => 818.0,
            'I' | 'J' | 'i' | 'j' | 'l' => 278.0,
            'f' | 't' | 'r' => 411.0,
            ',' | '.' | ' ' | ':' | ';' => 318.0,
            '_' | '–' | '-' => 500.0,
            'E' | 'F' | 'L' | 'P' | 'T' => 640.0,
            'A'..='Z' => 780.0,
            '0'..='9' => 636.0,
            _ => 620.0,
        })
        .sum();
    em / 1000.0 * LABEL_PX * if bold { 1.08 } else { 1.0 } + 2.0
}

/// What a label may cover, with what it costs to cover it.
pub(super) struct Clutter<'a> {
    /// Labels placed before.
    pub(super) placed: &'a [Rect],
    /// Links, rails, hatches and leaders.
    pub(super) segments: &'a [Segment],
    /// The threads' lines (a label over a thread reads better than one
    /// over a link: the thread is thin).
    pub(super) threads: &'a [Segment],
    /// Points.
    pub(super) dots: &'a [Px],
    /// Where labels may go.
    pub(super) clip: &'a Rect,
}

/// Distances from the point at which a label stands off on a leader, px,
/// and the directions tried at each.
const LEADER_RADII: [f64; 4] = [20.0, 32.0, 46.0, 64.0];
const LEADER_DIRECTIONS: usize = 16;

/// Places a label `w` px wide near the point (x, y): the spot of eight around
/// it that covers the fewest labels, links, threads and points; where each
/// of those covers something, also spots farther off, joined to the point
/// by a leader line. Another label is never covered while a spot is free.
/// `None` when `droppable` and every spot covers another label.
pub(super) fn place_label(w: f64, (x, y): Px, c: &Clutter, droppable: bool) -> Option<LabelSpot> {
    let h = LABEL_PX;
    let gap = 6.0;
    let boxed = |tx: f64, ty: f64, anchor: &str| {
        let x0 = match anchor {
            "start" => tx,
            "end" => tx - w,
            _ => tx - w / 2.0,
        };
        Rect {
            x0,
            y0: ty - h + 2.0,
            x1: x0 + w,
            y1: ty + 2.0,
        }
    };
    // (dx, dy, anchor): right, upper right, up, upper left, left, …
    let near: [(f64, f64, &'static str); 8] = [
        (gap, 4.0, "start"),
        (gap * 0.8, -gap * 0.8, "start"),
        (0.0, -gap - 2.0, "middle"),
        (-gap * 0.8, -gap * 0.8, "end"),
        (-gap, 4.0, "end"),
        (-gap * 0.8, gap * 0.8 + h, "end"),
        (0.0, gap + h, "middle"),
        (gap * 0.8, gap * 0.8 + h, "start"),
    ];
    // A spot's score (lower is better), or none when it may not be used.
    let score = |tx: f64, ty: f64, anchor: &'static str, leader: Option<Segment>, extra: f64| {
        let r = boxed(tx, ty, anchor);
        let label_hit: f64 = c.placed.iter().map(|p| r.overlap(p)).sum();
        if droppable && label_hit > 0.0 {
            return None;
        }
        let seg_hits = c.segments.iter().filter(|(a, b)| r.hit_by(*a, *b)).count() as f64;
        let thread_hits = c.threads.iter().filter(|(a, b)| r.hit_by(*a, *b)).count() as f64;
        let dot_hits = c.dots.iter().filter(|(px, py)| r.contains(*px, *py)).count() as f64;
        let outside = if r.x0 < c.clip.x0 || r.x1 > c.clip.x1 || r.y0 < c.clip.y0 || r.y1 > c.clip.y1 {
            1.0e4
        } else {
            0.0
        };
        // A leader that crosses another label hides part of it.
        let leader_hits = leader.map_or(0.0, |(a, b)| c.placed.iter().filter(|p| p.hit_by(a, b)).count() as f64);
        let covers_label = if label_hit > 0.0 {
            5000.0 + label_hit * 10.0
        } else {
            0.0
        };
        let total = covers_label
            + leader_hits * 300.0
            + seg_hits * 40.0
            + thread_hits * 12.0
            + dot_hits * 60.0
            + outside
            + extra;
        Some((
            total,
            LabelSpot {
                x: tx,
                y: ty,
                anchor,
                rect: r,
                leader,
            },
        ))
    };
    let mut best: Option<(f64, LabelSpot)> = None;
    let keep = |candidate: Option<(f64, LabelSpot)>, best: &mut Option<(f64, LabelSpot)>| {
        if let Some((s, spot)) = candidate
            && best.as_ref().is_none_or(|(b, _)| s < *b)
        {
            *best = Some((s, spot));
        }
    };
    for (k, (dx, dy, anchor)) in near.iter().enumerate() {
        keep(score(x + dx, y + dy, anchor, None, k as f64 * 0.5), &mut best);
    }
    // Clear of everything next to the point: no leader needed.
    if best.as_ref().is_some_and(|(s, _)| *s < 4.0) {
        return best.map(|(_, b)| b);
    }
    for (ring, radius) in LEADER_RADII.iter().enumerate() {
        for k in 0..LEADER_DIRECTIONS {
            let a = std::f64::consts::TAU * k as f64 / LEADER_DIRECTIONS as f64;
            let (ux, uy) = (a.cos(), a.sin());
            // The box's side toward the point faces it, its middle on the ray.
            let anchor = if ux > 0.35 {
                "start"
            } else if ux < -0.35 {
                "end"
            } else {
                "middle"
            };
            let (ex, ey) = (x + radius * ux, y + radius * uy);
            let ty = if uy > 0.35 {
                ey + h - 2.0
            } else if uy < -0.35 {
                ey - 2.0
            } else {
                ey + h / 2.0 - 2.0
            };
            let start = (x + 4.0 * ux, y + 4.0 * uy);
            let extra = 25.0 + 15.0 * ring as f64 + k as f64 * 0.1;
            keep(score(ex, ty, anchor, Some((start, (ex, ey))), extra), &mut best);
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
    fn labels_of_points_close_together_stand_off_rather_than_cover_each_other() {
        let clip = Rect {
            x0: 0.0,
            y0: 0.0,
            x1: 400.0,
            y1: 400.0,
        };
        // Five points 3 px apart on a line, each crossed by a link.
        let dots: Vec<Px> = (0..5).map(|k| (200.0, 200.0 + 3.0 * k as f64)).collect();
        let segments: Vec<Segment> = vec![((150.0, 150.0), (250.0, 260.0)), ((250.0, 150.0), (150.0, 260.0))];
        let mut placed: Vec<Rect> = Vec::new();
        let mut leaders = 0;
        for (k, at) in dots.iter().enumerate() {
            let others: Vec<Px> = dots.iter().copied().filter(|d| d != at).collect();
            let c = Clutter {
                placed: &placed,
                segments: &segments,
                threads: &[],
                dots: &others,
                clip: &clip,
            };
            let spot = place_label(label_width(&format!("T{k}_1"), true), *at, &c, false).unwrap();
            assert!(
                placed.iter().all(|p| spot.rect.overlap(p) == 0.0),
                "label {k} covers another: {spot:?}"
            );
            leaders += usize::from(spot.leader.is_some());
            placed.push(spot.rect);
        }
        assert!(leaders > 0, "crowded labels stand off on leaders");
        // A droppable label with no free spot left is dropped, not laid over.
        let full: Vec<Rect> = vec![Rect {
            x0: 100.0,
            y0: 100.0,
            x1: 300.0,
            y1: 300.0,
        }];
        let c = Clutter {
            placed: &full,
            segments: &[],
            threads: &[],
            dots: &[],
            clip: &clip,
        };
        assert!(place_label(28.0, (200.0, 200.0), &c, true).is_none());
    }

    #[test]
    fn dimension_names() {
        assert_eq!(dim_label("l", "A", "B"), "l_AB");
        assert_eq!(dim_label("r", "O2", "B"), "r_O2–B");
    }
}
