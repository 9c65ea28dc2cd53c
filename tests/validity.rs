//! Validity of the whole single-frame pipeline over random visualizations and extreme ratios.
//!
//! DESIGN.md §4 of the pipeline: "No fold-overs, ever ... Test it over extreme ratios (0.2× to
//! 5× per axis)". Every property here is one the renderer or a caller relies on:
//!
//! * the source mesh tiles the canvas (areas sum to `w·h`, every triangle positively oriented);
//! * the solved warp folds no triangle, checked by the library's count *and* by recomputing each
//!   deformed signed area here in `f64`, so a bug in `folded_triangles` cannot hide a fold;
//! * boundary vertices sit exactly on their side of the target (Eq. 10–11), corners exactly on
//!   the target's corners, interior vertices inside the target;
//! * the rendered frame has exactly the target size and every output pixel is written (rendered
//!   into a fully transparent image from an opaque source, every pixel must come out opaque).
//!
//! Images are drawn here by hand (discs, 1-px lines, pastel rectangles on a white, pastel or
//! dark background) so that the test needs no files.

use proptest::prelude::*;
use vizretarget::Boundary;
use vizretarget::{
    retarget, Image, Mesh, MeshOptions, Options, Renderer, Size, Solver, VsmBuilder, Warp,
};

// ---------------------------------------------------------------------------------------------
// Drawing

#[derive(Clone, Copy, Debug)]
enum Background {
    White,
    Pastel([u8; 3]),
    Dark([u8; 3]),
}

impl Background {
    fn rgba(self) -> [u8; 4] {
        match self {
            Background::White => [255, 255, 255, 255],
            Background::Pastel([r, g, b]) | Background::Dark([r, g, b]) => [r, g, b, 255],
        }
    }
}

/// A filled disc; the centre is a fraction of the canvas so that shrinking the canvas keeps it.
#[derive(Clone, Copy, Debug)]
struct Disc {
    fx: f32,
    fy: f32,
    radius: f32,
    rgb: [u8; 3],
}

/// A 1-px axis-aligned line, in canvas fractions.
#[derive(Clone, Copy, Debug)]
struct Line {
    horizontal: bool,
    at: f32,
    from: f32,
    to: f32,
    rgb: [u8; 3],
}

/// A filled pastel rectangle, in canvas fractions.
#[derive(Clone, Copy, Debug)]
struct Rect {
    x0: f32,
    y0: f32,
    x1: f32,
    y1: f32,
    rgb: [u8; 3],
}

#[derive(Clone, Debug)]
struct Scene {
    width: u32,
    height: u32,
    background: Background,
    rects: Vec<Rect>,
    lines: Vec<Line>,
    discs: Vec<Disc>,
}

fn opaque([r, g, b]: [u8; 3]) -> [u8; 4] {
    [r, g, b, 255]
}

/// Fills the pixels whose centres lie within `radius` of `(cx, cy)`.
fn fill_disc(img: &mut Image, cx: f32, cy: f32, radius: f32, rgba: [u8; 4]) {
    let (w, h) = (img.width() as f32, img.height() as f32);
    let y0 = (cy - radius).floor().max(0.0) as u32;
    let y1 = (cy + radius).ceil().min(h) as u32;
    let x0 = (cx - radius).floor().max(0.0) as u32;
    let x1 = (cx + radius).ceil().min(w) as u32;
    for y in y0..y1 {
        for x in x0..x1 {
            let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
            if dx * dx + dy * dy <= radius * radius {
                img.set(x, y, rgba);
            }
        }
    }
}

fn fill_rect(img: &mut Image, x0: u32, y0: u32, x1: u32, y1: u32, rgba: [u8; 4]) {
    for y in y0.min(img.height())..y1.min(img.height()) {
        for x in x0.min(img.width())..x1.min(img.width()) {
            img.set(x, y, rgba);
        }
    }
}

impl Scene {
    fn size(&self) -> Size {
        Size::new(self.width, self.height).unwrap()
    }

    fn draw(&self) -> Image {
        let mut img = Image::filled(self.size(), self.background.rgba());
        let (w, h) = (self.width as f32, self.height as f32);
        let px = |f: f32, side: f32| ((f * side) as u32).min(side as u32 - 1);
        for r in &self.rects {
            let (x0, x1) = (px(r.x0.min(r.x1), w), px(r.x0.max(r.x1), w) + 1);
            let (y0, y1) = (px(r.y0.min(r.y1), h), px(r.y0.max(r.y1), h) + 1);
            fill_rect(&mut img, x0, y0, x1, y1, opaque(r.rgb));
        }
        for l in &self.lines {
            let (along, across) = if l.horizontal { (w, h) } else { (h, w) };
            let at = px(l.at, across);
            let (a, b) = (px(l.from.min(l.to), along), px(l.from.max(l.to), along) + 1);
            if l.horizontal {
                fill_rect(&mut img, a, at, b, at + 1, opaque(l.rgb));
            } else {
                fill_rect(&mut img, at, a, at + 1, b, opaque(l.rgb));
            }
        }
        for d in &self.discs {
            fill_disc(&mut img, d.fx * w, d.fy * h, d.radius, opaque(d.rgb));
        }
        img
    }
}

/// HSV to RGB, all in [0, 1] (hue in turns).
fn hsv(h: f32, s: f32, v: f32) -> [u8; 3] {
    let h6 = (h.fract() * 6.0).min(5.999_999);
    let i = h6.floor();
    let f = h6 - i;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    let (r, g, b) = match i as u32 {
        0 => (v, t, p),
        1 => (q, v, p),
        2 => (p, v, t),
        3 => (p, q, v),
        4 => (t, p, v),
        _ => (v, p, q),
    };
    [r, g, b].map(|c| (c * 255.0).round() as u8)
}

// ---------------------------------------------------------------------------------------------
// The checks

/// Target side for a ratio, at least 1 px.
fn scaled(side: u32, ratio: f64) -> u32 {
    ((side as f64 * ratio).round() as u32).max(1)
}

fn twice_signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Checks the mesh invariants, solves, renders and checks the warp and the output; returns a
/// description of the first violation.
fn check(img: &Image, target: Size) -> Result<(), String> {
    let vsm = VsmBuilder::new().build(img.as_ref());
    let mesh = Mesh::build(&vsm, &MeshOptions::default());
    let src = img.size();
    let (w, h) = (src.width as f64, src.height as f64);

    // The source mesh tiles the canvas.
    let verts = mesh.vertices();
    let mut area = 0.0;
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = tri.map(|v| [verts[v as usize].x, verts[v as usize].y]);
        let a2 = twice_signed_area(a, b, c);
        if a2 <= 0.0 {
            return Err(format!("source triangle {t} {tri:?} has area {}", a2 / 2.0));
        }
        area += a2 / 2.0;
    }
    if ((area - w * h) / (w * h)).abs() > 1e-6 {
        return Err(format!(
            "source triangles cover {area}, canvas is {}",
            w * h
        ));
    }
    if mesh.boundary().len() != verts.len() {
        return Err("one boundary constraint per vertex".into());
    }

    let (warp, stats) = Solver::default()
        .solve(&mesh, &vsm, target)
        .map_err(|e| format!("solve failed: {e}"))?;
    check_warp(&mesh, &warp, target).map_err(|e| format!("{e}; solve stats {stats:?}"))?;

    let mut out = Image::new(target);
    Renderer::new().render(img.as_ref(), &mesh, &warp, &mut out);
    if out.size() != target {
        return Err(format!("rendered {} for target {target}", out.size()));
    }
    if let Some(i) = out.pixels().iter().position(|p| p[3] != 255) {
        let tw = target.width as usize;
        return Err(format!(
            "output pixel ({}, {}) not written: {:?}",
            i % tw,
            i / tw,
            out.pixels()[i]
        ));
    }
    Ok(())
}

fn check_warp(mesh: &Mesh, warp: &Warp, target: Size) -> Result<(), String> {
    let (tw, th) = (target.width as f64, target.height as f64);
    if warp.target() != target {
        return Err(format!("warp is for {}, not {target}", warp.target()));
    }
    let folded = warp.folded_triangles(mesh);
    if folded != 0 {
        return Err(format!("{folded} folded triangles (library count)"));
    }
    let q = warp.positions();
    if q.len() != mesh.vertices().len() {
        return Err("one position per vertex".into());
    }
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = tri.map(|v| [q[v as usize].x, q[v as usize].y]);
        let a2 = twice_signed_area(a, b, c);
        if a2.is_nan() || a2 <= 0.0 {
            return Err(format!(
                "deformed triangle {t} {tri:?} has signed area {} (recomputed): {a:?} {b:?} {c:?}",
                a2 / 2.0
            ));
        }
    }
    for (i, ((p, d), b)) in mesh
        .vertices()
        .iter()
        .zip(q)
        .zip(mesh.boundary())
        .enumerate()
    {
        let ok = match b {
            Boundary::Left => d.x == 0.0,
            Boundary::Right => d.x == tw,
            Boundary::Top => d.y == 0.0,
            Boundary::Bottom => d.y == th,
            Boundary::Corner => {
                let cx = if p.x == 0.0 { 0.0 } else { tw };
                let cy = if p.y == 0.0 { 0.0 } else { th };
                d.x == cx && d.y == cy
            }
            Boundary::Interior => true,
        };
        let inside = (0.0..=tw).contains(&d.x) && (0.0..=th).contains(&d.y);
        if !ok || !inside {
            return Err(format!(
                "vertex {i} ({b:?}) at source {p} went to {d}, target {target}"
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Random scenes

/// Per-axis ratios between the extremes; the extremes are drawn separately, more often.
const MID_RATIOS: [f64; 7] = [0.33, 0.5, 0.8, 1.0, 1.25, 1.6, 2.5];
const EXTREME_RATIOS: [f64; 2] = [0.2, 5.0];

fn ratio() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => prop::sample::select(&MID_RATIOS[..]),
        2 => prop::sample::select(&EXTREME_RATIOS[..]),
    ]
}

fn saturated() -> impl Strategy<Value = [u8; 3]> {
    (0.0f32..1.0, 0.7f32..=1.0, 0.55f32..=1.0).prop_map(|(h, s, v)| hsv(h, s, v))
}

fn pastel() -> impl Strategy<Value = [u8; 3]> {
    prop::array::uniform3(215u8..=255)
}

fn background() -> impl Strategy<Value = Background> {
    prop_oneof![
        Just(Background::White),
        pastel().prop_map(Background::Pastel),
        prop::array::uniform3(0u8..=50).prop_map(Background::Dark),
    ]
}

fn disc() -> impl Strategy<Value = Disc> {
    (0.0f32..=1.0, 0.0f32..=1.0, 2.0f32..=15.0, saturated()).prop_map(|(fx, fy, radius, rgb)| {
        Disc {
            fx,
            fy,
            radius,
            rgb,
        }
    })
}

fn line() -> impl Strategy<Value = Line> {
    (
        any::<bool>(),
        0.0f32..1.0,
        0.0f32..1.0,
        0.0f32..1.0,
        prop::array::uniform3(0u8..=160),
    )
        .prop_map(|(horizontal, at, from, to, rgb)| Line {
            horizontal,
            at,
            from,
            to,
            rgb,
        })
}

fn rect() -> impl Strategy<Value = Rect> {
    (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0, pastel()).prop_map(
        |(x0, y0, x1, y1, rgb)| Rect {
            x0,
            y0,
            x1,
            y1,
            rgb,
        },
    )
}

fn scene() -> impl Strategy<Value = Scene> {
    (
        40u32..=400,
        40u32..=400,
        background(),
        prop::collection::vec(rect(), 0..=4),
        prop::collection::vec(line(), 0..=6),
        prop::collection::vec(disc(), 0..=40),
    )
        .prop_map(|(width, height, background, rects, lines, discs)| Scene {
            width,
            height,
            background,
            rects,
            lines,
            discs,
        })
}

fn cases() -> u32 {
    let soak = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok());
    soak.unwrap_or(0).max(400)
}

proptest! {
    #![proptest_config(ProptestConfig {
        // 400 cases take about 6 s; `PROPTEST_CASES=5000` soaks longer (never fewer than 400).
        cases: cases(),
        // A failing case shrinks for at most two minutes, so a failure is reported in bounded
        // time (the case printed is then the smallest found so far).
        max_shrink_time: 120_000,
        // The default persistence looks for lib.rs beside the test and finds none in tests/:
        // record failing seeds in tests/validity.proptest-regressions instead (commit it).
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("proptest-regressions"),
        )),
        ..ProptestConfig::default()
    })]

    /// Random visualization, random target between 0.2× and 5× per axis: a valid warp and a
    /// fully written output of exactly the target size.
    #[test]
    fn random_scenes_retarget_validly(scene in scene(), rx in ratio(), ry in ratio()) {
        let img = scene.draw();
        let target = Size::new(scaled(scene.width, rx), scaled(scene.height, ry)).unwrap();
        if let Err(e) = check(&img, target) {
            return Err(TestCaseError::fail(format!(
                "{}x{} -> {target} (ratios {rx} x {ry}): {e}",
                scene.width, scene.height
            )));
        }
        let out = retarget(&img, target, &Options::default())
            .map_err(|e| TestCaseError::fail(format!("retarget failed: {e}")))?;
        prop_assert_eq!(out.image.size(), target);
    }
}

// ---------------------------------------------------------------------------------------------
// Extremes on a busy image

/// A tiny deterministic RNG (xorshift64*).
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// 300×200, pastel background with a frame line and a grid line, and about a hundred discs of
/// radius 3–9 packed 1–4 px apart: many marks whose rings crowd each other.
fn busy_image() -> Image {
    let size = Size::new(300, 200).unwrap();
    let mut img = Image::filled(size, [246, 244, 236, 255]);
    fill_rect(&mut img, 0, 0, 300, 1, [90, 90, 90, 255]);
    fill_rect(&mut img, 0, 100, 300, 101, [200, 200, 200, 255]);
    fill_rect(&mut img, 150, 0, 151, 200, [200, 200, 200, 255]);
    let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
    let mut placed: Vec<(f32, f32, f32)> = Vec::new();
    let mut tries = 0;
    while placed.len() < 110 && tries < 50_000 {
        tries += 1;
        let r = 3.0 + 6.0 * rng.unit();
        let (x, y) = (
            r + 2.0 + (296.0 - 2.0 * r) * rng.unit(),
            r + 2.0 + (196.0 - 2.0 * r) * rng.unit(),
        );
        let gap = 1.0 + 3.0 * rng.unit();
        if placed
            .iter()
            .all(|&(px, py, pr)| (x - px).hypot(y - py) > r + pr + gap)
        {
            placed.push((x, y, r));
            let rgb = hsv(rng.unit(), 0.85, 0.8);
            fill_disc(&mut img, x, y, r, opaque(rgb));
        }
    }
    assert!(placed.len() >= 100, "busy image has {} discs", placed.len());
    img
}

fn extreme(rx: f64, ry: f64) {
    let img = busy_image();
    let target = Size::new(scaled(300, rx), scaled(200, ry)).unwrap();
    if let Err(e) = check(&img, target) {
        panic!("300x200 -> {target} (ratios {rx} x {ry}): {e}");
    }
}

macro_rules! extremes {
    ($($name:ident: $rx:expr, $ry:expr;)*) => {$(
        #[test]
        fn $name() {
            extreme($rx, $ry);
        }
    )*};
}

extremes! {
    busy_x0_2: 0.2, 1.0;
    busy_x5: 5.0, 1.0;
    busy_y0_2: 1.0, 0.2;
    busy_y5: 1.0, 5.0;
    busy_x0_2_y0_2: 0.2, 0.2;
    busy_x0_2_y5: 0.2, 5.0;
    busy_x5_y0_2: 5.0, 0.2;
    busy_x5_y5: 5.0, 5.0;
}
