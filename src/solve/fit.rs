//! How large salient content can stay: the target scale of the size prior.
//!
//! The size prior pulls salient triangles towards scale 1. When the salient content of a row is
//! wider than the target (a map that fills the canvas, shrunk to half width), scale 1 cannot
//! hold; the energy then keeps the big salient regions near 1 and crushes whatever small
//! salient thing is left next to them (a legend at the edge). Asking instead for the largest
//! uniform scale at which the salient content fits lets everything shrink together and stay
//! in shape.
//!
//! The estimate: per row, the number of mark pixels (importance `S_m` at least the prior's
//! threshold; not the VSM, whose 3-px context band makes every line 9 px thick) that are not
//! part of a thin horizontal line: a rule, an axis or a grid line can shrink along its length at
//! no cost, so a pixel only counts if it belongs to a vertical run of at least
//! [`MIN_THICKNESS_PX`] mark pixels. Per row, the target width with a margin for the
//! background that must remain between marks, less the width the row's text keeps at its own
//! fit ([`text_fit_scales`]: text is read, a chart beside it reads as well narrower), over the
//! row's count, is the scale at which that row fits; the 2nd percentile of those (the 98th
//! percentile of the counts when there is no text) gives the scale; likewise per column for
//! the height. Rows are not independent (the mesh is continuous), so
//! this is a lower bound on the shrink needed, which is the side to err on: a prior slightly
//! too large is repaired by the fold rounds, a prior too small would shrink marks for nothing.

use crate::image::Size;
use crate::saliency::Vsm;

/// Share of a row text may take in the output.
const TEXT_FILL: f64 = 0.95;
/// Share of a row the salient content may take in the output.
const FILL: f64 = 0.85;
/// Percentile of rows (columns) whose salient width must fit.
const PERCENTILE: f64 = 0.98;
/// Thinner salient runs across a row (column) are lines along it, free to shrink.
const MIN_THICKNESS_PX: usize = 3;
/// Gaps between marks up to this many pixels belong to the block the marks form.
const MAX_GAP_PX: u32 = 8;

/// Pixels a line must keep for its marks: the marks themselves and the gaps shorter than
/// [`MAX_GAP_PX`] between them (a dense cluster of dots is one block, not its dots alone).
fn extent(line: impl Iterator<Item = bool>, max_gap: u32) -> u32 {
    let mut total = 0u32;
    let mut gap: Option<u32> = None; // None before the first mark
    for on in line {
        extent_step(&mut total, &mut gap, on, max_gap);
    }
    total
}

/// One pixel of [`extent`].
#[inline]
fn extent_step(total: &mut u32, gap: &mut Option<u32>, on: bool, max_gap: u32) {
    if on {
        if let Some(g) = *gap {
            if g < max_gap {
                *total += g;
            }
        }
        *total += 1;
        *gap = Some(0);
    } else if let Some(g) = gap.as_mut() {
        *g += 1;
    }
}

/// The scales salient content should keep: along x and y for content free to scale each axis
/// apart, each in `[its axis's linear scale, 1]`; and one for marks, which keep their shape.
///
/// Shrinking, marks take the smaller of the two axes' fits. When the canvas's area grows, it
/// gives room, and like Wang et al.'s scale-and-stretch (and the paper's free `s_t`) marks grow
/// with it, uniformly, by the geometric mean of the two axes' scales, as far as the salient
/// content's room along each axis allows (a canvas made wider at the same height lets dots grow only as
/// far as the columns they crowd have space above and below them).
pub(crate) fn salient_fit(
    vsm: &Vsm,
    target: Size,
    threshold: f32,
    text: &[crate::structure::TextBlock],
    text_scales: &[f64],
) -> ([f64; 2], f64) {
    let [rx, ry] = salient_room(vsm, target, threshold, text, text_scales);
    let size = vsm.size();
    let lx = target.width as f64 / size.width as f64;
    let ly = target.height as f64 / size.height as f64;
    let free = [rx.min(1.0).max(lx.min(1.0)), ry.min(1.0).max(ly.min(1.0))];
    let shrink = free[0].min(free[1]);
    let grow = (lx * ly).sqrt();
    let similar = if grow <= 1.0 {
        shrink
    } else {
        grow.min(rx).min(ry).max(shrink)
    };
    (free, similar)
}

/// Per axis, the scale at which the salient content fits: `FILL` times the target, less the
/// width (height) the text beside it keeps, over its extent; unclamped (infinite without
/// salient content, 0 where text alone fills a line).
fn salient_room(
    vsm: &Vsm,
    target: Size,
    threshold: f32,
    text: &[crate::structure::TextBlock],
    text_scales: &[f64],
) -> [f64; 2] {
    let grid = vsm.grid_size();
    let sc = vsm.scale() as usize;
    // Pixel lengths in map cells.
    let cells = MarkCells {
        w: grid.width as usize,
        h: grid.height as usize,
        sc,
        threshold,
        min_thickness: MIN_THICKNESS_PX.div_ceil(sc),
        max_gap: MAX_GAP_PX.div_ceil(sc as u32),
    };
    // Text has a fit of its own ([`text_fit_scales`]): its pixels do not count here.
    let mut masked;
    let imp = if text.is_empty() {
        vsm.importance()
    } else {
        masked = vsm.importance().to_vec();
        cells.mask_text(&mut masked, text);
        &masked[..]
    };
    let rows = cells.row_extents(imp);
    let cols = cells.column_extents(imp);
    let (text_rows, text_cols) = cells.text_lengths(text, text_scales);
    let (tw, th) = (target.width as f64, target.height as f64);
    // Rows were counted in image pixels, columns in map cells.
    let fit_x = percentile_room(&rows, &text_rows, 1.0, tw);
    let fit_y = percentile_room(&cols, &text_cols, sc as f64, th);
    [fit_x, fit_y]
}

/// The importance map's grid (`w × h` cells of `sc` pixels) and what counts as a mark on it:
/// importance at least `threshold`, in runs of at least `min_thickness` cells across the line
/// measured, with gaps up to `max_gap` cells kept with the marks around them.
struct MarkCells {
    w: usize,
    h: usize,
    sc: usize,
    threshold: f32,
    min_thickness: usize,
    max_gap: u32,
}

impl MarkCells {
    /// The cells `(x0, x1, y0, y1)` (ends excluded) a text block covers, in the grid.
    fn cells_of(&self, b: &crate::structure::TextBlock) -> (usize, usize, usize, usize) {
        let (sc, w, h) = (self.sc, self.w, self.h);
        (
            (b.x0 as usize / sc).min(w),
            (b.x1 as usize).div_ceil(sc).min(w),
            (b.y0 as usize / sc).min(h),
            (b.y1 as usize).div_ceil(sc).min(h),
        )
    }

    /// Zeroes the importance under every text block.
    fn mask_text(&self, imp: &mut [f32], text: &[crate::structure::TextBlock]) {
        let w = self.w;
        for b in text {
            let (x0, x1, y0, y1) = self.cells_of(b);
            for y in y0..y1 {
                imp[y * w + x0..y * w + x1].fill(0.0);
            }
        }
    }

    /// Per row, the pixels its marks keep ([`extent`]), counting only mark cells in vertical
    /// runs of at least `min_thickness` (a horizontal line shrinks along its length for free).
    /// A cell's run is known when the run ends, so rows are filled in per column run, walking
    /// rows in order (per-column counters, row-major reads).
    fn row_extents(&self, imp: &[f32]) -> Vec<u32> {
        let (w, h) = (self.w, self.h);
        let mut thick_v = vec![false; w * h];
        let mut run = vec![0u32; w];
        for y in 0..=h {
            for x in 0..w {
                if y < h && imp[y * w + x] >= self.threshold {
                    run[x] += 1;
                    continue;
                }
                let len = run[x] as usize;
                if len >= self.min_thickness {
                    for yy in y - len..y {
                        thick_v[yy * w + x] = true;
                    }
                }
                run[x] = 0;
            }
        }
        thick_v
            .chunks_exact(w)
            .map(|r| extent(r.iter().copied(), self.max_gap) * self.sc as u32)
            .collect()
    }

    /// Per column, in cells, what [`MarkCells::row_extents`] is per row: mark cells in
    /// horizontal runs of at least `min_thickness`, with the gap logic of [`extent`] run per
    /// column through per-column state (row-major reads).
    fn column_extents(&self, imp: &[f32]) -> Vec<u32> {
        let (w, h) = (self.w, self.h);
        let mut cols = vec![0u32; w];
        let mut gap: Vec<Option<u32>> = vec![None; w];
        for y in 0..h {
            let row = &imp[y * w..][..w];
            let mut len = 0usize;
            for x in 0..=w {
                if x < w && row[x] >= self.threshold {
                    len += 1;
                    continue;
                }
                let thick = len >= self.min_thickness;
                for xx in x - len..x {
                    extent_step(&mut cols[xx], &mut gap[xx], thick, self.max_gap);
                }
                if x < w {
                    extent_step(&mut cols[x], &mut gap[x], false, self.max_gap);
                }
                len = 0;
            }
        }
        cols
    }

    /// Per row and per column, the output pixels the text on it keeps at its own fit
    /// ([`text_fit_scales`]); the salient content beside it shares what is left. Without this
    /// a legend beside a waffle chart is squeezed to unreadable so that the chart can keep the
    /// scale the whole row would allow.
    fn text_lengths(
        &self,
        text: &[crate::structure::TextBlock],
        text_scales: &[f64],
    ) -> (Vec<f64>, Vec<f64>) {
        let mut text_rows = vec![0f64; self.h];
        let mut text_cols = vec![0f64; self.w];
        for (k, b) in text.iter().enumerate() {
            let s = text_scales.get(k).copied().unwrap_or(1.0);
            let (x0, x1, y0, y1) = self.cells_of(b);
            for r in &mut text_rows[y0..y1] {
                *r += s * b.x1.saturating_sub(b.x0) as f64;
            }
            for c in &mut text_cols[x0..x1] {
                *c += s * b.y1.saturating_sub(b.y0) as f64;
            }
        }
        (text_rows, text_cols)
    }
}

/// Per line, the scale at which its salient extent (`extents` times `unit` pixels) fits beside
/// its text in `FILL` of `out` pixels; the low [`PERCENTILE`] of those (the 98th percentile of
/// extents when there is no text). Infinite without salient content.
fn percentile_room(extents: &[u32], text: &[f64], unit: f64, out: f64) -> f64 {
    let mut f: Vec<f64> = extents
        .iter()
        .zip(text)
        .map(|(&e, &t)| {
            let e = e as f64 * unit;
            if e > 0.0 {
                (FILL * out - t).max(0.0) / e
            } else {
                f64::INFINITY
            }
        })
        .collect();
    f.sort_unstable_by(f64::total_cmp);
    let i = ((f.len() as f64 - 1.0) * (1.0 - PERCENTILE)).round() as usize;
    f.get(i).copied().unwrap_or(f64::INFINITY)
}

/// The scale each text block can keep, at most 1.
///
/// Lines are walls: every vertex on a vertical line shares its x, so the rows a line crosses
/// are cut there into cells whose output widths hold for the line's whole length. A cell
/// (between two walls, over the rows both span) needs the width of its widest row of text.
/// Each row's target width (with the margin of [`TEXT_FILL`]) is shared among its cells in
/// proportion to their needs, and a block must fit its share beside the rest of its row's
/// text in its cell; likewise for columns, horizontal lines and the target height. A title
/// alone on its row keeps more than a legend crowded into one row with other labels, and a
/// table in a panel beside a crowded one shrinks even where its own rows are short.
pub(crate) fn text_fit_scales(
    text: &[crate::structure::TextBlock],
    structure: &crate::structure::Structure,
    size: Size,
    target: Size,
) -> Vec<f64> {
    let fx = axis_fit(text, &structure.vertical, size, target, true);
    let fy = axis_fit(text, &structure.horizontal, size, target, false);
    fx.iter()
        .zip(&fy)
        .map(|(a, b)| a.min(*b).min(1.0))
        .collect()
}

/// Least gap between two neighbouring labels of one axis, output pixels.
const LABEL_GAP_PX: f64 = 4.0;
/// The share of the plain linear scale a data area is expected to keep at least (it gives
/// some of its room to the text around it).
const AREA_SCALE_GUESS: f64 = 0.9;

/// Lowers `scales` of the text blocks tied to a data area ([`super::boundary::attachments`])
/// so that neighbours along one axis (tick labels) do not overlap once the area is scaled:
/// their centres move with the area, their sizes with their own scale.
pub(crate) fn attached_fit(
    text: &[crate::structure::TextBlock],
    attached: &[Option<super::boundary::Attached>],
    size: Size,
    target: Size,
    scales: &mut [f64],
) {
    let mut groups: std::collections::HashMap<(usize, bool), Vec<usize>> = Default::default();
    for (k, a) in attached.iter().enumerate() {
        if let Some(a) = a {
            groups.entry((a.area, a.along_x)).or_default().push(k);
        }
    }
    for ((_, along_x), mut ks) in groups {
        let est = AREA_SCALE_GUESS
            * if along_x {
                target.width as f64 / size.width as f64
            } else {
                target.height as f64 / size.height as f64
            };
        let extent = |k: usize| {
            let b = &text[k];
            if along_x {
                (b.x0 as f64, b.x1 as f64)
            } else {
                (b.y0 as f64, b.y1 as f64)
            }
        };
        ks.sort_by(|&a, &b| extent(a).0.total_cmp(&extent(b).0));
        for w in ks.windows(2) {
            let ((a0, a1), (b0, b1)) = (extent(w[0]), extent(w[1]));
            // Blocks side by side across the axis (two lines of one title) do not crowd.
            if b0 < a1 {
                continue;
            }
            let apart = ((b0 + b1) - (a0 + a1)) / 2.0 * est - LABEL_GAP_PX;
            let need = ((a1 - a0) + (b1 - b0)) / 2.0;
            let fit = (apart / need).clamp(0.05, 1.0);
            for &k in w {
                scales[k] = scales[k].min(fit);
            }
        }
    }
}

/// [`text_fit_scales`] along one axis: x (`horizontal`, walls are vertical lines) or y.
fn axis_fit(
    text: &[crate::structure::TextBlock],
    walls: &[crate::structure::Line],
    size: Size,
    target: Size,
    horizontal: bool,
) -> Vec<f64> {
    use std::collections::HashMap;
    // Along the squeezed axis `a` (x for rows), across it `c`.
    let (len_a, len_c, out) = if horizontal {
        (size.width, size.height, target.width)
    } else {
        (size.height, size.width, target.height)
    };
    let spans: Vec<(u32, u32, u32, u32)> = text
        .iter()
        .map(|b| {
            let s = if horizontal {
                (b.x0, b.x1, b.y0, b.y1)
            } else {
                (b.y0, b.y1, b.x0, b.x1)
            };
            (s.0, s.1, s.2.min(len_c), s.3.min(len_c))
        })
        .collect();
    // Bands of rows between the places where a block or a wall starts or ends.
    let mut cuts: Vec<u32> = vec![0, len_c];
    for &(_, _, c0, c1) in &spans {
        cuts.extend([c0, c1]);
    }
    for l in walls {
        cuts.extend([
            (l.from.max(0.0) as u32).min(len_c),
            (l.to.ceil().max(0.0) as u32).min(len_c),
        ]);
    }
    cuts.sort_unstable();
    cuts.dedup();
    type Cell = (usize, usize);
    struct Band {
        range: (u32, u32),
        cells: Vec<Cell>,
        /// Text along the band in each cell, and each block's cell.
        sums: HashMap<Cell, f64>,
        of_block: Vec<(usize, Cell)>,
    }
    let mut need: HashMap<Cell, f64> = HashMap::new();
    let mut bands = Vec::new();
    for w in cuts.windows(2) {
        let (c0, c1) = (w[0], w[1]);
        // Walls across this band, sorted along it; the canvas sides bound every band.
        let cf = c0 as f64 + 0.5;
        let mut ws: Vec<(f64, usize)> = walls
            .iter()
            .enumerate()
            .filter(|(_, l)| l.from <= cf && cf < l.to)
            .map(|(i, l)| (l.pos, i))
            .collect();
        ws.push((0.0, usize::MAX - 1));
        ws.push((len_a as f64, usize::MAX));
        ws.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut band = Band {
            range: (c0, c1),
            cells: ws.windows(2).map(|w| (w[0].1, w[1].1)).collect(),
            sums: HashMap::new(),
            of_block: Vec::new(),
        };
        for (i, &(a0, a1, b0, b1)) in spans.iter().enumerate() {
            if b0 >= c1 || b1 <= c0 {
                continue;
            }
            let mid = (a0 + a1) as f64 / 2.0;
            let k = ws.partition_point(|w| w.0 <= mid).clamp(1, ws.len() - 1);
            let cell = (ws[k - 1].1, ws[k].1);
            *band.sums.entry(cell).or_default() += (a1 - a0) as f64;
            band.of_block.push((i, cell));
        }
        for (&cell, &v) in &band.sums {
            let e = need.entry(cell).or_default();
            *e = e.max(v);
        }
        bands.push(band);
    }
    let mut fit = vec![1.0f64; text.len()];
    for band in &bands {
        if band.range.0 == band.range.1 {
            continue;
        }
        // The row's width is shared among its cells in proportion to what they need.
        let total: f64 = band.cells.iter().filter_map(|c| need.get(c)).sum();
        for &(i, cell) in &band.of_block {
            let width = TEXT_FILL * out as f64 * need[&cell] / total;
            fit[i] = fit[i].min(width / band.sums[&cell]);
        }
    }
    fit
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::saliency::VsmBuilder;
    use crate::structure::{Line, Structure, TextBlock};

    #[test]
    fn extent_closes_small_gaps_only() {
        let line = |s: &str| extent(s.chars().map(|c| c == '#'), MAX_GAP_PX);
        assert_eq!(line("..###..."), 3);
        assert_eq!(line("###....###"), 10);
        assert_eq!(line("###...........###"), 6);
        assert_eq!(line("........"), 0);
    }

    #[test]
    fn lines_do_not_count_as_content_that_must_keep_scale() {
        let size = Size::new(400, 200).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        for y in (20..200).step_by(20) {
            for x in 0..400 {
                img.set(x, y, [0, 0, 0, 255]);
            }
        }
        for x in [10u32, 390] {
            for y in 0..200 {
                img.set(x, y, [0, 0, 0, 255]);
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        assert_eq!(
            salient_fit(&vsm, Size::new(200, 200).unwrap(), 0.4, &[], &[]).0,
            [1.0, 1.0]
        );
        assert_eq!(
            salient_fit(&vsm, Size::new(400, 100).unwrap(), 0.4, &[], &[]).0,
            [1.0, 1.0]
        );
    }

    /// A dark checkerboard of `cell`-px squares over `xs × ys`: salient in every row it spans.
    fn checker(img: &mut Image, xs: std::ops::Range<u32>, ys: std::ops::Range<u32>, cell: u32) {
        for y in ys {
            for x in xs.clone() {
                if (x / cell + y / cell).is_multiple_of(2) {
                    img.set(x, y, [20, 20, 20, 255]);
                }
            }
        }
    }

    /// Three 10-px squares far apart on a 400×200 canvas.
    fn three_marks() -> Image {
        let mut img = Image::filled(Size::new(400, 200).unwrap(), [255; 4]);
        for (cx, cy) in [(50u32, 50u32), (200, 120), (330, 80)] {
            for y in cy - 5..cy + 5 {
                for x in cx - 5..cx + 5 {
                    img.set(x, y, [215, 25, 28, 255]);
                }
            }
        }
        img
    }

    #[test]
    fn sparse_marks_keep_scale_one_and_wide_content_shrinks() {
        let size = Size::new(400, 200).unwrap();
        let vsm = VsmBuilder::new().build(three_marks().as_ref());
        assert_eq!(
            salient_fit(&vsm, Size::new(200, 200).unwrap(), 0.4, &[], &[]).0,
            [1.0, 1.0]
        );

        // A salient band 300 px wide in every row cannot keep scale 1 in 200 px.
        let mut img = Image::filled(size, [255; 4]);
        checker(&mut img, 50..350, 0..200, 3);
        let vsm = VsmBuilder::new().build(img.as_ref());
        let [sx, sy] = salient_fit(&vsm, Size::new(200, 200).unwrap(), 0.4, &[], &[]).0;
        assert!((0.5..0.7).contains(&sx), "{sx}");
        // The height does not change: nothing to fit along y but the margin.
        assert!(sy > sx, "{sy}");
    }

    /// Marks grow with the canvas's area by the geometric mean of the axes' scales, as far
    /// as the room of their columns allows; shrinking, they keep the smaller fit.
    #[test]
    fn marks_grow_with_a_growing_canvas_as_far_as_the_room_allows() {
        let vsm = VsmBuilder::new().build(three_marks().as_ref());
        let fit = |w, h| salient_fit(&vsm, Size::new(w, h).unwrap(), 0.4, &[], &[]).1;
        assert!(
            (fit(800, 200) - 2f64.sqrt()).abs() < 1e-9,
            "{}",
            fit(800, 200)
        );
        assert!((fit(600, 150) - 1.125f64.sqrt()).abs() < 1e-9);
        assert_eq!(fit(200, 200), 1.0);
        // The area shrinks: no growth.
        assert_eq!(fit(800, 80), 1.0);
        // A column of marks filling the height has no room to grow into.
        let mut img = Image::filled(Size::new(400, 200).unwrap(), [255; 4]);
        for y in 0..200 {
            for x in 190..210 {
                img.set(x, y, [215, 25, 28, 255]);
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        let similar = salient_fit(&vsm, Size::new(800, 200).unwrap(), 0.4, &[], &[]).1;
        assert_eq!(similar, 1.0);
    }

    /// Text in a row takes its width off the room the salient content beside it has.
    #[test]
    fn text_in_a_row_leaves_the_salient_content_less_room() {
        let size = Size::new(400, 100).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        checker(&mut img, 20..220, 20..80, 4);
        let vsm = VsmBuilder::new().build(img.as_ref());
        let target = Size::new(250, 100).unwrap();
        // The room before clamping to the linear scale (which hides it at this target).
        let [alone, _] = salient_room(&vsm, target, 0.4, &[], &[]);
        let legend = [block(260, 30, 380, 70)];
        let [beside, _] = salient_room(&vsm, target, 0.4, &legend, &[1.0]);
        let [beside_half, _] = salient_room(&vsm, target, 0.4, &legend, &[0.5]);
        // (0.85·250 − 120) / extent against 0.85·250 / extent.
        let want = (0.85 * 250.0 - 120.0) / (0.85 * 250.0);
        assert!((beside / alone - want).abs() < 0.02, "{beside} / {alone}");
        assert!(beside_half > beside, "{beside_half} vs {beside}");
    }

    fn block(x0: u32, y0: u32, x1: u32, y1: u32) -> TextBlock {
        TextBlock::upright(x0, y0, x1, y1)
    }

    /// Two panels side by side: a vertical line between them keeps one x for its whole
    /// length, so each panel needs its widest row of text on every row it spans, and two
    /// labels on different rows, each alone in its row, must still share the width.
    #[test]
    fn a_wall_makes_a_panel_need_its_widest_row_everywhere() {
        let size = Size::new(1000, 400).unwrap();
        let target = Size::new(500, 400).unwrap();
        // Left panel: a wide label at the top; right panel: a label lower down, where the left
        // panel is empty.
        let text = vec![block(20, 20, 420, 40), block(620, 300, 900, 320)];
        let none = Structure::default();
        let free = text_fit_scales(&text, &none, size, target);
        assert_eq!(free, vec![1.0, 1.0], "each alone in its row fits");
        let walled = Structure {
            vertical: vec![Line {
                pos: 500.0,
                from: 0.0,
                to: 400.0,
                width: 1,
            }],
            ..Structure::default()
        };
        let fit = text_fit_scales(&text, &walled, size, target);
        // Every row needs 400 px on the left and 280 on the right: 680 > 475, both shrink
        // alike.
        for f in &fit {
            assert!((f - 0.95 * 500.0 / 680.0).abs() < 1e-9, "{fit:?}");
        }
    }
}
