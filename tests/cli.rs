//! The command line as a user meets it: every bad input gives one line on stderr naming the
//! problem, a non-zero exit, no panic, and no output or temporary file left behind. Inputs are
//! made by each test in its own temporary folder.

mod common;
use common::{assert_fails, assert_only, run, stderr};

use std::path::PathBuf;

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

fn png_bytes(w: u32, h: u32) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    chart(w, h)
        .write_to(&mut out, image::ImageFormat::Png)
        .unwrap();
    out.into_inner()
}

/// A temporary folder holding `name` with `bytes`.
fn folder_with(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
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

#[test]
fn crc32_matches_a_png_encoder() {
    // The IHDR of a real PNG ends with the CRC our helper must reproduce.
    let png = png_bytes(3, 2);
    assert_eq!(
        crc32(&png[12..29]).to_be_bytes(),
        png[29..33],
        "crc of IHDR"
    );
}

#[test]
fn missing_input_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(
        dir.path(),
        &["nothere.png", "--size", "100x100", "-o", "out.png"],
    );
    assert_fails(&out, 1, &["nothere.png", "No such file"]);
    // The OS message must appear once, not twice.
    assert_eq!(
        stderr(&out).matches("No such file").count(),
        1,
        "{}",
        stderr(&out)
    );
    assert_only(dir.path(), &[]);
}

#[test]
fn corrupt_png() {
    let mut bytes = PNG_SIGNATURE.to_vec();
    let mut x = 0x2545_F491u32;
    bytes.extend((0..2000).map(|_| {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x as u8
    }));
    let (dir, _) = folder_with("noise.png", &bytes);
    let out = run(
        dir.path(),
        &["noise.png", "--size", "100x100", "-o", "out.png"],
    );
    assert_fails(&out, 1, &["noise.png", "corrupt PNG"]);
    assert_only(dir.path(), &["noise.png"]);
}

#[test]
fn truncated_png() {
    let png = png_bytes(300, 200);
    let (dir, _) = folder_with("half.png", &png[..png.len() / 2]);
    let out = run(
        dir.path(),
        &["half.png", "--size", "150x200", "-o", "out.png"],
    );
    assert_fails(&out, 1, &["half.png", "truncated PNG"]);
    assert_only(dir.path(), &["half.png"]);
}

#[test]
fn unsupported_format_bmp() {
    // A BMP header: recognised as BMP, which this tool does not read.
    let mut bmp = b"BM".to_vec();
    bmp.extend_from_slice(&[0u8; 64]);
    let (dir, _) = folder_with("chart.bmp", &bmp);
    let out = run(
        dir.path(),
        &["chart.bmp", "--size", "100x100", "-o", "out.png"],
    );
    assert_fails(&out, 1, &["chart.bmp", "unsupported format BMP"]);
    assert_only(dir.path(), &["chart.bmp"]);
}

#[test]
fn unsupported_format_text() {
    let (dir, _) = folder_with("notes.png", b"this is a text file, not a picture\n");
    let out = run(
        dir.path(),
        &["notes.png", "--size", "100x100", "-o", "out.png"],
    );
    assert_fails(&out, 1, &["notes.png", "unsupported format"]);
    assert_only(dir.path(), &["notes.png"]);
}

#[test]
fn empty_input_file() {
    let (dir, _) = folder_with("empty.png", b"");
    let out = run(
        dir.path(),
        &["empty.png", "--size", "100x100", "-o", "out.png"],
    );
    assert_fails(&out, 1, &["empty.png", "empty file"]);
    assert_only(dir.path(), &["empty.png"]);
}

/// Usage errors found while parsing: exit 2, one line naming the value.
fn assert_usage_error(args: &[&str], words: &[&str]) {
    let (dir, _) = folder_with("in.png", &png_bytes(300, 200));
    let mut all = vec!["in.png", "-o", "out.png"];
    all.extend_from_slice(args);
    let out = run(dir.path(), &all);
    assert_fails(&out, 2, words);
    assert_only(dir.path(), &["in.png"]);
}

#[test]
fn target_of_zero() {
    assert_usage_error(
        &["--size", "0x100"],
        &["'0x100'", "out of range", "1 to 16384"],
    );
}

#[test]
fn size_not_a_number() {
    assert_usage_error(&["--size", "abcx100"], &["'abc'", "not a whole number"]);
}

#[test]
fn width_not_a_number() {
    assert_usage_error(&["--width", "ten"], &["'ten'", "not a whole number"]);
}

#[test]
fn negative_width() {
    assert_usage_error(&["--width", "-5"], &["-5", "out of range"]);
}

#[test]
fn absurd_target() {
    assert_usage_error(
        &["--size", "20000x100"],
        &["20000", "out of range", "16384"],
    );
}

#[test]
fn no_target_given() {
    assert_usage_error(&[], &["--size", "--width", "--height"]);
}

#[test]
fn alpha_out_of_range() {
    let (dir, _) = folder_with("in.png", &png_bytes(300, 200));
    let out = run(
        dir.path(),
        &["in.png", "--width", "150", "--alpha", "1", "-o", "out.png"],
    );
    // A usage error: exit 2, as documented.
    assert_fails(&out, 2, &["alpha 1", "out of range", "4 to 200"]);
    assert_only(dir.path(), &["in.png"]);
}

#[test]
fn huge_declared_png_is_refused_from_its_header() {
    // A well-formed IHDR (correct CRC) declaring 20000x20000 RGB8, then a tiny IDAT: decoding
    // pixels would need 1.2 GB, so the refusal must come from the header (the message quotes
    // the declared size, which only the header gives).
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&20000u32.to_be_bytes());
    ihdr.extend_from_slice(&20000u32.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    let mut png = PNG_SIGNATURE.to_vec();
    png.extend(png_chunk(b"IHDR", &ihdr));
    png.extend(png_chunk(
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    ));
    png.extend(png_chunk(b"IEND", &[]));
    let (dir, _) = folder_with("huge.png", &png);
    let out = run(
        dir.path(),
        &["huge.png", "--size", "100x100", "-o", "out.png"],
    );
    assert_fails(&out, 1, &["huge.png", "20000x20000", "out of range"]);
    assert_only(dir.path(), &["huge.png"]);
}

#[test]
fn unknown_output_extension() {
    let (dir, _) = folder_with("in.png", &png_bytes(300, 200));
    let out = run(
        dir.path(),
        &["in.png", "--size", "150x200", "-o", "out.bmp"],
    );
    // A usage error: exit 2, as documented.
    assert_fails(&out, 2, &["out.bmp", "unsupported output format", ".png"]);
    assert_only(dir.path(), &["in.png"]);
}

#[test]
fn output_folder_missing() {
    let (dir, _) = folder_with("in.png", &png_bytes(300, 200));
    let out = run(
        dir.path(),
        &["in.png", "--size", "150x200", "-o", "no/such/out.png"],
    );
    assert_fails(&out, 1, &["no/such/out.png", "does not exist"]);
    assert_only(dir.path(), &["in.png"]);
}

#[test]
fn existing_output_is_not_clobbered_by_a_failed_run() {
    let png = png_bytes(300, 200);
    let (dir, _) = folder_with("half.png", &png[..png.len() / 2]);
    let before = b"precious bytes that must survive".to_vec();
    std::fs::write(dir.path().join("out.png"), &before).unwrap();
    let out = run(
        dir.path(),
        &["half.png", "--size", "150x200", "-o", "out.png"],
    );
    assert_fails(&out, 1, &["half.png", "truncated"]);
    assert_eq!(std::fs::read(dir.path().join("out.png")).unwrap(), before);
    assert_only(dir.path(), &["half.png", "out.png"]);
}

/// A successful run: exit 0, quiet stderr, output decodes to `w` x `h`, only `files` left.
fn assert_writes(args: &[&str], output: &str, w: u32, h: u32) -> Vec<u8> {
    let (dir, _) = folder_with("in.png", &png_bytes(300, 200));
    let mut all = vec!["in.png", "-o", output];
    all.extend_from_slice(args);
    let out = run(dir.path(), &all);
    assert!(out.status.success(), "failed: {}", stderr(&out));
    assert!(stderr(&out).is_empty(), "stderr: {}", stderr(&out));
    let bytes = std::fs::read(dir.path().join(output)).unwrap();
    let img = image::load_from_memory(&bytes).unwrap();
    assert_eq!((img.width(), img.height()), (w, h));
    assert_only(dir.path(), &["in.png", output]);
    bytes
}

#[test]
fn size_gives_that_size() {
    let bytes = assert_writes(&["--size", "150x200"], "out.png", 150, 200);
    assert!(bytes.starts_with(PNG_SIGNATURE));
}

#[test]
fn width_alone_keeps_height() {
    assert_writes(&["--width", "120"], "out.png", 120, 200);
}

#[test]
fn height_alone_keeps_width() {
    assert_writes(&["--height", "90"], "out.png", 300, 90);
}

#[test]
fn jpg_output_is_jpeg() {
    let bytes = assert_writes(&["--size", "150x200"], "out.jpg", 150, 200);
    assert!(bytes.starts_with(&[0xFF, 0xD8, 0xFF]), "JPEG magic");
    assert_eq!(
        image::guess_format(&bytes).unwrap(),
        image::ImageFormat::Jpeg
    );
}

#[test]
fn existing_output_is_replaced_on_success() {
    let (dir, _) = folder_with("in.png", &png_bytes(300, 200));
    std::fs::write(dir.path().join("out.png"), b"old").unwrap();
    let out = run(dir.path(), &["in.png", "--width", "150", "-o", "out.png"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("out.png")).unwrap();
    assert_eq!((img.width(), img.height()), (150, 200));
    assert_only(dir.path(), &["in.png", "out.png"]);
}

#[test]
fn help_teaches() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &["--help"]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(help.contains("aspect ratio"), "{help}");
    assert!(help.contains("Examples (run from a clone"), "{help}");
    assert_eq!(
        help.matches("\n    vizretarget ").count(),
        3,
        "three examples first: {help}"
    );
    // clap wraps the help at 100 columns: an example longer than that would be cut in two.
    let examples = help.split("\nExamples").nth(1).unwrap();
    assert!(
        examples.lines().all(|l| l.chars().count() <= 100),
        "{examples}"
    );
    for want in [
        "1 to 16384",
        "4 to 200",
        "[default: 20]",
        ".png, .jpg, .jpeg or .webp",
    ] {
        assert!(help.contains(want), "help lacks {want:?}: {help}");
    }
}

/// A debug folder that cannot be made fails the run naming the option and the folder.
#[test]
fn an_unwritable_debug_folder_is_named() {
    let (dir, _) = folder_with("in.png", &png_bytes(120, 80));
    std::fs::write(dir.path().join("file"), b"not a folder").unwrap();
    let out = run(
        dir.path(),
        &[
            "in.png",
            "--width",
            "60",
            "--debug-dir",
            "file/dbg",
            "-o",
            "o.png",
        ],
    );
    assert_fails(&out, 1, &["--debug-dir", "file/dbg"]);
}

/// `chart(w, h)` encoded as `format`.
fn encoded(w: u32, h: u32, format: image::ImageFormat) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    image::DynamicImage::ImageRgb8(chart(w, h))
        .write_to(&mut out, format)
        .unwrap();
    out.into_inner()
}

/// An animated GIF of `n` frames of `chart(w, h)`.
fn animated_gif(w: u32, h: u32, n: usize) -> Vec<u8> {
    let mut bytes = Vec::new();
    {
        let mut enc = image::codecs::gif::GifEncoder::new(&mut bytes);
        let frame = image::DynamicImage::ImageRgb8(chart(w, h)).into_rgba8();
        enc.encode_frames((0..n).map(|_| image::Frame::new(frame.clone())))
            .unwrap();
    }
    bytes
}

/// The size of the PNG in `bytes`, and that it is one.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    let img = image::load_from_memory_with_format(bytes, image::ImageFormat::Png).unwrap();
    (img.width(), img.height())
}

/// One picture on stdin is one picture, recognised by content as image tools read `-`: a PNG,
/// JPEG, WebP or GIF file; to a file, to stdout (as PNG), into a folder. A stream of PNGs stays
/// a stream, and an animated GIF an animation (issue 39).
#[test]
fn one_picture_on_stdin_is_one_picture() {
    use common::run_with_stdin;
    use image::ImageFormat;
    let dir = tempfile::tempdir().unwrap();
    let png = png_bytes(120, 80);
    for (name, bytes) in [
        ("png", png.clone()),
        ("jpeg", encoded(120, 80, ImageFormat::Jpeg)),
        ("webp", encoded(120, 80, ImageFormat::WebP)),
        ("gif", encoded(120, 80, ImageFormat::Gif)),
    ] {
        let out = run_with_stdin(
            dir.path(),
            &["-", "--width", "50%", "-o", "out.png"],
            &bytes,
        );
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let written = std::fs::read(dir.path().join("out.png")).unwrap();
        assert_eq!(png_size(&written), (60, 80), "{name}");
        let out = run_with_stdin(dir.path(), &["-", "--width", "50%", "-o", "-"], &bytes);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        assert_eq!(png_size(&out.stdout), (60, 80), "{name} to stdout is a PNG");
    }
    // Into a folder, numbered as a stream's frames are: stdin names none.
    let out = run_with_stdin(
        dir.path(),
        &["-", "--width", "60", "-o", "pics/", "-q"],
        &png,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let written = std::fs::read(dir.path().join("pics/frame-00000.png")).unwrap();
    assert_eq!(png_size(&written), (60, 80));
    // One picture may take the options of one picture only.
    let out = run_with_stdin(
        dir.path(),
        &["-", "--width", "60", "-o", "dbg.png", "--debug-dir", "dbg"],
        &png,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("dbg/mesh-after.png").is_file());
    // Two PNGs are a stream: not one picture, and YUV4MPEG2 on stdout.
    let two = [png.clone(), png_bytes(120, 80)].concat();
    let out = run_with_stdin(dir.path(), &["-", "--width", "60", "-o", "two.png"], &two);
    assert_fails(&out, 2, &["two.png", "stream"]);
    let out = run_with_stdin(dir.path(), &["-", "--width", "60", "-o", "-", "-q"], &two);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout.starts_with(b"YUV4MPEG2 W60 H80"));
    assert_eq!(out.stdout.windows(6).filter(|w| w == b"FRAME\n").count(), 2);
    // An animated GIF is an animation: refused into one picture, naming stdin, and whole into
    // a GIF.
    let gif = animated_gif(120, 80, 3);
    let out = run_with_stdin(dir.path(), &["-", "--width", "60", "-o", "anim.png"], &gif);
    assert_fails(&out, 2, &["stdin", "3 frames", "anim.png"]);
    let out = run_with_stdin(
        dir.path(),
        &["-", "--width", "60", "-o", "anim.gif", "-q"],
        &gif,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let frames = image::codecs::gif::GifDecoder::new(std::io::Cursor::new(
        std::fs::read(dir.path().join("anim.gif")).unwrap(),
    ))
    .unwrap();
    use image::AnimationDecoder;
    assert_eq!(frames.into_frames().count(), 3);
    // What is no picture on stdin is named as such.
    let out = run_with_stdin(dir.path(), &["-", "--width", "60", "-o", "x.png"], b"hello");
    assert_fails(&out, 1, &["stdin", "not a picture"]);
    assert!(!dir.path().join("x.png").exists());
}

/// `--size 50%` scales both sides, as ImageMagick's `-resize 50%` does (issue 39).
#[test]
fn a_lone_percentage_scales_both_sides() {
    let (dir, _) = folder_with("in.png", &png_bytes(120, 80));
    for (size, want) in [("200%", (240, 160)), ("50%", (60, 40)), ("50%x", (60, 80))] {
        let out = run(dir.path(), &["in.png", "--size", size, "-o", "out.png"]);
        assert!(out.status.success(), "{size}: {}", stderr(&out));
        let img = image::open(dir.path().join("out.png")).unwrap();
        assert_eq!((img.width(), img.height()), want, "{size}");
    }
    let out = run(dir.path(), &["in.png", "--size", "0%", "-o", "out.png"]);
    assert_fails(&out, 2, &["0%", "out of range"]);
}

/// Watching a folder that is not there says so (issue 39), and a file is not a folder.
#[test]
fn watching_a_missing_folder_says_it_does_not_exist() {
    let (dir, _) = folder_with("in.png", &png_bytes(120, 80));
    let out = run(
        dir.path(),
        &["watch", "nowhere/", "-o", "out/", "--width", "60"],
    );
    assert_fails(&out, 1, &["nowhere/", "does not exist"]);
    let out = run(
        dir.path(),
        &["watch", "in.png", "-o", "out/", "--width", "60"],
    );
    assert_fails(&out, 1, &["in.png", "not a folder"]);
    assert_only(dir.path(), &["in.png"]);
}

/// `-o /dev/null` writes and discards, to time a run (issue 39): for one picture, a stream
/// and the statistics, and the device stays a device.
#[cfg(unix)]
#[test]
fn dev_null_takes_any_output() {
    use std::os::unix::fs::FileTypeExt;
    let (dir, _) = folder_with("in.png", &png_bytes(120, 80));
    std::fs::write(dir.path().join("anim.gif"), animated_gif(120, 80, 3)).unwrap();
    for args in [
        &["in.png", "--width", "60", "-o", "/dev/null"][..],
        &[
            "in.png",
            "--width",
            "60",
            "-o",
            "/dev/null",
            "--output-format",
            "png",
        ],
        &[
            "anim.gif",
            "--width",
            "60",
            "-o",
            "/dev/null",
            "--stats-json",
            "/dev/null",
        ],
        &[
            "anim.gif",
            "--width",
            "60",
            "-o",
            "/dev/null",
            "--output-format",
            "gif",
        ],
    ] {
        let out = run(dir.path(), args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        let meta = std::fs::metadata("/dev/null").unwrap();
        assert!(
            meta.file_type().is_char_device(),
            "/dev/null is still a device"
        );
    }
    assert_only(dir.path(), &["anim.gif", "in.png"]);
    // Nothing left beside it either.
    let litter: Vec<_> = std::fs::read_dir("/dev")
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with(".null."))
        .collect();
    assert!(litter.is_empty(), "{litter:?}");
}
