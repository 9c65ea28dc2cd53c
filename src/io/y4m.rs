//! YUV4MPEG2, the self-describing raw video of `ffmpeg -f yuv4mpegpipe`: a header line
//! (`YUV4MPEG2 W640 H360 F25:1 Ip A1:1 C420jpeg`), then per frame a `FRAME` line and the Y, U
//! and V planes, 8 bits a sample.
//!
//! Colour: BT.601 limited range (Y 16-235, U and V 16-240), what ffmpeg uses by default when it
//! converts RGB for `yuv4mpegpipe`. Chroma: 4:2:0 (any siting: `420jpeg`, `420mpeg2`,
//! `420paldv`, `420`), 4:2:2, 4:4:4 and `mono`. Subsampled chroma is upsampled with the
//! 3/4-1/4 triangle filter (libjpeg's "fancy upsampling"): nearest-neighbour chroma left
//! visible 2-px steps along coloured edges, which the saliency map then took for edges.
//!
//! Output is 4:2:0 (`C420jpeg`, the layout every consumer takes), chroma as the mean of each
//! 2x2 block.

use super::pipe::{read_full, write_error};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::limits::Limits;
use crate::retarget::{Frame, Retargeted};
use crate::stream::{FrameSink, FrameSource};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::PathBuf;

/// A frame rate as a fraction, frames per second = `num / den`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct FrameRate {
    pub num: u32,
    pub den: u32,
}

impl FrameRate {
    /// `num / den`, reduced; `None` if either is 0.
    pub fn new(num: u32, den: u32) -> Option<FrameRate> {
        if num == 0 || den == 0 {
            return None;
        }
        let g = gcd(num, den);
        Some(FrameRate {
            num: num / g,
            den: den / g,
        })
    }

    /// From frames per second: whole numbers exactly, NTSC rates (29.97...) as `N000:1001`,
    /// anything else to a thousandth. `None` unless 0.001 to 1000.
    pub fn from_fps(fps: f64) -> Option<FrameRate> {
        if !(0.001..=1000.0).contains(&fps) {
            return None;
        }
        if (fps - fps.round()).abs() < 1e-9 {
            return FrameRate::new(fps.round() as u32, 1);
        }
        let ntsc = fps * 1001.0 / 1000.0;
        if (ntsc - ntsc.round()).abs() < 1e-3 {
            return FrameRate::new(ntsc.round() as u32 * 1000, 1001);
        }
        FrameRate::new((fps * 1000.0).round() as u32, 1000)
    }

    /// The rate at which each frame lasts `ms` milliseconds.
    pub fn from_duration_ms(ms: u32) -> Option<FrameRate> {
        FrameRate::new(1000, ms)
    }

    pub fn fps(self) -> f64 {
        self.num as f64 / self.den as f64
    }

    /// How long one frame lasts, rounded to a millisecond.
    pub fn duration_ms(self) -> u32 {
        ((self.den as u64 * 1000 + self.num as u64 / 2) / self.num as u64) as u32
    }
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Chroma layouts of 8-bit YUV4MPEG2.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Chroma {
    C420,
    C422,
    C444,
    Mono,
}

impl Chroma {
    /// Horizontal and vertical subsampling.
    fn factors(self) -> (usize, usize) {
        match self {
            Chroma::C420 => (2, 2),
            Chroma::C422 => (2, 1),
            Chroma::C444 | Chroma::Mono => (1, 1),
        }
    }
}

/// The longest header line accepted (ffmpeg writes under 100 bytes).
const MAX_LINE: u64 = 4096;

/// Frames from a YUV4MPEG2 stream.
pub struct Y4mSource<R> {
    reader: BufReader<R>,
    name: PathBuf,
    size: Size,
    chroma: Chroma,
    rate: Option<FrameRate>,
    next_index: u64,
    buf: Vec<u8>,
    line: Vec<u8>,
    ended: bool,
    limits: Limits,
}

impl<R: Read + Send> Y4mSource<R> {
    /// Reads and checks the stream header within the default [`Limits`]; `name` names the
    /// stream in errors.
    pub fn new(reader: R, name: impl Into<PathBuf>) -> Result<Self, Error> {
        Y4mSource::with_limits(reader, name, &Limits::default())
    }

    /// Reads and checks the stream header, its frame size against `limits` (frames are
    /// counted against them as they are read); `name` names the stream in errors.
    pub fn with_limits(
        reader: R,
        name: impl Into<PathBuf>,
        limits: &Limits,
    ) -> Result<Self, Error> {
        let name = name.into();
        let mut reader = BufReader::with_capacity(1 << 16, reader);
        let mut line = Vec::new();
        (&mut reader)
            .take(MAX_LINE)
            .read_until(b'\n', &mut line)
            .map_err(|e| Error::io(&name, e))?;
        if !line.starts_with(b"YUV4MPEG2") {
            return Err(Error::decode(&name, "not a YUV4MPEG2 stream"));
        }
        if line.last() != Some(&b'\n') {
            return Err(Error::decode(
                &name,
                "truncated YUV4MPEG2 header: the stream ends before its first line does",
            ));
        }
        // Parsed as bytes: a parameter's tag is one byte and its value runs to the next space,
        // whatever bytes it holds (an `X` comment may hold anything). Tokens of a lossily
        // decoded string were once split after their first byte, which panicked when that
        // byte began a multi-byte character (found by fuzzing).
        let header = &line[9..line.len() - 1];
        let (mut w, mut h, mut chroma, mut rate) = (None, None, Chroma::C420, None);
        for token in header.split(|b| b.is_ascii_whitespace()) {
            let Some((&tag, value)) = token.split_first() else {
                continue;
            };
            let text = std::str::from_utf8(value).ok();
            match tag {
                b'W' => w = text.and_then(|v| v.parse::<u32>().ok()),
                b'H' => h = text.and_then(|v| v.parse::<u32>().ok()),
                b'F' => {
                    rate = text
                        .and_then(|v| v.split_once(':'))
                        .and_then(|(n, d)| FrameRate::new(n.parse().ok()?, d.parse().ok()?))
                }
                b'C' => {
                    chroma = match value {
                        b"420jpeg" | b"420mpeg2" | b"420paldv" | b"420" => Chroma::C420,
                        b"422" => Chroma::C422,
                        b"444" => Chroma::C444,
                        b"mono" => Chroma::Mono,
                        other => {
                            return Err(Error::decode(
                                &name,
                                format!(
                                    "unsupported YUV4MPEG2 colour space C{}: 8-bit 420, \
                                     422, 444 or mono only (ffmpeg: -pix_fmt yuv420p)",
                                    String::from_utf8_lossy(other).escape_debug()
                                ),
                            ))
                        }
                    }
                }
                _ => {} // I (interlacing), A (pixel aspect), X (comments): not needed.
            }
        }
        let (Some(w), Some(h)) = (w, h) else {
            return Err(Error::decode(
                &name,
                "YUV4MPEG2 header lacks a valid width (W) or height (H)",
            ));
        };
        let size = limits.check_size(&name, "YUV4MPEG2", w as u64, h as u64)?;
        Ok(Y4mSource {
            reader,
            name,
            size,
            chroma,
            rate,
            next_index: 0,
            buf: Vec::new(),
            line,
            ended: false,
            limits: limits.clone(),
        })
    }

    /// The frame size from the header.
    pub fn size(&self) -> Size {
        self.size
    }

    /// The frame rate from the header (`F`), if given.
    pub fn frame_rate(&self) -> Option<FrameRate> {
        self.rate
    }

    pub fn chroma(&self) -> Chroma {
        self.chroma
    }

    fn plane_bytes(&self) -> (usize, usize) {
        let (w, h) = (self.size.width as usize, self.size.height as usize);
        let (sx, sy) = self.chroma.factors();
        let chroma = match self.chroma {
            Chroma::Mono => 0,
            _ => w.div_ceil(sx) * h.div_ceil(sy),
        };
        (w * h, chroma)
    }

    fn truncated(&mut self, expected: usize, got: usize) -> Error {
        self.ended = true;
        Error::TruncatedFrame {
            path: self.name.clone(),
            frame_index: self.next_index,
            expected,
            got,
        }
    }
}

impl<R: Read + Send> FrameSource for Y4mSource<R> {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        if self.ended {
            return Ok(None);
        }
        let (luma, chroma) = self.plane_bytes();
        let total = luma + 2 * chroma;
        self.line.clear();
        (&mut self.reader)
            .take(MAX_LINE)
            .read_until(b'\n', &mut self.line)
            .map_err(|e| Error::io(&self.name, e))?;
        if self.line.is_empty() {
            self.ended = true;
            return Ok(None);
        }
        if let Err(e) = self.limits.check_frame_index(&self.name, self.next_index) {
            self.ended = true;
            return Err(e);
        }
        if !self.line.starts_with(b"FRAME") || !matches!(self.line.get(5), Some(b' ' | b'\n')) {
            self.ended = true;
            return Err(Error::decode(
                &self.name,
                format!(
                    "frame {}: expected a FRAME header in the YUV4MPEG2 stream",
                    self.next_index
                ),
            ));
        }
        if self.line.last() != Some(&b'\n') {
            return Err(self.truncated(total, 0));
        }
        self.buf.resize(total, 0);
        let got =
            read_full(&mut self.reader, &mut self.buf).map_err(|e| Error::io(&self.name, e))?;
        if got < total {
            return Err(self.truncated(total, got));
        }
        let (y, uv) = self.buf.split_at(luma);
        let (u, v) = uv.split_at(chroma);
        let image = yuv_to_rgba(self.size, self.chroma, y, u, v);
        let mut frame = Frame::new(image, self.next_index);
        frame.duration_ms = self.rate.map(FrameRate::duration_ms);
        self.next_index += 1;
        Ok(Some(frame))
    }
}

/// BT.601 limited range to RGB, 16.16 fixed point.
#[inline]
fn to_rgb(y: i32, u: i32, v: i32) -> [u8; 4] {
    let c = 76309 * (y - 16) + 32768;
    let (d, e) = (u - 128, v - 128);
    let clamp = |x: i32| (x >> 16).clamp(0, 255) as u8;
    [
        clamp(c + 104597 * e),
        clamp(c - 25675 * d - 53279 * e),
        clamp(c + 132201 * d),
        255,
    ]
}

/// Converts planes to RGBA; chroma upsampled with the 3/4-1/4 triangle filter.
fn yuv_to_rgba(size: Size, chroma: Chroma, y: &[u8], u: &[u8], v: &[u8]) -> Image {
    let (w, h) = (size.width as usize, size.height as usize);
    let (sx, sy) = chroma.factors();
    let (cw, ch) = (w.div_ceil(sx), h.div_ceil(sy));
    // Sized first and written row by row: `extend` from a mapped iterator went pixel by pixel.
    let mut pixels = vec![[0u8; 4]; w * h];
    // Chroma of one output row, scaled by 16.
    let (mut ur, mut vr) = (vec![0u16; w], vec![0u16; w]);
    let (mut uv_col_u, mut uv_col_v) = (vec![0u16; cw], vec![0u16; cw]);
    for row in 0..h {
        let yrow = &y[row * w..(row + 1) * w];
        let prow = &mut pixels[row * w..(row + 1) * w];
        if chroma == Chroma::Mono {
            for (o, &l) in prow.iter_mut().zip(yrow) {
                *o = to_rgb(l as i32, 128, 128);
            }
            continue;
        }
        // Vertical pass (x4).
        let (a, b) = if sy == 2 {
            let a = row / 2;
            let b = if row % 2 == 0 {
                a.saturating_sub(1)
            } else {
                (a + 1).min(ch - 1)
            };
            (a, b)
        } else {
            (row, row)
        };
        for (plane, col) in [(u, &mut uv_col_u), (v, &mut uv_col_v)] {
            let (pa, pb) = (&plane[a * cw..(a + 1) * cw], &plane[b * cw..(b + 1) * cw]);
            for ((c, &x), &z) in col.iter_mut().zip(pa).zip(pb) {
                *c = 3 * x as u16 + z as u16;
            }
        }
        // Horizontal pass (x4 again).
        for (col, out) in [(&uv_col_u, &mut ur), (&uv_col_v, &mut vr)] {
            if sx == 2 {
                for (x, o) in out.iter_mut().enumerate() {
                    let c = x / 2;
                    let n = if x % 2 == 0 {
                        c.saturating_sub(1)
                    } else {
                        (c + 1).min(cw - 1)
                    };
                    *o = 3 * col[c] + col[n];
                }
            } else {
                for (o, &c) in out.iter_mut().zip(col.iter()) {
                    *o = 4 * c;
                }
            }
        }
        for (o, ((&l, &cu), &cv)) in prow.iter_mut().zip(yrow.iter().zip(&ur).zip(&vr)) {
            *o = to_rgb(l as i32, ((cu + 8) >> 4) as i32, ((cv + 8) >> 4) as i32);
        }
    }
    Image::from_pixels(size, pixels).unwrap_or_else(|| Image::new(size))
}

/// BT.601 limited range from RGB: (Y, U, V).
#[inline]
fn to_yuv(p: [u8; 4]) -> (u8, i32, i32) {
    let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
    let y = ((66 * r + 129 * g + 25 * b + 128) >> 8) + 16;
    let u = (-38 * r - 74 * g + 112 * b + 128) >> 8;
    let v = (112 * r - 94 * g - 18 * b + 128) >> 8;
    (y as u8, u, v)
}

/// Writes frames as YUV4MPEG2 4:2:0. The header is written with the first frame: its size,
/// and the rate given to [`Y4mSink::new`] or else the first frame's duration, else 25 fps.
pub struct Y4mSink<W: Write + Send> {
    writer: std::io::BufWriter<W>,
    name: PathBuf,
    rate: Option<FrameRate>,
    size: Option<Size>,
    buf: Vec<u8>,
}

impl<W: Write + Send> Y4mSink<W> {
    pub fn new(writer: W, name: impl Into<PathBuf>, rate: Option<FrameRate>) -> Self {
        Y4mSink {
            writer: std::io::BufWriter::with_capacity(1 << 20, writer),
            name: name.into(),
            rate,
            size: None,
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

impl<W: Write + Send> FrameSink for Y4mSink<W> {
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), Error> {
        let img = &frame.image;
        let size = img.size();
        match self.size {
            None => {
                let rate = self
                    .rate
                    .or_else(|| frame.duration_ms.and_then(FrameRate::from_duration_ms))
                    .unwrap_or(FrameRate { num: 25, den: 1 });
                let header = format!(
                    "YUV4MPEG2 W{} H{} F{}:{} Ip A1:1 C420jpeg XYSCSS=420JPEG\n",
                    size.width, size.height, rate.num, rate.den
                );
                self.writer
                    .write_all(header.as_bytes())
                    .map_err(|e| write_error(&self.name, e))?;
                self.size = Some(size);
            }
            Some(s) if s != size => {
                return Err(Error::FrameSizeMismatch {
                    frame_index: frame.frame_index,
                    expected: s,
                    got: size,
                })
            }
            Some(_) => {}
        }
        let (w, h) = (size.width as usize, size.height as usize);
        let (cw, ch) = (w.div_ceil(2), h.div_ceil(2));
        self.buf.clear();
        self.buf.extend_from_slice(b"FRAME\n");
        let y0 = self.buf.len();
        self.buf.resize(y0 + w * h + 2 * cw * ch, 0);
        let (yp, uv) = self.buf[y0..].split_at_mut(w * h);
        let (up, vp) = uv.split_at_mut(cw * ch);
        let px = img.pixels();
        // Luma in one flat loop (vectors), then chroma per 2×2 block: a whole block sums four
        // samples and rounds by a shift; a block cut by an odd edge averages what it has.
        for (o, &p) in yp.iter_mut().zip(px) {
            *o = to_yuv(p).0;
        }
        let (mut su, mut sv, mut n) = (vec![0i32; cw], vec![0i32; cw], vec![0i32; cw]);
        for cy in 0..ch {
            let rows = (2 * cy..(2 * cy + 2).min(h)).map(|yy| &px[yy * w..][..w]);
            let (urow, vrow) = (&mut up[cy * cw..][..cw], &mut vp[cy * cw..][..cw]);
            for sums in [&mut su, &mut sv, &mut n] {
                sums.fill(0);
            }
            for row in rows {
                for (x, &p) in row.iter().enumerate() {
                    let (_, u, v) = to_yuv(p);
                    su[x / 2] += u;
                    sv[x / 2] += v;
                    n[x / 2] += 1;
                }
            }
            for cx in 0..cw {
                let n = n[cx];
                let mean = |s: i32| match n {
                    4 => (s + 2) >> 2,
                    _ => (s + n / 2).div_euclid(n),
                };
                urow[cx] = (128 + mean(su[cx])) as u8;
                vrow[cx] = (128 + mean(sv[cx])) as u8;
            }
        }
        self.writer
            .write_all(&self.buf)
            .map_err(|e| write_error(&self.name, e))
    }

    fn finish(&mut self) -> Result<(), Error> {
        self.writer.flush().map_err(|e| write_error(&self.name, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_all(bytes: &[u8]) -> (Vec<Frame>, Option<Error>) {
        let mut src = match Y4mSource::new(bytes, "test") {
            Ok(s) => s,
            Err(e) => return (Vec::new(), Some(e)),
        };
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
    fn rates() {
        assert_eq!(FrameRate::from_fps(25.0), FrameRate::new(25, 1));
        assert_eq!(FrameRate::from_fps(29.97), FrameRate::new(30000, 1001));
        assert_eq!(FrameRate::from_fps(12.5), FrameRate::new(25, 2));
        assert_eq!(FrameRate::from_duration_ms(40), FrameRate::new(25, 1));
        assert_eq!(FrameRate::new(30000, 1001).unwrap().duration_ms(), 33);
        assert_eq!(FrameRate::from_fps(0.0), None);
    }

    #[test]
    fn colours_round_trip_through_420() {
        // Flat 4x4 blocks of colour survive RGB -> Y4M 4:2:0 -> RGB within a few levels.
        let colours = [
            [255, 0, 0, 255],
            [0, 128, 255, 255],
            [20, 20, 20, 255],
            [250, 250, 240, 255],
        ];
        let size = Size::new(8, 8).unwrap();
        let mut img = Image::new(size);
        for y in 0..8 {
            for x in 0..8 {
                img.set(x, y, colours[((y / 4) * 2 + x / 4) as usize]);
            }
        }
        let mut sink = Y4mSink::new(Vec::new(), "mem", FrameRate::new(30, 1));
        for i in 0..3 {
            sink.write_frame(&crate::io::test_frame(img.clone(), i, None))
                .unwrap();
        }
        sink.finish().unwrap();
        let bytes = sink.into_inner().unwrap();
        assert!(bytes.starts_with(b"YUV4MPEG2 W8 H8 F30:1 "));
        let (frames, err) = read_all(&bytes);
        assert!(err.is_none(), "{err:?}");
        assert_eq!(frames.len(), 3);
        for (i, f) in frames.iter().enumerate() {
            assert_eq!(f.frame_index, i as u64);
            assert_eq!(f.duration_ms, Some(33));
            // Block interiors (away from the chroma filter's reach).
            for (x, y, c) in [(1, 1, 0), (6, 1, 1), (1, 6, 2), (6, 6, 3)] {
                let got = f.image.get(x, y);
                for k in 0..3 {
                    assert!(
                        (got[k] as i32 - colours[c][k] as i32).abs() <= 3,
                        "pixel {x},{y}: {got:?} vs {:?}",
                        colours[c]
                    );
                }
            }
        }
    }

    #[test]
    fn c444_and_frame_params_and_bad_input() {
        let mut bytes = b"YUV4MPEG2 W2 H1 F25:1 C444 XCOLORRANGE=LIMITED\n".to_vec();
        for i in 0..4u8 {
            bytes.extend_from_slice(b"FRAME Ixyz\n");
            bytes.extend_from_slice(&[16 + i, 235, 128, 128, 128, 128]);
        }
        let (frames, err) = read_all(&bytes);
        assert!(err.is_none());
        assert_eq!(frames.len(), 4);
        assert_eq!(frames[0].image.get(0, 0), [0, 0, 0, 255]);
        assert_eq!(frames[0].image.get(1, 0), [255, 255, 255, 255]);
        assert_eq!(frames[0].duration_ms, Some(40));

        let mut short = bytes.clone();
        short.truncate(short.len() - 2);
        let (frames, err) = read_all(&short);
        assert_eq!(frames.len(), 3);
        assert!(matches!(
            err,
            Some(Error::TruncatedFrame {
                frame_index: 3,
                expected: 6,
                got: 4,
                ..
            })
        ));

        let (_, err) = read_all(b"YUV4MPEG2 W2 H1 C420p10\n");
        assert!(err.unwrap().to_string().contains("C420p10"));
        let (_, err) = read_all(b"YUV4MPEG2 H1 C444\n");
        assert!(err.unwrap().to_string().contains("width"));
        let (_, err) = read_all(b"YUV4MPEG2 W2 H1\nJUNK\n");
        assert!(err.unwrap().to_string().contains("FRAME"));
        let (_, err) = read_all(b"YUV4MPEG2 W0 H1\n");
        assert!(err.unwrap().to_string().contains("out of range"));
    }
}
