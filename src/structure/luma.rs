//! Luminance at full resolution, composited over white, as bytes: the input of line and text
//! detection (both need the pixel grid exactly; the VSM may be at half resolution).

use crate::image::ImageRef;

/// Rec. 601 luma of every pixel (over white), row-major.
pub(crate) fn luma(image: ImageRef<'_>, out: &mut Vec<u8>) {
    // Sized first, then one loop over both slices, in 16-bit lanes (every term fits): it runs
    // in vectors, where `extend` from a mapped iterator went pixel by pixel.
    out.clear();
    out.resize(image.pixels().len(), 0);
    for (o, p) in out.iter_mut().zip(image.pixels()) {
        let a = p[3] as u16;
        let y = (p[0] as u16 * 77 + p[1] as u16 * 150 + p[2] as u16 * 29) >> 8;
        *o = div255(y * a + 255 * (255 - a) + 127);
    }
}

/// The `w × h` image `l` transposed (`h × w`: column `x` becomes row `x`), so that vertical
/// lines and sideways text are read along rows as well. Copied in square blocks that stay in
/// cache on both sides.
pub(crate) fn transposed(l: &[u8], w: usize, h: usize) -> Vec<u8> {
    const BLOCK: usize = 32;
    let mut t = vec![0u8; w * h];
    for y0 in (0..h).step_by(BLOCK) {
        for x0 in (0..w).step_by(BLOCK) {
            for y in y0..(y0 + BLOCK).min(h) {
                let row = &l[y * w..][x0..(x0 + BLOCK).min(w)];
                for (x, &v) in (x0..).zip(row) {
                    t[x * h + y] = v;
                }
            }
        }
    }
    t
}

/// `x / 255` for `x` up to 65152 (the most the luma's blend reaches), without a division.
#[inline(always)]
fn div255(x: u16) -> u8 {
    ((x + 1 + (x >> 8)) >> 8) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dividing_by_255_without_a_division_is_exact() {
        for x in 0..=65152u16 {
            assert_eq!(div255(x) as u16, x / 255, "{x}");
        }
    }
}
