//! No fold-overs (§5.2.2): a deformed triangle with non-positive signed area never reaches the
//! renderer.
//!
//! The repair is kept local, in three steps, each only if the previous one left folds:
//! 1. re-solve with the weights of the folded triangles tripled, up to eight rounds (same
//!    pattern; the factor is updated by rank-one updates where few unknowns changed, else
//!    factorized numerically again; done by the caller, [`super::Solver`]). A round costs a
//!    few rank-one updates, a global blend the whole picture's quality, so there are enough
//!    rounds (eight) that crowded stills rarely leave the later steps anything to do;
//! 2. untangle: move the free vertices of folded triangles, least salient first, towards the
//!    centroid of their neighbours while that raises the smallest incident area;
//! 3. blend towards linear scaling (always fold-free) only around what is still folded, with a
//!    weight that fades over a few rings of triangles; the global blend is the last guarantee.
//!
//! A global blend from the start is valid but costs quality everywhere (marks lose much of
//! their roundness; DESIGN.md has the measurement), which is why it comes last.

use super::boundary::Layout;
use crate::mesh::Mesh;
use crate::raster::{cross, snap, FixedPoint};
use glam::DVec2;

/// Twice the deformed signed area of triangle `t`, exactly, on the fixed-point grid.
#[inline]
pub(crate) fn deformed_cross(mesh: &Mesh, pos: &[DVec2], t: usize) -> i64 {
    let tri = mesh.triangles()[t];
    cross(tri.map(|v| {
        let p = pos[v as usize];
        FixedPoint::from_f64(p.x, p.y)
    }))
}

/// Indices of folded (non-positive area) triangles.
pub(crate) fn folded(mesh: &Mesh, pos: &[DVec2]) -> Vec<usize> {
    (0..mesh.triangles().len())
        .filter(|&t| deformed_cross(mesh, pos, t) <= 0)
        .collect()
}

/// Incident triangles of each vertex, as a CSR list.
pub(crate) struct VertexTriangles {
    start: Vec<u32>,
    tris: Vec<u32>,
}

impl VertexTriangles {
    pub fn new(mesh: &Mesh) -> VertexTriangles {
        let nv = mesh.vertices().len();
        let mut start = vec![0u32; nv + 1];
        for tri in mesh.triangles() {
            for &v in tri {
                start[v as usize + 1] += 1;
            }
        }
        for i in 0..nv {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut tris = vec![0u32; start[nv] as usize];
        for (t, tri) in mesh.triangles().iter().enumerate() {
            for &v in tri {
                tris[fill[v as usize] as usize] = t as u32;
                fill[v as usize] += 1;
            }
        }
        VertexTriangles { start, tris }
    }

    pub fn of(&self, v: usize) -> &[u32] {
        &self.tris[self.start[v] as usize..self.start[v + 1] as usize]
    }
}

/// Step 2: local untangling. Returns how many vertices moved.
pub(crate) fn untangle(
    mesh: &Mesh,
    layout: &Layout,
    lambda: &[f64],
    vt: &VertexTriangles,
    pos: &mut [DVec2],
) -> usize {
    let mut moved = 0;
    for _sweep in 0..30 {
        let bad = folded(mesh, pos);
        if bad.is_empty() {
            break;
        }
        // Free vertices of folded triangles, least salient first.
        let mut verts: Vec<usize> = bad
            .iter()
            .flat_map(|&t| mesh.triangles()[t])
            .map(|v| v as usize)
            .filter(|&v| layout.is_private(&layout.x[v]) || layout.is_private(&layout.y[v]))
            .collect();
        verts.sort_unstable();
        verts.dedup();
        let salience = |v: usize| -> f64 {
            vt.of(v)
                .iter()
                .map(|&t| lambda[t as usize])
                .fold(0.0, f64::max)
        };
        verts.sort_by(|&a, &b| salience(a).total_cmp(&salience(b)));
        let mut progress = false;
        for v in verts {
            let min_area = |pos: &[DVec2]| -> i64 {
                vt.of(v)
                    .iter()
                    .map(|&t| deformed_cross(mesh, pos, t as usize))
                    .min()
                    .unwrap_or(i64::MAX)
            };
            let before = min_area(pos);
            if before > 0 {
                continue;
            }
            // Centroid of the 1-ring.
            let mut c = DVec2::ZERO;
            let mut n = 0.0;
            for &t in vt.of(v) {
                for &u in &mesh.triangles()[t as usize] {
                    if u as usize != v {
                        c += pos[u as usize];
                        n += 1.0;
                    }
                }
            }
            if n == 0.0 {
                continue;
            }
            c /= n;
            let old = pos[v];
            let mut best = (before, old);
            for f in [1.0, 0.75, 0.5, 0.25] {
                let mut p = old + (c - old) * f;
                // Only coordinates of their own: a boundary, line or block coordinate stays.
                if !layout.is_private(&layout.x[v]) {
                    p.x = old.x;
                }
                if !layout.is_private(&layout.y[v]) {
                    p.y = old.y;
                }
                pos[v] = DVec2::new(snap(p.x), snap(p.y));
                let a = min_area(pos);
                if a > best.0 {
                    best = (a, pos[v]);
                }
            }
            pos[v] = best.1;
            if best.1 != old {
                moved += 1;
                progress = true;
            }
        }
        if !progress {
            break;
        }
    }
    moved
}

/// Step 3: blends towards `linear` around the folds, fading over `rings` rings of triangles,
/// with the smallest blend factor that removes every fold; falls back to a global blend.
/// Returns the blend factor used (0 if nothing was needed) and whether it was global.
pub(crate) fn blend_towards_linear(
    mesh: &Mesh,
    vt: &VertexTriangles,
    linear: &[DVec2],
    pos: &mut [DVec2],
) -> (f64, bool) {
    let bad = folded(mesh, pos);
    if bad.is_empty() {
        return (0.0, false);
    }
    const RINGS: usize = 4;
    // Ring distance of each vertex from the folded triangles.
    let nv = mesh.vertices().len();
    let mut dist = vec![usize::MAX; nv];
    let mut frontier: Vec<usize> = bad
        .iter()
        .flat_map(|&t| mesh.triangles()[t])
        .map(|v| v as usize)
        .collect();
    for &v in &frontier {
        dist[v] = 0;
    }
    for d in 1..=RINGS {
        let mut next = Vec::new();
        for &v in &frontier {
            for &t in vt.of(v) {
                for &u in &mesh.triangles()[t as usize] {
                    if dist[u as usize] == usize::MAX {
                        dist[u as usize] = d;
                        next.push(u as usize);
                    }
                }
            }
        }
        frontier = next;
    }
    let local_weight: Vec<f64> = dist
        .iter()
        .map(|&d| {
            if d == usize::MAX {
                0.0
            } else {
                1.0 - d as f64 / (RINGS + 1) as f64
            }
        })
        .collect();
    let global = vec![1.0; nv];
    let orig = pos.to_vec();
    for (weights, is_global) in [(&local_weight, false), (&global, true)] {
        let apply = |t: f64, pos: &mut [DVec2]| {
            for v in 0..nv {
                let k = t * weights[v];
                let p = orig[v] * (1.0 - k) + linear[v] * k;
                pos[v] = DVec2::new(snap(p.x), snap(p.y));
            }
        };
        apply(1.0, pos);
        if !folded(mesh, pos).is_empty() {
            continue;
        }
        // Bisection for the smallest factor that leaves no fold.
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for _ in 0..20 {
            let mid = 0.5 * (lo + hi);
            apply(mid, pos);
            if folded(mesh, pos).is_empty() {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        apply(hi, pos);
        return (hi, is_global);
    }
    // Linear scaling of a valid mesh is valid; only grid snapping of a degenerate sliver could
    // get here. Keep linear positions (the caller checks and reports).
    pos.copy_from_slice(linear);
    (1.0, true)
}
