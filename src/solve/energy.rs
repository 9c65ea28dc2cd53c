//! The linear resizing energy of §5.2 (Eq. 8, 9, 12), assembled as one sparse symmetric
//! positive-definite system `H u = b` in the vertex positions and the per-triangle scales.
//!
//! # The energy, and what differs from the printed equations
//! Per triangle `t` (area `A_t`, Jacobian `J_t` of the affine map from its source to its deformed
//! shape, scale unknowns `a_t` along x and `b_t` along y, target scales `δ = (δx, δy)`):
//!
//! ```text
//! E = Σ_t Â_t·w_t·[(J00 − δx·a_t)² + (J11 − δy·b_t)²]       shape along the axes (Eq. 8–9)
//!   + Σ_t Â_t·max(w_t, ε)·(J01² + J10²)                     no shear, no rotation
//!   + Σ_t κ·Â_t·w_t·(δx·a_t − δy·b_t)²                       content keeps its aspect, a little
//!   + Σ_t μ_t·A_t·[(a_t − 1)² + (b_t − 1)²]                  size prior on salient triangles
//!   + Σ_{t~n} β·¼(A_t + A_n)·max(√(w_t·w_n), σ)·Σ_axes (a_t − a_n)²   scale smoothing (Eq. 12)
//! ```
//!
//! A mark's fan and the inside of a text block keep their shape: their `a_t` and `b_t` are one
//! unknown ([`Layout`]), and the first and third lines become the paper's `‖J − sI‖²`.
//!
//! * **Per-axis scales.** The paper asks every triangle to stay similar to itself (`J ≈ sI`). A
//!   visualization is mostly rectangles: panels, bars, cells, axes, which a designer squeezes
//!   along one axis and keeps along the other (a responsive layout), while dots and text keep
//!   their shape. With one scale, a bar chart halved in width is halved in height too, its bars'
//!   sides shrink below what reads as a line and the height they had is empty. With two, the
//!   shape term only resists shear and rotation (which bend lines and tilt bars) and what the
//!   prior and smoothing ask; `κ` keeps a trace of the paper's similarity for salient content.
//! * **Jacobian form.** Eq. 8 sums `‖e' − s·e‖²` over a triangle's edges. The same idea written as
//!   `A·‖J − sI‖²` (the paper's own `∫ S‖J_F − P‖²` of §5.2.1) is still linear, but weighs a
//!   triangle by its area instead of its edge lengths: a mark's fan of long thin triangles is
//!   held by what it covers, so marks stay rounder and fold less.
//! * **Slivers.** `Â_t = max(A_t, ζ·Ā)` with `Ā` the mean triangle area: a sliver between a line
//!   and a label beside it, or between two close lines, keeps its shape as firmly as a triangle
//!   of that size, instead of flipping at the least push. `ζ = 0.5`: slivers are far smaller
//!   than half the mean, so they all get the floor, while a triangle of ordinary size keeps
//!   the weight of its own area.
//! * **Weights.** `w_t = max(λ_t^p, floor)` with `λ_t` the mean VSM over the triangle's pixels
//!   (Eq. 9), `p = 4` and `floor = 0.03`. Squaring is not enough contrast: with `λ²` the empty
//!   background still resists and marks get squeezed. With per-axis scales the floor no longer
//!   makes empty ground resist a squeeze, only an uneven one; that is what it is for: near 0
//!   the ground between marks takes a squeeze wherever it lands and folds in whole columns,
//!   and `0.03` still leaves it about 30 times softer than a mark.
//! * **Where λ goes in Eq. 12.** Printed, the smoothing term is `(λ_t s_t − λ_n s_n)²`: between an
//!   empty triangle (`λ ≈ 0`) and a salient one it pulls the salient scale towards zero, so the
//!   marks next to empty space shrink. We take the weight out of the square, as a coupling
//!   strength `√(w_t w_n)`: it ties scales inside salient regions (a mark scales as one piece)
//!   and lets salient and empty neighbours differ freely. Empty ground keeps a coupling
//!   `σ = 0.1`: with none it takes a squeeze wherever the solve happens to put it, and the
//!   20-px gap between two panels closes while wide margins elsewhere stay (with `σ = 0.1`
//!   the gap keeps its share).
//! * **Flat triangles** (no edge inside) weigh `λ_t = 0` however salient their colour
//!   ([`super::weights`]): a header bar or a panel's inside looks the same squeezed, and
//!   the edges that bound it keep their shape in triangles of their own. The room a flat
//!   region gives goes to what must keep its size, the text blocks above all.
//! * **Size prior.** Without it, shrinking a canvas shrinks marks too (the scales are free):
//!   `μ_t` pulls them towards 1 (towards `δ`, which carries the enhancement of §5.4 and the
//!   fit of [`super::fit`]; on a growing canvas marks aim at the geometric mean of the axes' scales
//!   instead), only on triangles with `λ_t ≥ 0.4`. Applied to light layers (map regions) too,
//!   it crushes the gaps between them.
//!
//! The x and y unknowns only meet through similar triangles' shared scale and `κ`; the unknowns
//! are laid out by [`Layout`].

use super::boundary::{Coord, Layout, FIXED};
use crate::error::Error;
use crate::mesh::{Mesh, NONE};
use glam::DVec2;

/// Tuning of the energy. The defaults are what works across the generated and real cases.
#[derive(Clone, Debug)]
pub struct EnergyParams {
    /// Exponent `p` of `w_t = λ_t^p`.
    pub weight_power: f64,
    /// Floor of `w_t`.
    pub weight_floor: f64,
    /// `λ_t` from which the size prior applies.
    pub prior_threshold: f64,
    /// Strength of the size prior relative to the shape term.
    pub prior_strength: f64,
    /// `β`, the strength of scale smoothing.
    pub smoothing: f64,
    /// How strongly a text block holds its scale (per unit of area, relative to a mark's
    /// shape term): text must stay legible, so it gives way last.
    pub text_strength: f64,
    /// `τ`, how strongly a local update holds a re-sampled vertex where the previous frame's
    /// warp put its source position (temporal coherence: background around a moving mark
    /// stays put; salient triangles, weighted ~1, still take the shape they need).
    pub temporal: f64,
    /// Least weight of the shear and rotation residuals (`J01`, `J10`) per unit of area: the
    /// ground between marks is free to stretch or squeeze along either axis, much less to
    /// shear, so rows and columns of a layout stay rows and columns.
    pub shear_floor: f64,
    /// `κ`, how strongly content that is not a mark or text keeps one scale for both axes
    /// (0: bars, panels and cells squeeze along one axis like a responsive layout; large: the
    /// paper's similarity everywhere).
    pub similarity: f64,
    /// Least coupling of neighbouring scales (Eq. 12) per unit of area: empty ground absorbs
    /// a change evenly instead of all of it in one band (which would fold).
    pub smoothing_floor: f64,
    /// A triangle smaller than this share of the mean triangle keeps its shape as firmly as
    /// one of that size: the slivers between a line and a label beside it, or between two
    /// close lines, would otherwise flip at the least push.
    pub sliver_area: f64,
    /// The size prior of salient content free to scale each axis apart (bars, cells, panels),
    /// relative to that of marks and text: it gives way to them first.
    pub free_prior: f64,
}

impl Default for EnergyParams {
    fn default() -> Self {
        EnergyParams {
            weight_power: 4.0,
            weight_floor: 0.03,
            prior_threshold: 0.4,
            prior_strength: 1.0,
            smoothing: 0.5,
            temporal: 0.05,
            text_strength: 0.2,
            shear_floor: 0.01,
            similarity: 0.1,
            smoothing_floor: 0.1,
            sliver_area: 0.5,
            free_prior: 1.0,
        }
    }
}

/// The range each field of [`EnergyParams`] must lie in, in the order
/// [`EnergyParams::validate`] checks them. Strengths and exponents are at least 0: a negative
/// one would make `H` indefinite (no minimum to solve for). Floors, thresholds and shares are
/// compared with `λ_t` or weights (both at most 1) or with the mean triangle area: above 1 they
/// would hold empty ground as firmly as fully salient content. The upper bounds of strengths
/// keep the system's entries far from overflowing (areas reach millions of px²).
const RANGES: [(&str, f64, f64); 12] = [
    ("weight_power", 0.0, 16.0),
    // Above 0: `w_t` is then never 0, so every triangle's shape term is positive definite.
    ("weight_floor", 1e-9, 1.0),
    ("prior_threshold", 0.0, 1.0),
    ("prior_strength", 0.0, 1e6),
    ("smoothing", 0.0, 1e6),
    ("text_strength", 0.0, 1e6),
    ("temporal", 0.0, 1e6),
    ("shear_floor", 0.0, 1.0),
    ("similarity", 0.0, 1e6),
    ("smoothing_floor", 0.0, 1.0),
    ("sliver_area", 0.0, 1.0),
    ("free_prior", 0.0, 1e6),
];

impl EnergyParams {
    /// Checks every field: finite and within its range (see the fields' docs for what each
    /// means). The error names the first field out of range, its value and what is allowed.
    pub fn validate(&self) -> Result<(), Error> {
        // Destructured whole, so that a new field cannot be added without a check.
        let EnergyParams {
            weight_power,
            weight_floor,
            prior_threshold,
            prior_strength,
            smoothing,
            text_strength,
            temporal,
            shear_floor,
            similarity,
            smoothing_floor,
            sliver_area,
            free_prior,
        } = *self;
        let values = [
            weight_power,
            weight_floor,
            prior_threshold,
            prior_strength,
            smoothing,
            text_strength,
            temporal,
            shear_floor,
            similarity,
            smoothing_floor,
            sliver_area,
            free_prior,
        ];
        for ((name, lo, hi), v) in RANGES.into_iter().zip(values) {
            // NaN is in no range.
            if !(lo..=hi).contains(&v) {
                return Err(Error::InvalidOptions(format!(
                    "{name} {v} is out of range: allowed {lo} to {hi}"
                )));
            }
        }
        Ok(())
    }
}

/// Per-triangle inputs of one numeric assembly.
pub(crate) struct TriangleTerms<'a> {
    /// `λ_t`, mean saliency.
    pub lambda: &'a [f64],
    /// Extra weight factor per triangle (fold repair raises it), usually 1.
    pub boost: &'a [f64],
    /// Target scales per triangle along x and y (`δ_k` of Eq. 13), usually 1.
    pub delta: &'a [[f64; 2]],
    /// Per vertex, where the temporal term pulls it and how much more than `τ` (empty: no
    /// temporal term).
    pub anchors: &'a [Option<(DVec2, f64)>],
    /// Per text block, the scale it is pulled to (missing: 1), and how many times more firmly
    /// than [`EnergyParams::text_strength`] (missing: 1).
    pub text_targets: &'a [f64],
    pub text_hold: &'a [f64],
    /// Per-triangle enhancement factors (empty: none); a factor other than 1 brings the size
    /// prior to its triangle whatever its saliency.
    pub enhance: &'a [f64],
}

/// Least weight of an enhanced triangle.
const ENHANCED_WEIGHT: f64 = 0.5;

/// Source-shape data of one triangle, fixed for a topology.
#[derive(Copy, Clone, Debug)]
pub(crate) struct TriangleGeometry {
    pub area: f64,
    /// Gradients of the three barycentric basis functions.
    pub grad: [DVec2; 3],
}

pub(crate) fn geometry(mesh: &Mesh) -> Vec<TriangleGeometry> {
    (0..mesh.triangles().len())
        .map(|t| {
            let [p0, p1, p2] = mesh.triangle_points(t);
            let (e1, e2) = (p1 - p0, p2 - p0);
            let det = e1.perp_dot(e2);
            // Rows of D⁻¹, D = [e1 e2].
            let g1 = DVec2::new(e2.y, -e2.x) / det;
            let g2 = DVec2::new(-e1.y, e1.x) / det;
            TriangleGeometry {
                area: 0.5 * det,
                grad: [-(g1 + g2), g1, g2],
            }
        })
        .collect()
}

/// The effective weight `w_t`.
#[inline]
pub(crate) fn weight(p: &EnergyParams, lambda: f64) -> f64 {
    lambda.max(0.0).powf(p.weight_power).max(p.weight_floor)
}

/// Walks every entry of `H` in a fixed order (that depends on the topology and layout only),
/// calling `entry(i, j, v)` with `i ≤ j`, and adds the right-hand side into `rhs`.
///
/// Convention: the energy is `uᵀHu − 2bᵀu + const`, so the minimum solves `Hu = b`. With
/// local coordinates `z = c + C u`, a local quadratic `zᵀKz` adds `CᵀKC` to `H` and `−CᵀKc`
/// to `b`; both are walked over every ordered pair of local coordinates, keeping the upper
/// triangle (`i ≤ j`), which is exactly `H`'s upper triangle.
///
/// The walk's order is the pattern's: every term calls `entry` for its pairs even where its
/// weight is 0 this time (the k-th call is the k-th slot of [`super::cholesky::SparseSystem`]).
pub(crate) fn assemble(
    mesh: &Mesh,
    layout: &Layout,
    geom: &[TriangleGeometry],
    terms: &TriangleTerms<'_>,
    params: &EnergyParams,
    rhs: &mut [f64],
    entry: impl FnMut(usize, usize, f64),
) {
    rhs.fill(0.0);
    let a = Assembly {
        mesh,
        layout,
        geom,
        terms,
        params,
        w: effective_weights(terms, params),
    };
    let mut sink = Sink { rhs, entry };
    let tris = mesh.triangles();
    let mean_area = mesh.size().width as f64 * mesh.size().height as f64 / tris.len().max(1) as f64;
    for (t, tri) in tris.iter().enumerate() {
        if layout.s_var[t][0] == FIXED {
            continue; // all corners fixed: a constant
        }
        // Weights of the diagonal residuals (J00 − δx·a, J11 − δy·b) and of the off-diagonal
        // ones (J01, J10: shear and rotation), which even empty ground resists a little.
        let stiff = stiffness(layout, tri, geom[t].area, params.sliver_area * mean_area);
        let cd = stiff * a.w[t];
        let co = stiff * a.w[t].max(params.shear_floor * terms.boost[t]);
        a.shape(&mut sink, t, tri, cd, co);
        a.size_prior(&mut sink, t, cd);
    }
    a.smoothing(&mut sink);
    a.text(&mut sink);
    a.temporal(&mut sink);
}

/// `w_t` times the repair's boost, per triangle. An enhanced triangle (§5.4) matters whatever
/// its saliency: it holds the scale asked of it as firmly as salient content.
fn effective_weights(terms: &TriangleTerms<'_>, params: &EnergyParams) -> Vec<f64> {
    terms
        .lambda
        .iter()
        .zip(terms.boost)
        .enumerate()
        .map(|(t, (&l, &b))| {
            let enhanced = terms.enhance.get(t).is_some_and(|&e| e != 1.0);
            let w = weight(params, l);
            if enhanced {
                w.max(ENHANCED_WEIGHT) * b
            } else {
                w * b
            }
        })
        .collect()
}

/// Where a walk of `H` goes: each entry of its upper triangle to `entry`, in the walk's order,
/// and the right-hand side into `rhs`. Generic over `entry` so that the per-entry call of the
/// numeric assembly (the hot loop) is inlined.
struct Sink<'r, F> {
    rhs: &'r mut [f64],
    entry: F,
}

impl<F: FnMut(usize, usize, f64)> Sink<'_, F> {
    /// Adds `K[a][b]` for local coordinates `za`, `zb`.
    #[inline]
    fn pair(&mut self, za: &Coord, zb: &Coord, k: f64) {
        for (va, ca) in za.terms() {
            for (vb, cb) in zb.terms() {
                if va <= vb {
                    (self.entry)(va, vb, k * ca * cb);
                }
            }
            if zb.c != 0.0 {
                self.rhs[va] -= k * ca * zb.c;
            }
        }
    }
}

/// The inputs of one walk of `H`, shared by its terms.
struct Assembly<'a, 't> {
    mesh: &'a Mesh,
    layout: &'a Layout,
    geom: &'a [TriangleGeometry],
    terms: &'a TriangleTerms<'t>,
    params: &'a EnergyParams,
    /// [`effective_weights`].
    w: Vec<f64>,
}

impl Assembly<'_, '_> {
    /// Eq. 8–9 on triangle `t`: its Jacobian against its scales times `δ`, the diagonal
    /// residuals weighted `cd`, shear and rotation `co`.
    #[inline]
    fn shape<F: FnMut(usize, usize, f64)>(
        &self,
        sink: &mut Sink<'_, F>,
        t: usize,
        tri: &[u32; 3],
        cd: f64,
        co: f64,
    ) {
        let layout = self.layout;
        let g = &self.geom[t];
        let [sx, sy] = layout.s_var[t];
        let [dx, dy] = self.terms.delta[t];
        let xs = tri.map(|v| layout.x[v as usize]);
        let ys = tri.map(|v| layout.y[v as usize]);
        // Row 0 of J is the gradient of x', row 1 that of y':
        //   K[xj][xk] = cd gj.x gk.x + co gj.y gk.y,  K[yj][yk] = co gj.x gk.x + cd gj.y gk.y,
        //   K[xj][a] = −cd δx gj.x,  K[yj][b] = −cd δy gj.y,  K[a][a] = cd δx²,  K[b][b] = cd δy².
        for (coords, comp, sv, d) in [(&xs, 0usize, sx, dx), (&ys, 1usize, sy, dy)] {
            let s = Coord::var(sv);
            let (kx, ky) = if comp == 0 { (cd, co) } else { (co, cd) };
            for j in 0..3 {
                for k in 0..3 {
                    let (gj, gk) = (g.grad[j], g.grad[k]);
                    sink.pair(&coords[j], &coords[k], kx * gj.x * gk.x + ky * gj.y * gk.y);
                }
                let gj = g.grad[j];
                let kjs = -cd * d * if comp == 0 { gj.x } else { gj.y };
                sink.pair(&coords[j], &s, kjs);
                sink.pair(&s, &coords[j], kjs);
            }
            sink.pair(&s, &s, cd * d * d);
        }
    }

    /// The size prior `μ_t` on triangle `t`'s scales (0 below the threshold, but walked all
    /// the same) and, for a triangle with a scale per axis, the pull `κ·cd·(δx·a − δy·b)²`
    /// towards similarity.
    #[inline]
    fn size_prior<F: FnMut(usize, usize, f64)>(&self, sink: &mut Sink<'_, F>, t: usize, cd: f64) {
        let params = self.params;
        let [sx, sy] = self.layout.s_var[t];
        let [dx, dy] = self.terms.delta[t];
        let lambda = self.terms.lambda[t];
        let enhanced = self.terms.enhance.get(t).is_some_and(|&e| e != 1.0);
        let mu = if lambda >= params.prior_threshold || enhanced {
            params.prior_strength * self.geom[t].area * self.w[t]
        } else {
            0.0
        };
        let (a, b) = (Coord::var(sx), Coord::var(sy));
        if sx == sy {
            sink.pair(&a, &a, mu);
            sink.rhs[sx as usize] += mu;
        } else {
            let mu = mu * params.free_prior;
            let ks = params.similarity * cd;
            sink.pair(&a, &a, mu + ks * dx * dx);
            sink.pair(&b, &b, mu + ks * dy * dy);
            sink.pair(&a, &b, -ks * dx * dy);
            sink.pair(&b, &a, -ks * dx * dy);
            sink.rhs[sx as usize] += mu;
            sink.rhs[sy as usize] += mu;
        }
    }

    /// Eq. 12, weight outside the square, per axis (half each, so that two similar triangles
    /// are tied as strongly as by one shared scale).
    fn smoothing<F: FnMut(usize, usize, f64)>(&self, sink: &mut Sink<'_, F>) {
        let (layout, geom, w, params) = (self.layout, self.geom, &self.w, self.params);
        for (t, nb) in self.mesh.neighbours().iter().enumerate() {
            for &n in nb {
                if n == NONE || (n as usize) < t {
                    continue;
                }
                let n = n as usize;
                if layout.s_var[t][0] == FIXED || layout.s_var[n][0] == FIXED {
                    continue;
                }
                let b = params.smoothing
                    * 0.25
                    * (geom[t].area + geom[n].area)
                    * (w[t] * w[n]).sqrt().max(params.smoothing_floor);
                for axis in 0..2 {
                    let (st, sn) = (
                        layout.s_var[t][axis] as usize,
                        layout.s_var[n][axis] as usize,
                    );
                    (sink.entry)(st, st, b);
                    (sink.entry)(sn, sn, b);
                    (sink.entry)(st.min(sn), st.max(sn), -b);
                }
            }
        }
    }

    /// Text blocks: their scale pulled to δ (as large as the space allows, at most 1).
    fn text<F: FnMut(usize, usize, f64)>(&self, sink: &mut Sink<'_, F>) {
        let Some(st) = self.mesh.structure() else {
            return;
        };
        let terms = self.terms;
        for (k, block) in self.layout.blocks.iter().enumerate() {
            if block[2] == FIXED {
                continue;
            }
            let b = &st.text[k];
            let area = ((b.x1 - b.x0) * (b.y1 - b.y0)) as f64;
            let mu =
                self.params.text_strength * area * terms.text_hold.get(k).copied().unwrap_or(1.0);
            let sv = block[2] as usize;
            (sink.entry)(sv, sv, mu);
            sink.rhs[sv] += mu * terms.text_targets.get(k).copied().unwrap_or(1.0);
        }
    }

    /// Temporal term: τ·|z − anchor|² on anchored coordinates.
    fn temporal<F: FnMut(usize, usize, f64)>(&self, sink: &mut Sink<'_, F>) {
        let tau = self.params.temporal;
        for (v, a) in self.terms.anchors.iter().enumerate() {
            let Some((a, k)) = *a else { continue };
            for (z, target) in [(self.layout.x[v], a.x), (self.layout.y[v], a.y)] {
                if z.is_fixed() {
                    continue;
                }
                let shifted = Coord {
                    c: z.c - target,
                    ..z
                };
                sink.pair(&shifted, &shifted, tau * k);
            }
        }
    }
}

/// `Â_t`: the triangle's area, at least `floor` (slivers hold their shape), except along a
/// data area's side: a sliver between the area and a tick label or a gutter is where the
/// area's map meets the free warp, and must give way.
fn stiffness(layout: &Layout, tri: &[u32; 3], area: f64, floor: f64) -> f64 {
    let on_area = tri.map(|v| layout.on_area.get(v as usize).copied().unwrap_or(false));
    if on_area.contains(&true) && on_area.contains(&false) {
        area
    } else {
        area.max(floor)
    }
}

/// Energy of given positions and scales (for tests and diagnostics).
#[cfg(test)]
pub(crate) fn energy_of(
    mesh: &Mesh,
    layout: &Layout,
    geom: &[TriangleGeometry],
    terms: &TriangleTerms<'_>,
    params: &EnergyParams,
    pos: &[DVec2],
    scales: &[[f64; 2]],
) -> f64 {
    let mut e = 0.0;
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let g = &geom[t];
        let mean_area =
            mesh.size().width as f64 * mesh.size().height as f64 / mesh.triangles().len() as f64;
        let stiff = stiffness(layout, tri, g.area, params.sliver_area * mean_area);
        let w = weight(params, terms.lambda[t]) * terms.boost[t];
        let wo = w.max(params.shear_floor * terms.boost[t]);
        let mut j = [[0.0; 2]; 2];
        for k in 0..3 {
            let p = pos[tri[k] as usize];
            j[0][0] += p.x * g.grad[k].x;
            j[0][1] += p.x * g.grad[k].y;
            j[1][0] += p.y * g.grad[k].x;
            j[1][1] += p.y * g.grad[k].y;
        }
        let [a, b] = scales[t];
        let [dx, dy] = terms.delta[t];
        e += stiff * w * ((j[0][0] - dx * a).powi(2) + (j[1][1] - dy * b).powi(2));
        let [sx, sy] = layout.s_var[t];
        e += stiff * wo * (j[0][1].powi(2) + j[1][0].powi(2));
        let mu = if terms.lambda[t] >= params.prior_threshold {
            params.prior_strength * g.area * w
        } else {
            0.0
        };
        if sx == sy {
            e += mu * (a - 1.0).powi(2);
        } else {
            e += mu * params.free_prior * ((a - 1.0).powi(2) + (b - 1.0).powi(2));
            e += params.similarity * stiff * w * (dx * a - dy * b).powi(2);
        }
    }
    for (t, nb) in mesh.neighbours().iter().enumerate() {
        for &n in nb {
            if n == NONE || (n as usize) < t {
                continue;
            }
            let n = n as usize;
            let wt = weight(params, terms.lambda[t]) * terms.boost[t];
            let wn = weight(params, terms.lambda[n]) * terms.boost[n];
            let b = params.smoothing
                * 0.25
                * (geom[t].area + geom[n].area)
                * (wt * wn).sqrt().max(params.smoothing_floor);
            for (st, sn) in scales[t].iter().zip(&scales[n]) {
                e += b * (st - sn).powi(2);
            }
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_valid() {
        EnergyParams::default().validate().unwrap();
    }

    /// Every field is checked: below its range, above it, NaN and infinite are refused with
    /// the field's name and range; its bounds are allowed.
    #[test]
    fn each_field_out_of_range_is_refused_by_name() {
        type Field = fn(&mut EnergyParams) -> &mut f64;
        let fields: [(&str, Field); 12] = [
            ("weight_power", |p| &mut p.weight_power),
            ("weight_floor", |p| &mut p.weight_floor),
            ("prior_threshold", |p| &mut p.prior_threshold),
            ("prior_strength", |p| &mut p.prior_strength),
            ("smoothing", |p| &mut p.smoothing),
            ("text_strength", |p| &mut p.text_strength),
            ("temporal", |p| &mut p.temporal),
            ("shear_floor", |p| &mut p.shear_floor),
            ("similarity", |p| &mut p.similarity),
            ("smoothing_floor", |p| &mut p.smoothing_floor),
            ("sliver_area", |p| &mut p.sliver_area),
            ("free_prior", |p| &mut p.free_prior),
        ];
        for (name, field) in fields {
            let &(_, lo, hi) = RANGES.iter().find(|r| r.0 == name).unwrap();
            let below = if lo > 0.0 { lo / 2.0 } else { -1e-3 };
            for bad in [below, hi * 1.5, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut p = EnergyParams::default();
                *field(&mut p) = bad;
                let e = p.validate().expect_err(name).to_string();
                let want = format!("{name} {bad} is out of range: allowed {lo} to {hi}");
                assert!(e.contains(&want), "{e}");
            }
            for ok in [lo, hi] {
                let mut p = EnergyParams::default();
                *field(&mut p) = ok;
                p.validate().unwrap();
            }
        }
    }
}
