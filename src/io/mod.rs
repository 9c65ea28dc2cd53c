//! Reading and writing frames: still images in, still images out.

mod still;

pub use still::{read_still, write_still, OutputFormat};
