//! Still images: PNG, JPEG, WebP and the first frame of a GIF in (recognised by their magic
//! bytes, not their extension); PNG or JPEG out, written atomically.

use crate::error::Error;
use crate::image::{Image, Size, MAX_SIDE};
use image::{ImageDecoder, ImageError, ImageFormat};
use std::io::{BufRead, BufReader, Cursor, Read, Seek, Write};
use std::path::Path;

/// Most bytes read from an input that is not a regular file (a pipe, a device): 1 GiB. A regular
/// file is streamed, so only its header is read before the size checks.
const MAX_STREAMED_BYTES: u64 = 1 << 30;

/// Most bytes a decoder may allocate: the `image` crate's default of 512 MiB, about a
/// 11000x11000 RGBA picture.
const MAX_DECODE_BYTES: u64 = 512 * 1024 * 1024;

/// Reads a still image (the first frame of an animation), as RGBA8.
///
/// The format is recognised by content. Sizes above [`MAX_SIDE`] are refused from the header,
/// before any pixel is decoded.
pub fn read_still(path: &Path) -> Result<Image, Error> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let meta = file.metadata().map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        return Err(Error::decode(path, "is a directory, not an image"));
    }
    if meta.is_file() {
        return decode_from(BufReader::new(file), path);
    }
    // Pipes and devices cannot seek, and `/dev/zero` never ends: read a bounded amount.
    let mut bytes = Vec::new();
    file.take(MAX_STREAMED_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > MAX_STREAMED_BYTES {
        return Err(Error::decode(path, "input stream is larger than 1 GiB"));
    }
    decode_still(&bytes, path)
}

/// Decodes a still image from memory; `path` only names it in errors.
pub fn decode_still(bytes: &[u8], path: &Path) -> Result<Image, Error> {
    decode_from(Cursor::new(bytes), path)
}

fn decode_from<R: BufRead + Seek>(source: R, path: &Path) -> Result<Image, Error> {
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
    let mut limits = image::Limits::no_limits();
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    reader.limits(limits);
    // Building the decoder reads the header only; the size is checked before any pixel.
    let decoder = reader
        .into_decoder()
        .map_err(|e| Error::decode(path, describe(&name, e)))?;
    let (w, h) = decoder.dimensions();
    if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
        return Err(Error::decode(
            path,
            format!("{name} declares {w}x{h} px: out of range, each side must be 1 to {MAX_SIDE}"),
        ));
    }
    let decoded = image::DynamicImage::from_decoder(decoder)
        .map_err(|e| Error::decode(path, describe(&name, e)))?;
    let rgba = decoded.into_rgba8();
    let size = Size::new(rgba.width(), rgba.height()).map_err(|_| {
        Error::decode(
            path,
            format!(
                "image size {}x{} is not supported",
                rgba.width(),
                rgba.height()
            ),
        )
    })?;
    Image::from_rgba_bytes(size, rgba.as_raw())
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

/// One line saying what is wrong with the file: truncated, corrupt, unsupported or too large.
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
        ImageError::Limits(_) => {
            return format!(
                "{name} image needs more than {} MiB to decode",
                MAX_DECODE_BYTES >> 20
            )
        }
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

/// Decoders may quote raw bytes from the file: keep the message on one printable line.
fn one_line(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

/// Still output formats.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    Png,
    Jpeg,
}

impl OutputFormat {
    /// The format a path's extension asks for (`.png`, `.jpg`, `.jpeg`), if any.
    pub fn from_path(path: &Path) -> Option<OutputFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(OutputFormat::Png),
            "jpg" | "jpeg" => Some(OutputFormat::Jpeg),
            _ => None,
        }
    }
}

/// Encodes `image` into memory.
pub fn encode_still(image: &Image, format: OutputFormat) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let (w, h) = (image.width(), image.height());
    match format {
        OutputFormat::Png => {
            let enc = image::codecs::png::PngEncoder::new_with_quality(
                &mut out,
                image::codecs::png::CompressionType::Fast,
                image::codecs::png::FilterType::Adaptive,
            );
            use image::ImageEncoder;
            if image.is_opaque() {
                let rgb: Vec<u8> = image
                    .pixels()
                    .iter()
                    .flat_map(|p| [p[0], p[1], p[2]])
                    .collect();
                enc.write_image(&rgb, w, h, image::ExtendedColorType::Rgb8)
            } else {
                enc.write_image(image.as_bytes(), w, h, image::ExtendedColorType::Rgba8)
            }
            .map_err(|e| e.to_string())?;
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
            enc.encode(&rgb, w, h, image::ExtendedColorType::Rgb8)
                .map_err(|e| e.to_string())?;
        }
    }
    Ok(out)
}

/// Writes `image` to `path` atomically: encoded in memory, written to a temporary file beside
/// it, then renamed. A failure leaves no file, or the old one, at `path`.
pub fn write_still(image: &Image, path: &Path, format: OutputFormat) -> Result<(), Error> {
    let bytes = encode_still(image, format)
        .map_err(|m| Error::decode(path, format!("encoding failed: {m}")))?;
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
