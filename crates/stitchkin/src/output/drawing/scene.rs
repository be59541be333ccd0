//! What a drawing shows, computed once before anything is written: the
//! solved positions per frame in drawing coordinates (mm), the thread
//! polylines, cam outlines, trajectories, crank circles and slider travel
//! ([`Scene`]); its fit to the page ([`Page`]); and what each point is
//! drawn as ([`Roles`]).

use std::collections::BTreeSet;

use super::layout::Screen;
use super::structure::{Structure, guide_line};
use super::threads::{PathFrame, thread_frame, thread_polylines};
use super::{DrawOptions, Projection, Solved, Timing, projection};
use crate::error::Error;
use crate::geometry::{V2, V3};
use crate::mechanism::Mechanism;
use crate::model::{Machine, Model};
use crate::thread::cam::CamPlacement;
use crate::thread::{Span, Threads};

/// Per item, per frame, a polyline in drawing coordinates (mm).
type Lines = Vec<Vec<Vec<V2<f64>>>>;

/// Everything drawn, per frame, in drawing coordinates (mm, y up).
pub(super) struct Scene<'a> {
    pub(super) model: &'a Model,
    pub(super) opts: &'a DrawOptions,
    pub(super) mech: Mechanism<f64>,
    /// The thread paths the mechanism moves, when the model has any.
    threads: Option<Threads<f64>>,
    pub(super) proj: Projection,
    /// The view in words (subtitle) and the names of its three axes.
    pub(super) view_words: String,
    pub(super) axis_names: [String; 3],
    /// Points whose path over the cycle is drawn.
    pub(super) traced: Vec<usize>,
    /// Frames drawn (1 for a still drawing) and their φ, deg.
    pub(super) nf: usize,
    pub(super) phis: Vec<f64>,
    pub(super) timing: Timing,
    pub(super) st: Structure,
    /// World positions per frame: the model's points, then the structure's
    /// own (arm centres on an axis).
    pub(super) pos: Vec<Vec<V3<f64>>>,
    /// Per frame, per thread path: where the thread runs.
    pub(super) path_frames: Vec<Vec<PathFrame>>,
    /// `pos` projected.
    pub(super) pts2: Vec<Vec<V2<f64>>>,
    /// Per thread path, per frame, the thread's polyline.
    pub(super) polylines: Lines,
    /// The cams a thread runs over, and their outlines per frame.
    pub(super) used_cams: Vec<usize>,
    pub(super) cam_outlines: Lines,
    /// The cams that drive followers, turning with φ.
    pub(super) follower_cams: Vec<FollowerCam>,
    /// Per traced point, its path over the cycle.
    pub(super) trajectories: Vec<(usize, Vec<V2<f64>>)>,
    /// Per crank circle, per frame, the circle.
    pub(super) circles: Lines,
    /// Per slider, its travel along the guide (over the cycle when known).
    pub(super) travel: Vec<Option<(f64, f64)>>,
}

impl<'a> Scene<'a> {
    /// Projects what is drawn of the `solved` machine.
    pub(super) fn build(model: &'a Model, solved: Solved, opts: &'a DrawOptions) -> Result<Scene<'a>, Error> {
        let Solved {
            machine: Machine {
                mechanism: mech,
                threads,
            },
            traced,
            phis,
            slots,
            cycle,
        } = solved;
        let (proj, view_words, axis_names) = projection(model, &mech, &opts.view)?;
        let nf = phis.len();
        let st = Structure::of(&mech, model);
        let pos: Vec<Vec<V3<f64>>> = slots.iter().map(|s| st.positions(s)).collect();
        let threads_ref = threads.as_ref();
        let path_frames: Vec<Vec<PathFrame>> = match threads_ref {
            Some(t) => slots
                .iter()
                .zip(&phis)
                .map(|(s, &phi)| thread_frame(t, s, phi))
                .collect::<Result<_, _>>()?,
            None => Vec::new(),
        };
        let pts2 = pos
            .iter()
            .map(|f| f.iter().map(|p| proj.project(p)).collect())
            .collect();
        let (polylines, used_cams, cam_outlines) = match threads_ref {
            Some(t) => {
                let used = used_cams(t);
                let outlines = cam_outlines(t, &used, &slots, &proj);
                (
                    thread_lines(t, &slots, &path_frames, opts.animate, &proj),
                    used,
                    outlines,
                )
            }
            None => (Vec::new(), Vec::new(), Vec::new()),
        };
        let trajectories = match &cycle {
            Some(c) => traced
                .iter()
                .map(|&s| (s, c.iter().map(|f| proj.project(&f[s])).collect()))
                .collect(),
            None => Vec::new(),
        };
        let circles = crank_circles(&st, &pos, &proj);
        let follower_cams = follower_cams(&mech, &slots, &proj);
        let travel = slider_travel(&st, cycle.as_ref().unwrap_or(&slots));
        Ok(Scene {
            model,
            opts,
            proj,
            view_words,
            axis_names,
            traced,
            nf,
            phis,
            timing: Timing {
                frames: nf,
                dur: opts.duration_s,
            },
            st,
            pos,
            path_frames,
            pts2,
            polylines,
            used_cams,
            cam_outlines,
            follower_cams,
            trajectories,
            circles,
            travel,
            mech,
            threads,
        })
    }

    pub(super) fn threads(&self) -> Option<&Threads<f64>> {
        self.threads.as_ref()
    }

    /// The number of the model's points (the structure's own come after).
    pub(super) fn np(&self) -> usize {
        self.mech.n_points()
    }

    pub(super) fn names(&self) -> &[String] {
        &self.model.point_names
    }

    /// A point's name; empty for a point of the structure's own.
    pub(super) fn name_of(&self, i: usize) -> String {
        if i < self.np() {
            self.names()[i].clone()
        } else {
            String::new()
        }
    }

    /// Whether a thread legend is drawn.
    pub(super) fn has_legend(&self) -> bool {
        self.threads().is_some_and(|t| !t.paths.is_empty())
    }
}

/// Per path, per frame, the thread's polyline.
fn thread_lines(
    t: &Threads<f64>,
    slots: &[Vec<V3<f64>>],
    path_frames: &[Vec<PathFrame>],
    animate: bool,
    proj: &Projection,
) -> Lines {
    (0..t.paths.len())
        .map(|j| {
            let path = &t.paths[j];
            let frames: Vec<PathFrame> = path_frames.iter().map(|f| f[j].clone()).collect();
            let guide_pts: Vec<V3<f64>> = slots
                .iter()
                .flat_map(|s| path.nodes.iter().map(|&i| s[i]).collect::<Vec<_>>())
                .collect();
            thread_polylines(&frames, &guide_pts, animate)
                .into_iter()
                .map(|l| l.iter().map(|p| proj.project(p)).collect())
                .collect()
        })
        .collect()
}

/// The cams some thread span runs over.
fn used_cams(t: &Threads<f64>) -> Vec<usize> {
    (0..t.cams.len())
        .filter(|&c| t.spans.iter().any(|s| matches!(s, Span::Cam { cam, .. } if *cam == c)))
        .collect()
}

/// Per used cam, per frame, its profile (120 points a turn).
fn cam_outlines(t: &Threads<f64>, used: &[usize], slots: &[Vec<V3<f64>>], proj: &Projection) -> Lines {
    used.iter()
        .map(|&ci| {
            let c = &t.cams[ci];
            slots
                .iter()
                .map(|s| match CamPlacement::new(s[c.center], s[c.marker], c.axis) {
                    Some(at) => (0..120)
                        .map(|k| {
                            let th = k as f64 * std::f64::consts::TAU / 120.0;
                            proj.project(&(at.center + (at.u * th.cos() + at.v * th.sin()) * c.profile.rho(th)))
                        })
                        .collect(),
                    None => Vec::new(),
                })
                .collect()
        })
        .collect()
}

/// A cam driving a follower (`cam_follower`), per frame in drawing
/// coordinates: its working profile, pitch curve and a groove's outer flank
/// turned with the cam, and the roller round the follower's point.
pub(super) struct FollowerCam {
    pub(super) name: String,
    pub(super) profile: Vec<Vec<V2<f64>>>,
    pub(super) pitch: Vec<Vec<V2<f64>>>,
    /// Empty per frame without a groove.
    pub(super) outer: Vec<Vec<V2<f64>>>,
    /// Empty per frame without a roller.
    pub(super) roller: Vec<Vec<V2<f64>>>,
    /// A flat face's segment; empty per frame without one.
    pub(super) face: Vec<Vec<V2<f64>>>,
}

/// Points round a cam's outline (every 1°).
const CAM_OUTLINE_SAMPLES: usize = 360;

/// Each cam-and-follower group's cam, from the cam's outline
/// ([`crate::mechanism::cam_follower::CamFollower::outline`]) turned by its
/// cam angle in each frame; a frame where it cannot be made is left empty.
fn follower_cams(mech: &Mechanism<f64>, slots: &[Vec<V3<f64>>], proj: &Projection) -> Vec<FollowerCam> {
    use crate::mechanism::Step;
    use crate::mechanism::cam_follower::Contact;
    mech.steps
        .iter()
        .filter_map(|s| match s {
            Step::CamFollower(c) => Some(&**c),
            _ => None,
        })
        .map(|c| {
            let mut cam = FollowerCam {
                name: c.name.clone(),
                profile: Vec::new(),
                pitch: Vec::new(),
                outer: Vec::new(),
                roller: Vec::new(),
                face: Vec::new(),
            };
            let r_r = match c.cam.contact {
                Contact::Roller(r) => r,
                _ => 0.0,
            };
            for s in slots {
                let (c3, k3) = (s[c.center], s[c.marker]);
                let centre = c.plane.project(&c3);
                // Out of the plane: where the cam's centre stands off it.
                let rise = c3 - c.plane.lift(centre, 0.0);
                let at = |q: &V2<f64>, delta: f64| {
                    let (sn, cs) = delta.sin_cos();
                    let w = centre + V2::new(q.x * cs - q.y * sn, q.x * sn + q.y * cs);
                    proj.project(&(c.plane.lift(w, 0.0) + rise))
                };
                let pivot = c.pivot.map(|p| c.plane.project(&s[p]));
                let made = c
                    .cam
                    .cam_angle(centre, c.plane.project(&k3))
                    .and_then(|d| Ok((d, c.cam.outline(centre, pivot, CAM_OUTLINE_SAMPLES)?)));
                let to_drawing = |w: V2<f64>| proj.project(&(c.plane.lift(w, 0.0) + rise));
                let face = match &made {
                    Ok((d, _)) if d.is_finite() => c
                        .cam
                        .face_segment(centre, *d, pivot)
                        .map_or(Vec::new(), |[a, b]| vec![to_drawing(a), to_drawing(b)]),
                    _ => Vec::new(),
                };
                cam.face.push(face);
                let (profile, pitch, outer) = match made {
                    Ok((d, o)) if d.is_finite() => (
                        o.profile.iter().map(|q| at(q, d)).collect(),
                        o.pitch.iter().map(|q| at(q, d)).collect(),
                        o.outer.iter().map(|q| at(q, d)).collect(),
                    ),
                    _ => (Vec::new(), Vec::new(), Vec::new()),
                };
                cam.profile.push(profile);
                cam.pitch.push(pitch);
                cam.outer.push(outer);
                let roller = if r_r > 0.0 {
                    let r = c.plane.project(&s[c.out]);
                    (0..=48)
                        .map(|k| {
                            let th = k as f64 * std::f64::consts::TAU / 48.0;
                            let w = r + V2::new(th.cos(), th.sin()) * r_r;
                            proj.project(&(c.plane.lift(w, 0.0) + rise))
                        })
                        .collect()
                } else {
                    Vec::new()
                };
                cam.roller.push(roller);
            }
            cam
        })
        .collect()
}

/// Crank circles (static: their centres are fixed in every preset; a
/// moving centre is followed per frame).
fn crank_circles(st: &Structure, pos: &[Vec<V3<f64>>], proj: &Projection) -> Lines {
    st.circles
        .iter()
        .map(|c| {
            pos.iter()
                .map(|f| {
                    (0..=72)
                        .map(|k| {
                            let th = k as f64 * std::f64::consts::TAU / 72.0;
                            proj.project(&(f[c.center] + (c.u * th.cos() + c.v * th.sin()) * c.r))
                        })
                        .collect()
                })
                .collect()
        })
        .collect()
}

/// Slider travel along each guide over `samples` (the cycle when known).
fn slider_travel(st: &Structure, samples: &[Vec<V3<f64>>]) -> Vec<Option<(f64, f64)>> {
    st.sliders
        .iter()
        .map(|s| {
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
        .collect()
}

/// The page: its size, the legend's column and the scale that fits the
/// scene into the rest.
pub(super) struct Page {
    pub(super) w: f64,
    pub(super) h: f64,
    pub(super) legend_w: f64,
    pub(super) screen: Screen,
}

impl Page {
    /// Fit to the page: everything drawn, with room around it for labels.
    pub(super) fn fit(sc: &Scene) -> Page {
        let (w, h) = (sc.opts.width, sc.opts.height);
        let legend_w = if sc.has_legend() { 190.0 } else { 0.0 };
        let (ax0, ax1, ay0, ay1) = (24.0, w - legend_w - 24.0, 64.0, h - 74.0);
        let mut lo = V2::new(f64::INFINITY, f64::INFINITY);
        let mut hi = V2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        let mut grow = |q: &V2<f64>| {
            if q.x.is_finite() && q.y.is_finite() {
                lo = lo.inf(q);
                hi = hi.sup(q);
            }
        };
        sc.pts2.iter().flatten().for_each(&mut grow);
        sc.polylines.iter().flatten().flatten().for_each(&mut grow);
        sc.cam_outlines.iter().flatten().flatten().for_each(&mut grow);
        for c in &sc.follower_cams {
            c.profile.iter().chain(&c.outer).flatten().for_each(&mut grow);
        }
        sc.trajectories.iter().flat_map(|(_, t)| t).for_each(&mut grow);
        sc.circles.iter().flatten().flatten().for_each(&mut grow);
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
        Page { w, h, legend_w, screen }
    }
}

/// What each point is drawn as.
pub(super) struct Roles {
    /// Fixed points a link turns about: a pivot on a hatched ground.
    pub(super) pivots: Vec<usize>,
    /// Moving points shared by two links or more: a revolute joint.
    pub(super) joints: Vec<usize>,
    /// Moving spherical joints: a ball-end.
    pub(super) balls: Vec<usize>,
    /// Moving points of one link only: a dot.
    pub(super) dots: Vec<usize>,
    /// Thread guides: eyelets (always in contact) and one-sided guides.
    pub(super) guide_nodes: BTreeSet<usize>,
    pub(super) pin_nodes: BTreeSet<usize>,
}

impl Roles {
    /// Roles of points: by how many links and sliders hold each, and how the
    /// thread paths use it.
    pub(super) fn of(sc: &Scene) -> Roles {
        let (st, model, np) = (&sc.st, sc.model, sc.np());
        let mut membership = vec![0usize; sc.pos[0].len()];
        for b in &st.bodies {
            for &p in &b.pts {
                membership[p] += 1;
            }
        }
        for s in &st.sliders {
            membership[s.at] += 1;
        }
        let threads = sc.threads();
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
        let moving_with = |count: fn(usize) -> bool| -> Vec<usize> {
            (0..np)
                .filter(|&i| !model.is_fixed(i) && count(membership[i]) && !st.spherical.contains(&i))
                .collect()
        };
        Roles {
            pivots: (0..np).filter(|&i| model.is_fixed(i) && membership[i] > 0).collect(),
            joints: moving_with(|m| m >= 2),
            balls: st.spherical.iter().copied().filter(|i| !model.is_fixed(*i)).collect(),
            dots: moving_with(|m| m == 1),
            guide_nodes,
            pin_nodes,
        }
    }
}
