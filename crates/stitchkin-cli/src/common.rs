//! What the subcommands share: the model, output and path arguments, loading the
//! model, writing a result, reading measured curves, and the diagnostic a
//! failed command prints.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use miette::{Diagnostic, LabeledSpan, NamedSource, SourceCode};
use stitchkin::error::{Error, Input, IoError, ModelError, ParamError};
use stitchkin::eval::CycleTable;
use stitchkin::model::{Model, Params};
use stitchkin::presets;
use stitchkin::study::measured::{MeasuredMatch, measured_match};
use stitchkin::study::straightness::{Reference, StraightnessOptions, Window};
use stitchkin::study::tune::set_stitch_value;
use stitchkin::{MeasuredCurve, read_curve};

/// The model a command works on: a file, a preset or the default preset,
/// with parameter overrides.
#[derive(Args)]
pub(crate) struct ModelArgs {
    /// Model file (TOML). Without it, --preset or the default preset is used.
    model: Option<PathBuf>,
    /// A shipped preset by name (see `stitchkin presets`).
    #[arg(long, conflicts_with = "model")]
    preset: Option<String>,
    /// Override a parameter: NAME=VALUE in the parameter's unit (mm, deg or N).
    /// Repeatable. Values outside the parameter's adjustable range are rejected.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    /// Material thickness m (compressed), mm: sets the parameter the
    /// model's [stitch] m_mm names, within its range.
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub thickness: Option<String>,
    /// Stitch length t, mm: sets the parameter the model's [stitch] t_mm
    /// names, within its range.
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub stitch: Option<String>,
}

/// The help of `--thickness` and `--stitch` where they are a grid's axis
/// (`nomogram`, `plot nomogram`), for `mut_arg`.
pub(crate) const THICKNESS_AXIS_HELP: &str = "Material thickness m, mm: LO:HI:N (N values, ends included), LO:HI \
    (11 values) or one value; each sets the parameter [stitch] m_mm names, within its range (default: 5 values over \
    that range)";
pub(crate) const STITCH_AXIS_HELP: &str = "Stitch length t, mm: LO:HI:N, LO:HI or one value; each sets the \
    parameter [stitch] t_mm names, within its range (default: the model's stitch length)";

/// The formats of a result that is a table: readable text, CSV or JSON.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum TableFormat {
    Table,
    Csv,
    Json,
}

/// The formats of a result read as a whole: readable text or JSON.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum TableOrJson {
    Table,
    Json,
}

/// The `--format` help of a command with [`TableOrJson`] (`mut_arg`).
pub(crate) const TABLE_OR_JSON_HELP: &str =
    "Output format: a readable table or JSON (default: the table, wherever it goes; -o FILE.json JSON)";

/// How a table command picks its format without `--format`, appended to
/// its `--format` help.
pub(crate) const DEFAULT_FORMAT_HELP: &str = " (default: the readable one on a terminal, CSV into a pipe or a file; -o FILE.json JSON, -o FILE.txt the readable one)";

/// The formats of a streamed table: readable text or CSV.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum TableOrCsv {
    Table,
    Csv,
}

/// `--format` and `-o/--output`. Without `--format` the result is shown
/// where it goes ([`ByDestination`]). A command whose formats are not a
/// table's, CSV and JSON says which in its `--format` help (`mut_arg`).
#[derive(Args)]
pub(crate) struct OutputArgs<F: ValueEnum + Clone + Send + Sync + 'static = TableFormat> {
    /// Output format: a readable table, CSV or JSON (default: the table on
    /// a terminal, CSV into a pipe or a file; -o FILE.json JSON, -o FILE.txt
    /// the table).
    #[arg(long, value_enum)]
    pub format: Option<F>,
    /// Write to FILE instead of stdout (written completely or not at all).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

impl<F: ValueEnum + Clone + Send + Sync + ByDestination + 'static> OutputArgs<F> {
    /// The format asked for, or the one [`ByDestination`] picks for where
    /// the result goes.
    pub fn format(&self) -> F {
        format_or_default(self.format.clone(), self.output.as_deref())
    }

    /// Writes `text` to the file (saying so on stderr) or to stdout: text
    /// tidied for people ([`tidy`]), JSON as the library wrote it (data for
    /// programs, the same as the Python package's).
    pub fn emit(&self, text: &str) -> Result<(), Error> {
        if self.format().is_json() {
            emit(text.as_bytes(), self.output.as_ref())
        } else {
            emit_text(text, self.output.as_ref())
        }
    }
}

/// One convention for every command, by where its result goes (docs/cli.md,
/// "What a command prints"):
/// - stdout a terminal and no `-o`: text for people (a readable table or
///   summary);
/// - into a pipe or `-o FILE`: a command with a table writes the table as
///   CSV (`-o FILE.json`: JSON; `-o FILE.txt`: the readable text); a command
///   whose result is read as a whole (match, tune, fit) writes its text
///   (`-o FILE.json`: JSON);
/// - `--format` always wins.
///
/// The choice is a function of the destination, so a test can ask it
/// without a terminal.
pub(crate) trait ByDestination: Sized {
    /// The format for `output` (`-o`), or stdout when it is a terminal
    /// (`is_terminal`) or not.
    fn by_destination(output: Option<&Path>, is_terminal: bool) -> Self;

    /// Whether this is JSON, data for programs written as it is.
    fn is_json(&self) -> bool {
        false
    }
}

/// The file's extension, lower-case.
fn extension(path: &Path) -> Option<String> {
    path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase)
}

impl ByDestination for TableFormat {
    fn by_destination(output: Option<&Path>, is_terminal: bool) -> Self {
        match output {
            None if is_terminal => TableFormat::Table,
            None => TableFormat::Csv,
            Some(path) => match extension(path).as_deref() {
                Some("json") => TableFormat::Json,
                Some("txt") => TableFormat::Table,
                _ => TableFormat::Csv,
            },
        }
    }

    fn is_json(&self) -> bool {
        matches!(self, TableFormat::Json)
    }
}

impl ByDestination for TableOrJson {
    fn by_destination(output: Option<&Path>, _is_terminal: bool) -> Self {
        match output.and_then(extension).as_deref() {
            Some("json") => TableOrJson::Json,
            _ => TableOrJson::Table,
        }
    }

    fn is_json(&self) -> bool {
        matches!(self, TableOrJson::Json)
    }
}

impl ByDestination for TableOrCsv {
    fn by_destination(output: Option<&Path>, is_terminal: bool) -> Self {
        match TableFormat::by_destination(output, is_terminal) {
            TableFormat::Table => TableOrCsv::Table,
            _ => TableOrCsv::Csv,
        }
    }
}

/// `given`, or the format for `output` and this process's stdout.
pub(crate) fn format_or_default<F: ByDestination>(given: Option<F>, output: Option<&Path>) -> F {
    given.unwrap_or_else(|| F::by_destination(output, output.is_none() && stdout_is_terminal()))
}

/// Whether stdout is a terminal. `STITCHKIN_TERMINAL=1` (or `0`) says so
/// instead, for tests and scripts that want the terminal's output in a
/// pipe (or the pipe's on a terminal).
pub(crate) fn stdout_is_terminal() -> bool {
    match std::env::var("STITCHKIN_TERMINAL").as_deref() {
        Ok("1") => true,
        Ok("0") => false,
        _ => std::io::IsTerminal::is_terminal(&std::io::stdout()),
    }
}

/// The line under a readable result that says how to get the whole table.
pub(crate) fn full_table_hint(what: &str) -> String {
    format!("({what}: pipe it, `-o FILE.csv` (or .json), or `--format csv`)\n")
}

/// The search of `tune`, `nomogram` and `report`: what to adjust, how hard
/// to look.
#[derive(Args)]
pub(crate) struct SearchArgs {
    /// Settings to adjust, comma-separated (default: the model's machine
    /// settings, without the thread's tension settings).
    #[arg(long, value_delimiter = ',', value_name = "NAME,…")]
    pub adjust: Option<Vec<String>>,
    /// Global samples of each tuning (default 32 per setting, at least 64).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub samples: usize,
    /// Seed of the global search (the same seed, the same answer).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Step of the main-shaft angle φ, degrees.
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    pub step: f64,
    /// What to minimise: the mismatch of P and P' (match), or the thread's
    /// highest peak tension as a share of its breaking force (peak-tension;
    /// needs thread physics). The physical checks are constraints either way.
    #[arg(long, value_enum, default_value = "match")]
    pub objective: Objective,
    /// Let --adjust name job inputs (the material, the stitch length, the
    /// thread): searched as if they were machine settings.
    #[arg(long)]
    pub allow_inputs: bool,
    /// Let --adjust name fixed dimensions (a part's size or place): a
    /// search over the machine's design, not its settings.
    #[arg(long)]
    pub allow_dimensions: bool,
}

/// `--objective`.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum Objective {
    Match,
    PeakTension,
}

impl SearchArgs {
    /// Checks the search's limits before any preparation.
    pub fn check(&self) -> Result<(), Error> {
        stitchkin::study::tune::check_samples(self.samples)
    }

    /// Lets the search adjust the kinds of parameter --allow-inputs and
    /// --allow-dimensions name, besides the machine settings.
    pub fn allow(&self, model: &mut Model) {
        if self.allow_inputs {
            model.allow_adjusting(stitchkin::model::ParamKind::Input);
        }
        if self.allow_dimensions {
            model.allow_adjusting(stitchkin::model::ParamKind::Dimension);
        }
    }

    /// Refuses a job input or a fixed dimension among `adjust` that
    /// --allow-inputs or --allow-dimensions has not let in, naming the
    /// option that would (the tuning refuses it too, in its own words).
    pub fn check_kinds(model: &Model, adjust: &[String]) -> Result<(), Error> {
        for name in adjust {
            if let Some(r) = stitchkin::study::tune::KindRefusal::of(model, name) {
                let flag = match r.kind {
                    stitchkin::model::ParamKind::Input => "--allow-inputs",
                    _ => "--allow-dimensions",
                };
                return Err(Error::Param(ParamError::new(
                    Input::Adjust,
                    r.message(),
                    Some(r.help(Some(flag))),
                )));
            }
        }
        Ok(())
    }

    /// The tuning options with the settings to `adjust`.
    pub fn options(&self, adjust: Vec<String>) -> stitchkin::study::tune::TuneOptions {
        stitchkin::study::tune::TuneOptions {
            objective: match self.objective {
                Objective::Match => stitchkin::study::tune::TuneObjective::Match,
                Objective::PeakTension => stitchkin::study::tune::TuneObjective::PeakTension,
            },
            adjust,
            samples: self.samples,
            seed: self.seed,
            step_deg: self.step,
        }
    }
}

/// The point, the line and the part of the cycle of `straightness` and
/// `tolerance`.
#[derive(Args)]
pub(crate) struct PathArgs {
    /// The point whose path is measured (e.g. E, the needle of altin-needle).
    #[arg(long, value_name = "POINT")]
    point: String,
    /// Measure from the line through two model points H → T (e.g. a guide's N1,N2).
    #[arg(long, value_name = "H,T", conflicts_with = "fit")]
    line: Option<String>,
    /// Measure from the least-squares line of the path (the default).
    #[arg(long)]
    fit: bool,
    /// Part of the cycle: cycle, down (the working stroke, from the far dead
    /// centre along the line to the near one), up, or FROM:TO in degrees of φ.
    #[arg(long, default_value = "cycle", value_name = "PART")]
    over: String,
    /// Step of the main-shaft angle φ, degrees (the extremes are refined below it).
    #[arg(long, default_value_t = 1.0, value_name = "DEG", allow_negative_numbers = true)]
    step: f64,
}

impl PathArgs {
    /// The straightness options on `model`.
    pub fn options(&self, model: &Model) -> Result<StraightnessOptions, Error> {
        Ok(StraightnessOptions {
            point: model
                .moving_point_slot(&self.point)
                .map_err(|e| e.given_in(Input::Point))?,
            reference: match &self.line {
                Some(l) => Reference::parse_line(model, l)?,
                None => Reference::Fit,
            },
            window: Window::parse(&self.over)?,
            step_deg: self.step,
        })
    }
}

/// The model and its parameters with the overrides applied (`--set`, then
/// `--thickness` and `--stitch`); impossible geometry with the overrides is
/// reported here, before any evaluation.
pub(crate) fn load(args: &ModelArgs) -> Result<(Model, Params), Error> {
    let (model, mut params) = load_without_job(args)?;
    for (which, flag, input, given) in [
        ("m", "--thickness", Input::Thickness, &args.thickness),
        ("t", "--stitch", Input::StitchLength, &args.stitch),
    ] {
        let Some(text) = given else { continue };
        let value = job_value(text, which, flag, input)?;
        set_stitch_value(&model, &mut params, which, value).map_err(|e| match e {
            Error::Param(p) => Error::Param(p.in_input(input)),
            other => other,
        })?;
    }
    if args.thickness.is_some() || args.stitch.is_some() {
        model.machine::<f64>(&params)?;
    }
    Ok((model, params))
}

/// One value of `--thickness` or `--stitch`, mm.
fn job_value(text: &str, which: &str, flag: &str, input: Input) -> Result<f64, Error> {
    let what = if which == "m" { "thickness" } else { "stitch length" };
    if text.contains(':') {
        return Err(Error::Param(ParamError::new(
            input,
            format!("`{text}` is a range, and this command takes one {what}"),
            Some(format!(
                "give one value in mm, e.g. {flag} 3; a range LO:HI:N is for `stitchkin nomogram` and `stitchkin plot \
                 nomogram` (or `stitchkin sweep --vary NAME=LO:HI:N` over the parameter)"
            )),
        )));
    }
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(Error::Param(ParamError::new(
            input,
            format!("`{text}` is not a {what}"),
            Some(format!("give a number in mm, e.g. {flag} 3")),
        ))),
    }
}

/// The model and its parameters with `--set` applied, but not
/// `--thickness` and `--stitch` (a nomogram reads them as its axes).
pub(crate) fn load_without_job(args: &ModelArgs) -> Result<(Model, Params), Error> {
    let model = match (&args.model, &args.preset) {
        (Some(path), _) => Model::from_path(path)?,
        (None, Some(name)) => Model::preset(name)?,
        (None, None) => Model::preset(presets::DEFAULT)?,
    };
    let mut params = model.defaults();
    let mut set: Vec<&str> = Vec::new();
    for s in &args.set {
        let name = s.split_once('=').map_or(s.as_str(), |(n, _)| n.trim());
        if set.contains(&name) {
            return Err(Error::Param(ParamError::new(
                Input::Set,
                format!("`{name}` is set twice"),
                Some("set each parameter once".into()),
            )));
        }
        set.push(name);
        model.set_str(&mut params, s)?;
    }
    // One value, one place: the stitch's thickness and length are given
    // with --thickness and --stitch or with --set, not both.
    for (which, flag, given) in [("m", "--thickness", &args.thickness), ("t", "--stitch", &args.stitch)] {
        if let (Some(_), Some(name)) = (given, model.stitch_param(which))
            && set.contains(&name)
        {
            return Err(Error::Param(ParamError::new(
                Input::Set,
                format!("`{name}` is given twice: with --set {name}=… and with {flag}"),
                Some(format!("give it once, with {flag}")),
            )));
        }
    }
    model.machine::<f64>(&params)?;
    Ok((model, params))
}

/// Writes `bytes` to `out` (completely or not at all), saying so on
/// stderr, or to stdout.
pub(crate) fn emit(bytes: &[u8], out: Option<&PathBuf>) -> Result<(), Error> {
    match out {
        Some(path) => {
            stitchkin::output::write_atomic(path, bytes)?;
            note_written(path, bytes.len());
            Ok(())
        }
        None => {
            let mut stdout = std::io::stdout().lock();
            match stdout.write_all(bytes).and_then(|_| stdout.flush()) {
                Ok(()) => Ok(()),
                // A closed pipe (`| head`) is not an error.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
                Err(e) => Err(Error::Io(IoError::os("write to stdout", None, e))),
            }
        }
    }
}

/// [`emit`] of text for people or programs, tidied by [`tidy`].
pub(crate) fn emit_text(text: &str, out: Option<&PathBuf>) -> Result<(), Error> {
    emit(tidy(text).as_bytes(), out)
}

/// Text as it is printed: papers cited by authors and year
/// (`stitchkin::references`), no negative zero (`-0.00`).
pub(crate) fn tidy(text: &str) -> String {
    stitchkin::format::without_negative_zeros(&stitchkin::references::cited(text)).into_owned()
}

/// A [`stitchkin::output::Sink`] as an `io::Write`, for the writers that
/// stream a table (CSV, JSON) instead of building it whole in memory; it
/// counts the bytes for [`note_written`].
pub(crate) struct SinkWriter<'a> {
    pub sink: &'a mut stitchkin::output::Sink,
    pub bytes: usize,
}

impl<'a> SinkWriter<'a> {
    pub fn new(sink: &'a mut stitchkin::output::Sink) -> Self {
        SinkWriter { sink, bytes: 0 }
    }
}

impl Write for SinkWriter<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.sink.write(buf).map_err(|e| std::io::Error::other(e.to_string()))?;
        self.bytes += buf.len();
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// `value` as pretty JSON ending in a newline.
pub(crate) fn json(value: &impl serde::Serialize) -> Result<String, Error> {
    Ok(serde_json::to_string_pretty(value).map_err(|e| Error::Internal(format!("cannot write JSON: {e}")))? + "\n")
}

/// A progress bar on stderr when it is a terminal (hidden otherwise), of
/// `len` steps drawn by `template` (`{rate}`: steps per second, a whole
/// number grouped by thousands: `{rate} settings/s`).
pub(crate) fn progress_bar(len: usize, template: &str) -> indicatif::ProgressBar {
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len as u64);
    // `{rate}`: a whole number per second (`12 652/s`), not indicatif's
    // `{per_sec}` (`12,651.6851/s`).
    let style = indicatif::ProgressStyle::with_template(template)
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
        .with_key(
            "rate",
            |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_str(&stitchkin::format::rate_number(state.per_sec()));
            },
        );
    bar.set_style(style);
    bar
}

/// Reads the `--measured` curves, `[THREAD=]FILE` each: the thread (when
/// given) and the curve.
pub(crate) fn read_measured(specs: &[String]) -> Result<Vec<(Option<String>, MeasuredCurve)>, Error> {
    specs
        .iter()
        .map(|spec| {
            let (thread, file) = match spec.split_once('=') {
                Some((t, f)) if !t.is_empty() && !t.contains(['/', '\\', '.']) => (Some(t.to_string()), f),
                _ => (None, spec.as_str()),
            };
            Ok((thread, read_curve(Path::new(file))?))
        })
        .collect()
}

/// Reads the `--measured` curves and sets each beside its thread.
pub(crate) fn measured(specs: &[String], table: &CycleTable) -> Result<Vec<MeasuredMatch>, Error> {
    read_measured(specs)?
        .iter()
        .map(|(thread, curve)| measured_match(table, curve, thread.as_deref()))
        .collect()
}

/// Writes `text` to stderr, where notes and summaries go; a closed stderr
/// (`2>&1 | head`) silences it instead of ending the program.
pub(crate) fn note(text: &str) {
    let _ = std::io::stderr().lock().write_all(tidy(text).as_bytes());
}

/// Says on stderr that `path` was written, with its size.
pub(crate) fn note_written(path: &Path, bytes: usize) {
    let size = if bytes >= 10_000 {
        format!("{} kB", bytes / 1000)
    } else {
        format!("{bytes} bytes")
    };
    note_line(&format!("wrote {} ({size})", path.display()));
}

/// [`note`] with a line end.
pub(crate) fn note_line(text: &str) {
    note(&format!("{text}\n"));
}

/// Stopped by Ctrl-C (SIGINT), SIGTERM or SIGHUP, the program first deletes
/// the temporary files of outputs it was writing, then exits with 128 + the
/// signal's number, as a shell reports a program the signal ended.
pub(crate) fn remove_temporaries_on_signal() {
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        if let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
            std::thread::spawn(move || {
                if let Some(signal) = signals.forever().next() {
                    stitchkin::output::remove_temporaries();
                    std::process::exit(128 + signal);
                }
            });
        }
    }
}

/// Into a pipe or a log, a diagnostic keeps each message on one line:
/// wrapping at an assumed 80 columns splits messages at places that depend
/// on the file's path, which makes logs hard to search.
pub(crate) fn unwrapped_diagnostics_off_terminal() {
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        let _ = miette::set_hook(Box::new(|_| {
            Box::new(miette::MietteHandlerOpts::new().width(100_000).build())
        }));
    }
}

/// A command line that does not parse, reported in the same style as every
/// other error (the message, then its help: clap's tip and usage), with
/// clap's exit code 2; `--help` and `--version` print as clap prints them.
pub(crate) fn exit_on_bad_arguments(e: clap::Error) -> ! {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion)
        || matches!(e.kind(), ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand)
    {
        e.exit();
    }
    let text = e.render().to_string();
    let mut lines = text.lines();
    let message = lines.next().unwrap_or("").trim_start_matches("error: ").to_string();
    let help: Vec<&str> = lines.map(str::trim).filter(|l| !l.is_empty()).collect();
    let report = if help.is_empty() {
        miette::miette!("{message}")
    } else {
        miette::miette!(help = help.join("\n"), "{message}")
    };
    let _ = writeln!(std::io::stderr(), "Error: {report:?}");
    std::process::exit(2);
}

/// The command-line flag of a library input.
pub(crate) fn flag(input: Input) -> &'static str {
    match input {
        Input::Preset => "--preset",
        Input::Set => "--set",
        Input::Vary => "--vary",
        Input::Samples => "--samples",
        Input::Step => "--step",
        Input::Rpm => "--rpm",
        Input::Columns => "--columns",
        Input::Point => "--point",
        Input::Points => "--points",
        Input::Trajectories => "--trajectories",
        Input::Series => "--series",
        Input::Thread => "--thread",
        Input::Plane => "--plane",
        Input::View => "--view",
        Input::Figure => "--figure",
        Input::Figures => "--figures",
        Input::Thickness => "--thickness",
        Input::StitchLength => "--stitch",
        Input::Width => "--width",
        Input::Incline => "--incline",
        Input::EdgeFraction => "--edge",
        Input::Interlace => "--interlace",
        Input::SeamLength => "--seam",
        Input::Waste => "--waste",
        Input::StitchType => "--type",
        Input::Adjust => "--adjust",
        Input::Tolerance => "--tol",
        Input::LengthTolerance => "--length-tol",
        Input::Line => "--line",
        Input::Over => "--over",
        Input::Limit => "--limit",
        Input::Phi => "--phi",
        Input::Frames => "--frames",
        Input::Duration => "--duration",
        Input::ProfilePoints => "--points",
        Input::Smooth => "--smooth",
        Input::MinRadius => "--min-radius",
        Input::MaxPressureAngle => "--max-pressure-angle",
        Input::AnchorRadius => "--anchor-radius",
        Input::Cam => "--cam",
        Input::Target => "--target",
        Input::Measured => "--measured",
        _ => "an option",
    }
}

/// The error of a value this command takes in `flag`, where other commands
/// take the same input under the flag [`flag`] names (`report
/// --nomogram-thickness` for `--thickness`).
pub(crate) fn in_flag(e: Error, flag: &str) -> Error {
    match e {
        Error::Param(p) if p.input.is_some() => {
            Error::Param(ParamError::general(format!("{} (in {flag})", p.message), p.help))
        }
        other => other,
    }
}

/// The diagnostic of a failed command: a model-file error with its place in
/// the file, a parameter error naming its flag, any other with its help.
pub(crate) fn diagnostic(e: Error) -> miette::Report {
    // Papers by authors and year, as everywhere else the program prints.
    let cite = |t: &str| stitchkin::references::cited(t).into_owned();
    match e {
        Error::Model(mut m) => {
            m.message = cite(&m.message);
            m.help = m.help.as_deref().map(cite);
            let src = NamedSource::new(m.file.clone(), m.text.to_string());
            miette::Report::new(FileDiagnostic { err: *m, src })
        }
        Error::Param(p) => {
            let message = cite(&p.describe(|i| flag(i).to_string()));
            match p.help {
                Some(h) => miette::miette!(help = cite(&h), "{message}"),
                None => miette::miette!("{message}"),
            }
        }
        other => {
            let message = cite(&other.to_string());
            match other.help() {
                Some(h) => miette::miette!(help = cite(h), "{message}"),
                None => miette::miette!("{message}"),
            }
        }
    }
}

/// A model-file error shown with its place in the file.
#[derive(Debug)]
struct FileDiagnostic {
    err: ModelError,
    src: NamedSource<String>,
}

impl std::fmt::Display for FileDiagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.err.line_col() {
            Some((l, c)) => write!(f, "{}:{l}:{c}: ", self.err.file)?,
            None => write!(f, "{}: ", self.err.file)?,
        }
        if !self.err.path.is_empty() {
            write!(f, "{}: ", self.err.path)?;
        }
        write!(f, "{}", self.err.message)
    }
}

impl std::error::Error for FileDiagnostic {}

/// The longest line of a model file shown under its error; a longer one
/// (a generated or damaged file) is named by line and column only.
const MAX_SHOWN_LINE_CHARS: usize = 400;

impl FileDiagnostic {
    /// The span to underline in the file, when its lines are short enough
    /// to show.
    fn shown_span(&self) -> Option<std::ops::Range<usize>> {
        let span = self.err.span.clone()?;
        let text = &*self.err.text;
        let (start, end) = (span.start.min(text.len()), span.end.min(text.len()));
        let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[end..].find('\n').map_or(text.len(), |i| end + i);
        let long = text
            .get(line_start..line_end)
            .is_none_or(|l| l.chars().count() > MAX_SHOWN_LINE_CHARS);
        (!long).then_some(span)
    }
}

impl Diagnostic for FileDiagnostic {
    fn help<'a>(&'a self) -> Option<Box<dyn std::fmt::Display + 'a>> {
        self.err
            .help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn std::fmt::Display>)
    }
    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.shown_span().map(|_| &self.src as &dyn SourceCode)
    }
    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = self.shown_span()?;
        let len = span.len().max(1);
        Some(Box::new(std::iter::once(LabeledSpan::new(
            Some("here".into()),
            span.start,
            len,
        ))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(output: Option<&str>, terminal: bool) -> &'static str {
        match TableFormat::by_destination(output.map(Path::new), terminal) {
            TableFormat::Table => "table",
            TableFormat::Csv => "csv",
            TableFormat::Json => "json",
        }
    }

    /// A terminal gets text for people; a pipe or a file the table, as the
    /// file's name says.
    #[test]
    fn a_table_is_shown_by_where_it_goes() {
        assert_eq!(table(None, true), "table");
        assert_eq!(table(None, false), "csv");
        for terminal in [true, false] {
            assert_eq!(table(Some("out.csv"), terminal), "csv");
            assert_eq!(table(Some("out"), terminal), "csv");
            assert_eq!(table(Some("OUT.JSON"), terminal), "json");
            assert_eq!(table(Some("out.txt"), terminal), "table");
        }
        assert!(matches!(TableOrCsv::by_destination(None, true), TableOrCsv::Table));
        assert!(matches!(
            TableOrCsv::by_destination(Some(Path::new("a.json")), false),
            TableOrCsv::Csv
        ));
    }

    /// A result read as a whole is its text everywhere, JSON for a .json
    /// file.
    #[test]
    fn a_screen_is_the_same_everywhere() {
        for (output, terminal) in [(None, true), (None, false), (Some("m.txt"), false), (Some("m"), true)] {
            assert!(matches!(
                TableOrJson::by_destination(output.map(Path::new), terminal),
                TableOrJson::Table
            ));
        }
        assert!(matches!(
            TableOrJson::by_destination(Some(Path::new("m.json")), false),
            TableOrJson::Json
        ));
    }

    /// --format wins over the destination.
    #[test]
    fn a_format_given_wins() {
        assert!(matches!(
            format_or_default(Some(TableFormat::Csv), None),
            TableFormat::Csv
        ));
        assert!(matches!(
            format_or_default(Some(TableFormat::Table), Some(Path::new("x.csv"))),
            TableFormat::Table
        ));
        assert!(matches!(
            format_or_default::<TableFormat>(None, Some(Path::new("x.json"))),
            TableFormat::Json
        ));
    }

    /// Printed text cites papers by authors and year and has no negative
    /// zero.
    #[test]
    fn printed_text_is_tidied() {
        assert_eq!(
            tidy("max -0.00 mm (seed 002 eq. 15), min -0.5 mm"),
            "max 0.00 mm (Kharzhevskyi et al. (n.d.) eq. 15), min -0.5 mm"
        );
    }
}
