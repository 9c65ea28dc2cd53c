//! Stream throughput of the threaded pipeline, in memory (no decoding or encoding), at
//! 1280×720 → 720×720, for the three kinds of stream the issue names:
//! (a) static content, (b) a few small marks moving each frame, (c) every frame different.
//! Prints frames per second and the reuse shares. `cargo bench --bench stream`.
//!
//! The end-to-end figures with raw frames through stdin and stdout, beside ffmpeg's scale
//! filter on the same frames, come from `benches/stream_vs_ffmpeg.sh`.

use std::sync::atomic::AtomicBool;
use std::time::Instant;
use vizretarget::stream::{FrameSink, NoProgress, VecSource};
use vizretarget::{Error, Frame, Image, Options, Pipeline, Retargeted, Size};

/// A dashboard-like frame: panels, a line chart whose data scrolls with `shift`, dots of which
/// `movers` drift with `t`; with `shift` > 0 the background is a gradient that changes with it
/// too, so every tile of every frame differs.
pub fn frame(size: Size, t: u32, movers: usize, shift: u32) -> Image {
    let (w, h) = (size.width, size.height);
    let mut img = Image::filled(size, [248, 248, 250, 255]);
    if shift > 0 {
        for y in 0..h {
            for x in 0..w {
                let v = ((x + y + shift) % 64) as u8;
                img.set(x, y, [190 + v, 200 + v / 2, 230, 255]);
            }
        }
    }
    let mut rect = |x0: u32, y0: u32, x1: u32, y1: u32, c: [u8; 4]| {
        for y in y0..y1.min(h) {
            for x in x0..x1.min(w) {
                img.set(x, y, c);
            }
        }
    };
    rect(0, 0, w, 40, [40, 60, 90, 255]);
    rect(20, 60, w / 2 - 10, h - 20, [255, 255, 255, 255]);
    rect(w / 2 + 10, 60, w - 20, h - 20, [235, 245, 238, 255]);
    // Line chart in the left panel.
    for x in 30..w / 2 - 20 {
        let v = (((x + shift) as f32) * 0.05).sin() * 80.0 + (h / 2) as f32;
        for dy in 0..3 {
            img.set(x, (v as u32 + dy).min(h - 1), [31, 119, 180, 255]);
        }
    }
    // Dots in the right panel.
    let mut seed = 12345u32;
    for i in 0..40 {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        let mut cx = w / 2 + 40 + seed % (w / 2 - 80);
        let cy = 90 + (seed / 7) % (h - 140);
        if i < movers {
            cx = (cx + 3 * t) % (w / 2 - 60) + w / 2 + 30;
        }
        let c = [[214, 39, 40, 255], [44, 160, 44, 255], [255, 127, 14, 255]][i % 3];
        for y in cy.saturating_sub(7)..cy + 7 {
            for x in cx.saturating_sub(7)..cx + 7 {
                let (dx, dy) = (x as i32 - cx as i32, y as i32 - cy as i32);
                if dx * dx + dy * dy <= 36 && x < w && y < h {
                    img.set(x, y, c);
                }
            }
        }
    }
    img
}

struct CountSink(u64);
impl FrameSink for CountSink {
    fn write_frame(&mut self, f: &Retargeted) -> Result<(), Error> {
        std::hint::black_box(f.image.pixels()[0]);
        self.0 += 1;
        Ok(())
    }
    fn finish(&mut self) -> Result<(), Error> {
        Ok(())
    }
}

/// A named stream: how its frames are drawn, and whether reuse is on.
type Kind = (&'static str, Box<dyn Fn(u32) -> Image>, bool);

fn main() {
    let size = Size::new(1280, 720).unwrap();
    let target = Size::new(720, 720).unwrap();
    let n = 120u32;
    let kinds: [Kind; 4] = [
        ("(a) static", Box::new(move |_| frame(size, 0, 0, 0)), true),
        (
            "(b) 3 marks moving",
            Box::new(move |t| frame(size, t, 3, 0)),
            true,
        ),
        (
            "(c) every frame different",
            Box::new(move |t| frame(size, t, 40, 7 * t + 1)),
            true,
        ),
        (
            "(c) same, reuse off",
            Box::new(move |t| frame(size, t, 40, 7 * t + 1)),
            false,
        ),
    ];
    eprintln!(
        "in-memory pipeline, 1280x720 -> 720x720, {n} frames, {} threads available",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    for (name, make, reuse) in kinds {
        let mut options = Options::default();
        options.reuse.enabled = reuse;
        let frames: Vec<Frame> = (0..n).map(|t| Frame::new(make(t), t as u64)).collect();
        let mut source = VecSource::new(frames);
        let mut sink = CountSink(0);
        let cancel = AtomicBool::new(false);
        let t0 = Instant::now();
        let s = Pipeline::run(
            target,
            &options,
            &mut source,
            &mut sink,
            &NoProgress,
            &cancel,
        )
        .unwrap();
        let secs = t0.elapsed().as_secs_f64();
        let per = |v: f64| v / s.frames as f64;
        eprintln!(
            "{name:28} {:7.1} fps   reused {:3} updated {:3} rebuilt {:3}   ms/frame: vsm {:.1} mesh {:.1} solve {:.1} render {:.1}",
            s.frames as f64 / secs,
            s.reused,
            s.updated,
            s.rebuilt,
            per(s.stage_ms.vsm_ms),
            per(s.stage_ms.mesh_ms),
            per(s.stage_ms.solve_ms),
            per(s.stage_ms.render_ms)
        );
    }
}
