//! Key points by saliency level under the `α` budget (§5.1, Eq. 7).
//!
//! The paper samples each level with its own interval `I_k`, shorter where the level's saliency
//! mass is larger, and caps the total at `C_p = w·h/α²`. Eq. 7 as printed mixes units (a point
//! count over a square root of summed saliency), so we keep its shape and make it concrete:
//!
//! * base intervals `I_3 = α/2`, `I_2 = α`, `I_1 = 3α`: dense on salient content, sparse on empty
//!   background (with α = 20: 10, 20 and 60 px);
//! * if the lattices would exceed the budget, every interval grows by the same factor
//!   `sqrt(N / C_p)`, so a busier frame gets a coarser mesh, never a bigger one;
//! * each `I_k × I_k` cell holding pixels of level k contributes one point, at the centroid of
//!   those pixels. A thin line or a narrow bar then gets points on it even when it falls between
//!   lattice positions (point sampling at cell centres would miss it);
//! * a point closer than `I_k / 2` to an earlier one is dropped (Poisson-disk rejection, higher
//!   levels first), as is a lattice point inside a mark's ring.
//!
//! Corners are always key points; the sides get points at the interval of the level of the
//! content touching them.

use super::marks::Mark;
use crate::saliency::{SaliencyLevel, Vsm};
use glam::DVec2;

/// Why a key point exists.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum KeyPointKind {
    Corner,
    Side,
    /// On the ring around a small mark.
    MarkRing,
    /// At the centre of a small mark.
    MarkCentre,
    /// A lattice point of a saliency level.
    Lattice(SaliencyLevel),
}

/// A key point of §5.1.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct KeyPoint {
    pub pos: DVec2,
    pub kind: KeyPointKind,
}

/// Base interval of each level, in units of α.
const BASE_INTERVAL: [f64; 3] = [3.0, 2.0, 0.5];
/// Smallest interval, px: below this triangles get thinner than the rendering resolution.
const MIN_INTERVAL_PX: f64 = 4.0;
/// Key points on each mark's ring.
pub(crate) const RING_POINTS: usize = 8;
/// Lattice points closer to a mark than this many ring radii are dropped.
pub(crate) const RING_EXCLUSION: f64 = 1.5;
/// Rings may take at most this share of the budget; beyond it the largest marks keep theirs.
const RING_BUDGET_SHARE: f64 = 0.5;
/// Rings every image may have whatever its budget: the budget scales with the area, but a
/// small chart still has a few dozen marks, and a mark without a ring is squeezed with the
/// ground around it (128 rings are about 1150 vertices, a few ms of solve).
const MIN_RINGS: usize = 128;

/// The per-level intervals `I_k` for a VSM, after the budget.
pub(crate) fn intervals(vsm: &Vsm, alpha: f32, reserved: usize) -> [f64; 3] {
    let size = vsm.size();
    let budget = size.area() as f64 / (alpha as f64 * alpha as f64);
    let cell_area = (vsm.scale() * vsm.scale()) as usize;
    let mut count = [0usize; 3];
    for &v in vsm.values() {
        count[SaliencyLevel::of(v).index()] += cell_area;
    }
    let mut iv = BASE_INTERVAL.map(|b| (b * alpha as f64).max(MIN_INTERVAL_PX));
    let wanted: f64 = (0..3).map(|k| count[k] as f64 / (iv[k] * iv[k])).sum();
    let room = (budget - reserved as f64).max(budget * 0.25);
    if wanted > room {
        let f = (wanted / room).sqrt();
        iv = iv.map(|i| i * f);
    }
    iv
}

/// Samples the key points of `vsm` (corners first, then sides, marks and lattices).
pub(crate) fn sample_key_points(vsm: &Vsm, alpha: f32, marks: &[Mark]) -> Vec<KeyPoint> {
    let size = vsm.size();
    let (w, h) = (size.width as f64, size.height as f64);
    let budget = size.area() as f64 / (alpha as f64 * alpha as f64);

    // Marks: keep the largest within the ring budget.
    let max_rings =
        (((budget * RING_BUDGET_SHARE) / (RING_POINTS + 1) as f64) as usize).max(MIN_RINGS);
    let mut marks: Vec<&Mark> = marks.iter().collect();
    if marks.len() > max_rings {
        marks.sort_by_key(|m| std::cmp::Reverse(m.pixels));
        marks.truncate(max_rings);
    }
    let iv = intervals(vsm, alpha, marks.len() * (RING_POINTS + 1));
    let mut grid = PointGrid::new(w, h, MIN_INTERVAL_PX * 2.0);
    let mut out = Vec::new();
    let push = |out: &mut Vec<KeyPoint>, grid: &mut PointGrid, pos: DVec2, kind| {
        grid.insert(pos);
        out.push(KeyPoint { pos, kind });
    };

    for c in [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)] {
        push(
            &mut out,
            &mut grid,
            DVec2::new(c.0, c.1),
            KeyPointKind::Corner,
        );
    }
    for p in side_points(vsm, &iv) {
        push(&mut out, &mut grid, p, KeyPointKind::Side);
    }

    for m in &marks {
        push(&mut out, &mut grid, m.center, KeyPointKind::MarkCentre);
        for i in 0..RING_POINTS {
            let a = std::f64::consts::TAU * (i as f64 + 0.5) / RING_POINTS as f64;
            let p = m.center + m.ring_radius * DVec2::new(a.cos(), a.sin());
            if p.x > 0.5 && p.y > 0.5 && p.x < w - 0.5 && p.y < h - 0.5 {
                push(&mut out, &mut grid, p, KeyPointKind::MarkRing);
            }
        }
    }
    let mut exclusion = PointGrid::new(w, h, 32.0);
    let mut excl_r: Vec<(DVec2, f64)> = Vec::new();
    for m in &marks {
        excl_r.push((m.center, m.ring_radius * RING_EXCLUSION));
        exclusion.insert_disc(m.center, m.ring_radius * RING_EXCLUSION, excl_r.len() - 1);
    }

    // The lattices' share of the budget is estimated from level areas ([`intervals`]); thin
    // salient content (graph edges, outlines) touches more cells than its area suggests, so
    // the lattices are counted and, when over, sampled again with wider intervals: the
    // budget holds for the whole mesh, as Eq. 7 means it to.
    let fixed = out.len();
    let room = (budget - fixed as f64).max(budget * 0.25);
    let mut iv = iv;
    for attempt in 0..LATTICE_ATTEMPTS {
        let mut trial = grid.clone();
        out.truncate(fixed);
        for level in [
            SaliencyLevel::Salient,
            SaliencyLevel::Context,
            SaliencyLevel::Background,
        ] {
            let i = iv[level.index()];
            for p in cell_centroids(vsm, level, i) {
                if exclusion.in_disc(p, &excl_r) || trial.any_within(p, 0.5 * i) {
                    continue;
                }
                push(&mut out, &mut trial, p, KeyPointKind::Lattice(level));
            }
        }
        let lattice = (out.len() - fixed) as f64;
        if lattice <= room * 1.02 || attempt + 1 == LATTICE_ATTEMPTS {
            break;
        }
        // Widened by the whole ratio, not its square root: an area's points fall with the
        // square of the interval, a line's only with the interval, and it is lines that
        // overshoot.
        let f = lattice / room;
        iv = iv.map(|i| i * f);
    }
    out
}

/// Samplings of the lattices at most, to bring them within the budget.
const LATTICE_ATTEMPTS: usize = 3;

/// Points along the four sides (corners excluded), spaced by the interval of the most salient
/// level within one fine interval of the side.
fn side_points(vsm: &Vsm, iv: &[f64; 3]) -> Vec<DVec2> {
    let size = vsm.size();
    let (w, h) = (size.width, size.height);
    let fine = iv[2].max(1.0);
    let depth = (fine.ceil() as u32).clamp(1, w.min(h));
    let mut out = Vec::new();
    // (length, map a position t along the side to a point, level near t)
    let sides: [(u32, bool, bool); 4] = [
        (w, true, false),  // top: along x, y = 0
        (w, true, true),   // bottom
        (h, false, false), // left: along y, x = 0
        (h, false, true),  // right
    ];
    for (len, along_x, far) in sides {
        let level_at = |t: u32| -> SaliencyLevel {
            let mut best = SaliencyLevel::Background;
            let lo = t.saturating_sub(depth / 2);
            let hi = (t + depth / 2).min(len - 1);
            for s in (lo..=hi).step_by(2) {
                for d in (0..depth).step_by(2) {
                    let (x, y) = match (along_x, far) {
                        (true, false) => (s, d),
                        (true, true) => (s, h - 1 - d.min(h - 1)),
                        (false, false) => (d, s),
                        (false, true) => (w - 1 - d.min(w - 1), s),
                    };
                    best = best.max(vsm.level(x.min(w - 1), y.min(h - 1)));
                }
            }
            best
        };
        let mut last = 0.0f64;
        let mut t = fine;
        let end = len as f64;
        while t < end - 0.5 * fine {
            let lvl = level_at(t as u32);
            let step = iv[lvl.index()];
            if t - last >= step && end - t >= 0.5 * step {
                let p = match (along_x, far) {
                    (true, false) => DVec2::new(t.round(), 0.0),
                    (true, true) => DVec2::new(t.round(), h as f64),
                    (false, false) => DVec2::new(0.0, t.round()),
                    (false, true) => DVec2::new(w as f64, t.round()),
                };
                out.push(p);
                last = t;
            }
            t += fine;
        }
    }
    out
}

/// One point per `interval`-sized cell holding pixels of `level`: their centroid (image
/// pixels; the map may be coarser than the image).
fn cell_centroids(vsm: &Vsm, level: SaliencyLevel, interval: f64) -> Vec<DVec2> {
    let grid = vsm.grid_size();
    let sc = vsm.scale() as f64;
    let (w, h) = (grid.width as usize, grid.height as usize);
    let cell = (interval / sc).max(1.0); // in map cells
    let cols = ((w as f64 / cell).ceil() as usize).max(1);
    let rows = ((h as f64 / cell).ceil() as usize).max(1);
    let mut acc = vec![(0f64, 0f64, 0u32); cols * rows];
    let values = vsm.values();
    let lo = level.lower_bound();
    let hi = match level {
        SaliencyLevel::Background => SaliencyLevel::Context.lower_bound(),
        SaliencyLevel::Context => SaliencyLevel::Salient.lower_bound(),
        SaliencyLevel::Salient => f32::INFINITY,
    };
    // Every second cell in each direction is plenty to place a centroid.
    let step = if cell >= 8.0 { 2 } else { 1 };
    let inv_cell = 1.0 / cell;
    for y in (0..h).step_by(step) {
        let row = &values[y * w..][..w];
        let cy = ((y as f64 * inv_cell) as usize).min(rows - 1);
        for x in (0..w).step_by(step) {
            let v = row[x];
            if v >= lo && v < hi {
                let cx = ((x as f64 * inv_cell) as usize).min(cols - 1);
                let a = &mut acc[cy * cols + cx];
                a.0 += x as f64 + 0.5;
                a.1 += y as f64 + 0.5;
                a.2 += 1;
            }
        }
    }
    let min_count = (((cell * cell) / (step * step) as f64) * 0.02).max(1.0) as u32;
    acc.iter()
        .filter(|a| a.2 >= min_count)
        .map(|a| DVec2::new(a.0 / a.2 as f64 * sc, a.1 / a.2 as f64 * sc))
        .collect()
}

/// A uniform bucket grid for "is there a point within r" queries.
#[derive(Clone)]
struct PointGrid {
    cell: f64,
    cols: usize,
    rows: usize,
    buckets: Vec<Vec<(DVec2, usize)>>,
}

impl PointGrid {
    fn new(w: f64, h: f64, cell: f64) -> PointGrid {
        let cols = ((w / cell).ceil() as usize).max(1);
        let rows = ((h / cell).ceil() as usize).max(1);
        PointGrid {
            cell,
            cols,
            rows,
            buckets: vec![Vec::new(); cols * rows],
        }
    }

    fn cell_of(&self, p: DVec2) -> (usize, usize) {
        let cx = ((p.x / self.cell).floor().max(0.0) as usize).min(self.cols - 1);
        let cy = ((p.y / self.cell).floor().max(0.0) as usize).min(self.rows - 1);
        (cx, cy)
    }

    fn insert(&mut self, p: DVec2) {
        let (cx, cy) = self.cell_of(p);
        self.buckets[cy * self.cols + cx].push((p, 0));
    }

    /// Registers disc `id` in every cell its bounding box touches.
    fn insert_disc(&mut self, c: DVec2, r: f64, id: usize) {
        let (x0, y0) = self.cell_of(c - DVec2::splat(r));
        let (x1, y1) = self.cell_of(c + DVec2::splat(r));
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                self.buckets[cy * self.cols + cx].push((c, id));
            }
        }
    }

    fn in_disc(&self, p: DVec2, discs: &[(DVec2, f64)]) -> bool {
        let (cx, cy) = self.cell_of(p);
        self.buckets[cy * self.cols + cx]
            .iter()
            .any(|&(_, id)| discs[id].0.distance_squared(p) < discs[id].1 * discs[id].1)
    }

    fn any_within(&self, p: DVec2, r: f64) -> bool {
        let (x0, y0) = self.cell_of(p - DVec2::splat(r));
        let (x1, y1) = self.cell_of(p + DVec2::splat(r));
        let r2 = r * r;
        (y0..=y1).any(|cy| {
            (x0..=x1).any(|cx| {
                self.buckets[cy * self.cols + cx]
                    .iter()
                    .any(|&(q, _)| q.distance_squared(p) < r2)
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Image, Size};
    use crate::mesh::{Mesh, MeshOptions};
    use crate::saliency::VsmBuilder;

    fn count_near(mesh: &Mesh, c: DVec2, r: f64) -> usize {
        mesh.vertices()
            .iter()
            .filter(|p| p.distance(c) <= r)
            .count()
    }

    /// Dense on salient content, sparse on empty background, within budget.
    /// Thin salient content (the edges of a graph) touches many more lattice cells than its
    /// area suggests; the mesh still stays within the budget `w·h/α²`.
    #[test]
    fn thin_lines_stay_within_budget() {
        let size = Size::new(600, 400).unwrap();
        let mut img = Image::filled(size, [250; 4]);
        // Parallel diagonal rules 48 px apart (no crossings: those would be found as marks).
        for k in 0..30i32 {
            for x in 0..600i32 {
                let y = x / 2 - 300 + 48 * k;
                if (0..400).contains(&y) {
                    img.set(x as u32, y as u32, [90, 90, 90, 255]);
                }
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        let mesh = Mesh::build(&vsm, &MeshOptions::default());
        let budget = 600.0 * 400.0 / 400.0;
        assert!(
            mesh.vertices().len() as f64 <= budget * 1.05,
            "{} vertices for a budget of {budget}",
            mesh.vertices().len()
        );
    }

    #[test]
    fn density_follows_saliency_and_budget_holds() {
        let size = Size::new(400, 300).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        for y in 60..240 {
            for x in 40..160 {
                // a busy, striped salient block on the left
                if (x / 4 + y / 4) % 2 == 0 {
                    img.set(x, y, [20, 20, 20, 255]);
                }
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        // The paper's budget holds where the mesh shapes the picture (not under one affine
        // map, whose mesh is the coarsest: `MeshOptions::budget_alpha`).
        let options = MeshOptions {
            regions: crate::structure::Regions::Auto,
            ..MeshOptions::default()
        };
        let mesh = Mesh::build(&vsm, &options);
        let budget = 400.0 * 300.0 / 400.0;
        assert!(
            mesh.vertices().len() as f64 <= budget * 1.1,
            "{} vertices",
            mesh.vertices().len()
        );
        let busy = mesh
            .vertices()
            .iter()
            .filter(|p| p.x > 40.0 && p.x < 160.0 && p.y > 60.0 && p.y < 240.0)
            .count();
        let empty = mesh
            .vertices()
            .iter()
            .filter(|p| p.x > 240.0 && p.x < 360.0 && p.y > 60.0 && p.y < 240.0)
            .count();
        assert!(busy > 8 * empty.max(1), "busy {busy} vs empty {empty}");
    }

    /// A 6-px dot alone in white space is content: it gets vertices all around it.
    #[test]
    fn a_small_dot_in_empty_space_gets_a_ring() {
        let size = Size::new(600, 400).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        let c = DVec2::new(301.0, 207.0);
        for y in 0..400u32 {
            for x in 0..600u32 {
                if DVec2::new(x as f64 + 0.5, y as f64 + 0.5).distance(c) <= 3.0 {
                    img.set(x, y, [215, 25, 28, 255]);
                }
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        let mesh = Mesh::build(&vsm, &MeshOptions::default());
        assert!(count_near(&mesh, c, 10.0) >= 9, "ring + centre");
        // Every direction around the dot has a vertex within 10 px.
        for k in 0..8 {
            let a = std::f64::consts::TAU * k as f64 / 8.0;
            let dir = DVec2::new(a.cos(), a.sin());
            let covered = mesh.vertices().iter().any(|p| {
                let d = *p - c;
                d.length() <= 10.0 && d.length() > 2.0 && d.normalize().dot(dir) > 0.7
            });
            assert!(covered, "direction {k}");
        }
        // And the background stays sparse.
        assert!(mesh.vertices().len() < 150, "{}", mesh.vertices().len());
    }

    /// On a frame large enough for a half-resolution map, a 6-px dot is still a mark with its
    /// ring, placed where the dot is.
    #[test]
    fn a_small_dot_on_a_large_frame_gets_a_ring() {
        let size = Size::new(1400, 800).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        let c = DVec2::new(700.0, 413.0);
        for y in 400..426u32 {
            for x in 687..714u32 {
                if DVec2::new(x as f64 + 0.5, y as f64 + 0.5).distance(c) <= 3.0 {
                    img.set(x, y, [215, 25, 28, 255]);
                }
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        assert_eq!(vsm.scale(), 2);
        assert!(vsm.get(700, 413) > 0.5);
        let mesh = Mesh::build(&vsm, &MeshOptions::default());
        assert_eq!(mesh.marks().len(), 1);
        assert!(
            mesh.marks()[0].center.distance(c) < 1.5,
            "{:?}",
            mesh.marks()[0]
        );
        assert!(count_near(&mesh, c, 12.0) >= 9, "ring + centre");
    }

    #[test]
    fn one_affine_map_takes_the_coarsest_mesh() {
        let mut img = Image::filled(Size::new(400, 300).unwrap(), [255; 4]);
        for y in (20..280).step_by(7) {
            for x in (20..380).step_by(5) {
                img.set(x, y, [0, 0, 0, 255]);
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        let count = |regions| {
            let options = MeshOptions {
                regions,
                ..MeshOptions::default()
            };
            Mesh::build(&vsm, &options).vertices().len()
        };
        let (affine, auto) = (
            count(crate::structure::Regions::Affine),
            count(crate::structure::Regions::Auto),
        );
        assert!(affine * 4 < auto, "affine {affine}, auto {auto} vertices");
    }

    #[test]
    fn corners_and_sides_are_present() {
        let size = Size::new(200, 120).unwrap();
        let img = Image::filled(size, [255; 4]);
        let vsm = VsmBuilder::new().build(img.as_ref());
        let options = MeshOptions {
            regions: crate::structure::Regions::Free,
            ..MeshOptions::default()
        };
        let mesh = Mesh::build(&vsm, &options);
        for c in [(0.0, 0.0), (200.0, 0.0), (0.0, 120.0), (200.0, 120.0)] {
            assert!(mesh.vertices().contains(&DVec2::new(c.0, c.1)));
        }
        let top = mesh.vertices().iter().filter(|p| p.y == 0.0).count();
        let left = mesh.vertices().iter().filter(|p| p.x == 0.0).count();
        assert!(top >= 3 && left >= 2, "top {top} left {left}");
    }
}
