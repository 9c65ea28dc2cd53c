//! The dashboard-like animation the stream benchmarks time: `benches/stream.rs` in memory,
//! `examples/raw_frames.rs` as raw frames for `benches/stream_vs_ffmpeg.sh`.

use vizretarget::{Image, Size};

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
