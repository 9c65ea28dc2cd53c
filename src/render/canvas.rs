//! The map of a canvas taken whole ([`crate::structure::Regions::Affine`]): linear along each
//! axis, but for its text bands ([`crate::structure::Bands`]), which keep their size while the
//! rest shrinks by one scale. A chart drawn anew at a smaller size does the same: its
//! labels keep their type, its plot gives way, and inside the plot every position and length
//! stays proportional (one segment of one linear map).

use glam::DVec2;

use crate::image::Size;
use crate::structure::Structure;

/// Least scale of a gap, as a share of the linear resize's scale: a margin keeps a quarter
/// of what a linear resize leaves it, so that panels and labels stay apart.
const LEAST_GAP_SHARE: f64 = 0.25;

/// Least growth of a plot over the linear resize's scale for its margins to give way to
/// it: a tenth. A plot a few percent larger is hardly seen, while its margins pressed to the
/// canvas' edge are (judged blind, such copies lost to a linear resize; at a tenth or more
/// the larger plot won).
const LEAST_GROWTH: f64 = 0.1;

/// Least width (height) of the parts around the plots, in pixels, for them to be kept at
/// their size: about the height of the smallest type read on a screen; less is a frame's or
/// an axis' lines, which hold no type.
const LEAST_PARTS_PX: f64 = 8.0;

/// Least scale of a plot, as a share of the linear resize's, when the parts around it keep
/// their size ([`AxisMap::around_plots`]): half. Below it the data would be drawn smaller
/// than the type that labels it gains; from there the type shrinks with the plot.
const LEAST_PLOT_SHARE: f64 = 0.5;

/// A monotone piecewise-linear map of one axis, source `[0, n]` onto output `[0, m]`.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisMap {
    /// `(source, output)`, both increasing; the first is `(0, 0)`, the last `(n, m)`.
    knots: Vec<[f64; 2]>,
}

impl AxisMap {
    /// `x' = x · m / n`.
    pub fn linear(n: u32, m: u32) -> AxisMap {
        AxisMap {
            knots: vec![[0.0, 0.0], [n as f64, m as f64]],
        }
    }

    /// `n` source pixels onto `m`: the half-open text `bands` at their size (or as near as
    /// the `gaps` can make room for, down to a quarter of their linear size); then, with what
    /// the margins at the canvas' edge can still give, everything else (the plot) at one
    /// scale above the linear resize's, up to the source's own: blank margins give way to
    /// what is read before it shrinks, while the space between a band and the plot (a
    /// title's, an axis' labels') keeps its share and the text stays clear of the plot.
    /// Linear when the axis does not shrink or nothing can give way. Inside the plot every
    /// position and length stays proportional (one scale). A band starts on a whole output
    /// pixel (copied, not resampled between pixels) and every other stretch keeps the phase
    /// a resize at its scale would give it (its thin lines fall on pixels as they would
    /// there).
    ///
    /// `margins` are the gaps at the canvas' edge that may give way to the plot (blank
    /// page); the plot grows only where it grows visibly, by a tenth or more.
    pub fn with_bands(
        n: u32,
        m: u32,
        bands: &[[u32; 2]],
        gaps: &[[u32; 2]],
        margins: &[[u32; 2]],
    ) -> AxisMap {
        AxisMap::with_bands_at_most(n, m, [bands, gaps, margins], 1.0).0
    }

    /// The scales [`AxisMap::with_bands`] gives: `None` when the map is linear.
    fn scales(n: u32, m: u32, [bands, gaps, margins]: Spans) -> Option<Scales> {
        let (nf, mf) = (n as f64, m as f64);
        let (kept, give) = (spanned(bands), spanned(gaps));
        if m >= n || give <= 0.0 || kept + give > nf {
            return None;
        }
        let linear = mf / nf;
        let (least_gap, plot) = (LEAST_GAP_SHARE * linear, nf - kept - give);
        // The bands first, with the plot at the linear scale: every gap gives alike.
        let room = linear * (kept + give) - least_gap * give;
        let band = match kept > 0.0 {
            true => (room / kept).clamp(linear, 1.0),
            false => linear,
        };
        let gap = (linear * (kept + give) - band * kept) / give;
        // Then the plot, with what the margins have left above their least share.
        let edge = spanned(&edge_gaps(gaps, margins).collect::<Vec<_>>());
        let spare = (gap - least_gap).max(0.0) * edge;
        let scale = match plot > 0.0 {
            true => (linear + spare / plot).min(1.0),
            false => linear,
        };
        let grows = |s: f64| s > linear * (1.0 + 1e-6);
        (grows(band) || grows(scale)).then_some(Scales { band, gap, scale })
    }

    /// [`AxisMap::with_bands`] with the plot's scale at most `most` (and at least the linear
    /// resize's): the margins keep what the plot does not take. Also the plot's scale.
    fn with_bands_at_most(n: u32, m: u32, spans: Spans, most: f64) -> (AxisMap, f64) {
        let linear = m as f64 / n as f64;
        let Some(Scales {
            band, gap, scale, ..
        }) = AxisMap::scales(n, m, spans)
        else {
            return (AxisMap::linear(n, m), linear);
        };
        let scale = scale.min(most).max(linear);
        // A plot a few percent larger is hardly seen; its margins pressed to the edge are.
        let scale = if scale >= linear * (1.0 + LEAST_GROWTH) {
            scale
        } else {
            linear
        };
        if band <= linear * (1.0 + 1e-6) && scale <= linear * (1.0 + 1e-6) {
            return (AxisMap::linear(n, m), linear);
        }
        (AxisMap::with_scales(n, m, spans, [band, gap, scale]), scale)
    }

    /// `n` source pixels onto `m` with the plot narrowed to `scale`, below the linear
    /// resize's, the bands and the gaps beside them as [`AxisMap::with_bands`] has them: the
    /// blank margins at the canvas' edge take the rest (more than they had, as the plot
    /// takes less). `None` without margins.
    fn narrowed(n: u32, m: u32, spans: Spans, scale: f64) -> Option<AxisMap> {
        let [_, gaps, margins] = spans;
        let linear = m as f64 / n as f64;
        let [band, gap] =
            AxisMap::scales(n, m, spans).map_or([linear, linear], |s| [s.band, s.gap]);
        let edge = spanned(&edge_gaps(gaps, margins).collect::<Vec<_>>());
        (edge > 0.0 && scale < linear)
            .then(|| AxisMap::with_scales(n, m, spans, [band, gap, scale]))
    }

    /// The map with the bands at scale `band`, the gaps beside them at `gap`, the plot at
    /// `scale` and the margins taking what is left of `m` (beyond the plot's scale, in equal
    /// shares at the two ends).
    pub(crate) fn with_scales(
        n: u32,
        m: u32,
        spans: Spans,
        [band, gap, scale]: [f64; 3],
    ) -> AxisMap {
        let [bands, gaps, margins] = spans;
        let (nf, mf) = (n as f64, m as f64);
        let linear = mf / nf;
        let plot = nf - spanned(bands) - spanned(gaps);
        // The margins take what is left; the gaps beside bands keep `gap`.
        let kept = spanned(bands);
        let edges: Vec<[u32; 2]> = edge_gaps(gaps, margins).collect();
        let (edge, inner) = (spanned(&edges), spanned(gaps) - spanned(&edges));
        let room = mf - band * kept - gap * inner - scale * plot;
        let margin = match edge > 0.0 {
            true => room / edge,
            false => gap,
        };
        // Room the margins take beyond the plot's scale is split evenly between the two
        // ends, as a letterbox centres its picture: shared by their widths, a picture whose
        // content sits off its middle came out further off (judged blind, a graph with
        // bands of 471 and 135 px lost to the letterbox).
        let ends = match edges[..] {
            [a, b] if a[0] == 0 && b[1] == n && margin > scale => {
                let extra = (room - scale * edge) / 2.0;
                let width = |g: [u32; 2]| (g[1] - g[0]) as f64;
                Some([(a, scale + extra / width(a)), (b, scale + extra / width(b))])
            }
            _ => None,
        };
        let gap_scale = |g: &[u32; 2]| match ends {
            Some(e) => e.iter().find(|(s, _)| s == g).map_or(gap, |&(_, k)| k),
            None if edges.contains(g) => margin,
            None => gap,
        };
        let mut spans: Vec<([u32; 2], f64, bool)> = (bands.iter().map(|&b| (b, band, true)))
            .chain(gaps.iter().map(|g| (*g, gap_scale(g), false)))
            .collect();
        spans.sort_by_key(|s| s.0[0]);
        let knots = |snap: bool| {
            // Where a stretch of the plot starts: snapped, a whole number of pixels from
            // where a resize at the plot's scale puts it.
            let in_phase = |pos: f64, out: f64| match snap {
                true => pos * scale + (out - pos * scale).round(),
                false => out,
            };
            let mut knots = vec![[0.0, 0.0]];
            let (mut pos, mut out) = (0.0, 0.0);
            let push = |knots: &mut Vec<[f64; 2]>, x: f64, o: f64| {
                if x > knots.last().map_or(-1.0, |k: &[f64; 2]| k[0]) {
                    knots.push([x, o]);
                }
            };
            for &([a, e], span_scale, is_band) in &spans {
                let (a, e) = (a as f64, e as f64);
                if a > pos {
                    // The stretch before, of the plot, in its phase.
                    out = in_phase(pos, out);
                    push(&mut knots, pos, out);
                    out += (a - pos) * scale;
                }
                if snap && is_band {
                    out = out.round();
                }
                push(&mut knots, a, out);
                out += (e - a) * span_scale;
                pos = e;
            }
            if nf > pos {
                out = in_phase(pos, out);
                push(&mut knots, pos, out);
            }
            if knots.last().is_some_and(|k| k[0] >= nf) {
                knots.pop();
            }
            knots.push([nf, mf]);
            AxisMap { knots }
        };
        // Snapped, unless a stretch would be squeezed to under half its scale.
        let snapped = knots(true);
        if snapped.least_slope() >= 0.5 * LEAST_GAP_SHARE * linear {
            return snapped;
        }
        knots(false)
    }

    /// `n` source pixels onto `m` as the chart's author would lay them out again: the
    /// `plots` (the spans its data areas cover) take the room the parts around them leave.
    /// Everything outside the plots (tick labels, axis titles, legends, the gutters between
    /// panels) keeps its size, the blank `margins` (clean runs without text: the page's
    /// margins, the space between a plot and its labels) give way first, down to
    /// [`LEAST_GAP_SHARE`] of the linear resize's scale, and every plot takes one scale, so
    /// that plots side by side share it and every position and length inside them stays
    /// proportional. Where that would leave a plot under [`LEAST_PLOT_SHARE`] of the linear
    /// resize's scale, the parts around the plots shrink together. Linear when the axis does
    /// not shrink, when no plot is given, or when the parts would shrink below the linear
    /// resize's scale (the layout would only lose to it).
    ///
    /// Each stretch kept at its size starts on a whole output pixel: its pixels are copied,
    /// not resampled between two.
    ///
    /// `type_spans` are where text stands: drawn content outside the plots that holds no
    /// type (a panel not found as a data area, a picture) and outweighs the type beside it
    /// means the picture is not a chart laid out around its plots, and the map is linear
    /// (kept at its size, such a panel would take the plots' room).
    pub fn around_plots(
        n: u32,
        m: u32,
        plots: &[[u32; 2]],
        margins: &[[u32; 2]],
        type_spans: &[[u32; 2]],
    ) -> AxisMap {
        let (nf, mf) = (n as f64, m as f64);
        let linear = mf / nf;
        let plot = spanned(plots);
        if m >= n || plot <= 0.0 {
            return AxisMap::linear(n, m);
        }
        // The spans outside the plots: blank margins, and the parts around the plots.
        let outside = complement(n, plots);
        let margins: Vec<[u32; 2]> = (outside.iter())
            .flat_map(|o| {
                (margins.iter())
                    .map(|g| [g[0].max(o[0]), g[1].min(o[1])])
                    .filter(|g| g[0] < g[1])
            })
            .collect();
        let parts_spans: Vec<[u32; 2]> = (outside.iter())
            .flat_map(|&o| complement_within(o, &margins))
            .collect();
        let (mut margins, mut parts_spans) = (margins, parts_spans);
        if spanned(&parts_spans) < LEAST_PARTS_PX {
            // A frame's or an axis' lines hold no type to keep: they are ground.
            margins.append(&mut parts_spans);
            margins.sort_unstable();
        }
        let (margin, parts) = (spanned(&margins), spanned(&parts_spans));
        let typed: f64 = (parts_spans.iter())
            .flat_map(|p| {
                (type_spans.iter())
                    .map(move |t| (t[1].min(p[1]) as f64 - t[0].max(p[0]) as f64).max(0.0))
            })
            .sum();
        if parts - typed > typed {
            return AxisMap::linear(n, m);
        }
        let least = LEAST_PLOT_SHARE * linear;
        let plot_at = |part: f64, gap: f64| (mf - parts * part - margin * gap) / plot;
        // Blank space gives way first, down to its least share, as a chart's author lets
        // the plot take the room its paddings leave; but a plot a few percent larger is
        // hardly seen, while its margins pressed to the edge are.
        let mut gap = LEAST_GAP_SHARE * linear;
        let grown = plot_at(1.0, gap);
        // Where the type around the plot keeps its size, its margins at the linear
        // resize's scale would leave the plot well under the linear resize's: the margins
        // at the edges of what is laid out (the canvas, or a card laid out in its slot) give
        // way then (an author's re-render pads its edges a few pixels), those between the
        // plot and its labels keep their share (judged blind: pressed too, a title over its
        // plot shrank and an axis title touched its labels).
        let at_edge = |g: &[u32; 2]| g[0] == 0 || g[1] == n;
        let edge_margin: f64 = margins
            .iter()
            .filter(|g| at_edge(g))
            .map(|g| (g[1] - g[0]) as f64)
            .sum();
        let mut inner_gap = None;
        let mut scale = grown;
        if grown > linear && grown < linear * (1.0 + LEAST_GROWTH) {
            let kept = plot_at(1.0, linear);
            let edged = (mf - parts - edge_margin * gap - (margin - edge_margin) * linear) / plot;
            match edged >= kept * (1.0 + LEAST_GROWTH) && edged >= least && edged <= 1.0 {
                true => {
                    inner_gap = Some(linear);
                    scale = edged;
                }
                false => {
                    gap = linear;
                    scale = plot_at(1.0, gap);
                }
            }
        }
        let mut scales = [1.0, gap, scale];
        if scales[2] < least {
            let gap = scales[1];
            let part = match parts > 0.0 {
                true => (mf - plot * least - margin * gap) / parts,
                false => linear,
            };
            if part <= linear {
                return AxisMap::linear(n, m);
            }
            scales = [part, gap, least];
        }
        if scales[2] > 1.0 {
            // A plot is never magnified: what is left goes to the margins, or the parts.
            let rest = mf - plot;
            scales = match margin > 0.0 {
                true => [1.0, (rest - parts) / margin, 1.0],
                false => [rest / parts, linear, 1.0],
            };
        }
        let [part, gap, scale] = scales;
        let at_linear = |k: f64, len: f64| len <= 0.0 || (k - linear).abs() < 1e-9;
        if at_linear(scale, plot) && at_linear(part, parts) && at_linear(gap, margin) {
            return AxisMap::linear(n, m);
        }
        let margin_gap = |g: &[u32; 2]| match at_edge(g) {
            true => gap,
            false => inner_gap.unwrap_or(gap),
        };
        let mut spans: Vec<([u32; 2], f64, bool)> = (plots.iter().map(|&p| (p, scale, false)))
            .chain(margins.iter().map(|&g| (g, margin_gap(&g), false)))
            .chain(parts_spans.iter().map(|&o| (o, part, true)))
            .collect();
        spans.sort_by_key(|s| s.0[0]);
        AxisMap::of_spans(n, m, &spans)
    }

    /// The map of `n` source pixels onto `m` that takes each of `spans` (`(span, scale,
    /// kept)`, sorted, tiling `0..n`) at its scale, a span kept at its size (`kept` and scale
    /// 1) starting on a whole output pixel; linear where rounding would fold it.
    pub(crate) fn of_spans(n: u32, m: u32, spans: &[([u32; 2], f64, bool)]) -> AxisMap {
        let (nf, mf) = (n as f64, m as f64);
        let mut knots = vec![[0.0, 0.0]];
        let mut out = 0.0;
        for &([a, e], k, kept) in spans {
            // A part kept at its size starts on a whole pixel (the stretch before gives or
            // takes the fraction).
            if kept && (k - 1.0).abs() < 1e-9 && a > 0 {
                out = f64::round(out);
                match knots.last_mut() {
                    Some(last) if last[0] >= a as f64 => *last = [a as f64, out],
                    _ => knots.push([a as f64, out]),
                }
            }
            out += (e - a) as f64 * k;
            knots.push([e as f64, out.min(mf)]);
        }
        // Rounding may leave the last knot a fraction off the end: the end is `m`.
        if let Some(last) = knots.last_mut() {
            *last = [nf, mf];
        }
        knots.dedup_by(|b, a| b[0] <= a[0]);
        if knots.windows(2).any(|k| k[1][1] < k[0][1]) {
            return AxisMap::linear(n, m);
        }
        AxisMap { knots }
    }

    /// Whether the map is one linear segment over source `[a, b]`.
    pub(crate) fn is_linear_over(&self, a: f64, b: f64) -> bool {
        let s = (self.apply(b) - self.apply(a)) / (b - a).max(1e-9);
        (self.knots.windows(2))
            .filter(|k| k[1][0] > a && k[0][0] < b)
            .all(|k| (slope(k[0], k[1]) - s).abs() < 1e-6)
    }

    /// Whether the map is one linear segment.
    pub fn is_linear(&self) -> bool {
        self.knots.len() == 2
    }

    /// The segment holding `x` along `coord` (0: source, 1: output), ends extended.
    fn segment(&self, v: f64, coord: usize) -> ([f64; 2], [f64; 2]) {
        let k = &self.knots;
        let i = k[1..k.len() - 1].partition_point(|p| p[coord] <= v);
        (k[i], k[i + 1])
    }

    /// Where the map takes source position `x`.
    pub fn apply(&self, x: f64) -> f64 {
        let (a, b) = self.segment(x, 0);
        a[1] + (x - a[0]) * slope(a, b)
    }

    /// The source position the map takes to output position `y`.
    pub fn inverse(&self, y: f64) -> f64 {
        let (a, b) = self.segment(y, 1);
        let s = slope(a, b);
        if s > 0.0 {
            a[0] + (y - a[1]) / s
        } else {
            a[0]
        }
    }

    /// The map's scale at source position `x`.
    pub fn slope(&self, x: f64) -> f64 {
        let (a, b) = self.segment(x, 0);
        slope(a, b)
    }

    /// This map moved by `by` along the source (`[0]`) and the output (`[1]`): a panel's map
    /// laid out on its own, placed where the panel and its slot stand.
    pub(crate) fn moved(&self, by: [f64; 2]) -> AxisMap {
        AxisMap {
            knots: (self.knots.iter())
                .map(|k| [k[0] + by[0], k[1] + by[1]])
                .collect(),
        }
    }

    /// The part of this map over source `[a, b]`, moved to start at `(0, 0)`: a panel's own
    /// map, for resampling the panel alone.
    pub(crate) fn within(&self, a: f64, b: f64) -> AxisMap {
        let (ya, yb) = (self.apply(a), self.apply(b));
        let mut knots = vec![[0.0, 0.0]];
        knots.extend(
            (self.knots.iter())
                .filter(|k| k[0] > a && k[0] < b)
                .map(|k| [k[0] - a, k[1] - ya]),
        );
        knots.push([b - a, (yb - ya).round()]);
        AxisMap { knots }
    }

    /// This map with source positions `at` taken to whole output pixels (knots within a
    /// pixel of them give way): panels cut there are drawn in slots of whole pixels.
    pub(crate) fn snapped(&self, at: &[f64]) -> AxisMap {
        let mut knots: Vec<[f64; 2]> = (self.knots.iter())
            .filter(|k| at.iter().all(|&p| (k[0] - p).abs() >= 1.0))
            .copied()
            .chain(at.iter().map(|&p| [p, self.apply(p).round()]))
            .collect();
        knots.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let mut high = f64::NEG_INFINITY;
        for k in &mut knots {
            k[1] = k[1].max(high);
            high = k[1];
        }
        AxisMap { knots }
    }

    /// The least scale of any segment (how far the resampler's filter must reach).
    pub fn least_slope(&self) -> f64 {
        (self.knots.windows(2))
            .map(|k| slope(k[0], k[1]))
            .fold(f64::INFINITY, f64::min)
    }
}

/// The scales of a map with bands: of its bands, of the gaps beside them, and of its plot.
struct Scales {
    band: f64,
    gap: f64,
    scale: f64,
}

/// The bands, gaps and margins of one axis.
type Spans<'a> = [&'a [[u32; 2]]; 3];

/// The gaps of `gaps` that are `margins` (a stream keeps only what every frame has).
fn edge_gaps<'a>(
    gaps: &'a [[u32; 2]],
    margins: &'a [[u32; 2]],
) -> impl Iterator<Item = [u32; 2]> + 'a {
    gaps.iter().copied().filter(move |g| margins.contains(g))
}

/// The half-open spans of `[0, n)` that none of `spans` (sorted, not overlapping) covers.
pub(super) fn complement(n: u32, spans: &[[u32; 2]]) -> Vec<[u32; 2]> {
    complement_within([0, n], spans)
}

/// The pieces of `span` that none of `cuts` (sorted, not overlapping) covers.
pub(super) fn complement_within([a, b]: [u32; 2], cuts: &[[u32; 2]]) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    let mut at = a;
    for c in cuts.iter().filter(|c| c[1] > a && c[0] < b) {
        if c[0] > at {
            out.push([at, c[0]]);
        }
        at = at.max(c[1]);
    }
    if at < b {
        out.push([at, b]);
    }
    out
}

/// The length the half-open `spans` cover together.
fn spanned(spans: &[[u32; 2]]) -> f64 {
    spans.iter().map(|b| (b[1] - b[0]) as f64).sum()
}

fn slope(a: [f64; 2], b: [f64; 2]) -> f64 {
    if b[0] > a[0] {
        (b[1] - a[1]) / (b[0] - a[0])
    } else {
        0.0
    }
}

/// A panel's place on the target: its source rectangle, the slot it is drawn in (both
/// `[x0, y0, x1, y1]`, half-open), and the maps of its axes (source to output positions,
/// exact over the panel; the slot's ends are the maps' images of the panel's ends).
#[derive(Clone, Debug, PartialEq)]
pub struct PanelMap {
    pub src: [u32; 4],
    pub slot: [u32; 4],
    pub x: AxisMap,
    pub y: AxisMap,
    /// The source rectangle the panel keeps at one scale, text and all (a card's body not
    /// squeezed), if any.
    pub body: Option<[u32; 4]>,
}

/// The panel of `panels` that holds source point `q` (the nearest where none does: a point
/// on the picture's far edge).
pub(crate) fn panel_at(panels: &[PanelMap], q: DVec2) -> Option<&PanelMap> {
    let distance = |p: &PanelMap| {
        let dx = (p.src[0] as f64 - q.x).max(q.x - p.src[2] as f64).max(0.0);
        let dy = (p.src[1] as f64 - q.y).max(q.y - p.src[3] as f64).max(0.0);
        dx + dy
    };
    (panels.iter()).min_by(|a, b| distance(a).total_cmp(&distance(b)))
}

/// The two axes' maps of a canvas taken whole; or, for a picture of panels, each panel's
/// (`x` and `y` then the linear resize's, for what asks of the whole).
#[derive(Clone, Debug, PartialEq)]
pub struct CanvasMap {
    pub x: AxisMap,
    pub y: AxisMap,
    /// Each panel's place and maps ([`crate::render::panels`]); empty for one picture.
    pub panels: Vec<PanelMap>,
}

impl CanvasMap {
    /// The linear resize's map of a `source` canvas onto `target`.
    pub fn linear(source: Size, target: Size) -> CanvasMap {
        CanvasMap {
            x: AxisMap::linear(source.width, target.width),
            y: AxisMap::linear(source.height, target.height),
            panels: Vec::new(),
        }
    }

    /// The map of a `source` canvas onto `target` that keeps `structure`'s text bands.
    ///
    /// Where the margins let the plot grow along both axes, it grows no further along one
    /// than keeps its shape between the linear resize's and its own: the plot of a picture
    /// halved both ways, with wide side margins, is not drawn wider than it was.
    pub fn new(structure: Option<&Structure>, source: Size, target: Size) -> CanvasMap {
        CanvasMap::laid_out(structure, source, target, true)
    }

    /// [`CanvasMap::new`] without the plots' layout ([`AxisMap::around_plots`]): the text
    /// bands and margins alone give way.
    pub(crate) fn without_plots(
        structure: Option<&Structure>,
        source: Size,
        target: Size,
    ) -> CanvasMap {
        CanvasMap::laid_out(structure, source, target, false)
    }

    fn laid_out(
        structure: Option<&Structure>,
        source: Size,
        target: Size,
        with_plots: bool,
    ) -> CanvasMap {
        let empty = crate::structure::Bands::default();
        let b = structure.map_or(&empty, |s| &s.bands);
        let (n, m) = ([source.width, source.height], [target.width, target.height]);
        let spans: [Spans; 2] = [
            [&b.x, &b.gaps_x, &b.margins_x],
            [&b.y, &b.gaps_y, &b.margins_y],
        ];
        // Each axis' plot scale alone (its linear one when nothing gives way)...
        let alone: [f64; 2] = std::array::from_fn(|k| {
            let linear = m[k] as f64 / n[k] as f64;
            AxisMap::scales(n[k], m[k], spans[k]).map_or(linear, |s| s.scale)
        });
        // ...held so that the plot's aspect (x scale over y scale) lies between the linear
        // resize's and 1.
        let linear_aspect = (m[0] as f64 / n[0] as f64) / (m[1] as f64 / n[1] as f64);
        let (lo, hi) = (linear_aspect.min(1.0), linear_aspect.max(1.0));
        let most = [alone[1] * hi, alone[0] / lo];
        let [(x, px), (y, py)] =
            std::array::from_fn(|k| AxisMap::with_bands_at_most(n[k], m[k], spans[k], most[k]));
        // Where the plot is stretched along one axis beside the other (a picture made lower
        // but no narrower) and that axis has blank margins, the plot narrows to its own shape
        // and the margins widen: a graph or a map keeps its shapes, as when drawn anew.
        // (A plot grown into its margins beyond the other axis' scale grows only to it.)
        let narrow = |k: usize, own: f64, other: f64, map: AxisMap| {
            if !b.free || own < other * (1.0 + LEAST_GROWTH) {
                return map;
            }
            let linear = m[k] as f64 / n[k] as f64;
            match other < linear {
                true => AxisMap::narrowed(n[k], m[k], spans[k], other).unwrap_or(map),
                false => AxisMap::with_bands_at_most(n[k], m[k], spans[k], other).0,
            }
        };
        // Where data areas were found, they take the room the parts around them leave.
        let plots = [
            (&b.plots_x, &b.blank_x, &b.type_x),
            (&b.plots_y, &b.blank_y, &b.type_y),
        ];
        let laid_out = |k: usize, map: AxisMap| match plots[k] {
            (p, g, t) if with_plots && !p.is_empty() && m[k] < n[k] => {
                // Where the layout declines (linear), the text bands still give way.
                let around = AxisMap::around_plots(n[k], m[k], p, g, t);
                match around.is_linear() {
                    true => map,
                    false => around,
                }
            }
            _ => map,
        };
        CanvasMap {
            x: laid_out(0, narrow(0, px, py, x)),
            y: laid_out(1, narrow(1, py, px, y)),
            panels: Vec::new(),
        }
    }

    /// The affine map `[ax, bx, ay, by]` that agrees with this one around `p`.
    pub fn local(&self, p: DVec2) -> [f64; 4] {
        let (x, y) = match panel_at(&self.panels, p) {
            Some(panel) => (&panel.x, &panel.y),
            None => (&self.x, &self.y),
        };
        let (sx, sy) = (x.slope(p.x), y.slope(p.y));
        [sx, x.apply(p.x) - sx * p.x, sy, y.apply(p.y) - sy * p.y]
    }
}

/// The maps of a frame's data areas as what floats over them reads them: each area's affine
/// map (`[ax, bx, ay, by]`, [`crate::Warp::area_maps`]), or, on a canvas taken whole, the
/// canvas' map around the point asked about.
#[derive(Copy, Clone, Debug)]
pub struct AreaMaps<'m> {
    pub areas: &'m [Option<[f64; 4]>],
    pub canvas: Option<&'m CanvasMap>,
}

impl AreaMaps<'_> {
    /// The map that carries area `k` around source point `p`.
    pub fn at(&self, k: usize, p: DVec2) -> Option<[f64; 4]> {
        let affine = (*self.areas.get(k)?)?;
        Some(self.canvas.map_or(affine, |c| c.local(p)))
    }
}

impl<'m, const N: usize> From<&'m [Option<[f64; 4]>; N]> for AreaMaps<'m> {
    fn from(areas: &'m [Option<[f64; 4]>; N]) -> Self {
        AreaMaps {
            areas,
            canvas: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The layout of a chart halved in width: the y axis' labels (0..80) and a legend
    /// (900..1000) keep their size, the plot (80..900) takes the rest at one scale.
    #[test]
    fn parts_around_a_plot_keep_their_size_and_the_plot_takes_the_rest() {
        let m = AxisMap::around_plots(1000, 500, &[[80, 900]], &[], &[[0, 80], [900, 1000]]);
        assert!((m.slope(40.0) - 1.0).abs() < 1e-9, "labels at their size");
        assert!((m.slope(950.0) - 1.0).abs() < 1e-9, "legend at its size");
        let s = m.slope(500.0);
        assert!((s - (500.0 - 180.0) / 820.0).abs() < 0.01, "{s}");
        for x in [100.0, 400.0, 850.0] {
            assert!((m.apply(x) - m.apply(80.0) - s * (x - 80.0)).abs() < 1e-6);
        }
        assert_eq!(
            m.apply(900.0).fract(),
            0.0,
            "a kept part starts on a whole pixel"
        );
        assert_eq!((m.apply(0.0), m.apply(1000.0)), (0.0, 500.0));
    }

    /// A picture narrowed to half its scale, its blank margins 10 and 20 px wide: the room
    /// left over is split evenly between its ends, as a letterbox centres it (shared by the
    /// margins' widths, the content sat 10 px off the middle).
    #[test]
    fn room_the_margins_take_beyond_the_plots_scale_centres_the_picture() {
        let gaps = [[0, 10], [80, 100]];
        let m = AxisMap::with_scales(100, 100, [&[], &gaps, &gaps], [0.5, 0.5, 0.5]);
        let (left, right) = (m.apply(10.0), 100.0 - m.apply(80.0));
        assert!(
            (m.apply(80.0) - left - 35.0).abs() < 1e-9,
            "the plot at its scale"
        );
        // The whole picture at half scale, 50 px wide, centred: 25 px either side of it.
        assert!((left - 5.0 - 25.0).abs() < 1e-9, "{left}");
        assert!((right - 10.0 - 25.0).abs() < 1e-9, "{right}");
    }

    /// A panel beside the plot that holds no type (not found as a data area) is no part to
    /// keep at its size: the picture is not laid out (linear), rather than the plot crushed.
    #[test]
    fn an_untyped_panel_beside_a_plot_is_not_kept() {
        let m = AxisMap::around_plots(1280, 720, &[[10, 600]], &[], &[]);
        assert!(m.is_linear());
        // The same with its labels' columns typed: laid out.
        let m = AxisMap::around_plots(1280, 720, &[[10, 600]], &[], &[[600, 1280]]);
        assert!(!m.is_linear());
    }

    /// Two panels side by side share one scale; the gutter between them keeps its size.
    #[test]
    fn plots_side_by_side_share_one_scale() {
        let m = AxisMap::around_plots(1000, 600, &[[50, 480], [520, 950]], &[], &[[0, 1000]]);
        let (a, b) = (m.slope(200.0), m.slope(700.0));
        assert!((a - b).abs() < 1e-9, "{a} {b}");
        assert!((m.slope(500.0) - 1.0).abs() < 1e-9);
    }

    /// Blank margins give way first, to their least share; parts that would leave the plot
    /// under half the linear scale shrink with it; nothing to lay out is linear.
    #[test]
    fn margins_give_way_and_the_plot_keeps_a_least_share() {
        let m = AxisMap::around_plots(1000, 500, &[[100, 900]], &[[0, 100]], &[[900, 1000]]);
        let margin = m.slope(50.0);
        assert!((margin - LEAST_GAP_SHARE * 0.5).abs() < 1e-9, "{margin}");
        assert!((m.slope(950.0) - 1.0).abs() < 1e-9);
        // Parts of 800 px around a plot of 200: at their size the plot would vanish.
        let crowded = AxisMap::around_plots(1000, 500, &[[400, 600]], &[], &[[0, 1000]]);
        let plot = crowded.slope(500.0);
        assert!((plot - LEAST_PLOT_SHARE * 0.5).abs() < 1e-9, "{plot}");
        let parts = crowded.slope(100.0);
        assert!(parts > 0.5 && parts < 1.0, "{parts}");
        assert!(AxisMap::around_plots(1000, 500, &[], &[], &[]).is_linear());
        assert!(AxisMap::around_plots(500, 1000, &[[0, 400]], &[], &[]).is_linear());
    }

    proptest! {
        /// Whatever the plots and margins, the layout is a monotone map of [0, n] onto [0, m].
        #[test]
        fn a_layout_is_monotone_and_onto(
            n in 20u32..3000,
            share in 0.1f64..0.99,
            cuts in proptest::collection::vec(0.0f64..1.0, 0..6),
        ) {
            let m = ((n as f64 * share) as u32).max(1);
            let mut at: Vec<u32> = cuts.iter().map(|c| (c * n as f64) as u32).collect();
            at.sort_unstable();
            at.dedup();
            let plots: Vec<[u32; 2]> =
                at.chunks_exact(2).filter(|p| p[0] < p[1]).map(|p| [p[0], p[1]]).collect();
            let map = AxisMap::around_plots(n, m, &plots, &[], &[[0, n]]);
            prop_assert_eq!(map.apply(0.0), 0.0);
            prop_assert!((map.apply(n as f64) - m as f64).abs() < 1e-9);
            let mut last = 0.0;
            for i in 0..=40 {
                let y = map.apply(n as f64 * i as f64 / 40.0);
                prop_assert!(y >= last - 1e-9, "{} < {}", y, last);
                last = y;
            }
        }
    }

    #[test]
    fn labels_take_what_the_gaps_give_and_the_plot_keeps_the_linear_scale() {
        // Labels at 10..60 with gaps around them; the plot from 70 on.
        let m = AxisMap::with_bands(1000, 500, &[[10, 60]], &[[0, 10], [60, 70]], &[[0, 10]]);
        assert!(
            m.slope(30.0) > 0.5,
            "the labels grow back toward their size"
        );
        // One linear-scale segment over the plot, in the linear resize's phase.
        let s = m.slope(500.0);
        assert!((s - 0.5).abs() < 1e-3, "{s}");
        for x in [100.0, 400.0, 900.0] {
            assert!((m.apply(x) - m.apply(70.0) - s * (x - 70.0)).abs() < 1e-9);
        }
        assert_eq!(
            (m.apply(70.0) - 35.0).fract(),
            0.0,
            "the plot keeps its phase"
        );
        assert_eq!(m.apply(10.0).fract(), 0.0, "a band starts on a whole pixel");
        assert_eq!(m.apply(1000.0), 500.0);
    }

    #[test]
    fn gaps_give_way_down_to_a_quarter() {
        let m = AxisMap::with_bands(1000, 500, &[[100, 200]], &[[0, 100]], &[[0, 100]]);
        let gap = m.slope(50.0);
        assert!((gap - LEAST_GAP_SHARE * 0.5).abs() < 0.02, "{gap}");
        assert!(m.slope(150.0) > 0.5 && m.slope(150.0) < 1.0);
        assert!((m.slope(600.0) - 0.5).abs() < 1e-2);
    }

    #[test]
    fn blank_margins_give_way_to_the_plot() {
        let m = AxisMap::with_bands(
            1000,
            500,
            &[],
            &[[0, 100], [900, 1000]],
            &[[0, 100], [900, 1000]],
        );
        // The margins keep a quarter of their linear share; the plot takes the rest.
        let s = (500.0 - LEAST_GAP_SHARE * 0.5 * 200.0) / 800.0;
        assert!(s > 0.5);
        for x in [150.0, 500.0, 850.0] {
            assert!((m.slope(x) - s).abs() < 1e-9, "{}", m.slope(x));
            assert!((m.apply(x) - m.apply(100.0) - s * (x - 100.0)).abs() < 1e-9);
        }
        assert!(m.slope(50.0) < 0.5 && m.slope(950.0) < 0.5);
        assert_eq!(m.apply(1000.0), 500.0);
    }

    /// A bar chart made lower, its title, tick labels and axis title kept at their size:
    /// with its margins at the linear resize's scale the plot would come out well under it
    /// (0.54 of its height against 0.60); the margins give way and it grows back past it.
    #[test]
    fn margins_give_way_where_the_type_around_a_plot_keeps_its_size() {
        let (plots, margins) = ([[57, 495]], [[0, 31], [502, 503], [517, 522], [540, 568]]);
        let type_spans = [[31, 57], [495, 502], [503, 517], [522, 540]];
        let m = AxisMap::around_plots(568, 340, &plots, &margins, &type_spans);
        let linear = 340.0 / 568.0;
        let plot = m.slope(300.0);
        assert!(plot > linear, "plot at {plot}, linear {linear}");
        assert!(
            m.slope(15.0) < 0.5 * linear,
            "top margin at {}",
            m.slope(15.0)
        );
        assert!((m.slope(40.0) - 1.0).abs() < 1e-9, "the title at its size");
    }

    #[test]
    fn the_plot_never_grows_past_its_own_size() {
        let m = AxisMap::with_bands(1000, 900, &[], &[[0, 500]], &[[0, 500]]);
        assert!((m.slope(700.0) - 1.0).abs() < 1e-9, "{}", m.slope(700.0));
        assert!((m.slope(200.0) - 0.8).abs() < 1e-9, "{}", m.slope(200.0));
    }

    #[test]
    fn the_plot_grows_no_wider_than_its_own_shape() {
        let size = Size::new(1000, 1000).unwrap();
        let mut s = Structure::default();
        s.bands.gaps_x = vec![[0, 200], [800, 1000]];
        s.bands.margins_x = s.bands.gaps_x.clone();
        // Halved both ways: the side margins alone would draw the plot at 0.75 x 0.5.
        let halved = CanvasMap::new(Some(&s), size, Size::new(500, 500).unwrap());
        assert!(halved.x.is_linear() && halved.y.is_linear());
        // Halved in width only: the plot grows back toward its shape, up to it at most.
        let narrow = CanvasMap::new(Some(&s), size, Size::new(500, 1000).unwrap());
        assert!((narrow.x.slope(500.0) - 0.75).abs() < 1e-9);
        // Halved in width, to 80 % in height with top and bottom margins too: the x scale
        // may not pass the y scale.
        s.bands.gaps_y = vec![[0, 150], [850, 1000]];
        s.bands.margins_y = s.bands.gaps_y.clone();
        let both = CanvasMap::new(Some(&s), size, Size::new(500, 800).unwrap());
        let (sx, sy) = (both.x.slope(500.0), both.y.slope(500.0));
        assert!(sx > 0.5 && sy > 0.8 && sx <= sy + 1e-9, "{sx} {sy}");
    }

    #[test]
    fn a_free_picture_made_lower_keeps_its_shape_in_wider_margins() {
        let size = Size::new(1000, 600).unwrap();
        let mut s = Structure::default();
        s.bands.gaps_x = vec![[0, 300], [700, 1000]];
        s.bands.margins_x = s.bands.gaps_x.clone();
        s.bands.free = true;
        let lower = Size::new(1000, 360).unwrap();
        let map = CanvasMap::new(Some(&s), size, lower);
        assert!(map.y.is_linear());
        // The plot at the height's scale both ways, centred.
        for x in [320.0, 500.0, 680.0] {
            assert!((map.x.slope(x) - 0.6).abs() < 1e-9, "{}", map.x.slope(x));
        }
        // 400 px of plot at 0.6 leave 760 px to the two 300 px margins alike: 380 each.
        let (left, right) = (map.x.apply(300.0), 1000.0 - map.x.apply(700.0));
        assert!(
            (left - 380.0).abs() <= 1.0 && (right - 380.0).abs() <= 1.0,
            "{left} {right}"
        );
        assert_eq!(map.x.apply(1000.0), 1000.0);
        // A chart (a data area was found) is not made smaller than the linear resize draws
        // it: its margins keep their share.
        s.bands.free = false;
        assert!(CanvasMap::new(Some(&s), size, lower).x.is_linear());
        // Nor is a free picture without margins, or one whose shape barely changes.
        s.bands.free = true;
        let no_margins = Structure::default();
        assert!(CanvasMap::new(Some(&no_margins), size, lower).x.is_linear());
        let barely = Size::new(1000, 570).unwrap();
        assert!(CanvasMap::new(Some(&s), size, barely).x.is_linear());
    }

    #[test]
    fn a_narrowed_plot_leaves_its_text_bands_their_size() {
        // A title band at the top, the space under it, and a blank page at the bottom.
        let size = Size::new(1000, 1000).unwrap();
        let mut s = Structure::default();
        s.bands.y = vec![[0, 40]];
        s.bands.gaps_y = vec![[40, 60], [850, 1000]];
        s.bands.margins_y = vec![[850, 1000]];
        s.bands.free = true;
        let map = CanvasMap::new(Some(&s), size, Size::new(500, 800).unwrap());
        let (band, plot) = (map.y.slope(20.0), map.y.slope(500.0));
        assert!((plot - 0.5).abs() < 1e-9, "{plot}");
        assert!(
            band > 0.8,
            "the title keeps more than the linear scale: {band}"
        );
        assert_eq!(map.y.apply(1000.0), 800.0);
    }

    #[test]
    fn a_plot_grows_visibly_or_not_at_all() {
        // Thin margins would let the plot grow by under a percent: it keeps the linear scale
        // and the margins theirs.
        assert!(AxisMap::with_bands(1000, 500, &[], &[[0, 10]], &[[0, 10]]).is_linear());
        // A gap that is no margin (a header bar's fill at the edge) gives nothing to the plot.
        assert!(AxisMap::with_bands(1000, 500, &[], &[[0, 300]], &[]).is_linear());
        assert!(!AxisMap::with_bands(1000, 500, &[], &[[0, 300]], &[[0, 300]]).is_linear());
    }

    #[test]
    fn no_gap_or_no_shrink_is_linear() {
        assert!(AxisMap::with_bands(1000, 500, &[[0, 40]], &[], &[]).is_linear());
        assert!(AxisMap::with_bands(1000, 500, &[], &[], &[]).is_linear());
        assert!(AxisMap::with_bands(500, 800, &[[0, 40]], &[[40, 60]], &[]).is_linear());
        assert!(AxisMap::with_bands(500, 500, &[[0, 40]], &[[40, 60]], &[]).is_linear());
    }

    proptest! {
        #[test]
        fn the_map_is_monotone_and_inverts(
            n in 50u32..2000,
            share in 0.2f64..0.99,
            cuts in prop::collection::vec((0.0f64..1.0, 0.0f64..0.1, any::<bool>()), 0..8),
        ) {
            let m = ((n as f64 * share) as u32).max(1);
            let mut spans: Vec<([u32; 2], bool)> = cuts
                .iter()
                .map(|&(a, l, band)| {
                    let a = ((a * n as f64) as u32).min(n - 1);
                    ([a, (a + (l * n as f64) as u32 + 1).min(n)], band)
                })
                .collect();
            spans.sort();
            spans.dedup_by(|b, a| b.0[0] < a.0[1]);
            let pick = |band: bool| spans.iter().filter(|s| s.1 == band).map(|s| s.0).collect::<Vec<_>>();
            let gaps = pick(false);
            let margins: Vec<[u32; 2]> = gaps.iter().copied().filter(|g| g[0] == 0 || g[1] == n).collect();
            let map = AxisMap::with_bands(n, m, &pick(true), &gaps, &margins);
            prop_assert!((map.apply(0.0)).abs() < 1e-9);
            prop_assert!((map.apply(n as f64) - m as f64).abs() < 1e-9);
            let mut last = -1.0;
            for i in 0..=200 {
                let x = n as f64 * i as f64 / 200.0;
                let y = map.apply(x);
                prop_assert!(y >= last - 1e-9);
                last = y;
                if map.slope(x) > 0.0 {
                    prop_assert!((map.inverse(y) - x).abs() < 1e-6, "{} {}", x, map.inverse(y));
                }
            }
            prop_assert!(map.least_slope() >= 0.5 * LEAST_GAP_SHARE * m as f64 / n as f64 - 1e-9);
        }
    }
}
