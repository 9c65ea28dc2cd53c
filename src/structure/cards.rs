//! Cards: a dashboard's boxes, framed or filled, standing apart on the page's ground (a
//! header bar, a chart's card, a map's, a table's, a row of figures). A responsive page gives
//! each card a slot of the new screen and lays its content out in it: a chart squeezed with
//! its type at its size, a map or a picture at one scale, its title at its size. One map per
//! axis for the whole page cannot (the cards of one row are not those of the next), and the
//! panels between plots ([`super::panels`]) find no plot in a map's or a table's card.
//!
//! The page is cut along its gutters, runs of the page's ground colour across the part
//! being cut (an XY cut, rows first); every part with drawn content must be boxed (its edges
//! one colour that is not the ground: a frame or a fill), else the picture is no page of
//! cards.

use super::panels::{clean_lines, grown_over, pieces, Card, Panel, Split};
use super::spans::{merged, runs_where};
use super::TextBlock;
use crate::image::ImageRef;

/// Most a pixel may differ from a colour, per channel, and still be of it: flat fills but
/// for a compression's faint noise.
const TOL: i16 = 6;
/// Least gutter between two cards, pixels.
const LEAST_GUTTER_PX: u32 = 3;
/// Least side of a card, pixels.
const LEAST_CARD_PX: u32 = 24;
/// Deepest nesting of cuts: rows of columns of rows of cards.
const MOST_DEPTH: u32 = 4;
/// Least share of a box's edge line in one colour: a frame's line with its title set in it,
/// a fill with a shadow's corner.
const EDGE_SHARE: f64 = 0.7;
/// Most share of a ground line's pixels that may be something else.
const STRAY_SHARE: f64 = 0.01;
/// Stray pixels a ground line may have whatever its length (a window's rounded corner).
const STRAY_PX: usize = 8;
/// Most gap, pixels, between a card's body and text beside it that goes with it (or the
/// text's line height, where more): a colour bar's labels under it, a bar's label left of
/// it, a facet's title over it (a card's title stands further, past its rule).
const JOIN_PX: u32 = 12;
/// Distinct colours a card's fill is sought among (the first seen, on its sparse grid).
const COLOURS_COUNTED: usize = 32;
/// Least share of a card's sides a data area covers to be the card's frame.
const CARD_FRAME_SHARE: f64 = 0.9;
/// Pixels at each end of a frame's line that its rounded corners may take.
const CORNER_PX: u32 = 8;

/// The cards of `image` (text `text`, labelled plots `plots`) on its page's `ground`; `None`
/// where no gutter splits it or a part with drawn content is not boxed.
pub(crate) fn detect(
    image: ImageRef<'_>,
    text: &[TextBlock],
    plots: &[[u32; 4]],
    ground: [u8; 3],
) -> Option<Panel> {
    let (w, h) = (image.width(), image.height());
    if w < 2 * LEAST_CARD_PX || h < 2 * LEAST_CARD_PX {
        return None;
    }
    let page = Page {
        image,
        text,
        plots,
        ground: [ground[0], ground[1], ground[2], 255],
    };
    let root = page.cut([0, 0, w, h], 0)?;
    root.split.as_ref()?;
    let leaves = root.leaves();
    let boxed = leaves.iter().filter(|l| l.card.is_some()).count();
    (boxed >= 2).then_some(root)
}

struct Page<'a> {
    image: ImageRef<'a>,
    text: &'a [TextBlock],
    plots: &'a [[u32; 4]],
    ground: [u8; 4],
}

fn near(a: [u8; 4], b: [u8; 4]) -> bool {
    (0..3).all(|c| (a[c] as i16 - b[c] as i16).abs() <= TOL)
}

impl Page<'_> {
    fn px(&self, x: u32, y: u32) -> [u8; 4] {
        self.image.pixels()[y as usize * self.image.width() as usize + x as usize]
    }

    /// The pixel at `q` along line `p` of axis `k` (0: a column, 1: a row).
    fn on_line(&self, k: usize, p: u32, q: u32) -> [u8; 4] {
        match k {
            0 => self.px(p, q),
            _ => self.px(q, p),
        }
    }

    /// Whether line `p` along axis `k` is the ground across `rect`, but for a few pixels
    /// ([`STRAY_SHARE`]: a window's corner, a stray mark).
    fn ground_line(&self, rect: [u32; 4], k: usize, p: u32) -> bool {
        let o = 1 - k;
        let n = rect[o + 2] - rect[o];
        let allowed = ((n as f64 * STRAY_SHARE) as usize).max(STRAY_PX);
        (rect[o]..rect[o + 2])
            .filter(|&q| !near(self.on_line(k, p, q), self.ground))
            .nth(allowed)
            .is_none()
    }

    /// Whether line `p` along axis `k` is one colour across `rect` but near its ends (a
    /// frame's line or the padding inside it, between rounded corners).
    fn plain_line(&self, rect: [u32; 4], k: usize, p: u32) -> bool {
        let o = 1 - k;
        let n = rect[o + 2] - rect[o];
        let corner = CORNER_PX.min(n / 8);
        let c = self.on_line(k, p, rect[o] + n / 2);
        (rect[o] + corner..rect[o + 2] - corner).all(|q| near(self.on_line(k, p, q), c))
    }

    /// The panel of `rect`, cut along its gutters, or its card; `None` where a part with
    /// drawn content is not boxed.
    fn cut(&self, rect: [u32; 4], depth: u32) -> Option<Panel> {
        let gutters: [Vec<[u32; 2]>; 2] = std::array::from_fn(|k| {
            let (lo, hi) = (rect[k], rect[k + 2]);
            runs_where(lo, hi, |p| self.ground_line(rect, k, p))
                .into_iter()
                .filter(|g| g[0] > lo && g[1] < hi && g[1] - g[0] >= LEAST_GUTTER_PX)
                .collect()
        });
        let cuts: [Vec<u32>; 2] = std::array::from_fn(|k| {
            let mut cuts = Vec::new();
            for g in &gutters[k] {
                let cut = (g[0] + g[1]) / 2;
                let prev = cuts.last().copied().unwrap_or(rect[k]);
                if cut - prev >= LEAST_CARD_PX && rect[k + 2] - cut >= LEAST_CARD_PX {
                    cuts.push(cut);
                }
            }
            cuts
        });
        let k = match cuts[1].len() >= cuts[0].len() {
            true => 1,
            false => 0,
        };
        if depth >= MOST_DEPTH || cuts[k].is_empty() {
            return self.leaf(rect);
        }
        let parts = (pieces(rect, k, &cuts[k]).into_iter())
            .map(|r| self.cut(r, depth + 1))
            .collect::<Option<Vec<Panel>>>()?;
        // Along the cut, the parts with a body take the room the gutters and the parts of
        // text alone leave ([`crate::render::AxisMap::around_plots`]).
        let bodies: [Vec<[u32; 2]>; 2] = std::array::from_fn(|a| {
            merged(
                parts
                    .iter()
                    .filter(|p| holds_body(p))
                    .map(|p| [p.rect[a], p.rect[a + 2]]),
            )
        });
        let mut me = self.spans(rect);
        me.plots = bodies;
        me.blank = std::array::from_fn(|a| match a == k {
            true => gutters[k].clone(),
            false => Vec::new(),
        });
        me.split = Some(Split {
            columns: k == 0,
            parts,
            own: true,
        });
        Some(me)
    }

    /// A panel of `rect` with its type's spans and its labelled plots' (grown over the words
    /// across their ends, as [`super::panels`] grows them), nothing else yet.
    fn spans(&self, rect: [u32; 4]) -> Panel {
        let centre_in = |b: [u32; 4]| {
            let (cx, cy) = ((b[0] + b[2]) / 2, (b[1] + b[3]) / 2);
            cx >= rect[0] && cx < rect[2] && cy >= rect[1] && cy < rect[3]
        };
        let words: Vec<[u32; 4]> = (self.text.iter())
            .map(|t| [t.x0, t.y0, t.x1 + 1, t.y1 + 1])
            .filter(|&t| centre_in(t))
            .collect();
        let plots: Vec<[u32; 4]> = (self.plots.iter().copied())
            .filter(|&p| centre_in(p))
            .collect();
        let along = |b: &[u32; 4], k: usize| [b[k], b[k + 2]];
        Panel {
            rect,
            plots: std::array::from_fn(|k| {
                let bare = merged(plots.iter().map(|b| along(b, k)));
                grown_over(&bare, &words, k)
            }),
            type_spans: std::array::from_fn(|k| merged(words.iter().map(|b| along(b, k)))),
            blank: [Vec::new(), Vec::new()],
            split: None,
            card: None,
        }
    }

    /// The leaf of `rect`: a card where its content is boxed, a panel of text alone where
    /// it holds no drawn content, `None` (no page of cards) otherwise.
    fn leaf(&self, rect: [u32; 4]) -> Option<Panel> {
        let mut me = self.spans(rect);
        let Some(boxed) = self.content(rect) else {
            // Ground alone: a part of no content.
            return Some(me);
        };
        // A data area as large as the card is the card's frame, not a plot in it.
        let frame = |s: &[[u32; 2]], k: usize| {
            let side = (boxed[k + 2] - boxed[k]) as f64;
            (s.iter()).any(|s| (s[1] - s[0]) as f64 >= CARD_FRAME_SHARE * side)
        };
        if frame(&me.plots[0], 0) && frame(&me.plots[1], 1) {
            me.plots = [Vec::new(), Vec::new()];
        }
        let inside = self.boxed(boxed).map(|fill| {
            let inner = self.inner(boxed);
            let body = inner.and_then(|i| self.body(i, fill));
            let i = inner.unwrap_or(boxed);
            let stretch = std::array::from_fn(|k| match body {
                Some(b) => {
                    let fill_line = |p: &u32| {
                        self.plain_line(boxed, k, *p)
                            && near(self.on_line(k, *p, (boxed[1 - k] + boxed[3 - k]) / 2), fill)
                    };
                    let before = middle_run((i[k]..b[k][0]).rev(), fill_line);
                    let after = middle_run(b[k][1].max(i[k + 2])..boxed[k + 2], fill_line);
                    [before, after]
                }
                None => [None, None],
            });
            (inner, body, stretch)
        });
        match inside {
            // A box of its fill alone (a bar, a heat map's cell, a swatch) is a mark, drawn
            // on the ground as the rest of a chart is: no page of cards.
            Some((None, _, _)) => None,
            Some((Some(inner), body, stretch)) => {
                me.card = Some(Card {
                    body,
                    frame: boxed,
                    inner,
                    stretch,
                });
                // Its blank runs, for a card laid out around its plots (a card without
                // plots finds its own, beside its body).
                if !me.plots[0].is_empty() && !me.plots[1].is_empty() {
                    me.blank = std::array::from_fn(|k| {
                        let clean = clean_lines(self.image, rect, k == 0);
                        runs_where(rect[k], rect[k + 2], |p| clean[(p - rect[k]) as usize])
                    });
                }
                Some(me)
            }
            None => {
                // Unboxed: only text on the ground (a page's title) may stand outside cards.
                let ink = self.ink(boxed, self.ground);
                (!ink.iter().any(|&i| i)).then_some(me)
            }
        }
    }

    /// `rect` less the ground lines around it; `None` for ground alone.
    fn content(&self, rect: [u32; 4]) -> Option<[u32; 4]> {
        let mut r = rect;
        while r[1] < r[3] && self.ground_line(r, 1, r[1]) {
            r[1] += 1;
        }
        while r[3] > r[1] && self.ground_line(r, 1, r[3] - 1) {
            r[3] -= 1;
        }
        while r[0] < r[2] && self.ground_line(r, 0, r[0]) {
            r[0] += 1;
        }
        while r[2] > r[0] && self.ground_line(r, 0, r[2] - 1) {
            r[2] -= 1;
        }
        (r[0] < r[2] && r[1] < r[3]).then_some(r)
    }

    /// The fill of box `r` where its four edges are each mostly one colour other than the
    /// ground (a frame or a fill): the commonest colour of its inside.
    fn boxed(&self, r: [u32; 4]) -> Option<[u8; 4]> {
        if r[2] - r[0] < LEAST_CARD_PX || r[3] - r[1] < LEAST_CARD_PX {
            return None;
        }
        let edge = |k: usize, p: u32| {
            let o = 1 - k;
            let at = |q: u32| self.on_line(k, p, q);
            let (lo, hi) = (r[o], r[o + 2]);
            let n = hi - lo;
            // The colour of a quarter, the middle or three quarters along, whichever most
            // of the line has (a title set in the frame's line hides one of them).
            [1, 2, 3].iter().any(|i| {
                let c = at(lo + n * i / 4);
                let same = (lo..hi).filter(|&q| near(at(q), c)).count();
                !near(c, self.ground) && same as f64 >= EDGE_SHARE * n as f64
            })
        };
        let all = edge(1, r[1]) && edge(1, r[3] - 1) && edge(0, r[0]) && edge(0, r[2] - 1);
        all.then(|| self.commonest(r))
    }

    /// The commonest colour of `r`, read on a sparse grid: a fill outnumbers every other
    /// colour, so a run of equal pixels counts once and the first few colours seen suffice.
    fn commonest(&self, r: [u32; 4]) -> [u8; 4] {
        let mut count: Vec<([u8; 4], u32)> = Vec::with_capacity(COLOURS_COUNTED);
        for y in (r[1]..r[3]).step_by(4) {
            for x in (r[0]..r[2]).step_by(4) {
                let p = self.px(x, y);
                if let Some(c) = count.iter_mut().find(|c| c.0 == p) {
                    c.1 += 1;
                } else if count.len() < COLOURS_COUNTED {
                    count.push((p, 1));
                }
            }
        }
        (count.into_iter())
            .max_by_key(|&(c, n)| (n, std::cmp::Reverse(c)))
            .map_or([255; 4], |(c, _)| c)
    }

    /// For each pixel of `r`, row by row: whether it is ink, other than `fill` and outside
    /// every text block (and the pixel around it).
    fn ink(&self, r: [u32; 4], fill: [u8; 4]) -> Vec<bool> {
        let (w, h) = ((r[2] - r[0]) as usize, (r[3] - r[1]) as usize);
        let mut ink = vec![false; w * h];
        for y in r[1]..r[3] {
            for x in r[0]..r[2] {
                ink[(y - r[1]) as usize * w + (x - r[0]) as usize] = !near(self.px(x, y), fill);
            }
        }
        for t in self.text {
            let (x0, y0) = (
                t.x0.saturating_sub(1).max(r[0]),
                t.y0.saturating_sub(1).max(r[1]),
            );
            let (x1, y1) = ((t.x1 + 2).min(r[2]), (t.y1 + 2).min(r[3]));
            for y in y0..y1.max(y0) {
                for x in x0..x1.max(x0) {
                    ink[(y - r[1]) as usize * w + (x - r[0]) as usize] = false;
                }
            }
        }
        ink
    }

    /// The inside of box `r`: less the lines along its edges one colour across (its
    /// frame's lines, its padding); `None` for a box of such lines alone.
    fn inner(&self, r: [u32; 4]) -> Option<[u32; 4]> {
        let mut i = r;
        for k in 0..2 {
            while i[k] < i[k + 2] && self.plain_line(r, k, i[k]) {
                i[k] += 1;
            }
            while i[k + 2] > i[k] && self.plain_line(r, k, i[k + 2] - 1) {
                i[k + 2] -= 1;
            }
        }
        (i[0] < i[2] && i[1] < i[3]).then_some(i)
    }

    /// The body of inside `i` of a box filled with `fill`: from the first to the last line
    /// along each axis that holds ink outside text; `None` for a box of text alone.
    fn body(&self, i: [u32; 4], fill: [u8; 4]) -> Option<[[u32; 2]; 2]> {
        let mut ink = self.ink(i, fill);
        let (w, h) = ((i[2] - i[0]) as usize, (i[3] - i[1]) as usize);
        // A rule across the card (under its title, between a table's rows) is a line, not
        // a body: it stretches with the card.
        for k in 0..2 {
            for p in i[k]..i[k + 2] {
                if self.plain_line(i, k, p) {
                    let q = (p - i[k]) as usize;
                    match k {
                        0 => (0..h).for_each(|y| ink[y * w + q] = false),
                        _ => ink[q * w..(q + 1) * w].fill(false),
                    }
                }
            }
        }
        let rows: Vec<bool> = (0..h)
            .map(|y| ink[y * w..(y + 1) * w].iter().any(|&v| v))
            .collect();
        let cols: Vec<bool> = (0..w).map(|x| (0..h).any(|y| ink[y * w + x])).collect();
        let span = |lines: &[bool], at: u32| {
            let first = lines.iter().position(|&v| v)? as u32;
            let last = lines.iter().rposition(|&v| v)? as u32;
            Some([at + first, at + last + 1])
        };
        let mut b = [span(&cols, i[0])?, span(&rows, i[1])?];
        // Text beside the body is its own (a table's or a bar chart's row labels, a legend,
        // a colour bar's labels): at the body's one scale, it is never condensed. Text across
        // a gap (a card's title over it) keeps its size.
        loop {
            let grown = (self.text.iter())
                .filter(|t| {
                    let (cx, cy) = ((t.x0 + t.x1) / 2, (t.y0 + t.y1) / 2);
                    (i[0]..i[2]).contains(&cx) && (i[1]..i[3]).contains(&cy)
                })
                .fold(b, |b, t| {
                    let join = JOIN_PX.max(t.line_height);
                    let t = [[t.x0, t.x1 + 1], [t.y0, t.y1 + 1]];
                    let beside = (0..2).any(|k| {
                        let o = 1 - k;
                        let across = t[o][0] < b[o][1] && t[o][1] > b[o][0];
                        let near = t[k][1] + join >= b[k][0] && t[k][0] <= b[k][1] + join;
                        across && near
                    });
                    match beside {
                        true => {
                            std::array::from_fn(|k| [b[k][0].min(t[k][0]), b[k][1].max(t[k][1])])
                        }
                        false => b,
                    }
                });
            if grown == b {
                break;
            }
            b = grown;
        }
        Some(b)
    }
}

/// The middle of the first run of `lines` (in the order given) where `ok` holds.
fn middle_run(lines: impl Iterator<Item = u32>, ok: impl Fn(&u32) -> bool) -> Option<u32> {
    let run: Vec<u32> = lines.skip_while(|p| !ok(p)).take_while(|p| ok(p)).collect();
    run.get(run.len() / 2).copied()
}

/// Whether panel `p` holds drawn content: a card's body or a plot, in it or in its parts.
fn holds_body(p: &Panel) -> bool {
    p.leaves()
        .iter()
        .any(|l| l.card.as_ref().is_some_and(|c| c.body.is_some()) || !l.plots[0].is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Image, Size};

    const GROUND: [u8; 4] = [240, 240, 240, 255];

    fn fill(img: &mut Image, r: [u32; 4], c: [u8; 4]) {
        for y in r[1]..r[3] {
            for x in r[0]..r[2] {
                img.set(x, y, c);
            }
        }
    }

    fn title(x0: u32, y0: u32) -> TextBlock {
        TextBlock {
            x0,
            y0,
            x1: x0 + 80,
            y1: y0 + 12,
            line_height: 12,
            sideways: false,
        }
    }

    /// Two framed cards on a page's ground, each a title and a body: two cards, side by
    /// side, each body found under its title, the title outside it.
    #[test]
    fn framed_boxes_on_the_ground_are_cards() {
        let mut img = Image::filled(Size::new(400, 200).unwrap(), GROUND);
        let text = [title(20, 20), title(220, 20)];
        for x0 in [10, 210] {
            fill(&mut img, [x0, 10, x0 + 180, 190], [200, 200, 200, 255]);
            fill(&mut img, [x0 + 1, 11, x0 + 179, 189], [255; 4]);
            fill(&mut img, [x0 + 30, 70, x0 + 150, 170], [30, 120, 180, 255]);
        }
        for t in &text {
            fill(&mut img, [t.x0, t.y0, t.x1, t.y1], [0, 0, 0, 255]);
        }
        let root = detect(img.as_ref(), &text, &[], [240, 240, 240]).expect("cards");
        let split = root.split.as_ref().unwrap();
        assert!(split.columns && split.own);
        let leaves = root.leaves();
        assert_eq!(leaves.len(), 2);
        for (l, x0) in leaves.iter().zip([10, 210]) {
            let card = l.card.as_ref().expect("a card");
            assert_eq!(card.frame, [x0, 10, x0 + 180, 190]);
            assert_eq!(card.body, Some([[x0 + 30, x0 + 150], [70, 170]]));
            assert!(card.stretch[1][0].is_some_and(|y| y > 32 && y < 70));
        }
    }

    /// Ink standing on the ground outside any box (a chart drawn on the page itself), or
    /// boxes of their fill alone (a histogram's bars), are no page of cards.
    #[test]
    fn ink_on_the_ground_is_no_card() {
        let mut img = Image::filled(Size::new(400, 200).unwrap(), GROUND);
        fill(&mut img, [10, 10, 190, 190], [255; 4]);
        fill(&mut img, [230, 40, 380, 42], [0, 0, 0, 255]);
        fill(&mut img, [230, 40, 232, 180], [0, 0, 0, 255]);
        fill(&mut img, [260, 100, 280, 120], [200, 30, 30, 255]);
        assert!(detect(img.as_ref(), &[], &[], [240, 240, 240]).is_none());
        let mut bars = Image::filled(Size::new(400, 200).unwrap(), GROUND);
        for i in 0..8 {
            fill(
                &mut bars,
                [20 + 45 * i, 150 - 15 * i, 55 + 45 * i, 190],
                [150, 100, 200, 255],
            );
        }
        assert!(detect(bars.as_ref(), &[], &[], [240, 240, 240]).is_none());
    }
}
