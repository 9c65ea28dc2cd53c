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
use super::{areas, Line, TextBlock};
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
/// Least share of a card's inside an x axis drawn alone spans ([`Page::labelled_axis`]).
const AXIS_SHARE: f64 = 0.5;
/// Least tick labels along each of its axes for a plot of an x axis drawn alone: three
/// make a scale, two may be a legend's.
const AXIS_LABELS: usize = 3;
/// How far from its axis a tick label stands, in its heights (tick, padding).
const AXIS_REACH_LINES: u32 = 3;
/// Pixels at each end of a frame's line that its rounded corners may take.
const CORNER_PX: u32 = 8;

/// The cards of `image` (text `text`, labelled plots `plots`, lines `lines`: horizontal,
/// vertical) on its page's `ground`; `None` where no gutter splits it or a part with drawn
/// content is not boxed.
pub(crate) fn detect(
    image: ImageRef<'_>,
    text: &[TextBlock],
    plots: &[[u32; 4]],
    lines: [&[Line]; 2],
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
        lines,
        ground: [ground[0], ground[1], ground[2], 255],
        tallest_line: text.iter().map(|t| t.line_height).max().unwrap_or(0),
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
    lines: [&'a [Line]; 2],
    ground: [u8; 4],
    /// The tallest line of type, pixels: how far a title may stand out of its frame.
    tallest_line: u32,
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

    /// Whether something crosses the run of ground lines `g` along axis `k` in `rect`: a
    /// pixel off the ground on every line of it (a tall card's thin side, which the stray
    /// pixels a ground line may have would let a cut sever).
    fn crossed(&self, rect: [u32; 4], k: usize, g: [u32; 2]) -> bool {
        let o = 1 - k;
        (rect[o]..rect[o + 2])
            .filter(|&q| !near(self.on_line(k, g[0], q), self.ground))
            .any(|q| (g[0] + 1..g[1]).all(|p| !near(self.on_line(k, p, q), self.ground)))
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
                .filter(|g| !self.crossed(rect, k, *g))
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

    /// The boxes of the text blocks whose centre lies in `rect`.
    fn words(&self, rect: [u32; 4]) -> Vec<[u32; 4]> {
        (self.text.iter())
            .map(|t| [t.x0, t.y0, t.x1 + 1, t.y1 + 1])
            .filter(|&t| centre_in(rect, t))
            .collect()
    }

    /// A panel of `rect` with its type's spans and its labelled plots' (grown over the words
    /// across their ends, as [`super::panels`] grows them), nothing else yet.
    fn spans(&self, rect: [u32; 4]) -> Panel {
        let words = self.words(rect);
        let plots: Vec<[u32; 4]> = (self.plots.iter().copied())
            .filter(|&p| centre_in(rect, p))
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
        let Some(content) = self.content(rect) else {
            // Ground alone: a part of no content.
            return Some(me);
        };
        let (boxed, titles) = self.framed(content);
        // A title set in the frame's line is type, read as text or not: it keeps its size.
        for (k, spans) in me.type_spans.iter_mut().enumerate() {
            *spans = merged(
                spans
                    .iter()
                    .copied()
                    .chain(titles.iter().map(|t| [t[k], t[k + 2]])),
            );
        }
        // A data area as large as the card is the card's frame, not a plot in it.
        let frame = |s: &[[u32; 2]], k: usize| {
            let side = (boxed[k + 2] - boxed[k]) as f64;
            (s.iter()).any(|s| (s[1] - s[0]) as f64 >= CARD_FRAME_SHARE * side)
        };
        if frame(&me.plots[0], 0) && frame(&me.plots[1], 1) {
            me.plots = [Vec::new(), Vec::new()];
        }
        let inside = self.boxed(boxed, &titles).map(|fill| {
            let inner = self.inner(boxed, &titles);
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
                if me.plots[0].is_empty() || me.plots[1].is_empty() {
                    me.plots = self.plots_in(inner);
                }
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
                let ink = self.ink(content, self.ground);
                (!ink.iter().any(|&i| i)).then_some(me)
            }
        }
    }

    /// The labelled plots inside a card's `inner` box, along each axis (grown over the words
    /// across their ends): the picture's data areas took the card's frame for the plot.
    fn plots_in(&self, inner: [u32; 4]) -> [Vec<[u32; 2]>; 2] {
        let r = inner.map(|v| v as f64);
        // A plot holding more words than its axes' labels is a picture of labelled cells (a
        // treemap, an annotated heat map): squeezed, its words at their size would no
        // longer fit their cells, so it keeps one scale with its card.
        let cells = |a: [u32; 4]| {
            let ticks = super::panels::tick_labels(a, self.text);
            let inside = (self.text.iter())
                .filter(|t| centre_in(a, [t.x0, t.y0, t.x1 + 1, t.y1 + 1]))
                .count();
            ticks < super::panels::LEAST_TICK_LABELS || inside > ticks
        };
        let mut found: Vec<[u32; 4]> = (areas::within(self.lines[0], self.lines[1], r).iter())
            .map(|a| [a.x0, a.y0, a.x1, a.y1].map(|v| v.round() as u32))
            .filter(|&a| !cells(a))
            .collect();
        if found.is_empty() {
            found.extend(self.labelled_axis(inner).filter(|&a| !cells(a)));
        }
        // Only the words on an axis' side of a plot (its tick labels, left and under it)
        // grow it: a card's title over the plot may straddle its end.
        let words = self.words(inner);
        std::array::from_fn(|k| {
            let o = 1 - k;
            let axis_side: Vec<[u32; 4]> = (words.iter().copied())
                .filter(|t| {
                    let c = (t[o] + t[o + 2]) / 2;
                    found.iter().any(|b| match k {
                        0 => c >= b[1] && t[1] >= b[1],
                        _ => c < b[2] && t[2] <= b[2],
                    })
                })
                .collect();
            let bare = merged(found.iter().map(|b| [b[k], b[k + 2]]));
            grown_over(&bare, &axis_side, k)
        })
    }

    /// The plot over an x axis drawn without its y axis (a web chart's baseline, a
    /// terminal's dotted axis): a long line across `inner` with tick labels under it, and
    /// a column of tick labels at its start, the plot reaching up to the topmost of them.
    fn labelled_axis(&self, inner: [u32; 4]) -> Option<[u32; 4]> {
        let long = (inner[2] - inner[0]) as f64 * AXIS_SHARE;
        let words = self.words(inner);
        (self.lines[0].iter())
            .filter(|l| {
                let inside = |v: f64, lo: u32, hi: u32| v >= lo as f64 && v <= hi as f64;
                l.to - l.from >= long
                    && inside(l.pos, inner[1], inner[3])
                    && inside(l.from, inner[0], inner[2])
                    && inside(l.to, inner[0], inner[2])
            })
            .filter_map(|l| {
                let (pos, from, to) = (l.pos as u32, l.from as u32, l.to as u32);
                let reach = |t: &[u32; 4]| AXIS_REACH_LINES * (t[3] - t[1]);
                let under = (words.iter())
                    .filter(|t| {
                        let cx = (t[0] + t[2]) / 2;
                        t[1] >= pos && t[1] <= pos + reach(t) && (from..to).contains(&cx)
                    })
                    .count();
                let left: Vec<&[u32; 4]> = (words.iter())
                    .filter(|t| {
                        // Up to its own height past the axis' start: the tick drawn with it.
                        let end = from + (t[3] - t[1]);
                        t[0] < from && t[2] <= end && t[2] + reach(t) >= from && t[3] <= pos + 2
                    })
                    .collect();
                let top = left.iter().map(|t| (t[1] + t[3]) / 2).min()?;
                (under >= AXIS_LABELS && left.len() >= AXIS_LABELS && top + 1 < pos).then_some([
                    from,
                    top,
                    to,
                    pos + 1,
                ])
            })
            .max_by_key(|p| (p[2] - p[0]) * (p[3] - p[1]))
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
    fn boxed(&self, r: [u32; 4], titles: &[[u32; 4]]) -> Option<[u8; 4]> {
        if r[2] - r[0] < LEAST_CARD_PX || r[3] - r[1] < LEAST_CARD_PX {
            return None;
        }
        // Along each line, the span the titles set in it hide.
        let edge = |k: usize, p: u32| {
            let o = 1 - k;
            let skip = (titles.iter())
                .filter(|t| t[k] <= p && p < t[k + 2])
                .fold([u32::MAX, 0], |s, t| [s[0].min(t[o]), s[1].max(t[o + 2])]);
            self.edge_line_but(r, k, p, skip)
        };
        let all = edge(1, r[1]) && edge(1, r[3] - 1) && edge(0, r[0]) && edge(0, r[2] - 1);
        all.then(|| self.commonest(r))
    }

    /// Whether line `p` along axis `k` across box `r` is mostly one colour other than the
    /// ground ([`EDGE_SHARE`]): a frame's line, or a fill's edge.
    fn edge_line(&self, r: [u32; 4], k: usize, p: u32) -> bool {
        self.edge_line_but(r, k, p, [0, 0])
    }

    /// [`Page::edge_line`] along the line but for span `skip` of it (a title's).
    fn edge_line_but(&self, r: [u32; 4], k: usize, p: u32, skip: [u32; 2]) -> bool {
        let o = 1 - k;
        let at = |q: u32| self.on_line(k, p, q);
        let (lo, hi) = (r[o], r[o + 2]);
        let kept = |q: &u32| *q < skip[0] || *q >= skip[1];
        let n = (lo..hi).filter(kept).count() as u32;
        if n == 0 || n < (hi - lo) / 4 {
            return false;
        }
        // The colour of a quarter, the middle or three quarters along, whichever most
        // of the line has (a title set in the frame's line hides one of them).
        let nth = |i: u32| (lo..hi).filter(kept).nth(i as usize);
        [1, 2, 3].iter().filter_map(|i| nth(n * i / 4)).any(|c0| {
            let c = at(c0);
            let same = (lo..hi).filter(kept).filter(|&q| near(at(q), c)).count();
            !near(c, self.ground) && same as f64 >= EDGE_SHARE * n as f64
        })
    }

    /// Box `r` (content on the ground) less what a title set in its frame's line sticks
    /// out beyond that line (a terminal's panels: the title over the frame's top line,
    /// standing taller than it), and the text blocks that do. Along each side whose line
    /// is no frame, the frame's line is sought inward, no further than the text across the
    /// side reaches.
    fn framed(&self, r: [u32; 4]) -> ([u32; 4], Vec<[u32; 4]>) {
        let mut b = r;
        let mut titles: Vec<[u32; 4]> = Vec::new();
        for (k, far) in [(1, false), (1, true), (0, false), (0, true)] {
            let o = 1 - k;
            if b[k + 2] - b[k] < LEAST_CARD_PX {
                break;
            }
            let side = if far { b[k + 2] - 1 } else { b[k] };
            if self.edge_line(b, k, side) {
                continue;
            }
            let across: Vec<[u32; 4]> = (self.text.iter())
                .map(|t| [t.x0, t.y0, t.x1 + 1, t.y1 + 1])
                .filter(|t| t[k] <= side && side < t[k + 2])
                .filter(|t| t[o] >= b[o] && t[o + 2] <= b[o + 2])
                .collect();
            // A title not read as text (its glyphs touch the line) reaches a line of type.
            let reach = (across.iter())
                .map(|t| {
                    if far {
                        side - t[k]
                    } else {
                        t[k + 2] - 1 - side
                    }
                })
                .max()
                .unwrap_or(self.tallest_line);
            // The span the ink sticking out covers along the side, so far: the title's,
            // which hides that much of the frame's line.
            let mut stuck = [u32::MAX, 0];
            let mut found = None;
            for d in 1..=reach.min((b[k + 2] - b[k]) / 2) {
                let l = if far { side + 1 - d } else { side + d - 1 };
                for q in b[o]..b[o + 2] {
                    if !near(self.on_line(k, l, q), self.ground) {
                        stuck = [stuck[0].min(q), stuck[1].max(q + 1)];
                    }
                }
                let p = if far { side - d } else { side + d };
                if self.edge_line_but(b, k, p, stuck) {
                    found = Some((p, d));
                    break;
                }
            }
            let Some((p, d)) = found else {
                continue;
            };
            if across.is_empty() && stuck[0] < stuck[1] {
                // The title's box: the ink sticking out, as far again past the line.
                let (k0, k1) = match far {
                    true => (p.saturating_sub(d), side + 1),
                    false => (side, p + d + 1),
                };
                titles.push(match k {
                    0 => [k0, stuck[0], k1, stuck[1]],
                    _ => [stuck[0], k0, stuck[1], k1],
                });
            }
            match far {
                true => b[k + 2] = p + 1,
                false => b[k] = p,
            }
            titles.extend(across);
        }
        (b, titles)
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
    /// frame's lines, its padding; the `titles` set in them aside); `None` for a box of
    /// such lines alone.
    fn inner(&self, r: [u32; 4], titles: &[[u32; 4]]) -> Option<[u32; 4]> {
        let plain = |k: usize, p: u32| match titles.is_empty() {
            true => self.plain_line(r, k, p),
            false => self.plain_line_but(r, k, p, titles),
        };
        let mut i = r;
        for k in 0..2 {
            while i[k] < i[k + 2] && plain(k, i[k]) {
                i[k] += 1;
            }
            while i[k + 2] > i[k] && plain(k, i[k + 2] - 1) {
                i[k + 2] -= 1;
            }
        }
        (i[0] < i[2] && i[1] < i[3]).then_some(i)
    }

    /// [`Page::plain_line`], the pixels of boxes `skip` aside.
    fn plain_line_but(&self, rect: [u32; 4], k: usize, p: u32, skip: &[[u32; 4]]) -> bool {
        let o = 1 - k;
        let n = rect[o + 2] - rect[o];
        let corner = CORNER_PX.min(n / 8);
        let skipped =
            |q: u32| (skip.iter()).any(|b| b[o] <= q && q < b[o + 2] && b[k] <= p && p < b[k + 2]);
        let mut seen = (rect[o] + corner..rect[o + 2] - corner)
            .filter(|&q| !skipped(q))
            .map(|q| self.on_line(k, p, q));
        let Some(c) = seen.next() else {
            return true;
        };
        seen.all(|v| near(v, c))
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

/// Whether the centre of box `b` lies in `rect`.
fn centre_in(rect: [u32; 4], b: [u32; 4]) -> bool {
    let (cx, cy) = ((b[0] + b[2]) / 2, (b[1] + b[3]) / 2);
    cx >= rect[0] && cx < rect[2] && cy >= rect[1] && cy < rect[3]
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
        let root = detect(img.as_ref(), &text, &[], [&[], &[]], [240, 240, 240]).expect("cards");
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

    /// A terminal's panels: frames of one thin line on a black page, each filled with the
    /// page's black, their titles set in the top line and standing taller than it (one title
    /// not read as text). A tall panel beside two short ones: the row between the short ones
    /// crosses the tall one's sides, and is no gutter. Three cards, each framed at its line.
    #[test]
    fn framed_panels_with_titles_in_their_lines_are_cards() {
        const BLACK: [u8; 4] = [0, 0, 0, 255];
        const LINE: [u8; 4] = [9, 206, 208, 255];
        let mut img = Image::filled(Size::new(400, 300).unwrap(), BLACK);
        let frame = |img: &mut Image, r: [u32; 4]| {
            fill(img, [r[0], r[1], r[2], r[1] + 1], LINE);
            fill(img, [r[0], r[3] - 1, r[2], r[3]], LINE);
            fill(img, [r[0], r[1], r[0] + 1, r[3]], LINE);
            fill(img, [r[2] - 1, r[1], r[2], r[3]], LINE);
        };
        let boxes = [[5, 20, 195, 290], [205, 20, 395, 140], [205, 170, 395, 290]];
        let mut text = Vec::new();
        for (i, b) in boxes.iter().enumerate() {
            frame(&mut img, *b);
            // The title: 12 px of type over the line, from 6 px above it.
            let t = title(b[0] + 10, b[1] - 6);
            fill(&mut img, [t.x0, t.y0, t.x1, t.y1], [255; 4]);
            if i != 2 {
                text.push(t);
            }
            // A body: two bars inside.
            fill(&mut img, [b[0] + 30, b[3] - 60, b[0] + 60, b[3] - 20], LINE);
            fill(
                &mut img,
                [b[0] + 80, b[3] - 80, b[0] + 110, b[3] - 30],
                LINE,
            );
        }
        let root = detect(img.as_ref(), &text, &[], [&[], &[]], [0, 0, 0]).expect("cards");
        let leaves = root.leaves();
        let cards: Vec<&Card> = leaves.iter().filter_map(|l| l.card.as_ref()).collect();
        assert_eq!(
            cards.len(),
            3,
            "{:?}",
            cards.iter().map(|c| c.frame).collect::<Vec<_>>()
        );
        for (l, b) in leaves.iter().zip(boxes) {
            // Each title is type, the one not read as text too: it keeps its size.
            let title = [b[1] - 6, b[1] + 6];
            let typed = |s: &[u32; 2]| s[0] <= title[0] && title[1] <= s[1];
            assert!(l.type_spans[1].iter().any(typed), "{:?}", l.type_spans[1]);
        }
        for (c, b) in cards.iter().zip(boxes) {
            assert_eq!(c.frame, b, "framed at its line, not at its title's top");
            assert!(
                c.inner[1] > b[1],
                "the frame's line is no part of its inside"
            );
            let body = c.body.expect("a body");
            assert_eq!(
                body[1],
                [b[3] - 80, b[3] - 20],
                "the body is the bars alone"
            );
        }
    }

    /// A card's chart drawn with its x axis alone (a web chart's baseline): the line with
    /// tick labels under it and a column of tick labels at its start is a plot, reaching up
    /// to the topmost label; a line with labels under it alone is none.
    #[test]
    fn an_x_axis_with_labels_on_both_sides_is_a_cards_plot() {
        let mut img = Image::filled(Size::new(400, 300).unwrap(), GROUND);
        let block = |x0: u32, y0: u32, w: u32| TextBlock {
            x0,
            y0,
            x1: x0 + w,
            y1: y0 + 12,
            line_height: 12,
            sideways: false,
        };
        let mut text = vec![title(20, 20), title(220, 20)];
        for x0 in [10, 210] {
            fill(&mut img, [x0, 10, x0 + 180, 290], [200, 200, 200, 255]);
            fill(&mut img, [x0 + 1, 11, x0 + 179, 289], [255; 4]);
            // The axis, a series over it.
            fill(&mut img, [x0 + 40, 240, x0 + 170, 241], [0, 0, 0, 255]);
            fill(&mut img, [x0 + 60, 120, x0 + 150, 200], [30, 120, 180, 255]);
            // Under the axis, three tick labels.
            text.extend((0..3).map(|i| block(x0 + 50 + 40 * i, 246, 20)));
        }
        // At the start of the left card's axis, three tick labels up its height.
        text.extend((0..3).map(|i| block(22, 90 + 60 * i, 16)));
        for t in &text {
            fill(&mut img, [t.x0, t.y0, t.x1, t.y1], [60, 60, 60, 255]);
        }
        let axis = Line {
            pos: 240.5,
            from: 50.0,
            to: 180.0,
            width: 1,
        };
        let other = Line {
            from: 250.0,
            to: 380.0,
            ..axis
        };
        let h = [axis, other];
        let root = detect(img.as_ref(), &text, &[], [&h, &[]], [240, 240, 240]).expect("cards");
        let leaves = root.leaves();
        assert_eq!(leaves.len(), 2);
        // Up to the top label, grown over it as a plot is over the words across its ends.
        assert_eq!(leaves[0].plots, [vec![[50, 180]], vec![[90, 241]]]);
        assert!(leaves[1].plots.iter().all(|p| p.is_empty()));
    }

    /// A grid with its tick labels beside it in a card is a plot; the same grid holding
    /// more words than its axis has labels (a treemap's, an annotated heat map's cells) is
    /// none: its words would not fit their cells squeezed.
    #[test]
    fn a_grid_of_labelled_cells_is_no_cards_plot() {
        let mut img = Image::filled(Size::new(400, 300).unwrap(), GROUND);
        let block = |x0: u32, y0: u32| TextBlock {
            x0,
            y0,
            x1: x0 + 16,
            y1: y0 + 12,
            line_height: 12,
            sideways: false,
        };
        let mut text = vec![title(20, 20), title(220, 20)];
        let mut h = Vec::new();
        for x0 in [10, 210] {
            fill(&mut img, [x0, 10, x0 + 180, 290], [200, 200, 200, 255]);
            fill(&mut img, [x0 + 1, 11, x0 + 179, 289], [255; 4]);
            for i in 0..5 {
                let y = 80 + 40 * i;
                fill(&mut img, [x0 + 50, y, x0 + 170, y + 1], [0, 0, 0, 255]);
                h.push(Line {
                    pos: y as f64 + 0.5,
                    from: (x0 + 50) as f64,
                    to: (x0 + 170) as f64,
                    width: 1,
                });
                // A tick label at each line's start.
                text.push(block(x0 + 20, y - 6));
            }
        }
        // The right card's cells each hold a word.
        text.extend((0..4).flat_map(|i| [block(270, 94 + 40 * i), block(330, 94 + 40 * i)]));
        for t in &text {
            fill(&mut img, [t.x0, t.y0, t.x1, t.y1], [60, 60, 60, 255]);
        }
        let root = detect(img.as_ref(), &text, &[], [&h, &[]], [240, 240, 240]).expect("cards");
        let leaves = root.leaves();
        assert_eq!(leaves.len(), 2);
        assert_eq!(leaves[0].plots[1], vec![[74, 247]], "{:?}", leaves[0].plots);
        assert!(leaves[1].plots.iter().all(|p| p.is_empty()));
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
        assert!(detect(img.as_ref(), &[], &[], [&[], &[]], [240, 240, 240]).is_none());
        let mut bars = Image::filled(Size::new(400, 200).unwrap(), GROUND);
        for i in 0..8 {
            fill(
                &mut bars,
                [20 + 45 * i, 150 - 15 * i, 55 + 45 * i, 190],
                [150, 100, 200, 255],
            );
        }
        assert!(detect(bars.as_ref(), &[], &[], [&[], &[]], [240, 240, 240]).is_none());
    }
}
