//! Model files: loading, checking, parameters, and resolution into a
//! [`Mechanism`] that can be solved at any φ.
//!
//! ```
//! use stitchkin::model::Model;
//! let model = Model::preset("needle876").unwrap();
//! let mut params = model.defaults();
//! model.set(&mut params, "alpha", 20.0).unwrap();
//! let mech = model.mechanism::<f64>(&params).unwrap();
//! assert!(mech.n_points() > 0);
//! ```

pub mod expr;
pub mod file;
mod load;
mod physics;
mod resolve;
pub(crate) mod spans;
pub mod stitch_setup;

use std::sync::Arc;

use crate::error::{Input, ModelError, ParamError, did_you_mean};
use crate::mechanism::Mechanism;
use crate::scalar::Real;
use crate::thread::ThreadPath;
use expr::Expr;
pub use file::{AngleUnit, LengthUnit, ModelFile, ModelUnits, ParamKind, Provenance, Unit};
use spans::KeyPath;

/// Index of a compiled quantity (an expression of parameters).
pub(crate) type QuantityId = usize;

/// The largest magnitude of a value of a model file (mm or deg): far beyond
/// any machine, far below where squares and sums overflow.
pub const MAX_MAGNITUDE: f64 = 1.0e6;

/// A parameter as declared.
#[derive(Debug, Clone)]
pub struct ParamDef {
    pub name: String,
    pub unit: Unit,
    /// Nominal value (settable parameters).
    pub value: Option<f64>,
    /// Derived parameters' expression.
    pub expr: Option<Expr>,
    pub range: Option<[f64; 2]>,
    pub source: Option<String>,
    pub provenance: Option<Provenance>,
    /// What it is on the machine: as the file declares it, or the default
    /// (`docs/model-format.md` §4).
    pub kind: ParamKind,
    /// Whether the file declares `kind` (otherwise it is the default).
    pub kind_declared: bool,
    /// The part or quantity in plain words.
    pub label: Option<String>,
    /// One sentence: what the part is and which way the value moves it.
    pub what: Option<String>,
    /// What a technician does to raise the value.
    pub increase: Option<String>,
    /// What a technician does to lower the value.
    pub decrease: Option<String>,
}

impl ParamDef {
    pub fn is_derived(&self) -> bool {
        self.expr.is_some()
    }

    /// A machine setting with room to move: a range `[lo, hi]`, lo < hi.
    pub fn is_adjustable_setting(&self) -> bool {
        self.kind == ParamKind::Setting && !self.is_derived() && self.range.is_some_and(|[lo, hi]| lo < hi)
    }

    /// The label, or the name when the file gives none.
    pub fn label_or_name(&self) -> &str {
        self.label.as_deref().unwrap_or(&self.name)
    }
    pub fn unit_str(&self) -> &'static str {
        self.unit.as_str()
    }

    /// `value` of this parameter (in its unit) in the unit results are
    /// given in: mm for a length, deg for an angle.
    pub fn to_result_unit(&self, value: f64) -> f64 {
        value * self.unit.to_result_unit()
    }

    /// A value in the unit results are given in (mm, deg) in this
    /// parameter's unit.
    pub fn from_result_unit(&self, value: f64) -> f64 {
        value / self.unit.to_result_unit()
    }
}

#[derive(Debug, Clone)]
pub(crate) struct FrameDef {
    pub name: String,
    pub parent: Option<usize>,
    pub origin: Option<[QuantityId; 3]>,
    pub rotate: Vec<(usize, QuantityId)>,
}

#[derive(Debug, Clone)]
pub(crate) enum PointKind {
    Fixed { frame: usize, coords: [QuantityId; 3] },
    Moving,
}

/// A direction: a named axis of a frame with a sign, or a vector.
#[derive(Debug, Clone)]
pub(crate) enum AxisDef {
    Named(usize, f64),
    Vector([QuantityId; 3], KeyPath),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ClosureRef {
    Unknown(usize),
    Known(usize),
}

#[derive(Debug, Clone)]
pub(crate) enum ClosureDef {
    Distance {
        a: ClosureRef,
        b: ClosureRef,
        l: QuantityId,
    },
    OnLine {
        p: usize,
        h: usize,
        t: usize,
    },
}

/// A step before its parameters are resolved.
#[derive(Debug, Clone)]
pub(crate) enum StepDef {
    Crank {
        center: usize,
        out: usize,
        frame: usize,
        axis: AxisDef,
        zero_dir: Option<AxisDef>,
        radius: QuantityId,
        phase: QuantityId,
        speed: f64,
    },
    Rrr {
        p1: usize,
        p2: usize,
        l1: QuantityId,
        l2: QuantityId,
        sign: f64,
        plane: usize,
        out: usize,
    },
    Rrp {
        from: usize,
        through: usize,
        toward: Option<usize>,
        dir: Option<QuantityId>,
        offset: QuantityId,
        l: QuantityId,
        sign: f64,
        plane: usize,
        out: usize,
    },
    Rpr {
        from: usize,
        pivot: usize,
        e: QuantityId,
        d: QuantityId,
        plane: usize,
        out: usize,
    },
    Rssr {
        from: usize,
        l: QuantityId,
        pivot: usize,
        frame: usize,
        axis: AxisDef,
        r: QuantityId,
        offset: QuantityId,
        zero_dir: Option<AxisDef>,
        sign: f64,
        out: usize,
    },
    PointOnLine {
        from: usize,
        through: usize,
        toward: Option<usize>,
        dir: Option<AxisDef>,
        frame: usize,
        l: QuantityId,
        sign: f64,
        out: usize,
    },
    Rigid {
        base: [usize; 2],
        d: QuantityId,
        angle: QuantityId,
        lift: QuantityId,
        plane: usize,
        out: usize,
    },
    Rigid3 {
        frame: [usize; 3],
        at: [QuantityId; 3],
        out: usize,
    },
    Offset {
        from: usize,
        by: [QuantityId; 3],
        frame: usize,
        out: usize,
    },
    Newton {
        dim: usize,
        plane: usize,
        outs: Vec<usize>,
        guess: Vec<QuantityId>,
        closures: Vec<ClosureDef>,
    },
    CamFollower(Box<load::cam_follower::CamFollowerDef>),
}

impl StepDef {
    pub(crate) fn inputs(&self) -> Vec<usize> {
        match self {
            StepDef::Crank { center, .. } => vec![*center],
            StepDef::Rrr { p1, p2, .. } => vec![*p1, *p2],
            StepDef::Rrp {
                from, through, toward, ..
            }
            | StepDef::PointOnLine {
                from, through, toward, ..
            } => {
                let mut v = vec![*from, *through];
                v.extend(toward);
                v
            }
            StepDef::Rpr { from, pivot, .. } => vec![*from, *pivot],
            StepDef::Rssr { from, pivot, .. } => vec![*from, *pivot],
            StepDef::Rigid { base, .. } => base.to_vec(),
            StepDef::Rigid3 { frame, .. } => frame.to_vec(),
            StepDef::Offset { from, .. } => vec![*from],
            StepDef::CamFollower(c) => {
                let mut v = vec![c.center, c.marker];
                v.extend(c.pivot);
                v
            }
            StepDef::Newton { closures, .. } => {
                let mut v = Vec::new();
                for c in closures {
                    match c {
                        ClosureDef::Distance { a, b, .. } => {
                            for r in [a, b] {
                                if let ClosureRef::Known(s) = r {
                                    v.push(*s);
                                }
                            }
                        }
                        ClosureDef::OnLine { h, t, .. } => v.extend([*h, *t]),
                    }
                }
                v
            }
        }
    }

    pub(crate) fn outputs(&self) -> Vec<usize> {
        match self {
            StepDef::Crank { out, .. }
            | StepDef::Rrr { out, .. }
            | StepDef::Rrp { out, .. }
            | StepDef::Rpr { out, .. }
            | StepDef::Rssr { out, .. }
            | StepDef::PointOnLine { out, .. }
            | StepDef::Rigid { out, .. }
            | StepDef::Rigid3 { out, .. }
            | StepDef::Offset { out, .. } => vec![*out],
            StepDef::CamFollower(c) => vec![c.out],
            StepDef::Newton { outs, .. } => outs.clone(),
        }
    }

    /// Whether the step keeps every point in the world xy-plane.
    fn is_planar_xy(&self) -> bool {
        match self {
            StepDef::Crank { frame, axis, .. } => *frame == 0 && matches!(axis, AxisDef::Named(2, _)),
            StepDef::Rrr { plane, .. } | StepDef::Rrp { plane, .. } | StepDef::Rpr { plane, .. } => *plane == 0,
            StepDef::Rigid { plane, .. } => *plane == 0,
            StepDef::Newton { dim, plane, .. } => *dim == 2 && *plane == 0,
            StepDef::CamFollower(c) => c.plane == 0,
            StepDef::Rssr { .. } | StepDef::PointOnLine { .. } | StepDef::Rigid3 { .. } | StepDef::Offset { .. } => {
                false
            }
        }
    }
}

/// Rigid bodies of a mechanism as sets of point slots: two points on one
/// body keep their distance (a thread segment between them is constant).
pub(crate) fn bodies(steps: &[StepDef], kinds: &[PointKind]) -> Vec<Vec<usize>> {
    let mut bodies: Vec<Vec<usize>> = vec![
        (0..kinds.len())
            .filter(|&i| matches!(kinds[i], PointKind::Fixed { .. }))
            .collect(),
    ];
    // Translating bodies (sliders and points offset from them).
    let mut translating: Vec<usize> = Vec::new();
    let join = |bodies: &mut Vec<Vec<usize>>, on: &[usize], out: usize| {
        if let Some(b) = bodies.iter_mut().find(|b| on.iter().all(|p| b.contains(p))) {
            b.push(out);
        }
    };
    for s in steps {
        match s {
            StepDef::Crank { center, out, .. } => bodies.push(vec![*center, *out]),
            StepDef::Rrr { p1, p2, out, .. } => {
                bodies.push(vec![*p1, *out]);
                bodies.push(vec![*p2, *out]);
            }
            StepDef::Rrp { from, out, .. } | StepDef::PointOnLine { from, out, .. } => {
                bodies.push(vec![*from, *out]);
                translating.push(bodies.len());
                bodies.push(vec![*out]);
            }
            StepDef::Rpr { pivot, out, .. } => bodies.push(vec![*pivot, *out]),
            StepDef::Rssr { from, pivot, out, .. } => {
                bodies.push(vec![*pivot, *out]);
                bodies.push(vec![*from, *out]);
            }
            StepDef::Rigid { base, out, .. } => join(&mut bodies, base, *out),
            StepDef::Rigid3 { frame, out, .. } => join(&mut bodies, frame, *out),
            // A rocking follower turns about its pivot; a translating one
            // slides on its own.
            StepDef::CamFollower(c) => match c.pivot {
                Some(p) => bodies.push(vec![p, c.out]),
                None => bodies.push(vec![c.out]),
            },
            StepDef::Offset { from, out, .. } => match translating.iter().find(|&&b| bodies[b].contains(from)) {
                Some(&b) => bodies[b].push(*out),
                None => {
                    translating.push(bodies.len());
                    bodies.push(vec![*from, *out]);
                }
            },
            StepDef::Newton { closures, outs, .. } => {
                for c in closures {
                    if let ClosureDef::Distance { a, b, .. } = c {
                        let slot = |r: &ClosureRef| match r {
                            ClosureRef::Unknown(u) => outs[*u],
                            ClosureRef::Known(k) => *k,
                        };
                        bodies.push(vec![slot(a), slot(b)]);
                    }
                }
            }
        }
    }
    bodies
}

/// The `[thread]` table, compiled.
#[derive(Debug, Clone)]
pub(crate) struct ThreadsDef {
    pub convention: file::TakeUpConvention,
    pub elongation: Option<QuantityId>,
    pub phi0_deg: Option<f64>,
    pub tension_n: Option<f64>,
    pub paths: Vec<PathDef>,
    pub cams: Vec<CamDef>,
    pub layout: Arc<ThreadLayout>,
    /// Each path's thread physics (`[thread.physics]`), in path order.
    pub physics: Vec<Option<physics::PhysicsDef>>,
}

#[derive(Debug, Clone)]
pub(crate) struct CamDef {
    pub name: String,
    pub center: usize,
    pub marker: usize,
    pub axis: AxisDef,
    pub frame: usize,
    pub profile: ProfileDef,
    /// Smallest curvature numerator over the profile (> 0: convex).
    pub convex_min: f64,
    pub path: KeyPath,
}

#[derive(Debug, Clone)]
pub(crate) enum ProfileDef {
    Disc { r: QuantityId, e: QuantityId },
    Polar { theta: Vec<f64>, rho: Vec<f64> },
}

#[derive(Debug, Clone)]
pub(crate) enum CamContactDef {
    Exact { sense: f64 },
    Offset { gamma: QuantityId },
}

/// The thread paths' structure, which no parameter changes: each path's
/// pieces as indices into one list of distinct pieces (two contours of one
/// needle share their first guides), built once when the model is loaded.
#[derive(Debug)]
pub(crate) struct ThreadLayout {
    pub paths: Arc<[ThreadPath]>,
    /// Each distinct piece, as (path, piece of that path) with its definition.
    pub pieces: Vec<(usize, usize)>,
}

impl ThreadLayout {
    /// The layout of `paths`; `fixed(slot)`: whether a point never moves.
    pub(crate) fn new(paths: &[PathDef], fixed: impl Fn(usize) -> bool) -> ThreadLayout {
        let mut pieces: Vec<(usize, usize)> = Vec::new();
        let mut out = Vec::with_capacity(paths.len());
        for (pi, p) in paths.iter().enumerate() {
            let mut ids = Vec::with_capacity(p.spans.len());
            let mut pin_span = vec![None; p.nodes.len()];
            for (si, sp) in p.spans.iter().enumerate() {
                let id = match pieces.iter().position(|&(pj, sj)| same_piece(&paths[pj].spans[sj], sp)) {
                    Some(id) => id,
                    None => {
                        pieces.push((pi, si));
                        pieces.len() - 1
                    }
                };
                if let SpanDef::Pin { node, .. } | SpanDef::Cam { node, .. } = sp {
                    pin_span[*node] = Some(id);
                }
                ids.push(id);
            }
            // An eyelet between two eyelets, all three fixed.
            let m = p.nodes.len();
            let eyelet = |i: usize| pin_span[i].is_none() && fixed(p.nodes[i]);
            let fixed_turn = (0..m)
                .map(|i| i > 0 && i + 1 < m && eyelet(i - 1) && eyelet(i) && eyelet(i + 1))
                .collect();
            out.push(ThreadPath {
                name: p.name.clone(),
                label: p.label.clone(),
                nodes: p.nodes.clone(),
                node_names: p.node_names.clone(),
                friction: p.friction.clone(),
                spans: ids,
                pin_span,
                fixed_turn,
            });
        }
        ThreadLayout {
            paths: out.into(),
            pieces,
        }
    }
}

/// Whether two pieces are one: the same ends, guide and parameters (where
/// in its path a guide stands does not matter).
fn same_piece(x: &SpanDef, y: &SpanDef) -> bool {
    let same_axis = |p: &AxisDef, q: &AxisDef| match (p, q) {
        (AxisDef::Named(f, s), AxisDef::Named(g, t)) => f == g && s == t,
        (AxisDef::Vector(v, _), AxisDef::Vector(w, _)) => v == w,
        _ => false,
    };
    match (x, y) {
        (
            SpanDef::Straight { a, b, constant },
            SpanDef::Straight {
                a: a2,
                b: b2,
                constant: c2,
            },
        ) => (a, b, constant) == (a2, b2, c2),
        (
            SpanDef::Pin {
                a,
                b,
                c,
                axis,
                frame,
                r,
                sense,
                ..
            },
            SpanDef::Pin {
                a: a2,
                b: b2,
                c: c2,
                axis: x2,
                frame: f2,
                r: r2,
                sense: s2,
                ..
            },
        ) => (a, b, c, frame, r) == (a2, b2, c2, f2, r2) && sense == s2 && same_axis(axis, x2),
        (
            SpanDef::Cam { a, b, cam, contact, .. },
            SpanDef::Cam {
                a: a2,
                b: b2,
                cam: m2,
                contact: k2,
                ..
            },
        ) => {
            (a, b, cam) == (a2, b2, m2)
                && match (contact, k2) {
                    (CamContactDef::Exact { sense }, CamContactDef::Exact { sense: s2 }) => sense == s2,
                    (CamContactDef::Offset { gamma }, CamContactDef::Offset { gamma: g2 }) => gamma == g2,
                    _ => false,
                }
        }
        _ => false,
    }
}

#[derive(Debug, Clone)]
pub(crate) struct PathDef {
    pub name: String,
    pub label: Option<String>,
    pub nodes: Vec<usize>,
    pub node_names: Vec<String>,
    pub friction: Vec<f64>,
    pub spans: Vec<SpanDef>,
}

#[derive(Debug, Clone)]
pub(crate) enum SpanDef {
    Straight {
        a: usize,
        b: usize,
        constant: bool,
    },
    Pin {
        a: usize,
        b: usize,
        c: usize,
        axis: AxisDef,
        frame: usize,
        r: QuantityId,
        sense: f64,
        node: usize,
    },
    Cam {
        a: usize,
        b: usize,
        cam: usize,
        contact: CamContactDef,
        node: usize,
    },
}

#[derive(Debug, Clone)]
pub(crate) enum MeasureDef {
    Distance {
        a: usize,
        b: usize,
    },
    LineDeviation {
        p: usize,
        h: usize,
        t: usize,
        plane: Option<usize>,
    },
    Coordinate {
        p: usize,
        from: Option<usize>,
        frame: usize,
        axis: AxisDef,
    },
}

/// What a dyad's transmission angle is called in output.
#[derive(Debug, Clone)]
pub struct DyadInfo {
    /// Key in column names: `mu_{key}_deg`.
    pub key: String,
    /// Label for messages.
    pub label: String,
}

/// Parameter values, one per declared parameter (derived ones are filled in
/// when a mechanism is resolved).
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    pub values: Vec<f64>,
}

/// A cam as the model file declares it, in the file's own words.
#[derive(Debug, Clone, PartialEq)]
pub struct CamDeclaration {
    /// The shaft's centre point.
    pub center: String,
    /// The point that turns with the shaft.
    pub marker: String,
    /// The shaft's axis as TOML (`"z"`, `[0, 0, 1]`), when declared.
    pub axis_toml: Option<String>,
    /// The frame the axis is given in, when declared.
    pub frame: Option<String>,
}

/// A model resolved with one setting: the mechanism and, when the model
/// has thread paths, the paths it moves. The mechanism knows nothing of
/// the threads; the threads read the mechanism's solved points.
#[derive(Debug, Clone)]
pub struct Machine<T: Real> {
    pub mechanism: Mechanism<T>,
    pub threads: Option<crate::thread::Threads<T>>,
}

/// A checked, compiled model. Cheap to resolve with new parameter values.
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) file_name: String,
    pub(crate) text: Arc<str>,
    file: ModelFile,
    pub(crate) params: Vec<ParamDef>,
    param_order: Vec<usize>,
    exprs: Vec<Expr>,
    expr_paths: Vec<KeyPath>,
    positive: Vec<(QuantityId, KeyPath, &'static str)>,
    within: Vec<(QuantityId, KeyPath, &'static str, f64)>,
    frames: Vec<FrameDef>,
    /// Point names by slot.
    pub(crate) point_names: Vec<String>,
    point_kinds: Vec<PointKind>,
    steps: Vec<StepDef>,
    labels: Arc<[String]>,
    measures: Vec<MeasureDef>,
    /// Measure names, in order.
    pub(crate) measure_names: Vec<String>,
    /// Dyads with a transmission angle, in order.
    pub(crate) dyads: Vec<DyadInfo>,
    /// Link-angle names (`angle_A_B`), in order.
    pub(crate) link_angle_names: Vec<String>,
    /// Points printed by default.
    pub(crate) output_points: Vec<usize>,
    /// Every point stays in the world xy-plane (z columns are omitted).
    pub(crate) planar: bool,
    threads: Option<ThreadsDef>,
    stitch: Option<stitch_setup::StitchDef>,
    /// Which parameters besides the machine settings a search may adjust
    /// when they are named ([`Model::allow_adjusting`]).
    allowed: AllowedKinds,
}

/// The kinds of parameter, besides the machine settings, that a search
/// (`tune`, a nomogram) may adjust when they are named.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct AllowedKinds {
    inputs: bool,
    dimensions: bool,
}

impl Model {
    /// Loads a model from TOML text; `file_name` is used in messages.
    pub fn from_toml_str(text: &str, file_name: &str) -> Result<Model, Box<ModelError>> {
        let mut ld = load::Loader::new(file_name, text);
        let file = ld.parse(text)?;
        let param_order = ld.parameters(&file)?;
        ld.frames(&file)?;
        ld.fixed_points(&file)?;
        ld.declare_moving(&file)?;
        let drivers = ld.drivers(&file)?;
        let groups = ld.groups(&file)?;
        let keys: Vec<(String, &'static str)> = file
            .groups
            .iter()
            .map(|g| (load::group_key(g), load::group_kind(g)))
            .collect();
        let mut all: Vec<(StepDef, String, KeyPath)> = drivers
            .into_iter()
            .enumerate()
            .map(|(k, (s, l))| (s, l, KeyPath::root().key("drivers").index(k)))
            .collect();
        // Groups keep their dyad key for transmission-angle columns.
        let mut group_keys = std::collections::HashMap::new();
        for ((s, l, p), (key, _)) in groups.into_iter().zip(keys.iter()) {
            group_keys.insert(l.clone(), key.clone());
            all.push((s, l, p));
        }
        let ordered = ld.order(all)?;
        let kinds_now: Vec<PointKind> = ld.points.iter().map(|(_, k)| k.clone()).collect();
        let steps_now: Vec<StepDef> = ordered.iter().map(|(s, _)| s.clone()).collect();
        let body_sets = bodies(&steps_now, &kinds_now);
        let same_body = |a: usize, b: usize| a == b || body_sets.iter().any(|s| s.contains(&a) && s.contains(&b));
        let threads = ld.threads(&file, &same_body)?;
        let stitch = ld.stitch(&file, threads.as_ref())?;
        ld.param_kinds(&file, threads.as_ref())?;
        let measures = ld.measures(&file)?;
        let output_points = ld.output_points(&file)?;
        let point_names = ld.point_names();
        let point_kinds: Vec<PointKind> = ld.points.iter().map(|(_, k)| k.clone()).collect();
        let (steps, labels): (Vec<StepDef>, Vec<String>) = ordered.into_iter().unzip();

        let mut dyads = Vec::new();
        let mut link_angle_names = Vec::new();
        for (s, label) in steps.iter().zip(&labels) {
            let key = group_keys.get(label).cloned().unwrap_or_default();
            let n = |i: &usize| point_names[*i].as_str();
            match s {
                StepDef::Rrr { p1, p2, out, .. } => {
                    link_angle_names.push(format!("angle_{}_{}", n(p1), n(out)));
                    link_angle_names.push(format!("angle_{}_{}", n(p2), n(out)));
                }
                StepDef::Rrp { from, out, .. } => link_angle_names.push(format!("angle_{}_{}", n(from), n(out))),
                StepDef::Rpr { pivot, out, .. } => link_angle_names.push(format!("angle_{}_{}", n(pivot), n(out))),
                StepDef::Rssr { pivot, out, .. } => link_angle_names.push(format!("angle_{}_{}", n(pivot), n(out))),
                _ => {}
            }
            if matches!(
                s,
                StepDef::Rrr { .. }
                    | StepDef::Rrp { .. }
                    | StepDef::Rpr { .. }
                    | StepDef::Rssr { .. }
                    | StepDef::PointOnLine { .. }
            ) {
                dyads.push(DyadInfo {
                    key,
                    label: label.clone(),
                });
            }
        }
        let fixed_flat = point_kinds.iter().all(|k| match k {
            PointKind::Fixed { frame, coords } => {
                *frame == 0 && matches!(ld.exprs[coords[2]], Expr::Num(z) if z == 0.0)
            }
            PointKind::Moving => true,
        });
        let flat = |q: QuantityId| matches!(ld.exprs[q], Expr::Num(z) if z == 0.0);
        let planar = fixed_flat
            && steps
                .iter()
                .all(|s| s.is_planar_xy() || matches!(s, StepDef::Offset { by, frame: 0, .. } if flat(by[2])))
            && steps.iter().all(
                |s| !matches!(s, StepDef::Rigid { lift, .. } if !matches!(ld.exprs[*lift], Expr::Num(z) if z == 0.0)),
            );
        let frames = std::mem::take(&mut ld.frames);
        let params = std::mem::take(&mut ld.params);
        let exprs = std::mem::take(&mut ld.exprs);
        let expr_paths = std::mem::take(&mut ld.expr_paths);
        let positive = std::mem::take(&mut ld.positive);
        let within = std::mem::take(&mut ld.within);
        let (file_name, text, _) = ld.into_parts();
        let model = Model {
            file_name,
            text,
            file,
            params,
            param_order,
            exprs,
            expr_paths,
            positive,
            within,
            frames,
            point_names,
            point_kinds,
            steps,
            labels: labels.into(),
            measure_names: measures.iter().map(|(n, _)| n.clone()).collect(),
            measures: measures.into_iter().map(|(_, m)| m).collect(),
            dyads,
            link_angle_names,
            output_points,
            planar,
            threads,
            stitch,
            allowed: AllowedKinds::default(),
        };
        // Resolve once with the nominal values so impossible geometry is
        // reported at load time.
        model.machine::<f64>(&model.defaults())?;
        Ok(model)
    }

    /// Loads a model file from disk.
    pub fn from_path(path: &std::path::Path) -> Result<Model, crate::Error> {
        let bytes = std::fs::read(path)
            .map_err(|e| crate::Error::Io(crate::error::IoError::os("read model file", Some(path), e)))?;
        Ok(Model::from_toml_bytes(&bytes, &path.display().to_string())?)
    }

    /// Reads a model from the bytes of a file: UTF-8 text, or an error at the
    /// first byte that is not (line, column and byte).
    pub fn from_toml_bytes(bytes: &[u8], file_name: &str) -> Result<Model, Box<ModelError>> {
        match std::str::from_utf8(bytes) {
            Ok(text) => Model::from_toml_str(text, file_name),
            Err(e) => {
                let at = e.valid_up_to();
                Err(Box::new(ModelError {
                    file: file_name.to_string(),
                    // The text up to the bad byte is exact; after it, shown with
                    // replacement characters.
                    text: String::from_utf8_lossy(bytes).into(),
                    span: Some(at..at + '\u{FFFD}'.len_utf8()),
                    path: String::new(),
                    message: format!("byte {at} (0x{:02x}) is not UTF-8 text", bytes[at]),
                    help: Some(
                        "model files are UTF-8: save the file as UTF-8 (a text editor's \"encoding\" setting), or \
                         remove the character there"
                            .into(),
                    ),
                }))
            }
        }
    }

    /// A shipped preset by name (see [`crate::presets`]).
    pub fn preset(name: &str) -> Result<Model, crate::Error> {
        let p = crate::presets::get(name).map_err(crate::Error::Param)?;
        Ok(Model::from_toml_str(p.toml, &format!("preset:{}", p.name))?)
    }

    /// Nominal parameter values.
    pub fn defaults(&self) -> Params {
        Params {
            values: self.params.iter().map(|p| p.value.unwrap_or(0.0)).collect(),
        }
    }

    /// Index of a parameter.
    pub fn param_index(&self, name: &str) -> Option<usize> {
        self.params.iter().position(|p| p.name == name)
    }

    /// Sets a parameter, checking that it exists, is settable and lies in
    /// its adjustable range.
    pub fn set(&self, params: &mut Params, name: &str, value: f64) -> Result<(), ParamError> {
        let Some(i) = self.param_index(name) else {
            let hint = did_you_mean(name, self.params.iter().map(|p| p.name.as_str()));
            return Err(ParamError::general(
                format!("the model has no parameter `{name}`"),
                Some(match hint {
                    Some(s) => format!("did you mean `{s}`?"),
                    None => format!(
                        "its parameters are: {}",
                        self.params
                            .iter()
                            .filter(|p| !p.is_derived())
                            .map(|p| p.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                }),
            ));
        };
        let p = &self.params[i];
        if p.is_derived() {
            return Err(ParamError::general(
                format!("`{name}` is derived from other parameters and cannot be set"),
                Some("set the parameters its expression uses instead".into()),
            ));
        }
        if !value.is_finite() {
            return Err(ParamError::general(format!("`{name}` must be a finite number"), None));
        }
        if value.abs() > MAX_MAGNITUDE {
            return Err(ParamError::general(
                format!("{name} = {value} is too large to compute with"),
                Some(format!("give a value within ±{MAX_MAGNITUDE} {}", p.unit_str())),
            ));
        }
        if let Some([lo, hi]) = p.range
            && (value < lo || value > hi)
        {
            return Err(ParamError::general(
                format!(
                    "{name} = {value} {} is outside its adjustable range {lo}…{hi} {}",
                    p.unit_str(),
                    p.unit_str()
                ),
                Some(format!("choose a value between {lo} and {hi}")),
            ));
        }
        params.values[i] = value;
        Ok(())
    }

    /// Parses `NAME=VALUE` and applies it.
    pub fn set_str(&self, params: &mut Params, assignment: &str) -> Result<(), ParamError> {
        let Some((name, value)) = assignment.split_once('=') else {
            return Err(ParamError::new(
                Input::Set,
                format!("`{assignment}` is not an assignment"),
                Some("write NAME=VALUE, e.g. alpha=20".into()),
            ));
        };
        let (name, value) = (name.trim(), value.trim());
        let v: f64 = value.parse().map_err(|_| {
            ParamError::new(
                Input::Set,
                format!("`{assignment}`: `{value}` is not a number"),
                Some("values are plain numbers in the parameter's unit (the model's length or angle unit, N or a pure number)".into()),
            )
        })?;
        self.set(params, name, v).map_err(|e| e.in_input(Input::Set))
    }

    /// Resolves every parameter with `params` into a solvable mechanism
    /// (without the thread paths: see [`Self::machine`]).
    pub fn mechanism<T: Real>(&self, params: &Params) -> Result<Mechanism<T>, Box<ModelError>> {
        let base: Vec<T> = params.values.iter().map(|&v| T::cst(v)).collect();
        self.mechanism_with(&base)
    }

    /// Like [`Self::mechanism`] with parameter values of type `T`, so the
    /// result carries derivatives with respect to seeded parameters.
    pub fn mechanism_with<T: Real>(&self, base: &[T]) -> Result<Mechanism<T>, Box<ModelError>> {
        let q = self.quantities(base)?;
        Ok(resolve::machine(self, &q, false)?.mechanism)
    }

    /// Resolves every parameter with `params` into the mechanism and the
    /// thread paths it moves.
    pub fn machine<T: Real>(&self, params: &Params) -> Result<Machine<T>, Box<ModelError>> {
        let base: Vec<T> = params.values.iter().map(|&v| T::cst(v)).collect();
        self.machine_with(&base)
    }

    /// Like [`Self::machine`] with parameter values of type `T`.
    pub fn machine_with<T: Real>(&self, base: &[T]) -> Result<Machine<T>, Box<ModelError>> {
        let q = self.quantities(base)?;
        resolve::machine(self, &q, true)
    }

    /// Every parameter's value with `params`, derived ones evaluated (in
    /// parameter order, as `params.values`).
    pub fn parameter_values(&self, params: &Params) -> Result<Vec<f64>, Box<ModelError>> {
        let mut pv = params.values.clone();
        for &i in &self.param_order {
            if let Some(e) = &self.params[i].expr {
                pv[i] = e.eval(&pv);
            }
        }
        match self.params.iter().zip(&pv).find(|(_, v)| !v.is_finite()) {
            // quantities() says which and why.
            Some(_) => self.quantities(&params.values).map(|_| pv),
            None => Ok(pv),
        }
    }

    /// What to check when derived parameter `i` has no value: the values
    /// its expression reads, the settable ones first.
    fn derived_help<T: Real>(&self, i: usize, pv: &[T]) -> String {
        let mut used = Vec::new();
        if let Some(e) = &self.params[i].expr {
            e.params(&mut used);
        }
        used.sort_unstable();
        used.dedup();
        used.sort_by_key(|&j| self.params[j].is_derived());
        let values: Vec<String> = used
            .iter()
            .map(|&j| {
                let p = &self.params[j];
                format!("{} = {} {}", p.name, crate::format::fmt_num(pv[j].re()), p.unit_str())
            })
            .collect();
        format!(
            "its expression reads {}; with these values it takes acos or asin of a number outside −1…1, a square \
             root of a negative number or divides by zero: the dimensions cannot form the geometry the expression \
             describes. Move the parameters you set back toward their defaults.",
            values.join(", ")
        )
    }

    /// Every value of the file (each expression) resolved with the
    /// parameter values `base`, checked finite and, where required, positive.
    pub(crate) fn quantities<T: Real>(&self, base: &[T]) -> Result<Vec<T>, Box<ModelError>> {
        let mut pv: Vec<T> = base.to_vec();
        for &i in &self.param_order {
            if let Some(e) = &self.params[i].expr {
                pv[i] = e.eval(&pv);
            }
        }
        for (i, p) in self.params.iter().enumerate() {
            if p.is_derived() && !pv[i].re().is_finite() {
                return Err(self.error_at(
                    &KeyPath::root().key("parameters").key(&p.name).key("expr"),
                    format!(
                        "derived parameter `{}` evaluates to {} with these values",
                        p.name,
                        pv[i].re()
                    ),
                    Some(self.derived_help(i, &pv)),
                ));
            }
        }
        let q: Vec<T> = self.exprs.iter().map(|e| e.eval(&pv)).collect();
        for (k, v) in q.iter().enumerate() {
            if !v.re().is_finite() {
                return Err(self.error_at(
                    &self.expr_paths[k],
                    format!("this value evaluates to {} with the current parameters", v.re()),
                    Some("check the expression's inputs (division by zero, acos/sqrt out of range)".into()),
                ));
            }
            // Lengths this large square to infinity in the closures: caught
            // here, where the file says which value it is.
            if v.re().abs() > MAX_MAGNITUDE {
                return Err(self.error_at(
                    &self.expr_paths[k],
                    format!("this value is {}, too large to compute with", v.re()),
                    Some(format!(
                        "a sewing machine's lengths, coordinates and angles stay within ±{MAX_MAGNITUDE} (mm or deg)"
                    )),
                ));
            }
        }
        for (qi, path, what, max_deg) in &self.within {
            let v = q[*qi].re();
            if v.is_nan() || v.abs() >= *max_deg {
                return Err(self.error_at(
                    path,
                    format!("{what} = {v}° is outside −{max_deg}°…{max_deg}°"),
                    Some(format!("give an angle strictly between −{max_deg}° and {max_deg}°")),
                ));
            }
        }
        for (qi, path, what) in &self.positive {
            if q[*qi].re() <= 0.0 {
                return Err(self.error_at(
                    path,
                    format!("{what} must be positive, got {} mm", q[*qi].re()),
                    Some("lengths and radii are positive numbers of mm".into()),
                ));
            }
        }
        Ok(q)
    }

    fn error_at(&self, path: &KeyPath, message: impl Into<String>, help: Option<String>) -> Box<ModelError> {
        let spans = spans::SpanIndex::new(&self.text);
        Box::new(ModelError {
            file: self.file_name.clone(),
            text: self.text.clone(),
            span: spans.find(path),
            path: path.to_string(),
            message: message.into(),
            help,
        })
    }

    /// Labels of the solve steps, in solve order.
    pub fn step_labels(&self) -> &[String] {
        &self.labels
    }

    /// The file the model was read from (or `preset:NAME`).
    pub fn file_name(&self) -> &str {
        &self.file_name
    }

    /// The model file's text, for pointing at a place in it.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The parameters as declared, in file order.
    pub fn params(&self) -> &[ParamDef] {
        &self.params
    }

    /// Point names by slot (the order of a cycle's point columns).
    pub fn point_names(&self) -> &[String] {
        &self.point_names
    }

    /// Measure names, in order.
    pub fn measure_names(&self) -> &[String] {
        &self.measure_names
    }

    /// The dyads with a transmission angle, in order.
    pub fn dyads(&self) -> &[DyadInfo] {
        &self.dyads
    }

    /// Link-angle names (`angle_A_B`), in order.
    pub fn link_angle_names(&self) -> &[String] {
        &self.link_angle_names
    }

    /// The slots of the points a cycle prints by default.
    pub fn output_points(&self) -> &[usize] {
        &self.output_points
    }

    /// Whether every point stays in the world xy-plane (a cycle then has no
    /// z columns).
    pub fn is_planar(&self) -> bool {
        self.planar
    }

    /// The model's short name (`[model] name`), as presets are called.
    pub fn name(&self) -> &str {
        &self.file.model.name
    }

    /// The machine's title, when the file gives one.
    pub fn title(&self) -> Option<&str> {
        self.file.model.title.as_deref()
    }

    /// The publication the model follows (`seed`, see docs/references.md).
    pub fn seed(&self) -> Option<&str> {
        self.file.model.seed.as_deref()
    }

    /// Main-shaft speed for real velocities and accelerations, rev/min.
    pub fn rpm(&self) -> Option<f64> {
        self.file.model.rpm
    }

    /// The model's own caveats: reconstructions and transferred results.
    pub fn caveats(&self) -> &[String] {
        &self.file.model.caveats
    }

    /// The model file's free-text notes.
    pub fn notes(&self) -> Option<&str> {
        self.file.model.notes.as_deref()
    }

    /// φ0, where the take-up P is counted from (`[thread] phi0_deg`; by
    /// default the cycle's start), degrees.
    pub fn take_up_phi0_deg(&self) -> f64 {
        self.file
            .thread
            .as_ref()
            .and_then(|t| t.phi0_deg)
            .unwrap_or(self.phi_start_deg())
    }

    /// Whether the model declares thread paths (`[thread]`).
    pub fn has_threads(&self) -> bool {
        self.file.thread.is_some()
    }

    /// The thread paths' names, in file order (empty without `[thread]`).
    pub fn thread_path_names(&self) -> Vec<&str> {
        self.file
            .thread
            .as_ref()
            .map_or_else(Vec::new, |t| t.paths.iter().map(|p| p.name.as_str()).collect())
    }

    /// The stitch the machine makes (`[stitch]`), as declared.
    pub fn stitch_spec(&self) -> Option<&file::StitchFile> {
        self.file.stitch.as_ref()
    }

    /// Whether the model describes the stitch it makes (`[stitch]`).
    pub fn has_stitch(&self) -> bool {
        self.file.stitch.is_some()
    }

    /// The stitch type as the file names it (`"401"`, `"504"`, …), when
    /// the model has `[stitch]`.
    pub fn stitch_type(&self) -> Option<&str> {
        self.file.stitch.as_ref().map(|s| s.stitch_type.as_str())
    }

    /// The units the model's parameters and expressions are written in
    /// (`[model] units`; default mm and deg). Results are in mm and deg
    /// whatever they are.
    pub fn units(&self) -> ModelUnits {
        self.file.model.units.unwrap_or_default()
    }

    /// The parameter the stitch's material thickness (`which` = `"m"`,
    /// `[stitch] m_mm`) or stitch length (`"t"`, `t_mm`) is set through;
    /// `None` without `[stitch]` or where the value is a fixed number.
    pub fn stitch_param(&self, which: &str) -> Option<&str> {
        let s = self.file.stitch.as_ref()?;
        match if which == "m" { &s.m_mm } else { &s.t_mm } {
            file::Value::Expr(name) if self.param_index(name.trim()).is_some() => Some(name.trim()),
            _ => None,
        }
    }

    /// A cam's declaration as the model file writes it (centre, marker,
    /// axis and frame), for writing a synthesised profile back into the
    /// file.
    pub fn cam_declaration(&self, name: &str) -> Option<CamDeclaration> {
        let c = self.file.cams.iter().find(|c| c.name == name)?;
        let value = |v: &file::Value| match v {
            file::Value::Number(x) => crate::format::fmt_num(*x),
            file::Value::Expr(e) => format!("{e:?}"),
        };
        let axis_toml = c.axis.as_ref().map(|ax| match ax {
            file::Axis::Named(s) => format!("{s:?}"),
            file::Axis::Vector(v) => format!("[{}]", v.iter().map(value).collect::<Vec<_>>().join(", ")),
        });
        Some(CamDeclaration {
            center: c.center.clone(),
            marker: c.marker.clone(),
            axis_toml,
            frame: c.frame.clone(),
        })
    }

    /// A cam as declared in the file, by name.
    pub fn cam_spec(&self, name: &str) -> Option<&file::Cam> {
        self.file.cams.iter().find(|c| c.name == name)
    }

    /// The file as parsed, in the file's own shape (`schema` documents it).
    pub fn file(&self) -> &ModelFile {
        &self.file
    }

    /// Main-shaft angle where a cycle starts, degrees.
    pub fn phi_start_deg(&self) -> f64 {
        self.file.model.phi_start_deg.unwrap_or(0.0)
    }

    /// Index of a frame by name (`world` is 0).
    pub fn frame_index(&self, name: &str) -> Option<usize> {
        self.frames.iter().position(|f| f.name == name)
    }

    /// Names of the model's frames.
    pub fn frame_names(&self) -> Vec<&str> {
        self.frames.iter().map(|f| f.name.as_str()).collect()
    }

    /// Whether a point is fixed.
    pub fn is_fixed(&self, slot: usize) -> bool {
        matches!(self.point_kinds[slot], PointKind::Fixed { .. })
    }

    /// The names of the points that move, in slot order.
    pub fn moving_point_names(&self) -> Vec<&str> {
        (0..self.point_names.len())
            .filter(|&i| !self.is_fixed(i))
            .map(|i| self.point_names[i].as_str())
            .collect()
    }

    /// The slot of a point by name.
    pub fn point_slot(&self, name: &str) -> Result<usize, PointError> {
        self.point_names
            .iter()
            .position(|p| p == name)
            .ok_or_else(|| PointError::Unknown {
                name: name.to_string(),
                closest: did_you_mean(name, self.point_names.iter().map(String::as_str)).map(str::to_string),
                points: self.point_names.clone(),
            })
    }

    /// The slots of points by name, in order (a cycle's `points` to
    /// tabulate); an unknown name is an error of `input`.
    pub fn point_slots(&self, names: &[String], input: Input) -> Result<Vec<usize>, crate::Error> {
        names
            .iter()
            .map(|n| self.point_slot(n).map_err(|e| e.given_in(input)))
            .collect()
    }

    /// The slot of a point that moves, by name (a fixed point has no path).
    pub fn moving_point_slot(&self, name: &str) -> Result<usize, PointError> {
        let slot = self.point_slot(name)?;
        if self.is_fixed(slot) {
            return Err(PointError::Fixed {
                name: name.to_string(),
                moving: self.moving_point_names().into_iter().map(str::to_string).collect(),
            });
        }
        Ok(slot)
    }

    /// The settings a tuning adjusts by default: the model's machine
    /// settings (`kind = "setting"`, with a range), in file order, except
    /// the thread's tension settings (the regulator, a clamp, the check
    /// spring: what `[thread.physics]` reads), which a tuning adjusts when
    /// named; none when the model has no stitch process. `base` is the
    /// setting the tuning starts from (the list does not depend on it).
    pub fn default_adjustables(&self, base: &Params) -> Result<Vec<String>, crate::Error> {
        let _ = base;
        if !self.has_stitch() {
            return Ok(Vec::new());
        }
        Ok(self
            .params
            .iter()
            .filter(|p| p.is_adjustable_setting() && !self.is_thread_setting(&p.name))
            .map(|p| p.name.clone())
            .collect())
    }

    /// The machine settings (`kind = "setting"`), in file order.
    pub fn machine_settings(&self) -> Vec<&str> {
        self.params
            .iter()
            .filter(|p| p.kind == ParamKind::Setting)
            .map(|p| p.name.as_str())
            .collect()
    }

    /// Lets a search (`tune`, a nomogram) adjust parameters of `kind` when
    /// they are named: job inputs (`--allow-inputs`) or fixed dimensions
    /// (`--allow-dimensions`). Machine settings always may be.
    pub fn allow_adjusting(&mut self, kind: ParamKind) {
        match kind {
            ParamKind::Setting => {}
            ParamKind::Input => self.allowed.inputs = true,
            ParamKind::Dimension => self.allowed.dimensions = true,
        }
    }

    /// Whether a search may adjust a parameter of `kind` when it is named
    /// (see [`Model::allow_adjusting`]).
    pub fn may_adjust(&self, kind: ParamKind) -> bool {
        match kind {
            ParamKind::Setting => true,
            ParamKind::Input => self.allowed.inputs,
            ParamKind::Dimension => self.allowed.dimensions,
        }
    }

    /// Whether parameter `name` anywhere in `lo`…`hi` leaves the stitch
    /// process as it is at `base` (`nominal`, its [`Model::stitch_setup`]).
    /// Decided by comparing the stitch's inputs (m, t, every organ's sampled
    /// motion, the moments) at both ends and a third of the way along:
    /// identical inputs give identical P'. A setting whose stitch process
    /// cannot be resolved changes it.
    pub fn leaves_stitch_alone(
        &self,
        base: &Params,
        nominal: &stitch_setup::StitchSetup,
        name: &str,
        lo: f64,
        hi: f64,
    ) -> Result<bool, ParamError> {
        for x in [lo, hi, lo + (hi - lo) / 3.0] {
            let mut p = base.clone();
            self.set(&mut p, name, x)?;
            match self.stitch_setup(&p) {
                Ok(Some(s)) if &s == nominal => {}
                _ => return Ok(false),
            }
        }
        Ok(true)
    }
}

/// A point name the model cannot take where it was given.
#[derive(Debug, Clone, PartialEq)]
pub enum PointError {
    /// The model has no point of that name.
    Unknown {
        name: String,
        /// The model's point closest to the name, when it looks like a typo.
        closest: Option<String>,
        /// Every point of the model, in slot order.
        points: Vec<String>,
    },
    /// The point is fixed where a moving point is needed: it has no path.
    Fixed {
        name: String,
        /// The points that move, in slot order.
        moving: Vec<String>,
    },
}

impl PointError {
    /// The error of a point name given in `input`, with the points to
    /// choose from.
    pub fn given_in(&self, input: Input) -> crate::Error {
        crate::Error::Param(match self {
            PointError::Unknown { name, closest, points } => ParamError::new(
                input,
                format!("the model has no point `{name}`{}", typo_hint(closest)),
                Some(format!("its points are: {}", points.join(", "))),
            ),
            PointError::Fixed { name, moving } => ParamError::new(
                input,
                format!("point `{name}` is fixed, so it has no path"),
                Some(format!("the moving points are: {}", moving.join(", "))),
            ),
        })
    }
}

impl std::fmt::Display for PointError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PointError::Unknown { name, closest, .. } => {
                write!(f, "the model has no point `{name}`{}", typo_hint(closest))
            }
            PointError::Fixed { name, .. } => write!(f, "point `{name}` is fixed, so it has no path"),
        }
    }
}

impl std::error::Error for PointError {}

/// ` (did you mean `X`?)` for a likely typo, else nothing.
fn typo_hint(closest: &Option<String>) -> String {
    closest
        .as_ref()
        .map(|s| format!(" (did you mean `{s}`?)"))
        .unwrap_or_default()
}

/// The JSON Schema of the model file format, pretty-printed.
pub fn schema_json() -> String {
    let schema = schemars::schema_for!(ModelFile);
    serde_json::to_string_pretty(&schema).expect("a schema always serializes") + "\n"
}
