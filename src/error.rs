//! The library's one error type. Variants are the ones a caller acts on differently.

use crate::size::{InvalidSize, Size, MAX_SIDE};
use std::path::PathBuf;

/// Everything that can go wrong in the library.
///
/// `Debug` shows the same one line as `Display` (`out.png: Permission denied (os error 13)`),
/// so that `fn main() -> Result<(), vizretarget::Error>` reports an error readably when `?`
/// returns it; match on the variants to see the fields.
#[derive(thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An option is out of range; the message names the value and what is allowed.
    #[error("invalid option: {0}")]
    InvalidOptions(String),

    /// A width or height is zero or above [`crate::MAX_SIDE`].
    #[error("invalid size {width}x{height}: each side must be between 1 and {max}", max = MAX_SIDE)]
    InvalidSize { width: u32, height: u32 },

    /// A frame's size differs from the stream's.
    #[error("frame {frame_index} is {got}, but the stream is {expected}")]
    FrameSizeMismatch {
        frame_index: u64,
        expected: Size,
        got: Size,
    },

    /// An input could not be decoded (corrupt, truncated or unsupported).
    #[error("{}: {message}", path.display())]
    Decode { path: PathBuf, message: String },

    /// Reading or writing failed.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// The sparse solver failed, which only happens on a malformed mesh (a bug).
    #[error("the linear solve failed: {0}")]
    Solve(String),

    /// The input had no frames at all.
    #[error("no frames in {}", .0.display())]
    NoFrames(PathBuf),

    /// A bug: a stage panicked, or something the library keeps true did not hold. The
    /// message says where, or which.
    #[error("internal error: {0}")]
    Internal(String),

    /// The reader of the output went away (a closed pipe, `| head`): nothing more can be
    /// written, which for a stream is a normal way to end.
    #[error("the output was closed by its reader")]
    OutputClosed,

    /// An input went past one of the [`crate::Limits`]: `message` says what it declared or
    /// needs and the limit; the caller may name the option that raises `limit`, with
    /// `needed` when known: what the input needs, in the limit's unit (pixels of a frame,
    /// frames, bytes of memory).
    #[error("{}: {message}", path.display())]
    LimitExceeded {
        path: PathBuf,
        limit: Limit,
        message: String,
        needed: Option<u64>,
    },

    /// A picture could not be encoded: the format and the encoder's message.
    #[error("encoding failed: {0}")]
    Encode(String),

    /// The input ended inside a frame: `got` of `expected` bytes of frame `frame_index`.
    #[error("{}: frame {frame_index} is incomplete: {got} of {expected} bytes", path.display())]
    TruncatedFrame {
        path: PathBuf,
        frame_index: u64,
        expected: usize,
        got: usize,
    },

    /// The output format cannot hold what it was given (a GIF's sides are 16-bit, at most
    /// 65535 px): `message` names the format and its limit. Neither the input nor the
    /// library is at fault; another format can hold it.
    #[error("{}: {message}", path.display())]
    Unsupported { path: PathBuf, message: String },

    /// A method was called in a state that does not allow it (a frame sent after `flush`, a
    /// frame added to a GIF already finished): a bug in the caller. The message names the
    /// call and the state.
    #[error("called out of order: {0}")]
    OutOfOrder(String),
}

/// Which limit an input went past ([`Error::LimitExceeded`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Limit {
    /// [`crate::Limits::max_pixels`].
    Pixels,
    /// [`crate::Limits::max_frames`].
    Frames,
    /// [`crate::Limits::memory_budget`].
    Memory,
}

impl From<InvalidSize> for Error {
    fn from(e: InvalidSize) -> Error {
        Error::InvalidSize {
            width: e.width,
            height: e.height,
        }
    }
}

impl From<crate::target::InvalidTarget> for Error {
    fn from(e: crate::target::InvalidTarget) -> Error {
        Error::InvalidOptions(e.0)
    }
}

impl std::fmt::Debug for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Display::fmt(self, f)
    }
}

impl Error {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Error {
        Error::Io {
            path: path.into(),
            source,
        }
    }
    pub(crate) fn decode(path: impl Into<PathBuf>, message: impl Into<String>) -> Error {
        Error::Decode {
            path: path.into(),
            message: message.into(),
        }
    }
}
