//! Vertices and constraint edges for the structure: every detected line becomes a chain of
//! key points joined by constrained Delaunay edges, every text block a ring of key points
//! around its box. The triangulation then has edges exactly along lines and block borders, and
//! the solver can keep them straight and rigid ([`super::Role`]).

use super::Role;
use crate::image::Size;
use crate::raster::snap;
use crate::structure::{Line, Structure, TextBlock};
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
    }
}

/// The skeleton of `s` on a `size` canvas, with key points every `step` px along lines.
pub(crate) fn skeleton(s: &Structure, size: Size, step: f64) -> Skeleton {
    let (w, h) = (size.width as f64, size.height as f64);
    let step = step.max(8.0);
    let used = as_used(s, size);
    let blocks = &used.text;
    let inside_block = |p: DVec2, margin: f64| {
        blocks.iter().any(|b| {
            p.x > b.x0 as f64 - margin
                && p.x < b.x1 as f64 + margin
                && p.y > b.y0 as f64 - margin
                && p.y < b.y1 as f64 + margin
        })
    };
    let (horizontal, vertical) = (&used.horizontal, &used.vertical);

    let mut index: HashMap<(u64, u64), usize> = HashMap::new();
    let mut sk = Skeleton::default();
    let mut add = |sk: &mut Skeleton, p: DVec2, role: Role| -> usize {
        let p = DVec2::new(snap(p.x.clamp(0.0, w)), snap(p.y.clamp(0.0, h)));
        let key = (p.x.to_bits(), p.y.to_bits());
        let i = *index.entry(key).or_insert_with(|| {
            sk.points.push((p, Role::default()));
            sk.points.len() - 1
        });
        let r = &mut sk.points[i].1;
        r.hline = r.hline.or(role.hline);
        r.vline = r.vline.or(role.vline);
        r.block = r.block.or(role.block);
        i
    };

    // Text blocks: a ring of points, joined.
    for (k, b) in blocks.iter().enumerate() {
        let role = Role {
            block: Some(k as u32),
            ..Role::default()
        };
        let sp = (b.line_height as f64).max(step);
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
                ring.push(add(&mut sk, a + (z - a) * (i as f64 / n as f64), role));
            }
        }
        for i in 0..ring.len() {
            sk.edges.push([ring[i], ring[(i + 1) % ring.len()]]);
        }
    }

    // Lines: points along each, at crossings with the other direction, joined where the
    // segment between two points stays clear of text blocks.
    for (horizontal_pass, lines, others) in [
        (true, &horizontal, &vertical),
        (false, &vertical, &horizontal),
    ] {
        for (k, l) in lines.iter().enumerate() {
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
            let at = |t: f64| {
                if horizontal_pass {
                    DVec2::new(t, l.pos)
                } else {
                    DVec2::new(l.pos, t)
                }
            };
            let mut prev: Option<(usize, f64)> = None;
            for &t in &along {
                let p = at(t);
                if inside_block(p, 2.0) {
                    prev = None;
                    continue;
                }
                let mut role = Role::default();
                if horizontal_pass {
                    role.hline = Some(k as u32);
                } else {
                    role.vline = Some(k as u32);
                }
                // A crossing point is on the other line too.
                for (j, o) in others.iter().enumerate() {
                    if (o.pos - t).abs() < 1e-9
                        && l.pos > o.from - JOIN_PX
                        && l.pos < o.to + JOIN_PX
                    {
                        if horizontal_pass {
                            role.vline = Some(j as u32);
                        } else {
                            role.hline = Some(j as u32);
                        }
                    }
                }
                let i = add(&mut sk, p, role);
                if let Some((pi, pt)) = prev {
                    let mid = at((pt + t) / 2.0);
                    if !inside_block(mid, 2.0) && pi != i {
                        sk.edges.push([pi, i]);
                    }
                }
                prev = Some((i, t));
            }
        }
    }
    // Data areas: points along their sides, joined, so that no triangle straddles a side
    // (inside, the warp is one affine map; outside, it is free). A side along a line reuses
    // the line's points.
    for a in &s.areas {
        let corners = [
            DVec2::new(a.x0, a.y0),
            DVec2::new(a.x1, a.y0),
            DVec2::new(a.x1, a.y1),
            DVec2::new(a.x0, a.y1),
        ];
        let mut ring: Vec<usize> = Vec::new();
        for c in 0..4 {
            let (p, q) = (corners[c], corners[(c + 1) % 4]);
            let n = ((p.distance(q) / step).round() as usize).max(1);
            for i in 0..n {
                let at = p + (q - p) * (i as f64 / n as f64);
                let near = sk.points.iter().position(|(o, _)| o.distance(at) < 2.0);
                let i = match near {
                    Some(i) => i,
                    None if inside_block(at, 1.0) => continue,
                    None => add(&mut sk, at, Role::default()),
                };
                if ring.last() != Some(&i) {
                    ring.push(i);
                }
            }
        }
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            if a != b {
                sk.edges.push([a, b]);
            }
        }
    }
    sk.structure = used;
    sk
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
