//! Concatenated PNGs (`ffmpeg -f image2pipe -c:v png`) from a chopped stream.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vizretarget::io::PngStreamSource;
use vizretarget_fuzz::{drain, split_chops, Choppy};

fuzz_target!(|data: &[u8]| {
    let (chops, stream) = split_chops(data);
    let mut src = PngStreamSource::new(Choppy::new(stream, chops, true), "stdin");
    let (frames, err) = drain(&mut src, None, 64);
    // Each PNG is at least signature + IHDR + IEND (8 + 25 + 12 bytes).
    assert!(frames.len() * 45 <= stream.len());
    if stream.is_empty() {
        assert!(
            frames.is_empty() && err.is_none(),
            "an empty stream is no frames"
        );
    }
});
