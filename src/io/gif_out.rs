//! Animated GIF out.
//!
//! - **Palette**: built from the first frame ([`super::quantize`]) and written as the global
//!   colour table. A later frame whose changed pixels the palette fits badly (mean residual
//!   above [`REBUILD_RESIDUAL`] over at least 1% of the frame) gets a new palette built from
//!   it, written as a local table and kept for the frames after it: the palette changes
//!   slowly, and only when the content does.
//! - **Changed rectangle**: each frame after the first is written as the bounding box of the
//!   pixels that differ from the previous frame; inside it, pixels unchanged since the last
//!   frame (or already showing the right colour) are transparent, so the viewer keeps them.
//!   Ordered dithering makes this exact: an unchanged pixel maps to the same index again.
//! - **Transparency** in the content (alpha < 128) is kept. A pixel that turns transparent
//!   needs the previous frame cleared (disposal `Background`), so each frame is held until
//!   the next one arrives and its disposal is decided then.
//! - **Timing**: each frame's delay is [`Retargeted::duration_ms`], or the `frame_rate` of
//!   [`GifOptions`] when given, else 100 ms; rounded to GIF's 10 ms units with the rounding
//!   error carried, so 30 fps comes out as 3, 3, 4, ... centiseconds.
//! - **Files** are written through a temporary file and renamed at [`FrameSink::finish`].

use super::atomic::AtomicFile;
use super::pipe::write_error;
use super::quantize::{build_palette, pack, Quantizer, MAX_COLORS};
use super::y4m::FrameRate;
use crate::error::Error;
use crate::image::{Image, Size};
use crate::retarget::Retargeted;
use crate::stream::{FrameSink, Repeat};
use gif::DisposalMethod;
use std::borrow::Cow;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Mean residual (weighted RGB units, about 2 per level) above which a frame's changed pixels
/// ask for a new palette.
pub const REBUILD_RESIDUAL: f64 = 10.0;

/// How a GIF is written.
#[derive(Clone, Debug)]
pub struct GifOptions {
    /// Loop count; [`Repeat::Infinite`] by default.
    pub repeat: Repeat,
    /// Overrides every frame's duration when set.
    pub frame_rate: Option<FrameRate>,
    /// Duration of frames that carry none, when `frame_rate` is not set: 100 ms.
    pub default_duration_ms: u32,
}

impl Default for GifOptions {
    fn default() -> Self {
        GifOptions {
            repeat: Repeat::Infinite,
            frame_rate: None,
            default_duration_ms: 100,
        }
    }
}

#[derive(Copy, Clone, Debug, PartialEq, Eq)]
struct Rect {
    x: usize,
    y: usize,
    w: usize,
    h: usize,
}

impl Rect {
    fn is_empty(&self) -> bool {
        self.w == 0 || self.h == 0
    }
    fn union(self, o: Rect) -> Rect {
        if self.is_empty() {
            return o;
        }
        if o.is_empty() {
            return self;
        }
        let (x0, y0) = (self.x.min(o.x), self.y.min(o.y));
        let x1 = (self.x + self.w).max(o.x + o.w);
        let y1 = (self.y + self.h).max(o.y + o.h);
        Rect {
            x: x0,
            y: y0,
            w: x1 - x0,
            h: y1 - y0,
        }
    }
}

/// Bounding box accumulator.
#[derive(Default)]
struct Bbox(Option<(usize, usize, usize, usize)>);
impl Bbox {
    fn add_span(&mut self, y: usize, x0: usize, x1: usize) {
        self.0 = Some(match self.0 {
            None => (x0, y, x1, y),
            Some((a, b, c, _)) => (a.min(x0), b, c.max(x1), y),
        });
    }
    fn rect(&self) -> Rect {
        match self.0 {
            None => Rect {
                x: 0,
                y: 0,
                w: 0,
                h: 0,
            },
            Some((x0, y0, x1, y1)) => Rect {
                x: x0,
                y: y0,
                w: x1 - x0 + 1,
                h: y1 - y0 + 1,
            },
        }
    }
}

/// A frame encoded but not written: its disposal depends on the next frame.
struct Pending {
    rect: Rect,
    indices: Vec<u8>,
    local_palette: Option<Vec<u8>>,
    transparent: u8,
    delay_cs: u16,
    dispose: DisposalMethod,
}

impl Pending {
    /// Grows the rectangle to cover `r`, new pixels transparent (they keep the canvas).
    fn extend(&mut self, r: Rect) {
        let n = self.rect.union(r);
        if n == self.rect {
            return;
        }
        let mut idx = vec![self.transparent; n.w * n.h];
        for y in 0..self.rect.h {
            let dst = (self.rect.y - n.y + y) * n.w + (self.rect.x - n.x);
            idx[dst..dst + self.rect.w]
                .copy_from_slice(&self.indices[y * self.rect.w..(y + 1) * self.rect.w]);
        }
        self.rect = n;
        self.indices = idx;
    }
}

/// Writes retargeted frames as an animated GIF into `W`.
pub struct GifSink<W: Write + Send> {
    writer: Option<W>,
    encoder: Option<gif::Encoder<W>>,
    name: PathBuf,
    options: GifOptions,
    commit: Option<fn(W) -> Result<(), Error>>,
    finished: Option<W>,
    size: Option<Size>,
    quant: Option<Quantizer>,
    palette_is_global: bool,
    prev_in: Vec<[u8; 4]>,
    shown: Vec<[u8; 4]>,
    pending: Option<Pending>,
    clock_ms: f64,
    frames: u64,
    palettes: u64,
}

impl GifSink<AtomicFile> {
    /// A GIF file at `path`, written through a temporary file beside it and renamed at
    /// [`FrameSink::finish`]; a run that fails before leaves no file (or the old one).
    pub fn create(path: &Path, options: GifOptions) -> Result<Self, Error> {
        let file = AtomicFile::create(path)?;
        let mut sink = GifSink::new(file, path, options);
        sink.commit = Some(AtomicFile::commit);
        Ok(sink)
    }
}

impl<W: Write + Send> GifSink<W> {
    /// A GIF written into `writer`; `name` names it in errors.
    pub fn new(writer: W, name: impl Into<PathBuf>, options: GifOptions) -> Self {
        GifSink {
            writer: Some(writer),
            encoder: None,
            name: name.into(),
            options,
            commit: None,
            finished: None,
            size: None,
            quant: None,
            palette_is_global: true,
            prev_in: Vec::new(),
            shown: Vec::new(),
            pending: None,
            clock_ms: 0.0,
            frames: 0,
            palettes: 0,
        }
    }

    /// The writer after [`FrameSink::finish`] (for sinks made with [`GifSink::new`]).
    pub fn into_inner(self) -> Option<W> {
        self.finished
    }

    /// How many palettes were built (1 + the number of palette updates).
    pub fn palettes_built(&self) -> u64 {
        self.palettes
    }

    fn encoding_error(&self, e: gif::EncodingError) -> Error {
        match e {
            gif::EncodingError::Io(io) => write_error(&self.name, io),
            other => Error::decode(&self.name, format!("GIF encoding failed: {other}")),
        }
    }

    fn write_pending(&mut self) -> Result<(), Error> {
        let Some(p) = self.pending.take() else {
            return Ok(());
        };
        let frame = gif::Frame {
            left: p.rect.x as u16,
            top: p.rect.y as u16,
            width: p.rect.w as u16,
            height: p.rect.h as u16,
            delay: p.delay_cs,
            dispose: p.dispose,
            transparent: Some(p.transparent),
            palette: p.local_palette,
            buffer: Cow::Owned(p.indices),
            ..Default::default()
        };
        let result = match self.encoder.as_mut() {
            Some(enc) => enc.write_frame(&frame),
            None => {
                return Err(Error::Internal(
                    "a GIF frame was pending with no encoder to write it".into(),
                ))
            }
        };
        result.map_err(|e| self.encoding_error(e))
    }

    /// Delay of the next frame in centiseconds, carrying the rounding error.
    fn delay_cs(&mut self, duration_ms: Option<u32>) -> u16 {
        let ms = match self.options.frame_rate {
            Some(r) => 1000.0 * r.den as f64 / r.num as f64,
            None => duration_ms.unwrap_or(self.options.default_duration_ms) as f64,
        };
        let start = (self.clock_ms / 10.0).round();
        self.clock_ms += ms;
        let end = (self.clock_ms / 10.0).round();
        (end - start).clamp(0.0, u16::MAX as f64) as u16
    }

    /// Indices for `rect` of `px` (T where the pixel is kept or transparent); returns the sum
    /// of residuals and the number of pixels quantized.
    fn map_rect(
        &mut self,
        px: &[[u8; 4]],
        width: usize,
        rect: Rect,
        first: bool,
        out: &mut Vec<u8>,
    ) -> (u64, u64) {
        let Some(q) = self.quant.as_mut() else {
            return (0, 0);
        };
        let t = q.transparent();
        out.clear();
        out.resize(rect.w * rect.h, t);
        let (mut residual, mut n) = (0u64, 0u64);
        let mut last: Option<(u32, super::quantize::Mix)> = None;
        for y in rect.y..rect.y + rect.h {
            let row = &px[y * width + rect.x..y * width + rect.x + rect.w];
            let prev = &self.prev_in[y * width + rect.x..y * width + rect.x + rect.w];
            let shown = &self.shown[y * width + rect.x..y * width + rect.x + rect.w];
            let dst = &mut out[(y - rect.y) * rect.w..(y - rect.y + 1) * rect.w];
            for (i, &p) in row.iter().enumerate() {
                if p[3] < 128 || (!first && p == prev[i] && shown[i][3] != 0) {
                    continue;
                }
                let c = pack(p);
                let m = match last {
                    Some((lc, m)) if lc == c => m,
                    _ => {
                        let m = q.mix(c);
                        last = Some((c, m));
                        m
                    }
                };
                dst[i] = m.at(rect.x + i, y);
                residual += m.residual() as u64;
                n += 1;
            }
        }
        (residual, n)
    }
}

/// The picture being added, as the steps of [`GifSink::add_frame`] read it.
struct Incoming<'a> {
    px: &'a [[u8; 4]],
    w: usize,
    h: usize,
    /// The first frame: written whole, with the global palette.
    first: bool,
}

impl<W: Write + Send> GifSink<W> {
    /// Adds one picture shown for `duration_ms` (or as [`GifOptions`] says). This is what
    /// [`FrameSink::write_frame`] does with a retargeted frame; it also writes plain pictures
    /// as an animation.
    pub fn add_frame(&mut self, img: &Image, duration_ms: Option<u32>) -> Result<(), Error> {
        let size = img.size();
        let first = self.size.is_none();
        if !first && self.encoder.is_none() {
            return Err(Error::OutOfOrder(format!(
                "{}: a frame added to a GIF already finished",
                self.name.display()
            )));
        }
        match self.size {
            None => self.start(img)?,
            Some(s) if s != size => {
                return Err(Error::FrameSizeMismatch {
                    frame_index: self.frames,
                    expected: s,
                    got: size,
                })
            }
            Some(_) => {}
        }
        let delay_cs = self.delay_cs(duration_ms);
        let f = Incoming {
            px: img.pixels(),
            w: size.width as usize,
            h: size.height as usize,
            first,
        };
        let rect = self.rect_to_redraw(&f);
        self.write_pending()?;
        let pending = self.encode(&f, rect, delay_cs)?;
        self.remember_input(&f);
        self.pending = Some(pending);
        self.frames += 1;
        Ok(())
    }

    /// Writes the header at the first frame: the GIF's size is that frame's, and its global
    /// palette is built from it. A size the format cannot hold is refused before the writer
    /// is used, so that a frame that fits can still start the file.
    fn start(&mut self, img: &Image) -> Result<(), Error> {
        let size = img.size();
        let (w, h) = (size.width as usize, size.height as usize);
        if w > u16::MAX as usize || h > u16::MAX as usize {
            return Err(Error::Unsupported {
                path: self.name.clone(),
                message: format!(
                    "{size} is too large for a GIF: its sides are at most {} px",
                    u16::MAX
                ),
            });
        }
        let quant = Quantizer::new(non_empty(build_palette(img.pixels(), MAX_COLORS)));
        self.palettes += 1;
        let writer = self.writer.take().ok_or_else(|| {
            Error::OutOfOrder(format!(
                "{}: a frame added after writing the GIF's header failed",
                self.name.display()
            ))
        })?;
        let mut enc = gif::Encoder::new(writer, w as u16, h as u16, &quant.gif_palette())
            .map_err(|e| self.encoding_error(e))?;
        let repeat = match self.options.repeat {
            Repeat::Infinite => gif::Repeat::Infinite,
            Repeat::Times(n) => gif::Repeat::Finite(n),
        };
        enc.set_repeat(repeat).map_err(|e| self.encoding_error(e))?;
        self.encoder = Some(enc);
        self.quant = Some(quant);
        self.size = Some(size);
        self.prev_in = vec![[0; 4]; w * h];
        self.shown = vec![[0; 4]; w * h];
        Ok(())
    }

    /// The rectangle this frame redraws: the whole first frame, then the bounding box of what
    /// changed. Pixels turning transparent over shown ones need the previous frame cleared
    /// (disposal `Background`), which also clears its rectangle: this frame then redraws
    /// that too.
    fn rect_to_redraw(&mut self, f: &Incoming) -> Rect {
        if f.first {
            return Rect {
                x: 0,
                y: 0,
                w: f.w,
                h: f.h,
            };
        }
        let (changed, clear) = self.changes(f);
        let mut rect = changed.rect();
        let clear = clear.rect();
        if !clear.is_empty() {
            if let Some(cleared) = self.clear_pending(clear, f.w) {
                rect = rect.union(cleared);
            }
        }
        rect
    }

    /// What changed since the last frame, and which of those pixels turn transparent over
    /// shown ones. Each row is compared whole first: most rows of a chart's frame are equal.
    fn changes(&self, f: &Incoming) -> (Bbox, Bbox) {
        let w = f.w;
        let (mut changed, mut clear) = (Bbox::default(), Bbox::default());
        for y in 0..f.h {
            let (a, b) = (&f.px[y * w..(y + 1) * w], &self.prev_in[y * w..(y + 1) * w]);
            if a == b {
                continue;
            }
            let x0 = a.iter().zip(b).position(|(p, q)| p != q).unwrap_or(0);
            let x1 = w
                - 1
                - a.iter()
                    .rev()
                    .zip(b.iter().rev())
                    .position(|(p, q)| p != q)
                    .unwrap_or(0);
            changed.add_span(y, x0, x1);
            let shown = &self.shown[y * w..(y + 1) * w];
            for x in x0..=x1 {
                if a[x][3] < 128 && shown[x][3] != 0 {
                    clear.add_span(y, x, x);
                }
            }
        }
        (changed, clear)
    }

    /// Makes the pending frame clear its rectangle, grown over `clear`, once shown; returns
    /// that rectangle, which the canvas no longer shows (`None`: no frame is pending).
    fn clear_pending(&mut self, clear: Rect, w: usize) -> Option<Rect> {
        let p = self.pending.as_mut()?;
        p.extend(clear);
        p.dispose = DisposalMethod::Background;
        let r = p.rect;
        for y in r.y..r.y + r.h {
            self.shown[y * w + r.x..y * w + r.x + r.w].fill([0; 4]);
        }
        Some(r)
    }

    /// The frame's indices over `rect`, held until the next frame decides its disposal. A
    /// frame with nothing to redraw is one transparent pixel: it still carries the delay.
    fn encode(&mut self, f: &Incoming, rect: Rect, delay_cs: u16) -> Result<Pending, Error> {
        let transparent = |s: &Self| s.quant.as_ref().map_or(0, |q| q.transparent());
        if rect.is_empty() {
            return Ok(Pending {
                rect: Rect {
                    x: 0,
                    y: 0,
                    w: 1,
                    h: 1,
                },
                indices: vec![transparent(self)],
                transparent: transparent(self),
                local_palette: None,
                delay_cs,
                dispose: DisposalMethod::Keep,
            });
        }
        let mut indices = Vec::new();
        let (residual, n) = self.map_rect(f.px, f.w, rect, f.first, &mut indices);
        if palette_is_stale(f, residual, n) {
            self.quant = Some(Quantizer::new(non_empty(build_palette(f.px, MAX_COLORS))));
            self.palettes += 1;
            self.palette_is_global = false;
            self.map_rect(f.px, f.w, rect, f.first, &mut indices);
        }
        let q = self
            .quant
            .as_ref()
            .ok_or_else(|| Error::Internal("a GIF frame after the first has no palette".into()))?;
        keep_shown(q, &mut self.shown, f.w, rect, &mut indices);
        let local_palette = (!self.palette_is_global).then(|| q.gif_palette());
        Ok(Pending {
            rect,
            indices,
            transparent: transparent(self),
            local_palette,
            delay_cs,
            dispose: DisposalMethod::Keep,
        })
    }

    /// Keeps this frame's input to compare the next one with (rows that differ copied).
    fn remember_input(&mut self, f: &Incoming) {
        for y in 0..f.h {
            let r = y * f.w..(y + 1) * f.w;
            if self.prev_in[r.clone()] != f.px[r.clone()] {
                self.prev_in[r.clone()].copy_from_slice(&f.px[r]);
            }
        }
    }
}

/// Whether the palette fits this frame's changed pixels so badly (mean residual above
/// [`REBUILD_RESIDUAL`] over at least 1% of the frame) that a new one is built from it. The
/// first frame's palette is built from that frame.
fn palette_is_stale(f: &Incoming, residual: u64, n: u64) -> bool {
    let mean = residual as f64 / n.max(1) as f64;
    !f.first && n * 100 >= (f.w * f.h) as u64 && mean > REBUILD_RESIDUAL
}

/// Makes transparent the indices of `rect` whose pixel already shows their colour (the viewer
/// keeps it, and runs of the transparent index compress well), and records the others in
/// `shown`.
fn keep_shown(q: &Quantizer, shown: &mut [[u8; 4]], w: usize, rect: Rect, indices: &mut [u8]) {
    let t = q.transparent();
    let colors = q.colors();
    for y in 0..rect.h {
        let shown = &mut shown[(rect.y + y) * w + rect.x..(rect.y + y) * w + rect.x + rect.w];
        for (i, s) in indices[y * rect.w..(y + 1) * rect.w].iter_mut().zip(shown) {
            if *i == t {
                continue;
            }
            let c = colors[*i as usize];
            let c = [c[0], c[1], c[2], 255];
            if *s == c {
                *i = t;
            } else {
                *s = c;
            }
        }
    }
}

impl<W: Write + Send> FrameSink for GifSink<W> {
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), Error> {
        self.add_frame(&frame.image, frame.duration_ms)
    }

    fn finish(&mut self) -> Result<(), Error> {
        if self.frames == 0 {
            return Err(Error::NoFrames(self.name.clone()));
        }
        self.write_pending()?;
        let Some(enc) = self.encoder.take() else {
            return Ok(()); // already finished
        };
        let mut w = enc.into_inner().map_err(|e| self.encoding_error(e))?;
        w.flush().map_err(|e| write_error(&self.name, e))?;
        match self.commit.take() {
            Some(commit) => commit(w),
            None => {
                self.finished = Some(w);
                Ok(())
            }
        }
    }
}

/// A palette needs at least one colour (a frame of only transparent pixels has none).
fn non_empty(mut p: Vec<[u8; 3]>) -> Vec<[u8; 3]> {
    if p.is_empty() {
        p.push([0, 0, 0]);
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decodes a GIF as a browser shows it (through our own GIF reader).
    fn decode(bytes: &[u8]) -> (Vec<crate::Frame>, Option<Repeat>) {
        use crate::stream::FrameSource;
        let mut src = super::super::gif_in::GifSource::new(bytes, "out.gif").unwrap();
        let mut v = Vec::new();
        while let Some(f) = src.next_frame().unwrap() {
            v.push(f);
        }
        let r = src.repeat();
        (v, r)
    }

    fn encode(frames: &[Image], durations: &[Option<u32>], options: GifOptions) -> Vec<u8> {
        let mut sink = GifSink::new(Vec::new(), "mem.gif", options);
        for (i, img) in frames.iter().enumerate() {
            sink.write_frame(&crate::io::test_frame(
                img.clone(),
                i as u64,
                durations.get(i).copied().flatten(),
            ))
            .unwrap();
        }
        sink.finish().unwrap();
        sink.into_inner().unwrap()
    }

    fn flat_scene(t: u32) -> Image {
        let size = Size::new(40, 30).unwrap();
        let mut img = Image::filled(size, [240, 244, 248, 255]);
        for y in 5..15 {
            for x in (2 + t)..(8 + t) {
                img.set(x, y, [214, 39, 40, 255]);
            }
        }
        img
    }

    #[test]
    fn flat_colours_round_trip_exactly_with_delays_and_loops() {
        let frames: Vec<Image> = (0..5).map(flat_scene).collect();
        let bytes = encode(
            &frames,
            &[Some(40), Some(70), None, Some(120), Some(10)],
            GifOptions {
                repeat: Repeat::Times(2),
                ..Default::default()
            },
        );
        let (back, repeat) = decode(&bytes);
        assert_eq!(repeat, Some(Repeat::Times(2)));
        assert_eq!(back.len(), 5);
        for (a, b) in frames.iter().zip(&back) {
            assert_eq!(a.pixels(), b.image.pixels(), "frame {}", b.frame_index);
        }
        let d: Vec<_> = back.iter().map(|f| f.duration_ms).collect();
        assert_eq!(d, [Some(40), Some(70), Some(100), Some(120), Some(10)]);
    }

    #[test]
    fn unchanged_frames_are_tiny_and_frame_rate_carries_rounding() {
        let frames: Vec<Image> = (0..4).map(|_| flat_scene(0)).collect();
        let bytes = encode(
            &frames,
            &[],
            GifOptions {
                frame_rate: FrameRate::new(30, 1),
                ..Default::default()
            },
        );
        let (back, repeat) = decode(&bytes);
        assert_eq!(repeat, Some(Repeat::Infinite));
        assert_eq!(back.len(), 4);
        assert!(back.iter().all(|f| f.image.pixels() == frames[0].pixels()));
        let d: Vec<_> = back.iter().map(|f| f.duration_ms.unwrap()).collect();
        assert_eq!(d, [30, 40, 30, 30]);
        // A single-frame GIF of the scene plus three 1-px frames.
        let one = encode(&frames[..1], &[], GifOptions::default());
        assert!(
            bytes.len() < one.len() + 3 * 40,
            "{} vs {}",
            bytes.len(),
            one.len()
        );
    }

    #[test]
    fn pixels_turning_transparent_are_cleared() {
        let size = Size::new(6, 4).unwrap();
        let a = Image::filled(size, [10, 200, 10, 255]);
        let mut b = a.clone();
        b.set(2, 1, [0, 0, 0, 0]);
        b.set(5, 3, [0, 0, 0, 0]);
        let mut c = b.clone();
        c.set(0, 0, [255, 0, 0, 255]);
        let frames = [a, b, c.clone(), c];
        let (back, _) = decode(&encode(&frames, &[], GifOptions::default()));
        assert_eq!(back.len(), 4);
        for (x, y) in frames.iter().zip(&back) {
            assert_eq!(x.pixels(), y.image.pixels(), "frame {}", y.frame_index);
        }
    }

    #[test]
    fn new_colours_bring_a_new_palette_once_and_static_colours_stay() {
        // A grey scene, then a rainbow appears over a third of it and stays.
        let size = Size::new(90, 60).unwrap();
        let grey = |x: u32| [(x * 255 / 89) as u8; 3];
        let mut frames = Vec::new();
        for t in 0..6 {
            let mut img = Image::new(size);
            for y in 0..60 {
                for x in 0..90u32 {
                    let g = grey(x);
                    let c = if t >= 2 && y < 20 {
                        [
                            (x * 255 / 89) as u8,
                            (y * 12) as u8,
                            (255 - x * 255 / 89) as u8,
                        ]
                    } else {
                        g
                    };
                    img.set(x, y, [c[0], c[1], c[2], 255]);
                }
            }
            frames.push(img);
        }
        let mut sink = GifSink::new(Vec::new(), "mem.gif", GifOptions::default());
        for f in &frames {
            sink.add_frame(f, None).unwrap();
        }
        sink.finish().unwrap();
        assert_eq!(
            sink.palettes_built(),
            2,
            "one update, when the rainbow came"
        );
        let (back, _) = decode(&sink.into_inner().unwrap());
        assert_eq!(back.len(), 6);
        for (a, b) in frames.iter().zip(&back) {
            // Means over 8x8 tiles stay close to the input everywhere.
            for ty in 0..7 {
                for tx in 0..11 {
                    for k in 0..3 {
                        let (mut sa, mut sb) = (0i32, 0i32);
                        for y in ty * 8..ty * 8 + 8 {
                            for x in tx * 8..tx * 8 + 8 {
                                sa += a.get(x, y)[k] as i32;
                                sb += b.image.get(x, y)[k] as i32;
                            }
                        }
                        assert!(
                            (sa - sb).abs() <= 64 * 6,
                            "frame {} tile {tx},{ty}",
                            b.frame_index
                        );
                    }
                }
            }
        }
        // The grey part below the rainbow is the same in every frame.
        for f in &back[1..] {
            for y in 20..60 {
                assert_eq!(f.image.row(y), back[0].image.row(y));
            }
        }
    }

    #[test]
    fn a_side_over_65535_px_is_a_size_a_gif_cannot_hold() {
        // Wider than any `Size::new` allows, but a caller may build one.
        let wide = Image::new(Size {
            width: 65536,
            height: 1,
        });
        let mut sink = GifSink::new(Vec::new(), "wide.gif", GifOptions::default());
        let e = sink.add_frame(&wide, None).unwrap_err();
        assert!(matches!(e, Error::Unsupported { .. }), "{e}");
        assert_eq!(
            e.to_string(),
            "wide.gif: 65536x1 is too large for a GIF: its sides are at most 65535 px"
        );
        // Refused before anything was written: a frame that fits still makes the GIF.
        sink.add_frame(&flat_scene(0), None).unwrap();
        sink.finish().unwrap();
        assert_eq!(decode(&sink.into_inner().unwrap()).0.len(), 1);
    }

    #[test]
    fn a_frame_added_after_finish_is_refused_as_out_of_order() {
        let mut sink = GifSink::new(Vec::new(), "mem.gif", GifOptions::default());
        sink.add_frame(&flat_scene(0), None).unwrap();
        sink.finish().unwrap();
        let e = sink.add_frame(&flat_scene(1), None).unwrap_err();
        assert!(matches!(e, Error::OutOfOrder(_)), "{e}");
        assert!(e.to_string().contains("already finished"), "{e}");
    }

    #[test]
    fn gradient_is_dithered_not_banded() {
        // 300 distinct colours: more than a palette holds.
        let size = Size::new(300, 20).unwrap();
        let mut img = Image::new(size);
        for y in 0..20 {
            for x in 0..300u32 {
                img.set(
                    x,
                    y,
                    [(x * 255 / 299) as u8, 80, (255 - x * 255 / 299) as u8, 255],
                );
            }
        }
        let (back, _) = decode(&encode(
            std::slice::from_ref(&img),
            &[],
            GifOptions::default(),
        ));
        // Column means over 8 rows follow the gradient within 2 levels.
        for x in (0..300).step_by(7) {
            let mean: f32 = (0..8)
                .map(|y| back[0].image.get(x, y)[0] as f32)
                .sum::<f32>()
                / 8.0;
            let want = img.get(x, 0)[0] as f32;
            assert!((mean - want).abs() <= 6.0, "x {x}: {mean} vs {want}");
        }
    }
}
