//! Box-filtered reductions of the source, by `2^lx` along x and `2^ly` along y ("ripmaps"),
//! built on demand for one frame.
//!
//! A background triangle shrunk 3× along x would need three taps per output pixel from the
//! source; one bilinear tap in the level halved along x covers the same footprint. On the
//! 1500×800 → 750×800 graph case this took the renderer from 1.25 M to about 0.6 M taps.
//! Levels are per axis because retargeting shrinks one axis far more than the other.

use crate::image::{Image, ImageRef, Size};

/// Levels per axis: reductions up to 8×; beyond that the renderer's taps cover the rest.
pub(crate) const LEVELS: usize = 4;

/// The levels of one source frame.
#[derive(Default)]
pub(crate) struct Ripmap {
    levels: Vec<Option<Image>>,
}

impl Ripmap {
    /// Forgets the levels of the previous frame (keeps nothing that could be stale).
    pub fn clear(&mut self) {
        self.levels.clear();
        self.levels.resize_with(LEVELS * LEVELS, || None);
    }

    /// The level `(lx, ly)` of `src`, building it (and the levels it derives from) if needed.
    /// Level `(0, 0)` is `src` itself.
    pub fn level<'a>(&'a mut self, src: ImageRef<'a>, lx: usize, ly: usize) -> ImageRef<'a> {
        if lx == 0 && ly == 0 {
            return src;
        }
        self.ensure(src, lx, ly);
        self.levels[lx * LEVELS + ly]
            .as_ref()
            .expect("built")
            .as_ref()
    }

    fn ensure(&mut self, src: ImageRef<'_>, lx: usize, ly: usize) {
        if (lx == 0 && ly == 0) || self.levels[lx * LEVELS + ly].is_some() {
            return;
        }
        // Derive from the level one step back along x when possible, else along y.
        let (px, py, along_x) = if lx > 0 {
            (lx - 1, ly, true)
        } else {
            (lx, ly - 1, false)
        };
        self.ensure(src, px, py);
        let parent = if px == 0 && py == 0 {
            src
        } else {
            self.levels[px * LEVELS + py]
                .as_ref()
                .expect("built")
                .as_ref()
        };
        let img = halve(parent, along_x);
        self.levels[lx * LEVELS + ly] = Some(img);
    }
}

/// `src` halved along one axis: each texel is the alpha-weighted mean of two (an odd last one
/// is kept as is).
fn halve(src: ImageRef<'_>, along_x: bool) -> Image {
    let (w, h) = (src.width() as usize, src.height() as usize);
    let (nw, nh) = if along_x {
        (w.div_ceil(2), h)
    } else {
        (w, h.div_ceil(2))
    };
    let size = Size {
        width: nw as u32,
        height: nh as u32,
    };
    let px = src.pixels();
    let mut out = Vec::with_capacity(nw * nh);
    for y in 0..nh {
        for x in 0..nw {
            let (a, b) = if along_x {
                let i = y * w + 2 * x;
                (px[i], px[if 2 * x + 1 < w { i + 1 } else { i }])
            } else {
                let i = 2 * y * w + x;
                (px[i], px[if 2 * y + 1 < h { i + w } else { i }])
            };
            out.push(mean2(a, b));
        }
    }
    Image::from_pixels(size, out).expect("size matches")
}

#[inline]
fn mean2(a: [u8; 4], b: [u8; 4]) -> [u8; 4] {
    if a[3] == 255 && b[3] == 255 {
        return [
            ((a[0] as u16 + b[0] as u16 + 1) >> 1) as u8,
            ((a[1] as u16 + b[1] as u16 + 1) >> 1) as u8,
            ((a[2] as u16 + b[2] as u16 + 1) >> 1) as u8,
            255,
        ];
    }
    let (wa, wb) = (a[3] as u32, b[3] as u32);
    let sum = wa + wb;
    if sum == 0 {
        return [0, 0, 0, 0];
    }
    let c = |k: usize| ((a[k] as u32 * wa + b[k] as u32 * wb + sum / 2) / sum) as u8;
    [c(0), c(1), c(2), sum.div_ceil(2) as u8]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halving_averages_pairs_and_keeps_odd_edges() {
        let px = vec![[10, 20, 30, 255], [30, 40, 50, 255], [100, 100, 100, 255]];
        let img = Image::from_pixels(Size::new(3, 1).unwrap(), px).unwrap();
        let h = halve(img.as_ref(), true);
        assert_eq!(h.size(), Size::new(2, 1).unwrap());
        assert_eq!(h.pixels(), &[[20, 30, 40, 255], [100, 100, 100, 255]]);
        // Transparent pixels do not darken their neighbour.
        let px = vec![[200, 0, 0, 255], [0, 0, 0, 0]];
        let img = Image::from_pixels(Size::new(1, 2).unwrap(), px).unwrap();
        assert_eq!(halve(img.as_ref(), false).pixels(), &[[200, 0, 0, 128]]);
    }

    #[test]
    fn levels_compose() {
        let img = Image::filled(Size::new(13, 7).unwrap(), [9, 8, 7, 255]);
        let mut r = Ripmap::default();
        r.clear();
        let l = r.level(img.as_ref(), 2, 1);
        assert_eq!(l.size(), Size::new(4, 4).unwrap());
        assert!(l.pixels().iter().all(|&p| p == [9, 8, 7, 255]));
    }
}
