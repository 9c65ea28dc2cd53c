//! The visual saliency map (VSM) of §4: `S_vsm = S_m + S_d + S_sec`, normalized to `[0, 1]`.
//!
//! * `lab`: the feature vector `[L, a, b, m]` (Lab plus the mid channel);
//! * `frequency_tuned`: importance `S_m` (Eq. 1–2);
//! * `edges`: Sobel and 7×7 dilation `S_d` (Eq. 3–4);
//! * `second_region`: the second-peak regions `S_sec` (Eq. 5), the SSDC fix;
//! * `levels`: the three saliency levels.
//!
//! Normalization. Each component is scaled to `[0, 1]` by its maximum before the sum, and the sum
//! by its own maximum, as the paper says; but each divisor has a floor (`IMPORTANCE_FLOOR`,
//! `EDGE_FLOOR`, 1 for the sum) so that a nearly uniform frame, whose largest difference is a
//! barely visible ripple, is not stretched into full saliency.

mod edges;
mod frequency_tuned;
mod lab;
mod levels;
mod second_region;

pub use levels::SaliencyLevel;

use crate::image::{ImageRef, Size};

/// Frames with more pixels than this get a map at half resolution.
pub const FULL_RESOLUTION_MAX_PX: usize = 600_000;

/// `S_m` divisor floor, in Lab units (ΔE 20: a clearly visible difference).
const IMPORTANCE_FLOOR: f32 = 20.0;
/// Sobel divisor floor: a step of ΔL = 25 (Sobel gain 4).
const EDGE_FLOOR: f32 = 100.0;
/// Dilation radius of Eq. 4 (a 7×7 square).
pub const DILATION_RADIUS: usize = 3;

/// The frame-wide constants a VSM was normalized with. A region of a later frame computed with
/// the same constants ([`VsmBuilder::update_region`]) matches the rest of the map exactly, which
/// is what lets a stream recompute only where pixels changed.
#[derive(Clone, Debug, PartialEq)]
pub struct VsmNorm {
    /// Mean feature `[L, a, b, m]` (the `G(∞)` of Eq. 2).
    pub mean: [f32; 4],
    /// Divisor of `S_m`.
    pub importance_div: f32,
    /// Divisor of the Sobel magnitude.
    pub edge_div: f32,
    /// `S_sec` per histogram bin of the normalized importance (Eq. 5).
    pub boost: [f32; second_region::BINS],
    /// Divisor of the sum.
    pub final_div: f32,
}

/// A visual saliency map: one value in `[0, 1]` per map cell, plus the parts later stages use.
///
/// The map covers the image at `scale` image pixels per cell along each axis (1, or 2 for
/// frames above `FULL_RESOLUTION_MAX_PX`): the mesh it guides has key points 10 px apart or
/// more, and a 6-px dot is still 3 cells, while the saliency passes and everything that reads
/// the map cost a quarter.
#[derive(Debug)]
pub struct Vsm {
    size: Size,
    grid: Size,
    scale: u32,
    values: Vec<f32>,
    importance: Vec<f32>,
    edges: Vec<f32>,
    norm: Option<Box<VsmNorm>>,
}

impl Clone for Vsm {
    fn clone(&self) -> Vsm {
        Vsm {
            size: self.size,
            grid: self.grid,
            scale: self.scale,
            values: self.values.clone(),
            importance: self.importance.clone(),
            edges: self.edges.clone(),
            norm: self.norm.clone(),
        }
    }

    /// Into the planes `self` has: a stream's maps are recycled, and a fresh megabyte-sized
    /// plane costs its page faults every frame.
    fn clone_from(&mut self, other: &Vsm) {
        self.size = other.size;
        self.grid = other.grid;
        self.scale = other.scale;
        self.values.clone_from(&other.values);
        self.importance.clone_from(&other.importance);
        self.edges.clone_from(&other.edges);
        self.norm.clone_from(&other.norm);
    }
}

impl Vsm {
    /// A map of `size` with no planes yet, for [`VsmBuilder::build_into`].
    pub(crate) fn empty(size: Size) -> Vsm {
        Vsm {
            size,
            grid: size,
            scale: 1,
            values: Vec::new(),
            importance: Vec::new(),
            edges: Vec::new(),
            norm: None,
        }
    }

    /// The image (canvas) size the map covers.
    pub fn size(&self) -> Size {
        self.size
    }

    /// The map's own resolution: the dimensions of [`Vsm::values`] and the other planes.
    pub fn grid_size(&self) -> Size {
        self.grid
    }

    /// Image pixels per map cell along each axis.
    pub fn scale(&self) -> u32 {
        self.scale
    }

    /// `S_vsm`, row-major over [`Vsm::grid_size`], each in `[0, 1]`.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// Normalized importance `S_m` (Eq. 2), in `[0, 1]`.
    pub fn importance(&self) -> &[f32] {
        &self.importance
    }

    /// Normalized Sobel magnitude `S_e` before dilation (Eq. 3), in `[0, 1]`: where marks are,
    /// not their 3-px context.
    pub fn edges(&self) -> &[f32] {
        &self.edges
    }

    /// The constants this map was normalized with (`None` for a map given as values).
    #[cfg(test)]
    pub(crate) fn norm(&self) -> Option<&VsmNorm> {
        self.norm.as_deref()
    }

    /// Saliency at an image pixel.
    #[inline]
    pub fn get(&self, x: u32, y: u32) -> f32 {
        let (gx, gy) = (
            (x / self.scale).min(self.grid.width - 1),
            (y / self.scale).min(self.grid.height - 1),
        );
        self.values[gy as usize * self.grid.width as usize + gx as usize]
    }

    /// Saliency level at an image pixel.
    #[inline]
    pub fn level(&self, x: u32, y: u32) -> SaliencyLevel {
        SaliencyLevel::of(self.get(x, y))
    }

    /// Copies the cells of `other` (same size and scale) that lie in the tiles of `mask`.
    pub(crate) fn copy_tiles_from(&mut self, other: &Vsm, mask: &crate::tiles::TileMask) {
        if other.size != self.size || other.scale != self.scale {
            *self = other.clone();
            return;
        }
        let s = self.scale;
        let gw = self.grid.width as usize;
        for [x0, y0, x1, y1] in mask.rects(self.size) {
            let (cx0, cy0) = ((x0 / s) as usize, (y0 / s) as usize);
            let (cx1, cy1) = (
                (x1.div_ceil(s) as usize).min(gw),
                (y1.div_ceil(s) as usize).min(self.grid.height as usize),
            );
            for y in cy0..cy1 {
                let r = y * gw + cx0..y * gw + cx1;
                self.values[r.clone()].copy_from_slice(&other.values[r.clone()]);
                self.importance[r.clone()].copy_from_slice(&other.importance[r.clone()]);
                self.edges[r.clone()].copy_from_slice(&other.edges[r]);
            }
        }
    }

    /// The values, importance and edge planes, for raising them where vector marks lie (§5.3)
    /// or content is held. A raised cell should raise its edge too: the solver lets flat
    /// cells (no edge) give way like empty ground.
    pub(crate) fn planes_mut(&mut self) -> (&mut [f32], &mut [f32], &mut [f32]) {
        (&mut self.values, &mut self.importance, &mut self.edges)
    }

    /// A VSM from given values (clamped to `[0, 1]`), e.g. a user-painted map. Importance and
    /// edges are taken equal to the values.
    pub fn from_values(size: Size, values: Vec<f32>) -> Option<Vsm> {
        if values.len() != size.area() {
            return None;
        }
        let values: Vec<f32> = values.into_iter().map(|v| v.clamp(0.0, 1.0)).collect();
        Some(Vsm {
            size,
            grid: size,
            scale: 1,
            importance: values.clone(),
            edges: values.clone(),
            values,
            norm: None,
        })
    }
}

/// A pixel rectangle `[x0, x1) × [y0, y1)`.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct Rect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Rect {
    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }
    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }
    pub fn is_empty(&self) -> bool {
        self.width() == 0 || self.height() == 0
    }
    /// Grown by `m` on every side, clipped to `size`.
    pub fn grow(&self, m: u32, size: Size) -> Rect {
        Rect {
            x0: self.x0.saturating_sub(m),
            y0: self.y0.saturating_sub(m),
            x1: (self.x1 + m).min(size.width),
            y1: (self.y1 + m).min(size.height),
        }
    }
}

/// Computes VSMs, keeping its scratch planes between frames.
#[derive(Default)]
pub struct VsmBuilder {
    lab: lab::LabConverter,
    features: [Vec<f32>; 4],
    ring: Vec<f32>,
    tmp: Vec<f32>,
    dilated: Vec<f32>,
    crop: Vec<[u8; 4]>,
    /// A region's values, importance and edges ([`VsmBuilder::update_region`]).
    region: [Vec<f32>; 3],
    lab_only: bool,
    full_resolution: bool,
}

impl VsmBuilder {
    pub fn new() -> VsmBuilder {
        VsmBuilder::default()
    }

    /// A builder that drops the mid channel and uses Lab alone, as Achanta et al. did: only for
    /// comparisons (it misses light layers, the paper's Fig. 4b).
    pub fn lab_only() -> VsmBuilder {
        VsmBuilder {
            lab_only: true,
            ..VsmBuilder::default()
        }
    }

    /// A builder that always maps at full resolution, whatever the frame size.
    pub fn full_resolution() -> VsmBuilder {
        VsmBuilder {
            full_resolution: true,
            ..VsmBuilder::default()
        }
    }

    /// Image pixels per map cell for a frame of `size`.
    pub fn scale_for(&self, size: Size) -> u32 {
        if self.full_resolution || size.area() <= FULL_RESOLUTION_MAX_PX {
            1
        } else {
            2
        }
    }

    /// The VSM of `image`. Deterministic: the same pixels give the same map.
    pub fn build(&mut self, image: ImageRef<'_>) -> Vsm {
        let mut vsm = Vsm::empty(image.size());
        self.build_into(image, &mut vsm);
        vsm
    }

    /// Like [`VsmBuilder::build`], reusing the planes of `vsm` (no allocation once warm).
    pub fn build_into(&mut self, image: ImageRef<'_>, vsm: &mut Vsm) {
        let size = image.size();
        let scale = self.scale_for(size);
        let grid = grid_of(size, scale);
        for p in [&mut vsm.values, &mut vsm.importance, &mut vsm.edges] {
            p.resize(grid.area(), 0.0);
        }
        let mut crop = std::mem::take(&mut self.crop);
        let cref = if scale == 1 {
            image
        } else {
            downsample(
                image,
                Rect {
                    x0: 0,
                    y0: 0,
                    x1: grid.width,
                    y1: grid.height,
                },
                scale,
                &mut crop,
            );
            ImageRef::new(grid, &crop).expect("grid size")
        };
        let norm = self.run(
            cref,
            None,
            &mut vsm.values,
            &mut vsm.importance,
            &mut vsm.edges,
        );
        self.crop = crop;
        vsm.size = size;
        vsm.grid = grid;
        vsm.scale = scale;
        vsm.norm = Some(Box::new(norm));
    }

    /// The importance alone (Eq. 1–2, normalized as [`VsmBuilder::build_into`] does), into
    /// `vsm`'s planes: `values` is the importance too, `edges` zero, and the map has no
    /// constants (a region update rebuilds it). What a canvas taken whole reads of its map (the
    /// blobs of its floating marks, and whether a frame changed) for under half the cost of a
    /// whole map: no Sobel, dilation or second-region boost.
    pub(crate) fn build_importance_into(&mut self, image: ImageRef<'_>, vsm: &mut Vsm) {
        let size = image.size();
        let step = self.scale_for(size);
        let grid = grid_of(size, step);
        let mut crop = std::mem::take(&mut self.crop);
        let cref = if step == 1 {
            image
        } else {
            let cells = Rect {
                x0: 0,
                y0: 0,
                x1: grid.width,
                y1: grid.height,
            };
            downsample(image, cells, step, &mut crop);
            ImageRef::new(grid, &crop).expect("grid size")
        };
        let (w, h) = (grid.width as usize, grid.height as usize);
        let n = (w * h) as f64;
        let sum = self.lab.convert_all(cref.pixels(), &mut self.features);
        if self.lab_only {
            self.features[3].fill(0.0);
        }
        let mean = [0, 1, 2, 3].map(|k| match k {
            3 if self.lab_only => 0.0,
            _ => (sum[k] / n) as f32,
        });
        let imp_max = frequency_tuned::importance(
            &self.features,
            w,
            h,
            mean,
            &mut self.ring,
            &mut vsm.importance,
        );
        scale(&mut vsm.importance, imp_max.max(IMPORTANCE_FLOOR));
        vsm.values.clone_from(&vsm.importance);
        vsm.edges.clear();
        vsm.edges.resize(grid.area(), 0.0);
        self.crop = crop;
        vsm.size = size;
        vsm.grid = grid;
        vsm.scale = step;
        vsm.norm = None;
    }

    /// Recomputes `vsm` inside `rect` (image pixels) from `image`, a later frame of the same
    /// size, with the constants `vsm` was built with: inside the rect's map cells the result
    /// equals what a full build with those constants would give. Maps without constants, or of
    /// another size, are rebuilt.
    pub(crate) fn update_region(&mut self, image: ImageRef<'_>, vsm: &mut Vsm, rect: Rect) {
        let size = image.size();
        let Some(norm) = vsm.norm.clone().filter(|_| vsm.size == size) else {
            self.build_into(image, vsm);
            return;
        };
        let (s, grid) = (vsm.scale, vsm.grid);
        // The rect in map cells (covering every cell it touches).
        let rect = Rect {
            x0: (rect.x0 / s).min(grid.width),
            y0: (rect.y0 / s).min(grid.height),
            x1: rect.x1.div_ceil(s).min(grid.width),
            y1: rect.y1.div_ceil(s).min(grid.height),
        };
        if rect.is_empty() {
            return;
        }
        // Blur and Sobel reach 1 cell, the dilation 3 more: a margin of 5 makes the inner rect
        // independent of the crop's borders.
        let outer = rect.grow(DILATION_RADIUS as u32 + 2, grid);
        let (ow, oh) = (outer.width() as usize, outer.height() as usize);
        let mut crop = std::mem::take(&mut self.crop);
        downsample(image, outer, s, &mut crop);
        let csize = Size {
            width: ow as u32,
            height: oh as u32,
        };
        let cref = ImageRef::new(csize, &crop).expect("crop size");
        let [mut v, mut i, mut e] = std::mem::take(&mut self.region);
        for p in [&mut v, &mut i, &mut e] {
            p.resize(ow * oh, 0.0);
        }
        self.run(cref, Some(&norm), &mut v, &mut i, &mut e);
        let w = grid.width as usize;
        for y in rect.y0..rect.y1 {
            let cy = (y - outer.y0) as usize;
            let (cx0, cx1) = ((rect.x0 - outer.x0) as usize, (rect.x1 - outer.x0) as usize);
            let dst = y as usize * w;
            let (d0, d1) = (dst + rect.x0 as usize, dst + rect.x1 as usize);
            vsm.values[d0..d1].copy_from_slice(&v[cy * ow + cx0..cy * ow + cx1]);
            vsm.importance[d0..d1].copy_from_slice(&i[cy * ow + cx0..cy * ow + cx1]);
            vsm.edges[d0..d1].copy_from_slice(&e[cy * ow + cx0..cy * ow + cx1]);
        }
        self.crop = crop;
        self.region = [v, i, e];
    }

    /// The whole computation on `image` into the three planes (already sized); with `norm`
    /// given, its constants are used instead of this image's own. Returns the constants used.
    fn run(
        &mut self,
        image: ImageRef<'_>,
        norm: Option<&VsmNorm>,
        values: &mut [f32],
        importance: &mut Vec<f32>,
        edges: &mut Vec<f32>,
    ) -> VsmNorm {
        let size = image.size();
        let (w, h) = (size.width as usize, size.height as usize);
        let n = (w * h) as f64;
        let sum = self.lab.convert_all(image.pixels(), &mut self.features);
        if self.lab_only {
            self.features[3].fill(0.0);
        }
        let mean = match norm {
            Some(nm) => nm.mean,
            None => [0, 1, 2, 3].map(|k| {
                if self.lab_only && k == 3 {
                    0.0
                } else {
                    (sum[k] / n) as f32
                }
            }),
        };
        let imp_max =
            frequency_tuned::importance(&self.features, w, h, mean, &mut self.ring, importance);
        let importance_div = norm.map_or(imp_max.max(IMPORTANCE_FLOOR), |nm| nm.importance_div);
        scale(importance, importance_div);
        let edge_max = edges::sobel(&self.features[0], w, h, edges);
        let edge_div = norm.map_or(edge_max.max(EDGE_FLOOR), |nm| nm.edge_div);
        scale(edges, edge_div);
        edges::dilate(
            edges,
            w,
            h,
            DILATION_RADIUS,
            &mut self.tmp,
            &mut self.dilated,
        );

        let boost = match norm {
            Some(nm) => nm.boost,
            None => second_region::second_region_boost(importance),
        };
        for ((v, &m), &d) in values.iter_mut().zip(importance.iter()).zip(&self.dilated) {
            *v = m + d + boost[second_region::bin_of(m)];
        }
        let final_div = norm.map_or(max_of(values).max(1.0), |nm| nm.final_div);
        scale(values, final_div);
        VsmNorm {
            mean,
            importance_div,
            edge_div,
            boost,
            final_div,
        }
    }
}

/// The map size for an image of `size` at `scale` image pixels per cell.
fn grid_of(size: Size, scale: u32) -> Size {
    Size {
        width: size.width.div_ceil(scale).max(1),
        height: size.height.div_ceil(scale).max(1),
    }
}

/// The map cells `cells` of `image` at `scale` image pixels per cell, into `out`: each cell is
/// the mean of its (up to) `scale × scale` pixels, composited over white first so that a
/// half-transparent edge averages like it looks.
fn downsample(image: ImageRef<'_>, cells: Rect, scale: u32, out: &mut Vec<[u8; 4]>) {
    out.clear();
    let (w, h) = (image.width(), image.height());
    let px = image.pixels();
    if scale == 1 {
        for y in cells.y0..cells.y1 {
            out.extend_from_slice(&px[(y * w + cells.x0) as usize..(y * w + cells.x1) as usize]);
        }
        return;
    }
    if scale == 2 {
        // The common case, two rows at a time with 16-bit lanes (SWAR) for opaque quads,
        // into a buffer sized first; the cells whose pixels all lie inside the image (all
        // but a last column or row of an odd side) need no clamping.
        #[inline(always)]
        fn spread(p: [u8; 4]) -> u64 {
            let x = u32::from_le_bytes(p) as u64;
            (x & 0xFF) | (x & 0xFF00) << 8 | (x & 0xFF_0000) << 16
        }
        #[inline(always)]
        fn mean(q: [[u8; 4]; 4]) -> [u8; 4] {
            if q.iter().all(|p| p[3] == 255) {
                let sum =
                    spread(q[0]) + spread(q[1]) + spread(q[2]) + spread(q[3]) + 0x0002_0002_0002;
                let m = sum >> 2;
                [
                    (m & 0xFF) as u8,
                    (m >> 16 & 0xFF) as u8,
                    (m >> 32 & 0xFF) as u8,
                    255,
                ]
            } else {
                let mut sum = [0u32; 3];
                for p in q {
                    let a = p[3] as u32;
                    for k in 0..3 {
                        sum[k] += (p[k] as u32 * a + 255 * (255 - a) + 127) / 255;
                    }
                }
                let c = sum.map(|v| ((v + 2) / 4) as u8);
                [c[0], c[1], c[2], 255]
            }
        }
        let (cw, w) = ((cells.x1 - cells.x0) as usize, w as usize);
        out.resize(cw * (cells.y1 - cells.y0) as usize, [0; 4]);
        // Cells `x0..inner` have both their columns inside the image.
        let inner = (cells.x1 as usize).min(w / 2).max(cells.x0 as usize);
        for (cy, orow) in (cells.y0..cells.y1).zip(out.chunks_exact_mut(cw.max(1))) {
            let ya = (2 * cy).min(h - 1) as usize;
            let yb = (2 * cy + 1).min(h - 1) as usize;
            let (ra, rb) = (&px[ya * w..][..w], &px[yb * w..][..w]);
            let x0 = cells.x0 as usize;
            let (qa, qb) = (&ra[2 * x0..2 * inner], &rb[2 * x0..2 * inner]);
            // The AND of whole pixels (its top byte is the AND of the alphas), not `all`
            // (whose early exit goes a byte at a time).
            let and = |q: &[[u8; 4]]| q.iter().fold(u32::MAX, |m, p| m & u32::from_le_bytes(*p));
            if (and(qa) & and(qb)) >> 24 == 255 {
                opaque_means(qa, qb, orow);
            } else {
                let pairs = qa.chunks_exact(2).zip(qb.chunks_exact(2));
                for (o, (a, b)) in orow.iter_mut().zip(pairs) {
                    *o = mean([a[0], a[1], b[0], b[1]]);
                }
            }
            for (o, cx) in orow[inner - x0..].iter_mut().zip(inner..cells.x1 as usize) {
                let xa = (2 * cx).min(w - 1);
                let xb = (2 * cx + 1).min(w - 1);
                *o = mean([ra[xa], ra[xb], rb[xa], rb[xb]]);
            }
        }
        return;
    }
    for cy in cells.y0..cells.y1 {
        let (y0, y1) = (cy * scale, ((cy + 1) * scale).min(h));
        for cx in cells.x0..cells.x1 {
            let (x0, x1) = (cx * scale, ((cx + 1) * scale).min(w));
            let mut sum = [0u32; 3];
            let mut n = 0u32;
            for y in y0..y1 {
                for &p in &px[(y * w + x0) as usize..(y * w + x1) as usize] {
                    let a = p[3] as u32;
                    if a == 255 {
                        for k in 0..3 {
                            sum[k] += p[k] as u32;
                        }
                    } else {
                        for k in 0..3 {
                            sum[k] += (p[k] as u32 * a + 255 * (255 - a) + 127) / 255;
                        }
                    }
                    n += 1;
                }
            }
            let n = n.max(1);
            let c = sum.map(|v| ((v + n / 2) / n) as u8);
            out.push([c[0], c[1], c[2], 255]);
        }
    }
}

crate::simd::with_feature! {
    "avx2";
    /// The cells of two opaque rows `a` and `b` (pixel pairs side by side) into `out`, each
    /// channel the rounded mean of its four bytes, as [`downsample`]'s `mean` makes them.
    /// Whole pixels as words, two channels to a word in 16-bit halves (four bytes and the
    /// rounding sum to 1022 at most: no carry crosses a half), in a loop the compiler keeps in
    /// vectors; a loop over bytes went one byte at a time.
    fn opaque_means(a: &[[u8; 4]], b: &[[u8; 4]], out: &mut [[u8; 4]]) => opaque_means_body {
        const M: u32 = 0x00FF_00FF;
        let word = |p: &[u8; 4]| u32::from_le_bytes(*p);
        for ((o, a), b) in out.iter_mut().zip(a.chunks_exact(2)).zip(b.chunks_exact(2)) {
            let q = [word(&a[0]), word(&a[1]), word(&b[0]), word(&b[1])];
            let lo = q.iter().map(|&p| p & M).fold(0x0002_0002, |s, v| s + v);
            let hi = q.iter().map(|&p| (p >> 8) & M).fold(0x0002_0002, |s, v| s + v);
            let mean = ((lo >> 2) & M) | ((hi >> 2) & M) << 8;
            *o = (mean | 0xFF00_0000).to_le_bytes();
        }
    }
}

/// The largest value (0 for an empty or all-negative slice), in a form that vectorizes:
/// eight running maxima by comparison, no NaN handling (VSM values are never NaN).
pub(crate) fn max_of(v: &[f32]) -> f32 {
    let mut m = [0f32; 8];
    let chunks = v.chunks_exact(8);
    let rest = chunks.remainder();
    for c in chunks {
        for k in 0..8 {
            m[k] = if c[k] > m[k] { c[k] } else { m[k] };
        }
    }
    let mut best = 0f32;
    for &x in m.iter().chain(rest) {
        best = if x > best { x } else { best };
    }
    best
}

/// Divides by `divisor` (at least the largest value), clamping to 1 against rounding.
fn scale(v: &mut [f32], divisor: f32) {
    let inv = 1.0 / divisor;
    for x in v.iter_mut() {
        *x = (*x * inv).min(1.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;

    fn disc_image(w: u32, h: u32, cx: f32, cy: f32, r: f32, fg: [u8; 4], bg: [u8; 4]) -> Image {
        let mut img = Image::filled(Size::new(w, h).unwrap(), bg);
        for y in 0..h {
            for x in 0..w {
                let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                if dx * dx + dy * dy <= r * r {
                    img.set(x, y, fg);
                }
            }
        }
        img
    }

    #[test]
    fn saturated_disc_on_white_is_salient() {
        let img = disc_image(80, 60, 40.0, 30.0, 8.0, [215, 25, 28, 255], [255; 4]);
        let vsm = VsmBuilder::new().build(img.as_ref());
        assert_eq!(vsm.level(40, 30), SaliencyLevel::Salient);
        assert!(vsm.get(40, 30) > 0.5);
        // Far from the disc, the white background is not.
        assert_eq!(vsm.level(5, 5), SaliencyLevel::Background);
        assert!(vsm.get(75, 55) < 0.1);
    }

    /// A region recomputed on a later frame with the first frame's constants equals a full
    /// build of the later frame with those constants, inside the region; outside, the map is
    /// untouched.
    #[test]
    fn region_update_matches_a_full_build_inside_the_region() {
        let a = disc_image(120, 90, 40.0, 30.0, 8.0, [215, 25, 28, 255], [255; 4]);
        let mut b = a.clone();
        for y in 50..70 {
            for x in 70..95 {
                b.set(x, y, [44, 123, 182, 255]);
            }
        }
        let mut builder = VsmBuilder::new();
        let mut vsm = builder.build(a.as_ref());
        let before = vsm.clone();
        let rect = Rect {
            x0: 60,
            y0: 40,
            x1: 105,
            y1: 80,
        };
        builder.update_region(b.as_ref(), &mut vsm, rect);
        // Reference: b computed with a's constants over the whole frame.
        let (mut v, mut i, mut e) = (
            vec![0.0; 120 * 90],
            vec![0.0; 120 * 90],
            vec![0.0; 120 * 90],
        );
        builder.run(b.as_ref(), before.norm(), &mut v, &mut i, &mut e);
        for y in 0..90u32 {
            for x in 0..120u32 {
                let k = (y * 120 + x) as usize;
                let inside = x >= rect.x0 && x < rect.x1 && y >= rect.y0 && y < rect.y1;
                let want = if inside { v[k] } else { before.values()[k] };
                assert_eq!(vsm.values()[k], want, "({x},{y}) inside {inside}");
            }
        }
        assert!(vsm.get(70, 60) > vsm.get(82, 60), "edges above the inside");
        assert!(vsm.get(82, 60) > 0.15, "its inside is context");
    }

    /// Each cell is the rounded mean of its (up to) four pixels, composited over white, in
    /// opaque rows (the vector path) and in rows with a transparent pixel alike, odd sides
    /// included.
    #[test]
    fn a_half_scale_cell_is_the_mean_of_its_pixels() {
        for (w, h, hole) in [
            (9u32, 7u32, false),
            (9, 7, true),
            (16, 4, false),
            (1, 3, true),
        ] {
            let mut v = 12_345u32;
            let mut img = Image::new(Size::new(w, h).unwrap());
            for y in 0..h {
                for x in 0..w {
                    v = v.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                    let [a, b, c, _] = v.to_le_bytes();
                    img.set(x, y, [a, b, c, 255]);
                }
            }
            if hole {
                img.set(0, 1, [10, 20, 30, 100]);
            }
            let cells = Rect {
                x0: 0,
                y0: 0,
                x1: w.div_ceil(2),
                y1: h.div_ceil(2),
            };
            let mut out = Vec::new();
            downsample(img.as_ref(), cells, 2, &mut out);
            for cy in 0..cells.y1 {
                for cx in 0..cells.x1 {
                    let quad = [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| {
                        img.get((2 * cx + dx).min(w - 1), (2 * cy + dy).min(h - 1))
                    });
                    let over_white = |p: [u8; 4], k: usize| {
                        let a = p[3] as u32;
                        (p[k] as u32 * a + 255 * (255 - a) + 127) / 255
                    };
                    let want: [u8; 3] = std::array::from_fn(|k| {
                        ((quad.iter().map(|&p| over_white(p, k)).sum::<u32>() + 2) / 4) as u8
                    });
                    let got = out[(cy * cells.x1 + cx) as usize];
                    assert_eq!(
                        got,
                        [want[0], want[1], want[2], 255],
                        "{w}x{h} cell ({cx}, {cy})"
                    );
                }
            }
        }
    }

    /// The means compiled for AVX2 (where this processor has it) and for the baseline give
    /// the same bytes.
    #[test]
    fn every_build_of_the_means_gives_the_same_bytes() {
        for (n, seed) in [(2, 1), (64, 2), (1282, 3)] {
            let px: Vec<[u8; 4]> = (crate::image::noise_pixels(2 * n, seed).into_iter())
                .map(|[r, g, b, _]| [r, g, b, 255])
                .collect();
            let (a, b) = px.split_at(n);
            let (mut wide, mut base) = (vec![[0u8; 4]; n / 2], vec![[0u8; 4]; n / 2]);
            opaque_means(a, b, &mut wide);
            opaque_means_body(a, b, &mut base);
            assert_eq!(wide, base);
        }
    }

    #[test]
    fn the_importance_alone_is_the_whole_maps_importance() {
        let mut img = disc_image(900, 700, 300.0, 400.0, 120.0, [200, 40, 40, 255], [250; 4]);
        img.set(700, 100, [10, 10, 10, 255]);
        let full = VsmBuilder::new().build(img.as_ref());
        let mut lite = Vsm::empty(img.size());
        // Planes of another map first: nothing of them may stay.
        lite.values = vec![7.0; 5];
        lite.edges = vec![3.0; 100_000];
        VsmBuilder::new().build_importance_into(img.as_ref(), &mut lite);
        assert_eq!(lite.importance(), full.importance());
        assert_eq!(lite.values(), full.importance());
        assert_eq!(lite.edges().len(), full.edges().len());
        assert!(lite.edges().iter().all(|&e| e == 0.0));
        assert_eq!(
            (lite.size(), lite.grid_size()),
            (full.size(), full.grid_size())
        );
        assert!(lite.norm().is_none() && full.norm().is_some());
        assert_eq!(lite.scale(), 2, "a map at half resolution");
    }

    #[test]
    fn uniform_image_has_no_salient_pixels() {
        for colour in [[255, 255, 255, 255], [30, 90, 200, 255], [0, 0, 0, 0]] {
            let img = Image::filled(Size::new(64, 48).unwrap(), colour);
            let vsm = VsmBuilder::new().build(img.as_ref());
            assert!(vsm.values().iter().all(|&v| v == 0.0), "{colour:?}");
        }
    }

    /// A light pastel region on white among saturated yellow marks (the paper's Fig. 4 case):
    /// Lab weighs the marks' strong hue (b ≈ 80) against the region's small lightness
    /// difference, so the region's importance stays at background level; the mid channel adds
    /// the lightness difference once more and lifts it to the context level. The second-region
    /// boost then keeps the whole flat region together in the VSM.
    #[test]
    fn pastel_region_is_found_with_the_mid_channel() {
        let pastel = [253, 224, 221, 255];
        let (w, h) = (200u32, 150u32);
        let mut img = Image::filled(Size::new(w, h).unwrap(), [255; 4]);
        for y in 20..67 {
            for x in 40..103 {
                img.set(x, y, pastel);
            }
        }
        for (cx, cy) in [(10.0, 10.0), (190.0, 140.0), (10.0, 140.0), (190.0, 10.0)] {
            for y in 0..h {
                for x in 0..w {
                    let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                    if dx * dx + dy * dy <= 25.0 {
                        img.set(x, y, [255, 215, 0, 255]);
                    }
                }
            }
        }
        let with_m = VsmBuilder::new().build(img.as_ref());
        let lab_only = VsmBuilder::lab_only().build(img.as_ref());
        let i = (43 * w + 70) as usize;
        let (a, b) = (lab_only.importance()[i], with_m.importance()[i]);
        assert_eq!(
            SaliencyLevel::of(a),
            SaliencyLevel::Background,
            "Lab alone: {a}"
        );
        assert_eq!(SaliencyLevel::of(b), SaliencyLevel::Context, "with m: {b}");
        assert!(with_m.level(70, 43) >= SaliencyLevel::Context);
        assert!(
            with_m.get(150, 75) < 0.15,
            "white background stays background"
        );
        assert_eq!(with_m.level(190, 140), SaliencyLevel::Salient);
    }
}
