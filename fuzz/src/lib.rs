//! Helpers shared by the fuzz targets.

use std::io::{ErrorKind, Read};
use vizretarget::{Error, Frame, FrameSource};

/// A reader over `data` whose reads are cut short as `chops` says (one byte per read: how many
/// bytes that read may return, 0 meaning an `Interrupted` error when `interrupts` is set), as a
/// pipe delivers a stream in pieces. An interruption is transient, as EINTR is: the read after
/// one always goes ahead (chops of all zeros once made every read fail, forever, and
/// `read_until` rightly retried forever: a hang of the harness, not of the reader).
pub struct Choppy<'a> {
    data: &'a [u8],
    chops: &'a [u8],
    next: usize,
    interrupts: bool,
    interrupted: bool,
}

impl<'a> Choppy<'a> {
    pub fn new(data: &'a [u8], chops: &'a [u8], interrupts: bool) -> Self {
        Choppy {
            data,
            chops,
            next: 0,
            interrupts,
            interrupted: false,
        }
    }
}

impl Read for Choppy<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if buf.is_empty() || self.data.is_empty() {
            return Ok(0);
        }
        let limit = if self.chops.is_empty() {
            usize::MAX
        } else {
            let c = self.chops[self.next % self.chops.len()];
            self.next += 1;
            if c == 0 && self.interrupts && !self.interrupted {
                self.interrupted = true;
                return Err(std::io::Error::new(ErrorKind::Interrupted, "EINTR"));
            }
            self.interrupted = false;
            // Mostly small pieces, sometimes everything at once.
            if c >= 0xF0 {
                usize::MAX
            } else {
                c as usize % 17 + 1
            }
        };
        let n = buf.len().min(self.data.len()).min(limit);
        buf[..n].copy_from_slice(&self.data[..n]);
        self.data = &self.data[n..];
        Ok(n)
    }
}

/// Splits the fuzz input: the first byte says how many of the following bytes steer the reads,
/// the rest is the stream.
pub fn split_chops(data: &[u8]) -> (&[u8], &[u8]) {
    match data.split_first() {
        Some((&n, rest)) => rest.split_at((n as usize % 16).min(rest.len())),
        None => (&[], &[]),
    }
}

/// Everything a source delivers (at most `max` frames), checking the contract every source
/// keeps: frames numbered 0, 1, 2... in order, each of `size` when given, and after an error or
/// the end only `Ok(None)`.
pub fn drain(
    src: &mut dyn FrameSource,
    size: Option<vizretarget::Size>,
    max: usize,
) -> (Vec<Frame>, Option<Error>) {
    let mut frames: Vec<Frame> = Vec::new();
    let mut error = None;
    for _ in 0..max {
        match src.next_frame() {
            Ok(Some(f)) => {
                assert_eq!(f.frame_index, frames.len() as u64, "frames in order");
                if let Some(s) = size {
                    assert_eq!(f.image.size(), s, "every frame has the stream's size");
                }
                assert_eq!(
                    f.image.pixels().len(),
                    f.image.size().area(),
                    "pixels match the size"
                );
                frames.push(f);
            }
            Ok(None) => break,
            Err(e) => {
                // Every error renders as one line naming what went wrong.
                let msg = e.to_string();
                assert!(!msg.is_empty());
                error = Some(e);
                break;
            }
        }
    }
    if frames.len() < max {
        for _ in 0..2 {
            assert!(
                matches!(src.next_frame(), Ok(None)),
                "a source that ended or failed stays ended"
            );
        }
    }
    (frames, error)
}
