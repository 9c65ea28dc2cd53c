//! One picture in, one picture out: the still job, by the mesh or by another `--method`.

use super::args::MethodArg;
use super::{library_error, usage, Cli};
use anyhow::{bail, Context, Result};
use std::io::{IsTerminal, Write};
use std::path::Path;
use vizretarget::io::{
    encode_still, is_std, probe_still, read_still_with, write_still, OutputFormat, PictureFile,
};
use vizretarget::{debug, retarget, retarget_with, Image, Method, Options, Retargeted, Size};

/// Runs the still-image job: one picture in, one out (`-`: stdout). `picture` is the one
/// stdin held, when `input` is `-`.
pub fn run(
    cli: &Cli,
    input: &Path,
    picture: Option<&PictureFile>,
    output: &Path,
    format: OutputFormat,
) -> Result<()> {
    let input = picture.map_or(input, |p| p.name());
    // Fail before the work, not after it: the output's folder must exist.
    let out_dir = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if is_std(output) {
        if std::io::stdout().is_terminal() {
            usage!(
                "refusing to write a picture to a terminal: pipe stdout into a program \
                 (| display -) or give -o FILE"
            );
        }
    } else if !out_dir.is_dir() {
        bail!(
            "{}: the output folder {} does not exist",
            output.display(),
            out_dir.display()
        );
    }
    let limits = cli.limits_for(false);
    let mut options = Options::default()
        .with_alpha(cli.alpha)
        .with_regions(cli.regions.into())
        .with_fill(cli.fill)
        .with_layout(!cli.no_layout)
        .with_analysis(cli.debug_dir.is_some());
    options = super::marks::apply(&cli.vector, options, &limits)?;
    if let Some(layer) = super::marks::still_layer(&cli.vector)? {
        options = options.with_marks(layer);
    }
    options.validate().map_err(library_error)?;
    if cli.size.is_none() && cli.width.is_none() && cli.height.is_none() && !cli.same_size {
        usage!("no target size: give --size WxH, or --width N and/or --height N");
    }
    // The header first: the job's memory is checked before the picture is decoded.
    let from = match picture {
        Some(p) => p.probe(&limits)?,
        None => probe_still(input, &limits)?,
    };
    let target = cli.target().resolve(from)?;
    limits.check_still(input, from, target)?;
    let image = match picture {
        Some(p) => p.decode(&limits)?,
        None => read_still_with(input, &limits)?,
    };
    if cli.method != MethodArg::Mesh {
        return still_with(cli, input, output, format, &image, target, &options);
    }
    let out = retarget(&image, target, &options)?;
    write_output(&out.image, output, format)?;
    if let Some(dir) = &cli.debug_dir {
        debug::write(dir, &image, &out).with_context(|| {
            format!(
                "--debug-dir: cannot write the pictures into {}",
                dir.display()
            )
        })?;
    }
    if cli.stats {
        print_stats(input, image.size(), &out);
    }
    Ok(())
}

/// Writes the picture to `output`, or as one file to stdout for `-` (a reader that closes it
/// early is no error, as for streams).
pub fn write_output(image: &Image, output: &Path, format: OutputFormat) -> Result<()> {
    if !is_std(output) {
        return Ok(write_still(image, output, format)?);
    }
    let bytes = encode_still(image, format)?;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(&bytes).and_then(|_| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(e).context("stdout: cannot write the picture")
        }
        _ => Ok(()),
    }
}

/// The still job with `--method` other than mesh: resize, write, and the debug pictures and
/// stats line that the method has.
fn still_with(
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
    write_output(&out.image, output, format)?;
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

fn print_stats(input: &Path, from: Size, out: &Retargeted) {
    let s = &out.stats;
    let t = &s.times;
    eprintln!(
        "{}: {} -> {}: {} vertices, {} triangles, DOF {}, {} unknowns; \
         vsm {:.1} ms, mesh {:.1} ms, solve {:.1} ms, render {:.1} ms, total {:.1} ms; \
         folds after first solve {}, repair rounds {}, untangled {}, blend {:.3}{}; \
         text blocks {} ({} held at their size), snapped to pixels {}{}; \
         data areas {}, floating marks and text {}{}{}",
        input.display(),
        from,
        out.image.size(),
        s.vertices,
        s.triangles,
        s.dof,
        s.solve.unknowns,
        t.vsm_ms,
        t.mesh_ms,
        t.solve_ms,
        t.render_ms,
        t.total_ms(),
        s.solve.folds_first_solve,
        s.solve.repair_rounds,
        s.solve.untangled,
        s.solve.blend,
        if s.solve.blend_global {
            " (global)"
        } else {
            ""
        },
        s.solve.text_blocks,
        s.solve.text_held,
        s.solve.snapped,
        if s.solve.fans_held || s.solve.unknowns == 0 {
            ""
        } else {
            "; marks' fans not held rigid (they left folds)"
        },
        s.data_areas,
        s.floated,
        match (s.dropped, s.panels) {
            (0, 0) => String::new(),
            (d, 0) => format!(" ({d} tick labels thinned out)"),
            (d, p) =>
                format!(" ({d} tick labels thinned out); {p} panels laid out each in its slot"),
        },
        match s.fitted {
            Some([x0, y0, x1, y1]) => format!(
                "; drawn at one scale, {}x{} at ({x0}, {y0}), on its ground",
                x1 - x0,
                y1 - y0
            ),
            None => String::new(),
        },
    );
}
