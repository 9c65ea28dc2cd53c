//! One picture in, one picture out: the still job.

use super::args::MethodArg;
use super::{library_error, usage, Cli};
use anyhow::{bail, Context, Result};
use std::io::{IsTerminal, Write};
use std::path::Path;
use vizretarget::io::{
    encode_still, is_std, probe_still, read_still_with, write_still, OutputFormat,
};
use vizretarget::{debug, retarget, Image, Options, Retargeted, Size};

/// Runs the still-image job: one picture in, one out (`-`: stdout).
pub fn run(cli: &Cli, input: &Path, output: &Path, format: OutputFormat) -> Result<()> {
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
    let from = probe_still(input, &limits)?;
    let target = cli.target().resolve(from)?;
    limits.check_still(input, from, target)?;
    let image = read_still_with(input, &limits)?;
    if cli.method != MethodArg::Mesh {
        return super::compare::still_with(cli, input, output, format, &image, target, &options);
    }
    let out = retarget(&image, target, &options)?;
    write_output(&out.image, output, format)?;
    if let Some(dir) = &cli.debug_dir {
        write_debug(dir, &image, &out)?;
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

fn write_debug(dir: &Path, input: &vizretarget::Image, out: &Retargeted) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let a = out.analysis.as_ref().context("analysis was not kept")?;
    let structure = a.mesh.structure().cloned().unwrap_or_default();
    let pictures = [
        ("vsm.png", debug::vsm_image(&a.vsm)),
        ("structure.png", debug::structure_overlay(input, &structure)),
        ("levels.png", debug::levels_image(&a.vsm)),
        (
            "mesh-before.png",
            debug::mesh_overlay(input, a.mesh.vertices(), a.mesh.triangles()),
        ),
        (
            "mesh-after.png",
            debug::mesh_overlay(&out.image, a.warp.positions(), a.mesh.triangles()),
        ),
    ];
    for (name, img) in pictures {
        write_still(&img, &dir.join(name), OutputFormat::Png)?;
    }
    let path = dir.join("structure.json");
    let mut json = structure_json(&structure);
    json["text_out"] = text_out_json(input, &a.mesh, &a.warp);
    std::fs::write(&path, json.to_string())
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// The detected structure as JSON: lines as `[pos, from, to, width]`, text blocks as
/// `[x0, y0, x1, y1, line_height]`, in input pixels.
fn structure_json(s: &vizretarget::structure::Structure) -> serde_json::Value {
    let lines = |v: &[vizretarget::structure::Line]| -> Vec<serde_json::Value> {
        v.iter()
            .map(|l| serde_json::json!([l.pos, l.from, l.to, l.width]))
            .collect()
    };
    serde_json::json!({
        "horizontal": lines(&s.horizontal),
        "vertical": lines(&s.vertical),
        "text": s.text.iter().map(|b| serde_json::json!([b.x0, b.y0, b.x1, b.y1, b.line_height])).collect::<Vec<_>>(),
        "areas": s.areas.iter().map(|a| serde_json::json!([a.x0, a.y0, a.x1, a.y1, format!("{:?}", a.kind)])).collect::<Vec<_>>(),
    })
}

/// Where the warp put each text block: `[x0, y0, x1, y1, scale]` in output pixels, the box of
/// its vertices and its width's scale (a block keeps one scale), or null for a block without
/// vertices of its own. A block inside a data area is drawn over the area's map at its own
/// scale, centred where the map takes its centre.
fn text_out_json(
    input: &vizretarget::Image,
    mesh: &vizretarget::mesh::Mesh,
    warp: &vizretarget::Warp,
) -> serde_json::Value {
    let out = warp.positions();
    let maps = warp.area_maps(mesh);
    let placed = mesh.structure().map_or(Vec::new(), |s| {
        vizretarget::render::area_text_placements(input, s, &maps, warp.target())
    });
    let floated = |k: usize| -> Option<serde_json::Value> {
        let p = (*placed.get(k)?)?;
        let b = mesh.structure()?.text.get(k)?;
        let (hw, hh) = (
            p.scale * (b.x1 - b.x0) as f64 / 2.0,
            p.scale * (b.y1 - b.y0) as f64 / 2.0,
        );
        let (cx, cy) = (p.centre.x, p.centre.y);
        Some(serde_json::json!([
            cx - hw,
            cy - hh,
            cx + hw,
            cy + hh,
            p.scale
        ]))
    };
    let n = mesh.structure().map_or(0, |s| s.text.len());
    let mut boxes = vec![None::<[f64; 6]>; n];
    for (i, r) in mesh.roles().iter().enumerate() {
        let Some(k) = r.block else { continue };
        let (p, q) = (mesh.vertices()[i], out[i]);
        let b = boxes[k as usize].get_or_insert([q.x, q.y, q.x, q.y, p.x, p.x]);
        *b = [
            b[0].min(q.x),
            b[1].min(q.y),
            b[2].max(q.x),
            b[3].max(q.y),
            b[4].min(p.x),
            b[5].max(p.x),
        ];
    }
    boxes
        .iter()
        .enumerate()
        .map(|(k, b)| {
            floated(k).unwrap_or_else(|| match b {
                Some(b) if b[5] > b[4] => {
                    serde_json::json!([b[0], b[1], b[2], b[3], (b[2] - b[0]) / (b[5] - b[4])])
                }
                _ => serde_json::Value::Null,
            })
        })
        .collect()
}

fn print_stats(input: &Path, from: Size, out: &Retargeted) {
    let s = &out.stats;
    let t = &s.times;
    eprintln!(
        "{}: {} -> {}: {} vertices, {} triangles, DOF {}, {} unknowns; \
         vsm {:.1} ms, mesh {:.1} ms, solve {:.1} ms, render {:.1} ms, total {:.1} ms; \
         folds after first solve {}, repair rounds {}, untangled {}, blend {:.3}{}; \
         text blocks {} ({} held at their size), snapped to pixels {}{}; \
         data areas {}, floating marks and text {}",
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
    );
}
