//! Small raster marks floating over a kept warp: §5.3's adjustment of marks (drawn at their
//! own size where the warp carries their centre) for the marks of a stream that the mesh does
//! not ring.
//!
//! While saliency elsewhere stands still a stream keeps its mesh and solution, so a dot that
//! moved, or appeared, has no ring of its own. Rendered through whatever triangles it landed
//! in, it would be squashed; re-meshed around, it would drag the warp of everything near it
//! along from frame to frame (the coastlines beside a moving dot would shimmer). Instead it
//! floats: its pixels are painted out of the source, the source is warped as before, and the
//! mark is copied at full size, shifted by whole pixels to where the warp carries its centre.
//! Only the pixels it covered and now covers change.

use super::fill::fill_from_surroundings;
use crate::image::{Image, Size};
use crate::mesh::Mark;
use crate::saliency::Vsm;
use glam::DVec2;

/// Importance from which a pixel near a mark is part of it (the blob itself is found at 0.5;
/// this takes in most of its antialiased rim, the one-pixel growth below the rest).
const RIM_IMPORTANCE: f32 = 0.25;
/// Pixels beyond the blob's bounding box looked at for its rim.
const RIM_PX: u32 = 2;

/// One floating mark: its pixels in the source and the whole-pixel shift they are copied with.
#[derive(Clone, Debug)]
struct Paste {
    /// Source rectangle `[x0, y0, x1, y1)` the mask covers.
    rect: [u32; 4],
    /// One flag per pixel of `rect`, row by row.
    mask: Vec<bool>,
    offset: (i64, i64),
}

/// The floating marks of one frame.
#[derive(Clone, Debug, Default)]
pub(crate) struct Floating {
    pastes: Vec<Paste>,
}

impl Floating {
    /// The marks of `src` in `marks`, each placed by `place` (where the warp carries a source
    /// point; a mark it cannot place is left to the warp) on a canvas of `target`.
    pub fn new(
        src: &Image,
        vsm: &Vsm,
        marks: &[Mark],
        target: Size,
        place: impl Fn(DVec2) -> Option<DVec2>,
    ) -> Floating {
        let (w, h) = (src.width(), src.height());
        let s = vsm.scale();
        let gw = vsm.grid_size().width as usize;
        let imp = vsm.importance();
        let mut pastes = Vec::with_capacity(marks.len());
        for m in marks {
            let Some(to) = place(m.center) else {
                continue;
            };
            let d = to - m.center;
            if !d.x.is_finite() || !d.y.is_finite() {
                continue;
            }
            let [bx0, by0, bx1, by1] = m.bbox;
            let rect = [
                bx0.saturating_sub(RIM_PX),
                by0.saturating_sub(RIM_PX),
                (bx1 + RIM_PX).min(w),
                (by1 + RIM_PX).min(h),
            ];
            let (rw, rh) = ((rect[2] - rect[0]) as usize, (rect[3] - rect[1]) as usize);
            if rw == 0 || rh == 0 {
                continue;
            }
            let core: Vec<bool> = (0..rw * rh)
                .map(|i| {
                    let (x, y) = (rect[0] + (i % rw) as u32, rect[1] + (i / rw) as u32);
                    imp[(y / s) as usize * gw + (x / s) as usize] >= RIM_IMPORTANCE
                })
                .collect();
            let r2 = m.ring_radius * m.ring_radius;
            let mask: Vec<bool> = (0..rw * rh)
                .map(|i| {
                    let (x, y) = (i % rw, i / rw);
                    let p = DVec2::new(
                        (rect[0] as usize + x) as f64 + 0.5,
                        (rect[1] as usize + y) as f64 + 0.5,
                    );
                    if p.distance_squared(m.center) > r2 {
                        return false;
                    }
                    let near = |dx: i64, dy: i64| {
                        let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                        nx >= 0
                            && ny >= 0
                            && (nx as usize) < rw
                            && (ny as usize) < rh
                            && core[ny as usize * rw + nx as usize]
                    };
                    (-1..=1).any(|dy| (-1..=1).any(|dx| near(dx, dy)))
                })
                .collect();
            if mask.iter().any(|&b| b) {
                // A mark carried to the canvas's edge is pushed back inside it whole (the
                // warp squeezes the border, a mark drawn at its own size would be clipped).
                let keep_inside = |d: f64, lo: u32, hi: u32, side: u32| {
                    let d = d.round() as i64;
                    let (lo, hi, side) = (lo as i64, hi as i64, side as i64);
                    if hi - lo > side {
                        d
                    } else {
                        d.clamp(-lo, side - hi)
                    }
                };
                pastes.push(Paste {
                    rect,
                    mask,
                    offset: (
                        keep_inside(d.x, bx0, bx1, target.width),
                        keep_inside(d.y, by0, by1, target.height),
                    ),
                });
            }
        }
        Floating { pastes }
    }

    pub fn is_empty(&self) -> bool {
        self.pastes.is_empty()
    }

    /// Fills the floating marks' pixels of `image` (the source) from their surroundings, so
    /// the warp shows the ground under them. `scratch` is a reusable buffer.
    pub fn paint_out(&self, image: &mut Image, scratch: &mut Vec<bool>) {
        let w = image.width() as usize;
        scratch.clear();
        scratch.resize(image.pixels().len(), false);
        let mut todo = Vec::new();
        for p in &self.pastes {
            for (y, x) in p.pixels() {
                let i = y * w + x;
                if !scratch[i] {
                    scratch[i] = true;
                    todo.push(i as u32);
                }
            }
        }
        fill_from_surroundings(image, scratch, todo);
    }

    /// Copies the floating marks' pixels of `src` into `out`, each shifted by its offset
    /// (clipped to `out`).
    pub fn paste(&self, src: &Image, out: &mut Image) {
        let (sw, ow, oh) = (
            src.width() as usize,
            out.width() as i64,
            out.height() as i64,
        );
        let (sp, op) = (src.pixels(), out.pixels_mut());
        for p in &self.pastes {
            for (y, x) in p.pixels() {
                let (tx, ty) = (x as i64 + p.offset.0, y as i64 + p.offset.1);
                if (0..ow).contains(&tx) && (0..oh).contains(&ty) {
                    op[ty as usize * ow as usize + tx as usize] = sp[y * sw + x];
                }
            }
        }
    }

    /// The source rectangles `[x0, y0, x1, y1]` the floating marks read.
    pub fn source_rects(&self) -> impl Iterator<Item = [f64; 4]> + '_ {
        self.pastes.iter().map(|p| p.rect.map(|v| v as f64))
    }

    /// The output rectangles `[x0, y0, x1, y1]` the floating marks are copied to.
    pub fn output_rects(&self) -> impl Iterator<Item = [f64; 4]> + '_ {
        self.pastes.iter().map(|p| {
            let [x0, y0, x1, y1] = p.rect.map(|v| v as i64);
            let (dx, dy) = p.offset;
            [x0 + dx, y0 + dy, x1 + dx, y1 + dy].map(|v| v as f64)
        })
    }
}

impl Paste {
    /// The source pixels `(y, x)` of the mark.
    fn pixels(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let rw = (self.rect[2] - self.rect[0]) as usize;
        self.mask
            .iter()
            .enumerate()
            .filter(|(_, &b)| b)
            .map(move |(i, _)| {
                (
                    self.rect[1] as usize + i / rw,
                    self.rect[0] as usize + i % rw,
                )
            })
    }
}
