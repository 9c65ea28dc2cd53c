//! Frames per second of the GIF sink alone (palette, ordered dithering, changed rectangles,
//! LZW), on 60 frames of 640×720 drawn here: a dashboard with a vertical background gradient,
//! a gradient header, a scrolling area chart with a gradient fill, bars that grow, a moving
//! dot and a ring of colour stops. `cargo bench --bench gif_sink`.
//!
//! With `GIF_SINK_FRAMES=DIR` the frames are also written to `DIR/frame-000.png...`, for the
//! comparison with ffmpeg's two-pass palettegen/paletteuse on the same frames
//! (`benches/gif_vs_ffmpeg.sh` runs both).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use std::time::Instant;
use vizretarget::io::{GifOptions, GifSink};
use vizretarget::stream::FrameSink;
use vizretarget::{Image, Size};

const W: u32 = 640;
const H: u32 = 720;
const FRAMES: u32 = 60;

fn lerp(a: [f32; 3], b: [f32; 3], t: f32) -> [u8; 4] {
    let c = |k: usize| (a[k] + (b[k] - a[k]) * t).round().clamp(0.0, 255.0) as u8;
    [c(0), c(1), c(2), 255]
}

/// One dashboard frame at time `t`.
fn frame(t: u32) -> Image {
    let size = Size::new(W, H).expect("size");
    let mut img = Image::new(size);
    for y in 0..H {
        let bg = lerp(
            [236.0, 241.0, 248.0],
            [252.0, 250.0, 244.0],
            y as f32 / H as f32,
        );
        img.row_mut(y).fill(bg);
    }
    // Header: horizontal gradient.
    for y in 0..56 {
        for x in 0..W {
            img.set(
                x,
                y,
                lerp(
                    [20.0, 40.0, 90.0],
                    [60.0, 120.0, 170.0],
                    x as f32 / W as f32,
                ),
            );
        }
    }
    // Area chart, scrolling with t: the fill fades from blue to the panel colour.
    let (l, top, r, b) = (24u32, 80u32, 616u32, 400u32);
    for x in l..r {
        let v = ((x + 4 * t) as f32 * 0.03).sin() * 0.3 + ((x + 4 * t) as f32 * 0.011).cos() * 0.2;
        let yv = (top as f32 + (b - top) as f32 * (0.5 - v)) as u32;
        for y in top..b {
            let c = if y == yv || y == yv + 1 {
                [31, 119, 180, 255]
            } else if y > yv {
                lerp(
                    [120.0, 170.0, 220.0],
                    [245.0, 248.0, 252.0],
                    (y - yv) as f32 / (b - yv) as f32,
                )
            } else {
                [255, 255, 255, 255]
            };
            img.set(x, y, c);
        }
    }
    // Bars growing with t, each a vertical gradient.
    for k in 0..6u32 {
        let x0 = 40 + k * 95;
        let hgt = 60 + ((k * 37 + t * (k + 1)) % 180);
        for y in (640 - hgt)..640 {
            let c = lerp(
                [250.0, 160.0, 60.0],
                [200.0, 60.0, 40.0],
                (640 - y) as f32 / 240.0,
            );
            for x in x0..x0 + 60 {
                img.set(x, y, c);
            }
        }
    }
    // A colour wheel ring (many hues) and a moving dot.
    for y in 420..620u32 {
        for x in 420..620u32 {
            let (dx, dy) = (x as f32 - 520.0, y as f32 - 520.0);
            let d = (dx * dx + dy * dy).sqrt();
            if (60.0..90.0).contains(&d) {
                let a = (dy.atan2(dx) / std::f32::consts::TAU + 0.5) * 6.0;
                let f = a.fract();
                let c = match a as u32 {
                    0 => [1.0, f, 0.0],
                    1 => [1.0 - f, 1.0, 0.0],
                    2 => [0.0, 1.0, f],
                    3 => [0.0, 1.0 - f, 1.0],
                    4 => [f, 0.0, 1.0],
                    _ => [1.0, 0.0, 1.0 - f],
                };
                img.set(
                    x,
                    y,
                    lerp([0.0; 3], [c[0] * 255.0, c[1] * 255.0, c[2] * 255.0], 1.0),
                );
            }
        }
    }
    let (cx, cy) = (100.0 + 8.0 * t as f32, 680.0);
    for y in 668..692u32 {
        for x in 0..W {
            if (x as f32 - cx).hypot(y as f32 - cy) <= 10.0 {
                img.set(x, y, [214, 39, 40, 255]);
            }
        }
    }
    img
}

/// Encodes the frames in memory: (bytes, palettes built).
fn encode(frames: &[Image]) -> (usize, u64) {
    let mut sink = GifSink::new(Vec::new(), "bench.gif", GifOptions::default());
    for f in frames {
        sink.add_frame(f, Some(40)).expect("frame");
    }
    sink.finish().expect("finish");
    let palettes = sink.palettes_built();
    (sink.into_inner().map_or(0, |v| v.len()), palettes)
}

fn bench(c: &mut Criterion) {
    let frames: Vec<Image> = (0..FRAMES).map(frame).collect();
    if let Some(dir) = std::env::var_os("GIF_SINK_FRAMES") {
        let dir = std::path::PathBuf::from(dir);
        std::fs::create_dir_all(&dir).expect("frames folder");
        for (i, f) in frames.iter().enumerate() {
            let path = dir.join(format!("frame-{i:03}.png"));
            vizretarget::io::write_still(f, &path, vizretarget::io::OutputFormat::Png)
                .expect("write frame");
        }
        let gif = dir.join("vizretarget.gif");
        let mut sink = GifSink::create(&gif, GifOptions::default()).expect("gif");
        for f in &frames {
            sink.add_frame(f, Some(40)).expect("frame");
        }
        sink.finish().expect("finish");
    }
    // A plain measurement first, printed as frames per second (best of 3).
    let mut best = f64::INFINITY;
    let mut out = (0, 0);
    for _ in 0..3 {
        let t = Instant::now();
        out = encode(&frames);
        best = best.min(t.elapsed().as_secs_f64());
    }
    println!(
        "gif_sink: {FRAMES} frames {W}x{H} in {:.3} s = {:.1} frames/s, {} KiB, {} palette(s)",
        best,
        FRAMES as f64 / best,
        out.0 / 1024,
        out.1
    );
    let mut group = c.benchmark_group("gif_sink");
    group.sample_size(10);
    group.bench_function("60 frames 640x720", |b| {
        b.iter(|| encode(black_box(&frames)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
