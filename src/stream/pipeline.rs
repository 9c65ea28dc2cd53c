//! The threaded stage pipeline: ingest → VSM → mesh → solve → render → sink, one thread each,
//! joined by bounded channels.
//!
//! The stages are the calls the sequential [`crate::Retargeter`] chains
//! ([`crate::retarget::stages`]), so both give the same frames. Each stage loops over its input channel and ends when that channel closes;
//! dropping the sender is the shutdown signal (no sentinel messages, as in gifski). Channels
//! hold one frame each: memory stays flat on an endless stdin stream, and a slow sink slows
//! the source rather than piling frames up. Frame order is kept because every stage is one
//! thread and channels are FIFO. A run planned against a memory budget
//! ([`crate::Limits::plan_stream`]) may hand frames over with no slot at all (rendezvous
//! channels, as gifski between heavy stages): about half the frames in flight, each stage
//! waiting a little more for its neighbours.

use super::{FrameSink, FrameSource, Progress};
use crate::error::Error;
use crate::image::Size;
use crate::limits::MemoryPlan;
use crate::retarget::stages::{Stages, WithMesh, WithVsm, WithWarp};
use crate::retarget::{Decision, Frame, Options, Retargeted, StageTimes};
use crossbeam_channel::{bounded, Receiver, Sender};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// What a run did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunSummary {
    /// Frames written.
    pub frames: u64,
    /// Wall time of the run.
    pub elapsed: Duration,
    /// Frames rendered through the previous mesh and solution.
    pub reused: u64,
    /// Frames whose mesh was updated locally.
    pub updated: u64,
    /// Frames whose mesh was built from scratch.
    pub rebuilt: u64,
    /// Milliseconds per stage, summed over the frames.
    pub stage_ms: StageTimes,
    /// The reader of the output went away before the end.
    pub output_closed: bool,
    /// The run was cancelled (the cancel flag was set) before the input ended.
    pub cancelled: bool,
}

impl RunSummary {
    /// Frames per second over the run.
    pub fn fps(&self) -> f64 {
        self.frames as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}

/// Runs a source through the stages into a sink, each stage on a thread of its own: a target,
/// checked options, and a memory plan.
///
/// ```
/// use std::sync::atomic::AtomicBool;
/// use vizretarget::stream::{NoProgress, VecSink, VecSource};
/// use vizretarget::{Frame, Image, Options, Pipeline, Size};
/// let page = Image::filled(Size::new(80, 40)?, [255; 4]);
/// let frames = (0..3).map(|i| Frame::new(page.clone(), i));
/// let mut sink = VecSink::default();
/// let summary = Pipeline::new(Size::new(40, 40)?, &Options::default())?.run(
///     &mut VecSource::new(frames),
///     &mut sink,
///     &NoProgress,
///     &AtomicBool::new(false),
/// )?;
/// assert_eq!(summary.frames, 3);
/// assert_eq!(sink.frames[2].image.size(), Size::new(40, 40)?);
/// # Ok::<(), vizretarget::Error>(())
/// ```
pub struct Pipeline {
    target: Size,
    options: Options,
    plan: MemoryPlan,
}

/// A stage loop: `f` on every message until the input closes or the output is gone.
fn stage<I, O>(
    rx: Receiver<I>,
    tx: Sender<O>,
    stop: &AtomicBool,
    mut f: impl FnMut(I) -> Result<O, Error>,
) -> Result<(), Error> {
    for msg in rx {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let out = f(msg).inspect_err(|_| stop.store(true, Ordering::Relaxed))?;
        if tx.send(out).is_err() {
            break; // downstream ended (the sink stopped early): not an error here
        }
    }
    Ok(())
}

/// Spawns a stage loop ([`stage`]) on a thread of its own, named for the stage.
fn spawn_stage<'scope, 'env, I: Send + 'scope, O: Send + 'scope>(
    s: &'scope std::thread::Scope<'scope, 'env>,
    name: &str,
    rx: Receiver<I>,
    tx: Sender<O>,
    stop: &'scope AtomicBool,
    f: impl FnMut(I) -> Result<O, Error> + Send + 'scope,
) -> std::thread::ScopedJoinHandle<'scope, Result<(), Error>> {
    std::thread::Builder::new()
        .name(name.into())
        .spawn_scoped(s, move || stage(rx, tx, stop, f))
        .unwrap_or_else(|e| panic!("spawn the {name} stage: {e}"))
}

impl Pipeline {
    /// A pipeline to `target` (checked: each side 1 to [`crate::MAX_SIDE`]) with `options`
    /// (checked), one frame waiting between stages ([`MemoryPlan::unbounded`]).
    pub fn new(target: Size, options: &Options) -> Result<Pipeline, Error> {
        Size::new(target.width, target.height)?;
        options.validate()?;
        Ok(Pipeline {
            target,
            options: options.clone(),
            plan: MemoryPlan::unbounded(target, target),
        })
    }

    /// Runs within a memory plan: its channel capacity, and every frame admitted by
    /// [`MemoryPlan::admit`] as it is read (a larger frame that would not fit ends the run
    /// with [`Error::LimitExceeded`], after the frames before it).
    pub fn with_plan(mut self, plan: MemoryPlan) -> Pipeline {
        self.plan = plan;
        self
    }

    /// Retargets every frame of `source` into `sink`, in order. Stops early, successfully,
    /// when the sink reports [`Error::OutputClosed`] or `cancel` is set (frames already read
    /// are finished and written first, and the sink is always finished).
    pub fn run(
        &self,
        source: &mut dyn FrameSource,
        sink: &mut dyn FrameSink,
        progress: &dyn Progress,
        cancel: &AtomicBool,
    ) -> Result<RunSummary, Error> {
        let (target, options, plan) = (self.target, &self.options, &self.plan);
        let capacity = plan.channel_capacity;
        let start = Instant::now();
        let stop = AtomicBool::new(false);
        let mut summary = RunSummary::default();
        let (tx0, rx0) = bounded::<Frame>(capacity);
        let (tx1, rx1) = bounded::<WithVsm>(capacity);
        let (tx2, rx2) = bounded::<WithMesh>(capacity);
        let (tx3, rx3) = bounded::<WithWarp>(capacity);
        let (tx4, rx4) = bounded::<Retargeted>(capacity);

        let cancelled = AtomicBool::new(false);
        let results: Vec<Result<(), Error>> = std::thread::scope(|s| {
            let stop = &stop;
            let cancelled = &cancelled;
            let mut handles = Vec::new();
            handles.push(
                std::thread::Builder::new()
                    .name("ingest".into())
                    .spawn_scoped(s, move || {
                        ingest(source, plan, &tx0, stop, cancel, cancelled)
                    })
                    .unwrap_or_else(|e| panic!("spawn the ingest stage: {e}")),
            );
            let Stages {
                saliency: mut vsm_stage,
                mesh: mut mesh_stage,
                solve: mut solve_stage,
                render: render_stage,
            } = Stages::new(target, options);
            let mut render_stage = render_stage.in_pipeline();
            handles.push(spawn_stage(s, "vsm", rx0, tx1, stop, move |m: Frame| {
                vsm_stage.run(m)
            }));
            handles.push(spawn_stage(s, "mesh", rx1, tx2, stop, move |m: WithVsm| {
                mesh_stage.run(m)
            }));
            handles.push(spawn_stage(
                s,
                "solve",
                rx2,
                tx3,
                stop,
                move |m: WithMesh| solve_stage.run(m),
            ));
            handles.push(spawn_stage(
                s,
                "render",
                rx3,
                tx4,
                stop,
                move |m: WithWarp| render_stage.run(m),
            ));

            // The sink runs here, on the caller's thread (the sink need not be Send).
            let sink_result = drain(rx4, sink, progress, stop, &mut summary);
            // Leaving the loop drops the receiver: upstream stages see a closed channel.
            let mut results: Vec<Result<(), Error>> = handles.into_iter().map(join).collect();
            summary.cancelled = cancelled.load(Ordering::Relaxed);
            results.push(sink_result);
            results
        });
        let finished = sink.finish();
        // The first real error wins; a closed output is not one.
        for r in results {
            r?;
        }
        match finished {
            Err(Error::OutputClosed) => summary.output_closed = true,
            other => other?,
        }
        summary.elapsed = start.elapsed();
        Ok(summary)
    }
}

/// The ingest stage: reads frames from `source`, admits each to the memory plan, and hands
/// them on until the source ends, a stage stops, or the run is cancelled (`cancelled` then
/// records that the input did not end).
fn ingest(
    source: &mut dyn FrameSource,
    plan: &MemoryPlan,
    tx: &Sender<Frame>,
    stop: &AtomicBool,
    cancel: &AtomicBool,
    cancelled: &AtomicBool,
) -> Result<(), Error> {
    loop {
        if stop.load(Ordering::Relaxed) {
            return Ok(());
        }
        if cancel.load(Ordering::Relaxed) {
            cancelled.store(true, Ordering::Relaxed);
            return Ok(());
        }
        let Some(frame) = source.next_frame()? else {
            // A source that gives up waiting when cancelled (DetachedSource, a watched
            // folder) ends this way.
            if cancel.load(Ordering::Relaxed) {
                cancelled.store(true, Ordering::Relaxed);
            }
            return Ok(());
        };
        plan.admit(frame.frame_index, frame.image.size())?;
        if tx.send(frame).is_err() {
            return Ok(());
        }
    }
}

/// The sink stage: writes every retargeted frame, in order, counting it into `summary`. A
/// closed output ends it successfully; any other sink error ends it with that error. Either
/// way it raises `stop` for the stages upstream.
fn drain(
    rx: Receiver<Retargeted>,
    sink: &mut dyn FrameSink,
    progress: &dyn Progress,
    stop: &AtomicBool,
    summary: &mut RunSummary,
) -> Result<(), Error> {
    for out in rx {
        match sink.write_frame(&out) {
            Ok(()) => {}
            Err(Error::OutputClosed) => {
                summary.output_closed = true;
                stop.store(true, Ordering::Relaxed);
                break;
            }
            Err(e) => {
                stop.store(true, Ordering::Relaxed);
                return Err(e);
            }
        }
        summary.frames += 1;
        match out.stats.decision {
            Decision::Reuse => summary.reused += 1,
            Decision::Update => summary.updated += 1,
            Decision::Rebuild => summary.rebuilt += 1,
        }
        let t = &out.stats.times;
        summary.stage_ms.vsm_ms += t.vsm_ms;
        summary.stage_ms.mesh_ms += t.mesh_ms;
        summary.stage_ms.solve_ms += t.solve_ms;
        summary.stage_ms.render_ms += t.render_ms;
        progress.frame_done(&out.stats);
    }
    Ok(())
}

/// A stage thread's result, a panic in it turned into [`Error::Internal`] naming the stage.
fn join(h: std::thread::ScopedJoinHandle<'_, Result<(), Error>>) -> Result<(), Error> {
    let name = h.thread().name().unwrap_or("stage").to_string();
    h.join().unwrap_or_else(|panic| {
        let msg = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(Error::Internal(format!("the {name} stage panicked: {msg}")))
    })
}
