//! What is drawn, derived from the resolved mechanism's solve steps: the
//! links (bars and plates), sliders on their guide lines, link lengths for
//! `--dimensions` and crank circles, and the positions of every point.

use std::collections::BTreeSet;

use crate::geometry::{Plane as FramePlane, V2, V3, perp};
use crate::mechanism::newton::{Closure, NewtonGroup, PointRef};
use crate::mechanism::rssr::Rocker;
use crate::mechanism::{Mechanism, Step, rpr};
use crate::model::Model;

/// A point added to the drawing that is not a model point: a rocker's
/// centre on its axis, a slotted lever's foot.
#[derive(Debug, Clone)]
enum Extra {
    At(V3<f64>),
    SlotFoot {
        from: usize,
        pivot: usize,
        e: f64,
        plane: FramePlane<f64>,
    },
}

/// How a link is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    Crank,
    Bar,
    Rod,
    Offset,
    Plate,
}

impl Kind {
    pub(super) fn class(self) -> &'static str {
        match self {
            Kind::Crank => "link crank",
            Kind::Bar => "link bar",
            Kind::Rod => "link rod",
            Kind::Offset => "link offset",
            Kind::Plate => "link plate",
        }
    }
}

/// A rigid body: its points (slots, then extras numbered after the slots).
#[derive(Debug, Clone)]
pub(super) struct Body {
    pub(super) pts: Vec<usize>,
    pub(super) kind: Kind,
}

/// A slider's guide line at each φ: where it passes and which way it runs.
#[derive(Debug, Clone)]
pub(super) enum Guide {
    /// Planar: through `through` shifted by `offset` to the left, toward
    /// `toward` or along `dir` in `plane`.
    Planar {
        through: usize,
        toward: Option<usize>,
        dir: V2<f64>,
        offset: f64,
        plane: FramePlane<f64>,
    },
    /// Spatial: through `through` toward `toward` or along `dir`.
    Spatial {
        through: usize,
        toward: Option<usize>,
        dir: V3<f64>,
    },
    /// A slotted lever's slot: the block rides on the pin `from`.
    Slot {
        from: usize,
        pivot: usize,
        e: f64,
        plane: FramePlane<f64>,
    },
}

#[derive(Debug, Clone)]
pub(super) struct Slider {
    pub(super) at: usize,
    pub(super) guide: Guide,
}

/// A link length written with `--dimensions`.
#[derive(Debug, Clone)]
pub(super) struct Dim {
    pub(super) a: usize,
    pub(super) b: usize,
    pub(super) length: f64,
    /// `l` for links, `r` for crank and rocker radii.
    pub(super) symbol: &'static str,
}

/// A crank pin's circle: centre slot, the crank plane's unit vectors, radius.
#[derive(Debug, Clone)]
pub(super) struct Circle {
    pub(super) center: usize,
    pub(super) u: V3<f64>,
    pub(super) v: V3<f64>,
    pub(super) r: f64,
}

/// The drawing's structure, from the solve steps.
#[derive(Debug, Clone, Default)]
pub(super) struct Structure {
    extras: Vec<Extra>,
    pub(super) bodies: Vec<Body>,
    pub(super) sliders: Vec<Slider>,
    pub(super) dims: Vec<Dim>,
    pub(super) circles: Vec<Circle>,
    /// Ball-ended rod ends (RSSR).
    pub(super) spherical: BTreeSet<usize>,
    /// Fixed points that only place a guide line (drawn as a small cross).
    pub(super) guide_points: BTreeSet<usize>,
}

impl Structure {
    pub(super) fn of(mech: &Mechanism<f64>, model: &Model) -> Structure {
        let mut st = Structure::default();
        for step in &mech.steps {
            st.add(step, mech);
        }
        st.merge_triangles();
        // A guide-line point that is also a joint or a thread guide is drawn as such.
        let in_body: BTreeSet<usize> = st.bodies.iter().flat_map(|b| b.pts.iter().copied()).collect();
        st.guide_points.retain(|p| model.is_fixed(*p) && !in_body.contains(p));
        st
    }

    fn bar(&mut self, a: usize, b: usize, kind: Kind) {
        self.bodies.push(Body { pts: vec![a, b], kind });
    }

    fn dim(&mut self, a: usize, b: usize, length: f64, symbol: &'static str) {
        self.dims.push(Dim { a, b, length, symbol });
    }

    /// A point of the drawing's own after the model's `np`, at `extra`.
    fn extra(&mut self, np: usize, extra: Extra) -> usize {
        self.extras.push(extra);
        np + self.extras.len() - 1
    }

    /// The links, sliders, dimensions and circles of one solve step.
    fn add(&mut self, step: &Step<f64>, mech: &Mechanism<f64>) {
        match step {
            Step::Crank {
                center, out, r, u, v, ..
            } => {
                self.bar(*center, *out, Kind::Crank);
                self.dim(*center, *out, *r, "r");
                self.circles.push(Circle {
                    center: *center,
                    u: *u,
                    v: *v,
                    r: *r,
                });
            }
            Step::Rrr {
                p1, p2, l1, l2, out, ..
            } => {
                self.bar(*p1, *out, Kind::Bar);
                self.bar(*p2, *out, Kind::Bar);
                self.dim(*p1, *out, *l1, "l");
                self.dim(*p2, *out, *l2, "l");
            }
            Step::Rrp {
                from,
                through,
                toward,
                dir,
                offset,
                l,
                plane,
                out,
                ..
            } => {
                self.bar(*from, *out, Kind::Bar);
                self.dim(*from, *out, *l, "l");
                let guide = Guide::Planar {
                    through: *through,
                    toward: *toward,
                    dir: *dir,
                    offset: *offset,
                    plane: *plane,
                };
                self.sliders.push(Slider { at: *out, guide });
                self.guide_points.insert(*through);
                self.guide_points.extend(*toward);
            }
            Step::Rpr {
                from,
                pivot,
                e,
                plane,
                out,
                ..
            } => self.add_lever(mech.n_points(), *from, *pivot, *e, *plane, *out),
            Step::Rssr {
                from, rocker, l, out, ..
            } => self.add_rocker(mech, *from, rocker, *l, *out),
            Step::PointOnLine {
                from,
                through,
                toward,
                dir,
                l,
                out,
                ..
            } => {
                self.bar(*from, *out, Kind::Rod);
                self.dim(*from, *out, *l, "l");
                let guide = Guide::Spatial {
                    through: *through,
                    toward: *toward,
                    dir: *dir,
                };
                self.sliders.push(Slider { at: *out, guide });
                self.guide_points.insert(*through);
                self.guide_points.extend(*toward);
            }
            Step::Rigid { base, out, .. } => self.attach(&base[..], *out),
            Step::Rigid3 { frame, out, .. } => self.attach(&frame[..], *out),
            Step::Offset { from, out, .. } => self.bar(*from, *out, Kind::Offset),
            Step::Newton(g) => self.add_newton(g),
            Step::CamFollower(c) => {
                // The cam's shaft to its marker, and the follower: an arm
                // about its pivot, or a slider on its axis.
                self.bar(c.center, c.marker, Kind::Crank);
                match (c.pivot, c.cam.motion) {
                    (Some(p), _) => self.bar(p, c.out, Kind::Bar),
                    (None, crate::mechanism::cam_follower::Motion::Translating { u, offset }) => {
                        let guide = Guide::Planar {
                            through: c.center,
                            toward: None,
                            dir: u,
                            offset,
                            plane: c.plane,
                        };
                        self.sliders.push(Slider { at: c.out, guide });
                    }
                    (None, _) => {}
                }
            }
        }
    }

    /// A slotted lever (RPR): the lever from its pivot through the pivot's
    /// foot on the slot (when the slot is offset) to the lever point, and
    /// the slider `from` in the slot.
    fn add_lever(&mut self, np: usize, from: usize, pivot: usize, e: f64, plane: FramePlane<f64>, out: usize) {
        let mut pts = vec![pivot];
        if e.abs() > 1e-9 {
            pts.push(self.extra(np, Extra::SlotFoot { from, pivot, e, plane }));
        }
        pts.push(out);
        self.bodies.push(Body { pts, kind: Kind::Bar });
        let guide = Guide::Slot { from, pivot, e, plane };
        self.sliders.push(Slider { at: from, guide });
    }

    /// A spatial rocker (RSSR): it turns about its axis, drawn from the
    /// fixed point on the axis (its pivot) to the arm's centre, then out;
    /// the rod from `from` to `out` is ball-ended.
    fn add_rocker(&mut self, mech: &Mechanism<f64>, from: usize, rocker: &Rocker<f64>, l: f64, out: usize) {
        let np = mech.n_points();
        let c = rocker.c;
        let on_axis = mech
            .fixed
            .iter()
            .filter(|(_, p)| (p - c).cross(&rocker.w).norm() < 1e-6 * (1.0 + (p - c).norm()))
            .min_by(|a, b| (a.1 - c).norm().total_cmp(&(b.1 - c).norm()));
        let mut pts = Vec::new();
        match on_axis {
            Some((slot, p)) if (p - c).norm() < 1e-9 => pts.push(*slot),
            Some((slot, _)) => pts.extend([*slot, self.extra(np, Extra::At(c))]),
            None => pts.push(self.extra(np, Extra::At(c))),
        }
        let centre = *pts.last().expect("the arm has its centre");
        pts.push(out);
        self.bodies.push(Body { pts, kind: Kind::Bar });
        self.bar(from, out, Kind::Rod);
        self.dim(centre, out, rocker.r, "r");
        self.dim(from, out, l, "l");
        self.spherical.extend([from, out]);
    }

    /// A numerical group: a bar per distance closure, a slider per point
    /// held on a line.
    fn add_newton(&mut self, g: &NewtonGroup<f64>) {
        let slot = |r: &PointRef| match r {
            PointRef::Unknown(u) => g.outs[*u],
            PointRef::Known(k) => *k,
        };
        for c in &g.closures {
            match c {
                Closure::Distance { a, b, l } => {
                    self.bar(slot(a), slot(b), Kind::Bar);
                    self.dim(slot(a), slot(b), *l, "l");
                }
                Closure::OnLine { p, h, t } => {
                    let guide = Guide::Spatial {
                        through: *h,
                        toward: Some(*t),
                        dir: V3::x(),
                    };
                    self.sliders.push(Slider { at: *p, guide });
                    self.guide_points.extend([*h, *t]);
                }
            }
        }
    }

    /// `out` rides on the body of `base`: the plate holding at least two of
    /// them, or the bar between two of them made a plate, or a new plate.
    fn attach(&mut self, base: &[usize], out: usize) {
        let holds = |b: &Body| base.iter().filter(|p| b.pts.contains(p)).count() >= 2.min(base.len());
        let found = self
            .bodies
            .iter()
            .position(|b| b.kind == Kind::Plate && holds(b))
            .or_else(|| self.bodies.iter().position(|b| b.kind != Kind::Offset && holds(b)));
        match found {
            Some(i) => {
                let b = &mut self.bodies[i];
                b.kind = Kind::Plate;
                for p in base.iter().chain([&out]) {
                    if !b.pts.contains(p) {
                        b.pts.push(*p);
                    }
                }
            }
            None => {
                let mut pts = base.to_vec();
                pts.push(out);
                self.bodies.push(Body { pts, kind: Kind::Plate });
            }
        }
    }

    /// Three bars joining three points pairwise are one rigid triangle
    /// (a ternary link of a numerical group): drawn as a plate.
    fn merge_triangles(&mut self) {
        loop {
            let bars: Vec<(usize, [usize; 2])> = self
                .bodies
                .iter()
                .enumerate()
                .filter(|(_, b)| b.kind == Kind::Bar && b.pts.len() == 2)
                .map(|(i, b)| (i, [b.pts[0].min(b.pts[1]), b.pts[0].max(b.pts[1])]))
                .collect();
            let find = |a: usize, b: usize| bars.iter().find(|(_, e)| *e == [a.min(b), a.max(b)]).map(|(i, _)| *i);
            let mut merged = None;
            'search: for (i, [a, b]) in &bars {
                for (j, [c, d]) in &bars {
                    if j <= i {
                        continue;
                    }
                    let third = if c == a || c == b {
                        *d
                    } else if d == a || d == b {
                        *c
                    } else {
                        continue;
                    };
                    let shared = if c == a || d == a { *b } else { *a };
                    if third == *a || third == *b {
                        continue;
                    }
                    if let Some(k) = find(shared, third) {
                        merged = Some(([*i, *j, k], [*a, *b, third]));
                        break 'search;
                    }
                }
            }
            let Some((idx, pts)) = merged else { break };
            let mut idx = idx.to_vec();
            idx.sort_unstable();
            for i in idx.into_iter().rev() {
                self.bodies.remove(i);
            }
            self.bodies.push(Body {
                pts: pts.to_vec(),
                kind: Kind::Plate,
            });
        }
    }

    /// Every point of one frame: the model's slots, then the extras.
    pub(super) fn positions(&self, slots: &[V3<f64>]) -> Vec<V3<f64>> {
        let mut out = slots.to_vec();
        for e in &self.extras {
            out.push(match e {
                Extra::At(p) => *p,
                Extra::SlotFoot { from, pivot, e, plane } => {
                    let c = plane.project(&slots[*pivot]);
                    match rpr::rpr(plane.project(&slots[*from]), c, *e) {
                        Ok((u, _)) => plane.lift(c + perp(u) * *e, 0.0),
                        Err(_) => slots[*pivot],
                    }
                }
            });
        }
        out
    }
}

/// A guide line at one φ: a point on it and its unit direction (world).
pub(super) fn guide_line(g: &Guide, p: &[V3<f64>]) -> Option<(V3<f64>, V3<f64>)> {
    match g {
        Guide::Planar {
            through,
            toward,
            dir,
            offset,
            plane,
        } => {
            let h = plane.project(&p[*through]);
            let u = match toward {
                Some(t) => {
                    let d = plane.project(&p[*t]) - h;
                    if d.norm() <= 0.0 {
                        return None;
                    }
                    d / d.norm()
                }
                None => *dir,
            };
            Some((plane.lift(h + perp(u) * *offset, 0.0), plane.dir(u)))
        }
        Guide::Spatial { through, toward, dir } => {
            let u = match toward {
                Some(t) => {
                    let d = p[*t] - p[*through];
                    if d.norm() <= 0.0 {
                        return None;
                    }
                    d / d.norm()
                }
                None => *dir,
            };
            Some((p[*through], u))
        }
        Guide::Slot { from, pivot, e, plane } => {
            let c = plane.project(&p[*pivot]);
            let (u, _) = rpr::rpr(plane.project(&p[*from]), c, *e).ok()?;
            Some((plane.lift(c + perp(u) * *e, 0.0), plane.dir(u)))
        }
    }
}

/// Whether a guide line stays put over the cycle (drawn with rails and a
/// ground hatch).
pub(super) fn guide_is_fixed(g: &Guide, model: &Model) -> bool {
    match g {
        Guide::Planar { through, toward, .. } | Guide::Spatial { through, toward, .. } => {
            model.is_fixed(*through) && toward.is_none_or(|t| model.is_fixed(t))
        }
        Guide::Slot { .. } => false,
    }
}
