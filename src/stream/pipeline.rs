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

/// Runs a source through the stages into a sink.
pub struct Pipeline;

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
    /// Retargets every frame of `source` to `target` into `sink`, in order, each stage on its
    /// own thread. Stops early, successfully, when the sink reports [`Error::OutputClosed`]
    /// or `cancel` is set (frames already read are finished and written first, and the sink
    /// is always finished).
    pub fn run(
        target: Size,
        options: &Options,
        source: &mut dyn FrameSource,
        sink: &mut dyn FrameSink,
        progress: &dyn Progress,
        cancel: &AtomicBool,
    ) -> Result<RunSummary, Error> {
        let plan = MemoryPlan::unbounded(target, target);
        Pipeline::run_planned(&plan, target, options, source, sink, progress, cancel)
    }

    /// [`Pipeline::run`] within a memory plan: its channel capacity, and every frame admitted
    /// by [`MemoryPlan::admit`] as it is read (a larger frame that would not fit ends the run
    /// with [`Error::LimitExceeded`], after the frames before it).
    pub fn run_planned(
        plan: &MemoryPlan,
        target: Size,
        options: &Options,
        source: &mut dyn FrameSource,
        sink: &mut dyn FrameSink,
        progress: &dyn Progress,
        cancel: &AtomicBool,
    ) -> Result<RunSummary, Error> {
        Size::new(target.width, target.height)?;
        let capacity = plan.channel_capacity;
        options.validate()?;
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
                    .spawn_scoped(s, move || -> Result<(), Error> {
                        loop {
                            if stop.load(Ordering::Relaxed) {
                                return Ok(());
                            }
                            if cancel.load(Ordering::Relaxed) {
                                cancelled.store(true, Ordering::Relaxed);
                                return Ok(());
                            }
                            let frame = match source.next_frame() {
                                Ok(Some(f)) => f,
                                Ok(None) => {
                                    // A source that gives up waiting when cancelled
                                    // (DetachedSource, a watched folder) ends this way.
                                    if cancel.load(Ordering::Relaxed) {
                                        cancelled.store(true, Ordering::Relaxed);
                                    }
                                    return Ok(());
                                }
                                Err(e) => {
                                    return Err(e);
                                }
                            };
                            plan.admit(frame.frame_index, frame.image.size())?;
                            if tx0.send(frame).is_err() {
                                return Ok(());
                            }
                        }
                    })
                    .expect("spawn ingest"),
            );
            let Stages {
                saliency: mut vsm_stage,
                mesh: mut mesh_stage,
                solve: mut solve_stage,
                render: mut render_stage,
            } = Stages::new(target, options);
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
            let mut sink_result: Result<(), Error> = Ok(());
            for out in rx4 {
                match sink.write_frame(&out) {
                    Ok(()) => {}
                    Err(Error::OutputClosed) => {
                        summary.output_closed = true;
                        stop.store(true, Ordering::Relaxed);
                        break;
                    }
                    Err(e) => {
                        sink_result = Err(e);
                        stop.store(true, Ordering::Relaxed);
                        break;
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
            // Leaving the loop drops the receiver: upstream stages see a closed channel.
            let mut results: Vec<Result<(), Error>> = handles
                .into_iter()
                .map(|h| {
                    let name = h.thread().name().unwrap_or("stage").to_string();
                    h.join().unwrap_or_else(|panic| {
                        let msg = panic
                            .downcast_ref::<&str>()
                            .map(|s| s.to_string())
                            .or_else(|| panic.downcast_ref::<String>().cloned())
                            .unwrap_or_default();
                        Err(Error::Internal(format!("the {name} stage panicked: {msg}")))
                    })
                })
                .collect();
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
