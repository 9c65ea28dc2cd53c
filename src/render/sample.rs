//! Pixel sampling kernels: bilinear for magnification and mild minification, a box of bilinear
//! taps over the pixel's footprint where a region is minified strongly (so that 1-px lines fade
//! to grey instead of aliasing away).
//!
//! Opaque sources (nearly every visualization) take an integer path: 8-bit sub-pixel weights,
//! three channels, no alpha arithmetic. Sources with transparency take a float path that weighs
//! colours by alpha (premultiplied arithmetic), so transparent pixels never bleed their colour
//! into the edges of opaque ones. Coordinates become integers by truncation after a shift that
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

const LANE: u64 = (1 << 21) - 1;
const LANE12: u64 = 0xFFF | 0xFFF << 21 | 0xFFF << 42;

/// RGB spread into three 21-bit lanes of a `u64`.
#[inline(always)]
pub(crate) fn lanes(p: [u8; 4]) -> u64 {
    let x = u32::from_le_bytes(p) as u64;
    (x & 0xFF) | (x & 0xFF00) << 13 | (x & 0xFF_0000) << 26
}

/// The three lanes as separate channel values (still scaled by 4096).
#[inline(always)]
pub(crate) fn unpack(l: u64) -> [u32; 3] {
    [
        (l & LANE) as u32,
        (l >> 21 & LANE) as u32,
        (l >> 42 & LANE) as u32,
    ]
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

/// Pixel from the sum of `n` opaque samples (channels scaled by 4096); `inv = 1 / (4096 n)`.
#[inline(always)]
pub(crate) fn finish_sum(sum: [u32; 3], inv: f32) -> [u8; 4] {
    [
        (sum[0] as f32 * inv + 0.5) as u8,
        (sum[1] as f32 * inv + 0.5) as u8,
        (sum[2] as f32 * inv + 0.5) as u8,
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
            assert_eq!(a, finish_sum(unpack(t.bilinear_lanes(u, v)), 1.0 / 4096.0));
            let mut acc = [0.0; 4];
            t.bilinear_premul(u, v, &mut acc);
            let b = finish_premul(acc, 1);
            for k in 0..4 {
                assert!((a[k] as i32 - b[k] as i32).abs() <= 1, "{a:?} {b:?}");
            }
        }
    }
}
