//! The report job of `stitchkin report` (docs/report.md): the cycle at one
//! setting, the mechanism drawn, and when asked the measured curves, the
//! tuning and the nomogram, computed and handed to
//! [`crate::output::report`], which writes one self-contained HTML file.

use super::{chart_cycle, match_measured};
use crate::error::Error;
use crate::eval::{CycleOptions, check_options, run_cycle};
use crate::model::{Model, Params};
use crate::output::drawing::{DrawOptions, View};
use crate::output::report::{self, MechanismDrawing, Report, Tuning};
use crate::study::nomogram::{NomogramOptions, nomogram};
use crate::study::tune::{TuneOptions, tune};
use crate::thread::measured::MeasuredCurve;

/// What the report holds beyond its fixed sections.
#[derive(Debug, Clone)]
pub struct ReportOptions {
    /// φ step of every cycle, degrees.
    pub step_deg: f64,
    /// Main-shaft angle of the still mechanism drawing, degrees (default:
    /// the model's start).
    pub phi_deg: Option<f64>,
    /// View of the drawings (default: [`View::default_for`] the model).
    pub view: Option<View>,
    /// Include the drawing animated over the cycle.
    pub animate: bool,
    /// Tune the adjustable settings and report the result.
    pub tune: Option<TuneOptions>,
    /// Compute and draw a nomogram.
    pub nomogram: Option<NomogramOptions>,
    /// Measured curves to set beside the model, each with the thread it
    /// belongs to when the file does not say.
    pub measured: Vec<(Option<String>, MeasuredCurve)>,
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            step_deg: 1.0,
            phi_deg: None,
            view: None,
            animate: true,
            tune: None,
            nomogram: None,
            measured: Vec::new(),
        }
    }
}

/// Computes what the report on `model` at `params` shows and writes it as
/// one self-contained HTML document.
pub fn render(model: &Model, params: &Params, opts: &ReportOptions) -> Result<String, Error> {
    check_options(&CycleOptions {
        step_deg: opts.step_deg,
        ..Default::default()
    })?;
    // The tunings' limits, before the report's other work.
    for t in opts.tune.iter().chain(opts.nomogram.as_ref().map(|n| &n.tune)) {
        crate::study::tune::check_samples(t.samples)?;
    }
    let table = run_cycle(model, params, &chart_cycle(opts.step_deg))?;
    let measured = match_measured(&table, &opts.measured)?;
    let drawing = mechanism_drawing(model, params, opts)?;
    let tuning = match &opts.tune {
        Some(t) => Some(tuning(model, params, t, opts.step_deg)?),
        None => None,
    };
    let nomogram = match &opts.nomogram {
        Some(n) => Some(nomogram(model, params, n, || {})?),
        None => None,
    };
    let computed = Report {
        step_deg: opts.step_deg,
        table,
        drawing,
        measured,
        tuning,
        nomogram,
    };
    report::render(model, params, &computed)
}

/// The mechanism at the report's angle, dimensioned, and, when asked,
/// animated over one turn.
fn mechanism_drawing(model: &Model, params: &Params, opts: &ReportOptions) -> Result<MechanismDrawing, Error> {
    let phi = opts.phi_deg.unwrap_or_else(|| model.phi_start_deg());
    let view = opts.view.clone().unwrap_or_else(|| View::default_for(model));
    let still = DrawOptions {
        phi_deg: phi,
        view: view.clone(),
        dimensions: true,
        ..Default::default()
    };
    let still = crate::jobs::drawing::render(model, params, &still)?;
    let animated = if opts.animate {
        let moving = DrawOptions {
            phi_deg: phi,
            view,
            animate: true,
            ..Default::default()
        };
        Some(crate::jobs::drawing::render(model, params, &moving)?)
    } else {
        None
    };
    Ok(MechanismDrawing {
        phi_deg: phi,
        still,
        animated,
    })
}

/// The tuning with `opts` and the cycle at the setting it recommends.
fn tuning(model: &Model, params: &Params, opts: &TuneOptions, step_deg: f64) -> Result<Tuning, Error> {
    let result = tune(model, params, opts)?;
    let mut tuned = params.clone();
    for ((name, _), v) in result.names.iter().zip(&result.after) {
        model.set(&mut tuned, name, *v)?;
    }
    let table = run_cycle(model, &tuned, &chart_cycle(step_deg))?;
    Ok(Tuning { result, table })
}
