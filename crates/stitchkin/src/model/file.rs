//! The model file as written by a user: plain serde types, one per TOML table.
//!
//! These types are the single source of truth for the file format: they are
//! deserialized from TOML, and `stitchkin schema` derives the JSON Schema from
//! them. Nothing here is checked beyond its TOML shape; loading turns
//! a [`ModelFile`] into a validated, compiled [`super::Model`].

use indexmap::IndexMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A number, or an arithmetic expression of parameters in a string,
/// e.g. `"x_c + l_ef - l_ef*cos(alpha)"`. An expression is in the model's
/// units (`[model] units`; trigonometric functions take and give its angle
/// unit); a plain number in a field whose name carries a unit (`*_mm`,
/// `*_deg`, `*_n`) is in that unit, elsewhere in the model's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum Value {
    Number(f64),
    Expr(String),
}

/// A whole model file.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// What machine this is and where the cycle starts.
    pub model: ModelInfo,
    /// Named parameters: dimensions, angles and settings, kept in file
    /// order. Keys are names usable in expressions (`[A-Za-z_][A-Za-z0-9_]*`).
    #[serde(default)]
    pub parameters: IndexMap<String, Parameter>,
    /// Named fixed coordinate frames (besides `world`).
    #[serde(default)]
    pub frames: IndexMap<String, Frame>,
    /// Named fixed points (frame pivots, guide points, …).
    #[serde(default)]
    pub points: IndexMap<String, FixedPoint>,
    /// Cranks and eccentrics on the main shaft (class I mechanisms).
    #[serde(default)]
    pub drivers: Vec<Driver>,
    /// Structural groups, in any order: they are solved in dependency order.
    #[serde(default)]
    pub groups: Vec<Group>,
    /// Derived quantities evaluated at every φ (distances, deviations, …).
    #[serde(default)]
    pub measures: Vec<Measure>,
    /// What `stitchkin run` prints by default.
    #[serde(default)]
    pub output: Option<OutputSpec>,
    /// Thread paths and the take-up convention.
    #[serde(default)]
    pub thread: Option<ThreadSpec>,
    /// Thread feed cams the thread paths may bear on.
    #[serde(default)]
    pub cams: Vec<Cam>,
    /// The stitch process: what the stitch needs, P'(φ), and how P is
    /// compared with it.
    #[serde(default)]
    pub stitch: Option<StitchFile>,
}

/// A thread feed cam (seed 004 §2.5): a convex profile turning with its
/// shaft. Its orientation comes from `marker`, a point turning with it: the
/// direction from `center` to `marker` is profile angle 0.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Cam {
    /// Name used by thread nodes (`{ cam = "NAME" }`).
    pub name: String,
    /// A point on the shaft axis.
    pub center: String,
    /// A point turning with the cam (e.g. a crank pin on its shaft).
    pub marker: String,
    /// Shaft axis; default `"z"`. Profile angles grow counter-clockwise
    /// about it.
    #[serde(default)]
    pub axis: Option<Axis>,
    #[serde(default)]
    pub frame: Option<String>,
    /// A round disc set off the shaft: `{ radius_mm, eccentricity_mm }`,
    /// its centre toward profile angle 0.
    #[serde(default)]
    pub disc: Option<CamDisc>,
    /// A polar profile through points: `{ angle_deg = [...], radius_mm = [...] }`
    /// (angles increasing within one turn), a periodic cubic spline.
    #[serde(default)]
    pub polar: Option<CamPolar>,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CamDisc {
    pub radius_mm: Value,
    pub eccentricity_mm: Value,
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CamPolar {
    pub angle_deg: Vec<f64>,
    pub radius_mm: Vec<f64>,
}

/// How the thread meets a cam.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum CamContactModel {
    /// The taut thread wraps the convex profile (tangents plus arc).
    Exact,
    /// Seed 004: the contact is the end of the profile radius turned by
    /// `gamma_deg` from the one facing the guides.
    Offset,
}

/// The `[model]` table.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelInfo {
    /// Short identifier, e.g. `needle876`.
    pub name: String,
    /// The machine or mechanism, in words.
    #[serde(default)]
    pub title: Option<String>,
    /// Which seed paper the model comes from, e.g. `"002"`.
    #[serde(default)]
    pub seed: Option<String>,
    /// Main-shaft angle φ where a cycle starts, in degrees (e.g. the needle's
    /// bottom dead centre). Default 0.
    #[serde(default)]
    pub phi_start_deg: Option<f64>,
    /// Main-shaft speed used for real velocities and accelerations, rev/min.
    #[serde(default)]
    pub rpm: Option<f64>,
    /// Free text: reconstruction notes, assumptions.
    #[serde(default)]
    pub notes: Option<String>,
    /// One sentence each that every result of this model carries (the
    /// `match`, `run` and `check` summaries, the report, the web page):
    /// where it stands on a reconstruction the seeds leave open, or on a
    /// result carried over from another machine or stitch type.
    #[serde(default)]
    pub caveats: Vec<String>,
    /// The units the model's parameters, expressions and unnamed numbers
    /// are written in: `{ length = "in", angle = "rad" }`; default
    /// millimetres and degrees. Results are always in mm and degrees.
    #[serde(default)]
    pub units: Option<ModelUnits>,
}

/// The `[model] units` table.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelUnits {
    /// `"mm"` (default), `"cm"` or `"in"`.
    #[serde(default)]
    pub length: LengthUnit,
    /// `"deg"` (default) or `"rad"`.
    #[serde(default)]
    pub angle: AngleUnit,
}

/// The length unit a model is written in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub enum LengthUnit {
    /// Millimetres.
    #[default]
    #[serde(rename = "mm")]
    Mm,
    /// Centimetres (10 mm).
    #[serde(rename = "cm")]
    Cm,
    /// Inches (25.4 mm exactly).
    #[serde(rename = "in")]
    In,
}

/// The angle unit a model is written in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub enum AngleUnit {
    /// Degrees.
    #[default]
    #[serde(rename = "deg")]
    Deg,
    /// Radians (180/π degrees).
    #[serde(rename = "rad")]
    Rad,
}

impl LengthUnit {
    /// Millimetres in one of this unit.
    pub fn mm(self) -> f64 {
        match self {
            LengthUnit::Mm => 1.0,
            LengthUnit::Cm => 10.0,
            LengthUnit::In => 25.4,
        }
    }
    /// The parameter unit it is.
    pub fn unit(self) -> Unit {
        match self {
            LengthUnit::Mm => Unit::Mm,
            LengthUnit::Cm => Unit::Cm,
            LengthUnit::In => Unit::In,
        }
    }
}

impl AngleUnit {
    /// Degrees in one of this unit.
    pub fn deg(self) -> f64 {
        match self {
            AngleUnit::Deg => 1.0,
            AngleUnit::Rad => 180.0 / std::f64::consts::PI,
        }
    }
    /// The parameter unit it is.
    pub fn unit(self) -> Unit {
        match self {
            AngleUnit::Deg => Unit::Deg,
            AngleUnit::Rad => Unit::Rad,
        }
    }
}

/// Unit of a parameter: a length or an angle in the model's units
/// (`[model] units`), a pure number or newtons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub enum Unit {
    /// Millimetres.
    #[serde(rename = "mm")]
    Mm,
    /// Centimetres (a model with `units.length = "cm"`).
    #[serde(rename = "cm")]
    Cm,
    /// Inches (a model with `units.length = "in"`).
    #[serde(rename = "in")]
    In,
    /// Degrees.
    #[serde(rename = "deg")]
    Deg,
    /// Radians (a model with `units.angle = "rad"`).
    #[serde(rename = "rad")]
    Rad,
    /// A pure number (ratios, counts).
    #[serde(rename = "1")]
    One,
    /// Newtons (thread tensions, holding forces, stiffness EA).
    #[serde(rename = "N")]
    N,
}

impl Unit {
    /// Its name in the model file: `mm`, `cm`, `in`, `deg`, `rad`, `1`, `N`.
    pub fn as_str(self) -> &'static str {
        match self {
            Unit::Mm => "mm",
            Unit::Cm => "cm",
            Unit::In => "in",
            Unit::Deg => "deg",
            Unit::Rad => "rad",
            Unit::One => "1",
            Unit::N => "N",
        }
    }

    /// A length: `mm`, `cm` or `in`.
    pub fn is_length(self) -> bool {
        matches!(self, Unit::Mm | Unit::Cm | Unit::In)
    }

    /// An angle: `deg` or `rad`.
    pub fn is_angle(self) -> bool {
        matches!(self, Unit::Deg | Unit::Rad)
    }

    /// How many of the unit results are given in (mm for a length, deg
    /// for an angle) one of this unit is: 25.4 for `in`, 180/π for `rad`,
    /// 1 for the others.
    pub fn to_result_unit(self) -> f64 {
        match self {
            Unit::Cm => LengthUnit::Cm.mm(),
            Unit::In => LengthUnit::In.mm(),
            Unit::Rad => AngleUnit::Rad.deg(),
            Unit::Mm | Unit::Deg | Unit::One | Unit::N => 1.0,
        }
    }
}

/// Where a number comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Provenance {
    /// Printed in the seed paper.
    Published,
    /// Derived from published facts (figure-only dimension, typo fix, …).
    Reconstructed,
    /// Chosen to be realistic where the seed gives no number.
    Illustrative,
}

/// What a parameter is on the machine (`docs/model-format.md` §4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum ParamKind {
    /// A machine setting: what a technician adjusts on the machine (an
    /// eccentric's throw, a crank's timing, a guide's height). `tune`
    /// adjusts these, within their `range`.
    Setting,
    /// A job input: what the job brings (the material's thickness, the
    /// stitch length, the thread). Nomograms and sweeps vary it; `tune`
    /// never recommends it.
    Input,
    /// A fixed dimension: a part's size or place, made so and not adjusted
    /// on the machine (a derived parameter is always one).
    Dimension,
}

impl ParamKind {
    /// Its name in the model file and in JSON: `setting`, `input`,
    /// `dimension`.
    pub fn as_str(self) -> &'static str {
        match self {
            ParamKind::Setting => "setting",
            ParamKind::Input => "input",
            ParamKind::Dimension => "dimension",
        }
    }

    /// In words: `machine setting`, `job input`, `fixed dimension`.
    pub fn describe(self) -> &'static str {
        match self {
            ParamKind::Setting => "machine setting",
            ParamKind::Input => "job input",
            ParamKind::Dimension => "fixed dimension",
        }
    }
}

/// One `[parameters]` entry: either `value` (a settable number) or `expr`
/// (derived from other parameters).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Parameter {
    /// Nominal value, in `unit`.
    #[serde(default)]
    pub value: Option<f64>,
    /// Expression of other parameters; the parameter is then derived and
    /// cannot be set from the command line.
    #[serde(default)]
    pub expr: Option<String>,
    pub unit: Unit,
    /// Adjustable range `[min, max]`; overrides outside it are rejected.
    #[serde(default)]
    pub range: Option<[f64; 2]>,
    /// Where the number comes from (seed, table, line) or how it was chosen.
    #[serde(default)]
    pub source: Option<String>,
    #[serde(default)]
    pub provenance: Option<Provenance>,
    /// What it is on the machine: `"setting"`, `"input"` or `"dimension"`.
    /// Default: `input` for the parameter `[stitch] m_mm` or `t_mm` names
    /// and for the thread's stiffness and breaking force (`[thread.physics]`
    /// `ea_n`, `breaking_n`); `dimension` for a derived parameter; `setting`
    /// for one with a range `[lo, hi]`, lo < hi; otherwise `dimension`.
    #[serde(default)]
    pub kind: Option<ParamKind>,
    /// The part or quantity in plain words, as a technician names it, e.g.
    /// `"ball arm O2B on the take-up shaft"`.
    #[serde(default)]
    pub label: Option<String>,
    /// One sentence: what the part is on the machine and which way the
    /// value moves it.
    #[serde(default)]
    pub what: Option<String>,
    /// What a technician does to raise the value, as advice reads it after
    /// the label, e.g. `"slide it along the shaft toward the take-up arm"`
    /// (give `decrease` with it).
    #[serde(default)]
    pub increase: Option<String>,
    /// What a technician does to lower the value (give `increase` with it).
    #[serde(default)]
    pub decrease: Option<String>,
}

/// A coordinate axis name or a direction vector.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum Axis {
    /// `"x"`, `"y"`, `"z"`, or with a sign, `"-y"`.
    Named(String),
    /// Components `[x, y, z]` (need not be unit length).
    Vector(Vec<Value>),
}

/// A rotation about one axis, `["x", 20]`: axis name and angle in degrees.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(try_from = "Vec<Value>")]
pub struct Rotation(pub String, pub Value);

impl TryFrom<Vec<Value>> for Rotation {
    type Error = String;
    fn try_from(v: Vec<Value>) -> Result<Self, String> {
        match <[Value; 2]>::try_from(v) {
            Ok([Value::Expr(axis), angle]) => Ok(Rotation(axis, angle)),
            Ok(_) => Err("a rotation starts with its axis name: [\"x\", 20]".into()),
            Err(v) => Err(format!(
                "a rotation is [axis, angle in degrees], got {} elements",
                v.len()
            )),
        }
    }
}

/// A fixed coordinate frame: `p_parent = origin + R · p_local`, with `R` the
/// product of `rotate` taken left to right (each about the frame's current
/// axes).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Frame {
    /// Frame this one is given in; default `world`.
    #[serde(default)]
    pub parent: Option<String>,
    /// Origin in the parent frame, mm: `[x, y]` or `[x, y, z]`.
    #[serde(default)]
    pub origin: Option<Vec<Value>>,
    /// Rotations, e.g. `[["x", "alpha"]]` for a plane inclined by α about x.
    #[serde(default)]
    pub rotate: Vec<Rotation>,
}

/// A fixed point: `[x, y]`, `[x, y, z]` (world, mm) or a table with a frame.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum FixedPoint {
    Coords(Vec<Value>),
    InFrame(FixedPointInFrame),
}

#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FixedPointInFrame {
    /// Coordinates in `frame`, mm.
    pub at: Vec<Value>,
    /// Frame the coordinates are given in; default `world`.
    #[serde(default)]
    pub frame: Option<String>,
    #[serde(default)]
    pub source: Option<String>,
}

/// Kind of driver. A crank and an eccentric are the same kinematically
/// (the eccentric's radius is its eccentricity); the name documents the part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum DriverKind {
    Crank,
    Eccentric,
}

/// A crank or eccentric on the main shaft: its pin `out` turns about `axis`
/// through `center` at angle θ = speed·φ + phase, measured from `zero_dir`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Driver {
    #[serde(rename = "type")]
    pub kind: DriverKind,
    /// Name used in messages; default: the `out` point's name.
    #[serde(default)]
    pub name: Option<String>,
    /// Fixed point on the shaft axis.
    pub center: String,
    /// Name of the crank pin / eccentric centre this driver creates.
    pub out: String,
    /// Crank radius or eccentricity, mm.
    pub radius: Value,
    /// Shaft axis; default `"z"`. Positive rotation is right-handed about it.
    #[serde(default)]
    pub axis: Option<Axis>,
    /// Frame `axis` and `zero_dir` are given in; default `world`.
    #[serde(default)]
    pub frame: Option<String>,
    /// Direction of θ = 0, perpendicular to the axis; default: x for a z
    /// axis, y for x, z for y (cyclic), else any perpendicular.
    #[serde(default)]
    pub zero_dir: Option<Axis>,
    /// Phase offset added to φ, degrees.
    #[serde(default)]
    pub phase_deg: Option<Value>,
    /// Turns per main-shaft turn (1 for the main shaft itself; −1 turns the
    /// other way).
    #[serde(default)]
    pub speed: Option<f64>,
}

/// Which of two assemblies a group takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Branch {
    /// Left of the directed base line, looking against the plane normal
    /// (counter-clockwise side).
    Left,
    /// Right of the directed base line (clockwise side).
    Right,
    /// Ahead of the input point's foot along the line direction.
    Forward,
    /// Behind the input point's foot along the line direction.
    Backward,
}

/// A structural group or a rigid point, solved in dependency order.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Group {
    /// Planar dyad RRR: `out` at `lengths[0]` from `joints[0]` and
    /// `lengths[1]` from `joints[1]`.
    Rrr {
        #[serde(default)]
        name: Option<String>,
        joints: [String; 2],
        lengths: [Value; 2],
        out: String,
        /// `left` or `right` of the directed line `joints[0]` → `joints[1]`.
        branch: Branch,
        /// Frame whose local xy-plane is the plane of motion; default world.
        #[serde(default)]
        plane: Option<String>,
    },
    /// Planar dyad RRP: a rod of `length` from joint `from` to a slider
    /// `out` on the guide line through `through` (toward `toward`, or along
    /// `direction_deg` in the plane), offset `offset` to its left.
    Rrp {
        #[serde(default)]
        name: Option<String>,
        from: String,
        length: Value,
        through: String,
        #[serde(default)]
        toward: Option<String>,
        #[serde(default)]
        direction_deg: Option<Value>,
        /// Slider offset from the guide line, mm, positive to its left.
        #[serde(default)]
        offset: Option<Value>,
        out: String,
        /// `forward` or `backward` of `from`'s foot on the line.
        branch: Branch,
        #[serde(default)]
        plane: Option<String>,
    },
    /// Planar dyad RPR (slotted lever): a lever pivoting at `pivot` whose
    /// slot passes through the moving pin `from`, at `offset` to the slot
    /// line's left of the pivot. Creates `out` on the slot line at `distance`
    /// from the pivot's foot (positive toward the pin).
    Rpr {
        #[serde(default)]
        name: Option<String>,
        from: String,
        pivot: String,
        #[serde(default)]
        offset: Option<Value>,
        out: String,
        distance: Value,
        #[serde(default)]
        plane: Option<String>,
    },
    /// Spatial RSSR: rocker turning on a fixed axis through `pivot`, its
    /// ball end `out` at radius `arm` in the plane `offset` along the axis,
    /// joined to moving point `from` by a rod of length `rod`.
    Rssr {
        #[serde(default)]
        name: Option<String>,
        from: String,
        rod: Value,
        pivot: String,
        axis: Axis,
        arm: Value,
        #[serde(default)]
        offset: Option<Value>,
        out: String,
        /// `left` (counter-clockwise about the axis from `from`'s
        /// direction) or `right`.
        branch: Branch,
        #[serde(default)]
        frame: Option<String>,
        /// Direction of rocker angle 0 for the reported angle.
        #[serde(default)]
        zero_dir: Option<Axis>,
    },
    /// Spatial: `out` slides on the line through `through` (toward `toward`
    /// or along `direction`) at `length` from moving point `from`.
    PointOnLine {
        #[serde(default)]
        name: Option<String>,
        from: String,
        length: Value,
        through: String,
        #[serde(default)]
        toward: Option<String>,
        #[serde(default)]
        direction: Option<Axis>,
        #[serde(default)]
        frame: Option<String>,
        out: String,
        branch: Branch,
    },
    /// Planar rigid point: `out` at `distance` from `base[0]`, at
    /// `angle_deg` (counter-clockwise) from the link vector `base[0]` → `base[1]`.
    RigidPoint {
        #[serde(default)]
        name: Option<String>,
        base: [String; 2],
        distance: Value,
        #[serde(default)]
        angle_deg: Option<Value>,
        /// Height along the plane normal, mm (eyelets lifted off the plane).
        #[serde(default)]
        lift: Option<Value>,
        out: String,
        #[serde(default)]
        plane: Option<String>,
    },
    /// Spatial rigid point: `out` at local coordinates `at` in the link frame
    /// with origin `frame[0]`, x axis toward `frame[1]` and `frame[2]` in
    /// the local xy-plane (y positive on its side).
    #[serde(rename = "rigid_point_3d")]
    RigidPoint3d {
        #[serde(default)]
        name: Option<String>,
        frame: [String; 3],
        at: Vec<Value>,
        out: String,
    },
    /// A point riding on the same translating body as `from` (a needle bar,
    /// a slider): `out = from + by`, `by` a constant vector in `frame`.
    Offset {
        #[serde(default)]
        name: Option<String>,
        from: String,
        /// Offset `[dx, dy]` or `[dx, dy, dz]`, mm, in `frame`.
        by: Vec<Value>,
        #[serde(default)]
        frame: Option<String>,
        out: String,
    },
    /// Numerical group: Newton's method on the closure equations, continued
    /// from the previous φ. For anything without a closed form.
    Newton {
        name: String,
        /// Unknown points and their positions at φ start (the guess that
        /// picks the assembly), mm, in `plane` (2 coordinates) or world (3).
        unknowns: IndexMap<String, Vec<Value>>,
        constraints: Vec<Constraint>,
        /// Frame whose xy-plane holds a planar group; omit for spatial.
        #[serde(default)]
        plane: Option<String>,
        /// Whether the group is planar (2 unknowns per point); default:
        /// planar when the guesses have two coordinates.
        #[serde(default)]
        planar: Option<bool>,
    },
    /// A disc cam driving a follower (`docs/model-format.md`, "Cams and
    /// followers"): the cam turns about `center` with the point `marker`;
    /// `out` is the follower's roller centre, knife edge, a translating flat
    /// face's foot on the axis, or the point `arm` along a rocking flat face.
    CamFollower(Box<CamFollowerGroup>),
}

/// A `cam_follower` group.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CamFollowerGroup {
    #[serde(default)]
    pub name: Option<String>,
    /// The cam's shaft centre.
    pub center: String,
    /// A point turning with the cam (e.g. a crank pin on its shaft): the
    /// cam angle is the direction from `center` to it, less `zero_deg`.
    pub marker: String,
    /// The marker's direction (in the plane, from its x axis) at cam angle
    /// 0, deg; default 0.
    #[serde(default)]
    pub zero_deg: Option<Value>,
    /// `translating` or `rocking`.
    pub follower: FollowerKind,
    /// `knife`, `roller` or `flat` (a flat face square to a translating
    /// follower's axis, or on a rocking follower's arm).
    pub contact: ContactKind,
    /// The cam's base circle radius (its least radius), mm.
    pub base_radius: Value,
    /// The roller's radius, mm (`contact = "roller"`).
    #[serde(default)]
    pub roller_radius: Option<Value>,
    /// Translating: the way the follower lifts, deg in the plane.
    #[serde(default)]
    pub direction_deg: Option<Value>,
    /// Translating: the axis's distance from the cam's centre, mm, positive
    /// to the left of `direction_deg`; rocking with a flat face: the face's
    /// distance from the pivot, mm; default 0.
    #[serde(default)]
    pub offset: Option<Value>,
    /// Rocking: the arm's pivot.
    #[serde(default)]
    pub pivot: Option<String>,
    /// Rocking: pivot to roller centre (or knife edge), mm; a flat face:
    /// its point's distance along the face from the foot of the pivot's
    /// perpendicular.
    #[serde(default)]
    pub arm: Option<Value>,
    /// Rocking: `left` or `right` of the line from the pivot to the cam's
    /// centre, where the roller sits.
    #[serde(default)]
    pub branch: Option<Branch>,
    /// The follower's lift over the cam angle: mm for a translating
    /// follower, deg for a rocking one.
    pub lift: LiftFile,
    /// `spring` (force closure, the default) or `groove` (form closure: a
    /// groove or conjugate cams).
    #[serde(default)]
    pub closure: Option<ClosureKind>,
    /// Force closure: the spring and the follower's mass, for the check
    /// that the follower stays on the cam at the model's speed.
    #[serde(default)]
    pub spring: Option<SpringFile>,
    /// The largest pressure angle allowed, deg; default 30 for a
    /// translating follower, 45 for a rocking one.
    #[serde(default)]
    pub max_pressure_deg: Option<f64>,
    pub out: String,
    /// Frame whose xy-plane is the plane of motion; default world.
    #[serde(default)]
    pub plane: Option<String>,
}

/// How a cam's follower moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum FollowerKind {
    Translating,
    Rocking,
}

/// Where a follower touches its cam.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum ContactKind {
    Knife,
    Roller,
    Flat,
}

/// How a follower is kept on its cam.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum ClosureKind {
    Spring,
    Groove,
}

/// A follower's lift over the cam angle: a table (`angle_deg` with `mm`
/// or `deg`), or `segments` of motion laws.
#[derive(Debug, Clone, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LiftFile {
    /// Cam angles of the table, deg, increasing within one turn.
    #[serde(default)]
    pub angle_deg: Option<Vec<f64>>,
    /// A translating follower's lift at those angles, mm.
    #[serde(default)]
    pub mm: Option<Vec<f64>>,
    /// A rocking follower's lift (the arm's turn) at those angles, deg.
    #[serde(default)]
    pub deg: Option<Vec<f64>>,
    /// Segments in order over one turn from cam angle 0; the first starts
    /// from the last one's lift.
    #[serde(default)]
    pub segments: Option<Vec<LiftSegmentFile>>,
}

/// One segment of a lift: up to `end_deg` the follower goes to `lift_mm`
/// (or `lift_deg`) by `law`; the same lift as before is a dwell.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LiftSegmentFile {
    /// Cam angle where the segment ends, deg (the last one's is 360).
    pub end_deg: f64,
    /// The lift there, mm (translating follower).
    #[serde(default)]
    pub lift_mm: Option<Value>,
    /// The lift there, deg (rocking follower).
    #[serde(default)]
    pub lift_deg: Option<Value>,
    /// `cycloidal`, `harmonic` or `polynomial_345`; needed where the lift
    /// changes.
    #[serde(default)]
    pub law: Option<String>,
}

/// The spring holding a force-closed follower on its cam.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpringFile {
    /// Spring force at zero lift, N.
    pub preload_n: f64,
    /// Spring rate, N per mm of the follower's travel at the roller.
    pub rate_n_per_mm: f64,
    /// The follower's mass moved at the roller, kg (a rocking follower:
    /// its moment of inertia over the arm squared).
    pub mass_kg: f64,
}

/// One closure equation of a `newton` group: either
/// `{ distance = ["A", "B"], length = … }` (`|A − B| = length`) or
/// `{ on_line = "P", through = "H", toward = "T" }` (P on the line through
/// the already-solved points H and T).
#[derive(Debug, Clone, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Constraint {
    #[serde(default)]
    pub distance: Option<[String; 2]>,
    /// Length for a `distance` constraint, mm.
    #[serde(default)]
    pub length: Option<Value>,
    #[serde(default)]
    pub on_line: Option<String>,
    #[serde(default)]
    pub through: Option<String>,
    #[serde(default)]
    pub toward: Option<String>,
}

/// A derived quantity evaluated at every φ, with analogs.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Measure {
    /// `|points[0] − points[1]|`, mm.
    Distance { name: String, points: [String; 2] },
    /// Signed distance of `point` from the line through `through` toward
    /// `toward`, mm: positive on the left, in the plane of `plane`
    /// (default world xy). For a spatial line give `plane = "none"` to get
    /// the unsigned 3D distance.
    LineDeviation {
        name: String,
        point: String,
        through: String,
        toward: String,
        #[serde(default)]
        plane: Option<String>,
    },
    /// Coordinate of `point` along `axis` of `frame` measured from the
    /// frame origin (or from `from`), mm.
    Coordinate {
        name: String,
        point: String,
        axis: Axis,
        #[serde(default)]
        frame: Option<String>,
        #[serde(default)]
        from: Option<String>,
    },
}

/// The `[output]` table.
#[derive(Debug, Clone, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Points whose positions and analogs `stitchkin run` prints; default
    /// every moving point.
    #[serde(default)]
    pub points: Option<Vec<String>>,
}

/// Sign convention of the actual take-up P(φ).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum TakeUpConvention {
    /// `P = ξ(φ0) − ξ(φ)` (seed 000 eq. 2): thread given to the stitch as the
    /// feed contour shortens.
    Release,
    /// `P = ξ(φ) − ξ(φ0) + ΔP` (seed 001 eqs. 22–23), with the elongation
    /// allowance ΔP = `elongation_mm`.
    Feed,
}

/// The `[thread]` table: conventions shared by every path, and the paths.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ThreadSpec {
    /// Default `release`.
    #[serde(default)]
    pub convention: Option<TakeUpConvention>,
    /// Thread elongation allowance ΔP, mm (added under the `feed`
    /// convention; seed 001 uses about 6 mm).
    #[serde(default)]
    pub elongation_mm: Option<Value>,
    /// φ0 of P(φ0) = 0 (or ΔP), degrees; default the model's `phi_start_deg`.
    #[serde(default)]
    pub phi0_deg: Option<f64>,
    /// Thread tension set by the tension regulator, newtons (for the
    /// tension along the path by the capstan law).
    #[serde(default)]
    pub tension_n: Option<f64>,
    /// Default friction coefficient μ of the thread on every guide.
    #[serde(default)]
    pub friction: Option<f64>,
    /// The real thread and what holds it: its stiffness and strength, the
    /// regulator's hold, a check spring, thread clamps. With it, the
    /// thread's tension over the cycle is solved for every path the stitch
    /// compares (`docs/thread-physics.md`).
    #[serde(default)]
    pub physics: Option<ThreadPhysicsFile>,
    /// The thread paths, each from the tension regulator to an eye.
    pub paths: Vec<ThreadPath>,
}

/// The `[thread.physics]` table (and a path's own `physics`, whose fields
/// override it for that path): the thread sewn and the parts that hold it.
/// Forces in newtons, numbers or expressions of parameters with unit `N`.
#[derive(Debug, Clone, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ThreadPhysicsFile {
    /// The thread, in words (e.g. `tex 30 spun polyester`).
    #[serde(default)]
    pub thread: Option<String>,
    /// Where the numbers come from, and whether they are illustrative.
    #[serde(default)]
    pub source: Option<String>,
    /// Axial stiffness EA, N: the tension per unit strain (tex 30 spun
    /// polyester about 70–105 N).
    #[serde(default)]
    pub ea_n: Option<Value>,
    /// Breaking force, N (tex 30 spun polyester about 10.5 N).
    #[serde(default)]
    pub breaking_n: Option<Value>,
    /// The regulator's hold, N: the tension the thread needs just past the
    /// regulator to be drawn through it (the discs' 2μN and a pre-tensioner
    /// together; industrial needle threads about 0.6–1.7 N).
    #[serde(default)]
    pub regulator_n: Option<Value>,
    /// A check spring (take-up spring) on the path.
    #[serde(default)]
    pub check_spring: Option<CheckSpringFile>,
    /// Thread clamps at guides of the paths.
    #[serde(default)]
    pub clamps: Vec<ClampFile>,
}

/// A check spring: it holds thread out of the path between the node it
/// follows and the next, up to `take_up_mm`, at a tension that rises over
/// its travel. Give `force_n`, or `preload_n` and `rate_n_per_mm`.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckSpringFile {
    /// The path's node (a point name) the spring follows; it acts on the
    /// thread from there to the next node.
    pub after: String,
    /// The thread it stores over its travel, mm (Juki SC-916: 6–10 mm).
    pub take_up_mm: Value,
    /// The thread tension that holds it at the start and at the end of its
    /// travel, N.
    #[serde(default)]
    pub force_n: Option<[Value; 2]>,
    /// The thread tension at the start of its travel, N…
    #[serde(default)]
    pub preload_n: Option<Value>,
    /// …and how much it rises per mm of thread taken up, N/mm.
    #[serde(default)]
    pub rate_n_per_mm: Option<Value>,
}

/// A thread clamp: it holds the thread at a guide while the tensions on its
/// two sides differ by less than its hold (seed 000's G7).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ClampFile {
    /// The guide (a node's point name) it holds the thread at.
    pub at: String,
    /// Its holding force, N.
    pub hold_n: Value,
    /// When it is closed, `[from, to]` in the model's φ, degrees (default:
    /// always).
    #[serde(default)]
    pub closed_deg: Option<[f64; 2]>,
}

/// One thread path ("feed contour"): nodes in thread order, from the
/// tension regulator to the needle (or looper) eye.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ThreadPath {
    /// Column prefix, e.g. `n1_A` (letters, digits, `_`).
    pub name: String,
    /// Which needle or looper thread this is (free text for reports).
    #[serde(default)]
    pub thread: Option<String>,
    /// Friction coefficient for this path's guides (overrides `[thread]`).
    #[serde(default)]
    pub friction: Option<f64>,
    /// This path's own thread physics: each field given here overrides
    /// `[thread.physics]` (clamps add to it).
    #[serde(default)]
    pub physics: Option<ThreadPhysicsFile>,
    pub nodes: Vec<Node>,
}

/// A node of a thread path: a point name (an eyelet or guide the thread
/// passes through), or a table for a guide with more to say.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum Node {
    Point(String),
    Guide(GuideNode),
}

/// A guide given as a table: `{ at = "G1", friction = 0.2 }` for an eyelet
/// with its own friction, or `{ pin = "G4", axis = "z", wrap = "ccw" }` for a
/// one-sided cylindrical guide (a pin, or with `radius` a roller) the thread
/// bears on only when it would otherwise pass on the wrong side.
#[derive(Debug, Clone, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GuideNode {
    /// An eyelet: the thread passes through this point.
    #[serde(default)]
    pub at: Option<String>,
    /// A one-sided cylindrical guide whose axis passes through this point.
    #[serde(default)]
    pub pin: Option<String>,
    /// A cam (by name) the thread bears on between its neighbours.
    #[serde(default)]
    pub cam: Option<String>,
    /// For a cam: `exact` (default) or `offset`.
    #[serde(default)]
    pub contact: Option<CamContactModel>,
    /// For a cam with `contact = "offset"`: the contact angle γ, degrees
    /// (seed 004: 0.4–0.8 rad).
    #[serde(default)]
    pub gamma_deg: Option<Value>,
    /// The pin's axis direction (in `frame`).
    #[serde(default)]
    pub axis: Option<Axis>,
    #[serde(default)]
    pub frame: Option<String>,
    /// Which way the thread turns around the pin when it bears on it,
    /// about `axis` by the right-hand rule: `ccw` or `cw`.
    #[serde(default)]
    pub wrap: Option<Wrap>,
    /// Pin radius, mm (default 0).
    #[serde(default)]
    pub radius: Option<Value>,
    /// Friction coefficient μ on this guide.
    #[serde(default)]
    pub friction: Option<f64>,
}

/// Turning sense about a pin's axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Wrap {
    Ccw,
    Cw,
}

/// The `[stitch]` table (`docs/stitch-formation.md` §9): the stitch the
/// machine makes and the organs that make it. Angles of the cyclogram
/// (`*_deg` inside `[stitch]`, except `regulator.window_deg`) are cyclogram
/// angles φ_c: 0 = the needle's bottom dead centre, φ_c = φ −
/// `cyclogram_zero_deg`. Positions are in the stitch frame: x across the
/// seam toward the material edge, y along the seam in the feed direction,
/// z up, z = 0 the needle-plate top.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchFile {
    /// Stitch type: "301" (lockstitch), "401", "406", "407" (chain), "503"
    /// (two-thread overedge) or "504" (three-thread overedge).
    #[serde(rename = "type")]
    pub stitch_type: String,
    /// Compressed material thickness m, mm.
    pub m_mm: Value,
    /// Stitch length t, mm.
    pub t_mm: Value,
    /// Needle inclination β along the seam, degrees (default 0).
    #[serde(default)]
    pub tilt_deg: Option<Value>,
    /// Overedge width a_e (class 500), mm.
    #[serde(default)]
    pub overedge_width_mm: Option<Value>,
    /// Edge split e (0…1): the share of the edge covered by the lower-face
    /// looper thread (default 0.5).
    #[serde(default)]
    pub edge_split: Option<f64>,
    /// The model frame whose axes and origin are the stitch frame's
    /// (default: the world frame).
    #[serde(default)]
    pub frame: Option<String>,
    /// The model's φ of the needle's bottom dead centre (φ_c = 0), degrees.
    pub cyclogram_zero_deg: f64,
    /// Tolerance ε of the excess and deficit intervals, mm (default 0.5).
    #[serde(default)]
    pub tolerance_mm: Option<f64>,
    /// Where the thread of one stitch passes the tension regulator (drawn
    /// from the bobbin): P' draws it there and the mismatch metrics leave
    /// that window out. Default: computed from the thread's tension when
    /// every compared path carries `[thread.physics]`; otherwise the last
    /// 60° before each thread's stitch is pulled tight (the needle's TDC; a
    /// looper thread's draw-in).
    #[serde(default)]
    pub regulator: Option<StitchRegulator>,
    /// How the material is fed.
    pub feed: StitchFeed,
    /// The needles, in the order the looper catches their loops.
    pub needles: Vec<StitchNeedle>,
    /// The looper that catches the needle loops (the lower looper of 503
    /// and 504); every type but 301.
    #[serde(default)]
    pub looper: Option<StitchLooper>,
    /// The rotary hook that takes the needle loop around the bobbin (301).
    #[serde(default)]
    pub hook: Option<StitchHook>,
    /// Lockstitch 301: where the needle and bobbin threads interlace, a
    /// fraction of m below the top face (default 0.5, the balanced stitch).
    #[serde(default)]
    pub interlace: Option<Value>,
    /// The upper looper (504).
    #[serde(default)]
    pub upper_looper: Option<StitchUpperLooper>,
    /// The spreader (503).
    #[serde(default)]
    pub spreader: Option<StitchSpreader>,
    /// Cyclogram moments (503, 504), φ_c degrees.
    #[serde(default)]
    pub moments: Option<StitchMoments>,
}

/// Where the stitch's thread passes the tension regulator: give one of the
/// three (`docs/stitch-formation.md` §3.3).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchRegulator {
    /// One window `[from, to]` for every thread, in the model's φ, degrees
    /// (not the cyclogram angle), e.g. `[300, 360]`; it may not contain the
    /// take-up's φ0 inside it.
    #[serde(default)]
    pub window_deg: Option<[f64; 2]>,
    /// Each thread's window is the last this many degrees before its
    /// stitch is pulled tight: the needle's top dead centre for a needle
    /// thread, the draw-in (its lock) for a looper thread (default 60).
    #[serde(default)]
    pub width_deg: Option<Value>,
    /// `true`: the whole stitch passes at each thread's lock, nothing is
    /// left out of the metrics (the accounting of the reference tables).
    #[serde(default)]
    pub at_lock: Option<bool>,
    /// `true`: where the thread's tension draws it, computed for each
    /// setting (needs `[thread.physics]` on every compared path; the
    /// default when they have it).
    #[serde(default)]
    pub computed: Option<bool>,
}

/// The material transport T(φ_c).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchFeed {
    /// "harmonic": the feed dog of seed 004 §2.2.3 (with `start_deg` and
    /// `duration_deg`); "point": a feed-dog tooth point of the mechanism
    /// (with `point`).
    pub law: String,
    /// Harmonic: φ_c where the transport starts, degrees.
    #[serde(default)]
    pub start_deg: Option<Value>,
    /// Harmonic: how long it lasts, degrees.
    #[serde(default)]
    pub duration_deg: Option<Value>,
    /// Point: the mechanism point that is the feed dog's tooth; the material
    /// moves with its y while it is above the plate (z > 0, stitch frame).
    #[serde(default)]
    pub point: Option<String>,
}

/// A needle: its eye is a mechanism point (`eye`) or a stand-in law (`law`).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchNeedle {
    /// Thread name, the prefix of its columns (`n1.Pprime_mm`).
    pub name: String,
    /// The mechanism point that is the needle eye.
    #[serde(default)]
    pub eye: Option<String>,
    /// A stand-in law instead of a mechanism point.
    #[serde(default)]
    pub law: Option<NeedleLawFile>,
    /// With `eye`: the eye's height above the needle plate at TDC, along the
    /// needle, mm (the stitch frame's z of the eye is then ignored).
    #[serde(default)]
    pub eye_above_plate_mm: Option<Value>,
    /// Needle point below the eye, mm (default 2).
    #[serde(default)]
    pub point_below_eye_mm: Option<Value>,
    /// The thread path (`[[thread.paths]]`) compared with this thread.
    #[serde(default)]
    pub path: Option<String>,
    /// Catch φ1 (φ_c degrees, a number or an expression, e.g. `"30 -
    /// timing"` to follow a looper's timing); default: where the looper
    /// reaches the needle.
    #[serde(default)]
    pub catch_deg: Option<Value>,
    /// Drop φ4 (φ_c degrees, a number or an expression); default derived
    /// from the loop carry.
    #[serde(default)]
    pub drop_deg: Option<Value>,
}

/// Stand-in needle: S = stroke/2·(1 + cos(φ_c − bdc)).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NeedleLawFile {
    /// The needle line's x in the stitch frame, mm.
    pub x_mm: Value,
    /// Eye above the plate at TDC, along the needle, mm.
    pub eye_above_plate_mm: Value,
    pub stroke_mm: Value,
    /// φ_c of the bottom dead centre (default 0).
    #[serde(default)]
    pub bdc_deg: Option<Value>,
}

/// The rotary hook of a lockstitch (`docs/stitch-formation.md` §13): its
/// axis across the seam, turning twice per stitch. Lengths in mm.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchHook {
    /// Radius of the beak point's circle.
    pub beak_radius_mm: Value,
    /// Radius of the bobbin case's outline in the hook's plane.
    pub case_radius_mm: Value,
    /// The hook axis's distance from the needle line along the seam (+:
    /// in the feed direction); case radius < |offset| < beak radius.
    pub offset_mm: Value,
    /// The hook axis below the plate top; deeper than the beak radius.
    pub depth_mm: Value,
    /// The needle's rise from its BDC when the beak meets it: the hook's
    /// timing (default 2.0; the makers' gauges set 1.8–2.8).
    #[serde(default)]
    pub catch_rise_mm: Option<Value>,
    /// The beak's turn from the catch to where the loop leaves the hook,
    /// degrees.
    pub cast_off_deg: Value,
}

/// The looper that catches the needle loops.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchLooper {
    /// The mechanism point that is its catching point and eye.
    #[serde(default)]
    pub eye: Option<String>,
    /// A stand-in law instead.
    #[serde(default)]
    pub law: Option<LooperLawFile>,
    /// Plate top to the looper's upper face, mm.
    pub k_mm: Value,
    /// Half-cylinder radius of the looper body, mm.
    pub a_mm: Value,
    /// Straight sides of the looper body, mm.
    pub b_mm: Value,
    /// γmax, degrees (seed 004: 0.4–0.8 rad = 22.9°–45.8°).
    pub gamma_max_deg: Value,
    /// The looper thread's feed path (503, 504: the lower-looper thread).
    #[serde(default)]
    pub path: Option<String>,
}

/// Stand-in looper: harmonic across the seam, x = x_c − stroke/2·cos(φ_c −
/// far + 180°) with x = `catch_x_mm` at `catch_deg`; y = y0 − avoid·sin φ_c;
/// z = −depth.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LooperLawFile {
    pub stroke_mm: Value,
    /// φ_c of the far extreme of the carrying stroke.
    pub far_deg: Value,
    pub catch_deg: Value,
    /// x where the catch happens (the first needle's line), mm (default 0).
    #[serde(default)]
    pub catch_x_mm: Option<Value>,
    /// y of the loop on the looper, mm (default (k + b)·tan β).
    #[serde(default)]
    pub y0_mm: Option<Value>,
    /// Amplitude of the avoid motion along the seam, mm (default 0).
    #[serde(default)]
    pub avoid_mm: Option<Value>,
    /// Eye below the plate top, mm.
    pub depth_mm: Value,
}

/// The upper looper of stitch 504.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchUpperLooper {
    #[serde(default)]
    pub eye: Option<String>,
    #[serde(default)]
    pub law: Option<PolylineLawFile>,
    /// φ_c window where the pick-up of the lower thread is searched.
    pub pick_window_deg: [f64; 2],
    /// The upper looper thread's feed path.
    #[serde(default)]
    pub path: Option<String>,
}

/// The spreader of stitch 503: it takes the looper thread from the lower
/// looper and carries it over the material edge to the needle. It carries no
/// thread of its own (the looper thread's path is `[stitch.looper] path`).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchSpreader {
    /// The mechanism point that is the spreader's hook.
    #[serde(default)]
    pub eye: Option<String>,
    /// A stand-in law instead.
    #[serde(default)]
    pub law: Option<PolylineLawFile>,
    /// φ_c window where the pick-up of the looper thread is searched.
    pub pick_window_deg: [f64; 2],
}

/// Stand-in: the eye moves along a polyline, first point at `low_deg`, last
/// at `high_deg`, harmonically in between and back.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PolylineLawFile {
    /// Points `[x, y, z]` in the stitch frame, mm.
    pub polyline_mm: Vec<[f64; 3]>,
    pub low_deg: f64,
    pub high_deg: f64,
}

/// Cyclogram moments, φ_c degrees (seed 004 Table 2).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchMoments {
    /// φ3: the looper thread touches the needle.
    pub stab_deg: f64,
    /// φ_UD: the upper looper releases the lower thread's bight (504 only).
    #[serde(default)]
    pub upper_release_deg: Option<f64>,
    /// φ_SD: the spreader releases the looper thread (503 only).
    #[serde(default)]
    pub spreader_release_deg: Option<f64>,
    /// φ5: the looper thread is drawn into the loop.
    pub draw_in_deg: f64,
}
