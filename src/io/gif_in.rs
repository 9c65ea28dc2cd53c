//! Animated GIF in: every frame composited onto the logical screen as a browser shows it.
//!
//! A GIF frame is a rectangle at an offset on the canvas; transparent pixels let the canvas
//! show through. After a frame is shown its disposal method says what happens to its
//! rectangle: `Keep` (and `Any`) leave it, `Background` clears it to transparent (what
//! browsers do; the background colour index is ignored, as they ignore it), `Previous`
//! restores what was there before the frame was drawn. Delays (in 10 ms units) become
//! [`Frame::duration_ms`]; the NETSCAPE loop count becomes [`FrameSource::repeat`].
//!
//! [`Limits`] are checked before allocating: the logical screen when the header is read, each
//! frame's rectangle before its pixels are decompressed (a 20-byte frame may declare
//! 65535x65535), and for a file the number of frames, by walking its blocks first.

use crate::error::Error;
use crate::image::{Image, Size, MAX_SIDE};
use crate::limits::{human_bytes, Limits};
use crate::retarget::Frame;
use crate::stream::{FrameSource, Repeat};
use gif::{ColorOutput, DecodeOptions, DisposalMethod, MemoryLimit};
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};

/// Most bytes the `gif` decoder may allocate for what it keeps itself (an ICC profile, XMP)
/// when no limit says otherwise: 512 MiB.
const MEMORY_LIMIT: u64 = 512 << 20;

/// What the `gif` decoder may allocate itself (RGBA): four bytes per allowed pixel, within
/// the memory budget. Frame pixels go into our own buffer, checked by [`check_frame_rect`].
fn memory_limit(limits: &Limits) -> MemoryLimit {
    let by_pixels = limits
        .max_pixels
        .map_or(MEMORY_LIMIT, |p| p.saturating_mul(4));
    let bytes = limits.memory_budget.map_or(by_pixels, |b| b.min(by_pixels));
    match bytes.try_into() {
        Ok(limit) => MemoryLimit::Bytes(limit),
        Err(_) => MemoryLimit::Unlimited,
    }
}

/// Checks a frame's rectangle before its RGBA buffer is allocated. The rectangle is not
/// bounded by the canvas (16 bits a side: a 20-byte frame may declare 65535x65535, 16 GiB),
/// so it is held to [`Limits::max_pixels`], to the largest canvas when that is off, and to
/// the memory budget.
fn check_frame_rect(limits: &Limits, name: &Path, index: u64, w: u16, h: u16) -> Result<(), Error> {
    let (w, h) = (w as u64, h as u64);
    let what = format!("frame {index}");
    limits.check_pixels(name, &what, w, h)?;
    let largest = (MAX_SIDE as u64).pow(2);
    if w * h > largest {
        return Err(Error::decode(
            name,
            format!(
                "corrupt GIF: {what} declares {w}x{h} px, more than the largest canvas \
                 ({MAX_SIDE}x{MAX_SIDE})"
            ),
        ));
    }
    match limits.memory_budget {
        Some(budget) if w * h * 4 > budget => Err(Error::LimitExceeded {
            path: name.to_path_buf(),
            limit: crate::Limit::Memory,
            needed: None,
            message: format!(
                "{what} declares {w}x{h} px, {} to decode, above the memory limit of {}",
                human_bytes(w * h * 4),
                human_bytes(budget)
            ),
        }),
        _ => Ok(()),
    }
}

/// A rectangle on the canvas, clipped to it.
#[derive(Copy, Clone, Debug)]
struct Rect {
    x: usize,
    y: usize,
    w: usize,
    h: usize,
}

/// Frames of an animated GIF.
pub struct GifSource<R: Read> {
    decoder: gif::Decoder<BufReader<R>>,
    name: PathBuf,
    size: Size,
    canvas: Vec<[u8; 4]>,
    /// What to do before drawing the next frame: the last frame's disposal and rectangle, and
    /// for `Previous` the pixels it covered before it was drawn.
    dispose: Option<(DisposalMethod, Rect, Vec<[u8; 4]>)>,
    next_index: u64,
    total: Option<u64>,
    repeat: Repeat,
    ended: bool,
    limits: Limits,
    /// The current frame's pixels, reused.
    buffer: Vec<u8>,
}

impl GifSource<std::fs::File> {
    /// Opens a GIF file within the default [`Limits`]; see [`GifSource::open_with`].
    pub fn open(path: &Path) -> Result<Self, Error> {
        GifSource::open_with(path, &Limits::default())
    }

    /// Opens a GIF file. Its frames are counted first by walking the file's blocks without
    /// decompressing them, so [`FrameSource::len_hint`] is known and a file with more than
    /// [`Limits::max_frames`] is refused before any frame is decoded.
    pub fn open_with(path: &Path, limits: &Limits) -> Result<Self, Error> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let mut source = GifSource::with_limits(file, path, limits)?;
        let counted = std::fs::File::open(path)
            .ok()
            .and_then(|f| count_frames(f, limits.max_frames));
        source.total = checked_count(counted, path, limits)?;
        Ok(source)
    }
}

impl GifSource<std::io::Cursor<Vec<u8>>> {
    /// A GIF file held in memory (read from a pipe), its frames counted first as
    /// [`GifSource::open_with`] counts them.
    pub fn from_bytes(bytes: Vec<u8>, name: &Path, limits: &Limits) -> Result<Self, Error> {
        let counted = count_frames(&bytes[..], limits.max_frames);
        let mut source = GifSource::with_limits(std::io::Cursor::new(bytes), name, limits)?;
        source.total = checked_count(counted, name, limits)?;
        Ok(source)
    }
}

/// The frame count, checked against `limits`.
fn checked_count(
    counted: Option<(u64, bool)>,
    name: &Path,
    limits: &Limits,
) -> Result<Option<u64>, Error> {
    match counted {
        Some((n, more)) => {
            limits.check_frame_count(name, n, more)?;
            Ok(Some(n))
        }
        None => Ok(None),
    }
}

/// Counts frames without decoding them, stopping past `max`: the count and whether more
/// follow. `None` if the file cannot be walked to its end (the decoding pass then reports what
/// is wrong, at the frame where it is).
pub(crate) fn count_frames<R: Read>(file: R, max: Option<u64>) -> Option<(u64, bool)> {
    let mut options = DecodeOptions::new();
    options.skip_frame_decoding(true);
    options.allow_unknown_blocks(true);
    options.set_memory_limit(MemoryLimit::Bytes(MEMORY_LIMIT.try_into().ok()?));
    let mut d = options.read_info(BufReader::new(file)).ok()?;
    let mut n = 0;
    while d.read_next_frame().ok()?.is_some() {
        if max.is_some_and(|m| n >= m) {
            return Some((n, true));
        }
        n += 1;
    }
    Some((n, false))
}

impl<R: Read + Send> GifSource<R> {
    /// Reads the GIF header from `reader` within the default [`Limits`]; `name` names it in
    /// errors.
    pub fn new(reader: R, name: impl AsRef<Path>) -> Result<Self, Error> {
        GifSource::with_limits(reader, name, &Limits::default())
    }

    /// Reads the GIF header from `reader`; `name` names it in errors. The logical screen is
    /// checked against `limits` before the canvas is allocated; frames are counted as they
    /// are read.
    pub fn with_limits(reader: R, name: impl AsRef<Path>, limits: &Limits) -> Result<Self, Error> {
        let name = name.as_ref().to_path_buf();
        let mut options = DecodeOptions::new();
        options.set_color_output(ColorOutput::RGBA);
        // Extension blocks of a type the decoder does not know (an application's own) are
        // skipped, as browsers skip them.
        options.allow_unknown_blocks(true);
        options.set_memory_limit(memory_limit(limits));
        let decoder = options
            .read_info(BufReader::new(reader))
            .map_err(|e| describe(&name, None, e))?;
        let (w, h) = (decoder.width() as u64, decoder.height() as u64);
        let size = limits.check_size(&name, "GIF", w, h)?;
        let repeat = match decoder.repeat() {
            gif::Repeat::Infinite => Repeat::Infinite,
            gif::Repeat::Finite(n) => Repeat::Times(n),
        };
        Ok(GifSource {
            decoder,
            name,
            size,
            canvas: vec![[0; 4]; size.area()],
            dispose: None,
            next_index: 0,
            total: None,
            repeat,
            ended: false,
            limits: limits.clone(),
            buffer: Vec::new(),
        })
    }

    /// The logical screen size: the size of every frame.
    pub fn size(&self) -> Size {
        self.size
    }

    fn rows(&mut self, r: Rect) -> impl Iterator<Item = &mut [[u8; 4]]> {
        let w = self.size.width as usize;
        self.canvas
            .chunks_exact_mut(w)
            .skip(r.y)
            .take(r.h)
            .map(move |row| &mut row[r.x..r.x + r.w])
    }
}

impl<R: Read + Send> FrameSource for GifSource<R> {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        if self.ended {
            return Ok(None);
        }
        // Dispose of the previous frame.
        match self.dispose.take() {
            Some((DisposalMethod::Background, r, _)) => {
                for row in self.rows(r) {
                    row.fill([0; 4]);
                }
            }
            Some((DisposalMethod::Previous, r, saved)) => {
                for (row, old) in self.rows(r).zip(saved.chunks_exact(r.w.max(1))) {
                    row.copy_from_slice(old);
                }
            }
            _ => {}
        }
        let index = self.next_index;
        let fail = |s: &mut Self, e: Error| {
            s.ended = true;
            Err(e)
        };
        // The frame's header first: its rectangle is checked before its pixels are read.
        let (left, top, fw, fh, delay, dispose) = match self.decoder.next_frame_info() {
            Ok(Some(f)) => (f.left, f.top, f.width, f.height, f.delay, f.dispose),
            Ok(None) => {
                self.ended = true;
                if index == 0 {
                    return Err(Error::NoFrames(self.name.clone()));
                }
                return Ok(None);
            }
            Err(e) => return fail(self, describe(&self.name, Some(index), e)),
        };
        if let Err(e) = self.limits.check_frame_index(&self.name, index) {
            return fail(self, e);
        }
        if let Err(e) = check_frame_rect(&self.limits, &self.name, index, fw, fh) {
            return fail(self, e);
        }
        let (fw, fh) = (fw as usize, fh as usize);
        let mut buffer = std::mem::take(&mut self.buffer);
        buffer.clear();
        buffer.resize(fw * fh * 4, 0);
        if let Err(e) = self.decoder.read_into_buffer(&mut buffer) {
            return fail(self, describe(&self.name, Some(index), e));
        }
        let (sw, sh) = (self.size.width as usize, self.size.height as usize);
        let (fx, fy) = (left as usize, top as usize);
        let rect = Rect {
            x: fx.min(sw),
            y: fy.min(sh),
            w: (fx + fw).min(sw).saturating_sub(fx),
            h: (fy + fh).min(sh).saturating_sub(fy),
        };
        let saved = if dispose == DisposalMethod::Previous {
            self.rows(rect).flat_map(|r| r.to_vec()).collect()
        } else {
            Vec::new()
        };
        // Draw: opaque pixels replace the canvas, transparent ones let it show.
        for (dy, row) in self.rows(rect).enumerate() {
            let src = &buffer[dy * fw * 4..];
            for (dx, px) in row.iter_mut().enumerate() {
                let p = &src[dx * 4..dx * 4 + 4];
                if p[3] != 0 {
                    *px = [p[0], p[1], p[2], p[3]];
                }
            }
        }
        self.buffer = buffer;
        self.dispose = Some((dispose, rect, saved));
        let image = Image::from_pixels(self.size, self.canvas.clone()).ok_or_else(|| {
            Error::Internal(format!(
                "{}: frame {index}: the canvas does not fill the {} logical screen",
                self.name.display(),
                self.size
            ))
        })?;
        let mut out = Frame::new(image, index);
        out.duration_ms = Some(delay as u32 * 10);
        self.next_index += 1;
        Ok(Some(out))
    }

    fn len_hint(&self) -> Option<usize> {
        self.total
            .map(|t| t.saturating_sub(self.next_index) as usize)
    }

    fn repeat(&self) -> Option<Repeat> {
        Some(self.repeat)
    }
}

/// One line: which frame, truncated or corrupt.
fn describe(name: &Path, frame: Option<u64>, e: gif::DecodingError) -> Error {
    let at = frame.map_or_else(String::new, |i| format!(" in frame {i}"));
    let text = match &e {
        gif::DecodingError::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            return Error::decode(name, format!("truncated GIF: the file ends early{at}"))
        }
        gif::DecodingError::Io(io) => {
            return Error::io(name, std::io::Error::new(io.kind(), io.to_string()))
        }
        other => other.to_string(),
    };
    if text.contains("end of file") || text.contains("unexpected EOF") || text.contains("truncated")
    {
        Error::decode(name, format!("truncated GIF: the file ends early{at}"))
    } else {
        Error::decode(name, format!("corrupt GIF{at}: {text}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// left, top, width, height, indices, disposal, delay.
    type Spec<'a> = (u16, u16, u16, u16, &'a [u8], DisposalMethod, u16);

    /// A 4x3 GIF, palette black/red/green/blue, built frame by frame.
    fn gif(frames: &[Spec<'_>], repeat: gif::Repeat) -> Vec<u8> {
        let palette = [0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255];
        let mut out = Vec::new();
        {
            let mut enc = gif::Encoder::new(&mut out, 4, 3, &palette).unwrap();
            enc.set_repeat(repeat).unwrap();
            for &(left, top, width, height, px, dispose, delay) in frames {
                let frame = gif::Frame {
                    left,
                    top,
                    width,
                    height,
                    buffer: px.into(),
                    dispose,
                    delay,
                    transparent: Some(3),
                    ..Default::default()
                };
                enc.write_frame(&frame).unwrap();
            }
        }
        out
    }

    fn all(bytes: &[u8]) -> (GifSource<&[u8]>, Vec<Frame>) {
        let mut src = GifSource::new(bytes, "t.gif").unwrap();
        let mut v = Vec::new();
        while let Some(f) = src.next_frame().unwrap() {
            v.push(f);
        }
        (src, v)
    }

    const K: [u8; 4] = [0, 0, 0, 255];
    const R: [u8; 4] = [255, 0, 0, 255];
    const G: [u8; 4] = [0, 255, 0, 255];
    const T: [u8; 4] = [0, 0, 0, 0];

    #[test]
    fn disposal_methods_and_offsets() {
        let full = [0u8; 12]; // all black
        let bytes = gif(
            &[
                (0, 0, 4, 3, &full, DisposalMethod::Keep, 5),
                // 2x1 red at (1,1), then restored to black (Previous).
                (1, 1, 2, 1, &[1, 1], DisposalMethod::Previous, 7),
                // 1x1 green at (3,2) with a transparent pixel beside it (2,2): cleared after.
                (2, 2, 2, 1, &[3, 2], DisposalMethod::Background, 9),
                // Nothing drawn (fully transparent 1x1 at 0,0).
                (0, 0, 1, 1, &[3], DisposalMethod::Keep, 0),
            ],
            gif::Repeat::Finite(3),
        );
        let (src, f) = all(&bytes);
        assert_eq!(f.len(), 4);
        assert_eq!(src.repeat(), Some(Repeat::Times(3)));
        let idx: Vec<u64> = f.iter().map(|f| f.frame_index).collect();
        assert_eq!(idx, [0, 1, 2, 3]);
        let delays: Vec<_> = f.iter().map(|f| f.duration_ms).collect();
        assert_eq!(delays, [Some(50), Some(70), Some(90), Some(0)]);
        assert!(f[0].image.pixels().iter().all(|&p| p == K));
        assert_eq!(f[1].image.row(1), &[K, R, R, K]);
        assert_eq!(f[2].image.row(1), &[K, K, K, K], "Previous restored");
        assert_eq!(f[2].image.row(2), &[K, K, K, G]);
        assert_eq!(f[3].image.row(2), &[K, K, T, T], "Background cleared");
        assert_eq!(
            f[3].image.get(0, 0),
            K,
            "transparent pixel keeps the canvas"
        );
    }

    #[test]
    fn loop_count_infinite_and_none() {
        let full = [1u8; 12];
        let a = gif(
            &[(0, 0, 4, 3, &full, DisposalMethod::Keep, 2)],
            gif::Repeat::Infinite,
        );
        let (src, _) = all(&a);
        assert_eq!(src.repeat(), Some(Repeat::Infinite));
        let b = gif(
            &[(0, 0, 4, 3, &full, DisposalMethod::Keep, 2)],
            gif::Repeat::Finite(0),
        );
        let (src, f) = all(&b);
        assert_eq!(src.repeat(), Some(Repeat::Times(0)));
        assert_eq!(f.len(), 1);
    }

    #[test]
    fn frame_outside_the_screen_is_clipped() {
        let px = [2u8; 9];
        let (_, f) = all(&gif(
            &[(3, 2, 3, 3, &px, DisposalMethod::Keep, 1)],
            gif::Repeat::Infinite,
        ));
        assert_eq!(f[0].image.get(3, 2), G);
        assert_eq!(f[0].image.get(2, 2), T);
    }

    #[test]
    fn corrupt_frame_is_named() {
        let full = [1u8; 12];
        let mut bytes = gif(
            &[
                (0, 0, 4, 3, &full, DisposalMethod::Keep, 2),
                (0, 0, 4, 3, &full, DisposalMethod::Keep, 2),
            ],
            gif::Repeat::Infinite,
        );
        let cut = bytes.len() - 8;
        bytes.truncate(cut);
        let mut src = GifSource::new(&bytes[..], "anim.gif").unwrap();
        assert!(src.next_frame().unwrap().is_some());
        let e = src.next_frame().unwrap_err().to_string();
        assert!(e.contains("anim.gif") && e.contains("frame 1"), "{e}");
        assert!(src.next_frame().unwrap().is_none());
    }

    /// A GIF by hand: a `w`x`h` screen with a two-colour table, then `frames` frames each
    /// declaring the rectangle `fw`x`fh` but holding one pixel of LZW data.
    fn hostile(w: u16, h: u16, fw: u16, fh: u16, frames: usize) -> Vec<u8> {
        let mut b = b"GIF89a".to_vec();
        b.extend(w.to_le_bytes());
        b.extend(h.to_le_bytes());
        b.extend([0x80, 0, 0, 0, 0, 0, 255, 255, 255]);
        for _ in 0..frames {
            b.push(0x2c);
            b.extend([0, 0, 0, 0]);
            b.extend(fw.to_le_bytes());
            b.extend(fh.to_le_bytes());
            b.extend([0, 2, 2, 0x44, 0x01, 0]);
        }
        b.push(0x3b);
        b
    }

    #[test]
    fn a_huge_frame_rectangle_is_refused_before_its_buffer() {
        // The canvas is small; the frame claims 65535x65535 (16 GiB of RGBA).
        let bytes = hostile(4, 4, 65535, 65535, 1);
        let mut src = GifSource::new(&bytes[..], "h.gif").unwrap();
        let e = src.next_frame().unwrap_err();
        assert!(
            matches!(
                e,
                Error::LimitExceeded {
                    limit: crate::Limit::Pixels,
                    ..
                }
            ),
            "{e}"
        );
        // With every limit off, the largest canvas still bounds it.
        let mut src = GifSource::with_limits(&bytes[..], "h.gif", &Limits::unlimited()).unwrap();
        let e = src.next_frame().unwrap_err().to_string();
        assert!(
            e.contains("65535x65535") && e.contains("largest canvas"),
            "{e}"
        );
        // And a tight memory budget bounds a frame the pixel limit lets through.
        let bytes = hostile(4, 4, 4000, 4000, 1);
        let tight = Limits::default().with_memory_budget(Some(32 << 20));
        let mut src = GifSource::with_limits(&bytes[..], "h.gif", &tight).unwrap();
        let e = src.next_frame().unwrap_err();
        assert!(
            matches!(
                e,
                Error::LimitExceeded {
                    limit: crate::Limit::Memory,
                    ..
                }
            ),
            "{e}"
        );
        // The hand-built file itself is sound: a frame of its true size decodes.
        let (_, f) = all(&hostile(4, 4, 1, 1, 3));
        assert_eq!(f.len(), 3);
    }
}
