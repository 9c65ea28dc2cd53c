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
//! [`MIN_THICKNESS_PX`] mark pixels. The 98th percentile of the row counts, against the target
//! width with a margin for the background that must remain between marks, gives the scale;
//! likewise per column for the height. Rows are not independent (the mesh is continuous), so
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

/// The scale salient content should keep: in `[min(w'/w, h'/h), 1]`.
pub(crate) fn salient_fit_scale(vsm: &Vsm, target: Size, threshold: f32) -> f64 {
    let grid = vsm.grid_size();
    let sc = vsm.scale() as usize;
    let (w, h) = (grid.width as usize, grid.height as usize);
    // Pixel lengths in map cells.
    let min_thickness = MIN_THICKNESS_PX.div_ceil(sc);
    let max_gap = MAX_GAP_PX.div_ceil(sc as u32);
    let imp = vsm.importance();
    // Row widths: mark pixels in vertical runs of at least MIN_THICKNESS_PX. A pixel's run
    // is known when the run ends, so rows are filled in per column run, walking rows in order
    // (per-column counters, row-major reads).
    let mut thick_v = vec![false; w * h];
    let mut run = vec![0u32; w];
    for y in 0..=h {
        for x in 0..w {
            if y < h && imp[y * w + x] >= threshold {
                run[x] += 1;
                continue;
            }
            let len = run[x] as usize;
            if len >= min_thickness {
                for yy in y - len..y {
                    thick_v[yy * w + x] = true;
                }
            }
            run[x] = 0;
        }
    }
    let mut rows: Vec<u32> = thick_v
        .chunks_exact(w)
        .map(|r| extent(r.iter().copied(), max_gap) * sc as u32)
        .collect();
    // Column heights: mark pixels in horizontal runs of at least as many, with the gap logic
    // of `extent` run per column through per-column state.
    let mut cols = vec![0u32; w];
    let mut gap: Vec<Option<u32>> = vec![None; w];
    for y in 0..h {
        let row = &imp[y * w..][..w];
        let mut len = 0usize;
        for x in 0..=w {
            if x < w && row[x] >= threshold {
                len += 1;
                continue;
            }
            let thick = len >= min_thickness;
            for xx in x - len..x {
                extent_step(&mut cols[xx], &mut gap[xx], thick, max_gap);
            }
            if x < w {
                extent_step(&mut cols[x], &mut gap[x], false, max_gap);
            }
            len = 0;
        }
    }
    let pct = |v: &mut Vec<u32>| -> f64 {
        v.sort_unstable();
        let i = ((v.len() as f64 - 1.0) * PERCENTILE).round() as usize;
        v[i.min(v.len() - 1)] as f64
    };
    // Both in image pixels (rows were scaled when counted).
    let (rw, ch) = (pct(&mut rows), pct(&mut cols) * sc as f64);
    let (tw, th) = (target.width as f64, target.height as f64);
    let fit_x = if rw > 0.0 {
        FILL * tw / rw
    } else {
        f64::INFINITY
    };
    let fit_y = if ch > 0.0 {
        FILL * th / ch
    } else {
        f64::INFINITY
    };
    let size = vsm.size();
    let linear = (tw / size.width as f64).min(th / size.height as f64);
    fit_x.min(fit_y).min(1.0).max(linear.min(1.0))
}

/// The scale each text block can keep: the largest at which the text crossing any of its rows
/// fits the target width (with the margin of [`FILL`]), and likewise for its columns and the
/// target height; at most 1. A title alone on its row keeps more than a legend crowded into
/// one row with other labels.
pub(crate) fn text_fit_scales(
    text: &[crate::structure::TextBlock],
    size: Size,
    target: Size,
) -> Vec<f64> {
    let (w, h) = (size.width as usize, size.height as usize);
    let mut rows = vec![0u32; h];
    let mut cols = vec![0u32; w];
    for b in text {
        for r in rows[(b.y0 as usize).min(h)..(b.y1 as usize).min(h)].iter_mut() {
            *r += b.x1 - b.x0;
        }
        for c in cols[(b.x0 as usize).min(w)..(b.x1 as usize).min(w)].iter_mut() {
            *c += b.y1 - b.y0;
        }
    }
    text.iter()
        .map(|b| {
            let widest = rows[(b.y0 as usize).min(h)..(b.y1 as usize).min(h)]
                .iter()
                .copied()
                .max()
                .unwrap_or(0) as f64;
            let tallest = cols[(b.x0 as usize).min(w)..(b.x1 as usize).min(w)]
                .iter()
                .copied()
                .max()
                .unwrap_or(0) as f64;
            let fx = if widest > 0.0 {
                TEXT_FILL * target.width as f64 / widest
            } else {
                1.0
            };
            let fy = if tallest > 0.0 {
                TEXT_FILL * target.height as f64 / tallest
            } else {
                1.0
            };
            fx.min(fy).min(1.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::saliency::VsmBuilder;

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
            salient_fit_scale(&vsm, Size::new(200, 200).unwrap(), 0.4),
            1.0
        );
        assert_eq!(
            salient_fit_scale(&vsm, Size::new(400, 100).unwrap(), 0.4),
            1.0
        );
    }

    #[test]
    fn sparse_marks_keep_scale_one_and_wide_content_shrinks() {
        let size = Size::new(400, 200).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        for (cx, cy) in [(50u32, 50u32), (200, 120), (330, 80)] {
            for y in cy - 5..cy + 5 {
                for x in cx - 5..cx + 5 {
                    img.set(x, y, [215, 25, 28, 255]);
                }
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        assert_eq!(
            salient_fit_scale(&vsm, Size::new(200, 200).unwrap(), 0.4),
            1.0
        );

        // A salient band 300 px wide in every row cannot keep scale 1 in 200 px.
        let mut img = Image::filled(size, [255; 4]);
        for y in 0..200 {
            for x in 50..350 {
                if (x / 3 + y / 3) % 2 == 0 {
                    img.set(x, y, [20, 20, 20, 255]);
                }
            }
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        let s = salient_fit_scale(&vsm, Size::new(200, 200).unwrap(), 0.4);
        assert!((0.5..0.7).contains(&s), "{s}");
    }
}
