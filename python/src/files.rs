//! `retarget_file`: whatever the command line reads and writes (a still, an animated GIF, a
//! folder of frames; PNG, JPEG, WebP, GIF, a folder), through the library's `io` and
//! `Pipeline` as the command line drives them: a picture by `retarget`, anything with more
//! frames by the threaded pipeline with its reuse. Standard input and output (`-`) are the
//! command line's business and are refused here.

use crate::errors::{bad, to_py};
use crate::options::{self, Given};
use pyo3::exceptions::PyValueError;
use pyo3::PyResult;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use vizretarget::io::{
    is_std, list_images, open_input_with, open_sink, probe_still, read_still_with, resolve_output,
    sniff, write_still, Destination, FrameMarks, FrameRate, GifSource, InputFormat, InputKind,
    Magic, MarkedSource, OutputChoice, OutputFormat, SinkFormat, SinkOptions,
};
use vizretarget::stream::{FrameSource, NoProgress};
use vizretarget::{retarget, retarget_with, Error, Limits, Method, Options, Pipeline, Target};

/// Everything a file job needs, read from Python before the GIL is released.
pub struct Job {
    pub src: PathBuf,
    pub dst: PathBuf,
    pub target: Target,
    pub options: Options,
    pub method: Method,
    pub limits: Limits,
    pub fps: Option<f64>,
    pub marks: Option<PathBuf>,
}

impl Job {
    pub fn new(src: PathBuf, dst: PathBuf, target: Target, given: &Given<'_>) -> PyResult<Job> {
        if is_std(&src) || is_std(&dst) {
            return Err(PyValueError::new_err(
                "'-' (standard input or output) is for the command line: give file or folder paths",
            ));
        }
        let opts = options::options(given)?;
        Ok(Job {
            src,
            dst,
            target,
            method: options::method(given, &opts)?,
            options: opts,
            limits: options::limits(given)?,
            fps: given.get::<f64>("fps")?,
            marks: options::marks_path(given)?,
        })
    }
}

/// What a run did: frames written, and for a stream how many were reused, updated, rebuilt.
#[derive(Default)]
pub struct Done {
    pub frames: u64,
    pub reused: u64,
    pub updated: u64,
    pub rebuilt: u64,
    pub seconds: f64,
}

/// Runs `job`; called with the GIL released.
pub fn run(job: &Job) -> PyResult<Done> {
    let started = std::time::Instant::now();
    let destination = resolve_output(&job.dst, OutputChoice::Auto).map_err(to_py)?;
    let frames = frame_count(&job.src, &job.limits).map_err(to_py)?;
    let mut done = match (destination, frames) {
        (Destination::Still(format), Some(1)) => still(job, &job.dst, format)?,
        (Destination::Still(_), Some(n)) => {
            return Err(PyValueError::new_err(format!(
                "{}: an animated GIF of {n} frames does not fit in one picture ({}): write a \
                 .gif, or a folder (ending in /) for one PNG per frame",
                job.src.display(),
                job.dst.display()
            )))
        }
        (Destination::Still(_), None) => {
            return Err(PyValueError::new_err(format!(
                "{}: one picture cannot hold a folder of frames: write a .gif or a folder \
                 (ending in /)",
                job.dst.display()
            )))
        }
        // One picture into a folder keeps its name, as a folder of frames does.
        (Destination::Stream(SinkFormat::PngSeq), Some(1)) => {
            let stem = job
                .src
                .file_stem()
                .map_or_else(|| "picture".into(), |s| s.to_string_lossy().into_owned());
            if !job.dst.is_dir() {
                std::fs::create_dir(&job.dst).map_err(|e| {
                    to_py(Error::Io {
                        path: job.dst.clone(),
                        source: e,
                    })
                })?;
            }
            still(job, &job.dst.join(format!("{stem}.png")), OutputFormat::Png)?
        }
        (Destination::Stream(_), _) if job.method != Method::Mesh => {
            return Err(bad(
                "option method",
                format!(
                    "{} is for one picture; streams are retargeted with mesh",
                    job.method
                ),
            ))
        }
        (Destination::Stream(format), _) => stream(job, format)?,
    };
    done.seconds = started.elapsed().as_secs_f64();
    Ok(done)
}

/// How many frames `src` holds when it is one file (a GIF is counted without decoding;
/// another picture is one), `None` for a folder.
fn frame_count(src: &Path, limits: &Limits) -> Result<Option<u64>, Error> {
    if src.is_dir() {
        return Ok(None);
    }
    let mut head = Vec::new();
    if let Ok(f) = std::fs::File::open(src) {
        use std::io::Read;
        let _ = f.take(16).read_to_end(&mut head);
    }
    if sniff(&head) != Some(Magic::Gif) {
        return Ok(Some(1));
    }
    let gif = GifSource::open_with(src, limits)?;
    Ok(Some(gif.len_hint().map_or(1, |n| n.max(1) as u64)))
}

/// One picture: checked from its header, retargeted, written atomically.
fn still(job: &Job, dst: &Path, format: OutputFormat) -> PyResult<Done> {
    let from = probe_still(&job.src, &job.limits).map_err(to_py)?;
    let target = options::resolve(&job.target, from)?;
    job.limits
        .check_still(&job.src, from, target)
        .map_err(to_py)?;
    let image = read_still_with(&job.src, &job.limits).map_err(to_py)?;
    // The mesh as the command line runs it: `retarget_with` would keep the analysis too.
    let out = match job.method {
        Method::Mesh => retarget(&image, target, &job.options).map(|r| r.image),
        m => retarget_with(m, &image, target, &job.options).map(|r| r.image),
    }
    .map_err(to_py)?;
    write_still(&out, dst, format).map_err(to_py)?;
    Ok(Done {
        frames: 1,
        rebuilt: 1,
        ..Done::default()
    })
}

/// Frames in, frames out, through the threaded pipeline.
fn stream(job: &Job, format: SinkFormat) -> PyResult<Done> {
    let mut input =
        open_input_with(&job.src, InputFormat::Auto, None, &job.limits).map_err(to_py)?;
    let marks = match &job.marks {
        Some(p) => Some(FrameMarks::open(p, input.names.clone()).map_err(to_py)?),
        None if input.kind == InputKind::Folder && job.options.marks.is_none() => {
            let files = list_images(&job.src).map_err(to_py)?;
            match &input.names {
                Some(names) if FrameMarks::has_sidecars(&job.src, &files) => {
                    Some(FrameMarks::sidecars(&job.src, names.clone()))
                }
                _ => None,
            }
        }
        None => None,
    };
    if let Some(m) = marks {
        let frames: Box<dyn FrameSource> = std::mem::replace(
            &mut input.source,
            Box::new(vizretarget::stream::VecSource::new([])),
        );
        input.source = Box::new(MarkedSource::new(frames, m));
    }
    let from = input
        .frame_size()
        .map_err(to_py)?
        .ok_or_else(|| to_py(Error::NoFrames(job.src.clone())))?;
    let target = options::resolve(&job.target, from)?;
    let plan = job
        .limits
        .plan_stream(&job.src, from, target, format.held_bytes_per_pixel())
        .map_err(to_py)?;
    let frame_rate = match job.fps {
        Some(f) => Some(
            FrameRate::from_fps(f)
                .ok_or_else(|| bad("option fps", format!("{f} is out of range: 0.001 to 1000")))?,
        ),
        None => input.frame_rate,
    };
    let sink_options = SinkOptions {
        frame_rate,
        repeat: input.source.repeat(),
        names: input.names.clone(),
    };
    let mut sink = open_sink(&job.dst, format, sink_options).map_err(to_py)?;
    let summary = Pipeline::new(target, &job.options)
        .map_err(to_py)?
        .with_plan(plan)
        .run(
            &mut *input.source,
            &mut *sink,
            &NoProgress,
            &AtomicBool::new(false),
        )
        .map_err(to_py)?;
    if summary.frames == 0 {
        return Err(to_py(Error::NoFrames(job.src.clone())));
    }
    Ok(Done {
        frames: summary.frames,
        reused: summary.reused,
        updated: summary.updated,
        rebuilt: summary.rebuilt,
        seconds: 0.0,
    })
}
