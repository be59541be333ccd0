//! `stitchkin._native`: the library's models and cycles for Python, the
//! columns as NumPy arrays. The package `stitchkin` (python/stitchkin)
//! re-exports it with the Python-side helpers (`Table.to_pandas`).
//!
//! A thin shell, as the command line is: every computation is the
//! library's, and a call that computes releases the GIL.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use stitchkin::error::Input;
use stitchkin::eval::{CycleOptions, PathLengths, run_cycle, run_cycle_columns};
use stitchkin::model::{Model as LibModel, Params};
use stitchkin::study::design::{Design, Sweep, Vary};
use stitchkin::study::sweep::{self, Row, SweepPlan};
use stitchkin::study::{fit_measured, tune};

// Named in the package (`stitchkin.StitchkinError`), where it is
// re-exported: pickling finds it there (a Dask worker's error reaches the
// client with its attributes).
create_exception!(
    stitchkin,
    StitchkinError,
    PyException,
    "An error of stitchkin: a model file that does not load, a parameter out of its range, a position \
     with no assembly, a thread or stitch that cannot be formed. Its attributes say where and what to do: \
     `file`, `line`, `column` (for a model file; else None), `key` (where in the model, e.g. \
     `groups[2].lengths[1]`), `help`."
);

/// The library's error as a `StitchkinError` with its place and help. Its
/// message is the command line's: what is wrong, then a `help:` line with
/// the fix (a traceback shows both).
fn py_error(py: Python<'_>, e: &stitchkin::Error) -> PyErr {
    // Papers by authors and year, as the command line prints them.
    let cite = |t: &str| stitchkin::references::cited(t).into_owned();
    let mut message = cite(&e.to_string());
    if let Some(help) = e.help().map(cite).filter(|h| !message.contains(h.as_str())) {
        message = format!("{message}\n  help: {help}");
    }
    let err = StitchkinError::new_err(message);
    let value = err.value(py);
    let (file, line, column, key) = match e {
        stitchkin::Error::Model(m) => {
            let (line, column) = m.line_col().unzip();
            (
                Some(m.file.clone()),
                line,
                column,
                Some(m.path.clone()).filter(|p| !p.is_empty()),
            )
        }
        _ => (None, None, None, None),
    };
    // Setting attributes on a fresh exception object does not fail.
    let _ = value.setattr("file", file);
    let _ = value.setattr("line", line);
    let _ = value.setattr("column", column);
    let _ = value.setattr("key", key);
    let _ = value.setattr("help", e.help().map(cite));
    err
}

/// The names of the shipped presets, in the order `stitchkin presets` lists them.
#[pyfunction]
fn presets() -> Vec<&'static str> {
    stitchkin::presets::ALL.iter().map(|p| p.name).collect()
}

/// The name of the preset used when none is given (`stitchkin run`).
#[pyfunction]
fn default_preset() -> &'static str {
    stitchkin::presets::DEFAULT
}

/// A machine described by a model file: its mechanism, thread paths and
/// stitch. Load it with `Model.preset(name)`, `Model.load(path)` or
/// `Model.from_toml(text)`.
#[pyclass(module = "stitchkin", frozen)]
struct Model {
    model: LibModel,
}

impl Model {
    /// The model's default parameters with `set` applied (`{name: value}`
    /// in each parameter's unit, mm, deg or N), as `--set` does.
    fn params(&self, py: Python<'_>, set: Option<&Bound<'_, PyDict>>) -> PyResult<Params> {
        let mut params = self.model.defaults();
        if let Some(set) = set {
            for (name, value) in set.iter() {
                let name: String = name.extract()?;
                let value: f64 = value.extract()?;
                self.model
                    .set(&mut params, &name, value)
                    .map_err(|e| py_error(py, &stitchkin::Error::Param(e)))?;
            }
        }
        Ok(params)
    }

    /// A sweep's arguments checked as `stitchkin sweep` checks them, before
    /// any setting is computed: the settings (`set`), every varied
    /// parameter's name and range, the design and the figures. Returns the
    /// base setting, the sweep and its plan.
    #[allow(clippy::too_many_arguments)]
    fn plan_sweep(
        &self,
        py: Python<'_>,
        vary: &Bound<'_, PyAny>,
        samples: Option<usize>,
        method: &str,
        seed: u64,
        figures: Option<&[String]>,
        step: f64,
        set: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<(Params, Sweep, SweepPlan)> {
        let params = self.params(py, set)?;
        let specs = vary_specs(vary)?;
        let design = match (samples, method) {
            (None, _) => Design::Grid,
            (Some(samples), "lhs") => Design::Lhs { samples, seed },
            (Some(samples), "random") => Design::Random { samples, seed },
            (Some(_), other) => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "method `{other}` is not a sampling method: give \"lhs\" or \"random\""
                )));
            }
        };
        let model = &self.model;
        py.detach(|| {
            let vary = specs
                .iter()
                .map(|v| Vary::parse(model, v))
                .collect::<Result<Vec<_>, _>>()?;
            let sw = Sweep::new(vary, design)?;
            let plan = SweepPlan::new(model, &params, &sw, figures, step)?;
            Ok::<_, stitchkin::Error>((params, sw, plan))
        })
        .map_err(|e| py_error(py, &e))
    }
}

#[pymethods]
impl Model {
    /// A shipped preset by name (`stitchkin.presets()` lists them).
    #[staticmethod]
    fn preset(py: Python<'_>, name: &str) -> PyResult<Model> {
        LibModel::preset(name)
            .map(|model| Model { model })
            .map_err(|e| py_error(py, &e))
    }

    /// A model file (TOML) from disk.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Model> {
        LibModel::from_path(&path)
            .map(|model| Model { model })
            .map_err(|e| py_error(py, &e))
    }

    /// A model from its TOML text; `file_name` names it in errors.
    #[staticmethod]
    #[pyo3(signature = (text, file_name = "<string>"))]
    fn from_toml(py: Python<'_>, text: &str, file_name: &str) -> PyResult<Model> {
        LibModel::from_toml_str(text, file_name)
            .map(|model| Model { model })
            .map_err(|e| py_error(py, &stitchkin::Error::Model(e)))
    }

    /// The model's name (`[model] name`).
    #[getter]
    fn name(&self) -> &str {
        self.model.name()
    }

    /// The model file's text (TOML): with `file_name`, what
    /// `Model.from_toml` needs to load the same model elsewhere (a Dask
    /// worker, say).
    #[getter]
    fn toml(&self) -> &str {
        self.model.text()
    }

    /// The name the model's errors give its file (`preset:NAME` for a preset).
    #[getter]
    fn file_name(&self) -> &str {
        self.model.file_name()
    }

    /// The model's title, if it has one.
    #[getter]
    fn title(&self) -> Option<&str> {
        self.model.title()
    }

    /// The parameters as declared: a list of dicts with `name`, `unit`
    /// (`mm`, `deg` or `1`), `value` (the nominal value; None for a derived
    /// parameter), `range` (`(lo, hi)` or None), `derived`, `source`.
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for p in self.model.params() {
            let d = PyDict::new(py);
            d.set_item("name", &p.name)?;
            d.set_item("unit", p.unit_str())?;
            d.set_item("value", p.value)?;
            d.set_item("range", p.range.map(|[lo, hi]| (lo, hi)))?;
            d.set_item("derived", p.is_derived())?;
            d.set_item("source", p.source.as_deref().map(stitchkin::references::cited))?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// One main-shaft cycle, as `stitchkin run`: a `stitchkin.Table`, a
    /// mapping from the CSV's column names (`phi_deg`, `G.y_mm`,
    /// `PATH.P_B_mm`, …) to float64 arrays, the same numbers as the command
    /// line at the same settings.
    ///
    /// `step`: φ step, deg. `set`: `{name: value}` parameter overrides.
    /// `columns`: patterns where `*` matches anything (`["*.P_B_mm"]`);
    /// `phi_deg` is always kept. `analogs`: with the analog columns.
    /// `rpm`: adds real velocities and accelerations (default: the model's).
    /// `points`: the points whose coordinates (world frame, mm) are
    /// tabulated, fixed or moving (default: the model's output points), as
    /// `--points`.
    #[pyo3(signature = (step = 1.0, set = None, columns = None, analogs = true, rpm = None, points = None))]
    #[allow(clippy::too_many_arguments)]
    fn run<'py>(
        &self,
        py: Python<'py>,
        step: f64,
        set: Option<&Bound<'py, PyDict>>,
        columns: Option<Vec<String>>,
        analogs: bool,
        rpm: Option<f64>,
        points: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let params = self.params(py, set)?;
        let points = points
            .map(|p| self.model.point_slots(&p, Input::Points))
            .transpose()
            .map_err(|e| py_error(py, &e))?;
        let opts = CycleOptions {
            step_deg: step,
            rpm: rpm.or(self.model.rpm()),
            analogs,
            points,
            lean: false,
        };
        let model = &self.model;
        let table = py
            .detach(|| match &columns {
                // Only what the columns need: without a column of the
                // stitch's, no stitch process and no thread tension.
                Some(patterns) => run_cycle_columns(model, &params, &opts, patterns),
                None => run_cycle(model, &params, &opts),
            })
            .map_err(|e| py_error(py, &e))?;
        let out = PyDict::new(py);
        for c in table.columns {
            let array: Bound<'py, PyArray1<f64>> = c.values.into_pyarray(py);
            out.set_item(c.name, array)?;
        }
        py.import("stitchkin")?.getattr("Table")?.call1((out,))
    }

    /// How the take-up P matches the stitch's need P′, as `stitchkin match
    /// --format json`: a dict with, per thread (`threads`), the score,
    /// RMS(P − P′) and every other metric, the physical checks (`checks`),
    /// the stitch's inputs, the model's `name` (`model`) and `caveats`.
    /// Raises `StitchkinError` when the model has no `[stitch]` table.
    #[pyo3(signature = (step = 1.0, set = None))]
    fn r#match<'py>(
        &self,
        py: Python<'py>,
        step: f64,
        set: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let params = self.params(py, set)?;
        let model = &self.model;
        let json = py
            .detach(|| {
                let table = stitchkin::eval::run_match(model, &params, step)?;
                let Some(st) = &table.stitch else {
                    return Err(stitchkin::Error::Stitch(stitchkin::error::StitchError::new(
                        format!("model `{}`", model.name()),
                        "it has no [stitch] table, so there is no required take-up to match; add one \
                         (docs/model-format.md, \"Stitch process\") or use Model.preset(\"mf7923d\")",
                    )));
                };
                let internal = |e: serde_json::Error| stitchkin::Error::Internal(format!("cannot write JSON: {e}"));
                let json = stitchkin::output::match_json(model, &table, st).map_err(internal)?;
                serde_json::to_string(&json).map_err(internal)
            })
            .map_err(|e| py_error(py, &e))?;
        py.import("json")?.getattr("loads")?.call1((json,))
    }

    /// Every physical check of one cycle, as `stitchkin check` judges them:
    /// a dict with `ok` (every check passes) and `checks`, a list of dicts
    /// (`name`, `thread` (the thread, or the cam's group), `ok`, `value`,
    /// `limit` [low, high], `unit`, `at_deg`, `message`): the stitch's
    /// checks and each cam and follower's (`cam_pressure`, `cam_curvature`,
    /// `follower_contact`), and `cams`, per cam group its checks and
    /// `limit_rpm`, the highest speed its spring holds the follower at.
    /// `rpm`: the main shaft's speed for the spring's check (default: the
    /// model's).
    #[pyo3(signature = (step = 1.0, set = None, rpm = None))]
    fn check<'py>(
        &self,
        py: Python<'py>,
        step: f64,
        set: Option<&Bound<'py, PyDict>>,
        rpm: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let params = self.params(py, set)?;
        let model = &self.model;
        let json = py
            .detach(|| {
                let opts = CycleOptions {
                    step_deg: step,
                    rpm,
                    ..Default::default()
                };
                let table = run_cycle(model, &params, &opts)?;
                let checks: Vec<_> = table.all_checks().collect();
                let json = serde_json::json!({
                    "ok": table.checks_ok(),
                    "checks": checks,
                    "cams": table.cams,
                });
                serde_json::to_string(&json).map_err(|e| stitchkin::Error::Internal(format!("cannot write JSON: {e}")))
            })
            .map_err(|e| py_error(py, &e))?;
        py.import("json")?.getattr("loads")?.call1((json,))
    }

    /// The adjustable settings that make the take-up match the stitch best,
    /// as `stitchkin tune --format json`: a dict with the recommended
    /// setting, the match and checks before and after, how far each setting
    /// may move, and notes.
    ///
    /// `adjust`: the parameters to adjust (default: every one with an
    /// adjustable range that leaves the stitch alone). `samples`: global
    /// Latin-hypercube samples (0: 32 per parameter, at least 64), drawn
    /// with `seed`. `thickness`, `stitch`: the material thickness m and
    /// stitch length t, mm, to tune for. `set`: the starting setting.
    /// `objective`: what to minimise, `"match"` (the mismatch of P and P′)
    /// or `"peak-tension"` (the thread's highest peak tension as a share of
    /// its breaking force; needs thread physics), as `--objective`; the
    /// physical checks are constraints either way. A job input (material,
    /// stitch length) or a fixed dimension named in `adjust` is refused
    /// unless `allow_inputs` or `allow_dimensions` lets it in.
    #[pyo3(signature = (adjust = None, samples = 0, seed = 1, step = 1.0, thickness = None, stitch = None, set = None, objective = "match", allow_inputs = false, allow_dimensions = false))]
    #[allow(clippy::too_many_arguments)]
    fn tune<'py>(
        &self,
        py: Python<'py>,
        adjust: Option<Vec<String>>,
        samples: usize,
        seed: u64,
        step: f64,
        thickness: Option<f64>,
        stitch: Option<f64>,
        set: Option<&Bound<'py, PyDict>>,
        objective: &str,
        allow_inputs: bool,
        allow_dimensions: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let objective = match objective {
            "match" => tune::TuneObjective::Match,
            "peak-tension" | "peak_tension" => tune::TuneObjective::PeakTension,
            other => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "objective = {other:?}: give \"match\" or \"peak-tension\""
                )));
            }
        };
        let mut params = self.params(py, set)?;
        let mut allowed = self.model.clone();
        if allow_inputs {
            allowed.allow_adjusting(stitchkin::model::ParamKind::Input);
        }
        if allow_dimensions {
            allowed.allow_adjusting(stitchkin::model::ParamKind::Dimension);
        }
        let model = &allowed;
        for name in adjust.iter().flatten() {
            if let Some(r) = tune::KindRefusal::of(model, name) {
                let allow = match r.kind {
                    stitchkin::model::ParamKind::Input => "allow_inputs=True",
                    _ => "allow_dimensions=True",
                };
                let e = stitchkin::ParamError::general(r.message(), Some(r.help(Some(allow))));
                return Err(py_error(py, &stitchkin::Error::Param(e)));
            }
        }
        let json = py
            .detach(|| {
                tune::check_samples(samples)?;
                for (which, value) in [("m", thickness), ("t", stitch)] {
                    if let Some(v) = value {
                        tune::set_stitch_value(model, &mut params, which, v)?;
                    }
                }
                let adjust = match adjust {
                    Some(a) => a,
                    None => model.default_adjustables(&params)?,
                };
                let options = tune::TuneOptions {
                    objective,
                    adjust,
                    samples,
                    seed,
                    step_deg: step,
                };
                let result = tune::tune(model, &params, &options)?;
                serde_json::to_string(&result)
                    .map_err(|e| stitchkin::Error::Internal(format!("cannot write JSON: {e}")))
            })
            .map_err(|e| py_error(py, &e))?;
        py.import("json")?.getattr("loads")?.call1((json,))
    }

    /// The machine's setting from its measured take-up, as `stitchkin fit
    /// --measured` finds it: the parameters `adjust` fitted to the measured
    /// curves by weighted least squares within their bounds, with their
    /// confidence intervals, correlation and warnings.
    ///
    /// `measured`: a CSV file as `stitchkin match --measured` reads it
    /// (`phi_deg,n1.P_B_mm`, or several readings per φ, which give each
    /// sample its uncertainty), as a path, a `"THREAD=path"` string when
    /// its column does not name the thread, a list of them, or a dict
    /// `{thread: path}`. `adjust`: the parameters to fit, `NAME` (within
    /// its adjustable range) or `NAME=LO:HI`, e.g. `["z", "dphi"]` (or
    /// `"z,dphi"`); they start at the model's values with `set` applied.
    /// `step`: the cycle's φ step, deg (None: 1, or the largest step that
    /// holds every measured φ). `max_iterations`: Levenberg–Marquardt
    /// iterations at most. `confidence`: of the intervals, 0 < c < 1.
    ///
    /// A dict: `params` (per fitted parameter `name`, `label`, `unit`,
    /// `start`, `fitted`, `std_error` and `interval` [lo, hi] (None when
    /// the data do not determine it), its bounds `lo`, `hi`, `at_bound`),
    /// `fitted` ({name: fitted value}), `correlation` (a p × p NumPy array,
    /// NaN when the data determine none), `condition`, `chi2_per_dof`,
    /// `samples`, `dof`, `sigma_known`, `sigma_estimated_mm` (None when
    /// the curves carry their uncertainty), `confidence`, `quantile` (q of
    /// the intervals, fitted ± q·std_error) and `quantile_from`,
    /// `converged`, `iterations`, `stop`, `step_deg`, `cost` and
    /// `cost_start` (S = Σ r², at the end and the start), `warnings` (the
    /// parameters the data cannot tell apart, a bound reached, …), `notes`,
    /// and `curves`: per measured curve `phi_deg`, `measured_mm`,
    /// `model_mm`, `residual_mm` (model − measured) as NumPy arrays,
    /// `sigma_mm` (an array, or None when σ was estimated), `thread`,
    /// `path` (the thread path compared with), `source` (the file),
    /// `kind` (`"take_up"` or `"required"`), `exact_jacobian` and
    /// `rms_residual_mm`.
    ///
    /// With `advise`, `advice` is the tuning from the fitted setting as
    /// `Model.tune` returns it (`advice["tune"]`, at a 1° step, with
    /// `samples` and `seed` as `tune` takes them; None when the model has
    /// no stitch or no fitted parameter is a machine setting) and its
    /// `notes`; else `advice` is None.
    ///
    /// A file that cannot be read, a parameter the model does not have or
    /// data that cannot fit raise `StitchkinError` with its help; a
    /// `measured` or `adjust` of the wrong type, `TypeError`.
    #[pyo3(signature = (measured, adjust, *, step = None, max_iterations = 100, confidence = 0.95, set = None, advise = false, samples = 0, seed = 1))]
    #[allow(clippy::too_many_arguments)]
    fn fit_measured<'py>(
        &self,
        py: Python<'py>,
        measured: &Bound<'py, PyAny>,
        adjust: &Bound<'py, PyAny>,
        step: Option<f64>,
        max_iterations: usize,
        confidence: f64,
        set: Option<&Bound<'py, PyDict>>,
        advise: bool,
        samples: usize,
        seed: u64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let specs = measured_specs(measured)?;
        let adjust = adjust_names(adjust)?;
        let params = self.params(py, set)?;
        let model = &self.model;
        let (fit, advice) = py
            .detach(|| {
                if advise {
                    tune::check_samples(samples)?;
                }
                let curves = specs
                    .iter()
                    .map(|(thread, path)| {
                        Ok(fit_measured::CurveInput {
                            thread: thread.clone(),
                            curve: stitchkin::read_curve(path)?,
                        })
                    })
                    .collect::<Result<Vec<_>, stitchkin::Error>>()?;
                let options = fit_measured::FitMeasuredOptions {
                    adjust,
                    step_deg: step,
                    max_iterations,
                    confidence,
                };
                let fit = fit_measured::fit_measured(model, &params, &curves, &options)?;
                let advice = if advise {
                    let a = fit_measured::advise(model, &params, &fit, samples, seed, 1.0)?;
                    let tune = a
                        .tune
                        .as_ref()
                        .map(serde_json::to_string)
                        .transpose()
                        .map_err(|e| stitchkin::Error::Internal(format!("cannot write JSON: {e}")))?;
                    Some((tune, a.notes))
                } else {
                    None
                };
                Ok::<_, stitchkin::Error>((fit, advice))
            })
            .map_err(|e| py_error(py, &e))?;
        let out = PyDict::new(py);
        let list = PyList::empty(py);
        let fitted = PyDict::new(py);
        for p in &fit.params {
            let d = PyDict::new(py);
            d.set_item("name", &p.name)?;
            d.set_item("label", &p.label)?;
            d.set_item("unit", p.unit)?;
            d.set_item("start", p.start)?;
            d.set_item("fitted", p.fitted)?;
            d.set_item("std_error", p.std_error)?;
            d.set_item("interval", p.interval.map(|[lo, hi]| vec![lo, hi]))?;
            d.set_item("lo", p.lo)?;
            d.set_item("hi", p.hi)?;
            d.set_item("at_bound", p.at_bound)?;
            list.append(d)?;
            fitted.set_item(&p.name, p.fitted)?;
        }
        out.set_item("params", list)?;
        out.set_item("fitted", fitted)?;
        let n = fit.params.len();
        let correlation = if fit.correlation.len() == n {
            fit.correlation
        } else {
            vec![vec![f64::NAN; n]; n]
        };
        let correlation = PyArray2::from_vec2(py, &correlation)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("the correlation matrix: {e}")))?;
        out.set_item("correlation", correlation)?;
        out.set_item("condition", fit.condition)?;
        out.set_item("chi2_per_dof", fit.chi2_per_dof)?;
        out.set_item("samples", fit.samples)?;
        out.set_item("dof", fit.dof)?;
        out.set_item("sigma_known", fit.sigma_known)?;
        out.set_item("sigma_estimated_mm", fit.sigma_estimated_mm)?;
        out.set_item("confidence", fit.confidence)?;
        out.set_item("quantile", fit.quantile)?;
        out.set_item("quantile_from", &fit.quantile_from)?;
        out.set_item("converged", fit.converged)?;
        out.set_item("iterations", fit.iterations)?;
        out.set_item("stop", &fit.stop)?;
        out.set_item("step_deg", fit.step_deg)?;
        out.set_item("cost", fit.cost)?;
        out.set_item("cost_start", fit.cost_start)?;
        out.set_item("warnings", &fit.warnings)?;
        out.set_item("notes", &fit.notes)?;
        let curves = PyList::empty(py);
        for c in fit.curves {
            let d = PyDict::new(py);
            d.set_item("thread", &c.thread)?;
            d.set_item("path", &c.path)?;
            d.set_item("source", &c.source)?;
            d.set_item(
                "kind",
                match c.kind {
                    stitchkin::CurveKind::TakeUp => "take_up",
                    stitchkin::CurveKind::Required => "required",
                },
            )?;
            d.set_item("exact_jacobian", c.exact_jacobian)?;
            d.set_item("phi_deg", c.phi_deg.into_pyarray(py))?;
            d.set_item("measured_mm", c.measured_mm.into_pyarray(py))?;
            d.set_item("model_mm", c.model_mm.into_pyarray(py))?;
            d.set_item("residual_mm", c.residual_mm.into_pyarray(py))?;
            d.set_item("sigma_mm", c.sigma_mm.map(|s| s.into_pyarray(py)))?;
            d.set_item("rms_residual_mm", c.rms_residual_mm)?;
            curves.append(d)?;
        }
        out.set_item("curves", curves)?;
        match advice {
            Some((tune, notes)) => {
                let d = PyDict::new(py);
                let loads = py.import("json")?.getattr("loads")?;
                d.set_item("tune", tune.map(|t| loads.call1((t,))).transpose()?)?;
                d.set_item("notes", notes)?;
                out.set_item("advice", d)?;
            }
            None => out.set_item("advice", py.None())?,
        }
        Ok(out)
    }

    /// Figures of merit over a grid or samples of the adjustable
    /// parameters, as `stitchkin sweep`: a `stitchkin.Table` with `index`
    /// (int64), one column per varied parameter (`NAME_UNIT`), one per
    /// figure (NaN where a setting has none or did not evaluate) and
    /// `status` (`"ok"`, or why the setting did not evaluate).
    ///
    /// `vary`: `["NAME=LO:HI:N", …]` as `--vary` takes them, or
    /// `{name: (lo, hi, n)}`. `samples`: a Latin hypercube (`method="lhs"`)
    /// or random (`"random"`) design of that many settings, drawn with
    /// `seed`, instead of the grid. `figures`: patterns (`["*.score"]`),
    /// the defaults of the command line when None. `set`: the base setting.
    /// `shard=(k, n)`: only the k-th of n contiguous blocks of the
    /// settings, as `--shard K/N` (the blocks together are the sweep).
    #[pyo3(signature = (vary, samples = None, method = "lhs", seed = 1, figures = None, step = 1.0, set = None, shard = None))]
    #[allow(clippy::too_many_arguments)]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        vary: &Bound<'py, PyAny>,
        samples: Option<usize>,
        method: &str,
        seed: u64,
        figures: Option<Vec<String>>,
        step: f64,
        set: Option<&Bound<'py, PyDict>>,
        shard: Option<(usize, usize)>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (k, n) = shard.unwrap_or((1, 1));
        if !(n >= 1 && (1..=n).contains(&k)) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "shard=({k}, {n}) is not a shard (k, n) with 1 ≤ k ≤ n"
            )));
        }
        let (params, sw, plan) = self.plan_sweep(py, vary, samples, method, seed, figures.as_deref(), step, set)?;
        let model = &self.model;
        let rows = py
            .detach(|| {
                let range = sw.shard(k, n);
                let mut rows: Vec<Row> = Vec::with_capacity(range.len());
                sweep::run(
                    plan.job(model, &params, &sw),
                    range,
                    |row| {
                        rows.push(row.clone());
                        Ok::<_, stitchkin::Error>(())
                    },
                    |_| {},
                )?;
                Ok::<_, stitchkin::Error>(rows)
            })
            .map_err(|e| py_error(py, &e))?;
        let out = PyDict::new(py);
        let index: Vec<i64> = rows.iter().map(|r| r.index as i64).collect();
        out.set_item("index", index.into_pyarray(py))?;
        for (k, v) in sw.vary.iter().enumerate() {
            let unit = model.param_index(&v.name).map_or("", |i| model.params()[i].unit_str());
            let values: Vec<f64> = rows.iter().map(|r| r.values[k]).collect();
            out.set_item(format!("{}_{unit}", v.name), values.into_pyarray(py))?;
        }
        for (k, name) in plan.names.iter().enumerate() {
            let values: Vec<f64> = rows.iter().map(|r| r.figures[k].unwrap_or(f64::NAN)).collect();
            out.set_item(name, values.into_pyarray(py))?;
        }
        let status: Vec<&str> = rows.iter().map(|r| r.error.as_deref().unwrap_or("ok")).collect();
        out.set_item("status", py.import("numpy")?.getattr("array")?.call1((status,))?)?;
        py.import("stitchkin")?.getattr("Table")?.call1((out,))
    }

    /// Checks a sweep's arguments as `sweep` does (the same errors, the
    /// same messages as `stitchkin sweep`) and returns its number of
    /// settings, computing none of them: what `stitchkin.dask.sweep` calls
    /// on the client before it sends work to the cluster.
    #[pyo3(signature = (vary, samples = None, method = "lhs", seed = 1, figures = None, step = 1.0, set = None))]
    #[allow(clippy::too_many_arguments)]
    fn _check_sweep<'py>(
        &self,
        py: Python<'py>,
        vary: &Bound<'py, PyAny>,
        samples: Option<usize>,
        method: &str,
        seed: u64,
        figures: Option<Vec<String>>,
        step: f64,
        set: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<usize> {
        let (_, sw, _) = self.plan_sweep(py, vary, samples, method, seed, figures.as_deref(), step, set)?;
        Ok(sw.len())
    }

    fn __repr__(&self) -> String {
        format!("<stitchkin.Model {}>", self.model.name())
    }
}

/// The thread one finished stitch consumes, from the stitch's geometry, as
/// `stitchkin consumption --format json`: a dict per thread of the stitch,
/// per stitch (`length_mm`), per length of seam (`ratio`, mm/mm) and for
/// the seam without and with the waste allowance (`seam_m`,
/// `seam_with_waste_m`), and the totals. Taut consumption (`notes`).
///
/// `stitch_type`: 301, 401, 406, 407, 501–512, 514, 521, 602 or 605.
/// `thickness`: the material, mm. `stitch`: the stitch length, mm. `width`:
/// the overedge width, mm (500-class stitches). `incline`: the needle's
/// incline, deg. `edge`: where the looper threads meet on the edge, a
/// fraction of the thickness (0…1). `interlace`: where a lockstitch's
/// threads interlace, a fraction of the thickness below the top face (0.5:
/// balanced). `seam`: the seam's length, mm. `waste`: the allowance for
/// waste, per cent.
#[pyfunction]
#[pyo3(signature = (stitch_type, thickness, stitch, width = None, incline = 0.0, edge = 0.5, interlace = 0.5, seam = 1000.0, waste = 0.0))]
#[allow(clippy::too_many_arguments)]
fn consumption<'py>(
    py: Python<'py>,
    stitch_type: u16,
    thickness: f64,
    stitch: f64,
    width: Option<f64>,
    incline: f64,
    edge: f64,
    interlace: f64,
    seam: f64,
    waste: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let geometry = stitchkin::StitchGeometry {
        thickness_mm: thickness,
        stitch_mm: stitch,
        width_mm: width.unwrap_or(0.0),
        incline_deg: incline,
        edge_fraction: edge,
        interlace_fraction: interlace,
    };
    let seam = stitchkin::Seam {
        length_mm: seam,
        waste_pct: waste,
    };
    let json = stitchkin::consumption(stitch_type, &geometry)
        .and_then(|c| c.for_seam(&seam))
        .map_err(stitchkin::Error::Param)
        .and_then(|c| {
            serde_json::to_string(&c).map_err(|e| stitchkin::Error::Internal(format!("cannot write JSON: {e}")))
        })
        .map_err(|e| py_error(py, &e))?;
    py.import("json")?.getattr("loads")?.call1((json,))
}

/// Repeated readings of a take-up processed as Polyakov (2022) §3.4
/// (docs/studies.md, "Repeated readings"): the file at `path` holds several
/// readings per φ (a column per reading or rows of the same φ);
/// `resolution_mm` (the instrument's largest error, mm) and `confidence`
/// (0…1) stand for the file's `# resolution_mm` and `# confidence` lines.
/// A dict: per φ the NumPy arrays `phi_deg`, `n`, `mean_mm`, `s_mm`,
/// `s_mean_mm`, `t`, `ci_low_mm`, `ci_high_mm`, `random_mm`,
/// `systematic_mm`, `total_mm`, `relative_pct` (NaN where |x̄| ≤ Δ),
/// `sigma_mm`, and `outliers` (a list per φ of the flagged readings,
/// 1-based); and `confidence`, `resolution_mm`, `source`, `column`.
#[pyfunction]
#[pyo3(signature = (path, resolution_mm = None, confidence = None))]
fn process_readings<'py>(
    py: Python<'py>,
    path: PathBuf,
    resolution_mm: Option<f64>,
    confidence: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = stitchkin::ReadingOptions {
        resolution_mm,
        confidence,
    };
    let curve = py
        .detach(|| stitchkin::read_curve_with(&path, &options))
        .map_err(|e| py_error(py, &e))?;
    let Some(p) = curve.readings() else {
        let e = stitchkin::Error::Param(stitchkin::error::ParamError::general(
            format!("{}: one reading per φ, nothing to process", curve.source()),
            Some(
                "give several readings per φ (a column per reading, `phi_deg,P_mm,P_mm,…`, or rows of the same φ)"
                    .into(),
            ),
        ));
        return Err(py_error(py, &e));
    };
    let out = PyDict::new(py);
    fn column<T>(rows: &[T], f: impl Fn(&T) -> f64) -> Vec<f64> {
        rows.iter().map(f).collect()
    }
    out.set_item("phi_deg", column(&p.points, |q| q.phi_deg).into_pyarray(py))?;
    out.set_item(
        "n",
        p.points.iter().map(|q| q.n as i64).collect::<Vec<_>>().into_pyarray(py),
    )?;
    out.set_item("mean_mm", column(&p.points, |q| q.mean_mm).into_pyarray(py))?;
    out.set_item("s_mm", column(&p.points, |q| q.s_mm).into_pyarray(py))?;
    out.set_item("s_mean_mm", column(&p.points, |q| q.s_mean_mm).into_pyarray(py))?;
    out.set_item("t", column(&p.points, |q| q.t).into_pyarray(py))?;
    out.set_item("ci_low_mm", column(&p.points, |q| q.ci_low_mm).into_pyarray(py))?;
    out.set_item("ci_high_mm", column(&p.points, |q| q.ci_high_mm).into_pyarray(py))?;
    out.set_item("random_mm", column(&p.points, |q| q.random_mm).into_pyarray(py))?;
    out.set_item("systematic_mm", column(&p.points, |q| q.systematic_mm).into_pyarray(py))?;
    out.set_item("total_mm", column(&p.points, |q| q.total_mm).into_pyarray(py))?;
    out.set_item(
        "relative_pct",
        column(&p.points, |q| q.relative_pct.unwrap_or(f64::NAN)).into_pyarray(py),
    )?;
    out.set_item("sigma_mm", column(&p.points, |q| q.sigma_mm).into_pyarray(py))?;
    out.set_item(
        "outliers",
        p.points.iter().map(|q| q.outliers.clone()).collect::<Vec<_>>(),
    )?;
    out.set_item("confidence", p.confidence)?;
    out.set_item("resolution_mm", p.resolution_mm)?;
    out.set_item("source", curve.source())?;
    out.set_item("column", curve.column())?;
    Ok(out)
}

/// The time of one `Model.run(step, analogs=analogs)` computed in Rust,
/// without Python: the median of `repeat` calls after one warm-up, seconds
/// (as the bench times the Python calls).
/// With `lean`, the lean cycle studies read their figures from
/// (`CycleOptions::for_figures`: no analogs, wrap angles, tensions or link
/// angles).
/// For the peer benchmark (bench/peers.py), which compares it with the
/// same call from Python and with NumPy.
#[pyfunction]
#[pyo3(signature = (model, step = 1.0, analogs = true, repeat = 100, lean = false))]
fn _time_run(py: Python<'_>, model: &Model, step: f64, analogs: bool, repeat: usize, lean: bool) -> PyResult<f64> {
    let params = model.model.defaults();
    let opts = if lean {
        CycleOptions::for_figures(step)
    } else {
        CycleOptions {
            step_deg: step,
            rpm: model.model.rpm(),
            analogs,
            points: None,
            lean: false,
        }
    };
    let lib = &model.model;
    py.detach(|| {
        run_cycle(lib, &params, &opts)?;
        let mut times = (0..repeat.max(1))
            .map(|_| {
                let began = std::time::Instant::now();
                std::hint::black_box(run_cycle(lib, &params, &opts)?);
                Ok(began.elapsed().as_secs_f64())
            })
            .collect::<Result<Vec<f64>, stitchkin::Error>>()?;
        times.sort_by(f64::total_cmp);
        Ok::<_, stitchkin::Error>(times[times.len() / 2])
    })
    .map_err(|e| py_error(py, &e))
}

/// The time of the engine's own loop for a model's take-up, without a
/// table: the mechanism solved over one turn at `step` and every thread
/// path's length ξ(φ) (`eval::PathLengths`, the buffers kept between
/// calls, as the engine benchmark `mf7923d_take_up` times it); the median of `repeat` calls after one warm-up, seconds. For
/// the peer benchmark (bench/peers.py).
#[pyfunction]
#[pyo3(signature = (model, step = 1.0, repeat = 100))]
fn _time_take_up(py: Python<'_>, model: &Model, step: f64, repeat: usize) -> PyResult<f64> {
    let lib = &model.model;
    py.detach(|| {
        let mut lengths = PathLengths::new(lib, &lib.defaults(), step)?;
        lengths.evaluate()?;
        let mut times = (0..repeat.max(1))
            .map(|_| {
                let began = std::time::Instant::now();
                lengths.evaluate()?;
                std::hint::black_box(lengths.xi(0));
                Ok(began.elapsed().as_secs_f64())
            })
            .collect::<Result<Vec<f64>, stitchkin::Error>>()?;
        times.sort_by(f64::total_cmp);
        Ok(times[times.len() / 2])
    })
    .map_err(|e| py_error(py, &e))
}

/// The column of `names` that `name` most likely misspells, by the
/// library's `did_you_mean` (the command line's hint for a mistyped name):
/// among the names and the names without their unit ending (`z` for
/// `z_mm`). For `stitchkin.Table`'s missing-column error.
#[pyfunction]
fn _closest_column(name: &str, names: Vec<String>) -> Option<String> {
    let whole = stitchkin::error::did_you_mean(name, names.iter().map(String::as_str));
    whole.map(str::to_string).or_else(|| {
        let bases = names.iter().filter_map(|n| n.rsplit_once('_').map(|(base, _)| base));
        let base = stitchkin::error::did_you_mean(name, bases)?;
        names
            .iter()
            .find(|n| n.rsplit_once('_').is_some_and(|(b, _)| b == base))
            .cloned()
    })
}

/// `vary` as `--vary` specs: a list of `NAME=LO:HI:N` strings, or a dict
/// `{name: (lo, hi, n)}` (or `(lo, hi)`: 11 values).
fn vary_specs(vary: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    if let Ok(d) = vary.cast::<PyDict>() {
        d.iter()
            .map(|(name, range)| {
                let name: String = name.extract()?;
                let range: Vec<f64> = range.extract()?;
                Ok(match range.as_slice() {
                    [lo, hi, n] if n.fract() == 0.0 && *n >= 1.0 => format!("{name}={lo}:{hi}:{n}"),
                    [lo, hi] => format!("{name}={lo}:{hi}"),
                    _ => {
                        return Err(pyo3::exceptions::PyValueError::new_err(format!(
                            "vary[{name:?}] must be (lo, hi, n) with a whole n ≥ 1, or (lo, hi)"
                        )));
                    }
                })
            })
            .collect()
    } else {
        vary.extract::<Vec<String>>().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err(
                "vary is a list of \"NAME=LO:HI:N\" strings or a dict {name: (lo, hi, n)}",
            )
        })
    }
}

/// `measured` as `(thread, file)` pairs, as `--measured [THREAD=]FILE`
/// takes them: a path or `"THREAD=path"` string, a list of them, or a dict
/// `{thread: path}`. A string's `THREAD=` prefix is a thread only when it
/// holds no `/`, `\` or `.` (a path may hold `=`).
fn measured_specs(measured: &Bound<'_, PyAny>) -> PyResult<Vec<(Option<String>, PathBuf)>> {
    let wrong = || {
        pyo3::exceptions::PyTypeError::new_err(
            "measured is a CSV file's path, a \"THREAD=path\" string, a list of them or a dict {thread: path}",
        )
    };
    let one = |item: &Bound<'_, PyAny>| -> PyResult<(Option<String>, PathBuf)> {
        if let Ok(s) = item.extract::<String>() {
            return Ok(match s.split_once('=') {
                Some((t, f)) if !t.is_empty() && !t.contains(['/', '\\', '.']) => (Some(t.to_string()), f.into()),
                _ => (None, s.into()),
            });
        }
        item.extract::<PathBuf>().map(|p| (None, p)).map_err(|_| wrong())
    };
    if let Ok(d) = measured.cast::<PyDict>() {
        d.iter()
            .map(|(thread, path)| {
                Ok((
                    Some(thread.extract::<String>().map_err(|_| wrong())?),
                    path.extract::<PathBuf>().map_err(|_| wrong())?,
                ))
            })
            .collect()
    } else if measured.is_instance_of::<pyo3::types::PyString>() || measured.extract::<PathBuf>().is_ok() {
        Ok(vec![one(measured)?])
    } else {
        measured
            .try_iter()
            .map_err(|_| wrong())?
            .map(|item| one(&item?))
            .collect()
    }
}

/// `adjust` as the library takes it: a list of `NAME` or `NAME=LO:HI`
/// strings, or one string of them separated by commas (`"z,dphi"`, as
/// `--adjust z,dphi`).
fn adjust_names(adjust: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    if let Ok(s) = adjust.extract::<String>() {
        Ok(s.split(',')
            .map(|n| n.trim().to_string())
            .filter(|n| !n.is_empty())
            .collect())
    } else {
        adjust.extract::<Vec<String>>().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err(
                "adjust is a list of parameter names (NAME or NAME=LO:HI), e.g. [\"z\", \"dphi\"]",
            )
        })
    }
}

/// The native module of the `stitchkin` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Model>()?;
    m.add_function(wrap_pyfunction!(presets, m)?)?;
    m.add_function(wrap_pyfunction!(default_preset, m)?)?;
    m.add_function(wrap_pyfunction!(consumption, m)?)?;
    m.add_function(wrap_pyfunction!(process_readings, m)?)?;
    m.add_function(wrap_pyfunction!(_time_run, m)?)?;
    m.add_function(wrap_pyfunction!(_time_take_up, m)?)?;
    m.add_function(wrap_pyfunction!(_closest_column, m)?)?;
    m.add("StitchkinError", m.py().get_type::<StitchkinError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
