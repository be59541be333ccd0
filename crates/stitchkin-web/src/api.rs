//! The requests the page makes, answered without any HTTP machinery so
//! they can be tested directly: [`App::handle`] turns a method and a URL
//! into a [`Reply`] ([`App::handle_body`] with a request's body).
//!
//! | route | answer |
//! |---|---|
//! | `GET /` | the page (HTML, scripts inline) |
//! | `GET /api/models` | the model the server started with, every preset with its title, the file limits |
//! | `POST /api/models?name=FILE` | loads the model file in the body (`Content-Type: application/toml`): its key `file:ID`, or the library's message naming the place and the fix |
//! | `POST /api/measured?name=FILE` | reads the measured take-up curve in the body (`Content-Type: text/csv`, the CSV of `stitchkin match --measured`): its key `measured:ID`, what it is (`kind`, `thread`, `readings` per φ, `points`), or the library's message naming the line and the fix |
//! | `GET /api/model?model=KEY` | the model: parameters with units, ranges, roles and labels, threads, views |
//! | `GET /api/evaluate?model=KEY&p.NAME=V…&step=DEG&measured=KEY&measured_thread=T` | P/P′ chart (SVG) and the summary: readouts (a stroke, the thread per stitch), P per path, mismatch per stitch thread, transmission angles; with `measured`, the measured curve on the chart (its mean and error bars x̄ ± Δ for repeated readings) and its match to the model |
//! | `GET /api/drawing?model=KEY&p.NAME=V…&phi=DEG&view=V&animate=1` | the mechanism with its threads at φ, or animated over the cycle (SVG) |
//!
//! Each request names its model: `model=NAME` a preset, `model=file:ID` a
//! model file loaded before (the last [`MAX_FILES`] are kept while the
//! server runs), no `model` the one the server started with. Nothing a
//! request does changes what another one sees. A measured curve is named
//! the same way, `measured=measured:ID` (the last [`MAX_CURVES`] read are
//! kept), and set beside the thread its column names or `measured_thread`.
//!
//! Every query is checked before any work: an unknown key, a parameter the
//! model lacks or cannot set, a value that is not a number or lies outside
//! the parameter's range, a φ step outside 0.25…10°, more than
//! [`MAX_TRAJECTORIES`] trajectories, a measured curve the server does not
//! keep or a thread the model does not compare is a 400 whose JSON
//! body says what and how to fix it (`{"error": …, "help": …}`); a setting
//! the mechanism cannot assemble in is a 422 with the library's message.

use std::sync::{Arc, Mutex, OnceLock};

use serde_json::{Value, json};
use stitchkin::error::{Error, ModelError};
use stitchkin::eval::{CycleOptions, CycleTable, run_cycle};
use stitchkin::jobs::plot::Plot;
use stitchkin::model::file::{Axis as FileAxis, Measure};
use stitchkin::model::{Model, Params};
use stitchkin::output::plots;
use stitchkin::presets;
use stitchkin::study::measured::measured_match;
use stitchkin::study::stroke::{Axis, stroke};
use stitchkin::{CurveKind, MeasuredCurve, parse_curve_csv};

use crate::view::{self, DrawingRequest};

/// The page, with its scripts and styles inline (no other file is served).
const PAGE: &str = include_str!("page.html");

/// The largest model file the page may load, bytes: six times the largest
/// preset (altin504.toml, 43 kB).
pub const MAX_FILE_BYTES: usize = 256 * 1024;

/// Model files kept at once; loading one more forgets the one used least
/// recently.
pub const MAX_FILES: usize = 16;

/// The media type a model file is sent with (`POST /api/models`).
pub const TOML_TYPE: &str = "application/toml";

/// The largest measured curve the page may send, bytes: a reading every
/// 0.25° with twenty readings per φ is about 170 kB (the examples are 3 kB).
pub const MAX_CURVE_BYTES: usize = 256 * 1024;

/// Measured curves kept at once; reading one more forgets the one used
/// least recently.
pub const MAX_CURVES: usize = 16;

/// The media type a measured curve is sent with (`POST /api/measured`).
pub const CSV_TYPE: &str = "text/csv";

/// The longest query accepted, bytes (a model with a hundred parameters
/// needs about 3 kB).
pub const MAX_QUERY_BYTES: usize = 16 * 1024;

/// The longest path accepted, bytes (the routes are a few characters).
pub const MAX_PATH_BYTES: usize = 256;

/// The most trajectories one drawing shows (each named once).
pub const MAX_TRAJECTORIES: usize = 32;

/// The longest piece of a request an error message repeats, characters.
const ECHO_CHARS: usize = 64;

/// `s`, or its first `max_chars` characters and how long it was: for
/// repeating a request in an answer or a log without repeating all of it.
pub fn clip(s: &str, max_chars: usize) -> String {
    match s.char_indices().nth(max_chars) {
        None => s.to_string(),
        Some((end, _)) => format!("{}… ({} bytes)", &s[..end], s.len()),
    }
}

/// The φ step the page asks for by default, and the accepted range, deg.
pub const STEP_DEG: f64 = 1.0;
pub const STEP_RANGE_DEG: [f64; 2] = [0.25, 10.0];

/// An answer: status, content type and body.
#[derive(Debug, Clone, PartialEq)]
pub struct Reply {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
}

impl Reply {
    fn json(status: u16, v: &Value) -> Reply {
        Reply {
            status,
            content_type: "application/json; charset=utf-8",
            body: v.to_string().into_bytes(),
        }
    }
    fn svg(svg: String) -> Reply {
        Reply {
            status: 200,
            content_type: "image/svg+xml; charset=utf-8",
            body: svg.into_bytes(),
        }
    }
    /// A client error: what is wrong and how to fix it.
    pub fn error(status: u16, error: impl Into<String>, help: Option<&str>) -> Reply {
        // Papers by authors and year, as the command line prints them.
        let cite = stitchkin::references::cited;
        Reply::json(status, &json!({ "error": cite(&error.into()), "help": help.map(cite) }))
    }
    /// The body as text (tests, logs).
    pub fn text(&self) -> &str {
        std::str::from_utf8(&self.body).unwrap_or("")
    }
}

/// A library error as the page shows it: parameter problems are the
/// client's (400); a geometry, thread or stitch that cannot be formed with
/// these values is 422; anything else is the server's (500).
fn library_error(e: &Error) -> Reply {
    let status = match e {
        Error::Param(_) => 400,
        Error::Assembly(_)
        | Error::Thread(_)
        | Error::Stitch(_)
        | Error::Physical(_)
        | Error::NotFinite(_)
        | Error::Model(_) => 422,
        _ => 500,
    };
    let message = match e {
        // The file position means nothing on the page; the path does.
        Error::Model(m) if m.path.is_empty() => m.message.clone(),
        Error::Model(m) => format!("{}: {}", m.path, m.message),
        other => other.to_string(),
    };
    Reply::error(status, message, e.help())
}

/// The model a server started with and its settings, and the other models
/// a request may name: the presets, and the model files loaded while it
/// runs.
#[derive(Debug, Clone)]
pub struct App {
    pub model: Model,
    /// The settings the page starts from (the model's defaults with any
    /// `--set` of the command line).
    pub base: Params,
    store: Arc<Store>,
}

/// The presets (each loaded once, when first asked for), the loaded
/// model files and the measured curves read.
#[derive(Debug)]
struct Store {
    presets: Vec<OnceLock<Result<Arc<Model>, String>>>,
    files: Mutex<Kept<Model>>,
    curves: Mutex<Kept<MeasuredCurve>>,
}

/// What was sent and read (model files, measured curves), at most `max`,
/// with when each was last used.
#[derive(Debug)]
struct Kept<T> {
    entries: Vec<KeptEntry<T>>,
    clock: u64,
    max: usize,
}

#[derive(Debug)]
struct KeptEntry<T> {
    id: String,
    item: Arc<T>,
    used: u64,
}

impl<T> Kept<T> {
    fn new(max: usize) -> Kept<T> {
        Kept {
            entries: Vec::new(),
            clock: 0,
            max,
        }
    }

    fn get(&mut self, id: &str) -> Option<Arc<T>> {
        self.clock += 1;
        let clock = self.clock;
        self.entries.iter_mut().find(|e| e.id == id).map(|e| {
            e.used = clock;
            Arc::clone(&e.item)
        })
    }

    fn insert(&mut self, id: String, item: Arc<T>) {
        self.clock += 1;
        if self.entries.len() >= self.max
            && let Some(oldest) = (0..self.entries.len()).min_by_key(|&k| self.entries[k].used)
        {
            self.entries.swap_remove(oldest);
        }
        self.entries.push(KeptEntry {
            id,
            item,
            used: self.clock,
        });
    }
}

/// The model a request names, and the settings it starts from.
struct Chosen<'a> {
    model: Held<'a>,
    base: Params,
}

enum Held<'a> {
    Started(&'a Model),
    Shared(Arc<Model>),
}

impl std::ops::Deref for Held<'_> {
    type Target = Model;
    fn deref(&self) -> &Model {
        match self {
            Held::Started(m) => m,
            Held::Shared(m) => m,
        }
    }
}

/// A file's key: FNV-1a of its bytes, 16 hex digits (the same text is the
/// same model, whatever it is called).
fn file_id(bytes: &[u8]) -> String {
    let hash = bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{hash:016x}")
}

/// The routes, for the help of a 404.
const ROUTES: &str = "the page is at /, its data under /api/models, /api/model, /api/evaluate and /api/drawing; measured curves are sent to /api/measured";

impl App {
    pub fn new(model: Model, base: Params) -> App {
        App {
            model,
            base,
            store: Arc::new(Store {
                presets: presets::ALL.iter().map(|_| OnceLock::new()).collect(),
                files: Mutex::new(Kept::new(MAX_FILES)),
                curves: Mutex::new(Kept::new(MAX_CURVES)),
            }),
        }
    }

    /// Answers one request without a body. Only GET and HEAD are served
    /// (405 otherwise), and POST of a model file or a measured curve
    /// ([`App::handle_body`]).
    pub fn handle(&self, method: &str, url: &str) -> Reply {
        self.handle_body(method, url, None, &[])
    }

    /// Answers one request with its `Content-Type` and body (only `POST
    /// /api/models` and `POST /api/measured` read one).
    pub fn handle_body(&self, method: &str, url: &str, content_type: Option<&str>, body: &[u8]) -> Reply {
        let (path, query) = url.split_once('?').unwrap_or((url, ""));
        let post = method == "POST" && is_upload(path);
        if method != "GET" && method != "HEAD" && !post {
            return Reply::error(
                405,
                format!(
                    "{} is not served at {}",
                    clip(method, ECHO_CHARS),
                    clip(path, ECHO_CHARS)
                ),
                Some(
                    "use GET; only a model file (to /api/models) and a measured curve (to /api/measured) are sent, with POST",
                ),
            );
        }
        if path.len() > MAX_PATH_BYTES {
            return Reply::error(
                414,
                format!("the path is {} bytes, more than {MAX_PATH_BYTES}", path.len()),
                Some(ROUTES),
            );
        }
        if query.len() > MAX_QUERY_BYTES {
            return Reply::error(
                414,
                format!("the query is {} bytes, more than {MAX_QUERY_BYTES}", query.len()),
                None,
            );
        }
        if post {
            return Query::parse(query, &["name"])
                .and_then(|q| {
                    if path == "/api/measured" {
                        self.load_curve(&q, content_type, body)
                    } else {
                        self.load_file(&q, content_type, body)
                    }
                })
                .unwrap_or_else(|reply| reply);
        }
        if path == "/api/measured" {
            return Reply::error(
                405,
                format!("{} is not served at /api/measured", clip(method, ECHO_CHARS)),
                Some(&format!(
                    "send the curve's CSV with POST and `Content-Type: {CSV_TYPE}`; /api/evaluate takes its key as measured=KEY"
                )),
            );
        }
        let result =
            match path {
                "/" | "/index.html" => {
                    return Reply {
                        status: 200,
                        content_type: "text/html; charset=utf-8",
                        body: PAGE.as_bytes().to_vec(),
                    };
                }
                "/api/models" => Query::parse(query, &[]).map(|_| Reply::json(200, &self.models())),
                "/api/model" => Query::parse(query, &["model"])
                    .and_then(|q| self.chosen(&q))
                    .map(|c| Reply::json(200, &describe(&c.model, &c.base))),
                "/api/evaluate" => Query::parse(query, &["model", "step", "measured", "measured_thread"])
                    .and_then(|q| self.evaluate(&q)),
                "/api/drawing" => Query::parse(query, &["model", "phi", "view", "animate", "trajectories"])
                    .and_then(|q| self.drawing(&q)),
                "/favicon.ico" => {
                    return Reply {
                        status: 204,
                        content_type: "image/x-icon",
                        body: Vec::new(),
                    };
                }
                _ => Err(Reply::error(
                    404,
                    format!("there is nothing at {}", clip(path, ECHO_CHARS)),
                    Some(ROUTES),
                )),
            };
        result.unwrap_or_else(|reply| reply)
    }

    /// `/api/model` of the model the server started with: what the page
    /// needs to build its controls.
    pub fn describe(&self) -> Value {
        describe(&self.model, &self.base)
    }

    /// The preset the server started with, when it started with one as it
    /// ships (no `--set`).
    fn started_preset(&self) -> Option<&str> {
        let name = self.model.file_name().strip_prefix("preset:")?;
        let preset = presets::find(name)?;
        let same = self.model.defaults().values == self.base.values && self.model.text() == preset.toml;
        same.then_some(preset.name)
    }

    /// `/api/models`: the model the server started with, the presets, and
    /// how large a file may be loaded.
    fn models(&self) -> Value {
        let changed: serde_json::Map<String, Value> = self
            .model
            .params()
            .iter()
            .zip(self.model.defaults().values.iter().zip(&self.base.values))
            .filter(|(p, (d, v))| !p.is_derived() && d != v)
            .map(|(p, (_, v))| (p.name.clone(), json!(v)))
            .collect();
        let presets: Vec<Value> = presets::ALL
            .iter()
            .enumerate()
            .map(|(k, p)| match self.preset(k) {
                Ok(m) => json!({
                    "name": p.name,
                    "title": m.title(),
                    "seed": m.seed(),
                    "after": m.seed().and_then(stitchkin::references::cite_seed),
                }),
                Err(e) => json!({ "name": p.name, "title": null, "error": e }),
            })
            .collect();
        json!({
            "started": {
                "preset": self.started_preset(),
                "name": self.model.name(),
                "title": self.model.title(),
                "file": self.model.file_name(),
                "changed": changed,
            },
            "presets": presets,
            "default_preset": presets::DEFAULT,
            "max_file_bytes": MAX_FILE_BYTES,
            "max_files": MAX_FILES,
            "max_curve_bytes": MAX_CURVE_BYTES,
            "max_curves": MAX_CURVES,
        })
    }

    /// Preset `k` of [`presets::ALL`], loaded once.
    fn preset(&self, k: usize) -> Result<Arc<Model>, String> {
        self.store.presets[k]
            .get_or_init(|| {
                Model::preset(presets::ALL[k].name)
                    .map(Arc::new)
                    .map_err(|e| e.to_string())
            })
            .clone()
    }

    /// The model a query names (`model=NAME` a preset, `model=file:ID` a
    /// loaded file, none the model the server started with).
    fn chosen(&self, q: &Query) -> Result<Chosen<'_>, Reply> {
        let Some(key) = q.get("model") else {
            return Ok(Chosen {
                model: Held::Started(&self.model),
                base: self.base.clone(),
            });
        };
        let model = if let Some(id) = key.strip_prefix("file:") {
            let kept = self.store.files.lock().ok().and_then(|mut f| f.get(id));
            kept.ok_or_else(|| {
                Reply::error(
                    404,
                    format!(
                        "the model file `file:{}` is not kept by this server",
                        clip(id, ECHO_CHARS)
                    ),
                    Some(&format!(
                        "the server keeps the last {MAX_FILES} files loaded while it runs: load the file again"
                    )),
                )
            })?
        } else {
            let Some(k) = presets::ALL.iter().position(|p| p.name == key) else {
                let names: Vec<&str> = presets::ALL.iter().map(|p| p.name).collect();
                return Err(Reply::error(
                    400,
                    format!("model = `{}` is not a preset", clip(key, ECHO_CHARS)),
                    Some(&format!(
                        "the presets are {}; a loaded model file is file:ID (POST /api/models gives the ID); leave model out for the model the server started with",
                        names.join(", ")
                    )),
                ));
            };
            self.preset(k).map_err(|e| Reply::error(500, e, None))?
        };
        Ok(Chosen {
            base: model.defaults(),
            model: Held::Shared(model),
        })
    }

    /// `POST /api/models?name=FILE`: loads the model file in the body with
    /// the library's loader and keeps it under its key.
    fn load_file(&self, q: &Query, content_type: Option<&str>, body: &[u8]) -> Result<Reply, Reply> {
        let media = content_type.and_then(|c| c.split(';').next()).map(str::trim);
        if !media.is_some_and(|m| m.eq_ignore_ascii_case(TOML_TYPE)) {
            return Err(Reply::error(
                415,
                format!(
                    "a model file is sent as {TOML_TYPE}, not {}",
                    clip(content_type.unwrap_or("without a Content-Type"), ECHO_CHARS)
                ),
                Some(&format!(
                    "send the file's text as the body with `Content-Type: {TOML_TYPE}`"
                )),
            ));
        }
        if body.len() > MAX_FILE_BYTES {
            return Err(too_large("/api/models", Some(body.len())));
        }
        if body.is_empty() {
            return Err(Reply::error(
                400,
                "the model file is empty",
                Some("choose a TOML model file (presets/*.toml are examples; docs/model-format.md describes them)"),
            ));
        }
        let name = sent_name(q, "model.toml");
        let id = file_id(body);
        let kept = self.store.files.lock().ok().and_then(|mut f| f.get(&id));
        let model = match kept {
            Some(m) => m,
            None => {
                let model = Arc::new(Model::from_toml_bytes(body, &name).map_err(|e| file_error(&e, 422))?);
                if let Ok(mut files) = self.store.files.lock() {
                    files.insert(id.clone(), Arc::clone(&model));
                }
                model
            }
        };
        Ok(Reply::json(
            200,
            &json!({
                "model": format!("file:{id}"),
                "name": model.name(),
                "title": model.title(),
                "file": model.file_name(),
            }),
        ))
    }

    /// `POST /api/measured?name=FILE`: reads the measured take-up curve in
    /// the body with the library's reader (as `stitchkin match --measured`
    /// does: repeated readings processed per φ, seed 004 §3.4) and keeps it
    /// under its key.
    fn load_curve(&self, q: &Query, content_type: Option<&str>, body: &[u8]) -> Result<Reply, Reply> {
        let media = content_type.and_then(|c| c.split(';').next()).map(str::trim);
        if !media.is_some_and(|m| m.eq_ignore_ascii_case(CSV_TYPE)) {
            return Err(Reply::error(
                415,
                format!(
                    "a measured curve is sent as {CSV_TYPE}, not {}",
                    clip(content_type.unwrap_or("without a Content-Type"), ECHO_CHARS)
                ),
                Some(&format!(
                    "send the CSV file's text as the body with `Content-Type: {CSV_TYPE}`"
                )),
            ));
        }
        if body.len() > MAX_CURVE_BYTES {
            return Err(too_large("/api/measured", Some(body.len())));
        }
        if body.is_empty() {
            return Err(Reply::error(400, "the measured curve is empty", Some(CURVE_HELP)));
        }
        let name = sent_name(q, "measured.csv");
        let id = file_id(body);
        let kept = self.store.curves.lock().ok().and_then(|mut c| c.get(&id));
        let curve = match kept {
            Some(c) => c,
            None => {
                // Bytes that are not UTF-8 read as U+FFFD, as the command
                // line reads a file: they fail where a number is expected.
                let text = String::from_utf8_lossy(body);
                let curve = Arc::new(parse_curve_csv(&text, &name).map_err(|e| curve_error(&e))?);
                if let Ok(mut curves) = self.store.curves.lock() {
                    curves.insert(id.clone(), Arc::clone(&curve));
                }
                curve
            }
        };
        Ok(Reply::json(200, &curve_summary(&id, &curve)))
    }

    /// The measured curve a query names (`measured=measured:ID`), or the
    /// 400 that says how to send it.
    fn curve(&self, key: &str) -> Result<Arc<MeasuredCurve>, Reply> {
        let kept = key
            .strip_prefix("measured:")
            .and_then(|id| self.store.curves.lock().ok().and_then(|mut c| c.get(id)));
        kept.ok_or_else(|| {
            Reply::error(
                400,
                format!(
                    "measured = `{}` is not a measured curve this server keeps",
                    clip(key, ECHO_CHARS)
                ),
                Some(&format!(
                    "send the curve's CSV to POST /api/measured (on the page: Measured take-up (CSV)) and give the key it answers, measured:ID; the server keeps the last {MAX_CURVES} curves read while it runs"
                )),
            )
        })
    }

    /// The measured curve a query names and the thread it asks for it
    /// (`measured=KEY&measured_thread=T`), checked.
    fn measured<'q>(&self, q: &'q Query) -> Result<(Option<Arc<MeasuredCurve>>, Option<&'q str>), Reply> {
        let measured = q.get("measured").map(|key| self.curve(key)).transpose()?;
        let thread = q.get("measured_thread").map(str::trim).filter(|t| !t.is_empty());
        if measured.is_none() && q.get("measured_thread").is_some() {
            return Err(Reply::error(
                400,
                "measured_thread names the thread of a measured curve, and no measured curve is given",
                Some("give measured=KEY (from POST /api/measured) with it, or leave measured_thread out"),
            ));
        }
        if let Some(t) = thread
            && t.chars().count() > ECHO_CHARS
        {
            return Err(Reply::error(
                400,
                format!("measured_thread: no thread is named `{}`", clip(t, ECHO_CHARS)),
                Some("name one of the model's stitch threads (the evaluation lists them under stitch.threads)"),
            ));
        }
        Ok((measured, thread))
    }

    /// The settings a query asks for: the chosen model's base with each
    /// `p.NAME=V` applied (checked: known, settable, finite, in range), and
    /// assembling.
    fn params(&self, c: &Chosen, q: &Query) -> Result<Params, Reply> {
        let mut params = c.base.clone();
        for (name, value) in &q.params {
            let key = format!("p.{}", clip(name, ECHO_CHARS));
            if name.chars().count() > ECHO_CHARS {
                return Err(Reply::error(
                    400,
                    format!("{key}: no parameter has so long a name"),
                    Some("/api/model lists the parameters"),
                ));
            }
            let v = number(value, &key)?;
            c.model
                .set(&mut params, name, v)
                .map_err(|e| Reply::error(400, format!("{key}: {}", e.message), e.help.as_deref()))?;
        }
        c.model
            .machine::<f64>(&params)
            .map_err(|e| library_error(&Error::Model(e)))?;
        Ok(params)
    }

    /// `/api/evaluate`: the cycle at these settings, charted and summed up.
    fn evaluate(&self, q: &Query) -> Result<Reply, Reply> {
        let c = self.chosen(q)?;
        let model = &*c.model;
        let params = self.params(&c, q)?;
        let step = match q.get("step") {
            None => STEP_DEG,
            Some(s) => {
                let v = number(s, "step")?;
                let [lo, hi] = STEP_RANGE_DEG;
                if !(lo..=hi).contains(&v) {
                    return Err(Reply::error(
                        400,
                        format!("step = {v} deg is outside {lo}…{hi} deg"),
                        Some("a φ step of 1 deg draws smooth curves; 0.25 is finest"),
                    ));
                }
                v
            }
        };
        // The measured curve and its thread, checked before any work.
        let (measured, measured_thread) = self.measured(q)?;
        // What the page shows and charts: no analogs, no point columns, and
        // lean (no link angles, no per-guide wrap or tension columns, no
        // best lag; none of them is read below).
        let opts = CycleOptions {
            points: Some(Vec::new()),
            ..CycleOptions::for_figures(step)
        };
        let table = run_cycle(model, &params, &opts).map_err(|e| library_error(&e))?;
        // The measured curve beside its thread, on the cycle's grid.
        let matches = match &measured {
            None => Vec::new(),
            Some(curve) => vec![set_beside(&table, curve, measured_thread)?],
        };
        // The chart from the same cycle as the summary.
        let chart = match chart_kind(model) {
            Some(Plot::TakeUp) => Some(plots::take_up_with_measured(model, &table, &matches)),
            Some(_) => Some(plots::transmission(model, &table)),
            None => None,
        };
        let chart = chart.transpose().map_err(|e| library_error(&e))?.map(|c| c.render());
        // The thread's tension beside P and P′, where it is solved.
        let has_tension = table
            .stitch
            .iter()
            .flat_map(|s| &s.threads)
            .any(|t| t.tension.is_some());
        let tension_chart = if has_tension {
            Some(plots::tension(model, &table).map_err(|e| library_error(&e))?.render())
        } else {
            None
        };
        let readouts = readouts(model, &params, &table, step)?;
        let paths: Vec<Value> = table
            .paths
            .iter()
            .map(|p| json!({ "path": p.path, "thread": p.thread, "split": p.split, "max_p_mm": p.max_p_mm, "phi_at_max_deg": p.phi_at_max_deg, "min_p_mm": p.min_p_mm }))
            .collect();
        let threads: Vec<Value> = table
            .stitch
            .iter()
            .flat_map(|s| s.threads.iter())
            .map(|t| {
                let m = t.mismatch.as_ref();
                json!({
                    "thread": t.thread,
                    "path": t.path,
                    "per_stitch_mm": t.per_stitch_mm,
                    "max_pprime_mm": t.max_pprime_mm,
                    "split": t.split,
                    "max_pprime_eye_mm": t.max_pprime_eye_mm,
                    "regulator_windows_deg": t.regulator_windows_deg,
                    "regulator_computed": t.regulator_computed,
                    "tension": t.tension,
                    "rms_d_mm": m.map(|m| m.rms_d_mm),
                    "max_abs_d_mm": m.map(|m| m.max_abs_d_mm),
                    "max_abs_d_at_deg": m.map(|m| m.max_abs_d_at_deg),
                    "phase_shift_max_deg": m.map(|m| m.phase_shift_max_deg),
                    "score": m.and_then(|m| m.score),
                })
            })
            .collect();
        let stitch = table.stitch.as_ref().map(|s| {
            json!({
                "type": s.stitch_type,
                "m_mm": s.m_mm,
                "t_mm": s.t_mm,
                "threads": threads,
                "checks": s.checks,
                "regulator": s.regulator,
                "transfers": s.transfers,
            })
        });
        let mut warnings = table.warnings.clone();
        if let Some(s) = &table.stitch {
            warnings.extend(s.warnings.iter().cloned());
        }
        let mut answer = json!({
                "values": model.params().iter().zip(&params.values).filter(|(p, _)| !p.is_derived()).map(|(p, v)| (p.name.clone(), json!(v))).collect::<serde_json::Map<_, _>>(),
                "step_deg": step,
                "readouts": readouts,
                "chart_svg": chart,
                "tension_svg": tension_chart,
                "paths": paths,
                "stitch": stitch,
                // Papers by authors and year, as the command line prints them.
                "caveats": model
                    .caveats()
                    .iter()
                    .map(|c| stitchkin::references::cited(c).into_owned())
                    .collect::<Vec<_>>(),
                "transmission": table.transmission,
                // Every check of the cycle: the stitch's, then each cam's.
                "checks": table.all_checks().collect::<Vec<_>>(),
                "cams": table.cams,
                "warnings": warnings,
        });
        if let (Some(m), Some(key)) = (matches.first(), q.get("measured")) {
            answer["measured"] = measured_json(key, m, &table)?;
        }
        Ok(Reply::json(200, &answer))
    }

    /// `/api/drawing`: the mechanism at φ (or animated), as SVG.
    fn drawing(&self, q: &Query) -> Result<Reply, Reply> {
        let c = self.chosen(q)?;
        let params = self.params(&c, q)?;
        let phi_deg = match q.get("phi") {
            None => c.model.phi_start_deg(),
            Some(s) => number(s, "phi")?,
        };
        let animate = match q.get("animate") {
            None | Some("0") | Some("false") => false,
            Some("1") | Some("true") => true,
            Some(other) => {
                return Err(Reply::error(
                    400,
                    format!("animate = `{}` is not a switch", clip(other, ECHO_CHARS)),
                    Some("write animate=1 to animate over the cycle, animate=0 for a still"),
                ));
            }
        };
        let trajectories = trajectories(q.get("trajectories").unwrap_or(""))?;
        let view = q.get("view").unwrap_or("auto");
        if view.chars().count() > ECHO_CHARS {
            return Err(Reply::error(
                400,
                format!("view = `{}` is not a view of this model", clip(view, ECHO_CHARS)),
                Some("/api/model lists the views"),
            ));
        }
        let request = DrawingRequest {
            phi_deg,
            view: view.to_string(),
            animate,
            trajectories,
        };
        view::render(&c.model, &params, &request)
            .map(Reply::svg)
            .map_err(|e| library_error(&e))
    }
}

/// `/api/model` of a model from its starting settings.
fn describe(model: &Model, base: &Params) -> Value {
    let m_param = model.stitch_param("m").map(str::to_string);
    let t_param = model.stitch_param("t").map(str::to_string);
    let parameters: Vec<Value> = model
        .params()
        .iter()
        .enumerate()
        .filter(|(_, p)| !p.is_derived())
        .map(|(i, p)| {
            let role = if Some(&p.name) == m_param.as_ref() {
                "thickness"
            } else if Some(&p.name) == t_param.as_ref() {
                "stitch_length"
            } else if p.range.is_some() {
                "adjustable"
            } else {
                "setting"
            };
            json!({
                "name": p.name,
                "unit": p.unit_str(),
                "value": base.values[i],
                "nominal": p.value,
                "range": p.range,
                "role": role,
                "source": p.source.as_deref().map(stitchkin::references::cited),
                "kind": p.kind.as_str(),
                "label": p.label,
                "what": p.what,
            })
        })
        .collect();
    let threads: Vec<&str> = model.thread_path_names();
    json!({
        "name": model.name(),
        "title": model.title(),
        "file": model.file_name(),
        "phi_start_deg": model.phi_start_deg(),
        "parameters": parameters,
        "stitch": model.stitch_type().map(|t| json!({ "type": t, "m_param": m_param, "t_param": t_param })),
        "threads": threads,
        "chart": chart_kind(model).map(|p| match p { Plot::TakeUp => "takeup", _ => "mu" }),
        "views": view::names(model),
        "moving_points": model.moving_point_names(),
        "step_deg": STEP_DEG,
    })
}

/// The quantities a model is about, as figures the page shows first: the
/// thread each stitch takes, per stitch thread, for a model with a stitch
/// process (the stitch's own contour, as `stitchkin consumption`); for a
/// model without one, the stroke of every point a `coordinate` measure
/// follows (max − min along its axis, as `stitchkin stroke`: the needle
/// bar's stroke of needle876).
fn readouts(model: &Model, params: &Params, table: &CycleTable, step_deg: f64) -> Result<Vec<Value>, Reply> {
    if let Some(s) = &table.stitch {
        return Ok(s
            .threads
            .iter()
            .map(|t| {
                json!({
                    "name": format!("{}.per_stitch", t.thread),
                    "label": format!("thread per stitch, {}", t.thread),
                    "value": t.per_stitch_mm,
                    "unit": "mm",
                    "what": format!(
                        "the {} thread one finished stitch {} takes (m = {} mm, t = {} mm), from the stitch's contour",
                        t.thread, s.stitch_type, s.m_mm, s.t_mm
                    ),
                })
            })
            .collect());
    }
    let mut out = Vec::new();
    for m in &model.file().measures {
        let Measure::Coordinate {
            name,
            point,
            axis,
            frame,
            from,
        } = m
        else {
            continue;
        };
        // A coordinate from a moving point is not the point's stroke.
        let from_moving = from
            .as_deref()
            .is_some_and(|f| model.point_slot(f).is_ok_and(|s| !model.is_fixed(s)));
        let FileAxis::Named(letter) = axis else { continue };
        let letter = letter.trim_start_matches(['-', '+']);
        let spec = match frame.as_deref() {
            Some(f) if f != "world" => format!("{f}.{letter}"),
            _ => letter.to_string(),
        };
        let (Ok(slot), Ok(axis)) = (model.moving_point_slot(point), Axis::parse(model, &spec)) else {
            continue;
        };
        if from_moving {
            continue;
        }
        let s = stroke(model, params, slot, &axis, step_deg).map_err(|e| library_error(&e))?;
        let at = |d: &stitchkin::study::stroke::DeadCentre| {
            d.phi_deg.map_or_else(String::new, |p| format!(" at φ = {p:.1}°"))
        };
        out.push(json!({
            "name": format!("{name}.stroke"),
            "label": format!("{name} stroke"),
            "value": s.stroke_mm,
            "unit": "mm",
            "what": format!(
                "the travel of {point} along {}: from {:.2} mm{} to {:.2} mm{} (as `stitchkin stroke --point {point} --axis {spec}`)",
                axis.describe(),
                s.min.position_mm,
                at(&s.min),
                s.max.position_mm,
                at(&s.max),
            ),
        }));
    }
    Ok(out)
}

/// Whether `path` takes a POST with a body: a model file or a measured
/// curve.
pub fn is_upload(path: &str) -> bool {
    path == "/api/models" || path == "/api/measured"
}

/// The largest body a POST to `path` may carry, bytes.
pub fn max_body_bytes(path: &str) -> usize {
    if path == "/api/measured" {
        MAX_CURVE_BYTES
    } else {
        MAX_FILE_BYTES
    }
}

/// What a POST to `path` sends, for messages: "the model file" or "the
/// measured curve".
pub fn body_name(path: &str) -> &'static str {
    if path == "/api/measured" {
        "the measured curve"
    } else {
        "the model file"
    }
}

/// A body sent to `path` beyond [`max_body_bytes`] (its size when known).
pub fn too_large(path: &str, bytes: Option<usize>) -> Reply {
    let size = bytes.map_or_else(|| "larger".to_string(), |b| format!("{b} bytes"));
    let max = max_body_bytes(path);
    let help = if path == "/api/measured" {
        "choose the CSV file of the curve itself: a curve with ten readings every 10 deg is about 3 kB"
    } else {
        "choose the TOML model file itself: a model file is a few tens of kB (the largest preset, altin504.toml, is 43 kB)"
    };
    Reply::error(
        413,
        format!(
            "{} is {size}, more than the {} kB ({max} bytes) this server {}",
            body_name(path),
            max / 1024,
            if path == "/api/measured" { "reads" } else { "loads" }
        ),
        Some(help),
    )
}

/// The name a POST gives its file (`name=FILE`), for the messages: no
/// folders, not too long; `default` without one.
fn sent_name(q: &Query, default: &str) -> String {
    let name = q.get("name").map(|n| n.rsplit(['/', '\\']).next().unwrap_or(n).trim());
    match name {
        Some(n) if !n.is_empty() && !n.chars().any(char::is_control) => clip_name(n),
        _ => default.to_string(),
    }
}

/// What a measured curve's CSV looks like, for the help of an empty one.
const CURVE_HELP: &str = "choose a CSV file with a header `phi_deg,P_mm` (or `phi_deg,THREAD.P_B_mm`, `Pprime_mm` …) and one row per φ, \
    or the value column repeated once per reading with a line `# resolution_mm = 0.05` (examples/seed004-bench-lower.csv is one; docs/studies.md describes them)";

/// A measured curve that cannot be read: the library's message with its
/// place and fix (400), the line itself when the message names one.
fn curve_error(e: &Error) -> Reply {
    match e {
        Error::Model(m) => file_error(m, 400),
        other => Reply::error(400, other.to_string(), other.help()),
    }
}

/// What `POST /api/measured` answers: the curve's key and what it is.
fn curve_summary(id: &str, c: &MeasuredCurve) -> Value {
    let r = c.readings();
    let half: Vec<f64> = r
        .map(|r| r.points.iter().map(|p| p.total_mm).filter(|h| h.is_finite()).collect())
        .unwrap_or_default();
    let interval = (!half.is_empty()).then(|| {
        [
            half.iter().copied().fold(f64::INFINITY, f64::min),
            half.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        ]
    });
    let phis = c.phi_deg();
    json!({
        "key": format!("measured:{id}"),
        "file": c.source(),
        "column": c.column(),
        "kind": c.kind(),
        "what": match c.kind() {
            CurveKind::TakeUp => "P, an actual take-up",
            CurveKind::Required => "P′, a required take-up",
        },
        "split": c.split(),
        "thread": c.thread(),
        "readings": r.map_or(1, |r| r.max_n()),
        "points": phis.len(),
        "phi_deg": [phis.first(), phis.last()],
        "resolution_mm": r.map(|r| r.resolution_mm),
        "confidence": r.map(|r| r.confidence),
        "interval_mm": interval,
        "outliers": r.map(|r| r.outlier_count()),
    })
}

/// `curve` set beside its thread of the cycle `table` (`thread`, else the
/// one its column names); the library's message otherwise, with the
/// threads it can be set beside (`threads`, for the page's menu).
fn set_beside(
    table: &CycleTable,
    curve: &MeasuredCurve,
    thread: Option<&str>,
) -> Result<stitchkin::study::measured::MeasuredMatch, Reply> {
    measured_match(table, curve, thread).map_err(|e| {
        let mut reply = library_error(&e);
        if let Ok(mut v) = serde_json::from_slice::<Value>(&reply.body) {
            v["threads"] = json!(comparable_threads(table));
            reply.body = v.to_string().into_bytes();
        }
        reply
    })
}

/// The threads of a cycle a measured curve can be set beside: the stitch
/// threads compared with a path, or without a stitch the thread paths.
fn comparable_threads(table: &CycleTable) -> Vec<&str> {
    match &table.stitch {
        Some(s) => s
            .threads
            .iter()
            .filter(|t| t.path.is_some())
            .map(|t| t.thread.as_str())
            .collect(),
        None => table.paths.iter().map(|p| p.path.as_str()).collect(),
    }
}

/// The measured curve's match in the evaluation: the library's
/// [`MeasuredMatch`](stitchkin::study::measured::MeasuredMatch) with the
/// curve's key.
fn measured_json(key: &str, m: &stitchkin::study::measured::MeasuredMatch, table: &CycleTable) -> Result<Value, Reply> {
    let mut v = serde_json::to_value(m)
        .map_err(|e| Reply::error(500, format!("the measured match could not be written: {e}"), None))?;
    v["key"] = json!(key);
    v["threads"] = json!(comparable_threads(table));
    Ok(v)
}

/// A file name for messages: at most 100 characters.
fn clip_name(name: &str) -> String {
    match name.char_indices().nth(100) {
        None => name.to_string(),
        Some((end, _)) => format!("{}…", &name[..end]),
    }
}

/// A file that does not load (a model file: 422; a measured curve: 400):
/// the library's message with the place (file, line and column, the key
/// path) and the fix, and the line itself.
fn file_error(e: &ModelError, status: u16) -> Reply {
    let (line, column) = e.line_col().unzip();
    let mut message = match (line, column) {
        (Some(l), Some(c)) => format!("{}:{l}:{c}: ", e.file),
        _ => format!("{}: ", e.file),
    };
    if !e.path.is_empty() {
        message += &format!("{}: ", e.path);
    }
    message += &e.message;
    let excerpt = line.and_then(|l| e.text.lines().nth(l - 1)).map(|t| clip(t, 200));
    Reply::json(
        status,
        &json!({
            "error": stitchkin::references::cited(&message),
            "help": e.help.as_deref().map(stitchkin::references::cited),
            "line": line,
            "column": column,
            "excerpt": excerpt,
        }),
    )
}

/// The points of `trajectories=A,B…`, each once, in their first order; more
/// than [`MAX_TRAJECTORIES`] is a 400.
fn trajectories(list: &str) -> Result<Vec<String>, Reply> {
    let mut names: Vec<String> = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        if name.chars().count() > ECHO_CHARS {
            return Err(Reply::error(
                400,
                format!("trajectories: no point is named `{}`", clip(name, ECHO_CHARS)),
                Some("/api/model lists the points under moving_points"),
            ));
        }
        if names.iter().any(|n| n == name) {
            continue;
        }
        if names.len() == MAX_TRAJECTORIES {
            return Err(Reply::error(
                400,
                format!("trajectories names more than {MAX_TRAJECTORIES} points"),
                Some("name each moving point at most once (/api/model lists them under moving_points)"),
            ));
        }
        names.push(name.to_string());
    }
    Ok(names)
}

/// The chart the page shows: P/P′ for a model with threads, otherwise its
/// transmission angles, otherwise none.
fn chart_kind(model: &Model) -> Option<Plot> {
    if model.has_threads() {
        Some(Plot::TakeUp)
    } else if !model.dyads().is_empty() {
        Some(Plot::Mu)
    } else {
        None
    }
}

/// A number from the query, or a 400 naming the key.
fn number(s: &str, key: &str) -> Result<f64, Reply> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(Reply::error(
            400,
            format!("{key} = `{}` is not a finite number", clip(s, ECHO_CHARS)),
            Some("write a plain decimal number in the parameter's unit (mm, deg or N), e.g. 5.25"),
        )),
    }
}

/// A checked query: the parameter settings (`p.NAME=V`) and the other keys
/// the route allows, each at most once.
#[derive(Debug, Default)]
struct Query {
    params: Vec<(String, String)>,
    other: Vec<(String, String)>,
}

impl Query {
    fn parse(query: &str, allowed: &[&str]) -> Result<Query, Reply> {
        let mut q = Query::default();
        for (key, value) in form_urlencoded::parse(query.as_bytes()) {
            let (key, value) = (key.into_owned(), value.into_owned());
            let seen = q.params.iter().any(|(k, _)| key.strip_prefix("p.") == Some(k))
                || q.other.iter().any(|(k, _)| *k == key);
            if seen {
                return Err(Reply::error(
                    400,
                    format!("`{}` is given twice", clip(&key, ECHO_CHARS)),
                    Some("give each key once"),
                ));
            }
            if let Some(name) = key.strip_prefix("p.") {
                q.params.push((name.to_string(), value));
            } else if allowed.contains(&key.as_str()) {
                q.other.push((key, value));
            } else {
                let mut keys: Vec<String> = allowed.iter().map(|k| k.to_string()).collect();
                keys.push("p.NAME (a parameter)".into());
                return Err(Reply::error(
                    400,
                    format!("unknown query key `{}`", clip(&key, ECHO_CHARS)),
                    Some(&format!("this route takes: {}", keys.join(", "))),
                ));
            }
        }
        Ok(q)
    }

    fn get(&self, key: &str) -> Option<&str> {
        self.other.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }
}
