//! Keyword options, as the command line names them (`alpha`, `regions`, `enhance_region`,
//! `marks`, ...), to the library's [`Options`], [`Limits`] and target. Each value is checked
//! by the library (`Options::validate`, `Side::parse`, `Target::parse`): the messages are the
//! command line's. Only the spelling of a value from Python is handled here.

use crate::convert::picture;
use crate::errors::{bad, to_py};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyDictMethods, PyString, PyTuple};
use std::path::PathBuf;
use std::sync::Arc;
use vizretarget::vector::{parse_layer, read_layer};
use vizretarget::{
    parse_bytes, EnhanceMask, EnhanceRegion, Enhancement, Limits, MarkSize, Method, Options,
    Regions, Side, Size, Target, VectorLayer,
};

/// The options of one picture (`retarget`).
pub const STILL: &[&str] = &[
    "method",
    "regions",
    "fill",
    "layout",
    "alpha",
    "enhance",
    "enhance_region",
    "enhance_mask",
    "enhance_mask_factor",
    "marks",
    "paint_out_marks",
    "mark_size",
];
/// What a stream adds: its reuse policy.
pub const REUSE: &[&str] = &[
    "no_reuse",
    "reuse_tile",
    "tile_threshold",
    "rebuild_fraction",
];
/// What reading and writing files adds.
pub const FILES: &[&str] = &["max_pixels", "max_frames", "memory_limit", "fps"];
/// The options of `compare`.
pub const COMPARE: &[&str] = &["alpha", "mesh", "metrics"];

/// Options as given, checked against the names a call takes.
pub struct Given<'py> {
    dict: Option<Bound<'py, PyDict>>,
}

impl<'py> Given<'py> {
    /// `dict`'s keys must all be in one of `allowed`.
    pub fn new(dict: Option<Bound<'py, PyDict>>, allowed: &[&[&str]]) -> PyResult<Given<'py>> {
        if let Some(d) = &dict {
            for key in d.keys() {
                let key: String = key.extract()?;
                if !allowed.iter().any(|a| a.contains(&key.as_str())) {
                    let names: Vec<&str> = allowed.iter().flat_map(|a| a.iter().copied()).collect();
                    return Err(bad(
                        &format!("unknown option '{key}'"),
                        format!("allowed {}", names.join(", ")),
                    ));
                }
            }
        }
        Ok(Given { dict })
    }

    /// The value of `key`, unless absent or `None`.
    fn raw(&self, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
        match &self.dict {
            Some(d) => Ok(d.get_item(key)?.filter(|v| !v.is_none())),
            None => Ok(None),
        }
    }

    /// The value of `key` as `T`; a value of the wrong type is a `ValueError` naming it.
    pub fn get<T>(&self, key: &str) -> PyResult<Option<T>>
    where
        T: for<'a> FromPyObject<'a, 'py, Error = PyErr>,
    {
        match self.raw(key)? {
            Some(v) => v.extract::<T>().map(Some).map_err(|e| {
                let t = v
                    .get_type()
                    .name()
                    .map(|n| n.to_string())
                    .unwrap_or_default();
                bad(
                    &format!("option {key}"),
                    format!("{} (got {t})", e.value(v.py())),
                )
            }),
            None => Ok(None),
        }
    }
}

/// The library's options for a still or a stream.
pub fn options(given: &Given<'_>) -> PyResult<Options> {
    let mut o = Options::default();
    if let Some(a) = given.get::<f32>("alpha")? {
        o = o.with_alpha(a);
    }
    if let Some(r) = given.get::<String>("regions")? {
        o = o.with_regions(match r.trim().to_ascii_lowercase().as_str() {
            "affine" => Regions::Affine,
            "auto" => Regions::Auto,
            "free" => Regions::Free,
            _ => {
                return Err(bad(
                    "option regions",
                    format!("unknown regions {r:?}: allowed affine, auto, free"),
                ))
            }
        });
    }
    if let Some(f) = given.get::<bool>("fill")? {
        o = o.with_fill(f);
    }
    if let Some(l) = given.get::<bool>("layout")? {
        o = o.with_layout(l);
    }
    o.enhance = Enhancement {
        per_level: given.get::<[f64; 3]>("enhance")?.unwrap_or([1.0; 3]),
        regions: regions(given)?,
        mask: mask(given)?,
    };
    if let Some(layer) = marks(given)? {
        o = o.with_marks(layer);
    }
    if let Some(p) = given.get::<bool>("paint_out_marks")? {
        o.vector.paint_out = p;
    }
    if let Some(s) = given.get::<String>("mark_size")? {
        o.vector.size = match s.trim().to_ascii_lowercase().as_str() {
            "mesh" => MarkSize::Mesh,
            "keep" => MarkSize::Keep,
            _ => {
                return Err(bad(
                    "option mark_size",
                    format!("unknown mark size {s:?}: allowed mesh, keep"),
                ))
            }
        };
    }
    if let Some(n) = given.get::<bool>("no_reuse")? {
        o.reuse.enabled = !n;
    }
    if let Some(t) = given.get::<u32>("reuse_tile")? {
        o.reuse.tile_px = t;
    }
    if let Some(t) = given.get::<f32>("tile_threshold")? {
        o.reuse.tile_threshold = t;
    }
    if let Some(f) = given.get::<f64>("rebuild_fraction")? {
        o.reuse.rebuild_fraction = f;
    }
    o.validate().map_err(to_py)?;
    Ok(o)
}

/// `method`: `"mesh"` (the default) or a method compared against, which draws no marks
/// and enlarges nothing (refused with them, as on the command line).
pub fn method(given: &Given<'_>, options: &Options) -> PyResult<Method> {
    let method = match given.get::<String>("method")? {
        Some(m) => m.parse().map_err(to_py)?,
        None => Method::Mesh,
    };
    let vector = options.marks.is_some()
        || options.vector.paint_out
        || !options.enhance.is_identity()
        || given.raw("marks")?.is_some();
    if method != Method::Mesh && vector {
        return Err(bad(
            "option method",
            "marks, paint_out_marks and enhance* work with method mesh (the default)",
        ));
    }
    Ok(method)
}

/// `enhance_region`: one `(x, y, w, h, factor)` or a list of them (the last wins where
/// they overlap, as on the command line).
fn regions(given: &Given<'_>) -> PyResult<Vec<EnhanceRegion>> {
    let Some(v) = given.raw("enhance_region")? else {
        return Ok(Vec::new());
    };
    let one = |r: &Bound<'_, PyAny>| -> PyResult<EnhanceRegion> {
        let [x, y, width, height, factor] = r.extract::<[f64; 5]>().map_err(|_| {
            bad(
                "option enhance_region",
                "expected (x, y, width, height, factor) in input pixels, or a list of them",
            )
        })?;
        Ok(EnhanceRegion {
            x,
            y,
            width,
            height,
            factor,
        })
    };
    if let Ok(r) = one(&v) {
        return Ok(vec![r]);
    }
    let items: Vec<Bound<'_, PyAny>> = v.extract().map_err(|_| {
        bad(
            "option enhance_region",
            "expected a list of (x, y, w, h, factor)",
        )
    })?;
    items.iter().map(one).collect()
}

/// `enhance_mask`: a path or an array; white enlarges by `enhance_mask_factor` (1.5).
fn mask(given: &Given<'_>) -> PyResult<Option<Arc<EnhanceMask>>> {
    let Some(v) = given.raw("enhance_mask")? else {
        return Ok(None);
    };
    let factor = given.get::<f64>("enhance_mask_factor")?.unwrap_or(1.5);
    let image = match v.extract::<PathBuf>() {
        Ok(path) => vizretarget::io::read_still(&path).map_err(to_py)?,
        Err(_) => picture(&v, "option enhance_mask")?.image,
    };
    EnhanceMask::from_image(&image, factor)
        .map(|m| Some(Arc::new(m)))
        .map_err(to_py)
}

/// `marks` as one layer: a dict (the JSON format of `--marks`) or the path of a JSON file.
/// A path to a `.jsonl` file or a folder is for streams of files: see [`marks_path`].
fn marks(given: &Given<'_>) -> PyResult<Option<VectorLayer>> {
    let Some(v) = given.raw("marks")? else {
        return Ok(None);
    };
    if let Some(path) = path_of(&v)? {
        if path.is_dir() || path.extension().is_some_and(|e| e == "jsonl") {
            return Ok(None);
        }
        return read_layer(&path).map(Some).map_err(to_py);
    }
    layer(&v).map(Some)
}

/// A layer of marks from a dict in the JSON format of `--marks`.
pub fn layer(v: &Bound<'_, PyAny>) -> PyResult<VectorLayer> {
    let json = v.py().import("json")?;
    let text: String = json
        .call_method1("dumps", (v,))
        .map_err(|e| bad("marks", e.value(v.py())))?
        .extract()?;
    parse_layer(&text).map_err(|e| bad("marks", e))
}

/// `marks` when it names a JSON Lines file or a folder: per-frame marks of a stream.
pub fn marks_path(given: &Given<'_>) -> PyResult<Option<PathBuf>> {
    match given.raw("marks")? {
        Some(v) => {
            Ok(path_of(&v)?.filter(|p| p.is_dir() || p.extension().is_some_and(|e| e == "jsonl")))
        }
        None => Ok(None),
    }
}

/// `v` as a path if it is a `str` or an `os.PathLike`.
fn path_of(v: &Bound<'_, PyAny>) -> PyResult<Option<PathBuf>> {
    if v.is_instance_of::<PyString>() || v.hasattr("__fspath__")? {
        return Ok(Some(v.extract()?));
    }
    Ok(None)
}

/// The limits of reading files: the command line's defaults, `0` for no limit.
pub fn limits(given: &Given<'_>) -> PyResult<Limits> {
    let off = |v: u64| (v != 0).then_some(v);
    let d = Limits::default();
    let memory = match given.raw("memory_limit")? {
        Some(v) => match v.extract::<u64>() {
            Ok(n) => off(n),
            Err(_) => {
                let s: String = given.get("memory_limit")?.unwrap_or_default();
                off(parse_bytes(&s).map_err(|e| bad("option memory_limit", e))?)
            }
        },
        None => d.memory_budget,
    };
    Ok(Limits {
        max_pixels: given.get::<u64>("max_pixels")?.map_or(d.max_pixels, off),
        max_frames: given.get::<u64>("max_frames")?.map_or(d.max_frames, off),
        memory_budget: memory,
    })
}

/// The target as given: `(w, h)` with `None` for a side to keep and each side in px or a
/// string (`"50%"`); a string as `--size` takes it (`"400x600"`, `"50%x100%"`, `"400x"`); a
/// string of one side alone (`"50%"`) for both sides; `None` for the input's size.
pub fn target(size: &Bound<'_, PyAny>) -> PyResult<Target> {
    let side = |v: &Bound<'_, PyAny>| -> PyResult<Option<Side>> {
        if v.is_none() {
            return Ok(None);
        }
        if let Ok(s) = v.extract::<String>() {
            return Side::parse(&s).map(Some).map_err(|e| bad("size", e));
        }
        match v.extract::<i64>() {
            Ok(n) if !v.is_instance_of::<pyo3::types::PyBool>() => Side::px(n)
                .map(|n| Some(Side::Px(n)))
                .map_err(|e| bad("size", e)),
            _ => Err(bad(
                "size",
                format!(
                    "each side is a whole number of pixels, a percentage such as \"50%\", or None \
                     to keep it; got {}",
                    v.get_type().name()?
                ),
            )),
        }
    };
    if size.is_none() {
        return Ok(Target::default());
    }
    if let Ok(s) = size.extract::<String>() {
        if s.contains(['x', 'X']) {
            return Target::parse(&s).map_err(|e| bad("size", e));
        }
        let one = Side::parse(&s).map_err(|e| bad("size", e))?;
        return Ok(Target {
            width: Some(one),
            height: Some(one),
        });
    }
    let pair = size
        .cast::<PyTuple>()
        .ok()
        .map(|t| t.iter().collect::<Vec<_>>())
        .or_else(|| size.extract::<Vec<Bound<'_, PyAny>>>().ok())
        .filter(|v| v.len() == 2)
        .ok_or_else(|| {
            bad(
                "size",
                "expected (width, height), a side None to keep it, or a string such as \
                 \"400x600\", \"400x\" or \"50%\"",
            )
        })?;
    Ok(Target {
        width: side(&pair[0])?,
        height: side(&pair[1])?,
    })
}

/// `target` for an input of size `from`.
pub fn resolve(target: &Target, from: Size) -> PyResult<Size> {
    target.resolve(from).map_err(|e| bad("size", e))
}
