//! The importance detector of §4.1 (Eq. 1–2): frequency-tuned saliency (Achanta et al.) on the
//! feature vector `[L, a, b, m]`.
//!
//! `S_m = ‖mean(feature) − blur(feature)‖₂`: the image mean stands for `G(∞)`, a 3×3 binomial
//! blur (`¼[1,2,1]` separable) for `G(ε)`. The blur is the only smoothing: visualizations are
//! sharp, so the paper skips denoising.

/// Horizontal `¼[1,2,1]` of one row, borders clamped.
#[inline(always)]
fn hblur(src: &[f32], dst: &mut [f32]) {
    let w = src.len();
    if w == 1 {
        dst[0] = src[0];
        return;
    }
    dst[0] = 0.75 * src[0] + 0.25 * src[1];
    dst[w - 1] = 0.75 * src[w - 1] + 0.25 * src[w - 2];
    let n = w - 2;
    let (l, c, r) = (&src[..n], &src[1..n + 1], &src[2..]);
    for (i, o) in dst[1..n + 1].iter_mut().enumerate() {
        *o = 0.25 * (l[i] + r[i]) + 0.5 * c[i];
    }
}

crate::simd::with_feature! {
    "avx";
    /// Writes unnormalized `S_m` (Lab units) of the feature planes `[L, a, b, m]` into `out`;
    /// returns the largest value. `ring` is scratch.
    ///
    /// Row by row over planes (a ring of three horizontally blurred rows per channel), so that
    /// every inner loop runs over contiguous `f32`s and vectorizes, and the working set stays in
    /// cache.
    pub(crate) fn importance(
        planes: &[Vec<f32>; 4],
        w: usize,
        h: usize,
        mean: [f32; 4],
        ring: &mut Vec<f32>,
        out: &mut Vec<f32>,
    ) -> f32 => importance_body {
        out.resize(w * h, 0.0);
        ring.resize(4 * 3 * w, 0.0);
        let slot = |c: usize, r: usize| (c * 3 + r % 3) * w;
        for (c, plane) in planes.iter().enumerate() {
            for r in 0..2.min(h) {
                let s = slot(c, r);
                hblur(&plane[r * w..][..w], &mut ring[s..s + w]);
            }
        }
        let mut max = 0f32;
        for y in 0..h {
            if y >= 1 && y + 1 < h {
                for (c, plane) in planes.iter().enumerate() {
                    let s = slot(c, y + 1);
                    hblur(&plane[(y + 1) * w..][..w], &mut ring[s..s + w]);
                }
            }
            let (ru, rm, rd) = (y.saturating_sub(1), y, (y + 1).min(h - 1));
            let orow = &mut out[y * w..][..w];
            orow.fill(0.0);
            for c in 0..4 {
                let (up, mid, down) = (
                    &ring[slot(c, ru)..][..w],
                    &ring[slot(c, rm)..][..w],
                    &ring[slot(c, rd)..][..w],
                );
                let m = mean[c];
                for i in 0..w {
                    let d = m - (0.25 * (up[i] + down[i]) + 0.5 * mid[i]);
                    orow[i] += d * d;
                }
            }
            for o in orow.iter_mut() {
                *o = o.sqrt();
            }
            max = max.max(super::max_of(orow));
        }
        max
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_image_has_zero_importance_and_impulse_spreads_binomially() {
        let (w, h) = (7, 5);
        let planes = [3.0f32, 1.0, 2.0, 4.0].map(|v| vec![v; w * h]);
        let (mut t, mut o) = (Vec::new(), Vec::new());
        let max = importance(&planes, w, h, [3.0, 1.0, 2.0, 4.0], &mut t, &mut o);
        assert_eq!(max, 0.0);
        // An impulse in L spreads as the binomial kernel: centre 1/4, edge neighbours 1/8.
        let mut planes: [Vec<f32>; 4] = Default::default();
        for p in planes.iter_mut() {
            p.resize(w * h, 0.0);
        }
        planes[0][2 * w + 3] = 16.0;
        importance(&planes, w, h, [0.0; 4], &mut t, &mut o);
        assert_eq!(o[2 * w + 3], 4.0);
        assert_eq!(o[2 * w + 2], 2.0);
        assert_eq!(o[w + 2], 1.0);
    }

    #[test]
    fn every_build_gives_the_same_map() {
        let (w, h) = (61, 9);
        let mut v = 0x2545_f491u32;
        let planes: [Vec<f32>; 4] = std::array::from_fn(|_| {
            (0..w * h)
                .map(|_| {
                    v ^= v << 13;
                    v ^= v >> 17;
                    v ^= v << 5;
                    (v >> 8) as f32 / 65_536.0
                })
                .collect()
        });
        let mean = [40.0, -3.5, 7.25, 12.0];
        let (mut t, mut wide, mut base) = (Vec::new(), Vec::new(), Vec::new());
        let a = importance(&planes, w, h, mean, &mut t, &mut wide);
        let b = importance_body(&planes, w, h, mean, &mut t, &mut base);
        assert_eq!((a, &wide), (b, &base));
    }
}
