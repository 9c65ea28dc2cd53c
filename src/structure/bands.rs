//! Text bands: the columns (rows) of a picture where nothing but text stands, such as the left
//! margin holding a y axis' title and tick labels, or the rows of an x axis' labels under
//! its plot. A canvas taken whole ([`super::Regions::Affine`]) keeps these at their size
//! and gives the rest one linear map ([`crate::render::CanvasMap`]), as a chart drawn anew
//! at the smaller size keeps its labels' type and shrinks the plot: positions and lengths
//! inside the plot stay proportional, and the labels are not condensed.
//!
//! A column is clean when no pixel in it outside the text boxes differs from its left
//! neighbour, or from the pixel two to its left, by more than [`STEP`] levels: whatever a
//! different scale there could bend (a mark, a bar's end, a curve, a colour ramp) has such a
//! step. Horizontal lines and fills that cross the column have none, and stay straight under
//! any map along x. A block of text lends its columns to a band only when all of them are
//! clean (a word is never kinked), and no band lies inside a data area found from its axes.

use super::spans::{merged, runs_where};
use super::text::ALIGNED_PX;
use super::{DataArea, Line, TextBlock};
use crate::image::ImageRef;

/// Most step between neighbouring pixels (any channel) that still counts as flat: exact for
/// the flat fills of rendered charts, and a ramp of more than [`STEP`]/2 levels per pixel is
/// caught by the step over two pixels.
const STEP: u8 = 2;

/// Pixels around a text block's box that are its own (the glyphs' anti-aliased rims).
const PAD: u32 = 1;

/// The text bands of a picture: half-open ranges of source columns (`x`) and rows (`y`);
/// its gaps: runs of clean columns (rows) without text at the canvas' edge or beside a band
/// (margins, the space between an axis' title and its labels), which give way first; and
/// of those, its margins: the gaps at the canvas' edge that are mostly the picture's ground
/// (blank page, not a header bar's fill), which also give way to the plot.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Bands {
    pub x: Vec<[u32; 2]>,
    pub y: Vec<[u32; 2]>,
    pub gaps_x: Vec<[u32; 2]>,
    pub gaps_y: Vec<[u32; 2]>,
    pub margins_x: Vec<[u32; 2]>,
    pub margins_y: Vec<[u32; 2]>,
    /// No data area was found (no axes, frame, grid or bars): the picture is read by its
    /// shapes (a map, a node-link graph), which its plot keeps where the margins make room.
    pub free: bool,
    /// The source columns (`plots_x`) and rows (`plots_y`) the data areas span, merged: the
    /// plots, which take the room the parts around them (labels, legends, titles, gutters)
    /// leave, as a chart's author re-rendering it for a smaller screen lets them
    /// ([`crate::render::AxisMap::around_plots`]).
    pub plots_x: Vec<[u32; 2]>,
    pub plots_y: Vec<[u32; 2]>,
    /// Every run of clean columns (rows) without text outside the data areas, wherever it
    /// lies: the blank space a layout shrinks before anything drawn.
    pub blank_x: Vec<[u32; 2]>,
    pub blank_y: Vec<[u32; 2]>,
    /// The columns (rows) text blocks cover, merged: where the parts around the plots hold
    /// type ([`crate::render::AxisMap::around_plots`]).
    pub type_x: Vec<[u32; 2]>,
    pub type_y: Vec<[u32; 2]>,
    /// The rectangles, `[x0, y0, x1, y1]` half-open, of the data areas whose edges are
    /// labelled as an axis' are ([`super::panels::labelled`]): what is inside a plot (a
    /// card's frame around a table or a map is no plot its text is inside of). On a page of
    /// cards, the plots found inside the cards instead: each card's plot spans across by
    /// its plot spans down.
    pub plot_rects: Vec<[u32; 4]>,
    /// The panels the picture's plots stand in, where gutters split them apart
    /// ([`super::panels`]): each is laid out on its own.
    pub panels: Option<super::Panel>,
}

impl Bands {
    /// These bands as a stream keeps them after `before`'s: what both hold, along each axis.
    /// Bands only ever narrow, so the plot moves at most as often as a band is lost, and
    /// never back and forth as a transient (a mark passing through a margin) comes and goes;
    /// a stream whose layout changes ends with no bands, as a linear resize.
    pub fn kept(&self, before: &Bands) -> Bands {
        Bands {
            x: common(&self.x, &before.x),
            y: common(&self.y, &before.y),
            gaps_x: common(&self.gaps_x, &before.gaps_x),
            gaps_y: common(&self.gaps_y, &before.gaps_y),
            margins_x: common(&self.margins_x, &before.margins_x),
            margins_y: common(&self.margins_y, &before.margins_y),
            free: self.free && before.free,
            // The layout holds while the scene stands: the first frame's plots stay.
            plots_x: kept_plots(&self.plots_x, &before.plots_x),
            plots_y: kept_plots(&self.plots_y, &before.plots_y),
            blank_x: common(&self.blank_x, &before.blank_x),
            blank_y: common(&self.blank_y, &before.blank_y),
            type_x: kept_plots(&self.type_x, &before.type_x),
            type_y: kept_plots(&self.type_y, &before.type_y),
            plot_rects: match before.plot_rects.is_empty() {
                true => self.plot_rects.clone(),
                false => before.plot_rects.clone(),
            },
            panels: before.panels.clone().or_else(|| self.panels.clone()),
        }
    }
}

/// What a stream keeps of the frame that set its layout: the bands as they narrowed since,
/// and that frame's size and text, to tell a new scene (a folder of unrelated stills run as
/// one stream, a cut in an animation) from the same chart with its data moving.
#[derive(Clone, Debug)]
pub struct Scene {
    size: crate::image::Size,
    text: Vec<TextBlock>,
    bands: Bands,
}

/// Least share of a scene's text blocks found again, in place, in a frame of the same scene.
/// An animated chart keeps its axes' labels, titles and legend while its data moves (a
/// counter or a few values may change); another chart keeps few of them, if any.
const SAME_SCENE_TEXT: f64 = 0.5;

impl Scene {
    /// The bands for a frame of `size` with `text` found in it and bands `now`: the scene's,
    /// narrowed by the frame's ([`Bands::kept`]), while the frame belongs to it; else the
    /// frame's own, and it starts a new scene.
    pub fn keep(
        scene: &mut Option<Scene>,
        size: crate::image::Size,
        text: &[TextBlock],
        now: Bands,
    ) -> Bands {
        match scene.as_mut().filter(|s| s.holds(size, text)) {
            Some(s) => {
                s.bands = now.kept(&s.bands);
                s.bands.clone()
            }
            None => {
                *scene = Some(Scene {
                    size,
                    text: text.to_vec(),
                    bands: now.clone(),
                });
                now
            }
        }
    }

    /// Whether a frame of `size` with `text` is of this scene: the same size, and at least
    /// [`SAME_SCENE_TEXT`] of the scene's text blocks (all of the frame's, where the scene had
    /// none) stand where they stood.
    fn holds(&self, size: crate::image::Size, text: &[TextBlock]) -> bool {
        if size != self.size {
            return false;
        }
        let found = |a: &[TextBlock], b: &[TextBlock]| {
            let again = a
                .iter()
                .filter(|t| b.iter().any(|u| overlaps_most(t, u)))
                .count();
            again as f64 >= SAME_SCENE_TEXT * a.len() as f64
        };
        found(&self.text, text) && found(text, &self.text)
    }
}

/// Whether two blocks' boxes share at least half of their union: the same label, drawn again
/// where it was (a digit or two changed, or read a pixel wider).
fn overlaps_most(a: &TextBlock, b: &TextBlock) -> bool {
    let w = a.x1.min(b.x1).saturating_sub(a.x0.max(b.x0)) as u64;
    let h = a.y1.min(b.y1).saturating_sub(a.y0.max(b.y0)) as u64;
    let area = |t: &TextBlock| (t.x1 - t.x0) as u64 * (t.y1 - t.y0) as u64;
    let common = w * h;
    2 * common >= area(a) + area(b) - common
}

impl Bands {
    /// Whether text block `t` stands inside a plot: its centre inside a labelled data
    /// area's rectangle (a label on a mark, a cell's value; not the tick labels beside it).
    pub fn in_plot(&self, t: &super::TextBlock) -> bool {
        let (cx, cy) = ((t.x0 + t.x1) / 2, (t.y0 + t.y1) / 2);
        let inside = |r: &[u32; 4]| (r[0]..r[2]).contains(&cx) && (r[1]..r[3]).contains(&cy);
        self.plot_rects.iter().any(inside)
    }
}

/// The plots a stream keeps: those it had, while it had any (a plot that moves by a few
/// pixels from frame to frame would move every label with it).
fn kept_plots(now: &[[u32; 2]], before: &[[u32; 2]]) -> Vec<[u32; 2]> {
    match before.is_empty() {
        true => now.to_vec(),
        false => before.to_vec(),
    }
}

/// The half-open source spans that `areas` cover along x (`columns`) or y, merged.
fn spans_of(areas: &[DataArea], n: u32, columns: bool) -> Vec<[u32; 2]> {
    merged(areas.iter().map(|a| {
        let [lo, hi] = match columns {
            true => [a.x0, a.x1],
            false => [a.y0, a.y1],
        };
        [lo.floor().max(0.0) as u32, (hi.ceil() as u32).min(n)]
    }))
}

/// The half-open ranges both `a` and `b` cover (each sorted, not overlapping).
fn common(a: &[[u32; 2]], b: &[[u32; 2]]) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    for p in a {
        for q in b {
            let (lo, hi) = (p[0].max(q[0]), p[1].min(q[1]));
            if lo < hi {
                out.push([lo, hi]);
            }
        }
    }
    out.sort();
    out
}

/// The text bands of `image` with text blocks `text`, none inside `areas`.
pub(crate) fn detect(
    image: ImageRef<'_>,
    text: &[TextBlock],
    areas: &[DataArea],
    lines: [&[Line]; 2],
) -> Bands {
    let (w, h) = (image.width(), image.height());
    if w < 3 || h < 3 {
        return Bands::default();
    }
    let mut bands = if text.is_empty() {
        // No band: only the margins can give way, and only they need reading.
        Bands {
            gaps_x: margins(w, |x| step_across(image, x, true), |x| inside_x(areas, x)),
            gaps_y: margins(h, |y| step_across(image, y, false), |y| inside_y(areas, y)),
            ..Bands::default()
        }
    } else {
        scan(image, text, areas)
    };
    // The ground is read only where a gap reaches the canvas' edge.
    let at_edge = |g: &[u32; 2], n: u32| g[0] == 0 || g[1] == n;
    let edges =
        bands.gaps_x.iter().any(|g| at_edge(g, w)) || bands.gaps_y.iter().any(|g| at_edge(g, h));
    let ground = if edges { ground_of(image) } else { [0; 3] };
    let page = |g: &&[u32; 2], n: u32, columns: bool| {
        at_edge(g, n) && mostly_ground(image, **g, columns, ground)
    };
    bands.margins_x = (bands.gaps_x.iter())
        .filter(|g| page(g, w, true))
        .copied()
        .collect();
    bands.margins_y = (bands.gaps_y.iter())
        .filter(|g| page(g, h, false))
        .copied()
        .collect();
    bands.free = areas.is_empty();
    bands.type_x = merged(text.iter().map(|t| [t.x0, (t.x1 + 1).min(w)]));
    bands.type_y = merged(text.iter().map(|t| [t.y0, (t.y1 + 1).min(h)]));
    bands.plots_x = around_text(spans_of(areas, w, true), text, |t| [t.x0, t.x1 + 1]);
    bands.plots_y = around_text(spans_of(areas, h, false), text, |t| [t.y0, t.y1 + 1]);
    bands.plot_rects = (areas.iter())
        .map(|a| {
            let at = |v: f64, n: u32| (v.round().max(0.0) as u32).min(n);
            [at(a.x0, w), at(a.y0, h), at(a.x1, w), at(a.y1, h)]
        })
        .filter(|&r| super::panels::labelled(r, text))
        .collect();
    // Cards on a page's ground lay themselves out each in its slot; else the panels of a
    // figure, between its plots.
    bands.panels = super::cards::detect(image, text, &bands.plot_rects, lines, ground_of(image));
    match &bands.panels {
        // A card's plots are those found inside it: the picture's data areas took its
        // frame for one, and every word in the card (its title, its tick labels) for a
        // word inside a plot.
        Some(cards) => {
            bands.plot_rects = (cards.leaves().iter())
                .flat_map(|l| {
                    let [xs, ys] = &l.plots;
                    xs.iter()
                        .flat_map(move |x| ys.iter().map(move |y| [x[0], y[0], x[1], y[1]]))
                })
                .collect();
        }
        None => bands.panels = super::panels::detect(image, text, areas),
    }
    if text.is_empty() {
        // Without text no part is kept (it holds no type) and the layout declines unless the
        // plots reach the edge's margins: those are its blank runs (not read again: a
        // column-wise scan of a whole frame costs a text-less stream its frame rate).
        bands.blank_x = bands.gaps_x.clone();
        bands.blank_y = bands.gaps_y.clone();
    }
    bands
}

/// `plots` grown over every text block that straddles one of their ends (an axis' last tick
/// label, centred on the plot's edge): a block across two scales would be torn.
fn around_text(
    mut plots: Vec<[u32; 2]>,
    text: &[TextBlock],
    extent: impl Fn(&TextBlock) -> [u32; 2],
) -> Vec<[u32; 2]> {
    loop {
        let mut grown = false;
        for p in plots.iter_mut() {
            for t in text {
                let [a, b] = extent(t);
                if a < p[0] && b > p[0] {
                    (p[0], grown) = (a, true);
                }
                if a < p[1] && b > p[1] {
                    (p[1], grown) = (b, true);
                }
            }
        }
        plots = merged(plots.into_iter());
        if !grown {
            return plots;
        }
    }
}

/// The picture's ground: the colour most of its border pixels have.
pub(super) fn ground_of(image: ImageRef<'_>) -> [u8; 3] {
    let (w, h, px) = (
        image.width() as usize,
        image.height() as usize,
        image.pixels(),
    );
    let mut border: Vec<[u8; 3]> = (0..w)
        .flat_map(|x| [px[x], px[(h - 1) * w + x]])
        .chain((0..h).flat_map(|y| [px[y * w], px[y * w + w - 1]]))
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    border.sort_unstable();
    let (mut best, mut most, mut run) = (border[0], 0, 0);
    for (i, &c) in border.iter().enumerate() {
        run = if i > 0 && border[i - 1] == c {
            run + 1
        } else {
            1
        };
        if run > most {
            (best, most) = (c, run);
        }
    }
    best
}

/// Whether most pixels of the columns (rows, when `columns` is false) `span` are within
/// [`STEP`] of `ground`: a page margin, not the fill of a bar that runs along the edge.
fn mostly_ground(image: ImageRef<'_>, [a, b]: [u32; 2], columns: bool, ground: [u8; 3]) -> bool {
    let (w, h, px) = (
        image.width() as usize,
        image.height() as usize,
        image.pixels(),
    );
    let is_ground = |p: &[u8; 4]| !differs(*p, [ground[0], ground[1], ground[2], 255]);
    let (a, b) = (a as usize, b as usize);
    let (on, all) = match columns {
        true => (
            (0..h)
                .map(|y| {
                    px[y * w + a..y * w + b]
                        .iter()
                        .filter(|p| is_ground(p))
                        .count()
                })
                .sum::<usize>(),
            (b - a) * h,
        ),
        false => (
            px[a * w..b * w].iter().filter(|p| is_ground(p)).count(),
            (b - a) * w,
        ),
    };
    2 * on > all
}

/// [`detect`] by reading every pixel: the columns and rows that are clean, the runs of them
/// that text lends, and the gaps.
fn scan(image: ImageRef<'_>, text: &[TextBlock], areas: &[DataArea]) -> Bands {
    let (w, h) = (image.width(), image.height());
    let mut in_text = vec![false; (w * h) as usize];
    for t in text {
        let (x0, x1) = (t.x0.saturating_sub(PAD), (t.x1 + PAD).min(w - 1));
        let (y0, y1) = (t.y0.saturating_sub(PAD), (t.y1 + PAD).min(h - 1));
        if x0 > x1 {
            continue;
        }
        for y in y0..=y1 {
            in_text[(y * w + x0) as usize..=(y * w + x1) as usize].fill(true);
        }
    }
    let px = image.pixels();
    let differs_at = |a: usize, b: usize| differs(px[a], px[b]);
    // steps_x[x]: a step between columns x - 1 (or x - 2) and x outside text. A step found
    // only sets flags: where both it would set are set already, the pixel is not compared
    // (in a busy picture most columns and rows step early on, and the rest is skipped).
    let (mut steps_x, mut steps_y) = (vec![false; w as usize + 1], vec![false; h as usize + 1]);
    for y in 0..h {
        let yu = y as usize;
        for x in 0..w {
            let i = (y * w + x) as usize;
            let xu = x as usize;
            if in_text[i] {
                continue;
            }
            let left = |k: u32| x >= k && !in_text[i - k as usize] && differs_at(i, i - k as usize);
            if x >= 1 && !(steps_x[xu] && steps_x[xu - 1]) && (left(1) || left(2)) {
                steps_x[xu] = true;
                steps_x[xu - 1] = true;
            }
            let wk = w as usize;
            let up = |k: usize| yu >= k && !in_text[i - k * wk] && differs_at(i, i - k * wk);
            if y >= 1 && !(steps_y[yu] && steps_y[yu - 1]) && (up(1) || up(2)) {
                steps_y[yu] = true;
                steps_y[yu - 1] = true;
            }
        }
    }
    let clean_x = |x: u32| !steps_x[x as usize] && !steps_x[x as usize + 1] && !inside_x(areas, x);
    let clean_y = |y: u32| !steps_y[y as usize] && !steps_y[y as usize + 1] && !inside_y(areas, y);
    let xs: Vec<[u32; 2]> = text.iter().map(|t| [t.x0, t.x1.min(w - 1)]).collect();
    let ys: Vec<[u32; 2]> = text.iter().map(|t| [t.y0, t.y1.min(h - 1)]).collect();
    // A row of labels lends its columns all together or not at all, and a column of labels
    // its rows: a legend with one label at its size and the next squeezed reads as two.
    let rows = aligned(text, |t| [t.y0, t.y1]);
    let columns = aligned(text, |t| [t.x0, t.x1]);
    let x = runs(w, &xs, &rows, clean_x);
    let y = runs(h, &ys, &columns, clean_y);
    let (text_x, text_y) = (covered(w, &xs), covered(h, &ys));
    Bands {
        gaps_x: gaps(w, &x, |i| clean_x(i) && !text_x[i as usize]),
        gaps_y: gaps(h, &y, |i| clean_y(i) && !text_y[i as usize]),
        blank_x: runs_where(0, w, |i| clean_x(i) && !text_x[i as usize]),
        blank_y: runs_where(0, h, |i| clean_y(i) && !text_y[i as usize]),
        x,
        y,
        ..Bands::default()
    }
}

/// Whether two pixels differ by more than [`STEP`] in some colour channel.
fn differs(p: [u8; 4], q: [u8; 4]) -> bool {
    (0..3).any(|c| p[c].abs_diff(q[c]) > STEP)
}

/// Whether column `x` lies inside a data area of `areas`.
fn inside_x(areas: &[DataArea], x: u32) -> bool {
    areas.iter().any(|a| x as f64 > a.x0 && (x as f64) < a.x1)
}

/// Whether row `y` lies inside a data area of `areas`.
fn inside_y(areas: &[DataArea], y: u32) -> bool {
    areas.iter().any(|a| y as f64 > a.y0 && (y as f64) < a.y1)
}

/// Whether some pixel of column `i` (of row `i` when `columns` is false) steps by more than
/// [`STEP`] from the pixel one or two before it: what [`detect`] marks when no text masks
/// anything.
fn step_across(image: ImageRef<'_>, i: u32, columns: bool) -> bool {
    let (w, px) = (image.width() as usize, image.pixels());
    let i = i as usize;
    if columns {
        (0..image.height() as usize).any(|y| {
            let row = &px[y * w..][..w];
            (i >= 1 && differs(row[i], row[i - 1])) || (i >= 2 && differs(row[i], row[i - 2]))
        })
    } else {
        let row = |k: usize| &px[k * w..][..w];
        (i >= 1 && row(i).iter().zip(row(i - 1)).any(|(&p, &q)| differs(p, q)))
            || (i >= 2 && row(i).iter().zip(row(i - 2)).any(|(&p, &q)| differs(p, q)))
    }
}

/// The gaps of a picture without text: its blank margins, the clean runs at either end of
/// an axis of `n` positions, found from the ends inward (a position is clean when it and the
/// two after it have no `step`, and it lies in no data area, as in [`detect`]), so that only
/// the margins are read.
fn margins(n: u32, step: impl Fn(u32) -> bool, inside: impl Fn(u32) -> bool) -> Vec<[u32; 2]> {
    let mut known: Vec<Option<bool>> = vec![None; n as usize + 2];
    let mut stepped = |i: u32| {
        if i >= n {
            return false;
        }
        *known[i as usize].get_or_insert_with(|| step(i))
    };
    let mut clean = |i: u32| !stepped(i) && !stepped(i + 1) && !stepped(i + 2) && !inside(i);
    let lead = (0..n).find(|&i| !clean(i)).unwrap_or(n);
    if lead == n {
        return vec![[0, n]];
    }
    let trail = (0..n).rev().find(|&i| !clean(i)).map_or(0, |i| i + 1);
    let mut out = Vec::new();
    if lead > 0 {
        out.push([0, lead]);
    }
    if trail < n {
        out.push([trail, n]);
    }
    out
}

/// Which positions below `n` a span of `spans` (inclusive) covers.
fn covered(n: u32, spans: &[[u32; 2]]) -> Vec<bool> {
    let mut c = vec![false; n as usize];
    for &[a, b] in spans.iter().filter(|s| s[0] <= s[1]) {
        c[a as usize..=b as usize].fill(true);
    }
    c
}

/// The maximal runs of `empty` positions below `n` that touch the canvas' edge or a band of
/// `bands`: the margins, the space between an axis' title and its labels. An empty strip
/// inside a plot without a frame touches neither; it is part of an axis' range and keeps
/// its share of it.
fn gaps(n: u32, bands: &[[u32; 2]], empty: impl Fn(u32) -> bool) -> Vec<[u32; 2]> {
    let beside = |p: u32| bands.iter().any(|b| b[0] == p || b[1] == p);
    runs_where(0, n, empty)
        .into_iter()
        .filter(|&[a, e]| a == 0 || e == n || beside(a) || beside(e))
        .collect()
}

/// For each block, the least index of the blocks of its type size set in one line with it
/// (through any chain of neighbours), by `edges(t)`: both ends of its extent across that line.
fn aligned(text: &[TextBlock], edges: impl Fn(&TextBlock) -> [u32; 2]) -> Vec<usize> {
    let mut group: Vec<usize> = (0..text.len()).collect();
    for i in 0..text.len() {
        for j in 0..i {
            let (a, b) = (edges(&text[i]), edges(&text[j]));
            let line = a[0].abs_diff(b[0]) <= ALIGNED_PX || a[1].abs_diff(b[1]) <= ALIGNED_PX;
            if line && text[i].sideways == text[j].sideways && text[i].same_type_size(&text[j]) {
                let (gi, gj) = (group[i], group[j]);
                let (keep, drop) = (gi.min(gj), gi.max(gj));
                group
                    .iter_mut()
                    .filter(|g| **g == drop)
                    .for_each(|g| *g = keep);
            }
        }
    }
    group
}

/// The half-open runs of positions below `n` covered by the inclusive `spans` of the blocks
/// whose group (`group`, as [`aligned`]) has all its positions `clean`.
fn runs(n: u32, spans: &[[u32; 2]], group: &[usize], clean: impl Fn(u32) -> bool) -> Vec<[u32; 2]> {
    let all_clean = |&[a, b]: &[u32; 2]| a <= b && (a..=b).all(&clean);
    let mut band = vec![false; n as usize];
    let lends: Vec<bool> = (0..spans.len())
        .map(|i| (0..spans.len()).all(|j| group[j] != group[i] || all_clean(&spans[j])))
        .collect();
    for (&[a, b], _) in spans.iter().zip(&lends).filter(|(_, &l)| l) {
        band[a as usize..=b as usize].fill(true);
    }
    // A band does not take in most of a block that lends nothing: the block would be
    // drawn larger than its fellows (a legend's label beside a ring taken for a glyph).
    // Such a block's run is no band (and, with it, the runs it touches). A block the band
    // only grazes (an x axis' first label under a y axis' labels) floats or stays as it is.
    let mut changed = true;
    while changed {
        changed = false;
        for (&[a, b], _) in spans.iter().zip(&lends).filter(|(_, &l)| !l) {
            let inside = (a..=b).filter(|&i| band[i as usize]).count() as u32;
            if a > b || 2 * inside <= b - a + 1 {
                continue;
            }
            let (mut lo, mut hi) = (a as usize, b as usize);
            while lo > 0 && band[lo - 1] {
                lo -= 1;
            }
            while hi + 1 < band.len() && band[hi + 1] {
                hi += 1;
            }
            band[lo..=hi].fill(false);
            changed = true;
        }
    }
    let mut out: Vec<[u32; 2]> = Vec::new();
    for (i, &b) in band.iter().enumerate() {
        match out.last_mut() {
            Some(r) if b && r[1] == i as u32 => r[1] += 1,
            _ if b => out.push([i as u32, i as u32 + 1]),
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Image, Size};
    use proptest::prelude::*;

    /// A frame holds its scene while most of the scene's text stands where it stood (a
    /// value changed, a label read a pixel wider); other text, or another size, starts anew.
    #[test]
    fn a_scene_holds_while_its_text_stands() {
        let block = |x0, y0, w| TextBlock {
            x0,
            y0,
            x1: x0 + w,
            y1: y0 + 10,
            line_height: 10,
            sideways: false,
        };
        let size = Size::new(400, 300).unwrap();
        let text = vec![block(10, 10, 60), block(10, 100, 20), block(10, 200, 20)];
        let first = Bands {
            x: vec![[0, 40]],
            ..Bands::default()
        };
        let mut scene = None;
        assert_eq!(Scene::keep(&mut scene, size, &text, first.clone()), first);
        // The title read 3 px wider, a label gone, one new: the scene's bands, narrowed.
        let later = vec![block(10, 10, 63), block(10, 100, 20), block(300, 250, 30)];
        let narrower = Bands {
            x: vec![[0, 30]],
            ..Bands::default()
        };
        assert_eq!(
            Scene::keep(&mut scene, size, &later, narrower.clone()),
            narrower
        );
        let wider = Bands {
            x: vec![[0, 50]],
            ..Bands::default()
        };
        assert_eq!(
            Scene::keep(&mut scene, size, &text, wider.clone()),
            narrower,
            "bands only narrow within a scene"
        );
        // Another chart: its own bands.
        let other = vec![block(200, 20, 80), block(300, 120, 20), block(300, 220, 20)];
        assert_eq!(Scene::keep(&mut scene, size, &other, wider.clone()), wider);
        // The same text on a frame of another size: a new scene too.
        let big = Size::new(800, 300).unwrap();
        assert_eq!(Scene::keep(&mut scene, big, &other, first.clone()), first);
    }

    /// A blank strip at the canvas' edge is a page margin; a header bar's fill along the top
    /// edge is a gap (it may give way to its text) but no margin.
    #[test]
    fn a_margin_is_blank_page_and_a_header_bar_is_not() {
        let mut img = Image::filled(Size::new(200, 100).unwrap(), [255, 255, 255, 255]);
        for y in 0..20 {
            for x in 0..200 {
                img.set(x, y, [30, 60, 120, 255]);
            }
        }
        for y in 30..90 {
            for x in 40..160 {
                img.set(x, y, [200 - (x as u8) / 2, 80, 40, 255]);
            }
        }
        let b = detect(img.as_ref(), &[], &[], [&[], &[]]);
        // Clean columns and rows stop two short of a step (a step reaches two pixels).
        assert_eq!(b.gaps_x, vec![[0, 38], [162, 200]]);
        assert_eq!(b.margins_x, b.gaps_x);
        assert_eq!(b.gaps_y, vec![[0, 18], [92, 100]]);
        assert_eq!(b.margins_y, vec![[92, 100]], "{b:?}");
    }

    proptest! {
        /// Without text, the margins read from the ends inward are the gaps a scan of
        /// every pixel finds.
        #[test]
        fn margins_are_the_gaps_a_full_scan_finds(
            w in 3u32..60,
            h in 3u32..40,
            marks in prop::collection::vec((0u32..60, 0u32..40, 0u8..8), 0..6),
            area in any::<bool>(),
        ) {
            let mut img = Image::filled(Size::new(w, h).unwrap(), [250, 250, 250, 255]);
            for &(x, y, d) in &marks {
                // Faint steps (within STEP) and real ones.
                img.set(x % w, y % h, [250 - d, 250, 250, 255]);
            }
            let areas = match area {
                true => vec![DataArea {
                    x0: 1.0,
                    y0: 2.0,
                    x1: w as f64 / 2.0,
                    y1: h as f64 - 1.0,
                    kind: crate::structure::AreaKind::Axes,
                }],
                false => Vec::new(),
            };
            let (fast, full) = (detect(img.as_ref(), &[], &areas, [&[], &[]]), scan(img.as_ref(), &[], &areas));
            prop_assert_eq!(fast.gaps_x, full.gaps_x);
            prop_assert_eq!(fast.gaps_y, full.gaps_y);
            prop_assert!(fast.x.is_empty() && fast.y.is_empty());
        }
    }

    fn block(x0: u32, y0: u32, x1: u32, y1: u32) -> TextBlock {
        TextBlock::upright(x0, y0, x1, y1)
    }

    #[test]
    fn a_margin_of_labels_is_a_band_and_a_plot_is_not() {
        let mut img = Image::filled(Size::new(200, 100).unwrap(), [255, 255, 255, 255]);
        // A "label" at x 5..20 (its pixels are inside its box), a dot in the plot at x 100.
        for y in 40..50 {
            for x in 5..20 {
                img.set(x, y, [0, 0, 0, 255]);
            }
            for x in 98..104 {
                img.set(x, y + 20, [200, 0, 0, 255]);
            }
        }
        // A horizontal axis line across the whole width: it does not stop a band along x.
        for x in 0..200 {
            img.set(x, 90, [0, 0, 0, 255]);
        }
        // A label above the dot: its column has a step (the dot), so it is no band.
        let text = [block(5, 40, 19, 49), block(95, 10, 110, 20)];
        let b = detect(img.as_ref(), &text, &[], [&[], &[]]);
        assert_eq!(b.x, vec![[5, 20]]);
        // Rows 40..50 hold the label and the dot's rows do not overlap them; rows 10..20
        // hold the second label alone.
        assert_eq!(b.y, vec![[10, 21], [40, 50]]);
        // The blank columns left of the label touch the edge and the band: a gap. Those
        // right of it, up to the dot, touch the band too.
        assert_eq!(b.gaps_x.first(), Some(&[0, 5]));
        assert!(
            b.gaps_x.iter().all(|g| g[1] <= 97 || g[0] >= 104),
            "{:?}",
            b.gaps_x
        );
    }

    /// A legend: three labels set in one column at x 150, a mark in the first one's rows
    /// (a bubble at x 40). Rows are lent by the whole column or not at all; and a lone
    /// glyph-like ring left of the last label lends its rows alone, but a band may not take
    /// in most of the label beside it, which lends nothing.
    #[test]
    fn a_column_of_labels_lends_its_rows_all_or_none() {
        let mut img = Image::filled(Size::new(220, 120).unwrap(), [255; 4]);
        for y in 12..24 {
            for x in 36..48 {
                img.set(x, y, [30, 90, 200, 255]);
            }
        }
        let labels = [
            block(150, 10, 190, 22),
            block(150, 40, 190, 52),
            block(150, 70, 190, 82),
        ];
        let b = detect(img.as_ref(), &labels, &[], [&[], &[]]);
        assert!(b.y.is_empty(), "{:?}", b.y);
        let mut with_ring = labels.to_vec();
        with_ring.push(block(130, 71, 141, 82));
        let b = detect(img.as_ref(), &with_ring, &[], [&[], &[]]);
        assert!(b.y.iter().all(|r| r[1] <= 70 || r[0] >= 83), "{:?}", b.y);
        // Without the mark the whole column lends its rows.
        let clean = Image::filled(Size::new(220, 120).unwrap(), [255; 4]);
        let b = detect(clean.as_ref(), &labels, &[], [&[], &[]]);
        assert_eq!(b.y, vec![[10, 23], [40, 53], [70, 83]]);
    }

    /// In a stream, bands only narrow: a band lost in one frame does not come back, so the
    /// plot never moves back and forth.
    #[test]
    fn a_streams_bands_only_narrow() {
        let first = Bands {
            x: vec![[10, 40]],
            y: vec![[0, 20], [300, 320]],
            gaps_x: vec![[0, 10]],
            gaps_y: vec![[20, 30]],
            margins_x: vec![[0, 10]],
            margins_y: Vec::new(),
            free: true,
            ..Bands::default()
        };
        let transient = Bands {
            x: vec![[10, 40]],
            y: vec![[0, 20]],
            gaps_x: vec![[0, 10]],
            gaps_y: vec![[20, 30]],
            margins_x: Vec::new(),
            margins_y: Vec::new(),
            free: false,
            ..Bands::default()
        };
        let kept = transient.kept(&first);
        assert!(kept.margins_x.is_empty(), "a margin lost is lost");
        assert!(!kept.free, "a frame with axes makes the stream a chart");
        assert_eq!(kept.y, vec![[0, 20]]);
        let again = first.kept(&kept);
        assert_eq!(again, kept, "the lost band stays lost");
        let narrower = Bands {
            x: vec![[12, 50]],
            ..first.clone()
        };
        assert_eq!(narrower.kept(&again).x, vec![[12, 40]]);
    }

    #[test]
    fn a_colour_ramp_under_a_label_is_no_band() {
        let mut img = Image::filled(Size::new(120, 60).unwrap(), [255, 255, 255, 255]);
        for x in 0..120 {
            let v = 255 - (x * 3 / 2) as u8;
            for y in 0..10 {
                img.set(x, y, [v, v, 255, 255]);
            }
        }
        let b = detect(img.as_ref(), &[block(40, 30, 60, 40)], &[], [&[], &[]]);
        assert!(b.x.is_empty(), "{:?}", b.x);
    }

    #[test]
    fn no_band_inside_a_data_area() {
        let img = Image::filled(Size::new(100, 100).unwrap(), [255, 255, 255, 255]);
        let area = DataArea {
            x0: 30.0,
            y0: 30.0,
            x1: 90.0,
            y1: 90.0,
            kind: super::super::AreaKind::Axes,
        };
        let b = detect(
            img.as_ref(),
            &[block(50, 5, 60, 15), block(5, 50, 15, 60)],
            &[area],
            [&[], &[]],
        );
        assert_eq!(b.x, vec![[5, 16]]);
        assert_eq!(b.y, vec![[5, 16]]);
    }
}
