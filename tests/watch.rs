//! `vizretarget watch` as a dashboard exporter meets it: 100 snapshots dropped in quick
//! succession, a third of them written slowly in several chunks, must give exactly 100
//! outputs, each a whole PNG of the target size, each input read once; Ctrl-C (SIGINT) then
//! stops the watcher with exit code 130 and the statistics file lists every snapshot once.

mod common;

use common::snapshot;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const N: usize = 100;

/// Visible files of `dir` (temporary files of atomic writers are hidden).
fn visible(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
                .map(|e| e.path())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn hundred_snapshots_some_written_slowly_give_hundred_whole_outputs_once_each() {
    let root = tempfile::tempdir().unwrap();
    let (inbox, outbox) = (root.path().join("in"), root.path().join("out"));
    std::fs::create_dir(&inbox).unwrap();
    let stats = root.path().join("stats.json");
    let mut child = Command::new(env!("CARGO_BIN_EXE_vizretarget"))
        .arg("watch")
        .arg(&inbox)
        .arg("-o")
        .arg(&outbox)
        .args(["--size", "64x64", "--stats-json"])
        .arg(&stats)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Let the watcher start (it reads files already present too, so no event is lost).
    std::thread::sleep(Duration::from_millis(300));

    // Every third snapshot is written slowly: four chunks with pauses longer than the settle
    // time, from a writer thread, while the others land at once.
    let slow: Vec<(PathBuf, Vec<u8>)> = (0..N)
        .filter(|i| i % 3 == 0)
        .map(|i| (inbox.join(format!("snap-{i:03}.png")), snapshot(i)))
        .collect();
    let writer = std::thread::spawn(move || {
        let mut files: Vec<(std::fs::File, &[u8])> = slow
            .iter()
            .map(|(p, b)| (std::fs::File::create(p).unwrap(), &b[..]))
            .collect();
        for chunk in 0..4 {
            for (f, bytes) in &mut files {
                let n = bytes.len();
                let part = &bytes[n * chunk / 4..n * (chunk + 1) / 4];
                f.write_all(part).unwrap();
                f.flush().unwrap();
            }
            std::thread::sleep(Duration::from_millis(300));
        }
        // Files close here, all at once.
    });
    for i in (0..N).filter(|i| i % 3 != 0) {
        std::fs::write(inbox.join(format!("snap-{i:03}.png")), snapshot(i)).unwrap();
    }
    writer.join().unwrap();

    let start = Instant::now();
    while visible(&outbox).len() < N && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(50));
    }
    // A little longer, to catch a snapshot processed twice.
    std::thread::sleep(Duration::from_millis(500));
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let deadline = Instant::now() + Duration::from_secs(20);
    let code = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code();
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("the watcher did not stop after SIGINT");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(code, Some(130), "stderr: {err}");
    assert!(
        !err.contains("panicked") && !err.contains("warning"),
        "{err}"
    );

    let outputs = visible(&outbox);
    let want: Vec<PathBuf> = (0..N)
        .map(|i| outbox.join(format!("snap-{i:03}.png")))
        .collect();
    assert_eq!(outputs, want, "exactly one output per snapshot, same names");
    let all: Vec<String> = std::fs::read_dir(&outbox)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(all.len(), N, "no temporary file left: {all:?}");
    for p in &outputs {
        let img = image::open(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert_eq!((img.width(), img.height()), (64, 64), "{}", p.display());
    }

    // Each input read once: the statistics list every name exactly once, and so does stderr.
    let json = std::fs::read_to_string(&stats).unwrap();
    assert_eq!(json.matches("\"frame_index\"").count(), N, "{json}");
    for i in 0..N {
        let name = format!("snap-{i:03}.png");
        assert_eq!(
            json.matches(&format!("\"{name}\"")).count(),
            1,
            "{name} in {json}"
        );
        assert_eq!(
            err.matches(&format!("{name} ->")).count(),
            1,
            "{name} in {err}"
        );
    }
}

#[test]
fn existing_snapshots_first_in_natural_order_then_replacements_and_vanished_files() {
    let root = tempfile::tempdir().unwrap();
    let (inbox, outbox) = (root.path().join("in"), root.path().join("out"));
    std::fs::create_dir(&inbox).unwrap();
    for n in [10, 2, 1] {
        std::fs::write(inbox.join(format!("snap{n}.png")), snapshot(n)).unwrap();
    }
    std::fs::write(inbox.join("readme.txt"), b"not a snapshot").unwrap();
    let stats = root.path().join("stats.json");
    let child = Command::new(env!("CARGO_BIN_EXE_vizretarget"))
        .arg("watch")
        .arg(&inbox)
        .arg("-o")
        .arg(&outbox)
        .args(["--width", "48", "--stats-json"])
        .arg(&stats)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let wait_for = |n: usize| {
        let start = Instant::now();
        while visible(&outbox).len() < n && start.elapsed() < Duration::from_secs(30) {
            std::thread::sleep(Duration::from_millis(20));
        }
        assert_eq!(visible(&outbox).len(), n);
    };
    wait_for(3);
    // Replaced the way atomic writers do it: a hidden temporary file renamed over the old one.
    let tmp = inbox.join(".snap2.png.tmp");
    std::fs::write(&tmp, snapshot(42)).unwrap();
    std::fs::rename(&tmp, inbox.join("snap2.png")).unwrap();
    // A snapshot that disappears before it is complete.
    let mut f = std::fs::File::create(inbox.join("gone.png")).unwrap();
    f.write_all(&snapshot(5)[..40]).unwrap();
    drop(f);
    std::fs::remove_file(inbox.join("gone.png")).unwrap();
    std::fs::write(inbox.join("snap3.png"), snapshot(3)).unwrap();
    wait_for(4);
    std::thread::sleep(Duration::from_millis(400));
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!visible(&outbox).iter().any(|p| p.ends_with("gone.png")));
    let json = std::fs::read_to_string(&stats).unwrap();
    let order: Vec<&str> = json
        .match_indices("\"name\": \"")
        .map(|(i, m)| {
            let rest = &json[i + m.len()..];
            &rest[..rest.find('"').unwrap()]
        })
        .collect();
    assert_eq!(
        order,
        [
            "snap1.png",
            "snap2.png",
            "snap10.png",
            "snap2.png",
            "snap3.png"
        ],
        "{err}"
    );
    let img = image::open(outbox.join("snap2.png")).unwrap();
    assert_eq!(
        (img.width(), img.height()),
        (48, 64),
        "width alone keeps the height"
    );
}
