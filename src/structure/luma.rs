//! Luminance at full resolution, composited over white, as bytes: the input of line and text
//! detection (both need the pixel grid exactly; the VSM may be at half resolution).

use crate::image::ImageRef;

/// Rec. 601 luma of every pixel (over white), row-major.
pub(crate) fn luma(image: ImageRef<'_>, out: &mut Vec<u8>) {
    // Sized first, then one loop over both slices: it runs in vectors, where `extend` from
    // a mapped iterator went pixel by pixel.
    out.clear();
    out.resize(image.pixels().len(), 0);
    for (o, p) in out.iter_mut().zip(image.pixels()) {
        let a = p[3] as u32;
        let y = (p[0] as u32 * 77 + p[1] as u32 * 150 + p[2] as u32 * 29) >> 8;
        *o = ((y * a + 255 * (255 - a) + 127) / 255) as u8;
    }
}
