//! Writing results: CSV and JSON, SVG plots, and files that are never
//! half-written.

pub mod svg;
pub mod plots;
pub mod drawing;
pub mod report;
pub mod text;

use std::io::Write;
use std::path::Path;

use serde::Serialize;

use crate::error::Error;
use crate::eval::CycleTable;
use crate::model::{Model, Params};

/// Formats a number with 12 significant digits, shortest form
/// (`175`, `-3.14159265359`; `1.5e-10` for tiny and huge magnitudes).
pub fn fmt_num(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let rounded: f64 = format!("{x:.11e}").parse().unwrap_or(x);
    let a = rounded.abs();
    if (1e-4..1e15).contains(&a) { format!("{rounded}") } else { format!("{rounded:e}") }
}

/// The table as CSV: a header of unit-carrying column names, one row per φ.
pub fn write_csv(table: &CycleTable, out: &mut impl Write) -> std::io::Result<()> {
    let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
    writeln!(out, "{}", names.join(","))?;
    let mut line = String::new();
    for r in 0..table.rows() {
        line.clear();
        for (k, c) in table.columns.iter().enumerate() {
            if k > 0 {
                line.push(',');
            }
            line.push_str(&fmt_num(c.values[r]));
        }
        writeln!(out, "{line}")?;
    }
    Ok(())
}

#[derive(Serialize)]
struct JsonParam<'a> {
    name: &'a str,
    value: f64,
    unit: &'a str,
    derived: bool,
}

#[derive(Serialize)]
struct JsonRun<'a> {
    model: &'a str,
    title: Option<&'a str>,
    seed: Option<&'a str>,
    phi_start_deg: f64,
    parameters: Vec<JsonParam<'a>>,
    #[serde(flatten)]
    table: &'a CycleTable,
}

/// The run as JSON: model, parameter values, columns and summaries.
pub fn write_json(model: &Model, params: &Params, table: &CycleTable, out: &mut impl Write) -> std::io::Result<()> {
    let parameters = model
        .params
        .iter()
        .zip(&params.values)
        .filter(|(p, _)| !p.is_derived())
        .map(|(p, v)| JsonParam { name: &p.name, value: *v, unit: p.unit_str(), derived: false })
        .collect();
    let run = JsonRun {
        model: &model.file.model.name,
        title: model.file.model.title.as_deref(),
        seed: model.file.model.seed.as_deref(),
        phi_start_deg: model.phi_start_deg(),
        parameters,
        table,
    };
    serde_json::to_writer_pretty(&mut *out, &run).map_err(std::io::Error::other)?;
    writeln!(out)
}

/// The folder a file `path` goes into (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

/// Checks, before a long computation, that `path` can be written: its
/// folder exists.
pub fn check_folder(path: &Path) -> Result<(), Error> {
    let dir = folder_of(path);
    if dir.is_dir() {
        Ok(())
    } else {
        Err(Error::Io(format!("cannot write `{}`: there is no folder `{}`", path.display(), dir.display())))
    }
}

/// Writes `bytes` to `path` through a temporary file in the same folder and
/// a rename, so the file is either complete or untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let dir = folder_of(path);
    let name = path.file_name().ok_or_else(|| Error::Io(format!("`{}` is not a file path", path.display())))?;
    let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let io = |e: std::io::Error, what: &str| Error::Io(format!("cannot {what} `{}`: {e}", path.display()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp).map_err(|e| io(e, "create a temporary file for"))?;
        f.write_all(bytes).map_err(|e| io(e, "write"))?;
        f.sync_all().map_err(|e| io(e, "write"))?;
        std::fs::rename(&tmp, path).map_err(|e| io(e, "write"))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Streamed output: to stdout, or to a temporary file beside `path` that
/// replaces `path` only when [`Sink::finish`] is called, so a run that fails
/// half-way never leaves a half-written file (the temporary is removed when
/// the sink is dropped unfinished).
pub struct Sink {
    target: SinkTarget,
}

enum SinkTarget {
    Stdout(std::io::BufWriter<std::io::Stdout>),
    File { tmp: std::path::PathBuf, path: std::path::PathBuf, file: Option<std::io::BufWriter<std::fs::File>> },
}

impl Sink {
    pub fn new(path: Option<&Path>) -> Result<Sink, Error> {
        let target = match path {
            None => SinkTarget::Stdout(std::io::BufWriter::new(std::io::stdout())),
            Some(path) => {
                let dir = folder_of(path);
                let name = path.file_name().ok_or_else(|| Error::Io(format!("`{}` is not a file path", path.display())))?;
                let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
                let f = std::fs::File::create(&tmp)
                    .map_err(|e| Error::Io(format!("cannot create a temporary file for `{}`: {e}", path.display())))?;
                SinkTarget::File { tmp, path: path.to_path_buf(), file: Some(std::io::BufWriter::new(f)) }
            }
        };
        Ok(Sink { target })
    }

    pub fn write(&mut self, bytes: &[u8]) -> Result<(), Error> {
        match &mut self.target {
            SinkTarget::Stdout(w) => match w.write_all(bytes) {
                // A closed pipe (`| head`) ends the output quietly.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
                r => r.map_err(|e| Error::Io(format!("cannot write to stdout: {e}"))),
            },
            SinkTarget::File { path, file, .. } => file
                .as_mut()
                .expect("open until finished")
                .write_all(bytes)
                .map_err(|e| Error::Io(format!("cannot write `{}`: {e}", path.display()))),
        }
    }

    /// Flushes and, for a file, moves it into place.
    pub fn finish(mut self) -> Result<(), Error> {
        match &mut self.target {
            SinkTarget::Stdout(w) => match w.flush() {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Error::Io(format!("cannot write to stdout: {e}"))),
                _ => Ok(()),
            },
            SinkTarget::File { tmp, path, file } => {
                let w = file.take().expect("open until finished");
                let io = |e: std::io::Error| Error::Io(format!("cannot write `{}`: {e}", path.display()));
                let result = w
                    .into_inner()
                    .map_err(|e| io(e.into_error()))
                    .and_then(|f| f.sync_all().map_err(io))
                    .and_then(|_| std::fs::rename(&*tmp, &*path).map_err(io));
                if result.is_err() {
                    let _ = std::fs::remove_file(&*tmp);
                }
                result
            }
        }
    }
}

impl Drop for Sink {
    fn drop(&mut self) {
        if let SinkTarget::File { tmp, file: Some(_), .. } = &self.target {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_exact_enough() {
        assert_eq!(fmt_num(175.0), "175");
        assert_eq!(fmt_num(0.1 + 0.2), "0.3");
        assert_eq!(fmt_num(-1.5e-10), "-1.5e-10");
        assert_eq!(fmt_num(9.18e-16), "9.18e-16");
        assert_eq!(fmt_num(0.000123), "0.000123");
        assert_eq!(fmt_num(std::f64::consts::PI), "3.14159265359");
    }
}
