//! Seam carving (Avidan and Shamir 2007) with forward energy (Rubinstein, Shamir and Avidan
//! 2008): the width first, then the height (on the transposed planes).
//!
//! A vertical seam is one pixel per row, each next to the one above. Its cost is the forward
//! energy, the luminance differences its removal creates between pixels that become neighbours
//! (`C_U = |I(x+1) − I(x−1)|`, plus `|I(y−1, x) − I(x∓1)|` when it steps sideways), plus
//! [`SALIENCY_WEIGHT`] times the VSM of the pixels it removes, so that the marks the paper's
//! saliency finds are avoided too. Dynamic programming over the current planes finds the
//! cheapest seam; removing it shifts the rest of each row left by one.
//!
//! To enlarge, the `k` cheapest seams are found on a copy (removing them one after another)
//! and then every one of them is duplicated at once, the new pixel the mean of the seam pixel
//! and its right neighbour; at most half the current width per round, so the same seam is not
//! chosen over and over.
//!
//! Cost: each seam is one pass over the current image, `O(w·h)`; 1500×800 → 750×800 removes
//! 750 seams. The forward energy depends on the neighbours of each pixel, so the whole
//! cumulative map changes below a removed seam and is recomputed per seam; the per-pixel work
//! is a handful of float operations on row-contiguous planes.

use super::{ms_since, Mapping, MethodOutput, MethodStats};
use crate::image::{Image, Size};
use crate::retarget::StageTimes;
use crate::saliency::VsmBuilder;
use std::sync::Arc;
use std::time::Instant;

/// Energy of removing a fully salient pixel, in the luminance units (0–255) of the forward
/// energy: as much as cutting one black-white edge.
pub const SALIENCY_WEIGHT: f32 = 255.0;

/// For each pixel of a seam-carved output, the source position it came from (pixel indices;
/// an inserted pixel sits halfway between the two it averages).
#[derive(Clone, Debug)]
pub struct OriginMap {
    size: Size,
    xy: Vec<[f32; 2]>,
}

impl OriginMap {
    /// The output's size.
    pub fn size(&self) -> Size {
        self.size
    }

    /// The source position of output pixel `(x, y)`.
    pub fn get(&self, x: u32, y: u32) -> [f32; 2] {
        self.xy[y as usize * self.size.width as usize + x as usize]
    }

    /// All positions, row-major.
    pub fn positions(&self) -> &[[f32; 2]] {
        &self.xy
    }
}

pub(super) fn run(image: &Image, target: Size) -> MethodOutput {
    let mut times = StageTimes::default();
    let t = Instant::now();
    let vsm = VsmBuilder::new().build(image.as_ref());
    times.vsm_ms = ms_since(t);
    let t = Instant::now();
    let mut planes = Planes::new(image, |x, y| vsm.get(x, y));
    let mut dp = Scratch::default();
    planes.resize_width(target.width as usize, &mut dp);
    let mut planes = planes.transposed();
    planes.resize_width(target.height as usize, &mut dp);
    let planes = planes.transposed();
    times.solve_ms = ms_since(t);
    let t = Instant::now();
    let (out, origins) = planes.into_output();
    times.render_ms = ms_since(t);
    MethodOutput {
        method: super::Method::Seam,
        image: out,
        stats: MethodStats {
            times,
            ..MethodStats::default()
        },
        mapping: Mapping::Origins(Arc::new(origins)),
        vsm: Some(Arc::new(vsm)),
    }
}

/// The image being carved, one plane per quantity, rows `stride` apart, `w` of each in use.
#[derive(Clone)]
struct Planes {
    w: usize,
    h: usize,
    stride: usize,
    rgba: Vec<[u8; 4]>,
    /// Luminance of the colour over white, 0–255.
    lum: Vec<f32>,
    /// `SALIENCY_WEIGHT ×` the VSM.
    energy: Vec<f32>,
    /// Source position along the carved axis, and across it.
    along: Vec<f32>,
    across: Vec<f32>,
}

/// Buffers of the dynamic programming, kept across seams.
#[derive(Default)]
struct Scratch {
    prev: Vec<f32>,
    cur: Vec<f32>,
    choice: Vec<i8>,
    seam: Vec<usize>,
}

impl Planes {
    fn new(image: &Image, saliency: impl Fn(u32, u32) -> f32) -> Planes {
        let (w, h) = (image.width() as usize, image.height() as usize);
        let rgba = image.pixels().to_vec();
        let lum = rgba.iter().map(|&p| luminance(p)).collect();
        let mut energy = Vec::with_capacity(w * h);
        let mut along = Vec::with_capacity(w * h);
        let mut across = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                energy.push(SALIENCY_WEIGHT * saliency(x as u32, y as u32));
                along.push(x as f32);
                across.push(y as f32);
            }
        }
        Planes {
            w,
            h,
            stride: w,
            rgba,
            lum,
            energy,
            along,
            across,
        }
    }

    /// Removes or inserts vertical seams until the width is `target` (at least 1).
    fn resize_width(&mut self, target: usize, dp: &mut Scratch) {
        let target = target.max(1);
        while self.w > target {
            self.find_seam(dp);
            self.remove_seam(&dp.seam);
        }
        while self.w < target {
            let step = (target - self.w).min((self.w / 2).max(1));
            self.insert_seams(step, dp);
        }
    }

    /// The cheapest vertical seam by forward energy, into `dp.seam` (one x per row).
    fn find_seam(&self, dp: &mut Scratch) {
        let (w, h, s) = (self.w, self.h, self.stride);
        dp.prev.clear();
        dp.prev.extend_from_slice(&self.energy[..w]);
        dp.cur.clear();
        dp.cur.resize(w, 0.0);
        dp.choice.clear();
        dp.choice.resize(w * h, 0);
        for y in 1..h {
            let row = &self.lum[y * s..][..w];
            let up = &self.lum[(y - 1) * s..][..w];
            let e = &self.energy[y * s..][..w];
            let choice = &mut dp.choice[y * w..][..w];
            let (prev, cur) = (&dp.prev[..w], &mut dp.cur[..w]);
            if w == 1 {
                cur[0] = prev[0] + e[0];
                std::mem::swap(&mut dp.prev, &mut dp.cur);
                continue;
            }
            // Borders: the missing neighbour is the pixel itself.
            {
                let cu = (row[1] - row[0]).abs();
                let mu = prev[0] + cu;
                let mr = prev[1] + cu + (up[0] - row[1]).abs();
                let (m, d) = if mr < mu { (mr, 1) } else { (mu, 0) };
                cur[0] = m + e[0];
                choice[0] = d;
            }
            {
                let x = w - 1;
                let cu = (row[x] - row[x - 1]).abs();
                let mu = prev[x] + cu;
                let ml = prev[x - 1] + cu + (up[x] - row[x - 1]).abs();
                let (m, d) = if ml < mu { (ml, -1) } else { (mu, 0) };
                cur[x] = m + e[x];
                choice[x] = d;
            }
            for x in 1..w - 1 {
                let (l, r, u) = (row[x - 1], row[x + 1], up[x]);
                let cu = (r - l).abs();
                let ml = prev[x - 1] + cu + (u - l).abs();
                let mu = prev[x] + cu;
                let mr = prev[x + 1] + cu + (u - r).abs();
                let (mut m, mut d) = (mu, 0i8);
                if ml < m {
                    m = ml;
                    d = -1;
                }
                if mr < m {
                    m = mr;
                    d = 1;
                }
                cur[x] = m + e[x];
                choice[x] = d;
            }
            std::mem::swap(&mut dp.prev, &mut dp.cur);
        }
        let mut x = 0;
        for (i, &v) in dp.prev[..w].iter().enumerate() {
            if v < dp.prev[x] {
                x = i;
            }
        }
        dp.seam.clear();
        dp.seam.resize(h, 0);
        dp.seam[h - 1] = x;
        for y in (1..h).rev() {
            x = (x as isize + dp.choice[y * w + x] as isize) as usize;
            dp.seam[y - 1] = x;
        }
    }

    /// Removes one pixel per row.
    fn remove_seam(&mut self, seam: &[usize]) {
        let (w, s) = (self.w, self.stride);
        for (y, &x) in seam.iter().enumerate() {
            let r = y * s..y * s + w;
            self.rgba[r.clone()].copy_within(x + 1.., x);
            self.lum[r.clone()].copy_within(x + 1.., x);
            self.energy[r.clone()].copy_within(x + 1.., x);
            self.along[r.clone()].copy_within(x + 1.., x);
            self.across[r].copy_within(x + 1.., x);
        }
        self.w -= 1;
    }

    /// Duplicates the `k` (< width, or 1 for a width of 1) cheapest seams.
    fn insert_seams(&mut self, k: usize, dp: &mut Scratch) {
        let (w, h) = (self.w, self.h);
        // Which pixels to duplicate, found on a copy whose `along` holds current columns.
        let mut dup = vec![false; w * h];
        if w == 1 {
            dup.fill(true);
        } else {
            let mut copy = self.clone();
            for y in 0..h {
                for x in 0..w {
                    copy.along[y * copy.stride + x] = x as f32;
                }
            }
            for _ in 0..k {
                copy.find_seam(dp);
                for (y, &x) in dp.seam.iter().enumerate() {
                    dup[y * w + copy.along[y * copy.stride + x] as usize] = true;
                }
                copy.remove_seam(&dp.seam);
            }
        }
        let nw = w + k;
        let mut next = Planes {
            w: nw,
            h,
            stride: nw,
            rgba: Vec::with_capacity(nw * h),
            lum: Vec::with_capacity(nw * h),
            energy: Vec::with_capacity(nw * h),
            along: Vec::with_capacity(nw * h),
            across: Vec::with_capacity(nw * h),
        };
        for y in 0..h {
            let o = y * self.stride;
            for x in 0..w {
                let i = o + x;
                next.push_from(self, i);
                if dup[y * w + x] {
                    let j = if x + 1 < w {
                        i + 1
                    } else {
                        o + x.saturating_sub(1)
                    };
                    next.push_mean(self, i, j);
                }
            }
        }
        *self = next;
    }

    fn push_from(&mut self, src: &Planes, i: usize) {
        self.rgba.push(src.rgba[i]);
        self.lum.push(src.lum[i]);
        self.energy.push(src.energy[i]);
        self.along.push(src.along[i]);
        self.across.push(src.across[i]);
    }

    fn push_mean(&mut self, src: &Planes, i: usize, j: usize) {
        let (a, b) = (src.rgba[i], src.rgba[j]);
        self.rgba
            .push([0, 1, 2, 3].map(|k| (a[k] as u16 + b[k] as u16).div_ceil(2) as u8));
        self.lum.push((src.lum[i] + src.lum[j]) * 0.5);
        self.energy.push((src.energy[i] + src.energy[j]) * 0.5);
        self.along.push((src.along[i] + src.along[j]) * 0.5);
        self.across.push((src.across[i] + src.across[j]) * 0.5);
    }

    /// The planes with rows and columns swapped (and so the carved axis).
    fn transposed(&self) -> Planes {
        let (w, h, s) = (self.w, self.h, self.stride);
        fn t<T: Copy>(v: &[T], w: usize, h: usize, s: usize) -> Vec<T> {
            let mut out = Vec::with_capacity(w * h);
            for x in 0..w {
                out.extend((0..h).map(|y| v[y * s + x]));
            }
            out
        }
        Planes {
            w: h,
            h: w,
            stride: h,
            rgba: t(&self.rgba, w, h, s),
            lum: t(&self.lum, w, h, s),
            energy: t(&self.energy, w, h, s),
            along: t(&self.across, w, h, s),
            across: t(&self.along, w, h, s),
        }
    }

    /// The carved image and the source position of each of its pixels (planes in image
    /// orientation: `along` is x).
    fn into_output(self) -> (Image, OriginMap) {
        let (w, h, s) = (self.w, self.h, self.stride);
        let mut px = Vec::with_capacity(w * h);
        let mut xy = Vec::with_capacity(w * h);
        for y in 0..h {
            px.extend_from_slice(&self.rgba[y * s..][..w]);
            xy.extend((0..w).map(|x| [self.along[y * s + x], self.across[y * s + x]]));
        }
        let size = Size {
            width: w as u32,
            height: h as u32,
        };
        (
            Image::from_pixels(size, px).expect("planes match their size"),
            OriginMap { size, xy },
        )
    }
}

/// Rec. 601 luma of the colour composited over white.
fn luminance(p: [u8; 4]) -> f32 {
    let a = p[3] as f32 / 255.0;
    let c = |v: u8| v as f32 * a + 255.0 * (1.0 - a);
    0.299 * c(p[0]) + 0.587 * c(p[1]) + 0.114 * c(p[2])
}
