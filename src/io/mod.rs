//! Reading and writing frames: every way frames come in and go out.
//!
//! - In ([`crate::stream::FrameSource`]): still pictures ([`read_still`]), animated GIF
//!   ([`GifSource`]), a folder of pictures in natural order ([`DirSource`]), raw RGBA/RGB
//!   frames ([`RawSource`]), YUV4MPEG2 ([`Y4mSource`]), concatenated PNGs
//!   ([`PngStreamSource`]), a watched folder of snapshots ([`WatchSource`], feature `watch`).
//! - Out ([`crate::stream::FrameSink`]): still PNG/JPEG/WebP ([`write_still`]), animated GIF
//!   ([`GifSink`]), a folder of PNGs ([`PngSeqSink`]), raw frames ([`RawSink`]), YUV4MPEG2
//!   ([`Y4mSink`]), concatenated PNGs ([`PngStreamSink`]).
//! - [`open_input`], [`resolve_output`] and [`open_sink`] pick among them from a path and a
//!   format, as the command line does; [`path_shape`] tells one picture in a file from an
//!   animation or a folder, and [`peek_stdin`] one picture on stdin from a stream.
//!
//! Inputs are recognised by their first bytes, never by their names. Files are written
//! through a temporary file and a rename, so a reader never sees half a file; a run that
//! fails leaves no temporary file behind. Stream sinks turn a closed pipe into
//! [`crate::Error::OutputClosed`], which ends a run early but successfully.

mod atomic;
mod dir;
mod gif_in;
mod gif_out;
mod marks;
mod names;
mod natural;
mod open;
mod peek;
mod pipe;
mod png_seq;
mod png_stream;
mod quantize;
mod raw;
mod shape;
mod sniff;
mod still;
#[cfg(feature = "watch")]
mod watch;
mod y4m;

pub use atomic::{is_device, remove_temporary_files, AtomicFile};
pub use dir::{list_images, DirSource};
pub use gif_in::GifSource;
pub use gif_out::{GifOptions, GifSink};
pub use marks::{FrameMarks, MarkedSource};
pub use names::FrameNames;
pub use natural::natural_cmp;
#[cfg(feature = "watch")]
pub use open::open_watch;
pub use open::{
    is_std, open_input, open_input_with, open_peeked, open_sink, resolve_output, Destination,
    Input, InputFormat, InputKind, OutputChoice, SinkFormat, SinkOptions,
};
pub use peek::{peek_input, peek_stdin, Peeked, PictureFile};
pub use pipe::{stdin_stream, stdout_stream, STDIN_NAME, STDOUT_NAME};
pub use png_seq::{output_name, PngSeqSink};
pub use png_stream::{PngStreamSink, PngStreamSource};
pub use raw::{RawFormat, RawSink, RawSource};
pub use shape::{path_shape, PathShape};
pub use sniff::{sniff, Magic};
pub use still::{
    decode_still, decode_still_with, encode_still, probe_still, read_still, read_still_with,
    write_atomic, write_still, OutputFormat,
};
#[cfg(feature = "watch")]
pub use watch::{WatchOptions, WatchSource};
pub use y4m::{Chroma, FrameRate, Y4mSink, Y4mSource};

/// A retargeted frame for sink tests.
#[cfg(test)]
pub(crate) fn test_frame(
    image: crate::Image,
    frame_index: u64,
    duration_ms: Option<u32>,
) -> crate::Retargeted {
    crate::Retargeted {
        image,
        frame_index,
        duration_ms,
        stats: Default::default(),
        analysis: None,
        marks: None,
    }
}
