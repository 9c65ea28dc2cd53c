//! Text: clusters of small high-contrast strokes on a uniform ground, lined up in rows.
//!
//! 1. Stroke pixels: where the luminance range of the 3×3 neighbourhood exceeds
//!    [`STROKE_RANGE`] (a glyph's strokes and their 1-px surroundings; a uniform ground and the
//!    inside of filled shapes are not).
//! 2. Glyphs: 8-connected components of stroke pixels of glyph height ([`MIN_H`]–[`MAX_H`] px);
//!    letters closer than ~2 px merge into words, which is fine.
//! 3. Text lines: glyphs whose vertical extents overlap by 60 %, of similar height, closer
//!    horizontally than their height, joined; a group of one glyph only counts when wider than
//!    tall (a lone round blob is a mark, not text).
//! 4. Overlapping text lines become one block.

use super::Line;

/// Densest component taken for a bold glyph with a counter ([`encloses_ground`]); a filled
/// cell with a label inside (a heat map's) is ink to its edges, denser than this.
const MAX_INK_HOLED: f32 = 0.7;
/// Least height of display type (big values, headings), pixels.
const MIN_DISPLAY_H: u32 = 20;
/// Least area of a counter, pixels: a pinhole of antialiasing is not one.
const MIN_COUNTER_PX: usize = 3;

/// Luminance range in a 3×3 neighbourhood that marks a stroke pixel.
const STROKE_RANGE: u8 = 60;
/// Glyph (or word) height range, pixels.
const MIN_H: u32 = 7;
const MAX_H: u32 = 60;
/// Widest glyph component relative to its height (merged words run long).
const MAX_ASPECT: u32 = 14;
/// Most ink a glyph component holds: glyphs are mostly ground inside their box (measured on
/// the real dashboards: a stricter bound starts to lose words), where a filled disc or square
/// (a dot, a waffle cell, a legend swatch) is ink to its edges (0.6 to 0.8 of its box, which
/// is one pixel of halo wider).
const MAX_INK: f32 = 0.5;
/// Least ratio of height to width of a component taken for a glyph's lone stem whatever its
/// ink: an "l" of heavy type with its one-pixel halo is still three times as tall as wide.
const STEM_ASPECT: u32 = 3;
/// Densest component taken for merged letters (bold type set tight), if at least twice as wide
/// as tall: a legend swatch, as wide, is ink to its edges (above 0.7).
const MAX_INK_MERGED: f32 = 0.62;

/// A text block's bounding box `[x0, y0, x1, y1)` in image pixels, and its line height.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TextBlock {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
    /// Glyph height of its (tallest) line (across the line, for text set sideways).
    pub line_height: u32,
    /// Set up the side, read turned 90° (a y axis' title).
    pub sideways: bool,
}

/// Blocks whose left (right, top, bottom) edges lie within this of each other are set in one
/// column (row): a legend's labels, a y axis' tick labels.
pub(crate) const ALIGNED_PX: u32 = 2;

/// Line heights this close (as a share of the larger) are one size of type.
const SAME_TYPE_SIZE: f64 = 0.25;

impl TextBlock {
    /// Whether this block and `other` are set in one size of type: line heights within a
    /// quarter of the larger.
    pub fn same_type_size(&self, other: &TextBlock) -> bool {
        let (ha, hb) = (self.line_height as f64, other.line_height as f64);
        (ha - hb).abs() <= SAME_TYPE_SIZE * ha.max(hb)
    }
}

#[cfg(test)]
impl TextBlock {
    /// An upright block of one line filling its box: what tests set down as a label.
    pub(crate) fn upright(x0: u32, y0: u32, x1: u32, y1: u32) -> TextBlock {
        TextBlock {
            x0,
            y0,
            x1,
            y1,
            line_height: y1 - y0,
            sideways: false,
        }
    }
}

#[derive(Copy, Clone, Debug)]
struct Comp {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
    /// Share of the box's pixels that are ink (far from the ground), once measured.
    ink: f32,
}

impl Comp {
    fn h(&self) -> u32 {
        self.y1 - self.y0
    }
    fn w(&self) -> u32 {
        self.x1 - self.x0
    }
}

/// Text blocks of a `w × h` luminance image whose thin lines are `lines` (horizontal, vertical).
/// Components centred inside a block of `skip` (text read another way) are left out.
pub(crate) fn detect(
    l: &[u8],
    w: usize,
    h: usize,
    lines: [&[Line]; 2],
    skip: &[TextBlock],
) -> Vec<TextBlock> {
    let mut stroke = stroke_mask(l, w, h);
    clear_lines(&mut stroke, w, h, lines);
    let mut glyphs = Vec::new();
    for mut c in components(&stroke, w, h) {
        let (cx, cy) = ((c.x0 + c.x1) / 2, (c.y0 + c.y1) / 2);
        if skip
            .iter()
            .any(|b| (b.x0..b.x1).contains(&cx) && (b.y0..b.y1).contains(&cy))
        {
            continue;
        }
        let bg = ground(l, w, &c);
        if rims_a_fill(l, w, h, &c, bg) {
            continue;
        }
        let stems = glyph_ink(l, w, bg, &mut c);
        if c.ink <= MAX_INK {
            glyphs.push((c, stems));
        } else if c.w() * STEM_ASPECT <= c.h() {
            // A lone stem ("i", "l", "1", "I"): a bar of ink as dense as a filled shape, but
            // narrow as no dot, cell or swatch is. It joins a word beside it as a glyph without
            // stems would, never makes a line with other stems alone (thin bars in a row).
            glyphs.push((c, false));
        } else if c.ink <= MAX_INK_MERGED && c.w() >= 2 * c.h() {
            // Letters of a bold word merged into one component ("uce" of "dairy-produce"):
            // denser than a glyph, wider than a dot or a cell. It joins a word beside it as a
            // glyph without stems would, never makes a line alone.
            glyphs.push((c, false));
        } else if c.ink <= MAX_INK_HOLED && c.h() >= MIN_DISPLAY_H && encloses_ground(l, w, bg, &c)
        {
            // A bold glyph of display type with a counter ("8", "9", "e", "a" of a big value
            // in a dashboard's tile): as dense as a swatch, but ground lies inside it, as it
            // never does inside a filled dot, cell or swatch, nor between the cells of a
            // waffle or a grid (their gaps reach the outside). Hollow symbols are the size of
            // the body text they label, smaller than display type.
            glyphs.push((c, stems));
        } else if c.ink <= MAX_INK_HOLED
            && !frames_its_box(l, w, bg, &c)
            && encloses_ground(l, w, bg, &c)
        {
            // A bold letter with a counter in smaller type (the "B" of a title; left out, it
            // is squeezed and hidden under its floating word): its outline leaves a side of
            // its box open, where a hollow box symbol's walls run along all four. It joins a
            // word beside it as a glyph without stems would, never makes a line alone.
            glyphs.push((c, false));
        }
    }
    // No stroke within half a glyph's height above or below it, across its width.
    let clear = |c: &Comp| {
        let reach = c.h() / 2;
        let rows = (c.y0.saturating_sub(reach)..c.y0).chain(c.y1..(c.y1 + reach).min(h as u32));
        rows.into_iter().all(|y| {
            let row = &stroke[y as usize * w..][..w];
            !row[c.x0 as usize..c.x1 as usize].contains(&true)
        })
    };
    let lines = group_lines(glyphs, clear);
    merge_blocks(lines)
}

crate::simd::with_feature! {
    "avx2";
    /// Pixels whose 3×3 luminance range exceeds [`STROKE_RANGE`]. Separable max and min over
    /// shifted row slices, so that the loops vectorize (a per-pixel window scan was most of the
    /// detection time), each row's made once into a ring of three rows that stays in cache.
    fn stroke_mask(l: &[u8], w: usize, h: usize) -> Vec<bool> => stroke_mask_body {
        let (mut rmax, mut rmin) = (vec![0u8; 3 * w], vec![0u8; 3 * w]);
        // Row `y`'s maximum and minimum over each pixel and its left and right neighbours,
        // into slot `y % 3`.
        let across = |y: usize, rmax: &mut [u8], rmin: &mut [u8]| {
            let row = &l[y * w..][..w];
            let (omax, omin) = (&mut rmax[y % 3 * w..][..w], &mut rmin[y % 3 * w..][..w]);
            omax.copy_from_slice(row);
            omin.copy_from_slice(row);
            if w > 1 {
                for x in 0..w - 1 {
                    let r = row[x + 1];
                    omax[x] = omax[x].max(r);
                    omin[x] = omin[x].min(r);
                }
                for x in 1..w {
                    let l = row[x - 1];
                    omax[x] = omax[x].max(l);
                    omin[x] = omin[x].min(l);
                }
            }
        };
        let mut out = vec![false; w * h];
        for y in 0..h {
            // Rows y - 1 and y are in the ring already; y + 1 takes y - 2's slot.
            if y == 0 {
                across(0, &mut rmax, &mut rmin);
            }
            if y + 1 < h {
                across(y + 1, &mut rmax, &mut rmin);
            }
            let (a, b) = (y.saturating_sub(1), (y + 1).min(h - 1));
            // Slices of exactly `w` (as `[start..][..w]`): the loop below then runs free of
            // bounds checks, in vectors.
            let (sa, sy, sb) = (a % 3 * w, y % 3 * w, b % 3 * w);
            let (ma, mc, mb) = (&rmax[sa..][..w], &rmax[sy..][..w], &rmax[sb..][..w]);
            let (na, nc, nb) = (&rmin[sa..][..w], &rmin[sy..][..w], &rmin[sb..][..w]);
            let o = &mut out[y * w..][..w];
            let maxima = ma.iter().zip(mc).zip(mb);
            let minima = na.iter().zip(nc).zip(nb);
            for (o, (((&ma, &mc), &mb), ((&na, &nc), &nb))) in o.iter_mut().zip(maxima.zip(minima)) {
                *o = ma.max(mc).max(mb) - na.min(nc).min(nb) > STROKE_RANGE;
            }
        }
        out
    }
}

/// Glyph-sized 8-connected components.
fn components(mask: &[bool], w: usize, h: usize) -> Vec<Comp> {
    // Pixels not yet taken into a component, as bytes: most of a picture is ground, and
    // the next start is found eight pixels at a time.
    let mut left: Vec<u8> = mask.iter().map(|&m| m as u8).collect();
    let mut stack: Vec<(u32, u32)> = Vec::new();
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(start) = super::mask::next_marked(&left, from, true) {
        from = start + 1;
        left[start] = 0;
        stack.push(((start % w) as u32, (start / w) as u32));
        let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
        while let Some((x, y)) = stack.pop() {
            x0 = x0.min(x);
            y0 = y0.min(y);
            x1 = x1.max(x + 1);
            y1 = y1.max(y + 1);
            for (dx, dy) in crate::raster::NEIGHBOURS_8 {
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                if left[j] != 0 {
                    left[j] = 0;
                    stack.push((nx as u32, ny as u32));
                }
            }
        }
        let c = Comp {
            x0,
            y0,
            x1,
            y1,
            ink: 1.0,
        };
        if (MIN_H..=MAX_H).contains(&c.h()) && c.w() <= MAX_ASPECT * c.h() {
            out.push(c);
        }
    }
    out
}

/// Strokes of lines are not glyphs: a panel's title set into its frame line ("─Total
/// Transactions─") would otherwise join the frame into one component far too long for text.
/// The line's pixels and the one-pixel halo the stroke mask gives them are cleared (the
/// detected lines are longer than a glyph's stroke, [`super::lines::min_length`]: no glyph is
/// cut).
fn clear_lines(mask: &mut [bool], w: usize, h: usize, [horizontal, vertical]: [&[Line]; 2]) {
    for (l, across_len, along_len, horizontal) in
        [(horizontal, h, w, true), (vertical, w, h, false)]
            .into_iter()
            .flat_map(|(ls, a, b, hz)| ls.iter().map(move |l| (l, a, b, hz)))
    {
        // The line's pixels (none for an edge between two regions, on a boundary) and two on
        // each side: a faint antialiased row beside a line is part of its stroke too.
        let half = l.width as f64 / 2.0;
        let a0 = ((l.pos - half).floor() as i64 - 2).max(0) as usize;
        let a1 = (((l.pos + half).ceil() as i64 + 2).max(0) as usize).min(across_len);
        let (b0, b1) = (l.from as usize, (l.to as usize).min(along_len));
        for a in a0..a1 {
            for b in b0..b1 {
                let i = if horizontal { a * w + b } else { b * w + a };
                mask[i] = false;
            }
        }
    }
}

/// Whether a component holds glyph stems: a vertical run of ink at least 40 % of its height
/// (and 4 px). Letters and digits have them; a cluster of dots (a dot-matrix map, a dotted
/// line) does not, however its dots line up. Records the component's share of ink.
fn glyph_ink(l: &[u8], w: usize, bg: i16, c: &mut Comp) -> bool {
    let need = (c.h() * 2 / 5).max(4);
    let mut stems = false;
    let mut ink = 0u32;
    for x in c.x0..c.x1 {
        let mut run = 0;
        for y in c.y0..c.y1 {
            if is_ink(l, w, bg, x, y) {
                ink += 1;
                run += 1;
                stems |= run >= need;
            } else {
                run = 0;
            }
        }
    }
    c.ink = ink as f32 / (c.w() * c.h()) as f32;
    stems
}

/// Whether pixel `(x, y)` of a `w`-wide luminance image is ink on ground `bg`.
fn is_ink(l: &[u8], w: usize, bg: i16, x: u32, y: u32) -> bool {
    (l[y as usize * w + x as usize] as i16 - bg).abs() > STROKE_RANGE as i16
}

/// The ground a component lies on: the most common luminance on its box's border.
fn ground(l: &[u8], w: usize, c: &Comp) -> i16 {
    let mut hist = [0u32; 256];
    for x in c.x0..c.x1 {
        hist[l[c.y0 as usize * w + x as usize] as usize] += 1;
        hist[l[(c.y1 - 1) as usize * w + x as usize] as usize] += 1;
    }
    for y in c.y0..c.y1 {
        hist[l[y as usize * w + c.x0 as usize] as usize] += 1;
        hist[l[y as usize * w + (c.x1 - 1) as usize] as usize] += 1;
    }
    (0..256).max_by_key(|&v| hist[v]).unwrap_or(0) as i16
}

/// Whether the component is the rim of a filled shape: along most of one side, the pixels
/// just outside its box are ink. A glyph's stroke pixels take in the ground around its ink,
/// so ground lies beyond its box on every side; a legend swatch whose top and bottom edges
/// were cleared as lines leaves its left and right edges as glyph-sized strokes, with the
/// swatch's fill beside them (joined to the label next to it, a sliver of the swatch would
/// float with the label's text).
fn rims_a_fill(l: &[u8], w: usize, h: usize, c: &Comp, bg: i16) -> bool {
    let ink = |x: u32, y: u32| is_ink(l, w, bg, x, y);
    let most = |n: usize, of: u32| 2 * n > of as usize;
    let column = |x: u32| most((c.y0..c.y1).filter(|&y| ink(x, y)).count(), c.h());
    let row = |y: u32| most((c.x0..c.x1).filter(|&x| ink(x, y)).count(), c.w());
    (c.x0 > 0 && column(c.x0 - 1))
        || ((c.x1 as usize) < w && column(c.x1))
        || (c.y0 > 0 && row(c.y0 - 1))
        || ((c.y1 as usize) < h && row(c.y1))
}

/// Share of its length along which a side's outermost line of ink runs for the side to be a
/// wall: a box's wall runs along all of it but its antialiased corners, a letter's bowl
/// touches its side at a point.
const WALL_SHARE: u32 = 70;

/// Whether ink walls the component's box on all four sides (a hollow box symbol): on each
/// side, the outermost row or column holding ink has ink along [`WALL_SHARE`] % of it.
fn frames_its_box(l: &[u8], w: usize, bg: i16, c: &Comp) -> bool {
    let ink = |x: u32, y: u32| is_ink(l, w, bg, x, y);
    let walled = |line: &mut dyn Iterator<Item = u32>, along: &dyn Fn(u32) -> u32, len: u32| {
        line.map(along)
            .find(|&n| n > 0)
            .is_some_and(|n| n * 100 >= WALL_SHARE * len)
    };
    let column = |x: u32| (c.y0..c.y1).filter(|&y| ink(x, y)).count() as u32;
    let row = |y: u32| (c.x0..c.x1).filter(|&x| ink(x, y)).count() as u32;
    let (ih, iw) = (c.h().saturating_sub(2), c.w().saturating_sub(2));
    walled(&mut (c.x0..c.x1), &column, ih)
        && walled(&mut (c.x0..c.x1).rev(), &column, ih)
        && walled(&mut (c.y0..c.y1), &row, iw)
        && walled(&mut (c.y0..c.y1).rev(), &row, iw)
}

/// Whether the component's box holds ground enclosed by ink (a counter, at least
/// [`MIN_COUNTER_PX`]): pixels near the ground level `bg` ([`ground`]) that a 4-connected fill from the
/// box's border does not reach.
fn encloses_ground(l: &[u8], w: usize, bg: i16, c: &Comp) -> bool {
    let (bw, bh) = (c.w() as usize, c.h() as usize);
    if bw < 3 || bh < 3 {
        return false;
    }
    let px = |x: usize, y: usize| l[(c.y0 as usize + y) * w + c.x0 as usize + x];
    let ground: Vec<bool> = (0..bh)
        .flat_map(|y| (0..bw).map(move |x| (x, y)))
        .map(|(x, y)| (px(x, y) as i16 - bg).abs() <= STROKE_RANGE as i16)
        .collect();
    let mut reached = vec![false; bw * bh];
    let mut stack: Vec<usize> = Vec::new();
    for y in 0..bh {
        for x in 0..bw {
            let i = y * bw + x;
            if (x == 0 || y == 0 || x == bw - 1 || y == bh - 1) && ground[i] {
                reached[i] = true;
                stack.push(i);
            }
        }
    }
    while let Some(i) = stack.pop() {
        let (x, y) = (i % bw, i / bw);
        let mut visit = |j: usize| {
            if ground[j] && !reached[j] {
                reached[j] = true;
                stack.push(j);
            }
        };
        if x > 0 {
            visit(i - 1);
        }
        if x + 1 < bw {
            visit(i + 1);
        }
        if y > 0 {
            visit(i - bw);
        }
        if y + 1 < bh {
            visit(i + bw);
        }
    }
    ground
        .iter()
        .zip(&reached)
        .filter(|(&g, &r)| g && !r)
        .count()
        >= MIN_COUNTER_PX
}

// Glyph indices i, j address the sorted list and the union-find parents together.
#[allow(clippy::needless_range_loop)]
/// Joins glyphs into text lines (union-find over near neighbours in reading direction). A
/// glyph flagged without stems ([`glyph_ink`]: "s", "oy", "ce", letters of curves alone) only
/// joins a line through a neighbour with stems, never another stemless one: the trailing "s"
/// of "Crimes" and the "oy" of "Unemployment" belong to their words (left out, they are
/// squeezed as ground and the word is cut), while a cluster of dots still makes no line.
fn group_lines(
    mut comps: Vec<(Comp, bool)>,
    clear: impl Fn(&Comp) -> bool,
) -> Vec<(Comp, u32, usize)> {
    comps.sort_by_key(|(c, _)| (c.x0, c.y0));
    let n = comps.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for i in 0..n {
        let (a, sa) = comps[i];
        for j in i + 1..n {
            let (b, sb) = comps[j];
            if b.x0 > a.x1 + MAX_H {
                break;
            }
            if !sa && !sb {
                continue;
            }
            let (ha, hb) = (a.h(), b.h());
            let overlap = a.y1.min(b.y1) as i64 - a.y0.max(b.y0) as i64;
            if overlap * 10 < ha.min(hb) as i64 * 6 || ha.max(hb) > 2 * ha.min(hb) {
                continue;
            }
            let gap = b.x0 as i64 - a.x1 as i64;
            if gap <= ha.max(hb) as i64 {
                let (ra, rb) = (find(&mut parent, i), find(&mut parent, j));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // Per group: its box, line height, glyphs and glyphs with stems.
    let mut groups: std::collections::BTreeMap<usize, (Comp, u32, usize, usize)> =
        Default::default();
    for i in 0..n {
        let r = find(&mut parent, i);
        let (c, stems) = comps[i];
        let e = groups.entry(r).or_insert((c, c.h(), 0, 0));
        e.0 = Comp {
            x0: e.0.x0.min(c.x0),
            y0: e.0.y0.min(c.y0),
            x1: e.0.x1.max(c.x1),
            y1: e.0.y1.max(c.y1),
            ink: e.0.ink.max(c.ink),
        };
        e.1 = e.1.max(c.h());
        e.2 += 1;
        e.3 += stems as usize;
    }
    // A lone component is text when it is somewhat wider than tall (two digits that touch:
    // "85"; it is mostly ground, see [`MAX_INK`]); a round or square blob is a mark.
    let (mut lines, lone): (Vec<_>, Vec<_>) = groups
        .into_values()
        .filter(|(_, _, _, stems)| *stems >= 1)
        .partition(|(c, lh, k, _)| *k >= 2 || c.w() * 4 >= 5 * *lh);
    // A lone glyph with stems in line with text of its size is text too: the "0" that starts
    // a row of tick labels or ends a column of them (left out, it is squeezed beside labels
    // kept at their size). In line: on the same row, or sharing a left or right edge (a tick
    // mark under its label is centred on it, never edge to edge).
    let same_size = |lh: u32, olh: u32| lh.max(olh) * 4 <= lh.min(olh) * 5;
    let in_line = |c: &Comp, lh: u32, o: &Comp, olh: u32| {
        let overlap = c.y1.min(o.y1) as i64 - c.y0.max(o.y0) as i64;
        same_size(lh, olh)
            && (overlap * 10 >= c.h().min(o.h()) as i64 * 6
                || c.x0.abs_diff(o.x0) <= 1
                || c.x1.abs_diff(o.x1) <= 1)
    };
    // A row of lone glyphs evenly spaced is text too ([`evenly_spaced_rows`]), where words
    // of its size stand elsewhere (the other axis' labels): tick marks in a row are not.
    // A column of lone glyphs alone is text too: a y axis' single-digit tick labels ("2",
    // "4", "6"), at least three one above the other, aligned by an edge, each with ground
    // above and below it (pieces of small multiples' maps line up too, amid other strokes;
    // two glyphs may line up by chance).
    let in_column = |c: &Comp, o: &Comp| {
        let apart = c.y0 >= o.y1 || o.y0 >= c.y1;
        let (lo, hi) = (c.h().min(o.h()), c.h().max(o.h()));
        apart
            && hi * 4 <= lo * 5
            && (c.x0.abs_diff(o.x0) <= 1 || c.x1.abs_diff(o.x1) <= 1)
            && clear(o)
    };
    let column = |c: &Comp| clear(c) && lone.iter().filter(|o| in_column(c, &o.0)).count() >= 2;
    let in_row = evenly_spaced_rows(&lone.iter().map(|l| l.0).collect::<Vec<_>>());
    let found: Vec<_> = (lone.iter().zip(in_row))
        .filter(|((c, lh, _, _), row)| {
            (*row && lines.iter().any(|(_, olh, _, _)| same_size(*lh, *olh)))
                || lines.iter().any(|(o, olh, _, _)| in_line(c, *lh, o, *olh))
                || column(c)
        })
        .map(|(l, _)| *l)
        .collect();
    lines.extend(found);
    lines.into_iter().map(|(c, lh, k, _)| (c, lh, k)).collect()
}

/// Which of the lone glyphs `lone` stand in a row of lone glyphs, evenly spaced: an x axis'
/// single-digit tick labels ("5", "6", "7", "8" under each facet), which a locator sets at
/// equal steps, tops and baselines aligned. Three at least, each taller than wide (digits
/// and capitals are; a round or square marker is not), the steps between their centres
/// equal within [`EVEN_STEPS`] and wider than a glyph (a word's letters are closer).
/// Such a row was left out as marks, and the plots it labels were taken for no plot.
fn evenly_spaced_rows(lone: &[Comp]) -> Vec<bool> {
    let upright = |c: &Comp| c.h() * 5 >= c.w() * 6;
    let mut order: Vec<usize> = (0..lone.len()).filter(|&i| upright(&lone[i])).collect();
    order.sort_by_key(|&i| (lone[i].y1, lone[i].x0));
    let mut row = vec![false; lone.len()];
    let centre = |c: &Comp| (c.x0 + c.x1) as f64 / 2.0;
    for (k, &i) in order.iter().enumerate() {
        let c = &lone[i];
        // Its row: glyphs of its size whose top and baseline are its own, within a pixel,
        // by their centres.
        let mut mates: Vec<usize> = (order[k..].iter())
            .take_while(|&&j| lone[j].y1 <= c.y1 + 1)
            .chain(
                order[..k]
                    .iter()
                    .rev()
                    .take_while(|&&j| lone[j].y1 + 1 >= c.y1),
            )
            .copied()
            .filter(|&j| lone[j].y0.abs_diff(c.y0) <= 1)
            .collect();
        mates.sort_by(|&a, &b| centre(&lone[a]).total_cmp(&centre(&lone[b])));
        let at = mates.iter().position(|&j| j == i).unwrap_or(0);
        // Any three neighbours in a row, c among them, at equal steps.
        for s in at.saturating_sub(2)..=at {
            let Some(t) = mates.get(s..s + 3) else {
                continue;
            };
            let [a, b, d] = [t[0], t[1], t[2]].map(|j| centre(&lone[j]));
            let (g1, g2) = (b - a, d - b);
            let wide = (t.iter()).map(|&j| lone[j].w()).max().unwrap_or(0) as f64;
            if g1.min(g2) > wide && (g1 - g2).abs() <= EVEN_STEPS * g1.max(g2) {
                row[i] = true;
            }
        }
    }
    row
}

/// Most difference between two steps of a row of tick labels, as a share of the larger: a
/// locator's steps are equal, but a label's centre moves with its glyph's width by a pixel
/// or two, and a step may be short as 30 px.
const EVEN_STEPS: f64 = 0.15;

/// Overlapping text lines merged into blocks.
fn merge_blocks(lines: Vec<(Comp, u32, usize)>) -> Vec<TextBlock> {
    let mut blocks: Vec<TextBlock> = lines
        .into_iter()
        .map(|(c, lh, _)| TextBlock {
            x0: c.x0,
            y0: c.y0,
            x1: c.x1,
            y1: c.y1,
            line_height: lh,
            sideways: false,
        })
        .collect();
    loop {
        let mut merged = false;
        'outer: for i in 0..blocks.len() {
            for j in i + 1..blocks.len() {
                let (a, b) = (blocks[i], blocks[j]);
                let touch = a.x0 <= b.x1 && b.x0 <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1;
                if touch {
                    blocks[i] = TextBlock {
                        x0: a.x0.min(b.x0),
                        y0: a.y0.min(b.y0),
                        x1: a.x1.max(b.x1),
                        y1: a.y1.max(b.y1),
                        line_height: a.line_height.max(b.line_height),
                        sideways: a.sideways,
                    };
                    blocks.swap_remove(j);
                    merged = true;
                    break 'outer;
                }
            }
        }
        if !merged {
            return blocks;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_build_marks_the_same_strokes() {
        let (w, h) = (97, 41);
        let mut v = 0x8765_4321u32;
        let l: Vec<u8> = (0..w * h)
            .map(|_| {
                v ^= v << 13;
                v ^= v >> 17;
                v ^= v << 5;
                (v >> 24) as u8 / 3 + 170
            })
            .collect();
        let (wide, base) = (stroke_mask(&l, w, h), stroke_mask_body(&l, w, h));
        assert_eq!(wide, base);
        assert!(wide.contains(&true) && wide.contains(&false));
    }

    /// The mask is the 3×3 window's range as defined, at every size (one row or column too).
    #[test]
    fn strokes_are_the_windows_range() {
        for (w, h) in [(97, 41), (1, 5), (6, 1), (2, 2), (13, 3)] {
            let l: Vec<u8> = (crate::image::noise_pixels(w * h, (w * h) as u32).iter())
                .map(|p| p[0] / 2 + 100)
                .collect();
            let mask = stroke_mask(&l, w, h);
            for y in 0..h {
                for x in 0..w {
                    let window = (y.saturating_sub(1)..(y + 2).min(h))
                        .flat_map(|v| (x.saturating_sub(1)..(x + 2).min(w)).map(move |u| (u, v)));
                    let (lo, hi) = window.fold((255, 0), |(lo, hi), (u, v)| {
                        (l[v * w + u].min(lo), l[v * w + u].max(hi))
                    });
                    assert_eq!(
                        mask[y * w + x],
                        hi - lo > STROKE_RANGE,
                        "{w}x{h} ({x}, {y})"
                    );
                }
            }
        }
    }

    /// Four stems (a word's stemmed letters, 2×14 px) and, right after them, a component
    /// `extra` wide and 12 px tall with `holes` 6×5 holes, on white.
    fn word_with(extra: usize, holes: usize) -> (Vec<u8>, usize, usize) {
        let (w, h) = (120, 60);
        let mut l = vec![255u8; w * h];
        let mut ink = |x0: usize, y0: usize, x1: usize, y1: usize, v: u8| {
            for y in y0..y1 {
                l[y * w + x0..y * w + x1].fill(v);
            }
        };
        for k in 0..4 {
            ink(10 + 5 * k, 20, 12 + 5 * k, 34, 0);
        }
        ink(30, 22, 30 + extra, 34, 0);
        for k in 0..holes {
            ink(32 + 9 * k, 25, 38 + 9 * k, 30, 255);
        }
        (l, w, h)
    }

    /// Bold letters set tight merge into a component denser than a glyph ("uce" of
    /// "dairy-produce": 0.53 of its box): wider than tall, it joins the word beside it.
    #[test]
    fn merged_bold_letters_join_their_word() {
        // 30×12 with three holes: 270 of 32×14 pixels, 0.60.
        let (l, w, h) = word_with(30, 3);
        let blocks = detect(&l, w, h, [&[], &[]], &[]);
        assert_eq!(blocks.len(), 1, "{blocks:?}");
        assert!(blocks[0].x0 <= 10 && blocks[0].x1 >= 60, "{blocks:?}");
    }

    /// `stems` bars `width` wide and 14 tall, their left edges at `xs`, on white.
    fn bars(xs: &[usize], width: usize) -> (Vec<u8>, usize, usize) {
        let (w, h) = (160, 60);
        let mut l = vec![255u8; w * h];
        for &x0 in xs {
            for y in 20..34 {
                l[y * w + x0..y * w + x0 + width].fill(0);
            }
        }
        (l, w, h)
    }

    /// The "i" of heavy type between two words: a 3-px stem, denser (0.53 of its box with
    /// the halo) than any glyph, joins the word it stands in.
    #[test]
    fn a_heavy_lone_stem_joins_its_word() {
        let (l, w, h) = bars(&[10, 15, 20, 25, 48, 53, 58, 63], 2);
        let without = detect(&l, w, h, [&[], &[]], &[]);
        assert_eq!(without.len(), 2, "two words 21 px apart: {without:?}");
        let (mut l, w, h) = (l, w, h);
        for y in 20..34 {
            l[y * w + 36..y * w + 39].fill(0);
        }
        let blocks = detect(&l, w, h, [&[], &[]], &[]);
        assert_eq!(blocks.len(), 1, "{blocks:?}");
        assert!(blocks[0].x0 <= 10 && blocks[0].x1 >= 65, "{blocks:?}");
    }

    /// Draws a "0" (a 6×10 ring, strokes 2 px) with its top-left corner at `(x, y)`.
    fn zero(l: &mut [u8], w: usize, x: usize, y: usize) {
        for yy in y..y + 10 {
            for xx in x..x + 6 {
                let inner = (x + 2..x + 4).contains(&xx) && (y + 2..y + 8).contains(&yy);
                if !inner {
                    l[yy * w + xx] = 0;
                }
            }
        }
    }

    /// A lone "0" in line with labels of its size is text: at the start of a row of tick
    /// labels, or below a column of them sharing its right edge. Alone it is not (a lone
    /// round glyph is as likely a mark), and neither is a tick centred under a label.
    #[test]
    fn a_lone_zero_in_line_with_labels_is_text() {
        let (w, h) = (200, 100);
        // A row: "0" far left of "20" and "40".
        let mut l = vec![255u8; w * h];
        zero(&mut l, w, 10, 20);
        for x in [60, 100] {
            zero(&mut l, w, x, 20);
            zero(&mut l, w, x + 8, 20);
        }
        let row = detect(&l, w, h, [&[], &[]], &[]);
        assert_eq!(row.len(), 3, "{row:?}");
        assert!(row.iter().any(|b| b.x0 <= 10 && b.x1 <= 20), "{row:?}");
        // A column: "10" above "0", right edges aligned.
        let mut l = vec![255u8; w * h];
        for y in [20, 40] {
            zero(&mut l, w, 92, y);
        }
        zero(&mut l, w, 84, 20);
        let column = detect(&l, w, h, [&[], &[]], &[]);
        assert_eq!(column.len(), 2, "{column:?}");
        // Alone, and a tick centred under a label: no text but the label.
        let mut l = vec![255u8; w * h];
        zero(&mut l, w, 150, 70);
        zero(&mut l, w, 60, 20);
        zero(&mut l, w, 68, 20);
        for y in 34..44 {
            l[y * w + 66] = 0;
        }
        let alone = detect(&l, w, h, [&[], &[]], &[]);
        assert_eq!(alone.len(), 1, "{alone:?}");
        assert!(alone[0].x0 >= 59 && alone[0].y1 <= 32, "{alone:?}");
    }

    /// A glyph like a "7": a bar across its top and a stem down from it, in a 6×10 box.
    fn seven(l: &mut [u8], w: usize, x: usize, y: usize) {
        for xx in x..x + 6 {
            l[y * w + xx] = 0;
        }
        for yy in y..y + 10 {
            l[yy * w + x + 4] = 0;
        }
    }

    /// Single-digit tick labels of an x axis, evenly spaced in a row, are text where words of
    /// their size stand elsewhere; the same row where no word is of their size (tick marks)
    /// is not, nor are three such glyphs unevenly spaced.
    #[test]
    fn an_evenly_spaced_row_of_single_digits_is_text() {
        let (w, h) = (260, 100);
        let page = |xs: &[usize], word: bool| {
            let mut l = vec![255u8; w * h];
            for &x in xs {
                seven(&mut l, w, x, 60);
            }
            if word {
                // "00" far above: a y axis' label of the digits' size.
                zero(&mut l, w, 20, 10);
                zero(&mut l, w, 28, 10);
            }
            detect(&l, w, h, [&[], &[]], &[])
        };
        let row = page(&[60, 100, 140, 180], true);
        assert_eq!(row.iter().filter(|b| b.y0 >= 55).count(), 4, "{row:?}");
        let no_word = page(&[60, 100, 140, 180], false);
        assert!(no_word.is_empty(), "{no_word:?}");
        let uneven = page(&[40, 80, 150, 250], true);
        assert_eq!(
            uneven.iter().filter(|b| b.y0 >= 55).count(),
            0,
            "{uneven:?}"
        );
    }

    /// Thin bars in a row (a histogram's narrow bins) are stems without a word: no text.
    #[test]
    fn a_row_of_thin_bars_is_not_text() {
        let (l, w, h) = bars(&[10, 18, 26, 34, 42, 50], 4);
        assert_eq!(detect(&l, w, h, [&[], &[]], &[]), vec![]);
    }

    /// A filled swatch beside a word (a legend's) stays out of it, as does a dense square.
    #[test]
    fn swatches_and_dense_squares_stay_out_of_words() {
        for (extra, holes) in [(30, 0), (12, 1)] {
            let (l, w, h) = word_with(extra, holes);
            let blocks = detect(&l, w, h, [&[], &[]], &[]);
            assert_eq!(blocks.len(), 1, "{blocks:?}");
            assert!(blocks[0].x1 <= 30, "{extra}: {blocks:?}");
        }
    }

    /// A bold "B" of title type before its word: as dense as a swatch (more than half its box
    /// with the halo is ink) and shorter than display type, but its bowls leave the right side
    /// of its box open where a hollow box's walls close all four: it joins the word (left
    /// out, it was squeezed and hidden under the floating title: "ubble by group").
    #[test]
    fn a_bold_letter_with_counters_joins_its_word() {
        let (w, h) = (120, 60);
        let mut l = vec![255u8; w * h];
        let mut ink = |x0: usize, y0: usize, x1: usize, y1: usize| {
            for y in y0..y1 {
                l[y * w + x0..y * w + x1].fill(0);
            }
        };
        // The "B", 11×14 at (10, 20): a stem, three bars, two bowls' right sides.
        ink(10, 20, 14, 34);
        for y in [20, 26, 31] {
            ink(14, y, 19, y + 3);
        }
        ink(18, 22, 21, 26);
        ink(18, 28, 21, 32);
        // The rest of the word: stems 2 px wide, 2 px apart (stemmed letters).
        for k in 0..4 {
            ink(24 + 5 * k, 20, 26 + 5 * k, 34);
        }
        let blocks = detect(&l, w, h, [&[], &[]], &[]);
        assert_eq!(blocks.len(), 1, "{blocks:?}");
        assert!(blocks[0].x0 <= 10 && blocks[0].x1 >= 41, "{blocks:?}");
    }

    /// A dashboard tile's big bold value ("899"): each digit is as dense as a swatch, but
    /// holds counters, so the three make a text line.
    #[test]
    fn bold_digits_with_counters_are_text() {
        let (w, h) = (200, 100);
        let mut l = vec![255u8; w * h];
        for k in 0..3 {
            let x0 = 20 + 40 * k;
            // A 36×52 "8": ink with two 16×14 counters (0.76 of the box is ink, 0.6 with
            // the stroke mask's halo).
            for y in 20..72 {
                for x in x0..x0 + 36 {
                    let counter = (x0 + 10..x0 + 26).contains(&x)
                        && ((28..42).contains(&y) || (50..64).contains(&y));
                    if !counter {
                        l[y * w + x] = 0;
                    }
                }
            }
        }
        let blocks = detect(&l, w, h, [&[], &[]], &[]);
        assert_eq!(blocks.len(), 1, "{blocks:?}");
        assert!(blocks[0].x0 <= 20 && blocks[0].x1 >= 136, "{blocks:?}");
    }

    /// A waffle of dense cells 2 px apart merges into one component as dense as those
    /// digits, but the ground between its cells reaches the outside: no text.
    #[test]
    fn a_waffle_of_dense_cells_is_not_text() {
        let (w, h) = (200, 100);
        let mut l = vec![255u8; w * h];
        for j in 0..4 {
            for i in 0..10 {
                let (x0, y0) = (20 + 12 * i, 20 + 12 * j);
                for y in y0..y0 + 10 {
                    for x in x0..x0 + 10 {
                        l[y * w + x] = 40;
                    }
                }
            }
        }
        assert_eq!(detect(&l, w, h, [&[], &[]], &[]), vec![]);
    }
}
