//! Stage 4: the render (§5.2's warp drawn crisp), only of what changed when the previous
//! frame's output can be kept, with the frame's floating marks drawn over it, its vector marks
//! placed and drawn, and its output record.

use super::{ms, Meshed, WithWarp};
use crate::error::Error;
use crate::image::Image;
use crate::mesh::{Mark, Mesh};
use crate::render::{
    resize_mapped_on, AreaMaps, CanvasMap, Fit, Floating, MaskKind, Renderer, Threads,
};
use crate::retarget::frame::{Analysis, FrameStats, Retargeted, StageTimes};
use crate::retarget::options::Options;
use crate::retarget::reuse::Decision;
use crate::saliency::Vsm;
use crate::solve::Warp;
use crate::structure::Structure;
use crate::tiles::TileMask;
use crate::vector::{overlay, VectorLayer, VectorOptions};
use glam::DVec2;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;
use std::time::Instant;

/// Stage 4: the render, only of what changed when the previous frame's output can be kept,
/// with the frame's floating marks drawn over it.
pub(crate) struct RenderStage {
    renderer: Renderer,
    /// How vector marks are placed and drawn over the render.
    vector: VectorOptions,
    /// Keep each frame's VSM, mesh and warp in its output.
    keep_analysis: bool,
    prev: Option<Previous>,
    /// The source with floating marks painted out, and the mask buffer that paints them.
    painted: Option<Image>,
    scratch: Vec<bool>,
    /// How many marks and text blocks the last frame drew floating, and dropped.
    floated: usize,
    dropped: usize,
    /// Panels the last frame's canvas was laid out in.
    panels: usize,
    /// Where the last frame was drawn at one scale ([`Fit`]), if it was.
    fitted: Option<[u32; 4]>,
    /// Fill the target where nothing gives way ([`Options::fill`]) instead of a [`Fit`].
    fill: bool,
    /// Lay the plots out around their parts ([`Options::layout`]).
    layout: bool,
    /// Threads of a canvas' resize: all cores for a frame alone, one inside the threaded
    /// pipeline ([`RenderStage::in_pipeline`]).
    threads: Threads,
}

struct Previous {
    mesh: Arc<Mesh>,
    warp: Arc<Warp>,
    image: Image,
    opaque: bool,
    floating: Floating,
    /// The mesh stage's marks it was drawn with.
    marks: Arc<Vec<Mark>>,
}

impl RenderStage {
    pub fn new(options: &Options) -> RenderStage {
        RenderStage {
            renderer: Renderer::default(),
            vector: options.vector.clone(),
            keep_analysis: options.keep_analysis,
            prev: None,
            painted: None,
            scratch: Vec::new(),
            floated: 0,
            dropped: 0,
            panels: 0,
            fitted: None,
            fill: options.fill,
            layout: options.layout,
            threads: Threads::AllCores,
        }
    }

    /// The stage as one of the threaded pipeline's: the other stages keep the cores busy
    /// with other frames, so its resize runs on its own thread (the same bytes, in less time
    /// than threads that contend with those stages).
    pub fn in_pipeline(mut self) -> RenderStage {
        self.threads = Threads::One;
        self
    }

    /// The retargeted frame: the warped raster, the marks floating over it, the vector marks
    /// placed and drawn (§5.3), and the frame's statistics.
    pub fn run(&mut self, m: WithWarp) -> Result<Retargeted, Error> {
        let t = Instant::now();
        let mut image = self.draw(&m);
        let marks = m
            .frame
            .marks
            .as_ref()
            .map(|l| overlay(&mut image, l, &m.meshed.mesh, &m.solved.warp, &self.vector));
        let mut times = m.times;
        times.render_ms = ms(t);
        Ok(finish(
            m,
            image,
            marks,
            times,
            Drawn {
                floated: self.floated,
                dropped: self.dropped,
                panels: self.panels,
                fitted: self.fitted,
            },
            self.keep_analysis,
        ))
    }

    /// The warped raster with the frame's floating marks: only what changed is redrawn when
    /// the previous frame's output can be kept.
    fn draw(&mut self, w: &WithWarp) -> Image {
        let (src, vsm, m, warp) = (&w.frame.image, &w.sal.vsm, &w.meshed, &w.solved.warp);
        let (decision, dirty) = (w.solved.decision, &w.sal.dirty);
        let vector_marks = w.frame.marks.is_some();
        let mesh = &m.mesh;
        let opaque = src.is_opaque();
        let target = warp.target();
        let usable = self.prev.as_ref().filter(|p| {
            decision != Decision::Rebuild
                && p.image.size() == target
                && p.opaque == opaque
                && p.mesh.size() == mesh.size()
        });
        let unchanged = usable.filter(|p| {
            Arc::ptr_eq(&p.mesh, mesh) && Arc::ptr_eq(&p.warp, warp) && dirty.is_empty()
        });
        if let Some(p) = unchanged.filter(|p| Arc::ptr_eq(&p.marks, &m.floating)) {
            // Same pixels, mesh, warp and marks: the same output, floating marks and all,
            // already drawn (and a scaled mark blends its rim over what lies under it: twice
            // is not once).
            self.floated = p.floating.len();
            self.dropped = p.floating.dropped();
            return p.image.clone();
        }
        // A canvas taken whole is drawn by one map per axis; where nothing on it gives way,
        // at one scale ([`Fit`]): its marks stay round and its text keeps its shape there, so
        // nothing floats over it. Not under vector marks, which the warp places over the
        // whole target.
        let whole_canvas = mesh.structure().is_some_and(Structure::whole_canvas);
        // The text's placements where deciding the layout has found them already.
        let mut placed = None;
        let canvas = whole_canvas.then(|| match vector_marks {
            // A frame's vector marks are placed by the warp, linear over a canvas taken
            // whole: the picture under them follows the same map (its text bands and
            // margins keep no size of their own), or the marks would leave what they mark.
            true => CanvasMap::linear(mesh.size(), target),
            false if self.layout => {
                let (map, text) = laid_out(src, mesh, warp, target);
                placed = text;
                map
            }
            false => CanvasMap::without_plots(mesh.structure(), mesh.size(), target),
        });
        let fit = (canvas.as_ref())
            .filter(|_| !self.fill && !vector_marks)
            .and_then(|map| Fit::of(map, src.as_ref(), target));
        self.panels = match fit {
            Some(_) => 0,
            None => canvas.as_ref().map_or(0, |c| c.panels.len()),
        };
        self.fitted = fit.map(|f| {
            let [x, y] = f.at;
            [x, y, x + f.content.width, y + f.content.height]
        });
        let floating = match fit {
            Some(_) => Floating::default(),
            None => floating_marks(src, vsm, m, warp, canvas.as_ref(), self.layout, placed),
        };
        // The warp reads the source with the floating marks painted out.
        let warped = painted_out(
            src,
            &floating,
            mesh.structure(),
            &mut self.painted,
            &mut self.scratch,
        );
        // A canvas taken whole is resampled by one map per axis, as a plain linear resize is
        // ([`crate::render::resize_linear`]), with none of the crisp-line work that only a
        // bending warp needs (judged blind, its notches and specks were the defects left once
        // nothing bent).
        let unchanged = unchanged.is_some();
        let (mut out, pasted) = match (usable, fit, canvas.as_ref()) {
            (Some(p), _, _) if unchanged => {
                // Same pixels, mesh and warp: the same floating marks, already drawn (a
                // scaled mark blends its rim over what lies under it: twice is not once).
                (p.image.clone(), true)
            }
            (_, Some(fit), _) => (fit.draw(warped.as_ref(), target, self.threads), false),
            (_, None, Some(map)) => (
                resize_mapped_on(warped.as_ref(), target, map, self.threads),
                false,
            ),
            (None, None, None) => {
                let mut out = Image::new(target);
                self.renderer.render(warped.as_ref(), mesh, warp, &mut out);
                (out, false)
            }
            (Some(p), None, None) => {
                let out =
                    redraw_changed(&mut self.renderer, warped, mesh, warp, p, &floating, dirty);
                (out, false)
            }
        };
        if !pasted {
            floating.paste(src, &mut out);
        }
        self.floated = floating.len();
        self.dropped = floating.dropped();
        // The copy goes into the last output's buffer where it fits: a fresh one would cost
        // its page faults every frame.
        let image = match self.prev.take() {
            Some(Previous { mut image, .. }) if image.size() == out.size() => {
                image.pixels_mut().copy_from_slice(out.pixels());
                image
            }
            _ => out.clone(),
        };
        self.prev = Some(Previous {
            mesh: mesh.clone(),
            warp: warp.clone(),
            image,
            opaque,
            floating,
            marks: m.floating.clone(),
        });
        out
    }
}

/// The map of a canvas taken whole: its plots take the room the parts around them leave
/// ([`crate::render::AxisMap::around_plots`]) where its text keeps its size there; where the
/// text would be left to the plots' squeeze (a word on a busy ground cannot float, and the
/// canvas' text floats all of it or none), the text bands and margins alone give way.
/// Also the text's placements under the plots' map where it was chosen by them, so that
/// they are not laid out twice.
pub(crate) fn laid_out(
    src: &Image,
    mesh: &Mesh,
    warp: &Warp,
    target: crate::image::Size,
) -> (CanvasMap, Option<Placements>) {
    let structure = mesh.structure();
    let map = crate::render::canvas_map(structure, mesh.size(), target, true);
    let Some(st) = structure.filter(|s| !s.text.is_empty()) else {
        return (map, None);
    };
    let fallback = CanvasMap::without_plots(structure, mesh.size(), target);
    let areas = warp.area_maps(mesh);
    let placed = |map: &CanvasMap| {
        let maps = AreaMaps {
            areas: &areas,
            canvas: Some(map),
        };
        match crate::render::area_text_layout(src, st, maps, target, true) {
            (placements, false) => Some(placements),
            (_, true) => None,
        }
    };
    if map == fallback {
        return (map, None);
    }
    if let Some(placements) = placed(&map) {
        return (map, Some(placements));
    }
    // Cards whose plots were squeezed, where their type cannot keep its size beside them:
    // each card at one scale, before the picture's own fallback.
    if crate::render::squeezes(structure) {
        let whole = crate::render::canvas_map(structure, mesh.size(), target, false);
        if whole != fallback {
            if let Some(placements) = placed(&whole) {
                return (whole, Some(placements));
            }
        }
    }
    (fallback, None)
}

/// Where each text block of a frame is drawn ([`crate::render::area_text_placements`]).
pub(crate) type Placements = Vec<Option<crate::render::TextPlacement>>;

/// `src`, or, with marks floating, `src` with them painted out into the buffer `painted`.
fn painted_out<'a>(
    src: &'a Image,
    floating: &Floating,
    structure: Option<&Structure>,
    painted: &'a mut Option<Image>,
    scratch: &mut Vec<bool>,
) -> &'a Image {
    if floating.is_empty() {
        return src;
    }
    match painted {
        Some(p) if p.size() == src.size() => p.pixels_mut().copy_from_slice(src.pixels()),
        _ => *painted = Some(src.clone()),
    }
    let painted = painted.get_or_insert_with(|| src.clone());
    floating.paint_out(painted, structure, scratch);
    painted
}

/// The previous output with only what changed redrawn: triangles that are new or moved, lie
/// over tiles whose pixels changed, or lie under a floating mark of then or now (source
/// pixels under one were painted out differently, output pixels it was or is drawn on must be
/// drawn again).
fn redraw_changed(
    renderer: &mut Renderer,
    warped: &Image,
    mesh: &Mesh,
    warp: &Warp,
    prev: &Previous,
    floating: &Floating,
    dirty: &TileMask,
) -> Image {
    let kept = unchanged_triangles(&prev.mesh, &prev.warp, mesh, warp);
    let mut dirty = dirty.clone();
    let (mut src_rects, mut out_rects) = (Vec::new(), Vec::new());
    for f in [&prev.floating, floating] {
        src_rects.extend(f.source_rects());
        out_rects.extend(f.output_rects());
    }
    let t = dirty.tile_px() as f64;
    for [x0, y0, x1, y1] in src_rects {
        let (c0, r0) = ((x0 / t) as u32, (y0 / t) as u32);
        let (c1, r1) = ((x1 / t).ceil() as u32, (y1 / t).ceil() as u32);
        for r in r0..r1 {
            for c in c0..c1 {
                dirty.set(c, r);
            }
        }
    }
    let q = warp.positions();
    let tris = mesh.triangles();
    let drawn_over = |t: usize| {
        let v = tris[t].map(|i| q[i as usize]);
        let lo = v[0].min(v[1]).min(v[2]);
        let hi = v[0].max(v[1]).max(v[2]);
        out_rects.iter().any(|r| {
            lo.x < r[2] + 1.0 && hi.x > r[0] - 1.0 && lo.y < r[3] + 1.0 && hi.y > r[1] - 1.0
        })
    };
    let mut out = prev.image.clone();
    renderer.render_partial(warped.as_ref(), mesh, warp, &mut out, &|t, r| {
        kept[t] && !dirty.intersects(r[0], r[1], r[2], r[3]) && !drawn_over(t)
    });
    out
}

/// The marks drawn over the warp at their own shape: the marks of a stream that the kept
/// mesh does not ring (at their own size, where the warp carries them), and the marks of each
/// data area (at the area's one scale, the geometric mean of its map's scales, so that a
/// round mark stays round and sizes that encode data keep their proportions; centred where
/// the area's map takes their centre).
fn floating_marks(
    src: &Image,
    vsm: &Vsm,
    m: &Meshed,
    warp: &Warp,
    canvas_map: Option<&CanvasMap>,
    author_size: bool,
    placed: Option<Placements>,
) -> Floating {
    let mesh = &m.mesh;
    // Marks inside data areas (at the area's one scale, where its map takes their centre),
    // then the text blocks inside areas ([`crate::render::area_text_placements`]).
    let mut in_areas: Vec<(Mark, InArea)> = Vec::new();
    let (mut maps, mut canvas) = (Vec::new(), None);
    if let Some(s) = mesh.structure().filter(|s| !s.areas.is_empty()) {
        maps = warp.area_maps(mesh);
        canvas = canvas_map;
        in_areas = crate::render::area_marks(src, vsm, s)
            .into_iter()
            .map(|(mk, k, c)| (mk, InArea::Mark(k, c)))
            .collect();
        let area_maps = AreaMaps {
            areas: &maps,
            canvas,
        };
        let placements = placed.unwrap_or_else(|| {
            crate::render::area_text_layout(src, s, area_maps, warp.target(), author_size).0
        });
        for (t, p) in s.text.iter().zip(placements) {
            let Some(p) = p else { continue };
            let (bw, bh) = ((t.x1 - t.x0) as f64, (t.y1 - t.y0) as f64);
            let mark = Mark {
                center: DVec2::new((t.x0 + t.x1) as f64 / 2.0, (t.y0 + t.y1) as f64 / 2.0),
                ring_radius: 0.5 * (bw * bw + bh * bh).sqrt() + 1.5,
                bbox: [t.x0, t.y0, t.x1, t.y1],
                pixels: (bw * bh) as u32,
            };
            in_areas.push((mark, InArea::Text(p)));
        }
    }
    if m.floating.is_empty() && in_areas.is_empty() {
        return Floating::default();
    }
    // Stream marks inside an area float with the area's marks. On a canvas taken whole
    // there are none: it is resampled afresh from each frame, and its floats are found
    // afresh too, so a kept mesh changes nothing drawn (a stream mark pasted at its own size
    // there is one a fresh frame would draw squeezed).
    let whole_canvas = mesh.structure().is_some_and(Structure::whole_canvas);
    let loose: Vec<Mark> = if whole_canvas {
        Vec::new()
    } else {
        m.floating
            .iter()
            .filter(|f| {
                !in_areas
                    .iter()
                    .any(|(a, _)| a.center.distance(f.center) < a.ring_radius)
            })
            .copied()
            .collect()
    };
    let n_loose = loose.len();
    let mut marks = loose;
    marks.extend(in_areas.iter().map(|(mk, _)| *mk));
    let locator = (n_loose > 0).then(|| warp.locator(mesh));
    let area_maps = AreaMaps {
        areas: &maps,
        canvas,
    };
    // Under the layout ([`Options::layout`]) the marks keep the author's size where room
    // allows; otherwise each takes its map's geometric mean scale (its share of the area).
    // On a picture without plots (a node-link graph, a map) marks found by colour are some
    // of its shapes, not all: grown alone they would misstate the rest (judged blind).
    let charted = mesh
        .structure()
        .is_some_and(|s| !s.bands.plots_x.is_empty() || !s.bands.plots_y.is_empty());
    let mark_scale = (author_size && charted).then(|| marks_scale(&in_areas, area_maps));
    Floating::new(src, vsm, &marks, warp.target(), |i, mk| {
        if i < n_loose {
            return locator
                .as_ref()?
                .map_inside(mk.center)
                .map(|p| (p, 1.0, crate::render::RIM_PX, MaskKind::Salient));
        }
        let (k, colour) = match in_areas[i - n_loose].1 {
            InArea::Mark(k, c) => (k, c),
            // A text block's box and a pixel around it: its glyphs with their edges.
            InArea::Text(p) => {
                let kind = match p.dropped {
                    true => MaskKind::Dropped,
                    false => MaskKind::Whole,
                };
                return Some((p.centre, p.scale, 1, kind));
            }
        };
        let [ax, bx, ay, by] = area_maps.at(k, mk.center)?;
        let scale = mark_scale.unwrap_or((ax * ay).max(0.0).sqrt());
        let rim = crate::render::RIM_PX;
        Some((
            DVec2::new(ax * mk.center.x + bx, ay * mk.center.y + by),
            scale,
            rim,
            MaskKind::Colour(colour),
        ))
    })
}

/// Ground kept between two marks that stood apart, output pixels (at most what they had):
/// their antialiased rims would otherwise meet and read as one blob.
const MARK_GAP_PX: f64 = 2.0;

/// Most marks whose pairs [`marks_scale`] compares; above it they take the largest of
/// their maps' geometric-mean scales (a dense scatter leaves no room to grow anyway).
const MOST_MARKS_COMPARED: usize = 2000;

/// The one scale of a frame's area marks: the author's size (1: a chart drawn again for
/// another screen keeps its markers' point size) where room allows, that is, unless two marks
/// that stood apart would touch, or two that overlapped would overlap more; then the largest
/// scale that keeps every such pair as apart as it was,
/// but never under the maps' geometric mean (the marks' share of their plot's area, which
/// the picture had). One scale for all keeps a bubble's ratio to the others.
fn marks_scale(in_areas: &[(Mark, InArea)], maps: AreaMaps<'_>) -> f64 {
    let placed: Vec<(DVec2, DVec2, f64, f64)> = in_areas
        .iter()
        .filter_map(|(mk, what)| {
            let InArea::Mark(k, _) = *what else {
                return None;
            };
            let [ax, bx, ay, by] = maps.at(k, mk.center)?;
            let [x0, y0, x1, y1] = mk.bbox;
            let radius = 0.5 * f64::from((x1 - x0).max(y1 - y0));
            let out = DVec2::new(ax * mk.center.x + bx, ay * mk.center.y + by);
            Some((mk.center, out, radius, (ax * ay).max(0.0).sqrt()))
        })
        .collect();
    let floor = placed.iter().map(|p| p.3).fold(0.0, f64::max).min(1.0);
    if placed.len() > MOST_MARKS_COMPARED {
        return floor;
    }
    let mut scale: f64 = 1.0;
    for (i, a) in placed.iter().enumerate() {
        for b in &placed[i + 1..] {
            let reach = a.2 + b.2;
            let apart = a.0.distance(b.0);
            let gap = apart - reach;
            if reach > 0.0 && gap > 0.0 {
                // Apart by what they were, up to a rim's width or two.
                let keep = gap.min(MARK_GAP_PX);
                scale = scale.min((a.1.distance(b.1) - keep) / reach);
            } else if reach > 0.0 && apart > 0.0 {
                // Overlapping already: no more than they did (their centres' distance and
                // their sizes in one ratio), or bubbles merge and small ones hide.
                scale = scale.min(a.1.distance(b.1) / apart);
            }
        }
    }
    scale.clamp(floor, 1.0)
}

/// What floats in a data area: a mark (of area `k`, of one colour), or a text block, placed.
#[derive(Copy, Clone)]
enum InArea {
    Mark(usize, [u8; 3]),
    Text(crate::render::TextPlacement),
}

/// For each triangle of `mesh`: whether the previous mesh had it (the same three vertex ids)
/// with the same deformed positions, so that its pixels in the previous output still hold.
fn unchanged_triangles(pm: &Mesh, pw: &Warp, mesh: &Mesh, warp: &Warp) -> Vec<bool> {
    let same_mesh = std::ptr::eq(pm, mesh);
    let prev_pos: HashMap<u64, DVec2> = pm
        .ids()
        .iter()
        .copied()
        .zip(pw.positions().iter().copied())
        .collect();
    let key = |m: &Mesh, t: &[u32; 3]| {
        let mut k = t.map(|v| m.ids()[v as usize]);
        k.sort_unstable();
        k
    };
    let prev_tris: HashSet<[u64; 3]> = if same_mesh {
        HashSet::new()
    } else {
        pm.triangles().iter().map(|t| key(pm, t)).collect()
    };
    mesh.triangles()
        .iter()
        .map(|t| {
            (same_mesh || prev_tris.contains(&key(mesh, t)))
                && t.iter().all(|&v| {
                    prev_pos.get(&mesh.ids()[v as usize]) == Some(&warp.positions()[v as usize])
                })
        })
        .collect()
}

/// What the render drew besides the warp, for a frame's statistics.
struct Drawn {
    floated: usize,
    dropped: usize,
    panels: usize,
    fitted: Option<[u32; 4]>,
}

/// The output record of a frame.
fn finish(
    m: WithWarp,
    image: Image,
    marks: Option<Arc<VectorLayer>>,
    times: StageTimes,
    drawn: Drawn,
    keep_analysis: bool,
) -> Retargeted {
    let WithWarp {
        frame,
        sal,
        meshed,
        solved,
        ..
    } = m;
    let mesh = meshed.mesh;
    let stats = FrameStats {
        vertices: mesh.vertices().len(),
        triangles: mesh.triangles().len(),
        dof: mesh.dof(),
        solve: solved.stats,
        times,
        decision: solved.decision,
        updated_tiles: if solved.decision == Decision::Update {
            meshed.region.count()
        } else {
            0
        },
        frame_index: frame.frame_index,
        data_areas: mesh.structure().map_or(0, |s| s.areas.len()),
        floated: drawn.floated,
        dropped: drawn.dropped,
        panels: drawn.panels,
        fitted: drawn.fitted,
    };
    let analysis = keep_analysis.then_some(Analysis {
        vsm: sal.vsm,
        mesh,
        warp: solved.warp,
    });
    Retargeted {
        image,
        frame_index: frame.frame_index,
        duration_ms: frame.duration_ms,
        stats,
        analysis,
        marks,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mark(x: f64, y: f64, r: u32) -> (Mark, InArea) {
        let (cx, cy) = (x as u32, y as u32);
        let m = Mark {
            center: DVec2::new(x, y),
            ring_radius: r as f64 + 2.0,
            bbox: [cx - r, cy - r, cx + r, cy + r],
            pixels: 3 * r * r,
        };
        (m, InArea::Mark(0, [200, 0, 0]))
    }

    /// Halved along x: marks far apart keep the author's size; two that stood apart keep a
    /// gap, two that overlapped overlap no more than they did, both down to the floor of the
    /// map's geometric mean (the marks' share of their plot, which the picture had).
    #[test]
    fn marks_keep_their_size_where_room_allows() {
        let area = [Some([0.5, 0.0, 1.0, 0.0])];
        let maps = AreaMaps::from(&area);
        let floor = 0.5f64.sqrt();
        let apart = [mark(100.0, 100.0, 5), mark(300.0, 100.0, 5)];
        assert_eq!(marks_scale(&apart, maps), 1.0);
        // 24 px apart centre to centre, 10 px reach: at half width 12 apart, a 2 px gap kept.
        let near = [mark(100.0, 100.0, 5), mark(124.0, 100.0, 5)];
        assert!((marks_scale(&near, maps) - 1.0).abs() < 1e-9);
        // 16 px apart: 8 at half width, a 2 px gap kept at 0.6, under the floor.
        let close = [mark(100.0, 100.0, 5), mark(116.0, 100.0, 5)];
        assert!((marks_scale(&close, maps) - floor).abs() < 1e-9);
        // Apart along y, which the map keeps: the author's size.
        let stacked = [mark(100.0, 100.0, 5), mark(100.0, 116.0, 5)];
        assert!((marks_scale(&stacked, maps) - 1.0).abs() < 1e-9);
        // Overlapping along y (8 px apart, 10 px reach): kept apart as they were, at 1.
        let over = [mark(100.0, 100.0, 5), mark(100.0, 108.0, 5)];
        assert!((marks_scale(&over, maps) - 1.0).abs() < 1e-9);
        // Overlapping along a diagonal: their distance shrinks to 0.79 of itself, so do they.
        let diagonal = [mark(100.0, 100.0, 5), mark(105.0, 105.0, 5)];
        let s = marks_scale(&diagonal, maps);
        assert!((s - (1.25f64 / 2.0).sqrt()).abs() < 1e-9, "{s}");
    }
}
