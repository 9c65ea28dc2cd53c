//! `vizretarget watch DIR -o OUTDIR`: snapshots in, same-named retargeted files out.

use super::args::WatchArgs;
use super::report::{summary_line, PerFrame, Reporter};
use super::stream::same_folder;
use super::{interrupt, library_error, Outcome};
use anyhow::{bail, Context, Result};
use std::sync::atomic::Ordering;
use std::time::Duration;
use vizretarget::io::{open_watch, PngSeqSink, WatchOptions};
use vizretarget::stream::Progress;
use vizretarget::{Options, Pipeline, Size};

pub fn run(args: &WatchArgs) -> Result<Outcome> {
    let options = Options::default().with_alpha(args.alpha);
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
    let watch_options = WatchOptions {
        settle: Duration::from_millis(args.settle_ms),
        existing: true,
        cancel: cancel.clone(),
        on_warning: Box::new(|e| eprintln!("vizretarget: warning: {e}")),
    };
    let mut input = open_watch(&args.dir, watch_options).map_err(library_error)?;
    let names = input.names.clone();
    let mut sink = match sink {
        Ok(_) => PngSeqSink::create(&args.output, names.clone())?,
        Err(e) => return Err(library_error(e)),
    };
    let from = match (args.size, args.width, args.height) {
        (Some(_), _, _) | (None, Some(_), Some(_)) => input.known_size(),
        _ => input.frame_size()?,
    };
    let target = match (args.size, args.width, args.height, from) {
        (Some((w, h)), _, _, _) => Size::new(w, h)?,
        (None, Some(w), Some(h), _) => Size::new(w, h)?,
        (None, w, h, Some(f)) => Size::new(w.unwrap_or(f.width), h.unwrap_or(f.height))?,
        // Stopped before the first snapshot arrived.
        (None, _, _, None) => return Ok(Outcome::Interrupted),
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
    );
    let result = Pipeline::run(
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
        eprintln!("{}", summary_line(&summary, from, target));
    }
    Ok(if cancel.load(Ordering::SeqCst) {
        Outcome::Interrupted
    } else {
        Outcome::Done
    })
}
