//! A source read on a thread of its own, so that waiting for it can be given up.
//!
//! A source may block for as long as its writer likes: stdin from a program that has stopped
//! sending, a slow network file, a huge frame being decoded. [`Pipeline::run`] stops reading
//! when its cancel flag is set, but it cannot stop a read that has already begun, and the
//! pipeline waits for its threads. [`DetachedSource`] moves the source to a thread that
//! reads one frame per request; the consumer waits for the answer in short steps and, once
//! the cancel flag is set, ends the stream (`Ok(None)`) instead of waiting on. The reading
//! thread is abandoned: it ends by itself when its read returns (its frame is dropped), or
//! with the process.
//!
//! [`Pipeline::run`]: super::Pipeline::run

use super::{FrameSource, Repeat};
use crate::error::Error;
use crate::retarget::Frame;
use crossbeam_channel::{bounded, Receiver, RecvTimeoutError, Sender};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// How often a waiting consumer looks at the cancel flag.
const POLL: Duration = Duration::from_millis(20);

/// One answer of the reading thread: the frame and what the source says about the rest.
struct Answer {
    frame: Result<Option<Frame>, Error>,
    len_hint: Option<usize>,
    repeat: Option<Repeat>,
}

/// A [`FrameSource`] whose reads can be abandoned when `cancel` is set.
pub struct DetachedSource {
    requests: Option<Sender<()>>,
    answers: Receiver<Answer>,
    cancel: Arc<AtomicBool>,
    len_hint: Option<usize>,
    repeat: Option<Repeat>,
    /// Waiting for an answer to a request already sent.
    asked: bool,
    ended: bool,
}

impl DetachedSource {
    /// Moves `source` to a reading thread. Nothing is read before the first
    /// [`FrameSource::next_frame`]: frames are read one per request, never ahead.
    pub fn new(mut source: Box<dyn FrameSource>, cancel: Arc<AtomicBool>) -> DetachedSource {
        let (len_hint, repeat) = (source.len_hint(), source.repeat());
        let (req_tx, req_rx) = bounded::<()>(1);
        let (ans_tx, ans_rx) = bounded::<Answer>(1);
        let spawned = std::thread::Builder::new()
            .name("source".into())
            .spawn(move || {
                // Ends when the consumer is gone (its request sender dropped).
                for () in req_rx {
                    let frame = source.next_frame();
                    let last = !matches!(frame, Ok(Some(_)));
                    let answer = Answer {
                        frame,
                        len_hint: source.len_hint(),
                        repeat: source.repeat(),
                    };
                    if ans_tx.send(answer).is_err() || last {
                        break;
                    }
                }
            });
        let ended = spawned.is_err();
        DetachedSource {
            requests: Some(req_tx),
            answers: ans_rx,
            cancel,
            len_hint,
            repeat,
            asked: false,
            ended,
        }
    }
}

impl FrameSource for DetachedSource {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        if self.ended {
            return Ok(None);
        }
        if !self.asked {
            let sent = self.requests.as_ref().map(|r| r.send(()));
            if !matches!(sent, Some(Ok(()))) {
                self.ended = true;
                return Err(Error::Internal("the reading thread stopped".into()));
            }
            self.asked = true;
        }
        loop {
            if self.cancel.load(Ordering::Relaxed) {
                // Abandon the read in progress: the thread finds nobody to answer.
                self.ended = true;
                self.requests = None;
                return Ok(None);
            }
            match self.answers.recv_timeout(POLL) {
                Ok(answer) => {
                    self.asked = false;
                    self.len_hint = answer.len_hint;
                    self.repeat = answer.repeat;
                    if !matches!(answer.frame, Ok(Some(_))) {
                        self.ended = true;
                        self.requests = None;
                    }
                    return answer.frame;
                }
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    self.ended = true;
                    return Err(Error::Internal("the reading thread panicked".into()));
                }
            }
        }
    }

    fn len_hint(&self) -> Option<usize> {
        self.len_hint
    }

    fn repeat(&self) -> Option<Repeat> {
        self.repeat
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::stream::VecSource;
    use std::time::Instant;

    /// Frames, then a read that never returns (until `release` is set).
    struct Stuck {
        frames: VecSource,
        entered: Arc<AtomicBool>,
        release: Arc<AtomicBool>,
    }
    impl FrameSource for Stuck {
        fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
            if let Some(f) = self.frames.next_frame()? {
                return Ok(Some(f));
            }
            self.entered.store(true, Ordering::SeqCst);
            while !self.release.load(Ordering::SeqCst) {
                std::thread::sleep(Duration::from_millis(5));
            }
            Ok(None)
        }
    }

    fn frames(n: u64) -> VecSource {
        let size = crate::image::Size::new(4, 3).unwrap();
        VecSource::new((0..n).map(|i| Frame::new(Image::new(size), i)))
    }

    #[test]
    fn passes_frames_in_order_then_ends() {
        let cancel = Arc::new(AtomicBool::new(false));
        let mut s = DetachedSource::new(Box::new(frames(3)), cancel);
        assert_eq!(s.len_hint(), Some(3));
        for i in 0..3 {
            assert_eq!(s.next_frame().unwrap().unwrap().frame_index, i);
        }
        assert_eq!(s.len_hint(), Some(0));
        assert!(s.next_frame().unwrap().is_none());
        assert!(s.next_frame().unwrap().is_none());
    }

    #[test]
    fn a_blocked_read_is_abandoned_when_cancelled() {
        let cancel = Arc::new(AtomicBool::new(false));
        let (entered, release) = (
            Arc::new(AtomicBool::new(false)),
            Arc::new(AtomicBool::new(false)),
        );
        let stuck = Stuck {
            frames: frames(2),
            entered: entered.clone(),
            release: release.clone(),
        };
        let mut s = DetachedSource::new(Box::new(stuck), cancel.clone());
        assert!(s.next_frame().unwrap().is_some());
        assert!(s.next_frame().unwrap().is_some());
        // Ask for the third frame on another thread; cancel once the reading thread is
        // inside the read that never returns.
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || tx.send(s.next_frame().map(|f| f.is_none())));
        let guard = Instant::now() + Duration::from_secs(30);
        while !entered.load(Ordering::SeqCst) {
            assert!(Instant::now() < guard, "the read never started");
            std::thread::sleep(Duration::from_millis(1));
        }
        cancel.store(true, Ordering::SeqCst);
        let ended = rx
            .recv_timeout(Duration::from_secs(30))
            .expect("next_frame still waits on the blocked read after cancel");
        assert!(ended.unwrap(), "ends the stream");
        release.store(true, Ordering::SeqCst); // lets the abandoned thread end
    }
}
