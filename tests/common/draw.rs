//! Drawing synthetic charts for the tests: filled rectangles (axes, bars, frames) and discs
//! (dots, bubbles), with no antialiasing so that what is measured is what was drawn.

use vizretarget::Image;

/// Fills `[x0, x1) × [y0, y1)` of `img` (clipped) with `c`.
pub fn rect(img: &mut Image, x0: u32, y0: u32, x1: u32, y1: u32, c: [u8; 4]) {
    for y in y0..y1.min(img.height()) {
        for x in x0..x1.min(img.width()) {
            img.set(x, y, c);
        }
    }
}

/// A disc of radius `r` centred at `(cx, cy)` (pixel centres inside it), clipped.
pub fn disc(img: &mut Image, cx: f32, cy: f32, r: f32, c: [u8; 4]) {
    for y in (cy - r - 1.0).max(0.0) as u32..((cy + r + 2.0) as u32).min(img.height()) {
        for x in (cx - r - 1.0).max(0.0) as u32..((cx + r + 2.0) as u32).min(img.width()) {
            let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
            if dx * dx + dy * dy <= r * r {
                img.set(x, y, c);
            }
        }
    }
}
