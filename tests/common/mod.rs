//! Helpers the integration tests share: a snapshot for the watcher, running the binary and
//! checking how it failed for the command-line tests, and drawing synthetic charts
//! ([`draw`]); each test crate uses some.
#![allow(dead_code)]

pub mod draw;

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// The binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_vizretarget"))
}

/// Runs the binary in `dir` with `args`, no stdin, collecting everything.
pub fn run(dir: &Path, args: &[&str]) -> Output {
    bin().args(args).current_dir(dir).output().unwrap()
}

/// Runs the binary in `dir` with `stdin` fed from `input`, collecting everything.
pub fn run_with_stdin(dir: &Path, args: &[&str], input: impl AsRef<[u8]>) -> Output {
    let input = input.as_ref().to_vec();
    let mut child = bin()
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let feeder = std::thread::spawn(move || {
        let _ = stdin.write_all(&input); // the binary may stop reading early
    });
    let out = child.wait_with_output().unwrap();
    feeder.join().unwrap();
    out
}

/// The names in `dir` (hidden ones too), sorted.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The folder holds exactly `names`: no output left beside the inputs, no temporary file.
pub fn assert_only(dir: &Path, names: &[&str]) {
    let mut want: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    want.sort();
    assert_eq!(listing(dir), want, "files in {}", dir.display());
}

pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A failed run: exit `code`, one line on stderr holding every word of `words`, no panic.
pub fn assert_fails(out: &Output, code: i32, words: &[&str]) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(code), "exit code; stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err:?}");
    for w in words {
        assert!(err.contains(w), "stderr lacks {w:?}: {err}");
    }
}

/// A small chart as PNG bytes: its dot position and band colour depend on `i`.
pub fn snapshot(i: usize) -> Vec<u8> {
    let img = image::RgbImage::from_fn(96, 64, |x, y| {
        let (dx, dy) = (x as i32 - 20 - (i % 50) as i32, y as i32 - 36);
        if y < 8 {
            image::Rgb([(i * 37 % 256) as u8, (i * 91 % 256) as u8, 120])
        } else if dx * dx + dy * dy <= 36 {
            image::Rgb([214, 39, 40])
        } else if x == 4 || y == 60 {
            image::Rgb([90, 90, 90])
        } else {
            image::Rgb([255, 255, 255])
        }
    });
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}
