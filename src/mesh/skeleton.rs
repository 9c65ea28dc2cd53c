//! Vertices and constraint edges for the structure: every detected line becomes a chain of
//! key points joined by constrained Delaunay edges, every text block a ring of key points
//! around its box. The triangulation then has edges exactly along lines and block borders, and
//! the solver can keep them straight and rigid ([`super::Role`]).

use super::Role;
use crate::image::Size;
use crate::raster::snap;
use crate::structure::{DataArea, Line, Structure, TextBlock};
use glam::DVec2;
use std::collections::HashMap;

/// Lines closer than this to the canvas border are the border's business.
const BORDER_PX: f64 = 1.5;
/// Other key points closer than this to a line or a block are dropped.
const CLEARANCE_PX: f64 = 1.5;
/// A line end within this of a crossing line joins it there.
const JOIN_PX: f64 = 1.5;

/// Key points with roles, and the constraint edges between them (indices into `points`).
#[derive(Default, Debug)]
pub(crate) struct Skeleton {
    pub points: Vec<(DVec2, Role)>,
    pub edges: Vec<[usize; 2]>,
    /// The structure as used (lines near the border and blocks too small left out, blocks
    /// inset from the border); roles index into it.
    pub structure: Structure,
}

/// The structure as the mesh uses it: text blocks with a pixel of margin (their glyphs'
/// antialiased rims), kept two pixels from the border, those too small left out; lines near
/// the border left to the border.
pub(crate) fn as_used(s: &Structure, size: Size) -> Structure {
    let (w, h) = (size.width as f64, size.height as f64);
    let text: Vec<TextBlock> = s
        .text
        .iter()
        .filter_map(|b| {
            let x0 = (b.x0 as f64 - 1.0).max(2.0);
            let y0 = (b.y0 as f64 - 1.0).max(2.0);
            let x1 = (b.x1 as f64 + 1.0).min(w - 2.0);
            let y1 = (b.y1 as f64 + 1.0).min(h - 2.0);
            (x1 - x0 >= 4.0 && y1 - y0 >= 4.0).then_some(TextBlock {
                x0: x0 as u32,
                y0: y0 as u32,
                x1: x1 as u32,
                y1: y1 as u32,
                line_height: b.line_height,
                sideways: b.sideways,
            })
        })
        .collect();
    let keep_line = |l: &&Line, extent: f64| l.pos > BORDER_PX && l.pos < extent - BORDER_PX;
    Structure {
        horizontal: s
            .horizontal
            .iter()
            .filter(|l| keep_line(l, h))
            .copied()
            .collect(),
        vertical: s
            .vertical
            .iter()
            .filter(|l| keep_line(l, w))
            .copied()
            .collect(),
        text,
        areas: s.areas.clone(),
        bands: s.bands.clone(),
    }
}

/// The skeleton of `s` on a `size` canvas, with key points every `step` px along lines.
pub(crate) fn skeleton(s: &Structure, size: Size, step: f64) -> Skeleton {
    let step = step.max(8.0);
    let used = as_used(s, size);
    let mut b = Builder {
        sk: Skeleton::default(),
        index: HashMap::new(),
        size: (size.width as f64, size.height as f64),
        blocks: &used.text,
        step,
    };
    b.block_rings();
    let (horizontal, vertical) = (&used.horizontal, &used.vertical);
    b.line_chains(true, horizontal, vertical);
    b.line_chains(false, vertical, horizontal);
    b.area_rings(&s.areas);
    let mut sk = b.sk;
    sk.structure = used;
    sk
}

/// A skeleton being built. Points are kept once by position (after snapping), so that a
/// point shared by a block's ring, a line and an area's side is one vertex with every role.
struct Builder<'a> {
    sk: Skeleton,
    index: HashMap<(u64, u64), usize>,
    /// The canvas's width and height, which points are clamped into.
    size: (f64, f64),
    /// The text blocks as used.
    blocks: &'a [TextBlock],
    /// Key point spacing along lines and sides.
    step: f64,
}

impl Builder<'_> {
    /// The index of the point at `p` (clamped and snapped), added if new, with `role`'s
    /// lines and block added to the roles it has.
    fn add(&mut self, p: DVec2, role: Role) -> usize {
        let (w, h) = self.size;
        let p = DVec2::new(snap(p.x.clamp(0.0, w)), snap(p.y.clamp(0.0, h)));
        let key = (p.x.to_bits(), p.y.to_bits());
        let points = &mut self.sk.points;
        let i = *self.index.entry(key).or_insert_with(|| {
            points.push((p, Role::default()));
            points.len() - 1
        });
        let r = &mut self.sk.points[i].1;
        r.hline = r.hline.or(role.hline);
        r.vline = r.vline.or(role.vline);
        r.block = r.block.or(role.block);
        i
    }

    /// Whether `p` is inside a text block grown by `margin`.
    fn inside_block(&self, p: DVec2, margin: f64) -> bool {
        self.blocks.iter().any(|b| {
            p.x > b.x0 as f64 - margin
                && p.x < b.x1 as f64 + margin
                && p.y > b.y0 as f64 - margin
                && p.y < b.y1 as f64 + margin
        })
    }

    /// Text blocks: a ring of points around each box, joined, so that the triangulation has
    /// edges along its border and the solver can keep the box rigid.
    fn block_rings(&mut self) {
        for (k, b) in self.blocks.iter().enumerate() {
            let role = Role {
                block: Some(k as u32),
                ..Role::default()
            };
            let sp = (b.line_height as f64).max(self.step);
            let (x0, y0, x1, y1) = (b.x0 as f64, b.y0 as f64, b.x1 as f64, b.y1 as f64);
            let corners = [
                DVec2::new(x0, y0),
                DVec2::new(x1, y0),
                DVec2::new(x1, y1),
                DVec2::new(x0, y1),
            ];
            let mut ring = Vec::new();
            for c in 0..4 {
                let (a, z) = (corners[c], corners[(c + 1) % 4]);
                let n = ((a.distance(z) / sp).round() as usize).max(1);
                for i in 0..n {
                    ring.push(self.add(a + (z - a) * (i as f64 / n as f64), role));
                }
            }
            for i in 0..ring.len() {
                self.sk.edges.push([ring[i], ring[(i + 1) % ring.len()]]);
            }
        }
    }

    /// Lines of one direction (`horizontal` or not): points along each, also where a line
    /// of the other direction crosses it, joined where the segment between two points
    /// stays clear of text blocks (a block is meshed by its ring, not crossed).
    fn line_chains(&mut self, horizontal: bool, lines: &[Line], others: &[Line]) {
        for (k, l) in lines.iter().enumerate() {
            let at = |t: f64| {
                if horizontal {
                    DVec2::new(t, l.pos)
                } else {
                    DVec2::new(l.pos, t)
                }
            };
            let mut prev: Option<(usize, f64)> = None;
            for t in stations(l, others, self.step) {
                let p = at(t);
                if self.inside_block(p, 2.0) {
                    prev = None;
                    continue;
                }
                let i = self.add(p, line_role(horizontal, k, l, t, others));
                if let Some((pi, pt)) = prev {
                    let mid = at((pt + t) / 2.0);
                    if !self.inside_block(mid, 2.0) && pi != i {
                        self.sk.edges.push([pi, i]);
                    }
                }
                prev = Some((i, t));
            }
        }
    }

    /// Data areas: points along their sides, joined, so that no triangle straddles a side
    /// (inside, the warp is one affine map; outside, it is free). A side along a line reuses
    /// the line's points.
    fn area_rings(&mut self, areas: &[DataArea]) {
        for a in areas {
            let corners = [
                DVec2::new(a.x0, a.y0),
                DVec2::new(a.x1, a.y0),
                DVec2::new(a.x1, a.y1),
                DVec2::new(a.x0, a.y1),
            ];
            let mut ring: Vec<usize> = Vec::new();
            for c in 0..4 {
                let (p, q) = (corners[c], corners[(c + 1) % 4]);
                let n = ((p.distance(q) / self.step).round() as usize).max(1);
                for i in 0..n {
                    let at = p + (q - p) * (i as f64 / n as f64);
                    let near = self
                        .sk
                        .points
                        .iter()
                        .position(|(o, _)| o.distance(at) < 2.0);
                    let i = match near {
                        Some(i) => i,
                        None if self.inside_block(at, 1.0) => continue,
                        None => self.add(at, Role::default()),
                    };
                    if ring.last() != Some(&i) {
                        ring.push(i);
                    }
                }
            }
            for i in 0..ring.len() {
                let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                if a != b {
                    self.sk.edges.push([a, b]);
                }
            }
        }
    }
}

/// Where line `l` gets points: every `step` px or so from end to end, and where a line of
/// `others` crosses it or ends within [`JOIN_PX`] of it (so that the two share a vertex).
/// Increasing, those closer than 2 px merged.
fn stations(l: &Line, others: &[Line], step: f64) -> Vec<f64> {
    let mut along: Vec<f64> = Vec::new();
    let n = (((l.to - l.from) / step).round() as usize).max(1);
    for i in 0..=n {
        along.push(l.from + (l.to - l.from) * i as f64 / n as f64);
    }
    for o in others.iter() {
        if o.pos > l.from - JOIN_PX
            && o.pos < l.to + JOIN_PX
            && l.pos > o.from - JOIN_PX
            && l.pos < o.to + JOIN_PX
        {
            along.push(o.pos.clamp(l.from, l.to));
        }
    }
    along.sort_by(|a, b| a.total_cmp(b));
    along.dedup_by(|a, b| (*a - *b).abs() < 2.0);
    along
}

/// The role of the point at `t` along line `k` (`l`, `horizontal` or not): on that line, and
/// on a line of `others` too where it is their crossing.
fn line_role(horizontal: bool, k: usize, l: &Line, t: f64, others: &[Line]) -> Role {
    let mut role = Role::default();
    if horizontal {
        role.hline = Some(k as u32);
    } else {
        role.vline = Some(k as u32);
    }
    for (j, o) in others.iter().enumerate() {
        if (o.pos - t).abs() < 1e-9 && l.pos > o.from - JOIN_PX && l.pos < o.to + JOIN_PX {
            if horizontal {
                role.vline = Some(j as u32);
            } else {
                role.hline = Some(j as u32);
            }
        }
    }
    role
}

/// Whether an ordinary key point at `p` would crowd the skeleton (too close to a line or
/// inside a text block).
pub(crate) fn crowds(s: &Structure, p: DVec2) -> bool {
    let near_line = |l: &Line, across: f64, along: f64| {
        (across - l.pos).abs() < CLEARANCE_PX
            && along > l.from - CLEARANCE_PX
            && along < l.to + CLEARANCE_PX
    };
    s.horizontal.iter().any(|l| near_line(l, p.y, p.x))
        || s.vertical.iter().any(|l| near_line(l, p.x, p.y))
        || s.text.iter().any(|b| {
            p.x > b.x0 as f64 - CLEARANCE_PX
                && p.x < b.x1 as f64 + CLEARANCE_PX
                && p.y > b.y0 as f64 - CLEARANCE_PX
                && p.y < b.y1 as f64 + CLEARANCE_PX
        })
}
