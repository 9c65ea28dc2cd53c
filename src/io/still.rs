//! Still images: PNG, JPEG, WebP and the first frame of a GIF in (recognised by their magic
//! bytes, not their extension); PNG, JPEG or lossless WebP out, written atomically.

use super::gif_in::GifSource;
use super::sniff::{sniff, Magic};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::limits::Limits;
use crate::stream::FrameSource;
use image::{ColorType, ImageDecoder, ImageError, ImageFormat};
use std::io::{BufRead, BufReader, Cursor, Read, Seek, Write};
use std::path::Path;

/// Most bytes read from an input that is not a regular file (a pipe, a device): 1 GiB, or the
/// memory budget if smaller. A regular file is streamed, so only its header is read before the
/// size checks.
const MAX_STREAMED_BYTES: u64 = 1 << 30;

/// Reads a still image (the first frame of an animation), as RGBA8, within the default
/// [`Limits`].
pub fn read_still(path: &Path) -> Result<Image, Error> {
    read_still_with(path, &Limits::default())
}

/// Reads a still image (the first frame of an animation), as RGBA8.
///
/// The format is recognised by content. Sizes above [`crate::MAX_SIDE`] or [`Limits::max_pixels`]
/// are refused from the header, before any pixel is decoded; decoders may allocate up to
/// [`Limits::memory_budget`].
pub fn read_still_with(path: &Path, limits: &Limits) -> Result<Image, Error> {
    match open_still(path, limits)? {
        Opened::Gif(reader) => gif_first_frame(reader, path, limits),
        Opened::File(reader) => decode_from(reader, path, limits),
        Opened::Bytes(bytes) => decode_still_with(&bytes, path, limits),
    }
}

/// The first frame of a GIF, read as [`GifSource`] reads frames (composited as a browser
/// shows them, unknown extension blocks skipped), not by the `image` crate's decoder, which
/// refuses such blocks.
fn gif_first_frame<R: Read + Send>(
    reader: R,
    path: &Path,
    limits: &Limits,
) -> Result<Image, Error> {
    let mut gif = GifSource::with_limits(reader, path, limits)?;
    match gif.next_frame()? {
        Some(frame) => Ok(frame.image),
        None => Err(Error::decode(path, "the GIF has no frames")),
    }
}

/// The size a still image declares in its header, checked as [`read_still_with`] checks it,
/// without decoding a pixel: what a caller needs to check a job's memory before the decode.
pub fn probe_still(path: &Path, limits: &Limits) -> Result<Size, Error> {
    match open_still(path, limits)? {
        Opened::Gif(reader) => GifSource::with_limits(reader, path, limits).map(|g| g.size()),
        Opened::File(reader) => header_of(reader, path, limits).map(|(_, size, _)| size),
        Opened::Bytes(bytes) => probe_bytes(&bytes, path, limits),
    }
}

/// [`probe_still`] of a picture held in memory; `path` only names it in errors.
pub(crate) fn probe_bytes(bytes: &[u8], path: &Path, limits: &Limits) -> Result<Size, Error> {
    if sniff(bytes) == Some(Magic::Gif) {
        return GifSource::with_limits(bytes, path, limits).map(|g| g.size());
    }
    header_of(Cursor::new(bytes), path, limits).map(|(_, size, _)| size)
}

/// Most bytes read into memory from an input that cannot seek (a pipe, a device).
pub(crate) fn max_piped_bytes(limits: &Limits) -> u64 {
    limits
        .decode_bytes()
        .map_or(MAX_STREAMED_BYTES, |b| b.min(MAX_STREAMED_BYTES))
}

enum Opened {
    File(BufReader<std::fs::File>),
    /// A GIF file, read by [`GifSource`].
    Gif(BufReader<std::fs::File>),
    Bytes(Vec<u8>),
}

fn open_still(path: &Path, limits: &Limits) -> Result<Opened, Error> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let meta = file.metadata().map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        return Err(Error::decode(path, "is a directory, not an image"));
    }
    if meta.is_file() {
        let mut reader = BufReader::new(file);
        // Peeked, not consumed.
        let head = reader.fill_buf().map_err(|e| Error::io(path, e))?;
        if sniff(head) == Some(Magic::Gif) {
            return Ok(Opened::Gif(reader));
        }
        return Ok(Opened::File(reader));
    }
    // Pipes and devices cannot seek, and `/dev/zero` never ends: read a bounded amount.
    let max = max_piped_bytes(limits);
    let mut bytes = Vec::new();
    file.take(max + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > max {
        return Err(Error::decode(
            path,
            format!(
                "input stream is larger than {}",
                crate::limits::human_bytes(max)
            ),
        ));
    }
    Ok(Opened::Bytes(bytes))
}

/// Decodes a still image from memory within the default [`Limits`]; `path` only names it in
/// errors.
pub fn decode_still(bytes: &[u8], path: &Path) -> Result<Image, Error> {
    decode_still_with(bytes, path, &Limits::default())
}

/// Decodes a still image from memory; `path` only names it in errors.
pub fn decode_still_with(bytes: &[u8], path: &Path, limits: &Limits) -> Result<Image, Error> {
    if sniff(bytes) == Some(Magic::Gif) {
        return gif_first_frame(bytes, path, limits);
    }
    decode_from(Cursor::new(bytes), path, limits)
}

/// The decoder, after its header is read and its size checked.
fn header_of<'a, R: BufRead + Seek + 'a>(
    source: R,
    path: &Path,
    limits: &Limits,
) -> Result<(impl ImageDecoder + 'a, Size, String), Error> {
    let mut reader = image::ImageReader::new(source)
        .with_guessed_format()
        .map_err(|e| Error::io(path, e))?;
    let format = match reader.format() {
        Some(f) if f.reading_enabled() => f,
        Some(f) => {
            return Err(Error::decode(
                path,
                format!(
                    "unsupported format {} (expected PNG, JPEG, WebP or GIF)",
                    format_name(f)
                ),
            ))
        }
        None if is_empty(reader.into_inner()) => {
            return Err(Error::decode(path, "empty file, not an image"))
        }
        None => {
            return Err(Error::decode(
                path,
                "unsupported format (expected PNG, JPEG, WebP or GIF)",
            ))
        }
    };
    let name = format_name(format);
    let mut decode_limits = image::Limits::no_limits();
    decode_limits.max_alloc = limits.decode_bytes();
    reader.limits(decode_limits);
    // Building the decoder reads the header only; the size is checked before any pixel.
    let decoder = reader
        .into_decoder()
        .map_err(|e| decode_error(path, &name, e, limits))?;
    let (w, h) = decoder.dimensions();
    let size = limits.check_size(path, &name, w as u64, h as u64)?;
    Ok((decoder, size, name))
}

fn decode_from<R: BufRead + Seek>(source: R, path: &Path, limits: &Limits) -> Result<Image, Error> {
    let (decoder, size, name) = header_of(source, path, limits)?;
    let fail = |e: ImageError| decode_error(path, &name, e, limits);
    let px = size.area();
    let expand = |native: &[u8], bpp: usize, f: fn(&[u8]) -> [u8; 4]| -> Vec<[u8; 4]> {
        native.chunks_exact(bpp).map(f).collect()
    };
    // Into the picture's own buffer where the layout allows, so the peak is the decoder's
    // bytes plus the picture, not two more copies.
    let pixels: Vec<[u8; 4]> = match decoder.color_type() {
        ColorType::Rgba8 => {
            let mut pixels = vec![[0u8; 4]; px];
            decoder
                .read_image(pixels.as_flattened_mut())
                .map_err(fail)?;
            pixels
        }
        c @ (ColorType::Rgb8 | ColorType::L8 | ColorType::La8) => {
            let mut native = vec![0u8; decoder.total_bytes() as usize];
            decoder.read_image(&mut native).map_err(fail)?;
            match c {
                ColorType::Rgb8 => expand(&native, 3, |p| [p[0], p[1], p[2], 255]),
                ColorType::L8 => expand(&native, 1, |p| [p[0], p[0], p[0], 255]),
                _ => expand(&native, 2, |p| [p[0], p[0], p[0], p[1]]),
            }
        }
        _ => {
            let rgba = image::DynamicImage::from_decoder(decoder)
                .map_err(fail)?
                .into_rgba8();
            expand(rgba.as_raw(), 4, |p| [p[0], p[1], p[2], p[3]])
        }
    };
    Image::from_pixels(size, pixels)
        .ok_or_else(|| Error::decode(path, "the decoder returned a wrong number of pixels"))
}

fn is_empty<R: Read>(mut r: R) -> bool {
    matches!(r.read(&mut [0u8; 1]), Ok(0))
}

fn format_name(f: ImageFormat) -> String {
    match f {
        ImageFormat::Png => "PNG".into(),
        ImageFormat::Jpeg => "JPEG".into(),
        ImageFormat::WebP => "WebP".into(),
        ImageFormat::Gif => "GIF".into(),
        other => other
            .extensions_str()
            .first()
            .map_or_else(|| format!("{other:?}"), |e| e.to_ascii_uppercase()),
    }
}

/// The decoder's error as ours: over the memory budget, or what [`describe`] says.
fn decode_error(path: &Path, name: &str, e: ImageError, limits: &Limits) -> Error {
    match (&e, limits.memory_budget) {
        (ImageError::Limits(_), Some(budget)) => Error::LimitExceeded {
            path: path.to_path_buf(),
            limit: crate::Limit::Memory,
            needed: None,
            message: format!(
                "decoding this {name} needs more than the memory limit of {}",
                crate::limits::human_bytes(budget)
            ),
        },
        _ => Error::decode(path, describe(name, e)),
    }
}

/// One line saying what is wrong with the file: truncated, corrupt or unsupported.
fn describe(name: &str, e: ImageError) -> String {
    let truncated = {
        let mut src: Option<&(dyn std::error::Error + 'static)> = Some(&e);
        let mut eof = false;
        while let Some(s) = src {
            eof |= s
                .downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::UnexpectedEof);
            eof |= s.to_string().contains("end of file");
            src = s.source();
        }
        eof
    };
    let text = match &e {
        ImageError::Limits(l) => return one_line(&format!("{name} image: {l}")),
        ImageError::Unsupported(u) => return one_line(&format!("unsupported {name} variant: {u}")),
        // "Format error decoding Png: <detail>": keep the detail.
        ImageError::Decoding(d) => {
            std::error::Error::source(d).map_or_else(|| d.to_string(), |s| s.to_string())
        }
        other => other.to_string(),
    };
    if truncated {
        format!("truncated {name}: the file ends early")
    } else {
        one_line(&format!("corrupt {name}: {text}"))
    }
}

/// Decoders may quote raw bytes from the file: keep the message on one printable line. The
/// `png` crate names a chunk by its `Debug` form (`ChunkType { type: IHDR, critical: true,
/// .. }`): keep its name only.
fn one_line(s: &str) -> String {
    let mut s = s.to_string();
    while let Some(start) = s.find("ChunkType { type: ") {
        let Some(len) = s[start..].find('}') else {
            break;
        };
        let name: String = s[start + 18..].chars().take(4).collect();
        s.replace_range(start..start + len + 1, &name);
    }
    s.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

/// Still output formats.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    Png,
    Jpeg,
    /// Lossless WebP.
    WebP,
}

impl OutputFormat {
    /// The format a path's extension asks for (`.png`, `.jpg`, `.jpeg`, `.webp`), if any.
    pub fn from_path(path: &Path) -> Option<OutputFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(OutputFormat::Png),
            "jpg" | "jpeg" => Some(OutputFormat::Jpeg),
            "webp" => Some(OutputFormat::WebP),
            _ => None,
        }
    }

    /// The format's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            OutputFormat::Png => "PNG",
            OutputFormat::Jpeg => "JPEG",
            OutputFormat::WebP => "WebP",
        }
    }
}

/// The bytes of `image` for a lossless encoder: RGB when it is opaque (a quarter smaller to
/// compress), RGBA otherwise.
fn packed(image: &Image) -> (std::borrow::Cow<'_, [u8]>, image::ExtendedColorType) {
    if image.is_opaque() {
        let rgb = image.pixels().iter().flat_map(|p| [p[0], p[1], p[2]]);
        (
            rgb.collect::<Vec<u8>>().into(),
            image::ExtendedColorType::Rgb8,
        )
    } else {
        (image.as_bytes().into(), image::ExtendedColorType::Rgba8)
    }
}

/// Encodes `image` into memory; an encoder's refusal is [`Error::Encode`].
pub fn encode_still(image: &Image, format: OutputFormat) -> Result<Vec<u8>, Error> {
    encode(image, format).map_err(|e| Error::Encode(format!("{}: {e}", format.name())))
}

fn encode(image: &Image, format: OutputFormat) -> Result<Vec<u8>, ImageError> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    let (w, h) = (image.width(), image.height());
    match format {
        OutputFormat::Png => {
            let (bytes, colour) = packed(image);
            image::codecs::png::PngEncoder::new_with_quality(
                &mut out,
                image::codecs::png::CompressionType::Fast,
                image::codecs::png::FilterType::Adaptive,
            )
            .write_image(&bytes, w, h, colour)?;
        }
        OutputFormat::Jpeg => {
            // JPEG has no alpha: composite over white, as a viewer would show it.
            let rgb: Vec<u8> = image
                .pixels()
                .iter()
                .flat_map(|p| {
                    let a = p[3] as u32;
                    [0, 1, 2].map(|c| ((p[c] as u32 * a + 255 * (255 - a) + 127) / 255) as u8)
                })
                .collect();
            let mut enc = image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, 92);
            enc.encode(&rgb, w, h, image::ExtendedColorType::Rgb8)?;
        }
        OutputFormat::WebP => {
            let (bytes, colour) = packed(image);
            image::codecs::webp::WebPEncoder::new_lossless(&mut out)
                .write_image(&bytes, w, h, colour)?;
        }
    }
    Ok(out)
}

/// Writes `image` to `path` atomically: encoded in memory, written to a temporary file beside
/// it, then renamed. A failure leaves no file, or the old one, at `path`.
///
/// A path whose extension names another format than `format` (`out.jpg` with
/// [`OutputFormat::Png`]) is refused with [`Error::InvalidOptions`] before anything is
/// written: a viewer trusting the name would fail on the bytes. A name without one of the
/// known extensions takes `format`. [`OutputFormat::from_path`] gives the format a name asks
/// for.
pub fn write_still(image: &Image, path: &Path, format: OutputFormat) -> Result<(), Error> {
    if let Some(named) = OutputFormat::from_path(path).filter(|&f| f != format) {
        return Err(Error::InvalidOptions(format!(
            "{}: the name says {} but the picture was to be written as {}",
            path.display(),
            named.name(),
            format.name()
        )));
    }
    let bytes = encode_still(image, format).map_err(|e| match e {
        Error::Encode(m) => Error::decode(path, format!("encoding failed: {m}")),
        e => e,
    })?;
    write_atomic(path, &bytes)
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename
/// ([`AtomicFile`]: listed for removal if the program must exit at once).
///
/// [`AtomicFile`]: super::AtomicFile
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let mut file = super::atomic::AtomicFile::create(path)?;
    file.write_all(bytes).map_err(|e| Error::io(path, e))?;
    file.commit()
}
