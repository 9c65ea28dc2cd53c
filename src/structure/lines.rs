//! Long straight axis-aligned lines and edges: panel frames, axes, grid lines, bar sides.
//!
//! A horizontal edge is a run, along the boundary between two pixel rows, of pixels whose
//! luminance steps across the boundary as a drawn stroke's side does: by more than
//! [`STROKE_STEP`], and clearly more than the ground around it steps ([`Strokes`]); runs at
//! least [`min_length`] long (1-px gaps bridged) count: longer than a glyph's stroke, and
//! longer on a larger picture. A thin line (1–3 px) shows as two such edges a few rows apart
//! over the same span: it becomes one line along its middle, so that the mesh edge runs
//! through the line's pixels and the renderer can keep it one pixel sharp. A lone edge (the
//! top of a bar, the side of a filled panel) stays on its boundary.
//!
//! Shorter runs in a row, stepping the same way with gaps of a few pixels, are one line when
//! together they are long and mostly step: the tops of a waffle chart's cells, whose rows
//! wobble apart otherwise (each cell is held by nothing but its own saliency). Faint steps
//! (a plot's white grid on grey, a light panel border) make a line only when long, and bridge
//! the gaps where grid lines cross.

use super::mask::next_marked;

/// Least luminance step of a stroke's side on a clean ground: about a tenth of the lightness
/// scale (ΔL* ≈ 10, some 25 of the 255 sRGB levels), a difference that reads at a glance as a
/// drawn rule rather than as a tint of its ground. The usual light rules step more (#ddd on
/// white 34 levels, #dee2e6 30); fainter ones (#eee on white, a white grid on #ebebeb) are
/// weak lines at best.
const STROKE_STEP: i16 = 25;
/// On a textured ground (a dense scatter, pixel art, a photograph) a stroke's side must also
/// step clearly above the ground's own steps: by this many of their standard deviations, so
/// that the ground alone passes about 3 times in 1000 and cannot make a run.
const NOISE_SIGMAS: f32 = 3.0;
/// Standard deviation of normally spread steps over their median magnitude: the median,
/// unlike the spread itself, is not moved by the few lines crossing a tile.
const MEDIAN_TO_SIGMA: f32 = 1.4826;
/// Shortest line on a picture of screen resolution: longer than the tallest glyph of a
/// heading (about 30 px), so that no glyph's stroke is a line.
const GLYPH_PX: u32 = 32;
/// Shortest line as a share of the picture's shorter side: labels are set at about 1/50 of
/// it and headings at twice that, so on a larger (high-resolution) picture a line must also be
/// longer than 1/25 of its side to be longer than its glyphs.
const SIDE_SHARE: u32 = 25;
/// Least luminance step of a weak line's pixels, and its least length: light grid lines are
/// 15-30 levels off their ground (#ebebeb under white, #eee on white); texture edges that
/// faint rarely run straight this far.
const WEAK_STEP: i16 = 12;
const WEAK_MIN_PX: u32 = 150;
/// Gaps a weak line bridges: where a grid line crosses it, both sides of it are the crossing
/// line's colour and nothing steps.
const WEAK_GAP_PX: usize = 3;
/// Least share of a weak line's steps that go one way (a mark crossing it steps the other).
const WEAK_ONE_WAY: f32 = 0.8;
/// A chain of short runs ([`edge_runs`]): its gaps at most this wide, at least this many
/// runs, and at least this share of it stepping.
const CHAIN_GAP_PX: usize = 3;
const CHAIN_MIN_RUNS: usize = 3;
const CHAIN_COVER: f32 = 0.8;
/// Edges at most this far apart over the same span are the two sides of one thin line.
const THIN_PX: u32 = 3;

/// Shortest run that counts as a line in a `w × h` picture, in pixels: [`GLYPH_PX`], or
/// 1/[`SIDE_SHARE`] of the shorter side when that is longer.
pub(crate) fn min_length(w: usize, h: usize) -> u32 {
    (w.min(h) as u32 / SIDE_SHARE).max(GLYPH_PX)
}

/// An axis-aligned line: `pos` across it (a row or column boundary, or the middle of a thin
/// line), `from..to` along it, in image pixels.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Line {
    pub pos: f64,
    pub from: f64,
    pub to: f64,
    /// Thickness in pixels of a thin line (its pixels span `pos ± width/2`); 0 for an edge
    /// between two regions.
    pub width: u32,
}

/// What is found along one direction (edge runs, then lines): solid runs, chains of short
/// runs, and weak runs (see [`edge_runs`]).
#[derive(Default, Debug, PartialEq)]
pub(crate) struct Found<T = Line> {
    pub solid: Vec<T>,
    /// Rows of short collinear edges with small gaps: a waffle's cell tops.
    pub chained: Vec<T>,
    /// Long lines of low contrast: a plot's white grid on grey, a light panel border.
    pub weak: Vec<T>,
}

crate::simd::with_feature! {
    "avx2";
    /// Horizontal lines of a `w × h` luminance image.
    pub(crate) fn horizontal(l: &[u8], w: usize, h: usize) -> Found => horizontal_body {
        let runs = edge_runs(h, w, |b, steps| {
            // boundary b between rows b-1 and b: the step down it
            let (up, down) = (&l[(b - 1) * w..][..w], &l[b * w..][..w]);
            for ((s, &u), &d) in steps.iter_mut().zip(up).zip(down) {
                *s = d as i16 - u as i16;
            }
        });
        Found {
            solid: pair_thin(runs.solid),
            chained: pair_thin(runs.chained),
            weak: pair_thin(runs.weak),
        }
    }
}

/// Vertical lines of a `w × h` luminance image, given transposed ([`super::luma::transposed`],
/// shared with the sideways text search): column boundaries are walked as rows.
pub(crate) fn vertical(transposed: &[u8], w: usize, h: usize) -> Found {
    horizontal(transposed, h, w)
}

/// One run of steps along a boundary: `(boundary, from, to, rising)`, `rising` when the
/// luminance mostly grows across the boundary.
type EdgeRun = (u32, u32, u32, bool);

/// Runs along each interior boundary `1..n_boundaries` (positions `0..len`) of the steps
/// `edge` writes, 1-px gaps bridged:
/// * solid: steps of a stroke's side ([`Strokes`]), at least [`min_length`] long;
/// * chained: at least [`CHAIN_MIN_RUNS`] shorter such runs stepping the same way with gaps
///   up to [`CHAIN_GAP_PX`] that together are that long and mostly step ([`CHAIN_COVER`]): a
///   row of waffle cells, whose pieces are each too short to count;
/// * weak: steps above [`WEAK_STEP`], gaps up to [`WEAK_GAP_PX`] bridged, at least
///   [`WEAK_MIN_PX`] long, not mostly solid runs:
///   light grid lines and panel frames (a plot's white grid on grey, a #eee border), long
///   enough not to be a texture's edges. A weak run mostly of solid pieces, none of them
///   most of it, replaces them as one solid run: a line cut where lines of its colour cross.
#[inline(always)]
fn edge_runs(n_boundaries: usize, len: usize, edge: impl Fn(usize, &mut [i16])) -> Found<EdgeRun> {
    let min_len = min_length(len, n_boundaries);
    let strokes = Strokes::new(n_boundaries, len, min_len as usize, &edge);
    let mut out = Found::default();
    let mut steps = vec![0i16; len];
    let (mut stroke, mut faint) = (vec![0u8; len], vec![0u8; len]);
    let mut chain: Option<Chain> = None;
    for b in 1..n_boundaries {
        edge(b, &mut steps);
        strokes.mark(b, &steps, &mut stroke);
        for (f, &v) in faint.iter_mut().zip(&steps) {
            *f = (v.abs() > WEAK_STEP) as u8;
        }
        let first_solid = out.solid.len();
        for (start, end) in runs(&stroke, 1) {
            let rise = rising(&steps[start..end], &stroke[start..end]);
            let long = (end - start) as u32 >= min_len;
            if long {
                out.solid.push((b as u32, start as u32, end as u32, rise));
            }
            let cover = stroke[start..end].iter().filter(|&&s| s != 0).count();
            match &mut chain {
                Some(c) if !long && start - c.to <= CHAIN_GAP_PX && c.rise == rise => {
                    c.to = end;
                    c.runs += 1;
                    c.cover += cover;
                }
                _ => {
                    out.chained
                        .extend(chain.take().and_then(|c| c.run(b, min_len)));
                    chain = (!long).then_some(Chain {
                        from: start,
                        to: end,
                        runs: 1,
                        cover,
                        rise,
                    });
                }
            }
        }
        out.chained
            .extend(chain.take().and_then(|c| c.run(b, min_len)));
        // A line's side steps one way nearly all along; the rows of a noisy texture step
        // both ways by this much nearly everywhere.
        for (start, end) in runs(&faint, WEAK_GAP_PX) {
            if ((end - start) as u32) < WEAK_MIN_PX {
                continue;
            }
            let (up, down) = steps[start..end].iter().fold((0, 0), |(u, d), &v| {
                (u + (v > WEAK_STEP) as usize, d + (v < -WEAK_STEP) as usize)
            });
            if (up.max(down) as f32) < WEAK_ONE_WAY * (up + down) as f32 {
                continue;
            }
            let overlap =
                |s: &EdgeRun| (end.min(s.2 as usize)).saturating_sub(start.max(s.1 as usize));
            let (covered, longest) = (out.solid[first_solid..].iter())
                .map(overlap)
                .fold((0, 0), |(c, l), o| (c + o, l.max(o)));
            let run = (b as u32, start as u32, end as u32, up > down);
            if covered * 2 < end - start {
                out.weak.push(run);
            } else if longest * 2 < end - start {
                // Mostly solid pieces, none of them most of it: a solid line broken only where
                // lines of its colour cross it (nothing steps there), one solid run.
                let pieces = out.solid.split_off(first_solid);
                out.solid
                    .extend(pieces.into_iter().filter(|s| overlap(s) == 0));
                out.solid.push(run);
            }
        }
    }
    out
}

/// The least step of a stroke's side in each tile of the boundaries: [`STROKE_STEP`], or
/// [`NOISE_SIGMAS`] standard deviations of the tile's own steps where its ground is textured.
/// A tile is as wide as the shortest line: the ground a line is seen against, in which one
/// line is a few of the steps only.
struct Strokes {
    tile: usize,
    /// Tiles along a boundary.
    cols: usize,
    least: Vec<i16>,
}

/// The least step of a stroke's side on ground whose steps have this median magnitude.
fn least_step(median: usize) -> i16 {
    let noise = NOISE_SIGMAS * MEDIAN_TO_SIGMA * median as f32;
    STROKE_STEP.max(noise.round() as i16)
}

impl Strokes {
    /// The tiles of the steps `edge` writes along boundaries `1..n_boundaries`.
    ///
    /// Most tiles are clean ground, where half the steps or more are too small to raise the
    /// bar above [`STROKE_STEP`]: counting those decides them. Only the textured rest needs
    /// its median, from a histogram of a second pass over its rows.
    #[inline(always)]
    fn new(
        n_boundaries: usize,
        len: usize,
        tile: usize,
        edge: &impl Fn(usize, &mut [i16]),
    ) -> Strokes {
        let cols = len.div_ceil(tile);
        let rows = n_boundaries.div_ceil(tile);
        let quiet = (0..=255u16)
            .take_while(|&m| least_step(m as usize) == STROKE_STEP)
            .last()
            .unwrap_or(0);
        let mut steps = vec![0i16; len];
        let mut quiet_steps = vec![0u32; rows * cols];
        for b in 1..n_boundaries {
            edge(b, &mut steps);
            let row = &mut quiet_steps[b / tile * cols..][..cols];
            for (q, chunk) in row.iter_mut().zip(steps.chunks(tile)) {
                *q += chunk
                    .iter()
                    .map(|s| (s.unsigned_abs() <= quiet) as u32)
                    .sum::<u32>();
            }
        }
        let mut least = vec![STROKE_STEP; rows * cols];
        let mut hist = vec![[0u32; 256]; cols];
        for r in 0..rows {
            let bounds = (r * tile).max(1)..((r + 1) * tile).min(n_boundaries);
            let count = |c: usize| (bounds.len() * tile.min(len - c * tile)) as u32;
            let textured: Vec<usize> = (0..cols)
                .filter(|&c| 2 * quiet_steps[r * cols + c] < count(c))
                .collect();
            if textured.is_empty() {
                continue;
            }
            hist.iter_mut().for_each(|h| h.fill(0));
            for b in bounds.clone() {
                edge(b, &mut steps);
                for &c in &textured {
                    for &s in &steps[c * tile..][..tile.min(len - c * tile)] {
                        hist[c][s.unsigned_abs() as usize] += 1;
                    }
                }
            }
            for &c in &textured {
                let (n, mut seen) = (count(c), 0);
                let median = (hist[c].iter())
                    .position(|&k| {
                        seen += k;
                        2 * seen >= n
                    })
                    .unwrap_or(0);
                least[r * cols + c] = least_step(median);
            }
        }
        Strokes { tile, cols, least }
    }

    /// Marks where a step along boundary `b` is a stroke's side.
    #[inline(always)]
    fn mark(&self, b: usize, steps: &[i16], stroke: &mut [u8]) {
        let row = &self.least[b / self.tile * self.cols..][..self.cols];
        let tiles = stroke.chunks_mut(self.tile).zip(steps.chunks(self.tile));
        for ((marks, steps), &least) in tiles.zip(row) {
            for (m, &v) in marks.iter_mut().zip(steps) {
                *m = (v.abs() > least) as u8;
            }
        }
    }
}

/// Short runs along one boundary, so far one after another with small gaps.
struct Chain {
    from: usize,
    to: usize,
    runs: usize,
    /// Pixels that step.
    cover: usize,
    rise: bool,
}

impl Chain {
    /// The chain as one run, if it is one ([`edge_runs`]) in a picture whose lines are at
    /// least `min_len` long.
    fn run(&self, boundary: usize, min_len: u32) -> Option<EdgeRun> {
        let len = self.to - self.from;
        (self.runs >= CHAIN_MIN_RUNS
            && len as u32 >= min_len
            && self.cover as f32 >= CHAIN_COVER * len as f32)
            .then_some((boundary as u32, self.from as u32, self.to as u32, self.rise))
    }
}

/// Maximal runs `start..end` of the positions that are on (1, not 0), gaps up to `gap` px
/// bridged.
fn runs(on: &[u8], gap: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
    let mut i = 0;
    std::iter::from_fn(move || {
        i = next_marked(on, i, true)?;
        let start = i;
        let mut end = i + 1;
        loop {
            end = next_marked(on, end, false).unwrap_or(on.len());
            match (1..=gap).find(|&g| on.get(end + g) == Some(&1)) {
                Some(g) => end += g + 1,
                None => break,
            }
        }
        i = end;
        Some((start, end))
    })
}

/// Whether the steps of a run that are a stroke's side mostly rise.
fn rising(steps: &[i16], stroke: &[u8]) -> bool {
    steps
        .iter()
        .zip(stroke)
        .filter(|(_, &s)| s != 0)
        .map(|(&v, _)| v.signum() as i64)
        .sum::<i64>()
        > 0
}

/// Turns edge runs into lines: two runs of opposite steps (into the line and out of it) at
/// most [`THIN_PX`] apart covering mostly the same span are one thin line along their middle.
/// Two steps the same way are a ramp (a line's faint antialiased side, then the line): the
/// nearer opposite step is the line's other side.
fn pair_thin(mut edges: Vec<EdgeRun>) -> Vec<Line> {
    edges.sort_unstable();
    let mut used = vec![false; edges.len()];
    let mut out = Vec::new();
    for i in 0..edges.len() {
        if used[i] {
            continue;
        }
        let (b, f, t, rise) = edges[i];
        // A ramp: the next step the same way over the same span is where this line begins.
        let ramp = edges[i + 1..]
            .iter()
            .take_while(|e| e.0 <= b + 1)
            .any(|&(b2, f2, t2, r2)| {
                b2 == b + 1 && r2 == rise && {
                    let overlap = t.min(t2) as i64 - f.max(f2) as i64;
                    overlap * 10 >= (t - f).min(t2 - f2) as i64 * 8
                }
            });
        if ramp {
            continue;
        }
        let mut partner = None;
        for j in i + 1..edges.len() {
            let (b2, f2, t2, r2) = edges[j];
            if b2 > b + THIN_PX {
                break;
            }
            if used[j] || b2 == b || r2 == rise {
                continue;
            }
            let overlap = t.min(t2) as i64 - f.max(f2) as i64;
            let shorter = (t - f).min(t2 - f2) as i64;
            if overlap * 10 >= shorter * 8 {
                partner = Some(j);
                break;
            }
        }
        match partner {
            Some(j) => {
                used[j] = true;
                let (b2, f2, t2, _) = edges[j];
                out.push(Line {
                    pos: (b + b2) as f64 / 2.0,
                    from: f.max(f2) as f64,
                    to: t.min(t2) as f64,
                    width: b2 - b,
                });
            }
            None => out.push(Line {
                pos: b as f64,
                from: f as f64,
                to: t as f64,
                width: 0,
            }),
        }
        used[i] = true;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grey ground with noise, strokes and boxes: lines of every kind, and texture.
    fn busy_luma(w: usize, h: usize) -> Vec<u8> {
        let mut v = 0x1234_5678u32;
        (0..w * h)
            .map(|i| {
                v ^= v << 13;
                v ^= v >> 17;
                v ^= v << 5;
                let (x, y) = (i % w, i / w);
                let noise = (v >> 28) as u8;
                match (x, y) {
                    _ if y % 37 == 5 && x > 20 => 30,
                    _ if x % 53 == 9 && y > 10 => 60,
                    _ if (x / 11 + y / 7) % 9 == 0 => 200 - noise,
                    _ => 235 + noise,
                }
            })
            .collect()
    }

    #[test]
    fn every_build_finds_the_same_lines() {
        let (w, h) = (203, 151);
        let l = busy_luma(w, h);
        assert_eq!(horizontal(&l, w, h), horizontal_body(&l, w, h));
        assert!(!horizontal(&l, w, h).solid.is_empty());
    }

    #[test]
    fn a_thin_line_is_one_line_through_its_middle_and_an_edge_stays_an_edge() {
        let (w, h) = (120usize, 100usize);
        let mut l = vec![250u8; w * h];
        for x in 10..110 {
            l[20 * w + x] = 40; // 1-px line on row 20
        }
        for y in 40..100 {
            for x in 0..100 {
                l[y * w + x] = 90; // a filled block: one edge at boundary 40
            }
        }
        let hl = horizontal(&l, w, h).solid;
        assert_eq!(hl.len(), 2, "{hl:?}");
        assert_eq!(
            hl[0],
            Line {
                pos: 20.5,
                from: 10.0,
                to: 110.0,
                width: 1
            }
        );
        assert_eq!(
            hl[1],
            Line {
                pos: 40.0,
                from: 0.0,
                to: 100.0,
                width: 0
            }
        );
        let vl = vertical(&crate::structure::luma::transposed(&l, w, h), w, h).solid;
        assert_eq!(
            vl,
            vec![Line {
                pos: 100.0,
                from: 40.0,
                to: 100.0,
                width: 0
            }]
        );
    }

    /// Cells with 2-px gaps: the rows' tops and bottoms are chained lines, as are the cells'
    /// sides down each column of a 3-row waffle; a row with cells barely wider
    /// than its gaps (a text's baseline, a sparse dotted rule) is not.
    #[test]
    fn a_row_of_cells_is_a_chained_line_and_a_sparse_row_is_not() {
        let cells = |cell: usize, gap: usize, rows: usize| {
            let (w, h) = (200usize, 80usize);
            let mut l = vec![250u8; w * h];
            for r in 0..rows {
                let y0 = 10 + r * (cell + gap);
                for c in 0..10 {
                    let x0 = 10 + c * (cell + gap);
                    for y in y0..y0 + cell {
                        l[y * w + x0..y * w + x0 + cell].fill(40);
                    }
                }
            }
            (
                horizontal(&l, w, h),
                vertical(&crate::structure::luma::transposed(&l, w, h), w, h),
            )
        };
        let (h, v) = cells(14, 2, 3);
        assert!(h.solid.is_empty() && v.solid.is_empty());
        // Top of the first row, bottom of the last, and the 2-px white gaps between rows.
        let rows: Vec<(f64, f64, f64)> = h.chained.iter().map(|l| (l.pos, l.from, l.to)).collect();
        assert_eq!(
            rows,
            vec![
                (10.0, 10.0, 168.0),
                (25.0, 10.0, 168.0),
                (41.0, 10.0, 168.0),
                (56.0, 10.0, 168.0)
            ]
        );
        // Down the columns: the first cell's left side, the last one's right, 9 gaps between.
        assert_eq!(v.chained.len(), 11, "{:?}", v.chained);
        assert!(v.chained.iter().all(|l| (l.from, l.to) == (10.0, 56.0)));
        let (h, _) = cells(4, 3, 1);
        assert!(
            h.chained.is_empty() && h.solid.is_empty(),
            "{:?}",
            h.chained
        );
    }

    /// A plot's white grid lines on its grey area (20 levels apart) are weak lines when long
    /// enough; a short one is a texture's edge, and a dark rule is solid, not also weak.
    #[test]
    fn faint_long_lines_are_weak_lines() {
        let (w, h) = (300usize, 120usize);
        let mut l = vec![235u8; w * h];
        l[30 * w + 20..30 * w + 280].fill(255); // grid line, 260 px
        for y in 0..h {
            l[y * w + 150..y * w + 152].fill(255); // a crossing one: no step there
        }
        l[60 * w + 20..60 * w + 120].fill(255); // 100 px: too short to be sure
        l[90 * w + 20..90 * w + 280].fill(40); // a dark rule
        let found = horizontal(&l, w, h);
        let solid: Vec<f64> = found.solid.iter().map(|l| l.pos).collect();
        assert_eq!(solid, vec![90.5]);
        assert_eq!(
            found.weak,
            vec![Line {
                pos: 30.5,
                from: 20.0,
                to: 280.0,
                width: 1
            }]
        );
    }

    /// A grid line crossed by grid lines of its colour steps nowhere across them: its solid
    /// pieces are one solid line, as its weak run, which bridges the crossings, shows. Its two
    /// sides pair into one thin line over all of it.
    #[test]
    fn a_line_crossed_by_lines_of_its_colour_is_one_line() {
        let (w, h) = (300usize, 100usize);
        let mut l = vec![255u8; w * h];
        l[50 * w + 20..50 * w + 280].fill(200);
        l[51 * w + 20..51 * w + 280].fill(200);
        for row in l.chunks_exact_mut(w) {
            row[100..103].fill(200);
            row[200..203].fill(200);
        }
        let found = horizontal(&l, w, h);
        assert!(found.weak.is_empty(), "{:?}", found.weak);
        assert_eq!(
            found.solid,
            vec![Line {
                pos: 51.0,
                from: 20.0,
                to: 280.0,
                width: 2
            }]
        );
    }

    /// Noise steps by more than a weak line's step between nearly every two rows, both ways:
    /// no line.
    #[test]
    fn noise_makes_no_weak_lines() {
        let (w, h) = (400usize, 60usize);
        let mut s = 0x5eed_u32;
        let l: Vec<u8> = (0..w * h)
            .map(|_| {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                60 + (s >> 24) as u8 % 130
            })
            .collect();
        assert!(horizontal(&l, w, h).weak.is_empty());
        assert!(
            vertical(&crate::structure::luma::transposed(&l, w, h), w, h)
                .weak
                .is_empty()
        );
    }

    /// A glyph's stroke (a heading's "l", 30 px) is not a line and a rule a little longer is;
    /// on a picture twice as large (a rendering at twice the resolution, its glyphs twice as
    /// tall) both lengths double.
    #[test]
    fn the_shortest_line_is_longer_than_a_glyph_and_grows_with_the_picture() {
        let lines = |side: usize, lens: &[usize]| {
            let mut l = vec![250u8; side * side];
            for (i, &n) in lens.iter().enumerate() {
                let y = 10 + 10 * i;
                l[y * side + 10..y * side + 10 + n].fill(0);
            }
            let found = horizontal(&l, side, side);
            assert!(found.chained.is_empty() && found.weak.is_empty());
            (found.solid.iter())
                .map(|l| (l.to - l.from) as usize)
                .collect::<Vec<_>>()
        };
        assert_eq!(min_length(800, 600), GLYPH_PX);
        assert_eq!(lines(600, &[30, 36]), vec![36]);
        assert_eq!(min_length(1600, 1600), 2 * GLYPH_PX);
        assert_eq!(lines(1600, &[60, 36, 72]), vec![72]);
    }

    /// On a ground of three shades at random (pixel art, a dense scatter) steps as large as a
    /// light rule's run along every row; only a rule stepping clearly above them is a line.
    /// A light rule on a clean ground is one.
    #[test]
    fn a_textured_ground_makes_no_lines_and_a_clear_rule_on_it_does() {
        let (w, h) = (300usize, 200usize);
        let mut s = 0x5eed_u32;
        let mut l: Vec<u8> = (0..w * h)
            .map(|_| {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                [175, 210, 245][(s >> 24) as usize % 3]
            })
            .collect();
        // Taken against a clean ground's step, the texture alone would make lines.
        let step = |b: usize, x: usize| l[b * w + x] as i16 - l[(b - 1) * w + x] as i16;
        let texture_runs: usize = (1..h)
            .map(|b| {
                let on: Vec<u8> = (0..w)
                    .map(|x| (step(b, x).abs() > STROKE_STEP) as u8)
                    .collect();
                runs(&on, 1)
                    .filter(|(s, e)| (e - s) as u32 >= min_length(w, h))
                    .count()
            })
            .sum();
        assert!(texture_runs > 10, "{texture_runs}");
        assert!(horizontal(&l, w, h).solid.is_empty());
        assert!(
            vertical(&crate::structure::luma::transposed(&l, w, h), w, h)
                .solid
                .is_empty()
        );
        l[100 * w + 20..100 * w + 280].fill(0); // a black rule across the texture
        l[190 * w..200 * w].fill(255); // a clean strip, a #ddd rule in it
        l[195 * w + 20..195 * w + 280].fill(0xdd);
        let found: Vec<(f64, f64, f64)> = (horizontal(&l, w, h).solid.iter())
            .map(|l| (l.pos, l.from, l.to))
            .collect();
        assert_eq!(found[0], (100.5, 20.0, 280.0));
        assert!(found.contains(&(195.5, 20.0, 280.0)), "{found:?}");
    }

    proptest::proptest! {
        /// Runs found eight positions at a time are the runs a walk one position at a time
        /// finds, with any gap bridged.
        #[test]
        fn runs_are_found_as_a_walk_finds_them(
            on in proptest::collection::vec(proptest::prop_oneof![3 => proptest::strategy::Just(0u8), 2 => proptest::strategy::Just(1u8)], 0..70),
            gap in 0usize..4,
        ) {
            let at = |i: usize| on.get(i) == Some(&1);
            let mut walked = Vec::new();
            let mut i = 0;
            while i < on.len() {
                if !at(i) {
                    i += 1;
                    continue;
                }
                let start = i;
                let mut end = i + 1;
                loop {
                    if at(end) {
                        end += 1;
                    } else if let Some(g) = (1..=gap).find(|&g| at(end + g)) {
                        end += g + 1;
                    } else {
                        break;
                    }
                }
                walked.push((start, end));
                i = end;
            }
            proptest::prop_assert_eq!(runs(&on, gap).collect::<Vec<_>>(), walked);
        }
    }
}
