//! Rendering the warp: every output pixel is inverse-mapped through the deformed triangle that
//! owns it to the source triangle and sampled there.
//!
//! * ownership comes from [`crate::raster`]: exact fixed-point scan conversion, so shared edges
//!   leave no cracks and no pixel is drawn twice;
//! * each triangle's inverse map is affine; along a span it is two additions per pixel;
//! * [`sample`]: bilinear, or a box of bilinear taps over the pixel's footprint where the
//!   triangle minifies by more than 1.25× along an axis.

mod sample;

use crate::image::{Image, ImageRef};
use crate::mesh::Mesh;
use crate::raster::{rasterize, FixedPoint};
use crate::solve::Warp;
use glam::DVec2;
use sample::Texels;

/// Minification (source pixels per output pixel) from which a footprint is box-filtered.
const BOX_FILTER_FROM: f64 = 1.25;
/// Most taps along one axis of the footprint.
const MAX_TAPS: usize = 8;

/// Sources up to this many pixels get a pre-spread SWAR copy (8 bytes a pixel); larger ones
/// spread texels on the fly.
const LANE_TEXTURE_MAX_PX: usize = 1 << 24;

/// Renders warps. Keeps its scratch (tap offsets, the SWAR copy of the source) between calls.
#[derive(Default)]
pub struct Renderer {
    offsets: Vec<(f32, f32)>,
    lanes: Vec<u64>,
}

impl Renderer {
    pub fn new() -> Renderer {
        Renderer::default()
    }

    /// Draws `src` through `mesh` deformed by `warp` into `dst`, which must be the warp's
    /// target size (it is resized if not). Every pixel of `dst` is written.
    pub fn render(&mut self, src: ImageRef<'_>, mesh: &Mesh, warp: &Warp, dst: &mut Image) {
        let target = warp.target();
        if dst.size() != target {
            *dst = Image::new(target);
        }
        let opaque = src.pixels().iter().all(|p| p[3] == 255);
        self.lanes.clear();
        if opaque && src.pixels().len() <= LANE_TEXTURE_MAX_PX {
            self.lanes
                .extend(src.pixels().iter().map(|&p| sample::lanes(p)));
        }
        let tex = Texels {
            px: src.pixels(),
            lanes: &self.lanes,
            w: src.width() as i32,
            h: src.height() as i32,
        };
        let (tw, th) = (target.width, target.height);
        let twu = tw as usize;
        let out = dst.pixels_mut();
        let offsets = &mut self.offsets;
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let q: [DVec2; 3] = tri.map(|v| warp.positions()[v as usize]);
            let fq = q.map(|p| FixedPoint::from_f64(p.x, p.y));
            let p = mesh.triangle_points(t);
            // Inverse affine map: src = p0 + M (dst − q0), M = P Q⁻¹.
            let (e1, e2) = (q[1] - q[0], q[2] - q[0]);
            let det = e1.perp_dot(e2);
            if det <= 0.0 {
                continue; // covers no pixel; a solved warp never has one
            }
            let inv = [[e2.y / det, -e2.x / det], [-e1.y / det, e1.x / det]];
            let (f1, f2) = (p[1] - p[0], p[2] - p[0]);
            let m = [
                [
                    f1.x * inv[0][0] + f2.x * inv[1][0],
                    f1.x * inv[0][1] + f2.x * inv[1][1],
                ],
                [
                    f1.y * inv[0][0] + f2.y * inv[1][0],
                    f1.y * inv[0][1] + f2.y * inv[1][1],
                ],
            ];
            let col_x = DVec2::new(m[0][0], m[1][0]); // source step per output pixel in x
            let col_y = DVec2::new(m[0][1], m[1][1]);
            let nx = taps(col_x.length());
            let ny = taps(col_y.length());
            offsets.clear();
            for j in 0..ny {
                let oy = (j as f64 + 0.5) / ny as f64 - 0.5;
                for i in 0..nx {
                    let ox = (i as f64 + 0.5) / nx as f64 - 0.5;
                    let o = col_x * ox + col_y * oy;
                    offsets.push((o.x as f32, o.y as f32));
                }
            }
            let n = offsets.len() as u32;
            let offs = &offsets[..];
            let map = |x: f64, y: f64| -> DVec2 {
                let d = DVec2::new(x, y) - q[0];
                p[0] + DVec2::new(m[0][0] * d.x + m[0][1] * d.y, m[1][0] * d.x + m[1][1] * d.y)
            };
            let (du, dv) = (col_x.x, col_x.y);
            rasterize(fq, tw, th, |y, x0, x1| {
                let row = &mut out[y as usize * twu..][x0 as usize..x1 as usize];
                let start = map(x0 as f64 + 0.5, y as f64 + 0.5);
                // f32 stepping along one span (≤ a triangle wide) drifts by well under 0.01 px.
                let (mut u, mut v) = (start.x as f32, start.y as f32);
                let (du, dv) = (du as f32, dv as f32);
                match (opaque, n) {
                    (true, 1) => {
                        for px in row.iter_mut() {
                            *px = sample::finish_one(tex.bilinear_lanes(u, v));
                            u += du;
                            v += dv;
                        }
                    }
                    (true, _) => {
                        let inv = 1.0 / (4096.0 * n as f32);
                        for px in row.iter_mut() {
                            let mut sum = [0u32; 3];
                            for &(ou, ov) in offs {
                                let s = sample::unpack(tex.bilinear_lanes(u + ou, v + ov));
                                sum = [sum[0] + s[0], sum[1] + s[1], sum[2] + s[2]];
                            }
                            *px = sample::finish_sum(sum, inv);
                            u += du;
                            v += dv;
                        }
                    }
                    (false, _) => {
                        for px in row.iter_mut() {
                            let mut acc = [0f32; 4];
                            for &(ou, ov) in offs {
                                tex.bilinear_premul(u + ou, v + ov, &mut acc);
                            }
                            *px = sample::finish_premul(acc, n);
                            u += du;
                            v += dv;
                        }
                    }
                }
            });
        }
    }
}

#[inline]
fn taps(footprint: f64) -> usize {
    if footprint <= BOX_FILTER_FROM {
        1
    } else {
        (footprint.ceil() as usize).min(MAX_TAPS)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Size;
    use crate::mesh::Mesh;
    use crate::solve::Warp;

    fn checker(size: Size) -> Image {
        let mut img = Image::new(size);
        for y in 0..size.height {
            for x in 0..size.width {
                let v = if (x / 3 + y / 3) % 2 == 0 { 250 } else { 10 };
                img.set(x, y, [v, (x * 7) as u8, (y * 5) as u8, 255]);
            }
        }
        img
    }

    #[test]
    fn identity_warp_reproduces_the_image() {
        let size = Size::new(61, 37).unwrap();
        let img = checker(size);
        let mesh = Mesh::lattice(size, 9.0);
        let warp = Warp::linear(&mesh, size);
        let mut out = Image::new(size);
        Renderer::new().render(img.as_ref(), &mesh, &warp, &mut out);
        assert_eq!(out, img);
    }

    #[test]
    fn every_pixel_is_written_exactly_once() {
        let size = Size::new(50, 40).unwrap();
        let img = Image::filled(size, [10, 20, 30, 255]);
        let mesh = Mesh::lattice(size, 7.0);
        for target in [Size::new(17, 40).unwrap(), Size::new(123, 19).unwrap()] {
            let warp = Warp::linear(&mesh, target);
            // Transparent canvas: any pixel left unwritten would stay alpha 0.
            let mut out = Image::new(target);
            Renderer::new().render(img.as_ref(), &mesh, &warp, &mut out);
            assert!(out.pixels().iter().all(|p| *p == [10, 20, 30, 255]));
        }
    }

    #[test]
    fn transparency_is_kept_and_does_not_bleed() {
        let size = Size::new(40, 40).unwrap();
        let mut img = Image::new(size); // transparent black
        for y in 10..30 {
            for x in 10..30 {
                img.set(x, y, [200, 30, 30, 255]);
            }
        }
        let mesh = Mesh::lattice(size, 10.0);
        let target = Size::new(23, 40).unwrap();
        let mut out = Image::new(target);
        Renderer::new().render(img.as_ref(), &mesh, &Warp::linear(&mesh, target), &mut out);
        assert_eq!(out.get(0, 0)[3], 0);
        assert_eq!(out.get(11, 20), [200, 30, 30, 255]);
        // Edge pixels are partly transparent but keep the colour (no dark fringe).
        for p in out.pixels() {
            if p[3] > 0 {
                assert!(p[0] >= 199 && p[1] <= 31, "{p:?}");
            }
        }
    }

    #[test]
    fn strong_minification_averages_thin_lines() {
        let size = Size::new(100, 20).unwrap();
        let mut img = Image::filled(size, [255; 4]);
        for y in 0..20 {
            for x in (0..100).step_by(5) {
                img.set(x, y, [0, 0, 0, 255]);
            }
        }
        let mesh = Mesh::lattice(size, 10.0);
        let target = Size::new(20, 20).unwrap();
        let mut out = Image::new(target);
        Renderer::new().render(img.as_ref(), &mesh, &Warp::linear(&mesh, target), &mut out);
        // One black column in five: each output pixel is close to 80 % white.
        for p in out.pixels() {
            assert!((p[0] as i32 - 204).abs() < 30, "{p:?}");
        }
    }
}
