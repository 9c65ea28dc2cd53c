//! The edge half of the context detector (§4.2, Eq. 3–4): Sobel magnitude on L, then a 7×7 max
//! (dilation of radius 3) so that thin edges are wide enough to hold triangles.

/// Sobel magnitude of the L plane into `out` (borders clamped); returns the largest value.
///
/// Interior pixels run over shifted row slices so that the loop vectorizes; the two border
/// columns are done apart.
pub(crate) fn sobel(l: &[f32], w: usize, h: usize, out: &mut Vec<f32>) -> f32 {
    out.resize(w * h, 0.0);
    let at = |row: &[f32], x: isize| row[x.clamp(0, w as isize - 1) as usize];
    for y in 0..h {
        let up = &l[y.saturating_sub(1) * w..][..w];
        let mid = &l[y * w..][..w];
        let down = &l[(y + 1).min(h - 1) * w..][..w];
        let orow = &mut out[y * w..][..w];
        let one = |x: isize| -> f32 {
            let gx = (at(up, x + 1) + 2.0 * at(mid, x + 1) + at(down, x + 1))
                - (at(up, x - 1) + 2.0 * at(mid, x - 1) + at(down, x - 1));
            let gy = (at(down, x - 1) + 2.0 * at(down, x) + at(down, x + 1))
                - (at(up, x - 1) + 2.0 * at(up, x) + at(up, x + 1));
            (gx * gx + gy * gy).sqrt()
        };
        orow[0] = one(0);
        if w > 1 {
            orow[w - 1] = one(w as isize - 1);
        }
        if w > 2 {
            let n = w - 2;
            let (ul, uc, ur) = (&up[..n], &up[1..n + 1], &up[2..]);
            let (ml, mr) = (&mid[..n], &mid[2..]);
            let (dl, dc, dr) = (&down[..n], &down[1..n + 1], &down[2..]);
            let o = &mut orow[1..n + 1];
            for i in 0..n {
                let gx = (ur[i] + 2.0 * mr[i] + dr[i]) - (ul[i] + 2.0 * ml[i] + dl[i]);
                let gy = (dl[i] + 2.0 * dc[i] + dr[i]) - (ul[i] + 2.0 * uc[i] + ur[i]);
                o[i] = (gx * gx + gy * gy).sqrt();
            }
        }
    }
    super::max_of(out)
}

/// Square max filter of radius `r` (a `(2r+1)²` window) of non-negative values, into `out`.
///
/// Rows: zero-padded (equal to clamping for non-negative values), then a doubling scheme: the
/// max over 2 neighbours, over 4, and a window of `2r+1 ≤ 8` as the max of two overlapping
/// 4-windows (3 comparisons a pixel for r = 3). Columns: an element-wise max of `2r+1` rows,
/// which vectorizes.
pub(crate) fn dilate(
    src: &[f32],
    w: usize,
    h: usize,
    r: usize,
    tmp: &mut Vec<f32>,
    out: &mut Vec<f32>,
) {
    tmp.resize(w * h, 0.0);
    out.resize(w * h, 0.0);
    let n = 2 * r + 1;
    if n <= 8 {
        let mut pad = vec![0f32; w + 2 * r + 8];
        let mut m2 = vec![0f32; w + 2 * r + 8];
        let mut m4 = vec![0f32; w + 2 * r + 8];
        for (srow, trow) in src.chunks_exact(w).zip(tmp.chunks_exact_mut(w)) {
            pad[r..r + w].copy_from_slice(srow);
            let len = w + 2 * r;
            for i in 0..len {
                m2[i] = if pad[i] > pad[i + 1] {
                    pad[i]
                } else {
                    pad[i + 1]
                };
            }
            for i in 0..len {
                m4[i] = if m2[i] > m2[i + 2] { m2[i] } else { m2[i + 2] };
            }
            // Window [x, x + n) in padded coordinates = output x.
            let off = n.saturating_sub(4);
            for x in 0..w {
                trow[x] = if n >= 4 {
                    m4[x].max(m4[x + off])
                } else {
                    pad[x..x + n].iter().copied().fold(0.0, f32::max)
                };
            }
        }
    } else {
        for (srow, trow) in src.chunks_exact(w).zip(tmp.chunks_exact_mut(w)) {
            for (x, t) in trow.iter_mut().enumerate() {
                let lo = x.saturating_sub(r);
                let hi = (x + r).min(w - 1);
                *t = srow[lo..=hi].iter().copied().fold(0.0, f32::max);
            }
        }
    }
    for y in 0..h {
        let lo = y.saturating_sub(r);
        let hi = (y + r).min(h - 1);
        let orow = &mut out[y * w..][..w];
        orow.copy_from_slice(&tmp[lo * w..][..w]);
        for yy in lo + 1..=hi {
            for (o, &t) in orow.iter_mut().zip(&tmp[yy * w..][..w]) {
                *o = if t > *o { t } else { *o };
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

    /// The fast row scheme equals the plain window max, for every radius it handles.
    #[test]
    fn dilation_matches_the_plain_max() {
        let (w, h) = (23, 9);
        let src: Vec<f32> = (0..w * h).map(|i| ((i * 37) % 11) as f32).collect();
        for r in 0..=5 {
            let (mut t, mut o) = (Vec::new(), Vec::new());
            dilate(&src, w, h, r, &mut t, &mut o);
            for y in 0..h {
                for x in 0..w {
                    let mut m = 0f32;
                    for yy in y.saturating_sub(r)..=(y + r).min(h - 1) {
                        for xx in x.saturating_sub(r)..=(x + r).min(w - 1) {
                            m = m.max(src[yy * w + xx]);
                        }
                    }
                    assert_eq!(o[y * w + x], m, "r {r} at ({x},{y})");
                }
            }
        }
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
