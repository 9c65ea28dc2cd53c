//! Writes raw frames (RGB24 or RGBA) of a dashboard-like animation to stdout, for timing
//! vizretarget and ffmpeg on the same frames (`benches/stream_vs_ffmpeg.sh`).
//!
//! usage: raw_frames KIND N WxH [rgba|rgb24] > frames.raw
//! KIND: static (one frame repeated), movers (three dots move each frame), changing (every
//! tile of every frame changes).

use std::io::Write;
use vizretarget::{Image, Size};

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

fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 4 {
        eprintln!("usage: raw_frames static|movers|changing N WxH [rgba|rgb24]");
        std::process::exit(2);
    }
    let n: u32 = a[2].parse().expect("N");
    let (w, h) = a[3].split_once('x').expect("WxH");
    let size = Size::new(w.parse().expect("W"), h.parse().expect("H")).expect("size");
    let rgba = a.get(4).is_some_and(|f| f == "rgba");
    let out = std::io::stdout();
    let mut out = std::io::BufWriter::new(out.lock());
    let still = frame(size, 0, 0, 0);
    for t in 0..n {
        let img = match a[1].as_str() {
            "static" => still.clone(),
            "movers" => frame(size, t, 3, 0),
            _ => frame(size, t, 40, 7 * t + 1),
        };
        let bytes: Vec<u8> = if rgba {
            img.as_bytes().to_vec()
        } else {
            img.pixels()
                .iter()
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect()
        };
        if out.write_all(&bytes).is_err() {
            return;
        }
    }
}
