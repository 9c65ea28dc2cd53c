//! The threaded stage pipeline.

use super::{FrameSink, FrameSource, Progress};
use crate::error::Error;
use crate::image::Size;
use crate::retargeter::{Options, Retargeter, StageTimes, Status};
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

/// Runs a source through the stages into a sink.
pub struct Pipeline;

impl Pipeline {
    /// Retargets every frame of `source` to `target` into `sink`, in order. Stops early,
    /// successfully, when the sink reports [`Error::OutputClosed`] or `cancel` is set (frames
    /// already read are finished and written first).
    pub fn run(
        target: Size,
        options: &Options,
        source: &mut dyn FrameSource,
        sink: &mut dyn FrameSink,
        progress: &dyn Progress,
        cancel: &AtomicBool,
    ) -> Result<RunSummary, Error> {
        // First version: the sequential core. The threaded stages replace this body.
        let start = Instant::now();
        let mut summary = RunSummary::default();
        let mut r = Retargeter::new(target, options.clone())?;
        let result = (|| -> Result<(), Error> {
            loop {
                if cancel.load(Ordering::Relaxed) {
                    summary.cancelled = true;
                    break;
                }
                let Some(frame) = source.next_frame()? else {
                    break;
                };
                r.send_frame(frame)?;
                while let Ok(out) = r.receive_frame() {
                    match sink.write_frame(&out) {
                        Err(Error::OutputClosed) => {
                            summary.output_closed = true;
                            return Ok(());
                        }
                        other => other?,
                    }
                    summary.frames += 1;
                    summary.rebuilt += 1;
                    let t = &out.stats.times;
                    summary.stage_ms.vsm_ms += t.vsm_ms;
                    summary.stage_ms.mesh_ms += t.mesh_ms;
                    summary.stage_ms.solve_ms += t.solve_ms;
                    summary.stage_ms.render_ms += t.render_ms;
                    progress.frame_done(&out.stats);
                }
            }
            r.flush();
            while let Ok(out) = r.receive_frame() {
                sink.write_frame(&out)?;
            }
            debug_assert_eq!(r.receive_frame().err(), Some(Status::Done));
            Ok(())
        })();
        let finished = sink.finish();
        result?;
        match finished {
            Err(Error::OutputClosed) => summary.output_closed = true,
            other => other?,
        }
        summary.elapsed = start.elapsed();
        Ok(summary)
    }
}
