//! `retarget_file` and `retarget_files`: whatever the command line reads and writes (a
//! still, an animated GIF, a folder of frames; PNG, JPEG, WebP, GIF, a folder), through the
//! library's `io` and `Pipeline` as the command line drives them: a picture by
//! `Retargeter`, anything with more frames by the threaded pipeline with its reuse. Standard input and output (`-`) are the
//! command line's business and are refused here.

use crate::errors::{bad, to_py};
use crate::options::{self, Given};
use pyo3::exceptions::PyValueError;
use pyo3::PyResult;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use vizretarget::io::{
    is_std, list_images, open_input_with, open_sink, path_shape, probe_still, read_still_with,
    resolve_output, write_still, Destination, FrameMarks, FrameRate, InputFormat, InputKind,
    MarkedSource, OutputChoice, OutputFormat, PathShape, SinkFormat, SinkOptions,
};
use vizretarget::stream::{FrameSource, NoProgress};
use vizretarget::{
    retarget_with, Error, Frame, Limits, Method, Options, Pipeline, Retargeter, Size, Target,
};

/// Everything a file job needs, read from Python before the GIL is released.
#[derive(Clone)]
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
        check_paths(&src, &dst)?;
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

    /// The same job on other paths.
    pub fn with_paths(&self, src: PathBuf, dst: PathBuf) -> PyResult<Job> {
        check_paths(&src, &dst)?;
        Ok(Job {
            src,
            dst,
            ..self.clone()
        })
    }
}

fn check_paths(src: &Path, dst: &Path) -> PyResult<()> {
    if is_std(src) || is_std(dst) {
        return Err(PyValueError::new_err(
            "'-' (standard input or output) is for the command line: give file or folder paths",
        ));
    }
    Ok(())
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
    let started = Instant::now();
    let mut done = match finish(job, prepare(job)?)? {
        Step::Write(still) => still.write()?,
        Step::Done(done) => done,
    };
    done.seconds = started.elapsed().as_secs_f64();
    Ok(done)
}

/// Runs `jobs` in order, each as [`run`] would (the same files), on three threads as the
/// command line's stream runs its stages on threads of their own: each picture is read and
/// decoded on one while the one before it is retargeted on the calling thread, and written
/// (encoded, synced to disk, renamed) on a third. Stops at the first error, after the
/// pictures before it are written. Called with the GIL released.
pub fn run_all(jobs: &[Job]) -> PyResult<Vec<Done>> {
    let mut done: Vec<Done> = jobs.iter().map(|_| Done::default()).collect();
    let no_thread = |what: &str, e: std::io::Error| {
        pyo3::exceptions::PyOSError::new_err(format!("a {what} thread: {e}"))
    };
    let panicked = |what: &str| {
        pyo3::exceptions::PyRuntimeError::new_err(format!(
            "internal error: the {what} thread panicked"
        ))
    };
    let (read_tx, read_rx) = std::sync::mpsc::sync_channel::<(Instant, PyResult<Prepared>)>(1);
    let (write_tx, write_rx) = std::sync::mpsc::sync_channel::<(usize, Still, Instant)>(1);
    std::thread::scope(|s| {
        let reader = std::thread::Builder::new()
            .name("read".into())
            .spawn_scoped(s, move || {
                for job in jobs {
                    let started = Instant::now();
                    let prepared = prepare(job);
                    let failed = prepared.is_err();
                    // Sent in order; nothing is read past an error, or once the calling
                    // thread has stopped.
                    if read_tx.send((started, prepared)).is_err() || failed {
                        break;
                    }
                }
            })
            .map_err(|e| no_thread("reader", e))?;
        let writer = std::thread::Builder::new()
            .name("write".into())
            .spawn_scoped(s, move || -> PyResult<Vec<(usize, Done)>> {
                let mut written = Vec::new();
                for (i, still, started) in write_rx {
                    let mut d = still.write()?;
                    d.seconds = started.elapsed().as_secs_f64();
                    written.push((i, d));
                }
                Ok(written)
            })
            .map_err(|e| no_thread("writer", e))?;
        let mut failed = None;
        for (i, (started, prepared)) in read_rx.iter().enumerate() {
            match prepared.and_then(|p| finish(&jobs[i], p)) {
                Ok(Step::Write(still)) => {
                    if write_tx.send((i, still, started)).is_err() {
                        break; // the writer failed: its error is the one to raise
                    }
                }
                Ok(Step::Done(mut d)) => {
                    d.seconds = started.elapsed().as_secs_f64();
                    done[i] = d;
                }
                Err(e) => {
                    failed = Some(e);
                    break;
                }
            }
        }
        drop(read_rx); // a reader still ahead stops at its next send
        drop(write_tx);
        reader.join().map_err(|_| panicked("reader"))?;
        let written = writer.join().map_err(|_| panicked("writer"))??;
        if let Some(e) = failed {
            return Err(e);
        }
        for (i, d) in written {
            done[i] = d;
        }
        Ok(done)
    })
}

/// A picture retargeted, to be written.
pub struct Still {
    image: vizretarget::Image,
    dst: PathBuf,
    format: OutputFormat,
}

impl Still {
    fn write(self) -> PyResult<Done> {
        write_still(&self.image, &self.dst, self.format).map_err(to_py)?;
        Ok(Done {
            frames: 1,
            rebuilt: 1,
            ..Done::default()
        })
    }
}

/// What is left of a job once the calling thread has done its part.
enum Step {
    /// A picture to write.
    Write(Still),
    /// A stream, run through and written.
    Done(Done),
}

/// A job read as far as it can be ahead of the retargeting.
enum Prepared {
    /// A picture checked and decoded, for `target`, to be written to `dst`.
    Still {
        image: vizretarget::Image,
        target: Size,
        dst: PathBuf,
        format: OutputFormat,
    },
    /// A stream into a sink of this format, all of it left to do.
    Stream(SinkFormat),
}

/// A job up to the decoding of its picture; for a stream, what sink it writes.
fn prepare(job: &Job) -> PyResult<Prepared> {
    let destination = resolve_output(&job.dst, OutputChoice::Auto).map_err(to_py)?;
    match (
        destination,
        path_shape(&job.src, &job.limits).map_err(to_py)?,
    ) {
        (Destination::Still(format), PathShape::Picture | PathShape::UnreadableGif) => {
            read(job, job.dst.clone(), format)
        }
        (Destination::Still(_), PathShape::Animation(n)) => Err(PyValueError::new_err(format!(
            "{}: an animated GIF of {n} frames does not fit in one picture ({}): write a \
             .gif, or a folder (ending in /) for one PNG per frame",
            job.src.display(),
            job.dst.display()
        ))),
        (Destination::Still(_), PathShape::Folder) => Err(PyValueError::new_err(format!(
            "{}: one picture cannot hold a folder of frames: write a .gif or a folder \
             (ending in /)",
            job.dst.display()
        ))),
        // One picture into a folder keeps its name, as a folder of frames does.
        (Destination::Stream(SinkFormat::PngSeq), PathShape::Picture) => {
            let stem = job
                .src
                .file_stem()
                .map_or_else(|| "picture".into(), |s| s.to_string_lossy().into_owned());
            read(job, job.dst.join(format!("{stem}.png")), OutputFormat::Png)
        }
        (Destination::Stream(_), _) if job.method != Method::Mesh => Err(bad(
            "option method",
            format!(
                "{} is for one picture; streams are retargeted with mesh",
                job.method
            ),
        )),
        (Destination::Stream(format), _) => Ok(Prepared::Stream(format)),
    }
}

/// The rest of a job: its picture retargeted, to be written; a stream all the way.
fn finish(job: &Job, prepared: Prepared) -> PyResult<Step> {
    match prepared {
        Prepared::Still {
            image,
            target,
            dst,
            format,
        } => {
            // Into a folder: made here, not ahead, so that a batch that stops at an error
            // leaves none for the jobs after it.
            if let Some(folder) = dst.parent().filter(|_| dst != job.dst) {
                if !folder.is_dir() {
                    std::fs::create_dir(folder).map_err(|e| {
                        to_py(Error::Io {
                            path: folder.to_path_buf(),
                            source: e,
                        })
                    })?;
                }
            }
            let image = still(job, image, target)?;
            Ok(Step::Write(Still { image, dst, format }))
        }
        Prepared::Stream(format) => stream(job, format).map(Step::Done),
    }
}

/// One picture: checked from its header and decoded.
fn read(job: &Job, dst: PathBuf, format: OutputFormat) -> PyResult<Prepared> {
    let from = probe_still(&job.src, &job.limits).map_err(to_py)?;
    let target = options::resolve(&job.target, from)?;
    job.limits
        .check_still(&job.src, from, target)
        .map_err(to_py)?;
    let image = read_still_with(&job.src, &job.limits).map_err(to_py)?;
    Ok(Prepared::Still {
        image,
        target,
        dst,
        format,
    })
}

/// One picture retargeted. The mesh as the command line runs it, through `Retargeter`,
/// which takes the picture by value (`retarget` would copy it); `retarget_with` would keep
/// the analysis too.
fn still(job: &Job, image: vizretarget::Image, target: Size) -> PyResult<vizretarget::Image> {
    match job.method {
        Method::Mesh => Retargeter::new(target, job.options.clone())
            .and_then(|mut r| {
                r.send_frame(Frame::new(image, 0))?;
                r.flush();
                r.receive_frame()
                    .map_err(|_| Error::Internal("a still sent and flushed gave no frame".into()))
            })
            .map(|r| r.image),
        m => retarget_with(m, &image, target, &job.options).map(|r| r.image),
    }
    .map_err(to_py)
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
