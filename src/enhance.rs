//! Content enhancement (§5.4, Eq. 13): a factor `δ` per triangle asks it to take `δ` times the
//! scale it would otherwise get, so that what matters is enlarged, with or without resizing
//! the canvas (the paper's Fig. 9 enlarges a region at an unchanged size).
//!
//! A triangle's `δ` is the product of
//! * `per_level[k − 1]`, `δ_k` of its saliency level `k` (Eq. 13), by its triangle saliency
//!   `λ_t`, the mean VSM over its source pixels (the same scan conversion as the solver's
//!   `λ_t`; computed here from the VSM rather than taken from a first solve, which would cost
//!   a second solve for the same numbers);
//! * the factor of the last [`EnhanceRegion`] that contains its centroid (regions are source
//!   rectangles: later ones are painted over earlier ones, like brush strokes; in a stream
//!   they stay where they are in the source, and the mesh carries them);
//! * the [`EnhanceMask`] factor under its centroid;
//!
//! clamped to `[0.25, 4]`. The solver ([`crate::Solver::solve_enhanced`]) gives every triangle
//! whose `δ ≠ 1` the size prior, whatever its saliency.
//!
//! Regions and masks are also *held* for the solve ([`Enhancement::held`]): their saliency is
//! raised to at least 0.5, so that they grow as one piece. Without it, on a scatter map enlarged
//! 1.6× at the same size, only the dots' own fans of triangles grew (their weight `λ⁴` is high);
//! the empty gaps between them, whose weight is the floor, grew about 1.15×, and the enlarged
//! dots ran into each other, the opposite of what enlarging a crowd is for. Held, a region of
//! a test map grows 1.46× in spacing for 1.47× in mark size (`tests/vector.rs`).

use crate::error::Error;
use crate::image::{Image, Size};
use crate::mesh::Mesh;
use crate::raster::{rasterize, FixedPoint};
use crate::saliency::{SaliencyLevel, Vsm};
use std::sync::Arc;

/// Allowed range of every factor.
pub const FACTOR_RANGE: (f64, f64) = (0.25, 4.0);

/// What to enlarge (or shrink) and by how much; the default changes nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct Enhancement {
    /// `δ_k` for saliency levels k = 1 (background), 2 (context), 3 (salient) (Eq. 13).
    pub per_level: [f64; 3],
    /// Rectangles of the source with their factor; the last one holding a triangle's centroid
    /// applies.
    pub regions: Vec<EnhanceRegion>,
    /// A painted map of factors.
    pub mask: Option<Arc<EnhanceMask>>,
}

impl Default for Enhancement {
    fn default() -> Self {
        Enhancement {
            per_level: [1.0; 3],
            regions: Vec::new(),
            mask: None,
        }
    }
}

/// A rectangle of the source image, px, and its factor.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct EnhanceRegion {
    pub x: f64,
    pub y: f64,
    pub width: f64,
    pub height: f64,
    pub factor: f64,
}

impl EnhanceRegion {
    fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x && x < self.x + self.width && y >= self.y && y < self.y + self.height
    }
}

/// A factor per pixel, from a grey picture: black 1 (unchanged), white `max_factor`, linear
/// between: `factor = 1 + g/255 · (max_factor − 1)` with `g` the luma (Rec. 601) times the
/// alpha. A mask of another size than the frames is stretched over them (nearest pixel).
#[derive(Clone, Debug, PartialEq)]
pub struct EnhanceMask {
    size: Size,
    factors: Vec<f32>,
}

impl EnhanceMask {
    /// The mask of `image` with white meaning `max_factor` (in [`Enhancement::FACTOR_RANGE`]).
    pub fn from_image(image: &Image, max_factor: f64) -> Result<EnhanceMask, Error> {
        check_factor("the mask's factor", max_factor)?;
        let factors = image
            .pixels()
            .iter()
            .map(|p| {
                let luma = 0.299 * p[0] as f64 + 0.587 * p[1] as f64 + 0.114 * p[2] as f64;
                let g = luma * p[3] as f64 / 255.0;
                (1.0 + g / 255.0 * (max_factor - 1.0)) as f32
            })
            .collect();
        Ok(EnhanceMask {
            size: image.size(),
            factors,
        })
    }

    /// The mask's own size.
    pub fn size(&self) -> Size {
        self.size
    }

    /// The factor at point `(x, y)` of a `canvas`-sized frame.
    pub fn factor_at(&self, x: f64, y: f64, canvas: Size) -> f64 {
        let mx = (x / canvas.width as f64 * self.size.width as f64).floor();
        let my = (y / canvas.height as f64 * self.size.height as f64).floor();
        let mx = (mx.max(0.0) as u32).min(self.size.width - 1);
        let my = (my.max(0.0) as u32).min(self.size.height - 1);
        self.factors[my as usize * self.size.width as usize + mx as usize] as f64
    }
}

fn check_factor(what: &str, f: f64) -> Result<(), Error> {
    if !(FACTOR_RANGE.0..=FACTOR_RANGE.1).contains(&f) {
        return Err(Error::InvalidOptions(format!(
            "{what} {f} is out of range: allowed {} to {}",
            FACTOR_RANGE.0, FACTOR_RANGE.1
        )));
    }
    Ok(())
}

impl Enhancement {
    /// The factors a level or region may take: 0.25 to 4, a quarter to four times its size.
    pub const FACTOR_RANGE: (f64, f64) = FACTOR_RANGE;

    /// Whether this changes nothing (every factor 1, no mask).
    pub fn is_identity(&self) -> bool {
        self.per_level == [1.0; 3]
            && self.regions.iter().all(|r| r.factor == 1.0)
            && self.mask.is_none()
    }

    /// Checks every factor (in [`Enhancement::FACTOR_RANGE`]) and region (finite, positive size).
    pub fn validate(&self) -> Result<(), Error> {
        for (k, &d) in self.per_level.iter().enumerate() {
            check_factor(&format!("enhancement of saliency level {}", k + 1), d)?;
        }
        for (i, r) in self.regions.iter().enumerate() {
            let ok = [r.x, r.y, r.width, r.height].iter().all(|v| v.is_finite())
                && r.width > 0.0
                && r.height > 0.0;
            if !ok {
                return Err(Error::InvalidOptions(format!(
                    "enhancement region {} ({}, {}, {}x{}) needs finite numbers and a width and \
                     height above 0",
                    i + 1,
                    r.x,
                    r.y,
                    r.width,
                    r.height
                )));
            }
            check_factor(
                &format!("the factor of enhancement region {}", i + 1),
                r.factor,
            )?;
        }
        Ok(())
    }

    /// `δ` for every triangle of `mesh` (source coordinates), from `vsm` for the levels.
    pub fn triangle_factors(&self, mesh: &Mesh, vsm: &Vsm) -> Vec<f64> {
        let lambda = if self.per_level != [1.0; 3] {
            triangle_saliency(mesh, vsm)
        } else {
            Vec::new()
        };
        (0..mesh.triangles().len())
            .map(|t| {
                let p = mesh.triangle_points(t);
                let c = (p[0] + p[1] + p[2]) / 3.0;
                let mut d = match lambda.get(t) {
                    Some(&l) => self.per_level[SaliencyLevel::of(l as f32).index()],
                    None => 1.0,
                };
                if let Some(r) = self.regions.iter().rev().find(|r| r.contains(c.x, c.y)) {
                    d *= r.factor;
                }
                if let Some(m) = &self.mask {
                    d *= m.factor_at(c.x, c.y, mesh.size());
                }
                d.clamp(FACTOR_RANGE.0, FACTOR_RANGE.1)
            })
            .collect()
    }
}

/// Saliency an enhanced region is given at least for the solve (see [`Enhancement::held`]).
const HELD_SALIENCY: f32 = 0.5;

impl Enhancement {
    /// For the solve: `vsm` with every cell of a region or mask area whose factor is not 1
    /// raised to at least `HELD_SALIENCY`, or `None` when there is no such area. The size
    /// prior alone acts on a triangle's scale `s_t`, but an empty triangle's shape is held by
    /// its saliency weight, which is tiny (`λ⁴`): its `s_t` follows `δ` while the triangle
    /// itself hardly grows. Then only the marks' own fans grow, and the gaps between them
    /// not: enhanced marks run into each other, where the point of enhancing is to spread a
    /// crowd. Held, the region is enlarged as one piece, like a lens (the paper's Fig. 9).
    pub fn held(&self, vsm: &Vsm) -> Option<Vsm> {
        let regions: Vec<&EnhanceRegion> =
            self.regions.iter().filter(|r| r.factor != 1.0).collect();
        if regions.is_empty() && self.mask.is_none() {
            return None;
        }
        let mut out = vsm.clone();
        let size = vsm.size();
        let grid = vsm.grid_size();
        let cell = vsm.scale() as f64;
        let (values, _, edges) = out.planes_mut();
        for gy in 0..grid.height as usize {
            for gx in 0..grid.width as usize {
                let (x, y) = ((gx as f64 + 0.5) * cell, (gy as f64 + 0.5) * cell);
                let held = regions.iter().any(|r| r.contains(x, y))
                    || self
                        .mask
                        .as_ref()
                        .is_some_and(|m| m.factor_at(x, y, size) != 1.0);
                if held {
                    let i = gy * grid.width as usize + gx;
                    values[i] = values[i].max(HELD_SALIENCY);
                    edges[i] = edges[i].max(HELD_SALIENCY);
                }
            }
        }
        Some(out)
    }
}

/// `λ_t`: the mean of `vsm` over the pixel centres of each source triangle (its centroid's
/// value for a triangle too small to hold one), by the renderer's exact scan conversion.
fn triangle_saliency(mesh: &Mesh, vsm: &Vsm) -> Vec<f64> {
    let grid = vsm.grid_size();
    let (w, h) = (grid.width, grid.height);
    let inv = 1.0 / vsm.scale() as f64;
    let values = vsm.values();
    (0..mesh.triangles().len())
        .map(|t| {
            let p = mesh.triangle_points(t).map(|q| q * inv);
            let mut sum = 0.0f64;
            let mut n = 0u32;
            rasterize(
                p.map(|q| FixedPoint::from_f64(q.x, q.y)),
                w,
                h,
                |y, x0, x1| {
                    let row = &values[y as usize * w as usize..][x0 as usize..x1 as usize];
                    sum += row.iter().map(|&v| v as f64).sum::<f64>();
                    n += x1 - x0;
                },
            );
            if n == 0 {
                let c = (p[0] + p[1] + p[2]) / 3.0;
                let x = (c.x.max(0.0) as usize).min(w as usize - 1);
                let y = (c.y.max(0.0) as usize).min(h as usize - 1);
                values[y * w as usize + x] as f64
            } else {
                sum / n as f64
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factors_by_level_region_and_mask() {
        let size = Size::new(100, 50).unwrap();
        let mut values = vec![0.0f32; size.area()];
        for y in 0..50 {
            for x in 50..100 {
                values[y * 100 + x] = 0.9;
            }
        }
        let vsm = Vsm::from_values(size, values).unwrap();
        let mesh = Mesh::lattice(size, 10.0);
        let e = Enhancement {
            per_level: [1.0, 1.0, 1.5],
            regions: vec![EnhanceRegion {
                x: 0.0,
                y: 0.0,
                width: 20.0,
                height: 50.0,
                factor: 2.0,
            }],
            mask: None,
        };
        e.validate().unwrap();
        let f = e.triangle_factors(&mesh, &vsm);
        for (t, &d) in f.iter().enumerate() {
            let p = mesh.triangle_points(t);
            let c = (p[0] + p[1] + p[2]) / 3.0;
            let want = if c.x < 20.0 {
                2.0
            } else if c.x > 50.0 {
                1.5
            } else {
                1.0
            };
            assert_eq!(d, want, "triangle at {c}");
        }
        let mut white_right = Image::filled(Size::new(2, 1).unwrap(), [0, 0, 0, 255]);
        white_right.set(1, 0, [255; 4]);
        let m = EnhanceMask::from_image(&white_right, 1.5).unwrap();
        assert_eq!(m.factor_at(10.0, 10.0, size), 1.0);
        assert!((m.factor_at(90.0, 10.0, size) - 1.5).abs() < 1e-6);
        assert!(Enhancement {
            per_level: [1.0, 0.0, 1.0],
            ..Enhancement::default()
        }
        .validate()
        .is_err());
        assert!(Enhancement::default().is_identity());
    }
}
