//! The conventions a user of image tools expects, as a user met them: one picture to stdout is
//! a PNG, one picture into a folder keeps its name, an animation is never cut to its first
//! frame unasked, sizes may be percentages or one side, WebP can be written, usage errors exit
//! 2, an empty pipe says what may have gone wrong upstream, GIFs with an application's own
//! extension blocks are read, and the help says what is true.

mod common;

use common::{assert_fails, bin, listing, run_with_stdin, stderr};

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs the binary in `dir` with `args`, stdin empty.
fn run(dir: &Path, args: &[&str]) -> Output {
    run_with_stdin(dir, args, Vec::new())
}

fn assert_ok(out: &Output) {
    assert_eq!(out.status.code(), Some(0), "stderr: {}", stderr(out));
}

/// A chart-like picture: white, a blue disc, a red bar, a grey axis.
fn chart(w: u32, h: u32) -> image::RgbImage {
    image::RgbImage::from_fn(w, h, |x, y| {
        let (dx, dy) = (x as i32 - w as i32 / 4, y as i32 - h as i32 / 2);
        if dx * dx + dy * dy <= 10 * 10 {
            image::Rgb([40, 90, 200])
        } else if (w * 3 / 5..w * 3 / 5 + 20).contains(&x) && (h / 4..h - 12).contains(&y) {
            image::Rgb([210, 50, 40])
        } else if y + 10 == h || x == 10 {
            image::Rgb([90, 90, 90])
        } else {
            image::Rgb([255, 255, 255])
        }
    })
}

fn encode(img: &image::RgbImage, format: image::ImageFormat) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, format).unwrap();
    out.into_inner()
}

fn png_bytes(w: u32, h: u32) -> Vec<u8> {
    encode(&chart(w, h), image::ImageFormat::Png)
}

/// A temporary folder holding `in.png`, a 120x80 chart.
fn folder_with_png() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("in.png");
    std::fs::write(&path, png_bytes(120, 80)).unwrap();
    (dir, path)
}

/// A GIF of `n` 120x80 frames (the chart, its bar moving), looping forever.
fn gif_bytes(n: usize) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut out, 120, 80, &[]).unwrap();
        enc.set_repeat(gif::Repeat::Infinite).unwrap();
        for i in 0..n {
            let img = image::DynamicImage::ImageRgb8(chart(120 + 4 * i as u32, 80))
                .crop_imm(0, 0, 120, 80)
                .to_rgba8();
            let mut px = img.into_raw();
            let mut f = gif::Frame::from_rgba_speed(120, 80, &mut px, 10);
            f.delay = 10;
            enc.write_frame(&f).unwrap();
        }
    }
    out
}

fn size_of(bytes: &[u8]) -> (u32, u32) {
    let img = image::load_from_memory(bytes).expect("a picture");
    (img.width(), img.height())
}

fn size_of_file(path: &Path) -> (u32, u32) {
    size_of(&std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
}

// ---------------------------------------------------------------------------------------------
// 1. One picture to stdout is a PNG; a stream stays YUV4MPEG2.

#[test]
fn one_picture_to_stdout_is_a_png() {
    let (dir, _) = folder_with_png();
    let out = run(dir.path(), &["in.png", "--width", "60", "-o", "-"]);
    assert_ok(&out);
    assert!(out.stdout.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    assert_eq!(size_of(&out.stdout), (60, 80));
    assert!(!stderr(&out).contains("frame"), "{}", stderr(&out));
    // A stream to stdout is still YUV4MPEG2 by default.
    std::fs::write(dir.path().join("anim.gif"), gif_bytes(3)).unwrap();
    let out = run(dir.path(), &["anim.gif", "--width", "60", "-o", "-", "-q"]);
    assert_ok(&out);
    assert!(
        out.stdout.starts_with(b"YUV4MPEG2 W60 H80"),
        "not YUV4MPEG2"
    );
}

// 2. One picture into a folder keeps its name; from stdin it gets a default one.

#[test]
fn one_picture_into_a_folder_keeps_its_name() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("chart.jpg"),
        encode(&chart(120, 80), image::ImageFormat::Jpeg),
    )
    .unwrap();
    let out = run(dir.path(), &["chart.jpg", "--width", "60", "-o", "od/"]);
    assert_ok(&out);
    assert_eq!(listing(&dir.path().join("od")), ["chart.png"]);
    assert_eq!(size_of_file(&dir.path().join("od/chart.png")), (60, 80));
    // Into an existing folder too (no trailing /).
    let out = run(dir.path(), &["chart.jpg", "--width", "50", "-o", "od"]);
    assert_ok(&out);
    assert_eq!(size_of_file(&dir.path().join("od/chart.png")), (50, 80));
    // From stdin there is no name: frames are numbered.
    let out = run_with_stdin(
        dir.path(),
        &["-", "--width", "60", "-o", "piped/", "-q"],
        png_bytes(120, 80),
    );
    assert_ok(&out);
    assert_eq!(listing(&dir.path().join("piped")), ["frame-00000.png"]);
}

// 3. An animation is not cut to one picture unasked, whether a GIF or a folder.

#[test]
fn animated_gif_into_one_picture_is_refused_like_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("anim.gif"), gif_bytes(3)).unwrap();
    let out = run(dir.path(), &["anim.gif", "--width", "60", "-o", "x.png"]);
    assert_fails(&out, 2, &["anim.gif", "3 frames", ".gif", "folder"]);
    std::fs::create_dir(dir.path().join("frames")).unwrap();
    std::fs::write(dir.path().join("frames/a.png"), png_bytes(120, 80)).unwrap();
    let out = run(dir.path(), &["frames", "--width", "60", "-o", "x.png"]);
    assert_fails(&out, 2, &[".gif", "folder"]);
    assert_eq!(listing(dir.path()), ["anim.gif", "frames"]);
    // A GIF of one frame is one picture.
    std::fs::write(dir.path().join("one.gif"), gif_bytes(1)).unwrap();
    let out = run(dir.path(), &["one.gif", "--width", "60", "-o", "one.png"]);
    assert_ok(&out);
    assert_eq!(size_of_file(&dir.path().join("one.png")), (60, 80));
    // And the help says so.
    let help = String::from_utf8(bin().arg("--help").output().unwrap().stdout).unwrap();
    let flat = help.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        flat.contains("An animated GIF or a folder of frames needs a .gif, a folder or -"),
        "{help}"
    );
}

// 4. Percentages and one side.

#[test]
fn sizes_as_percentages_or_one_side() {
    let (dir, _) = folder_with_png();
    for (args, want) in [
        (&["--width", "50%"][..], (60, 80)),
        (&["--height", "50%"][..], (120, 40)),
        (&["--size", "50%x100%"][..], (60, 80)),
        (&["--width", "25%", "--height", "60"][..], (30, 60)),
        (&["-s", "100x"][..], (100, 80)),
        (&["-s", "x30"][..], (120, 30)),
    ] {
        let mut all = vec!["in.png", "-o", "out.png"];
        all.extend_from_slice(args);
        let out = run(dir.path(), &all);
        assert_ok(&out);
        assert_eq!(size_of_file(&dir.path().join("out.png")), want, "{args:?}");
    }
    // Percentages of each input: a stream's frames.
    std::fs::write(dir.path().join("anim.gif"), gif_bytes(2)).unwrap();
    let out = run(
        dir.path(),
        &["anim.gif", "--width", "50%", "-o", "seq/", "-q"],
    );
    assert_ok(&out);
    assert_eq!(
        size_of_file(&dir.path().join("seq/frame-00001.png")),
        (60, 80)
    );
}

#[test]
fn bad_percentages_and_sides_are_clear_usage_errors() {
    let (dir, _) = folder_with_png();
    for (opt, value, words) in [
        ("--width", "0%", &["'0%'", "above 0%"][..]),
        ("--width", "-5%", &["'-5%'", "above 0%"][..]),
        ("--height", "half%", &["'half%'", "not a percentage"][..]),
        ("--width", "1e9%", &["'1e9%'", "out of range"][..]),
        ("--size", "x", &["'x'", "neither side"][..]),
        ("--size", "ax", &["'a'", "not a whole number"][..]),
        ("--width", "ten", &["'ten'", "not a whole number"][..]),
    ] {
        let out = run(dir.path(), &["in.png", "-o", "out.png", opt, value]);
        assert_fails(&out, 2, words);
    }
    // Within range as a percentage, too large once resolved: named, exit 2.
    let out = run(
        dir.path(),
        &["in.png", "-o", "out.png", "--width", "20000%"],
    );
    assert_fails(&out, 2, &["20000% of the input's width (120 px)", "16384"]);
    assert_eq!(listing(dir.path()), ["in.png"]);
}

// 5. WebP out.

#[test]
fn webp_output_is_lossless_webp() {
    let (dir, _) = folder_with_png();
    let out = run(dir.path(), &["in.png", "--width", "60", "-o", "x.webp"]);
    assert_ok(&out);
    let webp = std::fs::read(dir.path().join("x.webp")).unwrap();
    assert!(webp.starts_with(b"RIFF") && &webp[8..12] == b"WEBP");
    let out = run(dir.path(), &["in.png", "--width", "60", "-o", "x.png"]);
    assert_ok(&out);
    let a = image::load_from_memory(&webp).unwrap().to_rgba8();
    let b = image::open(dir.path().join("x.png")).unwrap().to_rgba8();
    assert_eq!(a.dimensions(), (60, 80));
    assert!(a == b, "lossless: the same pixels as the PNG");
}

// 6. Usage errors exit 2; failures of a run exit 1.

#[test]
fn invalid_option_values_and_combinations_exit_2() {
    let (dir, _) = folder_with_png();
    std::fs::write(dir.path().join("anim.gif"), gif_bytes(2)).unwrap();
    for (args, words) in [
        (
            &["in.png", "--width", "60", "--alpha", "2", "-o", "o.png"][..],
            &["alpha", "4 to 200"][..],
        ),
        (
            &[
                "in.png",
                "--width",
                "60",
                "--tile-threshold",
                "2",
                "-o",
                "o.png",
            ][..],
            &["--tile-threshold", "0 to 1"][..],
        ),
        (
            &[
                "in.png",
                "--width",
                "60",
                "--reuse-tile",
                "2",
                "-o",
                "o.gif",
            ][..],
            &["--reuse-tile", "4 to 1024"][..],
        ),
        (
            &[
                "in.png",
                "--width",
                "60",
                "--rebuild-fraction",
                "1.5",
                "-o",
                "o.gif",
            ][..],
            &["--rebuild-fraction"][..],
        ),
        (
            &["in.png", "--width", "60", "-o", "c.bmp"][..],
            &["c.bmp", "unsupported output format"][..],
        ),
        (
            &[
                "anim.gif",
                "--width",
                "60",
                "--debug-dir",
                "dbg",
                "-o",
                "o.gif",
            ][..],
            &["--debug-dir", "one picture"][..],
        ),
        (
            &[
                "in.png",
                "--width",
                "60",
                "--output-format",
                "png",
                "-o",
                "o.jpg",
            ][..],
            &["o.jpg", "JPEG", "PNG"][..],
        ),
        (
            &[
                "anim.gif", "--width", "60", "--method", "seam", "-o", "o.gif",
            ][..],
            &["--method seam"][..],
        ),
        (
            &[
                "-",
                "--width",
                "60",
                "--input-format",
                "rgba",
                "-o",
                "o.gif",
            ][..],
            &["--input-size"][..],
        ),
    ] {
        let out = run(dir.path(), args);
        assert_fails(&out, 2, words);
    }
    assert_eq!(listing(dir.path()), ["anim.gif", "in.png"]);
    // A run that fails on its input is no usage error.
    std::fs::write(dir.path().join("bad.png"), b"\x89PNG\r\n\x1a\nbroken").unwrap();
    let out = run(dir.path(), &["bad.png", "--width", "60", "-o", "o.png"]);
    assert_fails(&out, 1, &["bad.png"]);
    let out = run(dir.path(), &["gone.png", "--width", "60", "-o", "o.png"]);
    assert_fails(&out, 1, &["gone.png"]);
}

// 7 and 8. Pipes: the help's examples work as given; an empty pipe says what may be wrong.

#[test]
fn empty_stdin_says_what_may_have_gone_wrong_upstream() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &["-", "--width", "60", "-o", "o.gif"]);
    assert_fails(
        &out,
        1,
        &[
            "nothing arrived on stdin",
            "did the program writing to the pipe fail",
            "-pix_fmt yuv420p",
        ],
    );
    assert_eq!(listing(dir.path()), Vec::<String>::new());
}

#[test]
fn help_pipe_examples_give_pixel_format_and_frame_rate() {
    let help = String::from_utf8(bin().arg("--help").output().unwrap().stdout).unwrap();
    assert!(
        help.contains(
            "ffmpeg -i streams/scatter-map.gif -f yuv4mpegpipe -pix_fmt yuv420p - \\\n      \
             | vizretarget -"
        ),
        "{help}"
    );
    let raw = help
        .lines()
        .skip_while(|l| !l.contains("ffmpeg -i streams/dashboard.gif -f rawvideo"))
        .take(2)
        .collect::<String>();
    assert!(
        raw.contains("--fps"),
        "the raw example keeps the frame rate: {raw}"
    );
}

// 9. Watch: each snapshot keeps its own other side; the closing line speaks of snapshots.

#[test]
fn watch_takes_each_snapshots_own_size_and_reports_time_per_snapshot() {
    let root = tempfile::tempdir().unwrap();
    let (inbox, outbox) = (root.path().join("in"), root.path().join("out"));
    std::fs::create_dir(&inbox).unwrap();
    std::fs::write(inbox.join("a.png"), common::snapshot(1)).unwrap(); // 96x64
    std::fs::write(inbox.join("b.png"), png_bytes(120, 80)).unwrap();
    std::fs::write(inbox.join("c.png"), png_bytes(100, 50)).unwrap();
    let child = bin()
        .arg("watch")
        .arg(&inbox)
        .arg("-o")
        .arg(&outbox)
        .args(["--width", "50%"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while (!outbox.is_dir() || listing(&outbox).len() < 3)
        && start.elapsed() < Duration::from_secs(30)
    {
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert_eq!(listing(&outbox), ["a.png", "b.png", "c.png"], "{err}");
    assert_eq!(size_of_file(&outbox.join("a.png")), (48, 64), "{err}");
    assert_eq!(size_of_file(&outbox.join("b.png")), (60, 80), "{err}");
    assert_eq!(size_of_file(&outbox.join("c.png")), (50, 50), "{err}");
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(
        last.contains("3 snapshots retargeted")
            && last.contains("ms mean")
            && last.contains("ms max"),
        "{err}"
    );
    assert!(!last.contains("fps"), "{err}");
}

// 10 and 12. The help says what is true of folders and of --debug-dir.

#[test]
fn help_says_which_folders_are_created_and_what_debug_dir_writes() {
    let help = String::from_utf8(bin().arg("--help").output().unwrap().stdout).unwrap();
    let flat = help.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(!flat.contains("the folder must exist"), "{help}");
    assert!(
        flat.contains("a folder output ending in / is created if missing"),
        "{help}"
    );
    assert!(
        flat.contains("two pictures of the mesh")
            && flat.contains("mesh-before.png")
            && flat.contains("mesh-after.png"),
        "{help}"
    );
    // And it is so: the folder ending in / is created, the file's folder is not.
    let (dir, _) = folder_with_png();
    let out = run(dir.path(), &["in.png", "--width", "60", "-o", "new/"]);
    assert_ok(&out);
    let out = run(dir.path(), &["in.png", "--width", "60", "-o", "none/x.png"]);
    assert_fails(&out, 1, &["none", "does not exist"]);
    let out = run(
        dir.path(),
        &[
            "in.png",
            "--width",
            "60",
            "-o",
            "x.png",
            "--debug-dir",
            "dbg",
        ],
    );
    assert_ok(&out);
    for name in ["mesh-before.png", "mesh-after.png"] {
        assert!(dir.path().join("dbg").join(name).is_file(), "{name}");
    }
}

// 11. The memory limit's hint says what is needed.

#[test]
fn memory_limit_hint_suggests_what_is_needed() {
    let (dir, _) = folder_with_png();
    let with_limit = |limit: &str| {
        let args = [
            "in.png",
            "--width",
            "60",
            "--memory-limit",
            limit,
            "-o",
            "o.png",
        ];
        run(dir.path(), &args)
    };
    let out = with_limit("1K");
    assert_fails(&out, 1, &["needs about", "raise it with --memory-limit"]);
    let err = stderr(&out);
    assert!(!err.contains("e.g. 4G"), "{err}");
    let mut needs = err.split("needs about ").nth(1).unwrap().split(' ');
    let needed: f64 = needs.next().unwrap().parse().unwrap();
    let mib = match needs.next().unwrap().trim_end_matches(',') {
        "MiB" => needed,
        "GiB" => needed * 1024.0,
        "KiB" => needed / 1024.0,
        u => panic!("{u}: {err}"),
    };
    let value = err
        .split("--memory-limit ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap();
    let suggested: f64 = match value.split_at(value.len() - 1) {
        (n, "M") => n.parse().unwrap(),
        (n, "G") => n.parse::<f64>().unwrap() * 1024.0,
        _ => panic!("{value}: {err}"),
    };
    assert!(suggested >= mib && suggested < mib + 1.5, "{err}");
    // And it is enough.
    assert_ok(&with_limit(value));
}

// 13. GIFs with an extension block of an unknown type, as browsers show them.

/// `gif` with an extension block of label 0x99 (unknown to decoders) and a small sub-block
/// put right after the global colour table, before any image descriptor.
fn with_unknown_extension(gif: &[u8]) -> Vec<u8> {
    let packed = gif[10];
    let table = if packed & 0x80 != 0 {
        3 << ((packed & 7) + 1)
    } else {
        0
    };
    let at = 13 + table;
    let mut out = gif[..at].to_vec();
    out.extend_from_slice(&[0x21, 0x99, 3, b'a', b'b', b'c', 0]);
    out.extend_from_slice(&gif[at..]);
    out
}

#[test]
fn gif_with_an_unknown_extension_block_is_read() {
    let dir = tempfile::tempdir().unwrap();
    // With a global colour table, so the block lands after it.
    let mut plain = Vec::new();
    {
        let palette = [255, 255, 255, 200, 30, 30];
        let mut enc = gif::Encoder::new(&mut plain, 4, 4, &palette).unwrap();
        for k in 0..2u8 {
            let mut f = gif::Frame::default();
            (f.width, f.height) = (4, 4);
            f.buffer = std::borrow::Cow::Owned((0..16).map(|i| (i + k) % 2).collect());
            enc.write_frame(&f).unwrap();
        }
    }
    let odd = with_unknown_extension(&plain);
    assert!(odd.windows(2).any(|w| w == [0x21, 0x99]));
    std::fs::write(dir.path().join("odd.gif"), &odd).unwrap();
    let out = run(
        dir.path(),
        &["odd.gif", "--width", "2", "-o", "odd-out.gif", "-q"],
    );
    assert_ok(&out);
    let mut d = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(dir.path().join("odd-out.gif")).unwrap())
        .unwrap();
    let mut frames = 0;
    while d.read_next_frame().unwrap().is_some() {
        frames += 1;
    }
    assert_eq!((frames, d.width(), d.height()), (2, 2, 4));
    // Its first frame as one picture, and one frame alone as a still.
    let out = run(dir.path(), &["odd.gif", "--width", "2", "-o", "seq/", "-q"]);
    assert_ok(&out);
    assert_eq!(listing(&dir.path().join("seq")).len(), 2);
    let mut one = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut one, 4, 4, &[0, 0, 0, 255, 255, 255]).unwrap();
        let mut f = gif::Frame::default();
        (f.width, f.height) = (4, 4);
        f.buffer = std::borrow::Cow::Owned(vec![1; 16]);
        enc.write_frame(&f).unwrap();
    }
    std::fs::write(dir.path().join("one.gif"), with_unknown_extension(&one)).unwrap();
    let out = run(dir.path(), &["one.gif", "--width", "2", "-o", "one.png"]);
    assert_ok(&out);
    assert_eq!(size_of_file(&dir.path().join("one.png")), (2, 4));
}

// 15. The library: a name that says another format is refused; errors read as one line.

#[test]
fn write_still_refuses_a_name_of_another_format() {
    use vizretarget::io::{encode_still, write_still, OutputFormat};
    use vizretarget::{Image, Size};
    let dir = tempfile::tempdir().unwrap();
    let img = Image::filled(Size::new(4, 3).unwrap(), [10, 20, 30, 255]);
    let jpg = dir.path().join("x.jpg");
    let e = write_still(&img, &jpg, OutputFormat::Png).unwrap_err();
    assert!(matches!(e, vizretarget::Error::InvalidOptions(_)), "{e}");
    assert!(e.to_string().contains("x.jpg"), "{e}");
    assert!(!jpg.exists());
    write_still(&img, &jpg, OutputFormat::Jpeg).unwrap();
    write_still(&img, &dir.path().join("x.webp"), OutputFormat::WebP).unwrap();
    // A name without a known extension takes the format given.
    write_still(&img, &dir.path().join("x.out"), OutputFormat::Png).unwrap();
    let bytes: Result<Vec<u8>, vizretarget::Error> = encode_still(&img, OutputFormat::WebP);
    assert!(bytes.unwrap().starts_with(b"RIFF"));
    // `?` in main prints Debug: the same line as Display.
    let e = vizretarget::io::read_still(&dir.path().join("none.png")).unwrap_err();
    assert_eq!(format!("{e:?}"), e.to_string());
    assert!(!format!("{e:?}").contains("Io {"), "{e:?}");
}

// 14. Shell completions.

#[test]
fn completions_for_bash_zsh_and_fish() {
    let dir = tempfile::tempdir().unwrap();
    for (shell, mark) in [
        ("bash", "complete -F"),
        ("zsh", "#compdef vizretarget"),
        ("fish", "complete -c vizretarget"),
    ] {
        let out = run(dir.path(), &["completions", shell]);
        assert_ok(&out);
        let script = String::from_utf8(out.stdout).unwrap();
        assert!(script.contains(mark), "{shell}: {script}");
        assert!(script.contains("memory-limit"), "{shell}");
    }
    let out = run(dir.path(), &["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let help = String::from_utf8(bin().arg("--help").output().unwrap().stdout).unwrap();
    assert!(help.contains("completions"), "{help}");
}
