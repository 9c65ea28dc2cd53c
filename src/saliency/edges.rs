//! The edge half of the context detector (§4.2, Eq. 3–4): Sobel magnitude on L, then a 7×7 max
//! (dilation of radius 3) so that thin edges are wide enough to hold triangles.

/// Sobel magnitude of `l` into `out` (borders clamped).
pub(crate) fn sobel(l: &[f32], w: usize, h: usize, out: &mut Vec<f32>) {
    out.clear();
    out.resize(w * h, 0.0);
    for y in 0..h {
        let up = &l[y.saturating_sub(1) * w..][..w];
        let mid = &l[y * w..][..w];
        let down = &l[(y + 1).min(h - 1) * w..][..w];
        let orow = &mut out[y * w..][..w];
        for x in 0..w {
            let xl = x.saturating_sub(1);
            let xr = (x + 1).min(w - 1);
            let gx = (up[xr] + 2.0 * mid[xr] + down[xr]) - (up[xl] + 2.0 * mid[xl] + down[xl]);
            let gy = (down[xl] + 2.0 * down[x] + down[xr]) - (up[xl] + 2.0 * up[x] + up[xr]);
            orow[x] = (gx * gx + gy * gy).sqrt();
        }
    }
}

/// Square max filter of radius `r` (a `(2r+1)²` window), separable, into `out`.
pub(crate) fn dilate(
    src: &[f32],
    w: usize,
    h: usize,
    r: usize,
    tmp: &mut Vec<f32>,
    out: &mut Vec<f32>,
) {
    tmp.clear();
    tmp.resize(w * h, 0.0);
    out.clear();
    out.resize(w * h, 0.0);
    for (srow, trow) in src.chunks_exact(w).zip(tmp.chunks_exact_mut(w)) {
        for x in 0..w {
            let lo = x.saturating_sub(r);
            let hi = (x + r).min(w - 1);
            trow[x] = srow[lo..=hi].iter().copied().fold(0.0, f32::max);
        }
    }
    for y in 0..h {
        let lo = y.saturating_sub(r);
        let hi = (y + r).min(h - 1);
        let orow = &mut out[y * w..][..w];
        orow.copy_from_slice(&tmp[lo * w..][..w]);
        for yy in lo + 1..=hi {
            for (o, &t) in orow.iter_mut().zip(&tmp[yy * w..][..w]) {
                *o = o.max(t);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sobel_of_a_step() {
        let (w, h) = (6, 3);
        let l: Vec<f32> = (0..w * h)
            .map(|i| if i % w >= 3 { 10.0 } else { 0.0 })
            .collect();
        let mut o = Vec::new();
        sobel(&l, w, h, &mut o);
        assert_eq!(o[w + 2], 40.0);
        assert_eq!(o[w + 3], 40.0);
        assert_eq!(o[w], 0.0);
        assert_eq!(o[w + 5], 0.0);
    }

    #[test]
    fn dilation_spreads_a_point_to_a_square() {
        let (w, h) = (11, 11);
        let mut s = vec![0.0f32; w * h];
        s[5 * w + 5] = 1.0;
        let (mut t, mut o) = (Vec::new(), Vec::new());
        dilate(&s, w, h, 3, &mut t, &mut o);
        for y in 0..h {
            for x in 0..w {
                let inside = (2..=8).contains(&x) && (2..=8).contains(&y);
                assert_eq!(o[y * w + x], if inside { 1.0 } else { 0.0 }, "({x},{y})");
            }
        }
    }
}
