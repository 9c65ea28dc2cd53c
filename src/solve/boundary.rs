//! The boundary constraints of Eq. 10–11, and the structure constraints, as a layout of
//! unknowns: each vertex coordinate is an affine function of at most two unknowns.
//!
//! * Eq. 11 as printed keeps a side vertex's other coordinate unchanged (`v'_i = (0, v_iy)`),
//!   which cannot hold when the height changes too; as DESIGN.md says, side vertices slide
//!   along their side and only the coordinate across it is fixed. Corners are fixed at the
//!   target's corners.
//! * A vertex on a horizontal line shares the line's one y unknown (the line stays straight and
//!   horizontal, exactly); on a vertical line, its x unknown.
//! * A vertex of a text block is `(tx + s·x, ty + s·y)` with the block's three unknowns: the
//!   block moves as one piece with one scale, no shear, no rotation.
//!
//! * A vertex inside a data area is `(bx + ax·x, by + ay·y)` with the area's four unknowns:
//!   the area is one axis-aligned affine map, exactly, so its grid stays even, its bars
//!   proportional and its frame straight. Areas of one width share `ax` (panels of a column, or
//!   small multiples, stay comparable), and areas over the same columns share `bx` too; the
//!   same along y. Text blocks and lines that lie mostly inside an area follow its map whole.
//!
//! All of this keeps the energy quadratic: substituting affine functions of the unknowns into
//! a quadratic leaves a quadratic, so the solve stays one sparse system.

use crate::image::Size;
use crate::mesh::{Boundary, Mesh, Role};
use crate::structure::TextBlock;
use glam::DVec2;
use std::collections::HashMap;

/// Marks an absent unknown.
pub(crate) const FIXED: u32 = u32::MAX;

/// A coordinate as `c + Σ k_i·u[v_i]` (absent terms have `v = FIXED`).
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct Coord {
    pub c: f64,
    pub v: [u32; 3],
    pub k: [f64; 3],
}

impl Coord {
    pub fn fixed(c: f64) -> Coord {
        Coord {
            c,
            v: [FIXED; 3],
            k: [0.0; 3],
        }
    }
    pub fn var(v: u32) -> Coord {
        Coord {
            c: 0.0,
            v: [v, FIXED, FIXED],
            k: [1.0, 0.0, 0.0],
        }
    }
    pub fn affine(c: f64, a: (u32, f64), b: (u32, f64)) -> Coord {
        Coord {
            c,
            v: [a.0, b.0, FIXED],
            k: [a.1, b.1, 0.0],
        }
    }
    /// `c + ka·u[a] + kb·u[b] + kd·u[d]`.
    pub fn affine3(c: f64, a: (u32, f64), b: (u32, f64), d: (u32, f64)) -> Coord {
        Coord {
            c,
            v: [a.0, b.0, d.0],
            k: [a.1, b.1, d.1],
        }
    }
    /// No unknown in it.
    pub fn is_fixed(&self) -> bool {
        self.v.iter().all(|&v| v == FIXED)
    }
    /// Its one unknown, when it is exactly one unknown (a free or line coordinate).
    pub fn single(&self) -> Option<u32> {
        (self.v[0] != FIXED
            && self.v[1] == FIXED
            && self.v[2] == FIXED
            && self.k[0] == 1.0
            && self.c == 0.0)
            .then_some(self.v[0])
    }
    /// The terms `(unknown, coefficient)`.
    #[inline]
    pub fn terms(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..3)
            .filter(|&i| self.v[i] != FIXED)
            .map(|i| (self.v[i] as usize, self.k[i]))
    }
    /// Its value for the unknowns `u`.
    pub fn eval(&self, u: &[f64]) -> f64 {
        self.c + self.terms().map(|(v, k)| k * u[v]).sum::<f64>()
    }
}

/// Gaps up to this long between collinear pieces of a line are bridged.
const JOIN_GAP_PX: f64 = 12.0;

/// For each line, the index of the group of collinear pieces it belongs to: pieces on the same
/// row (column) whose gap is short, or bridged by a text block sitting on the line (a panel
/// frame interrupted by its title).
fn joined_lines(
    lines: &[crate::structure::Line],
    s: &crate::structure::Structure,
    horizontal: bool,
) -> Vec<usize> {
    let mut order: Vec<usize> = (0..lines.len()).collect();
    order.sort_by(|&a, &b| {
        lines[a]
            .pos
            .total_cmp(&lines[b].pos)
            .then(lines[a].from.total_cmp(&lines[b].from))
    });
    let mut group = vec![0usize; lines.len()];
    let mut current = usize::MAX;
    let mut last: Option<usize> = None;
    for &i in &order {
        let joined = last.is_some_and(|j| {
            let (a, b) = (&lines[j], &lines[i]);
            a.pos == b.pos
                && (b.from - a.to <= JOIN_GAP_PX
                    || s.text.iter().any(|t| {
                        let (across0, across1, along0, along1) = if horizontal {
                            (t.y0 as f64, t.y1 as f64, t.x0 as f64, t.x1 as f64)
                        } else {
                            (t.x0 as f64, t.x1 as f64, t.y0 as f64, t.y1 as f64)
                        };
                        across0 <= a.pos
                            && a.pos <= across1
                            && along0 <= a.to + JOIN_GAP_PX
                            && along1 >= b.from - JOIN_GAP_PX
                    }))
        });
        if !joined {
            current = i;
        }
        group[i] = current;
        last = Some(i);
    }
    group
}

/// For each text block, the index of the first block of its row: one-line blocks on one line
/// of text (legend entries, the tick labels of an axis, the cells of a table row) whose
/// glyph heights agree within 40 % and whose middles within 30 % of a glyph height (digits
/// and words with descenders still meet). A row moves up and down as one and keeps one
/// scale, so its entries stay aligned and alike. Blocks with a vertical line between them do
/// not join: labels of two panels that happen to share a baseline need not share a scale.
pub(crate) fn text_rows(text: &[TextBlock], vertical: &[crate::structure::Line]) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..text.len()).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for i in 0..text.len() {
        for j in i + 1..text.len() {
            let (a, b) = (&text[i], &text[j]);
            let (la, lb) = (a.line_height.max(1) as f64, b.line_height.max(1) as f64);
            let single = |t: &TextBlock, lh: f64| ((t.y1 - t.y0) as f64) <= 1.6 * lh;
            let centre = |t: &TextBlock| (t.y0 + t.y1) as f64 / 2.0;
            let (left, right) = if a.x0 <= b.x0 { (a, b) } else { (b, a) };
            let walled = || {
                let (y0, y1) = (a.y0.min(b.y0) as f64, a.y1.max(b.y1) as f64);
                vertical.iter().any(|l| {
                    l.pos > left.x1 as f64 && l.pos < right.x0 as f64 && l.from <= y0 && l.to >= y1
                })
            };
            if single(a, la)
                && single(b, lb)
                && la.max(lb) <= 1.4 * la.min(lb)
                && (centre(a) - centre(b)).abs() <= (0.3 * la.min(lb)).max(1.5)
                && !walled()
            {
                let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    (0..text.len()).map(|i| find(&mut parent, i)).collect()
}

/// A text block tied to a data area: its centre follows the area's map along one axis, its
/// size its own scale (tick labels under their ticks, axis titles at the axis' middle, a
/// panel's title over its plot).
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) struct Attached {
    pub area: usize,
    /// Along x (the block is above or below the area) or along y (beside it).
    pub along_x: bool,
    /// The block's centre along that axis, source pixels.
    pub centre: f64,
}

/// How far from an area's side a block may sit and still belong to it, in line heights:
/// a tick label sits under its tick, an axis title a line or two further out.
const ATTACH_LINES: f64 = 3.0;

/// For each text block, the data area it is tied to, if any: a one-line block outside every
/// area, within [`ATTACH_LINES`] of an area's side and facing it (its centre within the side's
/// span); the nearest such area.
pub(crate) fn attachments(s: &crate::structure::Structure) -> Vec<Option<Attached>> {
    s.text
        .iter()
        .map(|b| {
            let (x0, y0, x1, y1) = (b.x0 as f64, b.y0 as f64, b.x1 as f64, b.y1 as f64);
            let lh = b.line_height.max(1) as f64;
            if y1 - y0 > 1.6 * lh {
                return None;
            }
            let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
            let reach = ATTACH_LINES * lh + 4.0;
            let mut best: Option<(f64, Attached)> = None;
            for (k, a) in s.areas.iter().enumerate() {
                let ow = (x1.min(a.x1) - x0.max(a.x0)).max(0.0);
                let oh = (y1.min(a.y1) - y0.max(a.y0)).max(0.0);
                if ow * oh > 0.0 {
                    return None;
                }
                let faces_x = cx >= a.x0 && cx <= a.x1;
                let faces_y = cy >= a.y0 && cy <= a.y1;
                let gap_y = (y0 - a.y1).max(a.y0 - y1);
                let gap_x = (x0 - a.x1).max(a.x0 - x1);
                let candidates = [
                    (faces_x && gap_y >= -2.0 && gap_y <= reach, gap_y, true, cx),
                    (faces_y && gap_x >= -2.0 && gap_x <= reach, gap_x, false, cy),
                ];
                for (ok, gap, along_x, centre) in candidates {
                    if ok && best.is_none_or(|(g, _)| gap < g) {
                        best = Some((
                            gap,
                            Attached {
                                area: k,
                                along_x,
                                centre,
                            },
                        ));
                    }
                }
            }
            best.map(|(_, a)| a)
        })
        .collect()
}

/// The least-squares map `[ax, bx, ay, by]` taking the source points to the output points
/// (`(source, output)` pairs), if they span both axes.
pub(crate) fn fit_map(pairs: impl Iterator<Item = (DVec2, DVec2)>) -> Option<[f64; 4]> {
    let (mut n, mut sx, mut sxx, mut su, mut sxu) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut sy, mut syy, mut sv, mut syv) = (0.0, 0.0, 0.0, 0.0);
    for (p, q) in pairs {
        n += 1.0;
        (sx, sxx, su, sxu) = (sx + p.x, sxx + p.x * p.x, su + q.x, sxu + p.x * q.x);
        (sy, syy, sv, syv) = (sy + p.y, syy + p.y * p.y, sv + q.y, syv + p.y * q.y);
    }
    let fit = |s: f64, ss: f64, t: f64, st: f64| {
        let d = n * ss - s * s;
        (d > 1e-9 * n * n).then(|| {
            let a = (n * st - s * t) / d;
            (a, (t - a * s) / n)
        })
    };
    let (ax, bx) = fit(sx, sxx, su, sxu)?;
    let (ay, by) = fit(sy, syy, sv, syv)?;
    Some([ax, bx, ay, by])
}

/// Which data area each vertex, line and text block follows, and which areas share unknowns.
#[derive(Default)]
struct AreaMembers {
    /// Per area, the group of each of its four unknowns `[ax, bx, ay, by]`.
    groups: Vec<[usize; 4]>,
    /// The area each text block and each line follows whole.
    blocks: Vec<Option<usize>>,
    hlines: Vec<Option<usize>>,
    vlines: Vec<Option<usize>>,
    areas: Vec<crate::structure::DataArea>,
}

/// The areas a vertex follows along x and along y.
#[derive(Default)]
struct VertexArea {
    x: Option<usize>,
    y: Option<usize>,
}

/// Sizes (px) within which two areas' widths or positions count as one.
const SAME_AXIS_PX: f64 = 3.0;

impl AreaMembers {
    fn of(s: &crate::structure::Structure) -> AreaMembers {
        let areas = s.areas.clone();
        let n = areas.len();
        let same = |a: f64, b: f64| (a - b).abs() <= SAME_AXIS_PX.max(0.01 * a.abs().max(b.abs()));
        // Group i of area k: the first area equal to it in that respect.
        let group =
            |k: usize, eq: &dyn Fn(usize, usize) -> bool| (0..=k).find(|&j| eq(j, k)).unwrap_or(k);
        let groups = (0..n)
            .map(|k| {
                let a = &areas;
                [
                    group(k, &|i, j| same(a[i].x1 - a[i].x0, a[j].x1 - a[j].x0)),
                    group(k, &|i, j| same(a[i].x0, a[j].x0) && same(a[i].x1, a[j].x1)),
                    group(k, &|i, j| same(a[i].y1 - a[i].y0, a[j].y1 - a[j].y0)),
                    group(k, &|i, j| same(a[i].y0, a[j].y0) && same(a[i].y1, a[j].y1)),
                ]
            })
            .collect();
        // Mostly inside: at least half of a block's box (`Structure::area_of`), half of a
        // line's length.
        let blocks = s.text.iter().map(|b| s.area_of(b)).collect();
        let line_in = |l: &crate::structure::Line, horizontal: bool| {
            areas.iter().position(|a| {
                let (p0, p1, s0, s1) = if horizontal {
                    (a.y0, a.y1, a.x0, a.x1)
                } else {
                    (a.x0, a.x1, a.y0, a.y1)
                };
                let along = (l.to.min(s1) - l.from.max(s0)).max(0.0);
                l.pos >= p0 - 1.0 && l.pos <= p1 + 1.0 && along >= 0.5 * (l.to - l.from)
            })
        };
        AreaMembers {
            groups,
            blocks,
            hlines: s.horizontal.iter().map(|l| line_in(l, true)).collect(),
            vlines: s.vertical.iter().map(|l| line_in(l, false)).collect(),
            areas,
        }
    }

    /// The areas vertex `p` with `role` follows: its block's or line's if they follow one,
    /// else the area it lies in (its sides counted in); a block or line that follows none
    /// keeps its own unknowns.
    fn of_vertex(&self, p: DVec2, role: crate::mesh::Role) -> VertexArea {
        if self.areas.is_empty() {
            return VertexArea::default();
        }
        if let Some(k) = role.block {
            let a = self.blocks.get(k as usize).copied().flatten();
            return VertexArea { x: a, y: a };
        }
        let at = self.areas.iter().position(|a| a.contains(p.x, p.y, 1e-6));
        let vl = role
            .vline
            .and_then(|k| self.vlines.get(k as usize).copied().flatten());
        let hl = role
            .hline
            .and_then(|k| self.hlines.get(k as usize).copied().flatten());
        VertexArea {
            x: at.or(vl),
            y: at.or(hl),
        }
    }
}

/// Hands out unknowns, numbered in the order they are asked for (the order of the system's
/// rows, which the pattern key and the assembly depend on).
#[derive(Default)]
struct Unknowns(u32);

impl Unknowns {
    fn fresh(&mut self) -> u32 {
        self.0 += 1;
        self.0 - 1
    }
}

/// One [`Layout::with_fixed`] under way: what the structure asks to share, the unknowns each
/// shared thing got so far, and the layout being filled vertex by vertex.
struct Builder<'a> {
    mesh: &'a Mesh,
    fixed: &'a [Option<DVec2>],
    /// Source and target sides.
    size: DVec2,
    target: DVec2,
    members: AreaMembers,
    attached: Vec<Option<Attached>>,
    /// Per horizontal (vertical) line, its group of collinear pieces ([`joined_lines`]).
    h_groups: Vec<usize>,
    v_groups: Vec<usize>,
    /// Per text block, its row ([`text_rows`]).
    rows: Vec<usize>,
    /// Per data area, the last frame's map where a vertex of it is held ([`frozen_maps`]).
    frozen: Vec<Option<[f64; 4]>>,
    next: Unknowns,
    /// The vertical place and scale `[ty, s]` of each row of text blocks.
    row_vars: HashMap<usize, [u32; 2]>,
    /// The unknown of each group of collinear line pieces.
    hpos: HashMap<usize, u32>,
    vpos: HashMap<usize, u32>,
    /// The scale shared by the blocks tied to one side of an area along y (a y axis' tick
    /// labels keep one size).
    side_scale: HashMap<(usize, bool), u32>,
    /// The shared unknowns of each group of areas, per kind (`[ax, bx, ay, by]` index).
    group_vars: HashMap<(u8, usize), u32>,
    layout: Layout,
}

impl<'a> Builder<'a> {
    fn new(mesh: &'a Mesh, target: Size, fixed: &'a [Option<DVec2>]) -> Builder<'a> {
        let nv = mesh.vertices().len();
        let st = mesh.structure();
        // Collinear pieces of one line (a frame interrupted by its title) share one unknown.
        let (h_groups, v_groups) = match st {
            Some(s) => (
                joined_lines(&s.horizontal, s, true),
                joined_lines(&s.vertical, s, false),
            ),
            None => (Vec::new(), Vec::new()),
        };
        let members = st.map(AreaMembers::of).unwrap_or_default();
        let frozen = frozen_maps(mesh, &members, fixed);
        let layout = Layout {
            x: Vec::with_capacity(nv),
            y: Vec::with_capacity(nv),
            s_var: vec![[FIXED; 2]; mesh.triangles().len()],
            blocks: vec![[FIXED; 3]; st.map_or(0, |s| s.text.len())],
            hlines: vec![FIXED; st.map_or(0, |s| s.horizontal.len())],
            vlines: vec![FIXED; st.map_or(0, |s| s.vertical.len())],
            areas: vec![[FIXED; 4]; members.groups.len()],
            on_area: vec![false; nv],
            dof: 0,
            n: 0,
            uses: Vec::new(),
        };
        Builder {
            mesh,
            fixed,
            size: DVec2::new(mesh.size().width as f64, mesh.size().height as f64),
            target: DVec2::new(target.width as f64, target.height as f64),
            attached: st.map(attachments).unwrap_or_default(),
            rows: st.map_or(Vec::new(), |s| text_rows(&s.text, &s.vertical)),
            members,
            h_groups,
            v_groups,
            frozen,
            next: Unknowns::default(),
            row_vars: HashMap::new(),
            hpos: HashMap::new(),
            vpos: HashMap::new(),
            side_scale: HashMap::new(),
            group_vars: HashMap::new(),
            layout,
        }
    }

    /// Lays out vertex `i` at source position `p` with boundary constraint `side`.
    fn vertex(&mut self, i: usize, p: DVec2, side: Boundary) {
        let role = self.mesh.roles().get(i).copied().unwrap_or_default();
        let across = self.across_side(p, side);
        if let Some(q) = self.fixed.get(i).copied().flatten() {
            let l = &mut self.layout;
            l.x.push(Coord::fixed(across[0].unwrap_or(q.x)));
            l.y.push(Coord::fixed(across[1].unwrap_or(q.y)));
            return;
        }
        let area = self.members.of_vertex(p, role);
        self.layout.on_area[i] = area.x.is_some() || area.y.is_some();
        let x = match across[0] {
            Some(c) => Coord::fixed(c),
            None => self.x_coord(p, role, area.x),
        };
        let y = match across[1] {
            Some(c) => Coord::fixed(c),
            None => self.y_coord(p, role, area.y),
        };
        self.layout.x.push(x);
        self.layout.y.push(y);
    }

    /// Eq. 11: across its side, a side or corner vertex sits on the target's side (x, then
    /// y); `None` along a side it slides on, and for an interior vertex.
    fn across_side(&self, p: DVec2, side: Boundary) -> [Option<f64>; 2] {
        let at = DVec2::select(p.cmpge(self.size), self.target, DVec2::ZERO);
        [
            side.fixes_x().then_some(at.x),
            side.fixes_y().then_some(at.y),
        ]
    }

    /// The x of a free vertex: its area's map, else its text block's, else its vertical
    /// line's, else an unknown of its own. The first vertex of a block sets the block's
    /// unknowns up.
    fn x_coord(&mut self, p: DVec2, role: Role, area: Option<usize>) -> Coord {
        if let Some(k) = area {
            return self.area_coord(k, 0, p.x, None);
        }
        if let Some(k) = role.block.map(|k| k as usize) {
            let bl = self.block_vars(k);
            return match self.attached(k) {
                Some(at) if at.along_x => {
                    let own = Some((bl[2], p.x - at.centre));
                    self.area_coord(at.area, 0, at.centre, own)
                }
                _ => Coord::affine(0.0, (bl[0], 1.0), (bl[2], p.x)),
            };
        }
        if let Some(k) = role.vline {
            return Coord::var(self.line_var(k as usize, false));
        }
        Coord::var(self.next.fresh())
    }

    /// The y of a free vertex, as [`Builder::x_coord`]; a block's unknowns are those its x
    /// set up.
    fn y_coord(&mut self, p: DVec2, role: Role, area: Option<usize>) -> Coord {
        if let Some(k) = area {
            return self.area_coord(k, 1, p.y, None);
        }
        if let Some(k) = role.block.map(|k| k as usize) {
            let bl = self.layout.blocks[k];
            return match self.attached(k) {
                Some(at) if !at.along_x => {
                    let own = Some((bl[2], p.y - at.centre));
                    self.area_coord(at.area, 1, at.centre, own)
                }
                _ => Coord::affine(0.0, (bl[1], 1.0), (bl[2], p.y)),
            };
        }
        if let Some(k) = role.hline {
            return Coord::var(self.line_var(k as usize, true));
        }
        Coord::var(self.next.fresh())
    }

    fn attached(&self, k: usize) -> Option<Attached> {
        self.attached.get(k).copied().flatten()
    }

    /// Text block `k`'s unknowns `(tx, ty, s)`, set up on first use. A block tied to an area
    /// along y has its own x, its y from the area and one scale per side of the area; the
    /// others share their row's vertical place and scale, and one tied along x takes its x
    /// from the area.
    fn block_vars(&mut self, k: usize) -> [u32; 3] {
        if self.layout.blocks[k][2] == FIXED {
            self.layout.blocks[k] = match self.attached(k) {
                Some(at) if !at.along_x => {
                    let s = *self
                        .side_scale
                        .entry((at.area, false))
                        .or_insert_with(|| self.next.fresh());
                    [self.next.fresh(), FIXED, s]
                }
                at => {
                    let g = self.rows[k];
                    let next = &mut self.next;
                    let [ty, s] = *self
                        .row_vars
                        .entry(g)
                        .or_insert_with(|| [next.fresh(), next.fresh()]);
                    [if at.is_some() { FIXED } else { next.fresh() }, ty, s]
                }
            };
        }
        self.layout.blocks[k]
    }

    /// The unknown of line `k` (its y if `horizontal`), shared with its collinear pieces.
    fn line_var(&mut self, k: usize, horizontal: bool) -> u32 {
        let (group, pos, vars) = if horizontal {
            (self.h_groups[k], &mut self.hpos, &mut self.layout.hlines)
        } else {
            (self.v_groups[k], &mut self.vpos, &mut self.layout.vlines)
        };
        let v = *pos.entry(group).or_insert_with(|| self.next.fresh());
        vars[k] = v;
        v
    }

    /// Unknown `i` of `[ax, bx, ay, by]` of area `k`, shared with the areas of its group.
    fn area_var(&mut self, k: usize, i: usize) -> u32 {
        let key = (i as u8, self.members.groups[k][i]);
        let v = *self
            .group_vars
            .entry(key)
            .or_insert_with(|| self.next.fresh());
        self.layout.areas[k][i] = v;
        v
    }

    /// Coordinate `pos` along `axis` (0 x, 1 y) of area `k`'s map (or of the last frame's,
    /// frozen); with `own = Some((s, d))`, plus a block's own scale `s` times `d`, its
    /// distance from its anchor.
    fn area_coord(&mut self, k: usize, axis: usize, pos: f64, own: Option<(u32, f64)>) -> Coord {
        match (
            self.frozen[k].map(|m| m[2 * axis] * pos + m[2 * axis + 1]),
            own,
        ) {
            (Some(c), None) => Coord::fixed(c),
            (Some(c), Some((s, d))) => Coord::affine(c, (s, d), (FIXED, 0.0)),
            (None, own) => {
                let b = self.area_var(k, 2 * axis + 1);
                let a = self.area_var(k, 2 * axis);
                match own {
                    None => Coord::affine(0.0, (b, 1.0), (a, pos)),
                    Some((s, d)) => Coord::affine3(0.0, (b, 1.0), (a, pos), (s, d)),
                }
            }
        }
    }

    /// The scale unknowns, after every position's: one per triangle that must stay similar
    /// (a mark's fan, the inside of a text block), one per axis for the others, none for a
    /// triangle whose corners are all fixed. Then how many coordinates use each unknown.
    fn finish(self) -> Layout {
        let Builder {
            mesh,
            mut next,
            layout: mut l,
            ..
        } = self;
        l.dof = next.0 as usize;
        let fans = mesh.fan_triangles();
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let active = tri
                .iter()
                .any(|&v| !l.x[v as usize].is_fixed() || !l.y[v as usize].is_fixed());
            if active {
                let similar =
                    fans.get(t).copied().unwrap_or(false) || mesh.triangle_block(t).is_some();
                if similar {
                    l.s_var[t] = [next.fresh(); 2];
                } else {
                    l.s_var[t] = [next.fresh(), next.fresh()];
                }
            }
        }
        l.n = next.0 as usize;
        l.uses = vec![0; l.n];
        for z in l.x.iter().chain(&l.y) {
            for (v, _) in z.terms() {
                l.uses[v] += 1;
            }
        }
        l
    }
}

/// A local update holds what lies outside the changed region where the last frame put it: an
/// area with a vertex held keeps the last frame's map (fitted to its held vertices, those it
/// follows along both axes that are not text) and is no unknown (a few free vertices could
/// not pin its four down). Per area, that map or `None`.
fn frozen_maps(
    mesh: &Mesh,
    members: &AreaMembers,
    fixed: &[Option<DVec2>],
) -> Vec<Option<[f64; 4]>> {
    let roles = mesh.roles();
    (0..members.groups.len())
        .map(|k| {
            let held_in = mesh.vertices().iter().enumerate().filter_map(|(i, &p)| {
                let role = roles.get(i).copied().unwrap_or_default();
                let a = members.of_vertex(p, role);
                (a.x == Some(k) && a.y == Some(k) && role.block.is_none())
                    .then(|| fixed.get(i).copied().flatten().map(|q| (p, q)))
                    .flatten()
            });
            fit_map(held_in)
        })
        .collect()
}

/// Which unknowns each vertex coordinate and each triangle scale are.
#[derive(Clone, Debug, Default)]
pub(crate) struct Layout {
    pub x: Vec<Coord>,
    pub y: Vec<Coord>,
    /// Unknown indices of each triangle's scales `(a_t, b_t)` along x and y, or [`FIXED`] for
    /// a triangle whose corners are all fixed (it takes no part in the system). A triangle
    /// that must stay similar to itself (a mark's fan, the inside of a text block) has one
    /// scale: both indices are the same unknown.
    pub s_var: Vec<[u32; 2]>,
    /// The unknowns of each text block: `(tx, ty, s)`.
    pub blocks: Vec<[u32; 3]>,
    /// The y unknown of each horizontal line, the x unknown of each vertical line
    /// ([`FIXED`] when no free vertex uses it).
    pub hlines: Vec<u32>,
    pub vlines: Vec<u32>,
    /// The unknowns `[ax, bx, ay, by]` of each data area's map `(bx + ax·x, by + ay·y)`
    /// ([`FIXED`] where no vertex uses them).
    pub areas: Vec<[u32; 4]>,
    /// Whether each vertex follows a data area's map (along x or y).
    pub on_area: Vec<bool>,
    /// Free position unknowns (the paper's DOF).
    pub dof: usize,
    /// Number of unknowns.
    pub n: usize,
    /// How many vertex coordinates use each unknown.
    pub uses: Vec<u32>,
}

impl Layout {
    /// Every vertex free but for the boundary and structure constraints.
    pub fn new(mesh: &Mesh, target: Size) -> Layout {
        Layout::with_fixed(mesh, target, &[])
    }

    /// Like [`Layout::new`], but vertex `i` with `fixed[i] = Some(p)` is held at `p` (a local
    /// update keeps everything outside the changed region where the last frame put it). An
    /// empty `fixed` fixes nothing.
    pub fn with_fixed(mesh: &Mesh, target: Size, fixed: &[Option<DVec2>]) -> Layout {
        let mut b = Builder::new(mesh, target, fixed);
        for (i, (&p, &side)) in mesh.vertices().iter().zip(mesh.boundary()).enumerate() {
            b.vertex(i, p, side);
        }
        b.finish()
    }

    /// Number of free position unknowns (the paper's DOF).
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// Whether coordinate `z` is an unknown of its own (not fixed, not shared with a line or a
    /// block): only those may be moved one vertex at a time.
    pub fn is_private(&self, z: &Coord) -> bool {
        z.single()
            .is_some_and(|v| self.uses.get(v as usize).copied().unwrap_or(0) == 1)
    }

    /// A hash of the pattern of unknowns, with the mesh topology: equal keys mean the same
    /// sparsity pattern and the same order of assembly.
    pub fn pattern_key(&self, mesh: &Mesh) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        mesh.triangles().hash(&mut h);
        for c in self.x.iter().chain(&self.y) {
            c.v.hash(&mut h);
        }
        self.s_var.hash(&mut h);
        self.blocks.hash(&mut h);
        h.finish()
    }
}
