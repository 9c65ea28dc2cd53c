//! Rendering the warp: every output pixel is inverse-mapped through the deformed triangle that
//! owns it to the source triangle and sampled there.
//!
//! * ownership comes from `crate::raster`: exact fixed-point scan conversion, so shared edges
//!   leave no cracks and no pixel is drawn twice;
//! * each triangle's inverse map is affine; along a span it is two additions per pixel;
//! * `sample`: bilinear where the triangle magnifies, a Catmull-Rom filter stretched over the
//!   pixel's footprint where it minifies (from a ripmap level past 2×).

mod canvas;
mod fill;
mod fit;
mod floating;
mod panels;
mod resize;
mod ripmap;
mod sample;

pub use canvas::{AreaMaps, AxisMap, CanvasMap, PanelMap};
pub(crate) use fill::fill_from_surroundings;
pub(crate) use fit::Fit;
pub(crate) use floating::{area_marks, area_text_layout, Floating, MaskKind, RIM_PX};
pub use floating::{area_text_placements, TextPlacement};
pub(crate) use panels::{canvas_map, squeezes};
pub use resize::{resize_linear, resize_mapped};
pub(crate) use resize::{resize_mapped_on, Threads};

use crate::image::{Image, ImageRef};
use crate::mesh::Mesh;
use crate::raster::{rasterize, FixedPoint};
use crate::solve::Warp;
use glam::DVec2;
use sample::{Filter, Kernel, Texels};
use std::collections::HashMap;

/// Footprint (source pixels per output pixel) up to which a minified triangle is filtered
/// from the source itself. Content kept at half its size or more (text, marks, what the
/// energy protects) is read sharp; content squeezed harder is empty ground by the energy's
/// design, read with one bilinear tap from the ripmap level that brings its footprint under a
/// texel (a fifth of the filter's cost).
const FILTER_UP_TO: f64 = 2.0;
/// Footprint from which content that is not read (outside text blocks and lines) is
/// area-filtered; below it one bilinear tap: an area filter would spread every 1-px rule
/// over two pixels for a 20 % shrink, where the aliasing it avoids is slight.
const AREA_FROM: f64 = 1.25;
/// A triangle whose inverse map is within this of the identity on the diagonal (magnifying by
/// at most ~10 %), with shear below [`CRISP_SHEAR`], is copied pixel for pixel.
const CRISP_TOLERANCE: f64 = 0.15;
/// Minification allowed for the copy: a rounding allowance, not a scale.
const CRISP_SLACK: f64 = 0.002;
/// Shear allowed for the copy.
const CRISP_SHEAR: f64 = 0.05;
/// A mark's fan triangle whose inverse map is within this of the identity (diagonal) is copied
/// rigidly; the mark then keeps its exact shape, and the small mismatch is absorbed at the
/// fan's rim, which lies in the background around the mark.
const RIGID_TOLERANCE: f64 = 0.15;
/// Shear allowed for a rigid copy.
const RIGID_SHEAR: f64 = 0.1;

/// Renders warps. Keeps its ripmap levels between calls.
///
/// The taps read the source as it is, 4 bytes a pixel: a copy pre-spread into SWAR lanes
/// (8 bytes a pixel) would save a few instructions per texel, but it doubles the memory the
/// taps walk and its page faults cost more than that saves.
#[derive(Default)]
pub struct Renderer {
    ripmap: ripmap::Ripmap,
    scratch: Scratch,
}

/// Vertically filtered texel columns of one span (float, and SWAR lanes), kept between spans
/// so that no span allocates.
#[derive(Default)]
struct Scratch {
    cols: Vec<sample::Column>,
    lane_cols: Vec<u64>,
}

impl Renderer {
    pub fn new() -> Renderer {
        Renderer::default()
    }

    /// Draws `src` through `mesh` deformed by `warp` into `dst`, which must be the warp's
    /// target size (it is resized if not). Every pixel of `dst` is written.
    pub fn render(&mut self, src: ImageRef<'_>, mesh: &Mesh, warp: &Warp, dst: &mut Image) {
        let target = warp.target();
        if dst.size() != target {
            *dst = Image::new(target);
        }
        self.render_partial(src, mesh, warp, dst, &|_, _| false);
    }

    /// Like [`Renderer::render`], but `dst` already holds the previous frame's output and a
    /// triangle `t` for which `keep(t, reach)` is true keeps its pixels there. `reach` is the
    /// source rectangle `[x0, y0, x1, y1]` its samples read (its bounding box grown by the
    /// filter's reach): a caller keeps a triangle whose deformed shape did not change and
    /// whose reach holds no changed source pixel, and the result equals a full render.
    pub fn render_partial(
        &mut self,
        src: ImageRef<'_>,
        mesh: &Mesh,
        warp: &Warp,
        dst: &mut Image,
        keep: &dyn Fn(usize, [f64; 4]) -> bool,
    ) {
        let target = warp.target();
        if dst.size() != target {
            *dst = Image::new(target);
        }
        let opaque = src.is_opaque();
        self.ripmap.clear(opaque);
        let frame = Frame {
            src,
            opaque,
            rigid: rigid_offsets(mesh, warp),
        };
        for t in 0..mesh.triangles().len() {
            let Some(tri) = Triangle::new(mesh, warp, t) else {
                continue; // covers no pixel; a solved warp never has one
            };
            match plan(&frame, &tri, keep) {
                Plan::Keep => {}
                Plan::Rigid(shift) => draw_rigid(src, &tri, shift, dst),
                Plan::Fill(c) => draw_fill(&tri, c, dst),
                Plan::Sample(span) => self.draw_sampled(&frame, &tri, span, dst),
            }
        }
        overlay_thin_lines(src, mesh, warp, dst);
    }

    /// Draws a sampled triangle: reads its ripmap level, fences its filters, and hands each
    /// span to the kernel [`plan`] chose.
    fn draw_sampled(
        &mut self,
        frame: &Frame<'_>,
        tri: &Triangle,
        span: SpanKernel,
        dst: &mut Image,
    ) {
        let f = &tri.filtering;
        let level = self.ripmap.level(frame.src, f.lx, f.ly);
        let tex = Texels {
            px: level.pixels(),
            w: level.width() as i32,
            h: level.height() as i32,
        };
        let fence = fence(tri.p);
        // The filters' texel ranges: the fence's texels, or the whole level.
        let (filter_x, filter_y) = if f.fenced {
            (
                Filter::new(f.kernel, f.fx as f32, fence[0] as i32, fence[2] as i32),
                Filter::new(f.kernel, f.fy as f32, fence[1] as i32, fence[3] as i32),
            )
        } else {
            (
                Filter::new(f.kernel, f.fx as f32, 0, tex.w - 1),
                Filter::new(f.kernel, f.fy as f32, 0, tex.h - 1),
            )
        };
        let m = tri.map.m;
        let sampler = Sampler {
            tex,
            // f32 stepping along one span (≤ a triangle wide) drifts by well under 0.01 px.
            du: (m[0][0] / f.kx) as f32,
            dv: (m[1][0] / f.ky) as f32,
            filter_x,
            filter_y,
            fenced: f.fenced,
            fence,
            opaque: frame.opaque,
        };
        let (tw, th) = (dst.width(), dst.height());
        let twu = tw as usize;
        let out = dst.pixels_mut();
        let scratch = &mut self.scratch;
        rasterize(tri.fq, tw, th, |y, x0, x1| {
            let row = &mut out[y as usize * twu..][x0 as usize..x1 as usize];
            // Output pixel centre → level coordinates.
            let s = tri.map.at(x0 as f64 + 0.5, y as f64 + 0.5);
            let start = DVec2::new(s.x / f.kx, s.y / f.ky);
            span(&sampler, (start.x as f32, start.y as f32), scratch, row);
        });
    }
}

/// What every triangle of one render reads.
struct Frame<'a> {
    src: ImageRef<'a>,
    /// Every source pixel is opaque: the integer paths apply.
    opaque: bool,
    /// Shifts of the small marks' fans ([`rigid_offsets`]).
    rigid: HashMap<u32, (i64, i64)>,
}

/// One triangle of the mesh as the render sees it: its corners on both sides, its inverse map
/// and how its samples are filtered.
struct Triangle {
    index: usize,
    vertices: [u32; 3],
    /// Source corners.
    p: [DVec2; 3],
    /// Output corners, for the scan conversion.
    fq: [FixedPoint; 3],
    map: InverseMap,
    filtering: Filtering,
}

impl Triangle {
    /// Triangle `t` under `warp`; `None` if it covers no pixel (its output corners are not
    /// counter-clockwise).
    fn new(mesh: &Mesh, warp: &Warp, t: usize) -> Option<Triangle> {
        let vertices = mesh.triangles()[t];
        let q: [DVec2; 3] = vertices.map(|v| warp.positions()[v as usize]);
        let p = mesh.triangle_points(t);
        let map = InverseMap::new(q, p)?;
        Some(Triangle {
            index: t,
            vertices,
            p,
            fq: q.map(|p| FixedPoint::from_f64(p.x, p.y)),
            map,
            filtering: Filtering::choose(mesh, t, &vertices, &map),
        })
    }

    /// The source rectangle `[x0, y0, x1, y1]` within `margin` of the triangle.
    fn reach(&self, margin: f64) -> [f64; 4] {
        let p = self.p;
        let lo = p[0].min(p[1]).min(p[2]) - DVec2::splat(margin);
        let hi = p[0].max(p[1]).max(p[2]) + DVec2::splat(margin);
        [lo.x, lo.y, hi.x, hi.y]
    }
}

/// A triangle's inverse affine map, output → source: `src = p0 + M (dst − q0)`, `M = P Q⁻¹`.
/// Affine, so along a span it is two additions per pixel.
#[derive(Copy, Clone)]
struct InverseMap {
    q0: DVec2,
    p0: DVec2,
    m: [[f64; 2]; 2],
}

impl InverseMap {
    /// The map taking output corners `q` to source corners `p`; `None` if `q` is not
    /// counter-clockwise (it covers no pixel).
    fn new(q: [DVec2; 3], p: [DVec2; 3]) -> Option<InverseMap> {
        let (e1, e2) = (q[1] - q[0], q[2] - q[0]);
        let det = e1.perp_dot(e2);
        if det <= 0.0 {
            return None;
        }
        let inv = [[e2.y / det, -e2.x / det], [-e1.y / det, e1.x / det]];
        let (f1, f2) = (p[1] - p[0], p[2] - p[0]);
        let m = [
            [
                f1.x * inv[0][0] + f2.x * inv[1][0],
                f1.x * inv[0][1] + f2.x * inv[1][1],
            ],
            [
                f1.y * inv[0][0] + f2.y * inv[1][0],
                f1.y * inv[0][1] + f2.y * inv[1][1],
            ],
        ];
        Some(InverseMap {
            q0: q[0],
            p0: p[0],
            m,
        })
    }

    /// The source point under the output point `(x, y)`.
    #[inline]
    fn at(&self, x: f64, y: f64) -> DVec2 {
        let (m, d) = (self.m, DVec2::new(x, y) - self.q0);
        self.p0 + DVec2::new(m[0][0] * d.x + m[0][1] * d.y, m[1][0] * d.x + m[1][1] * d.y)
    }

    /// The pixel's footprint on the source is the parallelogram of the map's two steps; its
    /// extent along each source axis picks the ripmap level.
    fn footprint(&self) -> (f64, f64) {
        let m = self.m;
        (m[0][0].abs() + m[0][1].abs(), m[1][0].abs() + m[1][1].abs())
    }

    /// Whether the map carries content at about its own size: its diagonal within
    /// `[lo, hi]`, its shear below `shear` on both axes.
    fn near_identity(&self, lo: f64, hi: f64, shear: f64) -> bool {
        let m = self.m;
        (lo..=hi).contains(&m[0][0])
            && (lo..=hi).contains(&m[1][1])
            && m[0][1].abs() < shear
            && m[1][0].abs() < shear
    }
}

/// How a triangle's samples are filtered, from its footprint and from what it carries.
#[derive(Copy, Clone)]
struct Filtering {
    /// It has a side on a structure line or a text block's border ([`on_structure`]).
    fenced: bool,
    /// Ripmap level along each axis, and the source pixels per level texel (`2^l`).
    lx: usize,
    ly: usize,
    kx: f64,
    ky: f64,
    /// Footprint in level texels along each axis, 1 where that axis is not filtered.
    fx: f64,
    fy: f64,
    kernel: Kernel,
    /// Some axis is filtered over the footprint.
    minify: bool,
}

impl Filtering {
    fn choose(mesh: &Mesh, t: usize, vertices: &[u32; 3], map: &InverseMap) -> Filtering {
        let (ex, ey) = map.footprint();
        // A triangle with a side on a structure line (or a text block's border) samples only
        // inside itself, at full resolution: the line, snapped onto the output grid by the
        // solver, then stays one pixel sharp instead of being averaged with what lies
        // across it by a ripmap texel or a bilinear tap.
        let (fenced, by_text) = on_structure(mesh, vertices);
        let (lx, ly) = if fenced || ex.max(ey) <= FILTER_UP_TO {
            (0, 0)
        } else {
            (level_for(ex), level_for(ey))
        };
        let (kx, ky) = ((1u32 << lx) as f64, (1u32 << ly) as f64);
        // Footprint in level texels along each axis; above one texel the pixel is filtered.
        let (fx, fy) = (ex / kx, ey / ky);
        // What is read (text blocks, and the triangles along their borders) is filtered
        // sharp; the rest by area, at a fraction of the cost (outside text blocks OCR reads
        // as many words either way, and thin lines are redrawn pixel for pixel anyway), and
        // only from [`AREA_FROM`], per axis.
        let (kernel, filter_from) = if by_text || mesh.triangle_block(t).is_some() {
            (Kernel::CatmullRom, 1.0 + 1e-6)
        } else {
            (Kernel::Area, AREA_FROM)
        };
        let (fx, fy) = (
            if fx > filter_from { fx } else { 1.0 },
            if fy > filter_from { fy } else { 1.0 },
        );
        Filtering {
            fenced,
            lx,
            ly,
            kx,
            ky,
            fx,
            fy,
            kernel,
            minify: fx.max(fy) > 1.0,
        }
    }

    /// Source pixels beyond the triangle that its samples may read: the filter's reach and
    /// the bilinear tap's, in level texels.
    fn margin(&self) -> f64 {
        let reach = if self.minify {
            self.kernel.reach(self.fx.max(self.fy) as f32) as f64
        } else {
            1.0
        };
        (reach + 2.0) * self.kx.max(self.ky)
    }
}

/// What one triangle's pixels are drawn with. [`plan`] decides it once per triangle; the span
/// kernels then only draw.
enum Plan {
    /// Left as the previous frame drew it.
    Keep,
    /// A small mark's fan copied from the source shifted by whole pixels `(dx, dy)`.
    Rigid((i64, i64)),
    /// Everything it reads is this one colour.
    Fill([u8; 4]),
    /// Sampled through its inverse map, each span by this kernel.
    Sample(SpanKernel),
}

/// How triangle `tri` is drawn: kept, copied rigidly, filled, or sampled, and then by which
/// span kernel.
fn plan(frame: &Frame<'_>, tri: &Triangle, keep: &dyn Fn(usize, [f64; 4]) -> bool) -> Plan {
    let (f, map) = (&tri.filtering, &tri.map);
    let margin = f.margin();
    if keep(tri.index, tri.reach(margin)) {
        return Plan::Keep;
    }
    // A small mark's fan, carried at about its own size: an exact copy shifted by whole
    // pixels (the mark's own shape, crisp, and moving in whole pixels in a stream).
    if map.near_identity(1.0 - RIGID_TOLERANCE, 1.0 + RIGID_TOLERANCE, RIGID_SHEAR) {
        if let Some(shift) = tri
            .vertices
            .iter()
            .find_map(|v| frame.rigid.get(v).copied())
        {
            return Plan::Rigid(shift);
        }
    }
    if let Some(c) = uniform_colour(&frame.src, tri.p, margin) {
        return Plan::Fill(c);
    }
    // Content carried at its own size (marks and text that keep their scale) is copied
    // pixel for pixel: bilinear would blur every edge by a fraction of a pixel, soften
    // 1-px lines and make a moving mark's whole outline flicker.
    // Only where the map magnifies or keeps size: nearest sampling never skips a source
    // pixel there, so a 1-px line cannot vanish (at most one is doubled).
    let crisp = f.lx == 0
        && f.ly == 0
        && map.near_identity(1.0 - CRISP_TOLERANCE, 1.0 + CRISP_SLACK, CRISP_SHEAR);
    Plan::Sample(if crisp {
        nearest_span
    } else if f.minify {
        filtered_kernel(frame.opaque, f.kernel)
    } else {
        bilinear_span
    })
}

/// The span kernel of a minified triangle: the one place the filters' const parameters
/// (opaque arithmetic, deringing) are chosen. Catmull-Rom's negative lobes need deringing,
/// the area filter has none; an opaque area filter has its integer path.
fn filtered_kernel(opaque: bool, kernel: Kernel) -> SpanKernel {
    match (opaque, kernel) {
        (true, Kernel::Area) => area_span_opaque,
        (true, Kernel::CatmullRom) => filtered_span::<true, true>,
        (false, Kernel::CatmullRom) => filtered_span::<false, true>,
        (false, Kernel::Area) => filtered_span::<false, false>,
    }
}

/// Copies a rigidly carried fan: every pixel from the source pixel `shift` before it
/// (clamped to the source).
fn draw_rigid(src: ImageRef<'_>, tri: &Triangle, (dx, dy): (i64, i64), dst: &mut Image) {
    let (tw, th) = (dst.width(), dst.height());
    let twu = tw as usize;
    let out = dst.pixels_mut();
    let (sw, sh) = (src.width() as i64, src.height() as i64);
    let px = src.pixels();
    rasterize(tri.fq, tw, th, |y, x0, x1| {
        let sy = (y as i64 - dy).clamp(0, sh - 1) as usize;
        let row = &mut out[y as usize * twu..][x0 as usize..x1 as usize];
        for (i, o) in row.iter_mut().enumerate() {
            let sx = (x0 as i64 + i as i64 - dx).clamp(0, sw - 1) as usize;
            *o = px[sy * sw as usize + sx];
        }
    });
}

/// Fills a triangle whose reach is one colour.
fn draw_fill(tri: &Triangle, c: [u8; 4], dst: &mut Image) {
    let (tw, th) = (dst.width(), dst.height());
    let twu = tw as usize;
    let out = dst.pixels_mut();
    rasterize(tri.fq, tw, th, |y, x0, x1| {
        out[y as usize * twu..][x0 as usize..x1 as usize].fill(c);
    });
}

/// The source box a fenced triangle's samples stay in. A side on a pixel boundary (an edge
/// between two regions) keeps samples half a pixel inside, so nothing of the other side is
/// read; a side through pixel centres (a thin line, the mesh edge along its middle) lets the
/// line's own pixels be read exactly.
fn fence(p: [DVec2; 3]) -> [f32; 4] {
    let (bmin, bmax) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
    let inset = |v: f64| if v.fract() == 0.0 { 0.5 } else { 0.0 };
    [
        (bmin.x + inset(bmin.x)).min(bmax.x) as f32,
        (bmin.y + inset(bmin.y)).min(bmax.y) as f32,
        (bmax.x - inset(bmax.x)).max(bmin.x) as f32,
        (bmax.y - inset(bmax.y)).max(bmin.y) as f32,
    ]
}

/// What the span kernels of one sampled triangle read.
struct Sampler<'a> {
    tex: Texels<'a>,
    /// Level coordinates' step per output pixel along a span.
    du: f32,
    dv: f32,
    filter_x: Filter,
    filter_y: Filter,
    /// Bilinear taps stay inside `fence` ([`fence`]).
    fenced: bool,
    fence: [f32; 4],
    opaque: bool,
}

/// Draws one span `row` of a sampled triangle, its first pixel's centre at level coordinates
/// `(u, v)`. A plain function, chosen once per triangle, so each kernel's inner loop is
/// compiled for its own case.
type SpanKernel = fn(&Sampler<'_>, (f32, f32), &mut Scratch, &mut [[u8; 4]]);

/// Pixel for pixel ([`plan`]'s crisp case).
fn nearest_span(s: &Sampler<'_>, (mut u, mut v): (f32, f32), _: &mut Scratch, row: &mut [[u8; 4]]) {
    for px in row.iter_mut() {
        *px = s.tex.nearest(u, v);
        u += s.du;
        v += s.dv;
    }
}

/// One bilinear tap a pixel, where the map magnifies or shrinks too little to filter.
fn bilinear_span(
    s: &Sampler<'_>,
    (mut u, mut v): (f32, f32),
    _: &mut Scratch,
    row: &mut [[u8; 4]],
) {
    let fence = s.fence;
    for px in row.iter_mut() {
        let (su, sv) = if s.fenced {
            (u.clamp(fence[0], fence[2]), v.clamp(fence[1], fence[3]))
        } else {
            (u, v)
        };
        *px = if s.opaque {
            sample::finish_one(s.tex.bilinear_lanes(su, sv))
        } else {
            let mut acc = [0f32; 4];
            s.tex.bilinear_premul(su, sv, &mut acc);
            sample::finish_premul(acc, 1)
        };
        u += s.du;
        v += s.dv;
    }
}

/// Whether a span of `n` pixels stepping `dv` per pixel stays on one `v`: an axis-aligned map
/// (nearly every triangle), whose span is filtered as one row, its vertical taps shared.
#[inline]
fn along_one_row(dv: f32, n: usize) -> bool {
    (dv * n as f32).abs() < 1e-3
}

/// The filters over each pixel's footprint: as one row where the span keeps its `v`, else
/// pixel by pixel.
fn filtered_span<const OPAQUE: bool, const DERING: bool>(
    s: &Sampler<'_>,
    (u, v): (f32, f32),
    scratch: &mut Scratch,
    row: &mut [[u8; 4]],
) {
    if along_one_row(s.dv, row.len()) {
        let v = v + s.dv * (row.len() / 2) as f32;
        let f = (&s.filter_x, &s.filter_y);
        s.tex
            .filtered_row::<OPAQUE, DERING>((u, s.du), v, f, &mut scratch.cols, row);
    } else {
        filtered_pixels::<OPAQUE, DERING>(s, (u, v), row);
    }
}

/// [`filtered_span`] for an opaque source under the area filter: its row in SWAR lanes.
fn area_span_opaque(
    s: &Sampler<'_>,
    (u, v): (f32, f32),
    scratch: &mut Scratch,
    row: &mut [[u8; 4]],
) {
    if along_one_row(s.dv, row.len()) {
        let v = v + s.dv * (row.len() / 2) as f32;
        let f = (&s.filter_x, &s.filter_y);
        s.tex
            .area_row_opaque((u, s.du), v, f, &mut scratch.lane_cols, row);
    } else {
        filtered_pixels::<true, false>(s, (u, v), row);
    }
}

/// The filters over each pixel's footprint, one pixel at a time (a rotated or sheared map).
#[inline(always)]
fn filtered_pixels<const OPAQUE: bool, const DERING: bool>(
    s: &Sampler<'_>,
    (mut u, mut v): (f32, f32),
    row: &mut [[u8; 4]],
) {
    for px in row.iter_mut() {
        *px = s
            .tex
            .filtered::<OPAQUE, DERING>(u, v, &s.filter_x, &s.filter_y);
        u += s.du;
        v += s.dv;
    }
}

/// Pixels copied on each side of a thin line with it: its antialiased rim and the ground just
/// beyond, which a squeezed neighbourhood would otherwise smear into each other.
const LINE_HALO_PX: i64 = 2;

/// Redraws the structure's thin lines (1–3 px rules, frames, grid lines) pixel for pixel along
/// their warped course, with [`LINE_HALO_PX`] on each side: a line shrunk across its width
/// would otherwise be averaged with what lies beside it (a 1-px rule at half width would become
/// a 50 % grey smear). The solver has put each line on the output grid the way it sat on the
/// source grid, so its pixels are copied whole; along the line, the source position comes from
/// the line's own vertices.
fn overlay_thin_lines(src: ImageRef<'_>, mesh: &Mesh, warp: &Warp, dst: &mut Image) {
    let Some(st) = mesh.structure() else { return };
    for horizontal in [true, false] {
        let lines = if horizontal {
            &st.horizontal
        } else {
            &st.vertical
        };
        for (k, l) in lines.iter().enumerate() {
            if l.width == 0 || l.width > 3 {
                continue;
            }
            if let Some((course, across)) = line_course(mesh, warp, horizontal, k) {
                copy_line(src, l, horizontal, &course, across, dst);
            }
        }
    }
}

/// A thin line's vertices in order along it: (source along, output along, output across).
type Course = Vec<(f64, f64, f64)>;

/// The course of thin line `k` (horizontal or vertical) and the output position across the
/// line its vertices share; `None` if it has fewer than two, or if they do not all lie on one
/// line across (the solver's shared unknown): such a line is left to the warp.
fn line_course(mesh: &Mesh, warp: &Warp, horizontal: bool, k: usize) -> Option<(Course, f64)> {
    let mut pts: Course = (mesh.roles().iter().enumerate())
        .filter(|(_, r)| {
            if horizontal {
                r.hline == Some(k as u32)
            } else {
                r.vline == Some(k as u32)
            }
        })
        .map(|(i, _)| {
            let (p, q) = (mesh.vertices()[i], warp.positions()[i]);
            if horizontal {
                (p.x, q.x, q.y)
            } else {
                (p.y, q.y, q.x)
            }
        })
        .collect();
    if pts.len() < 2 {
        return None;
    }
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let across = pts[0].2;
    if pts.iter().any(|p| p.2 != across) {
        return None;
    }
    Some((pts, across))
}

/// Copies line `l`'s source pixels, with [`LINE_HALO_PX`] on each side, to where its `course`
/// takes them: across, whole pixels from `across`; along, each output pixel from the source
/// position interpolated between the vertices around it.
fn copy_line(
    src: ImageRef<'_>,
    l: &crate::structure::Line,
    horizontal: bool,
    course: &[(f64, f64, f64)],
    across: f64,
    dst: &mut Image,
) {
    let (tw, th) = (dst.width() as i64, dst.height() as i64);
    let (sw, sh) = (src.width() as i64, src.height() as i64);
    let half = l.width as f64 / 2.0;
    let first_src = (l.pos - half).round() as i64;
    let first_dst = (across - half).round() as i64;
    for w in course.windows(2) {
        let ((s0, o0, _), (s1, o1, _)) = (w[0], w[1]);
        if o1 <= o0 {
            continue;
        }
        let (a, b) = (
            o0.ceil() as i64,
            (o1.ceil() as i64).min(if horizontal { tw } else { th }),
        );
        for o in a.max(0)..b {
            let t = (o as f64 + 0.5 - o0) / (o1 - o0);
            let s = (s0 + t * (s1 - s0)).floor() as i64;
            for i in -LINE_HALO_PX..l.width as i64 + LINE_HALO_PX {
                let (sx, sy, dx, dy) = if horizontal {
                    (s, first_src + i, o, first_dst + i)
                } else {
                    (first_src + i, s, first_dst + i, o)
                };
                if sx < 0
                    || sy < 0
                    || sx >= sw
                    || sy >= sh
                    || dx < 0
                    || dy < 0
                    || dx >= tw
                    || dy >= th
                {
                    continue;
                }
                let px = src.pixels()[(sy * sw + sx) as usize];
                dst.set(dx as u32, dy as u32, px);
            }
        }
    }
}

/// Whether a triangle has a side along one structure line or text-block border (`.0`), and
/// whether one along a text-block border (`.1`).
fn on_structure(mesh: &Mesh, tri: &[u32; 3]) -> (bool, bool) {
    let roles = mesh.roles();
    if roles.is_empty() {
        return (false, false);
    }
    (0..3).fold((false, false), |(any, text), i| {
        let (a, b) = (roles[tri[i] as usize], roles[tri[(i + 1) % 3] as usize]);
        let block = a.block.is_some() && a.block == b.block;
        let line =
            (a.hline.is_some() && a.hline == b.hline) || (a.vline.is_some() && a.vline == b.vline);
        (any || line || block, text || block)
    })
}

/// For each vertex at the centre of a small mark: the whole-pixel shift `(dx, dy)` from source
/// to output that its fan is copied with (the rounded displacement of the centre).
fn rigid_offsets(mesh: &Mesh, warp: &Warp) -> HashMap<u32, (i64, i64)> {
    mesh.mark_hubs()
        .iter()
        .map(|&(i, _)| {
            let d = warp.positions()[i as usize] - mesh.vertices()[i as usize];
            (i, (d.x.round() as i64, d.y.round() as i64))
        })
        .collect()
}

/// The colour of every source pixel within `margin` px of the triangle's bounding box, if
/// they all have one (stops at the first that differs).
fn uniform_colour(src: &ImageRef<'_>, p: [DVec2; 3], margin: f64) -> Option<[u8; 4]> {
    let (w, h) = (src.width() as f64, src.height() as f64);
    let lo =
        |a: f64, b: f64, c: f64| (a.min(b).min(c) - margin).floor().clamp(0.0, w.max(h)) as usize;
    let hi = |a: f64, b: f64, c: f64, lim: f64| {
        (a.max(b).max(c) + margin).ceil().clamp(0.0, lim) as usize
    };
    let (x0, y0) = (
        lo(p[0].x, p[1].x, p[2].x).min(src.width() as usize),
        lo(p[0].y, p[1].y, p[2].y).min(src.height() as usize),
    );
    let (x1, y1) = (hi(p[0].x, p[1].x, p[2].x, w), hi(p[0].y, p[1].y, p[2].y, h));
    if x0 >= x1 || y0 >= y1 {
        return None;
    }
    let rows = src.rows();
    let first = src.pixels()[y0 * src.width() as usize + x0];
    for row in rows.skip(y0).take(y1 - y0) {
        if row[x0..x1].iter().any(|&q| q != first) {
            return None;
        }
    }
    Some(first)
}

/// The ripmap level for a footprint of `extent` source pixels: the source itself up to
/// [`AREA_FROM`] (as the filters: a 1-px rule stays one dark pixel), else the first level that
/// brings it to at most one texel, so that one bilinear tap (two texels wide) covers it
/// without holes.
#[inline]
fn level_for(extent: f64) -> usize {
    if extent <= AREA_FROM {
        return 0;
    }
    let mut l = 0;
    while l + 1 < ripmap::LEVELS && extent / (1u32 << l) as f64 > 1.0 + 1e-9 {
        l += 1;
    }
    l
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Size;
    use crate::mesh::Mesh;
    use crate::solve::Warp;

    fn checker(size: Size) -> Image {
        let mut img = Image::new(size);
        for y in 0..size.height {
            for x in 0..size.width {
                let v = if (x / 3 + y / 3) % 2 == 0 { 250 } else { 10 };
                img.set(x, y, [v, (x * 7) as u8, (y * 5) as u8, 255]);
            }
        }
        img
    }

    /// The inverse map takes each output corner to its source corner, and a triangle turned
    /// over (clockwise on the output) has none.
    #[test]
    fn inverse_map_takes_output_corners_to_source_corners() {
        let p = [
            DVec2::new(3.0, 4.0),
            DVec2::new(13.0, 5.0),
            DVec2::new(4.0, 12.0),
        ];
        let q = [
            DVec2::new(1.0, 2.0),
            DVec2::new(7.5, 2.5),
            DVec2::new(2.0, 9.0),
        ];
        let map = InverseMap::new(q, p).unwrap();
        for (q, p) in q.iter().zip(&p) {
            assert!(map.at(q.x, q.y).distance(*p) < 1e-9, "{q} -> {p}");
        }
        assert!(InverseMap::new([q[0], q[2], q[1]], p).is_none());
    }

    #[test]
    fn identity_warp_reproduces_the_image() {
        let size = Size::new(61, 37).unwrap();
        let img = checker(size);
        let mesh = Mesh::lattice(size, 9.0);
        let warp = Warp::linear(&mesh, size);
        let mut out = Image::new(size);
        Renderer::new().render(img.as_ref(), &mesh, &warp, &mut out);
        assert_eq!(out, img);
    }

    /// The uniform-region shortcut gives the same pixels as sampling.
    #[test]
    fn uniform_fill_equals_sampling() {
        let size = Size::new(90, 60).unwrap();
        let mut img = Image::filled(size, [240, 240, 230, 255]);
        for y in 20..40 {
            for x in 30..50 {
                img.set(x, y, [30, 90, 200, 255]);
            }
        }
        let mesh = Mesh::lattice(size, 12.0);
        for target in [Size::new(37, 60).unwrap(), Size::new(200, 45).unwrap()] {
            let warp = Warp::linear(&mesh, target);
            let mut fast = Image::new(target);
            Renderer::new().render(img.as_ref(), &mesh, &warp, &mut fast);
            // Same image with one far pixel changed: no triangle is uniform any more... except
            // those away from it; compare per pixel away from that corner instead.
            let mut busy = img.clone();
            busy.set(0, 0, [0, 0, 0, 255]);
            busy.set(89, 59, [0, 0, 0, 255]);
            let mut slow = Image::new(target);
            Renderer::new().render(busy.as_ref(), &mesh, &warp, &mut slow);
            let (tw, th) = (target.width, target.height);
            for y in 0..th {
                for x in 0..tw {
                    let near_corner =
                        (x < tw / 5 && y < th / 5) || (x >= tw * 4 / 5 && y >= th * 4 / 5);
                    if !near_corner {
                        assert_eq!(fast.get(x, y), slow.get(x, y), "({x},{y}) -> {target}");
                    }
                }
            }
        }
    }

    /// A small mark carried at about its size is an exact copy of its source pixels, shifted
    /// by whole pixels: its shape and colours survive untouched.
    #[test]
    fn small_marks_are_copied_rigidly() {
        use crate::mesh::MeshOptions;
        use crate::saliency::VsmBuilder;
        use crate::solve::Solver;
        let size = Size::new(300, 160).unwrap();
        let mut img = Image::filled(size, [250, 250, 250, 255]);
        let (cx, cy) = (150.3f32, 80.6f32);
        for y in 0..160u32 {
            for x in 0..300u32 {
                let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                let d2 = dx * dx + dy * dy;
                if d2 <= 49.0 {
                    img.set(x, y, [44, 123, 182, 255]);
                } else if d2 <= 64.0 {
                    img.set(x, y, [120, 170, 210, 255]); // an anti-aliased rim
                }
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        let mesh = Mesh::build(&vsm, &MeshOptions::default());
        assert_eq!(mesh.marks().len(), 1);
        let target = Size::new(200, 160).unwrap();
        let (warp, _) = Solver::default().solve(&mesh, &vsm, target).unwrap();
        let mut out = Image::new(target);
        Renderer::new().render(img.as_ref(), &mesh, &warp, &mut out);
        // Find the shift that puts the mark's 17x17 block into the output exactly.
        let block = |im: &Image, x0: i64, y0: i64| -> Vec<[u8; 4]> {
            (0..17)
                .flat_map(|j| (0..17).map(move |i| (x0 + i, y0 + j)))
                .map(|(x, y)| im.get(x as u32, y as u32))
                .collect()
        };
        let want = block(&img, 142, 72);
        let found =
            (-60i64..0).any(|dx| (-3i64..=3).any(|dy| block(&out, 142 + dx, 72 + dy) == want));
        assert!(found, "the mark's pixels appear unchanged in the output");
    }

    #[test]
    fn every_pixel_is_written_exactly_once() {
        let size = Size::new(50, 40).unwrap();
        let img = Image::filled(size, [10, 20, 30, 255]);
        let mesh = Mesh::lattice(size, 7.0);
        for target in [Size::new(17, 40).unwrap(), Size::new(123, 19).unwrap()] {
            let warp = Warp::linear(&mesh, target);
            // Transparent canvas: any pixel left unwritten would stay alpha 0.
            let mut out = Image::new(target);
            Renderer::new().render(img.as_ref(), &mesh, &warp, &mut out);
            assert!(out.pixels().iter().all(|p| *p == [10, 20, 30, 255]));
        }
    }

    #[test]
    fn transparency_is_kept_and_does_not_bleed() {
        let size = Size::new(40, 40).unwrap();
        let mut img = Image::new(size); // transparent black
        for y in 10..30 {
            for x in 10..30 {
                img.set(x, y, [200, 30, 30, 255]);
            }
        }
        let mesh = Mesh::lattice(size, 10.0);
        let target = Size::new(23, 40).unwrap();
        let mut out = Image::new(target);
        Renderer::new().render(img.as_ref(), &mesh, &Warp::linear(&mesh, target), &mut out);
        assert_eq!(out.get(0, 0)[3], 0);
        assert_eq!(out.get(11, 20), [200, 30, 30, 255]);
        // Edge pixels are partly transparent but keep the colour (no dark fringe).
        for p in out.pixels() {
            if p[3] > 0 {
                assert!(p[0] >= 199 && p[1] <= 31, "{p:?}");
            }
        }
    }

    /// White, with a black 1-px column every 5 px from `first`, 20 px tall.
    fn stroke_columns(width: u32, first: u32) -> Image {
        let mut img = Image::filled(Size::new(width, 20).unwrap(), [255; 4]);
        for y in 0..20 {
            for x in (first..width).step_by(5) {
                img.set(x, y, [0, 0, 0, 255]);
            }
        }
        img
    }

    #[test]
    fn strong_minification_averages_thin_lines() {
        let img = stroke_columns(100, 0);
        let mesh = Mesh::lattice(img.size(), 10.0);
        let target = Size::new(20, 20).unwrap();
        let mut out = Image::new(target);
        Renderer::new().render(img.as_ref(), &mesh, &Warp::linear(&mesh, target), &mut out);
        // One black column in five: each output pixel is close to 80 % white. The last column
        // is left out: the 8× ripmap level's last texel covers only the 4 source columns left
        // (100 is not a multiple of 8), where this pattern has no black column.
        for y in 0..20 {
            for x in 0..19 {
                let p = out.get(x, y);
                assert!((p[0] as i32 - 204).abs() < 30, "({x},{y}) {p:?}");
            }
        }
        // Nothing aliases away: the mean over the frame is the source's mean.
        let mean = out.pixels().iter().map(|p| p[0] as f64).sum::<f64>() / 400.0;
        assert!((mean - 204.0).abs() < 8.0, "{mean}");
    }

    /// 1-px strokes (glyph stems, rules) shrunk to 0.7 stay dark: filtered over their
    /// footprint from the source, not read from a halved ripmap level, which would average
    /// each stroke with its ground before sampling (grey stems).
    #[test]
    fn thin_strokes_shrunk_to_0_7_keep_their_contrast() {
        let img = stroke_columns(200, 2);
        let mesh = Mesh::lattice(img.size(), 10.0);
        let target = Size::new(140, 20).unwrap();
        let mut out = Image::new(target);
        Renderer::new().render(img.as_ref(), &mesh, &Warp::linear(&mesh, target), &mut out);
        for k in 1..39 {
            let c = ((5 * k + 2) as f64 + 0.5) * 0.7;
            let darkest = (c as u32 - 1..=c as u32 + 1)
                .map(|x| out.get(x, 10)[0])
                .min()
                .unwrap();
            assert!(darkest <= 110, "stroke {k}: darkest {darkest}");
        }
    }

    /// Fine stripes shrunk 48× and 64× come out as their area average (near flat grey), not as
    /// moiré: past the ripmap's last level (8×) the area filter still spans the whole
    /// footprint (read only in part, 24-px stripes would come out as high-contrast moiré).
    #[test]
    fn strong_shrinks_average_fine_stripes() {
        let (w, h) = (4032u32, 16u32);
        let mut img = Image::new(Size::new(w, h).unwrap());
        for x in 0..w {
            let v = (127.5 + 127.5 * (std::f64::consts::TAU * (x as f64 + 0.5) / 24.0).sin()) as u8;
            for y in 0..h {
                img.set(x, y, [v, v, v, 255]);
            }
        }
        let mesh = Mesh::lattice(img.size(), 48.0);
        for tw in [84u32, 63] {
            let target = Size::new(tw, h).unwrap();
            let mut out = Image::new(target);
            Renderer::new().render(img.as_ref(), &mesh, &Warp::linear(&mesh, target), &mut out);
            let f = w as f64 / tw as f64;
            let mut err = 0.0;
            for x in 0..tw {
                let (a, b) = (x as f64 * f, (x + 1) as f64 * f);
                let mut area = 0.0;
                for i in a.floor() as u32..(b.ceil() as u32).min(w) {
                    let o = (b.min(i as f64 + 1.0) - a.max(i as f64)).max(0.0);
                    area += o * img.get(i, 0)[0] as f64;
                }
                err += (out.get(x, h / 2)[0] as f64 - area / f).powi(2);
            }
            let rms = (err / tw as f64).sqrt();
            assert!(rms < 3.0, "{tw}: rms {rms} from the area average");
        }
    }
}
