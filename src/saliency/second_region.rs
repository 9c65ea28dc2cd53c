//! The second half of the context detector (§4.2, Eq. 5): regions of one flat, light colour
//! (map layers, community hulls) that the importance detector rates low but a reader does not.
//!
//! The histogram of the normalized importance `S_m` has its tallest peak at the background.
//! The paper takes the second tallest peak `p_sec` and gives its pixels `sqrt(p_sec)`. A map has
//! several pastel layers, each its own peak, so every further peak that covers a real share of
//! the canvas (≥ [`LAYER_SHARE`]) is a layer too; the second peak is always one when it covers at
//! least [`MIN_SHARE`] (below that it is anti-aliasing, not a region).

/// Histogram resolution over `[0, 1]`.
pub const BINS: usize = 256;
/// Smallest share of pixels for the second peak to count as a region.
const MIN_SHARE: f64 = 0.002;
/// Smallest share for a further peak to count as another layer.
const LAYER_SHARE: f64 = 0.02;

/// For each histogram bin, the `S_sec` value its pixels get (0 for most bins).
pub(crate) fn second_region_boost(s_m: &[f32]) -> [f32; BINS] {
    let mut boost = [0f32; BINS];
    let mut hist = [0usize; BINS];
    for &v in s_m {
        hist[bin_of(v)] += 1;
    }
    let n = s_m.len().max(1) as f64;
    let tallest = (0..BINS)
        .max_by_key(|&b| (hist[b], usize::MAX - b))
        .unwrap_or(0);
    // Peaks: strictly above the left neighbour, at least the right one.
    let mut peaks: Vec<usize> = (0..BINS)
        .filter(|&b| {
            let left = if b == 0 { 0 } else { hist[b - 1] };
            let right = if b + 1 == BINS { 0 } else { hist[b + 1] };
            hist[b] > 0 && hist[b] > left && hist[b] >= right
        })
        .filter(|&b| b != tallest)
        .collect();
    peaks.sort_by_key(|&b| std::cmp::Reverse(hist[b]));
    for (rank, &b) in peaks.iter().enumerate() {
        let share = hist[b] as f64 / n;
        let counts = if rank == 0 {
            share >= MIN_SHARE
        } else {
            share >= LAYER_SHARE
        };
        if counts {
            let p_sec = (b as f32 + 0.5) / BINS as f32;
            boost[b] = p_sec.sqrt();
        }
    }
    boost
}

#[inline]
pub(crate) fn bin_of(v: f32) -> usize {
    // v is in [0, 1]; the u32 conversion saturates (NaN gives 0).
    ((v * (BINS as f32 - 0.001)) as u32 as usize).min(BINS - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_has_no_second_region() {
        assert!(second_region_boost(&[0.0; 1000]).iter().all(|&b| b == 0.0));
        assert!(second_region_boost(&[0.3; 1000]).iter().all(|&b| b == 0.0));
    }

    #[test]
    fn second_peak_is_boosted_by_its_square_root() {
        let mut s = vec![0.02f32; 10_000];
        s[..2000].fill(0.25);
        s[2000..2050].fill(0.9); // a few marks, not a region
        let boost = second_region_boost(&s);
        let b = bin_of(0.25);
        assert!((boost[b] - ((b as f32 + 0.5) / BINS as f32).sqrt()).abs() < 1e-6);
        assert_eq!(boost[bin_of(0.02)], 0.0);
        assert_eq!(boost[bin_of(0.9)], 0.0);
    }
}
