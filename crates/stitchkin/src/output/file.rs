//! Output files that are never half-written and never destroy what they
//! point at.
//!
//! - A regular file is written to a temporary file beside it and moved onto
//!   it only when complete, so it is either the old file or the new one. A
//!   replaced file keeps its permissions and, where the user may set them,
//!   its owner and group. A file with several hard links is rewritten in
//!   place after the temporary file is complete, so every link sees the new
//!   content (the one case that is not atomic: an interrupted copy leaves
//!   it short).
//! - A file nobody may write (no write permission bit) or this user may not
//!   write is refused, even for `root`: a read-only file is a promise.
//! - A device, a pipe or a socket (`-o /dev/null`, `-o /dev/stdout`, a FIFO)
//!   is written in place: a rename would put a regular file where it was.
//! - A symbolic link is followed: the file it names is written, the link
//!   stays a link.
//! - Temporary files are registered while they exist;
//!   [`remove_temporaries`] deletes them, for a program that is stopped
//!   (the command line calls it on SIGINT, SIGTERM and SIGHUP).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::{Error, IoError};

/// The temporary files that exist now, removed by [`remove_temporaries`].
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes every temporary output file this process has open: for a signal
/// handler, before the process exits half-way through writing a file.
pub fn remove_temporaries() {
    if let Ok(mut list) = TEMPORARIES.lock() {
        for tmp in list.drain(..) {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

fn register(tmp: &Path) {
    if let Ok(mut list) = TEMPORARIES.lock() {
        list.push(tmp.to_path_buf());
    }
}

fn unregister(tmp: &Path) {
    if let Ok(mut list) = TEMPORARIES.lock() {
        list.retain(|t| t != tmp);
    }
}

/// The folder a file `path` goes into (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Checks, before a long computation, that `path` can be written: its
/// folder exists, and an existing file may be replaced.
pub fn check_folder(path: &Path) -> Result<(), Error> {
    destination(path).map(|_| ())
}

/// What a replaced file keeps.
struct Existing {
    permissions: std::fs::Permissions,
    #[cfg(unix)]
    owner: (u32, u32),
    /// More than one hard link: rewritten in place, not renamed onto.
    linked: bool,
}

/// Where an output file goes.
enum Destination {
    /// A regular file, new (`existing` is `None`) or replaced: written to
    /// `tmp` in `real`'s folder, then moved onto `real` (the file a symbolic
    /// link names).
    Replace {
        real: PathBuf,
        tmp: PathBuf,
        existing: Option<Existing>,
    },
    /// A device, a pipe or a socket: written in place.
    InPlace,
}

fn refused(path: &Path, reason: impl Into<String>) -> Error {
    Error::Io(IoError::refused("write", Some(path), reason))
}

fn destination(path: &Path) -> Result<Destination, Error> {
    let real = match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => return Err(refused(path, "it is a folder; name a file in it")),
        Ok(m) if !m.is_file() => return Ok(Destination::InPlace),
        Ok(_) => std::fs::canonicalize(path).map_err(|e| Error::Io(IoError::os("write", Some(path), e)))?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => match std::fs::read_link(path) {
            // A link to a file yet to be made: make the file it names.
            Ok(target) => folder_of(path).join(target),
            Err(_) => path.to_path_buf(),
        },
        Err(e) => return Err(Error::Io(IoError::os("write", Some(path), e))),
    };
    let dir = folder_of(&real);
    if !dir.is_dir() {
        return Err(refused(path, format!("there is no folder `{}`", dir.display())));
    }
    let name = real.file_name().ok_or_else(|| refused(path, "it names no file"))?;
    let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let existing = match std::fs::metadata(&real) {
        Ok(m) => Some(existing_file(path, &real, m)?),
        Err(_) => None,
    };
    Ok(Destination::Replace { real, tmp, existing })
}

/// An existing regular file that may be replaced, with what it keeps.
fn existing_file(path: &Path, real: &Path, m: std::fs::Metadata) -> Result<Existing, Error> {
    let read_only = "it is read-only; make it writable (chmod u+w) or choose another file";
    if m.permissions().readonly() {
        return Err(refused(path, read_only));
    }
    // Opening for writing (without truncating) asks the system whether this
    // user may write it.
    if let Err(e) = std::fs::OpenOptions::new().write(true).open(real) {
        return Err(match e.kind() {
            std::io::ErrorKind::PermissionDenied => refused(path, "this user may not write it"),
            _ => Error::Io(IoError::os("write", Some(path), e)),
        });
    }
    #[cfg(unix)]
    let (owner, linked) = {
        use std::os::unix::fs::MetadataExt;
        ((m.uid(), m.gid()), m.nlink() > 1)
    };
    #[cfg(not(unix))]
    let linked = false;
    Ok(Existing {
        permissions: m.permissions(),
        #[cfg(unix)]
        owner,
        linked,
    })
}

/// Creates the temporary file `tmp` for `path`, registered for
/// [`remove_temporaries`]; a folder this user may not write is named.
fn create_temporary(path: &Path, tmp: &Path) -> Result<std::fs::File, Error> {
    let f = std::fs::File::create(tmp).map_err(|e| match e.kind() {
        std::io::ErrorKind::PermissionDenied => refused(
            path,
            format!("this user may not write in the folder `{}`", folder_of(tmp).display()),
        ),
        _ => Error::Io(IoError::os("write", Some(path), e)),
    })?;
    register(tmp);
    Ok(f)
}

/// Moves the complete temporary file `tmp` into place at `real`.
fn commit(path: &Path, tmp: &Path, real: &Path, existing: Option<&Existing>) -> Result<(), Error> {
    let io = |e: std::io::Error| Error::Io(IoError::os("write", Some(path), e));
    let result = match existing {
        Some(x) if x.linked => copy_in_place(tmp, real).map_err(io),
        Some(x) => {
            std::fs::set_permissions(tmp, x.permissions.clone()).map_err(io)?;
            // Owner and group as they were, where this user may set them
            // (root may; others keep their own).
            #[cfg(unix)]
            let _ = std::os::unix::fs::chown(tmp, Some(x.owner.0), Some(x.owner.1));
            std::fs::rename(tmp, real).map_err(io)
        }
        None => std::fs::rename(tmp, real).map_err(io),
    };
    let _ = std::fs::remove_file(tmp);
    unregister(tmp);
    result
}

/// Copies `tmp`'s bytes over `real` without replacing `real`'s inode, so
/// its hard links see them.
fn copy_in_place(tmp: &Path, real: &Path) -> std::io::Result<()> {
    let bytes = std::fs::read(tmp)?;
    let mut f = std::fs::OpenOptions::new().write(true).truncate(true).open(real)?;
    f.write_all(&bytes)?;
    f.sync_all()
}

/// Drops a temporary file that will not be committed.
fn discard(tmp: &Path) {
    let _ = std::fs::remove_file(tmp);
    unregister(tmp);
}

fn open_in_place(path: &Path) -> Result<std::fs::File, Error> {
    std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .map_err(|e| Error::Io(IoError::os("open", Some(path), e)))
}

/// Writes `bytes` to `path` whole or not at all (see the module docs).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let io = |e: std::io::Error| Error::Io(IoError::os("write", Some(path), e));
    match destination(path)? {
        Destination::InPlace => {
            let mut f = open_in_place(path)?;
            f.write_all(bytes).and_then(|_| f.flush()).map_err(io)
        }
        Destination::Replace { real, tmp, existing } => {
            let written = create_temporary(path, &tmp)
                .and_then(|mut f| f.write_all(bytes).and_then(|_| f.sync_all()).map_err(io));
            match written {
                Ok(()) => commit(path, &tmp, &real, existing.as_ref()),
                Err(e) => {
                    discard(&tmp);
                    Err(e)
                }
            }
        }
    }
}

/// Streamed output: to stdout, or to a file as [`write_atomic`] writes it,
/// put in place only when [`Sink::finish`] is called. A sink dropped
/// unfinished removes its temporary file, so a run that fails half-way
/// leaves the old file as it was.
pub struct Sink {
    target: SinkTarget,
}

enum SinkTarget {
    Stdout(std::io::BufWriter<std::io::Stdout>),
    /// A regular file: `tmp` moved onto `real` when finished.
    File {
        tmp: PathBuf,
        real: PathBuf,
        path: PathBuf,
        existing: Option<Existing>,
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
                Destination::Replace { real, tmp, existing } => SinkTarget::File {
                    file: Some(std::io::BufWriter::new(create_temporary(path, &tmp)?)),
                    tmp,
                    real,
                    path: path.to_path_buf(),
                    existing,
                },
                Destination::InPlace => SinkTarget::InPlace {
                    path: path.to_path_buf(),
                    file: std::io::BufWriter::new(open_in_place(path)?),
                },
            },
        };
        Ok(Sink { target })
    }

    pub fn write(&mut self, bytes: &[u8]) -> Result<(), Error> {
        match &mut self.target {
            SinkTarget::Stdout(w) => match w.write_all(bytes) {
                // A closed pipe (`| head`) ends the output quietly.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
                r => r.map_err(|e| Error::Io(IoError::os("write to stdout", None, e))),
            },
            SinkTarget::File { path, file, .. } => match file.as_mut() {
                Some(f) => f
                    .write_all(bytes)
                    .map_err(|e| Error::Io(IoError::os("write", Some(path), e))),
                None => Err(Error::Internal(format!(
                    "`{}` was written after it was finished",
                    path.display()
                ))),
            },
            SinkTarget::InPlace { path, file } => file
                .write_all(bytes)
                .map_err(|e| Error::Io(IoError::os("write", Some(path), e))),
        }
    }

    /// Flushes and, for a file, moves it into place.
    pub fn finish(mut self) -> Result<(), Error> {
        match &mut self.target {
            SinkTarget::Stdout(w) => match w.flush() {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    Err(Error::Io(IoError::os("write to stdout", None, e)))
                }
                _ => Ok(()),
            },
            SinkTarget::InPlace { path, file } => {
                file.flush().map_err(|e| Error::Io(IoError::os("write", Some(path), e)))
            }
            SinkTarget::File {
                tmp,
                real,
                path,
                existing,
                file,
            } => {
                let Some(w) = file.take() else {
                    return Err(Error::Internal(format!("`{}` was finished twice", path.display())));
                };
                let io = |e: std::io::Error| Error::Io(IoError::os("write", Some(path), e));
                let flushed = w
                    .into_inner()
                    .map_err(|e| io(e.into_error()))
                    .and_then(|f| f.sync_all().map_err(io));
                match flushed {
                    Ok(()) => commit(path, tmp, real, existing.as_ref()),
                    Err(e) => {
                        discard(tmp);
                        Err(e)
                    }
                }
            }
        }
    }
}

impl Drop for Sink {
    fn drop(&mut self) {
        if let SinkTarget::File { tmp, file: Some(_), .. } = &self.target {
            discard(tmp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        // A link to a file not yet made makes that file and stays a link.
        let (later, dangling) = (dir.join("later.csv"), dir.join("dangling.csv"));
        std::os::unix::fs::symlink("later.csv", &dangling).unwrap();
        write_atomic(&dangling, b"made").unwrap();
        assert!(std::fs::symlink_metadata(&dangling).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&later).unwrap(), b"made");
        // Nothing but the four names is left in the folder.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 4);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A replaced file keeps its permissions and its hard links; a
    /// read-only file is refused and left as it was.
    #[cfg(unix)]
    #[test]
    fn a_replaced_file_keeps_its_mode_links_and_read_only_promise() {
        use std::os::unix::fs::{MetadataExt, PermissionsExt};
        let dir = scratch("keeps");
        let private = dir.join("private.csv");
        write_atomic(&private, b"old").unwrap();
        std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_atomic(&private, b"new").unwrap();
        assert_eq!(std::fs::metadata(&private).unwrap().mode() & 0o777, 0o600);
        assert_eq!(std::fs::read(&private).unwrap(), b"new");

        let (a, b) = (dir.join("a.csv"), dir.join("b.csv"));
        write_atomic(&a, b"one").unwrap();
        std::fs::hard_link(&a, &b).unwrap();
        let inode = std::fs::metadata(&a).unwrap().ino();
        for streamed in [false, true] {
            let text: &[u8] = if streamed { b"three" } else { b"two" };
            if streamed {
                let mut sink = Sink::new(Some(&a)).unwrap();
                sink.write(text).unwrap();
                sink.finish().unwrap();
            } else {
                write_atomic(&a, text).unwrap();
            }
            assert_eq!(std::fs::read(&b).unwrap(), text, "the other link sees it");
            assert_eq!(std::fs::metadata(&a).unwrap().ino(), inode);
        }

        let locked = dir.join("locked.csv");
        write_atomic(&locked, b"keep me").unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o444)).unwrap();
        let e = write_atomic(&locked, b"gone").unwrap_err().to_string();
        assert!(e.contains("read-only"), "{e}");
        assert!(Sink::new(Some(&locked)).is_err());
        assert_eq!(std::fs::read(&locked).unwrap(), b"keep me");

        let e = write_atomic(&dir.join("no/such/folder/x.csv"), b"x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("there is no folder") && e.contains("no/such/folder"), "{e}");
        // No temporary file is left behind.
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// An unfinished sink's temporary file is removed when it is dropped,
    /// and is registered for `remove_temporaries` while it is open.
    #[test]
    fn temporary_files_do_not_outlive_the_write() {
        let dir = scratch("temporaries");
        let out = dir.join("s.csv");
        let tmp_count = || {
            std::fs::read_dir(&dir)
                .unwrap()
                .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().ends_with(".tmp"))
                .count()
        };
        let mut sink = Sink::new(Some(&out)).unwrap();
        sink.write(b"half").unwrap();
        assert_eq!(tmp_count(), 1);
        // Registered for `remove_temporaries` (not called here: it would
        // remove the other tests' files too; the command line's test sends
        // the signal).
        assert!(TEMPORARIES.lock().unwrap().iter().any(|t| t.starts_with(&dir)));
        drop(sink);
        assert!(!TEMPORARIES.lock().unwrap().iter().any(|t| t.starts_with(&dir)));
        let sink = Sink::new(Some(&out)).unwrap();
        drop(sink);
        assert_eq!(tmp_count(), 0);
        assert!(!out.exists(), "an unfinished sink makes no file");
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
        write_atomic(Path::new("/dev/null"), b"nothing").unwrap();
        assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
