//! Delaunay triangulation of the key points (by `spade`) and the adjacency the solver needs.

use glam::DVec2;
use spade::{DelaunayTriangulation, Point2, Triangulation};

/// Triangulates `points` (duplicates are merged). Returns the vertices in spade's order and the
/// triangles, each positively oriented (`(p1 − p0) × (p2 − p0) > 0`).
pub(crate) fn delaunay(points: &[DVec2]) -> (Vec<DVec2>, Vec<[u32; 3]>) {
    let input: Vec<Point2<f64>> = points.iter().map(|p| Point2::new(p.x, p.y)).collect();
    // Bulk loading is several times faster than inserting one by one, and deterministic.
    let tri: DelaunayTriangulation<Point2<f64>> =
        DelaunayTriangulation::bulk_load_stable(input).unwrap_or_default();
    let vertices: Vec<DVec2> = tri
        .vertices()
        .map(|v| {
            let p = v.position();
            DVec2::new(p.x, p.y)
        })
        .collect();
    let mut triangles = Vec::with_capacity(tri.num_inner_faces());
    for f in tri.inner_faces() {
        let [a, b, c] = f.vertices().map(|v| v.fix().index() as u32);
        let area = (vertices[b as usize] - vertices[a as usize])
            .perp_dot(vertices[c as usize] - vertices[a as usize]);
        if area > 0.0 {
            triangles.push([a, b, c]);
        } else if area < 0.0 {
            triangles.push([a, c, b]);
        }
        // Zero area cannot come out of a Delaunay triangulation of distinct points; skip it
        // rather than hand the solver a degenerate element.
    }
    (vertices, triangles)
}

/// For each triangle, the triangle across the edge opposite each of its vertices.
pub(crate) fn neighbours(triangles: &[[u32; 3]], _n_vertices: usize) -> Vec<[u32; 3]> {
    let mut edges: Vec<(u64, u32, u8)> = Vec::with_capacity(triangles.len() * 3);
    for (t, tri) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (tri[(i + 1) % 3], tri[(i + 2) % 3]);
            let key = (a.min(b) as u64) << 32 | a.max(b) as u64;
            edges.push((key, t as u32, i as u8));
        }
    }
    edges.sort_unstable();
    let mut out = vec![[super::NONE; 3]; triangles.len()];
    for pair in edges.windows(2) {
        if pair[0].0 == pair[1].0 {
            let (_, t0, i0) = pair[0];
            let (_, t1, i1) = pair[1];
            out[t0 as usize][i0 as usize] = t1;
            out[t1 as usize][i1 as usize] = t0;
        }
    }
    out
}
