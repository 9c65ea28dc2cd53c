//! Incremental triangulation for streams: when the saliency of a few tiles changes, only the
//! key points of those tiles are re-sampled, with `spade`'s `remove` and `insert`; every other
//! vertex keeps its position and its id, so its solved position can be carried over.

use super::marks::{find_marks, Mark};
use super::sampling::{sample_key_points, KeyPointKind, RING_EXCLUSION, RING_POINTS};
use super::skeleton::{as_used, crowds, skeleton};
use super::Role;
use super::{Mesh, MeshOptions};
use crate::image::Size;
use crate::raster::snap;
use crate::saliency::Vsm;
use crate::structure::Structure;
use crate::tiles::TileMask;
use glam::DVec2;
use spade::{ConstrainedDelaunayTriangulation, HasPosition, Point2, Triangulation};
use std::collections::HashMap;
use std::sync::Arc;

#[derive(Copy, Clone, Debug)]
struct KeyVertex {
    pos: Point2<f64>,
    id: u64,
}

impl HasPosition for KeyVertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.pos
    }
}

/// A (constrained) Delaunay triangulation of key points that can be updated tile by tile.
pub struct IncrementalMesh {
    tri: ConstrainedDelaunayTriangulation<KeyVertex>,
    size: Size,
    marks: Vec<Mark>,
    next_id: u64,
    /// The structure the skeleton came from, and each skeleton point's role by position.
    structure: Option<Arc<Structure>>,
    roles: HashMap<(u64, u64), Role>,
}

impl IncrementalMesh {
    /// Samples key points on `vsm` and triangulates them, numbering vertices from `first_id`
    /// (ids are never reused within a stream, so a rebuilt mesh shares none with the last).
    #[cfg(test)]
    pub fn build(vsm: &Vsm, options: &MeshOptions, first_id: u64) -> (IncrementalMesh, Mesh) {
        IncrementalMesh::build_with(vsm, None, options, first_id)
    }

    /// Like [`IncrementalMesh::build`], around `structure` (lines and text blocks): their
    /// skeleton's points and constraint edges go into a constrained Delaunay triangulation and
    /// ordinary key points that would crowd them are dropped.
    pub fn build_with(
        vsm: &Vsm,
        structure: Option<&Structure>,
        options: &MeshOptions,
        first_id: u64,
    ) -> (IncrementalMesh, Mesh) {
        IncrementalMesh::build_with_points(vsm, structure, &[], options, first_id)
    }

    /// Like [`IncrementalMesh::build_with`], with `extra` points that are always vertices (the
    /// centres of vector marks bound to the mesh, §5.3).
    pub fn build_with_points(
        vsm: &Vsm,
        structure: Option<&Structure>,
        extra: &[DVec2],
        options: &MeshOptions,
        first_id: u64,
    ) -> (IncrementalMesh, Mesh) {
        IncrementalMesh::build_with_marks(vsm, structure, extra, &[], options, first_id)
    }

    /// Like [`IncrementalMesh::build_with_points`], with `given` marks (vector marks, §5.3)
    /// ringed like the small marks found in `vsm`: each gets its centre and a ring of key
    /// points at its `ring_radius`, lattice points near it are dropped, and a found mark whose
    /// ring overlaps a given one's is dropped (it is the given mark, seen in the map). Given
    /// rings are outside the ring budget of the found marks, up to `GIVEN_RING_SHARE` times
    /// the key point budget (the largest by `pixels` first; the others keep their centres in
    /// `extra` only).
    pub fn build_with_marks(
        vsm: &Vsm,
        structure: Option<&Structure>,
        extra: &[DVec2],
        given: &[Mark],
        options: &MeshOptions,
        first_id: u64,
    ) -> (IncrementalMesh, Mesh) {
        let size = vsm.size();
        let sk = structure
            .filter(|s| !s.is_empty())
            .map(|s| skeleton(s, size, options.budget_alpha() as f64));
        let given = GivenRings::new(given, size, options.budget_alpha());
        let mut marks = found_marks(vsm, &given, sk.as_ref());
        let points = sample_key_points(vsm, options.budget_alpha(), &marks);
        let mut keys = KeyInput::new(size, first_id);
        for c in corners(size) {
            keys.push(c);
        }
        let SkeletonVertices { edges, roles } = match &sk {
            Some(sk) => keys.push_skeleton(sk),
            None => SkeletonVertices::default(),
        };
        for &p in extra {
            if p.x >= 0.0 && p.y >= 0.0 && p.x <= size.width as f64 && p.y <= size.height as f64 {
                keys.push(p);
            }
        }
        for p in given.key_points(size) {
            keys.push(p);
        }
        keys.push_sampled(&points, &given, sk.as_ref());
        let tri = ConstrainedDelaunayTriangulation::try_bulk_load_cdt(keys.input, edges, |_| {})
            .unwrap_or_default();
        marks.extend_from_slice(&given.marks);
        let inc = IncrementalMesh {
            tri,
            size,
            marks,
            next_id: keys.next_id,
            structure: sk.map(|sk| Arc::new(sk.structure)),
            roles,
        };
        let mesh = inc.to_mesh();
        (inc, mesh)
    }
}

/// The small marks found in `vsm` that get rings: not one whose ring overlaps a given mark's
/// (it is the given mark, seen in the map), nor one inside a text block of the skeleton
/// (text is meshed as blocks, never as marks).
fn found_marks(vsm: &Vsm, given: &GivenRings, sk: Option<&super::skeleton::Skeleton>) -> Vec<Mark> {
    let mut marks = find_marks(vsm);
    if !given.marks.is_empty() {
        marks.retain(|m| !given.near(m.center, m.ring_radius, 1.0));
    }
    if let Some(sk) = sk {
        marks.retain(|m| {
            !sk.structure.text.iter().any(|b| {
                m.center.x > b.x0 as f64
                    && m.center.x < b.x1 as f64
                    && m.center.y > b.y0 as f64
                    && m.center.y < b.y1 as f64
            })
        });
    }
    marks
}

/// The vertices of a mesh being built. Each position (clamped and snapped) is one vertex: a
/// point given twice (a skeleton point that is also a mark's centre) gets the index it has,
/// so that constraint edges name it; ids follow from the first one in the order vertices are
/// added.
struct KeyInput {
    size: Size,
    next_id: u64,
    input: Vec<KeyVertex>,
    seen: HashMap<(u64, u64), usize>,
}

/// The skeleton as vertices of the mesh being built.
#[derive(Default)]
struct SkeletonVertices {
    /// Its constraint edges between vertices (an edge whose ends became one vertex dropped).
    edges: Vec<[usize; 2]>,
    /// Each of its points' role, by the vertex's position.
    roles: HashMap<(u64, u64), Role>,
}

impl KeyInput {
    fn new(size: Size, first_id: u64) -> KeyInput {
        KeyInput {
            size,
            next_id: first_id,
            input: Vec::new(),
            seen: HashMap::new(),
        }
    }

    /// The index of the vertex at `p`, added if new; `None` for a point not finite.
    fn push(&mut self, p: DVec2) -> Option<usize> {
        if !p.x.is_finite() || !p.y.is_finite() {
            return None;
        }
        let v = key(p, self.size, self.next_id);
        let k = (v.pos.x.to_bits(), v.pos.y.to_bits());
        if let Some(&i) = self.seen.get(&k) {
            return Some(i);
        }
        self.next_id += 1;
        self.input.push(v);
        self.seen.insert(k, self.input.len() - 1);
        Some(self.input.len() - 1)
    }

    /// Adds the skeleton's points.
    fn push_skeleton(&mut self, sk: &super::skeleton::Skeleton) -> SkeletonVertices {
        let idx: Vec<Option<usize>> = sk.points.iter().map(|(p, _)| self.push(*p)).collect();
        let mut roles = HashMap::new();
        for (i, (_, role)) in idx.iter().zip(&sk.points) {
            if let Some(i) = i {
                let v = self.input[*i].pos;
                roles.insert((v.x.to_bits(), v.y.to_bits()), *role);
            }
        }
        let mut edges = Vec::new();
        for [a, b] in &sk.edges {
            if let (Some(a), Some(b)) = (idx[*a], idx[*b]) {
                if a != b {
                    edges.push([a, b]);
                }
            }
        }
        SkeletonVertices { edges, roles }
    }

    /// Adds the sampled key points but the corners (already in), lattice points within a
    /// given mark's exclusion disc (its ring stands for them), and points that would crowd
    /// the skeleton.
    fn push_sampled(
        &mut self,
        points: &[super::sampling::KeyPoint],
        given: &GivenRings,
        sk: Option<&super::skeleton::Skeleton>,
    ) {
        for k in points {
            if k.kind == KeyPointKind::Corner {
                continue;
            }
            if matches!(k.kind, KeyPointKind::Lattice(_)) && given.near(k.pos, 0.0, RING_EXCLUSION)
            {
                continue;
            }
            if let Some(sk) = sk {
                if crowds(&sk.structure, k.pos) {
                    continue;
                }
            }
            self.push(k.pos);
        }
    }
}

impl IncrementalMesh {
    /// The mesh of a canvas taken whole as one data area ([`Structure::whole_canvas`]): its
    /// two triangles. There the warp is the canvas's one linear map, which the corners alone
    /// carry, and the canvas is resampled as a plain resize: key points would shape nothing
    /// drawn, and sampling, triangulating and solving them cost most of a frame. The
    /// structure rides along for what floats over the resize (text, marks).
    pub fn canvas(size: Size, structure: &Structure, first_id: u64) -> (IncrementalMesh, Mesh) {
        let input: Vec<KeyVertex> = corners(size)
            .into_iter()
            .zip(first_id..)
            .map(|(p, id)| key(p, size, id))
            .collect();
        let tri = ConstrainedDelaunayTriangulation::bulk_load(input).unwrap_or_default();
        let inc = IncrementalMesh {
            tri,
            size,
            marks: Vec::new(),
            next_id: first_id + 4,
            structure: Some(Arc::new(as_used(structure, size))),
            roles: HashMap::new(),
        };
        let mesh = inc.to_mesh();
        (inc, mesh)
    }

    /// The next id this mesh would give a new vertex.
    pub fn next_id(&self) -> u64 {
        self.next_id
    }

    /// Re-samples the key points inside the tiles of `region` from `vsm` (a later frame's map):
    /// key points sampled there that an existing vertex already has (sampling is deterministic,
    /// so cells whose saliency did not change give the same points) keep that vertex and its
    /// id; the other vertices there are removed and the other new points inserted. Everything
    /// outside the region keeps its position and id. Corners never move.
    pub fn update(&mut self, vsm: &Vsm, options: &MeshOptions, region: &TileMask) -> Mesh {
        let size = self.size;
        let corner_pts = corners(size);
        // Marks of the region are replaced by those found now.
        let fresh_marks = find_marks(vsm);
        self.marks.retain(|m| !region.contains(m.center));
        self.marks.extend(
            fresh_marks
                .into_iter()
                .filter(|m| region.contains(m.center)),
        );
        // Sample with every current mark known (so their rings exclude lattice points), keep
        // what falls in the region.
        let points = sample_key_points(vsm, options.budget_alpha(), &self.marks);
        let bits = |p: Point2<f64>| (p.x.to_bits(), p.y.to_bits());
        // The structure's skeleton (line and text-block points and their constraint edges)
        // stays as built: ordinary points near it are neither removed nor added.
        let structure = self.structure.clone();
        let crowded = |p: DVec2| structure.as_deref().is_some_and(|s| crowds(s, p));
        let mut wanted: std::collections::HashMap<(u64, u64), Point2<f64>> = points
            .iter()
            .filter(|k| k.kind != KeyPointKind::Corner && region.contains(k.pos) && !crowded(k.pos))
            .map(|k| key(k.pos, size, 0).pos)
            .map(|p| (bits(p), p))
            .collect();
        let skeleton = &self.roles;
        let doomed: Vec<Point2<f64>> = self
            .tri
            .vertices()
            .map(|v| v.data().pos)
            .filter(|p| {
                let q = DVec2::new(p.x, p.y);
                region.contains(q)
                    && !corner_pts.contains(&q)
                    && !skeleton.contains_key(&bits(*p))
                    && wanted.remove(&bits(*p)).is_none()
            })
            .collect();
        for p in doomed {
            let _ = self.tri.locate_and_remove(p);
        }
        let mut fresh: Vec<Point2<f64>> = wanted.into_values().collect();
        // Insertion order decides nothing geometric, but keep ids deterministic.
        fresh.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        for pos in fresh {
            let _ = self.tri.insert(KeyVertex {
                pos,
                id: self.next_id,
            });
            self.next_id += 1;
        }
        self.to_mesh()
    }

    /// Whether `p` lies inside a text block of the structure the mesh was built around (text
    /// is meshed as blocks, never as marks).
    pub(crate) fn in_text(&self, p: DVec2) -> bool {
        self.structure.as_deref().is_some_and(|s| {
            s.text.iter().any(|b| {
                p.x > b.x0 as f64 && p.x < b.x1 as f64 && p.y > b.y0 as f64 && p.y < b.y1 as f64
            })
        })
    }

    /// The current triangulation as a [`Mesh`].
    pub fn to_mesh(&self) -> Mesh {
        let vertices: Vec<DVec2> = self
            .tri
            .vertices()
            .map(|v| DVec2::new(v.data().pos.x, v.data().pos.y))
            .collect();
        let ids: Vec<u64> = self.tri.vertices().map(|v| v.data().id).collect();
        let mut triangles = Vec::with_capacity(self.tri.num_inner_faces());
        for f in self.tri.inner_faces() {
            let [a, b, c] = f.vertices().map(|v| v.fix().index() as u32);
            let area = (vertices[b as usize] - vertices[a as usize])
                .perp_dot(vertices[c as usize] - vertices[a as usize]);
            if area > 0.0 {
                triangles.push([a, b, c]);
            } else if area < 0.0 {
                triangles.push([a, c, b]);
            }
        }
        let mesh = Mesh::from_parts(self.size, vertices, ids, triangles, self.marks.clone());
        match &self.structure {
            Some(st) => {
                let roles = mesh
                    .vertices()
                    .iter()
                    .map(|p| {
                        self.roles
                            .get(&(p.x.to_bits(), p.y.to_bits()))
                            .copied()
                            .unwrap_or_default()
                    })
                    .collect();
                mesh.with_structure(st.clone(), roles)
            }
            None => mesh,
        }
    }
}

/// Given marks may add at most this share of the key point budget `w·h/α²` in rings.
pub const GIVEN_RING_SHARE: f64 = 2.0;

/// Given marks (vector marks) with their rings, indexed by a bucket grid.
struct GivenRings {
    marks: Vec<Mark>,
    cell: f64,
    buckets: HashMap<(i64, i64), Vec<u32>>,
}

impl GivenRings {
    fn new(given: &[Mark], size: Size, alpha: f32) -> GivenRings {
        let budget = size.area() as f64 / (alpha as f64 * alpha as f64);
        let most = (budget * GIVEN_RING_SHARE / (RING_POINTS + 1) as f64) as usize;
        let mut marks: Vec<Mark> = given
            .iter()
            .filter(|m| m.center.is_finite() && m.ring_radius.is_finite() && m.ring_radius > 0.0)
            .copied()
            .collect();
        if marks.len() > most {
            marks.sort_by_key(|m| std::cmp::Reverse(m.pixels));
            marks.truncate(most);
        }
        let cell = 32.0;
        let mut buckets: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
        for (i, m) in marks.iter().enumerate() {
            // Reach of any query: its own radius is added in `near`, so index by the ring's
            // exclusion disc.
            let r = m.ring_radius * RING_EXCLUSION;
            for cy in
                ((m.center.y - r) / cell).floor() as i64..=((m.center.y + r) / cell).floor() as i64
            {
                for cx in ((m.center.x - r) / cell).floor() as i64
                    ..=((m.center.x + r) / cell).floor() as i64
                {
                    buckets.entry((cx, cy)).or_default().push(i as u32);
                }
            }
        }
        GivenRings {
            marks,
            cell,
            buckets,
        }
    }

    /// Whether a disc of radius `r` at `p` comes within `k` ring radii of a given mark.
    fn near(&self, p: DVec2, r: f64, k: f64) -> bool {
        if self.marks.is_empty() {
            return false;
        }
        // Cells within `r` of p: the buckets hold each mark over its exclusion disc.
        let (c0, c1) = (
            ((p.x - r) / self.cell).floor() as i64,
            ((p.x + r) / self.cell).floor() as i64,
        );
        let (r0, r1) = (
            ((p.y - r) / self.cell).floor() as i64,
            ((p.y + r) / self.cell).floor() as i64,
        );
        (r0..=r1).any(|cy| {
            (c0..=c1).any(|cx| {
                self.buckets.get(&(cx, cy)).is_some_and(|list| {
                    list.iter().any(|&i| {
                        let m = &self.marks[i as usize];
                        m.center.distance(p) < r + k * m.ring_radius
                    })
                })
            })
        })
    }

    /// Each given mark's centre and ring (points within half a pixel of the sides dropped).
    fn key_points(&self, size: Size) -> Vec<DVec2> {
        let (w, h) = (size.width as f64, size.height as f64);
        let mut out = Vec::with_capacity(self.marks.len() * (RING_POINTS + 1));
        for m in &self.marks {
            out.push(m.center);
            for i in 0..RING_POINTS {
                let a = std::f64::consts::TAU * (i as f64 + 0.5) / RING_POINTS as f64;
                let p = m.center + m.ring_radius * DVec2::new(a.cos(), a.sin());
                if p.x > 0.5 && p.y > 0.5 && p.x < w - 0.5 && p.y < h - 0.5 {
                    out.push(p);
                }
            }
        }
        out
    }
}

fn corners(size: Size) -> [DVec2; 4] {
    let (w, h) = (size.width as f64, size.height as f64);
    [
        DVec2::new(0.0, 0.0),
        DVec2::new(w, 0.0),
        DVec2::new(0.0, h),
        DVec2::new(w, h),
    ]
}

/// A key point clamped into the canvas and snapped to the fixed-point grid.
fn key(p: DVec2, size: Size, id: u64) -> KeyVertex {
    let (w, h) = (size.width as f64, size.height as f64);
    KeyVertex {
        pos: Point2::new(snap(p.x.clamp(0.0, w)), snap(p.y.clamp(0.0, h))),
        id,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::mesh::cross2;
    use crate::saliency::VsmBuilder;

    fn dots(size: Size, centres: &[(f32, f32)]) -> Image {
        let mut img = Image::filled(size, [255; 4]);
        for y in 0..size.height {
            for x in 0..size.width {
                for &(cx, cy) in centres {
                    let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                    if dx * dx + dy * dy <= 36.0 {
                        img.set(x, y, [215, 25, 28, 255]);
                    }
                }
            }
        }
        img
    }

    /// Moving one dot re-samples only its tiles: vertices elsewhere keep their ids and
    /// positions, the moved dot gets a ring where it is now, and the mesh stays valid.
    #[test]
    fn local_update_keeps_everything_outside_the_region() {
        let size = Size::new(320, 200).unwrap();
        let a = dots(size, &[(60.0, 50.0), (250.0, 150.0), (160.0, 100.0)]);
        let b = dots(size, &[(60.0, 50.0), (250.0, 150.0), (176.0, 100.0)]);
        let mut builder = VsmBuilder::new();
        let va = builder.build(a.as_ref());
        let vb = builder.build(b.as_ref());
        let opts = MeshOptions::default();
        let (mut inc, before) = IncrementalMesh::build(&va, &opts, 0);
        let mut region = TileMask::new(size, 32);
        for (c, r) in [(4, 2), (4, 3), (5, 2), (5, 3), (6, 2), (6, 3)] {
            region.set(c, r);
        }
        let after = inc.update(&vb, &opts, &region);
        // Valid: positive areas tiling the canvas.
        let area: f64 = (0..after.triangles().len())
            .map(|t| cross2(after.triangle_points(t)) / 2.0)
            .sum();
        assert!((area - 320.0 * 200.0).abs() < 1e-6);
        assert!((0..after.triangles().len()).all(|t| cross2(after.triangle_points(t)) > 0.0));
        // Outside the region: same ids at the same places.
        let old: std::collections::HashMap<u64, DVec2> = before
            .ids()
            .iter()
            .copied()
            .zip(before.vertices().iter().copied())
            .collect();
        let mut kept = 0;
        for (id, p) in before.ids().iter().zip(before.vertices()) {
            if !region.contains(*p) {
                let i = after
                    .ids()
                    .iter()
                    .position(|x| x == id)
                    .expect("kept vertex");
                assert_eq!(after.vertices()[i], *p);
                kept += 1;
            }
        }
        assert!(kept > 10);
        // Inside: new ids only, and a ring around the dot's new place.
        for (id, p) in after.ids().iter().zip(after.vertices()) {
            if region.contains(*p) && !old.contains_key(id) {
                assert!(*id >= before.ids().len() as u64);
            }
        }
        let c = DVec2::new(176.0, 100.0);
        let near = after
            .vertices()
            .iter()
            .filter(|p| p.distance(c) < 14.0)
            .count();
        assert!(near >= 9, "ring around the moved dot: {near}");
        let old_c = DVec2::new(160.0, 100.0);
        let stale = after
            .vertices()
            .iter()
            .filter(|p| p.distance(old_c) < 9.0 && p.distance(c) > 14.0)
            .count();
        assert_eq!(stale, 0, "no ring left where the dot was");
    }
}
