//! The layers of a mechanism drawing, one function each, called by
//! [`super::render`] in paint order: what lies underneath is written first.

use std::collections::BTreeSet;
use std::fmt::Write;

use super::layout::{Clutter, LabelSpot, Rect, RotBox, Segment, dim_label, hull, label_width, place_label};
use super::scene::{Page, Roles, Scene};
use super::structure::{Body, Dim, Guide, Kind, guide_is_fixed, guide_line};
use super::{Plane, View, pts_attr};
use crate::eval::wrap_deg;
use crate::format::{fmt_decimals, svg_num as n};
use crate::geometry::{V2, V3};
use crate::output::svg::{color, escape, nice_step};
use crate::thread::Span;

/// A slider's block, px: along the guide, across it.
const BLOCK: (f64, f64) = (18.0, 10.0);

/// The SVG being written, with what labels and dimensions keep clear of.
#[derive(Default)]
pub(super) struct Sheet {
    pub(super) svg: String,
    /// Links, rails and hatches at the first frame, px.
    segments: Vec<Segment>,
    /// The threads' lines at the first frame, px.
    threads: Vec<Segment>,
    /// Labels placed so far.
    labels: Vec<Rect>,
    /// Points and the grounds under pivots, px.
    dots: Vec<(f64, f64)>,
}

/// A scene on its page with its points' roles: what every layer draws from.
pub(super) struct Drawing<'a> {
    pub(super) sc: &'a Scene<'a>,
    pub(super) page: &'a Page,
    pub(super) roles: &'a Roles,
}

impl Drawing<'_> {
    /// Drawing coordinates (mm) to the page (px).
    fn px(&self, q: &V2<f64>) -> (f64, f64) {
        self.page.screen.px(*q)
    }

    fn scale(&self) -> f64 {
        self.page.screen.scale
    }

    /// A point's position at the first frame, px.
    fn at0(&self, p: usize) -> (f64, f64) {
        self.px(&self.sc.pts2[0][p])
    }

    /// The `translate` of point `p` at the first frame and its animation.
    fn translate(&self, p: usize) -> (String, String) {
        let v: Vec<String> = (0..self.sc.nf)
            .map(|k| {
                let (x, y) = self.px(&self.sc.pts2[k][p]);
                format!("{} {}", n(x), n(y))
            })
            .collect();
        (v[0].clone(), self.sc.timing.transform("translate", &v))
    }

    /// The `points` attribute of each frame of per-frame polylines.
    fn frames_attr(&self, frames: &[Vec<V2<f64>>]) -> Vec<String> {
        frames
            .iter()
            .map(|f| pts_attr(&f.iter().map(|q| self.px(q)).collect::<Vec<_>>()))
            .collect()
    }

    /// The `<svg>` element, its title, the white page, title and subtitle.
    pub(super) fn draw_header(&self, out: &mut Sheet) {
        let (sc, opts) = (self.sc, self.sc.opts);
        let (w, h) = (self.page.w, self.page.h);
        let title = if opts.animate {
            format!(
                "{}: mechanism over one turn from φ = {}°",
                sc.model.name(),
                fmt_decimals(opts.phi_deg, 3)
            )
        } else {
            format!(
                "{}: mechanism at φ = {}°",
                sc.model.name(),
                fmt_decimals(opts.phi_deg, 3)
            )
        };
        let projected = !(sc.model.planar && matches!(opts.view, View::Plane(Plane::Xy)));
        let view_words = &sc.view_words;
        let mut sub = match opts.view {
            View::Isometric => format!("{view_words}, to scale"),
            _ if projected => format!("projected onto {view_words}, to scale"),
            _ => format!("in {view_words}, to scale"),
        };
        if opts.animate {
            sub += &format!(
                "; {} frames per turn, {} s per turn",
                sc.nf,
                fmt_decimals(opts.duration_s, 3)
            );
        }
        if !sc.traced.is_empty() {
            sub += "; thin lines: paths over the cycle";
        }
        let s = &mut out.svg;
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="11" data-px-per-mm="{}" data-phi-deg="{}" data-frames="{nf}">"#,
            self.scale(),
            fmt_decimals(opts.phi_deg, 3),
            w = n(w),
            h = n(h),
            nf = sc.nf
        );
        let _ = writeln!(s, "<title>{}</title>", escape(&title));
        let _ = writeln!(
            s,
            r#"<rect x="0" y="0" width="{}" height="{}" fill="white"/>"#,
            n(w),
            n(h)
        );
        let _ = writeln!(
            s,
            r#"<text class="title" x="24" y="24" font-size="16" font-weight="bold">{}</text>"#,
            escape(&title)
        );
        let _ = writeln!(
            s,
            r##"<text class="subtitle" x="24" y="44" fill="#555">{}</text>"##,
            escape(&sub)
        );
    }

    /// Trajectories, under everything.
    pub(super) fn draw_trajectories(&self, out: &mut Sheet) {
        let names = self.sc.names();
        for (slot, t) in &self.sc.trajectories {
            let mut p: Vec<(f64, f64)> = t.iter().map(|q| self.px(q)).collect();
            if let Some(&f) = p.first() {
                p.push(f);
            }
            let _ = writeln!(
                out.svg,
                r##"<polyline class="trajectory" data-point="{}" fill="none" stroke="#9a9a9a" stroke-width="0.9" points="{}"><title>path of {} over the cycle</title></polyline>"##,
                escape(&names[*slot]),
                pts_attr(&p),
                escape(&names[*slot])
            );
        }
    }

    /// Crank circles: the pin's path.
    pub(super) fn draw_crank_circles(&self, out: &mut Sheet) {
        for (i, c) in self.sc.circles.iter().enumerate() {
            let frames = self.frames_attr(c);
            let _ = writeln!(
                out.svg,
                r##"<polyline class="crank-circle" data-center="{}" fill="none" stroke="#b0b0b0" stroke-width="0.8" stroke-dasharray="5 3 1 3" points="{}">{}</polyline>"##,
                escape(&self.sc.name_of(self.sc.st.circles[i].center)),
                frames[0],
                self.sc.timing.animate("points", &frames, false)
            );
        }
    }

    /// Guide lines: a centre line over the travel; rails and a ground hatch
    /// for a fixed guide.
    pub(super) fn draw_guides(&self, out: &mut Sheet) {
        let sc = self.sc;
        for (k, sl) in sc.st.sliders.iter().enumerate() {
            if matches!(sl.guide, Guide::Slot { .. }) {
                continue;
            }
            let fixed = guide_is_fixed(&sl.guide, sc.model);
            let mut center = Vec::with_capacity(sc.nf);
            let mut rails: Vec<[Vec<(f64, f64)>; 2]> = Vec::new();
            let mut hatch = String::new();
            for (f, p) in sc.pos.iter().enumerate() {
                let Some((o, u)) = guide_line(&sl.guide, p) else {
                    continue;
                };
                let t_now = (p[sl.at] - o).dot(&u);
                let (a, b) = match sc.travel[k] {
                    Some((a, b)) if fixed => (a.min(t_now), b.max(t_now)),
                    _ => (t_now, t_now),
                };
                let along = |t: f64| self.px(&sc.proj.project(&(o + u * t)));
                let margin = BLOCK.0 / self.scale();
                center.push(vec![along(a - 1.6 * margin), along(b + 1.6 * margin)]);
                if fixed && f == 0 {
                    let (d0, d1) = (along(a - 0.7 * margin), along(b + 0.7 * margin));
                    self.rails_and_hatch(d0, d1, &mut rails, &mut hatch, &mut out.segments);
                }
            }
            if center.is_empty() {
                continue;
            }
            let frames: Vec<String> = center.iter().map(|c| pts_attr(c)).collect();
            let _ = writeln!(
                out.svg,
                r##"<polyline class="guide-line" fill="none" stroke="#8a8a8a" stroke-width="0.8" stroke-dasharray="10 3 2 3" points="{}">{}</polyline>"##,
                frames[0],
                sc.timing.animate("points", &frames, false)
            );
            for [r1, r2] in &rails {
                for r in [r1, r2] {
                    out.segments.push((r[0], r[1]));
                    let _ = writeln!(
                        out.svg,
                        r##"<polyline class="guide-rail" fill="none" stroke="#444" stroke-width="1" points="{}"/>"##,
                        pts_attr(r)
                    );
                }
            }
            if !hatch.is_empty() {
                let _ = writeln!(
                    out.svg,
                    r##"<path class="ground" fill="none" stroke="#666" stroke-width="0.7" d="{}"/>"##,
                    hatch.trim_end()
                );
            }
        }
    }

    /// A fixed guide's two rails beside the block's path from `d0` to `d1`
    /// (px), and the ground hatch on the outer side of the second.
    fn rails_and_hatch(
        &self,
        d0: (f64, f64),
        d1: (f64, f64),
        rails: &mut Vec<[Vec<(f64, f64)>; 2]>,
        hatch: &mut String,
        segments: &mut Vec<Segment>,
    ) {
        let (dx, dy) = (d1.0 - d0.0, d1.1 - d0.1);
        let len = (dx * dx + dy * dy).sqrt();
        if len <= 1e-9 {
            return;
        }
        let (nx, ny) = (-dy / len, dx / len);
        let off = BLOCK.1 / 2.0 + 1.5;
        let r = |sgn: f64| {
            vec![
                (d0.0 + nx * off * sgn, d0.1 + ny * off * sgn),
                (d1.0 + nx * off * sgn, d1.1 + ny * off * sgn),
            ]
        };
        rails.push([r(1.0), r(-1.0)]);
        let hatch_side = r(-1.6);
        segments.push((hatch_side[0], hatch_side[1]));
        // Hatch on the outer side of the second rail.
        let steps = (len / 7.0).floor() as usize;
        for j in 0..=steps {
            let t = j as f64 / steps.max(1) as f64;
            let (bx, by) = (d0.0 + dx * t - nx * off, d0.1 + dy * t - ny * off);
            let _ = write!(
                hatch,
                "M{},{} l{},{} ",
                n(bx),
                n(by),
                n(-nx * 5.0 - dx / len * 4.0),
                n(-ny * 5.0 - dy / len * 4.0)
            );
        }
    }

    /// Cams: their profile, turning.
    pub(super) fn draw_cams(&self, out: &mut Sheet) {
        let Some(t) = self.sc.threads() else { return };
        for (j, &ci) in self.sc.used_cams.iter().enumerate() {
            let frames = self.frames_attr(&self.sc.cam_outlines[j]);
            let _ = writeln!(
                out.svg,
                r##"<polygon class="cam" data-cam="{}" fill="#f3efe6" stroke="#5a4a2a" stroke-width="1.3" points="{}"><title>cam {}</title>{}</polygon>"##,
                escape(&t.cams[ci].name),
                frames[0],
                escape(&t.cams[ci].name),
                self.sc.timing.animate("points", &frames, false)
            );
        }
    }

    /// Cams driving followers: the working profile (a groove's outer flank
    /// round it), the pitch curve dashed, and the roller or flat face,
    /// turning with φ.
    pub(super) fn draw_follower_cams(&self, out: &mut Sheet) {
        for c in &self.sc.follower_cams {
            let name = escape(&c.name);
            if c.profile.first().is_none_or(|f| f.is_empty()) {
                continue;
            }
            if c.outer.first().is_some_and(|f| !f.is_empty()) {
                let frames = self.frames_attr(&c.outer);
                let _ = writeln!(
                    out.svg,
                    r##"<polygon class="cam-groove" data-cam="{name}" fill="none" stroke="#5a4a2a" stroke-width="1.3" points="{}"><title>cam {name}: the groove's outer flank</title>{}</polygon>"##,
                    frames[0],
                    self.sc.timing.animate("points", &frames, false)
                );
            }
            let frames = self.frames_attr(&c.profile);
            let _ = writeln!(
                out.svg,
                r##"<polygon class="cam-profile" data-cam="{name}" fill="#f3efe6" stroke="#5a4a2a" stroke-width="1.3" points="{}"><title>cam {name}: the working profile</title>{}</polygon>"##,
                frames[0],
                self.sc.timing.animate("points", &frames, false)
            );
            if c.pitch.first().is_some_and(|f| !f.is_empty()) {
                let frames = self.frames_attr(&c.pitch);
                let _ = writeln!(
                    out.svg,
                    r##"<polygon class="cam-pitch" data-cam="{name}" fill="none" stroke="#9a8a6a" stroke-width="0.8" stroke-dasharray="6 3" points="{}"><title>cam {name}: the pitch curve (the follower's point round the cam)</title>{}</polygon>"##,
                    frames[0],
                    self.sc.timing.animate("points", &frames, false)
                );
            }
            if c.roller.first().is_some_and(|f| !f.is_empty()) {
                let frames = self.frames_attr(&c.roller);
                let _ = writeln!(
                    out.svg,
                    r##"<polygon class="cam-roller" data-cam="{name}" fill="#ffffff" stroke="#303030" stroke-width="1.2" points="{}"><title>roller of {name}</title>{}</polygon>"##,
                    frames[0],
                    self.sc.timing.animate("points", &frames, false)
                );
            }
            if c.face.first().is_some_and(|f| !f.is_empty()) {
                let frames = self.frames_attr(&c.face);
                let _ = writeln!(
                    out.svg,
                    r##"<polyline class="cam-face" data-cam="{name}" fill="none" stroke="#303030" stroke-width="2.2" stroke-linecap="round" points="{}"><title>flat face of {name}</title>{}</polyline>"##,
                    frames[0],
                    self.sc.timing.animate("points", &frames, false)
                );
            }
        }
    }

    /// Links: plates first, then bars.
    pub(super) fn draw_links(&self, out: &mut Sheet) {
        let (sc, np) = (self.sc, self.sc.np());
        let names = sc.names();
        let mut order: Vec<&Body> = sc.st.bodies.iter().collect();
        order.sort_by_key(|b| match b.kind {
            Kind::Plate => 0,
            Kind::Offset => 1,
            _ => 2,
        });
        for b in order {
            let (outline, closed) = self.link_outline(b);
            let frames: Vec<Vec<(f64, f64)>> = (0..sc.nf)
                .map(|k| outline.iter().map(|&p| self.px(&sc.pts2[k][p])).collect())
                .collect();
            for i in 0..frames[0].len().saturating_sub(1) {
                out.segments.push((frames[0][i], frames[0][i + 1]));
            }
            if closed && frames[0].len() > 2 {
                out.segments.push((frames[0][frames[0].len() - 1], frames[0][0]));
            }
            let values: Vec<String> = frames.iter().map(|f| pts_attr(f)).collect();
            let members: Vec<String> = b.pts.iter().filter(|&&p| p < np).map(|&p| names[p].clone()).collect();
            let drawn: Vec<String> = outline
                .iter()
                .map(|&p| if p < np { names[p].clone() } else { "·".into() })
                .collect();
            let (tag, style) = link_style(closed, b.kind);
            let class = if closed {
                Kind::Plate.class()
            } else if b.kind == Kind::Plate {
                Kind::Bar.class()
            } else {
                b.kind.class()
            };
            let _ = writeln!(
                out.svg,
                r#"<{tag} class="{class}" data-points="{}" data-body="{}" {style} points="{}"><title>{}</title>{}</{tag}>"#,
                escape(&drawn.join(" ")),
                escape(&members.join(" ")),
                values[0],
                escape(&members.join("–")),
                sc.timing.animate("points", &values, false)
            );
        }
    }

    /// The points a link is drawn through and whether it is closed: a
    /// plate's hull, or (collinear in this view) a bar between its two
    /// farthest points; a bar's own points.
    fn link_outline(&self, b: &Body) -> (Vec<usize>, bool) {
        if b.kind != Kind::Plate {
            return (b.pts.clone(), false);
        }
        let first: Vec<V2<f64>> = b.pts.iter().map(|&p| self.sc.pts2[0][p]).collect();
        let hl = hull(&first);
        let area: f64 = (0..hl.len())
            .map(|i| first[hl[i]].perp(&first[hl[(i + 1) % hl.len()]]))
            .sum::<f64>()
            / 2.0;
        let size = (0..first.len())
            .flat_map(|i| (0..first.len()).map(move |j| (i, j)))
            .map(|(i, j)| (first[i] - first[j]).norm())
            .fold(0.0, f64::max);
        if hl.len() >= 3 && area.abs() * self.scale() * self.scale() > 4.0 && size > 0.0 {
            return (hl.into_iter().map(|i| b.pts[i]).collect(), true);
        }
        // Collinear in this view: a bar between the two farthest points.
        let (mut bi, mut bj, mut best) = (0, 0, -1.0);
        for i in 0..first.len() {
            for j in i + 1..first.len() {
                let d = (first[i] - first[j]).norm();
                if d > best {
                    (bi, bj, best) = (i, j, d);
                }
            }
        }
        (vec![b.pts[bi], b.pts[bj]], false)
    }

    /// Thread paths, in their colours.
    pub(super) fn draw_threads(&self, out: &mut Sheet) {
        let Some(t) = self.sc.threads() else { return };
        for (j, path) in t.paths.iter().enumerate() {
            let frames: Vec<Vec<(f64, f64)>> = self.sc.polylines[j]
                .iter()
                .map(|l| l.iter().map(|q| self.px(q)).collect())
                .collect();
            out.threads.extend(frames[0].windows(2).map(|w| (w[0], w[1])));
            let values: Vec<String> = frames.iter().map(|f| pts_attr(f)).collect();
            let same_count = frames.iter().all(|f| f.len() == frames[0].len());
            let touched: Vec<&str> = (0..path.nodes.len())
                .filter(|&i| self.sc.path_frames[0][j].pieces[i].is_some())
                .map(|i| path.node_names[i].as_str())
                .collect();
            let _ = writeln!(
                out.svg,
                r#"<polyline class="thread" data-path="{}" data-nodes="{}" fill="none" stroke="{}" stroke-width="1.5" stroke-linejoin="round" stroke-opacity="0.95" points="{}"><title>thread path {}{}</title>{}</polyline>"#,
                escape(&path.name),
                escape(&touched.join(" ")),
                color(j),
                values[0],
                escape(&path.name),
                escape(&path.label.as_ref().map(|l| format!(" ({l})")).unwrap_or_default()),
                self.sc.timing.animate("points", &values, !same_count)
            );
        }
    }

    /// Sliders: a block along the guide, carried and turned with it.
    pub(super) fn draw_sliders(&self, out: &mut Sheet) {
        let sc = self.sc;
        for sl in &sc.st.sliders {
            let mut at = Vec::with_capacity(sc.nf);
            let mut angle = Vec::with_capacity(sc.nf);
            for p in sc.pos.iter() {
                let q = self.px(&sc.proj.project(&p[sl.at]));
                at.push(format!("{} {}", n(q.0), n(q.1)));
                let a = guide_line(&sl.guide, p)
                    .map(|(_, u)| sc.proj.direction(&u))
                    .filter(|d| d.norm() > 1e-6)
                    .map(|d| (-d.y).atan2(d.x).to_degrees());
                angle.push(a);
            }
            let along = angle.iter().any(Option::is_some);
            // Unwrapped so the block turns the short way between frames.
            let mut unwrapped: Vec<f64> = Vec::with_capacity(sc.nf);
            for a in &angle {
                let a = a.unwrap_or(0.0);
                let a = match unwrapped.last() {
                    Some(prev) => a + 360.0 * ((prev - a) / 360.0).round(),
                    None => a,
                };
                unwrapped.push(a);
            }
            let rot: Vec<String> = unwrapped.iter().map(|a| n(*a)).collect();
            let (bw, bh) = if along { BLOCK } else { (BLOCK.1, BLOCK.1) };
            let _ = writeln!(
                out.svg,
                r##"<g class="slider" data-point="{}" transform="translate({})">{}<g transform="rotate({})">{}<rect x="{}" y="{}" width="{}" height="{}" fill="white" stroke="#2a2a2a" stroke-width="1.4"/></g></g>"##,
                escape(&sc.name_of(sl.at)),
                at[0],
                sc.timing.transform("translate", &at),
                rot[0],
                sc.timing.transform("rotate", &rot),
                n(-bw / 2.0),
                n(-bh / 2.0),
                n(bw),
                n(bh)
            );
        }
    }

    /// Fixed pivots: a circle on a hatched ground; then fixed points that
    /// only place a guide line: a cross.
    pub(super) fn draw_pivots(&self, out: &mut Sheet) {
        let names = self.sc.names();
        for &p in &self.roles.pivots {
            let (x, y) = self.at0(p);
            let _ = writeln!(
                out.svg,
                r##"<g class="pivot" data-point="{}"><path d="M{},{} L{},{} L{},{} Z" fill="white" stroke="#2a2a2a" stroke-width="1.2"/><path class="ground" d="M{},{} L{},{} {}" fill="none" stroke="#2a2a2a" stroke-width="1"/><circle cx="{}" cy="{}" r="4" fill="white" stroke="#2a2a2a" stroke-width="1.5"/></g>"##,
                escape(&names[p]),
                n(x),
                n(y),
                n(x - 7.0),
                n(y + 11.0),
                n(x + 7.0),
                n(y + 11.0),
                n(x - 10.0),
                n(y + 11.0),
                n(x + 10.0),
                n(y + 11.0),
                (0..5)
                    .map(|j| {
                        let bx = x - 8.0 + 4.5 * j as f64;
                        format!("M{},{} l-4,4", n(bx + 2.0), n(y + 11.0))
                    })
                    .collect::<Vec<_>>()
                    .join(" "),
                n(x),
                n(y)
            );
        }
        for &p in &self.sc.st.guide_points {
            let (x, y) = self.at0(p);
            let _ = writeln!(
                out.svg,
                r##"<path class="fixed-point" data-point="{}" d="M{},{} h8 M{},{} v8" stroke="#555" stroke-width="1"/>"##,
                escape(&names[p]),
                n(x - 4.0),
                n(y),
                n(x),
                n(y - 4.0)
            );
        }
    }

    /// Moving points: a translated group per point (dots, joints, balls).
    pub(super) fn draw_points(&self, out: &mut Sheet) {
        for (list, class, shape) in [
            (&self.roles.dots, "point", r##"<circle r="2.2" fill="#2a2a2a"/>"##),
            (
                &self.roles.joints,
                "joint",
                r##"<circle r="3.6" fill="white" stroke="#2a2a2a" stroke-width="1.5"/>"##,
            ),
            (
                &self.roles.balls,
                "joint spherical",
                r##"<circle r="4.2" fill="white" stroke="#2a2a2a" stroke-width="1.5"/><circle r="1.6" fill="#2a2a2a"/>"##,
            ),
        ] {
            for &p in list.iter() {
                let (t0, anim) = self.translate(p);
                let _ = writeln!(
                    out.svg,
                    r#"<g class="{class}" data-point="{}" transform="translate({t0})">{anim}{shape}</g>"#,
                    escape(&self.sc.names()[p])
                );
            }
        }
    }

    /// Thread guides: eyelets (rings) and one-sided guides (filled while the
    /// thread bears on them, dashed while free), in their path's colour.
    pub(super) fn draw_thread_guides(&self, out: &mut Sheet) {
        let Some(t) = self.sc.threads() else { return };
        let names = self.sc.names();
        for &g in &self.roles.guide_nodes {
            let users: Vec<usize> = t
                .paths
                .iter()
                .enumerate()
                .filter(|(_, p)| p.nodes.contains(&g))
                .map(|(j, _)| j)
                .collect();
            let c = if users.len() == 1 { color(users[0]) } else { "#333333" };
            let (t0, anim) = self.translate(g);
            let _ = writeln!(
                out.svg,
                r#"<g class="guide eyelet" data-point="{}" transform="translate({t0})">{anim}<circle r="2.6" fill="white" stroke="{c}" stroke-width="1.3"/></g>"#,
                escape(&names[g])
            );
        }
        for &g in &self.roles.pin_nodes {
            self.draw_pin(out, g);
        }
    }

    /// A one-sided guide: engaged (filled) or free (dashed) at each frame,
    /// engaged when it is on any path through it.
    fn draw_pin(&self, out: &mut Sheet, g: usize) {
        let Some(t) = self.sc.threads() else { return };
        let names = self.sc.names();
        let (mut radius, mut users) = (0.0, Vec::new());
        for (j, p) in t.paths.iter().enumerate() {
            for i in 0..p.nodes.len() {
                if p.nodes[i] == g && p.pin_span[i].is_some() {
                    users.push((j, i));
                    if let Some(Span::Pin { r, .. }) = p.pin_span[i].map(|sp| &t.spans[sp]) {
                        radius = *r;
                    }
                }
            }
        }
        let engaged: Vec<bool> = (0..self.sc.nf)
            .map(|k| {
                users
                    .iter()
                    .any(|&(j, i)| self.sc.path_frames[k][j].guides[i].is_some_and(|g| g.engaged))
            })
            .collect();
        let c = if users.iter().map(|u| u.0).collect::<BTreeSet<_>>().len() == 1 {
            color(users[0].0)
        } else {
            "#333333"
        };
        let r_px = (radius * self.scale()).max(3.4);
        let state = if engaged[0] { "engaged" } else { "free" };
        let fill: Vec<String> = engaged
            .iter()
            .map(|e| if *e { c.to_string() } else { "white".to_string() })
            .collect();
        let dash: Vec<String> = engaged
            .iter()
            .map(|e| if *e { "none".to_string() } else { "2 1.5".to_string() })
            .collect();
        let (t0, anim) = self.translate(g);
        let timing = &self.sc.timing;
        let _ = writeln!(
            out.svg,
            r#"<g class="guide pin {state}" data-point="{}" transform="translate({t0})">{anim}<circle r="{}" fill="{}" fill-opacity="0.85" stroke="{c}" stroke-width="1.4" stroke-dasharray="{}">{}{}</circle><title>one-sided guide {}</title></g>"#,
            escape(&names[g]),
            n(r_px),
            fill[0],
            dash[0],
            timing.animate("fill", &fill, true),
            timing.animate("stroke-dasharray", &dash, true),
            escape(&names[g])
        );
    }

    /// Where labels and dimensions may go: the page less its margins and
    /// the legend.
    fn clip(&self) -> Rect {
        Rect {
            x0: 4.0,
            y0: 52.0,
            x1: self.page.w - self.page.legend_w - 4.0,
            y1: self.page.h - 64.0,
        }
    }

    /// Labels: moving points (coincident ones share a label), then fixed
    /// pivots and guide-line points, then fixed thread guides (dropped where
    /// no free spot is left).
    pub(super) fn draw_labels(&self, out: &mut Sheet) {
        let (sc, np) = (self.sc, self.sc.np());
        let names = sc.names();
        out.dots = (0..np).map(|p| self.at0(p)).collect();
        // The ground under each fixed pivot.
        out.dots.extend(self.roles.pivots.iter().flat_map(|&p| {
            let (x, y) = self.at0(p);
            [(x, y + 8.0), (x - 6.0, y + 12.0), (x + 6.0, y + 12.0)]
        }));
        let clip = self.clip();
        for (members, class, droppable) in self.label_groups() {
            let text = members
                .iter()
                .map(|&p| names[p].as_str())
                .collect::<Vec<_>>()
                .join(", ");
            let at = self.at0(members[0]);
            let others: Vec<(f64, f64)> = out
                .dots
                .iter()
                .copied()
                .filter(|d| (d.0 - at.0).abs() + (d.1 - at.1).abs() > 1.0)
                .collect();
            let clutter = Clutter {
                placed: &out.labels,
                segments: &out.segments,
                threads: &out.threads,
                dots: &others,
                clip: &clip,
            };
            let Some(LabelSpot {
                x: tx,
                y: ty,
                anchor,
                rect,
                leader,
            }) = place_label(label_width(&text, class == "label"), at, &clutter, droppable)
            else {
                continue;
            };
            out.labels.push(rect);
            let (fill, weight) = match class {
                "label" => ("#111", "bold"),
                "label fixed" => ("#333", "normal"),
                _ => ("#666", "normal"),
            };
            // A label standing off is joined to its point by a thin line.
            let line = match leader {
                Some((a, b)) => {
                    out.segments.push((a, b));
                    format!(
                        r##"<line class="leader" x1="{}" y1="{}" x2="{}" y2="{}" stroke="#888" stroke-width="0.7"/>"##,
                        n(a.0 - at.0),
                        n(a.1 - at.1),
                        n(b.0 - at.0),
                        n(b.1 - at.1)
                    )
                }
                None => String::new(),
            };
            let (t0, anim) = self.translate(members[0]);
            let _ = writeln!(
                out.svg,
                r#"<g class="{class}" data-names="{}" transform="translate({t0})">{anim}{line}<text x="{}" y="{}" text-anchor="{anchor}" fill="{fill}" font-weight="{weight}" stroke="white" stroke-width="3" paint-order="stroke">{}</text></g>"#,
                escape(&members.iter().map(|&p| names[p].as_str()).collect::<Vec<_>>().join(" ")),
                n(tx - at.0),
                n(ty - at.1),
                escape(&text)
            );
        }
    }

    /// The points labelled, in groups that share a label (they coincide in
    /// every frame), with the label's class and whether it may be dropped.
    fn label_groups(&self) -> Vec<(Vec<usize>, &'static str, bool)> {
        let (sc, np, model) = (self.sc, self.sc.np(), self.sc.model);
        let (pivots, guide_points) = (&self.roles.pivots, &sc.st.guide_points);
        let coincide =
            |a: usize, b: usize| (0..sc.nf).all(|k| (sc.pts2[k][a] - sc.pts2[k][b]).norm() * self.scale() < 0.8);
        let mut groups: Vec<(Vec<usize>, &'static str, bool)> = Vec::new();
        let mut add_groups = |members: Vec<usize>, class: &'static str, droppable: bool| {
            let mut left = members;
            while let Some(first) = left.first().copied() {
                let (same, rest): (Vec<usize>, Vec<usize>) = left.into_iter().partition(|&q| coincide(first, q));
                groups.push((same, class, droppable));
                left = rest;
            }
        };
        add_groups((0..np).filter(|&p| !model.is_fixed(p)).collect(), "label", false);
        add_groups(
            (0..np)
                .filter(|&p| model.is_fixed(p) && (pivots.contains(&p) || guide_points.contains(&p)))
                .collect(),
            "label fixed",
            false,
        );
        add_groups(
            (0..np)
                .filter(|&p| {
                    model.is_fixed(p)
                        && !pivots.contains(&p)
                        && !guide_points.contains(&p)
                        && (self.roles.guide_nodes.contains(&p) || self.roles.pin_nodes.contains(&p))
                })
                .collect(),
            "label guide",
            true,
        );
        groups
    }

    /// Dimensions: the length beside each link, along it, upright, where
    /// it covers the fewest labels and points (chosen at the first frame,
    /// then carried with the link).
    pub(super) fn draw_dimensions(&self, out: &mut Sheet) {
        let sc = self.sc;
        let mut done: BTreeSet<(usize, usize)> = BTreeSet::new();
        let mut dim_boxes: Vec<RotBox> = Vec::new();
        for d in &sc.st.dims {
            if !done.insert((d.a.min(d.b), d.a.max(d.b))) {
                continue;
            }
            let text = self.dimension_text(d);
            let tw = 5.6 * text.chars().count() as f64;
            let angles = self.upright_angles(d);
            let Some(((t, side, tier), bx)) = self.dimension_spot(d, &angles, tw, out, &dim_boxes) else {
                continue;
            };
            dim_boxes.push(bx);
            let at: Vec<String> = (0..sc.nf)
                .map(|k| {
                    let (x, y) = self.dimension_at(d, &angles, k, t, side, tier);
                    format!("{} {}", n(x), n(y))
                })
                .collect();
            let rot: Vec<String> = angles.iter().map(|a| n(*a)).collect();
            let _ = writeln!(
                out.svg,
                r##"<g class="dimension" data-length-mm="{}" transform="translate({})">{}<g transform="rotate({})">{}<text x="0" y="0" text-anchor="middle" font-size="10" fill="#1f4e79" stroke="white" stroke-width="3" paint-order="stroke">{}</text></g></g>"##,
                fmt_decimals(d.length, 3),
                at[0],
                sc.timing.transform("translate", &at),
                rot[0],
                sc.timing.transform("rotate", &rot),
                escape(&text)
            );
        }
    }

    /// `l_AB = 175 mm`: an arm's centre on its axis is named after the
    /// rocker's pivot.
    fn dimension_text(&self, d: &Dim) -> String {
        let sc = self.sc;
        let an = if d.a < sc.np() {
            sc.names()[d.a].clone()
        } else {
            sc.st
                .bodies
                .iter()
                .find(|b| b.pts.contains(&d.a))
                .map_or(String::new(), |b| sc.name_of(b.pts[0]))
        };
        format!(
            "{} = {} mm",
            dim_label(d.symbol, &an, &sc.name_of(d.b)),
            fmt_decimals(d.length, 3)
        )
    }

    /// Upright angle of the link at each frame, continuous over frames, deg.
    fn upright_angles(&self, d: &Dim) -> Vec<f64> {
        let mut angles: Vec<f64> = Vec::with_capacity(self.sc.nf);
        for frame in &self.sc.pts2 {
            let (a, b) = (self.px(&frame[d.a]), self.px(&frame[d.b]));
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let mut ang = if dx.hypot(dy) > 1e-9 {
                dy.atan2(dx).to_degrees()
            } else {
                0.0
            };
            if ang > 90.0 {
                ang -= 180.0;
            } else if ang <= -90.0 {
                ang += 180.0;
            }
            if let Some(p) = angles.last() {
                // Never upside down: a crank's text flips over at the vertical.
                ang += 360.0 * ((p - ang) / 360.0).round();
            }
            angles.push(ang);
        }
        angles
    }

    /// The dimension's baseline centre at frame `k`, a fraction `t` along
    /// the link, above it (side +1) or below it (−1), `tier` px farther out.
    fn dimension_at(&self, d: &Dim, angles: &[f64], k: usize, t: f64, side: f64, tier: f64) -> (f64, f64) {
        let (a, b) = (self.px(&self.sc.pts2[k][d.a]), self.px(&self.sc.pts2[k][d.b]));
        let (sn, cs) = angles[k].to_radians().sin_cos();
        let off = if side > 0.0 { 4.0 + tier } else { -11.0 - tier };
        (a.0 + (b.0 - a.0) * t + sn * off, a.1 + (b.1 - a.1) * t - cs * off)
    }

    /// The spot (t, side, tier) at the first frame whose text box, `tw` px
    /// wide, covers the fewest labels, dimensions, points and links, and
    /// that box.
    fn dimension_spot(
        &self,
        d: &Dim,
        angles: &[f64],
        tw: f64,
        out: &Sheet,
        dim_boxes: &[RotBox],
    ) -> Option<((f64, f64, f64), RotBox)> {
        let clip = self.clip();
        let own = (self.at0(d.a), self.at0(d.b));
        let mut best: Option<(f64, (f64, f64, f64), RotBox)> = None;
        for (tier, t, side) in [0.0, 7.0].iter().flat_map(|&tier| {
            [0.5, 0.35, 0.65, 0.2, 0.8]
                .into_iter()
                .flat_map(move |t| [(tier, t, 1.0), (tier, t, -1.0)])
        }) {
            let (x, y) = self.dimension_at(d, angles, 0, t, side, tier);
            let bx = RotBox {
                x,
                y,
                ang: angles[0].to_radians(),
                hw: tw / 2.0,
                top: -8.5,
                bottom: 2.5,
            };
            let samples = bx.samples();
            let covered = |hit: &dyn Fn(f64, f64) -> bool| samples.iter().filter(|(x, y)| hit(*x, *y)).count() as f64;
            // Labels are small: also test their corners and centres.
            let label_corners = out
                .labels
                .iter()
                .flat_map(|r| {
                    [
                        (r.x0, r.y0),
                        (r.x1, r.y0),
                        (r.x0, r.y1),
                        (r.x1, r.y1),
                        ((r.x0 + r.x1) / 2.0, (r.y0 + r.y1) / 2.0),
                    ]
                })
                .filter(|(x, y)| bx.contains(*x, *y))
                .count() as f64;
            let mut score = covered(&|x, y| out.labels.iter().any(|r| r.contains(x, y))) * 5.0
                + label_corners * 5.0
                + covered(&|x, y| dim_boxes.iter().any(|b: &RotBox| b.contains(x, y))) * 5.0
                + out.dots.iter().filter(|(px, py)| bx.contains(*px, *py)).count() as f64 * 40.0
                + tier * 0.5
                + (t - 0.5f64).abs() * 4.0;
            for (p, q) in &out.segments {
                if (*p, *q) == own || (*q, *p) == own {
                    continue;
                }
                score += (0..=16)
                    .filter(|j| {
                        let u = *j as f64 / 16.0;
                        bx.contains(p.0 + (q.0 - p.0) * u, p.1 + (q.1 - p.1) * u)
                    })
                    .count() as f64
                    * 3.0;
            }
            if samples.iter().any(|(x, y)| !clip.contains(*x, *y)) {
                score += 1.0e4;
            }
            if best.as_ref().is_none_or(|(s, _, _)| score < *s) {
                best = Some((score, (t, side, tier), bx));
            }
        }
        best.map(|(_, spot, bx)| (spot, bx))
    }

    /// The legend of thread paths and guides, right of the drawing.
    pub(super) fn draw_legend(&self, out: &mut Sheet) {
        let Some(t) = self.sc.threads().filter(|_| self.sc.has_legend()) else {
            return;
        };
        let s = &mut out.svg;
        let lx = self.page.w - self.page.legend_w + 8.0;
        let mut y = 74.0;
        let _ = writeln!(
            s,
            r#"<text class="legend-title" x="{}" y="{}" font-weight="bold">thread paths</text>"#,
            n(lx),
            n(y)
        );
        for (j, p) in t.paths.iter().enumerate() {
            y += 17.0;
            let _ = writeln!(
                s,
                r#"<line class="legend-sample" x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{}" stroke-width="2"/>"#,
                n(lx),
                n(lx + 24.0),
                color(j),
                y = n(y - 4.0)
            );
            let _ = writeln!(
                s,
                r#"<text class="legend" x="{}" y="{}">{}</text>"#,
                n(lx + 30.0),
                n(y),
                escape(&p.name)
            );
        }
        y += 24.0;
        let _ = writeln!(
            s,
            r##"<circle cx="{}" cy="{}" r="2.6" fill="white" stroke="#333" stroke-width="1.3"/><text class="legend" x="{}" y="{}">eyelet, guide</text>"##,
            n(lx + 12.0),
            n(y - 4.0),
            n(lx + 30.0),
            n(y)
        );
        if !self.roles.pin_nodes.is_empty() {
            y += 17.0;
            let _ = writeln!(
                s,
                r##"<circle cx="{}" cy="{}" r="3.4" fill="#333" stroke="#333" stroke-width="1.4"/><text class="legend" x="{}" y="{}">one-sided guide, bearing</text>"##,
                n(lx + 12.0),
                n(y - 4.0),
                n(lx + 30.0),
                n(y)
            );
            y += 17.0;
            let _ = writeln!(
                s,
                r##"<circle cx="{}" cy="{}" r="3.4" fill="white" stroke="#333" stroke-width="1.4" stroke-dasharray="2 1.5"/><text class="legend" x="{}" y="{}">one-sided guide, free</text>"##,
                n(lx + 12.0),
                n(y - 4.0),
                n(lx + 30.0),
                n(y)
            );
        }
        if !self.sc.used_cams.is_empty() {
            y += 17.0;
            let _ = writeln!(
                s,
                r##"<rect x="{}" y="{}" width="12" height="8" fill="#f3efe6" stroke="#5a4a2a"/><text class="legend" x="{}" y="{}">feed cam</text>"##,
                n(lx + 6.0),
                n(y - 9.0),
                n(lx + 30.0),
                n(y)
            );
        }
    }

    /// Scale bar: a round length of about 120 px, in mm.
    pub(super) fn draw_scale_bar(&self, out: &mut Sheet) {
        let scale = self.scale();
        let bar_mm = nice_step(120.0 / scale, 1);
        let bar_px = bar_mm * scale;
        let (bx, by) = (self.page.w / 2.0 - bar_px / 2.0, self.page.h - 30.0);
        let _ = writeln!(
            out.svg,
            r##"<g class="scale-bar" data-mm="{}"><rect x="{}" y="{}" width="{}" height="5" fill="white" stroke="#2a2a2a" stroke-width="1"/><rect x="{}" y="{}" width="{}" height="5" fill="#2a2a2a"/><text x="{}" y="{}" text-anchor="middle">0</text><text x="{}" y="{}" text-anchor="middle">{} mm</text></g>"##,
            fmt_decimals(bar_mm, 3),
            n(bx),
            n(by),
            n(bar_px),
            n(bx),
            n(by),
            n(bar_px / 2.0),
            n(bx),
            n(by + 18.0),
            n(bx + bar_px),
            n(by + 18.0),
            escape(&fmt_decimals(bar_mm, 3))
        );
    }

    /// The world directions of the view's three axes: the world's, or a
    /// frame's for a frame view.
    fn view_axes(&self) -> [V3<f64>; 3] {
        let world = [V3::x(), V3::y(), V3::z()];
        let View::Frame(name) = &self.sc.opts.view else {
            return world;
        };
        match self.sc.model.frame_index(name) {
            Some(i) if i > 0 => match &self.sc.mech.frame_plane(i).0 {
                Some(f) => [
                    f.dir_to_world(V3::x()),
                    f.dir_to_world(V3::y()),
                    f.dir_to_world(V3::z()),
                ],
                None => world,
            },
            _ => world,
        }
    }

    /// Axes of the view, bottom left.
    pub(super) fn draw_axes(&self, out: &mut Sheet) {
        let proj = &self.sc.proj;
        let s = &mut out.svg;
        let (ox, oy) = (44.0, self.page.h - 30.0);
        let _ = write!(s, r#"<g class="axes">"#);
        for (a, name) in self.view_axes().iter().zip(&self.sc.axis_names) {
            let d = proj.direction(a);
            if d.norm() < 0.2 {
                // Toward or away from the viewer: a dot or a cross.
                let toward = a.dot(&proj.right.cross(&proj.up)) > 0.0;
                let mark = if toward {
                    r##"<circle cx="0" cy="0" r="1.6" fill="#444"/>"##
                } else {
                    r##"<path d="M-2,-2 L2,2 M-2,2 L2,-2" stroke="#444"/>"##
                };
                let _ = write!(
                    s,
                    r##"<g transform="translate({} {})"><circle r="4" fill="none" stroke="#444"/>{mark}<text x="6" y="12" font-size="10" fill="#444">{}</text></g>"##,
                    n(ox),
                    n(oy),
                    escape(name)
                );
                continue;
            }
            let (ex, ey) = (ox + d.x * 24.0, oy - d.y * 24.0);
            let _ = write!(
                s,
                r##"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#444" stroke-width="1.2"/><circle cx="{}" cy="{}" r="1.5" fill="#444"/><text x="{}" y="{}" font-size="10" fill="#444" text-anchor="middle">{}</text>"##,
                n(ox),
                n(oy),
                n(ex),
                n(ey),
                n(ex),
                n(ey),
                n(ox + d.x * 33.0),
                n(oy - d.y * 33.0 + 4.0),
                escape(name)
            );
        }
        let _ = writeln!(s, "</g>");
    }

    /// The main-shaft angle: a dial, bottom right (0° to the right, φ
    /// counter-clockwise), its hand turning once per turn in an animation.
    pub(super) fn draw_phi_dial(&self, out: &mut Sheet) {
        let opts = self.sc.opts;
        let (dx, dy) = (self.page.w - 40.0, self.page.h - 34.0);
        let hand: Vec<String> = self
            .sc
            .phis
            .iter()
            .map(|p| format!("{} {} {}", n(-p), n(dx), n(dy)))
            .collect();
        let turn = if self.sc.timing.animated() {
            format!(
                r#"<animateTransform attributeName="transform" type="rotate" values="{};{} {} {}" dur="{}s" repeatCount="indefinite"/>"#,
                hand[0],
                n(-opts.phi_deg - 360.0),
                n(dx),
                n(dy),
                fmt_decimals(opts.duration_s, 3)
            )
        } else {
            String::new()
        };
        let phi_text = if opts.animate {
            format!("φ from {}°", fmt_decimals(wrap_deg(opts.phi_deg), 3))
        } else {
            format!("φ = {}°", fmt_decimals(opts.phi_deg, 3))
        };
        let _ = writeln!(
            out.svg,
            r##"<g class="phi-dial"><circle cx="{x}" cy="{y}" r="14" fill="white" stroke="#444"/><line x1="{x}" y1="{y}" x2="{}" y2="{y}" stroke="#bbb"/><g transform="rotate({})">{turn}<line x1="{x}" y1="{y}" x2="{}" y2="{y}" stroke="#c0392b" stroke-width="2" stroke-linecap="round"/></g><text x="{}" y="{}" text-anchor="end">{}</text></g>"##,
            n(dx + 14.0),
            hand[0],
            n(dx + 13.0),
            n(dx - 20.0),
            n(dy + 4.0),
            escape(&phi_text),
            x = n(dx),
            y = n(dy)
        );
    }
}

/// The SVG element and style of a link: a filled plate, or a bar (an
/// offset arm thinner and grey, a rod thinner than a crank or rocker).
fn link_style(closed: bool, kind: Kind) -> (&'static str, &'static str) {
    match (closed, kind) {
        (true, _) => (
            "polygon",
            r##"fill="#dfe6ef" fill-opacity="0.7" stroke="#2a2a2a" stroke-width="1.6" stroke-linejoin="round""##,
        ),
        (false, Kind::Offset) => (
            "polyline",
            r##"fill="none" stroke="#6a6a6a" stroke-width="1.3" stroke-linecap="round""##,
        ),
        (false, Kind::Rod) => (
            "polyline",
            r##"fill="none" stroke="#2a2a2a" stroke-width="2.2" stroke-linecap="round" stroke-linejoin="round""##,
        ),
        (false, _) => (
            "polyline",
            r##"fill="none" stroke="#2a2a2a" stroke-width="2.6" stroke-linecap="round" stroke-linejoin="round""##,
        ),
    }
}
