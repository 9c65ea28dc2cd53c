//! The four stages of the method as stateful functions, each remembering what it needs of the
//! previous frame. The sequential [`crate::Retargeter`] calls them one after the other; the
//! threaded [`super::Pipeline`] runs each on its own thread. Same functions, same frames.

use super::reuse::{changed_saliency, ReuseOptions};
use super::tiles::changed_tiles;
use super::Decision;
use crate::enhance::Enhancement;
use crate::error::Error;
use crate::image::{Image, Size};
use crate::mesh::{find_marks, IncrementalMesh, Mark, Mesh, MeshOptions, TileMask};
use crate::raster::snap;
use crate::render::{Floating, MaskKind, Renderer};
use crate::saliency::{Rect, Vsm, VsmBuilder, DILATION_RADIUS};
use crate::solve::{EnergyParams, SalientFit, SolveStats, Solver, Warp};
use crate::structure::Structure;
use glam::DVec2;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

/// How much harder than other re-sampled vertices a moved mark's centre is held where the
/// previous warp maps it.
const MARK_CENTRE_HOLD: f64 = 1000.0;

/// Above this share of changed tiles the VSM is recomputed whole (with fresh normalization).
const FULL_VSM_FRACTION: f64 = 0.5;

/// Stage 1: the VSM, recomputed only where pixels changed.
pub(crate) struct SaliencyStage {
    builder: VsmBuilder,
    prev: Option<Image>,
    vsm: Option<Arc<Vsm>>,
    reuse: ReuseOptions,
}

/// What the saliency stage hands on.
pub(crate) struct Saliency {
    pub vsm: Arc<Vsm>,
    /// Tiles whose pixels differ from the previous frame (all tiles for a first frame).
    pub dirty: TileMask,
    /// No previous frame of this size: everything downstream starts over.
    pub fresh: bool,
}

impl SaliencyStage {
    pub fn new(reuse: ReuseOptions) -> SaliencyStage {
        SaliencyStage {
            builder: VsmBuilder::new(),
            prev: None,
            vsm: None,
            reuse,
        }
    }

    pub fn run(&mut self, image: &Image) -> Saliency {
        let size = image.size();
        let same = self.reuse.enabled
            && self.prev.as_ref().is_some_and(|p| p.size() == size)
            && self.vsm.is_some();
        let out = if !same {
            let vsm = Arc::new(self.builder.build(image.as_ref()));
            let mut dirty = TileMask::new(size, self.reuse.tile_px);
            for r in 0..dirty.rows() {
                for c in 0..dirty.cols() {
                    dirty.set(c, r);
                }
            }
            Saliency {
                vsm,
                dirty,
                fresh: true,
            }
        } else {
            let prev = self.prev.as_ref().expect("checked");
            let dirty = changed_tiles(prev, image, self.reuse.tile_px);
            let current = self.vsm.as_ref().expect("checked");
            let vsm = if dirty.is_empty() {
                current.clone()
            } else if dirty.fraction() > FULL_VSM_FRACTION {
                Arc::new(self.builder.build(image.as_ref()))
            } else {
                let mut v = (**current).clone();
                for [x0, y0, x1, y1] in dirty.rects(size) {
                    self.builder
                        .update_region(image.as_ref(), &mut v, Rect { x0, y0, x1, y1 });
                }
                Arc::new(v)
            };
            Saliency {
                vsm,
                dirty,
                fresh: false,
            }
        };
        self.vsm = Some(out.vsm.clone());
        match &mut self.prev {
            Some(p) if p.size() == size => p.pixels_mut().copy_from_slice(image.pixels()),
            p => *p = Some(image.clone()),
        }
        out
    }
}

/// Stage 2: the reuse decision and the mesh (built, updated tile by tile, or kept).
pub(crate) struct MeshStage {
    options: MeshOptions,
    /// Detect lines and text and build the mesh around them.
    structure: bool,
    reuse: ReuseOptions,
    inc: Option<IncrementalMesh>,
    mesh: Option<Arc<Mesh>>,
    /// The VSM the current mesh was built for (tiles replaced as they are updated).
    reference: Option<Vsm>,
    last_vsm: Option<Arc<Vsm>>,
    next_id: u64,
    /// The points the current mesh was built to have as vertices, and the marks it was built
    /// to ring (vector marks, §5.3).
    points: Vec<DVec2>,
    rings: Vec<Mark>,
    /// This frame's small marks that the mesh does not ring.
    floating: Arc<Vec<Mark>>,
    /// Scratch: the map cells the reuse decision leaves out (around small marks).
    ignored: Vec<bool>,
}

/// What the mesh stage hands on.
pub(crate) struct Meshed {
    pub mesh: Arc<Mesh>,
    pub decision: Decision,
    /// The tiles whose key points were re-sampled (for [`Decision::Update`]).
    pub region: TileMask,
    /// Small marks of this frame that the mesh does not ring (they moved or appeared since
    /// it was built): drawn at their own size over the warp ([`crate::render::Floating`]).
    pub floating: Arc<Vec<Mark>>,
}

impl MeshStage {
    pub fn new(options: MeshOptions, reuse: ReuseOptions, structure: bool) -> MeshStage {
        MeshStage {
            options,
            structure,
            reuse,
            inc: None,
            mesh: None,
            reference: None,
            last_vsm: None,
            next_id: 0,
            points: Vec::new(),
            rings: Vec::new(),
            floating: Arc::default(),
            ignored: Vec::new(),
        }
    }

    /// The mesh for this frame, with `points` that must be vertices (vector mark centres) and
    /// `rings` (vector marks that stand alone): other points or rings than the current mesh's,
    /// or a local update touching a point, rebuild.
    pub fn run_with_marks(
        &mut self,
        s: &Saliency,
        image: &Image,
        points: &[DVec2],
        rings: &[Mark],
    ) -> Meshed {
        let vsm = &s.vsm;
        let size = vsm.size();
        let have = !s.fresh
            && self.reuse.enabled
            && self.mesh.as_ref().is_some_and(|m| m.size() == size)
            && self.reference.is_some()
            && self.points == points
            && self.rings == rings;
        // Raster marks float only without vector marks (those steer the mesh themselves).
        let floats = points.is_empty() && rings.is_empty();
        // Under one affine map the mesh is the coarsest and cheap to build again, while an
        // update would keep text found on an earlier frame: floated over this one, a label
        // that moved or grew out of its old box would be pasted torn.
        let rebuild_on_change = self.options.regions == crate::structure::Regions::Affine;
        let decision = if !have {
            Decision::Rebuild
        } else if self.last_vsm.as_ref().is_some_and(|l| Arc::ptr_eq(l, vsm)) {
            Decision::Reuse
        } else {
            let inc = self.inc.as_ref().expect("have");
            // On a canvas taken whole no stream mark floats over a kept warp (each frame is
            // resampled and its floats found afresh): there is nothing to find.
            let canvas = inc.structure().is_some_and(Structure::whole_canvas);
            let current: Vec<Mark> = if floats && !canvas {
                find_marks(vsm)
                    .into_iter()
                    .filter(|m| !inc.in_text(m.center))
                    .collect()
            } else {
                Vec::new()
            };
            // Small marks, where the mesh rings them and where they are now, do not count
            // as change: a mark that moves or appears floats over the kept warp. Their
            // saliency reaches beyond their box by the VSM's blur, Sobel and dilation.
            // Under one affine map nothing is ignored: a label appearing reads as small marks
            // too, and must be found as text on a rebuild.
            let ignore: Vec<[f64; 4]> = if floats && !rebuild_on_change {
                let mesh = self.mesh.as_ref().expect("have");
                let reach = ((DILATION_RADIUS + 2) as u32 * vsm.scale() + 1) as f64;
                mesh.marks()
                    .iter()
                    .chain(&current)
                    .map(|m| {
                        let [x0, y0, x1, y1] = m.bbox.map(|v| v as f64);
                        [x0 - reach, y0 - reach, x1 + reach, y1 + reach]
                    })
                    .collect()
            } else {
                Vec::new()
            };
            let changed = changed_saliency(
                self.reference.as_ref().expect("have"),
                vsm,
                &self.reuse,
                &ignore,
                &mut self.ignored,
            );
            if changed.is_empty() {
                self.floating = Arc::new(unringed(current, self.mesh.as_ref().expect("have")));
                Decision::Reuse
            } else if rebuild_on_change
                || changed.fraction() > self.reuse.rebuild_fraction
                || points.iter().any(|&p| changed.contains(p))
                || rings.iter().any(|m| {
                    let r = 1.5 * m.ring_radius;
                    let c = m.center;
                    changed.intersects(c.x - r, c.y - r, c.x + r, c.y + r)
                })
            {
                Decision::Rebuild
            } else {
                let region = changed.clone();
                let inc = self.inc.as_mut().expect("have");
                let mesh = Arc::new(inc.update(vsm, &self.options, &region));
                self.next_id = inc.next_id();
                if let Some(r) = self.reference.as_mut() {
                    r.copy_tiles_from(vsm, &region);
                }
                self.floating = Arc::new(unringed(current, &mesh));
                self.mesh = Some(mesh.clone());
                self.last_vsm = Some(vsm.clone());
                return Meshed {
                    mesh,
                    decision: Decision::Update,
                    region,
                    floating: self.floating.clone(),
                };
            }
        };
        self.last_vsm = Some(vsm.clone());
        if decision == Decision::Rebuild {
            let structure = self
                .structure
                .then(|| Structure::detect_with(image.as_ref(), self.options.regions));
            let (inc, mesh) = match structure {
                Some(s) if s.whole_canvas() && points.is_empty() && rings.is_empty() => {
                    IncrementalMesh::canvas(size, &s, self.next_id)
                }
                s => IncrementalMesh::build_with_marks(
                    vsm,
                    s.as_ref(),
                    points,
                    rings,
                    &self.options,
                    self.next_id,
                ),
            };
            self.points = points.to_vec();
            self.rings = rings.to_vec();
            self.next_id = inc.next_id();
            self.inc = Some(inc);
            self.mesh = Some(Arc::new(mesh));
            self.reference = Some((**vsm).clone());
            self.floating = Arc::default();
        }
        Meshed {
            mesh: self.mesh.clone().expect("built"),
            decision,
            region: TileMask::new(size, self.reuse.tile_px),
            floating: self.floating.clone(),
        }
    }
}

/// The marks of `current` that no mark of `mesh` rings: a mark whose box lies inside the ring
/// of one of the mesh's marks, centred within a pixel and a half of it, is still carried by
/// that ring's fan (the fan covers the whole ring).
fn unringed(current: Vec<Mark>, mesh: &Mesh) -> Vec<Mark> {
    current
        .into_iter()
        .filter(|c| {
            !mesh.marks().iter().any(|m| {
                let [x0, y0, x1, y1] = c.bbox.map(|v| v as f64);
                let r2 = m.ring_radius * m.ring_radius;
                m.center.distance(c.center) <= 1.5
                    && [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
                        .iter()
                        .all(|&(x, y)| DVec2::new(x, y).distance_squared(m.center) <= r2)
            })
        })
        .collect()
}

/// Stage 3: the solve, skipped on reuse, local on update.
pub(crate) struct SolveStage {
    solver: Solver,
    target: Size,
    prev: Option<(Arc<Mesh>, Arc<Warp>)>,
    salient_fit: SalientFit,
    /// Content enhancement (§5.4), when it changes anything.
    enhance: Option<Enhancement>,
}

/// What the solve stage hands on.
pub(crate) struct Solved {
    pub warp: Arc<Warp>,
    pub stats: SolveStats,
    /// The decision as carried out (an update whose local solve kept folds became a full
    /// solve: [`Decision::Rebuild`]).
    pub decision: Decision,
}

impl SolveStage {
    pub fn new(params: EnergyParams, target: Size) -> SolveStage {
        SolveStage {
            solver: Solver::new(params),
            target,
            prev: None,
            salient_fit: SalientFit::default(),
            enhance: None,
        }
    }

    /// With content enhancement: every solve is a full one with `δ` per triangle (a local
    /// update's solve has no `δ`).
    pub fn with_enhancement(mut self, enhance: &Enhancement) -> SolveStage {
        self.enhance = (!enhance.is_identity()).then(|| enhance.clone());
        self
    }

    pub fn run(&mut self, vsm: &Vsm, m: &Meshed) -> Result<Solved, Error> {
        let mesh = &m.mesh;
        if m.decision == Decision::Reuse {
            if let Some((pm, pw)) = &self.prev {
                if Arc::ptr_eq(pm, mesh) {
                    return Ok(Solved {
                        warp: pw.clone(),
                        stats: SolveStats {
                            salient_scale: self.salient_fit.similar,
                            salient_fit: self.salient_fit.free,
                            ..SolveStats::default()
                        },
                        decision: Decision::Reuse,
                    });
                }
            }
        }
        // A canvas taken whole has one linear map: nothing to solve (its text floats).
        let canvas = mesh.structure().filter(|s| s.whole_canvas());
        if let (None, Some(s)) = (&self.enhance, canvas) {
            let warp = Arc::new(Warp::linear(mesh, self.target));
            self.prev = Some((mesh.clone(), warp.clone()));
            return Ok(Solved {
                warp,
                stats: SolveStats {
                    text_blocks: s.text.len(),
                    ..SolveStats::default()
                },
                decision: Decision::Rebuild,
            });
        }
        if m.decision == Decision::Update && self.enhance.is_none() {
            if let Some((pm, pw)) = &self.prev {
                let held: HashMap<u64, DVec2> = pm
                    .ids()
                    .iter()
                    .copied()
                    .zip(pw.positions().iter().copied())
                    .collect();
                let fixed: Vec<Option<DVec2>> =
                    mesh.ids().iter().map(|id| held.get(id).copied()).collect();
                // New vertices are pulled to where the previous warp maps their source point.
                // A moved mark's centre is held much harder: it then lands where the old warp
                // maps it, a smooth function of its position, and the mark moves in the output
                // by as many whole pixels as that says (no extra jumps from re-solving).
                let locator = WarpLocator::new(pm, pw);
                let centres: std::collections::HashSet<(u64, u64)> = mesh
                    .marks()
                    .iter()
                    .map(|m| (snap(m.center.x).to_bits(), snap(m.center.y).to_bits()))
                    .collect();
                let anchors: Vec<Option<(DVec2, f64)>> = mesh
                    .vertices()
                    .iter()
                    .zip(&fixed)
                    .map(|(&p, f)| {
                        if f.is_some() {
                            return None;
                        }
                        let k = if centres.contains(&(p.x.to_bits(), p.y.to_bits())) {
                            MARK_CENTRE_HOLD
                        } else {
                            1.0
                        };
                        locator.map(p).map(|q| (q, k))
                    })
                    .collect();
                if let Some((warp, stats)) = self.solver.solve_local(
                    mesh,
                    vsm,
                    self.target,
                    &fixed,
                    &anchors,
                    self.salient_fit,
                )? {
                    let warp = Arc::new(warp);
                    self.prev = Some((mesh.clone(), warp.clone()));
                    return Ok(Solved {
                        warp,
                        stats,
                        decision: Decision::Update,
                    });
                }
            }
        }
        let (warp, stats) = match &self.enhance {
            Some(e) => {
                let delta = e.triangle_factors(mesh, vsm);
                let held = e.held(vsm);
                self.solver.solve_enhanced(
                    mesh,
                    held.as_ref().unwrap_or(vsm),
                    self.target,
                    &delta,
                )?
            }
            None => self.solver.solve(mesh, vsm, self.target)?,
        };
        self.salient_fit = SalientFit {
            free: stats.salient_fit,
            similar: stats.salient_scale,
        };
        let warp = Arc::new(warp);
        self.prev = Some((mesh.clone(), warp.clone()));
        // A full solve changes the whole frame, also when it stands in for an update whose
        // local solve kept folds.
        Ok(Solved {
            warp,
            stats,
            decision: Decision::Rebuild,
        })
    }
}

/// Maps source points through a mesh's warp (point location by a bucket grid of triangles).
struct WarpLocator<'a> {
    mesh: &'a Mesh,
    warp: &'a Warp,
    cell: f64,
    cols: usize,
    rows: usize,
    buckets: Vec<Vec<u32>>,
}

impl<'a> WarpLocator<'a> {
    fn new(mesh: &'a Mesh, warp: &'a Warp) -> WarpLocator<'a> {
        let size = mesh.size();
        let cell = 32.0;
        let cols = (size.width as f64 / cell).ceil().max(1.0) as usize;
        let rows = (size.height as f64 / cell).ceil().max(1.0) as usize;
        let mut buckets = vec![Vec::new(); cols * rows];
        for t in 0..mesh.triangles().len() {
            let p = mesh.triangle_points(t);
            let lo = p[0].min(p[1]).min(p[2]);
            let hi = p[0].max(p[1]).max(p[2]);
            let (c0, r0) = ((lo.x / cell) as usize, (lo.y / cell) as usize);
            let (c1, r1) = (
                ((hi.x / cell) as usize).min(cols - 1),
                ((hi.y / cell) as usize).min(rows - 1),
            );
            for r in r0.min(rows - 1)..=r1 {
                for c in c0.min(cols - 1)..=c1 {
                    buckets[r * cols + c].push(t as u32);
                }
            }
        }
        WarpLocator {
            mesh,
            warp,
            cell,
            cols,
            rows,
            buckets,
        }
    }

    /// Where the warp maps source point `q`, if it lies in the mesh.
    fn map(&self, q: DVec2) -> Option<DVec2> {
        let c = ((q.x / self.cell) as usize).min(self.cols - 1);
        let r = ((q.y / self.cell) as usize).min(self.rows - 1);
        for &t in &self.buckets[r * self.cols + c] {
            let p = self.mesh.triangle_points(t as usize);
            let d = (p[1] - p[0]).perp_dot(p[2] - p[0]);
            let b1 = (q - p[0]).perp_dot(p[2] - p[0]) / d;
            let b2 = (p[1] - p[0]).perp_dot(q - p[0]) / d;
            let b0 = 1.0 - b1 - b2;
            if b0 >= -1e-9 && b1 >= -1e-9 && b2 >= -1e-9 {
                let tri = self.mesh.triangles()[t as usize];
                let w = tri.map(|v| self.warp.positions()[v as usize]);
                return Some(w[0] * b0 + w[1] * b1 + w[2] * b2);
            }
        }
        None
    }
}

/// Stage 4: the render, only of what changed when the previous frame's output can be kept,
/// with the frame's floating marks drawn over it.
#[derive(Default)]
pub(crate) struct RenderStage {
    renderer: Renderer,
    prev: Option<Previous>,
    /// The source with floating marks painted out, and the mask buffer that paints them.
    painted: Option<Image>,
    scratch: Vec<bool>,
    /// How many marks and text blocks the last frame drew floating.
    floated: usize,
}

struct Previous {
    mesh: Arc<Mesh>,
    warp: Arc<Warp>,
    image: Image,
    opaque: bool,
    floating: Floating,
}

impl RenderStage {
    /// How many marks and text blocks the last frame drew floating over the warp.
    pub fn floated(&self) -> usize {
        self.floated
    }

    pub fn run(
        &mut self,
        src: &Image,
        vsm: &Vsm,
        m: &Meshed,
        warp: &Arc<Warp>,
        decision: Decision,
        dirty: &TileMask,
    ) -> Image {
        let mesh = &m.mesh;
        let opaque = src.is_opaque();
        let target = warp.target();
        let floating = floating_marks(src, vsm, m, warp);
        // The warp reads the source with the floating marks painted out.
        let warped: &Image = if floating.is_empty() {
            src
        } else {
            let painted = match &mut self.painted {
                Some(p) if p.size() == src.size() => {
                    p.pixels_mut().copy_from_slice(src.pixels());
                    p
                }
                p => p.insert(src.clone()),
            };
            floating.paint_out(painted, mesh.structure(), &mut self.scratch);
            painted
        };
        let usable = self.prev.as_ref().filter(|p| {
            decision != Decision::Rebuild
                && p.image.size() == target
                && p.opaque == opaque
                && p.mesh.size() == mesh.size()
        });
        // A canvas taken whole is one linear map: resampled as a plain linear resize is
        // ([`crate::render::resize_linear`]), with none of the crisp-line work that only a
        // bending warp needs (judged blind, its notches and specks were the defects left once
        // nothing bent).
        let whole_canvas = mesh.structure().is_some_and(Structure::whole_canvas);
        let unchanged = usable.is_some_and(|p| {
            Arc::ptr_eq(&p.mesh, mesh) && Arc::ptr_eq(&p.warp, warp) && dirty.is_empty()
        });
        let (mut out, pasted) = match usable {
            Some(p) if unchanged => {
                // Same pixels, mesh and warp: the same floating marks, already drawn (a
                // scaled mark blends its rim over what lies under it: twice is not once).
                (p.image.clone(), true)
            }
            _ if whole_canvas => (crate::render::resize_linear(warped.as_ref(), target), false),
            None => {
                let mut out = Image::new(target);
                self.renderer.render(warped.as_ref(), mesh, warp, &mut out);
                (out, false)
            }
            Some(p) => {
                let kept = unchanged_triangles(&p.mesh, &p.warp, mesh, warp);
                // Source pixels under floating marks (then and now) were painted out
                // differently; output pixels they were and are drawn on must be redrawn.
                let mut dirty = dirty.clone();
                let (mut src_rects, mut out_rects) = (Vec::new(), Vec::new());
                for f in [&p.floating, &floating] {
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
                        lo.x < r[2] + 1.0
                            && hi.x > r[0] - 1.0
                            && lo.y < r[3] + 1.0
                            && hi.y > r[1] - 1.0
                    })
                };
                let mut out = p.image.clone();
                self.renderer
                    .render_partial(warped.as_ref(), mesh, warp, &mut out, &|t, r| {
                        kept[t] && !dirty.intersects(r[0], r[1], r[2], r[3]) && !drawn_over(t)
                    });
                (out, false)
            }
        };
        if !pasted {
            floating.paste(src, &mut out);
        }
        self.floated = floating.len();
        self.prev = Some(Previous {
            mesh: mesh.clone(),
            warp: warp.clone(),
            image: out.clone(),
            opaque,
            floating,
        });
        out
    }
}

/// The marks drawn over the warp at their own shape: the marks of a stream that the kept
/// mesh does not ring (at their own size, where the warp carries them), and the marks of each
/// data area (at the area's one scale, the geometric mean of its map's scales, so that a
/// round mark stays round and sizes that encode data keep their proportions; centred where
/// the area's map takes their centre).
fn floating_marks(src: &Image, vsm: &Vsm, m: &Meshed, warp: &Warp) -> Floating {
    let mesh = &m.mesh;
    // Marks inside data areas (at the area's one scale, where its map takes their centre),
    // then the text blocks inside areas ([`crate::render::area_text_placements`]).
    let mut in_areas: Vec<(Mark, InArea)> = Vec::new();
    let mut maps = Vec::new();
    if let Some(s) = mesh.structure().filter(|s| !s.areas.is_empty()) {
        maps = warp.area_maps(mesh);
        in_areas = crate::render::area_marks(src, vsm, s)
            .into_iter()
            .map(|(mk, k, c)| (mk, InArea::Mark(k, c)))
            .collect();
        let placements = crate::render::area_text_placements(src, s, &maps, warp.target());
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
    let locator = (n_loose > 0).then(|| WarpLocator::new(mesh, warp));
    Floating::new(src, vsm, &marks, warp.target(), |i, mk| {
        if i < n_loose {
            return locator
                .as_ref()?
                .map(mk.center)
                .map(|p| (p, 1.0, crate::render::RIM_PX, MaskKind::Salient));
        }
        let (k, colour) = match in_areas[i - n_loose].1 {
            InArea::Mark(k, c) => (k, c),
            // A text block's box and a pixel around it: its glyphs with their edges.
            InArea::Text(p) => return Some((p.centre, p.scale, 1, MaskKind::Whole)),
        };
        let [ax, bx, ay, by] = (*maps.get(k)?)?;
        let (scale, rim) = ((ax * ay).max(0.0).sqrt(), crate::render::RIM_PX);
        Some((
            DVec2::new(ax * mk.center.x + bx, ay * mk.center.y + by),
            scale,
            rim,
            MaskKind::Colour(colour),
        ))
    })
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
