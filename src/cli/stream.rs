//! A stream of frames in, a stream out, through [`Pipeline::run`].

use super::report::{summary_line, PerFrame, Reporter};
use super::{interrupt, library_error, run_error, usage, Outcome};
use crate::cli::args::{Cli, InputArg};
use anyhow::{bail, Context, Result};
use std::io::IsTerminal;
use std::path::Path;
use std::sync::atomic::Ordering;
use vizretarget::io::MarkedSource;
use vizretarget::io::{
    is_std, open_input_with, open_peeked, open_sink, FrameRate, Input, InputFormat, InputKind,
    Peeked, SinkFormat, SinkOptions, STDIN_NAME,
};
use vizretarget::stream::{DetachedSource, Progress, VecSource};
use vizretarget::{Limits, Options, Pipeline, Regions, RunSummary, Size};

/// Runs the stream job; `peeked` is what was read of stdin to tell it was no single picture.
pub fn run(
    cli: &Cli,
    input_path: &Path,
    peeked: Option<Peeked>,
    output: &Path,
    format: SinkFormat,
) -> Result<Outcome> {
    let args = &cli.stream;
    let (limits, options) = check_request(cli, input_path, output, format)?;
    // Until the source is detached below, a signal ends the program at once: nothing has
    // been written yet, and opening stdin may wait on a writer that sends nothing.
    let mut input = open_frames(cli, input_path, peeked, &limits)?;
    // From here a first signal stops the reading (even a read that is blocked) and the frames
    // already read are finished and written.
    let cancel = interrupt::stop_gracefully();
    let frames = std::mem::replace(&mut input.source, Box::new(VecSource::new([])));
    input.source = Box::new(DetachedSource::new(frames, cancel.clone()));
    // The first frame's size (from the header, else by reading that frame): the target may
    // depend on it, and the memory plan does.
    let from = input.frame_size().map_err(|e| raw_hint(e, &input))?;
    if from.is_none() && interrupt::interrupted() {
        eprintln!("vizretarget: stopped before the first frame; nothing written");
        return Ok(Outcome::Interrupted);
    }
    let target = match (cli.target().fixed(), from) {
        (Some(t), _) => t,
        (None, Some(f)) => cli.target().resolve(f)?,
        (None, None) => bail!("{}: no frames", input_path.display()),
    };
    let sink_options = sink_options(cli, &input)?;
    let plan = match from {
        Some(f) => limits.plan_stream(input_path, f, target, format.held_bytes_per_pixel())?,
        None => bail!("{}: no frames", input_path.display()),
    };
    let mut sink = open_sink(output, format, sink_options)?;
    let reporter = reporter(cli, &input);
    let result = Pipeline::new(target, &options).and_then(|p| {
        p.with_plan(plan).run(
            &mut *input.source,
            &mut *sink,
            &reporter as &dyn Progress,
            &cancel,
        )
    });
    reporter.finish();
    if let Some(path) = &args.stats_json {
        reporter
            .write_json(path, result.as_ref().ok())
            .with_context(|| format!("{}: cannot write the statistics", path.display()))?;
    }
    let interrupted = cancel.load(Ordering::SeqCst);
    let Some(summary) = summary(result, interrupted, input_path, &input)? else {
        eprintln!("vizretarget: stopped before the first frame; nothing written");
        return Ok(Outcome::Interrupted);
    };
    if !args.quiet && !summary.output_closed {
        let linear = options.effective_regions() == Regions::Affine;
        eprintln!("{}", summary_line(&summary, from, target, linear));
    }
    Ok(if interrupted {
        Outcome::Interrupted
    } else {
        Outcome::Done
    })
}

/// Checks what can be refused before any input is read (where the output goes, the options
/// and the limits, whether the output would overwrite the input): a wrong command fails
/// before it waits on a pipe. The limits and options to run with.
fn check_request(
    cli: &Cli,
    input_path: &Path,
    output: &Path,
    format: SinkFormat,
) -> Result<(Limits, Options)> {
    check_output_place(output, format)?;
    if is_std(output) && format != SinkFormat::PngSeq && std::io::stdout().is_terminal() {
        usage!(
            "refusing to write binary frames to a terminal: pipe stdout into a program \
             (| ffplay -) or give -o FILE"
        );
    }
    if cli.debug_dir.is_some() {
        usage!("--debug-dir is for one picture; for a stream, retarget single frames with it");
    }
    let limits = cli.limits_for(is_std(input_path));
    let mut options = super::marks::apply(
        &cli.vector,
        Options::default()
            .with_alpha(cli.alpha)
            .with_regions(cli.regions.into())
            .with_fill(cli.fill)
            .with_layout(!cli.no_layout),
        &limits,
    )?;
    options.reuse = cli.stream.reuse();
    options.validate().map_err(library_error)?;
    if format == SinkFormat::PngSeq && !is_std(input_path) && same_folder(input_path, output) {
        usage!(
            "{}: writing into the input folder would replace the input frames; choose another \
             output folder",
            output.display()
        );
    }
    Ok((limits, options))
}

/// Opens the input as `--input-format` and `--input-size` say (or stdin from where `peeked`
/// left it), with the vector marks of each frame when `--marks` gives them.
fn open_frames(
    cli: &Cli,
    input_path: &Path,
    peeked: Option<Peeked>,
    limits: &Limits,
) -> Result<Input> {
    let args = &cli.stream;
    let input_size = args
        .input_size
        .map(|(w, h)| Size::new(w, h).map_err(vizretarget::Error::from))
        .transpose()
        .map_err(library_error)?;
    let input_format = match args.input_format {
        InputArg::Auto => InputFormat::Auto,
        InputArg::Rgba => InputFormat::Rgba,
        InputArg::Rgb24 => InputFormat::Rgb24,
        InputArg::Y4m => InputFormat::Y4m,
        InputArg::Png => InputFormat::PngStream,
    };
    let opened = match peeked {
        Some(p) => open_peeked(p, limits),
        None => open_input_with(input_path, input_format, input_size, limits),
    };
    let mut input = opened
        .map_err(|e| empty_stdin_hint(e, input_path))
        .map_err(library_error)?;
    if let Some(marks) = super::marks::frame_marks(&cli.vector, input_path, &input, args.quiet)? {
        let frames = std::mem::replace(&mut input.source, Box::new(VecSource::new([])));
        input.source = Box::new(MarkedSource::new(frames, marks));
    }
    Ok(input)
}

/// What the sink takes from the input: its frame rate (unless `--fps` sets one), its loop
/// count and its frames' names.
fn sink_options(cli: &Cli, input: &Input) -> Result<SinkOptions> {
    let frame_rate = match cli.stream.fps {
        Some(f) => Some(FrameRate::from_fps(f).context("--fps is out of range")?),
        None => input.frame_rate,
    };
    Ok(SinkOptions {
        frame_rate,
        repeat: input.source.repeat(),
        names: input.names.clone(),
    })
}

/// The progress bar, per-frame lines and statistics the options ask for.
fn reporter(cli: &Cli, input: &Input) -> Reporter {
    let args = &cli.stream;
    Reporter::new(
        input.source.len_hint(),
        args.quiet,
        if cli.stats {
            PerFrame::Stats
        } else {
            PerFrame::Nothing
        },
        input.names.clone(),
        args.stats_json.is_some(),
    )
}

/// The run's summary, or `None` when a signal stopped it before the first frame (nothing is
/// written then). A run that wrote no frame is an error naming the input, not the output:
/// the input is what was empty.
fn summary(
    result: Result<RunSummary, vizretarget::Error>,
    interrupted: bool,
    input_path: &Path,
    input: &Input,
) -> Result<Option<RunSummary>> {
    let input_name = if is_std(input_path) {
        Path::new(STDIN_NAME)
    } else {
        input_path
    };
    let summary = match result {
        // A GIF needs a frame: stopped before the first one, no file is written.
        Err(vizretarget::Error::NoFrames(_)) if interrupted => return Ok(None),
        // An empty input (raw stdin, whose size is given, is only found empty here) makes
        // the sink refuse to write nothing: the input is what to name.
        Err(vizretarget::Error::NoFrames(p)) if p != input_path => {
            bail!(
                "{}: no frames{}",
                input_name.display(),
                nothing_arrived(input_path)
            )
        }
        r => r.map_err(|e| raw_hint(e, input)).map_err(run_error)?,
    };
    if summary.frames == 0 && !interrupted && !summary.output_closed {
        bail!(
            "{}: no frames{}",
            input_name.display(),
            nothing_arrived(input_path)
        );
    }
    Ok(Some(summary))
}

/// A raw frame cut short usually means a wrong `--input-size` or `--input-format`: say so.
fn raw_hint(e: vizretarget::Error, input: &Input) -> vizretarget::Error {
    match (e, input.kind) {
        (
            vizretarget::Error::TruncatedFrame {
                path,
                frame_index,
                expected,
                got,
            },
            InputKind::Raw(f),
        ) => vizretarget::Error::Decode {
            path,
            message: format!(
                "frame {frame_index} is incomplete: {got} of {expected} bytes ({} {} frames \
                 are {expected} bytes each: check --input-size and --input-format)",
                input
                    .known_size()
                    .map_or_else(String::new, |s| s.to_string()),
                f.name()
            ),
        },
        (e, _) => e,
    }
}

/// What may have gone wrong upstream when stdin brought no frame.
fn nothing_arrived(input_path: &Path) -> &'static str {
    if is_std(input_path) {
        ": nothing arrived on stdin: did the program writing to the pipe fail?"
    } else {
        ""
    }
}

/// Nothing at all on stdin most often means the program writing into the pipe failed (its
/// own error is above ours) or wrote nothing it could: say so.
fn empty_stdin_hint(e: vizretarget::Error, input_path: &Path) -> vizretarget::Error {
    match e {
        vizretarget::Error::Decode { path, message }
            if is_std(input_path) && message.starts_with("the input is empty") =>
        {
            vizretarget::Error::Decode {
                path,
                message: "nothing arrived on stdin: did the program writing to the pipe fail? \
                          (ffmpeg needs -pix_fmt yuv420p for -f yuv4mpegpipe from a GIF or RGB \
                          source)"
                    .into(),
            }
        }
        e => e,
    }
}

/// Fails before the work if the output cannot be written where asked.
pub fn check_output_place(output: &Path, format: SinkFormat) -> Result<()> {
    if is_std(output) {
        return Ok(());
    }
    let parent = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if format == SinkFormat::PngSeq {
        if output.exists() && !output.is_dir() {
            bail!("{}: exists and is not a folder", output.display());
        }
    } else if output.is_dir() {
        bail!(
            "{}: is a folder; give a file name, or --output-format png-seq",
            output.display()
        );
    }
    if !parent.is_dir() {
        bail!(
            "{}: the output folder {} does not exist",
            output.display(),
            parent.display()
        );
    }
    Ok(())
}

/// Whether two paths name the same existing folder.
pub fn same_folder(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}
