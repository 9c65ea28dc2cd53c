//! Linear scaling: the crate's renderer over a two-triangle mesh scaled linearly, so that it
//! filters exactly as the mesh method does (bilinear, box-filtered ripmap taps where it
//! shrinks by more than 1.25×; thin lines do not alias away under strong minification).

use super::{ms_since, Mapping, MethodOutput, MethodStats};
use crate::image::{Image, ImageRef, Size};
use crate::mesh::Mesh;
use crate::render::Renderer;
use crate::retarget::StageTimes;
use crate::solve::Warp;
use std::time::Instant;

pub(super) fn run(image: &Image, target: Size) -> MethodOutput {
    let t = Instant::now();
    let out = resize(image.as_ref(), target);
    let (w, h) = (image.width() as f64, image.height() as f64);
    MethodOutput {
        method: super::Method::Linear,
        image: out,
        stats: MethodStats {
            times: StageTimes {
                render_ms: ms_since(t),
                ..StageTimes::default()
            },
            ..MethodStats::default()
        },
        mapping: Mapping::Affine {
            window: [0.0, 0.0, w, h],
        },
        vsm: None,
    }
}

/// `src` scaled to `target` (each axis on its own).
pub(super) fn resize(src: ImageRef<'_>, target: Size) -> Image {
    if src.size() == target {
        return src.to_owned();
    }
    let size = src.size();
    // One cell: the four corners, two triangles.
    let mesh = Mesh::lattice(size, size.width.max(size.height) as f64 * 2.0);
    let warp = Warp::linear(&mesh, target);
    let mut out = Image::new(target);
    Renderer::new().render(src, &mesh, &warp, &mut out);
    out
}
