//! Concatenated PNG files, as `ffmpeg -f image2pipe -c:v png -` writes them.
//!
//! PNG has no length field for the whole file, so the reader walks its chunks (length, type,
//! data, CRC) up to `IEND` and decodes the bytes of that one picture; the next byte starts the
//! next PNG.

use super::pipe::{read_full, write_error};
use super::sniff::PNG_SIGNATURE;
use super::still::{decode_still_with, encode_still, OutputFormat};
use crate::error::Error;
use crate::limits::Limits;
use crate::retarget::{Frame, Retargeted};
use crate::stream::{FrameSink, FrameSource};
use std::io::{BufReader, Read, Write};
use std::path::PathBuf;

/// The largest single PNG accepted in a stream: 1 GiB, as for still inputs (or the memory
/// budget, if smaller).
const MAX_PNG_BYTES: usize = 1 << 30;

/// Frames from a stream of PNG files.
pub struct PngStreamSource<R> {
    reader: BufReader<R>,
    name: PathBuf,
    next_index: u64,
    buf: Vec<u8>,
    ended: bool,
    limits: Limits,
    max_bytes: usize,
}

impl<R: Read + Send> PngStreamSource<R> {
    /// PNGs from `reader` within the default [`Limits`]; `name` names it in errors.
    pub fn new(reader: R, name: impl Into<PathBuf>) -> Self {
        PngStreamSource::with_limits(reader, name, &Limits::default())
    }

    /// PNGs from `reader`; each is checked against `limits` from its header before it is
    /// decoded, and frames are counted against them as they are read.
    pub fn with_limits(reader: R, name: impl Into<PathBuf>, limits: &Limits) -> Self {
        let max_bytes = limits
            .decode_bytes()
            .map_or(MAX_PNG_BYTES, |b| (b.min(MAX_PNG_BYTES as u64)) as usize);
        PngStreamSource {
            reader: BufReader::with_capacity(1 << 16, reader),
            name: name.into(),
            next_index: 0,
            buf: Vec::new(),
            ended: false,
            limits: limits.clone(),
            max_bytes,
        }
    }

    fn fail(&mut self, message: String) -> Error {
        self.ended = true;
        Error::decode(&self.name, message)
    }

    /// Appends exactly `n` bytes to `buf`; false if the stream ended first. The buffer grows
    /// with the bytes that arrive, not with what a chunk header claims.
    fn take(&mut self, n: usize) -> Result<bool, Error> {
        let start = self.buf.len();
        if n <= 1 << 16 {
            self.buf.resize(start + n, 0);
            let got = read_full(&mut self.reader, &mut self.buf[start..])
                .map_err(|e| Error::io(&self.name, e))?;
            self.buf.truncate(start + got);
            return Ok(got == n);
        }
        let got = (&mut self.reader)
            .take(n as u64)
            .read_to_end(&mut self.buf)
            .map_err(|e| Error::io(&self.name, e))?;
        Ok(got == n)
    }
}

impl<R: Read + Send> FrameSource for PngStreamSource<R> {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        if self.ended {
            return Ok(None);
        }
        let i = self.next_index;
        self.buf.clear();
        if !self.take(8)? {
            if self.buf.is_empty() {
                self.ended = true;
                return Ok(None);
            }
            return Err(self.fail(format!(
                "PNG {i} of the stream is incomplete: the stream ends inside its signature"
            )));
        }
        if let Err(e) = self.limits.check_frame_index(&self.name, i) {
            self.ended = true;
            return Err(e);
        }
        if self.buf[..8] != PNG_SIGNATURE[..] {
            return Err(self.fail(format!(
                "frame {i}: not a PNG (each frame of a PNG stream must start with the PNG \
                 signature)"
            )));
        }
        loop {
            let at = self.buf.len();
            if !self.take(8)? {
                return Err(self.fail(format!(
                    "PNG {i} of the stream is incomplete: the stream ends before its IEND chunk"
                )));
            }
            let len = u32::from_be_bytes([
                self.buf[at],
                self.buf[at + 1],
                self.buf[at + 2],
                self.buf[at + 3],
            ]) as usize;
            let is_end = &self.buf[at + 4..at + 8] == b"IEND";
            if len > i32::MAX as usize || self.buf.len() + len + 4 > self.max_bytes {
                return Err(self.fail(format!(
                    "PNG {i} of the stream is corrupt or larger than {} (a chunk claims {len} \
                     bytes)",
                    crate::limits::human_bytes(self.max_bytes as u64)
                )));
            }
            if !self.take(len + 4)? {
                return Err(self.fail(format!(
                    "PNG {i} of the stream is incomplete: the stream ends inside a chunk"
                )));
            }
            if is_end {
                break;
            }
        }
        let label = PathBuf::from(format!("{} (PNG {i})", self.name.display()));
        let image = decode_still_with(&self.buf, &label, &self.limits)
            .inspect_err(|_| self.ended = true)?;
        self.next_index += 1;
        Ok(Some(Frame::new(image, i)))
    }
}

/// Writes each frame as a PNG file, one after the other.
pub struct PngStreamSink<W: Write + Send> {
    writer: std::io::BufWriter<W>,
    name: PathBuf,
}

impl<W: Write + Send> PngStreamSink<W> {
    pub fn new(writer: W, name: impl Into<PathBuf>) -> Self {
        PngStreamSink {
            writer: std::io::BufWriter::with_capacity(1 << 20, writer),
            name: name.into(),
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

impl<W: Write + Send> FrameSink for PngStreamSink<W> {
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), Error> {
        let bytes = encode_still(&frame.image, OutputFormat::Png)
            .map_err(|m| Error::decode(&self.name, format!("encoding failed: {m}")))?;
        self.writer
            .write_all(&bytes)
            .map_err(|e| write_error(&self.name, e))
    }

    fn finish(&mut self) -> Result<(), Error> {
        self.writer.flush().map_err(|e| write_error(&self.name, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Image, Size};

    fn stream_of(n: u8) -> Vec<u8> {
        let mut sink = PngStreamSink::new(Vec::new(), "mem");
        for i in 0..n {
            let img = Image::filled(Size::new(3 + i as u32, 2).unwrap(), [i, 2 * i, 3, 255]);
            sink.write_frame(&crate::io::test_frame(img, i as u64, None))
                .unwrap();
        }
        sink.finish().unwrap();
        sink.into_inner().unwrap()
    }

    fn read_all(bytes: &[u8]) -> (Vec<Frame>, Option<Error>) {
        let mut src = PngStreamSource::new(bytes, "stdin");
        let mut out = Vec::new();
        loop {
            match src.next_frame() {
                Ok(Some(f)) => out.push(f),
                Ok(None) => return (out, None),
                Err(e) => return (out, Some(e)),
            }
        }
    }

    #[test]
    fn splits_at_iend_in_order() {
        let (frames, err) = read_all(&stream_of(5));
        assert!(err.is_none(), "{err:?}");
        assert_eq!(frames.len(), 5);
        for (i, f) in frames.iter().enumerate() {
            assert_eq!(f.frame_index, i as u64);
            assert_eq!(f.image.width(), 3 + i as u32);
            assert_eq!(f.image.get(0, 0), [i as u8, 2 * i as u8, 3, 255]);
        }
    }

    #[test]
    fn cut_stream_and_garbage_are_named() {
        let bytes = stream_of(3);
        let (frames, err) = read_all(&bytes[..bytes.len() - 5]);
        assert_eq!(frames.len(), 2);
        let msg = err.unwrap().to_string();
        assert!(msg.contains("PNG 2") && msg.contains("incomplete"), "{msg}");

        let mut bad = stream_of(1);
        bad.extend_from_slice(b"hello, not a png");
        let (frames, err) = read_all(&bad);
        assert_eq!(frames.len(), 1);
        assert!(err.unwrap().to_string().contains("not a PNG"));
    }
}
