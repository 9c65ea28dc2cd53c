//! Triangle saliency `λ_t` (Eq. 9): the mean VSM over the pixels of each source triangle, by the
//! same exact scan conversion the renderer uses (every pixel counted once).

use crate::mesh::Mesh;
use crate::raster::{rasterize, FixedPoint};
use crate::saliency::Vsm;

/// `λ_t` for every triangle of `mesh`, into `out`. A triangle too small to hold a pixel centre
/// takes the value at its centroid; with `hold_fans`, a mark's fan triangle is fully salient.
pub(crate) fn triangle_saliency(mesh: &Mesh, vsm: &Vsm, hold_fans: bool, out: &mut Vec<f64>) {
    let grid = vsm.grid_size();
    let (w, h) = (grid.width, grid.height);
    let inv = 1.0 / vsm.scale() as f64;
    let values = vsm.values();
    out.clear();
    out.reserve(mesh.triangles().len());
    for t in 0..mesh.triangles().len() {
        // In map cells.
        let p = mesh.triangle_points(t).map(|q| q * inv);
        let fp = p.map(|q| FixedPoint::from_f64(q.x, q.y));
        let mut sum = 0.0f64;
        let mut n = 0u32;
        rasterize(fp, w, h, |y, x0, x1| {
            let row = &values[y as usize * w as usize..][x0 as usize..x1 as usize];
            sum += sum_f32(row);
            n += x1 - x0;
        });
        if n == 0 {
            let c = (p[0] + p[1] + p[2]) / 3.0;
            let x = (c.x as usize).min(w as usize - 1);
            let y = (c.y as usize).min(h as usize - 1);
            out.push(values[y * w as usize + x] as f64);
        } else {
            out.push(sum / n as f64);
        }
    }
    // A mark's fan is the mark (§5.3: its footprint counts as salient): the ground between
    // the mark and its ring would otherwise dilute the fan's weight, and a lightly held fan
    // is squeezed with the ground around it.
    if hold_fans {
        for (l, &fan) in out.iter_mut().zip(mesh.fan_triangles()) {
            if fan {
                *l = l.max(1.0);
            }
        }
    }
}

/// Sum of a short row, in eight f32 lanes (vectorizes; a span is at most a few hundred pixels
/// of values in [0, 1], far from f32's precision limits), returned as f64.
#[inline]
fn sum_f32(row: &[f32]) -> f64 {
    let mut lanes = [0f32; 8];
    let chunks = row.chunks_exact(8);
    let rest = chunks.remainder();
    for c in chunks {
        for k in 0..8 {
            lanes[k] += c[k];
        }
    }
    let tail: f32 = rest.iter().sum();
    lanes.iter().map(|&v| v as f64).sum::<f64>() + tail as f64
}
