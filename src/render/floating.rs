//! Small raster marks floating over a kept warp: §5.3's adjustment of marks (drawn at their
//! own size where the warp carries their centre) for the marks of a stream that the mesh does
//! not ring.
//!
//! While saliency elsewhere stands still a stream keeps its mesh and solution, so a dot that
//! moved, or appeared, has no ring of its own. Rendered through whatever triangles it landed
//! in, it would be squashed; re-meshed around, it would drag the warp of everything near it
//! along from frame to frame (the coastlines beside a moving dot would shimmer). Instead it
//! floats: its pixels are painted out of the source, the source is warped as before, and the
//! mark is copied at full size, shifted by whole pixels to where the warp carries its centre.
//! Only the pixels it covered and now covers change.

use super::canvas::AreaMaps;
use super::fill::fill_from_surroundings;
use crate::image::{Image, Size};
use crate::mesh::Mark;
use crate::saliency::Vsm;
use crate::structure::TextBlock;
use crate::structure::ALIGNED_PX;
use glam::{DVec2, DVec3};

/// Importance from which a pixel near a mark is part of it (the blob itself is found at 0.5;
/// this takes in most of its antialiased rim, the one-pixel growth below the rest).
const RIM_IMPORTANCE: f32 = 0.25;
/// Pixels beyond the blob's bounding box looked at for its rim.
pub(crate) const RIM_PX: u32 = 2;

/// Thin lines (grid lines, axes, frames) that run under a painted-out mark are drawn on
/// through it first: the mark hid the line, so it was found as two pieces, one on each side
/// (or as one piece it crosses). Each pixel row (column) of the line is interpolated across
/// the gap between the line's pixels on either side, where most of the gap is masked. Without
/// it the ground closes over the line, and a mark drawn smaller than it was leaves a notch in
/// every grid line it sat on. Drawn pixels are cleared from `masked`.
fn continue_lines(image: &mut Image, st: &crate::structure::Structure, masked: &mut [bool]) {
    let (w, h) = (image.width() as usize, image.height() as usize);
    for (horizontal, lines) in [(true, &st.horizontal), (false, &st.vertical)] {
        let (len, across_len) = if horizontal { (w, h) } else { (h, w) };
        let mut thin: Vec<&crate::structure::Line> = lines
            .iter()
            .filter(|l| (1..=3).contains(&l.width))
            .collect();
        thin.sort_by(|a, b| a.pos.total_cmp(&b.pos).then(a.from.total_cmp(&b.from)));
        // Stretches `(line, window, gap)` to bridge: the gap between collinear pieces (or a
        // whole piece a mark crosses), looked for masked pixels within the window around it.
        type Gap<'a> = (&'a crate::structure::Line, (usize, usize), (usize, usize));
        let mut gaps: Vec<Gap> = Vec::new();
        for (i, l) in thin.iter().enumerate() {
            let (from, to) = (l.from.max(0.0) as usize, (l.to.ceil() as usize).min(len));
            gaps.push((l, (from, to), (from, to)));
            if let Some(n) = thin.get(i + 1) {
                if n.pos == l.pos && n.width == l.width && n.from > l.to {
                    let end = (n.to.ceil() as usize).min(len);
                    let gap = ((l.to.ceil() as usize).min(len), (n.from as usize).min(len));
                    gaps.push((l, (from, end), gap));
                }
            }
        }
        for (l, (from, to), (g0, g1)) in gaps {
            if to < from + 3 || g1 <= g0 {
                continue;
            }
            let first = (l.pos - l.width as f64 / 2.0).round().max(0.0) as usize;
            for across in first..(first + l.width as usize).min(across_len) {
                let at = |along: usize| {
                    if horizontal {
                        across * w + along
                    } else {
                        along * w + across
                    }
                };
                // The masked stretch over the gap: from its first masked pixel back, and from
                // its last one on, while masked.
                let Some(mut a) = (g0..g1).find(|&i| masked[at(i)]) else {
                    continue;
                };
                let mut b = (g0..g1).rev().find(|&i| masked[at(i)]).unwrap_or(a) + 1;
                while a > from && masked[at(a - 1)] {
                    a -= 1;
                }
                while b < to && masked[at(b)] {
                    b += 1;
                }
                let n_masked = (a..b).filter(|&i| masked[at(i)]).count();
                if a <= from || b >= to || 2 * n_masked < b - a {
                    continue;
                }
                // Ends: the nearest line pixels outside the stretch, past the mark's rim.
                let (e0, e1) = (
                    a.saturating_sub(RIM_PX as usize + 1).max(from),
                    (b + RIM_PX as usize).min(to - 1),
                );
                let (c0, c1) = (image.pixels()[at(e0)], image.pixels()[at(e1)]);
                let n = (e1 - e0) as f32;
                for along in e0 + 1..e1 {
                    let t = (along - e0) as f32 / n;
                    let mut c = [0u8; 4];
                    for ch in 0..4 {
                        c[ch] = (c0[ch] as f32 * (1.0 - t) + c1[ch] as f32 * t + 0.5) as u8;
                    }
                    image.pixels_mut()[at(along)] = c;
                    masked[at(along)] = false;
                }
            }
        }
    }
}

/// Which pixels around a floating mark go with it.
#[derive(Copy, Clone, Debug)]
pub(crate) enum MaskKind {
    /// Salient pixels (a stream's marks).
    Salient,
    /// Salient pixels of the mark's colour (a data area's marks: a line through a marker
    /// stays behind).
    Colour([u8; 3]),
    /// The whole box (a text block: its glyphs' antialiased edges too, or they would stay
    /// behind as a ghost outline).
    Whole,
    /// The whole box, painted out and never drawn: a tick label thinned out of its axis.
    Dropped,
}

/// Importance from which a pixel belongs to a data area's mark (as [`crate::mesh`]'s marks)
/// wherever the area's ground lies: importance is a colour's distance from the frame's mean,
/// so where the ground is far from it, marks may be too.
const AREA_MARK_IMPORTANCE: f32 = 0.5;
/// Importance above the area's ground (its median cell) from which a pixel belongs to a mark
/// all the same: a pale mark on a ground near the frame's mean colour (a cyan dot on a light
/// sea) is a mark, though nearer that mean than the strongest colours.
const MARK_ABOVE_GROUND: f32 = 0.2;
/// Largest mark of a data area, as a share of the area's shorter side: a bubble may be
/// large, but a blob spanning much of the plot is a region (an area fill, a band).
const AREA_MARK_SHARE: f64 = 0.35;
/// Most ratio of a round mark's bounding box sides.
const MAX_MARK_ASPECT: f64 = 1.35;
/// How far a round mark's ink's centre may lie from its box's centre, as a share of the box,
/// and the least share of its box it fills (a disc π/4 ≈ 0.785, a 1-px ring of radius 20
/// about 0.08: only a scatter of specks fills less); checked above marks of
/// [`SMALL_MARK_CELLS`] map cells or fewer across, whose shape is mostly their rim.
const MIN_MARK_FILL: f64 = 0.05;
const MARK_CENTRED: f64 = 0.1;
const SMALL_MARK_CELLS: f64 = 8.0;
/// Most cells of a blob too small to have a shape ([`MarkScan::blob_at`]): two by two.
const SPECK_CELLS: usize = 4;
/// Share of its bounding box above which a blob is a rectangle: a bar or a cell, whose
/// length is data read off the axis and must follow the area's map, not keep its shape.
const RECTANGLE_FILL: f64 = 0.9;

/// Least scale at which a text block inside a data area floats; below it, the block follows
/// the area's map like the rest (a linear resize's squeeze), since smaller type than this
/// reads worse than condensed type of full height.
const MIN_TEXT_FLOAT: f64 = 0.7;
/// Least share of the pixels around a text block's glyphs that are one colour for the block
/// to float: the ground of a title or a legend is flat, a label over a map or a cell
/// boundary is not (a glyph's own pixels on the box's edge keep this below 1).
const FLAT_GROUND: f64 = 0.9;
/// The scale of a block that cannot float at all: it keeps a scale (rather than none) so
/// that the labels aligned with it follow the map with it ([`share_scale`]).
const CANNOT_FLOAT: f64 = 0.0;
/// Least gap between two floating text blocks, output pixels.
const TEXT_GAP_PX: f64 = 2.0;
/// How far a block read alone (a title, an axis title) may step aside from where the map
/// puts it, in its own line heights: a label moved further than its own size detaches from
/// what it names.
const NUDGE_LINES: f64 = 1.0;

/// Where a text block inside a data area is drawn over the warp: its output centre and scale.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TextPlacement {
    pub centre: DVec2,
    pub scale: f64,
    /// Thinned out: a tick label dropped where its row would collide, as an axis' locator
    /// drops every other one ([`thin`]). Painted out of the picture and not drawn.
    pub dropped: bool,
}

/// The placement of each text block that lies mostly inside a data area, given the areas'
/// maps ([`crate::Warp::area_maps`]) and the output size: text keeps its size unless the area
/// shrinks along both axes (then it takes the larger of the two scales, never more than 1);
/// it is anchored where its column is aligned (a legend's labels by their left edge, a y
/// axis' tick labels by their right edge, anything else by its centre), at the place the
/// area's map takes that anchor; floating blocks that would overlap each other or hide ink
/// first step aside (at most `NUDGE_LINES` line heights, a row of labels across its line
/// and a column along its lines, as one), then are made smaller together, and a block that
/// would fall below `MIN_TEXT_FLOAT` is left to the map. Kept inside the output canvas.
pub fn area_text_placements<'m>(
    src: &Image,
    st: &crate::structure::Structure,
    maps: impl Into<AreaMaps<'m>>,
    target: Size,
) -> Vec<Option<TextPlacement>> {
    area_text_layout(src, st, maps.into(), target, false).0
}

/// [`area_text_placements`], with rows of tick labels thinned where they would collide
/// (`thinning`, under the layout), and whether the text on a canvas taken whole was left to
/// the map, all of it.
pub(crate) fn area_text_layout(
    src: &Image,
    st: &crate::structure::Structure,
    maps: AreaMaps<'_>,
    target: Size,
    thinning: bool,
) -> (Vec<Option<TextPlacement>>, bool) {
    let mut layout = TextLayout::new(src, st, maps, target);
    layout.thinning = thinning;
    let text = layout.text;
    let area_of = |t: &TextBlock| st.area_of(t);
    let scale: Vec<Option<f64>> = (0..text.len()).map(|i| layout.float_scale(i)).collect();
    let group = type_groups(text, &area_of, &scale, Alignment::Edges);
    let mut room = Room {
        scale,
        shift: vec![DVec2::ZERO; text.len()],
        covered: vec![None; text.len()],
        dropped: vec![false; text.len()],
    };
    let movers = movers(text, &group);
    if layout.thinning {
        layout.thin(&movers, &mut room);
    }
    layout.make_room(&movers, &mut room);
    let Room {
        mut scale,
        shift,
        dropped,
        ..
    } = room;
    // Text inside a plot (a label on a mark, a cell's value) is a role of its own: it does
    // not share the size its axes' labels can keep.
    share_scale(text, &area_of, &mut scale, &|i| layout.in_plot(i));
    let refused = layout.all_or_none_on_canvas(&mut scale);
    let placements = (0..text.len())
        .map(|i| {
            // A block the map already keeps at its size (a text band of a canvas) is drawn
            // where it stands by the resampler: floating it could only move it.
            if layout
                .map_of(i)
                .is_some_and(|[ax, _, ay, _]| (ax - 1.0).abs().max((ay - 1.0).abs()) < 1e-9)
            {
                return None;
            }
            let s = scale[i].filter(|&s| s >= layout.least_float)?;
            let b = layout.placed(i, s, shift[i])?;
            Some(TextPlacement {
                centre: DVec2::new((b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0),
                scale: s,
                dropped: dropped[i],
            })
        })
        .collect();
    (placements, refused)
}

/// How far outside a plot's edge an axis' tick labels stand, in their line heights (the
/// tick's length and the label's padding).
const TICK_REACH_LINES: f64 = 2.0;
/// Least labels in a row (column) that make an axis' ticks, which may be thinned.
const LEAST_TICKS: usize = 3;
/// Most deviation of tick labels' spacing from its mean, as a share of it: ticks are evenly
/// spaced (to a pixel's rounding and a label's width), a legend's entries are not.
const TICKS_EVEN: f64 = 0.15;

/// Times the floating blocks step aside and shrink before they are left as they are.
const MAKE_ROOM_ROUNDS: usize = 12;
/// Factor a block in the way shrinks by in each round.
const SHRINK_STEP: f64 = 0.9;

/// What placing the text blocks of one frame reads, found once: `placed` runs for every
/// trial place and scale.
struct TextLayout<'a> {
    src: &'a Image,
    st: &'a crate::structure::Structure,
    text: &'a [TextBlock],
    maps: AreaMaps<'a>,
    /// Each block's ground colour and the share of its box's ring it takes ([`box_ground`]).
    grounds: Vec<([u8; 3], f64)>,
    /// Whether each block's ink is one colour ([`one_ink`]): ink of two colours is not a
    /// word (a line through a marker, dots along an axis), so such a block follows the map
    /// and has no say in how the text floats.
    words: Vec<bool>,
    /// Each block's anchor along x ([`anchor`]).
    anchors: Vec<f64>,
    /// The output canvas, which every block is kept inside.
    size: (f64, f64),
    /// Least scale a block floats at ([`MIN_TEXT_FLOAT`]; on a page of cards, where text
    /// that cannot float leaves the page to a letterbox, the letterbox's scale where less).
    least_float: f64,
    /// The page is laid out as cards ([`crate::structure::Card`]).
    cards: bool,
    /// Thin crowded rows of tick labels ([`TextLayout::thin`]).
    thinning: bool,
}

/// Where the floating blocks stand while they make room for one another.
struct Room {
    /// Each block's scale (as [`TextLayout::float_scale`], then shrunk).
    scale: Vec<Option<f64>>,
    /// Each block's step aside from where its area's map puts it.
    shift: Vec<DVec2>,
    /// Whether each block at its scale and place covers ink, once looked at: it depends on
    /// its own box alone, so it is looked at again only once the block has shrunk or moved.
    covered: Vec<Option<bool>>,
    /// Blocks thinned out of their row or column ([`thin`]).
    dropped: Vec<bool>,
}

/// A group of blocks that steps aside as one, and the unit steps it may take.
struct Mover {
    members: Vec<usize>,
    moves: Vec<DVec2>,
}

impl<'a> TextLayout<'a> {
    fn new(
        src: &'a Image,
        st: &'a crate::structure::Structure,
        maps: AreaMaps<'a>,
        target: Size,
    ) -> TextLayout<'a> {
        let text = &st.text[..];
        let grounds: Vec<([u8; 3], f64)> = text.iter().map(|t| box_ground(src, t)).collect();
        let words = (text.iter().zip(&grounds))
            .map(|(t, g)| one_ink(src, t, g.0) && whole(src, t, g.0))
            .collect();
        let anchors = (0..text.len())
            .map(|i| anchor(src, text, grounds[i].0, i))
            .collect();
        // Laid out as cards (which may decline, and then are not).
        let cards = (st.bands.panels.as_ref().and_then(|p| p.split.as_ref()))
            .is_some_and(|split| split.own)
            && maps.canvas.is_some_and(|c| !c.panels.is_empty());
        TextLayout {
            src,
            st,
            text,
            maps,
            grounds,
            words,
            anchors,
            size: (target.width as f64, target.height as f64),
            thinning: false,
            least_float: match cards {
                true => {
                    let (w, h) = (src.width() as f64, src.height() as f64);
                    let letterbox = (target.width as f64 / w).min(target.height as f64 / h);
                    MIN_TEXT_FLOAT.min(letterbox)
                }
                false => MIN_TEXT_FLOAT,
            },
            cards,
        }
    }

    fn area_of(&self, t: &TextBlock) -> Option<usize> {
        self.st.area_of(t)
    }

    /// The map that carries block i: its area's, around the block's centre.
    fn map_of(&self, i: usize) -> Option<[f64; 4]> {
        let t = &self.text[i];
        let centre = DVec2::new((t.x0 + t.x1) as f64 / 2.0, (t.y0 + t.y1) as f64 / 2.0);
        self.maps.at(self.area_of(t)?, centre)
    }

    /// Output box of block i at scale `s`, moved by `d` (None: not in an area with a map).
    fn placed(&self, i: usize, s: f64, d: DVec2) -> Option<[f64; 4]> {
        let t = &self.text[i];
        let (tw, th) = self.size;
        let [ax, bx, ay, by] = self.map_of(i)?;
        let (x0, x1, y0, y1) = (t.x0 as f64, t.x1 as f64, t.y0 as f64, t.y1 as f64);
        let k = self.anchors[i];
        let ax_src = x0 + k * (x1 - x0);
        let (w, h) = (s * (x1 - x0), s * (y1 - y0));
        let left = (ax * ax_src + bx - k * w + d.x).clamp(0.0, (tw - w).max(0.0));
        let top = (ay * (y0 + y1) / 2.0 + by - h / 2.0 + d.y).clamp(0.0, (th - h).max(0.0));
        Some([left, top, left + w, top + h])
    }

    /// The scale block i would float at before it makes room for others: the larger of its
    /// area's two scales, at most 1; [`CANNOT_FLOAT`] on a busy ground, `None` if it is no
    /// word or has no map.
    fn float_scale(&self, i: usize) -> Option<f64> {
        // Only text on flat ground floats: its box, pasted whole, then hides nothing but
        // its own squeezed copy. A block on a busy ground (a label on a map, in a treemap's
        // cell, the crossing of a heat map's separators) follows the map, and so does
        // every label of its size ([`share_scale`]).
        if self.grounds[i].1 < FLAT_GROUND {
            return Some(CANNOT_FLOAT);
        }
        if !self.words[i] {
            return None;
        }
        let [ax, _, ay, _] = self.map_of(i)?;
        // Never wider or taller than the output: a title wider than the target at its size
        // shrinks to fit, whole, rather than run off the edge.
        let t = &self.text[i];
        let (bw, bh) = ((t.x1 + 1 - t.x0) as f64, (t.y1 + 1 - t.y0) as f64);
        let room = (self.size.0 / bw).min(self.size.1 / bh);
        Some(ax.max(ay).min(1.0).min(room))
    }

    /// Whether block i stands inside a plot of a canvas taken whole
    /// ([`crate::structure::Bands::in_plot`]): a label on a mark, a cell's value.
    fn in_plot(&self, i: usize) -> bool {
        let t = &self.text[i];
        self.on_canvas(t) && (self.st.bands.in_plot(t) || (self.cards && self.in_card_body(t)))
    }

    /// Whether block `t` stands inside the body of a card drawn at one scale
    /// ([`crate::structure::Card`]): its text (a map's names, a table's cells, the labels of
    /// a plot not squeezed) goes with it, as a plot's does.
    fn in_card_body(&self, t: &TextBlock) -> bool {
        let (cx, cy) = ((t.x0 + t.x1) / 2, (t.y0 + t.y1) / 2);
        let inside = |b: [u32; 4]| (b[0]..b[2]).contains(&cx) && (b[1]..b[3]).contains(&cy);
        (self.maps.canvas.iter())
            .flat_map(|c| &c.panels)
            .any(|m| m.body.is_some_and(inside))
    }

    /// Whether block `t` lies on a canvas taken whole.
    fn on_canvas(&self, t: &TextBlock) -> bool {
        (self.area_of(t))
            .is_some_and(|k| self.st.areas[k].kind == crate::structure::AreaKind::Canvas)
    }

    /// Whether block i drawn over `b` hides ink that is not text floating with it.
    fn covers(&self, i: usize, b: [f64; 4], floating: &[&TextBlock]) -> bool {
        let t = &self.text[i];
        covers_ink(self.src, t, self.grounds[i].0, b, self.map_of(i), floating)
    }

    /// Whether block i over `bi` is in the way: it overlaps another block's box or covers
    /// ink (cached in `covered`, see [`Room::covered`]).
    fn in_the_way(
        &self,
        (i, bi): (usize, [f64; 4]),
        boxes: &[Option<[f64; 4]>],
        covered: &mut Option<bool>,
        floating: &[&TextBlock],
    ) -> bool {
        clash(i, bi, boxes) || *covered.get_or_insert_with(|| self.covers(i, bi, floating))
    }

    /// Rows of at least [`LEAST_TICKS`] evenly spaced labels of one size along a plot's edge,
    /// an x axis' tick labels, whose neighbours would collide at their floating scale keep
    /// every other label from the first (the last too where the count is odd), every third
    /// while they still collide, and so on, as a chart's axis locator does for a narrower
    /// axis: type keeps its size, what is left stays under its tick, the steps even. A legend's entries and a column of bar names are never
    /// thinned.
    fn thin(&self, movers: &[Mover], room: &mut Room) {
        // A row of labels across panels side by side is each panel's axis, thinned apart.
        let rows = movers
            .iter()
            .filter(|m| m.moves.iter().all(|d| d.x == 0.0))
            .flat_map(|m| self.by_panel(&m.members));
        for members in rows.filter(|m| m.len() >= LEAST_TICKS) {
            let row = true;
            // Only an x axis' labels: a column of labels beside a plot names its bars or
            // rows one by one (judged blind, a bar chart with every other name dropped came
            // last), and a legend's row stands apart from the plots.
            if !self.beside_a_plot(&members, row) {
                continue;
            }
            let centre = |i: usize| {
                let t = &self.text[i];
                match row {
                    true => (t.x0 + t.x1) as f64 / 2.0,
                    false => (t.y0 + t.y1) as f64 / 2.0,
                }
            };
            let mut kept: Vec<usize> = members;
            kept.sort_by(|&a, &b| centre(a).total_cmp(&centre(b)));
            let steps: Vec<f64> = kept
                .windows(2)
                .map(|p| centre(p[1]) - centre(p[0]))
                .collect();
            let mean = steps.iter().sum::<f64>() / steps.len() as f64;
            if mean <= 0.0 || steps.iter().any(|s| (s - mean).abs() > TICKS_EVEN * mean) {
                continue;
            }
            let boxes = |kept: &[usize]| -> Vec<Option<[f64; 4]>> {
                kept.iter()
                    .map(|&i| {
                        (room.scale[i].filter(|&s| s > CANNOT_FLOAT))
                            .and_then(|s| self.placed(i, s, room.shift[i]))
                    })
                    .collect()
            };
            // Every k-th label from the first, for the least k whose labels do not collide:
            // steps kept even, as a locator keeps them (judged blind, "2.0 3.0 4.5" with the
            // last kept and the one before it dropped read as a bent axis). The last stays
            // where the step divides the row.
            let all = kept;
            let mut k = 1;
            loop {
                let next: Vec<usize> = all.iter().step_by(k).copied().collect();
                let b = boxes(&next);
                let collide = b.windows(2).any(|p| match (p[0], p[1]) {
                    (Some(a), Some(c)) => overlap(a, c),
                    _ => false,
                });
                if !collide || next.len() <= 2 {
                    for &i in &all {
                        room.dropped[i] = !next.contains(&i);
                    }
                    break;
                }
                k += 1;
            }
        }
    }

    /// `members` grouped by the panel their centres stand in ([`crate::structure::Panel`]),
    /// in the order of the panels; all of them where the picture is one panel.
    fn by_panel(&self, members: &[usize]) -> Vec<Vec<usize>> {
        let Some(root) = &self.st.bands.panels else {
            return vec![members.to_vec()];
        };
        let leaves = root.leaves();
        let mut groups = vec![Vec::new(); leaves.len()];
        for &i in members {
            let t = &self.text[i];
            let (cx, cy) = ((t.x0 + t.x1) / 2, (t.y0 + t.y1) / 2);
            let k = leaves.iter().position(|l| {
                cx >= l.rect[0] && cx < l.rect[2] && cy >= l.rect[1] && cy < l.rect[3]
            });
            groups[k.unwrap_or(0)].push(i);
        }
        groups.retain(|g| !g.is_empty());
        groups
    }

    /// Whether the labels `members` (a row when `row`, else a column) stand along a plot's
    /// edge as an axis' tick labels do: across the row, within [`TICK_REACH_LINES`] line
    /// heights outside one of the plots' spans, and along it inside one.
    fn beside_a_plot(&self, members: &[usize], row: bool) -> bool {
        let b = &self.st.bands;
        let (across, along) = match row {
            true => (&b.plots_y, &b.plots_x),
            false => (&b.plots_x, &b.plots_y),
        };
        members.iter().all(|&i| {
            let t = &self.text[i];
            let ([a0, a1], [l0, l1]) = match row {
                true => ([t.y0, t.y1], [t.x0, t.x1]),
                false => ([t.x0, t.x1], [t.y0, t.y1]),
            };
            let reach = (TICK_REACH_LINES * t.line_height as f64) as u32;
            let near = across
                .iter()
                .any(|p| (a0 >= p[1] && a0 <= p[1] + reach) || (a1 <= p[0] && a1 + reach >= p[0]));
            let inside = along.iter().any(|p| l0 + 1 >= p[0] && l1 <= p[1] + 1);
            near && inside
        })
    }

    /// Blocks in the way step aside, before any shrinks, to the nearest place that is clear:
    /// blocks read alone first (a title, an axis title), then aligned rows across their line
    /// and columns along theirs, each as one; those still in the way shrink, and again, for
    /// at most [`MAKE_ROOM_ROUNDS`].
    fn make_room(&self, movers: &[Mover], room: &mut Room) {
        let text = self.text;
        for _ in 0..MAKE_ROOM_ROUNDS {
            let floating: Vec<&TextBlock> = (0..text.len())
                .filter(|&j| room.scale[j].is_some_and(|s| s >= self.least_float))
                .map(|j| &text[j])
                .collect();
            let mut boxes: Vec<Option<[f64; 4]>> = (0..text.len())
                .map(|i| {
                    (room.scale[i].filter(|&s| s > CANNOT_FLOAT && !room.dropped[i]))
                        .and_then(|s| self.placed(i, s, room.shift[i]))
                })
                .collect();
            for mover in movers {
                self.step_aside(mover, room, &mut boxes, &floating);
            }
            let shrink: Vec<bool> = boxes
                .iter()
                .enumerate()
                .map(|(i, bi)| {
                    bi.is_some_and(|bi| {
                        self.in_the_way((i, bi), &boxes, &mut room.covered[i], &floating)
                    })
                })
                .collect();
            if !shrink.contains(&true) {
                break;
            }
            for ((s, c), &k) in room.scale.iter_mut().zip(&mut room.covered).zip(&shrink) {
                if k {
                    *s = s.map(|v| v * SHRINK_STEP);
                    *c = None;
                }
            }
        }
    }

    /// Moves `mover`'s blocks, if any is in the way, by the shortest of its steps (up to
    /// [`NUDGE_LINES`] line heights) that leaves them all clear, in `room` and in `boxes`.
    fn step_aside(
        &self,
        Mover { members, moves }: &Mover,
        room: &mut Room,
        boxes: &mut [Option<[f64; 4]>],
        floating: &[&TextBlock],
    ) {
        let conflict = members.iter().any(|&i| {
            boxes[i]
                .is_some_and(|bi| self.in_the_way((i, bi), boxes, &mut room.covered[i], floating))
        });
        // Text inside a plot of a canvas taken whole (a label on a mark, a cell's value, a
        // dot read as a glyph) stands where the plot's map takes it: where it stands is data,
        // which a step aside would move (judged blind: two scatter dots read as glyphs moved
        // off their values). It makes room by shrinking only.
        if !conflict
            || members
                .iter()
                .any(|&i| boxes[i].is_none() || self.in_plot(i))
        {
            return;
        }
        let (scale, shift) = (&room.scale, &mut room.shift);
        let reach = (members.iter())
            .map(|&i| NUDGE_LINES * scale[i].unwrap_or(0.0) * self.text[i].line_height as f64)
            .fold(f64::INFINITY, f64::min);
        let mut trial = boxes.to_vec();
        let found = (1..=reach.floor() as i32)
            .flat_map(|r| moves.iter().map(move |&m| m * r as f64))
            .find(|&d| {
                for &i in members {
                    trial[i] = scale[i].and_then(|s| self.placed(i, s, shift[i] + d));
                }
                members.iter().all(|&i| {
                    trial[i].is_some_and(|b| !clash(i, b, &trial) && !self.covers(i, b, floating))
                })
            });
        if let Some(d) = found {
            for &i in members {
                shift[i] += d;
                boxes[i] = trial[i];
                room.covered[i] = Some(false);
            }
        }
    }

    /// On a canvas taken whole, the text floats all of it or none: a title at its size over
    /// condensed labels reads worse than all of it condensed, and so do groups of blocks
    /// floating on their own beside condensed ones.
    /// Whether it was left to the map.
    fn all_or_none_on_canvas(&self, scale: &mut [Option<f64>]) -> bool {
        let text = self.text;
        let on_canvas = |t: &TextBlock| self.on_canvas(t);
        // Text inside a plot that cannot float follows the plot's map alone: it is no part
        // of the type around the plot, and turns nothing down.
        let refused = (0..text.len()).any(|i| {
            self.words[i]
                && !self.in_plot(i)
                && on_canvas(&text[i])
                && scale[i].is_none_or(|s| s < self.least_float)
        });
        if refused {
            for (i, s) in scale.iter_mut().enumerate() {
                if on_canvas(&text[i]) {
                    *s = None;
                }
            }
        }
        refused
    }
}

/// Boxes `a` and `b` lie closer than [`TEXT_GAP_PX`].
fn overlap(a: [f64; 4], b: [f64; 4]) -> bool {
    a[0] < b[2] + TEXT_GAP_PX
        && b[0] < a[2] + TEXT_GAP_PX
        && a[1] < b[3] + TEXT_GAP_PX
        && b[1] < a[3] + TEXT_GAP_PX
}

/// Block i over `bi` lies too close to another block's box.
fn clash(i: usize, bi: [f64; 4], boxes: &[Option<[f64; 4]>]) -> bool {
    boxes
        .iter()
        .enumerate()
        .any(|(j, bj)| i != j && bj.is_some_and(|bj| overlap(bi, bj)))
}

/// Each group that may move, with the directions it may move in: a block alone any way, a
/// row (an x axis' ticks) across its line, a column (a y axis' ticks) along its lines, so
/// that no label slides off the tick it names; blocks read alone first.
fn movers(text: &[TextBlock], group: &[usize]) -> Vec<Mover> {
    let mut movers: Vec<Mover> = Vec::new();
    for g in (0..text.len()).filter(|&g| group[g] == g) {
        let members: Vec<usize> = (0..text.len()).filter(|&i| group[i] == g).collect();
        let m = &members;
        let row = m
            .iter()
            .all(|&i| m.iter().all(|&j| text[i].y0 < text[j].y1));
        let column = m
            .iter()
            .all(|&i| m.iter().all(|&j| text[i].x0 < text[j].x1));
        let (up, down) = (DVec2::NEG_Y, DVec2::Y);
        let (left, right) = (DVec2::NEG_X, DVec2::X);
        let moves = match (m.len() == 1, row, column) {
            (true, _, _) => vec![up, down, left, right],
            (false, true, _) => vec![up, down],
            (false, false, true) => vec![left, right],
            _ => {
                // Aligned both ways (an x axis' labels and a y axis' meeting at a corner,
                // or across panels): its rows move as rows, the rest as columns.
                let (rows, rest) = lines_of(text, members, true);
                let (columns, rest) = lines_of(text, rest, false);
                movers.extend(rows.into_iter().map(|members| Mover {
                    members,
                    moves: vec![up, down],
                }));
                movers.extend(columns.into_iter().map(|members| Mover {
                    members,
                    moves: vec![left, right],
                }));
                movers.extend(rest.into_iter().map(|i| Mover {
                    members: vec![i],
                    moves: vec![up, down, left, right],
                }));
                continue;
            }
        };
        movers.push(Mover { members, moves });
    }
    movers.sort_by_key(|m| m.members.len() > 1);
    movers
}

/// The rows (`rows`) or columns of `members` with two blocks or more (blocks that overlap
/// each other across the line, all of them), and the blocks in none.
fn lines_of(text: &[TextBlock], members: Vec<usize>, rows: bool) -> (Vec<Vec<usize>>, Vec<usize>) {
    let across = |i: usize| match rows {
        true => [text[i].y0, text[i].y1],
        false => [text[i].x0, text[i].x1],
    };
    let mut lines: Vec<Vec<usize>> = Vec::new();
    for i in members {
        let [a0, a1] = across(i);
        let line = lines.iter_mut().find(|l| {
            l.iter().all(|&j| {
                let [b0, b1] = across(j);
                a0 < b1 && b0 < a1
            })
        });
        match line {
            Some(l) => l.push(i),
            None => lines.push(vec![i]),
        }
    }
    let (lines, single): (Vec<_>, Vec<_>) = lines.into_iter().partition(|l| l.len() >= 2);
    (lines, single.into_iter().flatten().collect())
}

/// Block i's anchor along x: 0 left, 0.5 centre, 1 right. A column is aligned by the edge
/// most of its blocks share: a y axis' "120" and "100" share their left edges by chance, all
/// its labels their right. Only labels of one type size make a column: a heading whose end
/// falls where a panel's labels end below it is still centred.
fn anchor(src: &Image, text: &[TextBlock], ground: [u8; 3], i: usize) -> f64 {
    let t = &text[i];
    if t.sideways {
        return 0.5;
    }
    // Blocks of its size aligned with `t` by an edge (above or below it).
    let column = |edge: fn(&TextBlock) -> u32| {
        text.iter()
            .enumerate()
            .filter(|&(j, o)| {
                j != i
                    && !o.sideways
                    && o.same_type_size(t)
                    && edge(o).abs_diff(edge(t)) <= ALIGNED_PX
                    && (o.y0 >= t.y1 || o.y1 <= t.y0)
            })
            .count()
    };
    match (column(|b| b.x0), column(|b| b.x1)) {
        (0, 0) => 0.5,
        // Both edges aligned (labels of one width): the side facing what they name, the
        // nearer ink, stays put.
        (left, right) if left == right => {
            let ink_nearer_right = ground_run(src, t, ground, 1) < ground_run(src, t, ground, -1);
            if ink_nearer_right {
                1.0
            } else {
                0.0
            }
        }
        (left, right) if right > left => 1.0,
        _ => 0.0,
    }
}

/// Pixels of `ground` from text block `t`'s side in direction `dir` (1 right, -1 left) along
/// its middle row, up to 4 line heights: how far the nearest ink on that side lies.
fn ground_run(src: &Image, t: &TextBlock, ground: [u8; 3], dir: i64) -> usize {
    let (y, reach) = ((t.y0 + t.y1) / 2, 4 * t.line_height as i64);
    let start = if dir > 0 {
        t.x1 as i64
    } else {
        t.x0 as i64 - 1
    };
    (0..reach)
        .map(|k| start + dir * k)
        .take_while(|&x| x >= 0 && x < src.width() as i64)
        .take_while(|&x| {
            let p = src.get(x as u32, y.min(src.height() - 1));
            same_colour([p[0], p[1], p[2]], ground)
        })
        .count()
}

/// Labels read together keep one size: the blocks of one aligned column (a legend, a y axis'
/// ticks, the centred titles of a dashboard's panels) or one row (an x axis' ticks) of the same type size in
/// one area take the smallest scale any of them could float at, and follow the map together
/// where one of them cannot float, since labels of two sizes read as two kinds of thing
/// (after tearing, the most visible defect). Shrinking a block
/// about its anchor keeps it inside the box it had, so no new overlap appears.
fn share_scale(
    text: &[TextBlock],
    area_of: &impl Fn(&TextBlock) -> Option<usize>,
    scale: &mut [Option<f64>],
    in_plot: &impl Fn(usize) -> bool,
) {
    let group = type_groups(text, area_of, scale, Alignment::Centres);
    let n = text.len();
    let key = |i: usize| group[i] + n * usize::from(in_plot(i));
    let mut least = vec![f64::INFINITY; 2 * n];
    for (i, s) in scale.iter().enumerate() {
        if let Some(s) = *s {
            least[key(i)] = least[key(i)].min(s);
        }
    }
    for (i, s) in scale.iter_mut().enumerate() {
        if s.is_some() {
            *s = Some(least[key(i)]);
        }
    }
}

/// Centred blocks closer than this many line heights are stacked labels of two kinds (a
/// tick label over its axis' title), not titles of panels side by side or one over another:
/// stacked labels sit one or two lines apart, panels are many lines tall.
const STACKED_LINES: f64 = 3.0;

/// How blocks line up to be one column or row ([`type_groups`]).
#[derive(Copy, Clone, PartialEq)]
enum Alignment {
    /// By a left or right edge, or by their tops or feet: the labels of an axis or a legend,
    /// which move together when they make room ([`movers`]).
    Edges,
    /// Also by their centres, and sideways text with sideways text: besides those, the
    /// titles of a grid of panels, centred over (or, set sideways, beside) their panels. They
    /// read as one kind of label and keep one size ([`share_scale`]), though they never move
    /// as one.
    Centres,
}

/// The group of each block (the index of one member): blocks of one aligned column or row
/// of the same type size and direction in one area are one group, any other block a group
/// of its own.
fn type_groups(
    text: &[TextBlock],
    area_of: &impl Fn(&TextBlock) -> Option<usize>,
    scale: &[Option<f64>],
    align: Alignment,
) -> Vec<usize> {
    let n = text.len();
    let mut group: Vec<usize> = (0..n).collect();
    let near = |a: u32, b: u32| a.abs_diff(b) <= ALIGNED_PX;
    fn root(g: &mut [usize], mut i: usize) -> usize {
        while g[i] != i {
            g[i] = g[g[i]];
            i = g[i];
        }
        i
    }
    for i in 0..n {
        for j in i + 1..n {
            let (a, b) = (&text[i], &text[j]);
            // Text set sideways is read with text set sideways only: its feet are on its side.
            if scale[i].is_none()
                || scale[j].is_none()
                || a.sideways != b.sideways
                || (a.sideways && align == Alignment::Edges)
                || area_of(a) != area_of(b)
            {
                continue;
            }
            if !a.same_type_size(b) {
                continue;
            }
            let (ha, hb) = (a.line_height as f64, b.line_height as f64);
            let apart_y = a.y0 >= b.y1 || a.y1 <= b.y0;
            let apart_x = a.x0 >= b.x1 || a.x1 <= b.x0;
            // Left, right or centre aligned: the titles of a grid of panels are centred
            // over their panels, one column of them per column of panels.
            let centres = align == Alignment::Centres;
            // Centred a few lines apart is a label and its caption (a tick and the axis'
            // title under it), two kinds of text; titles of panels stand a panel apart.
            let gap_y = a.y0.max(b.y0).saturating_sub(a.y1.min(b.y1)) as f64;
            let gap_x = a.x0.max(b.x0).saturating_sub(a.x1.min(b.x1)) as f64;
            let far = |gap: f64| gap >= STACKED_LINES * ha.max(hb);
            let centred =
                centres && far(gap_y) && (a.x0 + a.x1).abs_diff(b.x0 + b.x1) <= 2 * ALIGNED_PX;
            let column = apart_y && (near(a.x0, b.x0) || near(a.x1, b.x1) || centred);
            // Tops or feet aligned: a descender moves one and not the other. Sideways titles
            // of a row of panels are centred on their panels' heights instead.
            let centred_y = centres
                && a.sideways
                && far(gap_x)
                && (a.y0 + a.y1).abs_diff(b.y0 + b.y1) <= 2 * ALIGNED_PX;
            let row = apart_x && (near(a.y0, b.y0) || near(a.y1, b.y1) || centred_y);
            if column || row {
                let (ri, rj) = (root(&mut group, i), root(&mut group, j));
                group[ri] = rj;
            }
        }
    }
    (0..n).map(|i| root(&mut group, i)).collect()
}

/// A word is set in one colour: antialiased, its pixels lie between that colour and the
/// ground, all in one direction from the ground. Least cosine between a pixel's direction
/// and the ink's for the two to be one colour (grey and orange on white: 0.78), least share
/// of the ink in that colour, and least distance from the ground for a pixel to be ink
/// (beyond noise and faint antialiasing, whose direction is unsteady).
const SAME_INK_COS: f64 = 0.9;
const ONE_INK_SHARE: f64 = 0.75;
const INK_DISTANCE: f64 = 48.0;

/// Whether the ink of text block `t` on `ground` is one colour: judged against the
/// direction of its strongest pixel, the core of a stroke.
fn one_ink(src: &Image, t: &TextBlock, ground: [u8; 3]) -> bool {
    let g = DVec3::new(ground[0] as f64, ground[1] as f64, ground[2] as f64);
    let ink = |x: u32, y: u32| {
        let p = src.get(x, y);
        let d = DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64) - g;
        (d.length() > INK_DISTANCE).then_some(d)
    };
    let (x1, y1) = (t.x1.min(src.width()), t.y1.min(src.height()));
    let pixels = || (t.y0..y1).flat_map(move |y| (t.x0..x1).filter_map(move |x| ink(x, y)));
    let Some(core) = pixels().max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))
    else {
        return true;
    };
    let core = core.normalize();
    let (mut same, mut all) = (0u32, 0u32);
    for d in pixels() {
        all += 1;
        if d.normalize().dot(core) >= SAME_INK_COS {
            same += 1;
        }
    }
    same as f64 >= ONE_INK_SHARE * all as f64
}

/// Whether block `t` holds its words whole: no ink right beside its ends along its line
/// (within [`WHOLE_REACH_PX`], across the middle half of the line), nor, for a block
/// shorter than [`ACROSS_LINES`] line heights, right above or below it. A block found in pieces
/// ("Chi" of "Child", a sideways title read in upright bits) floated at its own scale beside
/// the rest left to the map reads torn (judged blind); such a piece follows the map with the
/// rest of its word.
fn whole(src: &Image, t: &TextBlock, ground: [u8; 3]) -> bool {
    let g = DVec3::new(ground[0] as f64, ground[1] as f64, ground[2] as f64);
    let ink = |x: u32, y: u32| {
        let p = src.get(x, y);
        (DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64) - g).length() > INK_DISTANCE
    };
    let (w, h) = (src.width(), src.height());
    // Along the line: x for upright text, y for text set sideways.
    let (lo, hi, a0, a1, n) = match t.sideways {
        false => (t.x0, t.x1, t.y0, t.y1, w),
        true => (t.y0, t.y1, t.x0, t.x1, h),
    };
    let quarter = (a1 - a0) / 4;
    let (m0, m1) = (a0 + quarter, (a1 - quarter).max(a0 + quarter + 1));
    let at = |along: u32, across: u32| match t.sideways {
        false => ink(along, across.min(h - 1)),
        true => ink(across.min(w - 1), along),
    };
    let beside = (1..=WHOLE_REACH_PX)
        .flat_map(|d| [lo.checked_sub(d), Some(hi + d).filter(|&v| v < n)])
        .flatten();
    let inked = |along: u32| (m0..m1).filter(|&a| at(along, a)).count() >= 2;
    if hi - lo >= ACROSS_LINES * (a1 - a0).max(1) {
        return !beside.into_iter().any(inked);
    }
    // Across the line too, for a block hardly longer than its line is high: the letters
    // of a word set the other way (a sideways title read as upright pieces) stand right
    // above and below the piece. (A longer line is no such piece, and its descenders may
    // reach past its box.)
    let n_across = match t.sideways {
        false => h,
        true => w,
    };
    let eighth = (hi - lo) / 8;
    let (l0, l1) = (lo + eighth, (hi - eighth).max(lo + eighth + 1));
    let over = (1..=WHOLE_REACH_PX)
        .flat_map(|d| [a0.checked_sub(d), Some(a1 + d).filter(|&v| v < n_across)])
        .flatten();
    let inked_across = |across: u32| (l0..l1).filter(|&l| at(l, across)).count() >= 2;
    !beside.into_iter().any(inked) && !over.into_iter().any(inked_across)
}

/// How far beside a text block's ends its word may go on ([`whole`]), pixels: closer than
/// the space between two words.
const WHOLE_REACH_PX: u32 = 2;
/// Length of a block, in line heights, from which it is looked at along its line only
/// ([`whole`]).
const ACROSS_LINES: u32 = 2;

/// Output pixels beyond a floating block's box whose source it may hide (the resampler's
/// reach, rounded to a pixel).
const RESAMPLE_REACH_PX: f64 = 1.0;
/// Most RGB distance from the ground colour of a pixel that is still ground to a floating
/// block (compression noise): a faint rule or a light panel edge, 40 or more from white,
/// is ink it must not hide.
const GROUND_NOISE: i32 = 24;

/// Share of the pixels a floating text block newly covers (beyond its own box) that may be
/// ink: a stray antialiased pixel, not a bar's end or a neighbouring cell.
const MAX_COVERED_INK: f64 = 0.01;

/// The colour of the ground a text block stands on: the most common colour of the ring of
/// pixels just inside its box (glyphs rarely touch their box on all four sides), and the
/// share of the ring it takes.
fn box_ground(src: &Image, t: &TextBlock) -> ([u8; 3], f64) {
    let counts = ring_colours(src, [t.x0, t.y0, t.x1, t.y1]);
    let all: u32 = counts.iter().map(|c| c.1).sum();
    counts
        .into_iter()
        .max_by_key(|&(_, n)| n)
        .map_or(([255; 3], 0.0), |(c, n)| (c, n as f64 / all.max(1) as f64))
}

const GROUND_COLOURS: usize = 3;

/// `rect` grown, side by side and by at most `reach` pixels, while the row or column beyond
/// it holds a pixel of `colour` along it: a blob's box from the saliency cells that hold it
/// misses its faint antialiased edge, which a pasted mark would otherwise cut off.
fn ink_box(src: &Image, rect: [u32; 4], colour: [u8; 3], reach: u32) -> [u32; 4] {
    let (w, h) = (src.width(), src.height());
    let [mut x0, mut y0, mut x1, mut y1] = [rect[0], rect[1], rect[2].min(w), rect[3].min(h)];
    let inked = |x: u32, y: u32| {
        let p = src.get(x, y);
        same_colour([p[0], p[1], p[2]], colour)
    };
    for _ in 0..reach {
        let mut grew = false;
        if x0 > 0 && (y0..y1).any(|y| inked(x0 - 1, y)) {
            x0 -= 1;
            grew = true;
        }
        if x1 < w && (y0..y1).any(|y| inked(x1, y)) {
            x1 += 1;
            grew = true;
        }
        if y0 > 0 && (x0..x1).any(|x| inked(x, y0 - 1)) {
            y0 -= 1;
            grew = true;
        }
        if y1 < h && (x0..x1).any(|x| inked(x, y1)) {
            y1 += 1;
            grew = true;
        }
        if !grew {
            break;
        }
    }
    [x0, y0, x1, y1]
}

/// Whether a blob of `colour` inside `rect` stands alone on a plain ground: its colour does
/// not run on from its box to the border of `rect` ([`runs_on`]: a region of a map, a
/// cluster, a line through a marker) and, bar a few pixels, at most [`GROUND_COLOURS`] colours once their
/// antialiased blends are folded in ([`unblended`]): a dot on the boundary of two regions,
/// a graph's node where lines of two colours meet it. So the ground painted in under it
/// stays plain.
fn stands_alone(src: &Image, rect: [u32; 4], colour: [u8; 3]) -> bool {
    let counts = ring_colours(src, rect);
    if counts.iter().any(|&(c, _)| same_colour(c, colour)) && runs_on(src, rect, colour) {
        return false;
    }
    let all: u32 = counts.iter().map(|c| c.1).sum();
    let mut inks = unblended(counts);
    inks.sort_unstable_by_key(|b| std::cmp::Reverse(b.1));
    let few: u32 = inks.iter().take(GROUND_COLOURS).map(|c| c.1).sum();
    few as f64 >= FLAT_GROUND * all.max(1) as f64
}

/// Whether `colour` on the border of `rect` (a blob's box grown by [`RIM_PX`] + 1) runs on
/// from the box inside: a pixel of it on the border joined to the box through pixels of it
/// in the band between them (8-connected: a slanted line one pixel wide joins). A neighbour
/// of that colour past a gap of ground (a scatter's two dots side by side) does not.
fn runs_on(src: &Image, rect: [u32; 4], colour: [u8; 3]) -> bool {
    let (w, h) = (src.width(), src.height());
    let [x0, y0] = [rect[0].min(w - 1), rect[1].min(h - 1)];
    let [x1, y1] = [rect[2].clamp(x0 + 1, w) - 1, rect[3].clamp(y0 + 1, h) - 1];
    let inset = RIM_PX + 1;
    let of = |x: u32, y: u32| {
        let p = src.get(x, y);
        same_colour([p[0], p[1], p[2]], colour)
    };
    // Depth into the band: 0 on the border, `inset` at the box.
    let depth = |x: u32, y: u32| (x - x0).min(x1 - x).min(y - y0).min(y1 - y);
    let rw = (x1 - x0 + 1) as usize;
    let mut seen = vec![false; rw * (y1 - y0 + 1) as usize];
    let mut stack: Vec<(u32, u32)> = (x0..=x1)
        .flat_map(|x| [(x, y0), (x, y1)])
        .chain((y0..=y1).flat_map(|y| [(x0, y), (x1, y)]))
        .filter(|&(x, y)| of(x, y))
        .collect();
    while let Some((x, y)) = stack.pop() {
        let at = (y - y0) as usize * rw + (x - x0) as usize;
        if std::mem::replace(&mut seen[at], true) {
            continue;
        }
        if depth(x, y) >= inset {
            return true;
        }
        for (dx, dy) in crate::raster::NEIGHBOURS_8 {
            let (nx, ny) = (x as i64 + dx, y as i64 + dy);
            if nx < x0 as i64 || ny < y0 as i64 || nx > x1 as i64 || ny > y1 as i64 {
                continue;
            }
            let (nx, ny) = (nx as u32, ny as u32);
            if depth(nx, ny) <= inset && of(nx, ny) {
                stack.push((nx, ny));
            }
        }
    }
    false
}

/// Colours with their counts, each blend of two others (an antialiased edge between a line
/// and the ground, where two lines cross) folded into the nearer of the two: the commonest
/// colour first, then the others from the farthest from it, so that a line's pure colour
/// comes before its paler edges.
fn unblended(mut counts: Vec<([u8; 3], u32)>) -> Vec<([u8; 3], u32)> {
    let dist = |a: [u8; 3], b: [u8; 3]| {
        (0..3)
            .map(|k| (a[k] as f64 - b[k] as f64).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let Some(first) = (0..counts.len()).max_by_key(|&i| counts[i].1) else {
        return counts;
    };
    let ground = counts.swap_remove(first);
    counts.sort_by(|a, b| dist(b.0, ground.0).total_cmp(&dist(a.0, ground.0)));
    let mut inks = vec![ground];
    for (c, n) in counts {
        let between = (0..inks.len())
            .flat_map(|i| (i + 1..inks.len()).map(move |j| (i, j)))
            .find(|&(i, j)| {
                let (a, b) = (inks[i].0, inks[j].0);
                dist(a, c) + dist(c, b) <= dist(a, b) + BLEND_SLACK
            });
        match between {
            Some((i, j)) => {
                let near = if dist(inks[i].0, c) <= dist(inks[j].0, c) {
                    i
                } else {
                    j
                };
                inks[near].1 += n;
            }
            None => inks.push((c, n)),
        }
    }
    inks
}

/// How far (RGB distance, the detour from the straight path) a colour may lie off the line
/// between two others to be their blend: antialiasing mixes along that line, up to the
/// rounding and noise one colour group ([`SAME_COLOUR`]) already spans on either side.
const BLEND_SLACK: f64 = SAME_COLOUR as f64 / 2.0;

/// The colours on the border pixels of `[x0, y0, x1, y1)` (clipped to the picture), each with
/// its pixel count; colours within [`SAME_COLOUR`] of each other count as one.
fn ring_colours(src: &Image, [x0, y0, x1, y1]: [u32; 4]) -> Vec<([u8; 3], u32)> {
    let (w, h) = (src.width(), src.height());
    let (x0, y0) = (x0.min(w - 1), y0.min(h - 1));
    let (x1, y1) = (x1.clamp(x0 + 1, w) - 1, y1.clamp(y0 + 1, h) - 1);
    let mut counts: Vec<([u8; 3], u32)> = Vec::new();
    let ring = (x0..=x1)
        .flat_map(|x| [(x, y0), (x, y1)])
        .chain((y0..=y1).flat_map(|y| [(x0, y), (x1, y)]));
    for (x, y) in ring {
        let p = src.get(x, y);
        let c = [p[0], p[1], p[2]];
        match counts.iter_mut().find(|(k, _)| same_colour(*k, c)) {
            Some((_, n)) => *n += 1,
            None => counts.push((c, 1)),
        }
    }
    counts
}

/// Whether text block `t`, drawn over the output box `b` (its whole box, ground and all),
/// would hide ink that is not its own: the source under `b` by its area's map, outside the
/// block's own box and the boxes of the text `floating` elsewhere (painted out where it
/// stands), is not all of the block's ground colour. A label may grow into empty
/// ground, never over a bar, a cell or its neighbour.
fn covers_ink(
    src: &Image,
    t: &TextBlock,
    ground: [u8; 3],
    b: [f64; 4],
    map: Option<[f64; 4]>,
    floating: &[&TextBlock],
) -> bool {
    let Some([ax, bx, ay, by]) = map else {
        return false;
    };
    if ax <= 0.0 || ay <= 0.0 {
        return false;
    }
    let (w, h) = (src.width() as f64, src.height() as f64);
    // The resampler draws an output pixel from the source around it: a faint rule just
    // outside the box still shows in the pixel the box's edge hides.
    let r = RESAMPLE_REACH_PX;
    let sx0 = ((b[0] - r - bx) / ax).floor().clamp(0.0, w) as u32;
    let sx1 = ((b[2] + r - bx) / ax).ceil().clamp(0.0, w) as u32;
    let sy0 = ((b[1] - r - by) / ay).floor().clamp(0.0, h) as u32;
    let sy1 = ((b[3] + r - by) / ay).ceil().clamp(0.0, h) as u32;
    let inside =
        |t: &TextBlock, x: u32, y: u32| x + 1 >= t.x0 && x <= t.x1 && y + 1 >= t.y0 && y <= t.y1;
    // Other floating blocks are painted out where they stand and drawn where they float.
    let near: Vec<&TextBlock> = (floating.iter().copied())
        .filter(|o| o.x0 <= sx1 && o.x1 + 1 >= sx0 && o.y0 <= sy1 && o.y1 + 1 >= sy0)
        .collect();
    // Past this much ink the answer is yes whatever the rest holds (`all` is at most the
    // rectangle's pixels): a label tried over a heat map's cells stops at its first few.
    let area = sx1.saturating_sub(sx0) as f64 * sy1.saturating_sub(sy0) as f64;
    let surely = MAX_COVERED_INK * area.max(1.0);
    let (mut ink, mut all) = (0u32, 0u32);
    for y in sy0..sy1 {
        for x in sx0..sx1 {
            if inside(t, x, y) {
                continue;
            }
            if near.iter().any(|o| inside(o, x, y)) {
                continue;
            }
            all += 1;
            let p = src.get(x, y);
            let d: i32 = (0..3)
                .map(|c| (p[c] as i32 - ground[c] as i32).pow(2))
                .sum();
            if d > GROUND_NOISE * GROUND_NOISE {
                ink += 1;
            }
        }
        if ink as f64 > surely {
            return true;
        }
    }
    ink as f64 > MAX_COVERED_INK * all.max(1) as f64
}

/// The marks inside data areas that float (drawn at one scale per area, centred where the
/// area's map takes their centre): blobs of high importance inside an area, clear of its
/// sides (a bar standing on the axis is the axis' business) and of text, not rectangles,
/// and smaller than [`AREA_MARK_SHARE`] of the area. Each with the index of its area.
pub(crate) fn area_marks(
    src: &Image,
    vsm: &Vsm,
    st: &crate::structure::Structure,
) -> Vec<(Mark, usize, [u8; 3])> {
    let grid = vsm.grid_size();
    let (gw, gh) = (grid.width as usize, grid.height as usize);
    let mut scan = MarkScan {
        src,
        // Blocks of two inks are not words (dots along an axis): they shelter no mark.
        text: (st.text.iter())
            .filter(|t| one_ink(src, t, box_ground(src, t).0))
            .collect(),
        s: vsm.scale() as f64,
        gw,
        gh,
        imp: vsm.importance(),
        seen: vec![false; gw * gh],
        stack: Vec::new(),
    };
    let mut out = Vec::new();
    for (k, a) in st.areas.iter().enumerate() {
        scan.area(k, a, &mut out);
    }
    out
}

/// The search for the data areas' marks: what it reads, and the blobs' flood fill's state,
/// kept across areas (a cell is in one blob at most).
struct MarkScan<'a> {
    src: &'a Image,
    /// Text blocks of one ink: a blob over one is a glyph, no mark.
    text: Vec<&'a TextBlock>,
    /// The importance map's cell size (source pixels), its size in cells, and its cells.
    s: f64,
    gw: usize,
    gh: usize,
    imp: &'a [f32],
    seen: Vec<bool>,
    stack: Vec<usize>,
}

/// One data area as its marks are looked for.
struct AreaCells {
    /// Cells `[c0, r0, c1, r1)` whose centre lies strictly inside the area.
    window: [usize; 4],
    /// Largest side of a mark ([`AREA_MARK_SHARE`] of the area's shorter side), pixels.
    max_side: f64,
    /// The area is a whole canvas taken as one ([`crate::structure::AreaKind::Canvas`]).
    whole_canvas: bool,
}

/// What a blob of one colour is to [`area_marks`].
enum BlobKind {
    /// A round mark standing alone, which floats.
    Mark(Mark),
    /// Not a mark (a region, a line, a bar): its colour's marks on a whole canvas do not float.
    Spoils,
    /// Says nothing of its colour: a speck, a glyph, what the area's edge cuts, a bar or a
    /// cell on a whole canvas.
    Mute,
}

impl MarkScan<'_> {
    /// Appends area `k`'s marks to `out`, each with `k` and its colour.
    fn area(
        &mut self,
        k: usize,
        a: &crate::structure::DataArea,
        out: &mut Vec<(Mark, usize, [u8; 3])>,
    ) {
        let s = self.s;
        // A whole canvas taken as one area (`--regions affine`) may be a map or a graph,
        // where a blob is as likely a region or a cluster as a mark: pasting some of them
        // round tears maps and leaves round marks beside squeezed ones, worse than a linear
        // resize's uniform squeeze. There a colour's marks float all together or
        // not at all: only if every blob of that colour is a round mark standing alone.
        let cells = AreaCells {
            window: [
                ((a.x0 / s).floor() as usize + 1).min(self.gw),
                ((a.y0 / s).floor() as usize + 1).min(self.gh),
                ((a.x1 / s).ceil() as usize).saturating_sub(1).min(self.gw),
                ((a.y1 / s).ceil() as usize).saturating_sub(1).min(self.gh),
            ],
            max_side: AREA_MARK_SHARE * (a.x1 - a.x0).min(a.y1 - a.y0),
            whole_canvas: a.kind == crate::structure::AreaKind::Canvas,
        };
        let first = out.len();
        // Colours with a blob that is no round mark standing alone, from each pass: a pale
        // colour spoils only pale marks (colours near one another need not be near a third).
        let mut spoiled: [Vec<[u8; 3]>; 2] = Default::default();
        let mut first_pale = usize::MAX;
        // Marks of strong colours first; then, of colours none of those has, pale marks on a
        // ground near the frame's mean (a cyan dot on a light sea). A strong colour's pale
        // shades (a bubble's translucent overlap, its antialiased rim) are its business.
        // Only on a canvas taken whole, where a colour floats all or none: in an area bounded
        // by axes a pale colour is as likely a strong mark's antialiased rim, floated alone.
        let pale = (median_importance(self.imp, self.gw, cells.window) + MARK_ABOVE_GROUND)
            .min(AREA_MARK_IMPORTANCE);
        let passes = if cells.whole_canvas && pale < AREA_MARK_IMPORTANCE {
            2
        } else {
            1
        };
        let mut strong: Vec<[u8; 3]> = Vec::new();
        for least in [AREA_MARK_IMPORTANCE, pale].into_iter().take(passes) {
            let pass_pale = least < AREA_MARK_IMPORTANCE;
            if pass_pale {
                first_pale = out.len();
            }
            let ([c0, r0, c1, r1], gw) = (cells.window, self.gw);
            for r in r0..r1 {
                let (row, end) = (r * gw, r * gw + c1.max(c0));
                let mut next = row + c0;
                // The next cell in no blob yet and important enough, by a scan of the row's
                // slices: most cells fail this test, so it is most of the search.
                while let Some(start) = next_candidate(&self.seen, self.imp, next..end, least) {
                    next = start + 1;
                    // One colour: a line chart's markers stand apart from the line through
                    // them.
                    let colour = cell_colour(self.src, s, start - row, r);
                    if pass_pale && strong.iter().any(|&k| same_colour(k, colour)) {
                        continue;
                    }
                    if !pass_pale && !strong.iter().any(|&k| same_colour(k, colour)) {
                        strong.push(colour);
                    }
                    match self.blob_at(start, least, colour, &cells) {
                        BlobKind::Mark(m) => out.push((m, k, colour)),
                        BlobKind::Spoils if cells.whole_canvas => {
                            spoiled[pass_pale as usize].push(colour)
                        }
                        BlobKind::Spoils | BlobKind::Mute => {}
                    }
                }
            }
        }
        if cells.whole_canvas {
            drop_spoiled(out, first, first_pale, &spoiled);
        }
    }

    /// Fills the blob of `colour` (cells of importance `least` or more) from cell `start`,
    /// and tells what it is.
    fn blob_at(&mut self, start: usize, least: f32, colour: [u8; 3], area: &AreaCells) -> BlobKind {
        let (src, s, gw, imp) = (self.src, self.s, self.gw, self.imp);
        let same =
            |j: usize| imp[j] >= least && same_colour(cell_colour(src, s, j % gw, j / gw), colour);
        let blob = flood(
            start,
            gw,
            area.window,
            &mut self.seen,
            &mut self.stack,
            same,
        );
        let [x0, y0, x1, y1] = blob.cells;
        let [c0, r0, c1, r1] = area.window;
        let touches = x0 <= c0 || y0 <= r0 || x1 >= c1 || y1 >= r1;
        let bbox = ink_box(
            src,
            [x0, y0, x1, y1].map(|v| (v as f64 * s) as u32),
            colour,
            s.ceil() as u32 + RIM_PX,
        );
        let (bw, bh) = ((bbox[2] - bbox[0]) as f64, (bbox[3] - bbox[1]) as f64);
        let fill = blob.count as f64 / ((x1 - x0) * (y1 - y0)) as f64;
        let in_text = self
            .text
            .iter()
            .any(|t| (bbox[0] < t.x1 && bbox[2] > t.x0) && (bbox[1] < t.y1 && bbox[3] > t.y0));
        // Specks, text and what the canvas' edge cuts say nothing of a colour.
        if touches || in_text || bw.max(bh) < 3.0 {
            return BlobKind::Mute;
        }
        let grown = [
            bbox[0].saturating_sub(RIM_PX + 1),
            bbox[1].saturating_sub(RIM_PX + 1),
            bbox[2] + RIM_PX + 1,
            bbox[3] + RIM_PX + 1,
        ];
        // A blob a few cells across is a filled square at cell resolution, whatever its
        // shape: only a larger one can be told for a rectangle.
        let (cw, ch) = ((x1 - x0) as f64, (y1 - y0) as f64);
        let rectangle = fill > RECTANGLE_FILL && cw.max(ch) > SMALL_MARK_CELLS;
        // A bar or a cell follows the map (its length is data) and says nothing of its
        // colour's round marks: a dashboard draws a progress bar in the green of its status
        // dots.
        if rectangle && area.whole_canvas {
            return BlobKind::Mute;
        }
        // A blob of a few cells has no shape at the map's resolution: a speck where a line
        // meets a mark, antialiased to a blend of both, a piece of a line in one of its
        // antialiased shades, or a mark's pale rim that the scan reached first, says nothing
        // of its colour.
        if blob.count <= SPECK_CELLS {
            return BlobKind::Mute;
        }
        if !is_round(&blob, fill)
            || bw.max(bh) > area.max_side
            || rectangle
            || (area.whole_canvas && !stands_alone(src, grown, colour))
        {
            return BlobKind::Spoils;
        }
        let centre = DVec2::new(
            (bbox[0] + bbox[2]) as f64 / 2.0,
            (bbox[1] + bbox[3]) as f64 / 2.0,
        );
        BlobKind::Mark(Mark {
            center: centre,
            ring_radius: 0.5 * (bw * bw + bh * bh).sqrt() + 1.5,
            bbox,
            pixels: (blob.count as f64 * s * s) as u32,
        })
    }
}

/// Drops the marks of `out` from `first` on whose colour is `spoiled` (`[0]`: by a blob of
/// the strong pass; `[1]`: of the pale pass, which spoils only the pale marks, from
/// `first_pale` on): on a whole canvas a colour's marks float all together or not at all.
fn drop_spoiled(
    out: &mut Vec<(Mark, usize, [u8; 3])>,
    first: usize,
    first_pale: usize,
    spoiled: &[Vec<[u8; 3]>; 2],
) {
    let mut i = 0;
    out.retain(|m: &(Mark, usize, [u8; 3])| {
        i += 1;
        let by = |k: &Vec<[u8; 3]>| k.iter().any(|&c| same_colour(c, m.2));
        i <= first || !(by(&spoiled[0]) || (i > first_pale && by(&spoiled[1])))
    });
}

/// Round marks only (a disc, a ring, a symbol about as wide as tall, its ink centred in its
/// box): a shape that is not may be anything (a group of cells, a piece of a map) and follows
/// the map, as a linear resize would draw it. `fill` is the share of its box the blob fills.
fn is_round(blob: &Blob, fill: f64) -> bool {
    let [x0, y0, x1, y1] = blob.cells;
    let (mx, my) = blob.mean;
    let (cw, ch) = ((x1 - x0) as f64, (y1 - y0) as f64);
    let centred = (mx - (x0 + x1) as f64 / 2.0).abs() <= MARK_CENTRED * cw
        && (my - (y0 + y1) as f64 / 2.0).abs() <= MARK_CENTRED * ch;
    cw.max(ch) <= MAX_MARK_ASPECT * cw.min(ch)
        && (cw.max(ch) <= SMALL_MARK_CELLS || (fill >= MIN_MARK_FILL && centred))
}

/// Colours this close (RGB distance) are one mark's: antialiasing and a marker's own shading
/// stay in, a line of another colour through it stays out.
const SAME_COLOUR: i32 = 60;

fn same_colour(a: [u8; 3], b: [u8; 3]) -> bool {
    let d: i32 = (0..3).map(|c| (a[c] as i32 - b[c] as i32).pow(2)).sum();
    d < SAME_COLOUR * SAME_COLOUR
}

/// The first cell of `range` in no blob yet and of importance `least` or more: eight cells
/// tested at a time without an early exit (one vector compare), then the one found.
fn next_candidate(
    seen: &[bool],
    imp: &[f32],
    range: std::ops::Range<usize>,
    least: f32,
) -> Option<usize> {
    let (seen, imp) = (&seen[range.clone()], &imp[range.clone()]);
    let hit = |(&seen, &v): (&bool, &f32)| !seen && v >= least;
    let (mut s8, mut i8) = (seen.chunks_exact(8), imp.chunks_exact(8));
    for (k, (s, i)) in (&mut s8).zip(&mut i8).enumerate() {
        if s.iter().zip(i).fold(false, |any, c| any | hit(c)) {
            let at = s.iter().zip(i).position(hit).expect("one of the eight");
            return Some(range.start + 8 * k + at);
        }
    }
    let done = seen.len() - s8.remainder().len();
    (s8.remainder().iter().zip(i8.remainder()))
        .position(hit)
        .map(|at| range.start + done + at)
}

/// The median importance of the cells `[c0, c1) × [r0, r1)` of a map `gw` cells wide (to a
/// 256th), 0 for no cells.
fn median_importance(imp: &[f32], gw: usize, [c0, r0, c1, r1]: [usize; 4]) -> f32 {
    // Four histograms, filled in turn: a run of equal values (a flat ground) then adds to
    // four counters instead of waiting on one.
    let mut hist = [[0u32; 256]; 4];
    let mut n = 0u32;
    for r in r0..r1 {
        let row = &imp[r * gw + c0..r * gw + c1.max(c0)];
        for (j, &v) in row.iter().enumerate() {
            // Selects, not `clamp` (which checks its bounds every call); NaN is 0 either way.
            let v = if v > 0.0 { v } else { 0.0 };
            let v = if v < 1.0 { v } else { 1.0 } * 255.0;
            // SAFETY: `v` lies in [0, 255]: it fits, and truncating it is the checked cast's
            // result (which tests each value's range again, most of this loop's time).
            let k = unsafe { v.to_int_unchecked::<u32>() } as usize;
            hist[j & 3][k & 255] += 1;
        }
        n += row.len() as u32;
    }
    let mut below = 0;
    let [h0, h1, h2, h3] = &hist;
    for (i, k) in (0..256).map(|i| (i, h0[i] + h1[i] + h2[i] + h3[i])) {
        below += k;
        if 2 * below > n {
            return i as f32 / 255.0;
        }
    }
    0.0
}

/// A blob of map cells: its box `[x0, y0, x1, y1)` in cells, its number of cells and the
/// mean of their centres.
struct Blob {
    cells: [usize; 4],
    count: usize,
    mean: (f64, f64),
}

/// The 8-connected blob of cells around `start` (a map `gw` cells wide) inside `[c0, r0, c1,
/// r1)` whose cells pass `same`; each is marked in `seen`. `stack` is scratch space.
fn flood(
    start: usize,
    gw: usize,
    [c0, r0, c1, r1]: [usize; 4],
    seen: &mut [bool],
    stack: &mut Vec<usize>,
    same: impl Fn(usize) -> bool,
) -> Blob {
    let (c, r) = (start % gw, start / gw);
    seen[start] = true;
    stack.push(start);
    let (mut x0, mut y0, mut x1, mut y1) = (c, r, c + 1, r + 1);
    let mut count = 0usize;
    let (mut sum_x, mut sum_y) = (0.0f64, 0.0f64);
    while let Some(i) = stack.pop() {
        let (x, y) = (i % gw, i / gw);
        count += 1;
        (sum_x, sum_y) = (sum_x + x as f64 + 0.5, sum_y + y as f64 + 0.5);
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x + 1), y1.max(y + 1));
        for (dx, dy) in [
            (-1i64, 0i64),
            (1, 0),
            (0, -1),
            (0, 1),
            (-1, -1),
            (1, 1),
            (-1, 1),
            (1, -1),
        ] {
            let (nx, ny) = (x as i64 + dx, y as i64 + dy);
            if nx < c0 as i64 || ny < r0 as i64 || nx >= c1 as i64 || ny >= r1 as i64 {
                continue;
            }
            let j = ny as usize * gw + nx as usize;
            if !seen[j] && same(j) {
                seen[j] = true;
                stack.push(j);
            }
        }
    }
    Blob {
        cells: [x0, y0, x1, y1],
        count,
        mean: (sum_x / count as f64, sum_y / count as f64),
    }
}

/// The source colour at the centre of VSM cell `(x, y)` (cells are `s` pixels wide).
fn cell_colour(src: &Image, s: f64, x: usize, y: usize) -> [u8; 3] {
    let px = ((x as f64 + 0.5) * s) as u32;
    let py = ((y as f64 + 0.5) * s) as u32;
    let p = src.get(px.min(src.width() - 1), py.min(src.height() - 1));
    [p[0], p[1], p[2]]
}

/// One floating mark: its pixels in the source and the whole-pixel shift they are copied with.
#[derive(Clone, Debug)]
struct Paste {
    /// Source rectangle `[x0, y0, x1, y1)` the mask covers.
    rect: [u32; 4],
    /// One flag per pixel of `rect`, row by row.
    mask: Vec<bool>,
    offset: (i64, i64),
    /// A mark drawn at another scale (a data area's marks): the source point `from` goes to
    /// the output point `to`, the mark around it scaled by `scale`. `None`: a whole-pixel
    /// copy by `offset`.
    scaled: Option<Scaled>,
    /// A solid round mark, drawn as the disc it is rather than resampled (see [`Disc`]).
    disc: Option<Disc>,
    /// Painted out and never drawn ([`MaskKind::Dropped`]).
    dropped: bool,
}

/// A solid round mark of one colour, as measured in the source: drawn scaled as a disc of
/// its colour, antialiased, centred on the output pixel grid's half-pixel lattice. A dot a
/// few pixels across resampled from its own raster keeps that raster's lopsided rim (a pixel
/// wider on one side); the disc it stands for does not.
#[derive(Copy, Clone, Debug)]
struct Disc {
    centre: DVec2,
    radius: f64,
    colour: [u8; 4],
}

/// Least roundness (minor over major axis of its coverage) and share of its box a mark's
/// coverage must have to be drawn as a disc: a disc fills π/4 of its box.
const DISC_ROUNDNESS: f64 = 0.9;
const DISC_FILL: f64 = 0.7;
/// Largest output radius, in pixels, of a mark drawn as a disc: above it a resampled mark's
/// rim is smooth enough, and a bubble may be translucent or overlap others (its measured
/// disc would take their ink for its own).
const DISC_MAX_RADIUS_PX: f64 = 6.0;

impl Disc {
    /// Draws the disc where `sc` takes it, at its scale: its centre put on a pixel's centre
    /// or on a pixel corner, whichever is nearer, so that it covers the pixels alike on every
    /// side (a centre on a corner across and a pixel's centre along comes out a pixel wider
    /// than tall), each pixel covered by the share of its 4×4 samples inside.
    fn draw(&self, sc: Scaled, out: &mut Image) {
        let c = sc.to + (self.centre - sc.from) * sc.scale;
        let corner = c.round();
        let centre = (c - 0.5).round() + 0.5;
        let c = if c.distance_squared(corner) <= c.distance_squared(centre) {
            corner
        } else {
            centre
        };
        let r = self.radius * sc.scale;
        let (ow, oh) = (out.width() as i64, out.height() as i64);
        let op = out.pixels_mut();
        const N: usize = 4;
        for ty in ((c.y - r).floor() as i64).max(0)..((c.y + r).ceil() as i64 + 1).min(oh) {
            for tx in ((c.x - r).floor() as i64).max(0)..((c.x + r).ceil() as i64 + 1).min(ow) {
                let inside = (0..N * N)
                    .filter(|k| {
                        let sx = tx as f64 + ((k % N) as f64 + 0.5) / N as f64;
                        let sy = ty as f64 + ((k / N) as f64 + 0.5) / N as f64;
                        DVec2::new(sx, sy).distance_squared(c) <= r * r
                    })
                    .count();
                if inside == 0 {
                    continue;
                }
                let a = inside as f32 / (N * N) as f32;
                let o = &mut op[(ty * ow + tx) as usize];
                for (v, &m) in o.iter_mut().zip(&self.colour) {
                    *v = (*v as f32 * (1.0 - a) + m as f32 * a + 0.5) as u8;
                }
            }
        }
    }

    /// The disc a mark of colour `c` in `rect` of `src` is, if it is one: each pixel's
    /// coverage is how far its colour lies from the ground (the box border's commonest colour)
    /// towards `c`, and every pixel mostly of the mark's colour must be that colour alone.
    fn of(src: &Image, rect: [u32; 4], c: [u8; 3]) -> Option<Disc> {
        // Up to two grounds (a dot on a border between land and sea), each a tenth of the
        // box's border or more.
        let mut rings = ring_colours(src, rect);
        rings.sort_by_key(|g| std::cmp::Reverse(g.1));
        let all: u32 = rings.iter().map(|g| g.1).sum();
        let grounds: Vec<[u8; 3]> = (rings.iter().take(2))
            .filter(|g| g.1 * 10 >= all)
            .map(|g| g.0)
            .collect();
        let dist = |a: [u8; 3], b: [u8; 3]| {
            (0..3)
                .map(|k| (a[k] as f64 - b[k] as f64).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        if grounds.is_empty() || grounds.iter().any(|&g| dist(g, c) < SAME_COLOUR as f64) {
            return None;
        }
        let (mut area, mut sx, mut sy) = (0.0, 0.0, 0.0);
        let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
        let (mut full, mut sum) = (0u32, [0f64; 4]);
        let [x0, y0, x1, y1] = rect;
        for y in y0..y1 {
            for x in x0..x1 {
                let p = src.get(x, y);
                let q = [p[0], p[1], p[2]];
                // Coverage along the line from the ground to the mark's colour; a colour off
                // that line (a third ink: a line through the dot, a label) is no disc.
                let dc = dist(q, c);
                let (dg, span) = grounds
                    .iter()
                    .map(|&g| (dist(q, g), dist(g, c)))
                    .min_by(|a, b| (a.0 + dc - a.1).total_cmp(&(b.0 + dc - b.1)))?;
                if dg + dc > span + SAME_COLOUR as f64 {
                    return None;
                }
                let w = (dg / span).clamp(0.0, 1.0);
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                area += w;
                (sx, sy) = (sx + w * px, sy + w * py);
                (sxx, syy, sxy) = (sxx + w * px * px, syy + w * py * py, sxy + w * px * py);
                if dc < SAME_COLOUR as f64 / 2.0 {
                    full += 1;
                    for (k, v) in sum.iter_mut().enumerate() {
                        *v += p[k] as f64;
                    }
                }
            }
        }
        if area < 4.0 || full == 0 {
            return None;
        }
        let (mx, my) = (sx / area, sy / area);
        let (cxx, cyy, cxy) = (
            sxx / area - mx * mx,
            syy / area - my * my,
            sxy / area - mx * my,
        );
        let (tr, det) = (cxx + cyy, cxx * cyy - cxy * cxy);
        let d = (tr * tr / 4.0 - det).max(0.0).sqrt();
        let (lo, hi) = (tr / 2.0 - d, tr / 2.0 + d);
        let radius = (area / std::f64::consts::PI).sqrt();
        // The box of the disc with these moments: a disc's variance along an axis is r²/4.
        let box_area = 16.0 * hi;
        if hi <= 0.0 || (lo / hi).sqrt() < DISC_ROUNDNESS || area < DISC_FILL * box_area {
            return None;
        }
        Some(Disc {
            centre: DVec2::new(mx, my),
            radius,
            colour: sum.map(|v| (v / full as f64).round() as u8),
        })
    }
}

#[derive(Copy, Clone, Debug)]
struct Scaled {
    from: DVec2,
    to: DVec2,
    scale: f64,
}

/// The floating marks of one frame.
#[derive(Clone, Debug, Default)]
pub(crate) struct Floating {
    pastes: Vec<Paste>,
}

impl Floating {
    /// The marks of `src` in `marks`, each placed by `place(index, mark)`: its output centre,
    /// its scale and the pixels beyond its box looked at for its rim ([`RIM_PX`] for a blob, 0
    /// for a text block, whose box holds its glyphs whole) on a canvas of `target` (a mark it
    /// cannot place is left to the warp). A mark
    /// at scale 1 is copied by whole pixels, another is resampled about its centre.
    pub fn new(
        src: &Image,
        vsm: &Vsm,
        marks: &[Mark],
        target: Size,
        place: impl Fn(usize, &Mark) -> Option<(DVec2, f64, u32, MaskKind)>,
    ) -> Floating {
        let mut pastes = Vec::with_capacity(marks.len());
        for (k, m) in marks.iter().enumerate() {
            let Some(placement) = place(k, m) else {
                continue;
            };
            if let Some(p) = Paste::new(src, vsm, m, target, placement) {
                pastes.push(p);
            }
        }
        Floating { pastes }
    }

    pub fn len(&self) -> usize {
        self.pastes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pastes.is_empty()
    }

    /// How many are painted out and not drawn (tick labels thinned out).
    pub fn dropped(&self) -> usize {
        self.pastes.iter().filter(|p| p.dropped).count()
    }

    /// Fills the floating marks' pixels of `image` (the source) from their surroundings, so
    /// the warp shows the ground under them. `scratch` is a reusable buffer, all clear
    /// between calls (cleared where it was set, not over the whole frame each time).
    pub fn paint_out(
        &self,
        image: &mut Image,
        lines: Option<&crate::structure::Structure>,
        scratch: &mut Vec<bool>,
    ) {
        let w = image.width() as usize;
        if scratch.len() != image.pixels().len() {
            scratch.clear();
            scratch.resize(image.pixels().len(), false);
        }
        debug_assert!(scratch.iter().all(|&m| !m), "scratch left clear");
        let mut todo = Vec::new();
        for p in &self.pastes {
            for (y, x) in p.pixels() {
                let i = y * w + x;
                if !scratch[i] {
                    scratch[i] = true;
                    todo.push(i as u32);
                }
            }
        }
        let masked = todo.clone();
        fill_from_surroundings(image, scratch, todo);
        if let Some(st) = lines {
            // Ground first, then the lines through it (filled from lines, the ground would
            // smudge grey around them).
            for &i in &masked {
                scratch[i as usize] = true;
            }
            continue_lines(image, st, scratch);
        }
        for &i in &masked {
            scratch[i as usize] = false;
        }
    }

    /// Copies the floating marks' pixels of `src` into `out`, each shifted by its offset
    /// (clipped to `out`).
    pub fn paste(&self, src: &Image, out: &mut Image) {
        let (sw, ow, oh) = (
            src.width() as usize,
            out.width() as i64,
            out.height() as i64,
        );
        let drawn = self.pastes.iter().filter(|p| !p.dropped);
        for p in drawn.clone().filter(|p| p.scaled.is_some()) {
            p.paste_scaled(src, out);
        }
        let (sp, op) = (src.pixels(), out.pixels_mut());
        for p in drawn.filter(|p| p.scaled.is_none()) {
            for (y, x) in p.pixels() {
                let (tx, ty) = (x as i64 + p.offset.0, y as i64 + p.offset.1);
                if (0..ow).contains(&tx) && (0..oh).contains(&ty) {
                    op[ty as usize * ow as usize + tx as usize] = sp[y * sw + x];
                }
            }
        }
    }

    /// The source rectangles `[x0, y0, x1, y1]` the floating marks read.
    pub fn source_rects(&self) -> impl Iterator<Item = [f64; 4]> + '_ {
        self.pastes.iter().map(|p| p.rect.map(|v| v as f64))
    }

    /// The output rectangles `[x0, y0, x1, y1]` the floating marks are copied to.
    pub fn output_rects(&self) -> impl Iterator<Item = [f64; 4]> + '_ {
        self.pastes.iter().map(|p| match p.scaled {
            Some(_) => p.scaled_rect().map(|v| v as f64),
            None => {
                let [x0, y0, x1, y1] = p.rect.map(|v| v as i64);
                let (dx, dy) = p.offset;
                [x0 + dx, y0 + dy, x1 + dx, y1 + dy].map(|v| v as f64)
            }
        })
    }
}

impl Paste {
    /// The paste of mark `m` placed at output centre `to` and `scale`, its rim looked for
    /// `rim` pixels beyond its box, its pixels those of `kind`; `None` for a placement that
    /// is no number, or a mark with no pixel.
    fn new(
        src: &Image,
        vsm: &Vsm,
        m: &Mark,
        target: Size,
        (to, scale, rim, kind): (DVec2, f64, u32, MaskKind),
    ) -> Option<Paste> {
        let d = to - m.center;
        if !(d.x.is_finite() && d.y.is_finite() && scale > 0.0 && scale.is_finite()) {
            return None;
        }
        let [bx0, by0, bx1, by1] = m.bbox;
        let rect = [
            bx0.saturating_sub(rim),
            by0.saturating_sub(rim),
            (bx1 + rim).min(src.width()),
            (by1 + rim).min(src.height()),
        ];
        if rect[2] - rect[0] == 0 || rect[3] - rect[1] == 0 {
            return None;
        }
        let mask = grow_within_ring(&core_mask(src, vsm, rect, kind), rect, m);
        if !mask.iter().any(|&b| b) {
            return None;
        }
        let offset = (
            keep_inside(d.x, bx0, bx1, target.width),
            keep_inside(d.y, by0, by1, target.height),
        );
        let scaled = ((scale - 1.0).abs() > 1e-9).then_some(Scaled {
            from: m.center,
            to,
            scale,
        });
        let disc = match (kind, &scaled) {
            (MaskKind::Colour(c), Some(sc)) => {
                Disc::of(src, rect, c).filter(|d| d.radius * sc.scale <= DISC_MAX_RADIUS_PX)
            }
            _ => None,
        };
        Some(Paste {
            rect,
            mask,
            offset,
            scaled,
            disc,
            dropped: matches!(kind, MaskKind::Dropped),
        })
    }

    /// The output pixels `[x0, y0, x1, y1)` a scaled mark may cover.
    fn scaled_rect(&self) -> [i64; 4] {
        let Some(sc) = self.scaled else {
            return [0; 4];
        };
        let at = |v: u32, from: f64, to: f64| to + (v as f64 - from) * sc.scale;
        [
            at(self.rect[0], sc.from.x, sc.to.x).floor() as i64 - 1,
            at(self.rect[1], sc.from.y, sc.to.y).floor() as i64 - 1,
            at(self.rect[2], sc.from.x, sc.to.x).ceil() as i64 + 1,
            at(self.rect[3], sc.from.y, sc.to.y).ceil() as i64 + 1,
        ]
    }

    /// Draws the mark resampled at its scale: each output pixel averages `n × n` samples of
    /// the source (`n` enough that a shrunk mark is area-filtered), each weighed by the mask,
    /// and is blended over what the warp drew by the share of samples on the mark.
    fn paste_scaled(&self, src: &Image, out: &mut Image) {
        let Some(sc) = self.scaled else { return };
        if let Some(d) = self.disc {
            return d.draw(sc, out);
        }
        let (ow, oh) = (out.width() as i64, out.height() as i64);
        let [x0, y0, x1, y1] = self.scaled_rect();
        let n = (1.0 / sc.scale).ceil().clamp(2.0, 8.0) as usize;
        let rw = (self.rect[2] - self.rect[0]) as i64;
        let rh = (self.rect[3] - self.rect[1]) as i64;
        let (sw, sp) = (src.width() as usize, src.pixels());
        let op = out.pixels_mut();
        for ty in y0.max(0)..y1.min(oh) {
            for tx in x0.max(0)..x1.min(ow) {
                let mut sum = [0f32; 4];
                let mut hits = 0u32;
                for j in 0..n {
                    for i in 0..n {
                        let ox = tx as f64 + (i as f64 + 0.5) / n as f64;
                        let oy = ty as f64 + (j as f64 + 0.5) / n as f64;
                        let sx = sc.from.x + (ox - sc.to.x) / sc.scale;
                        let sy = sc.from.y + (oy - sc.to.y) / sc.scale;
                        let (mx, my) = (
                            sx.floor() as i64 - self.rect[0] as i64,
                            sy.floor() as i64 - self.rect[1] as i64,
                        );
                        if mx < 0 || my < 0 || mx >= rw || my >= rh {
                            continue;
                        }
                        if !self.mask[(my * rw + mx) as usize] {
                            continue;
                        }
                        let c = sp[sy.floor() as usize * sw + sx.floor() as usize];
                        for (s, &v) in sum.iter_mut().zip(&c) {
                            *s += v as f32;
                        }
                        hits += 1;
                    }
                }
                if hits == 0 {
                    continue;
                }
                let a = hits as f32 / (n * n) as f32;
                let o = &mut op[(ty * ow + tx) as usize];
                for (k, v) in o.iter_mut().enumerate() {
                    let mark = sum[k] / hits as f32;
                    *v = (*v as f32 * (1.0 - a) + mark * a + 0.5) as u8;
                }
            }
        }
    }

    /// The source pixels `(y, x)` of the mark.
    fn pixels(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let rw = (self.rect[2] - self.rect[0]) as usize;
        self.mask
            .iter()
            .enumerate()
            .filter(|(_, &b)| b)
            .map(move |(i, _)| {
                (
                    self.rect[1] as usize + i / rw,
                    self.rect[0] as usize + i % rw,
                )
            })
    }
}

/// The pixels of `rect` (row by row) that belong to a mark of `kind`, before its rim:
/// salient enough to be part of it ([`RIM_IMPORTANCE`]), and of its colour for a
/// [`MaskKind::Colour`] mark.
fn core_mask(src: &Image, vsm: &Vsm, rect: [u32; 4], kind: MaskKind) -> Vec<bool> {
    let s = vsm.scale();
    let gw = vsm.grid_size().width as usize;
    let imp = vsm.importance();
    let (rw, rh) = ((rect[2] - rect[0]) as usize, (rect[3] - rect[1]) as usize);
    (0..rw * rh)
        .map(|i| {
            let (x, y) = (rect[0] + (i % rw) as u32, rect[1] + (i / rw) as u32);
            let salient = imp[(y / s) as usize * gw + (x / s) as usize] >= RIM_IMPORTANCE;
            match kind {
                MaskKind::Colour(c) => {
                    let p = src.get(x, y);
                    salient && same_colour([p[0], p[1], p[2]], c)
                }
                MaskKind::Salient => salient,
                MaskKind::Whole | MaskKind::Dropped => true,
            }
        })
        .collect()
}

/// `core` grown by one pixel (8-connected), within mark `m`'s ring: the antialiased rim goes
/// with the mark, what lies beyond its ring (a neighbour's ink) stays.
fn grow_within_ring(core: &[bool], rect: [u32; 4], m: &Mark) -> Vec<bool> {
    let (rw, rh) = ((rect[2] - rect[0]) as usize, (rect[3] - rect[1]) as usize);
    let r2 = m.ring_radius * m.ring_radius;
    (0..rw * rh)
        .map(|i| {
            let (x, y) = (i % rw, i / rw);
            let p = DVec2::new(
                (rect[0] as usize + x) as f64 + 0.5,
                (rect[1] as usize + y) as f64 + 0.5,
            );
            if p.distance_squared(m.center) > r2 {
                return false;
            }
            let near = |dx: i64, dy: i64| {
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                nx >= 0
                    && ny >= 0
                    && (nx as usize) < rw
                    && (ny as usize) < rh
                    && core[ny as usize * rw + nx as usize]
            };
            (-1..=1).any(|dy| (-1..=1).any(|dx| near(dx, dy)))
        })
        .collect()
}

/// The whole-pixel shift of a mark spanning `[lo, hi)` on a side of the canvas `side` long,
/// for a wanted shift `d`: a mark carried to the canvas's edge is pushed back inside it whole
/// (the warp squeezes the border, a mark drawn at its own size would be clipped), unless it is
/// larger than the canvas.
fn keep_inside(d: f64, lo: u32, hi: u32, side: u32) -> i64 {
    let d = d.round() as i64;
    let (lo, hi, side) = (lo as i64, hi as i64, side as i64);
    if hi - lo > side {
        d
    } else {
        d.clamp(-lo, side - hi)
    }
}

#[cfg(test)]
mod tests {

    /// A block holding a piece of a word (ink right after its end, or right above it: a
    /// sideways word read in upright pieces) is not whole; one with clear ground around it is.
    #[test]
    fn a_piece_of_a_word_is_not_whole() {
        let blank = || Image::filled(Size::new(80, 40).unwrap(), [255; 4]);
        let ink = |img: &mut Image, x0: u32, x1: u32, y0: u32, y1: u32| {
            for y in y0..y1 {
                for x in x0..x1 {
                    img.set(x, y, [0, 0, 0, 255]);
                }
            }
        };
        let t = TextBlock {
            x0: 20,
            y0: 10,
            x1: 40,
            y1: 22,
            line_height: 12,
            sideways: false,
        };
        let mut word = blank();
        ink(&mut word, 20, 24, 10, 23);
        ink(&mut word, 30, 34, 10, 23);
        assert!(whole(&word, &t, [255; 3]));
        let mut cut = word.clone();
        ink(&mut cut, 42, 46, 12, 20);
        assert!(!whole(&cut, &t, [255; 3]), "the word goes on after its end");
        let mut stacked = word.clone();
        ink(&mut stacked, 24, 36, 24, 30);
        assert!(!whole(&stacked, &t, [255; 3]), "letters right under it");
        let mut apart = word;
        ink(&mut apart, 46, 50, 12, 20);
        assert!(whole(&apart, &t, [255; 3]), "the next word, a space away");
    }

    /// A heading whose right end falls where a panel's right-aligned labels end, below it,
    /// stays centred; the labels keep their right edge.
    #[test]
    fn a_heading_is_no_member_of_a_column_of_labels() {
        let block = |x0: u32, y0: u32, x1: u32, h: u32| TextBlock {
            x0,
            y0,
            x1,
            y1: y0 + h,
            line_height: h,
            sideways: false,
        };
        let text = [
            block(531, 13, 734, 27),
            block(703, 94, 734, 16),
            block(683, 165, 734, 15),
            block(692, 236, 735, 15),
        ];
        let src = Image::filled(Size::new(800, 300).unwrap(), [255; 4]);
        assert_eq!(anchor(&src, &text, [255; 3], 0), 0.5);
        assert_eq!(anchor(&src, &text, [255; 3], 1), 1.0);
    }

    /// The titles of a 2×2 grid of panels, centred over their panels, and the sideways axis
    /// titles beside them: each could float at another scale, and after sharing they keep
    /// one size per kind (upright titles one, sideways titles another), while an axis' tick
    /// labels, aligned by edges, still make room as a column of their own.
    #[test]
    fn the_titles_of_a_grid_of_panels_keep_one_size() {
        let upright = |x0: u32, y0: u32, x1: u32| TextBlock {
            x0,
            y0,
            x1,
            y1: y0 + 15,
            line_height: 15,
            sideways: false,
        };
        let sideways = |x0: u32, y0: u32, x1: u32, y1: u32| TextBlock {
            x0,
            y0,
            x1,
            y1,
            line_height: 15,
            sideways: true,
        };
        let text = [
            upright(287, 54, 425),        // "Income and age", centre 356
            upright(943, 55, 1026),       // "Coverage", centre 984.5 (its foot lower by a "g")
            upright(327, 420, 385),       // "Scores", centre 356
            upright(917, 419, 1052),      // "Index over time", centre 984.5
            sideways(62, 166, 80, 250),   // "Age (years)", its right edge by Count's
            sideways(66, 549, 81, 597),   // "Count", centre 573
            sideways(691, 551, 706, 595), // "Index", centre 573
            upright(410, 700, 432),       // a tick label "50" ...
            upright(399, 718, 443),       // ... centred over its axis' title "Score"
        ];
        let area_of = |_: &TextBlock| Some(0);
        let mut scale = [0.81, 0.81, 1.0, 1.0, 1.0, 0.9, 0.81, 0.7, 1.0].map(Some);
        share_scale(&text, &area_of, &mut scale, &|_| false);
        assert!(scale[..4].iter().all(|&s| s == Some(0.81)), "{scale:?}");
        assert!(scale[4..7].iter().all(|&s| s == Some(0.81)), "{scale:?}");
        // A label a line over a caption centred under it is another kind of text.
        assert_eq!(scale[8], Some(1.0));
        // Making room, the titles are not one column that moves together.
        let edges = type_groups(&text, &area_of, &[Some(1.0); 9], Alignment::Edges);
        assert_ne!(edges[0], edges[2]);
        assert!(edges[4..7].iter().enumerate().all(|(i, &g)| g == 4 + i));
    }

    use super::*;

    /// Two dots of one colour side by side, a gap of ground between them, each stand alone
    /// (their colour floats); a dot on a slanted line of its colour, or a blob whose colour
    /// runs on past its box (a region, a bar cut by the box), does not.
    #[test]
    fn a_dot_beside_another_stands_alone_a_region_does_not() {
        let mut img = Image::filled(crate::image::Size::new(60, 40).unwrap(), [255; 4]);
        let red = [214, 39, 40, 255];
        for (cx, cy) in [(20.0f64, 20.0f64), (33.0, 20.0)] {
            for y in 0..40 {
                for x in 0..60 {
                    if (x as f64 + 0.5 - cx).hypot(y as f64 + 0.5 - cy) <= 5.0 {
                        img.set(x, y, red);
                    }
                }
            }
        }
        let grown = |b: [u32; 4]| [b[0] - 3, b[1] - 3, b[2] + 3, b[3] + 3];
        // The left dot's box: its ring crosses the right dot, 3 px off.
        assert!(stands_alone(&img, grown([15, 15, 25, 25]), [214, 39, 40]));
        // A slanted line of its colour through the left dot, one pixel wide.
        let mut lined = img.clone();
        for k in 0..12 {
            lined.set(24 + k, 24 + k, red);
        }
        assert!(!stands_alone(
            &lined,
            grown([15, 15, 25, 25]),
            [214, 39, 40]
        ));
        // A bar running on past the box it was cut to.
        for y in 15..25 {
            for x in 15..50 {
                img.set(x, y, red);
            }
        }
        assert!(!stands_alone(&img, grown([15, 15, 25, 25]), [214, 39, 40]));
    }

    #[test]
    fn the_next_candidate_is_the_first_unseen_important_cell() {
        let imp: Vec<f32> = (0..53)
            .map(|i| if i % 7 == 3 { 0.9 } else { 0.1 })
            .collect();
        let mut seen = vec![false; 53];
        for i in [3, 10, 17] {
            seen[i] = true;
        }
        let walk = |r: std::ops::Range<usize>, seen: &[bool]| {
            r.clone().find(|&i| !seen[i] && imp[i] >= 0.5)
        };
        for r in [0..53, 4..53, 11..40, 24..25, 50..53, 20..20, 0..3] {
            assert_eq!(next_candidate(&seen, &imp, r.clone(), 0.5), walk(r, &seen));
        }
        seen.iter_mut().for_each(|s| *s = true);
        assert_eq!(next_candidate(&seen, &imp, 0..53, 0.5), None);
    }

    #[test]
    fn the_median_importance_is_the_middle_cells_256th() {
        let (gw, gh) = (23, 11);
        let mut v = 0x0bad_5eedu32;
        let mut imp: Vec<f32> = (0..gw * gh)
            .map(|_| {
                v ^= v << 13;
                v ^= v >> 17;
                v ^= v << 5;
                (v >> 8) as f32 / (1 << 24) as f32 * 1.2 - 0.1
            })
            .collect();
        imp[gw + 5] = f32::NAN;
        let window = [2, 1, 19, 10];
        let mut levels: Vec<u32> = (1..10)
            .flat_map(|r| (2..19).map(move |c| r * gw + c))
            .map(|i| {
                let v = imp[i];
                if v.is_nan() {
                    0
                } else {
                    (v.clamp(0.0, 1.0) * 255.0) as u32
                }
            })
            .collect();
        levels.sort_unstable();
        // The first level at or past which more than half the cells lie.
        let want = levels[levels.len() / 2];
        assert_eq!(median_importance(&imp, gw, window), want as f32 / 255.0);
        assert_eq!(median_importance(&imp, gw, [3, 3, 3, 5]), 0.0);
    }
    use crate::structure::{AreaKind, DataArea, Structure};

    const INK: [u8; 4] = [0, 0, 0, 255];

    /// A white canvas with the given text blocks inked (a glyph-like stripe each) and `bars`
    /// filled, all inside one canvas-wide area.
    fn chart(blocks: &[[u32; 4]], bars: &[[u32; 4]]) -> (Image, Structure) {
        let mut img = Image::filled(Size::new(200, 100).unwrap(), [255; 4]);
        for &[x0, y0, x1, y1] in blocks {
            for y in y0 + 2..y1 - 2 {
                for x in (x0 + 1..x1 - 1).step_by(3) {
                    img.set(x, y, INK);
                }
            }
        }
        for &[x0, y0, x1, y1] in bars {
            for y in y0..y1 {
                for x in x0..x1 {
                    img.set(x, y, [200, 30, 30, 255]);
                }
            }
        }
        let st = Structure {
            text: blocks
                .iter()
                .map(|&[x0, y0, x1, y1]| TextBlock::upright(x0, y0, x1, y1))
                .collect(),
            areas: vec![DataArea {
                x0: 1.0,
                y0: 1.0,
                x1: 199.0,
                y1: 99.0,
                kind: AreaKind::Canvas,
            }],
            ..Structure::default()
        };
        (img, st)
    }

    /// Half width: the canvas' map is x' = x / 2, y' = y.
    const HALF_WIDTH: [f64; 4] = [0.5, 0.0, 1.0, 0.0];

    /// A solid dot drawn by a raster (its rim antialiased, a little lopsided) is measured as
    /// the disc it stands for and drawn as one: scaled by 0.7 it covers the output pixels
    /// alike on all four sides. A ring, or a dot with a line of a third colour through it, is
    /// no disc.
    /// A mark carried past the canvas' edge is pushed back just inside it; one inside keeps
    /// its rounded shift, and one wider than the canvas is not pushed at all.
    #[test]
    fn keep_inside_pushes_a_mark_back_inside_the_canvas() {
        // A mark over [10, 20) on a side 100 long.
        assert_eq!(keep_inside(-14.0, 10, 20, 100), -10);
        assert_eq!(keep_inside(85.0, 10, 20, 100), 80);
        assert_eq!(keep_inside(-3.4, 10, 20, 100), -3);
        assert_eq!(keep_inside(-14.0, 10, 120, 100), -14);
    }

    /// Antialiased edges fold into the line they edge, and a crossing of two lines into
    /// one of them; a third ink that lies between none stays a colour of its own.
    #[test]
    fn blends_fold_into_their_inks() {
        let (white, red, cyan) = ([255; 3], [248, 118, 109], [0, 191, 196]);
        let pink = [251, 186, 182];
        let crossing = [140, 150, 148];
        let violet = [150, 40, 200];
        let inks = unblended(vec![
            (white, 40),
            (pink, 9),
            (red, 6),
            (cyan, 5),
            (crossing, 3),
            (violet, 2),
        ]);
        let count = |c: [u8; 3]| inks.iter().find(|k| k.0 == c).map(|k| k.1);
        assert_eq!(inks.len(), 4, "{inks:?}");
        assert_eq!(count(white), Some(40));
        assert_eq!(count(red), Some(6 + 9 + 3), "{inks:?}");
        assert_eq!(count(cyan), Some(5), "{inks:?}");
        assert_eq!(count(violet), Some(2));
        assert_eq!(count(pink), None);
    }

    #[test]
    fn a_solid_dot_is_drawn_as_a_disc() {
        let ground = [240, 240, 240, 255];
        let mut src = Image::filled(Size::new(40, 40).unwrap(), ground);
        let (cx, cy, r) = (20.3, 19.8, 5.5);
        for y in 0..40 {
            for x in 0..40 {
                let d = DVec2::new(x as f64 + 0.5 - cx, y as f64 + 0.5 - cy).length();
                let a = (r + 0.5 - d).clamp(0.0, 1.0);
                let mix = |g: u8, m: u8| (g as f64 * (1.0 - a) + m as f64 * a).round() as u8;
                src.set(x, y, [mix(240, 200), mix(240, 30), mix(240, 40), 255]);
            }
        }
        let rect = [12, 12, 29, 29];
        let disc = Disc::of(&src, rect, [200, 30, 40]).expect("a solid dot");
        assert!(disc.centre.distance(DVec2::new(cx, cy)) < 0.1, "{disc:?}");
        assert!((disc.radius - r).abs() < 0.2, "{disc:?}");
        let mut out = Image::filled(Size::new(30, 30).unwrap(), ground);
        let sc = Scaled {
            from: DVec2::new(20.0, 20.0),
            to: DVec2::new(14.3, 14.6),
            scale: 0.7,
        };
        disc.draw(sc, &mut out);
        let inked: Vec<(i64, i64)> = (0..30i64)
            .flat_map(|y| (0..30i64).map(move |x| (x, y)))
            .filter(|&(x, y)| out.get(x as u32, y as u32)[1] < 135)
            .collect();
        // The same mirrored left to right, top to bottom and across the diagonal.
        let (x0, x1) = (
            inked.iter().map(|p| p.0).min(),
            inked.iter().map(|p| p.0).max(),
        );
        let (y0, y1) = (
            inked.iter().map(|p| p.1).min(),
            inked.iter().map(|p| p.1).max(),
        );
        let [x0, x1, y0, y1] = [x0, x1, y0, y1].map(Option::unwrap);
        assert!(inked.len() >= 20, "{inked:?}");
        for &(x, y) in &inked {
            for p in [
                (x0 + x1 - x, y),
                (x, y0 + y1 - y),
                (y - y0 + x0, x - x0 + y0),
            ] {
                assert!(inked.contains(&p), "{p:?} missing: {inked:?}");
            }
        }
        // A ring is no disc.
        let mut ring = Image::filled(Size::new(40, 40).unwrap(), ground);
        for y in 0..40 {
            for x in 0..40 {
                let d = DVec2::new(x as f64 + 0.5 - 20.0, y as f64 + 0.5 - 20.0).length();
                if (4.0..6.0).contains(&d) {
                    ring.set(x, y, [200, 30, 40, 255]);
                }
            }
        }
        assert!(Disc::of(&ring, rect, [200, 30, 40]).is_none());
        // Nor a dot with a dark line through it.
        for x in 12..29 {
            src.set(x, 20, [20, 20, 20, 255]);
        }
        assert!(Disc::of(&src, rect, [200, 30, 40]).is_none());
    }

    #[test]
    fn a_label_grows_into_empty_ground_only() {
        let target = Size::new(100, 100).unwrap();
        let label = [60, 40, 100, 50];
        let (img, st) = chart(&[label], &[]);
        let free = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        assert_eq!(
            free[0].map(|p| p.scale),
            Some(1.0),
            "room around it: own size"
        );

        // A bar just left of the label: at its own size and place the label's box would
        // cover it, so it steps aside or shrinks.
        let (img, st) = chart(&[label], &[[40, 38, 56, 52]]);
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        if let Some(p) = p[0] {
            let left = p.centre.x - p.scale * 20.0;
            assert!(left >= 0.5 * 56.0 - 0.5, "covers the bar: left edge {left}");
        }
        // Hemmed in on both sides, it cannot step aside and shrinks.
        let (img, st) = chart(&[label], &[[40, 38, 48, 52], [112, 38, 120, 52]]);
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        let p = p[0].expect("room for 3/4 of its size");
        assert!(p.scale < 1.0, "{p:?}");
        let (left, right) = (p.centre.x - p.scale * 20.0, p.centre.x + p.scale * 20.0);
        assert!(
            left >= 23.5 && right <= 56.5,
            "covers a bar: {left}..{right}"
        );
    }

    /// 60 % height: the canvas' map is x' = x, y' = 0.6 y.
    const H60: [f64; 4] = [1.0, 0.0, 0.6, 0.0];

    #[test]
    fn an_axis_title_in_the_way_steps_aside() {
        let target = Size::new(200, 60).unwrap();
        // A row of tick labels and an axis title just under it: squeezed together at 60 %
        // height, at their own size they would overlap.
        let ticks = [[20, 60, 40, 72], [80, 60, 100, 72], [140, 60, 160, 72]];
        let title = [85, 74, 125, 86];
        let (img, st) = chart(&[ticks[0], ticks[1], ticks[2], title], &[]);
        let p = area_text_placements(&img, &st, &[Some(H60)], target);
        assert!(p.iter().all(|p| p.is_some_and(|p| p.scale == 1.0)), "{p:?}");
        for (k, t) in ticks.iter().enumerate() {
            let c = p[k].unwrap().centre;
            assert_eq!(
                c,
                DVec2::new((t[0] + t[2]) as f64 / 2.0, 0.6 * 66.0),
                "tick {k}"
            );
        }
        let moved = p[3].unwrap().centre;
        assert_eq!(moved.x, 105.0, "the title moves across its line only");
        assert!(moved.y - 6.0 >= 0.6 * 66.0 + 6.0 + TEXT_GAP_PX, "{moved}");
        assert!(
            moved.y - 0.6 * 80.0 <= 12.0,
            "within a line height: {moved}"
        );
    }

    #[test]
    fn a_faint_rule_is_ink_a_label_keeps_clear_of() {
        let target = Size::new(200, 60).unwrap();
        let label = [80, 40, 120, 50];
        let (mut img, st) = chart(&[label], &[]);
        for x in 0..200 {
            for y in 52..54 {
                img.set(x, y, [230, 230, 230, 255]);
            }
        }
        let p = area_text_placements(&img, &st, &[Some(H60)], target);
        let p = p[0].expect("room above");
        let bottom = p.centre.y + 5.0 * p.scale;
        assert!(
            bottom <= 0.6 * 52.0 - 1.0,
            "hides the rule: bottom {bottom}"
        );
    }

    #[test]
    fn a_row_of_tick_labels_moves_as_one_across_its_line() {
        let target = Size::new(200, 60).unwrap();
        // An axis line just over the tick labels: at their own size under the 60 % map,
        // their boxes would reach over it.
        let ticks = [[20, 60, 40, 72], [80, 60, 100, 72], [140, 60, 160, 72]];
        let (img, st) = chart(&ticks, &[[0, 56, 200, 57]]);
        let p = area_text_placements(&img, &st, &[Some(H60)], target);
        let c: Vec<DVec2> = p.iter().map(|p| p.unwrap().centre).collect();
        for (k, t) in ticks.iter().enumerate() {
            assert_eq!(p[k].unwrap().scale, 1.0);
            assert_eq!(c[k].x, (t[0] + t[2]) as f64 / 2.0, "stays under its tick");
            assert_eq!(c[k].y, c[0].y, "one row");
        }
        assert!(c[0].y - 6.0 >= 0.6 * 57.0, "clear of the axis: {}", c[0].y);
    }

    #[test]
    fn labels_of_one_width_keep_the_side_facing_their_axis() {
        let target = Size::new(100, 100).unwrap();
        // Tick labels of one width (both edges aligned), 4 px left of a y axis.
        let ticks = [[100, 10, 120, 20], [100, 40, 120, 50], [100, 70, 120, 80]];
        let (img, st) = chart(&ticks, &[[124, 0, 126, 100]]);
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        for p in &p {
            let p = p.expect("room on the left");
            assert_eq!(p.scale, 1.0);
            assert_eq!(
                p.centre.x + 10.0,
                60.0,
                "right edges stay where the map puts them"
            );
        }
    }

    #[test]
    fn a_block_of_two_inks_shelters_no_mark() {
        let disc = |img: &mut Image, cx: f64, c: [u8; 4]| {
            for y in 40..60 {
                for x in (cx - 10.0) as u32..(cx + 10.0) as u32 {
                    if DVec2::new(x as f64 + 0.5 - cx, y as f64 + 0.5 - 50.0).length() <= 8.0 {
                        img.set(x, y, c);
                    }
                }
            }
        };
        let (_, mut st) = chart(&[], &[]);
        // Dots taken for a word, as dots along an axis can be.
        st.text.push(TextBlock {
            x0: 88,
            y0: 40,
            x1: 142,
            y1: 60,
            line_height: 20,
            sideways: false,
        });
        for (second, floats) in [([31, 119, 180, 255], false), ([255, 127, 14, 255], true)] {
            let mut img = Image::filled(Size::new(200, 100).unwrap(), [255; 4]);
            disc(&mut img, 100.0, [31, 119, 180, 255]);
            disc(&mut img, 130.0, second);
            let vsm = crate::saliency::VsmBuilder::new().build(img.as_ref());
            let marks = area_marks(&img, &vsm, &st);
            assert_eq!(
                marks.len(),
                if floats { 2 } else { 0 },
                "{second:?}: {marks:?}"
            );
        }
    }

    /// A dot's pale top rim, which the scan reaches before its core, is a sliver of three
    /// cells near the core's edge colour: it has no shape to judge, so it spoils none of
    /// the dots (make_charts seed 11's scatter kept them all squeezed).
    #[test]
    fn a_dots_rim_reached_first_spoils_no_dot() {
        // A matplotlib dot's coverage, in sixteenths (r ≈ 5.4 px on pixel centres).
        const DOT: [[u8; 11]; 11] = [
            [0, 0, 0, 5, 11, 12, 11, 5, 0, 0, 0],
            [0, 2, 13, 16, 16, 16, 16, 16, 13, 2, 0],
            [0, 13, 16, 16, 16, 16, 16, 16, 16, 13, 0],
            [5, 16, 16, 16, 16, 16, 16, 16, 16, 16, 5],
            [11, 16, 16, 16, 16, 16, 16, 16, 16, 16, 11],
            [12, 16, 16, 16, 16, 16, 16, 16, 16, 16, 12],
            [11, 16, 16, 16, 16, 16, 16, 16, 16, 16, 11],
            [5, 16, 16, 16, 16, 16, 16, 16, 16, 16, 5],
            [0, 13, 16, 16, 16, 16, 16, 16, 16, 13, 0],
            [0, 2, 13, 16, 16, 16, 16, 16, 13, 2, 0],
            [0, 0, 0, 5, 11, 12, 11, 5, 0, 0, 0],
        ];
        let (w, h) = (80usize, 40usize);
        let mut img = Image::filled(Size::new(w as u32, h as u32).unwrap(), [255; 4]);
        // Importance: a colour's distance from white, as a share of the dot's own.
        let mut imp = vec![0f32; w * h];
        for left in [10usize, 40] {
            for (dy, row) in DOT.iter().enumerate() {
                for (dx, &c) in row.iter().enumerate() {
                    let a = c as f32 / 16.0;
                    let v = |k: f32| (255.0 * (1.0 - a) + k * a).round() as u8;
                    let (x, y) = (left + dx, 14 + dy);
                    img.set(x as u32, y as u32, [v(214.0), v(39.0), v(40.0), 255]);
                    imp[y * w + x] = a;
                }
            }
        }
        let canvas = crate::structure::DataArea {
            x0: 1.0,
            y0: 1.0,
            x1: w as f64 - 1.0,
            y1: h as f64 - 1.0,
            kind: crate::structure::AreaKind::Canvas,
        };
        let mut scan = MarkScan {
            src: &img,
            text: Vec::new(),
            s: 1.0,
            gw: w,
            gh: h,
            imp: &imp,
            seen: vec![false; w * h],
            stack: Vec::new(),
        };
        let mut out = Vec::new();
        scan.area(0, &canvas, &mut out);
        assert_eq!(out.len(), 2, "{out:?}");
    }

    #[test]
    fn ink_of_two_colours_is_not_a_word() {
        let target = Size::new(100, 100).unwrap();
        let blocks = [[20, 5, 90, 15], [120, 60, 150, 70]];
        let (mut img, st) = chart(&blocks, &[]);
        assert!(one_ink(&img, &st.text[1], [255; 3]));
        // A grey line through an orange dot, taken for text.
        for y in 62..68 {
            for x in (121..135).step_by(3) {
                img.set(x, y, [255, 127, 14, 255]);
            }
            for x in (136..149).step_by(3) {
                img.set(x, y, [128, 128, 128, 255]);
            }
        }
        assert!(!one_ink(&img, &st.text[1], [255; 3]));
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        assert!(p[0].is_some() && p[1].is_none(), "{p:?}");
    }

    #[test]
    fn a_label_on_a_busy_ground_follows_the_map_with_its_column() {
        let target = Size::new(100, 100).unwrap();
        // Two left-aligned labels; the lower one stands on a striped ground.
        let blocks = [[100, 10, 140, 20], [100, 50, 140, 60]];
        let (mut img, st) = chart(&blocks, &[]);
        for y in 50..60 {
            for x in (100..140).step_by(2) {
                if img.get(x, y) != INK {
                    img.set(x, y, [30, 160, 60, 255]);
                }
            }
        }
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        assert_eq!(p, vec![None, None], "neither floats: one column, one size");

        // Alone, the label on flat ground floats at its own size.
        let (img, st) = chart(&blocks[..1], &[]);
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        assert_eq!(p[0].map(|p| p.scale), Some(1.0));
    }

    #[test]
    fn on_a_whole_canvas_text_floats_all_or_none() {
        let target = Size::new(100, 100).unwrap();
        // A title, and a label elsewhere (not aligned with it) on a striped ground.
        let blocks = [[20, 5, 90, 15], [120, 60, 150, 70]];
        let (mut img, st) = chart(&blocks, &[]);
        for y in 60..70 {
            for x in (120..150).step_by(2) {
                if img.get(x, y) != INK {
                    img.set(x, y, [30, 160, 60, 255]);
                }
            }
        }
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        assert_eq!(p, vec![None, None]);
        let (img, st) = chart(&blocks, &[]);
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        assert!(p.iter().all(|p| p.is_some()), "{p:?}");
    }

    /// Where the canvas' map keeps a block at its size (a text band), the resampler draws
    /// it where it stands; floated, it could only move.
    #[test]
    fn a_block_the_map_keeps_at_its_size_does_not_float() {
        let (img, st) = chart(&[[20, 40, 60, 50], [120, 40, 160, 50]], &[]);
        let band = crate::render::CanvasMap {
            x: crate::render::AxisMap::with_bands(
                200,
                100,
                &[[20, 61]],
                &[[0, 20], [61, 110]],
                &[[0, 20]],
            ),
            y: crate::render::AxisMap::linear(100, 100),
            panels: Vec::new(),
        };
        assert_eq!(band.local(DVec2::new(40.0, 45.0))[0], 1.0);
        let areas = [Some(HALF_WIDTH)];
        let maps = AreaMaps {
            areas: &areas,
            canvas: Some(&band),
        };
        let p = area_text_placements(&img, &st, maps, Size::new(100, 100).unwrap());
        assert!(p[0].is_none(), "the block in the band floats: {:?}", p[0]);
        assert!(p[1].is_some(), "the block outside it does not float");
    }

    #[test]
    fn a_legend_keeps_one_type_size() {
        let target = Size::new(100, 100).unwrap();
        // Three left-aligned labels; a bar right of the widest leaves it less room.
        let blocks = [[100, 10, 150, 20], [100, 30, 130, 40], [100, 50, 140, 60]];
        let (img, st) = chart(&blocks, &[[176, 8, 184, 22]]);
        let p = area_text_placements(&img, &st, &[Some(HALF_WIDTH)], target);
        let scales: Vec<Option<f64>> = p.iter().map(|p| p.map(|p| p.scale)).collect();
        assert!(
            scales.iter().all(|s| *s == scales[0]),
            "one legend, scales {scales:?}"
        );
        assert!(scales[0].is_some_and(|s| s < 1.0), "scales {scales:?}");
    }
}
