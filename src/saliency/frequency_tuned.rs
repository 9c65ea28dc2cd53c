//! The importance detector of §4.1 (Eq. 1–2): frequency-tuned saliency (Achanta et al.) on the
//! feature vector `[L, a, b, m]`.
//!
//! `S_m = ‖mean(feature) − blur(feature)‖₂`: the image mean stands for `G(∞)`, a 3×3 binomial
//! blur (`¼[1,2,1]` separable) for `G(ε)`. The blur is the only smoothing: visualizations are
//! sharp, so the paper skips denoising.

use super::lab::FeaturePlanes;

/// Horizontal then vertical `¼[1,2,1]` of one plane into `out`, clamping at the borders.
/// `tmp` holds the horizontal pass.
fn blur3(src: &[f32], w: usize, h: usize, tmp: &mut Vec<f32>, out: &mut Vec<f32>) {
    tmp.clear();
    tmp.resize(w * h, 0.0);
    out.clear();
    out.resize(w * h, 0.0);
    for (srow, trow) in src.chunks_exact(w).zip(tmp.chunks_exact_mut(w)) {
        if w == 1 {
            trow[0] = srow[0];
            continue;
        }
        trow[0] = 0.75 * srow[0] + 0.25 * srow[1];
        for x in 1..w - 1 {
            trow[x] = 0.25 * (srow[x - 1] + srow[x + 1]) + 0.5 * srow[x];
        }
        trow[w - 1] = 0.75 * srow[w - 1] + 0.25 * srow[w - 2];
    }
    for y in 0..h {
        let up = &tmp[y.saturating_sub(1) * w..][..w];
        let mid = &tmp[y * w..][..w];
        let down = &tmp[(y + 1).min(h - 1) * w..][..w];
        let orow = &mut out[y * w..][..w];
        for x in 0..w {
            orow[x] = 0.25 * (up[x] + down[x]) + 0.5 * mid[x];
        }
    }
}

/// Scratch for [`importance`].
#[derive(Default)]
pub(crate) struct Scratch {
    tmp: Vec<f32>,
    blurred: Vec<f32>,
}

/// Writes unnormalized `S_m` (in Lab units) into `out`.
pub(crate) fn importance(
    f: &FeaturePlanes,
    w: usize,
    h: usize,
    scratch: &mut Scratch,
    out: &mut Vec<f32>,
) {
    let n = w * h;
    out.clear();
    out.resize(n, 0.0);
    for plane in [&f.l, &f.a, &f.b, &f.m] {
        let mean = (plane.iter().map(|&v| v as f64).sum::<f64>() / n as f64) as f32;
        blur3(plane, w, h, &mut scratch.tmp, &mut scratch.blurred);
        for (o, &b) in out.iter_mut().zip(&scratch.blurred) {
            let d = mean - b;
            *o += d * d;
        }
    }
    for o in out.iter_mut() {
        *o = o.sqrt();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blur_keeps_constants_and_sums() {
        let (w, h) = (7, 5);
        let src = vec![3.0f32; w * h];
        let (mut t, mut o) = (Vec::new(), Vec::new());
        blur3(&src, w, h, &mut t, &mut o);
        assert!(o.iter().all(|&v| (v - 3.0).abs() < 1e-6));
        // An impulse spreads as the binomial kernel: centre 1/4, edge neighbours 1/8.
        let mut src = vec![0.0f32; w * h];
        src[2 * w + 3] = 16.0;
        blur3(&src, w, h, &mut t, &mut o);
        assert_eq!(o[2 * w + 3], 4.0);
        assert_eq!(o[2 * w + 2], 2.0);
        assert_eq!(o[w + 2], 1.0);
    }
}
