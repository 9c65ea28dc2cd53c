//! The reuse policy: compare a frame's VSM with the VSM the current mesh was built for, tile
//! by tile, and decide to reuse the mesh and solution, update them locally, or rebuild.

use crate::mesh::TileMask;
use crate::saliency::Vsm;

/// Thresholds of the reuse policy.
#[derive(Clone, Debug, PartialEq)]
pub struct ReuseOptions {
    /// Off: every frame is built from scratch (for comparison).
    pub enabled: bool,
    /// Side of the tiles changes are tracked in, in pixels.
    pub tile_px: u32,
    /// A tile whose mean absolute VSM change is below this is unchanged (VSM values are in
    /// `[0, 1]`; a 6-px dot moving inside a 32-px tile changes it by about 0.1).
    pub tile_threshold: f32,
    /// Above this share of changed tiles the mesh is rebuilt rather than updated.
    pub rebuild_fraction: f64,
}

impl Default for ReuseOptions {
    fn default() -> Self {
        ReuseOptions {
            enabled: true,
            tile_px: 32,
            tile_threshold: 0.02,
            rebuild_fraction: 0.3,
        }
    }
}

/// Tiles (of `tile_px` image pixels) where `now` differs from `reference` by more than the
/// threshold, not counting map cells within the rectangles `ignore` (`[x0, y0, x1, y1]` in
/// image px: where small marks were and are, which float over the warp instead of re-meshing
/// it). Both maps must have the same size and scale.
pub(crate) fn changed_saliency(
    reference: &Vsm,
    now: &Vsm,
    options: &ReuseOptions,
    ignore: &[[f64; 4]],
    scratch: &mut Vec<bool>,
) -> TileMask {
    let size = now.size();
    let mut mask = TileMask::new(size, options.tile_px);
    let s = now.scale();
    let grid = now.grid_size();
    let (gw, gh) = (grid.width as usize, grid.height as usize);
    let ignored = ignored_cells(ignore, s, gw, gh, scratch);
    let cells = (options.tile_px / s).max(1) as usize;
    let (a, b) = (reference.values(), now.values());
    for row in 0..mask.rows() as usize {
        let y0 = row * cells;
        let y1 = ((row + 1) * cells).min(gh);
        for col in 0..mask.cols() as usize {
            let x0 = col * cells;
            let x1 = ((col + 1) * cells).min(gw);
            if x0 >= x1 || y0 >= y1 {
                continue;
            }
            let mut sum = 0f32;
            for y in y0..y1 {
                let (ra, rb) = (&a[y * gw + x0..y * gw + x1], &b[y * gw + x0..y * gw + x1]);
                if ra == rb {
                    continue;
                }
                match ignored {
                    None => sum += ra.iter().zip(rb).map(|(p, q)| (p - q).abs()).sum::<f32>(),
                    Some(ig) => {
                        let skip = &ig[y * gw + x0..y * gw + x1];
                        sum += ra
                            .iter()
                            .zip(rb)
                            .zip(skip)
                            .filter(|(_, &k)| !k)
                            .map(|((p, q), _)| (p - q).abs())
                            .sum::<f32>();
                    }
                }
            }
            let mean = sum / ((x1 - x0) * (y1 - y0)) as f32;
            if mean > options.tile_threshold {
                mask.set(col as u32, row as u32);
            }
        }
    }
    mask
}

/// One flag per map cell (`gw × gh`, `s` px each) that meets a rectangle of `rects`, written
/// into `out`, or `None` without rectangles.
fn ignored_cells<'a>(
    rects: &[[f64; 4]],
    s: u32,
    gw: usize,
    gh: usize,
    out: &'a mut Vec<bool>,
) -> Option<&'a [bool]> {
    if rects.is_empty() {
        return None;
    }
    let s = s as f64;
    out.clear();
    out.resize(gw * gh, false);
    for &[x0, y0, x1, y1] in rects {
        let cx0 = (x0 / s).floor().max(0.0) as usize;
        let cy0 = (y0 / s).floor().max(0.0) as usize;
        let cx1 = ((x1 / s).ceil().max(0.0) as usize).min(gw);
        let cy1 = ((y1 / s).ceil().max(0.0) as usize).min(gh);
        for y in cy0..cy1 {
            out[y * gw + cx0..y * gw + cx1.max(cx0)].fill(true);
        }
    }
    Some(out)
}
