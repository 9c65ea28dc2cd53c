//! Pictures of the method's intermediate results, for `--debug-dir` and for reading the code
//! against the paper: the VSM (Fig. 2f), its saliency levels (Fig. 6) and the mesh over the
//! image before and after the warp (Fig. 11).

use crate::baseline::{Mapping, MethodOutput};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::io::{write_atomic, write_still, OutputFormat};
use crate::mesh::Mesh;
use crate::render::{area_text_placements, AreaMaps};
use crate::retarget::Retargeted;
use crate::saliency::{SaliencyLevel, Vsm};
use crate::solve::Warp;
use crate::structure::{Line, Structure};
use glam::DVec2;
use std::path::Path;

/// The VSM as a grey-scale image (white = 1), at the image's size.
pub fn vsm_image(vsm: &Vsm) -> Image {
    per_pixel(vsm, |v| {
        let g = (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        [g, g, g, 255]
    })
}

/// An image of the VSM's size with `f` of each pixel's saliency (maps at half resolution are
/// shown with each cell over its pixels).
fn per_pixel(vsm: &Vsm, f: impl Fn(f32) -> [u8; 4]) -> Image {
    let size = vsm.size();
    let px = (0..size.height)
        .flat_map(|y| (0..size.width).map(move |x| (x, y)))
        .map(|(x, y)| f(vsm.get(x, y)))
        .collect();
    Image::from_pixels(size, px).expect("same size")
}

/// Colour of each saliency level in [`levels_image`].
pub const LEVEL_COLOURS: [[u8; 4]; 3] = [
    [245, 245, 245, 255],
    [253, 174, 97, 255],
    [215, 25, 28, 255],
];

/// The saliency levels: k = 1 light grey, k = 2 orange, k = 3 red.
pub fn levels_image(vsm: &Vsm) -> Image {
    per_pixel(vsm, |v| LEVEL_COLOURS[SaliencyLevel::of(v).index()])
}

/// `base` with the triangles' edges drawn over it (anti-aliased, blue) and vertices as dots.
pub fn mesh_overlay(base: &Image, vertices: &[DVec2], triangles: &[[u32; 3]]) -> Image {
    let mut img = base.clone();
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    for (a, b) in edges {
        draw_line(
            &mut img,
            vertices[a as usize],
            vertices[b as usize],
            [30, 80, 220],
            0.75,
        );
    }
    for &v in vertices {
        draw_dot(&mut img, v, [20, 20, 120]);
    }
    img
}

fn blend(img: &mut Image, x: i64, y: i64, rgb: [u8; 3], a: f32) {
    let Size { width, height } = img.size();
    if x < 0 || y < 0 || x >= width as i64 || y >= height as i64 || a <= 0.0 {
        return;
    }
    let p = img.get(x as u32, y as u32);
    let mix = |c: u8, d: u8| (c as f32 * (1.0 - a) + d as f32 * a + 0.5) as u8;
    img.set(
        x as u32,
        y as u32,
        [
            mix(p[0], rgb[0]),
            mix(p[1], rgb[1]),
            mix(p[2], rgb[2]),
            p[3].max((a * 255.0) as u8),
        ],
    );
}

/// Xiaolin Wu's anti-aliased line (pixel centres at `i + 0.5`).
fn draw_line(img: &mut Image, a: DVec2, b: DVec2, rgb: [u8; 3], alpha: f32) {
    let (mut a, mut b) = (a - DVec2::splat(0.5), b - DVec2::splat(0.5));
    let steep = (b.y - a.y).abs() > (b.x - a.x).abs();
    if steep {
        a = DVec2::new(a.y, a.x);
        b = DVec2::new(b.y, b.x);
    }
    if a.x > b.x {
        std::mem::swap(&mut a, &mut b);
    }
    let dx = b.x - a.x;
    let grad = if dx == 0.0 { 0.0 } else { (b.y - a.y) / dx };
    let x0 = a.x.round() as i64;
    let x1 = b.x.round() as i64;
    for x in x0..=x1 {
        let y = a.y + grad * (x as f64 - a.x);
        let yf = y.floor();
        let f = (y - yf) as f32;
        let yi = yf as i64;
        for (yy, cov) in [(yi, 1.0 - f), (yi + 1, f)] {
            if steep {
                blend(img, yy, x, rgb, cov * alpha);
            } else {
                blend(img, x, yy, rgb, cov * alpha);
            }
        }
    }
}

fn draw_dot(img: &mut Image, c: DVec2, rgb: [u8; 3]) {
    let (cx, cy) = (c.x.floor() as i64, c.y.floor() as i64);
    for dy in -1..=1 {
        for dx in -1..=1 {
            let a = if dx == 0 && dy == 0 { 1.0 } else { 0.5 };
            blend(img, cx + dx, cy + dy, rgb, a);
        }
    }
}

/// `base` with the detected structure drawn over it: horizontal lines red, vertical lines blue,
/// text blocks as green boxes, data areas as orange ones.
pub fn structure_overlay(base: &Image, s: &crate::structure::Structure) -> Image {
    let mut img = base.clone();
    for l in &s.horizontal {
        draw_line(
            &mut img,
            DVec2::new(l.from, l.pos),
            DVec2::new(l.to, l.pos),
            [230, 20, 20],
            0.9,
        );
    }
    for l in &s.vertical {
        draw_line(
            &mut img,
            DVec2::new(l.pos, l.from),
            DVec2::new(l.pos, l.to),
            [20, 60, 230],
            0.9,
        );
    }
    let boxes = s
        .text
        .iter()
        .map(|b| ([b.x0, b.y0, b.x1, b.y1].map(|v| v as f64), [20, 170, 40]))
        .chain(
            s.areas
                .iter()
                .map(|a| ([a.x0, a.y0, a.x1, a.y1], [240, 140, 0])),
        );
    for ([x0, y0, x1, y1], colour) in boxes {
        for (a, c) in [
            ((x0, y0), (x1, y0)),
            ((x1, y0), (x1, y1)),
            ((x1, y1), (x0, y1)),
            ((x0, y1), (x0, y0)),
        ] {
            draw_line(
                &mut img,
                DVec2::new(a.0, a.1),
                DVec2::new(c.0, c.1),
                colour,
                0.9,
            );
        }
    }
    img
}

/// Writes the pictures of a frame's stages into `dir` (created if missing): the VSM
/// (`vsm.png`), its levels (`levels.png`), the lines and text found (`structure.png`, and as
/// JSON in `structure.json` with where the warp put each text block under `"text_out"`), and
/// the mesh over the input and over the output (`mesh-before.png`, `mesh-after.png`). Needs
/// the frame's analysis ([`crate::Options::keep_analysis`]).
pub fn write(dir: &Path, input: &Image, out: &Retargeted) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let a = out.analysis.as_ref().ok_or_else(|| {
        Error::InvalidOptions(
            "debug pictures need the analysis kept (Options::keep_analysis)".into(),
        )
    })?;
    let structure = a.mesh.structure().cloned().unwrap_or_default();
    let pictures = [
        ("vsm.png", vsm_image(&a.vsm)),
        ("structure.png", structure_overlay(input, &structure)),
        ("levels.png", levels_image(&a.vsm)),
        (
            "mesh-before.png",
            mesh_overlay(input, a.mesh.vertices(), a.mesh.triangles()),
        ),
        (
            "mesh-after.png",
            mesh_overlay(&out.image, a.warp.positions(), a.mesh.triangles()),
        ),
    ];
    for (name, img) in pictures {
        write_still(&img, &dir.join(name), OutputFormat::Png)?;
    }
    let path = dir.join("structure.json");
    let mut json = structure_json(&structure);
    json["text_out"] = text_out_json(input, &a.mesh, &a.warp);
    write_atomic(&path, json.to_string().as_bytes())
}

/// The detected structure as JSON: lines as `[pos, from, to, width]`, text blocks as
/// `[x0, y0, x1, y1, line_height]`, in input pixels.
fn structure_json(s: &Structure) -> serde_json::Value {
    let lines = |v: &[Line]| -> Vec<serde_json::Value> {
        v.iter()
            .map(|l| serde_json::json!([l.pos, l.from, l.to, l.width]))
            .collect()
    };
    serde_json::json!({
        "horizontal": lines(&s.horizontal),
        "vertical": lines(&s.vertical),
        "text": s.text.iter().map(|b| serde_json::json!([b.x0, b.y0, b.x1, b.y1, b.line_height])).collect::<Vec<_>>(),
        "areas": s.areas.iter().map(|a| serde_json::json!([a.x0, a.y0, a.x1, a.y1, format!("{:?}", a.kind)])).collect::<Vec<_>>(),
        "bands": bands_json(&s.bands),
    })
}

/// The spans a canvas taken whole is laid out by, as `[from, to)` source columns (`_x`) or
/// rows (`_y`): text bands, gaps, margins, plots, blank runs and type.
fn bands_json(b: &crate::structure::Bands) -> serde_json::Value {
    serde_json::json!({
        "x": b.x, "y": b.y, "gaps_x": b.gaps_x, "gaps_y": b.gaps_y,
        "margins_x": b.margins_x, "margins_y": b.margins_y, "free": b.free,
        "plots_x": b.plots_x, "plots_y": b.plots_y, "blank_x": b.blank_x, "blank_y": b.blank_y,
        "type_x": b.type_x, "type_y": b.type_y,
        "panels": b.panels.as_ref().map(|p| p.leaves().iter().map(|l| serde_json::json!({"rect": l.rect, "plots": l.plots, "type": l.type_spans, "blank": l.blank, "card": l.card.as_ref().map(|c| serde_json::json!({"frame": c.frame, "inner": c.inner, "body": c.body, "stretch": c.stretch}))})).collect::<Vec<_>>()),
    })
}

/// Where the warp put each text block: `[x0, y0, x1, y1, scale]` in output pixels, the box of
/// its vertices and its width's scale (a block keeps one scale), or null for a block without
/// vertices of its own. A block inside a data area is drawn over the area's map at its own
/// scale, centred where the map takes its centre.
fn text_out_json(input: &Image, mesh: &Mesh, warp: &Warp) -> serde_json::Value {
    let out = warp.positions();
    let maps = warp.area_maps(mesh);
    // The canvas' map and placements as the render stage chose them.
    let canvas = (mesh.structure().is_some_and(|s| s.whole_canvas()))
        .then(|| crate::retarget::stages::laid_out(input, mesh, warp, warp.target()));
    let placed = mesh.structure().map_or(Vec::new(), |s| match &canvas {
        Some((_, Some(placed))) => placed.clone(),
        _ => {
            let maps = AreaMaps {
                areas: &maps,
                canvas: canvas.as_ref().map(|c| &c.0),
            };
            area_text_placements(input, s, maps, warp.target())
        }
    });
    let floated = |k: usize| -> Option<serde_json::Value> {
        let p = (*placed.get(k)?)?;
        let b = mesh.structure()?.text.get(k)?;
        let (hw, hh) = (
            p.scale * (b.x1 - b.x0) as f64 / 2.0,
            p.scale * (b.y1 - b.y0) as f64 / 2.0,
        );
        let (cx, cy) = (p.centre.x, p.centre.y);
        Some(serde_json::json!([
            cx - hw,
            cy - hh,
            cx + hw,
            cy + hh,
            p.scale
        ]))
    };
    let n = mesh.structure().map_or(0, |s| s.text.len());
    let mut boxes = vec![None::<[f64; 6]>; n];
    for (i, r) in mesh.roles().iter().enumerate() {
        let Some(k) = r.block else { continue };
        let (p, q) = (mesh.vertices()[i], out[i]);
        let b = boxes[k as usize].get_or_insert([q.x, q.y, q.x, q.y, p.x, p.x]);
        *b = [
            b[0].min(q.x),
            b[1].min(q.y),
            b[2].max(q.x),
            b[3].max(q.y),
            b[4].min(p.x),
            b[5].max(p.x),
        ];
    }
    boxes
        .iter()
        .enumerate()
        .map(|(k, b)| {
            floated(k).unwrap_or_else(|| match b {
                Some(b) if b[5] > b[4] => {
                    serde_json::json!([b[0], b[1], b[2], b[3], (b[2] - b[0]) / (b[5] - b[4])])
                }
                // Drawn by the canvas' map (text that goes with a card's body).
                _ => match (&canvas, mesh.structure().and_then(|s| s.text.get(k))) {
                    (Some((map, _)), Some(t)) => {
                        let c = glam::DVec2::new(
                            (t.x0 + t.x1) as f64 / 2.0,
                            (t.y0 + t.y1) as f64 / 2.0,
                        );
                        let [ax, bx, ay, by] = map.local(c);
                        let (hw, hh) = ((t.x1 - t.x0) as f64 / 2.0, (t.y1 - t.y0) as f64 / 2.0);
                        let (cx, cy) = (ax * c.x + bx, ay * c.y + by);
                        serde_json::json!([
                            cx - ax * hw,
                            cy - ay * hh,
                            cx + ax * hw,
                            cy + ay * hh,
                            ax
                        ])
                    }
                    _ => serde_json::Value::Null,
                },
            })
        })
        .collect()
}

/// Writes into `dir` what another method has of [`write()`]'s pictures: the saliency map and its levels
/// (all but linear), the mesh before and after (grid).
pub fn write_method(dir: &Path, input: &Image, out: &MethodOutput) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let mut pictures = Vec::new();
    if let Some(vsm) = &out.vsm {
        pictures.push(("vsm.png", vsm_image(vsm)));
        pictures.push(("levels.png", levels_image(vsm)));
    }
    if let Mapping::Warp { mesh, warp } = &out.mapping {
        pictures.push((
            "mesh-before.png",
            mesh_overlay(input, mesh.vertices(), mesh.triangles()),
        ));
        pictures.push((
            "mesh-after.png",
            mesh_overlay(&out.image, warp.positions(), mesh.triangles()),
        ));
    }
    for (name, img) in pictures {
        write_still(&img, &dir.join(name), OutputFormat::Png)?;
    }
    Ok(())
}
