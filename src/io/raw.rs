//! Raw frames, byte-compatible with `ffmpeg -f rawvideo -pix_fmt rgba` (or `rgb24`): frames
//! of exactly `width·height·bytes_per_pixel` bytes, back to back, no header.
//!
//! The reader fills one frame at a time (RGBA straight into the frame's pixels, RGB through one
//! reused buffer), so memory stays flat on an endless pipe. Zero bytes at a frame boundary is
//! the end of the stream; a partial last frame is [`Error::TruncatedFrame`], reported after
//! every complete frame was delivered.

use super::pipe::{read_full, write_error};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::limits::Limits;
use crate::retarget::{Frame, Retargeted};
use crate::stream::{FrameSink, FrameSource};
use std::io::{Read, Write};
use std::path::PathBuf;

/// Pixel layouts of raw frames.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum RawFormat {
    /// 4 bytes a pixel: R, G, B, A (`-pix_fmt rgba`).
    Rgba,
    /// 3 bytes a pixel: R, G, B (`-pix_fmt rgb24`); read as opaque.
    Rgb24,
}

impl RawFormat {
    pub fn bytes_per_pixel(self) -> usize {
        match self {
            RawFormat::Rgba => 4,
            RawFormat::Rgb24 => 3,
        }
    }

    /// ffmpeg's name for the layout.
    pub fn name(self) -> &'static str {
        match self {
            RawFormat::Rgba => "rgba",
            RawFormat::Rgb24 => "rgb24",
        }
    }
}

/// Frames of a fixed size and layout from a byte stream.
pub struct RawSource<R> {
    reader: R,
    name: PathBuf,
    size: Size,
    format: RawFormat,
    next_index: u64,
    buf: Vec<u8>,
    ended: bool,
    max_frames: Option<u64>,
}

impl<R: Read + Send> RawSource<R> {
    /// Reads frames of `size` in `format` from `reader`; `name` names it in errors. No limit
    /// on the frame count (the caller chose the size).
    pub fn new(reader: R, name: impl Into<PathBuf>, size: Size, format: RawFormat) -> Self {
        RawSource {
            reader,
            name: name.into(),
            size,
            format,
            next_index: 0,
            buf: Vec::new(),
            ended: false,
            max_frames: None,
        }
    }

    /// As [`RawSource::new`], with `size` checked against `limits` and frames counted against
    /// them as they are read.
    pub fn with_limits(
        reader: R,
        name: impl Into<PathBuf>,
        size: Size,
        format: RawFormat,
        limits: &Limits,
    ) -> Result<Self, Error> {
        let mut src = RawSource::new(reader, name, size, format);
        let what = format!("--input-size {size}");
        limits.check_pixels(&src.name, &what, size.width as u64, size.height as u64)?;
        src.max_frames = limits.max_frames;
        Ok(src)
    }

    fn frame_bytes(&self) -> usize {
        self.size.area() * self.format.bytes_per_pixel()
    }
}

impl<R: Read + Send> FrameSource for RawSource<R> {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        if self.ended {
            return Ok(None);
        }
        let expected = self.frame_bytes();
        if let Some(max) = self.max_frames.filter(|&m| self.next_index >= m) {
            // One byte tells whether the stream goes on past the limit.
            let more =
                read_full(&mut self.reader, &mut [0u8; 1]).map_err(|e| Error::io(&self.name, e))?;
            self.ended = true;
            if more == 0 {
                return Ok(None);
            }
            return Err(crate::limits::too_many_frames(&self.name, max));
        }
        let (got, pixels) = match self.format {
            RawFormat::Rgba => {
                let mut pixels = vec![[0u8; 4]; self.size.area()];
                let got = read_full(&mut self.reader, pixels.as_flattened_mut());
                (got, Some(pixels))
            }
            RawFormat::Rgb24 => {
                self.buf.resize(expected, 0);
                (read_full(&mut self.reader, &mut self.buf), None)
            }
        };
        let got = got.map_err(|e| Error::io(&self.name, e))?;
        if got < expected {
            self.ended = true;
            if got == 0 {
                return Ok(None);
            }
            return Err(Error::TruncatedFrame {
                path: self.name.clone(),
                frame_index: self.next_index,
                expected,
                got,
            });
        }
        let pixels = pixels.unwrap_or_else(|| {
            let mut px = vec![[0u8; 4]; self.size.area()];
            rgb_to_rgba(&self.buf, &mut px);
            px
        });
        let image = Image::from_pixels(self.size, pixels).ok_or_else(|| {
            Error::Internal(format!(
                "{}: frame {}: the pixels read do not fill a {} frame",
                self.name.display(),
                self.next_index,
                self.size
            ))
        })?;
        let frame = Frame::new(image, self.next_index);
        self.next_index += 1;
        Ok(Some(frame))
    }
}

/// Writes frames as raw bytes (RGB drops alpha, as `ffmpeg -pix_fmt rgb24` does).
pub struct RawSink<W: Write + Send> {
    writer: std::io::BufWriter<W>,
    name: PathBuf,
    format: RawFormat,
    buf: Vec<u8>,
}

impl<W: Write + Send> RawSink<W> {
    pub fn new(writer: W, name: impl Into<PathBuf>, format: RawFormat) -> Self {
        RawSink {
            writer: std::io::BufWriter::with_capacity(1 << 20, writer),
            name: name.into(),
            format,
            buf: Vec::new(),
        }
    }

    /// The writer, once finished.
    pub fn into_inner(self) -> Result<W, Error> {
        let name = self.name;
        self.writer
            .into_inner()
            .map_err(|e| write_error(&name, e.into_error()))
    }
}

impl<W: Write + Send> FrameSink for RawSink<W> {
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), Error> {
        let bytes: &[u8] = match self.format {
            RawFormat::Rgba => frame.image.as_bytes(),
            RawFormat::Rgb24 => {
                let pixels = frame.image.pixels();
                self.buf.resize(3 * pixels.len(), 0);
                rgba_to_rgb(pixels, &mut self.buf);
                &self.buf
            }
        };
        self.writer
            .write_all(bytes)
            .map_err(|e| write_error(&self.name, e))
    }

    fn finish(&mut self) -> Result<(), Error> {
        self.writer.flush().map_err(|e| write_error(&self.name, e))
    }
}

crate::simd::with_feature! {
    "avx2";
    /// Opaque pixels from packed RGB bytes (as many as both hold). Sized first, then one
    /// loop over both buffers, byte by byte: with AVX2's byte shuffles that form runs about
    /// three times as fast as copying three-byte slices.
    fn rgb_to_rgba(rgb: &[u8], out: &mut [[u8; 4]]) => rgb_to_rgba_body {
        debug_assert_eq!(rgb.len(), 3 * out.len(), "every pixel gets its bytes");
        for (o, p) in out.iter_mut().zip(rgb.chunks_exact(3)) {
            *o = [p[0], p[1], p[2], 255];
        }
    }
}

crate::simd::with_feature! {
    "avx2";
    /// Packed RGB bytes of pixels, their alpha dropped (as many as both hold): as
    /// [`rgb_to_rgba`], byte by byte.
    fn rgba_to_rgb(px: &[[u8; 4]], out: &mut [u8]) => rgba_to_rgb_body {
        debug_assert_eq!(out.len(), 3 * px.len(), "every pixel gets its bytes");
        for (o, p) in out.chunks_exact_mut(3).zip(px) {
            o[0] = p[0];
            o[1] = p[1];
            o[2] = p[2];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_build_converts_the_same_bytes() {
        let rgb: Vec<u8> = (0..3 * 301u32).map(|i| (i * 37 % 251) as u8).collect();
        let (mut wide, mut base) = (vec![[0u8; 4]; 301], vec![[0u8; 4]; 301]);
        rgb_to_rgba(&rgb, &mut wide);
        rgb_to_rgba_body(&rgb, &mut base);
        assert_eq!(wide, base);
        assert!(wide
            .iter()
            .zip(rgb.chunks_exact(3))
            .all(|(o, p)| o[..3] == *p && o[3] == 255));
        let (mut back, mut back_base) = (vec![0u8; 3 * 301], vec![0u8; 3 * 301]);
        rgba_to_rgb(&wide, &mut back);
        rgba_to_rgb_body(&wide, &mut back_base);
        assert_eq!((&back, &back_base), (&rgb, &rgb));
    }

    fn frames(bytes: &[u8], size: Size, format: RawFormat) -> (Vec<Frame>, Option<Error>) {
        let mut src = RawSource::new(bytes, "test", size, format);
        let mut out = Vec::new();
        loop {
            match src.next_frame() {
                Ok(Some(f)) => out.push(f),
                Ok(None) => return (out, None),
                Err(e) => {
                    assert!(matches!(src.next_frame(), Ok(None)), "ends after an error");
                    return (out, Some(e));
                }
            }
        }
    }

    #[test]
    fn rgb24_frames_in_order_then_clean_end() {
        let size = Size::new(2, 1).unwrap();
        let bytes: Vec<u8> = (0..3u8).flat_map(|i| [i, 1, 2, i, 4, 5]).collect();
        let (f, err) = frames(&bytes, size, RawFormat::Rgb24);
        assert!(err.is_none());
        assert_eq!(f.len(), 3);
        for (i, fr) in f.iter().enumerate() {
            assert_eq!(fr.frame_index, i as u64);
            assert_eq!(
                fr.image.pixels(),
                &[[i as u8, 1, 2, 255], [i as u8, 4, 5, 255]]
            );
        }
    }

    #[test]
    fn partial_last_frame_is_an_error_after_the_complete_ones() {
        let size = Size::new(2, 2).unwrap();
        let mut bytes = vec![7u8; 16 * 2];
        bytes.extend([1, 2, 3]);
        let (f, err) = frames(&bytes, size, RawFormat::Rgba);
        assert_eq!(f.len(), 2);
        match err {
            Some(Error::TruncatedFrame {
                frame_index: 2,
                expected: 16,
                got: 3,
                ..
            }) => {}
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn empty_input_is_no_frames() {
        let (f, err) = frames(&[], Size::new(4, 4).unwrap(), RawFormat::Rgba);
        assert!(f.is_empty() && err.is_none());
    }

    #[test]
    fn sink_writes_bytes_and_maps_broken_pipe() {
        let img = Image::filled(Size::new(2, 1).unwrap(), [1, 2, 3, 4]);
        let out = crate::io::test_frame(img, 0, None);
        let mut sink = RawSink::new(Vec::new(), "mem", RawFormat::Rgb24);
        sink.write_frame(&out).unwrap();
        sink.finish().unwrap();
        assert_eq!(sink.into_inner().unwrap(), [1, 2, 3, 1, 2, 3]);

        struct Closed;
        impl Write for Closed {
            fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
                Err(std::io::ErrorKind::BrokenPipe.into())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Err(std::io::ErrorKind::BrokenPipe.into())
            }
        }
        let mut sink = RawSink::new(Closed, "pipe", RawFormat::Rgba);
        let big = crate::io::test_frame(Image::new(Size::new(1024, 1024).unwrap()), 0, None);
        assert!(matches!(sink.write_frame(&big), Err(Error::OutputClosed)));
    }
}
