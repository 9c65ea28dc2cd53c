//! Streams through the command line, as a user pipes them: every input kind keeps frame order
//! and count, GIF delays and loop count survive GIF -> GIF, a short last raw frame is an error
//! after every complete frame was written, and a reader closing stdout early is a quiet
//! success. Inputs are drawn by each test; frames are identified by the colour of a band along
//! their top edge, which retargeting keeps in place.

mod common;
use common::{bin, listing, run, run_with_stdin, stderr};

use std::io::{Read, Write};
use std::path::Path;
use std::process::{Command, Output, Stdio};

const W: u32 = 160;
const H: u32 = 120;
const TW: u32 = 100;
const TH: u32 = 120;

/// Distinct band colours, one per frame.
fn colour(i: usize) -> [u8; 3] {
    const C: [[u8; 3]; 12] = [
        [214, 39, 40],
        [31, 119, 180],
        [44, 160, 44],
        [255, 127, 14],
        [148, 103, 189],
        [23, 190, 207],
        [140, 86, 75],
        [227, 119, 194],
        [188, 189, 34],
        [20, 20, 20],
        [90, 200, 250],
        [250, 220, 60],
    ];
    C[i % C.len()]
}

/// A chart-like frame: white, a grey axis, a blue disc that moves with `i`, and a 16-px band
/// of `colour(i)` along the top.
fn frame(i: usize) -> image::RgbaImage {
    let band = colour(i);
    image::RgbaImage::from_fn(W, H, |x, y| {
        let (dx, dy) = (x as i32 - 50 - 3 * i as i32, y as i32 - 70);
        let p = if y < 16 {
            band
        } else if dx * dx + dy * dy <= 12 * 12 {
            [40, 90, 200]
        } else if x == 8 || y + 8 == H {
            [90, 90, 90]
        } else {
            [255, 255, 255]
        };
        image::Rgba([p[0], p[1], p[2], 255])
    })
}

fn png(img: &image::RgbaImage) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// Which frame a retargeted picture is, from its band colour (within `tol` per channel):
/// the first colour down the middle that is not the white ground (the picture may be drawn
/// at one scale, below a band of its ground).
fn which(img: &image::RgbaImage, tol: i32) -> Option<usize> {
    // Two rows into the band: its first may blend with the ground.
    let x = img.width() / 2;
    let top = (0..img.height()).find(|&y| img.get_pixel(x, y).0[..3].iter().any(|&v| v < 200))?;
    let p = img.get_pixel(x, (top + 2).min(img.height() - 1)).0;
    (0..12).find(|&i| {
        let c = colour(i);
        (0..3).all(|k| (p[k] as i32 - c[k] as i32).abs() <= tol)
    })
}

fn assert_ok(o: &Output) {
    let e = stderr(o);
    assert!(o.status.success(), "exit {:?}: {e}", o.status.code());
    assert!(!e.contains("panicked"), "{e}");
}

/// Splits raw RGBA output into frames and identifies each.
fn raw_frames(bytes: &[u8], tol: i32) -> Vec<Option<usize>> {
    let n = (TW * TH * 4) as usize;
    assert_eq!(
        bytes.len() % n,
        0,
        "whole frames only: {} bytes",
        bytes.len()
    );
    bytes
        .chunks_exact(n)
        .map(|c| {
            which(
                &image::RgbaImage::from_raw(TW, TH, c.to_vec()).unwrap(),
                tol,
            )
        })
        .collect()
}

fn expected(n: usize) -> Vec<Option<usize>> {
    (0..n).map(|i| Some(i % 12)).collect()
}

/// Writes an animated GIF of `n` frames with the given delays (centiseconds) and loop count.
fn write_gif(path: &Path, n: usize, delays: &[u16], repeat: gif::Repeat) {
    let mut file = std::fs::File::create(path).unwrap();
    let mut enc = gif::Encoder::new(&mut file, W as u16, H as u16, &[]).unwrap();
    enc.set_repeat(repeat).unwrap();
    for i in 0..n {
        let mut px = frame(i).into_raw();
        let mut f = gif::Frame::from_rgba_speed(W as u16, H as u16, &mut px, 10);
        f.delay = delays[i % delays.len()];
        enc.write_frame(&f).unwrap();
    }
}

/// Reads a GIF back as the gif crate composites it: (frames, delays, loop count).
fn read_gif(path: &Path) -> (Vec<image::RgbaImage>, Vec<u16>, gif::Repeat) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(std::fs::File::open(path).unwrap()).unwrap();
    let (w, h) = (d.width() as u32, d.height() as u32);
    let mut canvas = image::RgbaImage::new(w, h);
    let (mut frames, mut delays) = (Vec::new(), Vec::new());
    while let Some(f) = d.read_next_frame().unwrap() {
        // Our writer only uses disposal Keep on opaque content: draw opaque pixels.
        for y in 0..f.height as u32 {
            for x in 0..f.width as u32 {
                let i = ((y * f.width as u32 + x) * 4) as usize;
                let p = &f.buffer[i..i + 4];
                if p[3] != 0 {
                    canvas.put_pixel(
                        x + f.left as u32,
                        y + f.top as u32,
                        image::Rgba([p[0], p[1], p[2], p[3]]),
                    );
                }
            }
        }
        assert_eq!(f.dispose, gif::DisposalMethod::Keep);
        frames.push(canvas.clone());
        delays.push(f.delay);
    }
    let repeat = d.repeat();
    (frames, delays, repeat)
}

#[test]
fn gif_to_gif_keeps_order_delays_and_loop_count() {
    let dir = tempfile::tempdir().unwrap();
    let delays = [3u16, 5, 7, 12, 20, 4];
    write_gif(
        &dir.path().join("in.gif"),
        14,
        &delays,
        gif::Repeat::Finite(3),
    );
    let out = run(
        dir.path(),
        &["in.gif", "--size", "100x120", "-o", "out.gif", "-q"],
    );
    assert_ok(&out);
    let (frames, got_delays, repeat) = read_gif(&dir.path().join("out.gif"));
    assert_eq!(repeat, gif::Repeat::Finite(3));
    assert_eq!(frames.len(), 14);
    let want: Vec<u16> = (0..14).map(|i| delays[i % delays.len()]).collect();
    assert_eq!(got_delays, want);
    let ids: Vec<_> = frames.iter().map(|f| which(f, 0)).collect();
    assert_eq!(ids, expected(14));
    assert!(frames.iter().all(|f| f.dimensions() == (100, 120)));
    assert_eq!(listing(dir.path()), ["in.gif", "out.gif"]);

    // An infinitely looping GIF stays infinite; --fps sets the delays.
    write_gif(&dir.path().join("loop.gif"), 3, &[9], gif::Repeat::Infinite);
    let out = run(
        dir.path(),
        &[
            "loop.gif",
            "--size",
            "100x120",
            "-o",
            "loop-out.gif",
            "--fps",
            "25",
        ],
    );
    assert_ok(&out);
    let (frames, got_delays, repeat) = read_gif(&dir.path().join("loop-out.gif"));
    assert_eq!((frames.len(), repeat), (3, gif::Repeat::Infinite));
    assert_eq!(got_delays, [4, 4, 4]);
    assert!(
        stderr(&out).contains("3 frames"),
        "summary line: {}",
        stderr(&out)
    );
}

#[test]
fn folder_in_natural_order_to_folder_with_the_same_names() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("frames");
    std::fs::create_dir(&input).unwrap();
    // Natural order: frame1, frame2, frame9, frame10, frame11; the colour index follows it.
    for (k, n) in [10, 1, 11, 2, 9].into_iter().enumerate() {
        let rank = [1, 2, 9, 10, 11].iter().position(|&m| m == n).unwrap();
        let _ = k;
        std::fs::write(input.join(format!("frame{n}.png")), png(&frame(rank))).unwrap();
    }
    std::fs::write(input.join("notes.txt"), b"not a frame").unwrap();
    std::fs::write(input.join(".hidden.png"), png(&frame(7))).unwrap();
    let out = run(
        dir.path(),
        &[
            "frames",
            "--size",
            "100x120",
            "-o",
            "out/",
            "--stats-json",
            "stats.json",
        ],
    );
    assert_ok(&out);
    let names = [
        "frame1.png",
        "frame2.png",
        "frame9.png",
        "frame10.png",
        "frame11.png",
    ];
    let mut sorted = names.to_vec();
    sorted.sort();
    assert_eq!(listing(&dir.path().join("out")), sorted);
    for (rank, name) in names.iter().enumerate() {
        let img = image::open(dir.path().join("out").join(name))
            .unwrap()
            .into_rgba8();
        assert_eq!(img.dimensions(), (TW, TH));
        assert_eq!(which(&img, 0), Some(rank), "{name}");
    }
    let json = std::fs::read_to_string(dir.path().join("stats.json")).unwrap();
    let order: Vec<usize> = names
        .iter()
        .map(|n| json.find(&format!("\"{n}\"")).unwrap())
        .collect();
    assert!(
        order.windows(2).all(|w| w[0] < w[1]),
        "stats in natural order: {json}"
    );
    assert_eq!(json.matches("\"frame_index\"").count(), 5);
    assert!(json.contains("\"summary\"") && json.contains("\"decision\""));
}

fn raw_stream(n: usize, rgb: bool) -> Vec<u8> {
    let mut v = Vec::new();
    for i in 0..n {
        for p in frame(i).pixels() {
            v.extend_from_slice(if rgb { &p.0[..3] } else { &p.0[..] });
        }
    }
    v
}

#[test]
fn raw_rgba_and_rgb24_from_stdin_in_order() {
    let dir = tempfile::tempdir().unwrap();
    for (fmt, rgb) in [("rgba", false), ("rgb24", true)] {
        let out = run_with_stdin(
            dir.path(),
            &[
                "-",
                "--input-format",
                fmt,
                "--input-size",
                "160x120",
                "--size",
                "100x120",
                "-o",
                "-",
                "--output-format",
                "rgba",
                "-q",
            ],
            raw_stream(13, rgb),
        );
        assert_ok(&out);
        assert_eq!(raw_frames(&out.stdout, 0), expected(13), "{fmt}");
    }
}

#[test]
fn short_last_raw_frame_fails_after_writing_every_complete_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mut input = raw_stream(5, false);
    input.extend_from_slice(&[1, 2, 3, 4, 5, 6, 7]);
    let out = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--input-format",
            "rgba",
            "--input-size",
            "160x120",
            "--size",
            "100x120",
            "-o",
            "-",
            "--output-format",
            "rgba",
        ],
        input,
    );
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("incomplete") && err.contains("frame 5"),
        "{err}"
    );
    assert_eq!(out.stdout.len(), 5 * (TW * TH * 4) as usize);
    assert_eq!(raw_frames(&out.stdout, 0), expected(5));
}

#[test]
fn raw_stdin_without_a_format_is_explained() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_with_stdin(
        dir.path(),
        &["-", "--size", "100x120", "-o", "-"],
        raw_stream(1, false),
    );
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.contains("--input-format") && err.contains("--input-size"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

/// YUV4MPEG2 of the test frames, BT.601 limited range, 4:2:0 (2x2 means) or 4:4:4.
fn y4m_stream(n: usize, c444: bool) -> Vec<u8> {
    let mut v = format!(
        "YUV4MPEG2 W{W} H{H} F25:1 Ip A1:1 {}\n",
        if c444 {
            "C444"
        } else {
            "C420jpeg XYSCSS=420JPEG"
        }
    )
    .into_bytes();
    let yuv = |p: [u8; 4]| {
        let (r, g, b) = (p[0] as f32, p[1] as f32, p[2] as f32);
        (
            16.0 + 0.257 * r + 0.504 * g + 0.098 * b,
            128.0 - 0.148 * r - 0.291 * g + 0.439 * b,
            128.0 + 0.439 * r - 0.368 * g - 0.071 * b,
        )
    };
    for i in 0..n {
        let img = frame(i);
        v.extend_from_slice(if i % 2 == 0 {
            b"FRAME\n"
        } else {
            b"FRAME Ixyz\n"
        });
        v.extend(img.pixels().map(|p| yuv(p.0).0.round() as u8));
        let (s, cw, ch) = if c444 { (1, W, H) } else { (2, W / 2, H / 2) };
        for plane in [1, 2] {
            for cy in 0..ch {
                for cx in 0..cw {
                    let mut sum = 0.0;
                    for yy in 0..s {
                        for xx in 0..s {
                            let c = yuv(img.get_pixel(cx * s + xx, cy * s + yy).0);
                            sum += if plane == 1 { c.1 } else { c.2 };
                        }
                    }
                    v.push((sum / (s * s) as f32).round() as u8);
                }
            }
        }
    }
    v
}

#[test]
fn y4m_420_and_444_from_stdin_in_order() {
    let dir = tempfile::tempdir().unwrap();
    for c444 in [false, true] {
        let out = run_with_stdin(
            dir.path(),
            &[
                "-",
                "--size",
                "100x120",
                "-o",
                "-",
                "--output-format",
                "rgba",
                "-q",
            ],
            y4m_stream(11, c444),
        );
        assert_ok(&out);
        assert_eq!(raw_frames(&out.stdout, 8), expected(11), "444: {c444}");
    }
}

#[test]
fn y4m_out_has_a_header_from_the_target_and_the_input_timing() {
    let dir = tempfile::tempdir().unwrap();
    write_gif(&dir.path().join("in.gif"), 4, &[5], gif::Repeat::Infinite);
    let out = bin()
        .args(["in.gif", "--size", "100x120", "-o", "-", "-q"])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .output()
        .unwrap();
    assert_ok(&out);
    let header = b"YUV4MPEG2 W100 H120 F20:1 ";
    assert!(
        out.stdout.starts_with(header),
        "{:?}",
        String::from_utf8_lossy(&out.stdout[..40])
    );
    let frame_len = 6 + 100 * 120 + 2 * 50 * 60;
    let header_len = out.stdout.iter().position(|&b| b == b'\n').unwrap() + 1;
    assert_eq!(out.stdout.len(), header_len + 4 * frame_len);
    // Read back through our own reader: order kept.
    let back = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--size",
            "100x120",
            "-o",
            "-",
            "--output-format",
            "rgba",
            "-q",
        ],
        out.stdout,
    );
    assert_ok(&back);
    assert_eq!(raw_frames(&back.stdout, 10), expected(4));
}

#[test]
fn png_stream_from_stdin_to_a_png_sequence() {
    let dir = tempfile::tempdir().unwrap();
    let input: Vec<u8> = (0..12).flat_map(|i| png(&frame(i))).collect();
    let out = run_with_stdin(
        dir.path(),
        &["-", "--size", "100x120", "-o", "seq/", "-q"],
        input,
    );
    assert_ok(&out);
    let names = listing(&dir.path().join("seq"));
    let want: Vec<String> = (0..12).map(|i| format!("frame-{i:05}.png")).collect();
    assert_eq!(names, want);
    for (i, n) in names.iter().enumerate() {
        let img = image::open(dir.path().join("seq").join(n))
            .unwrap()
            .into_rgba8();
        assert_eq!(which(&img, 0), Some(i));
    }
    // And out again as a PNG stream on stdout, split by the same reader.
    let out = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--size",
            "100x120",
            "-o",
            "-",
            "--output-format",
            "png",
            "-q",
        ],
        (0..3).flat_map(|i| png(&frame(i))).collect::<Vec<u8>>(),
    );
    assert_ok(&out);
    let back = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--size",
            "100x120",
            "-o",
            "-",
            "--output-format",
            "rgba",
            "-q",
        ],
        out.stdout,
    );
    assert_ok(&back);
    assert_eq!(raw_frames(&back.stdout, 0), expected(3));
}

#[test]
fn reader_closing_stdout_early_is_a_quiet_success() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = bin()
        .args([
            "-",
            "--input-format",
            "rgb24",
            "--input-size",
            "160x120",
            "--size",
            "100x120",
            "-o",
            "-",
            "--output-format",
            "rgba",
        ])
        .current_dir(dir.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let feeder = std::thread::spawn(move || {
        for _ in 0..20 {
            if stdin.write_all(&raw_stream(12, true)).is_err() {
                break; // the binary stopped reading: expected
            }
        }
    });
    let mut stdout = child.stdout.take().unwrap();
    let mut first = vec![0u8; 1000];
    stdout.read_exact(&mut first).unwrap();
    drop(stdout); // `| head -c 1000`
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let status = child.wait().unwrap();
    feeder.join().unwrap();
    assert_eq!(status.code(), Some(0), "stderr: {err}");
    assert!(err.is_empty(), "quiet: {err}");
}

#[test]
fn still_in_gif_out_and_one_frame_gif_in() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("one.png"), png(&frame(4))).unwrap();
    let out = run(
        dir.path(),
        &["one.png", "--size", "100x120", "-o", "one.gif", "-q"],
    );
    assert_ok(&out);
    let (frames, _, _) = read_gif(&dir.path().join("one.gif"));
    assert_eq!(frames.len(), 1);
    assert_eq!(which(&frames[0], 0), Some(4));
    // A GIF with one frame is one picture; named .png it is still recognised, and into a
    // folder it keeps its name.
    write_gif(
        &dir.path().join("single.png"),
        1,
        &[10],
        gif::Repeat::Finite(0),
    );
    let out = run(
        dir.path(),
        &["single.png", "--size", "100x120", "-o", "seq/", "-q"],
    );
    assert_ok(&out);
    assert_eq!(listing(&dir.path().join("seq")), ["single.png"]);
}

#[test]
fn bad_stream_inputs_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    // A frame of another size in a folder.
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    std::fs::write(frames.join("a1.png"), png(&frame(0))).unwrap();
    std::fs::write(frames.join("a2.png"), png(&image::RgbaImage::new(50, 50))).unwrap();
    let out = run(
        dir.path(),
        &["frames", "--size", "100x120", "-o", "out.gif"],
    );
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("a2.png") && err.contains("same size"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");

    // A GIF whose second frame is cut off.
    write_gif(&dir.path().join("cut.gif"), 3, &[5], gif::Repeat::Infinite);
    let bytes = std::fs::read(dir.path().join("cut.gif")).unwrap();
    std::fs::write(dir.path().join("cut.gif"), &bytes[..bytes.len() * 2 / 3]).unwrap();
    let out = run(
        dir.path(),
        &["cut.gif", "--size", "100x120", "-o", "cut-out/"],
    );
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("cut.gif") && err.contains("frame"), "{err}");
    assert!(!err.contains("panicked"));

    // No temporary file is left anywhere.
    for d in [dir.path().to_path_buf(), dir.path().join("cut-out")] {
        if d.is_dir() {
            assert!(
                listing(&d).iter().all(|n| !n.ends_with(".tmp")),
                "{:?}",
                listing(&d)
            );
        }
    }
}

#[test]
fn ctrl_c_finishes_the_gif_and_exits_130() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().unwrap();
    let mut child = bin()
        .args([
            "-",
            "--input-format",
            "rgb24",
            "--input-size",
            "160x120",
            "--size",
            "100x120",
            "-o",
            "live.gif",
            "--stats",
        ])
        .current_dir(dir.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // An endless live stream: the feeder stops only when the binary stops reading.
    let mut stdin = child.stdin.take().unwrap();
    let feeder = std::thread::spawn(move || {
        let frames = raw_stream(12, true);
        while stdin.write_all(&frames).is_ok() {}
    });
    let mut lines = std::io::BufReader::new(child.stderr.take().unwrap()).lines();
    let mut seen = 0;
    while seen < 3 {
        let line = lines.next().expect("stderr ended early").unwrap();
        seen += line.starts_with("frame ") as usize;
    }
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let rest: Vec<String> = lines.map_while(Result::ok).collect();
    let status = child.wait().unwrap();
    feeder.join().unwrap();
    assert_eq!(status.code(), Some(130), "{rest:?}");
    assert!(!rest.iter().any(|l| l.contains("panicked")), "{rest:?}");
    let (frames, _, _) = read_gif(&dir.path().join("live.gif"));
    assert!(frames.len() >= 3, "{} frames", frames.len());
    let ids: Vec<_> = frames.iter().map(|f| which(f, 0)).collect();
    assert_eq!(ids, expected(frames.len()), "whole frames, in order");
    assert_eq!(listing(dir.path()), ["live.gif"], "no temporary file left");
}

/// The reuse policy's options reach the stream: a static stream reuses by default, is rebuilt
/// every frame with --no-reuse (same pixels either way: the content never changed), and a
/// threshold out of range is refused naming it.
#[test]
fn reuse_options_steer_the_stream() {
    let dir = tempfile::tempdir().unwrap();
    let one: Vec<u8> = frame(0).pixels().flat_map(|p| p.0).collect();
    let input: Vec<u8> = one.iter().copied().cycle().take(one.len() * 6).collect();
    let decisions = |extra: &[&str]| {
        let json = dir.path().join("stats.json");
        let mut args = vec![
            "-",
            "--input-format",
            "rgba",
            "--input-size",
            "160x120",
            "--size",
            "100x120",
            "-o",
            "-",
            "--output-format",
            "rgba",
            "-q",
            "--stats-json",
        ];
        args.push(json.to_str().unwrap());
        args.extend_from_slice(extra);
        let out = run_with_stdin(dir.path(), &args, input.clone());
        assert_ok(&out);
        let text = std::fs::read_to_string(&json).unwrap();
        let d: Vec<String> = text
            .split("\"decision\": \"")
            .skip(1)
            .map(|s| s.split('"').next().unwrap().to_string())
            .collect();
        (d, out.stdout)
    };
    let (reused, a) = decisions(&[]);
    assert_eq!(reused[0], "rebuild");
    assert!(reused[1..].iter().all(|d| d == "reuse"), "{reused:?}");
    let (rebuilt, b) = decisions(&["--no-reuse"]);
    assert_eq!(rebuilt.len(), 6);
    assert!(rebuilt.iter().all(|d| d == "rebuild"), "{rebuilt:?}");
    assert_eq!(a, b, "reuse must not change a static stream's pixels");

    let out = run_with_stdin(
        dir.path(),
        &[
            "-",
            "--input-format",
            "rgba",
            "--input-size",
            "160x120",
            "--size",
            "100x120",
            "-o",
            "-",
            "--output-format",
            "rgba",
            "--tile-threshold",
            "1.5",
        ],
        input.clone(),
    );
    assert_eq!(out.status.code(), Some(2), "a usage error");
    let e = stderr(&out);
    assert!(
        e.contains("--tile-threshold") && e.contains("1.5") && e.lines().count() == 1,
        "{e}"
    );
}
