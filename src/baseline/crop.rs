//! Cropping to the most salient window: scale uniformly so the image covers the target (fill),
//! then keep the target-shaped window with the largest summed VSM saliency, found with a
//! summed-area table over the map's cells. Among equally salient windows the most central one
//! wins (an empty image is centre-cropped).

use super::{linear, ms_since, Mapping, MethodOutput, MethodStats};
use crate::image::{Image, Size};
use crate::retarget::StageTimes;
use crate::saliency::{Vsm, VsmBuilder};
use std::sync::Arc;
use std::time::Instant;

pub(super) fn run(image: &Image, target: Size) -> MethodOutput {
    let mut times = StageTimes::default();
    let t = Instant::now();
    let vsm = VsmBuilder::new().build(image.as_ref());
    times.vsm_ms = ms_since(t);
    let t = Instant::now();
    let [x0, y0, ww, wh] = best_window(&vsm, target);
    times.solve_ms = ms_since(t);
    let t = Instant::now();
    let out = if ww == image.width() && wh == image.height() {
        linear::resize(image.as_ref(), target)
    } else {
        let mut px = Vec::with_capacity(ww as usize * wh as usize);
        for y in y0..y0 + wh {
            px.extend_from_slice(&image.row(y)[x0 as usize..(x0 + ww) as usize]);
        }
        let size = Size {
            width: ww,
            height: wh,
        };
        let cut = Image::from_pixels(size, px).expect("window inside the image");
        linear::resize(cut.as_ref(), target)
    };
    times.render_ms = ms_since(t);
    MethodOutput {
        method: super::Method::Crop,
        image: out,
        stats: MethodStats {
            times,
            ..MethodStats::default()
        },
        mapping: Mapping::Affine {
            window: [x0 as f64, y0 as f64, (x0 + ww) as f64, (y0 + wh) as f64],
        },
        vsm: Some(Arc::new(vsm)),
    }
}

/// The window `[x0, y0, width, height]` (source pixels) of the target's aspect ratio, as large
/// as the image allows along one axis, holding the most saliency.
pub(crate) fn best_window(vsm: &Vsm, target: Size) -> [u32; 4] {
    let size = vsm.size();
    let (w, h) = (size.width as f64, size.height as f64);
    // Cover: the scale at which the image fills the target on both axes.
    let f = (target.width as f64 / w).max(target.height as f64 / h);
    let ww = ((target.width as f64 / f).round() as u32).clamp(1, size.width);
    let wh = ((target.height as f64 / f).round() as u32).clamp(1, size.height);

    // Summed-area table over the map's cells (`s` image pixels per cell).
    let s = vsm.scale();
    let grid = vsm.grid_size();
    let (gw, gh) = (grid.width as usize, grid.height as usize);
    let mut sat = vec![0f64; (gw + 1) * (gh + 1)];
    for y in 0..gh {
        let mut row = 0f64;
        for x in 0..gw {
            row += vsm.values()[y * gw + x] as f64;
            sat[(y + 1) * (gw + 1) + x + 1] = sat[y * (gw + 1) + x + 1] + row;
        }
    }
    let total = sat[(gh + 1) * (gw + 1) - 1];
    let sum = |x0: usize, y0: usize, x1: usize, y1: usize| {
        sat[y1 * (gw + 1) + x1] - sat[y0 * (gw + 1) + x1] - sat[y1 * (gw + 1) + x0]
            + sat[y0 * (gw + 1) + x0]
    };
    // The window in cells, at least one.
    let cw = ((ww as f64 / s as f64).round() as usize).clamp(1, gw);
    let ch = ((wh as f64 / s as f64).round() as usize).clamp(1, gh);
    let eps = 1e-9 * total.max(1.0);
    let centre = ((gw - cw) as f64 / 2.0, (gh - ch) as f64 / 2.0);
    let mut best = (f64::NEG_INFINITY, f64::INFINITY, 0usize, 0usize);
    for cy in 0..=gh - ch {
        for cx in 0..=gw - cw {
            let v = sum(cx, cy, cx + cw, cy + ch);
            let d = (cx as f64 - centre.0).abs() + (cy as f64 - centre.1).abs();
            if v > best.0 + eps || (v >= best.0 - eps && d < best.1) {
                best = (v.max(best.0), d, cx, cy);
            }
        }
    }
    let x0 = (best.2 as u32 * s).min(size.width - ww);
    let y0 = (best.3 as u32 * s).min(size.height - wh);
    [x0, y0, ww, wh]
}
