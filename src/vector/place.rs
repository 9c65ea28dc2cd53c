//! Carrying marks through the deformed mesh (§5.3): barycentric coordinates in the source
//! triangle, applied to the same triangle's deformed vertices.

use super::{MarkSize, PointMark, Polyline, VectorLayer};
use crate::mesh::Mesh;
use crate::raster::snap;
use crate::solve::Warp;
use glam::DVec2;

/// Side of the buckets that index triangles for point location, px.
const CELL_PX: f64 = 32.0;
/// Points on a mark's rim used to measure the local scale.
const RIM_SAMPLES: usize = 8;
/// The local scale a mark's radius may take.
const SCALE_RANGE: (f64, f64) = (0.1, 10.0);

/// Maps source points to the output through a mesh and its warp.
pub struct MeshMap<'a> {
    mesh: &'a Mesh,
    warp: &'a Warp,
    cols: usize,
    rows: usize,
    buckets: Vec<Vec<u32>>,
    /// Vertex index by exact position, for points that are vertices.
    vertex_at: std::collections::HashMap<(u64, u64), u32>,
}

impl<'a> MeshMap<'a> {
    /// Indexes `mesh`'s triangles (a bucket grid); `warp` must be a warp of `mesh`.
    pub fn new(mesh: &'a Mesh, warp: &'a Warp) -> MeshMap<'a> {
        let size = mesh.size();
        let cols = (size.width as f64 / CELL_PX).ceil().max(1.0) as usize;
        let rows = (size.height as f64 / CELL_PX).ceil().max(1.0) as usize;
        let mut buckets = vec![Vec::new(); cols * rows];
        let ok = warp.positions().len() == mesh.vertices().len();
        for t in 0..if ok { mesh.triangles().len() } else { 0 } {
            let p = mesh.triangle_points(t);
            let lo = p[0].min(p[1]).min(p[2]);
            let hi = p[0].max(p[1]).max(p[2]);
            let c0 = ((lo.x / CELL_PX).max(0.0) as usize).min(cols - 1);
            let r0 = ((lo.y / CELL_PX).max(0.0) as usize).min(rows - 1);
            let c1 = ((hi.x / CELL_PX).max(0.0) as usize).min(cols - 1);
            let r1 = ((hi.y / CELL_PX).max(0.0) as usize).min(rows - 1);
            for r in r0..=r1 {
                for c in c0..=c1 {
                    buckets[r * cols + c].push(t as u32);
                }
            }
        }
        let vertex_at = mesh
            .vertices()
            .iter()
            .enumerate()
            .map(|(i, p)| ((p.x.to_bits(), p.y.to_bits()), i as u32))
            .collect();
        MeshMap {
            mesh,
            warp,
            cols,
            rows,
            buckets,
            vertex_at,
        }
    }

    /// Where the warp takes source point `p`. A vertex goes exactly where the warp puts it; a
    /// point inside a triangle by its barycentric coordinates there; a point outside the
    /// canvas by the affine map of the triangle nearest to it (it may land outside the
    /// output). `None` only for a non-finite point or an empty mesh.
    pub fn map(&self, p: DVec2) -> Option<DVec2> {
        if !p.is_finite() {
            return None;
        }
        // A point that snaps onto a vertex (mark centres are vertices, on the renderer's
        // fixed-point grid) goes where the vertex goes.
        let s = DVec2::new(snap(p.x), snap(p.y));
        if let Some(&v) = self.vertex_at.get(&(s.x.to_bits(), s.y.to_bits())) {
            return self.warp.positions().get(v as usize).copied();
        }
        let (t, b) = self.locate(p)?;
        let tri = self.mesh.triangles()[t];
        let q = tri.map(|v| self.warp.positions()[v as usize]);
        Some(q[0] * b[0] + q[1] * b[1] + q[2] * b[2])
    }

    /// The triangle holding `p` (or, outside the mesh, the one whose barycentric coordinates
    /// for `p` are least negative among those near it) and `p`'s barycentric coordinates.
    fn locate(&self, p: DVec2) -> Option<(usize, [f64; 3])> {
        let size = self.mesh.size();
        let q = DVec2::new(
            p.x.clamp(0.0, size.width as f64),
            p.y.clamp(0.0, size.height as f64),
        );
        let c = ((q.x / CELL_PX) as usize).min(self.cols - 1);
        let r = ((q.y / CELL_PX) as usize).min(self.rows - 1);
        let mut best: Option<(usize, [f64; 3], f64)> = None;
        for &t in &self.buckets[r * self.cols + c] {
            let b = barycentric(self.mesh.triangle_points(t as usize), p);
            let worst = b[0].min(b[1]).min(b[2]);
            if worst >= -1e-12 {
                return Some((t as usize, b));
            }
            if best.as_ref().is_none_or(|x| worst > x.2) {
                best = Some((t as usize, b, worst));
            }
        }
        best.map(|(t, b, _)| (t, b))
    }

    /// The local scale of the warp over a disc of radius `radius` around `centre`:
    /// `√|det A|` of the least-squares affine fit to where `RIM_SAMPLES` points of its rim
    /// go, clamped to [0.1, 10] (1 if it cannot be measured).
    pub fn local_scale(&self, centre: DVec2, radius: f64) -> f64 {
        let rho = radius.max(1.0);
        // Rim points symmetric about the centre: the fit's linear part is
        // Σ (q_i − q̄) d_iᵀ / Σ d_i d_iᵀ, and Σ d_i d_iᵀ = n ρ² / 2 · I.
        let mut a = [[0.0f64; 2]; 2];
        let mut mapped = [DVec2::ZERO; RIM_SAMPLES];
        for (i, m) in mapped.iter_mut().enumerate() {
            let ang = std::f64::consts::TAU * i as f64 / RIM_SAMPLES as f64;
            let d = DVec2::new(ang.cos(), ang.sin()) * rho;
            match self.map(centre + d) {
                Some(q) => *m = q,
                None => return 1.0,
            }
        }
        let mean = mapped.iter().copied().sum::<DVec2>() / RIM_SAMPLES as f64;
        for (i, q) in mapped.iter().enumerate() {
            let ang = std::f64::consts::TAU * i as f64 / RIM_SAMPLES as f64;
            let d = DVec2::new(ang.cos(), ang.sin()) * rho;
            let e = *q - mean;
            a[0][0] += e.x * d.x;
            a[0][1] += e.x * d.y;
            a[1][0] += e.y * d.x;
            a[1][1] += e.y * d.y;
        }
        let norm = RIM_SAMPLES as f64 * rho * rho / 2.0;
        let det = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / (norm * norm);
        let s = det.abs().sqrt();
        if s.is_finite() {
            s.clamp(SCALE_RANGE.0, SCALE_RANGE.1)
        } else {
            1.0
        }
    }
}

fn barycentric(t: [DVec2; 3], p: DVec2) -> [f64; 3] {
    let d = (t[1] - t[0]).perp_dot(t[2] - t[0]);
    if d == 0.0 {
        return [f64::NEG_INFINITY; 3];
    }
    let b1 = (p - t[0]).perp_dot(t[2] - t[0]) / d;
    let b2 = (t[1] - t[0]).perp_dot(p - t[0]) / d;
    [1.0 - b1 - b2, b1, b2]
}

/// `layer` carried through `mesh` deformed by `warp`, in output coordinates: every point's
/// centre and every polyline point mapped (§5.3), radii scaled by `size`'s rule, widths and
/// edges kept. Marks that cannot be mapped (an empty mesh) keep their coordinates.
pub fn place(layer: &VectorLayer, mesh: &Mesh, warp: &Warp, size: MarkSize) -> VectorLayer {
    let map = MeshMap::new(mesh, warp);
    let points = layer
        .points
        .iter()
        .map(|p| {
            let c = DVec2::new(p.x, p.y);
            let q = map.map(c).unwrap_or(c);
            let radius = match size {
                MarkSize::Keep => p.radius,
                MarkSize::Mesh => p.radius * map.local_scale(c, p.radius),
            };
            PointMark {
                x: q.x,
                y: q.y,
                radius,
                ..p.clone()
            }
        })
        .collect();
    let polylines = layer
        .polylines
        .iter()
        .map(|l| Polyline {
            points: l
                .points
                .iter()
                .map(|q| {
                    let s = DVec2::new(q[0], q[1]);
                    let t = map.map(s).unwrap_or(s);
                    [t.x, t.y]
                })
                .collect(),
            ..l.clone()
        })
        .collect();
    VectorLayer {
        points,
        polylines,
        edges: layer.edges.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Size;

    #[test]
    fn linear_warp_maps_affinely_and_scales_by_its_area() {
        let mesh = Mesh::lattice(Size::new(200, 100).unwrap(), 20.0);
        let warp = Warp::linear(&mesh, Size::new(100, 200).unwrap());
        let map = MeshMap::new(&mesh, &warp);
        for p in [
            DVec2::new(33.3, 47.9),
            DVec2::new(0.0, 0.0),
            DVec2::new(200.0, 100.0),
        ] {
            let q = map.map(p).unwrap();
            assert!(
                q.distance(DVec2::new(p.x * 0.5, p.y * 2.0)) < 1e-3,
                "{p} -> {q}"
            );
        }
        // Outside the canvas: the nearest triangle's affine map.
        let q = map.map(DVec2::new(-10.0, 50.0)).unwrap();
        assert!(q.distance(DVec2::new(-5.0, 100.0)) < 1e-3, "{q}");
        assert!((map.local_scale(DVec2::new(90.0, 50.0), 7.0) - 1.0).abs() < 1e-3);
        let warp = Warp::linear(&mesh, Size::new(100, 50).unwrap());
        let map = MeshMap::new(&mesh, &warp);
        assert!((map.local_scale(DVec2::new(90.0, 50.0), 7.0) - 0.5).abs() < 1e-3);
        assert_eq!(map.map(DVec2::new(f64::NAN, 1.0)), None);
    }

    #[test]
    fn placing_keeps_order_and_sizes_by_the_rule() {
        let mesh = Mesh::lattice(Size::new(200, 100).unwrap(), 20.0);
        let warp = Warp::linear(&mesh, Size::new(100, 50).unwrap());
        let layer = VectorLayer {
            points: vec![PointMark {
                id: Some("a".into()),
                x: 100.0,
                y: 40.0,
                radius: 6.0,
                fill: [1, 2, 3, 255],
                stroke: None,
            }],
            polylines: vec![Polyline {
                points: vec![[0.0, 0.0], [200.0, 100.0]],
                width: 3.0,
                color: [0, 0, 0, 255],
            }],
            edges: vec![],
        };
        let placed = place(&layer, &mesh, &warp, MarkSize::Mesh);
        let p = &placed.points[0];
        assert!((p.x - 50.0).abs() < 1e-3 && (p.y - 20.0).abs() < 1e-3);
        assert!((p.radius - 3.0).abs() < 1e-3);
        assert_eq!(p.id.as_deref(), Some("a"));
        assert_eq!(placed.polylines[0].width, 3.0);
        assert!((placed.polylines[0].points[1][0] - 100.0).abs() < 1e-3);
        let kept = place(&layer, &mesh, &warp, MarkSize::Keep);
        assert_eq!(kept.points[0].radius, 6.0);
    }
}
