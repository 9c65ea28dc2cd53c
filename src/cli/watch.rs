//! `vizretarget watch DIR -o OUTDIR`: snapshots in, same-named retargeted files out.

use super::args::{Target, WatchArgs};
use super::report::{PerFrame, Reporter};
use super::stream::same_folder;
use super::{interrupt, library_error, run_error, usage, Outcome};
use anyhow::{bail, Context, Result};
use std::collections::HashSet;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use vizretarget::io::{open_watch, FrameNames, PngSeqSink, SinkFormat, WatchOptions};
use vizretarget::stream::{FrameSink, FrameSource, Progress};
use vizretarget::{Frame, Limits, Options, Pipeline, Retargeted, RunSummary, Size};

pub fn run(args: &WatchArgs) -> Result<Outcome> {
    let options = check_request(args)?;
    let sink = PngSeqSink::create(&args.output, None);
    // A first signal stops watching between snapshots; the ones in flight are written.
    let cancel = interrupt::stop_gracefully();
    let limits = args.limits.limits(None);
    let mut input =
        open_watch(&args.dir, watch_options(args, &cancel, &limits)).map_err(library_error)?;
    let names = input.names.clone();
    let sink = match sink {
        Ok(_) => PngSeqSink::create(&args.output, names.clone())?,
        Err(e) => return Err(library_error(e)),
    };
    let failed = Arc::new(Mutex::new(HashSet::new()));
    let mut sink = KeepWatching {
        inner: sink,
        failed: failed.clone(),
    };
    let reporter = Reporter::new(
        None,
        args.quiet,
        if args.quiet {
            PerFrame::Nothing
        } else {
            PerFrame::Written(args.output.clone())
        },
        names.clone(),
        args.stats_json.is_some(),
    )
    .with_failed_writes(failed.clone());
    // Each snapshot gets its own target (a percentage, or the side not given, is taken from
    // it): the pipeline runs while the target stays the same, and starts again with the next
    // target when a snapshot needs another one.
    let mut group = SameTarget {
        inner: &mut *input.source,
        spec: Target::of(args.size, args.width, args.height),
        names,
        current: None,
        held: None,
    };
    let runs = Runs {
        args,
        limits: &limits,
        options: &options,
        cancel: &cancel,
    };
    let (total, result) = runs.until_stopped(&mut group, &mut sink, &reporter)?;
    if let Some(path) = &args.stats_json {
        reporter
            .write_json(path, result.as_ref().ok().map(|_| &total))
            .with_context(|| format!("{}: cannot write the statistics", path.display()))?;
    }
    result.map_err(run_error)?;
    if !args.quiet {
        let not_written = failed.lock().unwrap_or_else(|e| e.into_inner()).len();
        let note = match not_written {
            0 => String::new(),
            n => format!("; {n} not written"),
        };
        eprintln!("{}{note}", reporter.snapshot_line(total.cancelled));
    }
    Ok(if cancel.load(Ordering::SeqCst) {
        Outcome::Interrupted
    } else {
        Outcome::Done
    })
}

/// Checks what can be refused before watching starts: the options, the folder, and an output
/// folder that would feed the watch its own outputs. The options to run with.
fn check_request(args: &WatchArgs) -> Result<Options> {
    let options = Options::default()
        .with_alpha(args.alpha)
        .with_regions(args.regions.into())
        .with_fill(args.fill)
        .with_layout(!args.no_layout);
    options.validate().map_err(library_error)?;
    match std::fs::metadata(&args.dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => bail!("{}: not a folder: watch needs a folder", args.dir.display()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => bail!(
            "{}: does not exist: watch needs an existing folder",
            args.dir.display()
        ),
        Err(e) => bail!("{}: cannot read: {e}", args.dir.display()),
    }
    if same_folder(&args.dir, &args.output) {
        usage!(
            "{}: the output folder must not be the watched one (its outputs would be taken \
             for new snapshots)",
            args.output.display()
        );
    }
    Ok(options)
}

/// How the folder is watched: warnings (a snapshot that vanished or cannot be read) are
/// printed and watching goes on, with the option that raises a limit a snapshot went past.
fn watch_options(args: &WatchArgs, cancel: &Arc<AtomicBool>, limits: &Limits) -> WatchOptions {
    WatchOptions {
        settle: Duration::from_millis(args.settle_ms),
        existing: true,
        cancel: cancel.clone(),
        on_warning: Box::new(|e| match super::limit_hint_of(e) {
            Some(hint) => eprintln!("vizretarget: warning: {e}; {hint}"),
            None => eprintln!("vizretarget: warning: {e}"),
        }),
        limits: limits.clone(),
    }
}

/// What every run of the pipeline over the watched folder shares.
struct Runs<'a> {
    args: &'a WatchArgs,
    limits: &'a Limits,
    options: &'a Options,
    cancel: &'a Arc<AtomicBool>,
}

impl Runs<'_> {
    /// Runs the pipeline once per target, each run planned for the size of its first snapshot
    /// (waited for): a later, larger snapshot that would not fit the plan stops watching with
    /// an error. Returns the runs' summaries added up, and how the last run ended.
    fn until_stopped(
        &self,
        group: &mut SameTarget<'_>,
        sink: &mut KeepWatching,
        reporter: &Reporter,
    ) -> Result<(RunSummary, Result<(), vizretarget::Error>)> {
        let mut total = RunSummary::default();
        while let Some((from, target)) = group.start()? {
            let plan = self.limits.plan_stream(
                &self.args.dir,
                from,
                target,
                SinkFormat::PngSeq.held_bytes_per_pixel(),
            )?;
            let run = Pipeline::new(target, self.options).and_then(|p| {
                p.with_plan(plan)
                    .run(group, sink, reporter as &dyn Progress, self.cancel)
            });
            match run {
                Ok(s) => add(&mut total, &s),
                Err(e) => return Ok((total, Err(e))),
            }
            if self.cancel.load(Ordering::SeqCst) || group.held.is_none() {
                break;
            }
        }
        Ok((total, Ok(())))
    }
}

/// Adds one run's summary to the watch's.
fn add(total: &mut RunSummary, s: &RunSummary) {
    total.frames += s.frames;
    total.elapsed += s.elapsed;
    total.reused += s.reused;
    total.updated += s.updated;
    total.rebuilt += s.rebuilt;
    total.stage_ms.vsm_ms += s.stage_ms.vsm_ms;
    total.stage_ms.mesh_ms += s.stage_ms.mesh_ms;
    total.stage_ms.solve_ms += s.stage_ms.solve_ms;
    total.stage_ms.render_ms += s.stage_ms.render_ms;
    total.output_closed |= s.output_closed;
    total.cancelled |= s.cancelled;
}

/// The snapshots of one run of the pipeline: those whose target is `current`. The first one
/// with another target is held back and ends the run; the next run starts with it.
struct SameTarget<'a> {
    inner: &'a mut dyn FrameSource,
    spec: Target,
    names: Option<FrameNames>,
    current: Option<Size>,
    held: Option<(Frame, Size)>,
}

impl SameTarget<'_> {
    /// Waits for the first snapshot of the next run: its size and target, or `None` when
    /// watching stopped before one arrived.
    fn start(&mut self) -> Result<Option<(Size, Size)>> {
        if self.held.is_none() {
            match self.next_with_target().map_err(run_error)? {
                Some(held) => self.held = Some(held),
                None => return Ok(None),
            }
        }
        Ok(self.held.as_ref().map(|(f, t)| {
            self.current = Some(*t);
            (f.image.size(), *t)
        }))
    }

    /// The next snapshot with its target. One whose target is out of range (a percentage
    /// too large for it) is skipped with a warning: watching goes on.
    fn next_with_target(&mut self) -> Result<Option<(Frame, Size)>, vizretarget::Error> {
        loop {
            let Some(frame) = self.inner.next_frame()? else {
                return Ok(None);
            };
            match self.spec.resolve(frame.image.size()) {
                Ok(t) => return Ok(Some((frame, t))),
                Err(e) => {
                    let name = self.names.as_ref().and_then(|n| n.get(frame.frame_index));
                    eprintln!(
                        "vizretarget: warning: {}: {e}; skipped",
                        name.as_deref().unwrap_or("snapshot")
                    );
                }
            }
        }
    }
}

impl FrameSource for SameTarget<'_> {
    fn next_frame(&mut self) -> Result<Option<Frame>, vizretarget::Error> {
        let (frame, target) = match self.held.take() {
            Some(held) => held,
            None => match self.next_with_target()? {
                Some(next) => next,
                None => return Ok(None),
            },
        };
        if Some(target) != self.current {
            self.held = Some((frame, target));
            return Ok(None);
        }
        Ok(Some(frame))
    }
}

/// The output folder's sink that outlives a failed write (OUTDIR made read-only, a full
/// disk): the error is reported with the file's name, that output is skipped, and watching
/// goes on. A skipped snapshot is not retried by itself; it is retargeted again when it
/// changes (a new version, or a touch).
struct KeepWatching {
    inner: PngSeqSink,
    /// Frames whose output could not be written.
    failed: Arc<Mutex<HashSet<u64>>>,
}

impl FrameSink for KeepWatching {
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), vizretarget::Error> {
        match self.inner.write_frame(frame) {
            Ok(()) => Ok(()),
            Err(e) => {
                let (name, _) = self.inner.file_for(frame.frame_index);
                eprintln!(
                    "vizretarget: error: {e}; {name} not written (it is retargeted again when \
                     its snapshot changes); watching goes on"
                );
                self.failed
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .insert(frame.frame_index);
                Ok(())
            }
        }
    }

    fn finish(&mut self) -> Result<(), vizretarget::Error> {
        self.inner.finish()
    }
}
