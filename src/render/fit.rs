//! A canvas drawn at one scale: where nothing on a canvas taken whole can give way (no text
//! band kept at its size, no blank margin for the plot to grow into), its map is the linear
//! resize's, which squeezes every shape along one axis. Judged blind on the cases where the
//! default drew exactly that, readers preferred the picture at one scale, the smaller of the
//! two, centred on its own ground, to the squeezed one in every case (18 of 18, 2026-12-04):
//! nothing is bent, every position and size stays proportional, round marks stay round, and
//! the text keeps its shape, only smaller. The room left over is the picture's ground.

use super::canvas::CanvasMap;
use super::resize::{resize_linear_on, Threads};
use crate::image::{Image, ImageRef, Size};
use std::collections::HashMap;

/// Least change of aspect for a canvas to be drawn at one scale: below it the linear
/// resize's squeeze is too slight to see (a circle 2 % out of round), while the bands of
/// ground the scale would leave would show.
const LEAST_ASPECT_CHANGE: f64 = 1.02;

/// Least share of the pixels along the picture's edge that must be of one colour for the
/// picture to have a ground to stand on: most of the edge. Without one (a gradient, a photo
/// to the edge) the room left over would take a colour foreign to the picture, and the
/// canvas is left to the linear resize.
const LEAST_GROUND_SHARE: f64 = 0.5;

/// A canvas at one scale: its picture resized to `content` and put at `at` on a canvas of
/// its `ground`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct Fit {
    pub content: Size,
    pub at: [u32; 2],
    pub ground: [u8; 4],
}

impl Fit {
    /// The fit of canvas `src` onto `target` when `map` (the canvas' map) is the linear
    /// resize's along both axes, the aspect changes visibly and the picture has a ground;
    /// `None` otherwise.
    pub fn of(map: &CanvasMap, src: ImageRef<'_>, target: Size) -> Option<Fit> {
        let source = src.size();
        if !(map.x.is_linear() && map.y.is_linear() && map.panels.is_empty()) {
            return None;
        }
        let sx = target.width as f64 / source.width as f64;
        let sy = target.height as f64 / source.height as f64;
        if sx.max(sy) < sx.min(sy) * LEAST_ASPECT_CHANGE {
            return None;
        }
        let (ground, share) = ground(src);
        if share < LEAST_GROUND_SHARE {
            return None;
        }
        let s = sx.min(sy);
        let side = |n: u32, m: u32| ((n as f64 * s).round() as u32).clamp(1, m);
        let content = Size::new(
            side(source.width, target.width),
            side(source.height, target.height),
        )
        .ok()?;
        Some(Fit {
            content,
            at: [
                (target.width - content.width) / 2,
                (target.height - content.height) / 2,
            ],
            ground,
        })
    }

    /// `src` drawn on a `target` canvas of its ground, at this fit.
    pub fn draw(&self, src: ImageRef<'_>, target: Size, threads: Threads) -> Image {
        let mut out = Image::filled(target, self.ground);
        let content = resize_linear_on(src, self.content, threads);
        let (w, x0) = (self.content.width as usize, self.at[0] as usize);
        for (y, row) in content.pixels().chunks_exact(w).enumerate() {
            out.row_mut(self.at[1] + y as u32)[x0..x0 + w].copy_from_slice(row);
        }
        out
    }
}

/// Rings of pixels along the picture's edge read for its ground: more than twice a frame's
/// line is thick (one or two pixels), so that the ground inside it outnumbers it.
const GROUND_RINGS: usize = 6;

/// The colour most pixels of the picture's outer [`GROUND_RINGS`] rings have, and their share:
/// the ground the room left over takes (a page's white, a dark theme's black, a map's sea),
/// transparency and all. Rings along the whole edge, not a band as wide as a header bar,
/// which would outweigh the page around it.
fn ground(src: ImageRef<'_>) -> ([u8; 4], f64) {
    let (w, h) = (src.width() as usize, src.height() as usize);
    let px = src.pixels();
    let rings = GROUND_RINGS.min(w.div_ceil(2)).min(h.div_ceil(2));
    // Per colour: how many, and the first pixel seen of it (clear pixels are one colour,
    // drawn as the first of them: a uniform clear picture stays uniform).
    let mut count: HashMap<[u8; 4], (u32, [u8; 4])> = HashMap::new();
    let mut all = 0u32;
    for (y, row) in px.chunks_exact(w).enumerate() {
        // Whole rows near the top and bottom, the ends of the others.
        let (a, b) = match y < rings || y + rings >= h {
            true => (row, &row[w..]),
            false => (&row[..rings], &row[(w - rings).max(rings)..]),
        };
        for &p in a.iter().chain(b) {
            // Clear pixels are one ground, whatever colour they hide.
            let key = if p[3] == 0 { [0; 4] } else { p };
            count.entry(key).or_insert((0, p)).0 += 1;
            all += 1;
        }
    }
    // The commonest, the smallest value among equals: the same colour whatever the order.
    (count.into_iter())
        .max_by_key(|&(c, (n, _))| (n, std::cmp::Reverse(c)))
        .map_or(([255; 4], 0.0), |(_, (n, p))| (p, n as f64 / all as f64))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::AxisMap;

    /// A disc on a grey ground, halved in width: drawn at half size both ways, centred, on
    /// grey; the disc stays round.
    #[test]
    fn a_squeezed_canvas_keeps_its_shapes_at_one_scale() {
        let (source, target) = (Size::new(200, 100).unwrap(), Size::new(100, 100).unwrap());
        let mut img = Image::filled(source, [200, 200, 200, 255]);
        for y in 0..100u32 {
            for x in 0..200u32 {
                let (dx, dy) = (x as f64 + 0.5 - 100.0, y as f64 + 0.5 - 50.0);
                if dx * dx + dy * dy < 40.0 * 40.0 {
                    img.set(x, y, [20, 40, 200, 255]);
                }
            }
        }
        let fit = Fit::of(&CanvasMap::linear(source, target), img.as_ref(), target).expect("a fit");
        let (content, ground) = (Size::new(100, 50).unwrap(), [200, 200, 200, 255]);
        assert_eq!(
            fit,
            Fit {
                content,
                at: [0, 25],
                ground
            }
        );
        let out = fit.draw(img.as_ref(), target, Threads::One);
        assert_eq!(out.size(), target);
        // The ground above and below, the disc's extent equal both ways.
        assert_eq!(out.get(50, 5), [200, 200, 200, 255]);
        assert_eq!(out.get(50, 94), [200, 200, 200, 255]);
        let blue = |x: u32, y: u32| out.get(x, y)[2] > 150 && out.get(x, y)[0] < 80;
        let across = (0..100).filter(|&x| blue(x, 50)).count() as i64;
        let down = (0..100).filter(|&y| blue(50, y)).count() as i64;
        assert!(
            (across - 40).abs() <= 1 && (down - 40).abs() <= 1,
            "{across} {down}"
        );
    }

    /// A map that bends anything, an aspect that hardly changes, or a picture without a
    /// ground along its edge is not fitted.
    #[test]
    fn only_a_linear_map_of_a_changed_aspect_on_a_ground_is_fitted() {
        let source = Size::new(200, 100).unwrap();
        let white = Image::filled(source, [255; 4]);
        let src = white.as_ref();
        let same = Size::new(100, 50).unwrap();
        assert_eq!(Fit::of(&CanvasMap::linear(source, same), src, same), None);
        let slight = Size::new(101, 50).unwrap();
        assert_eq!(
            Fit::of(&CanvasMap::linear(source, slight), src, slight),
            None
        );
        let mut ramp = white.clone();
        for y in 0..100 {
            for x in 0..200 {
                ramp.set(x, y, [(x + y) as u8, 100, 200, 255]);
            }
        }
        let target = Size::new(100, 100).unwrap();
        assert_eq!(
            Fit::of(&CanvasMap::linear(source, target), ramp.as_ref(), target),
            None
        );
        let bent = CanvasMap {
            x: AxisMap::with_bands(200, 100, &[[10, 40]], &[[0, 10], [40, 70]], &[[0, 10]]),
            y: AxisMap::linear(100, 100),
            panels: Vec::new(),
        };
        assert!(!bent.x.is_linear());
        assert_eq!(Fit::of(&bent, src, target), None);
        // Taller too: the picture at its width's scale, centred down the canvas.
        let tall = Size::new(200, 300).unwrap();
        let fit = Fit::of(&CanvasMap::linear(source, tall), src, tall).unwrap();
        let (content, ground) = (Size::new(200, 100).unwrap(), [255; 4]);
        assert_eq!(
            fit,
            Fit {
                content,
                at: [0, 100],
                ground
            }
        );
    }

    /// The ground is the commonest colour along the edge, not a frame's line around it.
    #[test]
    fn the_ground_is_the_commonest_colour_along_the_edge() {
        let mut img = Image::filled(Size::new(200, 120).unwrap(), [250, 250, 250, 255]);
        for x in 0..200 {
            img.set(x, 0, [40, 40, 40, 255]);
            img.set(x, 119, [40, 40, 40, 255]);
        }
        for y in 0..120 {
            img.set(0, y, [40, 40, 40, 255]);
            img.set(199, y, [40, 40, 40, 255]);
        }
        let (colour, share) = ground(img.as_ref());
        assert_eq!(colour, [250, 250, 250, 255]);
        assert!((0.5..0.9).contains(&share), "{share}");
        let tiny = Image::filled(Size::new(1, 1).unwrap(), [1, 2, 3, 4]);
        assert_eq!(ground(tiny.as_ref()), ([1, 2, 3, 4], 1.0));
        // Clear pixels hiding many colours are one clear ground; a narrow picture's middle
        // column is counted once.
        let mut clear = Image::filled(Size::new(9, 30).unwrap(), [0; 4]);
        for (i, p) in clear.pixels_mut().iter_mut().enumerate() {
            *p = [i as u8, (i * 7) as u8, 3, 0];
        }
        clear.set(4, 15, [9, 9, 9, 255]);
        let (colour, share) = ground(clear.as_ref());
        assert_eq!(colour[3], 0);
        assert!(share < 1.0 && share > 0.99, "{share}");
    }
}
