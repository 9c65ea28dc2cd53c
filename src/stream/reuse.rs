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
/// threshold. Both maps must have the same size and scale.
pub(crate) fn changed_saliency(reference: &Vsm, now: &Vsm, options: &ReuseOptions) -> TileMask {
    let size = now.size();
    let mut mask = TileMask::new(size, options.tile_px);
    let s = now.scale();
    let grid = now.grid_size();
    let (gw, gh) = (grid.width as usize, grid.height as usize);
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
                sum += ra.iter().zip(rb).map(|(p, q)| (p - q).abs()).sum::<f32>();
            }
            let mean = sum / ((x1 - x0) * (y1 - y0)) as f32;
            if mean > options.tile_threshold {
                mask.set(col as u32, row as u32);
            }
        }
    }
    mask
}
