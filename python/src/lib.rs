//! `vizretarget._vizretarget`: the native half of the Python package `vizretarget`. Arrays
//! in, arrays out; the package's Python half (`python/vizretarget/__init__.py`) takes PIL
//! images and keyword options, and holds the docstrings users read.
//!
//! Everything here goes through the library's public API; the GIL is released while the
//! library works.

mod arrow;
mod convert;
mod errors;
mod files;
mod options;
mod stats;
mod stream;

use convert::{input, pack, picture, Out, Packed};
use errors::to_py;
use options::{Given, COMPARE, FILES, REUSE, STILL};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use vizretarget::compare::{compare as compare_methods, SheetOptions};
use vizretarget::{retarget_with, Frame, Method, Retargeter};

/// The extension's own allocations (the library's, not Python's) go to mimalloc. A still
/// needs some 15 to 25 MB of working memory, all freed when the call returns; glibc's malloc
/// gave it back to the kernel at once (its heap top trimmed, its large blocks unmapped, a
/// thread arena's pages dropped), so every call page-faulted it in again: about 4,000 faults
/// and 9 to 11 ms of system time a 1237×744 still, on 15 ms of work (2026-12-07, perf and
/// getrusage). The command line's stream never paid it (its frames overlap on its stage
/// threads). mimalloc keeps freed memory for a second before it returns it (its
/// `purge_delay`), so calls in a batch reuse it: 17 to 100 faults a still, and its faster
/// small allocations took user time from 15 to 10 ms a still. `local_dynamic_tls`: the
/// extension is a library Python loads with dlopen.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// `(result, stats)`: `image` (an `H×W×3` or `H×W×4` uint8 array, or an RGB or RGBA PIL
/// image) retargeted to `size`: an array of as many channels, or for a PIL image [`arrow::Pixels`]
/// for `PIL.Image.fromarrow`.
#[pyfunction]
#[pyo3(signature = (image, size, options=None))]
fn retarget<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    size: &Bound<'py, PyAny>,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyDict>>)> {
    let given = Given::new(options, &[STILL])?;
    let opts = options::options(&given)?;
    let method = options::method(&given, &opts)?;
    let target = options::target(size)?;
    let p = input(image, "image")?;
    let target = options::resolve(&target, p.image.size())?;
    // The mesh method straight through `Retargeter`, which takes the frame by value:
    // `vizretarget::retarget` would copy the picture once more.
    let (packed, stats) = py
        .detach(|| -> Result<(Packed, Option<_>), vizretarget::Error> {
            if method == Method::Mesh {
                let mut r = Retargeter::new(target, opts)?;
                r.send_frame(Frame::new(p.image, 0))?;
                r.flush();
                let out = r.receive_frame().map_err(|_| {
                    vizretarget::Error::Internal("a still sent and flushed gave no frame".into())
                })?;
                Ok((pack(out.image, p.out), Some(out.stats)))
            } else {
                let out = retarget_with(method, &p.image, target, &opts)?;
                Ok((pack(out.image, p.out), None))
            }
        })
        .map_err(to_py)?;
    let stats = stats.map(|s| stats::frame_stats(py, &s)).transpose()?;
    Ok((packed.into_py(py)?, stats))
}

/// `(sheet, measures_json)`: every method on `image`, side by side, and their measures.
#[pyfunction]
#[pyo3(signature = (image, size, options=None))]
fn compare<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    size: &Bound<'py, PyAny>,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyAny>, String)> {
    let given = Given::new(options, &[COMPARE])?;
    let mut opts = vizretarget::Options::default();
    if let Some(a) = given.get::<f32>("alpha")? {
        opts = opts.with_alpha(a);
    }
    opts.validate().map_err(to_py)?;
    let sheet_options = SheetOptions {
        mesh_overlay: given.get::<bool>("mesh")?.unwrap_or(false),
        metrics: given.get::<bool>("metrics")?.unwrap_or(false),
        ..SheetOptions::default()
    };
    let target = options::target(size)?;
    let p = input(image, "image")?;
    let target = options::resolve(&target, p.image.size())?;
    let (packed, json) = py
        .detach(|| -> Result<_, vizretarget::Error> {
            let c = compare_methods(&p.image, target, &opts)?;
            let sheet = c.sheet(&p.image, &sheet_options);
            let channels = if sheet.is_opaque() { 3 } else { 4 };
            let out = Out {
                channels,
                pil: false,
            };
            Ok((pack(sheet, out), c.metrics.to_json().to_string()))
        })
        .map_err(to_py)?;
    Ok((packed.into_py(py)?, json))
}

/// Retargets the picture, animated GIF or folder of frames `src` into `dst` as the command
/// line would; returns what it did as a dict.
#[pyfunction]
#[pyo3(signature = (src, dst, size, options=None))]
fn retarget_file<'py>(
    py: Python<'py>,
    src: PathBuf,
    dst: PathBuf,
    size: &Bound<'py, PyAny>,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let given = Given::new(options, &[STILL, REUSE, FILES])?;
    let job = files::Job::new(src, dst, options::target(size)?, &given)?;
    let done = py.detach(|| files::run(&job))?;
    done_dict(py, &done)
}

/// [`retarget_file`] for each `(src, dst)` of `pairs`, in order, the writing of each picture
/// overlapping the work on the next; returns one dict each.
#[pyfunction]
#[pyo3(signature = (pairs, size, options=None))]
fn retarget_files<'py>(
    py: Python<'py>,
    pairs: Vec<(PathBuf, PathBuf)>,
    size: &Bound<'py, PyAny>,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let given = Given::new(options, &[STILL, REUSE, FILES])?;
    let target = options::target(size)?;
    // The options read once, for every pair.
    let mut jobs: Vec<files::Job> = Vec::with_capacity(pairs.len());
    for (src, dst) in pairs {
        let job = match jobs.first() {
            None => files::Job::new(src, dst, target, &given)?,
            Some(first) => first.with_paths(src, dst)?,
        };
        jobs.push(job);
    }
    let done = py.detach(|| files::run_all(&jobs))?;
    done.iter().map(|d| done_dict(py, d)).collect()
}

fn done_dict<'py>(py: Python<'py>, done: &files::Done) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("frames", done.frames)?;
    d.set_item("reused", done.reused)?;
    d.set_item("updated", done.updated)?;
    d.set_item("rebuilt", done.rebuilt)?;
    d.set_item("seconds", done.seconds)?;
    Ok(d)
}

/// `(wall_ms, stages_ms)` of each of `repeat` calls of the library's own
/// `vizretarget::retarget` on `image` (default options), timed in Rust: what
/// `benches/python_overhead.py` compares the package's call with. `stages_ms` is the
/// frame's own stage total (`FrameStats::times`), which the bench subtracts to take the
/// machine's load out of the comparison.
#[pyfunction]
fn _library_ms(
    py: Python<'_>,
    image: &Bound<'_, PyAny>,
    size: &Bound<'_, PyAny>,
    repeat: usize,
) -> PyResult<Vec<(f64, f64)>> {
    let p = picture(image, "image")?;
    let target = options::resolve(&options::target(size)?, p.image.size())?;
    let opts = vizretarget::Options::default();
    py.detach(|| {
        (0..repeat)
            .map(|_| {
                let start = std::time::Instant::now();
                let out = vizretarget::retarget(&p.image, target, &opts)?;
                let ms = start.elapsed().as_secs_f64() * 1e3;
                let stages = out.stats.times.total_ms();
                drop(out);
                Ok((ms, stages))
            })
            .collect::<Result<Vec<_>, vizretarget::Error>>()
    })
    .map_err(to_py)
}

#[pymodule]
fn _vizretarget(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(retarget, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(retarget_file, m)?)?;
    m.add_function(wrap_pyfunction!(retarget_files, m)?)?;
    m.add_function(wrap_pyfunction!(_library_ms, m)?)?;
    m.add_class::<stream::NativeRetargeter>()?;
    m.add_class::<arrow::Pixels>()?;
    Ok(())
}
