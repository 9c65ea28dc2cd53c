//! YUV4MPEG2 in: header line, FRAME lines, planes in every chroma layout.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vizretarget::io::Y4mSource;
use vizretarget_fuzz::{drain, split_chops, Choppy};

fuzz_target!(|data: &[u8]| {
    let (chops, stream) = split_chops(data);
    let Ok(mut src) = Y4mSource::new(Choppy::new(stream, chops, true), "stdin") else {
        return;
    };
    let size = src.size();
    let _ = (src.frame_rate(), src.chroma());
    let (frames, _) = drain(&mut src, Some(size), 64);
    // Every frame needs at least its luma plane.
    assert!(frames.len() * size.area() <= stream.len());
});
