//! Writes raw frames (RGB24 or RGBA) of a dashboard-like animation to stdout, for timing
//! vizretarget and ffmpeg on the same frames (`benches/stream_vs_ffmpeg.sh`).
//!
//! usage: raw_frames KIND N WxH [rgba|rgb24] > frames.raw
//! KIND: static (one frame repeated), movers (three dots move each frame), changing (every
//! tile of every frame changes).

#[path = "../benches/common/dashboard.rs"]
mod dashboard;

use dashboard::frame;
use std::io::Write;
use vizretarget::Size;

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
