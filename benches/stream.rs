//! Stream throughput of the threaded pipeline, in memory (no decoding or encoding), at
//! 1280×720 → 720×720, for the three kinds of stream the issue names:
//! (a) static content, (b) a few small marks moving each frame, (c) every frame different.
//! Prints frames per second and the reuse shares, then each stage's milliseconds per frame
//! of the sequential core ([`vizretarget::Retargeter`], one frame at a time, its render on
//! every core): what a frame costs, without the pipeline's stages contending for the cores.
//! `cargo bench --bench stream`.
//!
//! The end-to-end figures with raw frames through stdin and stdout, beside ffmpeg's scale
//! filter on the same frames, come from `benches/stream_vs_ffmpeg.sh`.

#[path = "common/dashboard.rs"]
mod dashboard;

use dashboard::frame;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use vizretarget::stream::{FrameSink, NoProgress, VecSource};
use vizretarget::{Error, Frame, Image, Options, Pipeline, Retargeted, Retargeter, Size};

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
    for (name, make, reuse) in kinds.iter() {
        let reuse = *reuse;
        let mut options = Options::default();
        options.reuse.enabled = reuse;
        let frames: Vec<Frame> = (0..n).map(|t| Frame::new(make(t), t as u64)).collect();
        let mut source = VecSource::new(frames);
        let mut sink = CountSink(0);
        let cancel = AtomicBool::new(false);
        let t0 = Instant::now();
        let s = Pipeline::new(target, &options)
            .unwrap()
            .run(&mut source, &mut sink, &NoProgress, &cancel)
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
    eprintln!("sequential core, one frame at a time, ms/frame (mean of {n} frames):");
    // The two kinds that change, with reuse on.
    for (name, make, _) in &kinds[1..3] {
        let mut r = Retargeter::new(target, Options::default()).unwrap();
        let (mut sum, t0) = ([0f64; 4], Instant::now());
        for t in 0..n {
            r.send_frame(Frame::new(make(t), t as u64)).unwrap();
            let Ok(out) = r.receive_frame() else {
                panic!("no frame out for frame {t}");
            };
            let st = out.stats.times;
            for (s, v) in sum
                .iter_mut()
                .zip([st.vsm_ms, st.mesh_ms, st.solve_ms, st.render_ms])
            {
                *s += v;
            }
        }
        let wall = t0.elapsed().as_secs_f64() * 1000.0 / n as f64;
        let [vsm, mesh, solve, render] = sum.map(|v| v / n as f64);
        eprintln!(
            "{name:28} vsm {vsm:.1} mesh {mesh:.1} solve {solve:.1} render {render:.1}   total {:.1} (wall {wall:.1} with drawing the frame)",
            vsm + mesh + solve + render
        );
    }
}
