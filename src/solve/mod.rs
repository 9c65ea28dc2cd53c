//! Mesh resizing (§5.2): the energy, its boundary constraints, the sparse solve and the
//! fold-over repair, producing a [`Warp`].
//!
//! * `boundary`: Eq. 10–11 as a layout of unknowns;
//! * `weights`: the triangle saliency `λ_t` of Eq. 9;
//! * `energy`: Eq. 8, 9, 12 (and 13's `δ`) assembled into `H u = b`;
//! * `cholesky`: faer's sparse Cholesky with the symbolic factorization kept per topology;
//! * `repair`: no fold-overs, repaired locally.

mod boundary;
mod cholesky;
mod energy;
mod fit;
mod holds;
mod locate;
mod repair;
mod snapping;
mod weights;

pub use energy::EnergyParams;
pub use locate::Locator;

use crate::error::Error;
use crate::image::Size;
use crate::mesh::Mesh;
use crate::raster::snap;
use crate::saliency::Vsm;
use boundary::{Layout, FIXED};
use cholesky::SparseSystem;
use glam::DVec2;

/// Solved vertex positions for one [`Mesh`] on one target size.
///
/// # Guarantees
/// Positions lie on the renderer's fixed-point grid; every triangle has positive signed area
/// (no fold-overs); corners sit on the target's corners and side vertices on their side.
#[derive(Clone, Debug)]
pub struct Warp {
    target: Size,
    positions: Vec<DVec2>,
    scales: Vec<[f64; 2]>,
}

impl Warp {
    /// Linear scaling of `mesh` to `target`: always fold-free; the baseline.
    pub fn linear(mesh: &Mesh, target: Size) -> Warp {
        let sx = target.width as f64 / mesh.size().width as f64;
        let sy = target.height as f64 / mesh.size().height as f64;
        let positions = linear_positions(mesh, target);
        Warp {
            target,
            positions,
            scales: vec![[sx, sy]; mesh.triangles().len()],
        }
    }

    /// A warp that maps each vertex `(x, y)` of `mesh` to `(fx(x), fy(y))`: axis-aligned, so
    /// with `fx`, `fy` increasing it never folds ([`crate::baseline`]'s axis-aligned method).
    /// Positions are put on the renderer's grid; each triangle's scale is its area ratio's root.
    #[cfg(feature = "eval")]
    pub(crate) fn separable(
        mesh: &Mesh,
        target: Size,
        fx: impl Fn(f64) -> f64,
        fy: impl Fn(f64) -> f64,
    ) -> Warp {
        let positions: Vec<DVec2> = mesh
            .vertices()
            .iter()
            .map(|p| DVec2::new(snap(fx(p.x)), snap(fy(p.y))))
            .collect();
        let scales = (0..mesh.triangles().len())
            .map(|t| {
                let [a, b, c] = mesh.triangles()[t].map(|v| positions[v as usize]);
                let [p, q, r] = mesh.triangle_points(t);
                let before = (q - p).perp_dot(r - p);
                let after = (b - a).perp_dot(c - a);
                let s = if before > 0.0 {
                    (after / before).max(0.0).sqrt()
                } else {
                    1.0
                };
                [s, s]
            })
            .collect();
        Warp {
            target,
            positions,
            scales,
        }
    }

    /// Point location through this warp of `mesh` (see [`Locator`]).
    pub fn locator<'a>(&'a self, mesh: &'a Mesh) -> Locator<'a> {
        Locator::new(mesh, self)
    }

    /// The target canvas.
    pub fn target(&self) -> Size {
        self.target
    }

    /// Deformed vertex positions `V'`, on `[0, w'] × [0, h']`.
    pub fn positions(&self) -> &[DVec2] {
        &self.positions
    }

    /// The solved scales `(a_t, b_t)` of each triangle along x and y (equal for a triangle
    /// held similar), relative to the target scale the size prior asked of it.
    pub fn scales(&self) -> &[[f64; 2]] {
        &self.scales
    }

    /// The map `[ax, bx, ay, by]` (`x' = ax·x + bx`, `y' = ay·y + by`) that carries each data
    /// area of `mesh`'s structure, fitted to the vertices inside it that are not text (those
    /// follow it exactly, up to the renderer's grid); `None` for an area without two distinct
    /// vertex positions along each axis.
    pub fn area_maps(&self, mesh: &Mesh) -> Vec<Option<[f64; 4]>> {
        let Some(st) = mesh.structure() else {
            return Vec::new();
        };
        let roles = mesh.roles();
        st.areas
            .iter()
            .map(|a| {
                // A canvas taken whole is resampled by the plain resize's map: what floats over
                // it goes where that map takes it, not where a fit to snapped vertices would.
                if a.kind == crate::structure::AreaKind::Canvas {
                    let (w, h) = (mesh.size().width as f64, mesh.size().height as f64);
                    let t = self.target;
                    return Some([t.width as f64 / w, 0.0, t.height as f64 / h, 0.0]);
                }
                let inside = mesh.vertices().iter().enumerate().filter(|&(i, p)| {
                    a.contains(p.x, p.y, 0.0)
                        && roles.get(i).is_none_or(|r| r.block.is_none())
                        && !mesh.boundary()[i].fixes_x()
                        && !mesh.boundary()[i].fixes_y()
                });
                boundary::fit_map(inside.map(|(i, &p)| (p, self.positions[i])))
            })
            .collect()
    }

    /// Number of triangles with non-positive deformed area that the linear resize keeps
    /// open (always 0 for a solved warp). A sliver of the source that the linear resize's
    /// own fixed-point grid collapses (a few hundredths of a pixel wide, at a target of a
    /// few pixels) is degenerate in every map onto the target, the linear one too: it covers
    /// no pixel and is no fold.
    pub fn folded_triangles(&self, mesh: &Mesh) -> usize {
        let linear = linear_positions(mesh, self.target);
        (repair::folded(mesh, &self.positions).into_iter())
            .filter(|&t| repair::deformed_cross(mesh, &linear, t) > 0)
            .count()
    }
}

fn linear_positions(mesh: &Mesh, target: Size) -> Vec<DVec2> {
    let sx = target.width as f64 / mesh.size().width as f64;
    let sy = target.height as f64 / mesh.size().height as f64;
    mesh.vertices()
        .iter()
        .map(|p| DVec2::new(snap(p.x * sx), snap(p.y * sy)))
        .collect()
}

/// The target scales of the size prior (Eq. 13's `δ`) for one frame.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SalientFit {
    /// For salient content free to scale each axis apart (bars, cells, panels), along x and y.
    pub free: [f64; 2],
    /// For marks, which keep their shape.
    pub similar: f64,
}

impl Default for SalientFit {
    fn default() -> Self {
        SalientFit {
            free: [1.0; 2],
            similar: 1.0,
        }
    }
}

/// What one solve did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SolveStats {
    /// Unknowns of the sparse system (free coordinates plus one scale per triangle).
    pub unknowns: usize,
    /// Free vertex coordinates: the paper's DOF.
    pub dof: usize,
    /// Stored entries of the system's upper triangle.
    pub nnz: usize,
    /// Whether the symbolic factorization was computed (false: reused).
    pub symbolic: bool,
    /// Folded triangles straight after the first solve.
    pub folds_first_solve: usize,
    /// Re-solves with raised weights.
    pub repair_rounds: usize,
    /// Vertices moved by local untangling.
    pub untangled: usize,
    /// Whether the marks' fans were held rigid (false: given up to avoid a global blend).
    pub fans_held: bool,
    /// Blend factor towards linear scaling (0: none was needed).
    pub blend: f64,
    /// Whether the blend had to be global.
    pub blend_global: bool,
    /// The scale the size prior asked of marks, which keep their shape (1 unless they could
    /// not fit, or more on a canvas that grows).
    pub salient_scale: f64,
    /// The scales the size prior asked of other salient content along x and y.
    pub salient_fit: [f64; 2],
    /// Lines and text blocks moved onto the pixel grid after the solve.
    pub snapped: usize,
    /// Text blocks moved as one (a scale each).
    pub text_blocks: usize,
    /// Text blocks held at their target scale, by the hold stages that settled without folds.
    pub text_held: usize,
}

/// Solves the energy for meshes, keeping the symbolic factorization while the topology holds.
#[derive(Default)]
pub struct Solver {
    params: EnergyParams,
    system: SparseSystem,
    topology: Option<u64>,
    layout: Layout,
    geom: Vec<energy::TriangleGeometry>,
    lambda: Vec<f64>,
    boost: Vec<f64>,
    delta: Vec<[f64; 2]>,
    anchors: Vec<Option<(DVec2, f64)>>,
    /// Per-triangle enhancement factors (empty: none).
    enhance: Vec<f64>,
    /// Per text block, the scale it is pulled to, and how much more firmly than usual.
    text_targets: Vec<f64>,
    text_hold: Vec<f64>,
    pairs: Vec<(u32, u32)>,
    rhs: Vec<f64>,
}

/// A solution of the system: positions on the renderer's grid and the triangles' scales, and
/// the triangles those positions fold.
#[derive(Clone)]
struct Solution {
    positions: Vec<DVec2>,
    scales: Vec<[f64; 2]>,
    folded: Vec<usize>,
}

/// Folds after the first solve that local untangling may take care of.
const FEW_FOLDS: usize = 8;

/// Re-solves with tripled weights on folded triangles, at most this many times.
const REPAIR_ROUNDS: usize = 8;
const REPAIR_FACTOR: f64 = 3.0;

impl Solver {
    pub fn new(params: EnergyParams) -> Solver {
        Solver {
            params,
            ..Solver::default()
        }
    }

    /// The energy parameters.
    pub fn params(&self) -> &EnergyParams {
        &self.params
    }

    /// `λ_t` per triangle from the last solve.
    pub fn triangle_saliency(&self) -> &[f64] {
        &self.lambda
    }

    /// Solves `mesh` on `vsm` for `target`, repairing fold-overs.
    pub fn solve(
        &mut self,
        mesh: &Mesh,
        vsm: &Vsm,
        target: Size,
    ) -> Result<(Warp, SolveStats), Error> {
        self.enhance.clear();
        self.solve_inner(mesh, vsm, target)
    }

    /// Like [`Solver::solve`], with content enhancement (§5.4, Eq. 13): triangle `t` is asked to
    /// take `enhance[t]` times the scale it would otherwise get (1 = unchanged, 1.5 = half as
    /// large again). A triangle with a factor other than 1 gets the size prior whatever its
    /// saliency, so the factor acts on any level.
    pub fn solve_enhanced(
        &mut self,
        mesh: &Mesh,
        vsm: &Vsm,
        target: Size,
        enhance: &[f64],
    ) -> Result<(Warp, SolveStats), Error> {
        self.enhance.clear();
        self.enhance.extend_from_slice(enhance);
        self.enhance.resize(mesh.triangles().len(), 1.0);
        self.solve_inner(mesh, vsm, target)
    }

    fn solve_inner(
        &mut self,
        mesh: &Mesh,
        vsm: &Vsm,
        target: Size,
    ) -> Result<(Warp, SolveStats), Error> {
        self.text_targets = mesh.structure().map_or(Vec::new(), |s| {
            let mut t = fit::text_fit_scales(&s.text, s, mesh.size(), target);
            let attached = boundary::attachments(s);
            fit::attached_fit(&s.text, &attached, mesh.size(), target, &mut t);
            t
        });
        let text = mesh.structure().map_or(&[][..], |s| &s.text[..]);
        let tt = &self.text_targets;
        let threshold = self.params.prior_threshold as f32;
        let (free, similar) = fit::salient_fit(vsm, target, threshold, text, tt);
        let fit = SalientFit { free, similar };
        self.anchors.clear();
        // Marks' fans held rigid first; where that leaves folds only a blend of the whole warp
        // towards linear scaling would undo (crowded layouts where rigid fans, lines and text
        // blocks leave the ground between them no room), solved again with fans weighted by
        // their saliency alone: a blurred, shifted warp costs every line and label, a fan
        // held less firmly only its mark's roundness.
        let mut hold_fans = true;
        let (positions, scales, stats) = loop {
            weights::triangle_saliency(mesh, vsm, hold_fans, &mut self.lambda);
            let layout = Layout::new(mesh, target);
            let (
                Solution {
                    mut positions,
                    scales,
                    folded: bad,
                },
                mut stats,
            ) = self.solve_with(mesh, layout, target, fit)?;
            if !bad.is_empty() {
                let vt = repair::VertexTriangles::new(mesh);
                stats.untangled =
                    repair::untangle(mesh, &self.layout, &self.lambda, &vt, &mut positions);
                let linear = linear_positions(mesh, target);
                let (blend, global) =
                    repair::blend_towards_linear(mesh, &vt, &linear, &mut positions);
                stats.blend = blend;
                stats.blend_global = global;
                if global && hold_fans && mesh.fan_triangles().contains(&true) {
                    hold_fans = false;
                    continue;
                }
            }
            stats.fans_held = hold_fans;
            break (positions, scales, stats);
        };
        let warp = Warp {
            target,
            positions,
            scales,
        };
        #[cfg(any(debug_assertions, feature = "sanity-checks"))]
        assert_eq!(
            warp.folded_triangles(mesh),
            0,
            "a folded triangle would reach the renderer"
        );
        Ok((warp, stats))
    }

    /// Solves only around what changed: vertex `i` with `fixed[i] = Some(p)` stays at `p` (its
    /// position in the last frame's warp), the others are solved, with `salient_fit` as the
    /// size prior's targets along x and y (the value of the last full solve, so that a local update does not
    /// change the scale of everything else). Returns `None` if folds remain after the repair
    /// rounds: the caller then solves the whole mesh. A free vertex `i` with `anchors[i] =
    /// Some((p, k))` is pulled towards `p` by the temporal term ([`EnergyParams::temporal`]
    /// times `k`).
    pub(crate) fn solve_local(
        &mut self,
        mesh: &Mesh,
        vsm: &Vsm,
        target: Size,
        fixed: &[Option<DVec2>],
        anchors: &[Option<(DVec2, f64)>],
        salient_fit: SalientFit,
    ) -> Result<Option<(Warp, SolveStats)>, Error> {
        weights::triangle_saliency(mesh, vsm, true, &mut self.lambda);
        self.anchors.clear();
        self.anchors.extend_from_slice(anchors);
        let layout = Layout::with_fixed(mesh, target, fixed);
        let (
            Solution {
                positions,
                scales,
                folded: bad,
            },
            stats,
        ) = self.solve_with(mesh, layout, target, salient_fit)?;
        if !bad.is_empty() {
            return Ok(None);
        }
        let warp = Warp {
            target,
            positions,
            scales,
        };
        Ok(Some((warp, stats)))
    }

    /// Solves with the current `λ_t` on `layout`, the size prior aiming at `fit` along x and y
    /// (Eq. 13's `δ`; `fit.similar` for what keeps its shape): undoes a few folds locally or
    /// else by repair rounds, holds text near its target at it, and snaps the structure to the
    /// pixel grid; returns the solution (whose `folded` are the triangles still folded) and the
    /// stats.
    fn solve_with(
        &mut self,
        mesh: &Mesh,
        layout: Layout,
        target: Size,
        fit: SalientFit,
    ) -> Result<(Solution, SolveStats), Error> {
        let mut stats = SolveStats {
            salient_scale: fit.similar,
            salient_fit: fit.free,
            ..SolveStats::default()
        };
        self.layout = layout;
        stats.text_blocks = self.layout.blocks.len();
        self.reset_terms(mesh, fit);
        stats.symbolic = self.ensure_pattern(mesh)?;
        stats.unknowns = self.layout.n;
        stats.dof = self.layout.dof();
        stats.nnz = self.system.nnz();

        let mut sol = self.numeric_solve(mesh)?;
        stats.folds_first_solve = sol.folded.len();
        self.untangle_few(mesh, &mut sol, &mut stats);
        self.repair_rounds(mesh, &mut sol, &mut stats)?;
        self.hold_text_in_stages(mesh, target, &mut sol, &mut stats)?;
        if sol.folded.is_empty() {
            if let Some((snapped, n)) = snapping::snap_structure(mesh, &self.layout, &self.rhs) {
                sol.positions = snapped;
                stats.snapped = n;
            }
        }
        Ok((sol, stats))
    }

    /// Starts this solve's per-triangle terms afresh: no repair boost, no text held, and the
    /// size prior's targets `δ` for `fit`.
    fn reset_terms(&mut self, mesh: &Mesh, fit: SalientFit) {
        self.boost.clear();
        self.boost.resize(mesh.triangles().len(), 1.0);
        self.text_hold.clear();
        self.text_hold.resize(self.layout.blocks.len(), 1.0);
        self.delta.clear();
        self.delta.extend(self.layout.s_var.iter().map(|&[a, b]| {
            if a == b {
                [fit.similar; 2]
            } else {
                fit.free
            }
        }));
        for (d, &e) in self.delta.iter_mut().zip(&self.enhance) {
            *d = d.map(|v| v * e);
        }
        // A triangle inside a text block aims at the block's own scale.
        if let Some(st) = mesh.structure() {
            for t in 0..mesh.triangles().len() {
                let Some(k) = mesh.triangle_block(t).map(|b| b as usize) else {
                    continue;
                };
                if k < st.text.len() {
                    self.delta[t] = [self.text_targets.get(k).copied().unwrap_or(1.0)
                        * self.enhance.get(t).copied().unwrap_or(1.0);
                        2];
                }
            }
        }
    }

    /// A hash of what the assembly's order of entries depends on: the layout, the geometry
    /// and which vertices carry a temporal anchor. Equal keys share the sparsity pattern and
    /// its symbolic factorization.
    fn system_key(&self, mesh: &Mesh) -> u64 {
        let anchored = {
            use std::hash::{Hash, Hasher};
            let mut h = std::collections::hash_map::DefaultHasher::new();
            for a in &self.anchors {
                a.is_some().hash(&mut h);
            }
            h.finish()
        };
        self.layout.pattern_key(mesh) ^ geometry_key(mesh).rotate_left(1) ^ anchored.rotate_left(2)
    }

    /// Sets the system's pattern (and computes its symbolic factorization) unless the last
    /// solve's still holds; whether it did.
    fn ensure_pattern(&mut self, mesh: &Mesh) -> Result<bool, Error> {
        let key = self.system_key(mesh);
        if self.topology == Some(key) {
            return Ok(false);
        }
        self.geom = energy::geometry(mesh);
        self.pairs.clear();
        self.rhs.clear();
        self.rhs.resize(self.layout.n, 0.0);
        let terms = energy::TriangleTerms {
            lambda: &self.lambda,
            boost: &self.boost,
            delta: &self.delta,
            anchors: &self.anchors,
            text_targets: &self.text_targets,
            text_hold: &self.text_hold,
            enhance: &self.enhance,
        };
        let pairs = &mut self.pairs;
        energy::assemble(
            mesh,
            &self.layout,
            &self.geom,
            &terms,
            &self.params,
            &mut self.rhs,
            |i, j, _| pairs.push((i as u32, j as u32)),
        );
        self.system.set_pattern(self.layout.n, &self.pairs)?;
        self.topology = Some(key);
        Ok(true)
    }

    /// A few folds in empty ground after the first solve are undone locally (moving a vertex
    /// or two towards its neighbours) instead of by solving the whole system again with them
    /// held firmer; not next to a mark, whose ring moved would dent it.
    fn untangle_few(&mut self, mesh: &Mesh, sol: &mut Solution, stats: &mut SolveStats) {
        let bad = &sol.folded;
        if bad.is_empty()
            || bad.len() > FEW_FOLDS
            || !bad
                .iter()
                .all(|&t| self.lambda[t] < self.params.prior_threshold)
        {
            return;
        }
        let vt = repair::VertexTriangles::new(mesh);
        if next_to_a_mark(mesh, &vt, bad) {
            return;
        }
        let mut local = sol.positions.clone();
        let moved = repair::untangle(mesh, &self.layout, &self.lambda, &vt, &mut local);
        if repair::folded(mesh, &local).is_empty() {
            self.take_untangled(&local, &sol.positions);
            sol.positions = local;
            stats.untangled = moved;
            sol.folded.clear();
        }
    }

    /// Untangling moves private coordinates only (one unknown each): the solution vector,
    /// which snapping reads, takes the moved values (`moved` against `solved`) too.
    fn take_untangled(&mut self, moved: &[DVec2], solved: &[DVec2]) {
        for (v, (p, q)) in moved.iter().zip(solved).enumerate() {
            if p == q {
                continue;
            }
            for (z, c) in [(&self.layout.x[v], p.x), (&self.layout.y[v], p.y)] {
                if let Some(var) = z.single().filter(|_| self.layout.is_private(z)) {
                    self.rhs[var as usize] = c;
                }
            }
        }
    }

    /// Re-solves with raised weights on folded triangles until none is left or the rounds are
    /// spent.
    fn repair_rounds(
        &mut self,
        mesh: &Mesh,
        sol: &mut Solution,
        stats: &mut SolveStats,
    ) -> Result<(), Error> {
        let mut rounds = 0;
        while !sol.folded.is_empty() && rounds < REPAIR_ROUNDS {
            for &t in sol.folded.iter() {
                self.boost[t] *= REPAIR_FACTOR;
            }
            *sol = self.numeric_solve(mesh)?;
            rounds += 1;
        }
        stats.repair_rounds += rounds;
        Ok(())
    }

    /// Assembles values for the current pattern, factorizes and solves; returns snapped
    /// positions, scales and the triangles folded.
    fn numeric_solve(&mut self, mesh: &Mesh) -> Result<Solution, Error> {
        self.rhs.clear();
        self.rhs.resize(self.layout.n, 0.0);
        self.system.clear_values();
        let terms = energy::TriangleTerms {
            lambda: &self.lambda,
            boost: &self.boost,
            delta: &self.delta,
            anchors: &self.anchors,
            text_targets: &self.text_targets,
            text_hold: &self.text_hold,
            enhance: &self.enhance,
        };
        let system = &mut self.system;
        let mut k = 0usize;
        energy::assemble(
            mesh,
            &self.layout,
            &self.geom,
            &terms,
            &self.params,
            &mut self.rhs,
            |_, _, v| {
                system.add(k, v);
                k += 1;
            },
        );
        self.system.solve_warm(&mut self.rhs)?;
        let u = &self.rhs;
        if u.iter().any(|v| !v.is_finite()) {
            return Err(Error::Solve("non-finite solution".into()));
        }
        let l = &self.layout;
        let positions: Vec<DVec2> = (0..mesh.vertices().len())
            .map(|i| DVec2::new(snap(l.x[i].eval(u)), snap(l.y[i].eval(u))))
            .collect();
        // A triangle outside the system keeps the scale its deformed shape shows.
        let scales = (0..mesh.triangles().len())
            .map(|t| {
                if l.s_var[t][0] != FIXED {
                    return l.s_var[t].map(|v| u[v as usize]);
                }
                let p = mesh.triangle_points(t);
                let q = mesh.triangles()[t].map(|v| positions[v as usize]);
                let a0 = (p[1] - p[0]).perp_dot(p[2] - p[0]);
                let a1 = (q[1] - q[0]).perp_dot(q[2] - q[0]);
                [(a1 / a0).max(0.0).sqrt(); 2]
            })
            .collect();
        let folded = repair::folded(mesh, &positions);
        Ok(Solution {
            positions,
            scales,
            folded,
        })
    }
}

/// Whether a triangle of `folded` has a corner on a mark's fan (`vt`: each vertex's
/// triangles).
fn next_to_a_mark(mesh: &Mesh, vt: &repair::VertexTriangles, folded: &[usize]) -> bool {
    let fans = mesh.fan_triangles();
    folded.iter().any(|&t| {
        mesh.triangles()[t].iter().any(|&v| {
            vt.of(v as usize)
                .iter()
                .any(|&u| fans.get(u as usize).copied().unwrap_or(false))
        })
    })
}

/// A hash of the source geometry (the per-triangle data kept with the pattern depends on it).
fn geometry_key(mesh: &Mesh) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for p in mesh.vertices() {
        p.x.to_bits().hash(&mut h);
        p.y.to_bits().hash(&mut h);
    }
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::mesh::MeshOptions;
    use crate::saliency::VsmBuilder;

    fn scene() -> (Image, Vsm, Mesh) {
        let size = Size::new(240, 160).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        for (cx, cy) in [(60.0f32, 50.0f32), (170.0, 110.0), (120.0, 80.0)] {
            for y in 0..160u32 {
                for x in 0..240u32 {
                    let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                    if dx * dx + dy * dy <= 64.0 {
                        img.set(x, y, [215, 25, 28, 255]);
                    }
                }
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        let mesh = Mesh::build(&vsm, &MeshOptions::default());
        (img, vsm, mesh)
    }

    #[test]
    fn boundary_constraints_hold() {
        let (_, vsm, mesh) = scene();
        let target = Size::new(120, 160).unwrap();
        let (warp, _) = Solver::default().solve(&mesh, &vsm, target).unwrap();
        for ((p, q), b) in mesh
            .vertices()
            .iter()
            .zip(warp.positions())
            .zip(mesh.boundary())
        {
            use crate::mesh::Boundary::*;
            match b {
                Left => assert_eq!(q.x, 0.0),
                Right => assert_eq!(q.x, 120.0),
                Top => assert_eq!(q.y, 0.0),
                Bottom => assert_eq!(q.y, 160.0),
                Corner => assert_eq!(
                    *q,
                    DVec2::new(
                        if p.x > 0.0 { 120.0 } else { 0.0 },
                        if p.y > 0.0 { 160.0 } else { 0.0 }
                    )
                ),
                Interior => assert!(q.x > 0.0 && q.x < 120.0 && q.y > 0.0 && q.y < 160.0),
            }
        }
        assert_eq!(warp.folded_triangles(&mesh), 0);
    }

    /// Same size in, same size out: the identity is the exact minimum (zero energy).
    #[test]
    fn same_size_is_the_identity() {
        let (_, vsm, mesh) = scene();
        let (warp, _) = Solver::default().solve(&mesh, &vsm, vsm.size()).unwrap();
        for (p, q) in mesh.vertices().iter().zip(warp.positions()) {
            assert!(p.distance(*q) < 1e-3, "{p} -> {q}");
        }
    }

    /// The solve is the minimum: perturbing the solution never lowers the energy.
    #[test]
    fn solution_minimizes_the_energy() {
        let (_, vsm, mesh) = scene();
        let target = Size::new(150, 160).unwrap();
        let mut solver = Solver::default();
        let (warp, stats) = solver.solve(&mesh, &vsm, target).unwrap();
        assert_eq!(
            stats.repair_rounds, 0,
            "no folds expected in this mild case"
        );
        let geom = energy::geometry(&mesh);
        let ones = vec![1.0; mesh.triangles().len()];
        let terms = energy::TriangleTerms {
            lambda: &solver.lambda,
            boost: &ones,
            delta: &solver.delta,
            anchors: &[],
            text_targets: &[],
            text_hold: &[],
            enhance: &[],
        };
        let layout = Layout::new(&mesh, target);
        let e0 = energy::energy_of(
            &mesh,
            &layout,
            &geom,
            &terms,
            &solver.params,
            warp.positions(),
            warp.scales(),
        );
        for v in (0..mesh.vertices().len()).step_by(7) {
            if layout.x[v].single().is_none() {
                continue;
            }
            let mut p = warp.positions().to_vec();
            p[v].x += 0.05;
            let e1 = energy::energy_of(
                &mesh,
                &layout,
                &geom,
                &terms,
                &solver.params,
                &p,
                warp.scales(),
            );
            assert!(
                e1 >= e0 - 1e-6 * e0.abs().max(1.0),
                "vertex {v}: {e1} < {e0}"
            );
        }
    }

    /// Salient marks keep their size and shape while the background absorbs the change.
    #[test]
    fn marks_keep_scale_background_absorbs() {
        let (_, vsm, mesh) = scene();
        let target = Size::new(120, 160).unwrap();
        let mut solver = Solver::default();
        let (warp, _) = solver.solve(&mesh, &vsm, target).unwrap();
        let lambda = solver.triangle_saliency().to_vec();
        // Area-weighted ratios of deformed to source area, per class of triangle.
        let (mut sal, mut bg) = ([0.0, 0.0], [0.0, 0.0]);
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let p = mesh.triangle_points(t);
            let q = tri.map(|v| warp.positions()[v as usize]);
            let (a0, a1) = (
                (p[1] - p[0]).perp_dot(p[2] - p[0]),
                (q[1] - q[0]).perp_dot(q[2] - q[0]),
            );
            let class = if lambda[t] > 0.5 {
                &mut sal
            } else if lambda[t] < 0.05 {
                &mut bg
            } else {
                continue;
            };
            class[0] += a1;
            class[1] += a0;
        }
        let (sal, bg) = (sal[0] / sal[1], bg[0] / bg[1]);
        assert!(sal > 0.8, "salient area ratio {sal} (linear: 0.5)");
        assert!(bg < 0.5, "background area ratio {bg} (linear: 0.5)");
    }
}
