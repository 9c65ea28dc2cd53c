//! Animated GIF in: header, frames composited on the canvas, disposal.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vizretarget::io::GifSource;
use vizretarget::FrameSource;
use vizretarget_fuzz::{drain, split_chops, Choppy};

fuzz_target!(|data: &[u8]| {
    let (chops, stream) = split_chops(data);
    let Ok(mut src) = GifSource::new(Choppy::new(stream, chops, false), "in.gif") else {
        return;
    };
    let size = src.size();
    let _ = src.repeat();
    let _ = src.len_hint();
    drain(&mut src, Some(size), 256);
});
