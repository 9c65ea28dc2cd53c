//! Sizes in pixels: the ground floor, with its own error so that it depends on nothing.

/// Width and height in pixels. Both are at least 1 once validated by [`Size::new`].
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

/// Largest side the library accepts, for inputs and targets alike: 16384 px, as most GPUs and
/// image tools. Bigger values are almost always a typo and would allocate gigabytes.
pub const MAX_SIDE: u32 = 16384;

impl Size {
    /// A checked size: both sides in `1..=MAX_SIDE`.
    pub fn new(width: u32, height: u32) -> Result<Size, InvalidSize> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(InvalidSize { width, height });
        }
        Ok(Size { width, height })
    }

    /// Number of pixels.
    pub fn area(self) -> usize {
        self.width as usize * self.height as usize
    }
}

impl std::fmt::Display for Size {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

/// A width or height that is zero or above [`MAX_SIDE`]; converts into
/// [`crate::Error::InvalidSize`].
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct InvalidSize {
    pub width: u32,
    pub height: u32,
}

impl std::fmt::Display for InvalidSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "invalid size {}x{}: each side must be between 1 and {MAX_SIDE}",
            self.width, self.height
        )
    }
}

impl std::error::Error for InvalidSize {}
