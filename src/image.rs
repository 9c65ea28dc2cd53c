//! Owned and borrowed RGBA8 rasters.
//!
//! Every stage works on straight (not premultiplied) RGBA8 in rows; the renderer premultiplies on
//! the fly while filtering so that transparent pixels never bleed colour into their neighbours.

pub use crate::size::{Size, MAX_SIDE};

/// An owned RGBA8 image, rows top to bottom, no padding.
#[derive(Clone, PartialEq, Eq)]
pub struct Image {
    size: Size,
    data: Vec<[u8; 4]>,
}

impl std::fmt::Debug for Image {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Image").field("size", &self.size).finish()
    }
}

impl Image {
    /// A transparent black image.
    pub fn new(size: Size) -> Image {
        Image {
            size,
            data: vec![[0; 4]; size.area()],
        }
    }

    /// An image filled with one colour.
    pub fn filled(size: Size, rgba: [u8; 4]) -> Image {
        Image {
            size,
            data: vec![rgba; size.area()],
        }
    }

    /// Wraps RGBA8 pixels; `None` if the length does not match the size.
    pub fn from_pixels(size: Size, data: Vec<[u8; 4]>) -> Option<Image> {
        (data.len() == size.area()).then_some(Image { size, data })
    }

    /// Copies packed RGBA8 bytes (4 per pixel); `None` if the length does not match.
    pub fn from_rgba_bytes(size: Size, bytes: &[u8]) -> Option<Image> {
        if bytes.len() != size.area() * 4 {
            return None;
        }
        let data = bytes
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        Some(Image { size, data })
    }

    pub fn size(&self) -> Size {
        self.size
    }
    pub fn width(&self) -> u32 {
        self.size.width
    }
    pub fn height(&self) -> u32 {
        self.size.height
    }

    /// Pixels, row-major.
    pub fn pixels(&self) -> &[[u8; 4]] {
        &self.data
    }
    pub fn pixels_mut(&mut self) -> &mut [[u8; 4]] {
        &mut self.data
    }

    /// The pixels as packed bytes (RGBA, 4 per pixel).
    pub fn as_bytes(&self) -> &[u8] {
        self.data.as_flattened()
    }

    pub fn into_pixels(self) -> Vec<[u8; 4]> {
        self.data
    }

    /// A borrowed view.
    pub fn as_ref(&self) -> ImageRef<'_> {
        ImageRef {
            size: self.size,
            data: &self.data,
        }
    }

    /// One row.
    pub fn row(&self, y: u32) -> &[[u8; 4]] {
        let w = self.size.width as usize;
        &self.data[y as usize * w..(y as usize + 1) * w]
    }

    pub fn row_mut(&mut self, y: u32) -> &mut [[u8; 4]] {
        let w = self.size.width as usize;
        &mut self.data[y as usize * w..(y as usize + 1) * w]
    }

    pub fn get(&self, x: u32, y: u32) -> [u8; 4] {
        self.data[y as usize * self.size.width as usize + x as usize]
    }

    pub fn set(&mut self, x: u32, y: u32, rgba: [u8; 4]) {
        let w = self.size.width as usize;
        self.data[y as usize * w + x as usize] = rgba;
    }

    /// True when every pixel is fully opaque. The AND of whole pixels, 64 at a time (its top
    /// byte is the AND of their alphas): a test per pixel, with its early exit, went a byte
    /// at a time and cost a frame of a stream as much as the luma.
    pub fn is_opaque(&self) -> bool {
        all_opaque(&self.data)
    }
}

/// A borrowed RGBA8 image.
#[derive(Copy, Clone, Debug)]
pub struct ImageRef<'a> {
    size: Size,
    data: &'a [[u8; 4]],
}

impl<'a> ImageRef<'a> {
    /// True when every pixel is fully opaque ([`Image::is_opaque`]).
    pub fn is_opaque(&self) -> bool {
        all_opaque(self.data)
    }

    /// `None` if the slice length does not match the size.
    pub fn new(size: Size, data: &'a [[u8; 4]]) -> Option<ImageRef<'a>> {
        (data.len() == size.area()).then_some(ImageRef { size, data })
    }
    pub fn size(&self) -> Size {
        self.size
    }
    pub fn width(&self) -> u32 {
        self.size.width
    }
    pub fn height(&self) -> u32 {
        self.size.height
    }
    pub fn pixels(&self) -> &'a [[u8; 4]] {
        self.data
    }
    pub fn rows(&self) -> std::slice::ChunksExact<'a, [u8; 4]> {
        self.data.chunks_exact(self.size.width as usize)
    }
    pub fn to_owned(&self) -> Image {
        Image {
            size: self.size,
            data: self.data.to_vec(),
        }
    }
}

/// Whether every pixel's alpha is 255, by the AND of whole pixels 64 at a time (its top byte
/// is the AND of their alphas).
fn all_opaque(px: &[[u8; 4]]) -> bool {
    let and = |q: &[[u8; 4]]| q.iter().fold(u32::MAX, |m, p| m & u32::from_le_bytes(*p));
    let mut chunks = px.chunks_exact(64);
    chunks.all(|c| and(c) >> 24 == 255) && and(chunks.remainder()) >> 24 == 255
}

/// `n` pixels of xorshift noise (every channel, alpha too) from `seed`: the test input that
/// leaves no byte pattern for a fast path to lean on.
#[cfg(test)]
pub(crate) fn noise_pixels(n: usize, seed: u32) -> Vec<[u8; 4]> {
    let mut s = seed | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            s.to_le_bytes()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_translucent_pixel_anywhere_makes_a_picture_not_opaque() {
        for (w, h) in [(1, 1), (7, 3), (64, 1), (13, 11)] {
            let size = Size::new(w, h).unwrap();
            let img = Image::filled(size, [10, 20, 30, 255]);
            assert!(img.is_opaque() && img.as_ref().is_opaque(), "{w}x{h}");
            for (x, y) in [(0, 0), (w - 1, h - 1), (w / 2, h / 2)] {
                let mut t = img.clone();
                t.set(x, y, [10, 20, 30, 254]);
                assert!(
                    !t.is_opaque() && !t.as_ref().is_opaque(),
                    "{w}x{h} at ({x}, {y})"
                );
            }
        }
    }
}
