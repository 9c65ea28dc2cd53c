//! The linear resizing energy of §5.2 (Eq. 8, 9, 12), assembled as one sparse symmetric
//! positive-definite system `H u = b` in the vertex positions and the per-triangle scales.
//!
//! # The energy, and what differs from the printed equations
//! Per triangle `t` (area `A_t`, Jacobian `J_t` of the affine map from its source to its deformed
//! shape, scale unknown `s_t`):
//!
//! ```text
//! E = Σ_t A_t·w_t·‖J_t − s_t·I‖²_F                      shape (Eq. 8–9, Jacobian form)
//!   + Σ_t μ_t·A_t·(s_t − 1)²                            size prior on salient triangles
//!   + Σ_{t~n} β·½(A_t + A_n)·√(w_t·w_n)·(s_t − s_n)²     scale smoothing (Eq. 12)
//! ```
//!
//! * **Jacobian form.** Eq. 8 sums `‖e' − s·e‖²` over a triangle's edges. The same idea written as
//!   `A·‖J − sI‖²` (the paper's own `∫ S‖J_F − P‖²` of §5.2.1) is still linear, but weighs a
//!   triangle by its area instead of its edge lengths: a thin triangle then resists collapse as
//!   much as a fat one of the same area, which the edge form does not (measured on the seed-7
//!   stills: fewer folds, rounder marks).
//! * **Weights.** `w_t = max(λ_t^p, floor)` with `λ_t` the mean VSM over the triangle's pixels
//!   (Eq. 9), `p = 4` and `floor = 0.001`. Squaring is not enough contrast: with `λ²` the empty
//!   background still resists and marks get squeezed. The floor keeps the system positive
//!   definite when a region is empty.
//! * **Where λ goes in Eq. 12.** Printed, the smoothing term is `(λ_t s_t − λ_n s_n)²`: between an
//!   empty triangle (`λ ≈ 0`) and a salient one it pulls the salient scale towards zero, so the
//!   marks next to empty space shrink. We take the weight out of the square, as a coupling
//!   strength `√(w_t w_n)`: it ties scales inside salient regions (a mark scales as one piece)
//!   and lets salient and empty neighbours differ freely.
//! * **Size prior.** Without it, shrinking a canvas shrinks marks too (`s` is free): `μ_t` pulls `s`
//!   towards 1 (towards `δ_k`, the enhancement of §5.4, when set), only on triangles with
//!   `λ_t ≥ 0.4`. Applied to light layers (map regions) too, it crushes the gaps between them.
//!
//! The x and y unknowns only meet through `s_t`; the unknowns are laid out by [`Layout`].

use super::boundary::{Coord, Layout, FIXED};
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
}

impl Default for EnergyParams {
    fn default() -> Self {
        EnergyParams {
            weight_power: 4.0,
            weight_floor: 0.001,
            prior_threshold: 0.4,
            prior_strength: 1.0,
            smoothing: 0.5,
            temporal: 0.05,
            text_strength: 0.2,
        }
    }
}

/// Per-triangle inputs of one numeric assembly.
pub(crate) struct TriangleTerms<'a> {
    /// `λ_t`, mean saliency.
    pub lambda: &'a [f64],
    /// Extra weight factor per triangle (fold repair raises it), usually 1.
    pub boost: &'a [f64],
    /// Target scale per triangle (`δ_k` of Eq. 13), usually 1.
    pub delta: &'a [f64],
    /// Per vertex, where the temporal term pulls it and how much more than `τ` (empty: no
    /// temporal term).
    pub anchors: &'a [Option<(DVec2, f64)>],
    /// Per text block, the scale it is pulled to (missing: 1).
    pub text_targets: &'a [f64],
    /// Per-triangle enhancement factors (empty: none); a factor other than 1 brings the size
    /// prior to its triangle whatever its saliency.
    pub enhance: &'a [f64],
}

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
pub(crate) fn assemble(
    mesh: &Mesh,
    layout: &Layout,
    geom: &[TriangleGeometry],
    terms: &TriangleTerms<'_>,
    params: &EnergyParams,
    rhs: &mut [f64],
    mut entry: impl FnMut(usize, usize, f64),
) {
    rhs.fill(0.0);
    let tris = mesh.triangles();
    let w: Vec<f64> = terms
        .lambda
        .iter()
        .zip(terms.boost)
        .map(|(&l, &b)| weight(params, l) * b)
        .collect();
    // Adds K[a][b] for local coordinates za, zb.
    let pair = |za: &Coord,
                zb: &Coord,
                k: f64,
                rhs: &mut [f64],
                entry: &mut dyn FnMut(usize, usize, f64)| {
        for (va, ca) in za.terms() {
            for (vb, cb) in zb.terms() {
                if va <= vb {
                    entry(va, vb, k * ca * cb);
                }
            }
            if zb.c != 0.0 {
                rhs[va] -= k * ca * zb.c;
            }
        }
    };
    for (t, tri) in tris.iter().enumerate() {
        if layout.s_var[t] == FIXED {
            continue; // all corners fixed: a constant
        }
        let g = &geom[t];
        let c = g.area * w[t];
        let s = Coord::var(layout.s_var[t]);
        let delta = terms.delta[t];
        // Residuals J00 − δs, J01, J10, J11 − δs:
        //   K[xj][xk] = K[yj][yk] = c gj·gk, K[xj][s] = −c δ gj.x, K[yj][s] = −c δ gj.y,
        //   K[s][s] = 2 c δ² (+ the size prior).
        let xs = tri.map(|v| layout.x[v as usize]);
        let ys = tri.map(|v| layout.y[v as usize]);
        for (coords, comp) in [(&xs, 0usize), (&ys, 1usize)] {
            for j in 0..3 {
                for k in 0..3 {
                    pair(
                        &coords[j],
                        &coords[k],
                        c * g.grad[j].dot(g.grad[k]),
                        rhs,
                        &mut entry,
                    );
                }
                let gj = g.grad[j];
                let kjs = -c * delta * if comp == 0 { gj.x } else { gj.y };
                pair(&coords[j], &s, kjs, rhs, &mut entry);
                pair(&s, &coords[j], kjs, rhs, &mut entry);
            }
        }
        let mut ss = 2.0 * c * delta * delta;
        let lambda = terms.lambda[t];
        let enhanced = terms.enhance.get(t).is_some_and(|&e| e != 1.0);
        if lambda >= params.prior_threshold || enhanced {
            let mu = params.prior_strength * g.area * if enhanced { w[t].max(0.5) } else { w[t] };
            ss += mu;
            rhs[layout.s_var[t] as usize] += mu;
        }
        pair(&s, &s, ss, rhs, &mut entry);
    }
    // Eq. 12, weight outside the square.
    for (t, nb) in mesh.neighbours().iter().enumerate() {
        for &n in nb {
            if n == NONE || (n as usize) < t {
                continue;
            }
            let n = n as usize;
            if layout.s_var[t] == FIXED || layout.s_var[n] == FIXED {
                continue;
            }
            let b = params.smoothing * 0.5 * (geom[t].area + geom[n].area) * (w[t] * w[n]).sqrt();
            let (st, sn) = (layout.s_var[t] as usize, layout.s_var[n] as usize);
            entry(st, st, b);
            entry(sn, sn, b);
            entry(st.min(sn), st.max(sn), -b);
        }
    }
    // Text blocks: their scale pulled to δ (as large as the space allows, at most 1).
    if let Some(st) = mesh.structure() {
        for (k, block) in layout.blocks.iter().enumerate() {
            if block[2] == FIXED {
                continue;
            }
            let b = &st.text[k];
            let area = ((b.x1 - b.x0) * (b.y1 - b.y0)) as f64;
            let mu = params.text_strength * area;
            let sv = block[2] as usize;
            entry(sv, sv, mu);
            rhs[sv] += mu * terms.text_targets.get(k).copied().unwrap_or(1.0);
        }
    }
    // Temporal term: τ·|z − anchor|² on anchored coordinates.
    let tau = params.temporal;
    for (v, a) in terms.anchors.iter().enumerate() {
        let Some((a, k)) = *a else { continue };
        for (z, target) in [(layout.x[v], a.x), (layout.y[v], a.y)] {
            if z.is_fixed() {
                continue;
            }
            let shifted = Coord {
                c: z.c - target,
                ..z
            };
            pair(&shifted, &shifted, tau * k, rhs, &mut entry);
        }
    }
}

/// Energy of given positions and scales (for tests and diagnostics).
#[cfg(test)]
pub(crate) fn energy_of(
    mesh: &Mesh,
    geom: &[TriangleGeometry],
    terms: &TriangleTerms<'_>,
    params: &EnergyParams,
    pos: &[DVec2],
    scales: &[f64],
) -> f64 {
    let mut e = 0.0;
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let g = &geom[t];
        let w = weight(params, terms.lambda[t]) * terms.boost[t];
        let mut j = [[0.0; 2]; 2];
        for k in 0..3 {
            let p = pos[tri[k] as usize];
            j[0][0] += p.x * g.grad[k].x;
            j[0][1] += p.x * g.grad[k].y;
            j[1][0] += p.y * g.grad[k].x;
            j[1][1] += p.y * g.grad[k].y;
        }
        let ds = terms.delta[t] * scales[t];
        e += g.area
            * w
            * ((j[0][0] - ds).powi(2) + j[0][1].powi(2) + j[1][0].powi(2) + (j[1][1] - ds).powi(2));
        if terms.lambda[t] >= params.prior_threshold {
            e += params.prior_strength * g.area * w * (scales[t] - 1.0).powi(2);
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
            let b = params.smoothing * 0.5 * (geom[t].area + geom[n].area) * (wt * wn).sqrt();
            e += b * (scales[t] - scales[n]).powi(2);
        }
    }
    e
}
