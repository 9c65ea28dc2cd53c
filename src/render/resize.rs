//! A plain linear resize, separable Catmull-Rom (ImageMagick's `-filter Catrom -resize`): the
//! render of a canvas under one linear map. Against the crate's triangle renderer over two
//! triangles (bilinear, box-filtered where it shrinks), it keeps a heat map's 2-px separators
//! and small type apart, and it draws what a reader compares it with.
//!
//! Catmull-Rom's negative lobes overshoot a little at edges, as ImageMagick's do: that
//! overshoot is the filter's crispness. Clamping each sample to its neighbourhood's range
//! (as this resize once did) drew every edge a shade softer than the linear resize a reader
//! compares it with, and judged blind beside it, the softer copy lost the ties.

use super::canvas::{AxisMap, CanvasMap, PanelMap};
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
        Axis { n, taps, weights }
    }
}

/// Fractional bits of [`Across`]'s integer weights. A sum of products of bytes and weights
/// then fits 32 bits (and 24, so its float is exact), and a weight is off its float by
/// under 2⁻¹⁴ ([`Across::new`]): a sample moves by a few hundredths of a level, and comes out
/// one level off the float resize's in about one sample of a hundred that are not flat
/// (where the sum lands beside a level's edge).
const WEIGHT_BITS: u32 = 14;

/// [`WEIGHT_BITS`]' one: every sample's weights sum to it exactly, so flat stays flat.
const ONE: i32 = 1 << WEIGHT_BITS;

/// The taps of an axis resampled along rows, in integers: bytes times 16-bit weights summed
/// in 32 bits, sixteen products to an instruction (`pmaddwd`) where floats took eight, and
/// no row converted to floats first. Integer sums do not depend on their order: every build
/// and every machine gives the same bytes.
struct Across {
    /// Source and output samples.
    n: usize,
    m: usize,
    /// Taps of every sample, made equally many by zero weights before or after a sample's
    /// own taps, inside the row: a multiple of four where the row is that long, so the wide
    /// loop takes four at a time.
    k: usize,
    /// Each sample's first source sample.
    starts: Vec<usize>,
    /// `k` weights per sample, summing to [`ONE`].
    weights: Vec<i16>,
}

impl Across {
    fn new(axis: &Axis) -> Across {
        let n = axis.n;
        let most = (axis.taps.iter().map(|t| t.weights.len()).max()).map_or(0, |k| k.min(n));
        let k = match most.next_multiple_of(4) {
            k4 if k4 <= n => k4,
            _ => most,
        };
        let mut weights = Vec::with_capacity(k * axis.taps.len());
        let starts = (axis.taps.iter())
            .map(|t| {
                let start = t.start.min(n - k);
                let first = weights.len();
                weights.resize(first + (t.start - start), 0);
                // Each weight is the step between the rounded running sums before and after
                // it, the last sum exactly ONE: every weight within a unit of its float, and
                // together exactly ONE however many round to nothing (rounding each weight
                // alone left a remainder that grew with the taps).
                let own = &axis.weights[t.weights.clone()];
                let (mut sum, mut before) = (0f64, 0i32);
                for (j, &w) in own.iter().enumerate() {
                    sum += f64::from(w);
                    let after = match j + 1 == own.len() {
                        true => ONE,
                        false => (sum * f64::from(ONE)).round() as i32,
                    };
                    weights.push((after - before) as i16);
                    before = after;
                }
                weights.resize(first + k, 0);
                start
            })
            .collect();
        Across {
            n,
            m: axis.taps.len(),
            k,
            starts,
            weights,
        }
    }

    /// The sums of each of `R` rows of source samples (`n` each) resampled into `out` (`m`
    /// each): each channel's bytes times the weights, in units of [`ONE`].
    fn sums<const R: usize>(&self, rows: [&[[u8; 4]]; R], out: [&mut [[i32; 4]]; R]) {
        for r in 0..R {
            assert!(rows[r].len() >= self.n && out[r].len() >= self.m);
        }
        #[cfg(target_arch = "x86_64")]
        if self.k.is_multiple_of(4) && std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, checked just above; the rows' lengths are
            // checked above, and `k` is a multiple of four.
            unsafe { self.sums_avx2(rows, out) };
            return;
        }
        for (row, out) in rows.into_iter().zip(out) {
            self.sums_one_by_one(row, out);
        }
    }

    /// [`Across::sums`] of one row, one product at a time: every build's reference.
    #[inline(always)]
    fn sums_one_by_one(&self, row: &[[u8; 4]], out: &mut [[i32; 4]]) {
        let k = self.k;
        for ((o, &start), w) in out.iter_mut().zip(&self.starts).zip(self.weights.chunks(k)) {
            let mut acc = [0i32; 4];
            for (&w, p) in w.iter().zip(&row[start..start + k]) {
                for c in 0..4 {
                    acc[c] += i32::from(w) * i32::from(p[c]);
                }
            }
            *o = acc;
        }
    }

    /// [`Across::sums`] by AVX2, four taps of one sample at a time: their four pixels (16
    /// bytes) spread into two pairs of 16-bit channels, multiplied by two pairs of weights
    /// and summed pairwise (`pmaddwd`), each weight read once for all `R` rows.
    ///
    /// # Safety
    /// The processor has AVX2, `k` is a multiple of four, every row holds `n` samples and
    /// every output row `m`.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn sums_avx2<const R: usize>(&self, rows: [&[[u8; 4]]; R], out: [&mut [[i32; 4]]; R]) {
        use std::arch::x86_64::*;
        // Four pixels (r g b a, four times) in both halves: the low half spreads pixels 0
        // and 1 into 16-bit numbers [r0 r1 g0 g1 b0 b1 a0 a1], the high half pixels 2 and 3.
        let spread_px = _mm256_setr_epi8(
            0, -1, 4, -1, 1, -1, 5, -1, 2, -1, 6, -1, 3, -1, 7, -1, //
            8, -1, 12, -1, 9, -1, 13, -1, 10, -1, 14, -1, 11, -1, 15, -1,
        );
        // Four weights [w0 w1 w2 w3] in every quarter: w0 w1 repeated in the low half, w2
        // w3 in the high half, to meet the pixels' pairs.
        let spread_w = _mm256_setr_epi8(
            0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, //
            4, 5, 6, 7, 4, 5, 6, 7, 4, 5, 6, 7, 4, 5, 6, 7,
        );
        let k = self.k;
        let rows = rows.map(|r| r.as_ptr());
        let out = out.map(|o| o.as_mut_ptr());
        for (x, (&start, w)) in self
            .starts
            .iter()
            .zip(self.weights.chunks_exact(k))
            .enumerate()
        {
            let mut acc = [_mm256_setzero_si256(); R];
            for (g, w) in w.chunks_exact(4).enumerate() {
                // SAFETY: `w` holds four weights (eight bytes).
                let w = unsafe { std::ptr::read_unaligned(w.as_ptr() as *const i64) };
                let w = _mm256_shuffle_epi8(_mm256_set1_epi64x(w), spread_w);
                for r in 0..R {
                    // SAFETY: `start + k <= n` (built so), and the row holds `n` pixels.
                    let p = unsafe { rows[r].add(start + 4 * g) } as *const __m128i;
                    let p = _mm256_broadcastsi128_si256(unsafe { _mm_loadu_si128(p) });
                    let p = _mm256_shuffle_epi8(p, spread_px);
                    acc[r] = _mm256_add_epi32(acc[r], _mm256_madd_epi16(p, w));
                }
            }
            for r in 0..R {
                let lo = _mm256_castsi256_si128(acc[r]);
                let s = _mm_add_epi32(lo, _mm256_extracti128_si256::<1>(acc[r]));
                // SAFETY: `x < m`, and the output row holds `m` samples.
                unsafe { _mm_storeu_si128(out[r].add(x) as *mut __m128i, s) };
            }
        }
    }

    /// Source rows `first..` of `px` resampled into `band`'s rows (`m` each), rounded:
    /// four rows at a time, each weight read once for the four.
    #[inline(always)]
    fn rounded(&self, px: &[[u8; 4]], first: usize, band: &mut [[u8; 4]]) {
        let (n, m) = (self.n, self.m);
        let rows = band.len() / m.max(1);
        let mut sums = vec![[0i32; 4]; 4 * m];
        let src = |y: usize| &px[(first + y) * n..][..n];
        let mut y = 0;
        while y < rows {
            let (s0, rest) = sums.split_at_mut(m);
            let (s1, rest) = rest.split_at_mut(m);
            let (s2, s3) = rest.split_at_mut(m);
            let quad = (rows - y).min(4);
            if quad == 4 {
                self.sums(
                    [src(y), src(y + 1), src(y + 2), src(y + 3)],
                    [s0, s1, s2, s3],
                );
            } else {
                for (r, s) in [s0, s1, s2].into_iter().enumerate().take(quad) {
                    self.sums([src(y + r)], [s]);
                }
            }
            let out = band[y * m..(y + quad) * m].chunks_exact_mut(m);
            for (o, s) in out.zip(sums.chunks_exact(m)) {
                round_sums(s, o);
            }
            y += quad;
        }
    }

    /// One row of source samples resampled into `out` as floats (the sums over [`ONE`],
    /// exact): what the pass down the columns reads. `sums` is scratch space of `m`.
    #[inline(always)]
    fn row(&self, src: &[[u8; 4]], sums: &mut [[i32; 4]], out: &mut [[f32; 4]]) {
        self.sums([src], [&mut *sums]);
        for (o, &s) in out.as_flattened_mut().iter_mut().zip(sums.as_flattened()) {
            *o = s as f32 * (1.0 / ONE as f32);
        }
    }
}

/// Sums of [`Across`] (in units of [`ONE`]) written as bytes the way [`quantize`] writes a
/// float, in integers and exactly: the nearest 16-bit level, `q = ⌊(257 s + ONE/2) / ONE⌋`
/// in 0..=65535, then the 8-bit level below it, `⌊q / 257⌋`. The two floors are one,
/// `⌊(257 s + ONE/2) / (257 ONE)⌋`; with `ONE/2 = 257 h + r` (`r < 257`) and `s + h = a ONE
/// + b` (`0 ≤ b < ONE`) that is `a + (257 b + r) / (257 ONE)`, whose fraction stays below one.
/// So the byte is `⌊(s + h) / ONE⌋`, clamped to 0..=255.
#[inline(always)]
fn round_sums(sums: &[[i32; 4]], out: &mut [[u8; 4]]) {
    const H: i32 = ONE / 2 / 257;
    for (o, &s) in out.as_flattened_mut().iter_mut().zip(sums.as_flattened()) {
        *o = ((s + H) >> WEIGHT_BITS).clamp(0, 255) as u8;
    }
}

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
    "avx2";
    /// Rows `first..` of `px` resampled across into `band`'s rows, rounded (the rounding
    /// eight samples to an instruction where AVX2 multiplies 32-bit lanes).
    fn across_rounded(across: &Across, px: &[[u8; 4]], first: usize, band: &mut [[u8; 4]])
        => across_rounded_body {
        across.rounded(px, first, band)
    }
}

crate::simd::with_feature! {
    "avx";
    /// Output rows `first..` (`band`, rows of `tw`) resampled down from the rows `across`
    /// makes of `px` (copied as floats where `across` is `None`). Each of those rows is made
    /// once into a ring of as many rows as the longest tap: a band reads its rows while they
    /// are in cache, and no picture-sized buffer of floats is filled and read back.
    fn both_rounded(
        across: Option<&Across>,
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
        let (mut sums, mut acc) = (vec![[0i32; 4]; tw], vec![[0f32; 4]; tw]);
        for (t, orow) in taps.iter().zip(band.chunks_exact_mut(tw)) {
            let len = t.weights.len();
            for j in t.start..t.start + len {
                let slot = j % cap;
                if held[slot] == j {
                    continue;
                }
                let (src, dst) = (&px[j * sw..][..sw], &mut ring[slot * tw..][..tw]);
                match across {
                    Some(a) => a.row(src, &mut sums, dst),
                    None => {
                        for (o, &p) in dst.as_flattened_mut().iter_mut().zip(src.as_flattened()) {
                            *o = f32::from(p);
                        }
                    }
                }
                held[slot] = j;
            }
            let weights = &down.weights[t.weights.clone()];
            let ring_row = |k: usize| ring[(t.start + k) % cap * tw..][..tw].as_flattened();
            if weights.len() <= MOST_DOWN_TAPS {
                // Eight floats at a time, all taps summed in registers, then rounded: the
                // row of sums is never stored and read back once per tap.
                let mut rows = [&[][..]; MOST_DOWN_TAPS];
                for (k, r) in rows.iter_mut().enumerate().take(weights.len()) {
                    *r = ring_row(k);
                }
                let rows = &rows[..weights.len()];
                let out = orow.as_flattened_mut();
                let done = out.len() - out.len() % 8;
                let mut chunks = out[..done].chunks_exact_mut(8);
                for (i, o) in (&mut chunks).enumerate() {
                    let mut acc = [0f32; 8];
                    for (r, &w) in rows.iter().zip(weights) {
                        let v: &[f32; 8] = r[8 * i..][..8].try_into().expect("eight");
                        for c in 0..8 {
                            acc[c] += w * v[c];
                        }
                    }
                    for c in 0..8 {
                        o[c] = quantize(acc[c]);
                    }
                }
                for (i, o) in out.iter_mut().enumerate().skip(done) {
                    let sum = rows.iter().zip(weights).fold(0.0, |a, (r, &w)| a + w * r[i]);
                    *o = quantize(sum);
                }
                continue;
            }
            acc.fill([0.0; 4]);
            for (k, &w) in weights.iter().enumerate() {
                // Flat loops over the row's floats: vectors, whatever the channel count.
                for (a, &v) in acc.as_flattened_mut().iter_mut().zip(ring_row(k)) {
                    *a += w * v;
                }
            }
            round_row(&acc, orow);
        }
    }
}

/// Most taps down a column summed in registers ([`both_rounded`]); a wider filter (a
/// picture shrunk to under an eighth) sums row by row.
const MOST_DOWN_TAPS: usize = 32;

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
pub(crate) fn resize_linear_on(src: ImageRef<'_>, target: Size, threads: Threads) -> Image {
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
    if !map.panels.is_empty() {
        return resize_panels(src, target, &map.panels, threads);
    }
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
        let across = Across::new(&across.expect("an axis changes"));
        in_bands(out.pixels_mut(), tw, threads, |first, band| {
            across_rounded(&across, px, first, band)
        });
        return out;
    };
    // Down, from the rows across makes (an axis that keeps its size is copied).
    let across = across.as_ref().map(Across::new);
    in_bands(out.pixels_mut(), tw, threads, |first, band| {
        both_rounded(across.as_ref(), &down, px, tw, first, band)
    });
    out
}

/// `src` resampled onto `target` panel by panel, each in its slot by its own maps.
pub(crate) fn resize_panels(
    src: ImageRef<'_>,
    target: Size,
    panels: &[PanelMap],
    threads: Threads,
) -> Image {
    let mut out = Image::new(target);
    let w = src.width() as usize;
    for p in panels {
        let [x0, y0, x1, y1] = p.src;
        let [sx0, sy0, sx1, sy1] = p.slot;
        let (Ok(size), Ok(into)) = (Size::new(x1 - x0, y1 - y0), Size::new(sx1 - sx0, sy1 - sy0))
        else {
            continue;
        };
        let mut crop = Vec::with_capacity(size.width as usize * size.height as usize);
        for row in src
            .pixels()
            .chunks_exact(w)
            .skip(y0 as usize)
            .take(size.height as usize)
        {
            crop.extend_from_slice(&row[x0 as usize..x1 as usize]);
        }
        let Some(crop) = Image::from_pixels(size, crop) else {
            continue;
        };
        let map = CanvasMap {
            x: p.x.within(x0 as f64, x1 as f64),
            y: p.y.within(y0 as f64, y1 as f64),
            panels: Vec::new(),
        };
        let drawn = resize_mapped_on(crop.as_ref(), into, &map, threads);
        let tw = target.width as usize;
        for (r, row) in drawn.pixels().chunks_exact(into.width as usize).enumerate() {
            let at = (sy0 as usize + r) * tw + sx0 as usize;
            out.pixels_mut()[at..at + row.len()].copy_from_slice(row);
        }
    }
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
            panels: Vec::new(),
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
            panels: Vec::new(),
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
    /// pass in integers (weights in units of [`ONE`]), the pass down in floats.
    fn reference(src: &Image, target: Size) -> Image {
        let (sw, sh) = (src.width() as usize, src.height() as usize);
        let (tw, th) = (target.width as usize, target.height as usize);
        let (across, down) = (Across::new(&Axis::new(sw, tw)), Axis::new(sh, th));
        let sums = |x: usize, y: usize| {
            let w = &across.weights[x * across.k..][..across.k];
            let mut acc = [0i64; 4];
            for (j, &w) in w.iter().enumerate() {
                let v = src.get((across.starts[x] + j) as u32, y as u32);
                for c in 0..4 {
                    acc[c] += w as i64 * v[c] as i64;
                }
            }
            acc
        };
        let data = (0..th * tw)
            .map(|i| {
                let (x, y) = (i % tw, i / tw);
                if th == sh {
                    // Across alone: the sums, to the nearest 16-bit level, to the 8-bit level below.
                    return sums(x, y).map(|s| {
                        let q = ((257 * s + ONE as i64 / 2) as f64 / ONE as f64).floor();
                        (q.clamp(0.0, 65_535.0) / 257.0).floor() as u8
                    });
                }
                let mid = |j: usize| match tw == sw {
                    true => src.get(x as u32, j as u32).map(f32::from),
                    false => sums(x, j).map(|s| s as f32 / ONE as f32),
                };
                let t = &down.taps[y];
                let mut acc = [0f32; 4];
                for (k, &w) in down.weights[t.weights.clone()].iter().enumerate() {
                    let v = mid(t.start + k);
                    for c in 0..4 {
                        acc[c] += w * v[c];
                    }
                }
                acc.map(|c| ((c * 257.0 + 0.5).clamp(0.0, 65_535.5) as u32 / 257) as u8)
            })
            .collect();
        Image::from_pixels(target, data).unwrap()
    }

    /// The integer weights sum to one exactly, and stay within a rounding of the floats.
    #[test]
    fn integer_weights_sum_to_one_and_follow_the_floats() {
        for (n, m) in [
            (1280, 720),
            (37, 23),
            (5, 3),
            (3, 11),
            (1, 4),
            (90, 1),
            (8, 8),
        ] {
            let axis = Axis::new(n, m);
            let across = Across::new(&axis);
            for x in 0..m {
                let w = &across.weights[x * across.k..][..across.k];
                assert_eq!(
                    w.iter().map(|&v| v as i32).sum::<i32>(),
                    ONE,
                    "{n}->{m} {x}"
                );
                assert!(across.starts[x] + across.k <= n);
                // Each float tap is found at its place in the integers, within a unit.
                let t = &axis.taps[x];
                for (j, &f) in axis.weights[t.weights.clone()].iter().enumerate() {
                    let i = w[t.start + j - across.starts[x]];
                    assert!((i as f32 - f * ONE as f32).abs() <= 1.01, "{f} {i}");
                }
            }
        }
    }

    /// The integer rounding is the formula's, for every sum a byte and a weight sum can make.
    #[test]
    fn sums_round_by_the_formula() {
        let sums: Vec<i32> = (-70 * ONE..=320 * ONE)
            .step_by(7)
            .chain([ONE * 255, 0])
            .collect();
        let row: Vec<[i32; 4]> = sums
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        let mut out = vec![[0u8; 4]; row.len()];
        round_sums(&row, &mut out);
        for (&s, &o) in row.as_flattened().iter().zip(out.as_flattened()) {
            let q = ((257 * s as i64 + ONE as i64 / 2) as f64 / ONE as f64).floor();
            assert_eq!(o, (q.clamp(0.0, 65_535.0) / 257.0).floor() as u8, "{s}");
        }
        // Whole levels stay whole.
        let levels: Vec<[i32; 4]> = (0..64)
            .map(|l| [4 * l, 4 * l + 1, 4 * l + 2, 4 * l + 3])
            .collect();
        round_sums(
            &levels
                .iter()
                .map(|l| l.map(|v| v * ONE))
                .collect::<Vec<_>>(),
            &mut out[..64],
        );
        assert!((0..256).all(|v| out.as_flattened()[v] == v as u8));
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
        let (across, down) = (Across::new(&Axis::new(sw, tw)), Axis::new(sh, th));
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

        /// The sums by AVX2 (where this processor has it), four rows or one at a time, are
        /// the sums one product at a time.
        #[test]
        fn the_wide_sums_are_the_one_by_one_sums(
            sw in 1u32..300, tw in 1u32..300, seed: u32,
        ) {
            let (sw, tw) = (sw as usize, tw as usize);
            let px = crate::image::noise_pixels(4 * sw, seed);
            let across = Across::new(&Axis::new(sw, tw));
            let rows: [&[[u8; 4]]; 4] = std::array::from_fn(|r| &px[r * sw..][..sw]);
            let mut want = vec![[0i32; 4]; 4 * tw];
            for (r, w) in want.chunks_exact_mut(tw).enumerate() {
                across.sums_one_by_one(rows[r], w);
            }
            let mut got = vec![[0i32; 4]; 4 * tw];
            let [g0, g1, g2, g3] = got.chunks_exact_mut(tw).collect::<Vec<_>>().try_into().unwrap();
            across.sums(rows, [g0, g1, g2, g3]);
            proptest::prop_assert!(got == want);
            let mut one = vec![[0i32; 4]; tw];
            across.sums([rows[2]], [&mut one]);
            proptest::prop_assert!(one[..] == want[2 * tw..3 * tw]);
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
            let across = Across::new(&Axis::new(sw, tw));
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
