//! Thread paths ("feed contours") and the actual take-up P(φ).
//!
//! A path runs from the tension regulator through fixed guides, eyelets on
//! moving links and one-sided guides to the needle (or looper) eye. Its
//! length is the contour length ξ(φ) = Σ |segment| (seed 000 eqs. 3–6);
//! the actual take-up is P(φ) = ξ(φ0) − ξ(φ) (seed 000 eq. 2) or, in the
//! convention of seed 001 (eqs. 22–23), P(φ) = ξ(φ) − ξ(φ0) + ΔP.
//!
//! Paths are evaluated over a whole [`Pose`] at once, segment by segment;
//! a segment whose two ends ride on one rigid body (two fixed guides, two
//! eyelets on the needle bar) is computed once per pose, not per φ.

pub mod cam;
pub mod measured;
pub mod repeated;
pub mod tension;
pub mod wrap;

use serde::Serialize;

use crate::geometry::{Plane, V3};
use num_dual::Dual2_64;

use crate::mechanism::Pose;
use crate::mechanism::analogs::PoseAnalogs;
use crate::scalar::Real;

/// One piece of a path between two nodes the thread passes through. Paths
/// share pieces (two contours of one needle share their first guides), so
/// [`Threads`] keeps each distinct piece once.
#[derive(Debug, Clone, PartialEq)]
pub enum Span<T: Real> {
    /// A straight segment `a → b`; `constant` when both ends ride on one
    /// rigid body; `fixed[i]` when end `i` (a, b) never moves.
    Straight {
        a: usize,
        b: usize,
        constant: bool,
        fixed: [bool; 2],
    },
    /// `a → b` over a one-sided cylindrical guide through point `c` (named
    /// `name`), turning in the sense `sense` about `axis`.
    Pin {
        a: usize,
        b: usize,
        c: usize,
        axis: V3<T>,
        r: T,
        sense: f64,
        name: String,
    },
    /// `a → b` bearing on cam number `cam` of [`Threads::cams`].
    Cam {
        a: usize,
        b: usize,
        cam: usize,
        contact: CamModel,
    },
}

/// How the thread meets a cam (see [`cam`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CamModel {
    /// Taut thread over the convex profile, turning in `sense` about the axis.
    Exact { sense: f64 },
    /// Seed 004: contact at the profile radius turned by γ.
    Offset { gamma_rad: f64 },
}

/// A thread feed cam: profile, shaft axis, and the points that place it.
#[derive(Debug, Clone, PartialEq)]
pub struct Cam<T: Real> {
    pub name: String,
    /// Pose slot of a point on the shaft axis.
    pub center: usize,
    /// Pose slot of a point turning with the cam (profile angle 0).
    pub marker: usize,
    pub axis: V3<T>,
    pub profile: cam::Profile,
}

/// A thread path with every parameter resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct ThreadPath {
    pub name: String,
    /// Which thread this is, in words (`needle 1, contour A`).
    pub label: Option<String>,
    /// Pose slots of the nodes, in thread order (pins included).
    pub nodes: Vec<usize>,
    /// The nodes' point names.
    pub node_names: Vec<String>,
    /// Friction coefficient at each node (the first node's is unused).
    pub friction: Vec<f64>,
    /// Its pieces, as indices into [`Threads::spans`], in thread order.
    pub spans: Vec<usize>,
    /// For each node that is a pin, the index of its span.
    pub pin_span: Vec<Option<usize>>,
    /// For each node, whether the thread's turn there never changes over a
    /// cycle: an eyelet at a fixed point between two fixed points.
    pub fixed_turn: Vec<bool>,
}

/// How P(φ) is signed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Convention {
    /// `P = ξ(φ0) − ξ(φ)`.
    Release,
    /// `P = ξ(φ) − ξ(φ0) + ΔP`.
    Feed { elongation_mm: f64 },
}

impl Convention {
    /// P from ξ and ξ(φ0).
    #[inline]
    pub fn take_up<T: Real>(&self, xi: T, xi0: T) -> T {
        match self {
            Convention::Release => xi0 - xi,
            Convention::Feed { elongation_mm } => xi - xi0 + T::cst(*elongation_mm),
        }
    }
}

/// The thread part of a resolved model.
#[derive(Debug, Clone, PartialEq)]
pub struct Threads<T: Real> {
    /// The paths (shared by every mechanism resolved from one model).
    pub paths: std::sync::Arc<[ThreadPath]>,
    /// Every distinct piece of every path.
    pub spans: Vec<Span<T>>,
    pub cams: Vec<Cam<T>>,
    pub convention: Convention,
    /// φ0, degrees.
    pub phi0_deg: f64,
    /// Regulator tension, N.
    pub tension_n: Option<f64>,
    /// For each path (in path order): the unit vector u up its needle, in
    /// world coordinates, when the path ends at a needle's eye and its
    /// take-up is split at B, the eye's top position (seed 004 §2.3);
    /// `None` for a path split at its last node.
    pub split_up: Vec<Option<V3<T>>>,
}

/// Where a thread's take-up P (and the stitch's P′) is measured: where the
/// thread is split between the feed contour and the consumption contour
/// (docs/stitch-formation.md §3.2). P_B − P_eye = S(φ) − S(φ0), S the
/// needle's travel, for P and P′ alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SplitPoint {
    /// B, the fixed point at the needle eye's top position (columns
    /// `P_B_mm`, `Pprime_B_mm`), as seeds 000 and 004 plot it.
    #[serde(rename = "B")]
    B,
    /// The moving eye (columns `P_eye_mm`, `Pprime_eye_mm`; a looper
    /// thread's `Pprime_mm`).
    #[serde(rename = "eye")]
    Eye,
    /// The last node of a thread path that does not end at a needle's eye
    /// (column `P_mm`).
    #[serde(rename = "end")]
    End,
}

impl SplitPoint {
    /// As JSON gives it: `B`, `eye` or `end`.
    pub fn as_str(self) -> &'static str {
        match self {
            SplitPoint::B => "B",
            SplitPoint::Eye => "eye",
            SplitPoint::End => "end",
        }
    }
}

impl std::fmt::Display for SplitPoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A path evaluated over a pose.
#[derive(Debug, Clone, PartialEq)]
pub struct PathTrack<T: Real> {
    /// Contour length ξ at each φ, to the path's last node, mm.
    pub xi: Vec<T>,
    /// For a path split at B: u·N, the height of its eye N along the
    /// needle at each φ, mm; empty otherwise.
    pub eye_up: Vec<T>,
    /// For each pin of the path (in node order): whether the thread bears
    /// on it at each φ.
    pub engaged: Vec<Vec<bool>>,
}

impl<T: Real> PathTrack<T> {
    /// The length the take-up P is taken from at the `k`-th φ. For a path
    /// split at B it is the feed contour to B, ξ_B = ξ − S with S = u·(B − N)
    /// the needle's travel below B, plus the constant u·B (which cancels in
    /// P = ξ_B(φ0) − ξ_B(φ)): ξ + u·N. Otherwise ξ itself.
    #[inline]
    pub fn xi_at_split(&self, k: usize) -> T {
        match self.eye_up.get(k) {
            Some(&up) => self.xi[k] + up,
            None => self.xi[k],
        }
    }
}

/// A path whose contour cannot be formed at the `k`-th φ: a node inside a
/// guide.
#[derive(Debug, Clone, PartialEq)]
pub struct PathError {
    pub path: String,
    pub k: usize,
    pub message: String,
}

/// One distinct piece's lengths over a pose.
#[derive(Debug, Clone)]
struct SpanBuf<T: Real> {
    /// The length when it is the same at every φ (both ends on one body).
    constant: Option<T>,
    /// Otherwise the length at each φ…
    len: Vec<T>,
    /// …and, for a guide, whether the thread bears on it.
    on: Vec<bool>,
}

impl<T: Real> Default for SpanBuf<T> {
    fn default() -> Self {
        SpanBuf {
            constant: None,
            len: Vec::new(),
            on: Vec::new(),
        }
    }
}

impl<T: Real> SpanBuf<T> {
    /// Empty, keeping its buffers.
    fn reset(&mut self) {
        self.constant = None;
        self.len.clear();
        self.on.clear();
    }
}

/// The buffers of [`Threads::evaluate_into`], kept from one cycle to the
/// next so a study's inner loop allocates nothing once they have grown.
#[derive(Debug, Clone)]
pub struct ThreadWork<T: Real> {
    /// Every path's contour length and guide contacts from the last
    /// evaluation, in path order.
    pub tracks: Vec<PathTrack<T>>,
    spans: Vec<SpanBuf<T>>,
    /// Whether a piece with both ends on one body keeps the length it had
    /// in the first pose evaluated ([`Self::for_pieces`]).
    keep_constants: bool,
    /// The paths evaluated, by index (every path when empty), and the
    /// straight pieces none of them runs over, skipped (filled on the first
    /// evaluation).
    only: Vec<bool>,
    skip: Vec<bool>,
    /// The pieces whose lengths stay those the last evaluation left
    /// ([`Threads::keep_unmoved`]), for the next evaluation only.
    keep: Vec<bool>,
}

impl<T: Real> Default for ThreadWork<T> {
    fn default() -> Self {
        ThreadWork {
            tracks: Vec::new(),
            spans: Vec::new(),
            keep_constants: false,
            only: Vec::new(),
            skip: Vec::new(),
            keep: Vec::new(),
        }
    }
}

impl<T: Real> ThreadWork<T> {
    /// Buffers for a cycle evaluated a piece of it at a time, in order: a
    /// piece of thread with both ends on one body keeps the length it has
    /// at the first φ of the first piece, as in one evaluation of the
    /// whole cycle, so the pieces' ξ are the whole cycle's bit for bit.
    pub fn for_pieces() -> Self {
        ThreadWork {
            keep_constants: true,
            ..Default::default()
        }
    }

    /// Buffers that evaluate only the paths `wanted` (by index; a study
    /// that reads a few paths' P): a straight piece no wanted path runs
    /// over is not computed, and the other paths' tracks are left empty.
    /// Every guide and cam is still placed, so a setting where one of
    /// them cannot be formed fails as a whole evaluation does.
    pub fn only_paths(wanted: Vec<bool>) -> Self {
        ThreadWork {
            only: wanted,
            ..Default::default()
        }
    }

    /// Whether path `i` is evaluated.
    pub fn wants(&self, i: usize) -> bool {
        wanted(&self.only, i)
    }
}

/// Whether path `i` is evaluated under the mask `only` (every path when
/// it is empty).
fn wanted(only: &[bool], i: usize) -> bool {
    only.get(i).is_none_or(|&w| w)
}

impl<T: Real> Threads<T> {
    /// Contour length and guide contacts of every path at every φ of `pose`.
    /// With `project`, every node is first projected onto that plane and
    /// pins stand across it (the 2D model). Each distinct piece is computed
    /// once, a constant one once per pose.
    pub fn evaluate(&self, pose: &Pose<T>, project: Option<&Plane<T>>) -> Result<Vec<PathTrack<T>>, PathError> {
        let mut work = ThreadWork::default();
        self.evaluate_into(pose, project, &mut work)?;
        Ok(work.tracks)
    }

    crate::scalar::widest! {
        /// [`Self::evaluate`] into `work.tracks`, reusing `work`'s buffers: no
        /// heap allocation once they have the pose's size. Straight pieces and
        /// thin pins take their square roots a whole cycle at a time
        /// ([`Real::sqrt_slice`]).
        pub fn evaluate_into(&self, pose: &Pose<T>, project: Option<&Plane<T>>, work: &mut ThreadWork<T>) -> Result<(), PathError>
            => evaluate_in for Threads<T>, <T: Real>
    }

    /// [`Self::evaluate_into`], inlined into each vector-unit variant.
    #[inline(always)]
    fn evaluate_in(
        &self,
        pose: &Pose<T>,
        project: Option<&Plane<T>>,
        work: &mut ThreadWork<T>,
    ) -> Result<(), PathError> {
        let projected;
        let (pose, axis_override) = match project {
            Some(pl) => {
                projected = pose.projected(pl);
                (&projected, Some(normal_of(pl)))
            }
            None => (pose, None),
        };
        let n = pose.len();
        let keep_constants = work.keep_constants;
        work.spans.resize_with(self.spans.len(), SpanBuf::default);
        if !work.only.is_empty() && work.skip.len() != self.spans.len() {
            work.skip = (0..self.spans.len())
                .map(|s| {
                    matches!(self.spans[s], Span::Straight { .. })
                        && !self
                            .paths
                            .iter()
                            .enumerate()
                            .any(|(i, p)| work.wants(i) && p.spans.contains(&s))
                })
                .collect();
        }
        // Pieces kept from the last evaluation: asked for this one only.
        let keep = std::mem::take(&mut work.keep);
        let keep = if project.is_none() && keep.len() == self.spans.len() {
            keep
        } else {
            Vec::new()
        };
        for (i, span) in self.spans.iter().enumerate() {
            if keep.get(i) == Some(&true) {
                continue;
            }
            let buf = &mut work.spans[i];
            let kept = buf.constant.filter(|_| keep_constants);
            buf.reset();
            if work.skip.get(i) == Some(&true) {
                continue;
            }
            match span {
                Span::Straight {
                    a, b, constant: true, ..
                } if n > 0 => {
                    buf.constant =
                        Some(kept.unwrap_or_else(|| (pose.point(*b, 0) - pose.point(*a, 0)).norm_squared().sqrt()))
                }
                Span::Straight { a, b, fixed, .. } => {
                    // A fixed end is read once (one of the ends of most
                    // varying pieces is a guide on the frame).
                    let (ta, tb) = (pose.track(*a), pose.track(*b));
                    match fixed {
                        _ if n == 0 => {}
                        [true, _] => buf.len.extend(tb.iter().map(|q| (*q - ta[0]).norm_squared())),
                        [_, true] => buf.len.extend(ta.iter().map(|p| (tb[0] - *p).norm_squared())),
                        _ => buf.len.extend(ta.iter().zip(tb).map(|(p, q)| (*q - *p).norm_squared())),
                    }
                    T::sqrt_slice(&mut buf.len);
                }
                Span::Pin {
                    a,
                    b,
                    c,
                    axis,
                    r,
                    sense,
                    ..
                } if r.re() == 0.0 => {
                    let axis = axis_override.unwrap_or(*axis);
                    let ends = (pose.track(*a), pose.track(*b), pose.track(*c));
                    wrap::thin_pin_lengths(ends, axis, *sense, &mut buf.len, &mut buf.on)
                        .map_err(|k| self.inside(i, k))?;
                }
                Span::Pin {
                    a,
                    b,
                    c,
                    axis,
                    r,
                    sense,
                    ..
                } => {
                    let axis = axis_override.unwrap_or(*axis);
                    let (ta, tb, tc) = (pose.track(*a), pose.track(*b), pose.track(*c));
                    for k in 0..n {
                        let (l, e) =
                            wrap::pin_length(ta[k], tb[k], tc[k], axis, *r, *sense).ok_or_else(|| self.inside(i, k))?;
                        buf.len.push(l);
                        buf.on.push(e);
                    }
                }
                Span::Cam { a, b, cam, contact } => {
                    let c = &self.cams[*cam];
                    let axis = axis_override.unwrap_or(c.axis);
                    let (ta, tb, tc, tm) = (
                        pose.track(*a),
                        pose.track(*b),
                        pose.track(c.center),
                        pose.track(c.marker),
                    );
                    for k in 0..n {
                        let (l, e) = cam_length(&c.profile, *contact, axis, ta[k], tb[k], tc[k], tm[k])
                            .ok_or_else(|| self.inside(i, k))?;
                        buf.len.push(l);
                        buf.on.push(e);
                    }
                }
            }
        }
        // Its buffer back for the next marking.
        work.keep = keep;
        work.keep.clear();
        sum_paths(&self.paths, |s| matches!(self.spans[s], Span::Straight { .. }), n, work);
        let only = &work.only;
        for (i, ((path, track), up)) in self.paths.iter().zip(&mut work.tracks).zip(&self.split_up).enumerate() {
            track.eye_up.clear();
            if !wanted(only, i) {
                continue;
            }
            if let (Some(up), Some(&eye)) = (up, path.nodes.last()) {
                track.eye_up.extend(pose.track(eye).iter().map(|p| up.dot(p)));
            }
        }
        Ok(())
    }

    /// Marks the pieces whose lengths the next [`Self::evaluate_into`]
    /// into `work` keeps from the last: where `work` holds `before`'s
    /// pieces over a pose of the same positions (a study's previous
    /// setting), a piece defined as `before`'s whose ends and guide did
    /// not move (`moved`, per point: [`crate::mechanism::Mechanism::solve_since`])
    /// has the same lengths. Without a projection only.
    pub fn keep_unmoved(&self, before: &Threads<T>, moved: &[bool], work: &mut ThreadWork<T>) {
        work.keep.clear();
        if before.spans.len() != self.spans.len() || work.spans.len() != self.spans.len() {
            return;
        }
        let still = |s: &usize| !moved.get(*s).copied().unwrap_or(true);
        work.keep
            .extend(self.spans.iter().zip(&before.spans).map(|(span, was)| {
                span == was
                    && match span {
                        Span::Straight { a, b, .. } => still(a) && still(b),
                        Span::Pin { a, b, c, .. } => still(a) && still(b) && still(c),
                        Span::Cam { a, b, cam, .. } => {
                            let (c, c0) = (&self.cams[*cam], before.cams.get(*cam));
                            Some(c) == c0 && still(a) && still(b) && still(&c.center) && still(&c.marker)
                        }
                    }
            }));
    }

    /// Whether every piece of `path` is marked to keep its lengths in the
    /// next evaluation into `work` ([`Self::keep_unmoved`]): then its
    /// nodes, guides and pieces are the last setting's over the same
    /// positions, and so is everything read off the path over the cycle
    /// (its gaps and turns, `eval::PathCourse`).
    pub fn path_kept(&self, path: &ThreadPath, work: &ThreadWork<T>) -> bool {
        work.keep.len() == self.spans.len() && path.spans.iter().all(|&s| work.keep[s])
    }

    /// Every path at the `k`-th φ of `pose` alone: ξ (and u·N for a path
    /// split at B), one value each; no guide contacts.
    pub fn evaluate_at(&self, pose: &Pose<T>, k: usize) -> Result<Vec<PathTrack<T>>, PathError> {
        let lengths = self
            .spans
            .iter()
            .enumerate()
            .map(|(i, span)| match span {
                Span::Straight { a, b, .. } => Ok((pose.point(*b, k) - pose.point(*a, k)).norm_squared().sqrt()),
                Span::Pin {
                    a,
                    b,
                    c,
                    axis,
                    r,
                    sense,
                    ..
                } => wrap::pin_length(
                    pose.point(*a, k),
                    pose.point(*b, k),
                    pose.point(*c, k),
                    *axis,
                    *r,
                    *sense,
                )
                .map(|(l, _)| l)
                .ok_or_else(|| self.inside(i, k)),
                Span::Cam { a, b, cam, contact } => {
                    let c = &self.cams[*cam];
                    cam_length(
                        &c.profile,
                        *contact,
                        c.axis,
                        pose.point(*a, k),
                        pose.point(*b, k),
                        pose.point(c.center, k),
                        pose.point(c.marker, k),
                    )
                    .map(|(l, _)| l)
                    .ok_or_else(|| self.inside(i, k))
                }
            })
            .collect::<Result<Vec<T>, PathError>>()?;
        // Summed as `evaluate_into` sums, so ξ(φ0) here is bit for bit ξ at
        // φ0 in a cycle and P(φ0) is exactly 0.
        Ok(self
            .paths
            .iter()
            .zip(&self.split_up)
            .map(|(p, up)| {
                let constant = p
                    .spans
                    .iter()
                    .filter(|&&s| self.is_constant(s))
                    .fold(T::zero(), |x, &s| x + lengths[s]);
                let varying: Vec<T> = p
                    .spans
                    .iter()
                    .filter(|&&s| !self.is_constant(s))
                    .map(|&s| lengths[s])
                    .collect();
                let xi = varying.chunks(4).fold(constant, |x, c| match *c {
                    [a] => x + a,
                    [a, b] => x + (a + b),
                    [a, b, c] => x + (a + b + c),
                    [a, b, c, d, ..] => x + ((a + b) + (c + d)),
                    [] => x,
                });
                let eye_up = match (up, p.nodes.last()) {
                    (Some(up), Some(&eye)) => vec![up.dot(&pose.point(eye, k))],
                    _ => Vec::new(),
                };
                PathTrack {
                    xi: vec![xi],
                    eye_up,
                    engaged: Vec::new(),
                }
            })
            .collect())
    }

    /// Whether piece `s` has one length over a pose (see `evaluate_into`).
    fn is_constant(&self, s: usize) -> bool {
        matches!(self.spans[s], Span::Straight { constant: true, .. })
    }

    fn inside(&self, span: usize, k: usize) -> PathError {
        let path = self
            .paths
            .iter()
            .find(|p| p.spans.contains(&span))
            .map_or(String::new(), |p| p.name.clone());
        let message = match &self.spans[span] {
            Span::Pin { name, .. } => format!("a thread end lies inside the guide at `{name}`"),
            Span::Cam { cam, .. } => format!(
                "the thread cannot be laid on cam `{}`: a neighbouring guide lies inside its profile or on its shaft axis, \
                 its marker lies on the shaft axis, or (offset contact) the two guides face each other through the shaft",
                self.cams[*cam].name
            ),
            Span::Straight { .. } => "the path cannot be formed".to_string(),
        };
        PathError { path, k, message }
    }

    /// The angle the thread turns through at each node of `path` at the
    /// `k`-th φ, rad, into `turns.theta`: at an eyelet the angle between
    /// the pieces before and after it (from where the thread leaves a guide
    /// it bears on), at a pin or cam the wrap angle (0 when it does not
    /// bear). A turn between fixed points ([`ThreadPath::fixed_turn`]) is
    /// computed at the first φ asked of `turns` and kept.
    pub fn wrap_angles<'w>(&self, path: &ThreadPath, pose: &Pose<T>, k: usize, turns: &'w mut Turns) -> &'w [f64] {
        let m = path.nodes.len();
        let at = |i: usize| pose.point(path.nodes[i], k).map(|v| v.re());
        let Turns {
            theta,
            touch,
            fixed_kept,
        } = turns;
        theta.resize(m, 0.0);
        touch.clear();
        touch.resize(m, None);
        // Where the thread meets and leaves each guide that bears on it.
        for i in 0..m {
            let Some(s) = path.pin_span[i] else { continue };
            let (p, q) = (pose.point(path.nodes[i - 1], k), pose.point(path.nodes[i + 1], k));
            let (wrap_rad, t) = match &self.spans[s] {
                Span::Pin { c, axis, r, sense, .. } => {
                    // Angles need no analogs: solved in plain numbers.
                    let re = |v: V3<T>| v.map(|x| x.re());
                    let c = pose.point(*c, k);
                    match wrap::pin_wrap(re(p), re(q), re(c), re(*axis), r.re(), *sense) {
                        Some(w) => (w.wrap_rad, w.touch),
                        None => (0.0, None),
                    }
                }
                Span::Cam { cam, contact, .. } => {
                    let c = &self.cams[*cam];
                    let re = |v: V3<T>| v.map(|x| x.re());
                    match cam::CamPlacement::new(re(pose.point(c.center, k)), re(pose.point(c.marker, k)), re(c.axis))
                        .and_then(|pl| match contact {
                            CamModel::Exact { sense } => cam::exact_contact(&c.profile, &pl, re(p), re(q), *sense),
                            CamModel::Offset { gamma_rad } => {
                                cam::offset_contact(&c.profile, &pl, re(p), re(q), *gamma_rad)
                            }
                        }) {
                        Some(w) => (w.wrap_rad, w.touch),
                        None => (0.0, None),
                    }
                }
                Span::Straight { .. } => (0.0, None),
            };
            theta[i] = wrap_rad;
            touch[i] = t;
        }
        // The points the thread last and next touches around node i.
        let before = |i: usize| match (path.pin_span[i - 1], touch[i - 1]) {
            (Some(_), Some(t)) => t[1],
            (Some(_), None) => at(i - 2),
            (None, _) => at(i - 1),
        };
        let after = |i: usize| match (path.pin_span[i + 1], touch[i + 1]) {
            (Some(_), Some(t)) => t[0],
            (Some(_), None) => at(i + 2),
            (None, _) => at(i + 1),
        };
        for i in 1..m.saturating_sub(1) {
            if path.pin_span[i].is_some() || (*fixed_kept && path.fixed_turn[i]) {
                continue;
            }
            let p = at(i);
            let u = (p - before(i)).normalize();
            let w = (after(i) - p).normalize();
            let c = u.dot(&w);
            theta[i] = if c.is_finite() { c.clamp(-1.0, 1.0).acos() } else { 0.0 };
        }
        *fixed_kept = true;
        theta
    }
}

impl<T: Real> Threads<T> {
    /// The length of thread between each pair of consecutive nodes of
    /// `path` at the `k`-th φ of `pose`, from the pieces' lengths of the
    /// last evaluation of that pose in `work`, mm, into `out` (one per node
    /// gap). A straight piece is its own gap; a piece over a guide (a pin
    /// or a cam, a node of its own) is split at the guide in the ratio of
    /// its ends' distances from it: from a pin's axis (ρp : ρq, exactly
    /// where a thin pin's contact divides the unrolled thread, and where the
    /// straight thread crosses the axis' plane when it does not bear), from
    /// a cam's shaft.
    pub fn gap_lengths(&self, path: &ThreadPath, pose: &Pose<T>, work: &ThreadWork<T>, k: usize, out: &mut Vec<f64>) {
        out.clear();
        for &s in &path.spans {
            let buf = &work.spans[s];
            let len = buf.constant.unwrap_or_else(|| buf.len[k]).re();
            let at = |slot: usize| pose.point(slot, k).map(|x| x.re());
            match &self.spans[s] {
                Span::Straight { .. } => out.push(len),
                Span::Pin { a, b, c, axis, .. } => {
                    let (pa, pb, pc) = (at(*a), at(*b), at(*c));
                    let ax = axis.map(|x| x.re());
                    let off_axis = |p: V3<f64>| {
                        let w = p - pc;
                        (w - ax * w.dot(&ax)).norm()
                    };
                    let (ra, rb) = (off_axis(pa), off_axis(pb));
                    let f = if ra + rb > 0.0 { ra / (ra + rb) } else { 0.5 };
                    out.extend([len * f, len * (1.0 - f)]);
                }
                Span::Cam { a, b, cam, .. } => {
                    let pc = at(self.cams[*cam].center);
                    let (ra, rb) = ((at(*a) - pc).norm(), (at(*b) - pc).norm());
                    let f = if ra + rb > 0.0 { ra / (ra + rb) } else { 0.5 };
                    out.extend([len * f, len * (1.0 - f)]);
                }
            }
        }
    }
}

/// The capstan factor e^{μ·θ} of a node of friction `mu` that the thread
/// turns through `theta_rad`: the tension it passes on over the tension
/// that holds it back at slip (Euler–Eytelwein).
#[inline]
pub fn capstan_factor(mu: f64, theta_rad: f64) -> f64 {
    (mu * theta_rad).exp()
}

/// Tension after each node by the capstan (Euler–Eytelwein) law with
/// Amontons friction, `T_{i+1} = T_i · exp(μ_i · θ_i)`, from `t0` (N) at the
/// first node, the thread drawn toward the last node; θ_i the angle it
/// turns through at node i (rad), μ_i the friction there.
pub fn capstan<'a>(theta: &'a [f64], friction: &'a [f64], t0: f64) -> impl Iterator<Item = f64> + 'a {
    theta
        .iter()
        .zip(friction)
        .enumerate()
        .scan(t0, |t, (i, (theta_i, mu_i))| {
            if i > 0 {
                *t *= capstan_factor(*mu_i, *theta_i);
            }
            Some(*t)
        })
}

/// The buffers of [`Threads::wrap_angles`] for one path of one setting,
/// taken φ after φ: the angles at the last φ and the turns between fixed
/// points, which are computed once.
#[derive(Debug, Clone, Default)]
pub struct Turns {
    theta: Vec<f64>,
    touch: Vec<Option<[V3<f64>; 2]>>,
    /// Whether `theta` holds the fixed turns.
    fixed_kept: bool,
}

impl ThreadPath {
    /// Names of the path's pins, in order.
    pub fn pin_names(&self) -> Vec<&str> {
        (0..self.nodes.len())
            .filter(|&i| self.pin_span[i].is_some())
            .map(|i| self.node_names[i].as_str())
            .collect()
    }
}

/// Each path's ξ from its pieces' lengths in `work`: the sum of the constant
/// pieces and of the varying ones, four varying pieces per pass over ξ; and
/// the contacts of its guides (`straight(s)` tells a piece without one).
#[inline(always)]
fn sum_paths<T: Real>(paths: &[ThreadPath], straight: impl Fn(usize) -> bool, n: usize, work: &mut ThreadWork<T>) {
    work.tracks.resize_with(paths.len(), || PathTrack {
        xi: Vec::new(),
        eye_up: Vec::new(),
        engaged: Vec::new(),
    });
    for (i, (p, track)) in paths.iter().zip(&mut work.tracks).enumerate() {
        if !wanted(&work.only, i) {
            track.xi.clear();
            track.engaged.clear();
            continue;
        }
        let bufs = p.spans.iter().map(|&s| &work.spans[s]);
        let constant = bufs.clone().filter_map(|b| b.constant).fold(T::zero(), |x, l| x + l);
        track.xi.clear();
        track.xi.resize(n, constant);
        let mut parts: [&[T]; 4] = [&[]; 4];
        let mut m = 0;
        for b in bufs.filter(|b| b.constant.is_none()) {
            parts[m] = &b.len;
            m += 1;
            if m == 4 {
                add_parts(&mut track.xi, &parts);
                m = 0;
            }
        }
        add_parts(&mut track.xi, &parts[..m]);
        let guides = p.spans.iter().filter(|&&s| !straight(s)).count();
        track.engaged.resize_with(guides, Vec::new);
        for (g, &s) in p.spans.iter().filter(|&&s| !straight(s)).enumerate() {
            track.engaged[g].clone_from(&work.spans[s].on);
        }
    }
}

impl Threads<f64> {
    crate::scalar::widest! {
        /// [`Threads::evaluate_into`] with exact first and second analogs
        /// of ξ (in `Dual2_64`: value, d/dφ, d²/dφ²), from a pose in `f64`
        /// and its analogs in closed form ([`Mechanism::analogs`]), without
        /// a pose of dual numbers. A straight piece of length L = |d|,
        /// d = q − p, has L′ = d·d′/L and L″ = (|d′|² + d·d″ − L′²)/L; a
        /// guide or a cam is evaluated in dual numbers built at each φ from
        /// the same parts. The result equals the dual-number evaluation
        /// (test `analogs_in_closed_form_equal_the_dual_solve`).
        ///
        /// [`Mechanism::analogs`]: crate::mechanism::Mechanism::analogs
        pub fn evaluate_analogs(&self, pose: &Pose<f64>, an: &PoseAnalogs, work: &mut ThreadWork<Dual2_64>) -> Result<(), PathError>
            => evaluate_analogs_in for Threads<f64>
    }

    #[inline(always)]
    fn evaluate_analogs_in(
        &self,
        pose: &Pose<f64>,
        an: &PoseAnalogs,
        work: &mut ThreadWork<Dual2_64>,
    ) -> Result<(), PathError> {
        let n = pose.len();
        assert_eq!(an.len(), n, "analogs of the same cycle");
        let j = Jets { pose, an, n };
        work.spans.resize_with(self.spans.len(), SpanBuf::default);
        // Every piece is computed anew: none is kept from before.
        work.keep.clear();
        for (i, span) in self.spans.iter().enumerate() {
            let buf = &mut work.spans[i];
            buf.reset();
            self.span_analogs(i, span, &j, buf)?;
        }
        sum_paths(&self.paths, |s| matches!(self.spans[s], Span::Straight { .. }), n, work);
        for ((path, track), up) in self.paths.iter().zip(&mut work.tracks).zip(&self.split_up) {
            track.eye_up.clear();
            if let (Some(up), Some(&eye)) = (up, path.nodes.last()) {
                let [p, v, a] = j.tracks(eye);
                track
                    .eye_up
                    .extend((0..n).map(|k| Dual2_64::new(up.dot(&p[k]), up.dot(&v[k]), up.dot(&a[k]))));
            }
        }
        Ok(())
    }

    /// Span `i`'s length (and engagement) with its analogs at every φ.
    #[inline(always)]
    fn span_analogs(&self, i: usize, span: &Span<f64>, j: &Jets, buf: &mut SpanBuf<Dual2_64>) -> Result<(), PathError> {
        let n = j.n;
        let dual = |v: V3<f64>| v.map(Dual2_64::from_re);
        let pose = j.pose;
        match span {
            Span::Straight {
                a, b, constant: true, ..
            } if n > 0 => {
                buf.constant = Some(Dual2_64::from_re(
                    (pose.point(*b, 0) - pose.point(*a, 0)).norm_squared().sqrt(),
                ))
            }
            Span::Straight { a, b, .. } => {
                let [pa, va, aa] = j.tracks(*a);
                let [pb, vb, ab] = j.tracks(*b);
                buf.len.resize(n, Dual2_64::from_re(0.0));
                for (k, l) in buf.len.iter_mut().enumerate() {
                    *l = wrap::straight_jet([pb[k] - pa[k], vb[k] - va[k], ab[k] - aa[k]]);
                }
            }
            Span::Pin {
                a,
                b,
                c,
                axis,
                r,
                sense,
                ..
            } if *r == 0.0 => {
                let (ta, tb, tc) = (j.tracks(*a), j.tracks(*b), j.tracks(*c));
                let at = |t: [&[V3<f64>]; 3], k: usize| [t[0][k], t[1][k], t[2][k]];
                buf.len.resize(n, Dual2_64::from_re(0.0));
                buf.on.resize(n, false);
                let mut inside = false;
                for (k, (l, on)) in buf.len.iter_mut().zip(buf.on.iter_mut()).enumerate() {
                    let (len, engaged, bad) = wrap::thin_pin_jet(at(ta, k), at(tb, k), at(tc, k), *axis, *sense);
                    (*l, *on) = (len, engaged);
                    inside |= bad;
                }
                if inside {
                    let k = (0..n)
                        .find(|&k| wrap::thin_pin_jets(at(ta, k), at(tb, k), at(tc, k), *axis, *sense).is_none())
                        .unwrap_or(0);
                    return Err(self.inside(i, k));
                }
            }
            Span::Pin {
                a,
                b,
                c,
                axis,
                r,
                sense,
                ..
            } => {
                for k in 0..n {
                    let (l, e) = wrap::pin_length(
                        j.jet(*a, k),
                        j.jet(*b, k),
                        j.jet(*c, k),
                        dual(*axis),
                        Dual2_64::from_re(*r),
                        *sense,
                    )
                    .ok_or_else(|| self.inside(i, k))?;
                    buf.len.push(l);
                    buf.on.push(e);
                }
            }
            Span::Cam { a, b, cam, contact } => {
                let c = &self.cams[*cam];
                for k in 0..n {
                    let (l, e) = cam_length(
                        &c.profile,
                        *contact,
                        dual(c.axis),
                        j.jet(*a, k),
                        j.jet(*b, k),
                        j.jet(c.center, k),
                        j.jet(c.marker, k),
                    )
                    .ok_or_else(|| self.inside(i, k))?;
                    buf.len.push(l);
                    buf.on.push(e);
                }
            }
        }
        Ok(())
    }
}

/// `xi[k] += Σ_j parts[j][k]` for up to four parts in one pass.
#[inline]
fn add_parts<T: Real>(xi: &mut [T], parts: &[&[T]]) {
    match *parts {
        [] => {}
        [a] => xi.iter_mut().zip(a).for_each(|(x, a)| *x += *a),
        [a, b] => xi.iter_mut().zip(a).zip(b).for_each(|((x, a), b)| *x += *a + *b),
        [a, b, c] => xi
            .iter_mut()
            .zip(a)
            .zip(b)
            .zip(c)
            .for_each(|(((x, a), b), c)| *x += *a + *b + *c),
        [a, b, c, d, ..] => xi
            .iter_mut()
            .zip(a)
            .zip(b)
            .zip(c)
            .zip(d)
            .for_each(|((((x, a), b), c), d)| *x += (*a + *b) + (*c + *d)),
    }
}

/// Length of the thread `p → q` on a cam placed by its centre and marker.
fn cam_length<T: Real>(
    profile: &cam::Profile,
    model: CamModel,
    axis: V3<T>,
    p: V3<T>,
    q: V3<T>,
    center: V3<T>,
    marker: V3<T>,
) -> Option<(T, bool)> {
    let pl = cam::CamPlacement::new(center, marker, axis)?;
    let contact = match model {
        CamModel::Exact { sense } => cam::exact_contact(profile, &pl, p, q, sense),
        CamModel::Offset { gamma_rad } => cam::offset_contact(profile, &pl, p, q, gamma_rad),
    }?;
    Some((contact.length, contact.engaged))
}

fn normal_of<T: Real>(pl: &Plane<T>) -> V3<T> {
    match &pl.0 {
        None => V3::z(),
        Some(f) => f.dir_to_world(V3::z()),
    }
}

/// An interval of φ, degrees (`to` may exceed 360 when it wraps).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Interval {
    pub from_deg: f64,
    pub to_deg: f64,
}

/// Maximal runs where `flag[k]` holds, as φ intervals from the first to the
/// last sample of each run on the cycle grid `phis`, joining a run that
/// wraps past the cycle's end (its `to_deg` then exceeds the next turn's
/// start). A run over the whole cycle spans 360°.
pub fn intervals(flag: &[bool], phis: &[f64]) -> Vec<Interval> {
    let n = flag.len();
    if n == 0 {
        return Vec::new();
    }
    if flag.iter().all(|f| *f) {
        return vec![Interval {
            from_deg: phis[0],
            to_deg: phis[0] + 360.0,
        }];
    }
    // Start scanning just after a false entry so a wrapping run is whole.
    let start = (0..n).find(|&k| !flag[k]).unwrap_or(0);
    let mut out = Vec::new();
    let mut k = 0;
    while k < n {
        let i = (start + k) % n;
        if flag[i] {
            let first = k;
            while k < n && flag[(start + k) % n] {
                k += 1;
            }
            let a = phis[(start + first) % n];
            let b = phis[(start + k - 1) % n];
            let b = if b < a { b + 360.0 } else { b };
            out.push(Interval { from_deg: a, to_deg: b });
        } else {
            k += 1;
        }
    }
    out.sort_by(|x, y| x.from_deg.total_cmp(&y.from_deg));
    out
}

/// Positions and closed-form analogs of a solved cycle, read as dual
/// numbers (value, d/dφ, d²/dφ²).
struct Jets<'a> {
    pose: &'a Pose<f64>,
    an: &'a PoseAnalogs,
    n: usize,
}

impl<'a> Jets<'a> {
    /// A point as a dual vector at the k-th φ.
    #[inline(always)]
    fn jet(&self, slot: usize, k: usize) -> V3<Dual2_64> {
        let (p, v, a) = (self.pose.point(slot, k), self.an.vel(slot, k), self.an.acc(slot, k));
        V3::new(
            Dual2_64::new(p.x, v.x, a.x),
            Dual2_64::new(p.y, v.y, a.y),
            Dual2_64::new(p.z, v.z, a.z),
        )
    }

    /// A point's positions and analogs over the cycle, cut to its length.
    #[inline(always)]
    fn tracks(&self, slot: usize) -> [&'a [V3<f64>]; 3] {
        let n = self.n;
        [
            &self.pose.track(slot)[..n],
            &self.an.vel_track(slot)[..n],
            &self.an.acc_track(slot)[..n],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_join_a_run_that_wraps() {
        let phis: Vec<f64> = (0..12).map(|k| k as f64 * 30.0).collect();
        let flag = [
            true, true, false, false, true, true, true, false, false, false, true, true,
        ];
        let iv = intervals(&flag, &phis);
        assert_eq!(iv.len(), 2);
        assert_eq!((iv[0].from_deg, iv[0].to_deg), (120.0, 180.0));
        assert_eq!((iv[1].from_deg, iv[1].to_deg), (300.0, 390.0));
        assert_eq!(intervals(&[true; 4], &phis[..4])[0].to_deg, 360.0);
        assert!(intervals(&[false; 4], &phis[..4]).is_empty());
    }

    /// ξ with analogs from the `f64` pose and its closed-form analogs
    /// equals the dual-number solve's, for every preset with thread paths
    /// whose groups all have a closed form, at every φ of a cycle; and the
    /// same guides bear at the same φ.
    #[test]
    fn analogs_in_closed_form_equal_the_dual_solve() {
        use crate::mechanism::Phi;
        use crate::model::Model;
        let mut covered = 0;
        for preset in crate::presets::ALL {
            let model = Model::preset(preset.name).unwrap();
            let params = model.defaults();
            let crate::model::Machine {
                mechanism: mech,
                threads,
            } = model.machine::<f64>(&params).unwrap();
            let Some(threads) = &threads else { continue };
            if !mech.has_closed_form_analogs() {
                continue;
            }
            covered += 1;
            let phis_deg: Vec<f64> = (0..120)
                .map(|k| model.phi_start_deg() + 3.0 * k as f64 + 0.37)
                .collect();
            let phis = Phi::<f64>::table(&phis_deg);
            let mut pose = mech.new_pose(phis.len());
            mech.solve(&phis, &mut pose).unwrap();
            let mut an = PoseAnalogs::new(mech.n_points(), phis.len());
            mech.analogs(&phis, &pose, &mut an).unwrap();
            let mut work = ThreadWork::default();
            threads.evaluate_analogs(&pose, &an, &mut work).unwrap();

            let crate::model::Machine {
                mechanism: dual,
                threads: dual_threads,
            } = model.machine::<Dual2_64>(&params).unwrap();
            let mut dpose = dual.new_pose(phis.len());
            dual.solve(&Phi::table(&phis_deg), &mut dpose).unwrap();
            let reference = dual_threads.as_ref().unwrap().evaluate(&dpose, None).unwrap();
            for (p, (got, want)) in threads.paths.iter().zip(work.tracks.iter().zip(&reference)) {
                assert_eq!(got.engaged, want.engaged, "{} {}", preset.name, p.name);
                for (k, (x, y)) in got.xi.iter().zip(&want.xi).enumerate() {
                    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * (1.0 + b.abs());
                    assert!(
                        close(x.re, y.re, 1e-12) && close(x.v1, y.v1, 1e-9) && close(x.v2, y.v2, 1e-8),
                        "{} {} at φ {}: {x:?} vs {y:?}",
                        preset.name,
                        p.name,
                        phis_deg[k]
                    );
                }
            }
        }
        assert!(
            covered >= 2,
            "only {covered} presets with threads have closed-form analogs"
        );
    }

    /// The turns kept from the first φ ([`ThreadPath::fixed_turn`]) are
    /// those computed afresh at every φ, bit for bit, on every preset; and
    /// on the MF-7923D they are the eyelets among the fixed guides (G8
    /// rides on the needle bar).
    #[test]
    fn fixed_turns_kept_equal_turns_computed_at_every_phi() {
        use crate::mechanism::Phi;
        use crate::model::Model;
        let mut kept = 0;
        for preset in crate::presets::ALL {
            let model = Model::preset(preset.name).unwrap();
            let crate::model::Machine {
                mechanism: mech,
                threads,
            } = model.machine::<f64>(&model.defaults()).unwrap();
            let Some(threads) = &threads else { continue };
            let phis_deg: Vec<f64> = (0..90).map(|k| model.phi_start_deg() + 4.0 * k as f64).collect();
            let phis = Phi::<f64>::table(&phis_deg);
            let mut pose = mech.new_pose(phis.len());
            mech.solve(&phis, &mut pose).unwrap();
            for path in threads.paths.iter() {
                kept += path.fixed_turn.iter().filter(|&&f| f).count();
                let mut turns = Turns::default();
                for k in 0..phis.len() {
                    let fresh = threads.wrap_angles(path, &pose, k, &mut Turns::default()).to_vec();
                    let reused = threads.wrap_angles(path, &pose, k, &mut turns);
                    assert_eq!(
                        reused,
                        fresh.as_slice(),
                        "{} {} at φ {}",
                        preset.name,
                        path.name,
                        phis_deg[k]
                    );
                }
            }
        }
        assert!(kept > 0, "no preset has a turn between fixed guides");
        let model = Model::preset("mf7923d").unwrap();
        let machine = model.machine::<f64>(&model.defaults()).unwrap();
        let threads = machine.threads.unwrap();
        let n1_a = threads.paths.iter().find(|p| p.name == "n1_A").unwrap();
        let fixed: Vec<&str> = (0..n1_a.nodes.len())
            .filter(|&i| n1_a.fixed_turn[i])
            .map(|i| n1_a.node_names[i].as_str())
            .collect();
        assert_eq!(fixed, ["G1_1", "G2_1", "G6_1"]);
    }

    #[test]
    fn only_the_wanted_paths_are_evaluated_bit_for_bit() {
        use crate::mechanism::Phi;
        use crate::model::Model;
        let model = Model::preset("mf7923d").unwrap();
        let params = model.defaults();
        let crate::model::Machine {
            mechanism: mech,
            threads,
        } = model.machine::<f64>(&params).unwrap();
        let threads = threads.unwrap();
        let phis_deg: Vec<f64> = (0..90).map(|k| 4.0 * k as f64).collect();
        let mut pose = mech.new_pose(phis_deg.len());
        mech.solve(&Phi::table(&phis_deg), &mut pose).unwrap();
        let all = threads.evaluate(&pose, None).unwrap();
        // Contour A of each needle: the pieces only contour B runs over
        // are not computed.
        let wanted: Vec<bool> = threads.paths.iter().map(|p| p.name.ends_with("_A")).collect();
        assert!(wanted.iter().any(|&w| w) && wanted.iter().any(|&w| !w));
        let mut work = ThreadWork::only_paths(wanted.clone());
        for _ in 0..2 {
            threads.evaluate_into(&pose, None, &mut work).unwrap();
            let skipped = work.skip.iter().filter(|&&s| s).count();
            assert!(skipped > 0, "no piece skipped");
            for (i, (got, want)) in work.tracks.iter().zip(&all).enumerate() {
                if wanted[i] {
                    let bits = |t: &PathTrack<f64>| t.xi.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(got), bits(want), "{}", threads.paths[i].name);
                    assert_eq!(got.eye_up, want.eye_up);
                    assert_eq!(got.engaged, want.engaged);
                } else {
                    assert!(got.xi.is_empty() && got.eye_up.is_empty(), "{}", threads.paths[i].name);
                }
            }
        }
    }

    #[test]
    fn conventions() {
        assert_eq!(Convention::Release.take_up(90.0, 100.0), 10.0);
        assert_eq!(Convention::Feed { elongation_mm: 6.0 }.take_up(90.0, 100.0), -4.0);
    }
}
