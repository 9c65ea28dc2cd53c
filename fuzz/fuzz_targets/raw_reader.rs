//! Raw RGBA / RGB24 frames from a chopped stream; size and layout from the first bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vizretarget::io::{RawFormat, RawSource};
use vizretarget::{Error, Size};
use vizretarget_fuzz::{drain, split_chops, Choppy};

fuzz_target!(|data: &[u8]| {
    let Some((head, rest)) = data.split_first_chunk::<3>() else {
        return;
    };
    let format = if head[0] & 1 == 0 {
        RawFormat::Rgba
    } else {
        RawFormat::Rgb24
    };
    // Frame sizes come from the command line, not the stream: keep them small.
    let size = Size::new(1 + head[1] as u32 % 64, 1 + head[2] as u32 % 64).unwrap();
    let (chops, stream) = split_chops(rest);
    let mut src = RawSource::new(Choppy::new(stream, chops, true), "stdin", size, format);
    let (frames, err) = drain(&mut src, Some(size), usize::MAX);

    let bpp = format.bytes_per_pixel();
    let frame_bytes = size.area() * bpp;
    assert_eq!(
        frames.len(),
        stream.len() / frame_bytes,
        "every whole frame"
    );
    let tail = stream.len() % frame_bytes;
    match err {
        None => assert_eq!(tail, 0, "a partial frame is an error"),
        Some(Error::TruncatedFrame { expected, got, .. }) => {
            assert_eq!((expected, got), (frame_bytes, tail));
        }
        Some(e) => panic!("unexpected error {e}"),
    }
    for (f, bytes) in frames.iter().zip(stream.chunks_exact(frame_bytes)) {
        for (p, b) in f.image.pixels().iter().zip(bytes.chunks_exact(bpp)) {
            assert_eq!(p[..3], b[..3]);
            assert_eq!(p[3], if bpp == 4 { b[3] } else { 255 });
        }
    }
});
