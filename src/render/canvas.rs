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
    /// the `gaps` can make room for, down to a quarter of their linear size), everything else at the
    /// linear resize's scale, so that what is read off a position is where a linear resize
    /// puts it; linear when the axis does not shrink or nothing can give way. A band starts
    /// on a whole output pixel (copied, not resampled between pixels) and every other stretch
    /// keeps the linear resize's phase (its thin lines fall on pixels as they did).
    pub fn with_bands(n: u32, m: u32, bands: &[[u32; 2]], gaps: &[[u32; 2]]) -> AxisMap {
        let (nf, mf) = (n as f64, m as f64);
        let len = |v: &[[u32; 2]]| v.iter().map(|b| (b[1] - b[0]) as f64).sum::<f64>();
        let (kept, give) = (len(bands), len(gaps));
        if m >= n || kept <= 0.0 || give <= 0.0 || kept + give > nf {
            return AxisMap::linear(n, m);
        }
        let linear = mf / nf;
        let room = linear * (kept + give) - LEAST_GAP_SHARE * linear * give;
        let band = (room / kept).min(1.0);
        if band <= linear * (1.0 + 1e-6) {
            return AxisMap::linear(n, m);
        }
        let gap = (linear * (kept + give) - band * kept) / give;
        let mut spans: Vec<([u32; 2], f64, bool)> = (bands.iter().map(|&b| (b, band, true)))
            .chain(gaps.iter().map(|&g| (g, gap, false)))
            .collect();
        spans.sort_by_key(|s| s.0[0]);
        let knots = |snap: bool| {
            // Where a stretch at the linear scale starts: snapped, a whole number of pixels
            // from where the linear resize puts it.
            let in_phase = |pos: f64, out: f64| match snap {
                true => pos * linear + (out - pos * linear).round(),
                false => out,
            };
            let mut knots = vec![[0.0, 0.0]];
            let (mut pos, mut out) = (0.0, 0.0);
            let push = |knots: &mut Vec<[f64; 2]>, x: f64, o: f64| {
                if x > knots.last().map_or(-1.0, |k: &[f64; 2]| k[0]) {
                    knots.push([x, o]);
                }
            };
            for &([a, e], scale, is_band) in &spans {
                let (a, e) = (a as f64, e as f64);
                if a > pos {
                    // The stretch before at the linear scale, in the linear resize's phase.
                    out = in_phase(pos, out);
                    push(&mut knots, pos, out);
                    out += (a - pos) * linear;
                }
                if snap && is_band {
                    out = out.round();
                }
                push(&mut knots, a, out);
                out += (e - a) * scale;
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

    /// The least scale of any segment (how far the resampler's filter must reach).
    pub fn least_slope(&self) -> f64 {
        (self.knots.windows(2))
            .map(|k| slope(k[0], k[1]))
            .fold(f64::INFINITY, f64::min)
    }
}

fn slope(a: [f64; 2], b: [f64; 2]) -> f64 {
    if b[0] > a[0] {
        (b[1] - a[1]) / (b[0] - a[0])
    } else {
        0.0
    }
}

/// The two axes' maps of a canvas taken whole.
#[derive(Clone, Debug, PartialEq)]
pub struct CanvasMap {
    pub x: AxisMap,
    pub y: AxisMap,
}

impl CanvasMap {
    /// The map of a `source` canvas onto `target` that keeps `structure`'s text bands.
    pub fn new(structure: Option<&Structure>, source: Size, target: Size) -> CanvasMap {
        let bands = structure.map(|s| &s.bands);
        CanvasMap {
            x: AxisMap::with_bands(
                source.width,
                target.width,
                bands.map_or(&[][..], |b| &b.x[..]),
                bands.map_or(&[][..], |b| &b.gaps_x[..]),
            ),
            y: AxisMap::with_bands(
                source.height,
                target.height,
                bands.map_or(&[][..], |b| &b.y[..]),
                bands.map_or(&[][..], |b| &b.gaps_y[..]),
            ),
        }
    }

    /// The affine map `[ax, bx, ay, by]` that agrees with this one around `p`.
    pub fn local(&self, p: DVec2) -> [f64; 4] {
        let (sx, sy) = (self.x.slope(p.x), self.y.slope(p.y));
        [
            sx,
            self.x.apply(p.x) - sx * p.x,
            sy,
            self.y.apply(p.y) - sy * p.y,
        ]
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

    #[test]
    fn a_margin_keeps_its_size_and_the_plot_the_linear_scale() {
        // Labels at 10..60 with gaps around them; the plot from 70 on.
        let m = AxisMap::with_bands(1000, 500, &[[10, 60]], &[[0, 10], [60, 70]]);
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
        let m = AxisMap::with_bands(1000, 500, &[[100, 200]], &[[0, 100]]);
        let gap = m.slope(50.0);
        assert!((gap - LEAST_GAP_SHARE * 0.5).abs() < 0.02, "{gap}");
        assert!(m.slope(150.0) > 0.5 && m.slope(150.0) < 1.0);
        assert!((m.slope(600.0) - 0.5).abs() < 1e-2);
    }

    #[test]
    fn no_band_no_gap_or_no_shrink_is_linear() {
        assert!(AxisMap::with_bands(1000, 500, &[], &[[0, 40]]).is_linear());
        assert!(AxisMap::with_bands(1000, 500, &[[0, 40]], &[]).is_linear());
        assert!(AxisMap::with_bands(500, 800, &[[0, 40]], &[[40, 60]]).is_linear());
        assert!(AxisMap::with_bands(500, 500, &[[0, 40]], &[[40, 60]]).is_linear());
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
            let map = AxisMap::with_bands(n, m, &pick(true), &pick(false));
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
