//! The library's errors as Python exceptions, each with the library's own message: a bad
//! argument is a `ValueError`, a file that cannot be read or written an `OSError` (its
//! `FileNotFoundError` and `PermissionError` where the cause says so), a misuse or a bug a
//! `RuntimeError`.

use pyo3::exceptions::{
    PyFileNotFoundError, PyOSError, PyPermissionError, PyRuntimeError, PyValueError,
};
use pyo3::PyErr;
use vizretarget::Error;

/// `e` as the Python exception a caller would expect for it.
pub fn to_py(e: Error) -> PyErr {
    let message = e.to_string();
    match e {
        Error::InvalidOptions(_)
        | Error::InvalidSize { .. }
        | Error::FrameSizeMismatch { .. }
        | Error::LimitExceeded { .. } => PyValueError::new_err(message),
        Error::Io { source, .. } => match source.kind() {
            std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
            std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
            _ => PyOSError::new_err(message),
        },
        Error::OutOfOrder(_) | Error::Internal(_) | Error::Solve(_) => {
            PyRuntimeError::new_err(message)
        }
        // Decode, NoFrames, TruncatedFrame, Encode, Unsupported, OutputClosed: the file.
        _ => PyOSError::new_err(message),
    }
}

/// A `ValueError` naming `what`.
pub fn bad(what: &str, message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{what}: {message}"))
}
