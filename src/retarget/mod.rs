//! The sequential core: options, frames, the four stages and the reuse policy, and the
//! retargeter that runs the stages in order.
//!
//! `send_frame` / `receive_frame` / `flush` follow rav1e's encoder API: the core is sequential
//! and deterministic; the threaded [`crate::Pipeline`] runs the same stage calls
//! ([`stages`]) on threads, and nothing of a frame's handling is written twice.

mod frame;
mod options;
pub(crate) mod reuse;
pub(crate) mod stages;

pub use frame::{Analysis, Frame, FrameStats, Retargeted, StageTimes};
pub use options::Options;
pub use reuse::{Decision, ReuseOptions};

use crate::error::Error;
use crate::image::{Image, Size};
use stages::Stages;
use std::collections::VecDeque;

/// Why [`Retargeter::receive_frame`] has no frame.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Status {
    /// Send more frames.
    NeedMoreData,
    /// Flushed and drained: the stream is over.
    Done,
}

/// Retargets frames to one target size, in order, reusing the previous frame's mesh and
/// solution while the saliency barely changes (see [`ReuseOptions`]).
pub struct Retargeter {
    target: Size,
    stages: Stages,
    ready: VecDeque<Retargeted>,
    flushed: bool,
}

impl Retargeter {
    /// A retargeter for `target` (checked: each side 1 to [`crate::MAX_SIDE`]).
    pub fn new(target: Size, options: Options) -> Result<Retargeter, Error> {
        Size::new(target.width, target.height)?;
        options.validate()?;
        Ok(Retargeter {
            target,
            stages: Stages::new(target, &options),
            ready: VecDeque::new(),
            flushed: false,
        })
    }

    /// The target size.
    pub fn target(&self) -> Size {
        self.target
    }

    /// Processes a frame; its result is then available from [`Retargeter::receive_frame`].
    pub fn send_frame(&mut self, frame: Frame) -> Result<(), Error> {
        if self.flushed {
            return Err(Error::OutOfOrder("send_frame after flush".into()));
        }
        let out = self.stages.run(frame)?;
        self.ready.push_back(out);
        Ok(())
    }

    /// The next retargeted frame, in input order.
    pub fn receive_frame(&mut self) -> Result<Retargeted, Status> {
        match self.ready.pop_front() {
            Some(f) => Ok(f),
            None if self.flushed => Err(Status::Done),
            None => Err(Status::NeedMoreData),
        }
    }

    /// Ends the stream: frames still queued stay receivable, then `receive_frame` says `Done`.
    pub fn flush(&mut self) {
        self.flushed = true;
    }
}

/// Retargets one still image to `target`.
pub fn retarget(image: &Image, target: Size, options: &Options) -> Result<Retargeted, Error> {
    let mut r = Retargeter::new(target, options.clone())?;
    r.send_frame(Frame::new(image.clone(), 0))?;
    r.flush();
    r.receive_frame()
        .map_err(|_| Error::Internal("a still sent and flushed gave no frame".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_sent_after_flush_is_refused_as_out_of_order_and_the_queue_drains() {
        let size = Size::new(40, 20).unwrap();
        let mut r = Retargeter::new(Size::new(20, 20).unwrap(), Options::default()).unwrap();
        assert_eq!(r.receive_frame().err(), Some(Status::NeedMoreData));
        r.send_frame(Frame::new(Image::filled(size, [255; 4]), 0))
            .unwrap();
        r.flush();
        let e = r
            .send_frame(Frame::new(Image::filled(size, [255; 4]), 1))
            .unwrap_err();
        assert!(matches!(e, Error::OutOfOrder(_)), "{e}");
        assert!(e.to_string().contains("after flush"), "{e}");
        assert_eq!(r.receive_frame().map(|f| f.frame_index), Ok(0));
        assert_eq!(r.receive_frame().err(), Some(Status::Done));
    }
}
