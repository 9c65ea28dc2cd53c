//! Axis-aligned deformation (Panozzo, Weber and Sorkine, "Robust image retargeting via
//! axis-aligned deformation", 2012), which issue 5 asks to weigh against the mesh for layouts
//! made of panels.
//!
//! The image is cut into the columns and rows of a uniform grid; the unknowns are one scale per
//! column (`a_j`) and one per row (`b_i`), so the warp is `x' = X(x)`, `y' = Y(y)` with `X`, `Y`
//! piecewise linear and increasing. Every horizontal line stays horizontal, straight and
//! unbroken, every vertical one vertical, and nothing can fold; what it cannot do is keep a
//! round mark round where its column and row must scale differently.
//!
//! Energy, over the cells `(i, j)` of area `A_ij` and weight `w_ij` (mean VSM squared, text
//! blocks fully weighted, a floor for the empty ground):
//!
//! ```text
//! E = Σ A_ij·w_ij·(a_j − b_i)²                 cells keep their aspect (the paper's ASAP form)
//!   + μ·Σ A_ij·w_ij·((a_j − 1)² + (b_i − 1)²)  and their size, as the space allows
//!   + η·Σ A·((a_j − a_j+1)² + (b_i − b_i+1)²)  neighbouring columns (rows) alike
//! ```
//!
//! subject to `Σ a_j·w_j = W'`, `Σ b_i·h_i = H'` and a lower bound on every scale: a small
//! dense quadratic programme (a few hundred unknowns), solved by equality-constrained least
//! squares with an active set for the bounds.

use super::{ms_since, MethodOutput};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::mesh::Mesh;
use crate::retarget::{Options, StageTimes};
use crate::saliency::{Vsm, VsmBuilder};
use crate::solve::Warp;
use crate::structure::Structure;
use std::time::Instant;

/// Weight of a cell without content (keeps the system definite, lets the ground give way).
const WEIGHT_FLOOR: f64 = 0.005;
/// `μ`, the size prior, relative to the shape term.
const SIZE_PRIOR: f64 = 0.5;
/// `η`, the smoothness between neighbouring columns or rows, relative to the mean weight.
const SMOOTHNESS: f64 = 0.02;
/// Smallest scale of a column or row, as a share of the uniform scale along its axis.
const MIN_SHARE: f64 = 0.2;

pub(super) fn run(image: &Image, target: Size, options: &Options) -> Result<MethodOutput, Error> {
    let mut times = StageTimes::default();
    let t = Instant::now();
    let vsm = VsmBuilder::new().build(image.as_ref());
    times.vsm_ms = ms_since(t);
    let t = Instant::now();
    let structure = Structure::detect(image.as_ref());
    let mesh = Mesh::lattice(image.size(), options.alpha as f64);
    times.mesh_ms = ms_since(t);
    let t = Instant::now();
    let warp = solve(&mesh, &vsm, &structure, target);
    times.solve_ms = ms_since(t);
    Ok(super::lattice_output(
        super::Method::Axis,
        image,
        mesh,
        warp,
        vsm,
        times,
        0,
    ))
}

/// The separable warp of `mesh` (a lattice) to `target`.
pub(crate) fn solve(mesh: &Mesh, vsm: &Vsm, structure: &Structure, target: Size) -> Warp {
    let size = mesh.size();
    let xs = cuts(mesh.vertices().iter().map(|p| p.x));
    let ys = cuts(mesh.vertices().iter().map(|p| p.y));
    let w = cell_weights(vsm, structure, &xs, &ys);
    let widths: Vec<f64> = xs.windows(2).map(|c| c[1] - c[0]).collect();
    let heights: Vec<f64> = ys.windows(2).map(|c| c[1] - c[0]).collect();
    let sx = target.width as f64 / size.width as f64;
    let sy = target.height as f64 / size.height as f64;
    let (a, b) = scales(&w, &widths, &heights, sx, sy);
    let fx = mapping(&xs, &widths, &a, target.width as f64);
    let fy = mapping(&ys, &heights, &b, target.height as f64);
    Warp::separable(mesh, target, fx, fy)
}

/// The distinct coordinates of the lattice's vertices along one axis, increasing.
fn cuts(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    v
}

/// `w[i][j]` for row `i`, column `j`: mean VSM squared, at least the floor, 1 where a text
/// block lies (text must stay legible).
fn cell_weights(vsm: &Vsm, structure: &Structure, xs: &[f64], ys: &[f64]) -> Vec<Vec<f64>> {
    let size = vsm.size();
    let px = |v: f64, n: u32| (v.round().max(0.0) as u32).min(n);
    let mut out = vec![vec![0.0; xs.len() - 1]; ys.len() - 1];
    for (i, row) in out.iter_mut().enumerate() {
        let (y0, y1) = (px(ys[i], size.height), px(ys[i + 1], size.height));
        for (j, cell) in row.iter_mut().enumerate() {
            let (x0, x1) = (px(xs[j], size.width), px(xs[j + 1], size.width));
            let mut sum = 0.0f64;
            for y in y0..y1 {
                for x in x0..x1 {
                    sum += vsm.get(x, y) as f64;
                }
            }
            let n = ((x1 - x0) * (y1 - y0)).max(1) as f64;
            let mean = sum / n;
            let text = structure.text.iter().any(|b| {
                (b.x0 as f64) < xs[j + 1]
                    && (b.x1 as f64) > xs[j]
                    && (b.y0 as f64) < ys[i + 1]
                    && (b.y1 as f64) > ys[i]
            });
            *cell = if text {
                1.0
            } else {
                (mean * mean).max(WEIGHT_FLOOR)
            };
        }
    }
    out
}

/// Column scales `a` and row scales `b` minimizing the energy under the size constraints and
/// the lower bounds (`sx`, `sy`: the uniform scales).
fn scales(
    w: &[Vec<f64>],
    widths: &[f64],
    heights: &[f64],
    sx: f64,
    sy: f64,
) -> (Vec<f64>, Vec<f64>) {
    let axes = Axes {
        widths,
        heights,
        sx,
        sy,
    };
    let (m, n) = (widths.len(), heights.len());
    let energy = axes.energy(w);
    let mut z = axes.bounded_minimum(&energy);
    if z.iter().any(|v| !v.is_finite() || *v <= 0.0) {
        // Never expected (the system is definite); uniform scaling is always valid.
        return (vec![sx; m], vec![sy; n]);
    }
    let b = z.split_off(m);
    (z, b)
}

/// The problem's shape: the columns' widths and the rows' heights, and the uniform scales
/// `sx`, `sy` that the total width and height must come to. Unknowns are numbered columns
/// first: `z = [a; b]`.
struct Axes<'a> {
    widths: &'a [f64],
    heights: &'a [f64],
    sx: f64,
    sy: f64,
}

/// The energy as the quadratic form `zᵀQz − 2cᵀz`, `q` row-major over the unknowns.
struct Energy {
    q: Vec<f64>,
    c: Vec<f64>,
}

impl Axes<'_> {
    fn vars(&self) -> usize {
        self.widths.len() + self.heights.len()
    }

    /// The shape and size terms of every cell, then the smoothness between neighbours, whose
    /// weight `η` is relative to the cells' mean weight so that it means the same on busy and
    /// empty images.
    fn energy(&self, w: &[Vec<f64>]) -> Energy {
        let (widths, heights) = (self.widths, self.heights);
        let (m, n) = (widths.len(), heights.len());
        let vars = self.vars();
        let mut q = vec![0.0; vars * vars];
        let mut c = vec![0.0; vars];
        let mut total = 0.0;
        let mut weight_sum = 0.0;
        for (i, row) in w.iter().enumerate() {
            for (j, &wij) in row.iter().enumerate() {
                let k = widths[j] * heights[i] * wij;
                let (aj, bi) = (j, m + i);
                q[aj * vars + aj] += k * (1.0 + SIZE_PRIOR);
                q[bi * vars + bi] += k * (1.0 + SIZE_PRIOR);
                q[aj * vars + bi] -= k;
                q[bi * vars + aj] -= k;
                c[aj] += k * SIZE_PRIOR;
                c[bi] += k * SIZE_PRIOR;
                total += widths[j] * heights[i];
                weight_sum += k;
            }
        }
        let eta = SMOOTHNESS * weight_sum / total.max(1.0);
        let mut smooth = |u: usize, v: usize, k: f64| {
            q[u * vars + u] += k;
            q[v * vars + v] += k;
            q[u * vars + v] -= k;
            q[v * vars + u] -= k;
        };
        let height: f64 = heights.iter().sum();
        let width: f64 = widths.iter().sum();
        for j in 1..m {
            smooth(j - 1, j, eta * height * 0.5 * (widths[j - 1] + widths[j]));
        }
        for i in 1..n {
            smooth(
                m + i - 1,
                m + i,
                eta * width * 0.5 * (heights[i - 1] + heights[i]),
            );
        }
        Energy { q, c }
    }

    /// The minimum of `e` under the size constraints and the lower bounds, by an active set:
    /// solve with the bounds free, fix every unknown below its bound at the bound, solve
    /// again, until none is below (at most once per unknown). A singular system keeps the
    /// last solution (zeros if there is none: the caller falls back to uniform scaling).
    fn bounded_minimum(&self, e: &Energy) -> Vec<f64> {
        let vars = self.vars();
        let m = self.widths.len();
        let lower: Vec<f64> = (0..vars)
            .map(|v| MIN_SHARE * if v < m { self.sx } else { self.sy })
            .collect();
        let mut fixed: Vec<Option<f64>> = vec![None; vars];
        let mut z = vec![0.0; vars];
        for _ in 0..vars {
            let (mut k, mut rhs) = self.kkt(e, &fixed);
            match solve_dense(&mut k, &mut rhs, vars + 2) {
                Some(()) => z.copy_from_slice(&rhs[..vars]),
                None => break,
            }
            let mut clamped = false;
            for v in 0..vars {
                if fixed[v].is_none() && z[v] < lower[v] {
                    fixed[v] = Some(lower[v]);
                    clamped = true;
                }
            }
            if !clamped {
                break;
            }
        }
        z
    }

    /// The KKT system `[Q Aᵀ; A 0]` of `e` under the two size constraints (the last two rows),
    /// with the `fixed` unknowns as identity rows; row-major, and its right-hand side.
    fn kkt(&self, e: &Energy, fixed: &[Option<f64>]) -> (Vec<f64>, Vec<f64>) {
        let (widths, heights) = (self.widths, self.heights);
        let (m, n) = (widths.len(), heights.len());
        let vars = self.vars();
        let dim = vars + 2;
        let mut k = vec![0.0; dim * dim];
        let mut rhs = vec![0.0; dim];
        for r in 0..vars {
            if let Some(v) = fixed[r] {
                k[r * dim + r] = 1.0;
                rhs[r] = v;
                continue;
            }
            k[r * dim..r * dim + vars].copy_from_slice(&e.q[r * vars..(r + 1) * vars]);
            let (len, row) = if r < m {
                (widths[r], vars)
            } else {
                (heights[r - m], vars + 1)
            };
            k[r * dim + row] = len;
            rhs[r] = e.c[r];
        }
        for j in 0..m {
            k[vars * dim + j] = widths[j];
        }
        for i in 0..n {
            k[(vars + 1) * dim + m + i] = heights[i];
        }
        let height: f64 = heights.iter().sum();
        let width: f64 = widths.iter().sum();
        rhs[vars] = self.sx * width;
        rhs[vars + 1] = self.sy * height;
        (k, rhs)
    }
}

/// Gaussian elimination with partial pivoting of the `dim × dim` system in place; the
/// solution replaces `rhs`. `None` if singular.
fn solve_dense(k: &mut [f64], rhs: &mut [f64], dim: usize) -> Option<()> {
    for col in 0..dim {
        let pivot = (col..dim)
            .max_by(|&a, &b| k[a * dim + col].abs().total_cmp(&k[b * dim + col].abs()))?;
        if k[pivot * dim + col].abs() < 1e-12 {
            return None;
        }
        if pivot != col {
            for x in 0..dim {
                k.swap(pivot * dim + x, col * dim + x);
            }
            rhs.swap(pivot, col);
        }
        let p = k[col * dim + col];
        for r in col + 1..dim {
            let f = k[r * dim + col] / p;
            if f == 0.0 {
                continue;
            }
            for x in col..dim {
                k[r * dim + x] -= f * k[col * dim + x];
            }
            rhs[r] -= f * rhs[col];
        }
    }
    for col in (0..dim).rev() {
        let mut v = rhs[col];
        for x in col + 1..dim {
            v -= k[col * dim + x] * rhs[x];
        }
        rhs[col] = v / k[col * dim + col];
    }
    Some(())
}

/// The increasing piecewise-linear map of one axis: cut `cuts[j]` goes to the sum of the scaled
/// lengths before it, stretched to end exactly at `end`.
fn mapping<'a>(
    cuts: &'a [f64],
    lengths: &[f64],
    scales: &[f64],
    end: f64,
) -> impl Fn(f64) -> f64 + 'a {
    let mut out = Vec::with_capacity(cuts.len());
    let mut acc = 0.0;
    out.push(0.0);
    for (l, s) in lengths.iter().zip(scales) {
        acc += l * s;
        out.push(acc);
    }
    let k = if acc > 0.0 { end / acc } else { 1.0 };
    let out: Vec<f64> = out.into_iter().map(|v| v * k).collect();
    move |x: f64| {
        let j = match cuts.binary_search_by(|c| c.total_cmp(&x)) {
            Ok(j) => return out[j],
            Err(j) => j.clamp(1, cuts.len() - 1) - 1,
        };
        let t = (x - cuts[j]) / (cuts[j + 1] - cuts[j]);
        out[j] + t * (out[j + 1] - out[j])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::baseline::Mapping;

    /// A frame of 1-px lines and a text-like block on white: every horizontal and vertical line
    /// of the output is still one straight unbroken row or column, the output exactly the
    /// target, and the busy columns keep more of their width than the empty ones.
    #[test]
    fn lines_stay_straight_and_content_keeps_its_width() {
        let size = Size::new(400, 200).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        for x in 0..400 {
            img.set(x, 40, [0, 0, 0, 255]);
            img.set(x, 160, [0, 0, 0, 255]);
        }
        for y in 0..200 {
            img.set(30, y, [0, 0, 0, 255]);
            img.set(370, y, [0, 0, 0, 255]);
        }
        // Busy stripes between x = 60 and 140 (say, a column of labels).
        for y in (60..140).step_by(6) {
            for x in 60..140 {
                if (x / 3) % 2 == 0 {
                    img.set(x, y, [20, 20, 20, 255]);
                    img.set(x, y + 1, [20, 20, 20, 255]);
                }
            }
        }
        let target = Size::new(200, 200).unwrap();
        let out = run(&img, target, &Options::default()).unwrap();
        assert_eq!(out.image.size(), target);
        let Mapping::Warp { mesh, warp } = &out.mapping else {
            panic!("a warp")
        };
        assert_eq!(warp.folded_triangles(mesh), 0);
        // Each source x maps to one output x whatever y (and vice versa): axis-aligned.
        for (p, q) in mesh.vertices().iter().zip(warp.positions()) {
            for (p2, q2) in mesh.vertices().iter().zip(warp.positions()) {
                if p.x == p2.x {
                    assert_eq!(q.x, q2.x);
                }
                if p.y == p2.y {
                    assert_eq!(q.y, q2.y);
                }
            }
        }
        let xs = cuts(mesh.vertices().iter().map(|p| p.x));
        let x_out = |x: f64| {
            let i = mesh.vertices().iter().position(|p| p.x == x).unwrap();
            warp.positions()[i].x
        };
        let scale = |x0: f64, x1: f64| (x_out(x1) - x_out(x0)) / (x1 - x0);
        let busy = scale(
            *xs.iter().find(|&&x| x >= 60.0).unwrap(),
            *xs.iter().rev().find(|&&x| x <= 140.0).unwrap(),
        );
        let empty = scale(
            *xs.iter().find(|&&x| x >= 160.0).unwrap(),
            *xs.iter().rev().find(|&&x| x <= 340.0).unwrap(),
        );
        assert!(
            busy > 0.5 && empty < 0.5,
            "busy {busy:.2}, empty {empty:.2}"
        );
        // The horizontal rules are whole dark rows of the output.
        let dark_rows = (0..200)
            .filter(|&y| (0..200).all(|x| out.image.get(x, y)[0] < 128))
            .count();
        assert!(dark_rows >= 2, "{dark_rows} unbroken dark rows");
    }

    #[test]
    fn dense_solver_solves() {
        let mut k = vec![2.0, 1.0, 1.0, 3.0];
        let mut rhs = vec![3.0, 5.0];
        solve_dense(&mut k, &mut rhs, 2).unwrap();
        assert!((rhs[0] - 0.8).abs() < 1e-12 && (rhs[1] - 1.4).abs() < 1e-12);
    }
}
