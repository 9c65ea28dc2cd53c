//! Pixel sampling kernels: bilinear where a region is magnified; where it is minified, a
//! filter stretched over the pixel's footprint ([`Filter`]): Catmull-Rom (PIL's and
//! ImageMagick's antialiased bicubic) for what is read, the exact area for the rest. 1-px lines
//! fade to grey instead of aliasing away, and text shrunk to 0.7 stays sharp enough to read
//! (as with PIL's bicubic; a box of bilinear taps over a halved ripmap level blurs it).
//!
//! Bilinear samples of opaque sources (nearly every visualization) take an integer path: 8-bit
//! sub-pixel weights, three channels, no alpha arithmetic. The filters, and sources with
//! transparency, take a float path; with transparency it weighs colours by alpha
//! (premultiplied arithmetic), so transparent pixels never bleed their colour into the edges
//! of opaque ones. Coordinates become integers by truncation after a shift that
//! keeps them non-negative, never by `floor` (a libm call on baseline x86-64).

/// Source pixels with their dimensions.
#[derive(Copy, Clone)]
pub(crate) struct Texels<'a> {
    pub px: &'a [[u8; 4]],
    pub w: i32,
    pub h: i32,
}

/// Integer cell and 8-bit fraction of a coordinate (pixel centres at `i + 0.5`).
#[inline(always)]
fn split(u: f32) -> (i32, u32) {
    // +64 keeps the value positive for truncation; sources are < 16384 px.
    let f = ((u + 63.5) * 256.0) as i32 - 64 * 256;
    (f >> 8, (f & 255) as u32)
}

impl Texels<'_> {
    /// Indices of the four texels around `(u, v)` and the 8-bit fractions.
    #[inline(always)]
    fn taps(&self, u: f32, v: f32) -> ([usize; 4], u32, u32) {
        let (xi, tx) = split(u);
        let (yi, ty) = split(v);
        let x0 = xi.clamp(0, self.w - 1) as usize;
        let x1 = (xi + 1).clamp(0, self.w - 1) as usize;
        let y0 = (yi.clamp(0, self.h - 1) as usize) * self.w as usize;
        let y1 = ((yi + 1).clamp(0, self.h - 1) as usize) * self.w as usize;
        ([y0 + x0, y0 + x1, y1 + x0, y1 + x1], tx, ty)
    }

    #[inline(always)]
    fn corners(&self, u: f32, v: f32) -> ([[u8; 4]; 4], u32, u32) {
        let (i, tx, ty) = self.taps(u, v);
        (
            [self.px[i[0]], self.px[i[1]], self.px[i[2]], self.px[i[3]]],
            tx,
            ty,
        )
    }

    /// The texel whose square holds `(u, v)`.
    #[inline(always)]
    pub fn nearest(&self, u: f32, v: f32) -> [u8; 4] {
        let x = (((u + 64.0) as i32) - 64).clamp(0, self.w - 1) as usize;
        let y = (((v + 64.0) as i32) - 64).clamp(0, self.h - 1) as usize;
        self.px[y * self.w as usize + x]
    }

    /// Bilinear RGB of an opaque source as three 21-bit lanes of one `u64`, each the channel
    /// value scaled by 4096 (SWAR: one multiply per corner for all three channels).
    #[inline(always)]
    pub fn bilinear_lanes(&self, u: f32, v: f32) -> u64 {
        let (i, tx, ty) = self.taps(u, v);
        let (a, b) = (lanes(self.px[i[0]]), lanes(self.px[i[1]]));
        let (c, d) = (lanes(self.px[i[2]]), lanes(self.px[i[3]]));
        let (tx, ty) = (tx as u64, ty as u64);
        let top = a * (256 - tx) + b * tx;
        let bot = c * (256 - tx) + d * tx;
        ((top >> 4) & LANE12) * (256 - ty) + ((bot >> 4) & LANE12) * ty
    }

    /// Bilinear premultiplied RGBA (floats, alpha-weighted) added into `acc`.
    #[inline(always)]
    pub fn bilinear_premul(&self, u: f32, v: f32, acc: &mut [f32; 4]) {
        let (p, tx, ty) = self.corners(u, v);
        let (fx, fy) = (tx as f32 / 256.0, ty as f32 / 256.0);
        let k = [
            (1.0 - fx) * (1.0 - fy),
            fx * (1.0 - fy),
            (1.0 - fx) * fy,
            fx * fy,
        ];
        for (p, k) in p.iter().zip(k) {
            let a = p[3] as f32 * k;
            acc[0] += p[0] as f32 * a;
            acc[1] += p[1] as f32 * a;
            acc[2] += p[2] as f32 * a;
            acc[3] += a;
        }
    }
}

/// Most taps of [`Filter`] along one axis: a footprint of up to [`MAX_FILTER_SCALE`] texels.
pub(crate) const MAX_FILTER_TAPS: usize = 4 * MAX_FILTER_SCALE as usize + 1;
/// Widest footprint the Catmull-Rom filter spans (texels per output pixel); a wider one is
/// sampled from a ripmap level first, or aliases slightly. The area filter, one tap a texel,
/// spans up to `MAX_FILTER_TAPS - 2`: past the ripmap's last level (8×) a footprint is still
/// several texels wide, and reading only part of it makes moiré of fine stripes.
pub(crate) const MAX_FILTER_SCALE: f32 = 4.0;

/// Catmull-Rom (the cubic with `a = −0.5`): interpolating, sharp, support 2.
#[inline(always)]
fn cubic(x: f32) -> f32 {
    let x = x.abs();
    if x < 1.0 {
        (1.5 * x - 2.5) * x * x + 1.0
    } else if x < 2.0 {
        ((-0.5 * x + 2.5) * x - 4.0) * x + 2.0
    } else {
        0.0
    }
}

/// The kernel of a [`Filter`].
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Kernel {
    /// Catmull-Rom stretched over the footprint: sharp, for what is read (text, lines); up to
    /// `4·scale + 1` taps.
    CatmullRom,
    /// The exact area of the footprint over each texel (a box): soft and cheap, `scale + 1`
    /// taps at most; bilinear interpolation at scale 1.
    Area,
}

impl Kernel {
    /// Widest footprint whose taps fit in [`MAX_FILTER_TAPS`] (Area: scale + 2 taps).
    pub fn max_scale(self) -> f32 {
        match self {
            Kernel::CatmullRom => MAX_FILTER_SCALE,
            Kernel::Area => (MAX_FILTER_TAPS - 2) as f32,
        }
    }
    /// How far from the sample position (in texels) the kernel stretched by `scale` reads.
    pub fn reach(self, scale: f32) -> f32 {
        let scale = scale.clamp(1.0, self.max_scale());
        match self {
            Kernel::CatmullRom => 2.0 * scale,
            Kernel::Area => 0.5 * scale + 0.5,
        }
    }
}

/// The taps of a filter stretched by `scale` (at least 1) along one axis.
#[derive(Copy, Clone)]
pub(crate) struct Filter {
    kernel: Kernel,
    scale: f32,
    inv: f32,
    /// Texels the filter may read: `[lo, hi]` (edge texels stand in for those beyond).
    lo: i32,
    hi: i32,
}

impl Filter {
    /// A filter over `scale` texels (clamped to `[1, kernel.max_scale()]`) that reads texels
    /// `lo..=hi` only.
    pub fn new(kernel: Kernel, scale: f32, lo: i32, hi: i32) -> Filter {
        let scale = scale.clamp(1.0, kernel.max_scale());
        Filter {
            kernel,
            scale,
            inv: 1.0 / scale,
            lo,
            hi: hi.max(lo),
        }
    }

    /// How far from the sample position (in texels) the filter reads.
    pub fn reach(&self) -> f32 {
        self.kernel.reach(self.scale)
    }

    /// Weights of the texels around `u` (texel `i`'s centre at `i + 0.5`), normalized, into
    /// `w`; returns the first texel's index (clamped into range per tap by the caller through
    /// [`Filter::index`]) and the number of taps. Zero taps at the ends are left out, so a
    /// sample on a texel centre at scale 1 reads that texel alone.
    #[inline(always)]
    pub fn weights(&self, u: f32, w: &mut [f32; MAX_FILTER_TAPS]) -> (i32, usize) {
        // Floors by truncation of values kept positive (no libm call; sources are < 16384 px
        // and samples stay within a few texels of them).
        let floor = |x: f32| (x + 1024.0) as i32 - 1024;
        let (mut lo, mut n) = match self.kernel {
            Kernel::Area => {
                // Texel i covers [i, i + 1); the footprint [a, b).
                let (a, b) = (u - 0.5 * self.scale, u + 0.5 * self.scale);
                let lo = floor(a);
                let n = ((floor(b) - lo + 1).max(0) as usize).min(MAX_FILTER_TAPS);
                for (k, v) in w[..n].iter_mut().enumerate() {
                    let i = (lo + k as i32) as f32;
                    *v = (b.min(i + 1.0) - a.max(i)).max(0.0) * self.inv;
                }
                (lo, n)
            }
            Kernel::CatmullRom => {
                // Texels whose centres lie within (c − r, c + r].
                let (c, r) = (u - 0.5, 2.0 * self.scale);
                let lo = floor(c - r) + 1;
                let n = ((floor(c + r) - lo + 1).max(0) as usize).min(MAX_FILTER_TAPS);
                let mut sum = 0.0;
                for (k, v) in w[..n].iter_mut().enumerate() {
                    *v = cubic(((lo + k as i32) as f32 - c) * self.inv);
                    sum += *v;
                }
                if sum != 0.0 {
                    let k = 1.0 / sum;
                    for v in &mut w[..n] {
                        *v *= k;
                    }
                }
                (lo, n)
            }
        };
        while n > 0 && w[n - 1] == 0.0 {
            n -= 1;
        }
        let skip = w[..n].iter().take_while(|&&v| v == 0.0).count();
        if skip > 0 {
            w.copy_within(skip..n, 0);
            n -= skip;
            lo += skip as i32;
        }
        (lo, n)
    }

    /// The texel columns `n` samples at `u0 + i·du` read: the first and how many (none for
    /// no samples), with a texel of slack each side (the caller steps `u` by addition).
    #[inline(always)]
    pub fn columns(&self, u0: f32, du: f32, n: usize) -> Option<(i32, usize)> {
        let last = n.checked_sub(1)?;
        let u1 = u0 + du * last as f32;
        let r = self.reach();
        let first = (u0.min(u1) - 0.5 - r + 1024.0) as i32 - 1024 - 1;
        let end = (u0.max(u1) - 0.5 + r + 1024.0) as i32 - 1024 + 2;
        Some((first, (end - first).max(0) as usize))
    }

    /// Texel `i` clamped into the filter's range.
    #[inline(always)]
    pub fn index(&self, i: i32) -> usize {
        i.clamp(self.lo, self.hi) as usize
    }
}

/// One texel as four floats, its colour premultiplied by its alpha unless `OPAQUE`.
#[inline(always)]
fn texel<const OPAQUE: bool>(p: [u8; 4]) -> [f32; 4] {
    let f = [p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32];
    if OPAQUE {
        f
    } else {
        let a = f[3] * (1.0 / 255.0);
        [f[0] * a, f[1] * a, f[2] * a, f[3]]
    }
}

#[inline(always)]
fn mul_add(acc: &mut [f32; 4], p: [f32; 4], k: f32) {
    acc[0] += p[0] * k;
    acc[1] += p[1] * k;
    acc[2] += p[2] * k;
    acc[3] += p[3] * k;
}

/// The pixel of a filtered (premultiplied unless `OPAQUE`) sum.
#[inline(always)]
fn finish_filtered<const OPAQUE: bool>(acc: [f32; 4]) -> [u8; 4] {
    let q = |c: f32| (c + 0.5).clamp(0.0, 255.0) as u8;
    if OPAQUE {
        return [q(acc[0]), q(acc[1]), q(acc[2]), 255];
    }
    if acc[3] < 0.5 {
        return [0, 0, 0, 0];
    }
    let k = 255.0 / acc[3];
    [q(acc[0] * k), q(acc[1] * k), q(acc[2] * k), q(acc[3])]
}

impl Texels<'_> {
    /// The filtered colour at `(u, v)`: taps `fx` along x, `fy` along y, with alpha-weighted
    /// (premultiplied) arithmetic unless `OPAQUE`; clamped into the range of the texels read
    /// when `DERING` (a kernel with negative lobes would ring: a light halo around dark text
    /// on a coloured ground, colours the source does not have).
    #[inline(always)]
    pub fn filtered<const OPAQUE: bool, const DERING: bool>(
        &self,
        u: f32,
        v: f32,
        fx: &Filter,
        fy: &Filter,
    ) -> [u8; 4] {
        let mut wx = [0f32; MAX_FILTER_TAPS];
        let mut wy = [0f32; MAX_FILTER_TAPS];
        let (x0, nx) = fx.weights(u, &mut wx);
        let (y0, ny) = fy.weights(v, &mut wy);
        let mut acc = Column::EMPTY;
        for (j, &ky) in wy[..ny].iter().enumerate() {
            let row = &self.px[fy.index(y0 + j as i32) * self.w as usize..][..self.w as usize];
            let mut r = [0f32; 4];
            for (i, &kx) in wx[..nx].iter().enumerate() {
                let p = texel::<OPAQUE>(row[fx.index(x0 + i as i32)]);
                mul_add(&mut r, p, kx);
                if DERING {
                    acc.widen(p, p);
                }
            }
            mul_add(&mut acc.sum, r, ky);
        }
        finish_filtered::<OPAQUE>(acc.finish::<DERING>())
    }

    /// Fills `out` with the filtered colours at `(u0 + i·du, v)` ([`Texels::filtered`]): one
    /// row of samples that share their `v`, so the vertical taps are combined once per texel
    /// column (into `cols`) and each pixel sums only its horizontal taps over those.
    #[inline(always)]
    pub fn filtered_row<const OPAQUE: bool, const DERING: bool>(
        &self,
        (u0, du): (f32, f32),
        v: f32,
        (fx, fy): (&Filter, &Filter),
        cols: &mut Vec<Column>,
        out: &mut [[u8; 4]],
    ) {
        let Some((first, n)) = fx.columns(u0, du, out.len()) else {
            return;
        };
        let mut wy = [0f32; MAX_FILTER_TAPS];
        let (y0, ny) = fy.weights(v, &mut wy);
        cols.clear();
        cols.resize(n, Column::EMPTY);
        let w = self.w as usize;
        for (j, &ky) in wy[..ny].iter().enumerate() {
            let row = &self.px[fy.index(y0 + j as i32) * w..][..w];
            for (k, c) in cols.iter_mut().enumerate() {
                let p = texel::<OPAQUE>(row[fx.index(first + k as i32)]);
                mul_add(&mut c.sum, p, ky);
                if DERING {
                    c.widen(p, p);
                }
            }
        }
        let mut wx = [0f32; MAX_FILTER_TAPS];
        let mut u = u0;
        for px in out.iter_mut() {
            let (x0, nx) = fx.weights(u, &mut wx);
            let base = (x0 - first).max(0) as usize;
            let mut acc = Column::EMPTY;
            for (c, &kx) in cols[base..].iter().zip(&wx[..nx]) {
                mul_add(&mut acc.sum, c.sum, kx);
                if DERING {
                    acc.widen(c.lo, c.hi);
                }
            }
            *px = finish_filtered::<OPAQUE>(acc.finish::<DERING>());
            u += du;
        }
    }

    /// [`Texels::filtered_row`] for an opaque source and a kernel without negative lobes
    /// ([`Kernel::Area`]), in SWAR integer lanes: weights quantized to 12 bits (8 lose a level
    /// or more over the 15 taps of a wide footprint), the columns rounded back to 8 bits a
    /// channel before the horizontal pass, one multiply a tap for all three channels (within
    /// two levels of the float path, at about half its cost).
    #[inline(always)]
    pub fn area_row_opaque(
        &self,
        (u0, du): (f32, f32),
        v: f32,
        (fx, fy): (&Filter, &Filter),
        cols: &mut Vec<u64>,
        out: &mut [[u8; 4]],
    ) {
        let Some((first, n)) = fx.columns(u0, du, out.len()) else {
            return;
        };
        let mut w = [0f32; MAX_FILTER_TAPS];
        let mut q = [0u64; MAX_FILTER_TAPS];
        let (y0, ny) = fy.weights(v, &mut w);
        quantize(&w[..ny], &mut q);
        cols.clear();
        cols.resize(n, 0);
        let tw = self.w as usize;
        for (j, &k) in q[..ny].iter().enumerate() {
            let row = &self.px[fy.index(y0 + j as i32) * tw..][..tw];
            for (i, c) in cols.iter_mut().enumerate() {
                *c += lanes(row[fx.index(first + i as i32)]) * k;
            }
        }
        for c in cols.iter_mut() {
            *c = ((*c + ROUND12) >> WEIGHT_BITS) & LANE8;
        }
        let mut u = u0;
        for px in out.iter_mut() {
            let (x0, nx) = fx.weights(u, &mut w);
            quantize(&w[..nx], &mut q);
            let base = (x0 - first).max(0) as usize;
            let mut acc = 0u64;
            for (c, &k) in cols[base..].iter().zip(&q[..nx]) {
                acc += c * k;
            }
            let a = acc + ROUND12;
            *px = [
                (a >> WEIGHT_BITS & 255) as u8,
                (a >> (21 + WEIGHT_BITS) & 255) as u8,
                (a >> (42 + WEIGHT_BITS) & 255) as u8,
                255,
            ];
            u += du;
        }
    }
}

/// Bits of a quantized weight: a lane's 255 · 2^12 plus rounding stays below its 21 bits.
const WEIGHT_BITS: u32 = 12;
const WEIGHT_ONE: u64 = 1 << WEIGHT_BITS;
/// Rounding of each lane before dropping the weight's bits.
const ROUND12: u64 = (WEIGHT_ONE / 2) * (1 | 1 << 21 | 1 << 42);
/// The low 8 bits of each lane.
const LANE8: u64 = 0xFF | 0xFF << 21 | 0xFF << 42;

/// Non-negative weights summing to 1 as integers summing to [`WEIGHT_ONE`] (the rounding
/// error goes to the largest).
#[inline(always)]
fn quantize(w: &[f32], q: &mut [u64; MAX_FILTER_TAPS]) {
    let mut sum = 0i64;
    let mut big = 0;
    for (i, (&v, q)) in w.iter().zip(q.iter_mut()).enumerate() {
        *q = (v * WEIGHT_ONE as f32 + 0.5) as u64;
        sum += *q as i64;
        if v > w[big] {
            big = i;
        }
    }
    if !w.is_empty() {
        q[big] = (q[big] as i64 + WEIGHT_ONE as i64 - sum).max(0) as u64;
    }
}

/// A weighted sum of texels, with the range of the texels summed (for deringing).
#[derive(Copy, Clone, Debug)]
pub(crate) struct Column {
    sum: [f32; 4],
    lo: [f32; 4],
    hi: [f32; 4],
}

impl Column {
    const EMPTY: Column = Column {
        sum: [0.0; 4],
        lo: [f32::INFINITY; 4],
        hi: [f32::NEG_INFINITY; 4],
    };

    #[inline(always)]
    fn widen(&mut self, lo: [f32; 4], hi: [f32; 4]) {
        for k in 0..4 {
            self.lo[k] = self.lo[k].min(lo[k]);
            self.hi[k] = self.hi[k].max(hi[k]);
        }
    }

    /// The sum, clamped into the range when `DERING`.
    #[inline(always)]
    fn finish<const DERING: bool>(self) -> [f32; 4] {
        if !DERING {
            return self.sum;
        }
        let mut s = self.sum;
        for ((s, lo), hi) in s.iter_mut().zip(self.lo).zip(self.hi) {
            *s = s.max(lo).min(hi);
        }
        s
    }
}

const LANE12: u64 = 0xFFF | 0xFFF << 21 | 0xFFF << 42;

/// RGB spread into three 21-bit lanes of a `u64`.
#[inline(always)]
pub(crate) fn lanes(p: [u8; 4]) -> u64 {
    let x = u32::from_le_bytes(p) as u64;
    (x & 0xFF) | (x & 0xFF00) << 13 | (x & 0xFF_0000) << 26
}

/// One opaque bilinear sample as a pixel.
#[inline(always)]
pub(crate) fn finish_one(l: u64) -> [u8; 4] {
    let r = l + (2048 | 2048 << 21 | 2048 << 42);
    [
        (r >> 12 & 255) as u8,
        (r >> 33 & 255) as u8,
        (r >> 54 & 255) as u8,
        255,
    ]
}

/// Final pixel from `n` summed premultiplied samples.
#[inline(always)]
pub(crate) fn finish_premul(acc: [f32; 4], n: u32) -> [u8; 4] {
    if acc[3] <= 0.0 {
        return [0, 0, 0, 0];
    }
    let k = 1.0 / acc[3];
    [
        (acc[0] * k + 0.5) as u8,
        (acc[1] * k + 0.5) as u8,
        (acc[2] * k + 0.5) as u8,
        (acc[3] / n as f32 + 0.5).min(255.0) as u8,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_is_floor_with_fraction() {
        assert_eq!(split(0.5), (0, 0));
        assert_eq!(split(1.0), (0, 128));
        assert_eq!(split(0.0), (-1, 128));
        assert_eq!(split(2.75), (2, 64));
    }

    #[test]
    fn integer_and_float_paths_agree_on_opaque_pixels() {
        let px: Vec<[u8; 4]> = (0..64u32)
            .map(|i| [(i * 37) as u8, (i * 11) as u8, (i * 3) as u8, 255])
            .collect();
        let t = Texels {
            px: &px,
            w: 8,
            h: 8,
        };
        for (u, v) in [(0.5, 0.5), (3.3, 4.9), (7.9, 0.1), (5.0, 5.0)] {
            let a = finish_one(t.bilinear_lanes(u, v));
            let mut acc = [0.0; 4];
            t.bilinear_premul(u, v, &mut acc);
            let b = finish_premul(acc, 1);
            for k in 0..4 {
                assert!((a[k] as i32 - b[k] as i32).abs() <= 1, "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn filter_weights_are_normalized_and_a_texel_centre_reads_one_texel() {
        for kernel in [Kernel::CatmullRom, Kernel::Area] {
            for scale in [1.0f32, 1.3, 2.0, 3.7] {
                let f = Filter::new(kernel, scale, 0, 100);
                let mut w = [0f32; MAX_FILTER_TAPS];
                for k in 0..40 {
                    let u = 20.0 + k as f32 * 0.137;
                    let (first, n) = f.weights(u, &mut w);
                    let sum: f32 = w[..n].iter().sum();
                    assert!((sum - 1.0).abs() < 1e-5, "{kernel:?} {scale} {u}: {sum}");
                    // Every tap lies within the kernel's reach of the sample.
                    for i in first..first + n as i32 {
                        assert!((i as f32 + 0.5 - u).abs() <= f.reach() + 1e-4);
                    }
                }
            }
            let f = Filter::new(kernel, 1.0, 0, 100);
            let mut w = [0f32; MAX_FILTER_TAPS];
            assert_eq!(f.weights(7.5, &mut w), (7, 1), "{kernel:?}");
            assert_eq!(w[0], 1.0);
        }
    }

    /// Catmull-Rom's negative lobes would put a light halo, lighter than the ground, beside a
    /// dark stroke on a grey ground; clamped to the texels read, the output keeps the source's
    /// range.
    #[test]
    fn catmull_rom_does_not_ring() {
        let px: Vec<[u8; 4]> = (0..40)
            .map(|x| {
                if x == 20 {
                    [0, 0, 0, 255]
                } else {
                    [128, 128, 128, 255]
                }
            })
            .collect();
        let t = Texels {
            px: &px,
            w: 40,
            h: 1,
        };
        let fy = Filter::new(Kernel::CatmullRom, 1.0, 0, 0);
        for scale in [1.0f32, 1.4, 2.5] {
            let fx = Filter::new(Kernel::CatmullRom, scale, 0, 39);
            let mut darkest = 255;
            for k in 0..200 {
                let u = 10.0 + k as f32 * 0.1;
                let p = t.filtered::<true, true>(u, 0.5, &fx, &fy);
                assert!(p[0] <= 128, "{scale} at {u}: {p:?}");
                darkest = darkest.min(p[0]);
                let mut row = [[0u8; 4]; 3];
                let mut cols = Vec::new();
                t.filtered_row::<true, true>((u, 1.0), 0.5, (&fx, &fy), &mut cols, &mut row);
                assert_eq!(row[0], p, "the row path agrees with the single sample");
            }
            assert!(darkest < 128 - (100.0 / scale) as u8, "{scale}: {darkest}");
        }
    }

    /// The integer lanes of the area filter give the float path's colours within a level or
    /// two (8-bit weights, columns rounded to 8 bits).
    #[test]
    fn area_lanes_agree_with_the_float_path() {
        let (w, h) = (40usize, 12usize);
        let px: Vec<[u8; 4]> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                [
                    (x * 37 + y * 11) as u8,
                    (x * x * 3) as u8,
                    (255 - y * 20) as u8,
                    255,
                ]
            })
            .collect();
        let t = Texels {
            px: &px,
            w: w as i32,
            h: h as i32,
        };
        for (sx, sy) in [(1.3f32, 1.0f32), (1.9, 1.6), (3.5, 1.0)] {
            let fx = Filter::new(Kernel::Area, sx, 0, w as i32 - 1);
            let fy = Filter::new(Kernel::Area, sy, 0, h as i32 - 1);
            let (u0, du, v) = (3.3f32, sx, 5.7f32);
            let mut row = [[0u8; 4]; 9];
            let mut cols = Vec::new();
            t.area_row_opaque((u0, du), v, (&fx, &fy), &mut cols, &mut row);
            for (i, p) in row.iter().enumerate() {
                let q = t.filtered::<true, false>(u0 + du * i as f32, v, &fx, &fy);
                for k in 0..3 {
                    assert!(
                        (p[k] as i32 - q[k] as i32).abs() <= 2,
                        "{sx}x{sy} #{i}: {p:?} {q:?}"
                    );
                }
            }
        }
    }
}
