//! The requests the page makes, answered without any HTTP machinery so
//! they can be tested directly: [`App::handle`] turns a method and a URL
//! into a [`Reply`].
//!
//! | route | answer |
//! |---|---|
//! | `GET /` | the page (HTML, scripts inline) |
//! | `GET /api/model` | the model: parameters with units, ranges and roles, threads, views |
//! | `GET /api/evaluate?p.NAME=V…&step=DEG` | P/P′ chart (SVG) and the summary: P per path, mismatch per stitch thread, transmission angles |
//! | `GET /api/drawing?p.NAME=V…&phi=DEG&view=V&animate=1` | the mechanism with its threads at φ, or animated over the cycle (SVG) |
//!
//! Every query is checked before any work: an unknown key, a parameter the
//! model lacks or cannot set, a value that is not a number or lies outside
//! the parameter's range, a φ step outside 0.25…10°, more than
//! [`MAX_TRAJECTORIES`] trajectories is a 400 whose JSON
//! body says what and how to fix it (`{"error": …, "help": …}`); a setting
//! the mechanism cannot assemble in is a 422 with the library's message.

use serde_json::{Value, json};
use stitchkin::error::Error;
use stitchkin::eval::{CycleOptions, run_cycle};
use stitchkin::jobs::plot::Plot;
use stitchkin::model::{Model, Params};
use stitchkin::output::plots;

use crate::view::{self, DrawingRequest};

/// The page, with its scripts and styles inline (no other file is served).
const PAGE: &str = include_str!("page.html");

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
        Reply::json(status, &json!({ "error": error.into(), "help": help }))
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

/// The model a server shows, and its nominal settings.
#[derive(Debug, Clone)]
pub struct App {
    pub model: Model,
    /// The settings the page starts from (the model's defaults with any
    /// `--set` of the command line).
    pub base: Params,
}

impl App {
    pub fn new(model: Model, base: Params) -> App {
        App { model, base }
    }

    /// Answers one request. Only GET and HEAD are served (405 otherwise).
    pub fn handle(&self, method: &str, url: &str) -> Reply {
        if method != "GET" && method != "HEAD" {
            return Reply::error(
                405,
                format!("{method} is not served here"),
                Some("the page only reads: use GET"),
            );
        }
        let (path, query) = url.split_once('?').unwrap_or((url, ""));
        if path.len() > MAX_PATH_BYTES {
            return Reply::error(
                414,
                format!("the path is {} bytes, more than {MAX_PATH_BYTES}", path.len()),
                Some("the page is at /, its data under /api/model, /api/evaluate and /api/drawing"),
            );
        }
        if query.len() > MAX_QUERY_BYTES {
            return Reply::error(
                414,
                format!("the query is {} bytes, more than {MAX_QUERY_BYTES}", query.len()),
                None,
            );
        }
        let result = match path {
            "/" | "/index.html" => {
                return Reply {
                    status: 200,
                    content_type: "text/html; charset=utf-8",
                    body: PAGE.as_bytes().to_vec(),
                };
            }
            "/api/model" => Query::parse(query, &[]).map(|_| Reply::json(200, &self.describe())),
            "/api/evaluate" => Query::parse(query, &["step"]).and_then(|q| self.evaluate(&q)),
            "/api/drawing" => {
                Query::parse(query, &["phi", "view", "animate", "trajectories"]).and_then(|q| self.drawing(&q))
            }
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
                Some("the page is at /, its data under /api/model, /api/evaluate and /api/drawing"),
            )),
        };
        result.unwrap_or_else(|reply| reply)
    }

    /// `/api/model`: what the page needs to build its controls.
    pub fn describe(&self) -> Value {
        let model = &self.model;
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
                    "value": self.base.values[i],
                    "nominal": p.value,
                    "range": p.range,
                    "role": role,
                    "source": p.source,
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

    /// The settings a query asks for: the base with each `p.NAME=V` applied
    /// (checked: known, settable, finite, in range), and assembling.
    fn params(&self, q: &Query) -> Result<Params, Reply> {
        let mut params = self.base.clone();
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
            self.model
                .set(&mut params, name, v)
                .map_err(|e| Reply::error(400, format!("{key}: {}", e.message), e.help.as_deref()))?;
        }
        self.model
            .machine::<f64>(&params)
            .map_err(|e| library_error(&Error::Model(e)))?;
        Ok(params)
    }

    /// `/api/evaluate`: the cycle at these settings, charted and summed up.
    fn evaluate(&self, q: &Query) -> Result<Reply, Reply> {
        let params = self.params(q)?;
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
        let opts = CycleOptions {
            step_deg: step,
            analogs: false,
            points: Some(Vec::new()),
            ..Default::default()
        };
        let table = run_cycle(&self.model, &params, &opts).map_err(|e| library_error(&e))?;
        // The chart from the same cycle as the summary.
        let chart = match chart_kind(&self.model) {
            Some(Plot::TakeUp) => Some(plots::take_up(&self.model, &table)),
            Some(_) => Some(plots::transmission(&self.model, &table)),
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
            Some(
                plots::tension(&self.model, &table)
                    .map_err(|e| library_error(&e))?
                    .render(),
            )
        } else {
            None
        };
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
        Ok(Reply::json(
            200,
            &json!({
                "values": self.model.params().iter().zip(&params.values).filter(|(p, _)| !p.is_derived()).map(|(p, v)| (p.name.clone(), json!(v))).collect::<serde_json::Map<_, _>>(),
                "step_deg": step,
                "chart_svg": chart,
                "tension_svg": tension_chart,
                "paths": paths,
                "stitch": stitch,
                "caveats": self.model.caveats(),
                "transmission": table.transmission,
                "warnings": warnings,
            }),
        ))
    }

    /// `/api/drawing`: the mechanism at φ (or animated), as SVG.
    fn drawing(&self, q: &Query) -> Result<Reply, Reply> {
        let params = self.params(q)?;
        let phi_deg = match q.get("phi") {
            None => self.model.phi_start_deg(),
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
        view::render(&self.model, &params, &request)
            .map(Reply::svg)
            .map_err(|e| library_error(&e))
    }
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
