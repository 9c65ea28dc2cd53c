//! Pixel sampling kernels: bilinear for magnification and mild minification, a box of bilinear
//! taps over the pixel's footprint where a region is minified strongly (so that 1-px lines fade
//! to grey instead of aliasing away).
//!
//! Filtering weighs colours by alpha (premultiplied arithmetic), so transparent pixels never
//! bleed their colour into the edges of opaque ones.

use crate::image::ImageRef;

/// Accumulated premultiplied colour.
#[derive(Copy, Clone, Default)]
pub(crate) struct Acc {
    pub r: f32,
    pub g: f32,
    pub b: f32,
    pub a: f32,
}

impl Acc {
    #[inline]
    pub fn to_rgba(self, inv_n: f32) -> [u8; 4] {
        let a = self.a * inv_n;
        if a <= 0.0 {
            return [0, 0, 0, 0];
        }
        let k = 1.0 / self.a;
        [
            (self.r * k + 0.5) as u8,
            (self.g * k + 0.5) as u8,
            (self.b * k + 0.5) as u8,
            (a + 0.5).min(255.0) as u8,
        ]
    }
}

/// Adds the bilinear sample at source position `(u, v)` (pixel centres at `i + 0.5`), edges
/// clamped, with weight `wt`.
#[inline]
pub(crate) fn bilinear_into(src: &ImageRef<'_>, u: f32, v: f32, wt: f32, acc: &mut Acc) {
    let w = src.width() as i32;
    let h = src.height() as i32;
    let fx = u - 0.5;
    let fy = v - 0.5;
    let x0f = fx.floor();
    let y0f = fy.floor();
    let tx = fx - x0f;
    let ty = fy - y0f;
    let x0 = (x0f as i32).clamp(0, w - 1) as usize;
    let x1 = (x0f as i32 + 1).clamp(0, w - 1) as usize;
    let y0 = (y0f as i32).clamp(0, h - 1) as usize;
    let y1 = (y0f as i32 + 1).clamp(0, h - 1) as usize;
    let px = src.pixels();
    let wu = w as usize;
    let taps = [
        (px[y0 * wu + x0], (1.0 - tx) * (1.0 - ty)),
        (px[y0 * wu + x1], tx * (1.0 - ty)),
        (px[y1 * wu + x0], (1.0 - tx) * ty),
        (px[y1 * wu + x1], tx * ty),
    ];
    for (p, k) in taps {
        let a = p[3] as f32 * k * wt;
        acc.r += p[0] as f32 * a;
        acc.g += p[1] as f32 * a;
        acc.b += p[2] as f32 * a;
        acc.a += a;
    }
}

/// Bilinear sample of an opaque source (no alpha weighting needed).
#[inline]
pub(crate) fn bilinear_opaque(src: &ImageRef<'_>, u: f32, v: f32) -> [u8; 4] {
    let w = src.width() as i32;
    let h = src.height() as i32;
    let fx = u - 0.5;
    let fy = v - 0.5;
    let x0f = fx.floor();
    let y0f = fy.floor();
    let tx = fx - x0f;
    let ty = fy - y0f;
    let x0 = (x0f as i32).clamp(0, w - 1) as usize;
    let x1 = (x0f as i32 + 1).clamp(0, w - 1) as usize;
    let y0 = (y0f as i32).clamp(0, h - 1) as usize;
    let y1 = (y0f as i32 + 1).clamp(0, h - 1) as usize;
    let px = src.pixels();
    let wu = w as usize;
    let (a, b, c, d) = (
        px[y0 * wu + x0],
        px[y0 * wu + x1],
        px[y1 * wu + x0],
        px[y1 * wu + x1],
    );
    let mut out = [255u8; 4];
    for ch in 0..3 {
        let top = a[ch] as f32 + (b[ch] as f32 - a[ch] as f32) * tx;
        let bot = c[ch] as f32 + (d[ch] as f32 - c[ch] as f32) * tx;
        out[ch] = (top + (bot - top) * ty + 0.5) as u8;
    }
    out
}
