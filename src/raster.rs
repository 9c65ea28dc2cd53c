//! Exact triangle scan conversion in fixed point, shared by the triangle saliency (`λ_t` over
//! the source mesh) and the renderer (the deformed mesh over the output).
//!
//! Vertices live on a 1/4096-px grid and edge functions are evaluated in `i64`, so two
//! triangles sharing an edge see bit-identical edge values: with the tie rule below every pixel
//! centre of the canvas belongs to exactly one triangle (no cracks, no seams drawn twice), which
//! floating-point edge functions cannot promise. Solved positions are snapped to this grid
//! before the fold-over check, so the check and the renderer judge the same triangles.

/// Sub-pixel bits of the fixed-point grid.
pub const SUBPIXEL_BITS: u32 = 12;
/// One pixel in fixed-point units.
pub const ONE: i64 = 1 << SUBPIXEL_BITS;

/// The eight neighbours of a pixel, as steps `(dx, dy)`: what flood fills of 8-connected
/// pixels walk.
pub const NEIGHBOURS_8: [(i64, i64); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// Snaps a coordinate to the fixed-point grid, as an `f64` (exactly representable).
#[inline]
pub fn snap(v: f64) -> f64 {
    (v * ONE as f64).round() / ONE as f64
}

/// A point on the fixed-point grid.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct FixedPoint {
    pub x: i64,
    pub y: i64,
}

impl FixedPoint {
    #[inline]
    pub fn from_f64(x: f64, y: f64) -> FixedPoint {
        FixedPoint {
            x: (x * ONE as f64).round() as i64,
            y: (y * ONE as f64).round() as i64,
        }
    }
}

/// Twice the signed area, exactly, in fixed-point units squared.
#[inline]
pub fn cross(p: [FixedPoint; 3]) -> i64 {
    (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x)
}

/// For `k·x + c > 0` (`strict`) or `≥ 0`: the first `x` that passes when `k > 0`, the end
/// (exclusive) of the passing range when `k < 0`, as `(lo, hi)`.
///
/// The bound comes from a float division (an `i64` division costs tens of cycles and this runs
/// three times per row of every triangle), then is corrected exactly with integer arithmetic.
#[inline]
fn bound(k: i64, c: i64, strict: bool) -> (i64, i64) {
    let pass = |x: i64| {
        let e = k * x + c;
        e > 0 || (e == 0 && !strict)
    };
    if k == 0 {
        return if pass(0) {
            (i64::MIN, i64::MAX)
        } else {
            (0, 0)
        };
    }
    // Clamp the estimate to a range where k·x cannot overflow (|x| ≤ 2^31 pixels).
    let est = (-(c as f64) / k as f64).clamp(-2e9, 2e9);
    // Truncate, then step down for negatives: `floor` is a libm call on baseline x86-64.
    let mut x = est as i64;
    if (x as f64) > est {
        x -= 1;
    }
    if k > 0 {
        // Smallest passing x.
        while pass(x - 1) {
            x -= 1;
        }
        while !pass(x) {
            x += 1;
        }
        (x, i64::MAX)
    } else {
        // First failing x after the passing range.
        while !pass(x) {
            x -= 1;
        }
        while pass(x + 1) {
            x += 1;
        }
        (i64::MIN, x + 1)
    }
}

#[inline]
fn div_ceil(a: i64, b: i64) -> i64 {
    -((-a).div_euclid(b))
}

/// Calls `span(y, x0, x1)` for each pixel row `y` of a `width × height` canvas with the pixels
/// `x0..x1` whose centres lie in the triangle. The triangle must be positively oriented
/// ([`cross`] > 0); others cover nothing.
///
/// Tie rule: a centre exactly on an edge belongs to the triangle for which the edge runs
/// downwards (or leftwards when horizontal), so of two triangles sharing the edge exactly one
/// takes it.
pub fn rasterize(
    tri: [FixedPoint; 3],
    width: u32,
    height: u32,
    mut span: impl FnMut(u32, u32, u32),
) {
    if cross(tri) <= 0 {
        return;
    }
    let ymin = tri.iter().map(|p| p.y).min().unwrap_or(0);
    let ymax = tri.iter().map(|p| p.y).max().unwrap_or(0);
    // Rows whose centre (y + 0.5) is within [ymin, ymax].
    let half = ONE / 2;
    let row0 = div_ceil(ymin - half, ONE).max(0);
    let row1 = ((ymax - half).div_euclid(ONE)).min(height as i64 - 1);
    // Edge i runs from tri[i] to tri[i+1]; E(p) = d × (p − a) > 0 inside.
    let mut edges = [(0i64, 0i64, 0i64, 0i64, false); 3];
    for (i, e) in edges.iter_mut().enumerate() {
        let a = tri[i];
        let b = tri[(i + 1) % 3];
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let owner = dy > 0 || (dy == 0 && dx < 0);
        *e = (dx, dy, a.x, a.y, !owner);
    }
    for row in row0..=row1 {
        let py = row * ONE + half;
        let (mut lo, mut hi) = (0i64, width as i64);
        for &(dx, dy, ax, ay, strict) in &edges {
            // E(x) = dx·(py − ay) − dy·(px − ax), px = x·ONE + half
            //      = (−dy·ONE)·x + [dx·(py − ay) + dy·(ax − half)]
            let k = -dy * ONE;
            let c = dx * (py - ay) + dy * (ax - half);
            let (l, h) = bound(k, c, strict);
            lo = lo.max(l);
            hi = hi.min(h);
        }
        if lo < hi {
            span(row as u32, lo as u32, hi as u32);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fp(x: f64, y: f64) -> FixedPoint {
        FixedPoint::from_f64(x, y)
    }

    fn orient(mut t: [FixedPoint; 3]) -> [FixedPoint; 3] {
        if cross(t) < 0 {
            t.swap(1, 2);
        }
        t
    }

    /// Triangles tiling a canvas cover each pixel exactly once, whatever the vertex positions,
    /// including edges through pixel centres.
    #[test]
    fn a_fan_covers_every_pixel_once() {
        let (w, h) = (37u32, 23u32);
        let centres = [(18.5, 11.5), (10.0, 7.0), (0.5, 0.5), (20.123, 3.77)];
        for &(cx, cy) in &centres {
            let ring = [
                (0.0, 0.0),
                (w as f64 / 2.0 + 0.5, 0.0),
                (w as f64, 0.0),
                (w as f64, h as f64 / 3.0),
                (w as f64, h as f64),
                (5.5, h as f64),
                (0.0, h as f64),
                (0.0, 11.5),
            ];
            let mut count = vec![0u8; (w * h) as usize];
            for i in 0..ring.len() {
                let a = ring[i];
                let b = ring[(i + 1) % ring.len()];
                let t = orient([fp(cx, cy), fp(a.0, a.1), fp(b.0, b.1)]);
                rasterize(t, w, h, |y, x0, x1| {
                    for x in x0..x1 {
                        count[(y * w + x) as usize] += 1;
                    }
                });
            }
            assert!(
                count.iter().all(|&c| c == 1),
                "centre {cx},{cy}: {:?}",
                count.iter().filter(|&&c| c != 1).count()
            );
        }
    }

    #[test]
    fn inverted_triangles_cover_nothing() {
        let t = [fp(0.0, 0.0), fp(0.0, 10.0), fp(10.0, 0.0)];
        let t = if cross(t) > 0 { [t[0], t[2], t[1]] } else { t };
        let mut n = 0;
        rasterize(t, 20, 20, |_, a, b| n += b - a);
        assert_eq!(n, 0);
    }

    /// The float-estimated bounds agree with exact integer ones.
    #[test]
    fn bounds_are_exact() {
        let exact = |k: i64, c: i64, strict: bool| -> (i64, i64) {
            let pass = |x: i64| {
                let e = k * x + c;
                e > 0 || (e == 0 && !strict)
            };
            if k > 0 {
                ((-5000..5000).find(|&x| pass(x)).unwrap(), i64::MAX)
            } else {
                (
                    i64::MIN,
                    (-5000..5000).rev().find(|&x| pass(x)).unwrap() + 1,
                )
            }
        };
        let mut seed = 12345u64;
        for _ in 0..20000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let k = ((seed % 20001) as i64 - 10000) * ONE / 64;
            let x0 = ((seed >> 20) % 4000) as i64 - 2000;
            let jitter = ((seed >> 40) % 7) as i64 - 3;
            if k == 0 {
                continue;
            }
            let c = -k * x0 + jitter;
            for strict in [true, false] {
                assert_eq!(
                    bound(k, c, strict),
                    exact(k, c, strict),
                    "k {k} c {c} strict {strict}"
                );
            }
        }
    }

    #[test]
    fn coverage_matches_area() {
        let t = orient([fp(0.0, 0.0), fp(100.0, 0.0), fp(0.0, 80.0)]);
        let mut n = 0;
        rasterize(t, 200, 200, |_, a, b| n += b - a);
        assert!((n as f64 - 4000.0).abs() < 100.0, "{n}");
    }
}
