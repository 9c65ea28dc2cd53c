//! Palettes and dithering for GIF output.
//!
//! **Palette.** Visualizations are mostly flat colours (backgrounds, marks, text) plus a few
//! gradients and anti-aliased edges. Colours covering at least 0.2% of the frame (up to 64)
//! are kept exactly, so flat areas never dither; the remaining slots are filled by Wu's
//! method (`quantette`, MIT/Apache) over all other colours, weighted by pixel count. A frame
//! with at most 255 distinct colours keeps them all.
//!
//! **Dithering.** Ordered, not error diffusion: a pixel's index depends only on its colour and
//! position, so a static area maps to the same indices in every frame (no shimmer, and the GIF
//! writer can leave unchanged pixels transparent), and a change never ripples into pixels
//! below it as Floyd-Steinberg's error does. Each colour is drawn as a mix of two palette
//! entries: its nearest `p1` and the entry `p2` whose segment from `p1` passes closest to it,
//! in proportion `f` (the position of the colour along the segment) through an 8x8 Bayer
//! matrix. A penalty on the mix's own variance keeps far-apart entries from being mixed.
//! Colours within a level of an entry are not dithered. That gives smooth gradients
//! with no banding and clean flat areas.
//!
//! **Speed.** Each distinct colour's mix is computed once and kept in a hash map; it searches
//! only the 8 entries nearest to the colour's 6-bit-per-channel cell of RGB space (kept, lazily,
//! in a 64³ table), not the whole palette. Runs of equal pixels reuse the last answer.
//! Computing the mix per cell instead of per colour was tried first: it is faster but turns a
//! gradient into 4-level steps, visible as bands on dark gradients.

use quantette::deps::palette::Srgb;
use quantette::wu::{BinnerU8x3, WuU8x3};
use quantette::{PaletteCounts, PaletteSize};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Largest palette: 255 colours and one transparent index.
pub(crate) const MAX_COLORS: usize = 255;

/// Per-channel weights of the colour distance (squared weights 2, 4, 3: the eye is most
/// sensitive to green, least to blue).
const WEIGHT: [f32; 3] = [std::f32::consts::SQRT_2, 2.0, 1.732_050_8];

/// Below this weighted squared distance to an entry a colour is not dithered (one level off
/// in one channel): JPEG noise on a flat background does not turn into speckles.
const EXACT_D2: f32 = 6.0;

/// Penalty on mixing two entries far apart, times the mixture's variance.
const MIX_PENALTY: f32 = 0.05;

/// 8x8 Bayer matrix, thresholds 0..63.
const BAYER: [[u8; 8]; 8] = [
    [0, 32, 8, 40, 2, 34, 10, 42],
    [48, 16, 56, 24, 50, 18, 58, 26],
    [12, 44, 4, 36, 14, 46, 6, 38],
    [60, 28, 52, 20, 62, 30, 54, 22],
    [3, 35, 11, 43, 1, 33, 9, 41],
    [51, 19, 59, 27, 49, 17, 57, 25],
    [15, 47, 7, 39, 13, 45, 5, 37],
    [63, 31, 55, 23, 61, 29, 53, 21],
];

/// A multiplicative hasher for packed colours (the standard SipHash is 5x slower here).
#[derive(Default)]
pub(crate) struct ColorHasher(u64);
impl Hasher for ColorHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(5) ^ b as u64).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
        }
    }
    fn write_u32(&mut self, n: u32) {
        self.0 = (n as u64 ^ 0x9e37_79b9).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}
type ColorMap<V> = HashMap<u32, V, BuildHasherDefault<ColorHasher>>;

#[inline]
pub(crate) fn pack(p: [u8; 4]) -> u32 {
    u32::from_le_bytes([p[0], p[1], p[2], 0])
}

/// Builds a palette of at most `max` colours for the opaque pixels (alpha >= 128).
pub(crate) fn build_palette(pixels: &[[u8; 4]], max: usize) -> Vec<[u8; 3]> {
    let max = max.clamp(1, MAX_COLORS);
    let mut counts: ColorMap<u32> = ColorMap::default();
    let mut run: Option<(u32, u32)> = None;
    for &p in pixels.iter().filter(|p| p[3] >= 128) {
        let c = pack(p);
        match &mut run {
            Some((rc, n)) if *rc == c => *n += 1,
            _ => {
                if let Some((rc, n)) = run {
                    *counts.entry(rc).or_insert(0) += n;
                }
                run = Some((c, 1));
            }
        }
    }
    if let Some((rc, n)) = run {
        *counts.entry(rc).or_insert(0) += n;
    }
    let unpack = |c: u32| {
        let b = c.to_le_bytes();
        [b[0], b[1], b[2]]
    };
    let mut by_count: Vec<(u32, u32)> = counts.into_iter().collect();
    // Most frequent first; ties by colour so the palette is deterministic.
    by_count.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    if by_count.len() <= max {
        return by_count.into_iter().map(|(c, _)| unpack(c)).collect();
    }
    let total: u64 = by_count.iter().map(|&(_, n)| n as u64).sum();
    let dominant = by_count
        .iter()
        .take_while(|&&(_, n)| n as u64 * 500 >= total)
        .take(64.min(max / 2))
        .count();
    let mut palette: Vec<[u8; 3]> = by_count[..dominant]
        .iter()
        .map(|&(c, _)| unpack(c))
        .collect();
    let rest = &by_count[dominant..];
    let colors: Vec<Srgb<u8>> = rest
        .iter()
        .map(|&(c, _)| {
            let [r, g, b] = unpack(c);
            Srgb::new(r, g, b)
        })
        .collect();
    let weights: Vec<u32> = rest.iter().map(|&(_, n)| n).collect();
    let k = PaletteSize::from_usize_clamped(max - dominant);
    if let Ok(pc) = PaletteCounts::new(colors, weights) {
        if let Some(wu) = WuU8x3::run_palette_counts(&pc, BinnerU8x3::<32, 32, 32>::new()) {
            for c in wu.palette(k).as_slice() {
                let c = [c.red, c.green, c.blue];
                if !palette.contains(&c) {
                    palette.push(c);
                }
            }
        }
    }
    palette.truncate(max);
    palette
}

/// Maps colours to palette indices with ordered dithering, for one palette.
pub(crate) struct Quantizer {
    colors: Vec<[u8; 3]>,
    weighted: Vec<[f32; 3]>,
    /// Mixes of the colours seen so far (palette colours map to themselves).
    memo: ColorMap<Mix>,
    /// Per 6-bit cell: 0 = not computed yet, else 1 + the index of its candidates.
    cells: Vec<u32>,
    candidates: Vec<[u8; CANDIDATES]>,
}

/// Entries considered for the colours of one cell.
const CANDIDATES: usize = 8;

/// The memo is cleared past this many colours (a photo-like stream), bounding memory.
const MAX_MEMO: usize = 1 << 20;

/// One colour's answer: two entries, the share of the second, and how far the mix is from
/// the colour (weighted units).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct Mix(u32);

impl Mix {
    const VALID: u32 = 1 << 23;
    fn new(p1: u8, p2: u8, f: u8, residual: u8) -> Mix {
        Mix(Self::VALID | (residual as u32) << 24 | (f as u32) << 16 | (p2 as u32) << 8 | p1 as u32)
    }
    /// The index at `(x, y)`.
    #[inline]
    pub(crate) fn at(self, x: usize, y: usize) -> u8 {
        let f = ((self.0 >> 16) & 0x7f) as u8;
        if BAYER[y & 7][x & 7] < f {
            (self.0 >> 8) as u8
        } else {
            self.0 as u8
        }
    }
    /// Distance from the colour to what the mix shows, in weighted units.
    #[inline]
    pub(crate) fn residual(self) -> u32 {
        self.0 >> 24
    }
}

impl Quantizer {
    pub(crate) fn new(colors: Vec<[u8; 3]>) -> Quantizer {
        assert!(!colors.is_empty() && colors.len() <= MAX_COLORS);
        let weighted = colors
            .iter()
            .map(|&c| weigh([c[0] as f32, c[1] as f32, c[2] as f32]))
            .collect();
        let mut q = Quantizer {
            colors,
            weighted,
            memo: ColorMap::default(),
            cells: vec![0; 1 << 18],
            candidates: Vec::new(),
        };
        q.remember_palette();
        q
    }

    fn remember_palette(&mut self) {
        self.memo.clear();
        // The first of duplicates wins.
        for (i, &c) in self.colors.iter().enumerate().rev() {
            self.memo.insert(
                pack([c[0], c[1], c[2], 0]),
                Mix::new(i as u8, i as u8, 0, 0),
            );
        }
    }

    pub(crate) fn colors(&self) -> &[[u8; 3]] {
        &self.colors
    }

    /// The transparent index: one past the colours.
    pub(crate) fn transparent(&self) -> u8 {
        self.colors.len() as u8
    }

    /// The palette as GIF wants it: RGB triples, the transparent slot last.
    pub(crate) fn gif_palette(&self) -> Vec<u8> {
        let mut out: Vec<u8> = self.colors.iter().flatten().copied().collect();
        out.extend_from_slice(&[0, 0, 0]);
        out
    }

    /// The mix for a packed colour (see [`pack`]).
    #[inline]
    pub(crate) fn mix(&mut self, c: u32) -> Mix {
        if let Some(&m) = self.memo.get(&c) {
            return m;
        }
        let [r, g, b, _] = c.to_le_bytes();
        let cell = ((r as usize >> 2) << 12) | ((g as usize >> 2) << 6) | (b as usize >> 2);
        if self.cells[cell] == 0 {
            let centre = weigh([
                (r >> 2) as f32 * 4.0 + 1.5,
                (g >> 2) as f32 * 4.0 + 1.5,
                (b >> 2) as f32 * 4.0 + 1.5,
            ]);
            self.candidates.push(self.nearest(centre));
            self.cells[cell] = self.candidates.len() as u32;
        }
        let cands = self.candidates[self.cells[cell] as usize - 1];
        let m = self.compute(weigh([r as f32, g as f32, b as f32]), &cands);
        if self.memo.len() >= MAX_MEMO {
            self.remember_palette();
        }
        self.memo.insert(c, m);
        m
    }

    /// The entries nearest to `c` (repeating the last when the palette is smaller).
    fn nearest(&self, c: [f32; 3]) -> [u8; CANDIDATES] {
        let mut best = [(f32::INFINITY, 0u8); CANDIDATES];
        for (i, p) in self.weighted.iter().enumerate() {
            let d = d2(c, *p);
            if d < best[CANDIDATES - 1].0 {
                let mut k = CANDIDATES - 1;
                while k > 0 && best[k - 1].0 > d {
                    best[k] = best[k - 1];
                    k -= 1;
                }
                best[k] = (d, i as u8);
            }
        }
        let mut out = [0u8; CANDIDATES];
        for k in 0..CANDIDATES {
            out[k] = if best[k].0.is_finite() {
                best[k].1
            } else {
                out[k.saturating_sub(1)]
            };
        }
        out
    }

    /// The mix for `c` (weighted) among `cands`.
    fn compute(&self, c: [f32; 3], cands: &[u8; CANDIDATES]) -> Mix {
        let (p1, d1) = cands
            .iter()
            .map(|&i| (i as usize, d2(c, self.weighted[i as usize])))
            .fold(
                (0, f32::INFINITY),
                |best, x| if x.1 < best.1 { x } else { best },
            );
        let residual = |d: f32| d.max(0.0).sqrt().min(255.0) as u8;
        if d1 <= EXACT_D2 || self.colors.len() == 1 {
            return Mix::new(p1 as u8, p1 as u8, 0, residual(d1));
        }
        let a = self.weighted[p1];
        let e = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let (mut best, mut best_score, mut best_perp) = ((p1, 0.0f32), d1, d1);
        for &j in cands {
            let j = j as usize;
            if j == p1 {
                continue;
            }
            let q = self.weighted[j];
            let v = [q[0] - a[0], q[1] - a[1], q[2] - a[2]];
            let len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            if len2 <= 0.0 {
                continue;
            }
            let t = (e[0] * v[0] + e[1] * v[1] + e[2] * v[2]) / len2;
            if t <= 0.0 {
                continue;
            }
            let t = t.min(1.0);
            let r = [e[0] - t * v[0], e[1] - t * v[1], e[2] - t * v[2]];
            let perp = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
            let score = perp + MIX_PENALTY * t * (1.0 - t) * len2;
            if score < best_score {
                best = (j, t);
                best_score = score;
                best_perp = perp;
            }
        }
        let f = (best.1 * 64.0).round() as u8;
        Mix::new(p1 as u8, best.0 as u8, f.min(64), residual(best_perp))
    }
}

fn d2(a: [f32; 3], b: [f32; 3]) -> f32 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}

fn weigh(c: [f32; 3]) -> [f32; 3] {
    [c[0] * WEIGHT[0], c[1] * WEIGHT[1], c[2] * WEIGHT[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn few_colours_are_kept_exactly() {
        let px: Vec<[u8; 4]> = (0..1000)
            .map(|i| [(i % 7) as u8 * 30, 5, 200, 255])
            .chain([[9, 9, 9, 0]]) // transparent: not in the palette
            .collect();
        let pal = build_palette(&px, 255);
        assert_eq!(pal.len(), 7);
        let mut q = Quantizer::new(pal.clone());
        for (i, c) in pal.iter().enumerate() {
            let m = q.mix(pack([c[0], c[1], c[2], 255]));
            for (x, y) in [(0, 0), (3, 5), (7, 7)] {
                assert_eq!(m.at(x, y), i as u8);
            }
            assert_eq!(m.residual(), 0);
        }
        assert_eq!(q.transparent(), 7);
    }

    #[test]
    fn gradient_dithers_in_proportion_and_dominant_colours_stay_exact() {
        // A horizontal grey ramp 0..255 over 512 px, plus a large flat orange area.
        let mut px = Vec::new();
        for _y in 0..64 {
            for x in 0..512 {
                px.push([(x / 2) as u8, (x / 2) as u8, (x / 2) as u8, 255]);
            }
            px.extend(std::iter::repeat_n([250, 128, 14, 255], 256));
        }
        let pal = build_palette(&px, 16); // few entries: dithering must make up for it
        assert!(
            pal.contains(&[250, 128, 14]),
            "dominant colour kept: {pal:?}"
        );
        let mut q = Quantizer::new(pal.clone());
        // Mean shown grey over an 8x8 tile follows the ramp closely at every level.
        let greys: Vec<u32> = pal
            .iter()
            .filter(|c| c[0] == c[1])
            .map(|c| c[1] as u32)
            .collect();
        let (lo, hi) = (*greys.iter().min().unwrap(), *greys.iter().max().unwrap());
        assert!(
            lo <= 16 && hi >= 239,
            "the ramp's ends are covered: {greys:?}"
        );
        let mut worst = 0.0f32;
        for level in (lo..=hi).step_by(3) {
            let m = q.mix(pack([level as u8, level as u8, level as u8, 255]));
            let mut sum = 0.0;
            for y in 0..8 {
                for x in 0..8 {
                    sum += pal[m.at(x, y) as usize][1] as f32;
                }
            }
            worst = worst.max((sum / 64.0 - level as f32).abs());
        }
        assert!(worst <= 4.0, "mean over a tile is off by {worst}: {pal:?}");
        // The flat colour is never dithered.
        let m = q.mix(pack([250, 128, 14, 255]));
        let i = pal.iter().position(|&c| c == [250, 128, 14]).unwrap() as u8;
        assert!((0..8).all(|y| (0..8).all(|x| m.at(x, y) == i)));
    }
}
