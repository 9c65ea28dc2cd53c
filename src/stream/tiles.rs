//! Which tiles of a frame changed since the previous frame: a byte comparison of each tile's
//! rows, so an unchanged tile costs a `memcmp` and nothing else.

use crate::image::Image;
use crate::mesh::TileMask;

/// Tiles of `tile_px` where `a` and `b` (the same size) differ.
pub(crate) fn changed_tiles(a: &Image, b: &Image, tile_px: u32) -> TileMask {
    let size = a.size();
    let mut mask = TileMask::new(size, tile_px);
    let w = size.width as usize;
    let t = mask.tile_px() as usize;
    for (y, (ra, rb)) in a
        .pixels()
        .chunks_exact(w)
        .zip(b.pixels().chunks_exact(w))
        .enumerate()
    {
        if ra == rb {
            continue;
        }
        let row = (y / t) as u32;
        for (c, (ca, cb)) in ra.chunks(t).zip(rb.chunks(t)).enumerate() {
            if ca != cb {
                mask.set(c as u32, row);
            }
        }
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Size;

    #[test]
    fn finds_exactly_the_changed_tiles() {
        let size = Size::new(100, 70).unwrap();
        let a = Image::filled(size, [255; 4]);
        let mut b = a.clone();
        assert!(changed_tiles(&a, &b, 32).is_empty());
        b.set(33, 5, [0, 0, 0, 255]);
        b.set(99, 69, [0, 0, 0, 255]);
        let m = changed_tiles(&a, &b, 32);
        assert_eq!(m.count(), 2);
        assert!(m.get(1, 0) && m.get(3, 2));
    }
}
