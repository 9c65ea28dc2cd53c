//! numpy arrays to the library's RGBA8 [`Image`] and back.
//!
//! The library's frames own their pixels (a `Frame` holds an `Image`, and
//! `vizretarget::retarget` clones the picture it is lent), so one copy of the input is made
//! whatever the binding does: here it is the only one. A C-contiguous `H×W×4` array is
//! copied with one `memcpy`; `H×W×3` gains an opaque alpha; any other strides are walked
//! pixel by pixel. The copy is made while the GIL is held, so that no Python thread writes
//! the array while it is read. The output's pixels become the returned array's buffer
//! without a copy (RGBA), or are packed once to RGB.

use crate::arrow::{opaque_pixel, read_pil, Pixels};
use crate::errors::bad;
use numpy::ndarray::Array3;
use numpy::{
    dtype, IntoPyArray, PyArray3, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use vizretarget::{Image, Size};

/// A picture read from an array or a PIL image, and how its result goes back.
pub struct Picture {
    pub image: Image,
    pub out: Out,
}

/// What a result is given back as: the input's kind (an array or, for a PIL image,
/// [`Pixels`] for `PIL.Image.fromarrow`), with as many channels (3 or 4).
#[derive(Clone, Copy)]
pub struct Out {
    pub channels: usize,
    pub pil: bool,
}

/// Reads `obj`, an array as [`picture`] does or a PIL image in mode RGB or RGBA (the
/// package's Python half converts the other modes); `what` names it in errors.
pub fn input(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Picture> {
    if !obj.get_type().module()?.to_cow()?.starts_with("PIL.") {
        return picture(obj, what);
    }
    let mode: String = obj.getattr("mode")?.extract()?;
    let channels = match mode.as_str() {
        "RGB" => 3,
        "RGBA" => 4,
        _ => {
            return Err(bad(
                what,
                format!("expected a PIL image in mode RGB or RGBA, got {mode}"),
            ))
        }
    };
    let (w, h): (usize, usize) = obj.getattr("size")?.extract()?;
    let side = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    let size = Size::new(side(w), side(h)).map_err(|e| bad(what, e))?;
    let out = Out {
        channels,
        pil: true,
    };
    let Some(pixels) = read_pil(obj, w, h, channels == 3)? else {
        // Not exported in one piece (a large image, an older Pillow): through numpy.
        let array = obj.py().import("numpy")?.call_method1("asarray", (obj,))?;
        let p = picture(&array, what)?;
        return Ok(Picture {
            image: p.image,
            out,
        });
    };
    let image = Image::from_pixels(size, pixels)
        .ok_or_else(|| PyRuntimeError::new_err("internal error: pixel count"))?;
    Ok(Picture { image, out })
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
    // `as_slice` also takes a column-major array, whose bytes are in another order.
    let packed = if view.is_c_contiguous() {
        view.as_slice().ok()
    } else {
        None
    };
    // Written once each (no zeroing first).
    let pixels: Vec<[u8; 4]> = match packed {
        Some(bytes) if channels == 4 => bytes.as_chunks::<4>().0.to_vec(),
        Some(bytes) => rgb_to_rgba(bytes),
        None => view
            .as_array()
            .rows()
            .into_iter()
            .map(|lane| {
                let a = if channels == 4 { lane[3] } else { 255 };
                [lane[0], lane[1], lane[2], a]
            })
            .collect(),
    };
    let image = Image::from_pixels(size, pixels)
        .ok_or_else(|| PyRuntimeError::new_err("internal error: pixel count"))?;
    let pil = false;
    Ok(Picture {
        image,
        out: Out { channels, pil },
    })
}

/// Packed RGB to RGBA, opaque. Four pixels at a time, in arrays of fixed length, so that
/// the compiler turns each into one shuffle: byte by byte it took about 1 ms more on a
/// 1237x744 picture than copying RGBA. Collected from an iterator of known length, so that
/// each byte is written once (filling a zeroed vector wrote it twice).
fn rgb_to_rgba(bytes: &[u8]) -> Vec<[u8; 4]> {
    let n = bytes.len() / 3;
    let (src, src_rest) = bytes.as_chunks::<12>();
    let mut quads: Vec<[[u8; 4]; 4]> = Vec::with_capacity(n.div_ceil(4));
    quads.extend(src.iter().map(|s| {
        [
            [s[0], s[1], s[2], 255],
            [s[3], s[4], s[5], 255],
            [s[6], s[7], s[8], 255],
            [s[9], s[10], s[11], 255],
        ]
    }));
    if !src_rest.is_empty() {
        let mut last = [[0, 0, 0, 255]; 4];
        for (d, s) in last.iter_mut().zip(src_rest.as_chunks::<3>().0) {
            *d = [s[0], s[1], s[2], 255];
        }
        quads.push(last);
    }
    let mut out = quads.into_flattened();
    out.truncate(n);
    out
}

/// RGBA to packed RGB, four pixels at a time as [`rgb_to_rgba`].
fn rgba_to_rgb(pixels: &[[u8; 4]]) -> Vec<u8> {
    let n = pixels.len() * 3;
    let (src, src_rest) = pixels.as_chunks::<4>();
    let mut out: Vec<[u8; 12]> = Vec::with_capacity(n.div_ceil(12));
    out.extend(src.iter().map(|[a, b, c, d]| {
        [
            a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2],
        ]
    }));
    if !src_rest.is_empty() {
        let mut last = [0; 12];
        for (d, s) in last.as_chunks_mut::<3>().0.iter_mut().zip(src_rest) {
            *d = [s[0], s[1], s[2]];
        }
        out.push(last);
    }
    let mut out = out.into_flattened();
    out.truncate(n);
    out
}

/// A retargeted picture made ready for its [`Out`]; called with the GIL released (the
/// packing is the library's side of the work).
pub enum Packed {
    /// `H×W×channels` bytes for an array.
    Array {
        height: usize,
        width: usize,
        channels: usize,
        bytes: Vec<u8>,
    },
    /// The pixels as they are (the fourth byte 255 for RGB) for a PIL image.
    Pil(Pixels),
}

pub fn pack(image: Image, out: Out) -> Packed {
    let (width, height) = (image.width(), image.height());
    let mut pixels = image.into_pixels();
    if out.pil {
        if out.channels == 3 {
            // What Pillow keeps in an RGB pixel's unused byte.
            pixels.iter_mut().for_each(|p| *p = opaque_pixel(*p));
        }
        return Packed::Pil(Pixels::new(width, height, pixels));
    }
    let (width, height) = (width as usize, height as usize);
    let bytes = if out.channels == 4 {
        pixels.into_flattened()
    } else {
        rgba_to_rgb(&pixels)
    };
    Packed::Array {
        height,
        width,
        channels: out.channels,
        bytes,
    }
}

impl Packed {
    /// The array over the packed bytes, or the [`Pixels`] (no copy either way).
    pub fn into_py(self, py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
        match self {
            Packed::Array {
                height,
                width,
                channels,
                bytes,
            } => {
                let a = Array3::from_shape_vec((height, width, channels), bytes)
                    .map_err(|e| PyRuntimeError::new_err(format!("internal error: {e}")))?;
                Ok(a.into_pyarray(py).into_any())
            }
            Packed::Pil(p) => Ok(Bound::new(py, p)?.into_any()),
        }
    }
}
