//! A plain linear resize, separable Catmull-Rom (ImageMagick's `-filter Catrom -resize`): the
//! render of a canvas under one linear map. Against the crate's triangle renderer over two
//! triangles (bilinear, box-filtered where it shrinks), it keeps a heat map's 2-px separators
//! and small type apart, and it draws what a reader compares it with.
//!
//! Catmull-Rom's negative lobes overshoot a little at edges, as ImageMagick's do: that
//! overshoot is the filter's crispness. Clamping each sample to its neighbourhood's range
//! (as this resize once did) drew every edge a shade softer than the linear resize a reader
//! compares it with, and judged blind beside it, the softer copy lost the ties.

use super::canvas::{AxisMap, CanvasMap};
use crate::image::{Image, ImageRef, Size};

/// Catmull-Rom (B = 0, C = 1/2), support 2.
fn catmull_rom(x: f32) -> f32 {
    let x = x.abs();
    if x < 1.0 {
        1.5 * x * x * x - 2.5 * x * x + 1.0
    } else if x < 2.0 {
        -0.5 * x * x * x + 2.5 * x * x - 4.0 * x + 2.0
    } else {
        0.0
    }
}

/// The taps of one output sample along an axis: the first source index, and where its
/// weights (summing to 1) lie in [`Axis::weights`].
struct Taps {
    start: usize,
    weights: std::ops::Range<usize>,
}

/// The taps of every output sample along one axis, their weights in one buffer.
struct Axis {
    /// Source samples.
    n: usize,
    taps: Vec<Taps>,
    weights: Vec<f32>,
    /// The weights of [`Axis::padded`] taps again, laid out for [`Axis::filter_lanes`]: for
    /// each [`LANES`] samples and each tap, two samples' weights side by side, each repeated
    /// once per channel. A product of eight floats then takes its weights straight from
    /// memory instead of spreading each across the channels first.
    spread: Vec<[f32; 8]>,
}

impl Axis {
    /// The taps when `n` source samples become `m`.
    fn new(n: usize, m: usize) -> Axis {
        let scale = m as f32 / n as f32;
        // Shrinking widens the filter over the source samples each output sample stands for.
        let stretch = (1.0 / scale).max(1.0);
        Axis::from_centres(n, m, stretch, |i| ((i as f32 + 0.5) / scale - 0.5, stretch))
    }

    /// The taps when `n` source samples become `m` under `map` (source to output, monotone
    /// and piecewise linear): each output sample is filtered around the source position the
    /// map takes to it, as wide as the map shrinks there.
    fn mapped(n: usize, m: usize, map: &AxisMap) -> Axis {
        let widest = (1.0 / map.least_slope()).max(1.0) as f32;
        Axis::from_centres(n, m, widest, |i| {
            let x = map.inverse(i as f64 + 0.5);
            ((x - 0.5) as f32, (1.0 / map.slope(x)).max(1.0) as f32)
        })
    }

    /// The taps of `m` output samples, sample `i` centred on source position `at(i).0` with
    /// the filter stretched by `at(i).1` (at most `widest`).
    fn from_centres(n: usize, m: usize, widest: f32, at: impl Fn(usize) -> (f32, f32)) -> Axis {
        let mut weights = Vec::with_capacity(m * (4.0 * widest).ceil() as usize + m);
        let taps = (0..m)
            .map(|i| {
                let (centre, stretch) = at(i);
                let support = 2.0 * stretch;
                let lo = ((centre - support).floor() as i64 + 1).max(0) as usize;
                let hi = ((centre + support).floor() as i64)
                    .min(n as i64 - 1)
                    .max(lo as i64) as usize;
                let first = weights.len();
                weights.extend((lo..=hi).map(|j| catmull_rom((j as f32 - centre) / stretch)));
                let w = &mut weights[first..];
                let sum: f32 = w.iter().sum();
                if sum.abs() > 1e-6 {
                    w.iter_mut().for_each(|v| *v /= sum);
                } else {
                    // No tap carries weight (one sample far from the centre): the nearest.
                    w.iter_mut().for_each(|v| *v = 0.0);
                    w[(centre.round().clamp(lo as f32, hi as f32) as usize) - lo] = 1.0;
                }
                Taps {
                    start: lo,
                    weights: first..weights.len(),
                }
            })
            .collect();
        Axis {
            n,
            taps,
            weights,
            spread: Vec::new(),
        }
    }

    /// The same taps, each made `k` long (the most any has) by zero weights before or after
    /// it, inside the row: the tap loop then runs the same length for every sample, and the
    /// processor predicts its end instead of stalling on it every few samples. A zero weight
    /// adds nothing and bounds nothing, so the samples are the same.
    fn padded(self) -> Axis {
        let n = self.n;
        let k = (self.taps.iter().map(|t| t.weights.len()).max()).map_or(0, |k| k.min(n));
        let mut weights = Vec::with_capacity(k * self.taps.len());
        let taps: Vec<Taps> = (self.taps.iter())
            .map(|t| {
                let start = t.start.min(n - k);
                let front = t.start - start;
                let first = weights.len();
                weights.resize(first + front, 0.0);
                weights.extend_from_slice(&self.weights[t.weights.clone()]);
                weights.resize(first + k, 0.0);
                Taps {
                    start,
                    weights: first..first + k,
                }
            })
            .collect();
        let spread = (taps.chunks_exact(LANES))
            .flat_map(|q| {
                let w = |l: usize, j: usize| weights[q[l].weights.start + j];
                (0..k).flat_map(move |j| {
                    std::array::from_fn::<_, { LANES / 2 }, _>(|p| {
                        let l = 2 * p;
                        let (a, b) = (w(l, j), w(l + 1, j));
                        [a, a, a, a, b, b, b, b]
                    })
                })
            })
            .collect();
        Axis {
            n,
            taps,
            weights,
            spread,
        }
    }

    /// Sample `i` of a `row` of source samples.
    #[inline(always)]
    fn filter(&self, i: usize, row: &[[f32; 4]]) -> [f32; 4] {
        let t = &self.taps[i];
        let weights = &self.weights[t.weights.clone()];
        let src = &row[t.start..][..weights.len()];
        let mut acc = [0f32; 4];
        for (&w, v) in weights.iter().zip(src) {
            for c in 0..4 {
                acc[c] += w * v[c];
            }
        }
        acc
    }

    /// Samples `i..i + LANES` of each of `R` rows (`i` a multiple of [`LANES`]), as
    /// [`Axis::filter`] each (the same products, summed in the same order): two samples' four
    /// channels in one row of eight floats, their weights from [`Axis::spread`], each weight
    /// read once for all `R` rows. The sums are independent, so the processor overlaps them
    /// instead of waiting on each addition.
    #[inline(always)]
    fn filter_lanes<const R: usize>(
        &self,
        i: usize,
        rows: [&[[f32; 4]]; R],
    ) -> [[[f32; 4]; LANES]; R] {
        const PAIRS: usize = LANES / 2;
        let k = self.taps[i].weights.len();
        let taps = &self.taps[i..i + LANES];
        let mut src: [[&[[f32; 4]]; LANES]; R] = [[&[]; LANES]; R];
        for (src, row) in src.iter_mut().zip(rows) {
            for (s, t) in src.iter_mut().zip(taps) {
                *s = &row[t.start..][..k];
            }
        }
        let spread = &self.spread[i / LANES * PAIRS * k..][..PAIRS * k];
        let mut acc = [[[0f32; 8]; PAIRS]; R];
        for j in 0..k {
            for p in 0..PAIRS {
                let w = spread[PAIRS * j + p];
                for r in 0..R {
                    let (a, b) = (src[r][2 * p][j], src[r][2 * p + 1][j]);
                    let v = [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]];
                    for c in 0..8 {
                        acc[r][p][c] += w[c] * v[c];
                    }
                }
            }
        }
        let mut out = [[[0f32; 4]; LANES]; R];
        for (out, acc) in out.iter_mut().zip(&acc) {
            for (l, o) in out.iter_mut().enumerate() {
                o.copy_from_slice(&acc[l / 2][4 * (l % 2)..][..4]);
            }
        }
        out
    }

    /// Resamples the rows of `px` (`n` samples each) from row `first` on into rows of this
    /// axis's `m` samples, handing each to `out_row(y, row)` (`y` counted from `first`).
    #[inline(always)]
    fn across(
        &self,
        px: &[[u8; 4]],
        first: usize,
        rows: usize,
        mut out_row: impl FnMut(usize, &[[f32; 4]]),
    ) {
        let (n, m) = (self.n, self.taps.len());
        let mut rowf = [vec![[0f32; 4]; n], vec![[0f32; 4]; n]];
        let mut out = [vec![[0f32; 4]; m], vec![[0f32; 4]; m]];
        let mut y = 0;
        while y < rows {
            // Two rows at a time where two are left: each weight read once for both.
            let pair = y + 1 < rows;
            for (r, f) in rowf.iter_mut().enumerate().take(1 + pair as usize) {
                let row = &px[(first + y + r) * n..][..n];
                for (f, &p) in f.as_flattened_mut().iter_mut().zip(row.as_flattened()) {
                    *f = f32::from(p);
                }
            }
            // [`LANES`] samples at a time, each summing its taps in order (the same bytes as
            // one at a time).
            let done = m - m % LANES;
            let [oa, ob] = &mut out;
            for q in (0..done).step_by(LANES) {
                if pair {
                    let [a, b] = self.filter_lanes(q, [&rowf[0], &rowf[1]]);
                    oa[q..q + LANES].copy_from_slice(&a);
                    ob[q..q + LANES].copy_from_slice(&b);
                } else {
                    let [a] = self.filter_lanes(q, [&rowf[0]]);
                    oa[q..q + LANES].copy_from_slice(&a);
                }
            }
            for x in done..m {
                oa[x] = self.filter(x, &rowf[0]);
                if pair {
                    ob[x] = self.filter(x, &rowf[1]);
                }
            }
            out_row(y, oa);
            if pair {
                out_row(y + 1, ob);
            }
            y += 1 + pair as usize;
        }
    }
}

impl Axis {
    /// One row of source samples (`src`, converted into the scratch row `rowf`) resampled
    /// into `out`, as [`Axis::across`] makes each row.
    #[inline(always)]
    fn row(&self, src: &[[u8; 4]], rowf: &mut [[f32; 4]], out: &mut [[f32; 4]]) {
        for (f, &p) in rowf.as_flattened_mut().iter_mut().zip(src.as_flattened()) {
            *f = f32::from(p);
        }
        let m = self.taps.len();
        let done = m - m % LANES;
        for q in (0..done).step_by(LANES) {
            let [a] = self.filter_lanes(q, [&*rowf]);
            out[q..q + LANES].copy_from_slice(&a);
        }
        for (x, o) in out.iter_mut().enumerate().skip(done) {
            *o = self.filter(x, rowf);
        }
    }
}

/// Output samples filtered together by [`Axis::filter_lanes`].
const LANES: usize = 8;

/// Each float of `row` as ImageMagick's 16-bit build stores a resized sample and writes
/// it at 8 bits: rounded to the nearest 16-bit level, then cut to the 8-bit level below
/// ([`quantize`]). A reader compares this resize with ImageMagick's: rounded to the
/// nearest 8-bit level instead, every sample came out half a level lighter, dark text on
/// white a shade softer, and judged blind beside it the softer copy lost the ties.
#[inline(always)]
fn round_row(row: &[[f32; 4]], out: &mut [[u8; 4]]) {
    for (o, &v) in out.as_flattened_mut().iter_mut().zip(row.as_flattened()) {
        *o = quantize(v);
    }
}

/// `v` (0..=255, clamped) to 16 bits, rounded, then to 8 bits, truncated: `⌊round(257 v) /
/// 257⌋`, as ImageMagick 6.9 Q16 writes a resized sample (checked byte for byte against
/// `convert -filter Catrom -resize` on this machine). Exact levels stay exact; `257 v` is
/// rounded once more in floats, so within a float's step of a 16-bit half-level the result
/// may be the level above the formula's.
#[inline(always)]
fn quantize(v: f32) -> u8 {
    // Clamped by selects that also take a NaN to 0: the casts below need a number in range.
    let t = v * 257.0 + 0.5;
    let t = if t >= 0.0 { t } else { 0.0 };
    let t = if t <= 65_535.5 { t } else { 65_535.5 };
    // SAFETY: `t` lies in [0, 65535.5], so it fits an i32, and truncating it is its floor.
    // (A checked cast tests each lane's range and NaN again, in as many instructions as the
    // rest together.)
    let q = unsafe { t.to_int_unchecked::<i32>() } as f32;
    // A 16-bit level plus a half, over 257, lies at least 1/514 from a whole number: far
    // beyond the float's error, so this floor is exact.
    let o = (q + 0.5) * (1.0 / 257.0);
    // SAFETY: `o` lies in [0, 256).
    unsafe { o.to_int_unchecked::<i32>() as u8 }
}

crate::simd::with_feature! {
    "avx";
    /// Rows `first..` of `px` resampled across into `band`'s rows, rounded.
    fn across_rounded(across: &Axis, px: &[[u8; 4]], first: usize, band: &mut [[u8; 4]])
        => across_rounded_body {
        let tw = across.taps.len();
        across.across(px, first, band.len() / tw, |y, row| {
            round_row(row, &mut band[y * tw..][..tw])
        })
    }
}

crate::simd::with_feature! {
    "avx";
    /// Output rows `first..` (`band`, rows of `tw`) resampled down from the rows `across`
    /// makes of `px` (copied as floats where `across` is `None`). Each of those rows is made
    /// once into a ring of as many rows as the longest tap: a band reads its rows while they
    /// are in cache, and no picture-sized buffer of floats is filled and read back.
    fn both_rounded(
        across: Option<&Axis>,
        down: &Axis,
        px: &[[u8; 4]],
        tw: usize,
        first: usize,
        band: &mut [[u8; 4]],
    ) => both_rounded_body {
        let rows = band.len() / tw;
        let sw = px.len() / down.n.max(1);
        let taps = &down.taps[first..first + rows];
        let cap = (taps.iter().map(|t| t.weights.len()).max())
            .unwrap_or(1)
            .max(1);
        let mut ring = vec![[0f32; 4]; cap * tw];
        // The source row each slot of the ring holds. A row's taps are consecutive rows, at
        // most `cap`, so they never share a slot; the rows wanted only move down the picture
        // (but for a map's bends, where a row made again costs time, not bytes).
        let mut held = vec![usize::MAX; cap];
        let (mut rowf, mut acc) = (vec![[0f32; 4]; sw], vec![[0f32; 4]; tw]);
        for (t, orow) in taps.iter().zip(band.chunks_exact_mut(tw)) {
            let len = t.weights.len();
            for j in t.start..t.start + len {
                let slot = j % cap;
                if held[slot] == j {
                    continue;
                }
                let (src, dst) = (&px[j * sw..][..sw], &mut ring[slot * tw..][..tw]);
                match across {
                    Some(a) => a.row(src, &mut rowf, dst),
                    None => {
                        for (o, &p) in dst.as_flattened_mut().iter_mut().zip(src.as_flattened()) {
                            *o = f32::from(p);
                        }
                    }
                }
                held[slot] = j;
            }
            acc.fill([0.0; 4]);
            for (k, &w) in down.weights[t.weights.clone()].iter().enumerate() {
                // Flat loops over the row's floats: vectors, whatever the channel count.
                let row = ring[(t.start + k) % cap * tw..][..tw].as_flattened();
                for (a, &v) in acc.as_flattened_mut().iter_mut().zip(row) {
                    *a += w * v;
                }
            }
            round_row(&acc, orow);
        }
    }
}

/// Least rows per thread: below this a thread costs more than it saves.
const ROWS_PER_THREAD: usize = 64;

/// How many threads a resize may use.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Threads {
    /// One per core: a still, where nothing else runs beside the resize.
    AllCores,
    /// The calling thread alone: a stage of the threaded pipeline, where the other stages
    /// keep the cores busy with other frames, and more threads only contend with them.
    One,
}

/// Runs `f(first_row, band)` over bands of whole rows of `rows` (`row_len` items each), one
/// band per core with [`Threads::AllCores`]: the rows of a resize pass are independent.
fn in_bands<T: Send>(
    rows: &mut [T],
    row_len: usize,
    threads: Threads,
    f: impl Fn(usize, &mut [T]) + Sync,
) {
    let n = rows.len() / row_len.max(1);
    let cores = match threads {
        Threads::AllCores => std::thread::available_parallelism().map_or(1, |t| t.get()),
        Threads::One => 1,
    };
    let threads = cores.min(n / ROWS_PER_THREAD).max(1);
    if threads == 1 {
        f(0, rows);
        return;
    }
    let per = n.div_ceil(threads);
    std::thread::scope(|s| {
        for (b, band) in rows.chunks_mut(per * row_len).enumerate() {
            let f = &f;
            s.spawn(move || f(b * per, band));
        }
    });
}

/// `src` resized to `target`, each axis on its own.
pub fn resize_linear(src: ImageRef<'_>, target: Size) -> Image {
    resize_linear_on(src, target, Threads::AllCores)
}

/// [`resize_linear`] on `threads`.
fn resize_linear_on(src: ImageRef<'_>, target: Size, threads: Threads) -> Image {
    if src.size() == target {
        return src.to_owned();
    }
    let (sw, sh) = (src.width() as usize, src.height() as usize);
    let (tw, th) = (target.width as usize, target.height as usize);
    resize_axes(
        src,
        target,
        threads,
        [tw != sw, th != sh],
        || Axis::new(sw, tw),
        || Axis::new(sh, th),
    )
}

/// `src` resampled onto `target` by `map`, each axis on its own (a plain linear resize where
/// both of its axes are linear).
pub fn resize_mapped(src: ImageRef<'_>, target: Size, map: &CanvasMap) -> Image {
    resize_mapped_on(src, target, map, Threads::AllCores)
}

/// [`resize_mapped`] on `threads`.
pub(crate) fn resize_mapped_on(
    src: ImageRef<'_>,
    target: Size,
    map: &CanvasMap,
    threads: Threads,
) -> Image {
    if map.x.is_linear() && map.y.is_linear() {
        return resize_linear_on(src, target, threads);
    }
    let (sw, sh) = (src.width() as usize, src.height() as usize);
    let (tw, th) = (target.width as usize, target.height as usize);
    let axis = |n: usize, m: usize, a: &AxisMap| {
        if a.is_linear() {
            Axis::new(n, m)
        } else {
            Axis::mapped(n, m, a)
        }
    };
    resize_axes(
        src,
        target,
        threads,
        [
            tw != sw || !map.x.is_linear(),
            th != sh || !map.y.is_linear(),
        ],
        || axis(sw, tw, &map.x),
        || axis(sh, th, &map.y),
    )
}

/// `src` resampled onto `target` by the taps `across()` (along rows) and `down()` (along
/// columns), built only where that axis `changes`.
fn resize_axes(
    src: ImageRef<'_>,
    target: Size,
    threads: Threads,
    changes: [bool; 2],
    across: impl FnOnce() -> Axis,
    down: impl FnOnce() -> Axis,
) -> Image {
    let tw = target.width as usize;
    let px = src.pixels();
    let mut out = Image::new(target);
    debug_assert!(
        (changes[0] || target.width == src.width())
            && (changes[1] || target.height == src.height()),
        "an axis left alone keeps its length"
    );
    let (across, down) = (
        (changes[0] || !changes[1]).then(across),
        changes[1].then(down),
    );
    let Some(down) = down else {
        // Across only, rounded straight into the output.
        let across = across.expect("an axis changes").padded();
        in_bands(out.pixels_mut(), tw, threads, |first, band| {
            across_rounded(&across, px, first, band)
        });
        return out;
    };
    // Down, from the rows across makes (an axis that keeps its size is copied).
    let across = across.map(Axis::padded);
    in_bands(out.pixels_mut(), tw, threads, |first, band| {
        both_rounded(across.as_ref(), &down, px, tw, first, band)
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_band_is_copied_and_the_rest_is_the_linear_resize_moved_by_whole_pixels() {
        let size = Size::new(200, 20).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        let mut v = 7u32;
        for y in 0..20 {
            for x in 0..200 {
                v = v.wrapping_mul(1_103_515_245).wrapping_add(12345);
                let g = (v >> 24) as u8;
                img.set(x, y, [g, g / 2, 255 - g, 255]);
            }
        }
        let target = Size::new(100, 20).unwrap();
        let map = CanvasMap {
            // The gaps give the band just what it needs: the plot keeps the linear scale.
            x: AxisMap::with_bands(200, 100, &[[10, 40]], &[[0, 10], [40, 70]], &[[0, 10]]),
            y: AxisMap::linear(20, 20),
        };
        let out = resize_mapped(img.as_ref(), target, &map);
        let at = map.x.apply(10.0) as u32;
        assert_eq!(map.x.apply(10.0), at as f64);
        for x in 0..30 {
            for y in 0..20 {
                assert_eq!(out.get(at + x, y), img.get(10 + x, y), "band column {x}");
            }
        }
        let linear = resize_linear(img.as_ref(), target);
        let shift = map.x.apply(100.0) - 50.0;
        assert_eq!(shift.fract(), 0.0);
        for x in 52..98 {
            let moved = (x as f64 + shift) as u32;
            for y in 0..20 {
                assert_eq!(out.get(moved, y), linear.get(x, y), "plot column {x}");
            }
        }
    }

    /// Far from an edge each side keeps its colour; at the edge the filter overshoots by at
    /// most what Catmull-Rom's lobes weigh (under a tenth of the step).
    #[test]
    fn flat_stays_flat_and_edges_overshoot_as_catmull_rom_does() {
        let size = Size::new(40, 10).unwrap();
        let mut img = Image::filled(size, [200, 200, 200, 255]);
        for y in 0..10 {
            for x in 20..40 {
                img.set(x, y, [20, 20, 20, 255]);
            }
        }
        for target in [Size::new(17, 10).unwrap(), Size::new(97, 23).unwrap()] {
            let out = resize_linear(img.as_ref(), target);
            for p in out.pixels() {
                assert!(
                    (20 - 18..=200 + 18).contains(&p[0]),
                    "{p:?} overshoots more than the lobes weigh"
                );
            }
            // Far from the edge, each side keeps its colour.
            assert_eq!(out.get(0, 0), [200, 200, 200, 255]);
            assert_eq!(out.get(target.width - 1, 0), [20, 20, 20, 255]);
        }
    }

    #[test]
    fn an_axis_that_keeps_its_size_is_left_alone() {
        // Each row one colour, each column another shade: halving the width keeps every row's
        // colour exactly, and 60 % height keeps every column's.
        let size = Size::new(40, 30).unwrap();
        let data: Vec<[u8; 4]> = (0..30u8)
            .flat_map(|y| (0..40u8).map(move |x| [y * 8, x * 6, 0, 255]))
            .collect();
        let img = Image::from_pixels(size, data).unwrap();
        let out = resize_linear(img.as_ref(), Size::new(20, 30).unwrap());
        for y in 0..30u32 {
            assert!((0..20).all(|x| out.get(x, y)[0] == y as u8 * 8), "row {y}");
        }
        let out = resize_linear(img.as_ref(), Size::new(40, 18).unwrap());
        for x in 0..40u32 {
            assert!(
                (0..18).all(|y| out.get(x, y)[1] == x as u8 * 6),
                "column {x}"
            );
        }
    }

    /// An axis whose length stays but whose map does not (a free picture's plot narrowed
    /// into wider margins) is resampled by its map, not copied.
    #[test]
    fn an_axis_of_the_same_length_follows_its_map() {
        let size = Size::new(100, 40).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        for y in 0..40 {
            for x in 30..32 {
                img.set(x, y, [0, 0, 0, 255]);
            }
        }
        let map = CanvasMap {
            x: AxisMap::with_scales(
                100,
                100,
                [&[], &[[0, 20], [80, 100]], &[[0, 20], [80, 100]]],
                [1.0, 1.0, 0.5],
            ),
            y: AxisMap::linear(40, 20),
        };
        let out = resize_mapped(img.as_ref(), Size::new(100, 20).unwrap(), &map);
        let darkest = (0..100).min_by_key(|&x| out.get(x, 10)[0]).unwrap();
        let want = map.x.apply(31.0);
        assert!(
            (darkest as f64 + 0.5 - want).abs() <= 1.0,
            "{darkest} {want}"
        );
        assert!((want - 31.0).abs() > 3.0, "the map moves the line");
    }

    #[test]
    fn halving_averages_pairs() {
        let size = Size::new(8, 1).unwrap();
        let data: Vec<[u8; 4]> = (0..8u8).map(|i| [i * 20, 0, 0, 255]).collect();
        let img = Image::from_pixels(size, data).unwrap();
        let out = resize_linear(img.as_ref(), Size::new(4, 1).unwrap());
        // A ramp stays a ramp, each sample near the mean of the pair it stands for.
        for x in 1..3u32 {
            let want = (40 * x + 10) as i32;
            assert!(
                (out.get(x, 0)[0] as i32 - want).abs() <= 2,
                "{x}: {:?}",
                out.get(x, 0)
            );
        }
    }

    /// The resize as its formula reads, one sample at a time: the taps in order, the across
    /// pass kept in floats.
    fn reference(src: &Image, target: Size) -> Image {
        let (sw, sh) = (src.width() as usize, src.height() as usize);
        let (tw, th) = (target.width as usize, target.height as usize);
        let one = |axis: &Axis, i: usize, at: &dyn Fn(usize) -> [f32; 4]| {
            let t = &axis.taps[i];
            let mut acc = [0f32; 4];
            for (k, &w) in axis.weights[t.weights.clone()].iter().enumerate() {
                let v = at(t.start + k);
                for c in 0..4 {
                    acc[c] += w * v[c];
                }
            }
            acc
        };
        let (across, down) = (Axis::new(sw, tw), Axis::new(sh, th));
        let px = |x: usize, y: usize| src.get(x as u32, y as u32).map(f32::from);
        let mid: Vec<[f32; 4]> = (0..sh * tw)
            .map(|i| match tw == sw {
                true => px(i % tw, i / tw),
                false => one(&across, i % tw, &|j| px(j, i / tw)),
            })
            .collect();
        let data = (0..th * tw)
            .map(|i| {
                let v = match th == sh {
                    true => mid[i],
                    false => one(&down, i / tw, &|j| mid[j * tw + i % tw]),
                };
                v.map(|c| ((c * 257.0 + 0.5).clamp(0.0, 65_535.5) as u32 / 257) as u8)
            })
            .collect();
        Image::from_pixels(target, data).unwrap()
    }

    #[test]
    fn a_band_of_rows_is_the_same_rows_of_the_whole() {
        // Threads resample bands of output rows, each making its own ring of source rows.
        let (sw, sh, tw, th) = (37, 91, 23, 40);
        let px: Vec<[u8; 4]> = (0..sw * sh)
            .map(|i| {
                [
                    (i * 7 % 256) as u8,
                    (i * 13 % 256) as u8,
                    (i % 251) as u8,
                    255,
                ]
            })
            .collect();
        let (across, down) = (Axis::new(sw, tw).padded(), Axis::new(sh, th));
        let mut whole = vec![[0u8; 4]; th * tw];
        both_rounded(Some(&across), &down, &px, tw, 0, &mut whole);
        for split in [1, 17, 39] {
            let mut parts = vec![[0u8; 4]; th * tw];
            let (top, bottom) = parts.split_at_mut(split * tw);
            both_rounded(Some(&across), &down, &px, tw, 0, top);
            both_rounded(Some(&across), &down, &px, tw, split, bottom);
            assert!(parts == whole, "split at {split}");
        }
    }

    #[test]
    fn rows_quantize_as_imagemagick_writes_them() {
        // Exact levels stay; between two, the level below unless within half a 16-bit step
        // of the one above; past the ends, the ends.
        let row = [[0.0, 255.0, 100.0, 100.6], [100.999, 100.997, -3.0, 300.0]];
        let mut out = [[0u8; 4]; 2];
        round_row(&row, &mut out);
        assert_eq!(out, [[0, 255, 100, 100], [101, 100, 0, 255]]);
        // Every level and its neighbouring floats, and a fine sweep, against the formula in
        // double precision.
        // Every level, every place the output steps (`j - 0.5 / 257`), and the floats
        // beside them.
        let levels = (-4..260).flat_map(|k| {
            let (h, step) = (k as f32, k as f32 - 0.5 / 257.0);
            [
                h.next_down(),
                h,
                h.next_up(),
                step.next_down(),
                step,
                step.next_up(),
            ]
        });
        let sweep = (0..200_000).map(|i| -20.0 + i as f32 * 0.0015);
        let values: Vec<f32> = levels.chain(sweep).collect();
        let row: Vec<[f32; 4]> = values
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        let mut out = vec![[0u8; 4]; row.len()];
        round_row(&row, &mut out);
        for (&v, &o) in row.as_flattened().iter().zip(out.as_flattened()) {
            let q = (v as f64 * 257.0 + 0.5).floor().clamp(0.0, 65_535.0);
            let want = (q / 257.0).floor() as u8;
            // Within a float's step (at 257 v, up to 1/256) of a 16-bit half-level either
            // side may come out.
            let f = (v as f64 * 257.0 + 0.5).fract();
            assert!(
                o == want || !(5e-3..=1.0 - 5e-3).contains(&f),
                "{v}: {o} {want}"
            );
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
        /// The row loops, the flat float loops and the row rounding give the bytes of the
        /// formula, shrinking or growing either axis or both.
        #[test]
        fn the_fast_loops_give_the_formulas_bytes(
            sw in 1u32..90, sh in 1u32..90, tw in 1u32..90, th in 1u32..90, seed: u32,
        ) {
            let data = crate::image::noise_pixels((sw * sh) as usize, seed);
            let img = Image::from_pixels(Size::new(sw, sh).unwrap(), data).unwrap();
            let target = Size::new(tw, th).unwrap();
            let (fast, slow) = (resize_linear(img.as_ref(), target), reference(&img, target));
            proptest::prop_assert!(fast.pixels() == slow.pixels());
        }

        /// The loops compiled for AVX (where this processor has it) and for the baseline
        /// give the same bytes: a picture does not depend on the machine that drew it. (On a
        /// processor without AVX both calls run the baseline, and this holds trivially.)
        #[test]
        fn every_build_of_the_loops_gives_the_same_bytes(
            sw in 1u32..70, sh in 1u32..70, tw in 1u32..70, th in 1u32..70, seed: u32,
        ) {
            let px = crate::image::noise_pixels((sw * sh) as usize, seed);
            let (sw, sh, tw, th) = (sw as usize, sh as usize, tw as usize, th as usize);
            let across = Axis::new(sw, tw).padded();
            let (mut a, mut b) = (vec![[0u8; 4]; sh * tw], vec![[0u8; 4]; sh * tw]);
            across_rounded(&across, &px, 0, &mut a);
            across_rounded_body(&across, &px, 0, &mut b);
            proptest::prop_assert!(a == b);
            let down = Axis::new(sh, th);
            for across in [Some(&across), None] {
                let w = if across.is_some() { tw } else { sw };
                let (mut a, mut b) = (vec![[0u8; 4]; th * w], vec![[0u8; 4]; th * w]);
                both_rounded(across, &down, &px, w, 0, &mut a);
                both_rounded_body(across, &down, &px, w, 0, &mut b);
                proptest::prop_assert!(a == b);
            }
        }
    }
}
