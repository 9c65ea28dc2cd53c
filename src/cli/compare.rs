//! `vizretarget compare`: every method on one picture, the labelled sheet and the measures.

use super::args::{CompareArgs, Target};
use super::{library_error, usage};
use anyhow::{bail, Context, Result};
use std::io::Write;
use std::path::Path;
use vizretarget::compare::{compare, SheetOptions};
use vizretarget::io::{
    probe_still, read_still_with, resolve_output, write_still, Destination, OutputChoice,
};
use vizretarget::Options;

/// Writes the sheet and prints the table (or JSON) on stdout.
pub fn run(args: &CompareArgs) -> Result<()> {
    let format = match resolve_output(&args.output, OutputChoice::Auto).map_err(library_error)? {
        Destination::Still(f) => f,
        Destination::Stream(_) => usage!(
            "{}: the sheet is one picture: give a .png, .jpg, .jpeg or .webp file",
            args.output.display()
        ),
    };
    check_folder(&args.output)?;
    let options = Options::default().with_alpha(args.alpha);
    options.validate().map_err(library_error)?;
    let limits = args.limits.limits(None);
    let from = probe_still(&args.input, &limits)?;
    let target = Target::of(args.size, args.width, args.height).resolve(from)?;
    limits.check_compare(&args.input, from, target)?;
    let image = read_still_with(&args.input, &limits)?;
    let comparison = compare(&image, target, &options).map_err(library_error)?;
    let sheet = comparison.sheet(
        &image,
        &SheetOptions {
            mesh_overlay: args.mesh,
            metrics: args.metrics,
            ..SheetOptions::default()
        },
    );
    write_still(&sheet, &args.output, format)?;
    let text = if args.json {
        format!("{}\n", comparison.metrics.to_json())
    } else {
        comparison.metrics.to_string()
    };
    // A reader that closes stdout early (`| head`) is not an error.
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|_| stdout.flush())
    {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(e).context("cannot write the measures to stdout")
        }
        _ => Ok(()),
    }
}

/// Fail before the work, not after it: the output's folder must exist.
fn check_folder(output: &Path) -> Result<()> {
    let dir = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        bail!(
            "{}: the output folder {} does not exist",
            output.display(),
            dir.display()
        );
    }
    Ok(())
}
