//! Data areas: the rectangles of a chart where a position or a length is read off an axis
//! (a plot between its axes, a framed panel, a grid of evenly spaced lines or cells, bars on a
//! baseline). Inside one the warp must be a single axis-aligned affine map, or the chart lies;
//! outside (margins, gutters, titles, and pictures without axes such as maps and node-link
//! graphs) the paper's free warp stays.
//!
//! Found from the lines of [`super::lines`] only, by what makes an area in any charting tool:
//! * two long lines meeting at a corner (an x and a y axis, or two sides of a frame);
//! * at least [`MIN_GRID_LINES`] long parallel lines of one span, evenly spaced (grid lines,
//!   the white separators of a heat map's cells);
//! * at least [`MIN_BARS`] edges rising from one long line (bars sharing a baseline).
//!
//! A line is long when it spans [`MIN_SHARE`] of the picture along it: an axis spans most of
//! its panel, and a picture rarely holds panels narrower than that; the sides of marks, bars
//! and letters are shorter.

use super::Line;

/// Least share of the picture's side a line spans to bound a data area.
const MIN_SHARE: f64 = 0.1;
/// Least length of such a line in pixels, on small pictures.
const MIN_PX: f64 = 32.0;
/// How far apart two line ends may be and still meet at a corner, pixels: ticks and the
/// thickness of the lines themselves leave a few pixels between them.
const CORNER_PX: f64 = 4.0;
/// Longest tick, pixels, by which an axis line may run past the other axis at their corner:
/// matplotlib's 3.5 pt at 200 dpi is 10 px, ggplot2's 2.75 pt at 2× about 8.
const TICK_PX: f64 = 12.0;
/// Least number of evenly spaced lines that make a grid.
const MIN_GRID_LINES: usize = 4;
/// Most deviation of a grid's spacing from its median, as a share of it.
const GRID_EVEN: f64 = 0.15;
/// Least number of edges standing on one baseline that make a bar chart.
const MIN_BARS: usize = 3;
/// Areas overlapping by this share of the smaller one are one area.
const SAME_AREA: f64 = 0.6;

/// What an area was found by.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum AreaKind {
    /// Two long lines meeting at a corner: axes or a frame.
    Axes,
    /// Evenly spaced parallel lines: a grid, a heat map's cells.
    Grid,
    /// Bars standing on one baseline.
    Bars,
    /// The whole canvas, by request (`--regions affine`).
    Canvas,
}

/// A data area: the rectangle `[x0, x1] × [y0, y1]` (image pixels) that one affine map
/// carries.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct DataArea {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
    pub kind: AreaKind,
}

impl DataArea {
    /// Whether `(x, y)` lies in the area, `tol` pixels around it counted in.
    pub fn contains(&self, x: f64, y: f64, tol: f64) -> bool {
        x >= self.x0 - tol && x <= self.x1 + tol && y >= self.y0 - tol && y <= self.y1 + tol
    }

    fn area(&self) -> f64 {
        (self.x1 - self.x0).max(0.0) * (self.y1 - self.y0).max(0.0)
    }

    fn overlap(&self, o: &DataArea) -> f64 {
        let w = self.x1.min(o.x1) - self.x0.max(o.x0);
        let h = self.y1.min(o.y1) - self.y0.max(o.y0);
        w.max(0.0) * h.max(0.0)
    }
}

/// The data areas bounded by `horizontal` and `vertical` lines on a `w × h` picture.
pub(crate) fn detect(horizontal: &[Line], vertical: &[Line], w: f64, h: f64) -> Vec<DataArea> {
    detect_in(horizontal, vertical, [0.0, 0.0, w, h], false)
}

/// The data areas bounded by the lines lying in `rect` (`[x0, y0, x1, y1]`), long as a share
/// of its sides: the plots of a card, whose frame the whole picture's areas take for theirs
/// (a frame's corners make an area, and the plot inside it is one with it).
pub(crate) fn within(horizontal: &[Line], vertical: &[Line], rect: [f64; 4]) -> Vec<DataArea> {
    let inside = |l: &Line, pos: (f64, f64), along: (f64, f64)| {
        l.pos >= pos.0
            && l.pos <= pos.1
            && l.from >= along.0 - CORNER_PX
            && l.to <= along.1 + CORNER_PX
    };
    let (xs, ys) = ((rect[0], rect[2]), (rect[1], rect[3]));
    let hs: Vec<Line> = (horizontal.iter().copied())
        .filter(|l| inside(l, ys, xs))
        .collect();
    let vs: Vec<Line> = (vertical.iter().copied())
        .filter(|l| inside(l, xs, ys))
        .collect();
    detect_in(
        &joined(&hs, f64::INFINITY),
        &joined(&vs, f64::INFINITY),
        rect,
        true,
    )
}

/// The data areas of the lines in `rect`; `ragged`: a grid's lines need share one end only
/// (see [`grids`]).
fn detect_in(
    horizontal: &[Line],
    vertical: &[Line],
    rect: [f64; 4],
    ragged: bool,
) -> Vec<DataArea> {
    let (w, h) = (rect[2] - rect[0], rect[3] - rect[1]);
    let long = |l: &&Line, side: f64| l.to - l.from >= (MIN_SHARE * side).max(MIN_PX);
    let gap = 2.0 * CORNER_PX;
    let (horizontal, vertical) = (joined(horizontal, gap), joined(vertical, gap));
    let (horizontal, vertical) = (
        bridged(&horizontal, &vertical),
        bridged(&vertical, &horizontal),
    );
    let hs: Vec<&Line> = horizontal.iter().filter(|l| long(l, w)).collect();
    let vs: Vec<&Line> = vertical.iter().filter(|l| long(l, h)).collect();
    let mut found = Vec::new();
    corners(&hs, &vs, &mut found);
    grids(&hs, true, ragged, &mut found);
    grids(&vs, false, ragged, &mut found);
    bars(&hs, &vertical, &mut found);
    let min_side = MIN_PX;
    found.retain(|a: &DataArea| a.x1 - a.x0 >= min_side && a.y1 - a.y0 >= min_side);
    // Clear of the canvas border, which the boundary conditions hold.
    for a in &mut found {
        a.x0 = a.x0.max(rect[0] + 1.0);
        a.y0 = a.y0.max(rect[1] + 1.0);
        a.x1 = a.x1.min(rect[2] - 1.0);
        a.y1 = a.y1.min(rect[3] - 1.0);
    }
    merge(found)
}

/// Collinear pieces with gaps up to `gap` as one line: a heat map's separators, broken where
/// they cross (both sides of a crossing are the separator's colour, so nothing steps there);
/// in a card, whatever the gap, a grid line broken where a series crosses it.
fn joined(lines: &[Line], gap: f64) -> Vec<Line> {
    let mut sorted = lines.to_vec();
    sorted.sort_by(|a, b| a.pos.total_cmp(&b.pos).then(a.from.total_cmp(&b.from)));
    let mut out: Vec<Line> = Vec::with_capacity(sorted.len());
    for l in sorted {
        match out.last_mut() {
            Some(o) if (o.pos - l.pos).abs() < 0.75 && l.from - o.to <= gap => {
                o.to = o.to.max(l.to);
                o.width = o.width.max(l.width);
            }
            _ => out.push(l),
        }
    }
    out
}

/// `lines` with collinear pieces up to [`BRIDGE_PX`] apart joined where no long line of
/// `across` crosses between them or ends either piece there: an axis is read in pieces where a filled area meets it (a
/// density's tail standing on it changes its thickness there), and the plot it bounds must
/// not end at the break. Facets side by side have their frames' sides between their axes.
fn bridged(lines: &[Line], across: &[Line]) -> Vec<Line> {
    let long: Vec<&Line> = (across.iter())
        .filter(|l| l.to - l.from >= MIN_PX)
        .collect();
    let mut sorted = lines.to_vec();
    sorted.sort_by(|a, b| a.from.total_cmp(&b.from));
    let mut out: Vec<Line> = Vec::with_capacity(sorted.len());
    'next: for l in sorted {
        for o in out.iter_mut() {
            let gap = [o.to, l.from];
            let crossed = || {
                (long.iter()).any(|c| {
                    c.pos >= gap[0] - CORNER_PX
                        && c.pos <= gap[1] + CORNER_PX
                        && c.from <= o.pos + CORNER_PX
                        && c.to >= o.pos - CORNER_PX
                })
            };
            if (o.pos - l.pos).abs() < 0.75
                && l.from >= o.from
                && l.from - o.to <= BRIDGE_PX
                && !crossed()
            {
                o.to = o.to.max(l.to);
                o.width = o.width.max(l.width);
                continue 'next;
            }
        }
        out.push(l);
    }
    out
}

/// Widest break bridged in a line ([`bridged`]), pixels: where a fill's outline meets an
/// axis, its stroke and antialiasing, up to 16 px at 2×.
const BRIDGE_PX: f64 = 16.0;

/// Rectangles from a horizontal and a vertical line meeting at one end of each.
fn corners(hs: &[&Line], vs: &[&Line], out: &mut Vec<DataArea>) {
    for hl in hs {
        for vl in vs {
            let tol = CORNER_PX + (hl.width.max(vl.width) as f64);
            // A line's end at the other line, or past it by a tick at most (the tick at an
            // axis' first value is drawn in line with the other axis, and joins it).
            let ends_at = |end: f64, at: f64, outward: f64| {
                let past = (end - at) * outward;
                past >= -tol && past <= tol + TICK_PX
            };
            // The vertical line's end at the horizontal line, and the horizontal line's end at
            // the vertical line: the far ends give the rectangle's other sides.
            let y_far = if ends_at(vl.to, hl.pos, 1.0) {
                vl.from
            } else if ends_at(vl.from, hl.pos, -1.0) {
                vl.to
            } else {
                continue;
            };
            let x_far = if ends_at(hl.from, vl.pos, -1.0) {
                hl.to
            } else if ends_at(hl.to, vl.pos, 1.0) {
                hl.from
            } else {
                continue;
            };
            out.push(DataArea {
                x0: vl.pos.min(x_far),
                x1: vl.pos.max(x_far),
                y0: hl.pos.min(y_far),
                y1: hl.pos.max(y_far),
                kind: AreaKind::Axes,
            });
        }
    }
}

/// Rectangles spanned by evenly spaced parallel lines of one span; `ragged`: of one start
/// or one end, the rectangle spanning the longest (a grid a series covers in part).
fn grids(lines: &[&Line], horizontal: bool, ragged: bool, out: &mut Vec<DataArea>) {
    let mut sorted: Vec<&Line> = lines.to_vec();
    sorted.sort_by(|a, b| a.pos.total_cmp(&b.pos));
    let mut used = vec![false; sorted.len()];
    for i in 0..sorted.len() {
        if used[i] {
            continue;
        }
        let l = sorted[i];
        let tol = CORNER_PX.max(0.03 * (l.to - l.from));
        let same: Vec<usize> = (i..sorted.len())
            .filter(|&j| {
                let (from, to) = (
                    (sorted[j].from - l.from).abs() <= tol,
                    (sorted[j].to - l.to).abs() <= tol,
                );
                !used[j] && ((from && to) || ragged && (from || to))
            })
            .collect();
        // Positions a pixel or two apart are the two edges of one separator.
        let mut pos: Vec<f64> = Vec::new();
        for &j in &same {
            if pos.last().is_none_or(|&p| sorted[j].pos - p > 3.0) {
                pos.push(sorted[j].pos);
            }
        }
        if pos.len() < MIN_GRID_LINES {
            continue;
        }
        let mut gaps: Vec<f64> = pos.windows(2).map(|p| p[1] - p[0]).collect();
        gaps.sort_by(|a, b| a.total_cmp(b));
        let median = gaps[gaps.len() / 2];
        if median < 4.0
            || gaps
                .iter()
                .any(|g| (g - median).abs() > GRID_EVEN * median + 1.5)
        {
            continue;
        }
        for &j in &same {
            used[j] = true;
        }
        let (a0, a1) = (pos[0], pos[pos.len() - 1]);
        let (b0, b1) = (same.iter())
            .map(|&j| (sorted[j].from, sorted[j].to))
            .fold((l.from, l.to), |(a, b), (f, t)| (a.min(f), b.max(t)));
        out.push(if horizontal {
            DataArea {
                x0: b0,
                x1: b1,
                y0: a0,
                y1: a1,
                kind: AreaKind::Grid,
            }
        } else {
            DataArea {
                x0: a0,
                x1: a1,
                y0: b0,
                y1: b1,
                kind: AreaKind::Grid,
            }
        });
    }
}

/// Rectangles of bars standing on (or hanging from) a long horizontal line: the line's span,
/// up to the far end of the tallest bar.
fn bars(hs: &[&Line], vertical: &[Line], out: &mut Vec<DataArea>) {
    for base in hs {
        let tol = CORNER_PX + base.width as f64;
        let on = |v: &&Line| v.pos >= base.from - tol && v.pos <= base.to + tol;
        let up: Vec<&Line> = vertical
            .iter()
            .filter(|v| on(v) && (v.to - base.pos).abs() <= tol && v.from < base.pos - tol)
            .collect();
        let down: Vec<&Line> = vertical
            .iter()
            .filter(|v| on(v) && (v.from - base.pos).abs() <= tol && v.to > base.pos + tol)
            .collect();
        for (standing, up) in [(up, true), (down, false)] {
            if standing.len() < 2 * MIN_BARS {
                // Each bar shows two sides.
                continue;
            }
            let far = if up {
                standing.iter().map(|v| v.from).fold(f64::MAX, f64::min)
            } else {
                standing.iter().map(|v| v.to).fold(f64::MIN, f64::max)
            };
            out.push(DataArea {
                x0: base.from,
                x1: base.to,
                y0: base.pos.min(far),
                y1: base.pos.max(far),
                kind: AreaKind::Bars,
            });
        }
    }
}

/// Areas that overlap much become their union; areas inside another are part of it.
fn merge(mut areas: Vec<DataArea>) -> Vec<DataArea> {
    loop {
        let mut merged = false;
        'outer: for i in 0..areas.len() {
            for j in i + 1..areas.len() {
                let (a, b) = (areas[i], areas[j]);
                let small = a.area().min(b.area());
                if small > 0.0 && a.overlap(&b) >= SAME_AREA * small {
                    areas[i] = DataArea {
                        x0: a.x0.min(b.x0),
                        y0: a.y0.min(b.y0),
                        x1: a.x1.max(b.x1),
                        y1: a.y1.max(b.y1),
                        kind: if a.area() >= b.area() { a.kind } else { b.kind },
                    };
                    areas.swap_remove(j);
                    merged = true;
                    break 'outer;
                }
            }
        }
        if !merged {
            break;
        }
    }
    areas.sort_by(|a, b| a.y0.total_cmp(&b.y0).then(a.x0.total_cmp(&b.x0)));
    areas
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(pos: f64, from: f64, to: f64) -> Line {
        Line {
            pos,
            from,
            to,
            width: 1,
        }
    }

    /// A card's frame holding a plot: the picture's areas take the frame for the plot (the
    /// grid inside is one with it), the card's own find the grid, though a series hides
    /// part of one of its lines (pieces) and the end of another (ragged).
    #[test]
    fn a_plot_inside_a_frame_is_found_within_it() {
        let frame_h = [line(20.0, 10.0, 410.0), line(300.0, 10.0, 410.0)];
        let frame_v = [line(10.0, 20.0, 300.0), line(410.0, 20.0, 300.0)];
        let mut hs = frame_h.to_vec();
        for (i, y) in [80.0, 120.0, 160.0, 200.0, 240.0].into_iter().enumerate() {
            match i {
                1 => hs.extend([line(y, 60.0, 200.0), line(y, 260.0, 380.0)]),
                3 => hs.push(line(y, 60.0, 300.0)),
                _ => hs.push(line(y, 60.0, 380.0)),
            }
        }
        let whole = detect(&hs, &frame_v, 640.0, 340.0);
        assert_eq!(whole.len(), 1, "{whole:?}");
        assert_eq!(whole[0].kind, AreaKind::Axes);
        let inside = within(&hs, &frame_v, [11.0, 21.0, 409.0, 299.0]);
        assert_eq!(inside.len(), 1, "{inside:?}");
        let a = inside[0];
        assert_eq!(a.kind, AreaKind::Grid);
        assert_eq!([a.x0, a.y0, a.x1, a.y1], [60.0, 80.0, 380.0, 240.0]);
    }

    #[test]
    fn two_axes_meeting_make_an_area() {
        // y axis at x = 50 from y = 20 to 300, x axis at y = 300 from x = 50 to 600.
        let a = detect(
            &[line(300.0, 50.0, 600.0)],
            &[line(50.0, 20.0, 300.0)],
            640.0,
            340.0,
        );
        assert_eq!(a.len(), 1);
        assert_eq!(
            (a[0].x0, a[0].y0, a[0].x1, a[0].y1),
            (50.0, 20.0, 600.0, 300.0)
        );
        assert_eq!(a[0].kind, AreaKind::Axes);
    }

    /// The tick at the y axis' first value, drawn in line with the x axis, joins it: the x
    /// axis then runs past the corner by the tick's length, and still makes one.
    #[test]
    fn axes_meet_where_a_tick_runs_past_the_corner() {
        let a = detect(
            &[line(300.0, 41.0, 600.0)],
            &[line(50.0, 20.0, 300.0)],
            640.0,
            340.0,
        );
        assert_eq!(a.len(), 1, "{a:?}");
        assert_eq!((a[0].x0, a[0].x1), (50.0, 600.0));
        // Past it by more than a tick: a line crossing the axis, no corner.
        let b = detect(
            &[line(300.0, 20.0, 600.0)],
            &[line(50.0, 20.0, 300.0)],
            640.0,
            340.0,
        );
        assert!(b.is_empty(), "{b:?}");
    }

    /// An x axis read in two pieces where a filled area meets it (a density's tail), 14 px
    /// apart and half a pixel off, bounds one plot to its far end; two facets' axes as far
    /// apart, each ended by its frame's side, stay two.
    #[test]
    fn an_axis_broken_where_a_fill_meets_it_bounds_one_plot() {
        let mut far = line(300.5, 314.0, 600.0);
        far.width = 3;
        let a = detect(
            &[line(300.0, 50.0, 300.0), far],
            &[line(50.0, 20.0, 300.0)],
            640.0,
            340.0,
        );
        assert_eq!(a.len(), 1, "{a:?}");
        assert_eq!((a[0].x0, a[0].x1), (50.0, 600.0));
        let facets = detect(
            &[line(300.0, 50.0, 300.0), line(300.0, 314.0, 600.0)],
            &[
                line(50.0, 20.0, 300.0),
                line(300.0, 20.0, 300.0),
                line(314.0, 20.0, 300.0),
            ],
            640.0,
            340.0,
        );
        assert!(
            facets.iter().all(|a| a.x1 <= 300.0 || a.x0 >= 314.0),
            "{facets:?}"
        );
    }

    #[test]
    fn a_frame_is_one_area() {
        let hs = [line(20.0, 50.0, 600.0), line(300.0, 50.0, 600.0)];
        let vs = [line(50.0, 20.0, 300.0), line(600.0, 20.0, 300.0)];
        let a = detect(&hs, &vs, 640.0, 340.0);
        assert_eq!(a.len(), 1);
    }

    #[test]
    fn lines_apart_make_no_area() {
        // A long horizontal and a long vertical line that do not meet (a map's border pieces).
        let a = detect(
            &[line(300.0, 200.0, 600.0)],
            &[line(50.0, 20.0, 200.0)],
            640.0,
            340.0,
        );
        assert!(a.is_empty(), "{a:?}");
    }

    #[test]
    fn evenly_spaced_lines_make_a_grid() {
        let hs: Vec<Line> = (0..6)
            .map(|i| line(40.0 + 50.0 * i as f64, 100.0, 500.0))
            .collect();
        let a = detect(&hs, &[], 640.0, 400.0);
        assert_eq!(a.len(), 1);
        assert_eq!(a[0].kind, AreaKind::Grid);
        assert_eq!((a[0].y0, a[0].y1), (40.0, 290.0));
        // Uneven spacing is no grid.
        let uneven: Vec<Line> = [40.0, 60.0, 150.0, 170.0, 300.0]
            .iter()
            .map(|&p| line(p, 100.0, 500.0))
            .collect();
        assert!(detect(&uneven, &[], 640.0, 400.0).is_empty());
    }

    #[test]
    fn bars_on_a_baseline_make_an_area() {
        let base = [line(300.0, 40.0, 600.0)];
        let sides: Vec<Line> = (0..4)
            .flat_map(|i| {
                let x = 80.0 + 120.0 * i as f64;
                let top = 100.0 + 30.0 * i as f64;
                [line(x, top, 300.0), line(x + 60.0, top, 300.0)]
            })
            .collect();
        let a = detect(&base, &sides, 640.0, 340.0);
        assert_eq!(a.len(), 1);
        assert_eq!(a[0].kind, AreaKind::Bars);
        assert_eq!((a[0].y0, a[0].y1), (100.0, 300.0));
    }
}
