//! Errors: what went wrong, where, and what to write instead.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A problem in a model file, pointing at the place in the text; also in
/// the other files a user writes (facts to fit, measured curves).
///
/// Happens when a file does not parse, names something that does not exist,
/// mixes units, or describes an impossible geometry. `help` says what to
/// write instead.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelError {
    /// File name (or `preset:NAME`).
    pub file: String,
    /// The file's text, for showing the place.
    pub text: Arc<str>,
    /// Byte range of the offending text, when known.
    pub span: Option<Range<usize>>,
    /// Where in the model, e.g. `groups[2].lengths[1]`.
    pub path: String,
    pub message: String,
    pub help: Option<String>,
}

impl ModelError {
    /// 1-based line and column of the span start.
    pub fn line_col(&self) -> Option<(usize, usize)> {
        let at = self.span.as_ref()?.start.min(self.text.len());
        let before = &self.text[..at];
        let line = before.matches('\n').count() + 1;
        let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        Some((line, col))
    }
}

impl std::fmt::Display for ModelError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line_col() {
            Some((l, c)) => write!(f, "{}:{l}:{c}: ", self.file)?,
            None => write!(f, "{}: ", self.file)?,
        }
        if !self.path.is_empty() {
            write!(f, "{}: ", self.path)?;
        }
        write!(f, "{}", self.message)?;
        if let Some(h) = &self.help {
            write!(f, "\n  help: {h}")?;
        }
        Ok(())
    }
}

impl std::error::Error for ModelError {}

/// A position with no assembly: which group, where, and by how much.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("no assembly at φ = {phi_deg:.3}°: {group}: {message} (closure fails by {defect_mm:.4} mm)")]
pub struct AssemblyError {
    /// The structural group that cannot close (`group "23" (rrr)`).
    pub group: String,
    /// Main-shaft angle where it fails, degrees.
    pub phi_deg: f64,
    /// By how much the closure fails, mm.
    pub defect_mm: f64,
    /// What the group needs that the geometry cannot give.
    pub message: String,
}

/// An input a caller gives a computation, apart from the model file: which
/// one a [`ParamError`] is about.
///
/// The library names each by [`Input::name`]; a front end names it its own
/// way (the command line by its flag, the web page by its field), so the
/// library's messages never spell a flag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Input {
    /// A shipped preset's name.
    Preset,
    /// A parameter value `NAME=VALUE` over the model's default.
    Set,
    /// A varied parameter `NAME=LO:HI:N` of a sweep, chart or tuning.
    Vary,
    /// The number of random settings of a sweep or tuning.
    Samples,
    /// The step of φ, deg.
    Step,
    /// The main-shaft speed, rev/min.
    Rpm,
    /// The columns of a cycle table (names or `*` patterns).
    Columns,
    /// The point a stroke or straightness study follows.
    Point,
    /// The moving points whose motion is plotted.
    Points,
    /// The points whose paths a drawing traces.
    Trajectories,
    /// The columns a motion chart plots.
    Series,
    /// A thread path.
    Thread,
    /// The frame a chart or drawing projects onto.
    Plane,
    /// The frame a drawing looks along.
    View,
    /// The figure of merit a heat map shows.
    Figure,
    /// The figures of merit a sweep or sensitivity reports.
    Figures,
    /// The material thickness m, mm.
    Thickness,
    /// The stitch length t, mm.
    StitchLength,
    /// The overedge width a, mm.
    Width,
    /// The seam's incline β, deg.
    Incline,
    /// Where the looper threads meet on the edge, a fraction of m.
    EdgeFraction,
    /// Where a lockstitch's threads interlace, a fraction of m below the top.
    Interlace,
    /// The length of seam a consumption is wanted for, mm.
    SeamLength,
    /// The allowance for waste on a seam's thread, per cent.
    Waste,
    /// A stitch type, its ISO 4915 number.
    StitchType,
    /// The settings tuning or fitting may change.
    Adjust,
    /// Parameter tolerances `NAME=±T` of a tolerance study.
    Tolerance,
    /// One tolerance for every length, mm.
    LengthTolerance,
    /// The line a straightness study measures against (two points).
    Line,
    /// The φ interval a straightness study measures over.
    Over,
    /// The allowed deviation from the line, mm.
    Limit,
    /// The main-shaft angle of a drawing, deg.
    Phi,
    /// Frames per turn of an animation.
    Frames,
    /// Seconds per turn of an animation.
    Duration,
    /// The number of points of a synthesised cam profile.
    ProfilePoints,
    /// The smoothing window of a cam's target, deg.
    Smooth,
    /// The smallest radius of curvature of a cam, mm.
    MinRadius,
    /// The largest pressure angle of a cam, deg.
    MaxPressureAngle,
    /// The follower's radius at φ0 of a synthesised cam, mm.
    AnchorRadius,
    /// The cam to synthesise.
    Cam,
    /// A target curve P(φ) given as a file.
    Target,
    /// A measured curve given as a file.
    Measured,
}

impl Input {
    /// The library's name of the input, as in its options structs.
    pub fn name(self) -> &'static str {
        match self {
            Input::Preset => "preset",
            Input::Set => "set",
            Input::Vary => "vary",
            Input::Samples => "samples",
            Input::Step => "step",
            Input::Rpm => "rpm",
            Input::Columns => "columns",
            Input::Point => "point",
            Input::Points => "points",
            Input::Trajectories => "trajectories",
            Input::Series => "series",
            Input::Thread => "thread",
            Input::Plane => "plane",
            Input::View => "view",
            Input::Figure => "figure",
            Input::Figures => "figures",
            Input::Thickness => "thickness",
            Input::StitchLength => "stitch_length",
            Input::Width => "width",
            Input::Incline => "incline",
            Input::EdgeFraction => "edge_fraction",
            Input::Interlace => "interlace_fraction",
            Input::SeamLength => "seam_length",
            Input::Waste => "waste",
            Input::StitchType => "stitch_type",
            Input::Adjust => "adjust",
            Input::Tolerance => "tolerance",
            Input::LengthTolerance => "length_tolerance",
            Input::Line => "line",
            Input::Over => "over",
            Input::Limit => "limit",
            Input::Phi => "phi",
            Input::Frames => "frames",
            Input::Duration => "duration",
            Input::ProfilePoints => "profile_points",
            Input::Smooth => "smooth",
            Input::MinRadius => "min_radius",
            Input::MaxPressureAngle => "max_pressure_angle",
            Input::AnchorRadius => "anchor_radius",
            Input::Cam => "cam",
            Input::Target => "target",
            Input::Measured => "measured",
        }
    }

    /// Every input, for front ends that check they name each one.
    pub const ALL: [Input; 42] = [
        Input::Preset,
        Input::Set,
        Input::Vary,
        Input::Samples,
        Input::Step,
        Input::Rpm,
        Input::Columns,
        Input::Point,
        Input::Points,
        Input::Trajectories,
        Input::Series,
        Input::Thread,
        Input::Plane,
        Input::View,
        Input::Figure,
        Input::Figures,
        Input::Thickness,
        Input::StitchLength,
        Input::Width,
        Input::Incline,
        Input::EdgeFraction,
        Input::Interlace,
        Input::SeamLength,
        Input::Waste,
        Input::StitchType,
        Input::Adjust,
        Input::Tolerance,
        Input::LengthTolerance,
        Input::Line,
        Input::Over,
        Input::Limit,
        Input::Phi,
        Input::Frames,
        Input::Duration,
        Input::ProfilePoints,
        Input::Smooth,
        Input::MinRadius,
        Input::MaxPressureAngle,
        Input::AnchorRadius,
        Input::Cam,
        Input::Target,
        Input::Measured,
    ];
}

/// A value given to a computation that cannot be used: a parameter value
/// out of its range, a malformed range, an unknown name.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamError {
    /// The input the value was given in, when it is one of [`Input`].
    pub input: Option<Input>,
    /// What is wrong, in the library's words.
    pub message: String,
    /// What to give instead.
    pub help: Option<String>,
}

impl ParamError {
    /// A problem with a value given in `input`.
    pub fn new(input: Input, message: impl Into<String>, help: Option<String>) -> ParamError {
        ParamError {
            input: Some(input),
            message: message.into(),
            help,
        }
    }

    /// A problem with a value that is not given in one input (a parameter's
    /// range as the model states it, a combination of inputs).
    pub fn general(message: impl Into<String>, help: Option<String>) -> ParamError {
        ParamError {
            input: None,
            message: message.into(),
            help,
        }
    }

    /// The same problem, found in the value given in `input`.
    pub fn in_input(mut self, input: Input) -> ParamError {
        self.input.get_or_insert(input);
        self
    }

    /// The message with its input named by `name_of` (a front end's flag or
    /// field), as ``"{message} (in {name})"``.
    pub fn describe(&self, name_of: impl Fn(Input) -> String) -> String {
        match self.input {
            Some(input) => format!("{} (in {})", self.message, name_of(input)),
            None => self.message.clone(),
        }
    }
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.describe(|i| format!("`{}`", i.name())))
    }
}

impl std::error::Error for ParamError {}

/// A file or stream that cannot be read or written.
#[derive(Debug, Clone, thiserror::Error)]
#[error("cannot {action}{}: {reason}", .path.as_ref().map(|p| format!(" `{}`", p.display())).unwrap_or_default())]
pub struct IoError {
    /// What was being done: `read model file`, `write`, `write to stdout`.
    pub action: String,
    /// The file, when there is one.
    pub path: Option<PathBuf>,
    /// Why: the operating system's words, or what the library found (a
    /// folder where a file was named, a missing folder).
    pub reason: String,
    /// The operating system's error, when there is one.
    #[source]
    pub source: Option<Arc<std::io::Error>>,
}

impl IoError {
    /// `action` on `path` failed with the operating system's error `e`.
    pub fn os(action: impl Into<String>, path: Option<&Path>, e: std::io::Error) -> IoError {
        IoError {
            action: action.into(),
            path: path.map(Path::to_path_buf),
            reason: e.to_string(),
            source: Some(Arc::new(e)),
        }
    }

    /// `action` on `path` is refused for `reason`.
    pub fn refused(action: impl Into<String>, path: Option<&Path>, reason: impl Into<String>) -> IoError {
        IoError {
            action: action.into(),
            path: path.map(Path::to_path_buf),
            reason: reason.into(),
            source: None,
        }
    }

    /// The operating system's kind of error, when there is one.
    pub fn kind(&self) -> Option<std::io::ErrorKind> {
        self.source.as_ref().map(|e| e.kind())
    }
}

impl PartialEq for IoError {
    fn eq(&self, other: &IoError) -> bool {
        (&self.action, &self.path, &self.reason, self.kind())
            == (&other.action, &other.path, &other.reason, other.kind())
    }
}

/// A thread path that cannot be formed at some φ: a node inside a guide, a
/// span of no length, a wrap that cannot close.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("thread path `{path}`{}: {message}", .phi_deg.map(|p| format!(" at φ = {p:.3}°")).unwrap_or_default())]
pub struct ThreadError {
    /// The path's name.
    pub path: String,
    /// Main-shaft angle where it fails, degrees.
    pub phi_deg: Option<f64>,
    pub message: String,
    /// What to change, where the failure knows better than the usual fix
    /// (check the path's node order and guides).
    pub help: Option<String>,
}

/// A stitch process that cannot be evaluated: an organ inside the material,
/// a loop that is never caught, moments out of order.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{part}: {message}")]
pub struct StitchError {
    /// The part of the stitch at fault: `feed`, `stitch 504`, `thread N`.
    pub part: String,
    /// What is wrong and, where the part knows it, what to change.
    pub message: String,
}

impl StitchError {
    pub fn new(part: impl Into<String>, message: impl Into<String>) -> StitchError {
        StitchError {
            part: part.into(),
            message: message.into(),
        }
    }
}

/// A quantity that came out infinite or NaN; never written to output.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{quantity} is not finite{}: {cause}", .phi_deg.map(|p| format!(" at φ = {p:.3}°")).unwrap_or_default())]
pub struct NotFiniteError {
    /// The quantity: a column's name, `the synthesised cam profile`.
    pub quantity: String,
    /// Main-shaft angle where it happens, degrees, when it is one φ.
    pub phi_deg: Option<f64>,
    /// Why, as far as the library can tell, and what to change.
    pub cause: String,
}

/// A setting that evaluates but that no real machine can realise: physical
/// checks of the stitch (`stitch::checks`) fail.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "{} physical check(s) fail ({}): the model loads and assembles, but this setting cannot work on a real machine",
    .failed.len(),
    .failed.join(", ")
)]
pub struct PhysicalError {
    /// The failing checks, `THREAD CHECK` each.
    pub failed: Vec<String>,
}

/// Everything the library can fail with.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    #[error(transparent)]
    Model(#[from] Box<ModelError>),
    #[error(transparent)]
    Param(#[from] ParamError),
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// A value that came out infinite or NaN (e.g. infinite analogs at a
    /// dead point).
    #[error(transparent)]
    NotFinite(#[from] NotFiniteError),
    /// A thread path that cannot be formed at some φ.
    #[error(transparent)]
    Thread(#[from] ThreadError),
    /// A stitch process that cannot be evaluated.
    #[error(transparent)]
    Stitch(#[from] StitchError),
    /// A setting no real machine can realise.
    #[error(transparent)]
    Physical(#[from] PhysicalError),
    /// A file or stream that cannot be read or written.
    #[error(transparent)]
    Io(#[from] IoError),
    /// A state the library should never reach; the message asks for a
    /// report.
    #[error("{0} (a bug: please report it)")]
    Internal(String),
}

impl Error {
    /// What to do about it, when the error itself does not say: the model
    /// file's or parameter's own help, or the usual fix for an assembly,
    /// thread or stitch failure.
    pub fn help(&self) -> Option<&str> {
        match self {
            Error::Model(m) => m.help.as_deref(),
            Error::Param(p) => p.help.as_deref(),
            Error::Assembly(_) => Some(
                "check the dimensions and the branch of that group, or the φ range (`stitchkin check` shows where assembly is lost)",
            ),
            Error::Thread(t) => Some(
                t.help
                    .as_deref()
                    .unwrap_or("check the path's node order and the guides' positions at that φ"),
            ),
            Error::Stitch(_) => Some(
                "check the [stitch] table: organ motions, moments and the stitch frame (docs/model-format.md §13.11)",
            ),
            Error::Physical(_) => Some("each failing check's own message says what to change"),
            Error::NotFinite(_) | Error::Io(_) | Error::Internal(_) => None,
        }
    }
}

impl From<ModelError> for Error {
    fn from(e: ModelError) -> Self {
        Error::Model(Box::new(e))
    }
}

/// Closest of `candidates` to `name`, if it is plausibly a typo.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .into_iter()
        .map(|c| (strsim::damerau_levenshtein(&name.to_lowercase(), &c.to_lowercase()), c))
        .filter(|(d, c)| *d <= 2.max(c.len() / 3))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}
