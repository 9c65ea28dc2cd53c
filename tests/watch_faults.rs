//! `vizretarget watch` meeting the faults of an unattended folder: a snapshot deleted before it
//! is read, a snapshot it may not read, an output folder made read-only, the watched folder
//! removed and recreated. Each must give one clear line naming the file (or folder), and the
//! watcher must go on: a snapshot dropped after the fault is retargeted and written whole.
//!
//! Permissions: root reads and writes whatever the permission bits say (CAP_DAC_OVERRIDE),
//! so under root the watcher is started with CAP_DAC_OVERRIDE and CAP_DAC_READ_SEARCH dropped
//! from its capability bounding set (Linux), still as root: the bits then apply to it as to
//! any user, and the faults are the real ones (EACCES from open and create). Only where that
//! is impossible (root elsewhere, or no CAP_SETPCAP) are the two permission tests skipped,
//! saying why.
//!
//! No sleeps as synchronisation: each step waits for the watcher's stderr line that shows the
//! previous one was handled; timeouts only guard against a hang.

#![cfg(unix)]

mod common;

use common::{listing, snapshot};
use std::io::{BufRead, BufReader, Write};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// How long anything may take before the test fails instead of hanging.
const GUARD: Duration = Duration::from_secs(60);

/// Drops snapshot `i` into `dir` as `name`, whole at once (hidden temporary file, rename), the
/// way exporters do: the watcher reads it promptly.
fn drop_snapshot(dir: &Path, name: &str, i: usize) {
    let tmp = dir.join(format!(".{name}.part"));
    std::fs::write(&tmp, snapshot(i)).unwrap();
    std::fs::rename(&tmp, dir.join(name)).unwrap();
}

fn chmod(path: &Path, mode: u32) {
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
}

/// Whether permission bits bind this process (not root).
fn bits_bind_us() -> bool {
    // SAFETY: geteuid has no preconditions.
    unsafe { libc::geteuid() != 0 }
}

/// Makes permission bits apply to the child even when the tests run as root; `Err` (why)
/// where that cannot be done.
fn make_bits_bind(cmd: &mut Command) -> Result<(), String> {
    if bits_bind_us() {
        return Ok(());
    }
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        // CAP_DAC_OVERRIDE (1) and CAP_DAC_READ_SEARCH (2): without them in the bounding set,
        // the program execs without them, and root is refused like any owner without the bit.
        // SAFETY: prctl is a plain system call, safe between fork and exec.
        unsafe {
            cmd.pre_exec(|| {
                for cap in [1, 2] {
                    if libc::prctl(libc::PR_CAPBSET_DROP, cap, 0, 0, 0) != 0 {
                        return Err(std::io::Error::last_os_error());
                    }
                }
                Ok(())
            });
        }
        Ok(())
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = cmd;
        Err("running as root, and dropping CAP_DAC_OVERRIDE is Linux-only".into())
    }
}

/// A running `vizretarget watch IN -o OUT --size 64x64`, its stderr read line by line.
struct Watch {
    child: Child,
    rx: Receiver<String>,
    seen: Vec<String>,
    _root: tempfile::TempDir,
    inbox: PathBuf,
    outbox: PathBuf,
}

impl Watch {
    /// Starts the watcher on a fresh empty folder; `Err(why)` if permission bits were asked
    /// to bind it and cannot.
    fn start(extra: &[&str], bits_must_bind: bool) -> Result<Watch, String> {
        let root = tempfile::tempdir().unwrap();
        let (inbox, outbox) = (root.path().join("in"), root.path().join("out"));
        std::fs::create_dir(&inbox).unwrap();
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_vizretarget"));
        cmd.arg("watch")
            .arg(&inbox)
            .arg("-o")
            .arg(&outbox)
            .args(["--size", "64x64"])
            .args(extra)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        if bits_must_bind {
            make_bits_bind(&mut cmd)?;
        }
        let mut child = cmd
            .spawn()
            .map_err(|e| format!("cannot start the watcher without CAP_DAC_OVERRIDE: {e}"))?;
        let stderr = child.stderr.take().unwrap();
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let mut w = Watch {
            child,
            rx,
            seen: Vec::new(),
            _root: root,
            inbox,
            outbox,
        };
        // Watching has begun once a first snapshot comes out.
        drop_snapshot(&w.inbox, "first.png", 0);
        w.wait_line("first.png written", |l| l.contains("first.png ->"));
        Ok(w)
    }

    /// Waits for a stderr line satisfying `pred`; returns it.
    fn wait_line(&mut self, what: &str, pred: impl Fn(&str) -> bool) -> String {
        self.wait_count(1, what, pred)
    }

    /// Waits until `n` stderr lines satisfy `pred`; returns the `n`th.
    fn wait_count(&mut self, n: usize, what: &str, pred: impl Fn(&str) -> bool) -> String {
        let deadline = Instant::now() + GUARD;
        loop {
            if let Some(l) = self.seen.iter().filter(|l| pred(l)).nth(n - 1) {
                return l.clone();
            }
            let left = deadline.saturating_duration_since(Instant::now());
            match self.rx.recv_timeout(left) {
                Ok(line) => self.seen.push(line),
                Err(RecvTimeoutError::Timeout) => {
                    let _ = self.child.kill();
                    panic!("timed out waiting for {what}; stderr: {:#?}", self.seen)
                }
                Err(RecvTimeoutError::Disconnected) => {
                    panic!("the watcher ended before {what}; stderr: {:#?}", self.seen)
                }
            }
        }
    }

    /// Stops the watcher with SIGINT; its exit code and every stderr line.
    fn stop(&mut self) -> (Option<i32>, Vec<String>) {
        // SAFETY: kill(2) with the pid of our own child.
        assert_eq!(
            unsafe { libc::kill(self.child.id() as libc::pid_t, libc::SIGINT) },
            0
        );
        let deadline = Instant::now() + GUARD;
        let code = loop {
            if let Some(s) = self.child.try_wait().unwrap() {
                break s.code();
            }
            if Instant::now() > deadline {
                let _ = self.child.kill();
                panic!("the watcher did not stop after SIGINT");
            }
            std::thread::sleep(Duration::from_millis(10));
        };
        self.seen.extend(self.rx.iter());
        (code, std::mem::take(&mut self.seen))
    }
}

/// A test that fails midway must not leave its watcher running.
impl Drop for Watch {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// The lines that mention `name`, other than its `name -> output` line.
fn fault_lines<'a>(lines: &'a [String], name: &str) -> Vec<&'a String> {
    lines
        .iter()
        .filter(|l| l.contains(name) && !l.contains(&format!("{name} ->")))
        .collect()
}

/// Outputs are the visible files of OUTDIR, each a whole PNG of the target size.
fn whole_outputs(outbox: &Path) -> Vec<String> {
    let names = listing(outbox);
    for n in &names {
        assert!(!n.starts_with('.'), "a temporary file is left: {names:?}");
        let img = image::open(outbox.join(n)).unwrap_or_else(|e| panic!("{n}: {e}"));
        assert_eq!((img.width(), img.height()), (64, 64), "{n}");
    }
    names
}

#[test]
fn a_snapshot_deleted_before_it_is_read_is_reported_once_and_skipped() {
    // A long settle time: a file still open for writing is waited for (10 settle times), so it
    // is certainly deleted before it is read.
    let mut w = Watch::start(&["--settle-ms", "5000"], false).unwrap();
    let gone = w.inbox.join("gone.png");
    let mut writer = std::fs::File::create(&gone).unwrap();
    writer.write_all(&snapshot(5)[..200]).unwrap();
    writer.flush().unwrap();
    std::fs::remove_file(&gone).unwrap();
    // The writer closes after the deletion: that event too names gone.png.
    drop(writer);
    let line = w.wait_line("the vanished report", |l| l.contains("gone.png"));
    assert!(line.contains("vanished before it could be read"), "{line}");
    drop_snapshot(&w.inbox, "next.png", 1);
    w.wait_line("next.png written", |l| l.contains("next.png ->"));
    let (code, lines) = w.stop();
    let outbox = &w.outbox;
    assert_eq!(code, Some(130), "{lines:#?}");
    assert!(!lines.iter().any(|l| l.contains("panicked")), "{lines:#?}");
    assert_eq!(
        fault_lines(&lines, "gone.png").len(),
        1,
        "one line for the vanished file: {lines:#?}"
    );
    assert_eq!(whole_outputs(outbox), ["first.png", "next.png"]);
}

#[test]
fn a_snapshot_without_read_permission_is_reported_and_skipped_until_chmod() {
    let mut w = match Watch::start(&[], true) {
        Ok(w) => w,
        Err(why) => {
            eprintln!("skipped: {why}");
            return;
        }
    };
    // Mode 000 before it appears under its name: the watcher never sees it readable.
    let tmp = w.inbox.join(".secret.png.part");
    std::fs::write(&tmp, snapshot(2)).unwrap();
    chmod(&tmp, 0o000);
    std::fs::rename(&tmp, w.inbox.join("secret.png")).unwrap();
    let line = w.wait_line("the permission report", |l| l.contains("secret.png"));
    assert!(
        line.contains("cannot be read") && line.contains("ermission denied"),
        "{line}"
    );
    drop_snapshot(&w.inbox, "next.png", 3);
    w.wait_line("next.png written", |l| l.contains("next.png ->"));
    // Readable again: retargeted now, without being written anew.
    chmod(&w.inbox.join("secret.png"), 0o644);
    w.wait_line("secret.png written", |l| l.contains("secret.png ->"));
    let (code, lines) = w.stop();
    let outbox = &w.outbox;
    assert_eq!(code, Some(130), "{lines:#?}");
    assert!(!lines.iter().any(|l| l.contains("panicked")), "{lines:#?}");
    assert_eq!(
        fault_lines(&lines, "secret.png").len(),
        1,
        "one line for the unreadable file: {lines:#?}"
    );
    assert_eq!(
        whole_outputs(outbox),
        ["first.png", "next.png", "secret.png"]
    );
}

#[test]
fn an_output_folder_made_read_only_is_reported_per_file_and_watching_goes_on() {
    let stats = tempfile::NamedTempFile::new().unwrap();
    let stats_arg = stats.path().to_str().unwrap().to_string();
    let mut w = match Watch::start(&["--stats-json", &stats_arg], true) {
        Ok(w) => w,
        Err(why) => {
            eprintln!("skipped: {why}");
            return;
        }
    };
    chmod(&w.outbox, 0o555);
    drop_snapshot(&w.inbox, "blocked.png", 4);
    let line = w.wait_line("the write failure", |l| l.contains("blocked.png"));
    chmod(&w.outbox, 0o755);
    assert!(
        line.contains("not written") && line.contains("ermission denied"),
        "{line}"
    );
    drop_snapshot(&w.inbox, "next.png", 5);
    w.wait_line("next.png written", |l| l.contains("next.png ->"));
    let (code, lines) = w.stop();
    let outbox = &w.outbox;
    assert_eq!(code, Some(130), "{lines:#?}");
    assert!(!lines.iter().any(|l| l.contains("panicked")), "{lines:#?}");
    assert_eq!(
        fault_lines(&lines, "blocked.png").len(),
        1,
        "one line for the unwritten file, no 'blocked.png ->': {lines:#?}"
    );
    assert!(
        lines.last().unwrap().ends_with("; 1 not written"),
        "the summary counts it: {lines:#?}"
    );
    assert_eq!(whole_outputs(outbox), ["first.png", "next.png"]);
    let json = std::fs::read_to_string(stats.path()).unwrap();
    assert_eq!(json.matches("\"written\": false").count(), 1, "{json}");
    let at = json
        .find("\"blocked.png\"")
        .expect("blocked.png in the statistics");
    let entry = &json[at..at + json[at..].find('}').unwrap()];
    assert!(entry.contains("\"written\": false"), "{json}");
}

#[test]
fn the_watched_folder_removed_and_recreated_is_reported_and_watched_again() {
    let mut w = Watch::start(&[], false).unwrap();
    let inbox = w.inbox.clone();
    std::fs::remove_dir_all(&inbox).unwrap(); // first.png goes with it
    let gone = w.wait_line("the removal report", |l| {
        l.contains("removed or moved away")
    });
    assert!(gone.contains(&*inbox.to_string_lossy()), "{gone}");
    std::fs::create_dir(&inbox).unwrap();
    // At once, before the watcher may have found the folder again: read all the same. Its
    // name was done in the old folder; in the new one it is a new snapshot.
    drop_snapshot(&inbox, "first.png", 6);
    w.wait_line("the return report", |l| l.contains("is back"));
    drop_snapshot(&inbox, "next.png", 7);
    w.wait_line("next.png written", |l| l.contains("next.png ->"));
    w.wait_count(2, "first.png written again", |l| l.contains("first.png ->"));
    let (code, lines) = w.stop();
    let outbox = &w.outbox;
    assert_eq!(code, Some(130), "{lines:#?}");
    assert!(!lines.iter().any(|l| l.contains("panicked")), "{lines:#?}");
    let folder: Vec<_> = lines.iter().filter(|l| l.contains("folder")).collect();
    assert_eq!(folder.len(), 2, "one line gone, one line back: {lines:#?}");
    assert!(!lines.iter().any(|l| l.contains("vanished")), "{lines:#?}");
    assert_eq!(whole_outputs(outbox), ["first.png", "next.png"]);
}

#[test]
fn a_folder_recreated_unseen_is_not_taken_for_the_old_one() {
    // Removed and recreated while the watcher cannot look (stopped): on ext4 the new folder
    // often gets the old one's inode, yet the old watch is dead. The watcher must still
    // notice (its watch reports the deletion) and watch the new folder.
    let mut w = Watch::start(&[], false).unwrap();
    let inbox = w.inbox.clone();
    let pid = w.child.id() as libc::pid_t;
    // SAFETY: kill(2) with the pid of our own child.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGSTOP) }, 0);
    std::fs::remove_dir_all(&inbox).unwrap();
    std::fs::create_dir(&inbox).unwrap();
    // SAFETY: as above.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGCONT) }, 0);
    w.wait_line("the return report", |l| l.contains("is back"));
    drop_snapshot(&inbox, "next.png", 8);
    w.wait_line("next.png written", |l| l.contains("next.png ->"));
    let (code, lines) = w.stop();
    let outbox = &w.outbox;
    assert_eq!(code, Some(130), "{lines:#?}");
    assert!(
        lines.iter().any(|l| l.contains("removed or moved away")),
        "{lines:#?}"
    );
    assert_eq!(whole_outputs(outbox), ["first.png", "next.png"]);
}
