//! Luminance at full resolution, composited over white, as bytes: the input of line and text
//! detection (both need the pixel grid exactly; the VSM may be at half resolution).

use crate::image::ImageRef;

crate::simd::with_feature! {
    "avx2";
    /// Rec. 601 luma of every pixel (over white), row-major.
    pub(crate) fn luma(image: ImageRef<'_>, out: &mut Vec<u8>) => luma_body {
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
}

/// The `w × h` image `l` transposed (`h × w`: column `x` becomes row `x`), so that vertical
/// lines and sideways text are read along rows as well. In 8 × 8 blocks, each turned in
/// three word-wide swaps ([`transpose8`]) instead of 64 scattered byte stores.
pub(crate) fn transposed(l: &[u8], w: usize, h: usize) -> Vec<u8> {
    let mut t = vec![0u8; w * h];
    let (w8, h8) = (w - w % 8, h - h % 8);
    for y0 in (0..h8).step_by(8) {
        for x0 in (0..w8).step_by(8) {
            let mut a: [u64; 8] = std::array::from_fn(|i| {
                let row = &l[(y0 + i) * w + x0..][..8];
                u64::from_le_bytes(row.try_into().expect("eight bytes"))
            });
            transpose8(&mut a);
            for (i, v) in a.iter().enumerate() {
                t[(x0 + i) * h + y0..][..8].copy_from_slice(&v.to_le_bytes());
            }
        }
    }
    // The strips right of and below the whole blocks, a byte at a time.
    for y in 0..h {
        for x in w8..w {
            t[x * h + y] = l[y * w + x];
        }
    }
    for y in h8..h {
        for x in 0..w8 {
            t[x * h + y] = l[y * w + x];
        }
    }
    t
}

/// An 8 × 8 block of bytes (row `i` in `a[i]`, byte `j` of it column `j`) transposed in
/// place: swaps of single bytes between neighbouring rows, then of byte pairs two rows
/// apart, then of halves four rows apart.
#[inline(always)]
fn transpose8(a: &mut [u64; 8]) {
    /// A swap's shift, the mask of what it moves, and the rows it swaps between.
    type Step = (u32, u64, [(usize, usize); 4]);
    const STEPS: [Step; 3] = [
        (8, 0x00FF_00FF_00FF_00FF, [(0, 1), (2, 3), (4, 5), (6, 7)]),
        (16, 0x0000_FFFF_0000_FFFF, [(0, 2), (1, 3), (4, 6), (5, 7)]),
        (32, 0x0000_0000_FFFF_FFFF, [(0, 4), (1, 5), (2, 6), (3, 7)]),
    ];
    for (shift, mask, pairs) in STEPS {
        for (i, j) in pairs {
            let t = ((a[i] >> shift) ^ a[j]) & mask;
            a[j] ^= t;
            a[i] ^= t << shift;
        }
    }
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
    fn the_transpose_moves_every_byte_to_its_mirror_place() {
        for (w, h) in [(1, 1), (8, 8), (13, 7), (16, 24), (37, 21), (3, 40)] {
            let l: Vec<u8> = (0..w * h)
                .map(|i| ((i as u32).wrapping_mul(2_654_435_761) >> 24) as u8)
                .collect();
            let t = transposed(&l, w, h);
            for y in 0..h {
                for x in 0..w {
                    assert_eq!(t[x * h + y], l[y * w + x], "{w}x{h} at ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn every_build_of_the_luma_gives_the_formulas_bytes() {
        let (w, h) = (37u32, 23u32);
        let px = crate::image::noise_pixels((w * h) as usize, 0x9e37_79b9);
        let image = ImageRef::new(crate::image::Size::new(w, h).unwrap(), &px).unwrap();
        let (mut wide, mut base) = (Vec::new(), Vec::new());
        luma(image, &mut wide);
        luma_body(image, &mut base);
        assert_eq!(wide, base);
        for (&o, p) in wide.iter().zip(&px) {
            let y = (p[0] as u32 * 77 + p[1] as u32 * 150 + p[2] as u32 * 29) >> 8;
            let a = p[3] as u32;
            assert_eq!(o as u32, (y * a + 255 * (255 - a) + 127) / 255);
        }
    }

    #[test]
    fn dividing_by_255_without_a_division_is_exact() {
        for x in 0..=65152u16 {
            assert_eq!(div255(x) as u16, x / 255, "{x}");
        }
    }
}
