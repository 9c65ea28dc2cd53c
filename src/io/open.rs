//! The front door: an input path and format to a [`FrameSource`], an output path and format
//! to a [`FrameSink`]. The command line calls only these.

use super::atomic::{is_device, AtomicFile};
use super::dir::DirSource;
use super::gif_in::GifSource;
use super::gif_out::{GifOptions, GifSink};
use super::names::FrameNames;
use super::peek::{peek_stdin, Peeked};
use super::pipe::{read_full, stdin_stream, stdout_stream, STDIN_NAME, STDOUT_NAME};
use super::png_seq::PngSeqSink;
use super::png_stream::{PngStreamSink, PngStreamSource};
use super::raw::{RawFormat, RawSink, RawSource};
use super::sniff::{head_of, sniff, Magic, SNIFF_LEN};
use super::still::{read_still_with, OutputFormat};
use super::y4m::{FrameRate, Y4mSink, Y4mSource};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::limits::Limits;
use crate::retarget::{Frame, Retargeted};
use crate::stream::{FrameSink, FrameSource, Repeat};
use std::io::{Cursor, Read};
use std::path::Path;

/// How to read an input.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum InputFormat {
    /// By content: a folder, a GIF, PNG, JPEG, WebP or YUV4MPEG2 file; on stdin one picture
    /// (a PNG followed by the end of the input, a JPEG, WebP or GIF file), a PNG stream or
    /// YUV4MPEG2 ([`super::peek_stdin`]).
    #[default]
    Auto,
    /// Raw frames, 4 bytes a pixel; needs the frame size.
    Rgba,
    /// Raw frames, 3 bytes a pixel; needs the frame size.
    Rgb24,
    /// YUV4MPEG2.
    Y4m,
    /// Concatenated PNG files.
    PngStream,
}

/// What an input is, once opened.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum InputKind {
    /// One PNG, JPEG or WebP picture.
    Still,
    Gif,
    Folder,
    Raw(RawFormat),
    Y4m,
    PngStream,
    /// A watched folder of snapshots.
    Watch,
}

/// An opened input.
pub struct Input {
    pub source: Box<dyn FrameSource>,
    pub kind: InputKind,
    /// The name of each frame's file, for a folder.
    pub names: Option<FrameNames>,
    /// The frame rate the input declares (YUV4MPEG2's `F`).
    pub frame_rate: Option<FrameRate>,
    size: Option<Size>,
}

impl Input {
    /// One picture as a source of one frame.
    pub(crate) fn picture(image: Image) -> Input {
        let size = image.size();
        let one = OneFrame(Some(Frame::new(image, 0)));
        Input::new(Box::new(one), InputKind::Still, Some(size))
    }

    /// A GIF's frames.
    pub(crate) fn gif<R: Read + Send + 'static>(gif: GifSource<R>) -> Input {
        let size = gif.size();
        Input::new(Box::new(gif), InputKind::Gif, Some(size))
    }

    fn new(source: Box<dyn FrameSource>, kind: InputKind, size: Option<Size>) -> Input {
        Input {
            source,
            kind,
            names: None,
            frame_rate: None,
            size,
        }
    }

    /// The size of the frames when known without reading a frame (from a header).
    pub fn known_size(&self) -> Option<Size> {
        self.size
    }

    /// The size of the frames: from the header where there is one, else by reading the first
    /// frame (which the source then still delivers first). `None` for an empty input.
    pub fn frame_size(&mut self) -> Result<Option<Size>, Error> {
        if self.size.is_some() {
            return Ok(self.size);
        }
        let placeholder: Box<dyn FrameSource> = Box::new(OneFrame(None));
        let mut rest = std::mem::replace(&mut self.source, placeholder);
        let first = rest.next_frame();
        let first = match first {
            Ok(f) => f,
            Err(e) => {
                self.source = rest;
                return Err(e);
            }
        };
        self.size = first.as_ref().map(|f| f.image.size());
        self.source = Box::new(Prepend { first, rest });
        Ok(self.size)
    }
}

/// A source of one frame.
struct OneFrame(Option<Frame>);
impl FrameSource for OneFrame {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        Ok(self.0.take())
    }
    fn len_hint(&self) -> Option<usize> {
        Some(self.0.is_some() as usize)
    }
}

/// A frame already read, then the rest of the source.
struct Prepend {
    first: Option<Frame>,
    rest: Box<dyn FrameSource>,
}
impl FrameSource for Prepend {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        match self.first.take() {
            Some(f) => Ok(Some(f)),
            None => self.rest.next_frame(),
        }
    }
    fn len_hint(&self) -> Option<usize> {
        self.rest
            .len_hint()
            .map(|n| n + self.first.is_some() as usize)
    }
    fn repeat(&self) -> Option<Repeat> {
        self.rest.repeat()
    }
}

/// `-` means standard input or output.
pub fn is_std(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Opens `path` (a file, a folder, or `-` for stdin) as a source of frames within the default
/// [`Limits`]. `size` is the frame size of raw input.
pub fn open_input(path: &Path, format: InputFormat, size: Option<Size>) -> Result<Input, Error> {
    open_input_with(path, format, size, &Limits::default())
}

/// Opens `path` (a file, a folder, or `-` for stdin) as a source of frames. `size` is the
/// frame size of raw input. Every source checks frame sizes against `limits` from its header
/// before decoding, and counts frames against them: a GIF file or a folder before its first
/// frame, a stream as it is read. A raw file whose length is not a whole number of frames is
/// refused before any frame (its `size` or format is wrong).
pub fn open_input_with(
    path: &Path,
    format: InputFormat,
    size: Option<Size>,
    limits: &Limits,
) -> Result<Input, Error> {
    if is_std(path) && format == InputFormat::Auto {
        return open_peeked(peek_stdin(limits)?, limits);
    }
    if is_std(path) {
        let stdin = stdin_stream();
        return open_stream(stdin, Path::new(STDIN_NAME), format, size, true, limits);
    }
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        if format != InputFormat::Auto {
            return Err(Error::InvalidOptions(format!(
                "{} is a folder: its frames are recognised by content, give no input format",
                path.display()
            )));
        }
        let dir = DirSource::open_with(path, limits)?;
        let names = dir.names();
        let mut input = Input::new(Box::new(dir), InputKind::Folder, None);
        input.names = Some(names);
        return Ok(input);
    }
    if format == InputFormat::Auto {
        let head = head_of(path).map_err(|e| Error::io(path, e))?;
        match sniff(&head) {
            Some(Magic::Gif) => return Ok(Input::gif(GifSource::open_with(path, limits)?)),
            Some(Magic::Y4m) => {}
            // PNG, JPEG, WebP, and anything else: the still reader names what is wrong.
            _ => return Ok(Input::picture(read_still_with(path, limits)?)),
        }
    }
    if let (InputFormat::Rgba | InputFormat::Rgb24, Some(size)) = (format, size) {
        let f = raw_format(format);
        let frame = (size.area() * f.bytes_per_pixel()) as u64;
        if meta.is_file() && meta.len() % frame != 0 {
            return Err(Error::decode(
                path,
                format!(
                    "{} bytes is not a whole number of {size} {} frames ({frame} bytes each): \
                     check --input-size and --input-format",
                    meta.len(),
                    f.name()
                ),
            ));
        }
    }
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    open_stream(Box::new(file), path, format, size, false, limits)
}

/// Opens what [`super::peek_stdin`] found on stdin: one picture (a GIF's frames), or a
/// stream recognised by content.
pub fn open_peeked(peeked: Peeked, limits: &Limits) -> Result<Input, Error> {
    match peeked {
        Peeked::Picture(p) if p.is_gif() => {
            let name = p.name().to_path_buf();
            Ok(Input::gif(GifSource::from_bytes(
                p.into_bytes(),
                &name,
                limits,
            )?))
        }
        Peeked::Picture(p) => Ok(Input::picture(p.decode(limits)?)),
        Peeked::Stream(r) => open_stream(
            r,
            Path::new(STDIN_NAME),
            InputFormat::Auto,
            None,
            true,
            limits,
        ),
    }
}

fn raw_format(format: InputFormat) -> RawFormat {
    if format == InputFormat::Rgba {
        RawFormat::Rgba
    } else {
        RawFormat::Rgb24
    }
}

fn open_stream(
    mut reader: Box<dyn Read + Send>,
    name: &Path,
    format: InputFormat,
    size: Option<Size>,
    is_stdin: bool,
    limits: &Limits,
) -> Result<Input, Error> {
    let raw = |f: RawFormat| -> Result<Size, Error> {
        size.ok_or_else(|| {
            Error::InvalidOptions(format!(
                "raw {} frames need their size (--input-size WxH)",
                f.name()
            ))
        })
    };
    let format = match format {
        InputFormat::Auto => {
            let mut head = vec![0u8; SNIFF_LEN];
            let n = read_full(&mut reader, &mut head).map_err(|e| Error::io(name, e))?;
            head.truncate(n);
            if n == 0 {
                return Err(Error::decode(name, "the input is empty: no frames"));
            }
            let kind = sniff(&head);
            reader = Box::new(Cursor::new(head).chain(reader));
            match kind {
                Some(Magic::Png) => InputFormat::PngStream,
                Some(Magic::Y4m) => InputFormat::Y4m,
                Some(Magic::Gif) => {
                    return Ok(Input::gif(GifSource::with_limits(reader, name, limits)?));
                }
                _ if is_stdin => {
                    return Err(Error::decode(
                        name,
                        "not a picture (PNG, JPEG, WebP, GIF), a PNG stream or YUV4MPEG2: raw \
                         frames need --input-format rgba|rgb24 and --input-size WxH",
                    ))
                }
                _ => {
                    return Err(Error::decode(
                        name,
                        "unsupported format (expected PNG, JPEG, WebP, GIF or YUV4MPEG2)",
                    ))
                }
            }
        }
        f => f,
    };
    Ok(match format {
        InputFormat::Rgba | InputFormat::Rgb24 => {
            let f = raw_format(format);
            let size = raw(f)?;
            let src = RawSource::with_limits(reader, name, size, f, limits)?;
            Input::new(Box::new(src), InputKind::Raw(f), Some(size))
        }
        InputFormat::Y4m => {
            let src = Y4mSource::with_limits(reader, name, limits)?;
            let (size, rate) = (src.size(), src.frame_rate());
            let mut input = Input::new(Box::new(src), InputKind::Y4m, Some(size));
            input.frame_rate = rate;
            input
        }
        InputFormat::PngStream | InputFormat::Auto => {
            let src = PngStreamSource::with_limits(reader, name, limits);
            Input::new(Box::new(src), InputKind::PngStream, None)
        }
    })
}

/// Output formats a user can ask for.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum OutputChoice {
    /// By the path: `-` is YUV4MPEG2 on stdout, and so is a device such as `/dev/null`
    /// ([`super::is_device`]); a folder (existing, or a path ending in `/`) a PNG sequence,
    /// else the extension: `.gif`, `.png`, `.jpg`/`.jpeg`, `.webp`, `.y4m`. (The command
    /// line writes one picture to stdout or a device as PNG: it knows the input.)
    #[default]
    Auto,
    Gif,
    PngSeq,
    /// A still PNG file, or a PNG stream on stdout.
    Png,
    Jpeg,
    Rgba,
    Rgb24,
    Y4m,
}

/// Where frames go, decided from the path and the requested format.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Destination {
    /// One picture (the still path: `INPUT.png -o OUT.png`).
    Still(OutputFormat),
    /// A stream of frames.
    Stream(SinkFormat),
}

/// Stream outputs.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum SinkFormat {
    Gif,
    PngSeq,
    PngStream,
    Raw(RawFormat),
    Y4m,
}

/// Decides what `-o path` with `--output-format choice` writes, before any work. A device
/// (`/dev/null`) takes what stdout takes.
pub fn resolve_output(path: &Path, choice: OutputChoice) -> Result<Destination, Error> {
    use Destination::{Still, Stream};
    if is_std(path) || is_device(path) {
        return match choice {
            OutputChoice::Auto | OutputChoice::Y4m => Ok(Stream(SinkFormat::Y4m)),
            OutputChoice::Png => Ok(Stream(SinkFormat::PngStream)),
            OutputChoice::Rgba => Ok(Stream(SinkFormat::Raw(RawFormat::Rgba))),
            OutputChoice::Rgb24 => Ok(Stream(SinkFormat::Raw(RawFormat::Rgb24))),
            OutputChoice::Gif => Ok(Stream(SinkFormat::Gif)),
            OutputChoice::PngSeq | OutputChoice::Jpeg => Err(Error::InvalidOptions(
                "stdout takes rgba, rgb24, y4m, png (a PNG stream) or gif".into(),
            )),
        };
    }
    let folder_like = path.as_os_str().to_string_lossy().ends_with(['/', '\\']) || path.is_dir();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    Ok(match choice {
        OutputChoice::PngSeq => Stream(SinkFormat::PngSeq),
        OutputChoice::Auto if folder_like => Stream(SinkFormat::PngSeq),
        OutputChoice::Auto => match ext.as_deref() {
            Some("gif") => Stream(SinkFormat::Gif),
            Some("y4m") => Stream(SinkFormat::Y4m),
            Some("png") => Still(OutputFormat::Png),
            Some("jpg" | "jpeg") => Still(OutputFormat::Jpeg),
            Some("webp") => Still(OutputFormat::WebP),
            _ => {
                return Err(Error::InvalidOptions(format!(
                    "{}: unsupported output format: use a name ending in .png, .jpg, .jpeg or \
                     .webp (one picture), .gif or .y4m (an animation), a folder ending in / (a \
                     PNG sequence), or - (stdout)",
                    path.display()
                )))
            }
        },
        OutputChoice::Gif => Stream(SinkFormat::Gif),
        OutputChoice::Png if folder_like => Stream(SinkFormat::PngSeq),
        OutputChoice::Png => Still(named(path, OutputFormat::Png)?),
        OutputChoice::Jpeg => Still(named(path, OutputFormat::Jpeg)?),
        OutputChoice::Rgba => Stream(SinkFormat::Raw(RawFormat::Rgba)),
        OutputChoice::Rgb24 => Stream(SinkFormat::Raw(RawFormat::Rgb24)),
        OutputChoice::Y4m => Stream(SinkFormat::Y4m),
    })
}

/// `format`, unless the path's extension names another still format: `--output-format png
/// -o out.jpg` would write PNG bytes under a JPEG name.
fn named(path: &Path, format: OutputFormat) -> Result<OutputFormat, Error> {
    match OutputFormat::from_path(path) {
        Some(f) if f != format => Err(Error::InvalidOptions(format!(
            "{}: the name says {} but the output format asked for is {}",
            path.display(),
            f.name(),
            format.name()
        ))),
        _ => Ok(format),
    }
}

impl SinkFormat {
    /// Bytes the sink holds per output pixel while writing, for the memory plan
    /// ([`Limits::plan_stream`]): a GIF keeps the last input and shown frames, the pending
    /// frame's indices and the quantizer's maps; PNG encodes through an RGB copy and its
    /// compressed bytes; the others convert one frame at a time.
    pub fn held_bytes_per_pixel(self) -> u64 {
        match self {
            SinkFormat::Gif => 12,
            SinkFormat::PngSeq | SinkFormat::PngStream => 8,
            SinkFormat::Raw(_) => 3,
            SinkFormat::Y4m => 2,
        }
    }
}

/// Options of stream outputs.
#[derive(Clone, Debug, Default)]
pub struct SinkOptions {
    /// Frame rate: sets GIF delays and the YUV4MPEG2 header (else from the frames' durations).
    pub frame_rate: Option<FrameRate>,
    /// Loop count of a GIF (default: forever).
    pub repeat: Option<Repeat>,
    /// File names for a PNG sequence (from a folder or watched input).
    pub names: Option<FrameNames>,
}

/// Opens the sink for `format` at `path` (`-` for stdout). Files appear whole at
/// [`FrameSink::finish`]; a PNG sequence's folder is created if missing.
pub fn open_sink(
    path: &Path,
    format: SinkFormat,
    options: SinkOptions,
) -> Result<Box<dyn FrameSink>, Error> {
    let gif = GifOptions {
        repeat: options.repeat.unwrap_or(Repeat::Infinite),
        frame_rate: options.frame_rate,
        ..GifOptions::default()
    };
    if format == SinkFormat::PngSeq {
        return Ok(Box::new(PngSeqSink::create(path, options.names)?));
    }
    if is_std(path) {
        let out = stdout_stream();
        let name = Path::new(STDOUT_NAME);
        return Ok(match format {
            SinkFormat::Gif => Box::new(GifSink::new(out, name, gif)),
            SinkFormat::PngStream => Box::new(PngStreamSink::new(out, name)),
            SinkFormat::Raw(f) => Box::new(RawSink::new(out, name, f)),
            SinkFormat::Y4m => Box::new(Y4mSink::new(out, name, options.frame_rate)),
            SinkFormat::PngSeq => unreachable!("handled above"),
        });
    }
    if format == SinkFormat::Gif {
        return Ok(Box::new(GifSink::create(path, gif)?));
    }
    let file = AtomicFile::create(path)?;
    let inner: Box<dyn IntoWriter> = match format {
        SinkFormat::PngStream => Box::new(PngStreamSink::new(file, path)),
        SinkFormat::Raw(f) => Box::new(RawSink::new(file, path, f)),
        _ => Box::new(Y4mSink::new(file, path, options.frame_rate)),
    };
    Ok(Box::new(FileSink { inner: Some(inner) }))
}

/// A stream sink whose file is committed at finish.
trait IntoWriter: FrameSink {
    fn commit(self: Box<Self>) -> Result<(), Error>;
}
impl IntoWriter for PngStreamSink<AtomicFile> {
    fn commit(self: Box<Self>) -> Result<(), Error> {
        self.into_inner()?.commit()
    }
}
impl IntoWriter for RawSink<AtomicFile> {
    fn commit(self: Box<Self>) -> Result<(), Error> {
        self.into_inner()?.commit()
    }
}
impl IntoWriter for Y4mSink<AtomicFile> {
    fn commit(self: Box<Self>) -> Result<(), Error> {
        self.into_inner()?.commit()
    }
}

struct FileSink {
    inner: Option<Box<dyn IntoWriter>>,
}
impl FrameSink for FileSink {
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), Error> {
        match &mut self.inner {
            Some(s) => s.write_frame(frame),
            None => Err(Error::OutOfOrder(
                "a frame written to a sink already finished".into(),
            )),
        }
    }
    fn finish(&mut self) -> Result<(), Error> {
        match self.inner.take() {
            Some(mut s) => {
                s.finish()?;
                s.commit()
            }
            None => Ok(()),
        }
    }
}

/// Starts watching `dir` for snapshots ([`super::WatchSource`]); the frame names are in
/// [`Input::names`].
#[cfg(feature = "watch")]
pub fn open_watch(dir: &Path, options: super::WatchOptions) -> Result<Input, Error> {
    let source = super::WatchSource::new(dir, options)?;
    let names = source.names();
    let mut input = Input::new(Box::new(source), InputKind::Watch, None);
    input.names = Some(names);
    Ok(input)
}
