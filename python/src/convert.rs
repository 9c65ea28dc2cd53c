//! numpy arrays to the library's RGBA8 [`Image`] and back.
//!
//! The library's frames own their pixels (a `Frame` holds an `Image`, and
//! `vizretarget::retarget` clones the picture it is lent), so one copy of the input is made
//! whatever the binding does: here it is the only one. A C-contiguous `H×W×4` array is
//! copied with one `memcpy`; `H×W×3` gains an opaque alpha; any other strides are walked
//! pixel by pixel. The copy is made while the GIL is held, so that no Python thread writes
//! the array while it is read. The output's pixels become the returned array's buffer
//! without a copy (RGBA), or are packed once to RGB.

use crate::errors::bad;
use numpy::ndarray::Array3;
use numpy::{
    dtype, IntoPyArray, PyArray3, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use vizretarget::{Image, Size};

/// A picture read from an array, and whether it had 3 or 4 channels (the output gets as
/// many).
pub struct Picture {
    pub image: Image,
    pub channels: usize,
}

/// Reads `obj`, a numpy `uint8` array `H×W×3` or `H×W×4` of any strides; `what` names it
/// in errors.
pub fn picture(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Picture> {
    let py = obj.py();
    let Ok(untyped) = obj.cast::<PyUntypedArray>() else {
        let kind = obj.get_type().name()?;
        return Err(bad(
            what,
            format!("expected a numpy uint8 array H×W×3 or H×W×4 or a PIL image, got {kind}"),
        ));
    };
    let dt = untyped.dtype();
    if !dt.is_equiv_to(&dtype::<u8>(py)) {
        return Err(bad(
            what,
            format!(
                "expected dtype uint8 (0 to 255 per channel), got {}",
                dt.str()?
            ),
        ));
    }
    let shape = untyped.shape();
    if shape.len() != 3 || !(shape[2] == 3 || shape[2] == 4) {
        return Err(bad(
            what,
            format!("expected shape (H, W, 3) or (H, W, 4), got {shape:?}"),
        ));
    }
    let (h, w, channels) = (shape[0], shape[1], shape[2]);
    let side = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    let size = Size::new(side(w), side(h)).map_err(|e| bad(what, e))?;
    let array = obj.cast::<PyArray3<u8>>()?;
    let view = array.try_readonly().map_err(|e| bad(what, e))?;
    let mut pixels = vec![[0u8; 4]; size.area()];
    // `as_slice` also takes a column-major array, whose bytes are in another order.
    let packed = if view.is_c_contiguous() {
        view.as_slice().ok()
    } else {
        None
    };
    match packed {
        Some(bytes) if channels == 4 => pixels.as_flattened_mut().copy_from_slice(bytes),
        Some(bytes) => {
            for (p, s) in pixels.iter_mut().zip(bytes.chunks_exact(3)) {
                *p = [s[0], s[1], s[2], 255];
            }
        }
        None => {
            let a = view.as_array();
            for (p, lane) in pixels.iter_mut().zip(a.rows()) {
                *p = [
                    lane[0],
                    lane[1],
                    lane[2],
                    if channels == 4 { lane[3] } else { 255 },
                ];
            }
        }
    }
    let image = Image::from_pixels(size, pixels)
        .ok_or_else(|| PyRuntimeError::new_err("internal error: pixel count"))?;
    Ok(Picture { image, channels })
}

/// A retargeted picture packed for an array of `channels` (3 or 4): `(height, width, bytes)`.
/// Called with the GIL released: the packing is the library's side of the work.
pub struct Packed {
    height: usize,
    width: usize,
    channels: usize,
    bytes: Vec<u8>,
}

pub fn pack(image: Image, channels: usize) -> Packed {
    let (width, height) = (image.width() as usize, image.height() as usize);
    let pixels = image.into_pixels();
    let bytes = if channels == 4 {
        pixels.into_flattened()
    } else {
        pixels.iter().flat_map(|p| [p[0], p[1], p[2]]).collect()
    };
    Packed {
        height,
        width,
        channels,
        bytes,
    }
}

impl Packed {
    /// The array, over the packed bytes (no copy).
    pub fn into_array(self, py: Python<'_>) -> PyResult<Bound<'_, PyArray3<u8>>> {
        let a = Array3::from_shape_vec((self.height, self.width, self.channels), self.bytes)
            .map_err(|e| PyRuntimeError::new_err(format!("internal error: {e}")))?;
        Ok(a.into_pyarray(py))
    }
}
