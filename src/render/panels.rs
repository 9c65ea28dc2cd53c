//! The layout of a picture of panels ([`crate::structure::Panel`]): each panel gets a slot
//! and is laid out in it on its own, as a responsive page lays out its cards. Along the axis
//! a panel is cut, its parts share its map ([`AxisMap::around_plots`] over all they hold:
//! panels side by side share the scale of their plots, and the gutters and labels between
//! them keep their size); along the other axis each part lays itself out, unless a panel
//! above it was cut that way (then it follows that panel's map, and stays aligned with its
//! neighbours).

use super::canvas::{AxisMap, CanvasMap, PanelMap};
use crate::image::Size;
use crate::structure::{Card, Panel, Structure};

/// The map of a canvas taken whole: its panels' ([`laid_out`]) where gutters split its
/// plots apart and that lays anything out, else the picture's own ([`CanvasMap::new`]).
/// `squeeze`: a card's plots take the room its parts leave (else the card keeps one scale,
/// as a card without plots does: where its type cannot keep its size beside a squeezed
/// plot).
pub(crate) fn canvas_map(
    structure: Option<&Structure>,
    source: Size,
    target: Size,
    squeeze: bool,
) -> CanvasMap {
    let panels = structure.and_then(|s| s.bands.panels.as_ref());
    match panels.and_then(|p| laid_out(p, source, target, squeeze)) {
        Some(map) => map,
        None => CanvasMap::new(structure, source, target),
    }
}

/// Whether a card of `root` holds plots, which [`canvas_map`] may squeeze.
pub(crate) fn squeezes(structure: Option<&Structure>) -> bool {
    let panels = structure.and_then(|s| s.bands.panels.as_ref());
    panels.is_some_and(|p| {
        (p.leaves().iter())
            .any(|l| l.card.is_some() && !l.plots[0].is_empty() && !l.plots[1].is_empty())
    })
}

/// The map of the panels of `root` from `source` onto `target`; `None` where every panel
/// would be drawn as the linear resize draws it (nothing to lay out).
pub(crate) fn laid_out(
    root: &Panel,
    source: Size,
    target: Size,
    squeeze: bool,
) -> Option<CanvasMap> {
    // A panel that lays itself out along an axis that shrinks, whose drawn content outside
    // its plots outweighs its type (a map, a picture, a table not found as plots), would be
    // squeezed as no part of a chart is: the picture is then not laid out by panels at all
    // (judged blind, a squeezed county map, sprite field or table lost to the letterbox).
    let shrinks = [target.width < source.width, target.height < source.height];
    // Cards keep what is not a plot at one scale ([`card_maps`]): nothing of theirs is
    // squeezed.
    let cards = root.split.as_ref().is_some_and(|s| s.own);
    if !cards
        && root
            .leaves()
            .iter()
            .any(|l| (0..2).any(|k| shrinks[k] && untyped(l, k)))
    {
        return None;
    }
    let mut panels = Vec::new();
    lay(
        root,
        [0, 0, target.width, target.height],
        [None, None],
        squeeze,
        &mut panels,
    );
    let linear = CanvasMap::linear(source, target);
    let as_linear = |p: &PanelMap| {
        let ends = |m: &AxisMap, l: &AxisMap, a: u32, b: u32| {
            m.is_linear_over(a as f64, b as f64)
                && (m.apply(a as f64) - l.apply(a as f64)).abs() < 0.5
                && (m.apply(b as f64) - l.apply(b as f64)).abs() < 0.5
        };
        ends(&p.x, &linear.x, p.src[0], p.src[2]) && ends(&p.y, &linear.y, p.src[1], p.src[3])
    };
    if panels.iter().all(as_linear) || (cards && !bodies_grow(root, &panels, source, target)) {
        return None;
    }
    Some(CanvasMap { panels, ..linear })
}

/// Whether the cards' bodies (kept at one scale each, or plots squeezed, measured by the
/// square root of their area's scale) come out larger than the letterbox draws them, by [`LEAST_BODY_GROWTH`]: the largest of them, and all of them on average over
/// their area. Where the target narrows a page whose cards are as wide as their content,
/// the room a card gains is height its body cannot use (judged blind: the reflow's empty
/// halves of cards, around charts 4 to 7 % larger, lost to the letterbox at half width, and
/// won where the target's height shrank and the cards' paddings gave way).
fn bodies_grow(root: &Panel, panels: &[PanelMap], source: Size, target: Size) -> bool {
    let letterbox = (target.width as f64 / source.width as f64)
        .min(target.height as f64 / source.height as f64);
    let least = letterbox * (1.0 + LEAST_BODY_GROWTH);
    let (mut area, mut scaled, mut largest) = (0.0, 0.0, (0.0, 0.0));
    let (mut squeezed, mut stuck) = (false, false);
    for (leaf, map) in root.leaves().iter().zip(panels) {
        let Some(b) = leaf.card.as_ref().and_then(|c| c.body) else {
            continue;
        };
        let a = (b[0][1] - b[0][0]) as f64 * (b[1][1] - b[1][0]) as f64;
        // A plot squeezed along one axis grows as its area does.
        let (sx, sy) = (
            map.x.slope((b[0][0] + b[0][1]) as f64 / 2.0),
            map.y.slope((b[1][0] + b[1][1]) as f64 / 2.0),
        );
        let s = (sx * sy).sqrt();
        match map.body.is_some() {
            true => stuck |= s < least,
            false => squeezed = true,
        }
        area += a;
        scaled += a * s;
        if a > largest.0 {
            largest = (a, s);
        }
    }
    // A squeezed plot's type keeps its size: a card beside it left at the letterbox's
    // scale would set its type at half that size on one page (judged blind: a terminal's
    // dashboard at half width, its charts' labels at size over its table's and log's at
    // the letterbox's, ranked last by one judge of two).
    let one_type = !(squeezed && stuck);
    area <= 0.0 || (scaled / area >= least && largest.1 >= least && one_type)
}

/// Least growth of the cards' bodies over the letterbox for the page to be laid out as
/// cards: a body a few percent larger is hardly seen, the reflow's seams are.
const LEAST_BODY_GROWTH: f64 = 0.1;

/// Lays out `p` in `slot`, following the maps an enclosing panel cut along each axis
/// (`given`), and pushes its leaves' maps onto `out`.
fn lay(
    p: &Panel,
    slot: [u32; 4],
    given: [Option<AxisMap>; 2],
    squeeze: bool,
    out: &mut Vec<PanelMap>,
) {
    let maps: [AxisMap; 2] =
        std::array::from_fn(|k| given[k].clone().unwrap_or_else(|| own(p, slot, k)));
    let Some(split) = &p.split else {
        let ([x, y], body) = match &p.card {
            Some(card) if !squeeze || p.plots[0].is_empty() || p.plots[1].is_empty() => {
                let body = card.body.map(|b| [b[0][0], b[1][0], b[0][1], b[1][1]]);
                (card_maps(p, card, slot), body)
            }
            _ => (maps, None),
        };
        out.push(PanelMap {
            src: p.rect,
            slot,
            x,
            y,
            body,
        });
        return;
    };
    let k = match split.columns {
        true => 0,
        false => 1,
    };
    let cuts: Vec<f64> = (split.parts[1..].iter())
        .map(|c| c.rect[k] as f64)
        .collect();
    let cut_map = maps[k].snapped(&cuts);
    for c in &split.parts {
        let mut s = slot;
        s[k] = (cut_map.apply(c.rect[k] as f64).round() as u32).clamp(slot[k], slot[k + 2]);
        s[k + 2] = (cut_map.apply(c.rect[k + 2] as f64).round() as u32).clamp(s[k], slot[k + 2]);
        let mut g = given.clone();
        g[k] = Some(cut_map.clone());
        if split.own {
            g = [None, None];
        }
        lay(c, s, g, squeeze, out);
    }
}

/// The maps of card `p` (its `card`) onto `slot`, both axes at once: its body keeps one
/// scale, the largest at which it fits beside its type kept at its size (its blank runs,
/// the frame's padding and the page's gutters, giving way down to [`LEAST_BLANK_SHARE`] of
/// the slot's scale), never over its own size; where its type does not fit at its size,
/// all of it at the scale of the whole card fitted in the slot (a letterbox of the card).
/// The blank runs take what is left, so the card fills its slot and its frame its edges.
fn card_maps(p: &Panel, card: &Card, slot: [u32; 4]) -> [AxisMap; 2] {
    let body = card.body.unwrap_or([[p.rect[0]; 2], [p.rect[1]; 2]]);
    // Along each axis, local to the card: the body, the type outside it, the rest.
    let parts: [(f64, f64, f64, f64); 2] = std::array::from_fn(|k| {
        let (a, n) = (p.rect[k], (p.rect[k + 2] - p.rect[k]) as f64);
        let m = (slot[k + 2] - slot[k]) as f64;
        let b = (body[k][1] - body[k][0]) as f64;
        let typed: f64 = (p.type_spans[k].iter())
            .flat_map(|t| outside(*t, body[k]))
            .map(|t| (t[1].min(p.rect[k + 2]).saturating_sub(t[0].max(a))) as f64)
            .sum();
        (n, m, b, typed.min(n - b))
    });
    let fits = |(n, m, b, typed): (f64, f64, f64, f64)| {
        let blank = n - b - typed;
        match b > 0.0 {
            true => (m - typed - blank * LEAST_BLANK_SHARE * (m / n).min(1.0)) / b,
            false => f64::INFINITY,
        }
    };
    let letterbox = (parts[0].1 / parts[0].0).min(parts[1].1 / parts[1].0);
    let s = fits(parts[0]).min(fits(parts[1])).min(1.0);
    let (s, ts) = match s >= letterbox {
        true => (s, 1.0),
        false => (letterbox, letterbox),
    };
    std::array::from_fn(|k| {
        let (a, (n, m, _, _)) = (p.rect[k], parts[k]);
        let local = |sp: [u32; 2]| {
            [
                sp[0].clamp(a, p.rect[k + 2]) - a,
                sp[1].clamp(a, p.rect[k + 2]) - a,
            ]
        };
        let b = local(body[k]);
        let typed: Vec<[u32; 2]> = (p.type_spans[k].iter())
            .flat_map(|t| outside(*t, body[k]))
            .map(local)
            .filter(|t| t[0] < t[1])
            .collect();
        let mut spans: Vec<([u32; 2], f64, bool)> = vec![(b, s, false)];
        spans.extend(typed.iter().map(|&t| (t, ts, true)));
        let mut taken: Vec<[u32; 2]> = spans.iter().map(|x| x.0).filter(|x| x[0] < x[1]).collect();
        taken.sort_unstable();
        let blank = super::canvas::complement(n as u32, &taken);
        let blank_len: f64 = blank.iter().map(|g| (g[1] - g[0]) as f64).sum();
        let used =
            (b[1] - b[0]) as f64 * s + typed.iter().map(|t| (t[1] - t[0]) as f64).sum::<f64>() * ts;
        let room = m - used;
        // Room over: a line of the card's fill before its body and one after its content
        // take it (the body centred under its title; the frame, the title and the paddings
        // at their size, in line with the next card's); room short, or no such line:
        // every blank run gives way alike.
        let edges: Vec<[u32; 2]> = (card.stretch[k].iter().flatten())
            .filter(|&&l| l >= a && l < p.rect[k + 2])
            .map(|&l| [l - a, l - a + 1])
            .filter(|e| blank.iter().any(|g| g[0] <= e[0] && e[1] <= g[1]))
            .collect();
        // Without such a line, the blank inside the frame past the card's first content (its
        // title's start, or its body's) takes the room over: the frame stays at its slot's
        // edges, in line with its neighbours', and the ground around it and the padding
        // before its first content keep their size.
        let inner = [
            card.inner[k].max(a) - a,
            card.inner[k + 2].min(p.rect[k + 2]) - a,
        ];
        let frame = [[0, inner[0]], [inner[1], n as u32]];
        let first = (typed.iter().map(|t| t[0]))
            .chain(card.body.map(|_| b[0]))
            .min()
            .unwrap_or(0);
        let inside: Vec<[u32; 2]> = match edges.is_empty() {
            true => (blank.iter())
                .flat_map(|&g| super::canvas::complement_within(g, &frame))
                .filter(|g| g[0] >= first)
                .collect(),
            false => Vec::new(),
        };
        let over = room >= blank_len && (!edges.is_empty() || !inside.is_empty());
        let stretched: Vec<[u32; 2]> = match edges.is_empty() {
            true => inside,
            false => edges,
        };
        let blank: Vec<[u32; 2]> = match over {
            true => {
                let mut pieces: Vec<[u32; 2]> = (blank.iter())
                    .flat_map(|&g| super::canvas::complement_within(g, &stretched))
                    .collect();
                pieces.extend(stretched.iter().copied());
                pieces.sort_unstable();
                pieces
            }
            false => blank,
        };
        let scales: Vec<f64> = match over {
            true => {
                // Each stretched run takes an equal share.
                let share = (room - blank_len) / stretched.len() as f64;
                (blank.iter())
                    .map(|g| match stretched.contains(g) {
                        true => 1.0 + share / (g[1] - g[0]) as f64,
                        false => 1.0,
                    })
                    .collect()
            }
            false => {
                let g = match blank_len > 0.0 {
                    true => (room / blank_len).max(0.0),
                    false => 0.0,
                };
                vec![g; blank.len()]
            }
        };
        spans.extend(blank.iter().zip(scales).map(|(&r, g)| (r, g, false)));
        spans.retain(|x| x.0[0] < x.0[1]);
        spans.sort_by_key(|x| x.0[0]);
        let map = match blank_len > 0.0 {
            true => AxisMap::of_spans(n as u32, m as u32, &spans),
            false => AxisMap::linear(n as u32, m as u32),
        };
        map.moved([a as f64, slot[k] as f64])
    })
}

/// Least scale of a card's blank runs, as a share of its slot's (at most 1).
const LEAST_BLANK_SHARE: f64 = 0.25;

/// The parts of span `t` outside span `b`.
fn outside(t: [u32; 2], b: [u32; 2]) -> impl Iterator<Item = [u32; 2]> {
    [[t[0], t[1].min(b[0])], [t[0].max(b[1]), t[1]]]
        .into_iter()
        .filter(|s| s[0] < s[1])
}

/// Whether panel `p`'s drawn content along axis `k` outside its plots and blank runs
/// outweighs its type there.
fn untyped(p: &Panel, k: usize) -> bool {
    let (a, b) = (p.rect[k], p.rect[k + 2]);
    let covered = |spans: &[[u32; 2]]| -> u32 {
        (spans.iter())
            .map(|s| s[1].min(b).saturating_sub(s[0].max(a)))
            .sum()
    };
    let (plots, blank, typed) = (
        covered(&p.plots[k]),
        covered(&p.blank[k]),
        covered(&p.type_spans[k]),
    );
    let drawn = (b - a).saturating_sub(plots + blank + typed);
    drawn > typed && drawn as f64 >= LEAST_DRAWN_PX
}

/// Least drawn content, pixels, for a panel to be more than frames and rules.
const LEAST_DRAWN_PX: f64 = 8.0;

/// Panel `p`'s own map along axis `k` onto its `slot`: its plots take the room its parts
/// leave ([`AxisMap::around_plots`]), in picture coordinates.
fn own(p: &Panel, slot: [u32; 4], k: usize) -> AxisMap {
    let (a, n) = (p.rect[k], p.rect[k + 2] - p.rect[k]);
    let (c, m) = (slot[k], slot[k + 2] - slot[k]);
    let local = |spans: &[[u32; 2]]| -> Vec<[u32; 2]> {
        (spans.iter())
            .map(|s| [s[0].clamp(a, a + n) - a, s[1].clamp(a, a + n) - a])
            .filter(|s| s[0] < s[1])
            .collect()
    };
    let map = match m {
        0 => AxisMap::linear(n, 1),
        _ => AxisMap::around_plots(
            n,
            m,
            &local(&p.plots[k]),
            &local(&p.blank[k]),
            &local(&p.type_spans[k]),
        ),
    };
    map.moved([a as f64, c as f64])
}
