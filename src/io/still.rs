//! Still images: PNG, JPEG, WebP and the first frame of a GIF in (recognised by their magic
//! bytes, not their extension); PNG or JPEG out, written atomically.

use crate::error::Error;
use crate::image::{Image, Size, MAX_SIDE};
use std::io::{BufReader, Cursor, Write};
use std::path::Path;

/// Reads a still image (the first frame of an animation), as RGBA8.
///
/// Sizes above [`MAX_SIDE`] are refused before any pixel is decoded.
pub fn read_still(path: &Path) -> Result<Image, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    decode_still(&bytes, path)
}

/// Decodes a still image from memory; `path` only names it in errors.
pub fn decode_still(bytes: &[u8], path: &Path) -> Result<Image, Error> {
    let reader = image::ImageReader::new(BufReader::new(Cursor::new(bytes)))
        .with_guessed_format()
        .map_err(|e| Error::io(path, e))?;
    let Some(format) = reader.format() else {
        return Err(Error::decode(
            path,
            "unsupported format (expected PNG, JPEG, WebP or GIF)",
        ));
    };
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    let mut reader = reader;
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| match e {
        image::ImageError::Limits(_) => Error::decode(
            path,
            format!("{format:?} image is larger than {MAX_SIDE} px on a side"),
        ),
        image::ImageError::Unsupported(u) => Error::decode(path, format!("unsupported: {u}")),
        other => Error::decode(path, format!("corrupt or truncated {format:?}: {other}")),
    })?;
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
    Ok(Image::from_rgba_bytes(size, rgba.as_raw()).expect("decoder gives w*h*4 bytes"))
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

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    Ok(())
}
