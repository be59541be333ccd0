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

use crate::error::{Error, Input, NotFiniteError, ParamError};
use crate::format::{fmt_decimals, svg_num as n};
use crate::geometry::{Plane as FramePlane, V2, V3};
use crate::mechanism::Mechanism;
use crate::model::{Machine, Model};

pub mod cam;
mod layers;
mod layout;
mod scene;
mod structure;
mod threads;

use layers::{Drawing, Sheet};
use scene::{Page, Roles, Scene};

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
                    Input::View,
                    "no view given".into(),
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

fn param_error(input: impl Into<Option<Input>>, message: String, help: String) -> Error {
    Error::Param(ParamError {
        input: input.into(),
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

/// Refuses options no drawing can follow (frames, duration, sizes), naming
/// the option and the range it takes.
pub fn check_options(opts: &DrawOptions) -> Result<(), Error> {
    if !opts.phi_deg.is_finite() {
        return Err(param_error(
            Input::Phi,
            format!("the angle φ = {} is not a finite number", opts.phi_deg),
            "give φ in degrees, e.g. 90".into(),
        ));
    }
    if opts.animate {
        if opts.frames < 2 {
            return Err(param_error(
                Input::Frames,
                format!("an animation needs at least 2 frames per turn, got {}", opts.frames),
                "give 72 frames (5° per frame) or 120 (3°)".into(),
            ));
        }
        if opts.frames > 3600 {
            return Err(param_error(
                Input::Frames,
                format!("{} frames per turn would make a very large file", opts.frames),
                "give at most 3600 frames (0.1° per frame)".into(),
            ));
        }
        if !(opts.duration_s.is_finite() && opts.duration_s > 0.0) {
            return Err(param_error(
                Input::Duration,
                format!(
                    "the duration of one turn must be a positive number of seconds, got {}",
                    opts.duration_s
                ),
                "give 4 (seconds per turn of the main shaft)".into(),
            ));
        }
    }
    for (what, v) in [("width", opts.width), ("height", opts.height)] {
        if !(v.is_finite() && (200.0..=20000.0).contains(&v)) {
            return Err(param_error(
                None,
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
                    Input::View,
                    format!("the model has no frame `{name}`"),
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

/// A machine solved for a drawing: the positions of every point slot at
/// each frame's φ and, when it assembles all round (or trajectories are
/// asked for), over the cycle. Computed by [`crate::jobs::drawing`].
#[derive(Debug, Clone)]
pub struct Solved {
    /// The mechanism and its thread paths at the drawn setting.
    pub machine: Machine<f64>,
    /// Point slots whose path over the cycle is drawn.
    pub traced: Vec<usize>,
    /// The frames' φ, degrees.
    pub phis: Vec<f64>,
    /// Per frame, the position of every point slot (mm).
    pub slots: Vec<Vec<V3<f64>>>,
    /// Per φ of the cycle (1° steps), the position of every point slot.
    pub cycle: Option<Vec<Vec<V3<f64>>>>,
}

/// The drawing of the `solved` machine as an SVG document: at
/// `opts.phi_deg`, or animated over one turn (see [`DrawOptions`]).
pub fn render(model: &Model, solved: Solved, opts: &DrawOptions) -> Result<String, Error> {
    check_options(opts)?;
    let scene = Scene::build(model, solved, opts)?;
    let page = Page::fit(&scene);
    let roles = Roles::of(&scene);
    let d = Drawing {
        sc: &scene,
        page: &page,
        roles: &roles,
    };
    // Paint order: what lies underneath first; labels and dimensions last,
    // placed where they cover the least of what is drawn.
    let mut out = Sheet::default();
    d.draw_header(&mut out);
    d.draw_trajectories(&mut out);
    d.draw_crank_circles(&mut out);
    d.draw_guides(&mut out);
    d.draw_cams(&mut out);
    d.draw_follower_cams(&mut out);
    d.draw_links(&mut out);
    d.draw_threads(&mut out);
    d.draw_sliders(&mut out);
    d.draw_pivots(&mut out);
    d.draw_points(&mut out);
    d.draw_thread_guides(&mut out);
    d.draw_labels(&mut out);
    if opts.dimensions {
        d.draw_dimensions(&mut out);
    }
    d.draw_legend(&mut out);
    d.draw_scale_bar(&mut out);
    d.draw_axes(&mut out);
    d.draw_phi_dial(&mut out);
    out.svg.push_str("</svg>\n");
    if out.svg.contains("NaN") || out.svg.contains("inf") {
        return Err(Error::NotFinite(NotFiniteError {
            quantity: format!("a coordinate of the drawing of `{}`", model.name()),
            phi_deg: Some(opts.phi_deg),
            cause: "a point may sit on a dead point or a guide line may have no direction there".into(),
        }));
    }
    Ok(out.svg)
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
    fn bad_options_are_refused_naming_the_input() {
        let model = Model::preset("needle876").unwrap();
        let p = model.defaults();
        let err = |o: DrawOptions| crate::jobs::drawing::render(&model, &p, &o).unwrap_err().to_string();
        assert!(
            err(DrawOptions {
                phi_deg: f64::NAN,
                ..Default::default()
            })
            .contains("(in `phi`)")
        );
        assert!(
            err(DrawOptions {
                animate: true,
                frames: 1,
                ..Default::default()
            })
            .contains("(in `frames`)")
        );
        assert!(
            err(DrawOptions {
                animate: true,
                duration_s: 0.0,
                ..Default::default()
            })
            .contains("(in `duration`)")
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
