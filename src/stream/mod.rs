//! Streams of frames: where frames come from, where they go, and the pipeline between.
//!
//! The method's stages (VSM → mesh → solve → render) run as a sequential core in
//! [`crate::Retargeter`]; [`Pipeline`] runs the same stage calls on one thread each, joined
//! by bounded channels, between a [`FrameSource`] thread and a [`FrameSink`] thread. Both give
//! the same frames (a test checks it).

mod detached;
mod pipeline;

pub use detached::DetachedSource;
pub use pipeline::{Pipeline, RunSummary};

use crate::error::Error;
use crate::retarget::{Frame, FrameStats, Retargeted};

/// Where frames come from (a GIF, a folder, stdin, a watched directory...).
pub trait FrameSource: Send {
    /// The next frame, in order; `Ok(None)` at the end.
    fn next_frame(&mut self) -> Result<Option<Frame>, Error>;

    /// How many frames remain, when the source knows (a file does, a pipe does not).
    fn len_hint(&self) -> Option<usize> {
        None
    }

    /// How often the source animation repeats, if it says (an animated GIF does).
    fn repeat(&self) -> Option<Repeat> {
        None
    }
}

/// How often an animation plays.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Repeat {
    Infinite,
    /// Played this many extra times after the first (GIF's NETSCAPE loop count).
    Times(u16),
}

/// Where retargeted frames go (a GIF, a folder, stdout...).
pub trait FrameSink: Send {
    /// Writes one frame. [`Error::OutputClosed`] ends a run early but successfully.
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), Error>;

    /// Completes the output (a GIF's trailer, flushing a pipe). Called once, after the last
    /// frame, also when the run ends early.
    fn finish(&mut self) -> Result<(), Error>;
}

/// Told about every frame as it leaves the pipeline, e.g. to move a progress bar.
pub trait Progress: Sync {
    fn frame_done(&self, _stats: &FrameStats) {}
}

/// A [`Progress`] that ignores everything.
pub struct NoProgress;
impl Progress for NoProgress {}

/// A source over frames already in memory (tests, library users with their own decoding).
pub struct VecSource {
    frames: std::collections::VecDeque<Frame>,
}

impl VecSource {
    pub fn new(frames: impl IntoIterator<Item = Frame>) -> VecSource {
        VecSource {
            frames: frames.into_iter().collect(),
        }
    }
}

impl FrameSource for VecSource {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        Ok(self.frames.pop_front())
    }
    fn len_hint(&self) -> Option<usize> {
        Some(self.frames.len())
    }
}

/// A sink that keeps every frame in memory.
#[derive(Default)]
pub struct VecSink {
    pub frames: Vec<Retargeted>,
    pub finished: bool,
}

impl FrameSink for VecSink {
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), Error> {
        self.frames.push(frame.clone());
        Ok(())
    }
    fn finish(&mut self) -> Result<(), Error> {
        self.finished = true;
        Ok(())
    }
}
