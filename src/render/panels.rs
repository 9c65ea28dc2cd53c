//! The layout of a picture of panels ([`crate::structure::Panel`]): each panel gets a slot
//! and is laid out in it on its own, as a responsive page lays out its cards. Along the axis
//! a panel is cut, its parts share its map ([`AxisMap::around_plots`] over all they hold:
//! panels side by side share the scale of their plots, and the gutters and labels between
//! them keep their size); along the other axis each part lays itself out, unless a panel
//! above it was cut that way (then it follows that panel's map, and stays aligned with its
//! neighbours).

use super::canvas::{AxisMap, CanvasMap, PanelMap};
use crate::image::Size;
use crate::structure::{Panel, Structure};

/// The map of a canvas taken whole: its panels' ([`laid_out`]) where gutters split its
/// plots apart and that lays anything out, else the picture's own ([`CanvasMap::new`]).
pub(crate) fn canvas_map(structure: Option<&Structure>, source: Size, target: Size) -> CanvasMap {
    let panels = structure.and_then(|s| s.bands.panels.as_ref());
    match panels.and_then(|p| laid_out(p, source, target)) {
        Some(map) => map,
        None => CanvasMap::new(structure, source, target),
    }
}

/// The map of the panels of `root` from `source` onto `target`; `None` where every panel
/// would be drawn as the linear resize draws it (nothing to lay out).
pub(crate) fn laid_out(root: &Panel, source: Size, target: Size) -> Option<CanvasMap> {
    // A panel that lays itself out along an axis that shrinks, whose drawn content outside
    // its plots outweighs its type (a map, a picture, a table not found as plots), would be
    // squeezed as no part of a chart is: the picture is then not laid out by panels at all
    // (judged blind, a squeezed county map, sprite field or table lost to the letterbox).
    let shrinks = [target.width < source.width, target.height < source.height];
    if root
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
    if panels.iter().all(as_linear) {
        return None;
    }
    Some(CanvasMap { panels, ..linear })
}

/// Lays out `p` in `slot`, following the maps an enclosing panel cut along each axis
/// (`given`), and pushes its leaves' maps onto `out`.
fn lay(p: &Panel, slot: [u32; 4], given: [Option<AxisMap>; 2], out: &mut Vec<PanelMap>) {
    let maps: [AxisMap; 2] =
        std::array::from_fn(|k| given[k].clone().unwrap_or_else(|| own(p, slot, k)));
    let Some(split) = &p.split else {
        let [x, y] = maps;
        out.push(PanelMap {
            src: p.rect,
            slot,
            x,
            y,
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
        lay(c, s, g, out);
    }
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
