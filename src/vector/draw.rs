//! Antialiased drawing of a placed layer: analytic coverage, straight sRGB "over" blending
//! (see the module docs). Pixel `(x, y)` is the square `[x, x+1) × [y, y+1)`, sampled at its
//! centre, the convention of the mesh and the renderer.

use super::footprint::dist_to_segment;
use super::{PointMark, Rgba, VectorLayer};
use crate::image::Image;
use glam::DVec2;

/// Draws every mark of `layer` (output coordinates) onto `image`: polylines, edges, points.
pub(crate) fn draw_layer(image: &mut Image, layer: &VectorLayer) {
    let mut coverage = Vec::new();
    for l in &layer.polylines {
        let pts: Vec<DVec2> = l.points.iter().map(|q| DVec2::new(q[0], q[1])).collect();
        draw_polyline(image, &pts, l.width, l.color, &mut coverage);
    }
    for e in &layer.edges {
        let (Some(a), Some(b)) = (layer.points.get(e.from), layer.points.get(e.to)) else {
            continue;
        };
        let pts = [DVec2::new(a.x, a.y), DVec2::new(b.x, b.y)];
        draw_polyline(image, &pts, e.width, e.color, &mut coverage);
    }
    for p in &layer.points {
        draw_point(image, p);
    }
}

/// Blends `colour` with coverage `cov` over `dst` (straight alpha).
#[inline]
fn blend(dst: &mut [u8; 4], colour: Rgba, cov: f64) {
    let a = cov.clamp(0.0, 1.0) * colour[3] as f64 / 255.0;
    if a <= 0.0 {
        return;
    }
    let da = dst[3] as f64 / 255.0;
    let oa = a + da * (1.0 - a);
    if oa <= 0.0 {
        return;
    }
    for k in 0..3 {
        let v = (colour[k] as f64 * a + dst[k] as f64 * da * (1.0 - a)) / oa;
        dst[k] = v.round().clamp(0.0, 255.0) as u8;
    }
    dst[3] = (oa * 255.0).round().clamp(0.0, 255.0) as u8;
}

/// Pixel range `[lo, hi)` of the pixels whose centre may lie within `[a, b]`, clipped to `n`.
fn span(a: f64, b: f64, n: u32) -> (u32, u32) {
    if !(a.is_finite() && b.is_finite()) || b < a {
        return (0, 0);
    }
    let lo = (a - 0.5).floor().clamp(0.0, n as f64) as u32;
    let hi = (b - 0.5).ceil().max(-1.0) as i64 + 1;
    (lo, hi.clamp(0, n as i64) as u32)
}

/// A disc with its fill and, centred on its rim, its stroke.
///
/// Drawn about the pixel centre nearest to its place (at most half a pixel off): every disc of
/// a radius then has the same pixels, symmetric about both axes, wherever it lands, and a mark
/// that drifts by a fraction of a pixel between frames does not flicker along its rim (the
/// rasters' marks get the same whole-pixel treatment).
fn draw_point(image: &mut Image, p: &PointMark) {
    if !(p.x.is_finite() && p.y.is_finite() && p.radius.is_finite()) {
        return;
    }
    let p = &PointMark {
        x: (p.x - 0.5).round() + 0.5,
        y: (p.y - 0.5).round() + 0.5,
        ..p.clone()
    };
    let r = p.radius.max(0.0);
    let half_stroke = p.stroke.map_or(0.0, |s| s.width / 2.0);
    let reach = r + half_stroke + 0.5;
    let (x0, x1) = span(p.x - reach, p.x + reach, image.width());
    let (y0, y1) = span(p.y - reach, p.y + reach, image.height());
    for y in y0..y1 {
        let row = image.row_mut(y);
        let dy = y as f64 + 0.5 - p.y;
        for x in x0..x1 {
            let dx = x as f64 + 0.5 - p.x;
            let d = (dx * dx + dy * dy).sqrt();
            let px = &mut row[x as usize];
            let fill = r + 0.5 - d;
            if fill > 0.0 {
                blend(px, p.fill, fill);
            }
            if let Some(s) = &p.stroke {
                let (inner, outer) = (r - s.width / 2.0, r + s.width / 2.0);
                let cov = (outer + 0.5 - d).min(d - inner + 0.5);
                if cov > 0.0 {
                    blend(px, s.color, cov);
                }
            }
        }
    }
}

/// A polyline of width `width` with round joins and caps; one coverage per pixel (the
/// largest over its segments) so that joints are blended once.
fn draw_polyline(
    image: &mut Image,
    pts: &[DVec2],
    width: f64,
    colour: Rgba,
    coverage: &mut Vec<f32>,
) {
    if pts.is_empty() || width.is_nan() || width <= 0.0 || pts.iter().any(|p| !p.is_finite()) {
        return;
    }
    let half = width / 2.0;
    let reach = half + 0.5;
    let lo = pts.iter().copied().fold(DVec2::INFINITY, DVec2::min) - reach;
    let hi = pts.iter().copied().fold(DVec2::NEG_INFINITY, DVec2::max) + reach;
    let (bx0, bx1) = span(lo.x, hi.x, image.width());
    let (by0, by1) = span(lo.y, hi.y, image.height());
    if bx0 >= bx1 || by0 >= by1 {
        return;
    }
    let bw = (bx1 - bx0) as usize;
    coverage.clear();
    coverage.resize(bw * (by1 - by0) as usize, 0.0);
    let single = [pts[0], pts[0]];
    let segments: Vec<[DVec2; 2]> = if pts.len() == 1 {
        vec![single]
    } else {
        pts.windows(2).map(|w| [w[0], w[1]]).collect()
    };
    for [a, b] in segments {
        let (y0, y1) = span(a.y.min(b.y) - reach, a.y.max(b.y) + reach, image.height());
        for y in y0.max(by0)..y1.min(by1) {
            let yc = y as f64 + 0.5;
            // The part of the segment within `reach` of this row, grown by `reach` in x.
            let (t0, t1) = if (b.y - a.y).abs() < 1e-12 {
                (0.0, 1.0)
            } else {
                let ta = (yc - reach - a.y) / (b.y - a.y);
                let tb = (yc + reach - a.y) / (b.y - a.y);
                (ta.min(tb).clamp(0.0, 1.0), ta.max(tb).clamp(0.0, 1.0))
            };
            let (xa, xb) = (a.x + t0 * (b.x - a.x), a.x + t1 * (b.x - a.x));
            let (x0, x1) = span(xa.min(xb) - reach, xa.max(xb) + reach, image.width());
            let row = &mut coverage[(y - by0) as usize * bw..][..bw];
            for x in x0.max(bx0)..x1.min(bx1) {
                let d = dist_to_segment(DVec2::new(x as f64 + 0.5, yc), a, b);
                let c = (half + 0.5 - d).clamp(0.0, 1.0) as f32;
                let cell = &mut row[(x - bx0) as usize];
                *cell = cell.max(c);
            }
        }
    }
    for y in by0..by1 {
        let row = image.row_mut(y);
        let cov = &coverage[(y - by0) as usize * bw..][..bw];
        for (px, &c) in row[bx0 as usize..bx1 as usize].iter_mut().zip(cov) {
            if c > 0.0 {
                blend(px, colour, c as f64);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Size;
    use crate::vector::{Polyline, Stroke};

    /// Coverage-weighted moments of `colour` drawn on white: area (sum of coverage), centroid,
    /// roundness (√ of the covariance eigenvalues' ratio). Weighting by coverage measures the
    /// antialiased shape itself; thresholded pixels would add the grid's own anisotropy.
    fn moments(img: &Image, colour: [u8; 4]) -> (f64, f64, f64, f64) {
        let full: f64 = (0..3)
            .map(|k| (255.0 - colour[k] as f64).powi(2))
            .sum::<f64>()
            .sqrt();
        let mut pts = Vec::new();
        for y in 0..img.height() {
            for x in 0..img.width() {
                let p = img.get(x, y);
                let d: f64 = (0..3)
                    .map(|k| (p[k] as f64 - colour[k] as f64).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let w = (1.0 - d / full).clamp(0.0, 1.0);
                if w > 0.0 {
                    pts.push((x as f64 + 0.5, y as f64 + 0.5, w));
                }
            }
        }
        let n: f64 = pts.iter().map(|p| p.2).sum();
        let mx = pts.iter().map(|p| p.0 * p.2).sum::<f64>() / n;
        let my = pts.iter().map(|p| p.1 * p.2).sum::<f64>() / n;
        let (mut cxx, mut cyy, mut cxy) = (0.0, 0.0, 0.0);
        for (x, y, w) in pts {
            cxx += w * (x - mx) * (x - mx);
            cyy += w * (y - my) * (y - my);
            cxy += w * (x - mx) * (y - my);
        }
        let tr = cxx + cyy;
        let det = cxx * cyy - cxy * cxy;
        let disc = (tr * tr / 4.0 - det).max(0.0).sqrt();
        let round = ((tr / 2.0 - disc) / (tr / 2.0 + disc)).sqrt();
        (n, mx, my, round)
    }

    #[test]
    fn a_disc_is_round_centred_on_a_pixel_and_of_its_area() {
        let red = [215, 25, 28, 255];
        for (cx, cy, r) in [(20.3, 17.8, 6.0), (21.5, 20.5, 4.5), (19.9, 20.2, 9.25)] {
            let mut img = Image::filled(Size::new(40, 40).unwrap(), [255; 4]);
            draw_point(
                &mut img,
                &PointMark {
                    id: None,
                    x: cx,
                    y: cy,
                    radius: r,
                    fill: red,
                    stroke: Some(Stroke {
                        color: red,
                        width: 1.0,
                    }),
                },
            );
            // Fill to r, stroke of the same colour to r + 0.5.
            let (n, mx, my, round) = moments(&img, red);
            let want = std::f64::consts::PI * (r + 0.5) * (r + 0.5);
            assert!((n / want - 1.0).abs() < 0.02, "{n} px for r {r}");
            // About the nearest pixel centre.
            let snapped = |v: f64| (v - 0.5).round() + 0.5;
            assert!(
                (mx - snapped(cx)).abs() < 0.02 && (my - snapped(cy)).abs() < 0.02,
                "{mx},{my}"
            );
            assert!(round > 0.99, "{round}");
        }
    }

    #[test]
    fn a_line_covers_its_band_once_and_nothing_off_canvas_breaks() {
        let mut img = Image::filled(Size::new(50, 30).unwrap(), [255; 4]);
        let l = Polyline {
            points: vec![[5.0, 15.0], [25.0, 15.0], [45.0, 15.0]],
            width: 3.0,
            color: [0, 0, 0, 128],
        };
        draw_layer(
            &mut img,
            &VectorLayer {
                polylines: vec![l],
                ..VectorLayer::default()
            },
        );
        // The joint at x = 25 is blended once: the same grey as the rest of the line.
        assert_eq!(img.get(25, 14), img.get(15, 14));
        assert_eq!(img.get(25, 14), [127, 127, 127, 255]);
        assert_eq!(img.get(25, 10), [255; 4]);
        // Far off the canvas, huge or non-finite: nothing drawn, nothing panics.
        let mut far = VectorLayer::default();
        far.polylines.push(Polyline {
            points: vec![[-1e6, -1e6], [1e6, -1e6]],
            width: 2.2e6,
            color: [0, 0, 0, 255],
        });
        far.polylines.push(Polyline {
            points: vec![[f64::NAN, 0.0], [3.0, 4.0]],
            width: 2.0,
            color: [0, 0, 0, 255],
        });
        let mut img2 = Image::filled(Size::new(8, 8).unwrap(), [255; 4]);
        draw_layer(&mut img2, &far);
        assert!(img2.pixels().iter().all(|p| *p == [0, 0, 0, 255]));
    }
}
