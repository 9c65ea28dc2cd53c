//! Carrying marks through the deformed mesh (§5.3): barycentric coordinates in the source
//! triangle, applied to the same triangle's deformed vertices.

use super::{MarkSize, PointMark, Polyline, VectorLayer};
use crate::mesh::Mesh;
use crate::raster::snap;
use crate::solve::{Locator, Warp};
use glam::DVec2;

/// How far outside a triangle (in barycentric units) a point may lie and still be placed by
/// it rather than by the nearest triangle: only rounding.
const ON_TRIANGLE: f64 = 1e-12;
/// Points on a mark's rim used to measure the local scale.
const RIM_SAMPLES: usize = 8;
/// The local scale a mark's radius may take.
const SCALE_RANGE: (f64, f64) = (0.1, 10.0);

/// Maps source points to the output through a mesh and its warp: a vertex exactly where the
/// warp puts it, any other point through the [`Locator`].
pub struct MeshMap<'a> {
    locator: Locator<'a>,
    /// Vertex index by exact position, for points that are vertices.
    vertex_at: std::collections::HashMap<(u64, u64), u32>,
}

impl<'a> MeshMap<'a> {
    /// Indexes `mesh`'s triangles and vertices; `warp` must be a warp of `mesh`.
    pub fn new(mesh: &'a Mesh, warp: &'a Warp) -> MeshMap<'a> {
        let vertex_at = mesh
            .vertices()
            .iter()
            .enumerate()
            .map(|(i, p)| ((p.x.to_bits(), p.y.to_bits()), i as u32))
            .collect();
        MeshMap {
            locator: warp.locator(mesh),
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
            return self.locator.warp().positions().get(v as usize).copied();
        }
        self.locator.map_nearest(p, ON_TRIANGLE)
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
