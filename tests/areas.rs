//! Data areas (charts stay true): found on charts of each kind, one affine map inside each,
//! their floating marks at one scale, and nothing found where there are no axes.

use glam::DVec2;
use proptest::prelude::*;
use vizretarget::{retarget, Image, Options, Regions, Size};
use vizretarget::{AreaKind, Structure};

mod common;
use common::draw::{disc, rect};

const AXIS: [u8; 4] = [40, 40, 40, 255];
const DOT: [u8; 4] = [31, 119, 180, 255];

/// A scatter or bubble chart: an L of axes at (60, 340) spanning to (560, 30), dots of the
/// given radii at pseudo-random places inside (seeded).
fn scatter(seed: u32, radii: &[f32]) -> (Image, Vec<(f32, f32, f32)>) {
    let mut img = Image::filled(Size::new(600, 380).unwrap(), [255; 4]);
    rect(&mut img, 60, 30, 62, 340, AXIS);
    rect(&mut img, 60, 338, 560, 340, AXIS);
    let mut s = seed.max(1);
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        (s % 10_000) as f32 / 10_000.0
    };
    let mut dots: Vec<(f32, f32, f32)> = Vec::new();
    for &r in radii {
        for _ in 0..50 {
            let (x, y) = (90.0 + rnd() * 440.0, 60.0 + rnd() * 250.0);
            if dots
                .iter()
                .all(|&(a, b, q)| (a - x).hypot(b - y) > q + r + 6.0)
            {
                disc(&mut img, x, y, r, DOT);
                dots.push((x, y, r));
                break;
            }
        }
    }
    (img, dots)
}

/// A histogram: bars on a baseline, no y axis line.
fn histogram() -> Image {
    let mut img = Image::filled(Size::new(600, 380).unwrap(), [255; 4]);
    rect(&mut img, 40, 340, 560, 342, AXIS);
    for (i, h) in [60u32, 120, 200, 260, 180, 90, 40].iter().enumerate() {
        let x = 60 + 70 * i as u32;
        rect(&mut img, x, 340 - h, x + 50, 340, [148, 103, 189, 255]);
    }
    img
}

/// A heat map: cells of varied colour with white separators, no axis lines.
fn heatmap() -> Image {
    let mut img = Image::filled(Size::new(600, 380).unwrap(), [255; 4]);
    for r in 0..6u32 {
        for c in 0..9u32 {
            let v = ((r * 7 + c * 13) % 10) as u8;
            let col = [20 + 20 * v, 40 + 15 * v, 160 - 12 * v, 255];
            let (x, y) = (80 + c * 50, 40 + r * 50);
            rect(&mut img, x, y, x + 47, y + 47, col);
        }
    }
    img
}

/// A node-link graph: dots joined by slanted lines, no axes.
fn graph() -> Image {
    let mut img = Image::filled(Size::new(600, 380).unwrap(), [255; 4]);
    let nodes = [
        (100.0, 80.0),
        (300.0, 60.0),
        (500.0, 120.0),
        (200.0, 300.0),
        (420.0, 290.0),
    ];
    for (i, &(x0, y0)) in nodes.iter().enumerate() {
        let (x1, y1) = nodes[(i + 2) % nodes.len()];
        for k in 0..400 {
            let t = k as f32 / 400.0;
            disc(
                &mut img,
                x0 + t * (x1 - x0),
                y0 + t * (y1 - y0),
                1.0,
                [150, 150, 150, 255],
            );
        }
    }
    for &(x, y) in &nodes {
        disc(&mut img, x, y, 12.0, [214, 39, 40, 255]);
    }
    img
}

#[test]
fn regions_are_found_on_charts_of_each_kind_and_not_on_a_graph() {
    let (sc, _) = scatter(7, &[6.0; 20]);
    let found = |img: &Image| Structure::detect(img.as_ref()).areas;
    let a = found(&sc);
    assert_eq!(a.len(), 1, "scatter: {a:?}");
    assert_eq!(a[0].kind, AreaKind::Axes);
    assert!(
        (a[0].x0 - 61.0).abs() <= 2.0 && (a[0].y1 - 339.0).abs() <= 2.0,
        "{a:?}"
    );
    let h = found(&histogram());
    assert_eq!(h.len(), 1, "histogram: {h:?}");
    assert!(
        h[0].y0 <= 81.0 && (h[0].y1 - 341.0).abs() <= 2.0,
        "the tallest bar is in: {h:?}"
    );
    let m = found(&heatmap());
    assert_eq!(m.len(), 1, "heat map: {m:?}");
    assert!(
        m[0].x1 - m[0].x0 >= 400.0 && m[0].y1 - m[0].y0 >= 250.0,
        "{m:?}"
    );
    assert!(found(&graph()).is_empty(), "a graph has no axes");
}

#[test]
fn regions_free_and_affine_override_what_is_found() {
    let (sc, _) = scatter(7, &[6.0; 10]);
    let s = Structure::detect_with(sc.as_ref(), Regions::Free);
    assert!(s.areas.is_empty());
    let s = Structure::detect_with(graph().as_ref(), Regions::Affine);
    assert_eq!(s.areas.len(), 1);
    assert_eq!(s.areas[0].kind, AreaKind::Canvas);
}

/// Bounding boxes of the dot colour's connected blobs (4-connected), as (cx, cy, w, h).
fn blobs(img: &Image) -> Vec<(f64, f64, f64, f64)> {
    let (w, h) = (img.width() as usize, img.height() as usize);
    let is_dot = |x: usize, y: usize| {
        let p = img.get(x as u32, y as u32);
        (0..3)
            .map(|c| (p[c] as i32 - DOT[c] as i32).abs())
            .sum::<i32>()
            < 90
    };
    let mut seen = vec![false; w * h];
    let mut out = Vec::new();
    for start in 0..w * h {
        if seen[start] || !is_dot(start % w, start / w) {
            continue;
        }
        let mut stack = vec![start];
        seen[start] = true;
        let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
        while let Some(i) = stack.pop() {
            let (x, y) = (i % w, i / w);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x + 1), y1.max(y + 1));
            for (nx, ny) in [
                (x.wrapping_sub(1), y),
                (x + 1, y),
                (x, y.wrapping_sub(1)),
                (x, y + 1),
            ] {
                if nx < w && ny < h && !seen[ny * w + nx] && is_dot(nx, ny) {
                    seen[ny * w + nx] = true;
                    stack.push(ny * w + nx);
                }
            }
        }
        out.push((
            (x0 + x1) as f64 / 2.0,
            (y0 + y1) as f64 / 2.0,
            (x1 - x0) as f64,
            (y1 - y0) as f64,
        ));
    }
    out
}

/// The blob whose centre lies nearest `p`.
fn nearest(found: &[(f64, f64, f64, f64)], p: DVec2) -> (f64, f64, f64, f64) {
    *found
        .iter()
        .min_by(|a, b| {
            let da = DVec2::new(a.0, a.1).distance(p);
            let db = DVec2::new(b.0, b.1).distance(p);
            da.total_cmp(&db)
        })
        .unwrap()
}

/// With data areas found (`--regions auto`), bubbles of an area come out round, all at one
/// scale (sizes keep their proportions), and where the area's one affine map takes their
/// centres (positions read off the axes stay true).
#[test]
fn floating_marks_of_one_area_share_one_scale_and_sit_on_the_map() {
    let radii = [5.0, 8.0, 12.0, 16.0, 20.0, 7.0, 10.0, 14.0];
    let (img, dots) = scatter(11, &radii);
    let target = Size::new(300, 380).unwrap();
    let options = Options::default().with_regions(Regions::Auto);
    let out = retarget(&img, target, &options).unwrap().image;
    let found = blobs(&out);
    assert_eq!(found.len(), dots.len(), "{found:?}");
    // Match each dot to the blob nearest its linear image, then check one scale and one map.
    let mut scales = Vec::new();
    let mut pairs = Vec::new();
    for &(x, y, r) in &dots {
        let lin = DVec2::new(x as f64 * 0.5, y as f64);
        let b = nearest(&found, lin);
        let (bw, bh) = (b.2, b.3);
        assert!(
            (bw - bh).abs() <= (0.1 * bh).max(1.0),
            "a dot of radius {r} came out {bw}x{bh}: not round"
        );
        scales.push(bh / (2.0 * r as f64));
        pairs.push(((x as f64, y as f64), (b.0, b.1)));
    }
    let (lo, hi) = scales
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), &s| (a.min(s), b.max(s)));
    assert!(
        hi - lo <= 0.15,
        "one scale for one area's marks: {scales:?}"
    );
    // Centres on one axis-aligned map: fit x' = a x + b by least squares, residual small.
    for axis in 0..2 {
        let pts: Vec<(f64, f64)> = pairs
            .iter()
            .map(|&((x, y), (u, v))| if axis == 0 { (x, u) } else { (y, v) })
            .collect();
        let n = pts.len() as f64;
        let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
        let (mx, my) = (sx / n, sy / n);
        let cov: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let var: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let a = cov / var;
        let worst = pts
            .iter()
            .map(|p| (p.1 - (my + a * (p.0 - mx))).abs())
            .fold(0.0f64, f64::max);
        assert!(
            worst <= 1.5,
            "axis {axis}: a centre {worst:.2} px off the map"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Inside every data area the warp is one axis-aligned affine map: each vertex inside
    /// (not a text block's, not on the canvas border) lies where the area's map takes it, to
    /// the renderer's 1/4096-px grid, for random charts and targets.
    #[test]
    fn the_warp_is_affine_inside_every_data_area(
        seed in 1u32..10_000,
        tw in 120u32..900,
        th in 120u32..600,
    ) {
        let radii: Vec<f32> = (0..12).map(|i| 3.0 + ((seed + i * 7) % 12) as f32).collect();
        let (img, _) = scatter(seed, &radii);
        let options = Options::default().with_analysis(true);
        let out = retarget(&img, Size::new(tw, th).unwrap(), &options).unwrap();
        let a = out.analysis.as_ref().unwrap();
        let st = a.mesh.structure().unwrap();
        prop_assert!(!st.areas.is_empty());
        let maps = a.warp.area_maps(&a.mesh);
        for (k, area) in st.areas.iter().enumerate() {
            let [ax, bx, ay, by] = maps[k].expect("a map");
            prop_assert!(ax > 0.0 && ay > 0.0);
            for (i, p) in a.mesh.vertices().iter().enumerate() {
                let role = a.mesh.roles()[i];
                let b = a.mesh.boundary()[i];
                if !area.contains(p.x, p.y, 0.0) || role.block.is_some() || b.fixes_x() || b.fixes_y() {
                    continue;
                }
                let q = a.warp.positions()[i];
                let grid = 1.0 / 4096.0;
                prop_assert!((q.x - (ax * p.x + bx)).abs() <= grid, "x of {p:?}: {} vs {}", q.x, ax * p.x + bx);
                prop_assert!((q.y - (ay * p.y + by)).abs() <= grid, "y of {p:?}: {} vs {}", q.y, ay * p.y + by);
            }
        }
    }
}

/// The least-squares line `v' = a·v + b` through the pairs `(v, v')`, and the largest
/// distance of a pair from it.
fn fit(pairs: &[(f64, f64)]) -> (f64, f64, f64) {
    let n = pairs.len() as f64;
    let (mx, my) = (
        pairs.iter().map(|p| p.0).sum::<f64>() / n,
        pairs.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pairs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pairs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let a = if sxx > 0.0 { sxy / sxx } else { 1.0 };
    let b = my - a * mx;
    let worst = (pairs.iter())
        .map(|p| (p.1 - (a * p.0 + b)).abs())
        .fold(0.0, f64::max);
    (a, b, worst)
}

/// A stream of scatters: a dot moving a pixel, a small dark tick appearing (a label's
/// change), a faint speck in the margin, a dot of a new colour, a frame repeated.
fn scatter_stream() -> Vec<Image> {
    let (base, dots) = scatter(5, &[6.0, 9.0, 12.0, 7.0, 10.0]);
    let (x, y, r) = dots[0];
    let mut frames = vec![base.clone()];
    let mut moved = base.clone();
    disc(&mut moved, x, y, r + 1.0, [255; 4]);
    disc(&mut moved, x + 1.0, y, r, DOT);
    frames.push(moved.clone());
    let mut ticked = moved.clone();
    rect(&mut ticked, 20, 200, 23, 204, AXIS);
    frames.push(ticked.clone());
    // A speck in the margin: too faint for the saliency to count, a step for the bands.
    ticked.set(30, 120, [150, 150, 150, 255]);
    ticked.set(31, 120, [150, 150, 150, 255]);
    frames.push(ticked.clone());
    let mut red = ticked.clone();
    disc(&mut red, 500.0, 80.0, 8.0, [214, 39, 40, 255]);
    frames.push(red.clone());
    frames.push(red);
    frames
}

/// The frames of `stream` through the sequential core with `options`.
fn through(stream: &[Image], target: Size, options: Options) -> Vec<Image> {
    let mut r = vizretarget::Retargeter::new(target, options).unwrap();
    (stream.iter().enumerate())
        .map(|(i, f)| {
            r.send_frame(vizretarget::Frame::new(f.clone(), i as u64))
                .unwrap();
            let Ok(out) = r.receive_frame() else {
                panic!("no frame out for frame {i}");
            };
            out.image
        })
        .collect()
}

/// On a canvas taken whole every changed frame is drawn from its own pixels: the frames of a
/// stream are the frames each would give alone, whether the stream's maps are whole (the
/// analysis kept) or the importance alone, and with reuse on or off.
#[test]
fn a_canvas_streams_frames_are_the_frames_alone() {
    let stream = scatter_stream();
    let target = Size::new(300, 380).unwrap();
    let lite = through(&stream, target, Options::default());
    let whole = through(&stream, target, Options::default().with_analysis(true));
    let mut off = Options::default();
    off.reuse.enabled = false;
    let fresh = through(&stream, target, off);
    for (i, f) in stream.iter().enumerate() {
        let alone = retarget(f, target, &Options::default()).unwrap().image;
        assert!(
            lite[i] == alone,
            "frame {i}: the importance alone, in a stream"
        );
        assert!(whole[i] == alone, "frame {i}: the whole map, in a stream");
        assert!(fresh[i] == alone, "frame {i}: without reuse");
    }
    assert!(lite[1] != lite[0] && lite[4] != lite[3] && lite[5] == lite[4]);
}

#[test]
fn the_importance_alone_draws_what_the_whole_map_draws() {
    // Without the analysis kept, a canvas taken whole gets the importance alone (the blobs
    // its marks float by); kept, the whole map. The pictures must not differ.
    for seed in [3, 11, 29] {
        let (img, _) = scatter(seed, &[5.0, 9.0, 14.0, 6.0, 11.0]);
        for target in [Size::new(300, 380).unwrap(), Size::new(600, 200).unwrap()] {
            let lite = retarget(&img, target, &Options::default()).unwrap();
            let whole = retarget(&img, target, &Options::default().with_analysis(true)).unwrap();
            assert!(whole.analysis.is_some() && lite.analysis.is_none());
            assert!(lite.stats.floated > 0, "the dots float");
            assert!(lite.image == whole.image, "seed {seed} at {target:?}");
        }
    }
}

/// The default (`--regions affine`) bends nothing: every dot of a scatter comes out centred
/// where one map per axis puts it, at least the linear resize's scale (the blank margins
/// give way to the plot, nothing else does). Dots of a colour that paints only round marks
/// on a plain ground keep their shape, all at one scale (sizes keep their proportions);
/// where the same colour also paints a shape that is no mark (here an L), none of its dots
/// float, and all come out as the plot's ellipses (judged blind, round and squeezed marks
/// side by side read worse than all squeezed).
#[test]
fn the_default_keeps_positions_and_floats_a_colour_whole_or_not_at_all() {
    let radii = [5.0, 8.0, 12.0, 16.0, 20.0, 7.0, 10.0, 14.0];
    let target = Size::new(300, 380).unwrap();
    for with_l in [false, true] {
        let (mut img, dots) = scatter(11, &radii);
        if with_l {
            rect(&mut img, 566, 40, 574, 200, DOT);
            rect(&mut img, 566, 192, 596, 200, DOT);
        }
        // Filling the target: the floats over a linear map (without `fill` this picture,
        // where nothing gives way, is drawn at one scale and nothing floats).
        let fill = Options::default().with_fill(true);
        let out = retarget(&img, target, &fill).unwrap().image;
        let found = blobs(&out);
        assert_eq!(found.len(), dots.len() + with_l as usize, "{found:?}");
        let at: Vec<(f64, f64, f64, f64)> = (dots.iter())
            .map(|&(x, y, _)| nearest(&found, DVec2::new(x as f64 * 0.5, y as f64)))
            .collect();
        let xs: Vec<(f64, f64)> = (dots.iter().zip(&at))
            .map(|(d, b)| (d.0 as f64, b.0))
            .collect();
        let ys: Vec<(f64, f64)> = (dots.iter().zip(&at))
            .map(|(d, b)| (d.1 as f64, b.1))
            .collect();
        let ((ax, _, worst_x), (ay, _, worst_y)) = (fit(&xs), fit(&ys));
        assert!(
            worst_x <= 1.0 && worst_y <= 1.0,
            "off one map by {worst_x}, {worst_y}"
        );
        assert!((0.5 - 1e-3..=1.0).contains(&ax), "x scale {ax}");
        assert!((ay - 1.0).abs() < 1e-2, "y scale {ay}");
        let mut scales = Vec::new();
        for (&(_, _, r), &(_, _, bw, bh)) in dots.iter().zip(&at) {
            if with_l {
                // The plot's ellipse: as wide as its x scale makes it, as tall.
                assert!(
                    (bw - 2.0 * ax * r as f64).abs() <= 1.5 && (bh - 2.0 * r as f64).abs() <= 1.5,
                    "a dot of radius {r} came out {bw}x{bh}"
                );
            } else {
                assert!(
                    (bw - bh).abs() <= (0.1 * bh).max(1.5),
                    "a dot of radius {r} came out {bw}x{bh}: not round"
                );
                scales.push(bh / (2.0 * r as f64));
            }
        }
        if let (Some(lo), Some(hi)) = (
            scales.iter().copied().reduce(f64::min),
            scales.iter().copied().reduce(f64::max),
        ) {
            assert!(hi - lo <= 0.12, "scales {scales:?}");
        }
    }
}

/// A bar chart: axes and five bars on white, inside a 1-px frame at the canvas' edge when
/// `framed` (no blank margin then: every blank column lies inside the frame).
fn bars(framed: bool) -> Image {
    let mut img = Image::filled(Size::new(400, 240).unwrap(), [255; 4]);
    rect(&mut img, 30, 20, 32, 220, AXIS);
    rect(&mut img, 30, 218, 380, 220, AXIS);
    for (i, h) in [120u32, 80, 170, 60, 140].iter().enumerate() {
        let x = 60 + i as u32 * 60;
        rect(&mut img, x, 218 - h, x + 36, 218, [200, 80, 40, 255]);
    }
    if framed {
        rect(&mut img, 0, 0, 400, 1, AXIS);
        rect(&mut img, 0, 239, 400, 240, AXIS);
        rect(&mut img, 0, 0, 1, 240, AXIS);
        rect(&mut img, 399, 0, 400, 240, AXIS);
    }
    img
}

/// Where nothing gives way (bars and frames: no text, no blank strip at the canvas' edge),
/// the default draws the chart at one scale, the smaller of the two axes', centred on its
/// ground: exactly the linear resize of the picture to that size, with bands of its ground
/// beside it. With `fill`, exactly the linear resize to the target: a chart that is not bent
/// is drawn as a linear resize draws it, with no snapped or redrawn lines of its own.
#[test]
fn where_nothing_gives_way_the_default_draws_one_scale_and_fill_the_linear_resize() {
    let img = bars(true);
    let ground = [255, 255, 255, 255];
    for (target, content, at) in [
        ((200, 240), (200, 120), (0, 60)),
        ((400, 144), (240, 144), (80, 0)),
    ] {
        let target = Size::new(target.0, target.1).unwrap();
        let out = retarget(&img, target, &Options::default()).unwrap().image;
        let inner = Size::new(content.0, content.1).unwrap();
        let small = vizretarget::resize_linear(img.as_ref(), inner);
        for y in 0..target.height {
            for x in 0..target.width {
                let (u, v) = (x.wrapping_sub(at.0), y.wrapping_sub(at.1));
                let want = match u < inner.width && v < inner.height {
                    true => small.get(u, v),
                    false => ground,
                };
                assert_eq!(out.get(x, y), want, "{target:?} at ({x}, {y})");
            }
        }
        let fill = Options::default().with_fill(true);
        let out = retarget(&img, target, &fill).unwrap().image;
        let linear = vizretarget::resize_linear(img.as_ref(), target);
        assert!(
            out == linear,
            "{target:?}: --fill differs from the linear resize"
        );
    }
}

/// `img` retargeted to `target` by default as one frame that brings one vector dot of
/// `radius` at `at` (green).
fn with_a_dot(img: &Image, target: Size, at: DVec2, radius: f64) -> vizretarget::Retargeted {
    use vizretarget::vector::{PointMark, VectorLayer};
    let layer = VectorLayer {
        points: vec![PointMark {
            id: None,
            x: at.x,
            y: at.y,
            radius,
            fill: [20, 160, 60, 255],
            stroke: None,
        }],
        ..VectorLayer::default()
    };
    let mut r = vizretarget::Retargeter::new(target, Options::default()).unwrap();
    let frame = vizretarget::Frame::new(img.clone(), 0).with_marks(layer);
    r.send_frame(frame).unwrap();
    r.flush();
    r.receive_frame().unwrap()
}

/// A frame drawn at one scale says where ([`vizretarget::FrameStats::fitted`]); a frame that
/// brings vector marks is not drawn so (the warp places them over the whole target), and its
/// mark lands on the bar top it was given at.
#[test]
fn a_fitted_frame_says_where_and_vector_marks_keep_the_whole_target() {
    let img = bars(true);
    let target = Size::new(200, 240).unwrap();
    let plain = retarget(&img, target, &Options::default()).unwrap();
    assert_eq!(plain.stats.fitted, Some([0, 60, 200, 180]));
    // The tallest bar (third, x 180..216) tops out at y 48; a dot on it.
    let out = with_a_dot(&img, target, DVec2::new(198.0, 48.0), 4.0);
    assert_eq!(out.stats.fitted, None);
    let marks = out.marks.expect("placed marks");
    let (mx, my) = (marks.points[0].x, marks.points[0].y);
    let bar = |x: u32, y: u32| {
        let p = out.image.get(x, y);
        p[0] > 150 && p[1] < 130 && p[2] < 100
    };
    // Beside the dot (radius 4), the bar of output x 90..108.
    let top = (0..240)
        .find(|&y| bar(mx as u32 - 7, y))
        .expect("the bar beside the dot");
    assert!(
        (my - top as f64).abs() <= 2.0,
        "dot at {my}, bar top at {top}"
    );
}

/// A frame's vector marks are placed by the linear warp; the picture under them follows the
/// same map even where its blank margin would otherwise give way to the plot, so a mark
/// stays on what it marks.
#[test]
fn a_frames_vector_marks_stay_on_what_they_mark() {
    let mut img = Image::filled(Size::new(200, 100).unwrap(), [255; 4]);
    rect(&mut img, 150, 40, 190, 60, [30, 60, 200, 255]);
    let target = Size::new(100, 100).unwrap();
    // Alone, the blank margin gives way: the box is not where the linear map puts it.
    let alone = retarget(&img, target, &Options::default().with_fill(true)).unwrap();
    let blue = |out: &Image, x: u32| {
        let p = out.get(x, 50);
        p[2] > 150 && p[0] < 100
    };
    let centre = |out: &Image| {
        let xs: Vec<u32> = (0..100).filter(|&x| blue(out, x)).collect();
        (xs[0] + xs[xs.len() - 1] + 1) as f64 / 2.0
    };
    assert!(
        (centre(&alone.image) - 85.0).abs() > 3.0,
        "the map bends alone"
    );
    let out = with_a_dot(&img, target, DVec2::new(170.0, 30.0), 3.0);
    let mark_x = out.marks.expect("placed marks").points[0].x;
    assert!(
        (centre(&out.image) - mark_x).abs() <= 1.0,
        "box at {}, mark at {mark_x}",
        centre(&out.image)
    );
}

/// Bars' columns of `img` along row `y`: the runs of bar-coloured pixels, `[first, last]`.
fn bar_runs(img: &Image, y: u32) -> Vec<[u32; 2]> {
    let bar = |x: u32| {
        let p = img.get(x, y);
        p[0] > 150 && p[1] < 130
    };
    let mut runs: Vec<[u32; 2]> = Vec::new();
    for x in 0..img.width() {
        match runs.last_mut() {
            Some(r) if bar(x) && r[1] + 1 == x => r[1] = x,
            _ if bar(x) => runs.push([x, x]),
            _ => {}
        }
    }
    runs
}

/// The widths of five bars' `runs`, asserted even: equally wide and evenly spaced, to a
/// pixel.
fn even_bars(runs: &[[u32; 2]]) -> Vec<u32> {
    assert_eq!(runs.len(), 5, "{runs:?}");
    let widths: Vec<u32> = runs.iter().map(|r| r[1] - r[0] + 1).collect();
    let steps: Vec<u32> = runs.windows(2).map(|w| w[1][0] - w[0][0]).collect();
    let spread = |v: &[u32]| v.iter().max().unwrap() - v.iter().min().unwrap();
    assert!(spread(&widths) <= 1, "{widths:?}");
    assert!(spread(&steps) <= 1, "{steps:?}");
    widths
}

/// Where wide blank margins give way, the plot grows by one scale along the axis that
/// shrinks: its bars stay evenly spaced and equally wide, wider than a linear resize draws
/// them. Thin margins (the framed-less chart of [`bars`]) give nothing: a plot a few percent
/// larger is not worth margins pressed to the edge.
#[test]
fn blank_margins_give_way_to_the_plot_at_one_scale() {
    let mut img = Image::filled(Size::new(700, 240).unwrap(), [255; 4]);
    let chart = bars(false);
    for y in 0..240 {
        for x in 0..400 {
            img.set(150 + x, y, chart.get(x, y));
        }
    }
    let target = Size::new(350, 240).unwrap();
    let out = retarget(&img, target, &Options::default()).unwrap().image;
    let linear = vizretarget::resize_linear(img.as_ref(), target);
    let (runs, lin) = (bar_runs(&out, 200), bar_runs(&linear, 200));
    let widths = even_bars(&runs);
    assert!(
        widths[0] > lin[0][1] - lin[0][0] + 2,
        "{widths:?} against {lin:?}"
    );
    // Without the layout the thin margins of the chart alone give nothing (a plot a few
    // percent larger is not worth margins pressed to the edge): filling the target, the
    // linear resize.
    let fill = Options::default().with_fill(true).with_layout(false);
    let thin = retarget(&chart, Size::new(200, 240).unwrap(), &fill).unwrap();
    assert!(thin.image == vizretarget::resize_linear(chart.as_ref(), Size::new(200, 240).unwrap()));
}

/// The default layout: blank margins outside a plot give way first (to a quarter of the
/// linear scale), so the plot, one linear map, grows by a tenth or more over a linear resize
/// (its bars evenly spaced and equally wide); with the layout off, the same chart is the
/// linear resize.
#[test]
fn the_layout_lets_a_plot_take_its_blank_margins() {
    let chart = bars(false);
    let target = Size::new(200, 240).unwrap();
    let out = retarget(&chart, target, &Options::default()).unwrap();
    assert_eq!(out.stats.fitted, None, "laid out, not letterboxed");
    let linear = vizretarget::resize_linear(chart.as_ref(), target);
    let (runs, lin) = (bar_runs(&out.image, 200), bar_runs(&linear, 200));
    let widths = even_bars(&runs);
    let step = |r: &[[u32; 2]]| (r[4][0] - r[0][0]) as f64 / 4.0;
    assert!(
        step(&runs) >= 1.1 * step(&lin) - 1.0,
        "{runs:?} against {lin:?}"
    );
    assert!(widths[0] + 1 > lin[0][1] - lin[0][0], "{widths:?}");
}

/// Dark columns of `img` in `x0..x1` between rows `y0..y1`: the first and last, if any.
fn ink_columns(img: &Image, [x0, x1]: [u32; 2], [y0, y1]: [u32; 2]) -> Option<(u32, u32)> {
    let dark = |x: u32| (y0..y1).any(|y| img.get(x, y)[0] < 128);
    let first = (x0..x1).find(|&x| dark(x))?;
    let last = (x0..x1).rev().find(|&x| dark(x))?;
    Some((first, last))
}

/// Tick labels in a chart's left margin keep their width (the layout: the plot takes the
/// room they leave), while the plot keeps one scale: its bars evenly spaced and equally
/// wide. Without the layout they keep more of their width than a linear resize's half (the
/// margin's blank columns give way) and the plot at least the linear resize's scale.
#[test]
fn labels_in_a_margin_keep_their_width_and_the_plot_one_scale() {
    let mut img = Image::filled(Size::new(600, 300).unwrap(), [255; 4]);
    for (i, label) in ["1200", "800", "400"].iter().enumerate() {
        vizretarget::compare::draw_label(&mut img, 8.0, 40.0 + 80.0 * i as f32, 18.0, label);
    }
    rect(&mut img, 120, 20, 122, 280, AXIS);
    rect(&mut img, 120, 278, 590, 280, AXIS);
    for (i, h) in [120u32, 80, 170, 60, 140].iter().enumerate() {
        let x = 160 + i as u32 * 80;
        rect(&mut img, x, 278 - h, x + 40, 278, [200, 80, 40, 255]);
    }
    let target = Size::new(300, 300).unwrap();
    let out = retarget(&img, target, &Options::default()).unwrap().image;
    let linear = vizretarget::resize_linear(img.as_ref(), target);
    let rows = [35, 65];
    let (a, b) = ink_columns(&img, [0, 110], rows).expect("the label is drawn");
    let (c, d) = ink_columns(&out, [0, 55], rows).expect("the label is kept");
    let (e, f) = ink_columns(&linear, [0, 55], rows).expect("the label is resized");
    let (src, kept, squeezed) = (b - a + 1, d - c + 1, f - e + 1);
    assert!(
        kept as f64 >= 0.65 * src as f64 && kept > squeezed + 2,
        "label {src} px wide, kept {kept}, linear {squeezed}"
    );
    // Laid out, the labels keep their size (type at the author's size).
    assert!(
        kept as f64 >= 0.9 * src as f64,
        "label {src} px wide, kept {kept}"
    );
    // The plot: five bars, evenly spaced and equally wide (one linear map), at least half
    // as wide as the linear resize's (the plot takes the room the labels leave).
    let (runs, lin) = (bar_runs(&out, 270), bar_runs(&linear, 270));
    let widths = even_bars(&runs);
    assert!(
        2 * widths[0] > lin[0][1] - lin[0][0],
        "{widths:?} against {lin:?}"
    );
    // Without the layout, the text bands alone give way: the plot keeps at least the
    // linear resize's scale.
    let bands = retarget(&img, target, &Options::default().with_layout(false)).unwrap();
    let widths = even_bars(&bar_runs(&bands.image, 270));
    assert!(
        widths[0] >= lin[0][1] - lin[0][0],
        "{widths:?} against {lin:?}"
    );
}

/// Paints `c` over `img` where `inside` holds, antialiased: each pixel takes the share of
/// its 4 × 4 samples inside, within the box `[x0, y0, x1, y1)`.
fn paint_aa(
    img: &mut Image,
    [x0, y0, x1, y1]: [f32; 4],
    c: [u8; 4],
    inside: impl Fn(f32, f32) -> bool,
) {
    let (w, h) = (img.width() as f32, img.height() as f32);
    for y in y0.max(0.0) as u32..y1.min(h) as u32 {
        for x in x0.max(0.0) as u32..x1.min(w) as u32 {
            let n = (0..16)
                .filter(|k| {
                    inside(
                        x as f32 + (k % 4) as f32 / 4.0 + 0.125,
                        y as f32 + (k / 4) as f32 / 4.0 + 0.125,
                    )
                })
                .count();
            if n > 0 {
                let a = n as f32 / 16.0;
                let p = img.get(x, y);
                let q =
                    [0, 1, 2].map(|i| (p[i] as f32 * (1.0 - a) + c[i] as f32 * a).round() as u8);
                img.set(x, y, [q[0], q[1], q[2], 255]);
            }
        }
    }
}

/// A node-link graph whose black nodes are where many antialiased lines of two colours
/// meet (graph-03's): the lines' pale edges and their crossings make the ground around a
/// node busy, yet it is a mark standing alone. At half width, the default floats the nodes
/// round, all alike, as a linear resize would not.
#[test]
fn nodes_where_lines_of_two_colours_meet_stay_round() {
    let mut img = Image::filled(Size::new(640, 400).unwrap(), [255; 4]);
    let nodes: Vec<(f32, f32)> = (0..12)
        .map(|i| {
            let (col, row) = ((i % 4) as f32, (i / 4) as f32);
            (
                90.0 + 150.0 * col + 17.0 * row,
                70.0 + 130.0 * row + 11.0 * col,
            )
        })
        .collect();
    let colours = [[248, 118, 109, 255], [0, 191, 196, 255]];
    for (i, &(ax, ay)) in nodes.iter().enumerate() {
        for (k, j) in [i + 1, i + 3, i + 4, i + 5].into_iter().enumerate() {
            let Some(&(bx, by)) = nodes.get(j) else {
                continue;
            };
            let (dx, dy) = (bx - ax, by - ay);
            let len2 = dx * dx + dy * dy;
            let on_line = |x: f32, y: f32| {
                let t = (((x - ax) * dx + (y - ay) * dy) / len2).clamp(0.0, 1.0);
                let (px, py) = (ax + t * dx - x, ay + t * dy - y);
                px * px + py * py <= 1.1 * 1.1
            };
            let bbox = [
                ax.min(bx) - 2.0,
                ay.min(by) - 2.0,
                ax.max(bx) + 2.0,
                ay.max(by) + 2.0,
            ];
            paint_aa(&mut img, bbox, colours[(i + k) % 2], on_line);
        }
    }
    for &(cx, cy) in &nodes {
        let r = 6.5;
        let bbox = [cx - r - 1.0, cy - r - 1.0, cx + r + 1.0, cy + r + 1.0];
        paint_aa(&mut img, bbox, [0, 0, 0, 255], |x, y| {
            (x - cx).powi(2) + (y - cy).powi(2) <= r * r
        });
    }
    let out = retarget(&img, Size::new(320, 400).unwrap(), &Options::default())
        .unwrap()
        .image;
    // Each node's box: the 8-connected blobs of dark pixels, one per node.
    let boxes = dark_blobs(&out, |p| p[..3].iter().all(|&v| v < 90));
    assert_eq!(boxes.len(), nodes.len(), "{boxes:?}");
    for &(bw, bh) in &boxes {
        assert!(bw.abs_diff(bh) <= 1 && bw >= 6, "nodes {boxes:?}");
    }
}

/// The sizes `(w, h)` of the boxes of the 8-connected blobs of pixels of `out` that are `ink`.
fn dark_blobs(out: &Image, ink: impl Fn([u8; 4]) -> bool) -> Vec<(u32, u32)> {
    let (w, h) = (out.width(), out.height());
    let dark = |x: u32, y: u32| ink(out.get(x, y));
    let mut seen = vec![false; (w * h) as usize];
    let mut boxes = Vec::new();
    for start in 0..w * h {
        if seen[start as usize] || !dark(start % w, start / w) {
            continue;
        }
        let (mut stack, mut b) = (vec![start], [u32::MAX, u32::MAX, 0, 0]);
        seen[start as usize] = true;
        while let Some(i) = stack.pop() {
            let (x, y) = (i % w, i / w);
            b = [b[0].min(x), b[1].min(y), b[2].max(x + 1), b[3].max(y + 1)];
            for (nx, ny) in
                (-1i64..=1).flat_map(|dy| (-1i64..=1).map(move |dx| (x as i64 + dx, y as i64 + dy)))
            {
                if nx >= 0 && ny >= 0 && nx < w as i64 && ny < h as i64 {
                    let j = (ny as u32 * w + nx as u32) as usize;
                    if !seen[j] && dark(nx as u32, ny as u32) {
                        seen[j] = true;
                        stack.push(j as u32);
                    }
                }
            }
        }
        boxes.push((b[2] - b[0], b[3] - b[1]));
    }
    boxes
}
