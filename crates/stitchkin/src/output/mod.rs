//! Writing results: CSV and JSON, SVG plots, and files that are never
//! half-written.

pub mod drawing;
pub mod plots;
pub mod report;
pub mod svg;
pub mod text;

use std::io::Write;
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::Serialize;

use crate::error::Error;
use crate::eval::CycleTable;
use crate::format::{fmt_num, push_num};
use crate::model::{Model, Params};

/// The table as CSV: a header of unit-carrying column names, one row per φ.
pub fn write_csv(table: &CycleTable, out: &mut impl Write) -> std::io::Result<()> {
    let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
    writeln!(out, "{}", names.join(","))?;
    // Rows are written as text a block at a time on every core, and the
    // blocks go out in order; a batch of blocks is all that is held.
    const BLOCK_ROWS: usize = 1024;
    let rows = table.rows();
    let batch_rows = BLOCK_ROWS * 2 * rayon::current_num_threads();
    for batch in (0..rows).step_by(batch_rows) {
        let starts: Vec<usize> = (batch..rows.min(batch + batch_rows)).step_by(BLOCK_ROWS).collect();
        let blocks: Vec<Vec<u8>> = starts
            .into_par_iter()
            .map(|start| csv_rows(table, start..rows.min(start + BLOCK_ROWS)))
            .collect();
        for b in blocks {
            out.write_all(&b)?;
        }
    }
    Ok(())
}

/// The CSV text of the table's `rows`.
fn csv_rows(table: &CycleTable, rows: std::ops::Range<usize>) -> Vec<u8> {
    let mut text = Vec::new();
    for r in rows {
        for (k, c) in table.columns.iter().enumerate() {
            if k > 0 {
                text.push(b',');
            }
            push_num(&mut text, c.values[r]);
        }
        text.push(b'\n');
    }
    text
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
        .map(|(p, v)| JsonParam {
            name: &p.name,
            value: *v,
            unit: p.unit_str(),
            derived: false,
        })
        .collect();
    let run = JsonRun {
        model: model.name(),
        title: model.title(),
        seed: model.seed(),
        phi_start_deg: model.phi_start_deg(),
        parameters,
        table,
    };
    serde_json::to_writer_pretty(&mut *out, &run).map_err(std::io::Error::other)?;
    writeln!(out)
}

/// The folder a file `path` goes into (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Checks, before a long computation, that `path` can be written: its
/// folder exists.
pub fn check_folder(path: &Path) -> Result<(), Error> {
    let dir = folder_of(path);
    if dir.is_dir() {
        Ok(())
    } else {
        Err(Error::Io(format!(
            "cannot write `{}`: there is no folder `{}`",
            path.display(),
            dir.display()
        )))
    }
}

/// Where an output file goes.
enum Destination {
    /// A regular file, new or replaced: written to a temporary file in
    /// `real`'s folder, then renamed onto `real` (the file a symbolic link
    /// names, so the link stays a link).
    Replace { real: PathBuf, tmp: PathBuf },
    /// A device or a pipe (`-o /dev/null`, `-o /dev/stdout`, a FIFO):
    /// written in place, since a rename would put a file where it was.
    InPlace,
}

fn destination(path: &Path) -> Result<Destination, Error> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(Error::Io(format!(
            "cannot write `{}`: it is a folder; name a file in it",
            path.display()
        ))),
        Ok(m) if !m.is_file() => Ok(Destination::InPlace),
        found => {
            // An existing file through any links to it; a new one as named.
            let real = match found {
                Ok(_) => std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
                Err(_) => path.to_path_buf(),
            };
            let name = real
                .file_name()
                .ok_or_else(|| Error::Io(format!("`{}` is not a file path", path.display())))?;
            let tmp = folder_of(&real).join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
            Ok(Destination::Replace { real, tmp })
        }
    }
}

/// Writes `bytes` to `path` through a temporary file in the same folder and
/// a rename, so the file is either complete or untouched; a device or a pipe
/// is written in place.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let io = |e: std::io::Error, what: &str| Error::Io(format!("cannot {what} `{}`: {e}", path.display()));
    let (real, tmp) = match destination(path)? {
        Destination::InPlace => {
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(|e| io(e, "open"))?;
            return f.write_all(bytes).and_then(|_| f.flush()).map_err(|e| io(e, "write"));
        }
        Destination::Replace { real, tmp } => (real, tmp),
    };
    let result = (|| {
        let mut f = std::fs::File::create(&tmp).map_err(|e| io(e, "create a temporary file for"))?;
        f.write_all(bytes).map_err(|e| io(e, "write"))?;
        f.sync_all().map_err(|e| io(e, "write"))?;
        std::fs::rename(&tmp, &real).map_err(|e| io(e, "write"))
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
    /// A regular file: `tmp` renamed onto `real` when finished.
    File {
        tmp: PathBuf,
        real: PathBuf,
        path: PathBuf,
        file: Option<std::io::BufWriter<std::fs::File>>,
    },
    /// A device or a pipe, written in place.
    InPlace {
        path: PathBuf,
        file: std::io::BufWriter<std::fs::File>,
    },
}

impl Sink {
    pub fn new(path: Option<&Path>) -> Result<Sink, Error> {
        let target = match path {
            None => SinkTarget::Stdout(std::io::BufWriter::new(std::io::stdout())),
            Some(path) => match destination(path)? {
                Destination::Replace { real, tmp } => {
                    let f = std::fs::File::create(&tmp).map_err(|e| {
                        Error::Io(format!("cannot create a temporary file for `{}`: {e}", path.display()))
                    })?;
                    SinkTarget::File {
                        tmp,
                        real,
                        path: path.to_path_buf(),
                        file: Some(std::io::BufWriter::new(f)),
                    }
                }
                Destination::InPlace => {
                    let f = std::fs::OpenOptions::new()
                        .write(true)
                        .open(path)
                        .map_err(|e| Error::Io(format!("cannot open `{}`: {e}", path.display())))?;
                    SinkTarget::InPlace {
                        path: path.to_path_buf(),
                        file: std::io::BufWriter::new(f),
                    }
                }
            },
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
            SinkTarget::InPlace { path, file } => file
                .write_all(bytes)
                .map_err(|e| Error::Io(format!("cannot write `{}`: {e}", path.display()))),
        }
    }

    /// Flushes and, for a file, moves it into place.
    pub fn finish(mut self) -> Result<(), Error> {
        match &mut self.target {
            SinkTarget::Stdout(w) => match w.flush() {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    Err(Error::Io(format!("cannot write to stdout: {e}")))
                }
                _ => Ok(()),
            },
            SinkTarget::InPlace { path, file } => file
                .flush()
                .map_err(|e| Error::Io(format!("cannot write `{}`: {e}", path.display()))),
            SinkTarget::File { tmp, real, path, file } => {
                let w = file.take().expect("open until finished");
                let io = |e: std::io::Error| Error::Io(format!("cannot write `{}`: {e}", path.display()));
                let result = w
                    .into_inner()
                    .map_err(|e| io(e.into_error()))
                    .and_then(|f| f.sync_all().map_err(io))
                    .and_then(|_| std::fs::rename(&*tmp, &*real).map_err(io));
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

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("stitchkin-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A file is replaced whole; through a symbolic link the file it names
    /// is, and the link stays; a folder is refused.
    #[cfg(unix)]
    #[test]
    fn files_are_replaced_whole_and_links_kept() {
        let dir = scratch("links");
        let (file, link) = (dir.join("p.csv"), dir.join("latest.csv"));
        write_atomic(&file, b"old").unwrap();
        std::os::unix::fs::symlink(&file, &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&file).unwrap(), b"new");
        let mut sink = Sink::new(Some(&link)).unwrap();
        sink.write(b"streamed").unwrap();
        sink.finish().unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&file).unwrap(), b"streamed");
        let e = write_atomic(&dir, b"x").unwrap_err().to_string();
        assert!(e.contains("it is a folder"), "{e}");
        // Nothing but the two names is left in the folder.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A pipe (as a device such as /dev/null) is written in place: a rename
    /// would put a regular file where it was.
    #[cfg(unix)]
    #[test]
    fn pipes_and_devices_are_written_in_place() {
        use std::os::unix::fs::FileTypeExt;
        let dir = scratch("fifo");
        let fifo = dir.join("out.fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            panic!("mkfifo could not make a pipe to test with");
        }
        for streamed in [false, true] {
            let reader = {
                let fifo = fifo.clone();
                std::thread::spawn(move || std::fs::read(fifo).unwrap())
            };
            if streamed {
                let mut sink = Sink::new(Some(&fifo)).unwrap();
                sink.write(b"through the pipe").unwrap();
                sink.finish().unwrap();
            } else {
                write_atomic(&fifo, b"through the pipe").unwrap();
            }
            assert_eq!(reader.join().unwrap(), b"through the pipe");
            assert!(
                std::fs::metadata(&fifo).unwrap().file_type().is_fifo(),
                "the pipe stays a pipe"
            );
        }
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
