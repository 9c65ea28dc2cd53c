//! Panels: a picture of several plots (a dashboard's cards, a figure's sub-figures, facets)
//! split along the clean gutters between its plots, again within each part (an XY cut). A
//! responsive page lays each card out for its new slot; one map per axis for the whole
//! picture cannot, as soon as the panels of one row differ from those of the next (a wide
//! plot over two narrow ones: the wide one's labels stand where the narrow ones' plots do).
//! Each panel keeps what its own layout needs: the spans of its plots, of its type, and of
//! its blank runs along each axis ([`crate::render::CanvasMap`] lays them out).

use super::spans::{merged, runs_where};
use super::{DataArea, TextBlock};
use crate::image::ImageRef;

/// Most a gutter's pixels may differ from its first, per channel: a gutter is the page's
/// ground, flat but for a compression's faint noise.
const CLEAN_TOL: i16 = 6;
/// Deepest nesting of cuts: a figure of rows of panels of facets.
const MOST_DEPTH: u32 = 4;
/// Least side of a panel, pixels: narrower, it is a frame's line or a gutter, not a panel.
const LEAST_PANEL_PX: u32 = 24;

/// A rectangle of the picture and what its layout needs; split into parts along one axis,
/// or a leaf.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Panel {
    /// `[x0, y0, x1, y1]`, half-open, source pixels.
    pub rect: [u32; 4],
    /// Along x (`[0]`) and y (`[1]`): the spans its plots cover (grown over a text block
    /// across a plot's end, which goes with the plot), in picture coordinates.
    pub plots: [Vec<[u32; 2]>; 2],
    /// The spans its text covers.
    pub type_spans: [Vec<[u32; 2]>; 2],
    /// Clean runs (one colour across the panel, no text) outside its plots.
    pub blank: [Vec<[u32; 2]>; 2],
    /// Its parts, where a gutter between its plots splits it.
    pub split: Option<Split>,
    /// A dashboard's card (a framed or filled box on the page's ground, [`super::cards`]):
    /// where it holds no plot, its body keeps one scale in its slot.
    pub card: Option<Card>,
}

/// What a card's layout needs beyond a panel's: the spans its body covers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Card {
    /// Along x (`[0]`) and y (`[1]`): the span from the first to the last line of the card's
    /// inside holding ink outside its text (a map, a treemap, a table's rules, icons), in
    /// picture coordinates; `None` for a card of text alone.
    pub body: Option<[[u32; 2]; 2]>,
    /// The card's box (`[x0, y0, x1, y1]`, its frame or fill's extent) and its inside (the
    /// box less the plain lines along its edges: padding, the frame's lines).
    pub frame: [u32; 4],
    pub inner: [u32; 4],
    /// Along each axis, a line of the card's fill just before its body and one just after
    /// its content, where there are: where the room the card gains goes (the body centred
    /// under its title, nothing smeared but the fill).
    pub stretch: [[Option<u32>; 2]; 2],
}

/// A panel's parts, side by side along one axis.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Split {
    /// Side by side along x (cut by columns), or stacked along y.
    pub columns: bool,
    /// In order along that axis; they tile the panel.
    pub parts: Vec<Panel>,
    /// Each part lays itself out in its slot along both axes (cards, which need not line
    /// up), rather than following the panel's map along the cut (plots side by side share
    /// their scale).
    pub own: bool,
}

impl Panel {
    /// The leaves, in reading order.
    pub fn leaves(&self) -> Vec<&Panel> {
        match &self.split {
            None => vec![self],
            Some(s) => s.parts.iter().flat_map(|p| p.leaves()).collect(),
        }
    }
}

/// The panels of `image`, whose plots are `areas` and text `text`; `None` where no gutter
/// splits its plots apart (one panel: the picture's own layout is its plot's).
pub(crate) fn detect(image: ImageRef<'_>, text: &[TextBlock], areas: &[DataArea]) -> Option<Panel> {
    let (w, h) = (image.width(), image.height());
    if areas.len() < 2 || w < 2 * LEAST_PANEL_PX || h < 2 * LEAST_PANEL_PX {
        return None;
    }
    let rects: Vec<[u32; 4]> = areas
        .iter()
        .map(|a| {
            let lo = |v: f64, n: u32| (v.floor().max(0.0) as u32).min(n);
            let hi = |v: f64, n: u32| (v.ceil().max(0.0) as u32).min(n);
            [lo(a.x0, w), lo(a.y0, h), hi(a.x1, w), hi(a.y1, h)]
        })
        .filter(|r| r[0] < r[2] && r[1] < r[3] && labelled(*r, text))
        .collect();
    if rects.len() < 2 {
        return None;
    }
    let root = panel(image, text, &rects, [0, 0, w, h], 0);
    // Two panels with plots at least: else the picture's own layout is its one plot's.
    let plotted = root
        .leaves()
        .iter()
        .filter(|p| !p.plots[0].is_empty())
        .count();
    (plotted >= 2).then_some(root)
}

/// Whether the data area `r` is a plot read off an axis: at least [`LEAST_TICK_LABELS`]
/// text blocks stand just outside its left or its bottom edge, beside it. A card's frame
/// around a map, a table or a picture is found as an area too, but nothing labels its
/// edges; laid out as a plot, its content would be squeezed (judged blind: a county map, a
/// table, a field of sprites squeezed lost to the letterbox).
pub(super) fn labelled(r: [u32; 4], text: &[TextBlock]) -> bool {
    tick_labels(r, text) >= LEAST_TICK_LABELS
}

/// How many tick labels stand along rectangle `r`'s left edge or its bottom, whichever has
/// more ([`labelled`]).
pub(super) fn tick_labels(r: [u32; 4], text: &[TextBlock]) -> usize {
    let reach = |t: &TextBlock| TICK_REACH_LINES * t.line_height.max(1);
    let left = (text.iter())
        .filter(|t| {
            let cy = (t.y0 + t.y1) / 2;
            t.x1 <= r[0] + 2 && t.x1 + reach(t) >= r[0] && (r[1]..r[3]).contains(&cy)
        })
        .count();
    let below = (text.iter())
        .filter(|t| {
            let cx = (t.x0 + t.x1) / 2;
            t.y0 + 2 >= r[3] && t.y0 <= r[3] + reach(t) && (r[0]..r[2]).contains(&cx)
        })
        .count();
    left.max(below)
}

/// Least tick labels along an edge for an area to be a plot ([`labelled`]).
pub(super) const LEAST_TICK_LABELS: usize = 2;
/// How far outside a plot's edge its tick labels stand, in line heights.
const TICK_REACH_LINES: u32 = 3;

/// The panel of `rect` and, where a gutter between its plots splits it, its parts.
fn panel(
    image: ImageRef<'_>,
    text: &[TextBlock],
    areas: &[[u32; 4]],
    rect: [u32; 4],
    depth: u32,
) -> Panel {
    let centre_in = |b: [u32; 4]| {
        let (cx, cy) = ((b[0] + b[2]) / 2, (b[1] + b[3]) / 2);
        cx >= rect[0] && cx < rect[2] && cy >= rect[1] && cy < rect[3]
    };
    let clip = |b: [u32; 4]| {
        [
            b[0].clamp(rect[0], rect[2]),
            b[1].clamp(rect[1], rect[3]),
            b[2].clamp(rect[0], rect[2]),
            b[3].clamp(rect[1], rect[3]),
        ]
    };
    let plots: Vec<[u32; 4]> = (areas.iter().copied())
        .filter(|&a| centre_in(a))
        .map(clip)
        .collect();
    let words: Vec<[u32; 4]> = (text.iter())
        .map(|t| [t.x0, t.y0, t.x1 + 1, t.y1 + 1])
        .filter(|&t| centre_in(t))
        .map(clip)
        .collect();
    let along = |b: &[u32; 4], k: usize| [b[k], b[k + 2]];
    let type_spans: [Vec<[u32; 2]>; 2] =
        std::array::from_fn(|k| merged(words.iter().map(|b| along(b, k))));
    let bare: [Vec<[u32; 2]>; 2] =
        std::array::from_fn(|k| merged(plots.iter().map(|b| along(b, k))));
    let grown: [Vec<[u32; 2]>; 2] = std::array::from_fn(|k| grown_over(&bare[k], &words, k));
    let clean: [Vec<bool>; 2] = std::array::from_fn(|k| clean_lines(image, rect, k == 0));
    let blank: [Vec<[u32; 2]>; 2] = std::array::from_fn(|k| {
        let (lo, hi) = (rect[k], rect[k + 2]);
        let free = |p: u32| {
            clean[k][(p - lo) as usize] && !inside(&type_spans[k], p) && !inside(&grown[k], p)
        };
        runs_where(lo, hi, free)
    });
    let mut me = Panel {
        rect,
        plots: grown,
        type_spans,
        blank,
        split: None,
        card: None,
    };
    // Only a panel of two plots or more splits: a plot with its labels and legend is one
    // panel, laid out around its plot.
    if depth >= MOST_DEPTH || plots.len() < 2 {
        return me;
    }
    // Cut between groups of plots, along the axis with more gutters (rows first: reading
    // order), at the middle of the widest clean run between them that crosses no word (the
    // words between two plots go with the side they stand on: a plot's tick labels with it).
    let cuts: [Vec<u32>; 2] = std::array::from_fn(|k| {
        let (lo, hi) = (rect[k], rect[k + 2]);
        let mut cuts = Vec::new();
        for g in bare[k].windows(2) {
            let ok = |p: u32| {
                p >= lo
                    && p < hi
                    && clean[k][(p - lo) as usize]
                    && !words.iter().any(|t| t[k] < p && t[k + 2] > p)
            };
            let widest = runs_where(g[0][1], g[1][0], ok)
                .into_iter()
                .max_by_key(|r| (r[1] - r[0], r[0]));
            if let Some([r0, r1]) = widest {
                let cut = (r0 + r1) / 2;
                let prev = cuts.last().copied().unwrap_or(lo);
                if cut - prev >= LEAST_PANEL_PX && hi - cut >= LEAST_PANEL_PX {
                    cuts.push(cut);
                }
            }
        }
        cuts
    });
    let k = match cuts[1].len() >= cuts[0].len() {
        true => 1,
        false => 0,
    };
    if cuts[k].is_empty() {
        return me;
    }
    let parts = (pieces(rect, k, &cuts[k]).into_iter())
        .map(|r| panel(image, text, areas, r, depth + 1))
        .collect();
    me.split = Some(Split {
        columns: k == 0,
        parts,
        own: false,
    });
    me
}

/// The pieces of `rect` cut along axis `k` at `cuts` (sorted, inside it): they tile it.
pub(super) fn pieces(rect: [u32; 4], k: usize, cuts: &[u32]) -> Vec<[u32; 4]> {
    let bounds: Vec<u32> = std::iter::once(rect[k])
        .chain(cuts.iter().copied())
        .chain(std::iter::once(rect[k + 2]))
        .collect();
    (bounds.windows(2))
        .map(|b| {
            let mut r = rect;
            (r[k], r[k + 2]) = (b[0], b[1]);
            r
        })
        .collect()
}

/// `spans` grown over the extent along axis `k` of a word across either of their ends (a
/// tick label centred on a plot's first tick goes with the plot), once: the words that
/// overlap that label (the other axis' tick labels beside it) stay outside.
pub(super) fn grown_over(spans: &[[u32; 2]], words: &[[u32; 4]], k: usize) -> Vec<[u32; 2]> {
    let grown = spans.iter().map(|&[lo, hi]| {
        let across = |p: u32| words.iter().filter(move |t| t[k] < p && t[k + 2] > p);
        let lo = across(lo).map(|t| t[k]).min().unwrap_or(lo).min(lo);
        let hi = across(hi).map(|t| t[k + 2]).max().unwrap_or(hi).max(hi);
        [lo, hi]
    });
    merged(grown)
}

/// Whether `p` lies in one of `spans` (half-open).
pub(super) fn inside(spans: &[[u32; 2]], p: u32) -> bool {
    spans.iter().any(|s| s[0] <= p && p < s[1])
}

/// For each column (`columns`) or row of `rect`: whether it is one colour across the rect.
pub(super) fn clean_lines(image: ImageRef<'_>, rect: [u32; 4], columns: bool) -> Vec<bool> {
    let w = image.width() as usize;
    let px = image.pixels();
    let [x0, y0, x1, y1] = rect.map(|v| v as usize);
    let near =
        |a: [u8; 4], b: [u8; 4]| (0..4).all(|c| (a[c] as i16 - b[c] as i16).abs() <= CLEAN_TOL);
    match columns {
        true => {
            let mut clean = vec![true; x1 - x0];
            let first = &px[y0 * w + x0..y0 * w + x1];
            for y in y0 + 1..y1 {
                let row = &px[y * w + x0..y * w + x1];
                for ((c, &p), &f) in clean.iter_mut().zip(row).zip(first) {
                    *c = *c && near(p, f);
                }
            }
            clean
        }
        false => (y0..y1)
            .map(|y| {
                let row = &px[y * w + x0..y * w + x1];
                row.iter().all(|&p| near(p, row[0]))
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Image, Size};
    use crate::structure::AreaKind;

    fn area(x0: f64, y0: f64, x1: f64, y1: f64) -> DataArea {
        DataArea {
            x0,
            y0,
            x1,
            y1,
            kind: AreaKind::Axes,
        }
    }

    /// Two tick labels just left of `a`'s left edge, as a y axis' labels stand.
    fn ticks(a: &DataArea) -> [TextBlock; 2] {
        let (x1, y) = (a.x0 as u32 - 4, a.y0 as u32);
        let label = |y0: u32| TextBlock {
            x0: x1 - 14,
            y0,
            x1,
            y1: y0 + 9,
            line_height: 9,
            sideways: false,
        };
        [label(y + 5), label(y + 40)]
    }

    fn ticked(areas: &[DataArea]) -> Vec<TextBlock> {
        areas.iter().flat_map(ticks).collect()
    }

    fn fill(img: &mut Image, r: [u32; 4], c: [u8; 4]) {
        for y in r[1]..r[3] {
            for x in r[0]..r[2] {
                img.set(x, y, c);
            }
        }
    }

    /// A wide plot over two narrow ones, on a white page with grey cards: two rows, the
    /// second of two panels.
    #[test]
    fn a_wide_plot_over_two_narrow_ones_is_two_rows_the_second_of_two_panels() {
        let mut img = Image::filled(Size::new(400, 300).unwrap(), [255; 4]);
        for r in [
            [10, 10, 390, 140],
            [10, 160, 190, 290],
            [210, 160, 390, 290],
        ] {
            fill(&mut img, r, [200, 200, 200, 255]);
        }
        let areas = [
            area(30.0, 20.0, 380.0, 130.0),
            area(30.0, 170.0, 180.0, 280.0),
            area(230.0, 170.0, 380.0, 280.0),
        ];
        let p = detect(img.as_ref(), &ticked(&areas), &areas).expect("panels");
        let s = p.split.as_ref().unwrap();
        assert!(!s.columns, "rows first");
        assert_eq!(s.parts.len(), 2);
        assert!(s.parts[0].split.is_none());
        let row = s.parts[1].split.as_ref().expect("the second row splits");
        assert!(row.columns);
        assert_eq!(row.parts.len(), 2);
        let cut = row.parts[0].rect[2];
        assert!((190..210).contains(&cut), "{cut}");
        assert_eq!(p.leaves().len(), 3);
    }

    /// No gutter: a stroke across the gap between two plots keeps them one panel.
    #[test]
    fn no_clean_gutter_no_split() {
        let mut img = Image::filled(Size::new(400, 200).unwrap(), [255; 4]);
        fill(&mut img, [0, 100, 400, 101], [0, 0, 0, 255]);
        let areas = [
            area(10.0, 10.0, 180.0, 190.0),
            area(220.0, 10.0, 390.0, 190.0),
        ];
        assert!(detect(img.as_ref(), &[], &areas).is_none());
    }

    /// A title across the gutter between two plots is not cut, and a title alone makes no
    /// row: the plots side by side under it are one panel, as one picture lays them out.
    #[test]
    fn a_cut_crosses_no_word() {
        let img = Image::filled(Size::new(400, 200).unwrap(), [255; 4]);
        let areas = [
            area(30.0, 40.0, 180.0, 190.0),
            area(240.0, 40.0, 390.0, 190.0),
        ];
        let title = TextBlock {
            x0: 150,
            y0: 5,
            x1: 250,
            y1: 20,
            line_height: 15,
            sideways: false,
        };
        let mut text = ticked(&areas);
        assert!(detect(img.as_ref(), &text, &areas).is_some());
        text.push(title);
        assert!(detect(img.as_ref(), &text, &areas).is_none());
    }

    /// A frame nothing labels (a card around a map or a table) is no plot to split by.
    #[test]
    fn an_unlabelled_frame_is_no_plot() {
        let img = Image::filled(Size::new(400, 200).unwrap(), [255; 4]);
        let areas = [
            area(30.0, 40.0, 180.0, 190.0),
            area(240.0, 40.0, 390.0, 190.0),
        ];
        assert!(detect(img.as_ref(), &ticked(&areas[..1]), &areas).is_none());
        assert!(detect(img.as_ref(), &ticked(&areas), &areas).is_some());
    }
}
