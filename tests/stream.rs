//! Streams: reuse of mesh and solution, temporal coherence, and the threaded pipeline giving
//! the same frames as the sequential core.

use vizretarget::stream::{NoProgress, VecSink, VecSource};
use vizretarget::{Decision, Frame, Image, Options, Pipeline, Renderer, Retargeter, Size};

/// A light map-like background with dots; dots `movers` shift by `step` px per frame.
fn scene(size: Size, frame: u32, movers: usize) -> Image {
    let mut img = Image::filled(size, [236, 244, 250, 255]);
    let (w, h) = (size.width as f32, size.height as f32);
    // Pastel land.
    for y in 0..size.height {
        for x in 0..size.width {
            let (fx, fy) = (x as f32 / w, y as f32 / h);
            if (fx - 0.3).powi(2) + (fy - 0.5).powi(2) < 0.06 {
                img.set(x, y, [204, 235, 197, 255]);
            }
        }
    }
    let mut seed = 7u32;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        (seed % 10_000) as f32 / 10_000.0
    };
    let colours = [[215, 25, 28, 255], [44, 123, 182, 255], [26, 150, 65, 255]];
    for i in 0..24 {
        let (mut cx, cy) = (20.0 + rnd() * (w - 40.0), 20.0 + rnd() * (h - 40.0));
        let r = 4.0 + rnd() * 4.0;
        if i < movers {
            cx = (cx + 3.0 * frame as f32).min(w - 12.0);
        }
        let c = colours[i % 3];
        for y in (cy - r - 1.0) as u32..(cy + r + 2.0) as u32 {
            for x in (cx - r - 1.0) as u32..(cx + r + 2.0) as u32 {
                let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                if dx * dx + dy * dy <= r * r && x < size.width && y < size.height {
                    img.set(x, y, c);
                }
            }
        }
    }
    img
}

fn run_sequential(
    frames: &[Image],
    target: Size,
    options: &Options,
) -> Vec<vizretarget::Retargeted> {
    let mut r = Retargeter::new(target, options.clone()).unwrap();
    let mut out = Vec::new();
    for (i, f) in frames.iter().enumerate() {
        r.send_frame(Frame::new(f.clone(), i as u64)).unwrap();
        while let Ok(o) = r.receive_frame() {
            out.push(o);
        }
    }
    out
}

#[test]
fn static_stream_gives_identical_frames_and_reuses() {
    let size = Size::new(320, 200).unwrap();
    let target = Size::new(160, 200).unwrap();
    let frame = scene(size, 0, 0);
    let frames: Vec<Image> = (0..50).map(|_| frame.clone()).collect();
    let out = run_sequential(&frames, target, &Options::default());
    assert_eq!(out.len(), 50);
    assert_eq!(out[0].stats.decision, Decision::Rebuild);
    for o in &out[1..] {
        assert_eq!(o.stats.decision, Decision::Reuse, "frame {}", o.frame_index);
        assert_eq!(o.image, out[0].image, "frame {} differs", o.frame_index);
    }
}

/// A few dots moving: the mesh is updated locally, the output equals a fresh full render of
/// the frame through that frame's mesh and warp (the partial render is exact), no fold, and
/// pixels far from the movers do not change between frames.
#[test]
fn moving_marks_update_locally_and_stay_exact() {
    let size = Size::new(320, 200).unwrap();
    let target = Size::new(160, 200).unwrap();
    let frames: Vec<Image> = (0..12).map(|f| scene(size, f, 2)).collect();
    let options = Options::default().with_analysis(true);
    let out = run_sequential(&frames, target, &options);
    let updates = out
        .iter()
        .filter(|o| o.stats.decision == Decision::Update)
        .count();
    assert!(
        updates >= 8,
        "decisions: {:?}",
        out.iter().map(|o| o.stats.decision).collect::<Vec<_>>()
    );
    let mut renderer = Renderer::new();
    for (o, f) in out.iter().zip(&frames) {
        let a = o.analysis.as_ref().unwrap();
        assert_eq!(a.warp.folded_triangles(&a.mesh), 0);
        let mut full = Image::new(target);
        renderer.render(f.as_ref(), &a.mesh, &a.warp, &mut full);
        assert!(
            full == o.image,
            "frame {}: partial render differs from a full one",
            o.frame_index
        );
    }
    // Temporal coherence: the share of output pixels that change between frames stays small.
    for pair in out.windows(2) {
        let changed = pair[0]
            .image
            .pixels()
            .iter()
            .zip(pair[1].image.pixels())
            .filter(|(a, b)| a != b)
            .count();
        let share = changed as f64 / target.area() as f64;
        assert!(
            share < 0.15,
            "frame {}: {share:.3} of the output changed",
            pair[1].frame_index
        );
    }
}

#[test]
fn threaded_pipeline_gives_the_sequential_frames() {
    let size = Size::new(320, 200).unwrap();
    let target = Size::new(200, 150).unwrap();
    let frames: Vec<Image> = (0..16)
        .map(|f| {
            if f % 5 == 4 {
                scene(size, 0, 0)
            } else {
                scene(size, f, 3)
            }
        })
        .collect();
    let options = Options::default();
    let seq = run_sequential(&frames, target, &options);
    let mut source = VecSource::new(
        frames
            .iter()
            .enumerate()
            .map(|(i, f)| Frame::new(f.clone(), i as u64)),
    );
    let mut sink = VecSink::default();
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let summary = Pipeline::run(
        target,
        &options,
        &mut source,
        &mut sink,
        &NoProgress,
        &cancel,
    )
    .unwrap();
    assert_eq!(summary.frames, 16);
    assert!(sink.finished);
    assert_eq!(sink.frames.len(), seq.len());
    for (a, b) in sink.frames.iter().zip(&seq) {
        assert_eq!(a.frame_index, b.frame_index);
        assert_eq!(a.stats.decision, b.stats.decision);
        assert!(a.image == b.image, "frame {} differs", a.frame_index);
    }
    assert_eq!(
        summary.reused + summary.updated + summary.rebuilt,
        16,
        "{summary:?}"
    );
}

/// A sink whose reader goes away after `limit` frames.
struct ClosingSink {
    limit: usize,
    written: usize,
    finished: bool,
}

impl vizretarget::FrameSink for ClosingSink {
    fn write_frame(&mut self, _frame: &vizretarget::Retargeted) -> Result<(), vizretarget::Error> {
        if self.written == self.limit {
            return Err(vizretarget::Error::OutputClosed);
        }
        self.written += 1;
        Ok(())
    }
    fn finish(&mut self) -> Result<(), vizretarget::Error> {
        self.finished = true;
        Ok(())
    }
}

/// A source that fails after `good` frames.
struct FailingSource {
    good: u64,
    next: u64,
    frame: Image,
}

impl vizretarget::FrameSource for FailingSource {
    fn next_frame(&mut self) -> Result<Option<Frame>, vizretarget::Error> {
        if self.next == self.good {
            return Err(vizretarget::Error::TruncatedFrame {
                path: "stdin".into(),
                frame_index: self.next,
                expected: 100,
                got: 10,
            });
        }
        self.next += 1;
        Ok(Some(Frame::new(self.frame.clone(), self.next - 1)))
    }
}

#[test]
fn a_closed_output_ends_the_run_successfully() {
    let size = Size::new(120, 80).unwrap();
    let frames = (0..40).map(|i| Frame::new(scene(size, i, 2), i as u64));
    let mut source = VecSource::new(frames);
    let mut sink = ClosingSink {
        limit: 5,
        written: 0,
        finished: false,
    };
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let s = Pipeline::run(
        Size::new(60, 80).unwrap(),
        &Options::default(),
        &mut source,
        &mut sink,
        &NoProgress,
        &cancel,
    )
    .unwrap();
    assert!(s.output_closed);
    assert_eq!(s.frames, 5);
    assert!(sink.finished);
}

#[test]
fn a_failing_source_reports_its_error_after_the_good_frames() {
    let size = Size::new(120, 80).unwrap();
    let mut source = FailingSource {
        good: 7,
        next: 0,
        frame: scene(size, 0, 0),
    };
    let mut sink = VecSink::default();
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let err = Pipeline::run(
        Size::new(60, 80).unwrap(),
        &Options::default(),
        &mut source,
        &mut sink,
        &NoProgress,
        &cancel,
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            vizretarget::Error::TruncatedFrame { frame_index: 7, .. }
        ),
        "{err}"
    );
    assert_eq!(sink.frames.len(), 7, "every good frame is written first");
    assert!(sink.finished);
}

#[test]
fn cancel_stops_reading_and_finishes_the_output() {
    let size = Size::new(120, 80).unwrap();
    let mut source = VecSource::new((0..20).map(|i| Frame::new(scene(size, i, 1), i as u64)));
    let mut sink = VecSink::default();
    let cancel = std::sync::atomic::AtomicBool::new(true);
    let s = Pipeline::run(
        Size::new(60, 80).unwrap(),
        &Options::default(),
        &mut source,
        &mut sink,
        &NoProgress,
        &cancel,
    )
    .unwrap();
    assert!(s.cancelled);
    assert!(sink.finished);
    assert!(sink.frames.len() < 20);
}

/// Frames, then a read that blocks until `release` is set (stdin whose writer went quiet).
struct GoesQuiet {
    frames: VecSource,
    release: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

impl vizretarget::stream::FrameSource for GoesQuiet {
    fn next_frame(&mut self) -> Result<Option<Frame>, vizretarget::Error> {
        if let Some(f) = self.frames.next_frame()? {
            return Ok(Some(f));
        }
        while !self.release.load(std::sync::atomic::Ordering::SeqCst) {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        Ok(None)
    }
}

/// Sets the cancel flag once `after` frames are written.
struct CancelAfter {
    after: usize,
    done: std::sync::atomic::AtomicUsize,
    cancel: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

impl vizretarget::stream::Progress for CancelAfter {
    fn frame_done(&self, _stats: &vizretarget::FrameStats) {
        use std::sync::atomic::Ordering::SeqCst;
        if self.done.fetch_add(1, SeqCst) + 1 == self.after {
            self.cancel.store(true, SeqCst);
        }
    }
}

#[test]
fn cancel_during_a_blocked_read_ends_the_run_with_every_frame_read() {
    // The library's cancellation path as the CLI's signal handler uses it: the source
    // detached, the cancel flag set while the source is blocked for good.
    use std::sync::atomic::AtomicBool;
    use std::sync::Arc;
    let size = Size::new(120, 80).unwrap();
    let release = Arc::new(AtomicBool::new(false));
    let quiet = GoesQuiet {
        frames: VecSource::new((0..4).map(|i| Frame::new(scene(size, i, 1), i as u64))),
        release: release.clone(),
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let mut source = vizretarget::stream::DetachedSource::new(Box::new(quiet), cancel.clone());
    let progress = CancelAfter {
        after: 4,
        done: Default::default(),
        cancel: cancel.clone(),
    };
    let mut sink = VecSink::default();
    let s = Pipeline::run(
        Size::new(60, 80).unwrap(),
        &Options::default(),
        &mut source,
        &mut sink,
        &progress,
        &cancel,
    )
    .unwrap();
    release.store(true, std::sync::atomic::Ordering::SeqCst); // the abandoned read may end
    assert!(s.cancelled, "recorded as cancelled, not as the input's end");
    assert_eq!(s.frames, 4);
    let order: Vec<u64> = sink.frames.iter().map(|f| f.frame_index).collect();
    assert_eq!(order, [0, 1, 2, 3]);
    assert!(sink.finished, "the sink completes its output");
}

#[test]
fn stage_objects_can_move_between_threads() {
    fn sendable<T: Send>() {}
    sendable::<Retargeter>();
    sendable::<vizretarget::Retargeted>();
    sendable::<Options>();
}
