//! SIGINT and SIGTERM during a stream conversion, as a user or a service manager sends them:
//! the run ends promptly with exit code 128 + the signal (130, 143), the frames in flight are
//! finished, and the output is whole: a GIF that parses to its trailer and holds every frame
//! done, or a folder of whole PNGs and no temporary file. Also when the input is a pipe that
//! has stopped sending (the reader blocked in `read`), when the signal comes before the first
//! frame, and a second signal while the first one's stop is stuck (stdout not read).
//!
//! No sleeps as synchronisation: each test waits for what the process shows (its per-frame
//! lines on stderr, output files, and on Linux the system call its threads are blocked in);
//! timeouts only guard against a hang.

#![cfg(unix)]

mod common;
use common::listing;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

const W: u32 = 160;
const H: u32 = 120;
const TW: u32 = 100;
const TH: u32 = 120;

/// How long anything may take before the test fails instead of hanging.
const GUARD: Duration = Duration::from_secs(60);

/// Distinct band colours, one per frame.
fn colour(i: usize) -> [u8; 3] {
    const C: [[u8; 3]; 8] = [
        [214, 39, 40],
        [31, 119, 180],
        [44, 160, 44],
        [255, 127, 14],
        [148, 103, 189],
        [23, 190, 207],
        [20, 20, 20],
        [250, 220, 60],
    ];
    C[i % C.len()]
}

/// A chart-like frame: a moving disc, an axis, and a band of `colour(i)` along the top.
fn frame(i: usize) -> image::RgbaImage {
    let band = colour(i);
    image::RgbaImage::from_fn(W, H, |x, y| {
        let (dx, dy) = (x as i32 - 40 - (i % 60) as i32, y as i32 - 70);
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

fn raw_rgb(i: usize) -> Vec<u8> {
    frame(i).pixels().flat_map(|p| [p[0], p[1], p[2]]).collect()
}

/// Which frame a retargeted picture is, from its band colour: the first colour down the
/// middle that is not the white ground (the picture may be drawn at one scale, below a
/// band of its ground).
fn which(img: &image::RgbaImage) -> Option<usize> {
    // Two rows into the band: its first may blend with the ground.
    let x = img.width() / 2;
    let top = (0..img.height()).find(|&y| img.get_pixel(x, y).0[..3].iter().any(|&v| v < 200))?;
    let p = img.get_pixel(x, (top + 2).min(img.height() - 1)).0;
    (0..8).find(|&i| {
        let c = colour(i);
        (0..3).all(|k| (p[k] as i32 - c[k] as i32).abs() <= 24)
    })
}

fn in_order(n: usize) -> Vec<Option<usize>> {
    (0..n).map(|i| Some(i % 8)).collect()
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_vizretarget"))
}

fn send(child: &Child, sig: i32) {
    // SAFETY: kill(2) with the pid of our own child.
    let r = unsafe { libc::kill(child.id() as libc::pid_t, sig) };
    assert_eq!(r, 0, "kill failed");
}

/// Waits for the child to exit; its exit code (`None`: killed by a signal).
fn exit_code(child: &mut Child) -> Option<i32> {
    let deadline = Instant::now() + GUARD;
    loop {
        if let Some(s) = child.try_wait().unwrap() {
            return s.code();
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("the process did not end after the signal");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Polls `cond` every 10 ms until it holds; fails after [`GUARD`].
fn wait_until(what: &str, mut cond: impl FnMut() -> bool) {
    let deadline = Instant::now() + GUARD;
    while !cond() {
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The lines of the child's stderr, as they come.
struct Lines {
    rx: Receiver<String>,
    seen: Vec<String>,
}

impl Lines {
    fn of(child: &mut Child) -> Lines {
        let stderr = child.stderr.take().unwrap();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        Lines {
            rx,
            seen: Vec::new(),
        }
    }

    /// Waits until `n` lines in all satisfy `pred`.
    fn wait_for(&mut self, n: usize, what: &str, pred: impl Fn(&str) -> bool) {
        let deadline = Instant::now() + GUARD;
        while self.seen.iter().filter(|l| pred(l)).count() < n {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.rx.recv_timeout(left) {
                Ok(line) => self.seen.push(line),
                Err(RecvTimeoutError::Timeout) => {
                    panic!(
                        "timed out waiting for {what}; stderr so far: {:?}",
                        self.seen
                    )
                }
                Err(RecvTimeoutError::Disconnected) => {
                    panic!("stderr ended before {what}: {:?}", self.seen)
                }
            }
        }
    }

    /// Everything, once the process has ended.
    fn all(mut self) -> String {
        let deadline = Instant::now() + GUARD;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.rx.recv_timeout(left) {
                Ok(line) => self.seen.push(line),
                Err(RecvTimeoutError::Disconnected) => break,
                Err(RecvTimeoutError::Timeout) => panic!("stderr stays open"),
            }
        }
        self.seen.join("\n")
    }
}

/// Whether a thread of `pid` (named `thread`, or any) is blocked in the system call `nr`
/// (Linux: `/proc/PID/task/TID/syscall` starts with the call's number while it is blocked).
fn blocked_in(pid: u32, thread: Option<&str>, nr: libc::c_long) -> bool {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
        return false;
    };
    tasks.filter_map(Result::ok).any(|t| {
        let comm = std::fs::read_to_string(t.path().join("comm")).unwrap_or_default();
        let call = std::fs::read_to_string(t.path().join("syscall")).unwrap_or_default();
        thread.is_none_or(|name| comm.trim() == name)
            && call
                .split_whitespace()
                .next()
                .and_then(|n| n.parse::<libc::c_long>().ok())
                == Some(nr)
    })
}

/// Waits until a thread of `child` is blocked in `read`: the only file it reads is stdin.
fn wait_blocked_in_read(child: &Child) {
    let pid = child.id();
    wait_until("a thread to block reading stdin", || {
        blocked_in(pid, None, libc::SYS_read)
    });
}

/// A whole GIF: parses to its trailer; the frames as a viewer composites them, each checked
/// to be the target size.
fn gif_frames(bytes: &[u8]) -> Vec<image::RgbaImage> {
    assert_eq!(bytes.last(), Some(&0x3B), "the GIF ends with its trailer");
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(bytes).expect("a GIF header");
    assert_eq!((d.width() as u32, d.height() as u32), (TW, TH));
    let mut canvas = image::RgbaImage::new(TW, TH);
    let mut frames = Vec::new();
    while let Some(f) = d.read_next_frame().expect("every frame decodes") {
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
        frames.push(canvas.clone());
    }
    frames
}

/// A folder of outputs: only visible, whole PNGs of the target size; their names, sorted.
fn whole_pngs(dir: &Path) -> Vec<String> {
    let names = listing(dir);
    for n in &names {
        assert!(!n.starts_with('.'), "a temporary file is left: {names:?}");
        let img = image::open(dir.join(n)).unwrap_or_else(|e| panic!("{n}: {e}"));
        assert_eq!((img.width(), img.height()), (TW, TH), "{n}");
    }
    names
}

fn spawn(dir: &Path, args: &[&str], stdout: Stdio) -> Child {
    bin()
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn frame_line(l: &str) -> bool {
    l.starts_with("frame ")
}

#[test]
fn sigterm_while_stdin_sends_nothing_more_gives_a_whole_gif_and_143() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["-", "--size", "100x120", "-o", "live.gif", "--stats"];
    let mut child = spawn(dir.path(), &args, Stdio::null());
    let mut lines = Lines::of(&mut child);
    // Four PNGs, then the pipe stays open and silent: the reader blocks.
    let mut stdin = child.stdin.take().unwrap();
    for i in 0..4 {
        stdin.write_all(&png(&frame(i))).unwrap();
    }
    stdin.flush().unwrap();
    lines.wait_for(4, "four frames done", frame_line);
    wait_blocked_in_read(&child);
    send(&child, libc::SIGTERM);
    let code = exit_code(&mut child);
    let err = lines.all();
    drop(stdin);
    assert_eq!(code, Some(143), "{err}");
    assert!(err.contains("SIGTERM"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(listing(dir.path()), ["live.gif"], "no temporary file");
    let frames = gif_frames(&std::fs::read(dir.path().join("live.gif")).unwrap());
    let ids: Vec<_> = frames.iter().map(which).collect();
    assert_eq!(ids, in_order(4), "every frame read, in order");
}

#[test]
fn sigint_while_stdin_sends_nothing_more_gives_whole_pngs_and_130() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "-",
        "--input-format",
        "rgb24",
        "--input-size",
        "160x120",
        "--size",
        "100x120",
        "-o",
        "seq/",
    ];
    let mut child = spawn(dir.path(), &args, Stdio::null());
    let lines = Lines::of(&mut child);
    let mut stdin = child.stdin.take().unwrap();
    for i in 0..5 {
        stdin.write_all(&raw_rgb(i)).unwrap();
    }
    // Half a frame more: the reader waits inside a frame.
    stdin
        .write_all(&raw_rgb(5)[..(W * H * 3 / 2) as usize])
        .unwrap();
    stdin.flush().unwrap();
    let seq = dir.path().join("seq");
    wait_until("five PNGs", || {
        seq.is_dir() && listing(&seq).iter().filter(|n| !n.starts_with('.')).count() == 5
    });
    wait_blocked_in_read(&child);
    send(&child, libc::SIGINT);
    let code = exit_code(&mut child);
    let err = lines.all();
    drop(stdin);
    assert_eq!(code, Some(130), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let names = whole_pngs(&seq);
    let want: Vec<String> = (0..5).map(|i| format!("frame-{i:05}.png")).collect();
    assert_eq!(names, want);
    for (i, n) in names.iter().enumerate() {
        let img = image::open(seq.join(n)).unwrap().to_rgba8();
        assert_eq!(which(&img), Some(i), "{n}");
    }
}

#[test]
fn sigterm_midway_through_a_folder_leaves_the_first_frames_whole() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    const N: usize = 2000;
    let bytes: Vec<Vec<u8>> = (0..8).map(|i| png(&frame(i))).collect();
    for i in 0..N {
        std::fs::write(frames.join(format!("f{i}.png")), &bytes[i % 8]).unwrap();
    }
    let args = ["frames", "--size", "100x120", "-o", "seq/"];
    let mut child = spawn(dir.path(), &args, Stdio::null());
    let lines = Lines::of(&mut child);
    let seq = dir.path().join("seq");
    wait_until("three PNGs", || {
        seq.is_dir() && listing(&seq).iter().filter(|n| !n.starts_with('.')).count() >= 3
    });
    send(&child, libc::SIGTERM);
    let code = exit_code(&mut child);
    let err = lines.all();
    assert_eq!(code, Some(143), "{err}");
    assert!(err.contains("(interrupted)"), "the summary says so: {err}");
    let names = whole_pngs(&seq);
    assert!(
        (3..N).contains(&names.len()),
        "stopped midway: {} of {N} frames",
        names.len()
    );
    // The frames done are the first ones, each whole and the right one.
    let mut want: Vec<String> = (0..names.len()).map(|i| format!("f{i}.png")).collect();
    want.sort();
    assert_eq!(names, want);
    for n in &names {
        let i: usize = n[1..n.len() - 4].parse().unwrap();
        let img = image::open(seq.join(n)).unwrap().to_rgba8();
        assert_eq!(which(&img), Some(i % 8), "{n}");
    }
}

#[test]
fn sigint_midway_through_a_gif_file_gives_a_whole_shorter_gif() {
    let dir = tempfile::tempdir().unwrap();
    const N: usize = 2000;
    {
        let mut file = std::fs::File::create(dir.path().join("in.gif")).unwrap();
        let mut enc = gif::Encoder::new(&mut file, W as u16, H as u16, &[]).unwrap();
        let frames: Vec<gif::Frame> = (0..8)
            .map(|i| {
                let mut px = frame(i).into_raw();
                gif::Frame::from_rgba_speed(W as u16, H as u16, &mut px, 30)
            })
            .collect();
        for i in 0..N {
            enc.write_frame(&frames[i % 8]).unwrap();
        }
    }
    let args = ["in.gif", "--size", "100x120", "-o", "out.gif", "--stats"];
    let mut child = spawn(dir.path(), &args, Stdio::null());
    let mut lines = Lines::of(&mut child);
    lines.wait_for(3, "three frames done", frame_line);
    send(&child, libc::SIGINT);
    let code = exit_code(&mut child);
    let err = lines.all();
    assert_eq!(code, Some(130), "{err}");
    assert_eq!(
        listing(dir.path()),
        ["in.gif", "out.gif"],
        "no temporary file"
    );
    let frames = gif_frames(&std::fs::read(dir.path().join("out.gif")).unwrap());
    assert!(
        (3..N).contains(&frames.len()),
        "stopped midway: {} of {N}",
        frames.len()
    );
    let ids: Vec<_> = frames.iter().map(which).collect();
    assert_eq!(ids, in_order(frames.len()), "whole frames, in order");
    let done = err.lines().filter(|l| frame_line(l)).count();
    assert_eq!(frames.len(), done, "every frame done is in the GIF");
}

#[test]
fn sigterm_with_a_gif_on_stdout_completes_the_stream() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "-",
        "--size",
        "100x120",
        "-o",
        "-",
        "--output-format",
        "gif",
        "--stats",
    ];
    let mut child = spawn(dir.path(), &args, Stdio::piped());
    let mut lines = Lines::of(&mut child);
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut v = Vec::new();
        stdout.read_to_end(&mut v).unwrap();
        v
    });
    let mut stdin = child.stdin.take().unwrap();
    for i in 0..3 {
        stdin.write_all(&png(&frame(i))).unwrap();
    }
    stdin.flush().unwrap();
    lines.wait_for(3, "three frames done", frame_line);
    wait_blocked_in_read(&child);
    send(&child, libc::SIGTERM);
    let code = exit_code(&mut child);
    let err = lines.all();
    drop(stdin);
    assert_eq!(code, Some(143), "{err}");
    let frames = gif_frames(&reader.join().unwrap());
    let ids: Vec<_> = frames.iter().map(which).collect();
    assert_eq!(ids, in_order(3));
}

#[test]
fn a_signal_before_the_first_frame_writes_nothing() {
    // Waiting for the first bytes of stdin (to recognise the format): SIGINT ends at once.
    let dir = tempfile::tempdir().unwrap();
    let args = ["-", "--size", "100x120", "-o", "out.gif"];
    let mut child = spawn(dir.path(), &args, Stdio::null());
    let lines = Lines::of(&mut child);
    let stdin = child.stdin.take().unwrap();
    wait_blocked_in_read(&child);
    send(&child, libc::SIGINT);
    let code = exit_code(&mut child);
    let err = lines.all();
    drop(stdin);
    assert_eq!(code, Some(130), "{err}");
    assert!(
        err.contains("SIGINT") && err.contains("stopped at once"),
        "{err}"
    );
    assert!(listing(dir.path()).is_empty(), "{:?}", listing(dir.path()));

    // Raw frames: the GIF is begun (a temporary file) and the reader waits for the first
    // frame. SIGTERM stops the run: no GIF of no frames, no temporary file.
    let args = [
        "-",
        "--input-format",
        "rgba",
        "--input-size",
        "160x120",
        "--size",
        "100x120",
        "-o",
        "out.gif",
    ];
    let mut child = spawn(dir.path(), &args, Stdio::null());
    let lines = Lines::of(&mut child);
    let stdin = child.stdin.take().unwrap();
    wait_blocked_in_read(&child);
    assert_eq!(listing(dir.path()).len(), 1, "the GIF's temporary file");
    send(&child, libc::SIGTERM);
    let code = exit_code(&mut child);
    let err = lines.all();
    drop(stdin);
    assert_eq!(code, Some(143), "{err}");
    assert!(err.contains("nothing written"), "{err}");
    assert!(listing(dir.path()).is_empty(), "{:?}", listing(dir.path()));
}

#[test]
fn a_second_signal_quits_at_once_when_the_first_cannot_finish() {
    // Nobody reads stdout: the sink blocks in write, so the first signal's orderly stop cannot
    // complete; the second ends the program, with the second signal's code.
    let dir = tempfile::tempdir().unwrap();
    let args = [
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
    ];
    let mut child = spawn(dir.path(), &args, Stdio::piped());
    let mut lines = Lines::of(&mut child);
    let stdout = child.stdout.take().unwrap(); // held, never read
    let mut stdin = child.stdin.take().unwrap();
    // Frames without end, until the program stops reading (the sink's buffer and the pipe
    // fill up first) or goes away.
    let feeder = std::thread::spawn(move || {
        let frames: Vec<u8> = (0..8).flat_map(raw_rgb).collect();
        while stdin.write_all(&frames).is_ok() {}
    });
    let pid = child.id();
    wait_until("the sink to block in write", || {
        blocked_in(pid, Some("vizretarget"), libc::SYS_write)
    });
    send(&child, libc::SIGINT);
    lines.wait_for(1, "the first signal's message", |l| {
        l.contains("finishing the frames in flight")
    });
    send(&child, libc::SIGTERM);
    let code = exit_code(&mut child);
    let err = lines.all();
    drop(stdout);
    feeder.join().unwrap();
    assert_eq!(code, Some(143), "{err}");
    assert!(
        err.contains("SIGTERM") && err.contains("stopped at once"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}
