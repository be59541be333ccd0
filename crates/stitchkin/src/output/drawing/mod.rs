//! Mechanism drawings: a kinematic diagram of the model at one main-shaft
//! angle φ, or animated over the cycle, as SVG (docs/drawing.md).
//!
//! What is drawn comes from the resolved [`Mechanism`]'s solve steps: every
//! driver and group contributes its links (bars between joints; a point
//! fixed to a link turns the link into a filled plate), its joints (revolute
//! circles, spherical ball-ends, fixed pivots with a ground hatch) and its
//! sliders (a block on its guide line). Thread paths are polylines through
//! the guides the thread touches at that φ, in the path's colour; a
//! one-sided guide is filled while the thread bears on it and dashed while
//! it is free; feed cams are drawn with their profile. Everything is
//! projected by a [`View`] and drawn to one scale, with a scale bar in mm.
//!
//! The SVG is written by hand in the style of [`super::svg`]: coordinates
//! with two decimals, the generic `sans-serif` family, escaped text, CSS
//! classes on every element (tests count them), never a NaN. An animation
//! moves the same elements with SMIL (`<animate values=…>` and
//! `<animateTransform>`), which browsers play without any script.

use std::collections::BTreeSet;
use std::fmt::Write;

use super::svg::{color, escape, nice_step};
use crate::error::{Error, ParamError};
use crate::eval::{cycle_phis_deg, wrap_deg};
use crate::format::{fmt_decimals, svg_num as n};
use crate::geometry::{Plane as FramePlane, V2, V3};
use crate::mechanism::Mechanism;
use crate::model::{Model, Params};
use crate::thread::Span;
use crate::thread::cam::CamPlacement;

pub mod cam;
mod layout;
mod structure;
mod threads;

use layout::{LabelSpot, Rect, RotBox, Screen, Segment, dim_label, hull, place_label};
use structure::{Body, Guide, Kind, Structure, guide_is_fixed, guide_line, solve};
use threads::{PathFrame, thread_frame, thread_polylines};

/// A world coordinate plane to draw on (distinct from
/// [`crate::geometry::Plane`], a frame's plane of motion).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    /// x to the right, y up (the plane of a planar model).
    Xy,
    /// x to the right, z up.
    Xz,
    /// y to the right, z up.
    Yz,
}

/// How the drawing projects the mechanism.
#[derive(Debug, Clone, PartialEq)]
pub enum View {
    /// Orthogonal projection onto a world coordinate plane.
    Plane(Plane),
    /// Orthogonal projection onto the xy-plane of a model frame (its x to
    /// the right, its y up), as `stitchkin plot trajectory --plane FRAME`.
    Frame(String),
    /// Isometric drawing with world y up, x to the lower right and z to the
    /// lower left, each at 30° from the horizontal; lengths parallel to the
    /// world axes are drawn to scale.
    Isometric,
}

impl View {
    /// The view written as on the command line: `xy`, `xz`, `yz`, `iso`
    /// (or `isometric`), or the name of a model frame (checked when drawn).
    pub fn parse(text: &str) -> Result<View, Error> {
        Ok(match text.trim() {
            "" => {
                return Err(param_error(
                    "no view given (in --view)".into(),
                    "give xy, xz, yz, iso or the name of a model frame".into(),
                ));
            }
            "xy" => View::Plane(Plane::Xy),
            "xz" => View::Plane(Plane::Xz),
            "yz" => View::Plane(Plane::Yz),
            "iso" | "isometric" => View::Isometric,
            frame => View::Frame(frame.to_string()),
        })
    }

    /// The view that shows `model` best: its plane for a planar model, the
    /// isometric drawing for a spatial one.
    pub fn default_for(model: &Model) -> View {
        if model.planar {
            View::Plane(Plane::Xy)
        } else {
            View::Isometric
        }
    }

    /// The views `model` can be drawn in, as [`View::parse`] reads them:
    /// `xy`, `xz`, `yz`, `iso`, then the model's own frames.
    pub fn choices(model: &Model) -> Vec<String> {
        let mut out: Vec<String> = ["xy", "xz", "yz", "iso"].iter().map(|s| s.to_string()).collect();
        out.extend(
            model
                .frame_names()
                .into_iter()
                .filter(|f| *f != "world")
                .map(String::from),
        );
        out
    }

    /// The view's name as [`View::parse`] reads it.
    pub fn name(&self) -> String {
        match self {
            View::Plane(Plane::Xy) => "xy".into(),
            View::Plane(Plane::Xz) => "xz".into(),
            View::Plane(Plane::Yz) => "yz".into(),
            View::Isometric => "iso".into(),
            View::Frame(f) => f.clone(),
        }
    }
}

/// What to draw and how.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawOptions {
    /// Main-shaft angle φ, degrees: the position drawn, or the first frame
    /// of an animation.
    pub phi_deg: f64,
    pub view: View,
    /// Animate one full turn of the main shaft (SMIL), starting at `phi_deg`.
    pub animate: bool,
    /// Positions per turn in an animation (at least 2).
    pub frames: usize,
    /// Seconds per turn in an animation (positive).
    pub duration_s: f64,
    /// Moving points whose path over the cycle is drawn as a thin line;
    /// empty: none.
    pub trajectories: Vec<String>,
    /// Write the length of every link of known length (`l_AB = 175 mm`,
    /// crank and rocker radii `r_OA = 15 mm`) beside it.
    pub dimensions: bool,
    /// Size of the drawing, px.
    pub width: f64,
    pub height: f64,
}

impl Default for DrawOptions {
    fn default() -> Self {
        DrawOptions {
            phi_deg: 0.0,
            view: View::Plane(Plane::Xy),
            animate: false,
            frames: 72,
            duration_s: 4.0,
            trajectories: Vec::new(),
            dimensions: false,
            width: 900.0,
            height: 640.0,
        }
    }
}

fn param_error(message: String, help: String) -> Error {
    Error::Param(ParamError {
        message,
        help: Some(help),
    })
}

/// The view's linear map from world coordinates (mm) to drawing
/// coordinates (mm, y up): `(p − origin)·right`, `(p − origin)·up`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    pub origin: V3<f64>,
    pub right: V3<f64>,
    pub up: V3<f64>,
}

impl Projection {
    /// The projection of a world plane or the isometric drawing.
    pub fn of_plane(plane: Plane) -> Projection {
        let (right, up) = match plane {
            Plane::Xy => (V3::x(), V3::y()),
            Plane::Xz => (V3::x(), V3::z()),
            Plane::Yz => (V3::y(), V3::z()),
        };
        Projection {
            origin: V3::zeros(),
            right,
            up,
        }
    }

    /// Isometric drawing, world y up: x → (cos 30°, −sin 30°), y → (0, 1),
    /// z → (−cos 30°, −sin 30°). Unit vectors along the axes keep unit length.
    pub fn isometric() -> Projection {
        let (s, c) = 30f64.to_radians().sin_cos();
        Projection {
            origin: V3::zeros(),
            right: V3::new(c, 0.0, -c),
            up: V3::new(-s, 1.0, -s),
        }
    }

    /// The xy-plane of a frame placed by `plane`.
    pub fn of_frame(plane: &FramePlane<f64>) -> Projection {
        match &plane.0 {
            None => Projection::of_plane(Plane::Xy),
            Some(f) => Projection {
                origin: f.origin,
                right: f.dir_to_world(V3::x()),
                up: f.dir_to_world(V3::y()),
            },
        }
    }

    /// Drawing coordinates of a world point, mm.
    #[inline]
    pub fn project(&self, p: &V3<f64>) -> V2<f64> {
        let d = p - self.origin;
        V2::new(d.dot(&self.right), d.dot(&self.up))
    }

    /// Drawing direction of a world direction (not normalised).
    #[inline]
    pub fn direction(&self, d: &V3<f64>) -> V2<f64> {
        V2::new(d.dot(&self.right), d.dot(&self.up))
    }
}

fn check_options(opts: &DrawOptions) -> Result<(), Error> {
    if !opts.phi_deg.is_finite() {
        return Err(param_error(
            format!("the angle φ = {} is not a finite number (in --phi)", opts.phi_deg),
            "give --phi in degrees, e.g. --phi 90".into(),
        ));
    }
    if opts.animate {
        if opts.frames < 2 {
            return Err(param_error(
                format!(
                    "an animation needs at least 2 frames per turn, got {} (in --frames)",
                    opts.frames
                ),
                "give --frames 72 (5° per frame) or 120 (3°)".into(),
            ));
        }
        if opts.frames > 3600 {
            return Err(param_error(
                format!(
                    "{} frames per turn would make a very large file (in --frames)",
                    opts.frames
                ),
                "give at most --frames 3600 (0.1° per frame)".into(),
            ));
        }
        if !(opts.duration_s.is_finite() && opts.duration_s > 0.0) {
            return Err(param_error(
                format!(
                    "the duration of one turn must be a positive number of seconds, got {} (in --duration)",
                    opts.duration_s
                ),
                "give --duration 4 (seconds per turn of the main shaft)".into(),
            ));
        }
    }
    for (what, v) in [("width", opts.width), ("height", opts.height)] {
        if !(v.is_finite() && (200.0..=20000.0).contains(&v)) {
            return Err(param_error(
                format!("the drawing {what} {v} px is out of range"),
                "give a size between 200 and 20000 px".into(),
            ));
        }
    }
    Ok(())
}

/// The projection of `view` for `mech`, with a clear error for an unknown
/// frame.
fn projection(model: &Model, mech: &Mechanism<f64>, view: &View) -> Result<(Projection, String, [String; 3]), Error> {
    let axes = |a: &str, b: &str, c: &str| [a.to_string(), b.to_string(), c.to_string()];
    Ok(match view {
        View::Plane(p) => {
            let words = match p {
                Plane::Xy => "the world xy-plane",
                Plane::Xz => "the world xz-plane",
                Plane::Yz => "the world yz-plane",
            };
            (Projection::of_plane(*p), words.to_string(), axes("x", "y", "z"))
        }
        View::Isometric => (
            Projection::isometric(),
            "isometric drawing (world y up; lengths along x, y, z true)".to_string(),
            axes("x", "y", "z"),
        ),
        View::Frame(name) => {
            let i = model.frame_index(name).ok_or_else(|| {
                let mut views = vec!["xy", "xz", "yz", "iso"];
                views.extend(model.frame_names());
                param_error(
                    format!("the model has no frame `{name}` (in --view)"),
                    format!(
                        "views are xy, xz, yz, iso or a model frame; this model offers: {}",
                        views.join(", ")
                    ),
                )
            })?;
            if i == 0 {
                (
                    Projection::of_plane(Plane::Xy),
                    "the world xy-plane".to_string(),
                    axes("x", "y", "z"),
                )
            } else {
                let words = format!("the xy-plane of frame `{name}`");
                (
                    Projection::of_frame(&mech.frame_plane(i)),
                    words,
                    axes(&format!("{name}.x"), &format!("{name}.y"), &format!("{name}.z")),
                )
            }
        }
    })
}

/// Timing of an animation; one frame is a static drawing.
struct Timing {
    frames: usize,
    dur: f64,
}

impl Timing {
    fn animated(&self) -> bool {
        self.frames > 1
    }

    /// `<animate>` of `attr` through `values` (one per frame), back to the
    /// first at the end of the turn; nothing when the values never change.
    /// `discrete` holds each value for its frame (for what cannot morph).
    fn animate(&self, attr: &str, values: &[String], discrete: bool) -> String {
        if values.len() < 2 || values.iter().all(|v| *v == values[0]) {
            return String::new();
        }
        if discrete {
            let kt: Vec<String> = (0..values.len())
                .map(|k| fmt_decimals(k as f64 / values.len() as f64, 3))
                .collect();
            format!(
                r#"<animate attributeName="{attr}" values="{}" keyTimes="{}" calcMode="discrete" dur="{}s" repeatCount="indefinite"/>"#,
                values.join(";"),
                kt.join(";"),
                fmt_decimals(self.dur, 3)
            )
        } else {
            format!(
                r#"<animate attributeName="{attr}" values="{};{}" dur="{}s" repeatCount="indefinite"/>"#,
                values.join(";"),
                values[0],
                fmt_decimals(self.dur, 3)
            )
        }
    }

    /// `<animateTransform>` of the given type through `values`.
    fn transform(&self, kind: &str, values: &[String]) -> String {
        if values.len() < 2 || values.iter().all(|v| *v == values[0]) {
            return String::new();
        }
        format!(
            r#"<animateTransform attributeName="transform" type="{kind}" values="{};{}" dur="{}s" repeatCount="indefinite"/>"#,
            values.join(";"),
            values[0],
            fmt_decimals(self.dur, 3)
        )
    }
}

fn pts_attr(pts: &[(f64, f64)]) -> String {
    pts.iter()
        .map(|(x, y)| format!("{},{}", n(*x), n(*y)))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The drawing of `model` with `params` as an SVG document: at `opts.phi_deg`,
/// or animated over one turn (see [`DrawOptions`]).
pub fn render(model: &Model, params: &Params, opts: &DrawOptions) -> Result<String, Error> {
    check_options(opts)?;
    let mech = model.mechanism::<f64>(params)?;
    let (proj, view_words, axis_names) = projection(model, &mech, &opts.view)?;
    let traced = opts
        .trajectories
        .iter()
        .map(|p| crate::study::stroke::point_slot(model, p, "--trajectories", true))
        .collect::<Result<Vec<usize>, Error>>()?;
    let nf = if opts.animate { opts.frames } else { 1 };
    let phis: Vec<f64> = (0..nf).map(|k| opts.phi_deg + 360.0 * k as f64 / nf as f64).collect();
    let slots = solve(model, &mech, &phis)?;
    // The cycle: for trajectories (required) and the travel of sliders on
    // their guides (when it assembles all round).
    let cycle = match solve(model, &mech, &cycle_phis_deg(model.phi_start_deg(), 1.0)) {
        Ok(c) => Some(c),
        Err(e) if !traced.is_empty() => return Err(e),
        Err(_) => None,
    };
    let st = Structure::of(&mech, model);
    let pos: Vec<Vec<V3<f64>>> = slots.iter().map(|s| st.positions(s)).collect();
    let threads = mech.threads.as_ref();
    let path_frames: Vec<Vec<PathFrame>> = match threads {
        Some(t) => slots
            .iter()
            .zip(&phis)
            .map(|(s, &phi)| thread_frame(t, s, phi))
            .collect::<Result<_, _>>()?,
        None => Vec::new(),
    };
    let np = mech.n_points();
    let names = &model.point_names;
    let name_of = |i: usize| if i < np { names[i].clone() } else { String::new() };
    let timing = Timing {
        frames: nf,
        dur: opts.duration_s,
    };

    // ---- what is drawn, in drawing coordinates (mm) per frame ----
    let v2 = |p: &V3<f64>| proj.project(p);
    let pts2: Vec<Vec<V2<f64>>> = pos.iter().map(|f| f.iter().map(v2).collect()).collect();
    // Threads: per path, per frame, the polyline.
    let polylines: Vec<Vec<Vec<V2<f64>>>> = match threads {
        Some(t) => (0..t.paths.len())
            .map(|j| {
                let path = &t.paths[j];
                let frames: Vec<PathFrame> = path_frames.iter().map(|f| f[j].clone()).collect();
                let guide_pts: Vec<V3<f64>> = slots
                    .iter()
                    .flat_map(|s| path.nodes.iter().map(|&i| s[i]).collect::<Vec<_>>())
                    .collect();
                thread_polylines(&frames, &guide_pts, opts.animate)
                    .into_iter()
                    .map(|l| l.iter().map(v2).collect())
                    .collect()
            })
            .collect(),
        None => Vec::new(),
    };
    // Cam profiles per frame.
    let used_cams: Vec<usize> = match threads {
        Some(t) => (0..t.cams.len())
            .filter(|&c| t.spans.iter().any(|s| matches!(s, Span::Cam { cam, .. } if *cam == c)))
            .collect(),
        None => Vec::new(),
    };
    let cam_outlines: Vec<Vec<Vec<V2<f64>>>> = match threads {
        Some(t) => used_cams
            .iter()
            .map(|&ci| {
                let c = &t.cams[ci];
                slots
                    .iter()
                    .map(|s| match CamPlacement::new(s[c.center], s[c.marker], c.axis) {
                        Some(at) => (0..120)
                            .map(|k| {
                                let th = k as f64 * std::f64::consts::TAU / 120.0;
                                v2(&(at.center + (at.u * th.cos() + at.v * th.sin()) * c.profile.rho(th)))
                            })
                            .collect(),
                        None => Vec::new(),
                    })
                    .collect()
            })
            .collect(),
        None => Vec::new(),
    };
    let trajectories: Vec<(usize, Vec<V2<f64>>)> = match &cycle {
        Some(c) => traced
            .iter()
            .map(|&s| (s, c.iter().map(|f| v2(&f[s])).collect()))
            .collect(),
        None => Vec::new(),
    };
    // Crank circles (static: their centres are fixed in every preset; a
    // moving centre is followed per frame).
    let circles: Vec<Vec<Vec<V2<f64>>>> = st
        .circles
        .iter()
        .map(|c| {
            pos.iter()
                .map(|f| {
                    (0..=72)
                        .map(|k| {
                            let th = k as f64 * std::f64::consts::TAU / 72.0;
                            v2(&(f[c.center] + (c.u * th.cos() + c.v * th.sin()) * c.r))
                        })
                        .collect()
                })
                .collect()
        })
        .collect();
    // Slider travel along each guide (over the cycle when known).
    let travel: Vec<Option<(f64, f64)>> = st
        .sliders
        .iter()
        .map(|s| {
            let samples: Vec<&Vec<V3<f64>>> = match &cycle {
                Some(c) => c.iter().collect(),
                None => slots.iter().collect(),
            };
            let mut range: Option<(f64, f64)> = None;
            for f in samples {
                let full = st.positions(f);
                if let Some((o, u)) = guide_line(&s.guide, &full) {
                    let t = (full[s.at] - o).dot(&u);
                    range = Some(range.map_or((t, t), |(a, b)| (a.min(t), b.max(t))));
                }
            }
            range
        })
        .collect();

    // ---- fit to the page ----
    let (w, h) = (opts.width, opts.height);
    let has_legend = threads.is_some_and(|t| !t.paths.is_empty());
    let legend_w = if has_legend { 190.0 } else { 0.0 };
    let (ax0, ax1, ay0, ay1) = (24.0, w - legend_w - 24.0, 64.0, h - 74.0);
    let mut lo = V2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = V2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut grow = |q: &V2<f64>| {
        if q.x.is_finite() && q.y.is_finite() {
            lo = lo.inf(q);
            hi = hi.sup(q);
        }
    };
    pts2.iter().flatten().for_each(&mut grow);
    polylines.iter().flatten().flatten().for_each(&mut grow);
    cam_outlines.iter().flatten().flatten().for_each(&mut grow);
    trajectories.iter().flat_map(|(_, t)| t).for_each(&mut grow);
    circles.iter().flatten().flatten().for_each(&mut grow);
    if !(lo.x.is_finite() && hi.x.is_finite()) {
        lo = V2::zeros();
        hi = V2::zeros();
    }
    let span = (hi - lo).map(|d| d.max(1e-6));
    // Room around the mechanism for labels.
    let pad = 34.0;
    let scale = ((ax1 - ax0 - 2.0 * pad) / span.x).min((ay1 - ay0 - 2.0 * pad) / span.y);
    let scale = if scale.is_finite() && scale > 0.0 {
        scale.min(1.0e4)
    } else {
        1.0
    };
    let screen = Screen {
        scale,
        cx_mm: (lo.x + hi.x) / 2.0,
        cy_mm: (lo.y + hi.y) / 2.0,
        cx_px: (ax0 + ax1) / 2.0,
        cy_px: (ay0 + ay1) / 2.0,
    };
    let px = |q: &V2<f64>| screen.px(*q);

    // ---- roles of points ----
    let mut membership = vec![0usize; pos[0].len()];
    for b in &st.bodies {
        for &p in &b.pts {
            membership[p] += 1;
        }
    }
    for s in &st.sliders {
        membership[s.at] += 1;
    }
    let guide_nodes: BTreeSet<usize> = threads.map_or_else(BTreeSet::new, |t| {
        t.paths
            .iter()
            .flat_map(|p| {
                (0..p.nodes.len())
                    .filter(|&i| p.pin_span[i].is_none())
                    .map(|i| p.nodes[i])
            })
            .collect()
    });
    let pin_nodes: BTreeSet<usize> = threads.map_or_else(BTreeSet::new, |t| {
        t.spans
            .iter()
            .filter_map(|s| if let Span::Pin { c, .. } = s { Some(*c) } else { None })
            .collect()
    });
    let pivots: Vec<usize> = (0..np).filter(|&i| model.is_fixed(i) && membership[i] > 0).collect();
    let joints: Vec<usize> = (0..np)
        .filter(|&i| !model.is_fixed(i) && membership[i] >= 2 && !st.spherical.contains(&i))
        .collect();
    let balls: Vec<usize> = st.spherical.iter().copied().filter(|i| !model.is_fixed(*i)).collect();
    let dots: Vec<usize> = (0..np)
        .filter(|&i| !model.is_fixed(i) && membership[i] == 1 && !st.spherical.contains(&i))
        .collect();

    // ---- SVG ----
    let mut s = String::new();
    let title = if opts.animate {
        format!(
            "{}: mechanism over one turn from φ = {}°",
            model.name(),
            fmt_decimals(opts.phi_deg, 3)
        )
    } else {
        format!("{}: mechanism at φ = {}°", model.name(), fmt_decimals(opts.phi_deg, 3))
    };
    let projected = !(model.planar && matches!(opts.view, View::Plane(Plane::Xy)));
    let mut sub = match opts.view {
        View::Isometric => format!("{view_words}, to scale"),
        _ if projected => format!("projected onto {view_words}, to scale"),
        _ => format!("in {view_words}, to scale"),
    };
    if opts.animate {
        sub += &format!(
            "; {} frames per turn, {} s per turn",
            nf,
            fmt_decimals(opts.duration_s, 3)
        );
    }
    if !traced.is_empty() {
        sub += "; thin lines: paths over the cycle";
    }
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="11" data-px-per-mm="{}" data-phi-deg="{}" data-frames="{nf}">"#,
        scale,
        fmt_decimals(opts.phi_deg, 3),
        w = n(w),
        h = n(h)
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

    // Trajectories, under everything.
    for (slot, t) in &trajectories {
        let mut p: Vec<(f64, f64)> = t.iter().map(px).collect();
        if let Some(&f) = p.first() {
            p.push(f);
        }
        let _ = writeln!(
            s,
            r##"<polyline class="trajectory" data-point="{}" fill="none" stroke="#9a9a9a" stroke-width="0.9" points="{}"><title>path of {} over the cycle</title></polyline>"##,
            escape(&names[*slot]),
            pts_attr(&p),
            escape(&names[*slot])
        );
    }
    // Crank circles: the pin's path.
    for (i, c) in circles.iter().enumerate() {
        let frames: Vec<String> = c
            .iter()
            .map(|f| pts_attr(&f.iter().map(px).collect::<Vec<_>>()))
            .collect();
        let _ = writeln!(
            s,
            r##"<polyline class="crank-circle" data-center="{}" fill="none" stroke="#b0b0b0" stroke-width="0.8" stroke-dasharray="5 3 1 3" points="{}">{}</polyline>"##,
            escape(&name_of(st.circles[i].center)),
            frames[0],
            timing.animate("points", &frames, false)
        );
    }
    // Guide lines: a centre line over the travel; rails and a ground hatch
    // for a fixed guide.
    let block = (18.0, 10.0);
    // What labels and dimensions keep clear of: links, rails, hatches.
    let mut segments: Vec<Segment> = Vec::new();
    for (k, sl) in st.sliders.iter().enumerate() {
        if matches!(sl.guide, Guide::Slot { .. }) {
            continue;
        }
        let fixed = guide_is_fixed(&sl.guide, model);
        let margin = block.0 / scale;
        let mut center = Vec::with_capacity(nf);
        let mut rails: Vec<[Vec<(f64, f64)>; 2]> = Vec::new();
        let mut hatch = String::new();
        for (f, p) in pos.iter().enumerate() {
            let Some((o, u)) = guide_line(&sl.guide, p) else {
                continue;
            };
            let t_now = (p[sl.at] - o).dot(&u);
            let (a, b) = match travel[k] {
                Some((a, b)) if fixed => (a.min(t_now), b.max(t_now)),
                _ => (t_now, t_now),
            };
            let (p0, p1) = (
                px(&v2(&(o + u * (a - 1.6 * margin)))),
                px(&v2(&(o + u * (b + 1.6 * margin)))),
            );
            center.push(vec![p0, p1]);
            if fixed && f == 0 {
                let (d0, d1) = (
                    px(&v2(&(o + u * (a - 0.7 * margin)))),
                    px(&v2(&(o + u * (b + 0.7 * margin)))),
                );
                let (dx, dy) = (d1.0 - d0.0, d1.1 - d0.1);
                let len = (dx * dx + dy * dy).sqrt();
                if len > 1e-9 {
                    let (nx, ny) = (-dy / len, dx / len);
                    let off = block.1 / 2.0 + 1.5;
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
            }
        }
        if center.is_empty() {
            continue;
        }
        let frames: Vec<String> = center.iter().map(|c| pts_attr(c)).collect();
        let _ = writeln!(
            s,
            r##"<polyline class="guide-line" fill="none" stroke="#8a8a8a" stroke-width="0.8" stroke-dasharray="10 3 2 3" points="{}">{}</polyline>"##,
            frames[0],
            timing.animate("points", &frames, false)
        );
        for [r1, r2] in &rails {
            for r in [r1, r2] {
                segments.push((r[0], r[1]));
                let _ = writeln!(
                    s,
                    r##"<polyline class="guide-rail" fill="none" stroke="#444" stroke-width="1" points="{}"/>"##,
                    pts_attr(r)
                );
            }
        }
        if !hatch.is_empty() {
            let _ = writeln!(
                s,
                r##"<path class="ground" fill="none" stroke="#666" stroke-width="0.7" d="{}"/>"##,
                hatch.trim_end()
            );
        }
    }
    // Cams.
    if let Some(t) = threads {
        for (j, &ci) in used_cams.iter().enumerate() {
            let frames: Vec<String> = cam_outlines[j]
                .iter()
                .map(|f| pts_attr(&f.iter().map(px).collect::<Vec<_>>()))
                .collect();
            let _ = writeln!(
                s,
                r##"<polygon class="cam" data-cam="{}" fill="#f3efe6" stroke="#5a4a2a" stroke-width="1.3" points="{}"><title>cam {}</title>{}</polygon>"##,
                escape(&t.cams[ci].name),
                frames[0],
                escape(&t.cams[ci].name),
                timing.animate("points", &frames, false)
            );
        }
    }
    // Links: plates first, then bars.
    let mut order: Vec<&Body> = st.bodies.iter().collect();
    order.sort_by_key(|b| match b.kind {
        Kind::Plate => 0,
        Kind::Offset => 1,
        _ => 2,
    });
    for b in order {
        let first: Vec<V2<f64>> = b.pts.iter().map(|&p| pts2[0][p]).collect();
        let (outline, closed): (Vec<usize>, bool) = if b.kind == Kind::Plate {
            let hl = hull(&first);
            let area: f64 = (0..hl.len())
                .map(|i| first[hl[i]].perp(&first[hl[(i + 1) % hl.len()]]))
                .sum::<f64>()
                / 2.0;
            let size = (0..first.len())
                .flat_map(|i| (0..first.len()).map(move |j| (i, j)))
                .map(|(i, j)| (first[i] - first[j]).norm())
                .fold(0.0, f64::max);
            if hl.len() >= 3 && area.abs() * scale * scale > 4.0 && size > 0.0 {
                (hl.into_iter().map(|i| b.pts[i]).collect(), true)
            } else {
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
        } else {
            (b.pts.clone(), false)
        };
        let frames: Vec<Vec<(f64, f64)>> = (0..nf)
            .map(|k| outline.iter().map(|&p| px(&pts2[k][p])).collect())
            .collect();
        for i in 0..frames[0].len().saturating_sub(1) {
            segments.push((frames[0][i], frames[0][i + 1]));
        }
        if closed && frames[0].len() > 2 {
            segments.push((frames[0][frames[0].len() - 1], frames[0][0]));
        }
        let values: Vec<String> = frames.iter().map(|f| pts_attr(f)).collect();
        let members: Vec<String> = b.pts.iter().filter(|&&p| p < np).map(|&p| names[p].clone()).collect();
        let drawn: Vec<String> = outline
            .iter()
            .map(|&p| if p < np { names[p].clone() } else { "·".into() })
            .collect();
        let (tag, style) = match (closed, b.kind) {
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
        };
        let class = if closed {
            Kind::Plate.class()
        } else if b.kind == Kind::Plate {
            Kind::Bar.class()
        } else {
            b.kind.class()
        };
        let _ = writeln!(
            s,
            r#"<{tag} class="{class}" data-points="{}" data-body="{}" {style} points="{}"><title>{}</title>{}</{tag}>"#,
            escape(&drawn.join(" ")),
            escape(&members.join(" ")),
            values[0],
            escape(&members.join("–")),
            timing.animate("points", &values, false)
        );
    }
    // Thread paths.
    if let Some(t) = threads {
        for (j, path) in t.paths.iter().enumerate() {
            let frames: Vec<Vec<(f64, f64)>> = polylines[j].iter().map(|l| l.iter().map(px).collect()).collect();
            let values: Vec<String> = frames.iter().map(|f| pts_attr(f)).collect();
            let same_count = frames.iter().all(|f| f.len() == frames[0].len());
            let touched: Vec<&str> = (0..path.nodes.len())
                .filter(|&i| path_frames[0][j].pieces[i].is_some())
                .map(|i| path.node_names[i].as_str())
                .collect();
            let _ = writeln!(
                s,
                r#"<polyline class="thread" data-path="{}" data-nodes="{}" fill="none" stroke="{}" stroke-width="1.5" stroke-linejoin="round" stroke-opacity="0.95" points="{}"><title>thread path {}{}</title>{}</polyline>"#,
                escape(&path.name),
                escape(&touched.join(" ")),
                color(j),
                values[0],
                escape(&path.name),
                escape(&path.label.as_ref().map(|l| format!(" ({l})")).unwrap_or_default()),
                timing.animate("points", &values, !same_count)
            );
        }
    }
    // Sliders: a block along the guide, carried and turned with it.
    for sl in &st.sliders {
        let mut at = Vec::with_capacity(nf);
        let mut angle = Vec::with_capacity(nf);
        for p in pos.iter() {
            let q = px(&v2(&p[sl.at]));
            at.push(format!("{} {}", n(q.0), n(q.1)));
            let a = guide_line(&sl.guide, p)
                .map(|(_, u)| proj.direction(&u))
                .filter(|d| d.norm() > 1e-6)
                .map(|d| (-d.y).atan2(d.x).to_degrees());
            angle.push(a);
        }
        let along = angle.iter().any(Option::is_some);
        // Unwrapped so the block turns the short way between frames.
        let mut unwrapped: Vec<f64> = Vec::with_capacity(nf);
        for a in &angle {
            let a = a.unwrap_or(0.0);
            let a = match unwrapped.last() {
                Some(prev) => a + 360.0 * ((prev - a) / 360.0).round(),
                None => a,
            };
            unwrapped.push(a);
        }
        let rot: Vec<String> = unwrapped.iter().map(|a| n(*a)).collect();
        let (bw, bh) = if along { block } else { (block.1, block.1) };
        let _ = writeln!(
            s,
            r##"<g class="slider" data-point="{}" transform="translate({})">{}<g transform="rotate({})">{}<rect x="{}" y="{}" width="{}" height="{}" fill="white" stroke="#2a2a2a" stroke-width="1.4"/></g></g>"##,
            escape(&name_of(sl.at)),
            at[0],
            timing.transform("translate", &at),
            rot[0],
            timing.transform("rotate", &rot),
            n(-bw / 2.0),
            n(-bh / 2.0),
            n(bw),
            n(bh)
        );
    }
    // Fixed pivots: a circle on a hatched ground.
    for &p in &pivots {
        let (x, y) = px(&pts2[0][p]);
        let _ = writeln!(
            s,
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
    // Fixed points that only place a guide line.
    for &p in &st.guide_points {
        let (x, y) = px(&pts2[0][p]);
        let _ = writeln!(
            s,
            r##"<path class="fixed-point" data-point="{}" d="M{},{} h8 M{},{} v8" stroke="#555" stroke-width="1"/>"##,
            escape(&names[p]),
            n(x - 4.0),
            n(y),
            n(x),
            n(y - 4.0)
        );
    }
    // Moving points: a translated group per point.
    let translate = |p: usize| -> (String, String) {
        let v: Vec<String> = (0..nf)
            .map(|k| {
                let (x, y) = px(&pts2[k][p]);
                format!("{} {}", n(x), n(y))
            })
            .collect();
        (v[0].clone(), timing.transform("translate", &v))
    };
    for (list, class, shape) in [
        (&dots, "point", r##"<circle r="2.2" fill="#2a2a2a"/>"##),
        (
            &joints,
            "joint",
            r##"<circle r="3.6" fill="white" stroke="#2a2a2a" stroke-width="1.5"/>"##,
        ),
        (
            &balls,
            "joint spherical",
            r##"<circle r="4.2" fill="white" stroke="#2a2a2a" stroke-width="1.5"/><circle r="1.6" fill="#2a2a2a"/>"##,
        ),
    ] {
        for &p in list.iter() {
            let (t0, anim) = translate(p);
            let _ = writeln!(
                s,
                r#"<g class="{class}" data-point="{}" transform="translate({t0})">{anim}{shape}</g>"#,
                escape(&names[p])
            );
        }
    }
    // Thread guides: eyelets (rings) and one-sided guides (filled while the
    // thread bears on them, dashed while free), in their path's colour.
    if let Some(t) = threads {
        let path_of_node = |slot: usize| -> Vec<usize> {
            t.paths
                .iter()
                .enumerate()
                .filter(|(_, p)| p.nodes.contains(&slot))
                .map(|(j, _)| j)
                .collect()
        };
        for &g in &guide_nodes {
            let users = path_of_node(g);
            let c = if users.len() == 1 { color(users[0]) } else { "#333333" };
            let (t0, anim) = translate(g);
            let _ = writeln!(
                s,
                r#"<g class="guide eyelet" data-point="{}" transform="translate({t0})">{anim}<circle r="2.6" fill="white" stroke="{c}" stroke-width="1.3"/></g>"#,
                escape(&names[g])
            );
        }
        for &g in &pin_nodes {
            // The guide's state at each frame: engaged on any path through it.
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
            let engaged: Vec<bool> = (0..nf)
                .map(|k| {
                    users
                        .iter()
                        .any(|&(j, i)| path_frames[k][j].guides[i].is_some_and(|g| g.engaged))
                })
                .collect();
            let c = if users.iter().map(|u| u.0).collect::<BTreeSet<_>>().len() == 1 {
                color(users[0].0)
            } else {
                "#333333"
            };
            let r_px = (radius * scale).max(3.4);
            let state = if engaged[0] { "engaged" } else { "free" };
            let fill: Vec<String> = engaged
                .iter()
                .map(|e| if *e { c.to_string() } else { "white".to_string() })
                .collect();
            let dash: Vec<String> = engaged
                .iter()
                .map(|e| if *e { "none".to_string() } else { "2 1.5".to_string() })
                .collect();
            let (t0, anim) = translate(g);
            let _ = writeln!(
                s,
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
    }
    // Labels: moving points (coincident ones share a label), then fixed
    // pivots and guide-line points, then fixed thread guides (dropped where
    // no free spot is left).
    let clip = Rect {
        x0: 4.0,
        y0: 52.0,
        x1: w - legend_w - 4.0,
        y1: h - 64.0,
    };
    let mut all_dots: Vec<(f64, f64)> = (0..np).map(|p| px(&pts2[0][p])).collect();
    // The ground under each fixed pivot.
    all_dots.extend(pivots.iter().flat_map(|&p| {
        let (x, y) = px(&pts2[0][p]);
        [(x, y + 8.0), (x - 6.0, y + 12.0), (x + 6.0, y + 12.0)]
    }));
    let mut placed: Vec<Rect> = Vec::new();
    let coincide = |a: usize, b: usize| (0..nf).all(|k| (pts2[k][a] - pts2[k][b]).norm() * scale < 0.8);
    let mut groups: Vec<(Vec<usize>, &'static str, bool)> = Vec::new();
    let add_groups = |members: Vec<usize>,
                      class: &'static str,
                      droppable: bool,
                      groups: &mut Vec<(Vec<usize>, &'static str, bool)>| {
        let mut left = members;
        while let Some(first) = left.first().copied() {
            let (same, rest): (Vec<usize>, Vec<usize>) = left.into_iter().partition(|&q| coincide(first, q));
            groups.push((same, class, droppable));
            left = rest;
        }
    };
    add_groups(
        (0..np).filter(|&p| !model.is_fixed(p)).collect(),
        "label",
        false,
        &mut groups,
    );
    add_groups(
        (0..np)
            .filter(|&p| model.is_fixed(p) && (pivots.contains(&p) || st.guide_points.contains(&p)))
            .collect(),
        "label fixed",
        false,
        &mut groups,
    );
    add_groups(
        (0..np)
            .filter(|&p| {
                model.is_fixed(p)
                    && !pivots.contains(&p)
                    && !st.guide_points.contains(&p)
                    && (guide_nodes.contains(&p) || pin_nodes.contains(&p))
            })
            .collect(),
        "label guide",
        true,
        &mut groups,
    );
    for (members, class, droppable) in groups {
        let text = members
            .iter()
            .map(|&p| names[p].as_str())
            .collect::<Vec<_>>()
            .join(", ");
        let at = px(&pts2[0][members[0]]);
        let others: Vec<(f64, f64)> = all_dots
            .iter()
            .copied()
            .filter(|d| (d.0 - at.0).abs() + (d.1 - at.1).abs() > 1.0)
            .collect();
        let Some(LabelSpot {
            x: tx,
            y: ty,
            anchor,
            rect,
        }) = place_label(&text, at, &placed, &segments, &others, droppable, &clip)
        else {
            continue;
        };
        placed.push(rect);
        let (fill, weight) = match class {
            "label" => ("#111", "bold"),
            "label fixed" => ("#333", "normal"),
            _ => ("#666", "normal"),
        };
        let (t0, anim) = translate(members[0]);
        let _ = writeln!(
            s,
            r#"<g class="{class}" data-names="{}" transform="translate({t0})">{anim}<text x="{}" y="{}" text-anchor="{anchor}" fill="{fill}" font-weight="{weight}" stroke="white" stroke-width="3" paint-order="stroke">{}</text></g>"#,
            escape(&members.iter().map(|&p| names[p].as_str()).collect::<Vec<_>>().join(" ")),
            n(tx - at.0),
            n(ty - at.1),
            escape(&text)
        );
    }

    // Dimensions: the length beside each link, along it, upright, where
    // it covers the fewest labels and points (chosen at the first frame,
    // then carried with the link).
    if opts.dimensions {
        let mut done: BTreeSet<(usize, usize)> = BTreeSet::new();
        let mut dim_boxes: Vec<RotBox> = Vec::new();
        for d in &st.dims {
            if !done.insert((d.a.min(d.b), d.a.max(d.b))) {
                continue;
            }
            // An arm's centre on its axis is named after the rocker's pivot.
            let an = if d.a < np {
                names[d.a].clone()
            } else {
                st.bodies
                    .iter()
                    .find(|b| b.pts.contains(&d.a))
                    .map_or(String::new(), |b| name_of(b.pts[0]))
            };
            let text = format!(
                "{} = {} mm",
                dim_label(d.symbol, &an, &name_of(d.b)),
                fmt_decimals(d.length, 3)
            );
            let tw = 5.6 * text.chars().count() as f64;
            // Upright angle of the link at frame k, continuous over frames.
            let mut angles: Vec<f64> = Vec::with_capacity(nf);
            for frame in &pts2 {
                let (a, b) = (px(&frame[d.a]), px(&frame[d.b]));
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
            let spot = |k: usize, t: f64, side: f64, tier: f64| {
                let (a, b) = (px(&pts2[k][d.a]), px(&pts2[k][d.b]));
                let (sn, cs) = angles[k].to_radians().sin_cos();
                // The baseline above the link (side +1) or below it (−1),
                // `tier` px farther out.
                let off = if side > 0.0 { 4.0 + tier } else { -11.0 - tier };
                (a.0 + (b.0 - a.0) * t + sn * off, a.1 + (b.1 - a.1) * t - cs * off)
            };
            let mut best: Option<(f64, (f64, f64, f64), RotBox)> = None;
            let own = (px(&pts2[0][d.a]), px(&pts2[0][d.b]));
            for (tier, t, side) in [0.0, 7.0].iter().flat_map(|&tier| {
                [0.5, 0.35, 0.65, 0.2, 0.8]
                    .into_iter()
                    .flat_map(move |t| [(tier, t, 1.0), (tier, t, -1.0)])
            }) {
                let (x, y) = spot(0, t, side, tier);
                let bx = RotBox {
                    x,
                    y,
                    ang: angles[0].to_radians(),
                    hw: tw / 2.0,
                    top: -8.5,
                    bottom: 2.5,
                };
                let samples = bx.samples();
                let covered =
                    |hit: &dyn Fn(f64, f64) -> bool| samples.iter().filter(|(x, y)| hit(*x, *y)).count() as f64;
                // Labels are small: also test their corners and centres.
                let label_corners = placed
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
                let mut score = covered(&|x, y| placed.iter().any(|r| r.contains(x, y))) * 5.0
                    + label_corners * 5.0
                    + covered(&|x, y| dim_boxes.iter().any(|b: &RotBox| b.contains(x, y))) * 5.0
                    + all_dots.iter().filter(|(px, py)| bx.contains(*px, *py)).count() as f64 * 40.0
                    + tier * 0.5
                    + (t - 0.5f64).abs() * 4.0;
                for (p, q) in &segments {
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
            let Some((_, (t, side, tier), bx)) = best else { continue };
            dim_boxes.push(bx);
            let at: Vec<String> = (0..nf)
                .map(|k| {
                    let (x, y) = spot(k, t, side, tier);
                    format!("{} {}", n(x), n(y))
                })
                .collect();
            let rot: Vec<String> = angles.iter().map(|a| n(*a)).collect();
            let _ = writeln!(
                s,
                r##"<g class="dimension" data-length-mm="{}" transform="translate({})">{}<g transform="rotate({})">{}<text x="0" y="0" text-anchor="middle" font-size="10" fill="#1f4e79" stroke="white" stroke-width="3" paint-order="stroke">{}</text></g></g>"##,
                fmt_decimals(d.length, 3),
                at[0],
                timing.transform("translate", &at),
                rot[0],
                timing.transform("rotate", &rot),
                escape(&text)
            );
        }
    }
    // ---- legend, scale bar, axes, φ dial ----
    if let Some(t) = threads.filter(|_| has_legend) {
        let lx = w - legend_w + 8.0;
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
        if !pin_nodes.is_empty() {
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
        if !used_cams.is_empty() {
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
    // Scale bar: a round length of about 120 px, in mm.
    let bar_mm = nice_step(120.0 / scale, 1);
    let bar_px = bar_mm * scale;
    let (bx, by) = (w / 2.0 - bar_px / 2.0, h - 30.0);
    let _ = writeln!(
        s,
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
    // Axes of the view, bottom left.
    let (ox, oy) = (44.0, h - 30.0);
    let world_axes = match &opts.view {
        View::Frame(name) => match model.frame_index(name) {
            Some(i) if i > 0 => {
                let pl = mech.frame_plane(i);
                match &pl.0 {
                    Some(f) => [
                        f.dir_to_world(V3::x()),
                        f.dir_to_world(V3::y()),
                        f.dir_to_world(V3::z()),
                    ],
                    None => [V3::x(), V3::y(), V3::z()],
                }
            }
            _ => [V3::x(), V3::y(), V3::z()],
        },
        _ => [V3::x(), V3::y(), V3::z()],
    };
    let _ = write!(s, r#"<g class="axes">"#);
    for (a, name) in world_axes.iter().zip(&axis_names) {
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
    // The main-shaft angle: a dial, bottom right (0° to the right, φ
    // counter-clockwise), its hand turning once per turn in an animation.
    let (dx, dy) = (w - 40.0, h - 34.0);
    let hand: Vec<String> = phis.iter().map(|p| format!("{} {} {}", n(-p), n(dx), n(dy))).collect();
    let turn = if timing.animated() {
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
        s,
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
    s.push_str("</svg>\n");
    if s.contains("NaN") || s.contains("inf") {
        return Err(Error::NotFinite(format!(
            "the drawing of `{}` at φ = {}° came out with a non-finite coordinate; a point may sit on a dead point or a guide line may have no direction there",
            model.name(),
            fmt_decimals(opts.phi_deg, 3)
        )));
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn isometric_keeps_axis_lengths_at_120_degrees() {
        let iso = Projection::isometric();
        let axes = [
            iso.direction(&V3::x()),
            iso.direction(&V3::y()),
            iso.direction(&V3::z()),
        ];
        for a in &axes {
            assert_relative_eq!(a.norm(), 1.0, epsilon = 1e-12);
        }
        assert_relative_eq!(axes[1], V2::new(0.0, 1.0), epsilon = 1e-12);
        // x to the lower right and z to the lower left, 30° below the horizontal.
        assert_relative_eq!(axes[0].y.atan2(axes[0].x).to_degrees(), -30.0, epsilon = 1e-9);
        assert_relative_eq!(axes[2].y.atan2(axes[2].x).to_degrees(), -150.0, epsilon = 1e-9);
        for (i, j) in [(0, 1), (1, 2), (0, 2)] {
            assert_relative_eq!(axes[i].dot(&axes[j]), -0.5, epsilon = 1e-12);
        }
    }

    #[test]
    fn plane_views_keep_lengths_in_their_plane() {
        let (a, b) = (V3::new(3.0, -4.0, 7.0), V3::new(-2.0, 8.0, 7.0));
        let xy = Projection::of_plane(Plane::Xy);
        assert_relative_eq!((xy.project(&a) - xy.project(&b)).norm(), 13.0, epsilon = 1e-12);
        let xz = Projection::of_plane(Plane::Xz);
        assert_eq!(xz.project(&a), V2::new(3.0, 7.0));
        let yz = Projection::of_plane(Plane::Yz);
        assert_eq!(yz.project(&a), V2::new(-4.0, 7.0));
        // A frame turned about x by 90°: its y is the world z.
        let f = crate::geometry::Placement {
            rot: crate::geometry::axis_rotation(0, std::f64::consts::FRAC_PI_2),
            origin: V3::new(1.0, 2.0, 3.0),
        };
        let fr = Projection::of_frame(&FramePlane(Some(f)));
        assert_relative_eq!(fr.project(&V3::new(1.0, 2.0, 8.0)), V2::new(0.0, 5.0), epsilon = 1e-12);
    }

    #[test]
    fn bad_options_are_refused_with_the_flag() {
        let model = Model::preset("needle876").unwrap();
        let p = model.defaults();
        let err = |o: DrawOptions| render(&model, &p, &o).unwrap_err().to_string();
        assert!(
            err(DrawOptions {
                phi_deg: f64::NAN,
                ..Default::default()
            })
            .contains("--phi")
        );
        assert!(
            err(DrawOptions {
                animate: true,
                frames: 1,
                ..Default::default()
            })
            .contains("--frames")
        );
        assert!(
            err(DrawOptions {
                animate: true,
                duration_s: 0.0,
                ..Default::default()
            })
            .contains("--duration")
        );
        assert!(
            err(DrawOptions {
                view: View::Frame("nope".into()),
                ..Default::default()
            })
            .contains("no frame `nope`")
        );
        assert!(
            err(DrawOptions {
                trajectories: vec!["Q".into()],
                ..Default::default()
            })
            .contains("no point `Q`")
        );
        assert!(
            err(DrawOptions {
                trajectories: vec!["O".into()],
                ..Default::default()
            })
            .contains("fixed")
        );
    }
}
