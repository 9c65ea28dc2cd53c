//! The structure a visualization is made of, found from pixels only: long horizontal and
//! vertical lines (panel frames, axes, grid lines, bar sides) and text blocks. The mesh puts
//! vertices and edges on them and the solver keeps lines straight and axis-aligned and text
//! blocks similar (one scale, no shear), which the paper's energy alone does not.
//!
//! * `lines`: runs of luminance steps along pixel-row and -column boundaries;
//! * `text`: rows of small high-contrast components;
//! * `areas`: data areas, the rectangles bounded by axes, frames, grids or a baseline, where
//!   the warp is one affine map.

mod areas;
mod bands;
mod cards;
mod lines;
mod luma;
mod mask;
mod panels;
mod spans;
mod text;

pub use areas::{AreaKind, DataArea};
pub use bands::{Bands, Scene};
pub use lines::Line;
pub use panels::{Card, Panel, Split};
pub use text::TextBlock;
pub(crate) use text::ALIGNED_PX;

use crate::image::ImageRef;

/// What was found in one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Structure {
    /// Horizontal lines: `pos` is y.
    pub horizontal: Vec<Line>,
    /// Vertical lines: `pos` is x.
    pub vertical: Vec<Line>,
    /// Text blocks.
    pub text: Vec<TextBlock>,
    /// Data areas: one axis-aligned affine map each.
    pub areas: Vec<DataArea>,
    /// The columns and rows where only text stands, kept at their size on a canvas taken
    /// whole ([`Regions::Affine`]; empty otherwise).
    pub bands: Bands,
}

/// Least ratio of height to width of a block of text set up the side (a y axis' title): a
/// word of a few letters; a lone glyph or a column of digits turned over is no word.
const MIN_ROTATED_ASPECT: u32 = 2;

/// Text set up the side (a y axis' title, turned 90° either way): the text of the transposed
/// picture (`transposed`, the `w × h` luma's [`luma::transposed`]), turned back.
fn rotated_text(
    transposed: &[u8],
    w: usize,
    h: usize,
    [horizontal, vertical]: [&[Line]; 2],
) -> Vec<TextBlock> {
    text::detect(transposed, h, w, [vertical, horizontal], &[])
        .into_iter()
        .map(|b| TextBlock {
            x0: b.y0,
            y0: b.x0,
            x1: b.y1,
            y1: b.x1,
            line_height: b.line_height,
            sideways: true,
        })
        .filter(|b| b.y1 - b.y0 >= MIN_ROTATED_ASPECT * (b.x1 - b.x0))
        .collect()
}

/// Most gap between upright pieces of one sideways word, as a share of its line height:
/// the space between two letters.
const LETTER_GAP: f64 = 0.15;

/// Spread of heights (as a share of the tallest) above which upright blocks are not labels
/// of one type set in a column: the pieces of a sideways word are its letters' widths.
const PIECES_SPREAD: f64 = 0.25;

/// Whether upright blocks, stacked top to bottom, are pieces of sideways `word` rather than
/// a column of labels: they cover less than half its length (a few letters read upright),
/// or they are at least two, of heights that spread more than [`PIECES_SPREAD`], with at
/// least half of the gaps between neighbours no wider than [`LETTER_GAP`] (the gap of a
/// word space or a dotted abbreviation may be wider; the leading between labels, set
/// close, is about as wide).
fn pieces_of_one_word<'a>(pieces: impl Iterator<Item = &'a TextBlock>, word: &TextBlock) -> bool {
    let (line_height, length) = (word.line_height, word.y1 - word.y0);
    let mut pieces: Vec<&TextBlock> = pieces.collect();
    pieces.sort_by_key(|u| u.y0);
    let gaps = pieces.windows(2).map(|p| p[1].y0.saturating_sub(p[0].y1));
    let most = (LETTER_GAP * line_height as f64).max(1.0);
    let touching = gaps.clone().filter(|&g| g as f64 <= most).count();
    let (short, tall) = pieces.iter().fold((u32::MAX, 0), |(a, b), u| {
        (a.min(u.y1 - u.y0), b.max(u.y1 - u.y0))
    });
    let covered: u32 = pieces.iter().map(|u| u.y1 - u.y0).sum();
    2 * covered < length
        || pieces.len() >= 2
            && (tall - short) as f64 > PIECES_SPREAD * tall as f64
            && 2 * touching >= gaps.count()
}

/// Least canvas side (pixels) taken as one data area by [`Regions::Affine`].
const MIN_CANVAS_AREA_PX: u32 = 8;

/// Whether [`Regions::Affine`] takes a canvas of `size` whole. A canvas a few pixels wide has
/// no inside to hold: its boundary alone makes the warp linear (and an empty area would leave
/// the solve singular).
pub(crate) fn takes_canvas_whole(size: crate::image::Size) -> bool {
    size.width >= MIN_CANVAS_AREA_PX && size.height >= MIN_CANVAS_AREA_PX
}

/// Which regions of a picture are data areas (`--regions`).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Regions {
    /// Data areas where axes, frames, grids or bars show them; the free warp elsewhere.
    Auto,
    /// The whole canvas is one data area: one map per axis, linear but for its text bands
    /// (kept at their size, see [`Bands`]) and the blank margins its plot may grow into, text
    /// on a flat ground kept at its size where it has room; where nothing gives way, the
    /// picture at one scale on its ground (see [`crate::Options::fill`]). The default: judged
    /// blind on real charts, readers preferred it to the modes that bend (a chart that lies
    /// is worse than a squashed one) and to a linear resize.
    #[default]
    Affine,
    /// No data areas: the paper's free warp everywhere.
    Free,
}

impl Structure {
    /// Finds lines and text in `image`.
    pub fn detect(image: ImageRef<'_>) -> Structure {
        let (w, h) = (image.width() as usize, image.height() as usize);
        let mut l = Vec::new();
        luma::luma(image, &mut l);
        let t = luma::transposed(&l, w, h);
        let (h_found, v_found) = (lines::horizontal(&l, w, h), lines::vertical(&t, w, h));
        let (mut horizontal, mut vertical) = (h_found.solid, v_found.solid);
        // Text is found among solid lines only: a chain may run along the foot of a word, and
        // clearing a faint line's pixels would cut a texture into glyph-sized pieces.
        let upright =
            |sideways: &[TextBlock]| text::detect(&l, w, h, [&horizontal, &vertical], sideways);
        let mut text = upright(&[]);
        // A column of tick labels set close also reads as a sideways "word" (floated as one,
        // its labels would leave their ticks), and a sideways title's glyphs, a few at a time,
        // read as upright "words". The two differ in how the upright pieces stack: labels
        // stand apart by their leading, pieces of one sideways word touch, letter to letter.
        let touch = |s: &TextBlock, u: &TextBlock| {
            !(u.x0 > s.x1 || s.x0 > u.x1 || u.y0 > s.y1 || s.y0 > u.y1)
        };
        let sideways: Vec<TextBlock> = rotated_text(&t, w, h, [&horizontal, &vertical])
            .into_iter()
            .filter(|s| {
                let mut pieces = text.iter().filter(|u| touch(s, u)).peekable();
                // Of two readings of the same glyphs, the longer line wins: an upright line
                // across the sideways "word"'s column, at least as long as it, is a line
                // whose first letters, with what stacks under them (a legend's rings), read
                // turned.
                let crossed = || {
                    text.iter().any(|u| {
                        touch(s, u) && u.x0 <= s.x0 && u.x1 >= s.x1 && u.x1 - u.x0 >= s.y1 - s.y0
                    })
                };
                pieces.peek().is_none() || !crossed() && pieces_of_one_word(pieces, s)
            })
            .collect();
        // Where a sideways word was read in upright pieces, those pieces may have taken in a
        // glyph beside it (a tick label next to the title's letter): read the upright text
        // again without the sideways words' glyphs.
        if sideways.iter().any(|s| text.iter().any(|u| touch(s, u))) {
            text = upright(&sideways);
        }
        text.retain(|u| !sideways.iter().any(|s| touch(s, u)));
        text.extend(sideways);
        // A chain or a faint line crossing a text block is the foot or the top of its words.
        let clear = |line: &Line, across: fn(&TextBlock) -> [u32; 4]| {
            text.iter().all(|b| {
                let [a0, a1, s0, s1] = across(b);
                line.pos < a0 as f64 - 1.0
                    || line.pos > a1 as f64 + 1.0
                    || line.to <= s0 as f64
                    || line.from >= s1 as f64
            })
        };
        merge_lines(
            &mut horizontal,
            (h_found.chained.into_iter())
                .chain(h_found.weak)
                .filter(|l| clear(l, |b| [b.y0, b.y1, b.x0, b.x1])),
        );
        merge_lines(
            &mut vertical,
            (v_found.chained.into_iter())
                .chain(v_found.weak)
                .filter(|l| clear(l, |b| [b.x0, b.x1, b.y0, b.y1])),
        );
        let areas = areas::detect(&horizontal, &vertical, w as f64, h as f64);
        Structure {
            horizontal,
            vertical,
            text,
            areas,
            bands: Bands::default(),
        }
    }

    /// Like [`Structure::detect`], with the data areas chosen by `regions`.
    pub fn detect_with(image: ImageRef<'_>, regions: Regions) -> Structure {
        let mut s = Structure::detect(image);
        match regions {
            Regions::Auto => {}
            Regions::Free => s.areas.clear(),
            Regions::Affine => {
                let (w, h) = (image.width() as f64, image.height() as f64);
                if !takes_canvas_whole(image.size()) {
                    s.areas.clear();
                    return s;
                }
                s.bands = bands::detect(image, &s.text, &s.areas, [&s.horizontal, &s.vertical]);
                s.areas = vec![DataArea {
                    x0: 1.0,
                    y0: 1.0,
                    x1: w - 1.0,
                    y1: h - 1.0,
                    kind: AreaKind::Canvas,
                }];
            }
        }
        s
    }

    /// The data area text block `b` lies mostly inside (half of its box or more), if any: the
    /// block follows that area (one definition for the layout and for what floats).
    pub fn area_of(&self, b: &TextBlock) -> Option<usize> {
        let (x0, y0, x1, y1) = (b.x0 as f64, b.y0 as f64, b.x1 as f64, b.y1 as f64);
        self.areas.iter().position(|a| {
            let ow = (x1.min(a.x1) - x0.max(a.x0)).max(0.0);
            let oh = (y1.min(a.y1) - y0.max(a.y0)).max(0.0);
            ow * oh >= 0.5 * (x1 - x0) * (y1 - y0)
        })
    }

    /// The whole canvas is one data area ([`Regions::Affine`]): it is resampled by one map per
    /// axis (or at one scale where nothing gives way), and only those maps and what floats
    /// over it need the structure.
    pub fn whole_canvas(&self) -> bool {
        self.areas.iter().any(|a| a.kind == AreaKind::Canvas)
    }

    /// Nothing found.
    pub fn is_empty(&self) -> bool {
        self.horizontal.is_empty()
            && self.vertical.is_empty()
            && self.text.is_empty()
            && self.areas.is_empty()
    }
}

/// Adds `extra` to `lines`, a line that lies on one already there (same position and
/// thickness, overlapping along it: a waffle's cell tops found both as a solid edge and as a
/// chain) lengthening it instead. A vertex on two copies of one line takes the role of the
/// first only, and the second, left with a few vertices far apart, would be redrawn along the
/// wrong course.
fn merge_lines(lines: &mut Vec<Line>, extra: impl IntoIterator<Item = Line>) {
    for mut l in extra {
        // A lengthened line may reach another piece: merge until none is left to join.
        while let Some(i) = lines.iter().position(|o| {
            (o.pos - l.pos).abs() < 0.5 && o.width == l.width && l.from <= o.to && l.to >= o.from
        }) {
            let o = lines.swap_remove(i);
            l.from = l.from.min(o.from);
            l.to = l.to.max(o.to);
            l.pos = o.pos;
        }
        lines.push(l);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(pos: f64, from: f64, to: f64) -> Line {
        Line {
            pos,
            from,
            to,
            width: 0,
        }
    }

    #[test]
    fn a_line_found_twice_is_one_line() {
        let mut lines = vec![line(32.0, 42.0, 580.0)];
        merge_lines(
            &mut lines,
            [
                line(32.0, 42.0, 580.0),  // the same
                line(32.0, 560.0, 600.0), // overlapping: lengthens it
                line(32.0, 620.0, 700.0), // beyond it: another piece
                line(52.0, 42.0, 580.0),  // another row
            ],
        );
        lines.sort_by(|a, b| a.pos.total_cmp(&b.pos).then(a.from.total_cmp(&b.from)));
        assert_eq!(
            lines,
            [
                line(32.0, 42.0, 600.0),
                line(32.0, 620.0, 700.0),
                line(52.0, 42.0, 580.0)
            ]
        );
    }

    /// A piece that joins two others makes one line of all three, whatever the order.
    #[test]
    fn a_bridging_piece_joins_both_sides() {
        let mut lines = vec![line(32.0, 42.0, 580.0)];
        merge_lines(
            &mut lines,
            [line(32.0, 620.0, 700.0), line(32.0, 560.0, 650.0)],
        );
        assert_eq!(lines, [line(32.0, 42.0, 700.0)]);
    }

    /// A thin line and an edge at the same place are different things: both stay.
    #[test]
    fn lines_of_other_thickness_stay_apart() {
        let mut lines = vec![line(32.0, 42.0, 580.0)];
        let thin = Line {
            width: 2,
            ..line(32.0, 42.0, 580.0)
        };
        merge_lines(&mut lines, [thin]);
        assert_eq!(lines, [line(32.0, 42.0, 580.0), thin]);
    }
}
