//! After the solve, lines and text blocks are moved by less than half a pixel so that they
//! land on the output pixel grid the way they sat on the source grid: a 1-px line then maps
//! onto exactly one output row or column (the renderer samples it at texel centres and it stays
//! one pixel sharp, instead of a two-pixel smear at half contrast), and a text block kept at
//! its size becomes a whole-pixel shift of its glyphs (copied crisp).
//!
//! A move that would fold a triangle is not made.

use super::boundary::{Layout, FIXED};
use super::repair;
use crate::mesh::Mesh;
use crate::raster::snap;
use crate::structure::Structure;
use glam::DVec2;

/// Text blocks whose scale is within this of 1 are set to exactly 1.
const UNIT_SCALE_TOLERANCE: f64 = 0.03;

/// One adjustable element: the unknowns it moves, and their snapped values.
struct Element {
    vars: Vec<(usize, f64)>,
}

/// Positions from unknowns.
fn positions(mesh: &Mesh, layout: &Layout, u: &[f64]) -> Vec<DVec2> {
    (0..mesh.vertices().len())
        .map(|i| DVec2::new(snap(layout.x[i].eval(u)), snap(layout.y[i].eval(u))))
        .collect()
}

/// Snaps the structure of `mesh` in the solution `u`; returns the positions and how many
/// elements moved.
pub(crate) fn snap_structure(
    mesh: &Mesh,
    layout: &Layout,
    u: &[f64],
) -> Option<(Vec<DVec2>, usize)> {
    let st = mesh.structure()?;
    let mut elements: Vec<Element> = Vec::new();
    line_elements(st, layout, u, &mut elements);
    area_elements(st, layout, u, &mut elements);
    block_elements(st, layout, u, &mut elements);
    if elements.is_empty() {
        return None;
    }
    settle(mesh, layout, u, &elements)
}

/// A line keeps its offset from the grid: it moves by whole output pixels from where it sat.
/// Collinear pieces share one unknown, snapped once.
fn line_elements(st: &Structure, layout: &Layout, u: &[f64], out: &mut Vec<Element>) {
    let mut seen = std::collections::HashSet::new();
    let lines = [
        (&layout.hlines, &st.horizontal),
        (&layout.vlines, &st.vertical),
    ];
    for (vars, source) in lines {
        for (k, &v) in vars.iter().enumerate() {
            if v != FIXED && seen.insert(v) {
                let pos = source[k].pos;
                out.push(Element {
                    vars: vec![(v as usize, pos + (u[v as usize] - pos).round())],
                });
            }
        }
    }
}

/// A data area's map: both sides land on the output grid as they sat on the source grid
/// (its frame and axes stay one pixel sharp; areas of one width keep one scale).
fn area_elements(st: &Structure, layout: &Layout, u: &[f64], out: &mut Vec<Element>) {
    for (k, vars) in layout.areas.iter().enumerate() {
        let a = &st.areas[k];
        for (lo, hi, [va, vb]) in [
            (a.x0, a.x1, [vars[0], vars[1]]),
            (a.y0, a.y1, [vars[2], vars[3]]),
        ] {
            if va == FIXED || vb == FIXED || hi - lo < 1.0 {
                continue;
            }
            let (sa, sb) = (u[va as usize], u[vb as usize]);
            let on_grid = |p: f64| p + (sa * p + sb - p).round();
            let (l, h) = (on_grid(lo), on_grid(hi));
            let scale = (h - l) / (hi - lo);
            if scale > 0.0 {
                out.push(Element {
                    vars: vec![(va as usize, scale), (vb as usize, l - scale * lo)],
                });
            }
        }
    }
}

/// A text block near scale 1 is set to exactly 1 about its centre and shifted by whole
/// pixels, so that its glyphs are copied, not resampled.
fn block_elements(st: &Structure, layout: &Layout, u: &[f64], out: &mut Vec<Element>) {
    for (k, b) in layout.blocks.iter().enumerate() {
        // A block tied to a data area takes one coordinate from it: not a free whole.
        if b.contains(&FIXED) {
            continue;
        }
        let (tx, ty, s) = (u[b[0] as usize], u[b[1] as usize], u[b[2] as usize]);
        if (s - 1.0).abs() > UNIT_SCALE_TOLERANCE {
            continue;
        }
        let blk = &st.text[k];
        let c = DVec2::new(
            (blk.x0 + blk.x1) as f64 / 2.0,
            (blk.y0 + blk.y1) as f64 / 2.0,
        );
        out.push(Element {
            vars: vec![
                (b[0] as usize, (tx + (s - 1.0) * c.x).round()),
                (b[1] as usize, (ty + (s - 1.0) * c.y).round()),
                (b[2] as usize, 1.0),
            ],
        });
    }
}

/// Tries of [`settle`]. Each gives up every element next to a fold it finds, so the snapped
/// set shrinks towards the solve's own positions, which have none; where a few tries do not
/// get there, the solve's positions stand unsnapped.
const SETTLE_TRIES: usize = 4;

/// The positions with every element snapped, or, where that folds a triangle, without the
/// elements whose unknowns its corners use; and how many stayed snapped. `None` if folds
/// remain after [`SETTLE_TRIES`].
fn settle(
    mesh: &Mesh,
    layout: &Layout,
    u: &[f64],
    elements: &[Element],
) -> Option<(Vec<DVec2>, usize)> {
    let mut active = vec![true; elements.len()];
    for _ in 0..SETTLE_TRIES {
        let mut v = u.to_vec();
        for (e, &on) in elements.iter().zip(&active) {
            if on {
                for &(i, x) in &e.vars {
                    v[i] = x;
                }
            }
        }
        let pos = positions(mesh, layout, &v);
        let bad = repair::folded(mesh, &pos);
        if bad.is_empty() {
            let n = active.iter().filter(|&&a| a).count();
            return Some((pos, n));
        }
        give_up_at(mesh, layout, &bad, elements, &mut active);
    }
    None
}

/// Turns off the elements whose unknowns a folded triangle's corners use.
fn give_up_at(
    mesh: &Mesh,
    layout: &Layout,
    folded: &[usize],
    elements: &[Element],
    active: &mut [bool],
) {
    let mut touched = std::collections::HashSet::new();
    for &t in folded {
        for &vtx in &mesh.triangles()[t] {
            for z in [layout.x[vtx as usize], layout.y[vtx as usize]] {
                for (var, _) in z.terms() {
                    touched.insert(var);
                }
            }
        }
    }
    for (e, on) in elements.iter().zip(active.iter_mut()) {
        if e.vars.iter().any(|(i, _)| touched.contains(i)) {
            *on = false;
        }
    }
}
