//! How well, and how fast, each method resized an image: the paper's saliency preservation
//! (Fig. 15) and three more measures, per method, as a table ([`MetricsTable`]'s `Display`)
//! or JSON ([`MetricsTable::to_json`]).
//!
//! Every measure is defined for every method through the method's [`Mapping`] (how output
//! pixels relate to source pixels), so that the same rules judge a mesh, a crop and a seam
//! carving. "Salient" is the paper's saliency level 3 (`S_vsm ≥ 0.5`) of the source's VSM.
//!
//! * **saliency mean** (the paper's Fig. 15): the VSM of the *output* image, built afresh and
//!   normalized on its own like any VSM, averaged over the output's pixels. Higher means the
//!   output spends more of its pixels on what the saliency map calls important.
//! * **saliency carried** (the same figure read as Avidan and Shamir's "preserved energy", the
//!   paper's ref. \[2\], from which Fig. 15 takes its measure): the *source's* VSM carried by the
//!   mapping, averaged over the output's pixels, `Σ_t Σ_{p∈t} S(p)·det J_t / |out|`. A pixel of
//!   the output counts what the source pixel it shows was worth, so a method cannot score by
//!   making edges of its own (aliasing, squeezed strokes); linear scaling keeps the source's
//!   mean, a method that keeps what matters at its size and squeezes the ground raises it.
//! * **saliency kept**: `Σ S_out / Σ S_src`, the output's total saliency (sum of its own VSM
//!   over its pixels) over the source's. Shrinking by linear scaling to half the width keeps
//!   about half; a method that keeps the marks at their size and takes the change out of empty
//!   space keeps close to 1; a crop keeps what lies in its window. It can exceed 1 when
//!   enlarging.
//! * **distortion**: how far the map is from a similarity on salient content: per piece with
//!   Jacobian `J` (source to output), `‖J − s·I‖_F / s` with `s = (J₀₀ + J₁₁)/2`, averaged
//!   weighted by source area. Pieces are the triangles whose mean source saliency is ≥ 0.5 for
//!   mesh and grid; the (constant) scaling for linear and crop, counted when the kept window
//!   holds salient pixels; for seam carving, each output pixel whose source pixel is salient,
//!   with `J` the inverse of the finite differences of the source positions of its right and
//!   lower neighbours (a seam next to it shows as a local 2:1 squeeze). 0 is a pure
//!   similarity; halving one axis linearly gives 0.47. `None` when no salient content is kept.
//! * **salient area kept**: the output area covered by the images of the source's salient
//!   pixels over their source area: `Σ_t n_t·det J_t / Σ_t n_t` over mesh triangles with `n_t`
//!   salient pixels, `n_window·sx·sy / n` for linear and crop, and the number of output pixels
//!   whose source pixel is salient over `n` for seam carving. 1 keeps the marks at their size;
//!   linear scaling to half the width gives 0.5. `None` when the source has no salient pixel.
//!
//! Vertices and DOF (free vertex coordinates, the paper's Table 1) and milliseconds per stage
//! (see [`MethodStats`]) come from the run itself.

use crate::baseline::{Mapping, Method, MethodOutput, MethodStats};
use crate::image::{Image, Size};
use crate::mesh::{cross2, Mesh};
use crate::raster::{rasterize, FixedPoint};
use crate::retarget::StageTimes;
use crate::saliency::{SaliencyLevel, Vsm, VsmBuilder};
use crate::solve::Warp;
use glam::{DMat2, DVec2};
use std::fmt;

/// Source saliency from which a triangle counts as salient for the distortion.
pub const SALIENT_TRIANGLE: f64 = 0.5;

/// The measures of one method's output (see the module documentation for definitions).
#[derive(Clone, Debug, PartialEq)]
pub struct MethodMetrics {
    pub method: Method,
    /// The output size.
    pub size: Size,
    /// Mean VSM of the output's pixels (Fig. 15).
    pub saliency_mean: f64,
    /// Mean over the output's pixels of the source VSM they show.
    pub saliency_carried: f64,
    /// The output's total saliency over the source's.
    pub saliency_kept: f64,
    /// Area-weighted deviation from a similarity on salient content.
    pub distortion: Option<f64>,
    /// Output area of the source's salient pixels over their source area.
    pub salient_area_kept: Option<f64>,
    pub vertices: Option<usize>,
    pub dof: Option<usize>,
    pub times: StageTimes,
}

/// The measures of every method on one source image.
#[derive(Clone, Debug, PartialEq)]
pub struct MetricsTable {
    pub source: Size,
    pub target: Size,
    /// Mean VSM of the source's pixels (the reference for `saliency_mean`).
    pub source_saliency_mean: f64,
    /// Salient (level 3) pixels of the source.
    pub source_salient_px: usize,
    pub rows: Vec<MethodMetrics>,
}

impl MetricsTable {
    /// Measures every output against `source`. The source's VSM is taken from an output that
    /// kept one (all computed alike), or built.
    pub fn measure(source: &Image, outputs: &[MethodOutput]) -> MetricsTable {
        let vsm = match outputs.iter().find_map(|o| o.vsm.clone()) {
            Some(v) if v.size() == source.size() => v,
            _ => std::sync::Arc::new(VsmBuilder::new().build(source.as_ref())),
        };
        let src = SourceSaliency::new(&vsm);
        let rows = outputs.iter().map(|o| src.measure(o)).collect();
        MetricsTable {
            source: source.size(),
            target: outputs.first().map_or(source.size(), |o| o.image.size()),
            source_saliency_mean: src.sum / src.size.area() as f64,
            source_salient_px: src.salient,
            rows,
        }
    }

    /// The row of `method`, if measured.
    pub fn row(&self, method: Method) -> Option<&MethodMetrics> {
        self.rows.iter().find(|r| r.method == method)
    }

    /// The table as JSON: `{source, target, source_saliency_mean, source_salient_px, rows:
    /// [{method, width, height, saliency_mean, saliency_carried, saliency_kept, distortion,
    /// salient_area_kept,
    /// vertices, dof, ms: {vsm, mesh, solve, render, total}}]}`, `null` where not defined.
    pub fn to_json(&self) -> serde_json::Value {
        let rows: Vec<serde_json::Value> = self
            .rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "method": r.method.name(),
                    "width": r.size.width,
                    "height": r.size.height,
                    "saliency_mean": r.saliency_mean,
                    "saliency_carried": r.saliency_carried,
                    "saliency_kept": r.saliency_kept,
                    "distortion": r.distortion,
                    "salient_area_kept": r.salient_area_kept,
                    "vertices": r.vertices,
                    "dof": r.dof,
                    "ms": {
                        "vsm": r.times.vsm_ms,
                        "mesh": r.times.mesh_ms,
                        "solve": r.times.solve_ms,
                        "render": r.times.render_ms,
                        "total": r.times.total_ms(),
                    },
                })
            })
            .collect();
        serde_json::json!({
            "source": { "width": self.source.width, "height": self.source.height },
            "target": { "width": self.target.width, "height": self.target.height },
            "source_saliency_mean": self.source_saliency_mean,
            "source_salient_px": self.source_salient_px,
            "rows": rows,
        })
    }
}

impl fmt::Display for MetricsTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} -> {}; source: saliency mean {:.3}, {} salient px",
            self.source, self.target, self.source_saliency_mean, self.source_salient_px
        )?;
        let header = [
            "method",
            "size",
            "vertices",
            "DOF",
            "sal.mean",
            "sal.carried",
            "sal.kept",
            "distortion",
            "sal.area",
            "vsm ms",
            "mesh ms",
            "solve ms",
            "render ms",
            "total ms",
        ];
        let opt_u = |v: Option<usize>| v.map_or("-".to_string(), |v| v.to_string());
        let opt_f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
        let cells: Vec<[String; 14]> = self
            .rows
            .iter()
            .map(|r| {
                [
                    r.method.name().to_string(),
                    r.size.to_string(),
                    opt_u(r.vertices),
                    opt_u(r.dof),
                    format!("{:.3}", r.saliency_mean),
                    format!("{:.3}", r.saliency_carried),
                    format!("{:.3}", r.saliency_kept),
                    opt_f(r.distortion),
                    opt_f(r.salient_area_kept),
                    format!("{:.1}", r.times.vsm_ms),
                    format!("{:.1}", r.times.mesh_ms),
                    format!("{:.1}", r.times.solve_ms),
                    format!("{:.1}", r.times.render_ms),
                    format!("{:.1}", r.times.total_ms()),
                ]
            })
            .collect();
        let widths: Vec<usize> = (0..header.len())
            .map(|i| {
                cells
                    .iter()
                    .map(|c| c[i].len())
                    .chain([header[i].len()])
                    .max()
                    .unwrap_or(0)
            })
            .collect();
        let line = |f: &mut fmt::Formatter<'_>, items: &[&str]| -> fmt::Result {
            for (i, (s, w)) in items.iter().zip(&widths).enumerate() {
                if i == 0 {
                    write!(f, "{s:<w$}")?;
                } else {
                    write!(f, "  {s:>w$}")?;
                }
            }
            writeln!(f)
        };
        line(f, &header)?;
        for c in &cells {
            let items: Vec<&str> = c.iter().map(String::as_str).collect();
            line(f, &items)?;
        }
        Ok(())
    }
}

/// Measures one output against `source` (the VSM is built).
pub fn measure(source: &Image, output: &MethodOutput) -> MethodMetrics {
    let vsm = match &output.vsm {
        Some(v) if v.size() == source.size() => v.clone(),
        _ => std::sync::Arc::new(VsmBuilder::new().build(source.as_ref())),
    };
    SourceSaliency::new(&vsm).measure(output)
}

/// The source's VSM and the sums every row needs.
struct SourceSaliency<'a> {
    vsm: &'a Vsm,
    size: Size,
    sum: f64,
    salient: usize,
}

impl<'a> SourceSaliency<'a> {
    fn new(vsm: &'a Vsm) -> SourceSaliency<'a> {
        let (sum, salient) = pixel_sums(vsm);
        SourceSaliency {
            vsm,
            size: vsm.size(),
            sum,
            salient,
        }
    }

    fn measure(&self, out: &MethodOutput) -> MethodMetrics {
        let out_vsm = VsmBuilder::new().build(out.image.as_ref());
        let (out_sum, _) = pixel_sums(&out_vsm);
        let (distortion, area, carried) = match &out.mapping {
            Mapping::Warp { mesh, warp } => self.warp_measures(mesh, warp),
            Mapping::Affine { window } => self.affine_measures(*window, out.image.size()),
            Mapping::Origins(o) => self.origin_measures(o),
        };
        let MethodStats {
            vertices,
            dof,
            times,
            ..
        } = out.stats.clone();
        MethodMetrics {
            method: out.method,
            size: out.image.size(),
            saliency_mean: out_sum / out.image.size().area() as f64,
            saliency_carried: carried / out.image.size().area() as f64,
            saliency_kept: if self.sum > 0.0 {
                out_sum / self.sum
            } else {
                1.0
            },
            distortion,
            salient_area_kept: area,
            vertices,
            dof,
            times,
        }
    }

    /// Per triangle: mean source saliency, salient pixel count and Jacobian. Returns
    /// (distortion, salient area kept, carried saliency sum).
    fn warp_measures(&self, mesh: &Mesh, warp: &Warp) -> (Option<f64>, Option<f64>, f64) {
        let (w, h) = (self.size.width, self.size.height);
        let mut carried = 0.0;
        let (mut d_sum, mut d_weight) = (0.0, 0.0);
        let (mut area_out, mut n_total) = (0.0, 0usize);
        for t in 0..mesh.triangles().len() {
            let p = mesh.triangle_points(t);
            let q = mesh.triangles()[t].map(|v| warp.positions()[v as usize]);
            let fp = p.map(|v| FixedPoint::from_f64(v.x, v.y));
            let (mut sum, mut n, mut salient) = (0.0f64, 0usize, 0usize);
            rasterize(fp, w, h, |y, x0, x1| {
                for x in x0..x1 {
                    let s = self.vsm.get(x, y);
                    sum += s as f64;
                    salient += (SaliencyLevel::of(s) == SaliencyLevel::Salient) as usize;
                }
                n += (x1 - x0) as usize;
            });
            let mean = if n == 0 {
                let c = (p[0] + p[1] + p[2]) / 3.0;
                self.vsm.get(
                    (c.x.max(0.0) as u32).min(w - 1),
                    (c.y.max(0.0) as u32).min(h - 1),
                ) as f64
            } else {
                sum / n as f64
            };
            let Some(j) = jacobian(p, q) else { continue };
            // A sliver over no pixel centre still covers output area: at its centre's value.
            carried += if n == 0 {
                mean * (cross2(q) / 2.0).max(0.0)
            } else {
                sum * j.determinant().max(0.0)
            };
            if salient > 0 {
                area_out += salient as f64 * j.determinant();
                n_total += salient;
            }
            if mean >= SALIENT_TRIANGLE {
                let a = cross2(p) / 2.0;
                d_sum += a * similarity_deviation(j);
                d_weight += a;
            }
        }
        let distortion = (d_weight > 0.0).then(|| d_sum / d_weight);
        let area = (self.salient > 0).then(|| area_out / n_total.max(1) as f64);
        (distortion, area, carried)
    }

    /// A source window scaled to the whole output.
    fn affine_measures(&self, window: [f64; 4], out: Size) -> (Option<f64>, Option<f64>, f64) {
        let [x0, y0, x1, y1] = window;
        let sx = out.width as f64 / (x1 - x0).max(1e-9);
        let sy = out.height as f64 / (y1 - y0).max(1e-9);
        let mut inside = 0usize;
        let mut sum = 0.0f64;
        let (xa, xb) = (
            x0.max(0.0).ceil() as u32,
            (x1.min(self.size.width as f64)) as u32,
        );
        let (ya, yb) = (
            y0.max(0.0).ceil() as u32,
            (y1.min(self.size.height as f64)) as u32,
        );
        for y in ya..yb {
            for x in xa..xb {
                let v = self.vsm.get(x, y);
                sum += v as f64;
                inside += (SaliencyLevel::of(v) == SaliencyLevel::Salient) as usize;
            }
        }
        let j = DMat2::from_cols(DVec2::new(sx, 0.0), DVec2::new(0.0, sy));
        let distortion = (inside > 0).then(|| similarity_deviation(j));
        let area = (self.salient > 0).then(|| inside as f64 * sx * sy / self.salient as f64);
        (distortion, area, sum * sx * sy)
    }

    /// Source positions of every output pixel (seam carving).
    fn origin_measures(&self, o: &crate::baseline::OriginMap) -> (Option<f64>, Option<f64>, f64) {
        let size = o.size();
        let (w, h) = (size.width, size.height);
        let (sw, sh) = (self.size.width, self.size.height);
        let at = |x: u32, y: u32| {
            let [a, b] = o.get(x, y);
            DVec2::new(a as f64, b as f64)
        };
        let (mut d_sum, mut d_weight, mut kept) = (0.0, 0.0, 0usize);
        let mut carried = 0.0f64;
        for y in 0..h {
            for x in 0..w {
                let p = at(x, y);
                let sx = (p.x.round().max(0.0) as u32).min(sw - 1);
                let sy = (p.y.round().max(0.0) as u32).min(sh - 1);
                let v = self.vsm.get(sx, sy);
                carried += v as f64;
                if SaliencyLevel::of(v) != SaliencyLevel::Salient {
                    continue;
                }
                kept += 1;
                // Columns of the inverse map's Jacobian: source steps per output pixel.
                let dx = match (x + 1 < w, x > 0) {
                    (true, _) => at(x + 1, y) - p,
                    (false, true) => p - at(x - 1, y),
                    _ => DVec2::new(sw as f64, 0.0),
                };
                let dy = match (y + 1 < h, y > 0) {
                    (true, _) => at(x, y + 1) - p,
                    (false, true) => p - at(x, y - 1),
                    _ => DVec2::new(0.0, sh as f64),
                };
                let inv = DMat2::from_cols(dx, dy);
                let det = inv.determinant();
                if det <= 1e-9 {
                    continue;
                }
                d_sum += det * similarity_deviation(inv.inverse());
                d_weight += det;
            }
        }
        let distortion = (d_weight > 0.0).then(|| d_sum / d_weight);
        let area = (self.salient > 0).then(|| kept as f64 / self.salient as f64);
        (distortion, area, carried)
    }
}

/// Sum of the VSM over the image's pixels and the number of salient (level 3) pixels.
fn pixel_sums(vsm: &Vsm) -> (f64, usize) {
    let size = vsm.size();
    let (mut sum, mut salient) = (0.0f64, 0usize);
    for y in 0..size.height {
        let mut row = 0.0f64;
        for x in 0..size.width {
            let s = vsm.get(x, y);
            row += s as f64;
            salient += (SaliencyLevel::of(s) == SaliencyLevel::Salient) as usize;
        }
        sum += row;
    }
    (sum, salient)
}

/// The affine map's Jacobian taking source triangle `p` to `q`; `None` for a degenerate `p`.
fn jacobian(p: [DVec2; 3], q: [DVec2; 3]) -> Option<DMat2> {
    let src = DMat2::from_cols(p[1] - p[0], p[2] - p[0]);
    let dst = DMat2::from_cols(q[1] - q[0], q[2] - q[0]);
    (src.determinant().abs() > 1e-12).then(|| dst * src.inverse())
}

/// `‖J − s·I‖_F / s` with `s = (J₀₀ + J₁₁)/2`: 0 for a uniform scaling.
pub fn similarity_deviation(j: DMat2) -> f64 {
    let s = (j.x_axis.x + j.y_axis.y) / 2.0;
    let d = j - DMat2::from_diagonal(DVec2::splat(s));
    let norm = (d.x_axis.length_squared() + d.y_axis.length_squared()).sqrt();
    norm / s.abs().max(1e-9)
}
