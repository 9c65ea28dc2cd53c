//! Triangle saliency `λ_t` (Eq. 9): the mean VSM over the pixels of each source triangle, by the
//! same exact scan conversion the renderer uses (every pixel counted once).

use crate::mesh::Mesh;
use crate::raster::{rasterize, FixedPoint};
use crate::saliency::Vsm;

/// Normalized Sobel magnitude below which a triangle's pixels count as one flat colour.
const FLAT_EDGE: f32 = 0.02;

/// `λ_t` for every triangle of `mesh`, into `out`. A triangle too small to hold a pixel centre
/// takes the value at its centroid; with `hold_fans`, a mark's fan triangle is fully salient.
pub(crate) fn triangle_saliency(mesh: &Mesh, vsm: &Vsm, hold_fans: bool, out: &mut Vec<f64>) {
    let grid = vsm.grid_size();
    let (w, h) = (grid.width, grid.height);
    let inv = 1.0 / vsm.scale() as f64;
    let values = vsm.values();
    let edges = vsm.edges();
    out.clear();
    out.reserve(mesh.triangles().len());
    for t in 0..mesh.triangles().len() {
        // In map cells.
        let p = mesh.triangle_points(t).map(|q| q * inv);
        let fp = p.map(|q| FixedPoint::from_f64(q.x, q.y));
        let mut sum = 0.0f64;
        let mut n = 0u32;
        let mut edge = 0f32;
        rasterize(fp, w, h, |y, x0, x1| {
            let i = y as usize * w as usize;
            let row = &values[i..][x0 as usize..x1 as usize];
            sum += sum_f32(row);
            n += x1 - x0;
            edge = edges[i..][x0 as usize..x1 as usize]
                .iter()
                .fold(edge, |a, &e| a.max(e));
        });
        // A triangle of one flat colour looks the same however it is deformed: salient or not,
        // it gives way like empty ground (a header bar around its labels, the inside of a
        // panel), and the edges that bound it, in triangles of their own, keep their shape.
        // A mark's fan is the mark, flat or not.
        let fan = mesh.fan_triangles().get(t).copied().unwrap_or(false);
        if n > 0 && edge < FLAT_EDGE && !fan {
            out.push(0.0);
            continue;
        }
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
    // Inside a data area the map is one affine map whatever the weights: its triangles only
    // decide how much of the squeeze the area takes. A responsive layout gives it all that
    // the text around it does not need, so they weigh like empty ground (and text, held at
    // its size, does not lose to a large salient plot).
    if let Some(areas) = mesh
        .structure()
        .map(|s| &s.areas[..])
        .filter(|a| !a.is_empty())
    {
        for (t, l) in out.iter_mut().enumerate() {
            let p = mesh.triangle_points(t);
            let c = (p[0] + p[1] + p[2]) / 3.0;
            if areas.iter().any(|a| a.contains(c.x, c.y, 0.0)) {
                *l = 0.0;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::saliency::VsmBuilder;
    use crate::{Image, Size};
    use glam::DVec2;

    /// A red square on white is salient inside and out to its rim; a triangle inside it
    /// (no edge) gives way, one across its rim keeps the VSM's mean.
    #[test]
    fn flat_triangles_give_way_edged_ones_do_not() {
        let size = Size::new(200, 200).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        for y in 40..160 {
            for x in 40..160 {
                img.set(x, y, [220, 30, 30, 255]);
            }
        }
        let vsm = VsmBuilder::full_resolution().build(img.as_ref());
        assert!(vsm.get(100, 100) > 0.2, "the square is salient");
        let pts = [(70.0, 70.0), (130.0, 70.0), (100.0, 120.0), (20.0, 100.0)];
        let mesh = Mesh::from_points(size, pts.map(|(x, y)| DVec2::new(x, y)), Vec::new());
        let mut lambda = Vec::new();
        triangle_saliency(&mesh, &vsm, false, &mut lambda);
        let find = |c: DVec2| {
            (0..mesh.triangles().len())
                .find(|&t| {
                    let [a, b, d] = mesh.triangle_points(t);
                    let s = |p: DVec2, q: DVec2| (q - p).perp_dot(c - p) >= 0.0;
                    s(a, b) && s(b, d) && s(d, a)
                })
                .unwrap()
        };
        let inside = find(DVec2::new(100.0, 85.0));
        let across = find(DVec2::new(50.0, 95.0));
        assert_eq!(lambda[inside], 0.0);
        assert!(lambda[across] > 0.05, "rim triangle λ {}", lambda[across]);
    }

    /// Content raised in the VSM (a vector layer's marks, held regions) raises its edges too,
    /// so it is never taken for flat ground, even over a flat raster.
    #[test]
    fn raised_content_is_not_flat() {
        let size = Size::new(200, 200).unwrap();
        let img = Image::filled(size, [255; 4]);
        let mut vsm = VsmBuilder::full_resolution().build(img.as_ref());
        let (values, _, edges) = vsm.planes_mut();
        for y in 40..160 {
            for x in 40..160 {
                values[y * 200 + x] = 1.0;
                edges[y * 200 + x] = 1.0;
            }
        }
        let pts = [(70.0, 70.0), (130.0, 70.0), (100.0, 120.0)];
        let mesh = Mesh::from_points(size, pts.map(|(x, y)| DVec2::new(x, y)), Vec::new());
        let mut lambda = Vec::new();
        triangle_saliency(&mesh, &vsm, false, &mut lambda);
        let inside = (0..mesh.triangles().len())
            .find(|&t| {
                let c = mesh.triangle_points(t).iter().sum::<DVec2>() / 3.0;
                (c - DVec2::new(100.0, 87.0)).length() < 1.0
            })
            .expect("the inner triangle");
        assert!(lambda[inside] > 0.9, "λ {}", lambda[inside]);
    }
}
