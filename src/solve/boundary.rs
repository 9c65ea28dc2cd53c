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
use crate::mesh::Mesh;
use crate::structure::TextBlock;
use glam::DVec2;

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
        let (w, h) = (mesh.size().width as f64, mesh.size().height as f64);
        let (tw, th) = (target.width as f64, target.height as f64);
        let nv = mesh.vertices().len();
        let nt = mesh.triangles().len();
        let roles = mesh.roles();
        let fans = mesh.fan_triangles();
        let held = |i: usize| fixed.get(i).copied().flatten();
        let mut next = 0u32;
        let mut fresh = || {
            next += 1;
            next - 1
        };
        // Collinear pieces of one line (a frame interrupted by its title) share one unknown.
        let (st_h, st_v) = match mesh.structure() {
            Some(s) => (
                joined_lines(&s.horizontal, s, true),
                joined_lines(&s.vertical, s, false),
            ),
            None => (Vec::new(), Vec::new()),
        };
        let rows = mesh
            .structure()
            .map_or(Vec::new(), |s| text_rows(&s.text, &s.vertical));
        let mut row_vars: std::collections::HashMap<usize, [u32; 2]> = Default::default();
        let mut hpos: std::collections::HashMap<usize, u32> = Default::default();
        let mut vpos: std::collections::HashMap<usize, u32> = Default::default();
        let n_blocks = mesh.structure().map_or(0, |s| s.text.len());
        let n_h = mesh.structure().map_or(0, |s| s.horizontal.len());
        let n_v = mesh.structure().map_or(0, |s| s.vertical.len());
        let members = mesh.structure().map(AreaMembers::of).unwrap_or_default();
        let attached = mesh.structure().map(attachments).unwrap_or_default();
        // The scale shared by the blocks tied to one side of an area along y (a y axis' tick
        // labels keep one size).
        let mut side_scale: std::collections::HashMap<(usize, bool), u32> = Default::default();
        // A local update holds what lies outside the changed region where the last frame put
        // it: an area with a vertex held keeps the last frame's map (fitted to its held
        // vertices) and is no unknown (a few free vertices could not pin its four down).
        let frozen: Vec<Option<[f64; 4]>> = (0..members.groups.len())
            .map(|k| {
                let held_in = mesh.vertices().iter().enumerate().filter_map(|(i, &p)| {
                    let role = roles.get(i).copied().unwrap_or_default();
                    let a = members.of_vertex(p, role);
                    (a.x == Some(k) && a.y == Some(k) && role.block.is_none())
                        .then(|| held(i).map(|q| (p, q)))
                        .flatten()
                });
                fit_map(held_in)
            })
            .collect();
        let n_areas = members.groups.len();
        // The shared unknowns of each group (scale along x, offset along x, along y).
        let mut group_vars: std::collections::HashMap<(u8, usize), u32> = Default::default();
        let mut l = Layout {
            x: Vec::with_capacity(nv),
            y: Vec::with_capacity(nv),
            s_var: vec![[FIXED; 2]; nt],
            blocks: vec![[FIXED; 3]; n_blocks],
            hlines: vec![FIXED; n_h],
            vlines: vec![FIXED; n_v],
            areas: vec![[FIXED; 4]; n_areas],
            on_area: vec![false; nv],
            dof: 0,
            n: 0,
            uses: Vec::new(),
        };
        for (i, (&p, &b)) in mesh.vertices().iter().zip(mesh.boundary()).enumerate() {
            let role = roles.get(i).copied().unwrap_or_default();
            if let Some(q) = held(i) {
                l.x.push(Coord::fixed(if b.fixes_x() {
                    if p.x >= w {
                        tw
                    } else {
                        0.0
                    }
                } else {
                    q.x
                }));
                l.y.push(Coord::fixed(if b.fixes_y() {
                    if p.y >= h {
                        th
                    } else {
                        0.0
                    }
                } else {
                    q.y
                }));
                continue;
            }
            let block = role.block.map(|k| k as usize);
            let area = members.of_vertex(p, role);
            l.on_area[i] = area.x.is_some() || area.y.is_some();
            let mut area_var = |k: usize, i: usize, fresh: &mut dyn FnMut() -> u32| -> u32 {
                let key = (i as u8, members.groups[k][i]);
                let v = *group_vars.entry(key).or_insert_with(fresh);
                l.areas[k][i] = v;
                v
            };
            // Coordinate `pos` along `axis` (0 x, 1 y) of area `k`'s map (or of the last
            // frame's, frozen); with `own = Some((s, d))`, plus a block's own scale `s` times
            // `d`, its distance from its anchor.
            let mut area_coord = |k: usize,
                                  axis: usize,
                                  pos: f64,
                                  own: Option<(u32, f64)>,
                                  fresh: &mut dyn FnMut() -> u32|
             -> Coord {
                match (frozen[k].map(|m| m[2 * axis] * pos + m[2 * axis + 1]), own) {
                    (Some(c), None) => Coord::fixed(c),
                    (Some(c), Some((s, d))) => Coord::affine(c, (s, d), (FIXED, 0.0)),
                    (None, own) => {
                        let b = area_var(k, 2 * axis + 1, fresh);
                        let a = area_var(k, 2 * axis, fresh);
                        match own {
                            None => Coord::affine(0.0, (b, 1.0), (a, pos)),
                            Some((s, d)) => Coord::affine3(0.0, (b, 1.0), (a, pos), (s, d)),
                        }
                    }
                }
            };
            let x = if b.fixes_x() {
                Coord::fixed(if p.x >= w { tw } else { 0.0 })
            } else if let Some(k) = area.x {
                area_coord(k, 0, p.x, None, &mut fresh)
            } else if let Some(k) = block {
                if l.blocks[k][2] == FIXED {
                    l.blocks[k] = match attached.get(k).copied().flatten() {
                        // Tied along y: its own x, its y from the area, one scale per side.
                        Some(at) if !at.along_x => {
                            let s = *side_scale
                                .entry((at.area, false))
                                .or_insert_with(&mut fresh);
                            [fresh(), FIXED, s]
                        }
                        // Blocks of one row share their vertical place and scale; a block
                        // tied along x takes its x from the area.
                        at => {
                            let g = rows[k];
                            let [ty, s] = *row_vars.entry(g).or_insert_with(|| [fresh(), fresh()]);
                            [if at.is_some() { FIXED } else { fresh() }, ty, s]
                        }
                    };
                }
                let bl = l.blocks[k];
                match attached.get(k).copied().flatten() {
                    Some(at) if at.along_x => {
                        let own = Some((bl[2], p.x - at.centre));
                        area_coord(at.area, 0, at.centre, own, &mut fresh)
                    }
                    _ => Coord::affine(0.0, (bl[0], 1.0), (bl[2], p.x)),
                }
            } else if let Some(k) = role.vline {
                let group = st_v[k as usize];
                let v = *vpos.entry(group).or_insert_with(&mut fresh);
                l.vlines[k as usize] = v;
                Coord::var(v)
            } else {
                Coord::var(fresh())
            };
            let y = if b.fixes_y() {
                Coord::fixed(if p.y >= h { th } else { 0.0 })
            } else if let Some(k) = area.y {
                area_coord(k, 1, p.y, None, &mut fresh)
            } else if let Some(k) = block {
                let bl = l.blocks[k];
                match attached.get(k).copied().flatten() {
                    Some(at) if !at.along_x => {
                        let own = Some((bl[2], p.y - at.centre));
                        area_coord(at.area, 1, at.centre, own, &mut fresh)
                    }
                    _ => Coord::affine(0.0, (bl[1], 1.0), (bl[2], p.y)),
                }
            } else if let Some(k) = role.hline {
                let group = st_h[k as usize];
                let v = *hpos.entry(group).or_insert_with(&mut fresh);
                l.hlines[k as usize] = v;
                Coord::var(v)
            } else {
                Coord::var(fresh())
            };
            l.x.push(x);
            l.y.push(y);
        }
        l.dof = next as usize;
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let active = tri
                .iter()
                .any(|&v| !l.x[v as usize].is_fixed() || !l.y[v as usize].is_fixed());
            if active {
                let similar =
                    fans.get(t).copied().unwrap_or(false) || mesh.triangle_block(t).is_some();
                if similar {
                    l.s_var[t] = [next; 2];
                    next += 1;
                } else {
                    l.s_var[t] = [next, next + 1];
                    next += 2;
                }
            }
        }
        l.n = next as usize;
        l.uses = vec![0; l.n];
        for z in l.x.iter().chain(&l.y) {
            for (v, _) in z.terms() {
                l.uses[v] += 1;
            }
        }
        l
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
