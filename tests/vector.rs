//! Vector marks bound to the mesh (§5.3) and content enhancement (§5.4): the marks vizretarget
//! draws are round, sit where the deformed mesh carries their centres, none is lost; edges
//! follow their nodes; an enhanced region grows its marks without folding the mesh; JSON
//! errors name the file and line; streams carry marks and enhancement on every frame.

use glam::DVec2;
use std::sync::Arc;
use vizretarget::io::{FrameMarks, MarkedSource};
use vizretarget::stream::{NoProgress, VecSink, VecSource};
use vizretarget::vector::{parse_layer, PointMark};
use vizretarget::{
    retarget, Frame, FrameSource, Image, Mesh, Options, Pipeline, Retargeted, Retargeter, Size,
    VectorLayer, Warp,
};
use vizretarget::{EnhanceRegion, Enhancement};

const COLOURS: [[u8; 4]; 5] = [
    [215, 25, 28, 255],
    [44, 123, 182, 255],
    [26, 150, 65, 255],
    [230, 97, 1, 255],
    [123, 50, 148, 255],
];

/// A light map without marks: sea, and pastel land masses.
fn background(size: Size) -> Image {
    let mut img = Image::filled(size, [236, 244, 250, 255]);
    let (w, h) = (size.width as f64, size.height as f64);
    let lands = [(0.25, 0.4, 0.18), (0.7, 0.6, 0.22), (0.5, 0.15, 0.1)];
    for y in 0..size.height {
        for x in 0..size.width {
            let (fx, fy) = (x as f64 / w, y as f64 / h);
            for (i, &(cx, cy, r)) in lands.iter().enumerate() {
                let wobble = 1.0 + 0.15 * ((fx * 17.0 + i as f64).sin() * (fy * 13.0).cos());
                if ((fx - cx) * 1.6).powi(2) + (fy - cy).powi(2) < (r * wobble).powi(2) {
                    img.set(
                        x,
                        y,
                        [
                            [204, 235, 197, 255],
                            [254, 232, 200, 255],
                            [222, 203, 228, 255],
                        ][i],
                    );
                }
            }
        }
    }
    img
}

struct Rng(u32);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        (self.0 % 100_000) as f64 / 100_000.0
    }
}

/// `n` circles of radius `r0` to `r1` px, at least 3.2 radii apart, at least 2 radii from the
/// sides, on quarter pixels (exact in JSON).
fn circles(size: Size, n: usize, seed: u32, (r0, r1): (f64, f64)) -> VectorLayer {
    let mut rng = Rng(seed);
    let mut points: Vec<PointMark> = Vec::new();
    let (w, h) = (size.width as f64, size.height as f64);
    let q = |v: f64| (v * 4.0).round() / 4.0;
    while points.len() < n {
        let r = q(r0 + (r1 - r0) * rng.next());
        let m = 2.0 * r1;
        let (x, y) = (
            q(m + rng.next() * (w - 2.0 * m)),
            q(m + rng.next() * (h - 2.0 * m)),
        );
        if points
            .iter()
            .any(|p| (p.x - x).hypot(p.y - y) < 3.2 * p.radius.max(r))
        {
            continue;
        }
        points.push(PointMark {
            id: Some(format!("m{}", points.len())),
            x,
            y,
            radius: r,
            fill: COLOURS[points.len() % COLOURS.len()],
            stroke: None,
        });
    }
    VectorLayer {
        points,
        ..VectorLayer::default()
    }
}

/// A blob of one marker colour: pixel count, centroid (pixel centres), roundness as
/// `eval_markers.py` measures it (√ of the covariance eigenvalues' ratio).
#[derive(Debug)]
struct Blob {
    colour: usize,
    area: usize,
    centre: DVec2,
    roundness: f64,
}

impl Blob {
    /// Radius of the disc of the same area.
    fn radius(&self) -> f64 {
        (self.area as f64 / std::f64::consts::PI).sqrt()
    }
}

fn blobs(img: &Image) -> Vec<Blob> {
    let (w, h) = (img.width() as usize, img.height() as usize);
    let mut out = Vec::new();
    for (ci, c) in COLOURS.iter().enumerate() {
        let on: Vec<bool> = img
            .pixels()
            .iter()
            .map(|p| {
                (0..3)
                    .map(|k| (p[k] as f64 - c[k] as f64).powi(2))
                    .sum::<f64>()
                    .sqrt()
                    < 70.0
            })
            .collect();
        let mut seen = vec![false; w * h];
        for start in 0..w * h {
            if !on[start] || seen[start] {
                continue;
            }
            seen[start] = true;
            let mut stack = vec![start];
            let mut pts = Vec::new();
            while let Some(i) = stack.pop() {
                let (x, y) = (i % w, i / w);
                pts.push(DVec2::new(x as f64 + 0.5, y as f64 + 0.5));
                for dy in -1i64..=1 {
                    for dx in -1i64..=1 {
                        let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                        if nx >= 0 && ny >= 0 && (nx as usize) < w && (ny as usize) < h {
                            let j = ny as usize * w + nx as usize;
                            if on[j] && !seen[j] {
                                seen[j] = true;
                                stack.push(j);
                            }
                        }
                    }
                }
            }
            if pts.len() < 8 {
                continue;
            }
            let m = pts.iter().copied().sum::<DVec2>() / pts.len() as f64;
            let (mut xx, mut yy, mut xy) = (0.0, 0.0, 0.0);
            for p in &pts {
                let d = *p - m;
                xx += d.x * d.x;
                yy += d.y * d.y;
                xy += d.x * d.y;
            }
            let (tr, det) = (xx + yy, xx * yy - xy * xy);
            let disc = (tr * tr / 4.0 - det).max(0.0).sqrt();
            let roundness = ((tr / 2.0 - disc).max(1e-12) / (tr / 2.0 + disc)).sqrt();
            out.push(Blob {
                colour: ci,
                area: pts.len(),
                centre: m,
                roundness,
            });
        }
    }
    out
}

/// Where the deformed mesh carries source point `p`: barycentric coordinates in the source
/// triangle holding it, applied to that triangle's deformed vertices (independent of the
/// library's own locator).
fn carried(mesh: &Mesh, warp: &Warp, p: DVec2) -> DVec2 {
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let s = mesh.triangle_points(t);
        let d = (s[1] - s[0]).perp_dot(s[2] - s[0]);
        let b1 = (p - s[0]).perp_dot(s[2] - s[0]) / d;
        let b2 = (s[1] - s[0]).perp_dot(p - s[0]) / d;
        let b0 = 1.0 - b1 - b2;
        if b0 >= -1e-9 && b1 >= -1e-9 && b2 >= -1e-9 {
            let q = tri.map(|v| warp.positions()[v as usize]);
            return q[0] * b0 + q[1] * b1 + q[2] * b2;
        }
    }
    panic!("{p} is in no triangle");
}

/// The blob of `colour` nearest to `p`.
fn nearest(blobs: &[Blob], colour: [u8; 4], p: DVec2) -> &Blob {
    let ci = COLOURS.iter().position(|c| *c == colour).unwrap();
    blobs
        .iter()
        .filter(|b| b.colour == ci)
        .min_by(|a, b| a.centre.distance(p).total_cmp(&b.centre.distance(p)))
        .expect("a blob of the mark's colour")
}

fn with_analysis(marks: VectorLayer) -> Options {
    Options::default().with_analysis(true).with_marks(marks)
}

/// The issue's first case: a background with no marks plus 40 circles as JSON, to half width.
#[test]
fn forty_circles_at_half_width_are_round_in_place_and_all_there() {
    let size = Size::new(960, 600).unwrap();
    let layer = circles(size, 40, 11, (12.0, 16.0));
    // Through the JSON format, as a user would give them.
    let json = serde_json::json!({
        "points": layer.points.iter().map(|p| serde_json::json!({
            "id": p.id, "x": p.x, "y": p.y, "r": p.radius,
            "fill": [p.fill[0], p.fill[1], p.fill[2]],
        })).collect::<Vec<_>>()
    });
    let parsed = parse_layer(&json.to_string()).unwrap();
    assert_eq!(parsed, layer);
    let target = Size::new(480, 600).unwrap();
    let out = retarget(&background(size), target, &with_analysis(parsed)).unwrap();
    assert_eq!(out.image.size(), target);
    let a = out.analysis.as_ref().unwrap();
    assert_eq!(a.warp.folded_triangles(&a.mesh), 0);
    let placed = out.marks.as_ref().expect("placed marks");
    assert_eq!(placed.points.len(), 40);
    let found = blobs(&out.image);
    assert_eq!(found.len(), 40, "blobs found: {}", found.len());
    let mut worst_round: f64 = 1.0;
    let mut worst_offset: f64 = 0.0;
    for (src, p) in layer.points.iter().zip(&placed.points) {
        let want = carried(&a.mesh, &a.warp, DVec2::new(src.x, src.y));
        let at = DVec2::new(p.x, p.y);
        assert!(
            at.distance(want) < 1e-6,
            "placed {at}, mesh carries to {want}"
        );
        let b = nearest(&found, src.fill, want);
        worst_offset = worst_offset.max(b.centre.distance(want));
        worst_round = worst_round.min(b.roundness);
        assert!(
            p.radius > 0.5 * src.radius && p.radius <= src.radius * 1.01,
            "{}",
            p.radius
        );
    }
    eprintln!(
        "40 circles: worst roundness {worst_round:.4}, worst centre offset {worst_offset:.3} px"
    );
    assert!(
        worst_offset <= 1.0,
        "a drawn centre is {worst_offset} px off"
    );
    assert!(worst_round >= 0.98, "roundness {worst_round}");
}

/// A mark centre is a mesh vertex, and goes exactly where the warp takes that vertex.
#[test]
fn mark_centres_are_vertices_and_map_exactly() {
    let size = Size::new(320, 200).unwrap();
    let layer = circles(size, 12, 5, (6.0, 9.0));
    let out = retarget(
        &background(size),
        Size::new(200, 260).unwrap(),
        &with_analysis(layer.clone()),
    )
    .unwrap();
    let a = out.analysis.as_ref().unwrap();
    let placed = out.marks.as_ref().unwrap();
    for (src, p) in layer.points.iter().zip(&placed.points) {
        let c = DVec2::new(src.x, src.y);
        let v = a
            .mesh
            .vertices()
            .iter()
            .position(|q| q.distance(c) < 1e-3)
            .expect("the centre is a vertex");
        assert!(DVec2::new(p.x, p.y).distance(a.warp.positions()[v]) < 1e-3);
    }
}

/// Edges run from node centre to node centre wherever the nodes go.
#[test]
fn edges_follow_their_nodes() {
    let size = Size::new(360, 240).unwrap();
    let text = r##"{
      "points": [
        {"id": "a", "x": 60, "y": 60, "r": 7, "fill": "#d7191c"},
        {"id": "b", "x": 300, "y": 70, "r": 7, "fill": "#2c7bb6"},
        {"id": "c", "x": 180, "y": 190, "r": 7, "fill": "#1a9641"}
      ],
      "edges": [
        {"from": "a", "to": "b", "width": 2, "color": "#000000"},
        {"from": 1, "to": 2, "width": 2, "color": "#000000"},
        {"from": "c", "to": 0, "width": 2, "color": "#000000"}
      ]
    }"##;
    let layer = parse_layer(text).unwrap();
    let out = retarget(
        &background(size),
        Size::new(180, 240).unwrap(),
        &with_analysis(layer.clone()),
    )
    .unwrap();
    let a = out.analysis.as_ref().unwrap();
    let placed = out.marks.as_ref().unwrap();
    assert_eq!(placed.edges, layer.edges);
    for e in &placed.edges {
        for (i, end) in [(e.from, 0.0), (e.to, 1.0)] {
            let src = &layer.points[i];
            let want = carried(&a.mesh, &a.warp, DVec2::new(src.x, src.y));
            let p = &placed.points[i];
            assert!(DVec2::new(p.x, p.y).distance(want) < 1e-6, "end {end}");
        }
        // Drawn: black pixels along the segment between the carried nodes, outside the discs.
        let (p, q) = (&placed.points[e.from], &placed.points[e.to]);
        let (p, q) = (DVec2::new(p.x, p.y), DVec2::new(q.x, q.y));
        for k in 1..10 {
            let m = p + (q - p) * (k as f64 / 10.0);
            if m.distance(p) < 10.0 || m.distance(q) < 10.0 {
                continue;
            }
            let px = out.image.get(m.x as u32, m.y as u32);
            assert!(px[0] < 128 && px[1] < 128 && px[2] < 128, "{px:?} at {m}");
        }
    }
    // The nodes are drawn over their edges: each node's centre has its own colour.
    for p in &placed.points {
        assert_eq!(out.image.get(p.x as u32, p.y as u32), p.fill);
    }
}

/// The issue's second case: a region enhanced by 1.5 at an unchanged canvas size.
#[test]
fn an_enhanced_region_grows_its_marks_at_the_same_size() {
    let size = Size::new(480, 320).unwrap();
    let layer = circles(size, 24, 23, (7.0, 10.0));
    let region = EnhanceRegion {
        x: 150.0,
        y: 90.0,
        width: 180.0,
        height: 140.0,
        factor: 1.5,
    };
    let inside = |p: &PointMark| {
        p.x > region.x + p.radius
            && p.x < region.x + region.width - p.radius
            && p.y > region.y + p.radius
            && p.y < region.y + region.height - p.radius
    };
    assert!(layer.points.iter().filter(|p| inside(p)).count() >= 3);
    let bg = background(size);
    let plain = retarget(&bg, size, &with_analysis(layer.clone())).unwrap();
    let options = with_analysis(layer.clone()).with_enhancement(Enhancement {
        regions: vec![region],
        ..Enhancement::default()
    });
    let out = retarget(&bg, size, &options).unwrap();
    assert_eq!(out.image.size(), size);
    let a = out.analysis.as_ref().unwrap();
    assert_eq!(a.warp.folded_triangles(&a.mesh), 0);
    let (before, after) = (blobs(&plain.image), blobs(&out.image));
    assert_eq!(after.len(), 24);
    let placed = out.marks.as_ref().unwrap();
    let placed_plain = plain.marks.as_ref().unwrap();
    let mut least: f64 = f64::INFINITY;
    let ins: Vec<usize> = (0..layer.points.len())
        .filter(|&i| inside(&layer.points[i]))
        .collect();
    for &i in &ins {
        let src = &layer.points[i];
        let b0 = nearest(
            &before,
            src.fill,
            DVec2::new(placed_plain.points[i].x, placed_plain.points[i].y),
        );
        let b1 = nearest(
            &after,
            src.fill,
            DVec2::new(placed.points[i].x, placed.points[i].y),
        );
        let growth = b1.radius() / b0.radius();
        least = least.min(growth);
        assert!(
            growth >= 1.3,
            "mark {i}: area-equivalent radius grew {growth:.3}x"
        );
    }
    // The region grows as one piece: the gaps between its marks grow too, so enlarged marks
    // do not run into each other.
    let at = |l: &VectorLayer, i: usize| DVec2::new(l.points[i].x, l.points[i].y);
    let mut spread: f64 = f64::INFINITY;
    for (k, &i) in ins.iter().enumerate() {
        for &j in &ins[k + 1..] {
            let d0 = at(placed_plain, i).distance(at(placed_plain, j));
            spread = spread.min(at(placed, i).distance(at(placed, j)) / d0);
        }
    }
    eprintln!(
        "region x1.5: {} marks, radius grew >= {least:.3}x, spacing >= {spread:.3}x",
        ins.len()
    );
    assert!(spread >= 1.3, "the spacing of marks grew only {spread:.3}x");
}

/// Levels: enlarging level 3 (the marks, salient) at the same size grows every mark.
#[test]
fn a_level_factor_grows_salient_marks() {
    let size = Size::new(400, 260).unwrap();
    let layer = circles(size, 10, 3, (6.0, 9.0));
    let options = Options::default()
        .with_marks(layer.clone())
        .with_enhancement(Enhancement {
            per_level: [1.0, 1.0, 1.4],
            ..Enhancement::default()
        });
    let out = retarget(&background(size), size, &options).unwrap();
    let placed = out.marks.as_ref().unwrap();
    let grown = layer
        .points
        .iter()
        .zip(&placed.points)
        .filter(|(s, p)| p.radius > 1.2 * s.radius)
        .count();
    assert!(grown >= 8, "{grown} of 10 marks grew by 20 % or more");
}

fn write(path: &std::path::Path, text: &str) {
    std::fs::write(path, text).unwrap();
}

/// JSON errors name the file and the line; a JSON Lines file shorter than the stream is an
/// error naming the file and the frame.
#[test]
fn errors_name_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.json");
    write(
        &bad,
        "{\n  \"points\": [\n    {\"x\": 1, \"y\": 2, \"r\": 3,}\n  ]\n}\n",
    );
    let e = vizretarget::vector::read_layer(&bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.json") && e.contains("line 3"), "{e}");

    let lines = dir.path().join("marks.jsonl");
    write(
        &lines,
        "{\"points\": [{\"x\": 10, \"y\": 10, \"r\": 4}]}\n\n{}\n{\"points\": [{\"x\": 1}]}\n",
    );
    let mut marks = FrameMarks::open(&lines, None).unwrap();
    assert_eq!(marks.for_frame(0).unwrap().unwrap().points.len(), 1);
    assert!(marks.for_frame(1).unwrap().unwrap().is_empty());
    let e = marks.for_frame(2).unwrap_err().to_string();
    assert!(
        e.contains("marks.jsonl: line 4") && e.contains("missing field"),
        "{e}"
    );

    let short = dir.path().join("short.jsonl");
    write(&short, "{}\n{}\n");
    let frames: Vec<Frame> = (0..3)
        .map(|i| Frame::new(Image::filled(Size::new(40, 30).unwrap(), [250; 4]), i))
        .collect();
    let mut source = MarkedSource::new(
        Box::new(VecSource::new(frames)),
        FrameMarks::open(&short, None).unwrap(),
    );
    assert!(source.next_frame().unwrap().is_some());
    assert!(source.next_frame().unwrap().is_some());
    let e = source.next_frame().unwrap_err().to_string();
    assert!(
        e.contains("short.jsonl") && e.contains("2 frame(s)") && e.contains("frame 3"),
        "{e}"
    );
    // Out-of-range numbers in a layer built in code: a clear error, not a panic.
    let mut layer = circles(Size::new(100, 100).unwrap(), 1, 1, (4.0, 5.0));
    layer.points[0].x = f64::NAN;
    let e = retarget(
        &Image::filled(Size::new(100, 100).unwrap(), [255; 4]),
        Size::new(50, 100).unwrap(),
        &Options::default().with_marks(layer),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("points[0]"), "{e}");
}

/// Sidecars beside frame files, found by name.
#[test]
fn sidecars_give_each_frame_its_marks() {
    let dir = tempfile::tempdir().unwrap();
    let size = Size::new(120, 80).unwrap();
    for i in 0..3 {
        let p = dir.path().join(format!("frame-{i:04}.png"));
        vizretarget::io::write_still(&background(size), &p, vizretarget::io::OutputFormat::Png)
            .unwrap();
        if i != 1 {
            write(
                &dir.path().join(format!("frame-{i:04}.json")),
                &format!(
                    "{{\"points\": [{{\"x\": {}, \"y\": 40, \"r\": 5}}]}}",
                    30 + 20 * i
                ),
            );
        }
    }
    let input =
        vizretarget::io::open_input(dir.path(), vizretarget::io::InputFormat::Auto, None).unwrap();
    let names = input.names.clone();
    let mut source = MarkedSource::new(input.source, FrameMarks::open(dir.path(), names).unwrap());
    let xs: Vec<Option<f64>> = std::iter::from_fn(|| source.next_frame().unwrap())
        .map(|f| f.marks.map(|m| m.points[0].x))
        .collect();
    assert_eq!(xs, vec![Some(30.0), None, Some(70.0)]);
}

fn region_stream_options(layer: Option<VectorLayer>) -> Options {
    let mut o = Options::default().with_enhancement(Enhancement {
        regions: vec![EnhanceRegion {
            x: 100.0,
            y: 60.0,
            width: 160.0,
            height: 120.0,
            factor: 1.5,
        }],
        ..Enhancement::default()
    });
    o.marks = layer.map(Arc::new);
    o
}

/// Streams: the factors apply to every frame, the marks come with every frame, and the
/// threaded pipeline gives the sequential core's frames.
#[test]
fn a_stream_enhances_every_frame() {
    let size = Size::new(360, 240).unwrap();
    let layer = circles(size, 16, 9, (6.0, 9.0));
    let inside: Vec<usize> = (0..layer.points.len())
        .filter(|&i| {
            let p = &layer.points[i];
            p.x > 110.0 && p.x < 250.0 && p.y > 70.0 && p.y < 170.0
        })
        .collect();
    assert!(!inside.is_empty());
    let bg = background(size);
    // Frames differ (a moving dark square in a corner), so each is processed anew.
    let frames: Vec<Frame> = (0..3u32)
        .map(|i| {
            let mut img = bg.clone();
            for y in 200..220 {
                for x in 10 + 30 * i..30 + 30 * i {
                    img.set(x, y, [40, 40, 40, 255]);
                }
            }
            Frame::new(img, i as u64).with_marks(layer.clone())
        })
        .collect();
    let plain = retarget(&bg, size, &Options::default().with_marks(layer.clone())).unwrap();
    let options = region_stream_options(None);
    let mut sink = VecSink::default();
    Pipeline::new(size, &options)
        .unwrap()
        .run(
            &mut VecSource::new(frames.clone()),
            &mut sink,
            &NoProgress,
            &Default::default(),
        )
        .unwrap();
    assert_eq!(sink.frames.len(), 3);
    let mut seq = Retargeter::new(size, options).unwrap();
    let plain_marks = plain.marks.as_ref().unwrap();
    for (f, out) in frames.into_iter().zip(&sink.frames) {
        seq.send_frame(f).unwrap();
        let s: Retargeted = seq.receive_frame().unwrap();
        assert_eq!(s.image, out.image, "threaded == sequential");
        let placed = out.marks.as_ref().expect("marks on every frame");
        let found = blobs(&out.image);
        for &i in &inside {
            let src = &layer.points[i];
            let r0 = plain_marks.points[i].radius;
            assert!(
                placed.points[i].radius >= 1.3 * r0,
                "frame {}: mark {i}",
                out.frame_index
            );
            let b = nearest(
                &found,
                src.fill,
                DVec2::new(placed.points[i].x, placed.points[i].y),
            );
            assert!(
                b.radius() >= 1.3 * r0 * 0.95,
                "frame {}: drawn radius {}",
                out.frame_index,
                b.radius()
            );
        }
    }
}

/// Painting out: a raster that shows the marks too gets them filled from around before they
/// are redrawn, so each appears once (no warped copy beside the drawn one).
#[test]
fn painting_out_leaves_each_mark_once() {
    let size = Size::new(300, 200).unwrap();
    let layer = circles(size, 10, 17, (6.0, 9.0));
    let mut img = background(size);
    layer.draw(&mut img);
    let mut options = Options::default().with_marks(layer.clone());
    options.vector.paint_out = true;
    let out = retarget(&img, Size::new(150, 200).unwrap(), &options).unwrap();
    assert_eq!(blobs(&out.image).len(), 10);
}

/// A static stream with static marks reuses mesh and solution and gives identical frames; a
/// mark that moves rebuilds, and lands where the new mesh carries it.
#[test]
fn static_marks_reuse_and_moving_marks_follow() {
    let size = Size::new(320, 200).unwrap();
    let layer = circles(size, 8, 31, (6.0, 8.0));
    let bg = background(size);
    let target = Size::new(200, 200).unwrap();
    let mut r = Retargeter::new(target, Options::default().with_analysis(true)).unwrap();
    let mut outs = Vec::new();
    for i in 0..4u64 {
        let mut l = layer.clone();
        if i == 3 {
            l.points[0].x += 12.0;
        }
        r.send_frame(Frame::new(bg.clone(), i).with_marks(l))
            .unwrap();
        outs.push(r.receive_frame().unwrap());
    }
    use vizretarget::Decision;
    assert_eq!(outs[0].stats.decision, Decision::Rebuild);
    for o in &outs[1..3] {
        assert_eq!(o.stats.decision, Decision::Reuse, "frame {}", o.frame_index);
        assert_eq!(o.image, outs[0].image);
    }
    let last = &outs[3];
    assert_eq!(last.stats.decision, Decision::Rebuild);
    let a = last.analysis.as_ref().unwrap();
    let p = &last.marks.as_ref().unwrap().points[0];
    let want = carried(
        &a.mesh,
        &a.warp,
        DVec2::new(layer.points[0].x + 12.0, layer.points[0].y),
    );
    assert!(DVec2::new(p.x, p.y).distance(want) < 1e-6);
}
