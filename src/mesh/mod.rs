//! The adaptive triangle mesh of §5.1: key points sampled by saliency level, Delaunay
//! triangulated.
//!
//! * `marks`: small marks (a dot, a legend symbol, a short label) found as connected blobs;
//!   each gets a ring of key points so it sits in triangles of its own, whatever the lattice;
//! * `sampling`: the per-level lattices under the `α` budget (Eq. 7), corners and sides;
//! * `triangulate`: Delaunay by `spade`, plus the topology the solver needs.

mod incremental;
mod marks;
mod sampling;
mod skeleton;
mod triangulate;

pub use incremental::IncrementalMesh;
pub(crate) use marks::find_marks;
pub use marks::Mark;

use crate::image::Size;
use crate::raster::snap;
use crate::saliency::Vsm;
use crate::structure::Structure;
use glam::DVec2;

/// Which boundary constraint of Eq. 10–11 holds for a vertex.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Boundary {
    /// An interior vertex, free in x and y.
    Interior,
    /// On the left side: `x' = 0`, y free.
    Left,
    /// On the right side: `x' = w'`, y free.
    Right,
    /// On the top side: `y' = 0`, x free.
    Top,
    /// On the bottom side: `y' = h'`, x free.
    Bottom,
    /// A corner: fixed at the matching corner of the target.
    Corner,
}

impl Boundary {
    /// The constraint of a point of a `w × h` canvas.
    pub fn of(p: DVec2, size: Size) -> Boundary {
        let (w, h) = (size.width as f64, size.height as f64);
        let on_x = p.x == 0.0 || p.x == w;
        let on_y = p.y == 0.0 || p.y == h;
        match (on_x, on_y) {
            (true, true) => Boundary::Corner,
            (true, false) if p.x == 0.0 => Boundary::Left,
            (true, false) => Boundary::Right,
            (false, true) if p.y == 0.0 => Boundary::Top,
            (false, true) => Boundary::Bottom,
            (false, false) => Boundary::Interior,
        }
    }

    /// Whether x is fixed by the constraint.
    pub fn fixes_x(self) -> bool {
        matches!(self, Boundary::Left | Boundary::Right | Boundary::Corner)
    }

    /// Whether y is fixed by the constraint.
    pub fn fixes_y(self) -> bool {
        matches!(self, Boundary::Top | Boundary::Bottom | Boundary::Corner)
    }
}

/// Options of mesh construction.
#[derive(Clone, Debug)]
pub struct MeshOptions {
    /// The paper's `α`: the budget is `C_p = w·h/α²` key points.
    pub alpha: f32,
    /// Which regions are data areas (one affine map each).
    pub regions: crate::structure::Regions,
}

/// The `α` of a mesh under one affine map over the whole canvas ([`Regions::Affine`]): the
/// coarsest [`crate::Options`] allows. There the canvas is resampled linearly and the mesh
/// shapes nothing drawn: it only carries the structure and the map's solve, which a finer
/// mesh makes no truer (outputs are pixel-identical from α 20 to 200) but six times slower
/// on a large dashboard.
///
/// [`Regions::Affine`]: crate::structure::Regions::Affine
const AFFINE_ALPHA: f32 = 200.0;

impl MeshOptions {
    /// The `α` the key-point budget is drawn with: [`MeshOptions::alpha`], or
    /// `AFFINE_ALPHA` under one affine map.
    pub fn budget_alpha(&self) -> f32 {
        match self.regions {
            crate::structure::Regions::Affine => self.alpha.max(AFFINE_ALPHA),
            _ => self.alpha,
        }
    }
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            alpha: 20.0,
            regions: crate::structure::Regions::default(),
        }
    }
}

/// A triangle mesh over the source canvas `[0, w] × [0, h]` (pixel corners at integers).
///
/// # Guarantees
/// Every triangle has positive signed area `(p1 − p0) × (p2 − p0) > 0` (counter-clockwise with
/// y pointing down, i.e. clockwise on screen); the triangles tile the canvas; the four corners
/// are vertices; every vertex on the border has the matching [`Boundary`].
#[derive(Clone, Debug)]
pub struct Mesh {
    size: Size,
    vertices: Vec<DVec2>,
    /// A stable identity per vertex: a vertex kept by an incremental update keeps its id, so
    /// the solver can carry its solved position over and the renderer can tell what changed.
    ids: Vec<u64>,
    boundary: Vec<Boundary>,
    triangles: Vec<[u32; 3]>,
    /// `neighbours[t][i]`: the triangle across the edge opposite vertex `i`, or [`NONE`].
    neighbours: Vec<[u32; 3]>,
    marks: Vec<Mark>,
    /// [`Mesh::mark_hubs`] and [`Mesh::fan_triangles`], fixed with the topology.
    hubs: Vec<(u32, f64)>,
    fans: Vec<bool>,
    roles: Vec<Role>,
    structure: Option<std::sync::Arc<Structure>>,
}

/// What structure a vertex belongs to (see [`Structure`](crate::Structure)): the solver keeps a line's
/// vertices on one straight axis-aligned line and a text block's vertices in one similarity.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Role {
    /// Index of the horizontal line it lies on.
    pub hline: Option<u32>,
    /// Index of the vertical line it lies on.
    pub vline: Option<u32>,
    /// Index of the text block it bounds.
    pub block: Option<u32>,
}

/// No neighbour (a border edge).
pub const NONE: u32 = u32::MAX;

impl Mesh {
    /// Samples key points on `vsm`, around the lines and text blocks of `structure`, and
    /// triangulates them with the structure's edges as constraints.
    pub fn build_with(vsm: &Vsm, structure: &Structure, options: &MeshOptions) -> Mesh {
        IncrementalMesh::build_with(vsm, Some(structure), options, 0).1
    }

    /// Samples key points on `vsm` and triangulates them (§5.1).
    pub fn build(vsm: &Vsm, options: &MeshOptions) -> Mesh {
        let marks = marks::find_marks(vsm);
        let points = sampling::sample_key_points(vsm, options.budget_alpha(), &marks);
        Mesh::from_points(vsm.size(), points.iter().map(|k| k.pos), marks)
    }

    /// Triangulates given points; corners are added if missing, points outside the canvas are
    /// clamped to it, and all are snapped to the renderer's fixed-point grid.
    pub fn from_points(
        size: Size,
        points: impl IntoIterator<Item = DVec2>,
        marks: Vec<Mark>,
    ) -> Mesh {
        let (w, h) = (size.width as f64, size.height as f64);
        let mut pts: Vec<DVec2> = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(w, 0.0),
            DVec2::new(0.0, h),
            DVec2::new(w, h),
        ];
        pts.extend(
            points
                .into_iter()
                .filter(|p| p.is_finite())
                .map(|p| DVec2::new(snap(p.x.clamp(0.0, w)), snap(p.y.clamp(0.0, h)))),
        );
        let (vertices, triangles) = triangulate::delaunay(&pts);
        let ids = (0..vertices.len() as u64).collect();
        Mesh::from_parts(size, vertices, ids, triangles, marks)
    }

    /// Assembles a mesh from triangulated parts (triangles positively oriented).
    pub(crate) fn from_parts(
        size: Size,
        vertices: Vec<DVec2>,
        ids: Vec<u64>,
        triangles: Vec<[u32; 3]>,
        marks: Vec<Mark>,
    ) -> Mesh {
        let boundary = vertices.iter().map(|&p| Boundary::of(p, size)).collect();
        let neighbours = triangulate::neighbours(&triangles, vertices.len());
        let hubs = hubs_of(&marks, &vertices);
        let fans = fans_of(&hubs, &vertices, &triangles);
        Mesh {
            size,
            vertices,
            ids,
            boundary,
            triangles,
            neighbours,
            marks,
            hubs,
            fans,
            roles: Vec::new(),
            structure: None,
        }
    }

    /// Attaches the structure the mesh was built around, with each vertex's role in it.
    pub(crate) fn with_structure(
        mut self,
        structure: std::sync::Arc<Structure>,
        roles: Vec<Role>,
    ) -> Mesh {
        self.structure = Some(structure);
        self.roles = roles;
        self
    }

    /// Each vertex's role in the structure (empty when the mesh has none).
    pub fn roles(&self) -> &[Role] {
        &self.roles
    }

    /// The text block triangle `t` lies inside (all three corners bound it), if any.
    pub fn triangle_block(&self, t: usize) -> Option<u32> {
        let tri = self.triangles.get(t)?;
        let b = self.roles.get(tri[0] as usize)?.block?;
        tri.iter()
            .all(|&v| {
                self.roles
                    .get(v as usize)
                    .is_some_and(|r| r.block == Some(b))
            })
            .then_some(b)
    }

    /// The structure the mesh was built around, if any.
    pub fn structure(&self) -> Option<&Structure> {
        self.structure.as_deref()
    }

    /// A regular lattice mesh with cells of about `cell_px` (the grid baseline's topology).
    pub fn lattice(size: Size, cell_px: f64) -> Mesh {
        let (w, h) = (size.width as f64, size.height as f64);
        let nx = (w / cell_px).round().max(1.0) as usize;
        let ny = (h / cell_px).round().max(1.0) as usize;
        let pts = (0..=ny).flat_map(|j| {
            (0..=nx).map(move |i| DVec2::new(w * i as f64 / nx as f64, h * j as f64 / ny as f64))
        });
        Mesh::from_points(size, pts.collect::<Vec<_>>(), Vec::new())
    }

    /// The source canvas size.
    pub fn size(&self) -> Size {
        self.size
    }
    /// Vertex positions on the source canvas.
    pub fn vertices(&self) -> &[DVec2] {
        &self.vertices
    }
    /// Stable vertex ids (kept by a stream's incremental mesh, so later stages can tell a kept vertex from a new one).
    pub fn ids(&self) -> &[u64] {
        &self.ids
    }
    /// Boundary constraint per vertex.
    pub fn boundary(&self) -> &[Boundary] {
        &self.boundary
    }
    /// Triangles as vertex indices, positively oriented.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    /// Adjacent triangle across the edge opposite each vertex (`NONE`, `u32::MAX`, on the border).
    pub fn neighbours(&self) -> &[[u32; 3]] {
        &self.neighbours
    }
    /// The small marks the mesh was refined around.
    pub fn marks(&self) -> &[Mark] {
        &self.marks
    }

    /// The hub of each ringed mark: `(vertex at its centre, ring radius)`. A mark whose centre
    /// is no vertex (it lost its ring to the budget, or text took it) has none.
    pub fn mark_hubs(&self) -> &[(u32, f64)] {
        &self.hubs
    }

    /// Per triangle, whether it belongs to a mark's fan: one corner is a hub of
    /// [`Mesh::mark_hubs`] and the other two lie on (or inside) its ring. Those triangles are
    /// the mark: the solver holds them to a similarity, the renderer may copy them rigidly.
    pub fn fan_triangles(&self) -> &[bool] {
        &self.fans
    }

    /// Number of free vertex coordinates once the boundary constraints hold: the paper's DOF.
    pub fn dof(&self) -> usize {
        self.boundary
            .iter()
            .map(|b| (!b.fixes_x()) as usize + (!b.fixes_y()) as usize)
            .sum()
    }

    /// Source positions of a triangle's corners.
    pub fn triangle_points(&self, t: usize) -> [DVec2; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.vertices[a as usize],
            self.vertices[b as usize],
            self.vertices[c as usize],
        ]
    }
}

/// The vertices at the (snapped) centres of `marks`, with their ring radii.
fn hubs_of(marks: &[Mark], vertices: &[DVec2]) -> Vec<(u32, f64)> {
    if marks.is_empty() {
        return Vec::new();
    }
    let radius: std::collections::HashMap<(u64, u64), f64> = marks
        .iter()
        .map(|m| {
            let key = (snap(m.center.x).to_bits(), snap(m.center.y).to_bits());
            (key, m.ring_radius)
        })
        .collect();
    vertices
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            radius
                .get(&(p.x.to_bits(), p.y.to_bits()))
                .map(|&r| (i as u32, r))
        })
        .collect()
}

/// Per triangle, whether a corner is a hub and the other corners lie within its ring.
fn fans_of(hubs: &[(u32, f64)], vertices: &[DVec2], triangles: &[[u32; 3]]) -> Vec<bool> {
    if hubs.is_empty() {
        return vec![false; triangles.len()];
    }
    let radius: std::collections::HashMap<u32, f64> = hubs.iter().copied().collect();
    triangles
        .iter()
        .map(|tri| {
            tri.iter().any(|h| {
                radius.get(h).is_some_and(|&r| {
                    let c = vertices[*h as usize];
                    tri.iter()
                        .all(|&v| vertices[v as usize].distance(c) <= r * 1.01 + 0.01)
                })
            })
        })
        .collect()
}

/// Twice the signed area of a triangle: positive for the mesh's orientation.
#[inline]
#[cfg(any(test, feature = "eval"))]
pub fn cross2(p: [DVec2; 3]) -> f64 {
    (p[1] - p[0]).perp_dot(p[2] - p[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_tiles_the_canvas() {
        let size = Size::new(100, 60).unwrap();
        let m = Mesh::lattice(size, 20.0);
        let area: f64 = (0..m.triangles().len())
            .map(|t| cross2(m.triangle_points(t)) / 2.0)
            .sum();
        assert!((area - 6000.0).abs() < 1e-6);
        assert!((0..m.triangles().len()).all(|t| cross2(m.triangle_points(t)) > 0.0));
        assert_eq!(
            m.boundary()
                .iter()
                .filter(|&&b| b == Boundary::Corner)
                .count(),
            4
        );
        // 6×4 cells: 7×5 vertices, 2·(5+3) on sides minus... every border vertex is constrained.
        for (p, b) in m.vertices().iter().zip(m.boundary()) {
            let border = p.x == 0.0 || p.y == 0.0 || p.x == 100.0 || p.y == 60.0;
            assert_eq!(border, *b != Boundary::Interior);
        }
    }
}
