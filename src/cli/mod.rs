//! The command line: parses, wires the library's public API, reports. No method code here.
//!
//! - `still.rs`: one picture in, one out (`INPUT.png -o OUT.png`), by any `--method`.
//! - `stream.rs`: frames in (GIF, folder, stdin), frames out (GIF, folder, stdout), through
//!   [`vizretarget::Pipeline`].
//! - `watch.rs`: `vizretarget watch DIR -o OUTDIR`.
//! - `compare.rs`: `vizretarget compare INPUT -o SHEET.png`: every method side by side.
//! - `marks.rs`: `--marks` and `--enhance*` (vector marks §5.3, content enhancement §5.4).
//! - `input.rs`: what the input holds (one picture, an animation, a stream), stdin by content.
//! - `report.rs`: progress bar, summary line, `--stats-json`; `interrupt.rs`: SIGINT (Ctrl-C) and SIGTERM.

mod args;
mod compare;
mod input;
mod interrupt;
mod marks;
mod report;
mod still;
mod stream;
mod watch;

pub use args::Cli;

use anyhow::{anyhow, Context, Result};
use args::{Command, OutputArg};
use input::{picture, picture_name, Shape};
use vizretarget::io::{
    is_device, is_std, resolve_output, Destination, OutputChoice, OutputFormat, SinkFormat,
};

/// How a successful run ended.
pub enum Outcome {
    Done,
    /// Stopped by SIGINT or SIGTERM (exit 128 + the signal: 130, 143).
    Interrupted,
}

/// A usage error found after parsing: an option's value, or a combination of options and
/// inputs, that cannot work. Exit 2, like clap's own, so that a script can tell a wrong
/// command from a failed run (1).
#[derive(Debug)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// Returns a [`UsageError`] from the enclosing function.
macro_rules! usage {
    ($($arg:tt)*) => {
        return Err($crate::cli::UsageError(format!($($arg)*)).into())
    };
}
pub(crate) use usage;

/// Whether `e` is a usage error (exit 2): ours, or an option or size the library refused
/// before any work.
pub fn is_usage_error(e: &anyhow::Error) -> bool {
    e.downcast_ref::<UsageError>().is_some()
        || e.downcast_ref::<vizretarget::InvalidTarget>().is_some()
        || matches!(
            e.downcast_ref::<vizretarget::Error>(),
            Some(vizretarget::Error::InvalidOptions(_) | vizretarget::Error::InvalidSize { .. })
        )
}

/// The exit code of a run that ended with [`Outcome::Interrupted`].
pub fn interrupted_exit_code() -> u8 {
    interrupt::exit_code()
}

/// Runs the job the arguments ask for.
pub fn run(cli: Cli) -> Result<Outcome> {
    interrupt::install()?;
    match &cli.command {
        Some(Command::Watch(w)) => return watch::run(w),
        Some(Command::Compare(c)) => {
            compare::run(c)?;
            return Ok(Outcome::Done);
        }
        Some(Command::Completions { shell }) => {
            completions(*shell)?;
            return Ok(Outcome::Done);
        }
        None => {}
    }
    let (Some(input), Some(output)) = (cli.input.clone(), cli.output.clone()) else {
        usage!("give an INPUT and -o OUTPUT (see --help)");
    };
    let choice = match cli.stream.output_format {
        OutputArg::Auto => OutputChoice::Auto,
        OutputArg::Gif => OutputChoice::Gif,
        OutputArg::PngSeq => OutputChoice::PngSeq,
        OutputArg::Png => OutputChoice::Png,
        OutputArg::Jpeg => OutputChoice::Jpeg,
        OutputArg::Rgba => OutputChoice::Rgba,
        OutputArg::Rgb24 => OutputChoice::Rgb24,
        OutputArg::Y4m => OutputChoice::Y4m,
    };
    if cli.method != args::MethodArg::Mesh && marks::any(&cli.vector) {
        usage!("--marks, --paint-out-marks and --enhance* work with --method mesh (the default)");
    }
    let destination = resolve_output(&output, choice).map_err(library_error)?;
    let (shape, peeked) = Shape::of(&cli, &input)?;
    match (destination, shape) {
        (Destination::Still(format), Shape::Picture | Shape::UnreadableGif) => {
            still::run(&cli, &input, picture(peeked).as_ref(), &output, format)?;
            Ok(Outcome::Done)
        }
        (Destination::Still(_), Shape::Animation(n)) => usage!(
            "{}: an animated GIF of {n} frames does not fit in one picture ({}): write a .gif, \
             or a folder (ending in /) for one PNG per frame",
            input::name(&input).display(),
            output.display()
        ),
        (Destination::Still(_), Shape::Stream) => {
            // What stdin held and was no picture: first what is wrong with it, if anything.
            if let Some(peeked) = peeked {
                let limits = cli.limits_for(true);
                vizretarget::io::open_peeked(peeked, &limits).map_err(library_error)?;
            }
            usage!(
                "{}: one picture cannot hold a stream of frames: write a .gif, a folder (ending \
                 in /), or - (stdout)",
                output.display()
            )
        }
        // One picture into a folder keeps its name, as a folder of frames does (from stdin,
        // which names none, it is numbered as a stream's frames are).
        (Destination::Stream(SinkFormat::PngSeq), Shape::Picture) if !is_std(&input) => {
            stream::check_output_place(&output, SinkFormat::PngSeq)?;
            let file = output.join(picture_name(&input));
            if !output.is_dir() {
                std::fs::create_dir(&output)
                    .with_context(|| format!("{}: cannot create the folder", output.display()))?;
            }
            still::run(
                &cli,
                &input,
                picture(peeked).as_ref(),
                &file,
                OutputFormat::Png,
            )?;
            Ok(Outcome::Done)
        }
        // One picture on stdout (or a device: /dev/null) is a PNG file, as image tools
        // write it.
        (Destination::Stream(_), Shape::Picture)
            if (is_std(&output) || is_device(&output)) && choice == OutputChoice::Auto =>
        {
            still::run(
                &cli,
                &input,
                picture(peeked).as_ref(),
                &output,
                OutputFormat::Png,
            )?;
            Ok(Outcome::Done)
        }
        (Destination::Stream(_), _) if cli.method != args::MethodArg::Mesh => usage!(
            "--method {} is for one picture; streams are retargeted with mesh",
            vizretarget::Method::from(cli.method)
        ),
        (Destination::Stream(format), _) => stream::run(&cli, &input, peeked, &output, format),
    }
}

/// Writes the completion script of `shell` to stdout. Generated into memory first: the
/// generator panics on a failed write, and a reader closing stdout early is no error.
fn completions(shell: args::ShellArg) -> Result<()> {
    use clap::CommandFactory;
    use std::io::Write;
    let mut script = Vec::new();
    clap_complete::generate(
        clap_complete::Shell::from(shell),
        &mut Cli::command(),
        "vizretarget",
        &mut script,
    );
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(&script).and_then(|_| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(e).context("stdout: cannot write the completions")
        }
        _ => Ok(()),
    }
}

/// The option that raises the limit an error went past, to end its line with.
pub fn limit_hint(e: &anyhow::Error) -> Option<String> {
    limit_hint_of(e.downcast_ref::<vizretarget::Error>()?)
}

/// [`limit_hint`] of a library error: the option, with the value the input needs when the
/// error says (memory rounded up to a whole G, or M below 1 GiB).
pub fn limit_hint_of(e: &vizretarget::Error) -> Option<String> {
    use vizretarget::Limit;
    let vizretarget::Error::LimitExceeded { limit, needed, .. } = e else {
        return None;
    };
    let (option, value) = match limit {
        Limit::Pixels => ("--max-pixels", needed.map_or("N".into(), |n| n.to_string())),
        Limit::Frames => ("--max-frames", needed.map_or("N".into(), |n| n.to_string())),
        Limit::Memory => ("--memory-limit", needed.map_or("SIZE".into(), memory_value)),
        _ => return None,
    };
    Some(format!("raise it with {option} {value} (0: no limit)"))
}

/// `bytes` as a `--memory-limit` value that covers it: whole GiB, or MiB below 1 GiB.
fn memory_value(bytes: u64) -> String {
    const MIB: u64 = 1 << 20;
    const GIB: u64 = 1 << 30;
    if bytes > GIB {
        format!("{}G", bytes.div_ceil(GIB))
    } else {
        format!("{}M", bytes.div_ceil(MIB).max(1))
    }
}

/// The library's error as the command line reports it before a run: option problems are
/// usage errors (exit 2), without the "invalid option" prefix.
pub(crate) fn library_error(e: vizretarget::Error) -> anyhow::Error {
    match e {
        vizretarget::Error::InvalidOptions(m) => UsageError(m).into(),
        e => e.into(),
    }
}

/// The library's error once a run has started: what went wrong is in the input (the marks
/// of one frame), not in the command, so it exits 1.
pub(crate) fn run_error(e: vizretarget::Error) -> anyhow::Error {
    match e {
        vizretarget::Error::InvalidOptions(m) => anyhow!(m),
        e => e.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_hint_covers_what_is_needed() {
        let gib = 1u64 << 30;
        assert_eq!(memory_value(gib * 111 / 10), "12G");
        assert_eq!(memory_value(gib), "1024M");
        assert_eq!(memory_value(3 * gib), "3G");
        assert_eq!(memory_value(1), "1M");
    }
}
