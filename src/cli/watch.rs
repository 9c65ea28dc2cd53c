//! `vizretarget watch DIR -o OUTDIR`: snapshots in, same-named retargeted files out.

use super::args::WatchArgs;
use super::report::{summary_line, PerFrame, Reporter};
use super::stream::same_folder;
use super::{interrupt, library_error, Outcome};
use anyhow::{bail, Context, Result};
use std::collections::HashSet;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::Duration;
use vizretarget::io::{open_watch, PngSeqSink, SinkFormat, WatchOptions};
use vizretarget::stream::{FrameSink, Progress};
use vizretarget::{MemoryPlan, Options, Pipeline, Retargeted, Size};

pub fn run(args: &WatchArgs) -> Result<Outcome> {
    let options = Options::default()
        .with_alpha(args.alpha)
        .with_regions(args.regions.into());
    options.validate().map_err(library_error)?;
    if !args.dir.is_dir() {
        bail!("{}: not a folder: watch needs a folder", args.dir.display());
    }
    if same_folder(&args.dir, &args.output) {
        bail!(
            "{}: the output folder must not be the watched one (its outputs would be taken \
             for new snapshots)",
            args.output.display()
        );
    }
    let sink = PngSeqSink::create(&args.output, None);
    // A first signal stops watching between snapshots; the ones in flight are written.
    let cancel = interrupt::stop_gracefully();
    let limits = args.limits.limits(None);
    let watch_options = WatchOptions {
        settle: Duration::from_millis(args.settle_ms),
        existing: true,
        cancel: cancel.clone(),
        on_warning: Box::new(|e| match super::limit_hint_of(e) {
            Some(hint) => eprintln!("vizretarget: warning: {e}; {hint}"),
            None => eprintln!("vizretarget: warning: {e}"),
        }),
        limits: limits.clone(),
    };
    let mut input = open_watch(&args.dir, watch_options).map_err(library_error)?;
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
    // The first snapshot (waited for): the target may depend on its size, the memory plan
    // does. A later, larger snapshot that would not fit the plan stops watching with an error.
    let from = input.frame_size()?;
    let target = match (args.size, args.width, args.height, from) {
        (Some((w, h)), _, _, _) => Size::new(w, h)?,
        (None, Some(w), Some(h), _) => Size::new(w, h)?,
        (None, w, h, Some(f)) => Size::new(w.unwrap_or(f.width), h.unwrap_or(f.height))?,
        // Stopped before the first snapshot arrived.
        (None, _, _, None) => return Ok(Outcome::Interrupted),
    };
    let plan = match from {
        Some(f) => limits.plan_stream(
            &args.dir,
            f,
            target,
            SinkFormat::PngSeq.held_bytes_per_pixel(),
        )?,
        None => MemoryPlan::unbounded(target, target),
    };
    let reporter = Reporter::new(
        None,
        args.quiet,
        if args.quiet {
            PerFrame::Nothing
        } else {
            PerFrame::Written(args.output.clone())
        },
        names,
        args.stats_json.is_some(),
    )
    .with_failed_writes(failed.clone());
    let result = Pipeline::run_planned(
        &plan,
        target,
        &options,
        &mut *input.source,
        &mut sink,
        &reporter as &dyn Progress,
        &cancel,
    );
    if let Some(path) = &args.stats_json {
        reporter
            .write_json(path, result.as_ref().ok())
            .with_context(|| format!("{}: cannot write the statistics", path.display()))?;
    }
    let summary = result.map_err(library_error)?;
    if !args.quiet {
        let not_written = failed.lock().unwrap_or_else(|e| e.into_inner()).len();
        let note = match not_written {
            0 => String::new(),
            n => format!("; {n} not written"),
        };
        eprintln!("{}{note}", summary_line(&summary, from, target));
    }
    Ok(if cancel.load(Ordering::SeqCst) {
        Outcome::Interrupted
    } else {
        Outcome::Done
    })
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
