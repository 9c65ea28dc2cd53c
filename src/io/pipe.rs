//! Standard input and output as byte streams, and what a closed pipe means.
//!
//! Rust ignores `SIGPIPE`, so writing to a pipe whose reader went away (`| head -c 1000`)
//! returns `BrokenPipe`; every stream sink turns that into [`Error::OutputClosed`], which ends
//! a run early but successfully.

use crate::error::Error;
use std::io::{Read, Write};
use std::path::Path;

/// How standard input and output are named in messages.
pub const STDIN_NAME: &str = "stdin";
pub const STDOUT_NAME: &str = "stdout";

/// An error writing to `path`: [`Error::OutputClosed`] for a closed pipe, else [`Error::Io`].
pub(crate) fn write_error(path: &Path, e: std::io::Error) -> Error {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        Error::OutputClosed
    } else {
        Error::io(path, e)
    }
}

/// Standard output as an unbuffered byte stream (wrap it in a `BufWriter`). On Unix this is
/// a duplicate of file descriptor 1, so binary frames do not go through the line buffer of
/// [`std::io::Stdout`].
pub fn stdout_stream() -> Box<dyn Write + Send> {
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        if let Ok(fd) = std::io::stdout().as_fd().try_clone_to_owned() {
            return Box::new(std::fs::File::from(fd));
        }
    }
    Box::new(std::io::stdout())
}

/// Standard input as a byte stream (unbuffered on Unix: callers buffer).
pub fn stdin_stream() -> Box<dyn Read + Send> {
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        if let Ok(fd) = std::io::stdin().as_fd().try_clone_to_owned() {
            return Box::new(std::fs::File::from(fd));
        }
    }
    Box::new(std::io::stdin())
}

/// Reads until `buf` is full or the input ends; returns how many bytes were read.
pub(crate) fn read_full(r: &mut dyn Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match r.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}
