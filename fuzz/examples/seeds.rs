//! Writes small valid inputs for every target into `corpus/<target>/` (run from `fuzz/`:
//! `cargo run --example seeds`). Each file starts as its target expects: the raw reader's
//! three header bytes, and for the stream targets a first byte of 0 (no read chopping).

use std::fs;
use std::path::Path;
use vizretarget::io::{encode_still, OutputFormat, Y4mSink};
use vizretarget::stream::FrameSink;
use vizretarget::{Image, Retargeted, Size};

fn put(target: &str, name: &str, bytes: &[u8]) {
    let dir = Path::new("corpus").join(target);
    fs::create_dir_all(&dir).unwrap();
    fs::write(dir.join(name), bytes).unwrap();
}

fn picture(w: u32, h: u32, k: u8) -> Image {
    let mut img = Image::filled(Size::new(w, h).unwrap(), [255, 255, 255, 255]);
    for y in 0..h {
        for x in 0..w {
            if (x + y + k as u32).is_multiple_of(5) || (x > w / 3 && x < w / 2) {
                img.set(x, y, [20 * k, 90, 200, 255 - 40 * (x % 2) as u8]);
            }
        }
    }
    img
}

fn framed(image: Image, i: u64) -> Retargeted {
    Retargeted {
        image,
        frame_index: i,
        duration_ms: Some(40),
        stats: Default::default(),
        analysis: None,
        marks: None,
    }
}

fn gif(
    w: u16,
    h: u16,
    frames: &[(u16, u16, u16, u16, gif::DisposalMethod)],
    loops: gif::Repeat,
) -> Vec<u8> {
    let palette = [0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255];
    let mut out = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut out, w, h, &palette).unwrap();
        enc.set_repeat(loops).unwrap();
        for (k, &(left, top, fw, fh, dispose)) in frames.iter().enumerate() {
            let buffer: Vec<u8> = (0..fw as usize * fh as usize)
                .map(|i| ((i + k) % 5) as u8)
                .collect();
            let frame = gif::Frame {
                left,
                top,
                width: fw,
                height: fh,
                buffer: buffer.into(),
                dispose,
                delay: 3 + k as u16,
                transparent: Some(3),
                ..Default::default()
            };
            enc.write_frame(&frame).unwrap();
        }
    }
    out
}

fn main() {
    // raw_reader: [format, width-1, height-1, chop count] then frames.
    for (fmt, w, h, frames) in [
        (0u8, 4u8, 3u8, 2usize),
        (1, 3, 2, 3),
        (0, 1, 1, 1),
        (1, 8, 8, 1),
    ] {
        let bpp = if fmt == 0 { 4 } else { 3 };
        let mut v = vec![fmt, w - 1, h - 1, 0];
        v.extend((0..w as usize * h as usize * bpp * frames).map(|i| (i * 37) as u8));
        put(
            "raw_reader",
            &format!("{}-{w}x{h}x{frames}", ["rgba", "rgb24"][fmt as usize]),
            &v,
        );
    }
    // png_stream: one, then three PNGs back to back.
    let mut stream = vec![0u8];
    for k in 0..3 {
        let png = encode_still(&picture(5 + k as u32, 4, k), OutputFormat::Png).unwrap();
        if k == 0 {
            put("png_stream", "one", &[&[0u8][..], &png].concat());
        }
        stream.extend_from_slice(&png);
    }
    put("png_stream", "three", &stream);
    // Read in pieces of 1 to 17 bytes.
    put(
        "png_stream",
        "three-chopped",
        &[&[3u8, 4, 200, 0][..], &stream[1..]].concat(),
    );

    // gif_ingest: disposal methods, offsets, a frame beyond the screen, loop counts.
    use gif::DisposalMethod::*;
    let anim = gif(
        6,
        4,
        &[
            (0, 0, 6, 4, Keep),
            (1, 1, 2, 2, Previous),
            (3, 2, 3, 2, Background),
            (5, 3, 4, 4, Any),
        ],
        gif::Repeat::Infinite,
    );
    put("gif_ingest", "anim", &[&[0u8][..], &anim].concat());
    let one = gif(3, 3, &[(0, 0, 3, 3, Keep)], gif::Repeat::Finite(2));
    put("gif_ingest", "still", &[&[0u8][..], &one].concat());

    // y4m_reader: every chroma layout, two frames each.
    for (c, w, h) in [
        ("420jpeg", 5u32, 3u32),
        ("422", 4, 2),
        ("444", 3, 3),
        ("mono", 4, 4),
    ] {
        let mut bytes = format!("YUV4MPEG2 W{w} H{h} F25:1 Ip A1:1 C{c}\n").into_bytes();
        let (cw, ch) = match c {
            "420jpeg" => (w.div_ceil(2), h.div_ceil(2)),
            "422" => (w.div_ceil(2), h),
            "444" => (w, h),
            _ => (0, 0),
        };
        for f in 0..2u32 {
            bytes.extend_from_slice(b"FRAME\n");
            bytes.extend((0..w * h + 2 * cw * ch).map(|i| (16 + (i * 7 + f * 50) % 220) as u8));
        }
        put("y4m_reader", c, &[&[0u8][..], &bytes].concat());
    }
    let mut sink = Y4mSink::new(Vec::new(), "mem", None);
    for k in 0..2 {
        sink.write_frame(&framed(picture(6, 4, k), k as u64))
            .unwrap();
    }
    sink.finish().unwrap();
    put(
        "y4m_reader",
        "sink",
        &[&[0u8][..], &sink.into_inner().unwrap()].concat(),
    );

    // marks_json: the forms of the README and the tests.
    let layers = [
        r##"{"points": [{"id": "a", "x": 10, "y": 8, "r": 3, "fill": "#d7191c", "stroke": "#ffffff", "stroke_width": 1.5}, {"x": 30, "y": 20, "r": 2, "fill": [44, 123, 182, 200]}], "polylines": [{"points": [[1, 28], [12, 25], [39, 27]], "width": 2, "color": "#333"}], "edges": [{"from": "a", "to": 1, "width": 1.5, "color": "#55555580"}]}"##,
        r##"{"points": [{"id": "a", "x": 6, "y": 6, "r": 2}, {"id": "b", "x": 30, "y": 7, "r": 2}, {"id": "c", "x": 18, "y": 19, "radius": 2}], "edges": [{"from": "a", "to": "b"}, {"from": 1, "to": 2, "colour": [0, 0, 0]}, {"from": "c", "to": 0}]}"##,
        r##"{"polylines": [{"points": [[0, 0]]}, {"points": [[-5, 3], [50, 3.5], [20, 40]], "width": 0.5, "colour": "#0f08"}]}"##,
        "{}",
        "{\"points\": [{\"x\": 10, \"y\": 10, \"r\": 4}]}\n\n{}\n{\"points\": [{\"x\": 1, \"y\": 2, \"r\": 0}]}\n",
    ];
    for (i, l) in layers.iter().enumerate() {
        put("marks_json", &format!("layer-{i}"), l.as_bytes());
    }

    // retarget_frame: structured input from bytes; a few deterministic byte strings.
    for k in 0..6u32 {
        let v: Vec<u8> = (0..64 + 48 * k)
            .map(|i| (i.wrapping_mul(2654435761) >> (k + 3)) as u8)
            .collect();
        put("retarget_frame", &format!("bytes-{k}"), &v);
    }
}
