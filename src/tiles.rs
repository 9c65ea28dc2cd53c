//! Square tiles of the canvas: what a stream tracks change in. Below every stage (the saliency
//! updates, the mesh re-samples and the renderer redraws by tiles), so it depends on nothing
//! but the image.

use crate::image::{Image, Size};
use glam::DVec2;

/// A set of square tiles of the canvas.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TileMask {
    tile_px: u32,
    cols: u32,
    rows: u32,
    bits: Vec<bool>,
}

impl TileMask {
    /// An empty mask of `tile_px`-sized tiles over `size`.
    pub fn new(size: Size, tile_px: u32) -> TileMask {
        let tile_px = tile_px.max(1);
        let cols = size.width.div_ceil(tile_px);
        let rows = size.height.div_ceil(tile_px);
        TileMask {
            tile_px,
            cols,
            rows,
            bits: vec![false; (cols * rows) as usize],
        }
    }
    pub fn tile_px(&self) -> u32 {
        self.tile_px
    }
    pub fn cols(&self) -> u32 {
        self.cols
    }
    pub fn rows(&self) -> u32 {
        self.rows
    }
    pub fn set(&mut self, col: u32, row: u32) {
        if col < self.cols && row < self.rows {
            self.bits[(row * self.cols + col) as usize] = true;
        }
    }
    pub fn get(&self, col: u32, row: u32) -> bool {
        col < self.cols && row < self.rows && self.bits[(row * self.cols + col) as usize]
    }
    /// Number of set tiles.
    pub fn count(&self) -> usize {
        self.bits.iter().filter(|&&b| b).count()
    }
    pub fn is_empty(&self) -> bool {
        !self.bits.iter().any(|&b| b)
    }
    /// Share of tiles set.
    pub fn fraction(&self) -> f64 {
        self.count() as f64 / self.bits.len().max(1) as f64
    }
    /// Whether the tile holding image point `p` is set.
    pub fn contains(&self, p: DVec2) -> bool {
        if p.x < 0.0 || p.y < 0.0 {
            return false;
        }
        let t = self.tile_px as f64;
        // A point on a tile border belongs to both tiles.
        let (cx, cy) = ((p.x / t).floor() as u32, (p.y / t).floor() as u32);
        let on_x = p.x % t == 0.0 && cx > 0;
        let on_y = p.y % t == 0.0 && cy > 0;
        self.get(cx, cy)
            || (on_x && self.get(cx - 1, cy))
            || (on_y && self.get(cx, cy - 1))
            || (on_x && on_y && self.get(cx - 1, cy - 1))
    }
    /// Whether any set tile meets the rectangle `[x0, x1) × [y0, y1)` (image pixels).
    pub fn intersects(&self, x0: f64, y0: f64, x1: f64, y1: f64) -> bool {
        let t = self.tile_px as f64;
        let c0 = (x0 / t).floor().max(0.0) as u32;
        let r0 = (y0 / t).floor().max(0.0) as u32;
        let c1 = ((x1 / t).ceil().max(0.0) as u32).min(self.cols);
        let r1 = ((y1 / t).ceil().max(0.0) as u32).min(self.rows);
        (r0..r1).any(|r| (c0..c1).any(|c| self.get(c, r)))
    }
    /// Set tiles as pixel rectangles `(x0, y0, x1, y1)` clipped to `size`, runs of adjacent
    /// tiles in a row merged.
    pub fn rects(&self, size: Size) -> Vec<[u32; 4]> {
        let t = self.tile_px;
        let mut out = Vec::new();
        for r in 0..self.rows {
            let mut c = 0;
            while c < self.cols {
                if !self.get(c, r) {
                    c += 1;
                    continue;
                }
                let start = c;
                while c < self.cols && self.get(c, r) {
                    c += 1;
                }
                out.push([
                    start * t,
                    r * t,
                    (c * t).min(size.width),
                    ((r + 1) * t).min(size.height),
                ]);
            }
        }
        out
    }
}

/// Tiles of `tile_px` where `prev` and `now` (the same size) differ, with `prev` made a copy
/// of `now`: a row is copied only where it differs, right after it was compared (a stream's
/// unchanged rows are never copied, and the changed ones are still in cache), and a tile is
/// compared only until a difference is found in it.
pub(crate) fn take_changed_tiles(prev: &mut Image, now: &Image, tile_px: u32) -> TileMask {
    let size = prev.size();
    let mut mask = TileMask::new(size, tile_px);
    let w = size.width as usize;
    let t = mask.tile_px() as usize;
    for (y, (ra, rb)) in (prev.pixels_mut().chunks_exact_mut(w))
        .zip(now.pixels().chunks_exact(w))
        .enumerate()
    {
        if ra == rb {
            continue;
        }
        let row = (y / t) as u32;
        for (c, (ca, cb)) in ra.chunks(t).zip(rb.chunks(t)).enumerate() {
            // A tile found changed in a row above needs no comparing again.
            if !mask.get(c as u32, row) && ca != cb {
                mask.set(c as u32, row);
            }
        }
        ra.copy_from_slice(rb);
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
        let mut a = Image::filled(size, [255; 4]);
        let mut b = a.clone();
        assert!(take_changed_tiles(&mut a, &b, 32).is_empty());
        b.set(33, 5, [0, 0, 0, 255]);
        b.set(99, 69, [0, 0, 0, 255]);
        let m = take_changed_tiles(&mut a, &b, 32);
        assert_eq!(m.count(), 2);
        assert!(m.get(1, 0) && m.get(3, 2));
        // The previous frame became this one: compared again, nothing changed.
        assert!(a == b);
        assert!(take_changed_tiles(&mut a, &b, 32).is_empty());
    }
}
