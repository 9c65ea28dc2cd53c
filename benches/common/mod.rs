//! Synthetic visualizations at the canvas sizes of the paper's Table 1, drawn by hand.
//!
//! They imitate `../shared/tools/make_cases.py` (pastel map regions with grey outlines, pastel
//! graph communities with light edges, saturated round markers of radius 5–11 kept three radii
//! apart) so that the benches see comparable saliency and mesh sizes, but need neither Python
//! nor files at run time. Deterministic: a fixed xorshift seed per case.

use vizretarget::{Image, Size};

/// Saturated marker colours (ColorBrewer, as in `make_cases.py`).
const MARKER_COLOURS: [[u8; 3]; 5] = [
    [215, 25, 28],
    [44, 123, 182],
    [26, 150, 65],
    [230, 97, 1],
    [123, 50, 148],
];

/// Light, low-saturation region colours.
const PASTELS: [[u8; 3]; 8] = [
    [204, 235, 197],
    [222, 235, 247],
    [254, 230, 206],
    [239, 237, 245],
    [255, 255, 204],
    [229, 245, 224],
    [253, 224, 221],
    [224, 236, 244],
];

/// One benchmark case: an image, its target, and the paper's figures for the matching row.
pub struct Case {
    pub name: &'static str,
    pub image: Image,
    pub target: Size,
    pub paper: Paper,
}

/// The paper's figures for a canvas of the same size (Tables 1 and 2).
#[derive(Clone, Copy)]
pub struct Paper {
    /// The visualization the paper measured.
    pub label: &'static str,
    pub vertices: usize,
    pub dof: usize,
    /// Table 2: VSM generation.
    pub vsm_ms: f64,
    /// Table 1: mesh deformation.
    pub deform_ms: f64,
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Map,
    Ocean,
    Graph,
}

/// The four cases: scatter on a pastel map, graph with communities, ocean map, enlarged map.
pub fn cases() -> Vec<Case> {
    let spec = [
        (
            "scatter-map",
            (876, 374),
            Kind::Map,
            40,
            (385, 374),
            Paper {
                label: "SGM",
                vertices: 324,
                dof: 586,
                vsm_ms: 472.0,
                deform_ms: 19.0,
            },
        ),
        (
            "graph-communities",
            (1500, 800),
            Kind::Graph,
            70,
            (750, 800),
            Paper {
                label: "GC",
                vertices: 853,
                dof: 4824,
                vsm_ms: 1749.0,
                deform_ms: 161.0,
            },
        ),
        (
            "ocean-map-tall",
            (1320, 791),
            Kind::Ocean,
            50,
            (660, 791),
            Paper {
                label: "China map",
                vertices: 393,
                dof: 2142,
                vsm_ms: 1553.0,
                deform_ms: 32.0,
            },
        ),
        (
            "map-enlarge",
            (678, 680),
            Kind::Map,
            30,
            (1066, 680),
            Paper {
                label: "IG",
                vertices: 611,
                dof: 3498,
                vsm_ms: 653.0,
                deform_ms: 58.0,
            },
        ),
    ];
    spec.into_iter()
        .enumerate()
        .map(|(i, (name, (w, h), kind, markers, (tw, th), paper))| {
            let mut rng = XorShift::new(7_000 + i as u64);
            Case {
                name,
                image: still(&mut rng, w, h, kind, markers),
                target: Size::new(tw, th).unwrap(),
                paper,
            }
        })
        .collect()
}

/// xorshift64*: tiny, deterministic, good enough for placing marks.
struct XorShift(u64);

impl XorShift {
    fn new(seed: u64) -> XorShift {
        // Never zero; mix the seed a little so that neighbouring seeds differ at once.
        XorShift(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1)
    }

    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in `[lo, hi)`.
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }

    /// Uniform in `lo..=hi`.
    fn int(&mut self, lo: u32, hi: u32) -> u32 {
        lo + (self.next() % (hi - lo + 1) as u64) as u32
    }

    fn choose<T: Copy>(&mut self, items: &[T]) -> T {
        items[(self.next() % items.len() as u64) as usize]
    }
}

fn rgba([r, g, b]: [u8; 3]) -> [u8; 4] {
    [r, g, b, 255]
}

/// Fills pixels whose centres lie inside the ellipse.
fn fill_ellipse(img: &mut Image, cx: f64, cy: f64, rx: f64, ry: f64, c: [u8; 4]) {
    let (w, h) = (img.width() as f64, img.height() as f64);
    let (y0, y1) = ((cy - ry).floor().max(0.0), (cy + ry).ceil().min(h));
    let (x0, x1) = ((cx - rx).floor().max(0.0), (cx + rx).ceil().min(w));
    for y in y0 as u32..y1 as u32 {
        let dy = (y as f64 + 0.5 - cy) / ry;
        for x in x0 as u32..x1 as u32 {
            let dx = (x as f64 + 0.5 - cx) / rx;
            if dx * dx + dy * dy <= 1.0 {
                img.set(x, y, c);
            }
        }
    }
}

/// Fills pixels whose centres lie inside the polygon (even-odd rule).
fn fill_polygon(img: &mut Image, pts: &[(f64, f64)], c: [u8; 4]) {
    let (w, h) = (img.width(), img.height());
    let ymin = pts.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let ymax = pts.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    let mut xs = Vec::new();
    for y in ymin.floor().max(0.0) as u32..(ymax.ceil().min(h as f64)) as u32 {
        let sy = y as f64 + 0.5;
        xs.clear();
        for (i, &(ax, ay)) in pts.iter().enumerate() {
            let (bx, by) = pts[(i + 1) % pts.len()];
            if (ay <= sy) != (by <= sy) {
                xs.push(ax + (sy - ay) / (by - ay) * (bx - ax));
            }
        }
        xs.sort_by(f64::total_cmp);
        for span in xs.chunks_exact(2) {
            // Pixels with centre x + 0.5 in [span[0], span[1]).
            let x0 = (span[0] - 0.5).ceil().max(0.0) as u32;
            let x1 = ((span[1] - 0.5).ceil().max(0.0) as u32).min(w);
            for x in x0..x1 {
                img.set(x, y, c);
            }
        }
    }
}

/// A 1-px line (Bresenham between the pixels holding the end points), clipped to the image.
fn line(img: &mut Image, (ax, ay): (f64, f64), (bx, by): (f64, f64), c: [u8; 4]) {
    let (mut x, mut y) = (ax.floor() as i64, ay.floor() as i64);
    let (x1, y1) = (bx.floor() as i64, by.floor() as i64);
    let (dx, dy) = ((x1 - x).abs(), -(y1 - y).abs());
    let (sx, sy) = ((x1 - x).signum(), (y1 - y).signum());
    let mut err = dx + dy;
    loop {
        if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
            img.set(x as u32, y as u32, c);
        }
        if x == x1 && y == y1 {
            break;
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

/// A wobbly region outline: 14 points around an ellipse of aspect 0.8.
fn blob(rng: &mut XorShift, cx: f64, cy: f64, r: f64) -> Vec<(f64, f64)> {
    (0..14)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 14.0;
            let rr = r * rng.uniform(0.6, 1.25);
            (cx + rr * a.cos(), cy + rr * 0.8 * a.sin())
        })
        .collect()
}

struct Marker {
    x: f64,
    y: f64,
    r: f64,
}

/// Markers of radius 5–11, centres at least 3 radii sums apart, inside the canvas.
fn place_markers(rng: &mut XorShift, w: f64, h: f64, n: usize) -> Vec<Marker> {
    let mut marks: Vec<Marker> = Vec::new();
    let mut tries = 0;
    while marks.len() < n && tries < 20_000 {
        tries += 1;
        let r = rng.uniform(5.0, 11.0);
        let x = rng.uniform(r + 4.0, w - r - 4.0);
        let y = rng.uniform(r + 4.0, h - r - 4.0);
        if marks
            .iter()
            .all(|m| (x - m.x).hypot(y - m.y) > 3.0 * (r + m.r))
        {
            marks.push(Marker { x, y, r });
        }
    }
    marks
}

fn still(rng: &mut XorShift, w: u32, h: u32, kind: Kind, n_markers: usize) -> Image {
    let size = Size::new(w, h).unwrap();
    let base = if kind == Kind::Ocean {
        [236, 244, 250, 255]
    } else {
        [250, 250, 250, 255]
    };
    let mut img = Image::filled(size, base);
    let (wf, hf) = (w as f64, h as f64);
    match kind {
        Kind::Map | Kind::Ocean => {
            for _ in 0..rng.int(5, 9) {
                let (cx, cy) = (rng.uniform(0.05, 0.95) * wf, rng.uniform(0.1, 0.9) * hf);
                let r = rng.uniform(0.08, 0.22) * wf.min(hf) * 1.6;
                let pts = blob(rng, cx, cy, r);
                fill_polygon(&mut img, &pts, rgba(rng.choose(&PASTELS)));
                for i in 0..pts.len() {
                    line(
                        &mut img,
                        pts[i],
                        pts[(i + 1) % pts.len()],
                        [170, 170, 170, 255],
                    );
                }
            }
        }
        Kind::Graph => {
            for _ in 0..rng.int(3, 5) {
                let (cx, cy) = (rng.uniform(0.15, 0.85) * wf, rng.uniform(0.2, 0.8) * hf);
                let (rx, ry) = (rng.uniform(0.08, 0.18) * wf, rng.uniform(0.1, 0.25) * hf);
                fill_ellipse(&mut img, cx, cy, rx, ry, rgba(rng.choose(&PASTELS)));
            }
        }
    }
    let marks = place_markers(rng, wf, hf, n_markers);
    if kind == Kind::Graph {
        for (i, a) in marks.iter().enumerate() {
            for b in &marks[i + 1..] {
                if (a.x - b.x).hypot(a.y - b.y) < 0.25 * wf && rng.uniform(0.0, 1.0) < 0.4 {
                    line(&mut img, (a.x, a.y), (b.x, b.y), [190, 190, 190, 255]);
                }
            }
        }
    }
    for m in &marks {
        let c = rgba(rng.choose(&MARKER_COLOURS));
        fill_ellipse(&mut img, m.x, m.y, m.r, m.r, c);
    }
    img
}
