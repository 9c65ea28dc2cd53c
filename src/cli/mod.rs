//! The command line: parses, wires the library's public API, reports. No method code here.
//!
//! - `still.rs`: one picture in, one out (`INPUT.png -o OUT.png`).
//! - `stream.rs`: frames in (GIF, folder, stdin), frames out (GIF, folder, stdout), through
//!   [`vizretarget::Pipeline`].
//! - `watch.rs`: `vizretarget watch DIR -o OUTDIR`.
//! - `compare.rs`: `vizretarget compare INPUT -o SHEET.png`: every method side by side.
//! - `marks.rs`: `--marks` and `--enhance*` (vector marks §5.3, content enhancement §5.4).
//! - `report.rs`: progress bar, summary line, `--stats-json`; `interrupt.rs`: SIGINT (Ctrl-C) and SIGTERM.

mod args;
mod compare;
mod interrupt;
mod marks;
mod report;
mod still;
mod stream;
mod watch;

pub use args::Cli;

use anyhow::{anyhow, bail, Result};
use args::{Command, OutputArg};
use std::path::Path;
use vizretarget::io::{is_std, resolve_output, Destination, OutputChoice};

/// How a successful run ended.
pub enum Outcome {
    Done,
    /// Stopped by SIGINT or SIGTERM (exit 128 + the signal: 130, 143).
    Interrupted,
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
        None => {}
    }
    let (Some(input), Some(output)) = (cli.input.clone(), cli.output.clone()) else {
        bail!("give an INPUT and -o OUTPUT (see --help)");
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
        bail!("--marks, --paint-out-marks and --enhance* work with --method mesh (the default)");
    }
    match resolve_output(&output, choice).map_err(library_error)? {
        Destination::Still(format) if is_picture_file(&input) => {
            still::run(&cli, &input, &output, format)?;
            Ok(Outcome::Done)
        }
        Destination::Still(_) => bail!(
            "{}: one picture cannot hold a stream of frames: write a .gif, a folder (ending \
             in /), or - (stdout)",
            output.display()
        ),
        Destination::Stream(_) if cli.method != args::MethodArg::Mesh => bail!(
            "--method {} is for one picture; streams are retargeted with mesh",
            vizretarget::Method::from(cli.method)
        ),
        Destination::Stream(format) => stream::run(&cli, &input, &output, format),
    }
}

/// An input that is one file (a still, or a GIF whose first frame is used for a still output).
fn is_picture_file(input: &Path) -> bool {
    !is_std(input) && !input.is_dir()
}

/// The option that raises the limit an error went past, to end its line with.
pub fn limit_hint(e: &anyhow::Error) -> Option<&'static str> {
    limit_hint_of(e.downcast_ref::<vizretarget::Error>()?)
}

/// [`limit_hint`] of a library error.
pub fn limit_hint_of(e: &vizretarget::Error) -> Option<&'static str> {
    use vizretarget::Limit;
    match e {
        vizretarget::Error::LimitExceeded { limit, .. } => Some(match limit {
            Limit::Pixels => "raise it with --max-pixels N (0: no limit)",
            Limit::Frames => "raise it with --max-frames N (0: no limit)",
            Limit::Memory => "raise it with --memory-limit SIZE, e.g. 4G (0: no limit)",
            _ => return None,
        }),
        _ => None,
    }
}

/// The library's error as the command line reports it: option problems without the
/// "invalid option" prefix.
pub(crate) fn library_error(e: vizretarget::Error) -> anyhow::Error {
    match e {
        vizretarget::Error::InvalidOptions(m) => anyhow!(m),
        e => e.into(),
    }
}
