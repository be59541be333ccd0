//! Errors: what went wrong, where, and what to write instead.

use std::ops::Range;
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

/// A parameter override that cannot be applied (`--set NAME=VALUE`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct ParamError {
    pub message: String,
    pub help: Option<String>,
}

/// Everything the library can fail with.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Model(#[from] Box<ModelError>),
    #[error(transparent)]
    Param(#[from] ParamError),
    #[error(transparent)]
    Assembly(#[from] AssemblyError),
    /// A value that came out infinite or NaN (e.g. infinite analogs at a
    /// dead point); never written to output.
    #[error("{0}")]
    NotFinite(String),
    /// A thread path that cannot be formed at some φ.
    #[error("{0}")]
    Thread(String),
    /// A stitch process that cannot be evaluated: an organ inside the
    /// material, a loop that is never caught, moments out of order. The
    /// message names the organ, φ and the fix.
    #[error("{0}")]
    Stitch(String),
    /// A setting that evaluates but that no real machine can realise: a
    /// physical check of the stitch fails (`stitch::checks`). The message
    /// names the checks; each check's own message says what to change.
    #[error("{0}")]
    Physical(String),
    #[error("{0}")]
    Io(String),
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
            Error::Thread(_) => Some("check the path's node order and the guides' positions at that φ"),
            Error::Stitch(_) => Some(
                "check the [stitch] table: organ motions, moments and the stitch frame (docs/model-format.md §13.11)",
            ),
            Error::NotFinite(_) | Error::Physical(_) | Error::Io(_) => None,
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
