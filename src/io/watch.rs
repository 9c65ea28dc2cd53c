//! A watched directory of snapshots as a stream of frames (`vizretarget watch`).
//!
//! A dashboard exporter drops a PNG or JPEG into a folder every few seconds, sometimes
//! replacing the last one. [`WatchSource`] yields each new or replaced snapshot once, as a
//! frame, so the frames go through the same [`crate::Pipeline`] as any stream and the mesh and
//! solution are reused between snapshots that barely change.
//!
//! - **Never half-written.** A file is read only when its writer is done: 25 ms after a
//!   close-write event (or a rename into the folder: complete by construction). Where the
//!   platform reports close-write (Linux inotify), a file written without one yet is waited
//!   for up to 10 settle times (2 s by default: a writer that pauses longer than that without
//!   closing is taken as done); elsewhere, and for files already there at the start, the file
//!   must go unchanged for the settle time (200 ms by default). Either way its size and
//!   modification time must not have changed since the last look, and must be the same after
//!   the read as before. If decoding still fails, the file is retried when it changes again,
//!   or after another wait, up to 5 times; then it is reported and skipped until it changes.
//! - **Once each.** The (size, mtime, inode) of every file read is remembered; events that do
//!   not change it (a reader opening the file, a touch of its permissions) are ignored. A
//!   replaced snapshot has a new fingerprint and is read again.
//! - **Order.** Snapshots are read in the order they became complete, ties in the order they
//!   first appeared; one slow writer does not hold back the files after it. Files present when
//!   watching starts come first, in natural order of their names: they wait the same settle
//!   time, and a close-write event with no write seen before it (writes made before watching
//!   started) does not shorten one's wait.
//! - **Names.** Only `.png`, `.jpg` and `.jpeg` files (any case) directly in the folder count;
//!   hidden names (a leading `.`, as atomic writers' temporary files) are ignored. Each
//!   frame's file name is recorded in [`WatchSource::names`].
//! - **Faults** are reported to the warning callback and watching goes on; the library never
//!   prints. A file deleted before it could be read is reported once and skipped. A file that
//!   cannot be opened (no read permission) is skipped until its permissions or its content
//!   change (a `chmod` brings it back). The watched folder removed (or moved away) is reported
//!   once, whether the watcher says so or the path now holds another folder; the source then
//!   looks for a folder at the same path every 100 ms, watches it when it is back (reported
//!   too), and reads the snapshots in it as files already there at the start.
//! - **Stopping**: the cancel flag (SIGINT or SIGTERM in the CLI) ends the stream within 100 ms.

use super::names::FrameNames;
use super::natural::natural_cmp;
use super::still::read_still_with;
use crate::error::Error;
use crate::retarget::Frame;
use crate::stream::FrameSource;
use notify::event::{AccessKind, AccessMode, ModifyKind, RenameMode};
use notify::{Event, EventKind, RecursiveMode, Watcher};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};

/// How often a waiting source looks at the cancel flag.
const POLL: Duration = Duration::from_millis(100);
/// How many times a complete-looking file that fails to decode is retried.
const MAX_ATTEMPTS: u32 = 5;

/// Options of [`WatchSource`].
pub struct WatchOptions {
    /// Quiet time after the last event before a file with no close-write event is read.
    pub settle: Duration,
    /// Read the snapshots already in the folder first (in natural order of their names).
    pub existing: bool,
    /// Ends the stream when set.
    pub cancel: Arc<AtomicBool>,
    /// Told about files that vanished or could not be read; watching goes on.
    pub on_warning: Box<dyn FnMut(&Error) + Send>,
    /// Each snapshot is checked against these from its header before it is decoded.
    pub limits: crate::Limits,
}

impl Default for WatchOptions {
    fn default() -> Self {
        WatchOptions {
            settle: Duration::from_millis(200),
            existing: true,
            cancel: Arc::new(AtomicBool::new(false)),
            on_warning: Box::new(|_| {}),
            limits: crate::Limits::default(),
        }
    }
}

#[derive(Copy, Clone, Debug, PartialEq, Eq)]
struct Fingerprint {
    len: u64,
    mtime: Option<SystemTime>,
    inode: u64,
}

fn fingerprint(m: &std::fs::Metadata) -> Fingerprint {
    Fingerprint {
        len: m.len(),
        mtime: m.modified().ok(),
        inode: inode(m),
    }
}

fn inode(m: &std::fs::Metadata) -> u64 {
    #[cfg(unix)]
    return std::os::unix::fs::MetadataExt::ino(m);
    #[cfg(not(unix))]
    return 0;
}

/// What, besides the fingerprint, brings a skipped file back: its permissions.
fn permissions(m: &std::fs::Metadata) -> u32 {
    #[cfg(unix)]
    return std::os::unix::fs::PermissionsExt::mode(&m.permissions());
    #[cfg(not(unix))]
    return m.permissions().readonly() as u32;
}

/// What the events say about a file's writer.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum Writer {
    /// Closed after writing, or renamed in: complete.
    Closed,
    /// Written to, not closed yet.
    Open,
    /// Present when watching started: nothing known.
    Unknown,
}

/// Whether this platform's watcher reports close-write events.
const REPORTS_CLOSE_WRITE: bool = cfg!(any(target_os = "linux", target_os = "android"));

struct Candidate {
    path: PathBuf,
    /// Order of first appearance.
    seq: u64,
    /// Last event or observed change.
    changed_at: Instant,
    /// What is known about its writer.
    state: Writer,
    /// Fingerprint when last looked at.
    seen: Option<Fingerprint>,
    attempts: u32,
}

/// Frames from the snapshots written into a directory.
pub struct WatchSource {
    /// The folder as given (looked for again when it was removed).
    given: PathBuf,
    /// The folder, canonical.
    dir: PathBuf,
    /// The watched folder's inode: another one at the same path is a new folder.
    dir_inode: u64,
    /// `None` while the folder is gone.
    watcher: Option<notify::RecommendedWatcher>,
    /// The watcher reported the folder itself deleted or moved. Needed besides the inode
    /// check: a folder recreated at once often gets the freed inode back (ext4), while the
    /// old watch is dead.
    folder_gone: bool,
    events: Receiver<notify::Result<Event>>,
    candidates: Vec<Candidate>,
    done: HashMap<PathBuf, Fingerprint>,
    /// Files that could not be read or decoded, skipped until their fingerprint or
    /// permissions change.
    skipped: HashMap<PathBuf, (Fingerprint, u32)>,
    /// Files reported as vanished: the events that trail a deletion (a close by the writer)
    /// must not report them again. Forgotten when a file of that name is created.
    vanished: HashSet<PathBuf>,
    names: FrameNames,
    next_index: u64,
    next_seq: u64,
    options: WatchOptions,
}

/// Whether `path` is a snapshot of `dir`: a visible `.png`/`.jpg`/`.jpeg` directly in it.
fn is_snapshot(dir: &Path, path: &Path) -> bool {
    if path.parent() != Some(dir) {
        return false;
    }
    let Some(name) = path.file_name().map(|n| n.to_string_lossy()) else {
        return false;
    };
    if name.starts_with('.') {
        return false;
    }
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    matches!(ext.as_deref(), Some("png" | "jpg" | "jpeg"))
}

impl WatchSource {
    /// Starts watching `dir` (which must exist).
    pub fn new(dir: &Path, options: WatchOptions) -> Result<WatchSource, Error> {
        let meta = std::fs::metadata(dir).map_err(|e| Error::io(dir, e))?;
        if !meta.is_dir() {
            return Err(Error::decode(dir, "is not a folder: watch needs a folder"));
        }
        let given = dir.to_path_buf();
        let (dir, dir_inode, watcher, events) = start_watching(dir)?;
        let mut source = WatchSource {
            given,
            dir,
            dir_inode,
            watcher: Some(watcher),
            folder_gone: false,
            events,
            candidates: Vec::new(),
            done: HashMap::new(),
            skipped: HashMap::new(),
            vanished: HashSet::new(),
            names: FrameNames::new(),
            next_index: 0,
            next_seq: 0,
            options,
        };
        if source.options.existing {
            source.rescan()?;
        }
        Ok(source)
    }

    /// The folder being watched (canonical).
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Whether the watched folder is still there (the same folder, not a new one at its path).
    fn folder_is_there(&self) -> bool {
        match std::fs::metadata(&self.dir) {
            Ok(m) => m.is_dir() && inode(&m) == self.dir_inode,
            Err(_) => false,
        }
    }

    /// The folder was removed or moved away: stop watching it, forget its files.
    fn lose_folder(&mut self) {
        self.watcher = None;
        self.folder_gone = false;
        // A folder at this path later is a new one: all its snapshots are new.
        self.candidates.clear();
        self.done.clear();
        self.skipped.clear();
        self.vanished.clear();
        let e = Error::decode(
            &self.dir,
            "the watched folder was removed or moved away; waiting for it to come back",
        );
        self.warn(e);
    }

    /// Watches the folder again if one is back at its path; whether it is.
    fn find_folder(&mut self) -> bool {
        if !std::fs::metadata(&self.given).is_ok_and(|m| m.is_dir()) {
            return false;
        }
        let Ok((dir, dir_inode, watcher, events)) = start_watching(&self.given) else {
            return false; // gone again, or not readable yet: look again later
        };
        (self.dir, self.dir_inode) = (dir, dir_inode);
        self.watcher = Some(watcher);
        self.events = events;
        let e = Error::decode(&self.dir, "the watched folder is back; watching it again");
        self.warn(e);
        // Its snapshots count as files already there at the start.
        if let Err(e) = self.rescan() {
            self.warn(e);
        }
        true
    }

    /// The file name of each frame, by `frame_index`.
    pub fn names(&self) -> FrameNames {
        self.names.clone()
    }

    /// Adds every snapshot in the folder not already read as it is now, in natural order.
    fn rescan(&mut self) -> Result<(), Error> {
        let mut found: Vec<(String, PathBuf)> = Vec::new();
        for entry in std::fs::read_dir(&self.dir).map_err(|e| Error::io(&self.dir, e))? {
            let Ok(entry) = entry else { continue };
            let path = entry.path();
            if is_snapshot(&self.dir, &path) {
                found.push((entry.file_name().to_string_lossy().into_owned(), path));
            }
        }
        found.sort_by(|a, b| natural_cmp(&a.0, &b.0));
        for (_, path) in found {
            // Nothing is known about the writers of files already there.
            self.touch(path, Writer::Unknown);
        }
        Ok(())
    }

    /// Records activity on `path`.
    fn touch(&mut self, path: PathBuf, state: Writer) {
        let now = Instant::now();
        match self.candidates.iter_mut().find(|c| c.path == path) {
            Some(c) => {
                c.changed_at = now;
                c.state = state;
            }
            None => {
                self.candidates.push(Candidate {
                    path,
                    seq: self.next_seq,
                    changed_at: now,
                    state,
                    seen: None,
                    attempts: 0,
                });
                self.next_seq += 1;
            }
        }
    }

    fn handle(&mut self, event: Event) {
        if event.paths.iter().any(|p| p == &self.dir)
            && matches!(
                event.kind,
                EventKind::Remove(_) | EventKind::Modify(ModifyKind::Name(_))
            )
        {
            self.folder_gone = true;
            return;
        }
        if event.need_rescan() {
            if let Err(e) = self.rescan() {
                self.warn(e);
            }
            return;
        }
        let paths: Vec<PathBuf> = event
            .paths
            .iter()
            .filter(|p| is_snapshot(&self.dir, p))
            .cloned()
            .collect();
        match event.kind {
            EventKind::Access(AccessKind::Close(AccessMode::Write)) => {
                for p in paths {
                    match self.candidates.iter_mut().find(|c| c.path == p) {
                        // A writer seen at work is done.
                        Some(c) if c.state == Writer::Open => c.state = Writer::Closed,
                        // No write seen since it was found: the close trails writes made
                        // before (a file already there whose writer, or a forked process
                        // holding a copy of its descriptor until it execs, closes it only
                        // now). It says nothing new, and must not put the file ahead of the
                        // others found with it, which wait the settle time.
                        Some(_) => {}
                        None => self.touch(p, Writer::Closed),
                    }
                }
            }
            EventKind::Modify(ModifyKind::Name(RenameMode::To)) => {
                for p in paths {
                    self.vanished.remove(&p);
                    self.touch(p, Writer::Closed);
                }
            }
            EventKind::Modify(ModifyKind::Name(RenameMode::Both)) => {
                // paths = [from, to]: the new name arrived complete.
                if let Some(to) = event.paths.get(1) {
                    if is_snapshot(&self.dir, to) {
                        self.vanished.remove(to);
                        self.touch(to.clone(), Writer::Closed);
                    }
                }
            }
            EventKind::Modify(ModifyKind::Name(_)) | EventKind::Remove(_) => {
                // Gone (or renamed away): reading it will tell; nothing to do yet.
            }
            EventKind::Modify(ModifyKind::Metadata(_)) => {
                // Permissions or times changed, not the content: a file skipped for want of
                // read permission may be readable now. No writer is known to be at work.
                for p in paths {
                    if !self.candidates.iter().any(|c| c.path == p) {
                        self.touch(p, Writer::Unknown);
                    }
                }
            }
            EventKind::Create(_) | EventKind::Modify(_) => {
                for p in paths {
                    if matches!(event.kind, EventKind::Create(_)) {
                        self.vanished.remove(&p);
                    }
                    self.touch(p, Writer::Open);
                }
            }
            _ => {}
        }
    }

    fn warn(&mut self, e: Error) {
        (self.options.on_warning)(&e);
    }

    /// Reports a snapshot deleted before it could be read, once.
    fn report_vanished(&mut self, path: PathBuf) {
        if !self.vanished.contains(&path) {
            self.warn(Error::decode(
                &path,
                "vanished before it could be read; skipped",
            ));
            self.vanished.insert(path);
        }
    }

    /// Reads the first ready candidate, if any; returns how long to wait otherwise.
    fn try_ready(&mut self) -> Result<Result<Frame, Duration>, Error> {
        let now = Instant::now();
        let quiet = QuietTimes::new(self.options.settle);
        let mut wait = POLL;
        // Ready ones in order of readiness, then of appearance.
        self.candidates.sort_by_key(|c| (c.changed_at, c.seq));
        let mut i = 0;
        while i < self.candidates.len() {
            let Some((fp, mode)) = self.look(i) else {
                continue; // dropped: the next one is at `i` now
            };
            if let Some(left) = self.candidates[i].settling(fp, now, &quiet) {
                wait = wait.min(left);
                i += 1;
                continue;
            }
            match self.read(i, fp, mode) {
                Read::Frame(frame) => return Ok(Ok(frame)),
                Read::Kept => i += 1,
                Read::Dropped => {}
            }
        }
        Ok(Err(wait))
    }

    /// Candidate `i`'s fingerprint and permissions as it is now, or `None` when it is dropped:
    /// gone (reported), not a file, or already read (or given up on) as it is now.
    fn look(&mut self, i: usize) -> Option<(Fingerprint, u32)> {
        let meta = match std::fs::metadata(&self.candidates[i].path) {
            Ok(m) if m.is_file() => m,
            Ok(_) => {
                self.candidates.remove(i);
                return None;
            }
            Err(e) => {
                let c = self.candidates.remove(i);
                if e.kind() == std::io::ErrorKind::NotFound {
                    self.report_vanished(c.path);
                } else {
                    self.warn(Error::io(&c.path, e));
                }
                return None;
            }
        };
        let fp = fingerprint(&meta);
        let mode = permissions(&meta);
        let path = &self.candidates[i].path;
        if self.done.get(path) == Some(&fp) || self.skipped.get(path) == Some(&(fp, mode)) {
            self.candidates.remove(i);
            return None;
        }
        Some((fp, mode))
    }

    /// Reads candidate `i`, which looks complete. Waiting does not help a file that cannot be
    /// read: it is skipped until it changes. One that fails to decode may still be being
    /// written: it is tried again, up to [`MAX_ATTEMPTS`] times.
    fn read(&mut self, i: usize, fp: Fingerprint, mode: u32) -> Read {
        let path = self.candidates[i].path.clone();
        match read_still_with(&path, &self.options.limits) {
            Ok(image) => self.accept(i, fp, image),
            Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
                let c = self.candidates.remove(i);
                self.report_vanished(c.path);
                Read::Dropped
            }
            Err(Error::Io { source, .. })
                if source.kind() == std::io::ErrorKind::PermissionDenied =>
            {
                // A chmod brings it back.
                let c = self.candidates.remove(i);
                self.skipped.insert(c.path.clone(), (fp, mode));
                self.warn(Error::decode(
                    &c.path,
                    format!(
                        "cannot be read ({source}); skipped until its permissions or \
                         content change"
                    ),
                ));
                Read::Dropped
            }
            Err(e) => {
                let c = &mut self.candidates[i];
                c.attempts += 1;
                c.changed_at = Instant::now();
                c.state = Writer::Unknown;
                if c.attempts < MAX_ATTEMPTS {
                    return Read::Kept;
                }
                let c = self.candidates.remove(i);
                self.skipped.insert(c.path, (fp, mode)); // until it changes
                self.warn(e);
                Read::Dropped
            }
        }
    }

    /// Candidate `i`'s snapshot, decoded as `image`, becomes the next frame if the file did
    /// not change while it was read; if it did, a writer is at it again and it waits.
    fn accept(&mut self, i: usize, fp: Fingerprint, image: crate::image::Image) -> Read {
        let path = self.candidates[i].path.clone();
        let after = std::fs::metadata(&path).map(|m| fingerprint(&m)).ok();
        if after != Some(fp) {
            let c = &mut self.candidates[i];
            c.seen = after;
            c.changed_at = Instant::now();
            c.state = Writer::Open;
            return Read::Kept;
        }
        self.candidates.remove(i);
        self.done.insert(path.clone(), fp);
        let index = self.next_index;
        self.next_index += 1;
        self.names.insert_file(index, &path);
        Read::Frame(Frame::new(image, index))
    }
}

/// What became of a candidate that was read.
enum Read {
    Frame(Frame),
    /// Still a candidate: looked at again later.
    Kept,
    /// No longer a candidate.
    Dropped,
}

/// How long a file must go unchanged before it is read, by what is known of its writer.
struct QuietTimes {
    /// Closed after writing, or renamed in: complete, so an eighth of the settle time.
    closed: Duration,
    /// Nothing known: the settle time.
    unknown: Duration,
    /// Written to and not closed: where close-write is reported, a writer that pauses for
    /// 10 settle times without closing is taken as done; elsewhere no close is ever seen.
    open: Duration,
}

impl QuietTimes {
    fn new(settle: Duration) -> QuietTimes {
        QuietTimes {
            closed: settle / 8,
            unknown: settle,
            open: if REPORTS_CLOSE_WRITE {
                settle * 10
            } else {
                settle
            },
        }
    }
}

impl Candidate {
    /// How long this file must still go unchanged before it is read (`None`: ready), its
    /// fingerprint now `fp`. A change since the last look starts its quiet time again (at the
    /// first look the time of the event that brought it stands). An empty file is never
    /// ready: its writer has created it and not written it yet.
    fn settling(&mut self, fp: Fingerprint, now: Instant, quiet: &QuietTimes) -> Option<Duration> {
        if self.seen != Some(fp) {
            if self.seen.is_some() {
                self.changed_at = now;
            }
            self.seen = Some(fp);
        }
        let quiet_for = now.saturating_duration_since(self.changed_at);
        let needed = match self.state {
            Writer::Closed => quiet.closed,
            Writer::Unknown => quiet.unknown,
            Writer::Open => quiet.open,
        };
        (quiet_for < needed || fp.len == 0).then(|| {
            needed
                .saturating_sub(quiet_for)
                .max(Duration::from_millis(5))
        })
    }
}

/// Watches `dir`: its canonical path (events carry absolute paths), its inode, the watcher
/// and its events.
#[allow(clippy::type_complexity)]
fn start_watching(
    dir: &Path,
) -> Result<
    (
        PathBuf,
        u64,
        notify::RecommendedWatcher,
        Receiver<notify::Result<Event>>,
    ),
    Error,
> {
    let dir = dir.canonicalize().map_err(|e| Error::io(dir, e))?;
    let meta = std::fs::metadata(&dir).map_err(|e| Error::io(&dir, e))?;
    let (tx, events) = std::sync::mpsc::channel();
    let watch_error = |e: notify::Error| {
        Error::io(
            &dir,
            std::io::Error::other(format!("cannot watch the folder: {e}")),
        )
    };
    let mut watcher = notify::recommended_watcher(tx).map_err(watch_error)?;
    watcher
        .watch(&dir, RecursiveMode::NonRecursive)
        .map_err(watch_error)?;
    Ok((dir, inode(&meta), watcher, events))
}

impl FrameSource for WatchSource {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        loop {
            if self.options.cancel.load(Ordering::Relaxed) {
                return Ok(None);
            }
            if self.watcher.is_none() {
                // The folder is gone: look for it again every POLL.
                if !self.find_folder() {
                    std::thread::sleep(POLL);
                }
                continue;
            }
            while let Ok(event) = self.events.try_recv() {
                match event {
                    Ok(ev) => self.handle(ev),
                    Err(e) => self.warn(Error::io(
                        &self.dir,
                        std::io::Error::other(format!("watch error: {e}")),
                    )),
                }
            }
            // After the events: a deleted folder's files are not reported one by one.
            if self.folder_gone || !self.folder_is_there() {
                self.lose_folder();
                continue;
            }
            let wait = match self.try_ready()? {
                Ok(frame) => return Ok(Some(frame)),
                Err(wait) => wait,
            };
            match self.events.recv_timeout(wait.min(POLL)) {
                Ok(Ok(ev)) => self.handle(ev),
                Ok(Err(e)) => self.warn(Error::io(
                    &self.dir,
                    std::io::Error::other(format!("watch error: {e}")),
                )),
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(Error::io(
                        &self.dir,
                        std::io::Error::other("the folder watcher stopped"),
                    ))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn png(i: u8) -> Vec<u8> {
        let img = image::RgbImage::from_pixel(8, 6, image::Rgb([i, 0, 0]));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    /// snap2 was written in full before watching started but is closed only after (a slow
    /// exporter, or a process forked meanwhile holding a copy of the descriptor until it
    /// execs, as `cargo test` spawning another test's child does): its close-write event must
    /// not put it ahead of snap1. Files already there are read in natural order.
    #[test]
    fn a_close_after_the_start_keeps_files_already_there_in_natural_order() {
        let dir = tempfile::tempdir().unwrap();
        for n in [10, 1] {
            std::fs::write(dir.path().join(format!("snap{n}.png")), png(n)).unwrap();
        }
        let mut writer = std::fs::File::create(dir.path().join("snap2.png")).unwrap();
        writer.write_all(&png(2)).unwrap();
        let mut source = WatchSource::new(dir.path(), WatchOptions::default()).unwrap();
        drop(writer);
        let snap2 = source.dir.join("snap2.png");
        loop {
            let event = source.events.recv_timeout(Duration::from_secs(10));
            let event = event.expect("the close-write event of snap2").unwrap();
            let closes_snap2 = event.kind
                == EventKind::Access(AccessKind::Close(AccessMode::Write))
                && event.paths.contains(&snap2);
            source.handle(event);
            if closes_snap2 {
                break;
            }
        }
        // Found together (the same time, pinned here): none is ready before the others.
        let quiet = QuietTimes::new(source.options.settle);
        let found = Instant::now();
        let closed_wait_later = found + quiet.closed;
        for c in &mut source.candidates {
            c.changed_at = found;
            let fp = fingerprint(&std::fs::metadata(&c.path).unwrap());
            let ready = c.settling(fp, closed_wait_later, &quiet).is_none();
            assert!(!ready, "{} ready before the others", c.path.display());
        }
        let mut names = Vec::new();
        for _ in 0..3 {
            let frame = source.next_frame().unwrap().unwrap();
            names.push(source.names().get(frame.frame_index).unwrap());
        }
        assert_eq!(names, ["snap1.png", "snap2.png", "snap10.png"]);
    }
}
