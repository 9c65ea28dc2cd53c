//! Streams: reuse of mesh and solution, temporal coherence, and the threaded pipeline giving
//! the same frames as the sequential core.

use vizretarget::stream::{NoProgress, VecSink, VecSource};
use vizretarget::{Decision, Frame, Image, Options, Pipeline, Regions, Renderer, Retargeter, Size};

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

/// Pixels that differ between two images of the same size.
fn changed(a: &Image, b: &Image) -> usize {
    a.pixels()
        .iter()
        .zip(b.pixels())
        .filter(|(p, q)| p != q)
        .count()
}

/// Roundness (minor over major axis of the pixel covariance) of every 8-connected blob of
/// exactly `rgba` in `img` with at least `min_px` pixels.
fn blob_roundness(img: &Image, rgba: [u8; 4], min_px: usize) -> Vec<f64> {
    let (w, h) = (img.width() as usize, img.height() as usize);
    let px = img.pixels();
    let mut seen = vec![false; w * h];
    let mut out = Vec::new();
    for start in 0..w * h {
        if seen[start] || px[start] != rgba {
            continue;
        }
        seen[start] = true;
        let (mut stack, mut pts) = (vec![start], Vec::new());
        while let Some(i) = stack.pop() {
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            pts.push((x as f64, y as f64));
            for (dx, dy) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let (nx, ny) = (x + dx, y + dy);
                if nx >= 0 && ny >= 0 && (nx as usize) < w && (ny as usize) < h {
                    let j = ny as usize * w + nx as usize;
                    if !seen[j] && px[j] == rgba {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
        if pts.len() < min_px {
            continue;
        }
        let n = pts.len() as f64;
        let (mx, my) = pts
            .iter()
            .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
        let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
        for &(x, y) in &pts {
            sxx += (x - mx) * (x - mx) / n;
            syy += (y - my) * (y - my) / n;
            sxy += (x - mx) * (y - my) / n;
        }
        let (tr, det) = (sxx + syy, sxx * syy - sxy * sxy);
        let disc = (tr * tr / 4.0 - det).max(0.0).sqrt();
        let (big, small) = (tr / 2.0 + disc, (tr / 2.0 - disc).max(0.0));
        out.push((small / big).sqrt());
    }
    out
}

/// A few dots moving over a map while the rest stands still: the moved dots float over the
/// kept mesh and solution (later frames are reuses), they keep their round shape wherever the
/// warp carries them, and only the pixels they leave and reach change (re-meshing around
/// each moved dot changed about 2.4 times the input's share of pixels at half width).
#[test]
fn moving_marks_float_over_the_kept_warp() {
    let size = Size::new(320, 200).unwrap();
    let target = Size::new(160, 200).unwrap();
    let frames: Vec<Image> = (0..12).map(|f| scene(size, f, 2)).collect();
    let out = run_sequential(
        &frames,
        target,
        &Options::default().with_regions(Regions::Auto),
    );
    assert_eq!(out[0].stats.decision, Decision::Rebuild);
    // Until frame 9 the movers run free; then one runs into a cluster of dots and the group
    // grows too big to be a mark, which is a change of regions: a local update, not a rebuild.
    let decisions: Vec<Decision> = out.iter().map(|o| o.stats.decision).collect();
    assert!(
        decisions[1..9].iter().all(|&d| d == Decision::Reuse)
            && decisions[9..].iter().all(|&d| d != Decision::Rebuild),
        "decisions: {decisions:?}"
    );
    // On the reused frames the dots stay as round as they are in the input, floating ones as
    // well as those the mesh rings (compared in sorted order: the k-th least round dot of the
    // output against the k-th of the input; where a mover overlaps a dot both are cut in the
    // input too). Known limit, not asserted: once the cluster is too big for a ring, the
    // local update meshes it as a region and its dots are squeezed with it.
    let roundness = |img: &Image| {
        let mut r: Vec<f64> = [[215, 25, 28, 255], [44, 123, 182, 255], [26, 150, 65, 255]]
            .iter()
            .flat_map(|&c| blob_roundness(img, c, 20))
            .collect();
        r.sort_by(f64::total_cmp);
        r
    };
    for (o, f) in out.iter().zip(&frames) {
        if o.stats.decision == Decision::Update {
            continue;
        }
        let (got, want) = (roundness(&o.image), roundness(f));
        assert_eq!(got.len(), want.len(), "frame {}: dots lost", o.frame_index);
        for (g, w) in got.iter().zip(&want) {
            assert!(
                *g >= w - 0.05,
                "frame {}: roundness {got:.2?} for input {want:.2?}",
                o.frame_index
            );
        }
    }
    // A moved dot kept at its size changes as many output pixels as input pixels (plus its
    // antialiased rim): at half the canvas that is an amplification of about 2 by itself.
    // Anything that re-meshed or shimmered around it would change far more.
    for (pair, inputs) in out.windows(2).zip(frames.windows(2)) {
        if pair[1].stats.decision != Decision::Reuse {
            continue;
        }
        let (o, i) = (
            changed(&pair[0].image, &pair[1].image),
            changed(&inputs[0], &inputs[1]),
        );
        assert!(i > 0);
        assert!(
            o as f64 <= 1.25 * i as f64,
            "frame {}: {o} output pixels changed for {i} input pixels",
            pair[1].frame_index
        );
    }
}

/// A bar growing (a region too big to be a mark): the mesh is updated locally, the output
/// equals a fresh full render through that frame's mesh and warp (the partial render is
/// exact), no fold, and the output changes only near the bar.
#[test]
fn a_growing_region_updates_locally_and_stays_exact() {
    let size = Size::new(320, 200).unwrap();
    let target = Size::new(160, 200).unwrap();
    let frames: Vec<Image> = (0..10)
        .map(|f| {
            let mut img = scene(size, 0, 0);
            for y in 110 - 4 * f..190 {
                for x in 250..290 {
                    img.set(x, y, [120, 60, 160, 255]);
                }
            }
            img
        })
        .collect();
    // The mesh's own partial render, without floating marks (the default floats the scene's
    // dots, which a bare render through the mesh does not draw).
    let options = Options::default()
        .with_regions(Regions::Auto)
        .with_analysis(true);
    let out = run_sequential(&frames, target, &options);
    let updates = out
        .iter()
        .filter(|o| o.stats.decision == Decision::Update)
        .count();
    assert!(
        updates >= 6,
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
        let share = changed(&pair[0].image, &pair[1].image) as f64 / target.area() as f64;
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
    let summary = Pipeline::new(target, &options)
        .unwrap()
        .run(&mut source, &mut sink, &NoProgress, &cancel)
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
    let s = Pipeline::new(Size::new(60, 80).unwrap(), &Options::default())
        .unwrap()
        .run(&mut source, &mut sink, &NoProgress, &cancel)
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
    let err = Pipeline::new(Size::new(60, 80).unwrap(), &Options::default())
        .unwrap()
        .run(&mut source, &mut sink, &NoProgress, &cancel)
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
    let s = Pipeline::new(Size::new(60, 80).unwrap(), &Options::default())
        .unwrap()
        .run(&mut source, &mut sink, &NoProgress, &cancel)
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
    let s = Pipeline::new(Size::new(60, 80).unwrap(), &Options::default())
        .unwrap()
        .run(&mut source, &mut sink, &progress, &cancel)
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

/// Each streamed frame is within 8 pixels (more than 48 levels apart) of the same frame
/// retargeted alone with the default options.
fn assert_each_frame_is_the_fresh_one(
    out: &[vizretarget::Retargeted],
    frames: &[Image],
    target: Size,
) {
    for (o, f) in out.iter().zip(frames) {
        let fresh = vizretarget::retarget(f, target, &Options::default()).unwrap();
        let far = o
            .image
            .pixels()
            .iter()
            .zip(fresh.image.pixels())
            .filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) > 48))
            .count();
        assert!(
            far <= 8,
            "frame {} ({:?}): {far} pixels far from the fresh frame",
            o.frame_index,
            o.stats.decision
        );
    }
}

/// White ground, a static bar chart on the left, and on the right a dot moving, a bubble
/// growing by a pixel of radius per frame and a bar of the dot's colour.
fn growing(frame: u32) -> Image {
    let size = Size::new(320, 200).unwrap();
    let mut img = Image::filled(size, [255; 4]);
    for (i, h) in [120u32, 60, 150, 90].iter().enumerate() {
        let x = 12 + 28 * i as u32;
        for y in 180 - h..180 {
            for xx in x..x + 20 {
                img.set(xx, y, [44, 123, 182, 255]);
            }
        }
    }
    let disc = |img: &mut Image, cx: f32, cy: f32, r: f32, c: [u8; 4]| {
        for y in 0..200u32 {
            for x in 160..320u32 {
                let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                if dx * dx + dy * dy <= r * r {
                    img.set(x, y, c);
                }
            }
        }
    };
    disc(
        &mut img,
        250.0,
        100.0,
        10.0 + frame as f32,
        [215, 25, 28, 255],
    );
    disc(
        &mut img,
        180.0 + 4.0 * frame as f32,
        40.0,
        6.0,
        [26, 150, 65, 255],
    );
    // A green bar of the moving dot's colour: green marks no longer all round, a fresh frame
    // squeezes the dot with the rest.
    for y in 150..190 {
        for x in 290..300 {
            img.set(x, y, [26, 150, 65, 255]);
        }
    }
    img
}

/// The default on a stream: each frame, reused or updated, shows what the same frame
/// retargeted alone shows (no mark kept at a stale size or pasted where a fresh frame squeezes
/// it), and the static panel's output pixels stay byte-identical from frame to frame.
#[test]
fn a_kept_warp_draws_what_a_fresh_frame_draws_and_still_panels_stay_still() {
    let target = Size::new(160, 200).unwrap();
    let frames: Vec<Image> = (0..10).map(growing).collect();
    let out = run_sequential(&frames, target, &Options::default());
    // A handful of pixels for a subpixel of rounding; a dot pasted at its own size where the
    // fresh frame squeezes it is 60.
    assert_each_frame_is_the_fresh_one(&out, &frames, target);
    // The bar chart is the left 60 output columns; the dots never come within the
    // resampler's reach of it.
    for o in &out[1..] {
        for y in 0..200 {
            for x in 0..60 {
                assert_eq!(
                    o.image.get(x, y),
                    out[0].image.get(x, y),
                    "frame {} changed ({x}, {y})",
                    o.frame_index
                );
            }
        }
    }
}

/// A bar chart race in small: bars change length and the title's text changes every frame.
/// Text found on an earlier frame must not be floated over a later one (a label that moved or
/// grew out of its old box would be pasted torn): every frame equals the frame retargeted
/// alone.
#[test]
fn changing_text_is_found_afresh() {
    use vizretarget::compare::draw_label;
    let target = Size::new(200, 240).unwrap();
    let frame = |f: u32| {
        let mut img = Image::filled(Size::new(400, 240).unwrap(), [255; 4]);
        draw_label(
            &mut img,
            20.0,
            8.0,
            22.0,
            &format!("Visits, week {}", 1 + 7 * f),
        );
        for (i, len) in [300u32, 220, 160].iter().enumerate() {
            let len = (len + 13 * f * (i as u32 + 1)) % 340 + 20;
            let y = 60 + 50 * i as u32;
            draw_label(
                &mut img,
                4.0,
                y as f32 + 4.0,
                16.0,
                ["Oslo", "Lima", "Perth"][i],
            );
            for yy in y..y + 30 {
                for x in 60..60 + len.min(330) {
                    img.set(x, yy, [44, 123, 182, 255]);
                }
            }
        }
        img
    };
    let frames: Vec<Image> = (0..8).map(frame).collect();
    let options = Options {
        keep_analysis: true,
        ..Options::default()
    };
    let out = run_sequential(&frames, target, &options);
    // A stream keeps only the text bands all its frames share (so its plot does not move
    // back and forth); where a frame's own bands are those, it is drawn as if alone.
    // The blank runs a layout shrinks and the type it keeps matter only around plots,
    // which this picture has none of (its bars stand on no baseline).
    let bands = |r: &vizretarget::Retargeted| {
        let a = r.analysis.as_ref().expect("kept");
        a.mesh.structure().map(|s| {
            assert!(s.bands.plots_x.is_empty() && s.bands.plots_y.is_empty());
            vizretarget::Bands {
                blank_x: Vec::new(),
                blank_y: Vec::new(),
                type_x: Vec::new(),
                type_y: Vec::new(),
                ..s.bands.clone()
            }
        })
    };
    let alone: Vec<_> = frames
        .iter()
        .map(|f| vizretarget::retarget(f, target, &options).unwrap())
        .collect();
    let same: Vec<usize> = (0..frames.len())
        .filter(|&i| bands(&out[i]) == bands(&alone[i]))
        .collect();
    assert!(
        same.len() * 2 >= frames.len(),
        "frames {same:?} keep their own bands"
    );
    let pick =
        |v: &[vizretarget::Retargeted]| same.iter().map(|&i| v[i].clone()).collect::<Vec<_>>();
    let kept: Vec<Image> = same.iter().map(|&i| frames[i].clone()).collect();
    assert_each_frame_is_the_fresh_one(&pick(&out), &kept, target);
}
