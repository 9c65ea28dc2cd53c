//! The bad-input corpus (issue 8): every input here is made by its test, broken on purpose
//! (zero bytes, wrong magic, truncated, bit-flipped, declaring absurd sizes or frame counts, raw
//! frames of the wrong size, marks with NaN, negative radii or far off the canvas). Each must
//! give one line on stderr naming the input and exit 1, or a documented recovery; never a
//! panic, never a half-written output.
//!
//! Limits are exercised both ways where it is cheap: the input just past a limit is refused,
//! the input at the limit is accepted, so a check that refuses everything fails here too.

use std::path::Path;
use std::process::Output;
use vizretarget::io::{decode_still, decode_still_with, open_input_with, GifSource, InputFormat};
use vizretarget::stream::FrameSource;
use vizretarget::{Error, Limit, Limits};

// ---------------------------------------------------------------------------------------------
// Running the binary.

mod common;
use common::{assert_only, run, run_with_stdin, stderr};

/// Exit 1, exactly one line on stderr holding every one of `words`, no panic.
fn assert_fails(out: &Output, words: &[&str]) {
    common::assert_fails(out, 1, words);
    let err = stderr(out);
    assert!(err.starts_with("vizretarget: error: "), "{err}");
}

fn assert_ok(out: &Output) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(0), "stderr: {err}");
    assert!(!err.contains("error"), "{err}");
}

fn write(dir: &Path, name: &str, bytes: &[u8]) {
    std::fs::write(dir.join(name), bytes).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Making inputs.

/// A 300x200 chart-like picture: white, a blue disc, a red bar, a grey axis.
fn chart(w: u32, h: u32) -> image::RgbImage {
    image::RgbImage::from_fn(w, h, |x, y| {
        let (dx, dy) = (x as i32 - 80, y as i32 - 90);
        if dx * dx + dy * dy <= 15 * 15 {
            image::Rgb([40, 90, 200])
        } else if (180..210).contains(&x) && (60..180).contains(&y) {
            image::Rgb([210, 50, 40])
        } else if y + 10 == h || x == 10 {
            image::Rgb([90, 90, 90])
        } else {
            image::Rgb([255, 255, 255])
        }
    })
}

fn encode_png(img: &image::RgbImage) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

fn png_bytes(w: u32, h: u32) -> Vec<u8> {
    encode_png(&chart(w, h))
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

fn png_chunk(kind: &[u8; 4], data: &[u8]) -> Vec<u8> {
    let mut body = kind.to_vec();
    body.extend_from_slice(data);
    let mut out = (data.len() as u32).to_be_bytes().to_vec();
    out.extend_from_slice(&body);
    out.extend_from_slice(&crc32(&body).to_be_bytes());
    out
}

const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// A well-formed PNG (correct CRCs) whose IHDR declares `w`x`h` RGB8, with one empty IDAT:
/// only a reader that trusts the header would allocate for it.
fn png_declaring(w: u32, h: u32) -> Vec<u8> {
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    let mut png = PNG_SIGNATURE.to_vec();
    png.extend(png_chunk(b"IHDR", &ihdr));
    png.extend(png_chunk(
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    ));
    png.extend(png_chunk(b"IEND", &[]));
    png
}

/// A GIF by hand: a `w`x`h` screen with a two-colour table, then `frames` frames, each
/// declaring the rectangle `fw`x`fh` but holding one pixel of LZW data (15 bytes a frame).
fn gif_declaring(w: u16, h: u16, fw: u16, fh: u16, frames: usize) -> Vec<u8> {
    let mut b = b"GIF89a".to_vec();
    b.extend(w.to_le_bytes());
    b.extend(h.to_le_bytes());
    b.extend([0x80, 0, 0, 0, 0, 0, 255, 255, 255]);
    let mut frame = vec![0x2c, 0, 0, 0, 0];
    frame.extend(fw.to_le_bytes());
    frame.extend(fh.to_le_bytes());
    frame.extend([0, 2, 2, 0x44, 0x01, 0]);
    b.reserve(frame.len() * frames + 1);
    for _ in 0..frames {
        b.extend_from_slice(&frame);
    }
    b.push(0x3b);
    b
}

/// A real animated GIF (the `gif` encoder): `n` frames of 60x40, each a different colour.
fn gif_frames(n: usize) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut out, 60, 40, &[]).unwrap();
        enc.set_repeat(gif::Repeat::Infinite).unwrap();
        for i in 0..n {
            let c = [(i * 40) as u8, 100, 255 - (i * 40) as u8, 255];
            let mut px: Vec<u8> = c.repeat(60 * 40);
            let mut f = gif::Frame::from_rgba_speed(60, 40, &mut px, 30);
            f.delay = 5;
            enc.write_frame(&f).unwrap();
        }
    }
    out
}

/// How many frames a GIF file holds (a complete, valid file, or the test fails).
fn gif_frame_count(path: &Path) -> usize {
    let file = std::fs::File::open(path).unwrap();
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(file).unwrap();
    let mut n = 0;
    while d.read_next_frame().unwrap().is_some() {
        n += 1;
    }
    n
}

/// `n` raw RGBA frames of `w`x`h`.
fn raw_frames(n: usize, w: usize, h: usize) -> Vec<u8> {
    (0..n * w * h)
        .flat_map(|i| [(i % 251) as u8, 128, 64, 255])
        .collect()
}

/// A YUV4MPEG2 stream of `n` grey 4:2:0 frames of 64x48.
fn y4m(n: usize) -> Vec<u8> {
    let mut v = b"YUV4MPEG2 W64 H48 F25:1 Ip A1:1 C420jpeg\n".to_vec();
    for i in 0..n {
        v.extend_from_slice(b"FRAME\n");
        v.extend(std::iter::repeat_n(40 + i as u8 * 30, 64 * 48));
        v.extend(std::iter::repeat_n(128u8, 2 * 32 * 24));
    }
    v
}

// ---------------------------------------------------------------------------------------------
// One picture.

#[test]
fn zero_byte_picture() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "empty.png", b"");
    let out = run(dir.path(), &["empty.png", "--width", "50", "-o", "out.png"]);
    assert_fails(&out, &["empty.png", "empty file"]);
    assert_only(dir.path(), &["empty.png"]);
}

#[test]
fn wrong_magic_picture() {
    let dir = tempfile::tempdir().unwrap();
    let mut png = png_bytes(300, 200);
    png[..8].copy_from_slice(b"JUNKJUNK");
    write(dir.path(), "junk.png", &png);
    let out = run(dir.path(), &["junk.png", "--width", "150", "-o", "out.png"]);
    assert_fails(&out, &["junk.png", "unsupported format"]);
    // A GIF signature on PNG bytes: read as a GIF, whose screen is then nonsense.
    let mut png = png_bytes(300, 200);
    png[..6].copy_from_slice(b"GIF87a");
    write(dir.path(), "liar.png", &png);
    let out = run(dir.path(), &["liar.png", "--width", "150", "-o", "out.png"]);
    assert_fails(&out, &["liar.png", "GIF"]);
    assert_only(dir.path(), &["junk.png", "liar.png"]);
}

#[test]
fn truncated_picture_at_every_stage() {
    let dir = tempfile::tempdir().unwrap();
    let png = png_bytes(300, 200);
    // Inside the signature, inside IHDR, just after it, in the middle, just before IEND.
    for (i, cut) in [5, 20, 40, png.len() / 2, png.len() - 13]
        .into_iter()
        .enumerate()
    {
        let name = format!("cut{i}.png");
        write(dir.path(), &name, &png[..cut]);
        let out = run(dir.path(), &[&name, "--width", "150", "-o", "out.png"]);
        let err = stderr(&out);
        assert_fails(&out, &[&name]);
        assert!(
            err.contains("truncated") || err.contains("unsupported format"),
            "cut at {cut}: {err}"
        );
        std::fs::remove_file(dir.path().join(&name)).unwrap();
        assert_only(dir.path(), &[]);
    }
}

#[test]
fn bit_flipped_picture() {
    // Every 7th byte flipped in turn (the library; hundreds of cases): each is an error naming
    // the input, or a picture of the declared size; never a panic.
    let png = png_bytes(300, 200);
    let name = Path::new("flipped.png");
    let mut refused = 0;
    for at in (0..png.len()).step_by(7) {
        for bit in [0x01u8, 0x80] {
            let mut bad = png.clone();
            bad[at] ^= bit;
            match decode_still(&bad, name) {
                Ok(img) => assert!(img.width() >= 1 && img.height() >= 1),
                Err(e) => {
                    let msg = e.to_string();
                    assert!(msg.starts_with("flipped.png: "), "{msg}");
                    assert_eq!(msg.lines().count(), 1, "{msg}");
                    refused += 1;
                }
            }
        }
    }
    assert!(refused > 0, "no flipped byte was noticed");
    // The binary on a flip inside IHDR: the CRC catches it, the message names the chunk
    // plainly (not the decoder's debug form of it).
    let dir = tempfile::tempdir().unwrap();
    let mut bad = png.clone();
    bad[20] ^= 0x01;
    write(dir.path(), "flipped.png", &bad);
    let out = run(
        dir.path(),
        &["flipped.png", "--width", "150", "-o", "out.png"],
    );
    assert_fails(&out, &["flipped.png", "corrupt PNG", "CRC", "IHDR"]);
    assert!(!stderr(&out).contains("ChunkType"), "{}", stderr(&out));
    // And inside the compressed pixels.
    let mut bad = png.clone();
    let mid = png.len() / 2;
    bad[mid] ^= 0x10;
    write(dir.path(), "flipped.png", &bad);
    let out = run(
        dir.path(),
        &["flipped.png", "--width", "150", "-o", "out.png"],
    );
    assert_fails(&out, &["flipped.png", "corrupt PNG"]);
    assert_only(dir.path(), &["flipped.png"]);
}

#[test]
fn png_declaring_65535_square_is_refused_from_its_header() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "huge.png", &png_declaring(65535, 65535));
    let out = run(dir.path(), &["huge.png", "--width", "100", "-o", "out.png"]);
    assert_fails(&out, &["huge.png", "65535x65535", "out of range"]);
    assert_only(dir.path(), &["huge.png"]);
}

#[test]
fn png_over_the_pixel_limit_names_the_option() {
    let dir = tempfile::tempdir().unwrap();
    // 48 MP: within 16384 a side, above the default 40 MP.
    write(dir.path(), "big.png", &png_declaring(8000, 6000));
    let out = run(dir.path(), &["big.png", "--width", "100", "-o", "out.png"]);
    assert_fails(&out, &["big.png", "8000x6000", "40000000", "--max-pixels"]);
    // The option moves the limit both ways.
    write(dir.path(), "in.png", &png_bytes(300, 200));
    let out = run(
        dir.path(),
        &[
            "in.png",
            "--width",
            "150",
            "-o",
            "out.png",
            "--max-pixels",
            "59999",
        ],
    );
    assert_fails(&out, &["in.png", "300x200", "59999", "--max-pixels"]);
    assert_only(dir.path(), &["big.png", "in.png"]);
    let out = run(
        dir.path(),
        &[
            "in.png",
            "--width",
            "150",
            "-o",
            "out.png",
            "--max-pixels",
            "60000",
        ],
    );
    assert_ok(&out);
    assert_eq!(
        image::open(dir.path().join("out.png")).unwrap().width(),
        150
    );
}

#[test]
fn still_over_the_memory_limit_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "in.png", &png_bytes(300, 200));
    let out = run(
        dir.path(),
        &[
            "in.png",
            "--width",
            "150",
            "-o",
            "out.png",
            "--memory-limit",
            "20M",
        ],
    );
    assert_fails(&out, &["in.png", "300x200", "20 MiB", "--memory-limit"]);
    assert_only(dir.path(), &["in.png"]);
    let out = run(
        dir.path(),
        &[
            "in.png",
            "--width",
            "150",
            "-o",
            "out.png",
            "--memory-limit",
            "64M",
        ],
    );
    assert_ok(&out);
    // The sheet of every method needs more than one method.
    let out = run(
        dir.path(),
        &[
            "compare",
            "in.png",
            "--width",
            "150",
            "-o",
            "sheet.png",
            "--memory-limit",
            "30M",
        ],
    );
    assert_fails(
        &out,
        &["in.png", "comparing every method", "--memory-limit"],
    );
    assert_only(dir.path(), &["in.png", "out.png"]);
}

#[test]
fn limit_options_take_only_sane_values() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "in.png", &png_bytes(30, 20));
    for (opt, value) in [
        ("--memory-limit", "lots"),
        ("--memory-limit", "5X"),
        ("--max-pixels", "many"),
        ("--max-frames", "1.5"),
    ] {
        let out = run(
            dir.path(),
            &["in.png", "--width", "15", "-o", "o.png", opt, value],
        );
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{opt} {value}: {err}");
        assert!(err.contains(value) && !err.contains("panicked"), "{err}");
    }
    assert_only(dir.path(), &["in.png"]);
}

// ---------------------------------------------------------------------------------------------
// GIF.

#[test]
fn gif_declaring_65535_square_is_refused_from_its_header() {
    let dir = tempfile::tempdir().unwrap();
    let gif = gif_declaring(65535, 65535, 1, 1, 1);
    write(dir.path(), "huge.gif", &gif);
    let out = run(
        dir.path(),
        &["huge.gif", "--size", "100x100", "-o", "out.gif"],
    );
    assert_fails(&out, &["huge.gif", "65535x65535", "out of range"]);
    // The same from stdin.
    let out = run_with_stdin(
        dir.path(),
        &["-", "--size", "100x100", "-o", "out.gif"],
        &gif,
    );
    assert_fails(&out, &["stdin", "65535x65535", "out of range"]);
    // Read as one picture (a .png output) it is refused the same way.
    let out = run(
        dir.path(),
        &["huge.gif", "--size", "100x100", "-o", "out.png"],
    );
    assert_fails(&out, &["huge.gif", "65535x65535"]);
    assert_only(dir.path(), &["huge.gif"]);
}

#[test]
fn gif_screen_over_the_pixel_limit() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "big.gif", &gif_declaring(8000, 8000, 1, 1, 1));
    let out = run(
        dir.path(),
        &["big.gif", "--size", "100x100", "-o", "out.gif"],
    );
    assert_fails(&out, &["big.gif", "8000x8000", "--max-pixels"]);
    assert_only(dir.path(), &["big.gif"]);
}

#[test]
fn gif_frame_rectangle_of_65535_square_on_a_small_screen() {
    // The screen is 4x4; the frame's own rectangle claims 65535x65535 (16 GiB of RGBA).
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "rect.gif",
        &gif_declaring(4, 4, 65535, 65535, 1),
    );
    let out = run(dir.path(), &["rect.gif", "--size", "2x2", "-o", "out.gif"]);
    assert_fails(
        &out,
        &["rect.gif", "frame 0", "65535x65535", "--max-pixels"],
    );
    // With the pixel limit off, the largest canvas still bounds it.
    let out = run(
        dir.path(),
        &[
            "rect.gif",
            "--size",
            "2x2",
            "-o",
            "out.gif",
            "--max-pixels",
            "0",
        ],
    );
    assert_fails(&out, &["rect.gif", "frame 0", "largest canvas"]);
    assert_only(dir.path(), &["rect.gif"]);
}

#[test]
fn gif_with_a_million_frames_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    // 15 MB: a million 1x1 frames on a 4x4 screen.
    write(
        dir.path(),
        "million.gif",
        &gif_declaring(4, 4, 1, 1, 1_000_000),
    );
    let out = run(
        dir.path(),
        &["million.gif", "--size", "2x2", "-o", "out.gif"],
    );
    assert_fails(
        &out,
        &["million.gif", "more than 100000 frames", "--max-frames"],
    );
    assert_only(dir.path(), &["million.gif"]);
    // Through the library: refused when opened, before a frame is read.
    let e = open_input_with(
        &dir.path().join("million.gif"),
        InputFormat::Auto,
        None,
        &Limits::default(),
    )
    .err()
    .expect("refused");
    assert!(
        matches!(
            e,
            Error::LimitExceeded {
                limit: Limit::Frames,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn gif_frame_limit_is_exact() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "six.gif", &gif_frames(6));
    let out = run(
        dir.path(),
        &[
            "six.gif",
            "--size",
            "30x40",
            "-o",
            "out.gif",
            "--max-frames",
            "5",
        ],
    );
    assert_fails(&out, &["six.gif", "more than 5 frames", "--max-frames"]);
    assert_only(dir.path(), &["six.gif"]);
    let out = run(
        dir.path(),
        &[
            "six.gif",
            "--size",
            "30x40",
            "-o",
            "out.gif",
            "--max-frames",
            "6",
            "-q",
        ],
    );
    assert_ok(&out);
    assert_eq!(gif_frame_count(&dir.path().join("out.gif")), 6);
}

#[test]
fn gif_on_stdin_past_the_frame_limit_is_refused_before_decoding() {
    // A GIF on stdin is one animation, read whole (issue 39): its frames are counted first,
    // as a GIF file's are, and nothing is written.
    let dir = tempfile::tempdir().unwrap();
    let out = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--size",
            "30x40",
            "-o",
            "out.gif",
            "--max-frames",
            "3",
            "-q",
        ],
        gif_frames(5),
    );
    assert_fails(&out, &["stdin", "more than 3 frames", "--max-frames"]);
    assert_only(dir.path(), &[]);
}

#[test]
fn zero_byte_gif() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "empty.gif", b"");
    let out = run(
        dir.path(),
        &["empty.gif", "--size", "30x40", "-o", "out.gif"],
    );
    assert_fails(&out, &["empty.gif", "empty file"]);
    assert_only(dir.path(), &["empty.gif"]);
}

#[test]
fn truncated_gif_keeps_the_complete_frames() {
    let dir = tempfile::tempdir().unwrap();
    let gif = gif_frames(4);
    // Cut inside the last frame's data.
    write(dir.path(), "cut.gif", &gif[..gif.len() - 6]);
    let out = run(
        dir.path(),
        &["cut.gif", "--size", "30x40", "-o", "out.gif", "-q"],
    );
    assert_fails(&out, &["cut.gif", "frame 3"]);
    assert_eq!(gif_frame_count(&dir.path().join("out.gif")), 3);
    assert_only(dir.path(), &["cut.gif", "out.gif"]);
    // Cut inside the header: nothing to keep, nothing written.
    write(dir.path(), "head.gif", &gif[..9]);
    let out = run(
        dir.path(),
        &["head.gif", "--size", "30x40", "-o", "out2.gif"],
    );
    assert_fails(&out, &["head.gif"]);
    assert_only(dir.path(), &["cut.gif", "head.gif", "out.gif"]);
}

#[test]
fn bit_flipped_gif() {
    // Every 3rd byte flipped in turn, read through the library to the end: errors name the
    // input on one line, frames that decode have the screen's size; never a panic.
    let gif = gif_frames(3);
    let mut refused = 0;
    for at in (0..gif.len()).step_by(3) {
        let mut bad = gif.clone();
        bad[at] ^= 0x24;
        let mut src = match GifSource::with_limits(&bad[..], "flipped.gif", &Limits::default()) {
            Ok(s) => s,
            Err(e) => {
                assert!(e.to_string().starts_with("flipped.gif: "), "{e}");
                refused += 1;
                continue;
            }
        };
        let size = src.size();
        for _ in 0..10 {
            match src.next_frame() {
                Ok(Some(f)) => assert_eq!(f.image.size(), size),
                Ok(None) => break,
                Err(e) => {
                    let msg = e.to_string();
                    assert!(msg.starts_with("flipped.gif"), "{msg}");
                    assert_eq!(msg.lines().count(), 1, "{msg}");
                    refused += 1;
                    break;
                }
            }
        }
    }
    assert!(refused > 0, "no flipped byte was noticed");
}

// ---------------------------------------------------------------------------------------------
// Raw frames.

#[test]
fn raw_file_of_the_wrong_size_is_refused_before_any_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mut raw = raw_frames(3, 60, 40);
    raw.extend_from_slice(&[1, 2, 3, 4, 5, 6, 7]);
    write(dir.path(), "frames.rgba", &raw);
    let args = [
        "frames.rgba",
        "--input-format",
        "rgba",
        "--input-size",
        "60x40",
        "--size",
        "30x40",
        "-o",
        "out.gif",
    ];
    let out = run(dir.path(), &args);
    assert_fails(
        &out,
        &[
            "frames.rgba",
            "not a whole number",
            "--input-size",
            "--input-format",
        ],
    );
    assert_only(dir.path(), &["frames.rgba"]);
    // The same bytes read as the size they are not: also refused.
    write(dir.path(), "frames.rgba", &raw_frames(3, 60, 40));
    let mut wrong = args;
    wrong[4] = "61x40";
    let out = run(dir.path(), &wrong);
    assert_fails(&out, &["frames.rgba", "61x40", "not a whole number"]);
    assert_only(dir.path(), &["frames.rgba"]);
}

#[test]
fn raw_short_last_frame_on_stdin() {
    let dir = tempfile::tempdir().unwrap();
    let mut raw = raw_frames(3, 60, 40);
    raw.extend_from_slice(&[9; 100]);
    let out = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--input-format",
            "rgba",
            "--input-size",
            "60x40",
            "--size",
            "30x40",
            "-o",
            "out.gif",
            "-q",
        ],
        &raw,
    );
    assert_fails(
        &out,
        &[
            "stdin",
            "frame 3 is incomplete",
            "100 of 9600 bytes",
            "--input-size",
        ],
    );
    // Documented: the complete frames before are kept.
    assert_eq!(gif_frame_count(&dir.path().join("out.gif")), 3);
}

#[test]
fn raw_size_over_the_pixel_limit() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "frames.rgba", &raw_frames(1, 60, 40));
    let out = run(
        dir.path(),
        &[
            "frames.rgba",
            "--input-format",
            "rgba",
            "--input-size",
            "60x40",
            "--size",
            "30x40",
            "-o",
            "out.gif",
            "--max-pixels",
            "2399",
        ],
    );
    assert_fails(&out, &["frames.rgba", "60x40", "2399", "--max-pixels"]);
    assert_only(dir.path(), &["frames.rgba"]);
}

#[test]
fn raw_stdin_frame_limit_is_exact() {
    let dir = tempfile::tempdir().unwrap();
    let args = |out: &'static str| {
        vec![
            "-",
            "--input-format",
            "rgba",
            "--input-size",
            "60x40",
            "--size",
            "30x40",
            "-o",
            out,
            "--max-frames",
            "2",
            "-q",
        ]
    };
    let out = run_with_stdin(dir.path(), &args("three.gif"), raw_frames(3, 60, 40));
    assert_fails(&out, &["stdin", "past 2 frames", "--max-frames"]);
    assert_eq!(gif_frame_count(&dir.path().join("three.gif")), 2);
    let out = run_with_stdin(dir.path(), &args("two.gif"), raw_frames(2, 60, 40));
    assert_ok(&out);
    assert_eq!(gif_frame_count(&dir.path().join("two.gif")), 2);
}

#[test]
fn raw_empty_stdin_names_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--input-format",
            "rgba",
            "--input-size",
            "60x40",
            "--size",
            "30x40",
            "-o",
            "out.gif",
        ],
        b"",
    );
    assert_fails(&out, &["stdin: no frames"]);
    assert!(!stderr(&out).contains("out.gif"), "{}", stderr(&out));
    assert_only(dir.path(), &[]);
}

// ---------------------------------------------------------------------------------------------
// YUV4MPEG2.

#[test]
fn y4m_declaring_65535_square() {
    let dir = tempfile::tempdir().unwrap();
    let mut v = b"YUV4MPEG2 W65535 H65535 F25:1\nFRAME\n".to_vec();
    v.extend([0u8; 100]);
    write(dir.path(), "huge.y4m", &v);
    let out = run(
        dir.path(),
        &["huge.y4m", "--size", "32x48", "-o", "out.gif"],
    );
    assert_fails(&out, &["huge.y4m", "65535x65535", "out of range"]);
    assert_only(dir.path(), &["huge.y4m"]);
}

#[test]
fn y4m_short_last_frame() {
    let dir = tempfile::tempdir().unwrap();
    let v = y4m(3);
    write(dir.path(), "short.y4m", &v[..v.len() - 100]);
    let out = run(
        dir.path(),
        &["short.y4m", "--size", "32x48", "-o", "out.gif", "-q"],
    );
    assert_fails(
        &out,
        &["short.y4m", "frame 2 is incomplete", "4508 of 4608"],
    );
    assert_eq!(gif_frame_count(&dir.path().join("out.gif")), 2);
}

#[test]
fn y4m_header_that_is_not_text() {
    // A byte that is not UTF-8 right where a tag letter goes: it once split a multi-byte
    // character in two (a panic).
    let dir = tempfile::tempdir().unwrap();
    let mut v = b"YUV4MPEG2 \xffW64 H48\n".to_vec();
    let good = y4m(1);
    let body = good.iter().position(|&b| b == b'\n').unwrap() + 1;
    v.extend(&good[body..]);
    write(dir.path(), "odd.y4m", &v);
    let out = run(dir.path(), &["odd.y4m", "--size", "32x48", "-o", "out.gif"]);
    assert_fails(&out, &["odd.y4m", "width (W) or height (H)"]);
    assert_only(dir.path(), &["odd.y4m"]);
}

#[test]
fn y4m_stdin_frame_limit() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--size",
            "32x48",
            "-o",
            "out.gif",
            "--max-frames",
            "2",
            "-q",
        ],
        y4m(3),
    );
    assert_fails(&out, &["stdin", "past 2 frames"]);
    assert_eq!(gif_frame_count(&dir.path().join("out.gif")), 2);
}

// ---------------------------------------------------------------------------------------------
// A stream of PNGs on stdin.

fn png_stream_run(dir: &Path, input: &[u8]) -> Output {
    run_with_stdin(
        dir,
        &["-", "--size", "150x200", "-o", "out.gif", "-q"],
        input,
    )
}

#[test]
fn png_stream_frame_with_wrong_magic() {
    let dir = tempfile::tempdir().unwrap();
    let png = png_bytes(300, 200);
    let mut input = png.clone();
    input.extend_from_slice(b"JUNKJUNK");
    input.extend_from_slice(&png[8..]);
    let out = png_stream_run(dir.path(), &input);
    assert_fails(&out, &["stdin", "frame 1: not a PNG"]);
    assert_eq!(gif_frame_count(&dir.path().join("out.gif")), 1);
}

#[test]
fn png_stream_frame_declaring_65535_square() {
    let dir = tempfile::tempdir().unwrap();
    let mut input = png_bytes(300, 200);
    input.extend(png_declaring(65535, 65535));
    let out = png_stream_run(dir.path(), &input);
    assert_fails(&out, &["stdin (PNG 1)", "65535x65535", "out of range"]);
}

#[test]
fn png_stream_chunk_claiming_two_gigabytes() {
    let dir = tempfile::tempdir().unwrap();
    let mut input = PNG_SIGNATURE.to_vec();
    input.extend_from_slice(&0x7fff_0000u32.to_be_bytes());
    input.extend_from_slice(b"IDAT");
    input.extend_from_slice(&[0; 100]);
    let out = png_stream_run(dir.path(), &input);
    assert_fails(&out, &["stdin", "PNG 0", "2147418112 bytes"]);
    assert_only(dir.path(), &[]);
}

#[test]
fn png_stream_truncated() {
    // One PNG cut short is one picture (issue 39), named as such.
    let dir = tempfile::tempdir().unwrap();
    let png = png_bytes(300, 200);
    let out = png_stream_run(dir.path(), &png[..png.len() / 2]);
    assert_fails(&out, &["stdin", "truncated PNG"]);
    assert_only(dir.path(), &[]);
    // A stream whose second PNG is cut short keeps the first.
    let input = [&png[..], &png[..png.len() / 2]].concat();
    let out = png_stream_run(dir.path(), &input);
    assert_fails(&out, &["stdin", "PNG 1", "incomplete"]);
    assert_eq!(gif_frame_count(&dir.path().join("out.gif")), 1);
}

// ---------------------------------------------------------------------------------------------
// A folder of frames.

#[test]
fn folder_over_the_frame_limit_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    // The first frame is corrupt: were it decoded, the error would be about it.
    let mut bad = png_bytes(60, 40);
    let mid = bad.len() / 2;
    bad[mid] ^= 0xff;
    write(&frames, "f1.png", &bad);
    for i in 2..=4 {
        write(&frames, &format!("f{i}.png"), &png_bytes(60, 40));
    }
    let out = run(
        dir.path(),
        &[
            "frames",
            "--size",
            "30x40",
            "-o",
            "out/",
            "--max-frames",
            "3",
        ],
    );
    assert_fails(&out, &["frames", "holds 4 frames", "--max-frames"]);
    assert_only(dir.path(), &["frames"]);
}

#[test]
fn folder_with_a_zero_byte_and_a_truncated_file() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    for i in 1..=3 {
        write(&frames, &format!("f{i}.png"), &png_bytes(60, 40));
    }
    // Documented: a folder's frames are its pictures by content, so an empty file (a snapshot
    // not yet written) is not a frame.
    write(&frames, "f2b.png", b"");
    let out = run(
        dir.path(),
        &["frames", "--size", "30x40", "-o", "out/", "-q"],
    );
    assert_ok(&out);
    let mut written: Vec<_> = std::fs::read_dir(dir.path().join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["f1.png", "f2.png", "f3.png"]);
    // A truncated picture is one: the error names it.
    let png = png_bytes(60, 40);
    write(&frames, "f2b.png", &png[..png.len() / 2]);
    let out = run(
        dir.path(),
        &["frames", "--size", "30x40", "-o", "out2.gif", "-q"],
    );
    assert_fails(&out, &["f2b.png", "truncated PNG"]);
}

// ---------------------------------------------------------------------------------------------
// Vector marks.

fn marks_run(dir: &Path, json: &str) -> Output {
    write(dir, "in.png", &png_bytes(300, 200));
    write(dir, "marks.json", json.as_bytes());
    run(
        dir,
        &[
            "in.png",
            "--size",
            "150x200",
            "--marks",
            "marks.json",
            "-o",
            "out.png",
        ],
    )
}

#[test]
fn marks_with_nan() {
    let dir = tempfile::tempdir().unwrap();
    let out = marks_run(dir.path(), r#"{"points": [{"x": NaN, "y": 5, "r": 3}]}"#);
    assert_fails(&out, &["marks.json", "line 1 column 19", "JSON has no NaN"]);
    assert_only(dir.path(), &["in.png", "marks.json"]);
}

#[test]
fn marks_with_infinity() {
    let dir = tempfile::tempdir().unwrap();
    let out = marks_run(
        dir.path(),
        r#"{"points": [{"x": 10, "y": -Infinity, "r": 3}]}"#,
    );
    assert_fails(&out, &["marks.json", "JSON has no NaN or Infinity"]);
    let out = marks_run(dir.path(), r#"{"points": [{"x": 1e999, "y": 5, "r": 3}]}"#);
    assert_fails(&out, &["marks.json", "number out of range"]);
    assert_only(dir.path(), &["in.png", "marks.json"]);
}

#[test]
fn marks_with_negative_radius() {
    let dir = tempfile::tempdir().unwrap();
    let out = marks_run(
        dir.path(),
        r#"{"points": [{"x": 10, "y": 5, "r": 2}, {"x": 10, "y": 5, "r": -3}]}"#,
    );
    assert_fails(
        &out,
        &["marks.json", "points[1]: radius -3 is out of range"],
    );
    // A huge radius is named briefly, not in 300 digits.
    let out = marks_run(dir.path(), r#"{"points": [{"x": 10, "y": 5, "r": 1e300}]}"#);
    assert_fails(&out, &["marks.json", "radius 1e300"]);
    assert!(stderr(&out).len() < 200, "{}", stderr(&out));
    assert_only(dir.path(), &["in.png", "marks.json"]);
}

#[test]
fn marks_far_outside_the_canvas_are_carried_and_not_drawn() {
    // Documented: a mark outside the canvas is carried by the nearest triangle's warp and
    // drawn where it lands; far off, that is nowhere. Beyond ±1e6 the layer is refused.
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "in.png",
        &encode_png(&image::RgbImage::from_pixel(300, 200, image::Rgb([255; 3]))),
    );
    let layer = r##"{"points": [
        {"x": 100000, "y": -50000, "r": 40, "fill": "#ff0000"},
        {"x": -3, "y": 100, "r": 2, "fill": "#0000ff"},
        {"x": 150, "y": 100, "r": 6, "fill": "#00ff00"}]}"##;
    write(dir.path(), "marks.json", layer.as_bytes());
    let out = run(
        dir.path(),
        &[
            "in.png",
            "--size",
            "150x200",
            "--marks",
            "marks.json",
            "-o",
            "out.png",
        ],
    );
    assert_ok(&out);
    let img = image::open(dir.path().join("out.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (150, 200));
    let count = |f: fn(&image::Rgb<u8>) -> bool| img.pixels().filter(|p| f(p)).count();
    assert!(
        count(|p| p[1] > 200 && p[0] < 60 && p[2] < 60) > 20,
        "the mark inside is drawn"
    );
    assert_eq!(
        count(|p| p[0] > 200 && p[1] < 60 && p[2] < 60),
        0,
        "the far mark is not"
    );
    write(
        dir.path(),
        "marks.json",
        br#"{"polylines": [{"points": [[0, 0], [2e6, 5]]}]}"#,
    );
    let out = run(
        dir.path(),
        &[
            "in.png",
            "--size",
            "150x200",
            "--marks",
            "marks.json",
            "-o",
            "out2.png",
        ],
    );
    assert_fails(
        &out,
        &["marks.json", "polylines[0]", "(2000000, 5)", "1000000"],
    );
    assert_only(dir.path(), &["in.png", "marks.json", "out.png"]);
}

#[test]
fn marks_truncated_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = marks_run(dir.path(), r#"{"points": [{"x": 10, "y": 5, "r": 3}"#);
    assert_fails(&out, &["marks.json", "EOF while parsing", "line 1"]);
    let out = marks_run(dir.path(), "");
    assert_fails(&out, &["marks.json", "EOF while parsing"]);
    assert_only(dir.path(), &["in.png", "marks.json"]);
}

#[test]
fn marks_jsonl_with_a_bad_line_in_a_stream() {
    // Lines are read as the frames come (a stream may be endless): the frames before the bad
    // line are kept, the error names the file and the line.
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "in.y4m", &y4m(3));
    write(
        dir.path(),
        "marks.jsonl",
        b"{}\n{\"points\": [{\"x\": 5, \"y\": 5, \"r\": 2}]}\n{\"points\": [{\"x\": NaN}]}\n",
    );
    let out = run(
        dir.path(),
        &[
            "in.y4m",
            "--size",
            "32x48",
            "--marks",
            "marks.jsonl",
            "-o",
            "out.gif",
            "-q",
        ],
    );
    assert_fails(&out, &["marks.jsonl", "line 3, column", "JSON has no NaN"]);
    assert_eq!(gif_frame_count(&dir.path().join("out.gif")), 2);
}

// ---------------------------------------------------------------------------------------------
// The library's limits, typed.

#[test]
fn library_limits_are_typed_errors_naming_the_input() {
    let png = png_bytes(300, 200);
    let name = Path::new("in.png");
    let few = Limits::default().with_max_pixels(Some(59_999));
    let e = decode_still_with(&png, name, &few).unwrap_err();
    assert!(
        matches!(e, Error::LimitExceeded { limit: Limit::Pixels, ref path, .. } if path == name),
        "{e}"
    );
    assert!(decode_still_with(&png, name, &few.with_max_pixels(Some(60_000))).is_ok());
    // A still job's memory, from its sizes.
    let from = vizretarget::Size::new(300, 200).unwrap();
    let to = vizretarget::Size::new(150, 200).unwrap();
    let small = Limits::default().with_memory_budget(Some(20 << 20));
    let e = small.check_still(name, from, to).unwrap_err();
    assert!(
        matches!(
            e,
            Error::LimitExceeded {
                limit: Limit::Memory,
                ..
            }
        ),
        "{e}"
    );
    assert!(Limits::default().check_still(name, from, to).is_ok());
}
