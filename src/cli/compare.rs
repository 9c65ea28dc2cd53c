//! `vizretarget compare`: every method on one picture, the labelled sheet and the measures;
//! and `--method` for one picture with a method other than the mesh.

use super::args::{CompareArgs, MethodArg, Target};
use super::{library_error, usage, Cli};
use anyhow::{bail, Context, Result};
use std::io::Write;
use std::path::Path;
use vizretarget::compare::{compare, SheetOptions};
use vizretarget::io::OutputFormat;
use vizretarget::io::{
    probe_still, read_still_with, resolve_output, write_still, Destination, OutputChoice,
};
use vizretarget::{debug, retarget_with, Image, Method, Options, Size};

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

/// The still job with `--method` other than mesh: resize, write, and the debug pictures and
/// stats line that the method has.
pub fn still_with(
    cli: &Cli,
    input: &Path,
    output: &Path,
    format: OutputFormat,
    image: &Image,
    target: Size,
    options: &Options,
) -> Result<()> {
    let method = Method::from(cli.method);
    debug_assert_ne!(cli.method, MethodArg::Mesh);
    let out = retarget_with(method, image, target, options).map_err(library_error)?;
    super::still::write_output(&out.image, output, format)?;
    if let Some(dir) = &cli.debug_dir {
        debug::write_method(dir, image, &out).with_context(|| {
            format!(
                "--debug-dir: cannot write the pictures into {}",
                dir.display()
            )
        })?;
    }
    if cli.stats {
        let s = &out.stats;
        let t = &s.times;
        let mesh = match (s.vertices, s.triangles, s.dof) {
            (Some(v), Some(t), Some(d)) => format!("{v} vertices, {t} triangles, DOF {d}; "),
            _ => String::new(),
        };
        eprintln!(
            "{}: {} -> {} by {method}: {mesh}vsm {:.1} ms, mesh {:.1} ms, solve {:.1} ms, \
             render {:.1} ms, total {:.1} ms",
            input.display(),
            image.size(),
            out.image.size(),
            t.vsm_ms,
            t.mesh_ms,
            t.solve_ms,
            t.render_ms,
            t.total_ms(),
        );
    }
    Ok(())
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
