//! Writes the sample streams in `streams/` that the README and tests use. Deterministic, no
//! external data: everything is drawn by hand (filled discs, ellipses, rectangles, polygons,
//! 1-px lines) in flat colours, so the PNGs stay small.
//!
//! ```text
//! cargo run --release --example make_streams            # writes ./streams
//! cargo run --release --example make_streams -- DIR     # writes DIR
//! ```
//!
//! - `dashboard/frame-0000..0023.png`, 640x360: title bar, a live line chart whose newest point
//!   advances each frame, two counters as bars, status dots.
//! - `scatter-map/frame-0000..0029.png`, 720x405: pastel land on light blue, 30 dots of radius
//!   4-8, three of which move each frame.
//! - `graph/frame-0000..0019.png`, 640x480: nodes and thin grey edges over pastel community
//!   ellipses that grow as nodes join.
//!
//! Each stream is also written as an animated GIF beside its folder (`dashboard.gif`, ...),
//! read back from the PNGs and encoded with the library's GIF writer (`vizretarget::io`).
//!
//! `marks/` holds the inputs of the README's vector-marks examples: `map.png` (the scatter
//! map without its dots), `dots.json` (the first frame's 30 dots as a layer of vector marks)
//! and `scatter-map.jsonl` (each frame's dots, one line per frame of `scatter-map/`).

use image::{Rgb, RgbImage};
use std::f32::consts::TAU;
use std::path::{Path, PathBuf};

type C = [u8; 3];
const PALETTE: [C; 8] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [23, 190, 207],
];

/// A small deterministic generator (xorshift32), so the samples never change.
struct Rng(u32);
impl Rng {
    fn unit(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        (self.0 >> 8) as f32 / (1 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
}

fn put(img: &mut RgbImage, x: i32, y: i32, c: C) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, Rgb(c));
    }
}

fn rect(img: &mut RgbImage, x0: i32, y0: i32, x1: i32, y1: i32, c: C) {
    for y in y0..y1 {
        for x in x0..x1 {
            put(img, x, y, c);
        }
    }
}

/// Filled axis-aligned ellipse (a disc when `rx == ry`), pixel centres inside.
fn ellipse(img: &mut RgbImage, cx: f32, cy: f32, rx: f32, ry: f32, c: C) {
    for y in (cy - ry).floor() as i32..=(cy + ry).ceil() as i32 {
        for x in (cx - rx).floor() as i32..=(cx + rx).ceil() as i32 {
            let (dx, dy) = ((x as f32 + 0.5 - cx) / rx, (y as f32 + 0.5 - cy) / ry);
            if dx * dx + dy * dy <= 1.0 {
                put(img, x, y, c);
            }
        }
    }
}

fn disc(img: &mut RgbImage, cx: f32, cy: f32, r: f32, c: C) {
    ellipse(img, cx, cy, r, r, c);
}

/// 1-px line (Bresenham).
fn line(img: &mut RgbImage, (x0, y0): (i32, i32), (x1, y1): (i32, i32), c: C) {
    let (dx, dy) = ((x1 - x0).abs(), -(y1 - y0).abs());
    let (sx, sy) = ((x1 - x0).signum(), (y1 - y0).signum());
    let (mut x, mut y, mut err) = (x0, y0, dx + dy);
    loop {
        put(img, x, y, c);
        if x == x1 && y == y1 {
            return;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}

/// Filled polygon, even-odd rule, sampled at pixel centres.
fn polygon(img: &mut RgbImage, pts: &[(f32, f32)], c: C) {
    for y in 0..img.height() as i32 {
        let yc = y as f32 + 0.5;
        let mut xs: Vec<f32> = (0..pts.len())
            .filter_map(|i| {
                let ((x0, y0), (x1, y1)) = (pts[i], pts[(i + 1) % pts.len()]);
                ((y0 <= yc) != (y1 <= yc)).then(|| x0 + (yc - y0) / (y1 - y0) * (x1 - x0))
            })
            .collect();
        xs.sort_by(f32::total_cmp);
        for span in xs.chunks_exact(2) {
            rect(
                img,
                (span[0] - 0.5).ceil() as i32,
                y,
                (span[1] - 0.5).ceil() as i32,
                y + 1,
                c,
            );
        }
    }
}

/// A position from `gen` for a disc of radius `r` that keeps clear of the `placed` discs (the
/// first of 50 tries that does).
fn place(
    rng: &mut Rng,
    placed: &[(f32, f32, f32)],
    r: f32,
    mut gen: impl FnMut(&mut Rng) -> (f32, f32),
) -> (f32, f32) {
    let mut p = gen(rng);
    for _ in 0..50 {
        let clear = placed
            .iter()
            .all(|&(x, y, qr)| (x - p.0).hypot(y - p.1) > r + qr + 6.0);
        if clear {
            break;
        }
        p = gen(rng);
    }
    p
}

fn save(img: &RgbImage, dir: &Path, frame: usize) {
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let path = dir.join(format!("frame-{frame:04}.png"));
    let file = std::io::BufWriter::new(std::fs::File::create(&path).expect("create frame"));
    let enc = PngEncoder::new_with_quality(file, CompressionType::Best, FilterType::Adaptive);
    img.write_with_encoder(enc).expect("encode frame");
}

fn dashboard(dir: &Path) {
    let series: Vec<f32> = (0..40)
        .map(|i| 0.5 + 0.3 * (i as f32 * 0.45).sin() + 0.12 * (i as f32 * 1.7).cos())
        .collect();
    for f in 0..24 {
        let mut img = RgbImage::from_pixel(640, 360, Rgb([244, 246, 248]));
        rect(&mut img, 0, 0, 640, 36, [36, 52, 84]);
        for (i, w) in [70, 44, 96].into_iter().enumerate() {
            let x = 16 + [0, 80, 134][i];
            rect(&mut img, x, 13, x + w, 23, [230, 236, 245]); // title "words"
        }
        // Line chart with axes, gridlines and a series whose newest point advances.
        let (l, t, r, b) = (24, 52, 420, 340);
        rect(&mut img, l - 8, t - 8, r + 8, b + 8, [255, 255, 255]);
        for gy in (t..b).step_by(48) {
            line(&mut img, (l, gy), (r, gy), [226, 230, 234]);
        }
        for gx in (l..=r).step_by(44) {
            line(&mut img, (gx, t), (gx, b), [226, 230, 234]);
        }
        line(&mut img, (l, t), (l, b), [70, 70, 70]);
        line(&mut img, (l, b), (r, b), [70, 70, 70]);
        let pt = |i: usize| {
            (
                l + 4 + i as i32 * 11,
                b - (series[i] * (b - t) as f32) as i32,
            )
        };
        let newest = 12 + f;
        for i in 0..newest {
            line(&mut img, pt(i), pt(i + 1), [31, 119, 180]);
        }
        let (nx, ny) = pt(newest);
        disc(
            &mut img,
            nx as f32 + 0.5,
            ny as f32 + 0.5,
            5.0,
            [214, 39, 40],
        );
        // Two counters as cards with a bar and "digit" blocks that change.
        for (k, base) in [(0, 0.35f32), (1, 0.7)] {
            let y0 = 52 + k * 150;
            rect(&mut img, 440, y0 - 8, 624, y0 + 130, [255, 255, 255]);
            let v = (base + 0.25 * ((f as f32) * 0.5 + k as f32).sin()).clamp(0.05, 1.0);
            rect(&mut img, 452, y0 + 90, 612, y0 + 110, [232, 234, 238]);
            rect(
                &mut img,
                452,
                y0 + 90,
                452 + (160.0 * v) as i32,
                y0 + 110,
                PALETTE[k as usize + 1],
            );
            let digits = 2 + ((v * 37.0) as i32 + f as i32) % 3;
            for d in 0..digits {
                rect(
                    &mut img,
                    452 + d * 26,
                    y0 + 12,
                    472 + d * 26,
                    y0 + 60,
                    [50, 60, 76],
                );
            }
        }
        // Status dots: one flips colour every few frames.
        for i in 0..4 {
            let c = if i == 3 && (f / 4) % 2 == 1 {
                [214, 39, 40]
            } else {
                [44, 160, 44]
            };
            disc(&mut img, 560.0 + i as f32 * 18.0, 18.0, 5.0, c);
        }
        save(&img, dir, f);
    }
}

fn scatter_map(dir: &Path) {
    let mut rng = Rng(0x5EED_0001);
    let lands: Vec<(Vec<(f32, f32)>, C)> = [
        (170.0, 150.0, 120.0, [226, 240, 203]),
        (470.0, 120.0, 95.0, [245, 226, 200]),
        (560.0, 300.0, 80.0, [228, 218, 240]),
        (250.0, 320.0, 70.0, [250, 240, 200]),
    ]
    .into_iter()
    .map(|(cx, cy, r, c)| {
        let pts = (0..14)
            .map(|i| {
                let a = i as f32 / 14.0 * TAU;
                let rr = r * rng.range(0.65, 1.15);
                (cx + rr * a.cos() * 1.3, cy + rr * a.sin())
            })
            .collect();
        (pts, c)
    })
    .collect();
    let mut dots: Vec<(f32, f32, f32)> = Vec::new(); // x, y, radius; colour by index
    for i in 0..30 {
        let (pts, _) = &lands[i % lands.len()];
        let (cx, cy) = pts
            .iter()
            .fold((0.0, 0.0), |a, p| (a.0 + p.0 / 14.0, a.1 + p.1 / 14.0));
        let r = rng.range(4.0, 8.0);
        let (x, y) = place(&mut rng, &dots, r, |g| {
            (cx + g.range(-75.0, 75.0), cy + g.range(-50.0, 50.0))
        });
        dots.push((x.clamp(12.0, 708.0), y.clamp(12.0, 393.0), r));
    }
    // The dots of frame `f`: centre, radius, colour.
    let dots_at = |f: usize| -> Vec<(f32, f32, f32, C)> {
        let a = f as f32 / 30.0 * TAU;
        (dots.iter().enumerate())
            .map(|(i, &(x, y, r))| {
                let (x, y) = match i {
                    0 => (x + 60.0 * a.cos(), y + 30.0 * a.sin()), // circles
                    1 => (x + f as f32 * 6.0, y),                  // drifts east
                    2 => (x, y + 25.0 * (2.0 * a).sin()),          // bobs
                    _ => (x, y),
                };
                (x, y, r, PALETTE[(i + i / 4) % 8])
            })
            .collect()
    };
    let mut map = RgbImage::from_pixel(720, 405, Rgb([198, 224, 242]));
    for (pts, c) in &lands {
        polygon(&mut map, pts, *c);
    }
    let mut lines = String::new();
    for f in 0..30 {
        let mut img = map.clone();
        for &(x, y, r, c) in &dots_at(f) {
            disc(&mut img, x, y, r, c);
        }
        save(&img, dir, f);
        lines.push_str(&layer_json(&dots_at(f)));
        lines.push('\n');
    }
    // The vector marks' samples: the map without its dots, the first frame's dots as one
    // layer, and every frame's as JSON Lines.
    let marks = dir.parent().unwrap_or(Path::new(".")).join("marks");
    std::fs::create_dir_all(&marks).expect("create marks folder");
    map.save(marks.join("map.png")).expect("write map.png");
    std::fs::write(marks.join("dots.json"), layer_json(&dots_at(0)) + "\n").expect("dots.json");
    std::fs::write(marks.join("scatter-map.jsonl"), lines).expect("scatter-map.jsonl");
    println!("wrote {}", marks.display());
}

/// Dots as a layer of vector marks (the JSON of `vizretarget::vector`), on one line.
fn layer_json(dots: &[(f32, f32, f32, C)]) -> String {
    let points: Vec<String> = dots
        .iter()
        .map(|&(x, y, r, [cr, cg, cb])| {
            format!(
                "{{\"x\": {x:.1}, \"y\": {y:.1}, \"r\": {r:.1}, \"fill\": \"#{cr:02x}{cg:02x}{cb:02x}\"}}"
            )
        })
        .collect();
    format!("{{\"points\": [{}]}}", points.join(", "))
}

fn graph(dir: &Path) {
    let mut rng = Rng(0x5EED_0002);
    let centres = [(170.0, 160.0), (460.0, 150.0), (320.0, 350.0)];
    let pastel: [C; 3] = [[214, 232, 250], [253, 226, 204], [218, 242, 214]];
    // Nodes per community, in the order they join; each links to two earlier members.
    let nodes: Vec<Vec<(f32, f32, f32)>> = centres
        .iter()
        .map(|&(cx, cy)| {
            let mut ns: Vec<(f32, f32, f32)> = Vec::new();
            for j in 0..14 {
                let r = rng.range(5.0, 7.0);
                let (x, y) = place(&mut rng, &ns, r, |g| {
                    let (a, d) = (g.range(0.0, TAU), 12.0 + j as f32 * 6.0 * g.range(0.6, 1.0));
                    (cx + d * a.cos() * 1.2, cy + d * a.sin())
                });
                ns.push((x, y, r));
            }
            ns
        })
        .collect();
    let links: Vec<Vec<(usize, usize)>> = nodes
        .iter()
        .map(|ns| {
            (1..ns.len())
                .flat_map(|j| [(j, j / 2), (j, (j * 7 + 3) % j)])
                .collect()
        })
        .collect();
    let across = [
        ((0, 3), (1, 2)),
        ((1, 5), (2, 1)),
        ((2, 4), (0, 6)),
        ((0, 9), (2, 8)),
    ];
    for f in 0..20 {
        let mut img = RgbImage::from_pixel(640, 480, Rgb([255, 255, 255]));
        let shown = 5 + f * 9 / 19; // 5 members at first, all 14 at the end
        for (k, ns) in nodes.iter().enumerate() {
            let (cx, cy) = centres[k];
            let (rx, ry) = ns[..shown]
                .iter()
                .fold((0.0f32, 0.0f32), |(rx, ry), &(x, y, r)| {
                    (rx.max((x - cx).abs() + r), ry.max((y - cy).abs() + r))
                });
            ellipse(
                &mut img,
                cx,
                cy,
                (rx + 14.0) * 1.1,
                (ry + 14.0) * 1.1,
                pastel[k],
            );
        }
        let at = |k: usize, j: usize| (nodes[k][j].0 as i32, nodes[k][j].1 as i32);
        for (k, ls) in links.iter().enumerate() {
            for &(a, b) in ls.iter().filter(|&&(a, b)| a < shown && b < shown) {
                line(&mut img, at(k, a), at(k, b), [160, 160, 160]);
            }
        }
        for &((ka, a), (kb, b)) in across
            .iter()
            .filter(|&&((_, a), (_, b))| a < shown && b < shown)
        {
            line(&mut img, at(ka, a), at(kb, b), [160, 160, 160]);
        }
        for (k, ns) in nodes.iter().enumerate() {
            for &(x, y, r) in &ns[..shown] {
                disc(&mut img, x, y, r, PALETTE[k]);
            }
        }
        save(&img, dir, f);
    }
}

/// The PNG frames of `dir`, in order, as an animated GIF that loops forever.
fn write_gif(dir: &Path, gif: &Path, delay_ms: u32) {
    use vizretarget::io::{DirSource, GifOptions, GifSink};
    use vizretarget::stream::{FrameSink, FrameSource};
    let mut frames = DirSource::open(dir).expect("list frames");
    let mut sink = GifSink::create(gif, GifOptions::default()).expect("create GIF");
    while let Some(frame) = frames.next_frame().expect("read frame") {
        sink.add_frame(&frame.image, Some(delay_ms))
            .expect("encode frame");
    }
    sink.finish().expect("finish GIF");
}

fn main() {
    let root = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("streams"), PathBuf::from);
    let draw_dashboard: fn(&Path) = dashboard;
    // Frame durations of the GIF versions.
    for (name, draw, delay_ms) in [
        ("dashboard", draw_dashboard, 250),
        ("scatter-map", scatter_map, 100),
        ("graph", graph, 300),
    ] {
        let dir = root.join(name);
        std::fs::create_dir_all(&dir).expect("create stream folder");
        draw(&dir);
        println!("wrote {}", dir.display());
        let gif = root.join(format!("{name}.gif"));
        write_gif(&dir, &gif, delay_ms);
        println!("wrote {}", gif.display());
    }
}
