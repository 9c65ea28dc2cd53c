//! Output files that appear whole or not at all: written to a hidden temporary file beside the
//! target, renamed over it on [`AtomicFile::commit`], removed if dropped uncommitted.
//!
//! A path that is neither a file nor a folder, such as `/dev/null` or a named pipe, is written
//! in place: there is nothing to replace atomically, and a rename onto it would replace the
//! device itself.
//!
//! Every temporary file is also listed in a process-wide registry so that a program that must
//! exit at once (a second signal) can still remove them ([`remove_temporary_files`]).

use crate::error::Error;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

static TEMPORARY: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Removes every temporary file this process is still writing. For a program about to exit
/// without unwinding; files being written are lost, finished outputs are untouched.
pub fn remove_temporary_files() {
    remove_registered(|_| true);
}

/// Removes the registered temporary files `which` selects (tests select their own folder: the
/// registry is process-wide, and other tests write files at the same time).
fn remove_registered(which: impl Fn(&Path) -> bool) {
    let list = TEMPORARY.lock().unwrap_or_else(|e| e.into_inner());
    for p in list.iter().filter(|p| which(p)) {
        let _ = std::fs::remove_file(p);
    }
}

fn register(p: &Path) {
    TEMPORARY
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(p.to_path_buf());
}

fn unregister(p: &Path) {
    let mut list = TEMPORARY.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(i) = list.iter().position(|q| q == p) {
        list.swap_remove(i);
    }
}

/// A hidden temporary path in the folder of `path`: `.NAME.PID-N.tmp`.
pub(crate) fn temporary_path(path: &Path) -> PathBuf {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".{name}.{}-{n}.tmp", std::process::id()))
}

/// Whether `path` exists and is neither a regular file nor a folder (after symbolic links): a
/// device such as `/dev/null`, a named pipe, a socket.
pub fn is_device(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// A file being written; it replaces `path` only when committed.
pub struct AtomicFile {
    path: PathBuf,
    /// `None` for a device, written in place.
    tmp: Option<PathBuf>,
    file: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Starts writing `path` (through a temporary file in the same folder; a device such as
    /// `/dev/null` in place, see [`is_device`]).
    pub fn create(path: &Path) -> Result<AtomicFile, Error> {
        if is_device(path) {
            let file = File::options()
                .write(true)
                .open(path)
                .map_err(|e| Error::io(path, e))?;
            return Ok(AtomicFile {
                path: path.to_path_buf(),
                tmp: None,
                file: Some(BufWriter::with_capacity(1 << 20, file)),
            });
        }
        let tmp = temporary_path(path);
        let file = File::options()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|e| Error::io(path, e))?;
        register(&tmp);
        Ok(AtomicFile {
            path: path.to_path_buf(),
            tmp: Some(tmp),
            file: Some(BufWriter::with_capacity(1 << 20, file)),
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes, syncs and renames the file into place.
    pub fn commit(mut self) -> Result<(), Error> {
        let Some(w) = self.file.take() else {
            return Err(Error::io(
                &self.path,
                std::io::Error::other("already committed"),
            ));
        };
        let result = (|| {
            let f = w.into_inner().map_err(|e| e.into_error())?;
            let Some(tmp) = &self.tmp else {
                return Ok(()); // a device: written in place
            };
            f.sync_all()?;
            std::fs::rename(tmp, &self.path)
        })();
        match result {
            Ok(()) => {
                if let Some(tmp) = &self.tmp {
                    unregister(tmp);
                }
                Ok(())
            }
            Err(e) => Err(Error::io(&self.path, e)), // Drop removes the temporary file.
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.file {
            Some(f) => f.write(buf),
            None => Err(std::io::Error::other("file already committed")),
        }
    }
    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        match &mut self.file {
            Some(f) => f.write_all(buf),
            None => Err(std::io::Error::other("file already committed")),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.file {
            Some(f) => f.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        let Some(tmp) = &self.tmp else {
            return;
        };
        if tmp.exists() {
            self.file = None;
            let _ = std::fs::remove_file(tmp);
        }
        unregister(tmp);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The registry is process-wide: these tests must not run at the same time.
    static SERIAL: Mutex<()> = Mutex::new(());

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn appears_only_when_committed() {
        let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.bin");
        let mut f = AtomicFile::create(&path).unwrap();
        f.write_all(b"hello").unwrap();
        assert!(!path.exists());
        assert_eq!(names(dir.path()).len(), 1, "one temporary file");
        f.commit().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"hello");
        assert_eq!(names(dir.path()), ["out.bin"]);
    }

    #[test]
    fn dropped_leaves_nothing_and_keeps_the_old_file() {
        let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.bin");
        std::fs::write(&path, b"old").unwrap();
        let mut f = AtomicFile::create(&path).unwrap();
        f.write_all(b"new but unfinished").unwrap();
        drop(f);
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(names(dir.path()), ["out.bin"]);
    }

    #[test]
    fn a_device_is_written_in_place() {
        let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
        let null = Path::new("/dev/null");
        if !null.exists() {
            return; // not a Unix system
        }
        assert!(is_device(null));
        let mut f = AtomicFile::create(null).unwrap();
        f.write_all(b"discarded").unwrap();
        assert_eq!(f.tmp, None, "no temporary file beside a device");
        f.commit().unwrap();
        assert!(is_device(null), "still the device");
    }

    #[test]
    fn registry_removes_unfinished_files() {
        let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
        let dir = tempfile::tempdir().unwrap();
        let f = AtomicFile::create(&dir.path().join("x.gif")).unwrap();
        remove_registered(|p| p.starts_with(dir.path()));
        assert!(names(dir.path()).is_empty());
        drop(f);
    }
}
