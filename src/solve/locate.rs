//! Where a warp takes a source point: point location in the mesh by a bucket grid of
//! triangles, then the point's barycentric coordinates applied to the triangle's deformed
//! vertices (§5.3). One index for every user: a stream's warm start (new vertices pulled to
//! where the previous warp takes them), marks floating over a kept warp, and vector marks.

use super::Warp;
use crate::mesh::Mesh;
use glam::DVec2;

/// Side of the buckets that index triangles, px: a few triangles of a typical mesh each.
const CELL_PX: f64 = 32.0;

/// Tolerance of [`Locator::map_inside`]: a point this far (in barycentric units) outside a
/// triangle, as on a shared edge after rounding, still counts as inside it.
const INSIDE: f64 = 1e-9;

/// A mesh's triangles indexed for point location, with the warp that deforms them.
pub struct Locator<'a> {
    mesh: &'a Mesh,
    warp: &'a Warp,
    cols: usize,
    rows: usize,
    buckets: Vec<Vec<u32>>,
}

impl<'a> Locator<'a> {
    /// Indexes `mesh`'s triangles; `warp` must be a warp of `mesh` (a warp with another
    /// number of vertices indexes nothing, and no point is found).
    pub fn new(mesh: &'a Mesh, warp: &'a Warp) -> Locator<'a> {
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
        Locator {
            mesh,
            warp,
            cols,
            rows,
            buckets,
        }
    }

    /// The mesh indexed.
    pub fn mesh(&self) -> &'a Mesh {
        self.mesh
    }

    /// The warp applied.
    pub fn warp(&self) -> &'a Warp {
        self.warp
    }

    /// Where the warp takes source point `p`, if `p` lies in the mesh.
    pub fn map_inside(&self, p: DVec2) -> Option<DVec2> {
        self.locate(p, INSIDE, false).map(|(t, b)| self.apply(t, b))
    }

    /// Where the warp takes `p` by the triangle holding it (barycentric coordinates all at
    /// least `-tolerance`), or, when none of the triangles near `p` does (`p` outside the
    /// mesh), by the one whose least coordinate is largest: its affine map extended.
    pub fn map_nearest(&self, p: DVec2, tolerance: f64) -> Option<DVec2> {
        self.locate(p, tolerance, true)
            .map(|(t, b)| self.apply(t, b))
    }

    /// Triangle `t`'s deformed vertices weighted by `b`.
    fn apply(&self, t: usize, b: [f64; 3]) -> DVec2 {
        let tri = self.mesh.triangles()[t];
        let q = tri.map(|v| self.warp.positions()[v as usize]);
        q[0] * b[0] + q[1] * b[1] + q[2] * b[2]
    }

    /// The first triangle of `p`'s bucket that holds it within `tolerance`, with `p`'s
    /// barycentric coordinates there; failing that, if `nearest`, the bucket's triangle whose
    /// least coordinate is largest.
    fn locate(&self, p: DVec2, tolerance: f64, nearest: bool) -> Option<(usize, [f64; 3])> {
        if !p.is_finite() {
            return None;
        }
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
            if worst >= -tolerance {
                return Some((t as usize, b));
            }
            if nearest && best.as_ref().is_none_or(|x| worst > x.2) {
                best = Some((t as usize, b, worst));
            }
        }
        best.map(|(t, b, _)| (t, b))
    }
}

/// `p`'s barycentric coordinates in triangle `t` (all −∞ for a degenerate triangle).
fn barycentric(t: [DVec2; 3], p: DVec2) -> [f64; 3] {
    let d = (t[1] - t[0]).perp_dot(t[2] - t[0]);
    if d == 0.0 {
        return [f64::NEG_INFINITY; 3];
    }
    let b1 = (p - t[0]).perp_dot(t[2] - t[0]) / d;
    let b2 = (t[1] - t[0]).perp_dot(p - t[0]) / d;
    [1.0 - b1 - b2, b1, b2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Size;

    #[test]
    fn a_linear_warp_maps_inside_points_and_extends_outside() {
        // Three times narrower, half as tall: every point inside goes to (x/3, y/2).
        let mesh = Mesh::lattice(Size::new(300, 120).unwrap(), 25.0);
        let warp = Warp::linear(&mesh, Size::new(100, 60).unwrap());
        let loc = warp.locator(&mesh);
        let grid = (0..=12).flat_map(|i| (0..=6).map(move |j| (i as f64 * 25.0, j as f64 * 20.0)));
        for (x, y) in grid {
            let got = loc.map_inside(DVec2::new(x, y));
            let want = DVec2::new(x / 3.0, y / 2.0);
            assert!(
                got.is_some_and(|q| q.distance(want) < 1e-3),
                "({x}, {y}) -> {got:?}"
            );
        }
        // Left of the canvas: not inside, and the nearest triangle's map extended.
        let outside = DVec2::new(-30.0, 60.0);
        assert_eq!(loc.map_inside(outside), None);
        let q = loc.map_nearest(outside, 0.0).unwrap();
        assert!(q.distance(DVec2::new(-10.0, 30.0)) < 1e-3, "{q}");
    }

    #[test]
    fn a_warp_of_another_mesh_locates_nothing() {
        let mesh = Mesh::lattice(Size::new(200, 100).unwrap(), 20.0);
        let other = Mesh::lattice(Size::new(200, 100).unwrap(), 50.0);
        let warp = Warp::linear(&other, Size::new(100, 100).unwrap());
        let loc = Locator::new(&mesh, &warp);
        assert_eq!(loc.map_nearest(DVec2::new(50.0, 50.0), 0.0), None);
    }
}
