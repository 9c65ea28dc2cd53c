//! The structure a visualization is made of, found from pixels only: long horizontal and
//! vertical lines (panel frames, axes, grid lines, bar sides) and text blocks. The mesh puts
//! vertices and edges on them and the solver keeps lines straight and axis-aligned and text
//! blocks similar (one scale, no shear), which the paper's energy alone does not.
//!
//! * [`lines`]: runs of luminance steps along pixel-row and -column boundaries;
//! * [`text`]: rows of small high-contrast components.

mod lines;
mod luma;
mod text;

pub use lines::Line;
pub use text::TextBlock;

use crate::image::ImageRef;

/// What was found in one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Structure {
    /// Horizontal lines: `pos` is y.
    pub horizontal: Vec<Line>,
    /// Vertical lines: `pos` is x.
    pub vertical: Vec<Line>,
    /// Text blocks.
    pub text: Vec<TextBlock>,
}

impl Structure {
    /// Finds lines and text in `image`.
    pub fn detect(image: ImageRef<'_>) -> Structure {
        let (w, h) = (image.width() as usize, image.height() as usize);
        let mut l = Vec::new();
        luma::luma(image, &mut l);
        let (h_found, v_found) = (lines::horizontal(&l, w, h), lines::vertical(&l, w, h));
        let (mut horizontal, mut vertical) = (h_found.solid, v_found.solid);
        // Text is found among solid lines only: a chain may run along the foot of a word, and
        // clearing a faint line's pixels would cut a texture into glyph-sized pieces.
        let text = text::detect(&l, w, h, [&horizontal, &vertical]);
        // A chain or a faint line crossing a text block is the foot or the top of its words.
        let clear = |line: &Line, across: fn(&TextBlock) -> [u32; 4]| {
            text.iter().all(|b| {
                let [a0, a1, s0, s1] = across(b);
                line.pos < a0 as f64 - 1.0
                    || line.pos > a1 as f64 + 1.0
                    || line.to <= s0 as f64
                    || line.from >= s1 as f64
            })
        };
        horizontal.extend(
            (h_found.chained.into_iter())
                .chain(h_found.weak)
                .filter(|l| clear(l, |b| [b.y0, b.y1, b.x0, b.x1])),
        );
        vertical.extend(
            (v_found.chained.into_iter())
                .chain(v_found.weak)
                .filter(|l| clear(l, |b| [b.x0, b.x1, b.y0, b.y1])),
        );
        Structure {
            horizontal,
            vertical,
            text,
        }
    }

    /// Nothing found.
    pub fn is_empty(&self) -> bool {
        self.horizontal.is_empty() && self.vertical.is_empty() && self.text.is_empty()
    }
}
