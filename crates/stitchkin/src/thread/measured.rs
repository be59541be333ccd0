//! Measured (or wanted) take-up curves: an actual take-up P(φ) measured on
//! a machine, or a required take-up P′(φ), read from a CSV file to set
//! beside the model's own curves (docs/studies.md, "Measured curves (CSV)").
//!
//! A curve is periodic over one main-shaft turn: samples (φ_i, y_i), φ in
//! degrees strictly increasing with φ_{n−1} − φ_0 < 360°, y in mm. Between
//! two samples it is the straight line through them, and the segment from
//! the last sample to the first one a turn later (φ_0 + 360°) closes the
//! turn.
//!
//! ```
//! use stitchkin::thread::measured::{CurveKind, parse_curve_csv};
//!
//! let text = "# P = 3·(1 − cos φ), illustrative\nphi_deg,lower.P_mm\n0,0\n45,0.879\n90,3\n135,5.121\n180,6\n225,5.121\n270,3\n315,0.879\n";
//! let curve = parse_curve_csv(text, "lower.csv")?;
//! assert_eq!(curve.kind(), CurveKind::TakeUp);
//! assert_eq!(curve.thread(), Some("lower"));
//! // Halfway between the rows at 45° and 90°, and between 315° and 0° a turn later.
//! let p = curve.resample(&[67.5, 337.5]);
//! assert!((p[0] - 1.9395).abs() < 1e-12 && (p[1] - 0.4395).abs() < 1e-12);
//! # Ok::<(), stitchkin::Error>(())
//! ```

use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use serde::Serialize;

use crate::error::{Error, ModelError, did_you_mean};
use crate::format::fmt_num;
use crate::thread::repeated::{DEFAULT_CONFIDENCE, Processed};

/// The largest gap between consecutive samples a curve may have, deg, the
/// gap that closes the turn (from the last sample to the first + 360°)
/// included. A chosen limit: the curve is linear between samples, and a
/// take-up rises and drops within tens of degrees (seed 004's loop leaves
/// the looper between 270° and 305°), so across a wider gap the line would
/// invent the curve rather than follow it.
pub const MAX_GAP_DEG: f64 = 45.0;

/// The fewest rows a curve may have.
pub const MIN_ROWS: usize = 4;

/// What a curve's values are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CurveKind {
    /// An actual take-up P(φ), the thread the mechanism gives to or takes
    /// from the stitch (columns `P_mm`, `P_B_mm`, `P_eye_mm`).
    TakeUp,
    /// A required take-up P′(φ), the thread the stitch needs (columns
    /// `Pprime_mm`, `Pprime_B_mm`, `Pprime_eye_mm`).
    Required,
}

pub use super::SplitPoint;

/// A periodic curve over one main-shaft turn read from a CSV file: samples
/// (φ_i, y_i), φ strictly increasing within one turn, no gap wider than
/// [`MAX_GAP_DEG`], every value finite, at least [`MIN_ROWS`] samples.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeasuredCurve {
    phi_deg: Vec<f64>,
    values_mm: Vec<f64>,
    kind: CurveKind,
    split: Option<SplitPoint>,
    thread: Option<String>,
    column: String,
    source: String,
    /// The standard uncertainty of each sample's value, mm, when the curve
    /// comes with one (repeated readings processed to their mean).
    sigma_mm: Option<Vec<f64>>,
    /// The repeated readings behind the values, processed (seed 004 §3.4),
    /// when the file held several readings per φ.
    #[serde(skip_serializing_if = "Option::is_none")]
    readings: Option<Box<Processed>>,
}

/// The take-up column names without a thread prefix, and what each says.
const COLUMNS: [(&str, CurveKind, Option<SplitPoint>); 6] = [
    ("P_mm", CurveKind::TakeUp, None),
    ("P_B_mm", CurveKind::TakeUp, Some(SplitPoint::B)),
    ("P_eye_mm", CurveKind::TakeUp, Some(SplitPoint::Eye)),
    ("Pprime_mm", CurveKind::Required, None),
    ("Pprime_B_mm", CurveKind::Required, Some(SplitPoint::B)),
    ("Pprime_eye_mm", CurveKind::Required, Some(SplitPoint::Eye)),
];

const HEADER_HELP: &str = "write a header `phi_deg,P_mm` (an actual take-up P, mm) or `phi_deg,Pprime_mm` (a required take-up P′, mm); \
    `P_B_mm`/`P_eye_mm` say the thread is split at B (the needle eye's top position) or at the moving eye, \
    and a thread or path name with a dot may stand before it, e.g. `phi_deg,n1.Pprime_B_mm`";

const ROW_HELP: &str = "one row per φ: the angle in deg and the length in mm, separated by a comma, with a point for decimals, e.g. `30,1.25`";

impl MeasuredCurve {
    /// φ of the samples, deg, strictly increasing, last − first < 360°.
    pub fn phi_deg(&self) -> &[f64] {
        &self.phi_deg
    }

    /// The values at the samples, mm: P or P′ as [`Self::kind`] says.
    pub fn values_mm(&self) -> &[f64] {
        &self.values_mm
    }

    /// Whether the values are an actual take-up P or a required P′.
    pub fn kind(&self) -> CurveKind {
        self.kind
    }

    /// Where the thread is split, when the column says (`_B_mm`, `_eye_mm`).
    pub fn split(&self) -> Option<SplitPoint> {
        self.split
    }

    /// The thread or path name before the dot in the column name
    /// (`n1` of `n1.Pprime_mm`), when there is one.
    pub fn thread(&self) -> Option<&str> {
        self.thread.as_deref()
    }

    /// The value column's name as written in the header (`n1_A.P_B_mm`).
    pub fn column(&self) -> &str {
        &self.column
    }

    /// Where the curve came from (the file name given to the reader).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The curve at `phi_deg` (any turn, deg), mm: with φ reduced to
    /// [φ_0, φ_0 + 360°) and φ_i ≤ φ ≤ φ_{i+1} (φ_n = φ_0 + 360°,
    /// y_n = y_0 on the segment that closes the turn),
    /// y = y_i + (y_{i+1} − y_i)·(φ − φ_i)/(φ_{i+1} − φ_i). At a sample it
    /// is the sample's value exactly. For a curve with |y″| ≤ M (mm/rad²)
    /// sampled at most h rad apart it differs from the curve by at most
    /// M·h²/8. NaN for a non-finite φ.
    pub fn value_at(&self, phi_deg: f64) -> f64 {
        let Some(s) = periodic_segment(&self.phi_deg, phi_deg) else {
            return f64::NAN;
        };
        let (y0, y1) = (self.values_mm[s.i], self.values_mm[s.j]);
        let h = s.to_deg - s.from_deg;
        if h > 0.0 {
            y0 + (y1 - y0) * ((s.at_deg - s.from_deg) / h)
        } else {
            y0
        }
    }

    /// The curve at every φ of `phis_deg` (deg, any grid, any turn), mm:
    /// the periodic linear interpolation of [`Self::value_at`].
    pub fn resample(&self, phis_deg: &[f64]) -> Vec<f64> {
        phis_deg.iter().map(|&phi| self.value_at(phi)).collect()
    }

    /// The standard uncertainty of each sample's value, mm (same order as
    /// [`Self::values_mm`]), when the curve carries one: the weights of a
    /// fit to it are 1/σ². `None` for a curve of single values.
    pub fn sigma_mm(&self) -> Option<&[f64]> {
        self.sigma_mm.as_deref()
    }

    /// The repeated readings behind the curve processed as seed 004 §3.4
    /// does ([`crate::thread::repeated`]): per φ the mean (the curve's
    /// value), the interval, the errors and the flagged outliers. `None`
    /// for a curve of one value per φ.
    pub fn readings(&self) -> Option<&Processed> {
        self.readings.as_deref()
    }

    /// The half-width of the interval (the total error Δ of seed 004
    /// §3.4) at `phis_deg`, mm, linear between samples like the curve;
    /// `None` for a curve of one value per φ.
    pub fn interval_at(&self, phis_deg: &[f64]) -> Option<Vec<f64>> {
        let r = self.readings.as_deref()?;
        let half: Vec<f64> = r.points.iter().map(|p| p.total_mm).collect();
        Some(
            phis_deg
                .iter()
                .map(|&phi| match periodic_segment(&self.phi_deg, phi) {
                    None => f64::NAN,
                    Some(g) => {
                        let w = if g.to_deg > g.from_deg {
                            (g.at_deg - g.from_deg) / (g.to_deg - g.from_deg)
                        } else {
                            0.0
                        };
                        half[g.i] + (half[g.j] - half[g.i]) * w
                    }
                })
                .collect(),
        )
    }

    /// The curve with a standard uncertainty for each sample, mm: one
    /// finite value ≥ 0 per sample, or an error saying which is not.
    pub fn with_sigma_mm(mut self, sigma_mm: Vec<f64>) -> Result<Self, Error> {
        if sigma_mm.len() != self.values_mm.len() {
            return Err(Error::Param(crate::error::ParamError::general(
                format!(
                    "{}: {} uncertainties for {} samples",
                    self.source,
                    sigma_mm.len(),
                    self.values_mm.len()
                ),
                Some("give one standard uncertainty per sample".into()),
            )));
        }
        if let Some(i) = sigma_mm.iter().position(|s| !(s.is_finite() && *s >= 0.0)) {
            return Err(Error::Param(crate::error::ParamError::general(
                format!(
                    "{}: the uncertainty at φ = {} deg is {}, not a finite length ≥ 0",
                    self.source,
                    fmt_num(self.phi_deg[i]),
                    sigma_mm[i]
                ),
                Some("give a standard uncertainty ≥ 0 mm for every sample".into()),
            )));
        }
        self.sigma_mm = Some(sigma_mm);
        Ok(self)
    }
}

/// The segment of periodic samples that holds an angle (see
/// [`periodic_segment`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Segment {
    /// The samples at its ends: `j = i + 1`, or `j = 0` on the segment that
    /// closes the turn.
    pub i: usize,
    pub j: usize,
    /// Its ends, deg: φ_i and φ_j (φ_0 + 360° when it closes the turn).
    pub from_deg: f64,
    pub to_deg: f64,
    /// The angle reduced to [φ_0, φ_0 + 360°), deg, within [from, to].
    pub at_deg: f64,
}

/// The segment [φ_i, φ_{i+1}] of the samples `phis_deg` (strictly
/// increasing, last − first < 360°) that holds `phi_deg` reduced to
/// [φ_0, φ_0 + 360°), the last one running to φ_0 + 360°. `None` for no
/// samples or a non-finite φ.
pub(crate) fn periodic_segment(phis_deg: &[f64], phi_deg: f64) -> Option<Segment> {
    let (&first, &last) = (phis_deg.first()?, phis_deg.last()?);
    let mut at = first + (phi_deg - first).rem_euclid(360.0);
    if !at.is_finite() {
        return None;
    }
    if at >= first + 360.0 {
        // rem_euclid rounded up to a whole turn.
        at = first;
    }
    let n = phis_deg.len();
    Some(match phis_deg.partition_point(|&v| v <= at) {
        p if p >= n => Segment {
            i: n - 1,
            j: 0,
            from_deg: last,
            to_deg: first + 360.0,
            at_deg: at,
        },
        // p = 0 only if `at` were below φ_0, which the reduction rules out.
        0 => Segment {
            i: 0,
            j: 1 % n,
            from_deg: first,
            to_deg: phis_deg[1 % n],
            at_deg: first,
        },
        p => Segment {
            i: p - 1,
            j: p,
            from_deg: phis_deg[p - 1],
            to_deg: phis_deg[p],
            at_deg: at,
        },
    })
}

/// Reads a curve from the file at `path` ([`parse_curve_csv`]); the file
/// name as given names it in messages. A file that cannot be read is an
/// error naming it. Bytes that are not UTF-8 (a comment saved in another
/// encoding) are read as U+FFFD and fail only where a name or number is
/// expected.
pub fn read_curve(path: &Path) -> Result<MeasuredCurve, Error> {
    read_curve_with(path, &ReadingOptions::default())
}

/// How repeated readings are processed (seed 004 §3.4): the instrument's
/// resolution, mm (its largest error, the systematic error of each mean),
/// and the confidence of the intervals. Each, when given, stands for the
/// file's own `# resolution_mm = …` or `# confidence = …` line.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ReadingOptions {
    pub resolution_mm: Option<f64>,
    pub confidence: Option<f64>,
}

/// [`read_curve`] with the processing of repeated readings set by `options`.
pub fn read_curve_with(path: &Path, options: &ReadingOptions) -> Result<MeasuredCurve, Error> {
    let source = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| {
        Error::from(ModelError {
            file: source.clone(),
            text: Arc::from(""),
            span: None,
            path: String::new(),
            message: format!("cannot read the curve file: {e}"),
            help: Some(
                "give the path of a CSV file with a header `phi_deg,P_mm` (or `phi_deg,Pprime_mm`) and one row per φ"
                    .into(),
            ),
        })
    })?;
    parse_curve_csv_with(&String::from_utf8_lossy(&bytes), &source, options)
}

/// One line of the text, without its line ending.
struct Line<'a> {
    /// 1-based.
    number: usize,
    /// Byte offset of its start in the text.
    start: usize,
    text: &'a str,
}

/// One comma-separated field of a line, trimmed.
struct Field<'a> {
    span: Range<usize>,
    text: &'a str,
}

impl Line<'_> {
    fn span(&self) -> Range<usize> {
        self.start..self.start + self.text.len()
    }

    fn fields(&self) -> Vec<Field<'_>> {
        let mut out = Vec::new();
        let mut at = self.start;
        for raw in self.text.split(',') {
            let lead = raw.len() - raw.trim_start().len();
            let text = raw.trim();
            let from = at + lead;
            out.push(Field {
                span: from..from + text.len(),
                text,
            });
            at += raw.len() + 1;
        }
        out
    }
}

/// The lines that carry data: not blank, not a `#` comment.
fn data_lines(text: &str) -> impl Iterator<Item = Line<'_>> {
    let mut start = 0;
    text.split_inclusive('\n').enumerate().filter_map(move |(k, raw)| {
        let line = Line {
            number: k + 1,
            start,
            text: raw.trim_end_matches(['\n', '\r']),
        };
        start += raw.len();
        let t = line.text.trim_start_matches('\u{feff}').trim();
        (!t.is_empty() && !t.starts_with('#')).then_some(line)
    })
}

/// A value column's name: the thread prefix, what it is, where it is split.
fn column_kind(name: &str) -> Result<(Option<String>, CurveKind, Option<SplitPoint>), String> {
    let (prefix, base) = match name.rsplit_once('.') {
        Some((p, b)) => (Some(p), b),
        None => (None, name),
    };
    let Some(&(_, kind, split)) = COLUMNS.iter().find(|c| c.0 == base) else {
        let primed = base.replace(['\'', '′', '’'], "prime");
        // A near miss of a name that starts like one (`p_mm`, `Pprme_mm`),
        // not another quantity that happens to be short (`xi_mm`).
        let guess = if COLUMNS.iter().any(|c| c.0 == primed) {
            Some(primed.as_str())
        } else {
            did_you_mean(base, COLUMNS.iter().map(|c| c.0)).filter(|_| base.starts_with(['P', 'p']))
        };
        return Err(match guess {
            Some(g) => format!(
                "`{name}` is not a take-up column: did you mean `{}`?",
                prefix.map_or(g.to_string(), |p| format!("{p}.{g}"))
            ),
            None => format!(
                "`{name}` is not a take-up column; it must say what it is: P_mm, P_B_mm, P_eye_mm, Pprime_mm, Pprime_B_mm or Pprime_eye_mm"
            ),
        });
    };
    if let Some(p) = prefix
        && (p.is_empty() || !p.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
    {
        return Err(format!(
            "`{p}` before the dot in `{name}` is not a thread or path name (letters, digits and `_`)"
        ));
    }
    Ok((prefix.map(str::to_string), kind, split))
}

/// Reads a curve from CSV text; `source` (a file name) names it in
/// messages. The format (docs/studies.md, "Measured curves (CSV)"):
///
/// - a header with two columns in either order: `phi_deg`, the main-shaft
///   angle in deg, and one length in mm whose name says what it is,
///   `P_mm` (an actual take-up P) or `Pprime_mm` (a required take-up P′),
///   optionally split at B or the eye (`P_B_mm`, `P_eye_mm`,
///   `Pprime_B_mm`, `Pprime_eye_mm`) and optionally after a thread or path
///   name and a dot (`n1.Pprime_mm`, `n1_A.P_B_mm`); names may be quoted;
/// - then one row per φ, two fields each: φ strictly increasing, within
///   one turn (last − first < 360°), at least [`MIN_ROWS`] rows, every
///   value a finite number, no two consecutive φ (nor the last and the
///   first + 360°) more than [`MAX_GAP_DEG`] apart;
/// - blank lines and lines starting with `#` anywhere.
///
/// Repeated readings (seed 004 §3.4: ten readings every 10°) come as the
/// value column written once per reading (`phi_deg,P_mm,P_mm,P_mm`), or as
/// consecutive rows of the same φ, or both; every φ then needs at least two
/// readings, and the instrument's resolution is given by a line
/// `# resolution_mm = 0.05` (and optionally `# confidence = 0.95`). The
/// curve is then the mean at each φ, carrying its standard uncertainty
/// ([`MeasuredCurve::sigma_mm`]) and the processed table
/// ([`MeasuredCurve::readings`], [`crate::thread::repeated`]).
///
/// Every error is an [`Error::Model`] naming `source`, the line (and the
/// field) and the fix.
pub fn parse_curve_csv(text: &str, source: &str) -> Result<MeasuredCurve, Error> {
    parse_curve_csv_with(text, source, &ReadingOptions::default())
}

/// [`parse_curve_csv`] with the processing of repeated readings set by
/// `options` (each given option stands for the file's own line).
pub fn parse_curve_csv_with(text: &str, source: &str, options: &ReadingOptions) -> Result<MeasuredCurve, Error> {
    let file = CurveFile {
        source,
        text: Arc::from(text),
    };
    let mut lines = data_lines(text);
    let Some(header) = lines.next() else {
        return Err(file.err(
            None,
            "the curve file has no header: it is empty or holds only comments and blank lines".into(),
            HEADER_HELP,
        ));
    };
    let head = file.header(&header)?;
    let mut rows = Rows::default();
    for line in lines {
        file.row(&line, &head, &mut rows)?;
    }
    file.check_coverage(&header, &rows)?;
    let mut curve = MeasuredCurve {
        values_mm: rows.readings.iter().map(|r| r[0]).collect(),
        phi_deg: rows.phi_deg.clone(),
        kind: head.kind,
        split: head.split,
        thread: head.thread.clone(),
        column: head.column.clone(),
        source: source.to_string(),
        sigma_mm: None,
        readings: None,
    };
    if head.ncols > 2 || rows.readings.iter().any(|r| r.len() > 1) {
        let processed = file.process(&header, &head, &rows, options)?;
        curve.values_mm = processed.points.iter().map(|p| p.mean_mm).collect();
        curve.sigma_mm = Some(processed.points.iter().map(|p| p.sigma_mm).collect());
        curve.readings = Some(Box::new(processed));
    }
    Ok(curve)
}

/// A `# name = value` line of the file (a setting in a comment), with its
/// line and the span of its value.
fn setting(text: &str, name: &str) -> Option<(usize, Range<usize>, String)> {
    let mut start = 0;
    for (k, raw) in text.split_inclusive('\n').enumerate() {
        let line_start = start;
        start += raw.len();
        let t = raw.trim_start_matches('\u{feff}').trim();
        let Some(rest) = t.strip_prefix('#') else { continue };
        let Some((key, value)) = rest.split_once('=') else {
            continue;
        };
        if key.trim() == name {
            let value = value.trim();
            let at = raw
                .find(value)
                .map_or(line_start..line_start + raw.trim_end().len(), |o| {
                    line_start + o..line_start + o + value.len()
                });
            return Some((k + 1, at, value.to_string()));
        }
    }
    None
}

/// A curve file being read: its name and text, for errors that point at
/// the place.
struct CurveFile<'a> {
    source: &'a str,
    text: Arc<str>,
}

/// What the header says: which field is φ and what the other columns hold
/// (one take-up column, written once per reading).
struct Header {
    iphi: usize,
    /// The number of columns: φ and one per reading.
    ncols: usize,
    column: String,
    thread: Option<String>,
    kind: CurveKind,
    split: Option<SplitPoint>,
}

/// The rows read so far: each φ once, its readings, and the line and φ
/// field of its first row.
#[derive(Default)]
struct Rows {
    phi_deg: Vec<f64>,
    readings: Vec<Vec<f64>>,
    at: Vec<(usize, Range<usize>)>,
}

impl CurveFile<'_> {
    fn err(&self, span: Option<Range<usize>>, message: String, help: &str) -> Error {
        Error::from(ModelError {
            file: self.source.to_string(),
            text: self.text.clone(),
            span,
            path: String::new(),
            message,
            help: Some(help.to_string()),
        })
    }

    /// The header: two columns, `phi_deg` and one take-up column.
    fn header(&self, header: &Line<'_>) -> Result<Header, Error> {
        let names: Vec<Field> = header
            .fields()
            .into_iter()
            .map(|f| Field {
                span: f.span,
                text: f.text.trim_start_matches('\u{feff}').trim_matches('"').trim(),
            })
            .collect();
        let listed = names
            .iter()
            .map(|f| format!("`{}`", f.text))
            .collect::<Vec<_>>()
            .join(", ");
        if names.len() == 1 && [';', '\t'].iter().any(|c| header.text.contains(*c)) {
            return Err(self.err(
                Some(header.span()),
                format!(
                    "the header `{}` is one column: the columns are not separated by commas",
                    header.text.trim()
                ),
                "separate the columns with `,` (and write decimals with a point, `0.5`), e.g. `phi_deg,P_mm`",
            ));
        }
        if names.len() < 2 {
            return Err(self.err(
                Some(header.span()),
                format!(
                    "the header names {} column(s), {listed}; a curve has two: `phi_deg` and one take-up column",
                    names.len()
                ),
                HEADER_HELP,
            ));
        }
        let iphi = match names.iter().filter(|f| f.text == "phi_deg").count() {
            1 => names.iter().position(|f| f.text == "phi_deg").expect("counted"),
            0 => {
                let guess = names.iter().find_map(|f| did_you_mean(f.text, ["phi_deg"]).map(|_| f));
                let message = match guess {
                    Some(f) => {
                        format!(
                            "the header has no column `phi_deg` (got {listed}): did you mean `phi_deg` for `{}`?",
                            f.text
                        )
                    }
                    None => format!("the header has no column `phi_deg` (got {listed})"),
                };
                return Err(self.err(
                    Some(guess.map_or(header.span(), |f| f.span.clone())),
                    message,
                    "name the main-shaft angle column `phi_deg` (deg)",
                ));
            }
            _ => {
                return Err(self.err(
                    Some(header.span()),
                    "the header names `phi_deg` twice".into(),
                    HEADER_HELP,
                ));
            }
        };
        let value = &names[usize::from(iphi == 0)];
        if let Some(other) = names
            .iter()
            .enumerate()
            .find(|(k, f)| *k != iphi && f.text != value.text)
        {
            return Err(self.err(
                Some(other.1.span.clone()),
                format!(
                    "the header names {} column(s), {listed}; a curve has `phi_deg` and one take-up column, written once per reading for repeated readings",
                    names.len()
                ),
                &format!(
                    "give one file per curve; repeated readings repeat the same name, e.g. `phi_deg,{0},{0},{0}`",
                    value.text
                ),
            ));
        }
        let (thread, kind, split) =
            column_kind(value.text).map_err(|m| self.err(Some(value.span.clone()), m, HEADER_HELP))?;
        Ok(Header {
            iphi,
            ncols: names.len(),
            column: value.text.to_string(),
            thread,
            kind,
            split,
        })
    }

    /// One row: φ and its readings, φ after the previous row's (or the
    /// same: more readings of it) and within a turn of the first.
    fn row(&self, line: &Line<'_>, head: &Header, rows: &mut Rows) -> Result<(), Error> {
        let column = &head.column;
        let fields = line.fields();
        if head.ncols > 2 && fields.len() != head.ncols {
            return Err(self.err(
                Some(line.span()),
                format!(
                    "the row has {} field(s), the header {} (`phi_deg` and {} readings of `{column}`)",
                    fields.len(),
                    head.ncols,
                    head.ncols - 1
                ),
                &format!(
                    "give φ and {} readings on every row, separated by commas, with a point for decimals; \
                     a φ with fewer readings can take its readings on rows of their own in a file `phi_deg,{column}`",
                    head.ncols - 1
                ),
            ));
        }
        if fields.len() != 2 && head.ncols == 2 {
            let (message, help) = if fields.len() > 2 {
                (
                    format!(
                        "the row has {} fields, the header two (`phi_deg`, `{column}`)",
                        fields.len()
                    ),
                    format!("remove the extra fields; {ROW_HELP}"),
                )
            } else {
                (
                    format!("the row has one field, the header two (`phi_deg`, `{column}`)"),
                    format!("add the missing value; {ROW_HELP}"),
                )
            };
            return Err(self.err(Some(line.span()), message, &help));
        }
        let what = if head.kind == CurveKind::TakeUp {
            "the take-up P"
        } else {
            "the required take-up P′"
        };
        let phi = self.number(line, &fields[head.iphi], "phi_deg", "φ", "deg")?;
        let mut ys = Vec::with_capacity(fields.len() - 1);
        for (k, f) in fields.iter().enumerate() {
            if k != head.iphi {
                ys.push(self.number(line, f, column, what, "mm")?);
            }
        }
        let phi_span = fields[head.iphi].span.clone();
        if rows.phi_deg.last() == Some(&phi) {
            // Further readings of the same φ.
            rows.readings.last_mut().expect("a φ has readings").extend(ys);
            return Ok(());
        }
        if let (Some(&prev), Some((prev_line, _))) = (rows.phi_deg.last(), rows.at.last())
            && phi <= prev
        {
            return Err(self.err(
                Some(phi_span),
                format!(
                    "φ = {}° does not come after φ = {}° on line {prev_line}: the rows must run in strictly increasing φ",
                    fmt_num(phi),
                    fmt_num(prev)
                ),
                "sort the rows by φ and give each φ once (a turn may start at any φ, e.g. 174.85 … 533.85)",
            ));
        }
        if let (Some(&first), Some((first_line, _))) = (rows.phi_deg.first(), rows.at.first())
            && (phi - first >= 360.0 || first + 360.0 <= phi)
        {
            return Err(self.err(
                Some(phi_span),
                format!(
                    "φ = {}° is a whole turn or more after the first row's φ = {}° (line {first_line}); a curve covers one turn",
                    fmt_num(phi),
                    fmt_num(first)
                ),
                "give one turn, last φ − first φ < 360°: leave out the row that repeats the first a turn later (the curve closes the turn by itself)",
            ));
        }
        rows.phi_deg.push(phi);
        rows.readings.push(ys);
        rows.at.push((line.number, phi_span));
        Ok(())
    }

    /// The repeated readings processed (seed 004 §3.4): at least two per
    /// φ, the resolution given (by `options` or the file), the confidence
    /// in (0, 1).
    fn process(
        &self,
        header: &Line<'_>,
        head: &Header,
        rows: &Rows,
        options: &ReadingOptions,
    ) -> Result<Processed, Error> {
        if let Some(k) = rows.readings.iter().position(|r| r.len() < 2) {
            let many = rows.readings.iter().position(|r| r.len() > 1).unwrap_or(0);
            return Err(self.err(
                Some(rows.at[k].1.clone()),
                format!(
                    "φ = {}° has one reading (line {}), while φ = {}° has {} (line {}): repeated readings are processed per φ and need at least two at every φ",
                    fmt_num(rows.phi_deg[k]),
                    rows.at[k].0,
                    fmt_num(rows.phi_deg[many]),
                    rows.readings[many].len(),
                    rows.at[many].0
                ),
                &format!(
                    "give every φ at least two readings (consecutive rows of the same φ, or a column `{}` per reading); a curve of one value per φ gives each φ once",
                    head.column
                ),
            ));
        }
        let setting_help =
            "write it as a number with a point for decimals, e.g. `# resolution_mm = 0.05` or `# confidence = 0.95`";
        let from_file = |name: &str| -> Result<Option<f64>, Error> {
            match setting(&self.text, name) {
                None => Ok(None),
                Some((_, span, value)) => value
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .map(Some)
                    .ok_or_else(|| {
                        self.err(
                            Some(span),
                            format!("`{value}` ({name}) is not a finite number"),
                            setting_help,
                        )
                    }),
            }
        };
        let file_resolution = from_file("resolution_mm")?;
        let file_confidence = from_file("confidence")?;
        let place = |name: &str| setting(&self.text, name).map(|(_, span, _)| span);
        let resolution = match (options.resolution_mm, file_resolution) {
            (Some(r), _) => r,
            (None, Some(r)) => r,
            (None, None) => {
                return Err(self.err(
                    Some(header.span()),
                    format!(
                        "the file holds repeated readings (up to {} per φ) but not the instrument's resolution, the systematic error of every mean",
                        rows.readings.iter().map(Vec::len).max().unwrap_or(0)
                    ),
                    "add a line `# resolution_mm = 0.05` (the instrument's largest error, mm) before the header",
                ));
            }
        };
        if !(resolution.is_finite() && resolution > 0.0) {
            return Err(self.err(
                options
                    .resolution_mm
                    .is_none()
                    .then(|| place("resolution_mm"))
                    .flatten(),
                format!("the resolution {} mm is not a length > 0", fmt_num(resolution)),
                "give the instrument's resolution (its largest error) in mm, e.g. 0.05",
            ));
        }
        let confidence = options.confidence.or(file_confidence).unwrap_or(DEFAULT_CONFIDENCE);
        if !(confidence > 0.0 && confidence < 1.0) {
            return Err(self.err(
                options.confidence.is_none().then(|| place("confidence")).flatten(),
                format!("the confidence {} is not between 0 and 1", fmt_num(confidence)),
                "give the confidence as a fraction, e.g. 0.95 for 95 %",
            ));
        }
        let processed = Processed::new(&rows.phi_deg, &rows.readings, resolution, confidence);
        if let Some(k) = processed.points.iter().position(|p| {
            ![p.mean_mm, p.s_mm, p.total_mm, p.sigma_mm, p.ci_low_mm, p.ci_high_mm]
                .iter()
                .all(|v| v.is_finite())
        }) {
            return Err(self.err(
                Some(rows.at[k].1.clone()),
                format!(
                    "the readings of φ = {}° are too large to be processed (their spread overflows)",
                    fmt_num(rows.phi_deg[k])
                ),
                "give the readings in mm",
            ));
        }
        Ok(processed)
    }

    /// Field `f` of `line`, the column `name`, holding `what` in `unit`.
    fn number(&self, line: &Line<'_>, f: &Field<'_>, name: &str, what: &str, unit: &str) -> Result<f64, Error> {
        if f.text.is_empty() {
            return Err(self.err(
                Some(line.span()),
                format!("the {name} value is missing"),
                &format!("write {what} in {unit}; {ROW_HELP}"),
            ));
        }
        match f.text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.err(
                Some(f.span.clone()),
                format!("`{}` ({name}) is not a finite number", f.text),
                &format!(
                    "write {what} as a finite number in {unit}; leave out a row that was not measured (the curve is linear between rows, at most {}° apart)",
                    fmt_num(MAX_GAP_DEG)
                ),
            )),
            Err(_) => Err(self.err(
                Some(f.span.clone()),
                format!("`{}` ({name}) is not a number", f.text),
                &format!("write {what} as a number in {unit}; {ROW_HELP}"),
            )),
        }
    }

    /// Enough rows, and no gap wider than MAX_GAP_DEG around the turn.
    fn check_coverage(&self, header: &Line<'_>, rows: &Rows) -> Result<(), Error> {
        let (phi_deg, at) = (&rows.phi_deg, &rows.at);
        let gap_help = format!(
            "give a row at least every {}° of φ, closer where the take-up changes fast: the curve is linear between rows, and across a wider gap the line would invent it",
            fmt_num(MAX_GAP_DEG)
        );
        if phi_deg.len() < MIN_ROWS {
            return Err(self.err(
                Some(header.span()),
                format!(
                    "the curve has {} row(s) after its header; it needs at least {MIN_ROWS}",
                    phi_deg.len()
                ),
                &gap_help,
            ));
        }
        let n = phi_deg.len();
        // The widest gap, ending at sample `end` (0: the one closing the turn).
        let (gap, end) = (0..n)
            .map(|j| {
                (
                    if j == 0 {
                        phi_deg[0] + 360.0 - phi_deg[n - 1]
                    } else {
                        phi_deg[j] - phi_deg[j - 1]
                    },
                    j,
                )
            })
            .fold((f64::MIN, 0), |best, g| if g.0 > best.0 { g } else { best });
        if gap <= MAX_GAP_DEG {
            return Ok(());
        }
        let start = (end + n - 1) % n;
        let (to, to_line) = if end == 0 {
            (
                phi_deg[0] + 360.0,
                format!("line {}, the first row a turn later", at[0].0),
            )
        } else {
            (phi_deg[end], format!("line {}", at[end].0))
        };
        Err(self.err(
            Some(at[if end == 0 { start } else { end }].1.clone()),
            format!(
                "no row for {}° of φ, from φ = {}° (line {}) to φ = {}° ({to_line}); rows may be at most {}° apart",
                fmt_num(gap),
                fmt_num(phi_deg[start]),
                at[start].0,
                fmt_num(to),
                fmt_num(MAX_GAP_DEG)
            ),
            &gap_help,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows every `step` deg from `from` over one turn, the value `f(φ)`.
    fn rows(from: f64, step: f64, f: impl Fn(f64) -> f64) -> String {
        let n = (360.0 / step).round() as usize;
        (0..n)
            .map(|k| from + step * k as f64)
            .map(|x| format!("{x},{}\n", f(x)))
            .collect()
    }

    fn parse(text: &str) -> MeasuredCurve {
        parse_curve_csv(text, "t.csv").unwrap_or_else(|e| panic!("{e}"))
    }

    /// The error as shown (file:line:column: message, then its help).
    fn fails(text: &str) -> String {
        match parse_curve_csv(text, "t.csv") {
            Ok(c) => panic!("should fail: {text:?} gave {c:?}"),
            Err(e) => {
                assert!(matches!(e, Error::Model(_)) && e.help().is_some(), "{e:?}");
                e.to_string()
            }
        }
    }

    #[test]
    fn every_header_form_says_what_the_curve_is() {
        use CurveKind::{Required, TakeUp};
        use SplitPoint::{B, Eye};
        let body = rows(0.0, 30.0, |x| x / 100.0);
        for (name, kind, split, thread) in [
            ("P_mm", TakeUp, None, None),
            ("P_B_mm", TakeUp, Some(B), None),
            ("P_eye_mm", TakeUp, Some(Eye), None),
            ("Pprime_mm", Required, None, None),
            ("Pprime_B_mm", Required, Some(B), None),
            ("Pprime_eye_mm", Required, Some(Eye), None),
            ("n1.Pprime_mm", Required, None, Some("n1")),
            ("n1_A.P_B_mm", TakeUp, Some(B), Some("n1_A")),
            ("lower.P_mm", TakeUp, None, Some("lower")),
            ("needle.Pprime_eye_mm", Required, Some(Eye), Some("needle")),
        ] {
            let c = parse(&format!("phi_deg,{name}\n{body}"));
            assert_eq!(
                (c.kind(), c.split(), c.thread(), c.column(), c.source()),
                (kind, split, thread, name, "t.csv"),
                "{name}"
            );
            assert_eq!(c.phi_deg().len(), 12);
            assert_eq!(
                (c.phi_deg()[1], c.values_mm()[1], c.phi_deg()[11], c.values_mm()[11]),
                (30.0, 0.3, 330.0, 3.3)
            );
        }
        // Quoted names, spaces, a byte-order mark and Windows line ends.
        let c = parse(&format!(
            "\u{feff}\"phi_deg\" , \"n1.P_mm\"\r\n{}",
            body.replace('\n', "\r\n").replace(',', " , ")
        ));
        assert_eq!(
            (c.column(), c.thread(), c.values_mm()[11]),
            ("n1.P_mm", Some("n1"), 3.3)
        );
    }

    #[test]
    fn columns_come_in_either_order() {
        let a = parse("phi_deg,P_mm\n0,1\n45,2\n90,3\n135,4\n180,5\n225,6\n270,7\n315,8\n");
        let b = parse("P_mm,phi_deg\n1,0\n2,45\n3,90\n4,135\n5,180\n6,225\n7,270\n8,315\n");
        assert_eq!(a, b);
        assert_eq!(a.values_mm(), &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
    }

    #[test]
    fn comments_and_blank_lines_are_skipped() {
        let text = "# measured on the machine, 2 mm material\n\n  # the header follows\nphi_deg,P_mm\n0,0\n# a comment between rows\n45,1\n\n90,2\n135,3\n180,4\n   \n225,3\n270,2\n315,1\n# end\n";
        let c = parse(text);
        assert_eq!(c.phi_deg(), &[0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0]);
        assert_eq!(c.values_mm()[4], 4.0);
        // Lines are counted as in the file, comments and blanks included.
        let e = fails(&text.replace("135,3", "135,x"));
        assert!(e.starts_with("t.csv:10:5: `x` (P_mm) is not a number"), "{e}");
    }

    /// `text` is refused with an error shown as `start…`, containing `has`.
    fn refused(text: &str, start: &str, has: &str) {
        let e = fails(text);
        assert!(e.starts_with(start) && e.contains(has), "{text:?}:\n{e}");
    }

    #[test]
    fn header_errors_name_the_line_and_the_fix() {
        refused(
            "",
            "t.csv: the curve file has no header",
            "help: write a header `phi_deg,P_mm`",
        );
        refused(
            "# only a comment\n\n",
            "t.csv: the curve file has no header",
            "help: write a header",
        );
        let body = rows(0.0, 30.0, |_| 1.0);
        for (header, start, has) in [
            (
                "# x\nphi_deg;P_mm",
                "t.csv:2:1: the header `phi_deg;P_mm` is one column",
                "help: separate the columns with `,`",
            ),
            (
                "phi_deg,P_mm,Pprime_mm",
                "t.csv:1:14: the header names 3 column(s), `phi_deg`, `P_mm`, `Pprime_mm`; a curve has `phi_deg` and one take-up column",
                "help: give one file per curve; repeated readings repeat the same name, e.g. `phi_deg,P_mm,P_mm,P_mm`",
            ),
            (
                "phi_deg",
                "t.csv:1:1: the header names 1 column(s)",
                "help: write a header",
            ),
            (
                "phi,P_mm",
                "t.csv:1:1: the header has no column `phi_deg` (got `phi`, `P_mm`)",
                "help: name the main-shaft angle column `phi_deg` (deg)",
            ),
            (
                "P_mm,phi_dg",
                "t.csv:1:6: the header has no column `phi_deg` (got `P_mm`, `phi_dg`): did you mean `phi_deg` for `phi_dg`?",
                "help: name",
            ),
            (
                "phi_deg,phi_deg",
                "t.csv:1:1: the header names `phi_deg` twice",
                "help: write a header",
            ),
            (
                "phi_deg,xi_mm",
                "t.csv:1:9: `xi_mm` is not a take-up column; it must say what it is: P_mm, P_B_mm",
                "help: write a header",
            ),
            (
                "phi_deg,n1.P'_mm",
                "t.csv:1:9: `n1.P'_mm` is not a take-up column: did you mean `n1.Pprime_mm`?",
                "help: write a header",
            ),
            (
                "phi_deg,p_mm",
                "t.csv:1:9: `p_mm` is not a take-up column: did you mean `P_mm`?",
                "help: write a header",
            ),
            (
                "phi_deg,P",
                "t.csv:1:9: `P` is not a take-up column; it must say what it is",
                "help: write a header",
            ),
            (
                "phi_deg,n-1.P_mm",
                "t.csv:1:9: `n-1` before the dot in `n-1.P_mm` is not a thread or path name",
                "help: write a header",
            ),
            (
                "phi_deg,.P_mm",
                "t.csv:1:9: `` before the dot in `.P_mm` is not a thread or path name",
                "help: write a header",
            ),
        ] {
            refused(&format!("{header}\n{body}"), start, has);
        }
    }

    #[test]
    fn row_errors_name_the_line_and_the_fix() {
        let head = "phi_deg,P_mm\n0,0\n45,1\n";
        let tail = "180,4\n225,3\n270,2\n315,1\n";
        for (row, start, has) in [
            (
                "90,2,7",
                "t.csv:4:1: the row has 3 fields, the header two (`phi_deg`, `P_mm`)",
                "help: remove the extra fields; one row per φ",
            ),
            // A decimal comma makes an extra field; the help says to use a point.
            ("90,2,5", "t.csv:4:1: the row has 3 fields", "with a point for decimals"),
            (
                "90,2,",
                "t.csv:4:1: the row has 3 fields",
                "help: remove the extra fields",
            ),
            ("90", "t.csv:4:1: the row has one field", "help: add the missing value"),
            (
                "90,",
                "t.csv:4:1: the P_mm value is missing",
                "help: write the take-up P in mm",
            ),
            (",2", "t.csv:4:1: the phi_deg value is missing", "help: write φ in deg"),
            (
                "90, two",
                "t.csv:4:5: `two` (P_mm) is not a number",
                "help: write the take-up P as a number in mm",
            ),
            (
                "9O,2",
                "t.csv:4:1: `9O` (phi_deg) is not a number",
                "help: write φ as a number in deg",
            ),
            (
                "90,inf",
                "t.csv:4:4: `inf` (P_mm) is not a finite number",
                "leave out a row that was not measured",
            ),
            (
                "NaN,2",
                "t.csv:4:1: `NaN` (phi_deg) is not a finite number",
                "help: write φ as a finite number in deg",
            ),
            // Order: strictly increasing.
            (
                "30,2",
                "t.csv:4:1: φ = 30° does not come after φ = 45° on line 3",
                "help: sort the rows by φ and give each φ once",
            ),
        ] {
            refused(&format!("{head}{row}\n{tail}"), start, has);
        }
        // The same φ again is a second reading of it: every φ then needs two.
        refused(
            &format!("{head}45,2\n90,2\n135,3\n{tail}"),
            "t.csv:2:1: φ = 0° has one reading (line 2), while φ = 45° has 2 (line 3)",
            "help: give every φ at least two readings",
        );
        // One turn: the first row again a turn later is refused.
        refused(
            &format!("{head}90,2\n{tail}360,0\n"),
            "t.csv:9:1: φ = 360° is a whole turn or more after the first row's φ = 0° (line 2)",
            "help: give one turn, last φ − first φ < 360°: leave out the row that repeats the first",
        );
        // Too few rows: the header is pointed at.
        refused(
            "# c\nphi_deg,P_mm\n0,0\n90,1\n180,0\n",
            "t.csv:2:1: the curve has 3 row(s) after its header; it needs at least 4",
            "at least every 45°",
        );
        refused(
            "phi_deg,P_mm\n",
            "t.csv:1:1: the curve has 0 row(s)",
            "help: give a row",
        );
    }

    /// Rows every 30° over one turn, each with the readings `f(φ, k)`,
    /// k = 0…n−1, as columns.
    fn repeated(n: usize, f: impl Fn(f64, usize) -> f64) -> String {
        let head: Vec<&str> = std::iter::once("phi_deg")
            .chain(std::iter::repeat_n("P_mm", n))
            .collect();
        let mut text = format!("# resolution_mm = 0.05\n{}\n", head.join(","));
        for k in 0..12 {
            let phi = 30.0 * k as f64;
            let row: Vec<String> = (0..n).map(|j| format!("{}", f(phi, j))).collect();
            text += &format!("{phi},{}\n", row.join(","));
        }
        text
    }

    #[test]
    fn repeated_readings_give_the_mean_curve_with_its_uncertainty() {
        // Columns: 3 readings x − 0.1, x, x + 0.1 → mean x, s = 0.1.
        let c = parse(&repeated(3, |phi, j| phi / 100.0 + 0.1 * (j as f64 - 1.0)));
        let r = c.readings().expect("processed");
        assert_eq!((r.resolution_mm, r.confidence, r.points.len()), (0.05, 0.95, 12));
        let p = &r.points[3];
        assert_eq!((p.phi_deg, p.n), (90.0, 3));
        assert!((p.mean_mm - 0.9).abs() < 1e-12 && (p.s_mm - 0.1).abs() < 1e-12);
        assert!((c.values_mm()[3] - 0.9).abs() < 1e-12);
        let sigma = c.sigma_mm().expect("σ");
        assert!((sigma[3] - (0.01f64 / 3.0 + 0.0025 / 3.0).sqrt()).abs() < 1e-12);
        // t(0.975, 2) = 4.303: Δ_r = 4.303·0.1/√3.
        let half = c.interval_at(&[90.0, 105.0]).unwrap();
        assert!((half[0] - p.total_mm).abs() < 1e-15 && (half[1] - p.total_mm).abs() < 1e-12);
        assert!((p.random_mm - 4.302_652_729_911_275 * 0.1 / 3f64.sqrt()).abs() < 1e-9);
        // Rows per reading read the same; a flag's value stands for the file's.
        let mut rows_text = String::from("# resolution_mm = 0.05\nphi_deg,P_mm\n");
        for k in 0..12 {
            for j in 0..3 {
                rows_text += &format!("{},{}\n", 30 * k, 0.3 * k as f64 + 0.1 * (j as f64 - 1.0));
            }
        }
        let d = parse(&rows_text);
        assert_eq!(d.readings().unwrap().points[3].n, 3);
        assert!((d.values_mm()[3] - 0.9).abs() < 1e-12);
        let o = parse_curve_csv_with(
            &rows_text,
            "t.csv",
            &ReadingOptions {
                resolution_mm: Some(0.2),
                confidence: Some(0.99),
            },
        )
        .unwrap();
        assert_eq!(
            (o.readings().unwrap().resolution_mm, o.readings().unwrap().confidence),
            (0.2, 0.99)
        );
        // A curve of one value per φ carries none of it.
        let plain = parse(&format!("phi_deg,P_mm\n{}", rows(0.0, 30.0, |x| x)));
        assert!(plain.readings().is_none() && plain.sigma_mm().is_none() && plain.interval_at(&[0.0]).is_none());
    }

    #[test]
    fn repeated_readings_errors_name_the_place_and_the_fix() {
        // No resolution.
        let text = repeated(3, |_, j| j as f64).replace("# resolution_mm = 0.05\n", "");
        refused(
            &text,
            "t.csv:1:1: the file holds repeated readings (up to 3 per φ) but not the instrument's resolution",
            "help: add a line `# resolution_mm = 0.05`",
        );
        // Resolution ≤ 0 or not a number.
        refused(
            &repeated(3, |_, j| j as f64).replace("0.05", "0"),
            "t.csv:1:19: the resolution 0 mm is not a length > 0",
            "help: give the instrument's resolution",
        );
        refused(
            &repeated(3, |_, j| j as f64).replace("0.05", "fine"),
            "t.csv:1:19: `fine` (resolution_mm) is not a finite number",
            "help: write it as a number",
        );
        refused(
            &format!("# confidence = 1.5\n{}", repeated(3, |_, j| j as f64)),
            "t.csv:1:16: the confidence 1.5 is not between 0 and 1",
            "help: give the confidence as a fraction",
        );
        let e = parse_curve_csv_with(
            &repeated(3, |_, j| j as f64),
            "t.csv",
            &ReadingOptions {
                resolution_mm: Some(-1.0),
                confidence: None,
            },
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("t.csv: the resolution -1 mm is not a length > 0"), "{e}");
        // A ragged row.
        let text = repeated(3, |_, j| j as f64).replace("\n60,0,1,2\n", "\n60,0,1\n");
        refused(
            &text,
            "t.csv:5:1: the row has 3 field(s), the header 4 (`phi_deg` and 3 readings of `P_mm`)",
            "help: give φ and 3 readings on every row",
        );
        // Not a number.
        refused(
            &repeated(3, |_, j| j as f64).replace("\n60,0,1,2\n", "\n60,0,x,2\n"),
            "t.csv:5:6: `x` (P_mm) is not a number",
            "help: write the take-up P as a number in mm",
        );
        // A φ with one reading among repeated ones.
        let mut text = String::from("# resolution_mm = 0.1\nphi_deg,P_mm\n");
        for k in 0..12 {
            text += &format!("{},1\n", 30 * k);
            if k != 4 {
                text += &format!("{},1.2\n", 30 * k);
            }
        }
        refused(
            &text,
            "t.csv:11:1: φ = 120° has one reading (line 11), while φ = 0° has 2 (line 3)",
            "help: give every φ at least two readings",
        );
        // Huge readings overflow the spread: refused, never NaN.
        refused(
            &repeated(2, |_, j| if j == 0 { -1e308 } else { 1e308 }),
            "t.csv:3:1: the readings of φ = 0° are too large to be processed",
            "help:",
        );
    }

    #[test]
    fn the_turn_must_be_covered_every_45_degrees() {
        // 45° apart everywhere, the closing gap too: accepted.
        parse(&format!("phi_deg,P_mm\n{}", rows(10.0, 45.0, |x| x)));
        // A hole of 60° inside the turn: named by its ends and lines.
        let e = fails("phi_deg,P_mm\n0,0\n40,1\n80,1\n140,2\n180,2\n220,1\n260,1\n300,1\n330,0\n");
        assert!(e.starts_with("t.csv:5:1: no row for 60° of φ, from φ = 80° (line 4) to φ = 140° (line 5); rows may be at most 45° apart"), "{e}");
        assert!(
            e.contains("help: give a row at least every 45° of φ") && e.contains("the line would invent it"),
            "{e}"
        );
        // The gap that closes the turn: from the last row to the first a turn later.
        let e = fails("# c\nphi_deg,P_mm\n100,0\n140,1\n180,1\n220,2\n260,2\n300,1\n340,1\n380,1\n");
        assert!(e.starts_with("t.csv:10:1: no row for 80° of φ, from φ = 380° (line 10) to φ = 460° (line 3, the first row a turn later)"), "{e}");
        // The widest of several gaps is the one named.
        let e = fails("phi_deg,P_mm\n0,0\n50,0\n100,0\n170,0\n200,0\n250,0\n300,0\n");
        assert!(e.contains("no row for 70° of φ, from φ = 100°"), "{e}");
    }

    /// docs/studies.md, "Measured curves (CSV)": its example file reads as
    /// the text says, and its error is the one the reader gives.
    #[test]
    fn the_documented_example_and_error_are_true() {
        let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/studies.md")).unwrap();
        let section = &doc[doc.find("## Measured curves (CSV)").expect("the section")..];
        let example = section
            .split("```csv\n")
            .nth(1)
            .and_then(|b| b.split("```").next())
            .expect("a csv block");
        let c = parse(example);
        assert_eq!(
            (c.kind(), c.split(), c.thread(), c.column()),
            (CurveKind::TakeUp, None, Some("lower"), "lower.P_mm")
        );
        assert_eq!(
            c.phi_deg(),
            (0..12).map(|k| 30.0 * f64::from(k)).collect::<Vec<_>>().as_slice()
        );
        for (x, y) in c.phi_deg().iter().zip(c.values_mm()) {
            assert!((y - 3.0 * (1.0 - x.to_radians().cos())).abs() < 5e-4, "{x}: {y}");
        }
        // Halfway from 330° to 360° = 0°: 0.201 mm.
        assert!((c.value_at(345.0) - 0.201).abs() < 1e-12);
        let e = fails("phi_deg,P_mm\n0,0\n40,1\n80,1\n140,2\n180,2\n220,1\n260,1\n300,1\n330,0\n");
        let first = e.lines().next().unwrap();
        assert!(
            section.contains(&format!("× {first}\n")),
            "the doc does not show `{first}`"
        );
    }

    #[test]
    fn a_file_that_cannot_be_read_is_named() {
        let e = read_curve(Path::new("/nonexistent/altin.csv")).unwrap_err();
        let s = e.to_string();
        assert!(
            s.starts_with("/nonexistent/altin.csv: cannot read the curve file: ")
                && s.contains("help: give the path of a CSV file"),
            "{s}"
        );
    }

    #[test]
    fn a_file_is_read_whole() {
        let dir = std::env::temp_dir().join(format!("stitchkin-measured-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.csv");
        // A comment in another encoding than UTF-8 (0xE6 alone) does not matter.
        let mut bytes = b"# \xe6\n".to_vec();
        bytes.extend(format!("phi_deg,lower.P_mm\n{}", rows(0.0, 10.0, |x| x / 10.0)).bytes());
        std::fs::write(&path, bytes).unwrap();
        let c = read_curve(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(
            (c.source(), c.thread(), c.phi_deg().len(), c.values_mm()[35]),
            (path.display().to_string().as_str(), Some("lower"), 36, 35.0)
        );
    }

    #[test]
    fn resampling_a_sine_is_within_the_linear_bound() {
        // y = 10 sin φ mm sampled every h = 7.5°: |y″| ≤ M = 10 mm/rad², so
        // the line between samples is off by at most M·h²/8 = 0.0214184 mm
        // (h in rad), reached near the crests: 0.0212679 mm at φ = 86° on
        // the 1° grid.
        let sine = |x: f64| 10.0 * x.to_radians().sin();
        let c = parse(&format!("phi_deg,P_mm\n{}", rows(0.0, 7.5, sine)));
        let grid: Vec<f64> = (0..360).map(f64::from).collect();
        let got = c.resample(&grid);
        let bound = 10.0 * 7.5f64.to_radians().powi(2) / 8.0;
        assert!((bound - 0.021418412328752943).abs() < 1e-15);
        let err: Vec<f64> = grid.iter().zip(&got).map(|(x, y)| (y - sine(*x)).abs()).collect();
        assert!(err.iter().all(|e| *e <= bound), "{err:?}");
        let worst = err.iter().cloned().fold(0.0, f64::max);
        assert!(
            (worst - 0.02126790860458705).abs() < 1e-12 && err[86] == worst,
            "{worst}"
        );
        // Literal values: at 4° on [0°, 7.5°], at 86° on [82.5°, 90°].
        assert!((got[4] - 0.696139691840275).abs() < 1e-12 && (got[86] - 9.954372593993655).abs() < 1e-12);
        // At the samples, the samples themselves.
        for (x, y) in c.phi_deg().iter().zip(c.values_mm()) {
            assert_eq!(c.value_at(*x), *y);
        }
    }

    #[test]
    fn resampling_wraps_around_the_turn() {
        // A turn that starts at 200° (as `stitchkin run` writes a cycle
        // from φ0): rows 200, 230, …, 530; the last segment runs from 530°
        // to 560° = 200° a turn later.
        let c = parse(&format!("phi_deg,P_mm\n{}", rows(200.0, 30.0, |x| (x - 200.0) / 10.0)));
        assert_eq!(
            (c.phi_deg()[0], c.phi_deg()[11], c.values_mm()[11]),
            (200.0, 530.0, 33.0)
        );
        // φ in any turn: 215° = −145° = 575° is halfway from 200° to 230°.
        assert_eq!(c.resample(&[215.0, -145.0, 575.0, 935.0]), vec![1.5; 4]);
        // 0° = 360° lies on [350°, 380°]: 15 + 3·(10/30).
        assert!((c.value_at(0.0) - 16.0).abs() < 1e-12 && (c.value_at(360.0) - 16.0).abs() < 1e-12);
        // The closing segment, from 33 mm at 530° (= 170°) back to 0 at 560° (= 200°).
        assert!((c.value_at(540.0) - 22.0).abs() < 1e-12 && (c.value_at(180.0) - 22.0).abs() < 1e-12);
        assert!((c.value_at(199.999999) - 33.0 * 1e-6 / 30.0).abs() < 1e-9);
        assert_eq!(c.value_at(560.0), 0.0);
        assert!(c.value_at(f64::NAN).is_nan() && c.value_at(f64::INFINITY).is_nan());
        assert!(c.resample(&[]).is_empty());
    }

    #[test]
    fn segments_are_found_on_any_turn() {
        let xs = [10.0, 100.0, 190.0, 280.0];
        let s = periodic_segment(&xs, 5.0).unwrap();
        assert_eq!((s.i, s.j, s.from_deg, s.to_deg, s.at_deg), (3, 0, 280.0, 370.0, 365.0));
        let s = periodic_segment(&xs, -260.0).unwrap();
        assert_eq!((s.i, s.j, s.from_deg, s.to_deg, s.at_deg), (1, 2, 100.0, 190.0, 100.0));
        assert!(periodic_segment(&[], 0.0).is_none() && periodic_segment(&xs, f64::NAN).is_none());
        // Rounding that would land on a whole turn stays on the first sample.
        let s = periodic_segment(&xs, 10.0 - 1e-300).unwrap();
        assert!(s.at_deg >= 10.0 && s.at_deg < 370.0, "{s:?}");
    }

    /// What any text gives: an error that shows (file, line, help) or a
    /// curve that keeps every promise of the format; never a panic.
    fn check_any(text: &str) -> Result<(), proptest::test_runner::TestCaseError> {
        use proptest::prelude::*;
        match parse_curve_csv(text, "t.csv") {
            Err(e) => {
                let shown = e.to_string();
                prop_assert!(shown.starts_with("t.csv") && e.help().is_some(), "{shown}");
            }
            Ok(c) => {
                let (x, y) = (c.phi_deg(), c.values_mm());
                let n = x.len();
                prop_assert!(n >= MIN_ROWS && y.len() == n);
                prop_assert!(x.iter().chain(y).all(|v| v.is_finite()));
                prop_assert!(x.windows(2).all(|w| w[1] > w[0] && w[1] - w[0] <= MAX_GAP_DEG));
                prop_assert!(x[n - 1] - x[0] < 360.0 && x[0] + 360.0 - x[n - 1] <= MAX_GAP_DEG);
                if let Some(r) = c.readings() {
                    // Repeated readings: every processed number finite, n ≥ 2, σ given.
                    prop_assert!(r.points.len() == n && r.points.iter().all(|p| p.n >= 2));
                    let finite = r.points.iter().all(|p| {
                        [
                            p.mean_mm,
                            p.s_mm,
                            p.t,
                            p.ci_low_mm,
                            p.ci_high_mm,
                            p.total_mm,
                            p.sigma_mm,
                        ]
                        .iter()
                        .chain(p.relative_pct.iter())
                        .all(|v| v.is_finite())
                    });
                    prop_assert!(finite, "a processed number not finite");
                    prop_assert!(c.sigma_mm().is_some_and(|s| s.len() == n));
                }
                let (lo, hi) = y.iter().fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
                let tol = 1e-9 * (1.0 + lo.abs().max(hi.abs()));
                for v in c.resample(&[x[0], -1e9, -1.5, 0.0, 359.999, 1e12, f64::NAN]) {
                    prop_assert!(
                        v.is_nan() || (lo - tol..=hi + tol).contains(&v),
                        "{v} outside {lo}…{hi}"
                    );
                }
            }
        }
        Ok(())
    }

    /// Pieces of CSV text, good and bad, for the structured garbage.
    fn token() -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        prop_oneof![
            (0u32..40).prop_map(|k| format!("{}", k * 10)),
            any::<f64>().prop_map(|v| format!("{v}")),
            (-1e3f64..1e3).prop_map(|v| format!("{v}")),
            Just(String::new()),
            proptest::sample::select(vec![
                "phi_deg",
                "P_mm",
                "Pprime_B_mm",
                "n1.P_eye_mm",
                ".P_mm",
                "a..P_mm",
                "\"phi_deg\"",
                "\"",
                "#",
                "\u{feff}",
                "φ",
                "′",
                "inf",
                "-nan",
                "1e400",
                "-0",
                " ",
                "\r",
                ";",
                "\t",
                "x",
                "1,5",
                "\n",
                "\n#",
                "\u{10FFFF}",
            ])
            .prop_map(str::to_string),
        ]
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config { cases: 512, ..Default::default() })]

        #[test]
        fn any_text_is_read_or_refused_without_panic(text in "\\PC*") {
            check_any(&text)?;
        }

        #[test]
        fn any_bytes_are_read_or_refused_without_panic(bytes in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..300)) {
            check_any(&String::from_utf8_lossy(&bytes))?;
        }

        #[test]
        fn repeated_garbage_is_read_or_refused_without_panic(
            head in proptest::collection::vec(token(), 0..5),
            body in proptest::collection::vec(proptest::collection::vec(token(), 0..5), 0..20),
        ) {
            let mut text = format!("# resolution_mm = 0.05\n{}", head.join(","));
            for row in &body {
                text.push('\n');
                text.push_str(&row.join(","));
            }
            check_any(&text)?;
        }

        #[test]
        fn repeated_readings_parse_in_either_layout(
            values in proptest::collection::vec(-50.0f64..50.0, 36),
            per_row in proptest::prelude::any::<bool>(),
        ) {
            // Three readings at each of 12 φ, 30° apart.
            let mut text = String::from("# resolution_mm = 0.05\n");
            text += if per_row { "phi_deg,P_mm\n" } else { "phi_deg,P_mm,P_mm,P_mm\n" };
            for k in 0..12 {
                let v = &values[3 * k..3 * k + 3];
                if per_row {
                    for x in v { text += &format!("{},{x}\n", 30 * k) }
                } else {
                    text += &format!("{},{},{},{}\n", 30 * k, v[0], v[1], v[2]);
                }
            }
            let c = parse_curve_csv(&text, "t.csv").map_err(|e| proptest::test_runner::TestCaseError::fail(e.to_string()))?;
            for k in 0..12 {
                let mean = values[3 * k..3 * k + 3].iter().sum::<f64>() / 3.0;
                proptest::prop_assert!((c.values_mm()[k] - mean).abs() < 1e-9);
            }
            check_any(&text)?;
        }

        #[test]
        fn csv_like_garbage_is_read_or_refused_without_panic(
            head in proptest::collection::vec(token(), 0..4),
            body in proptest::collection::vec(proptest::collection::vec(token(), 0..4), 0..14),
            sep in proptest::sample::select(vec![",", ",", ",", ";", ", "]),
        ) {
            let mut text = head.join(sep);
            for row in &body {
                text.push('\n');
                text.push_str(&row.join(sep));
            }
            check_any(&text)?;
        }

        #[test]
        fn good_curves_parse_whatever_their_grid(
            start in -720.0f64..720.0,
            weights in proptest::collection::vec(0.5f64..1.0, 16..60),
            values in proptest::collection::vec(-50.0f64..50.0, 60),
            swap in proptest::prelude::any::<bool>(),
        ) {
            // n steps that fill one turn, the last one closing it: each at
            // most 360°/(16·0.5) = 45°.
            let total: f64 = weights.iter().sum();
            let mut phi = start;
            let mut text = String::from(if swap { "Pprime_mm,phi_deg\n" } else { "# c\nphi_deg,Pprime_mm\n" });
            for (w, v) in weights.iter().zip(&values) {
                if swap { text += &format!("{v},{phi}\n# c\n") } else { text += &format!("{phi},{v}\n\n") }
                phi += w / total * 360.0 * (1.0 - 1e-12);
            }
            let c = parse_curve_csv(&text, "t.csv").map_err(|e| proptest::test_runner::TestCaseError::fail(e.to_string()))?;
            proptest::prop_assert_eq!(c.values_mm(), &values[..weights.len()]);
            proptest::prop_assert_eq!(c.kind(), CurveKind::Required);
            check_any(&text)?;
        }
    }
}
