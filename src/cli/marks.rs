//! `--marks`, `--enhance*`: from arguments to the library's options and a source of per-frame
//! marks. Wiring only; the formats and the method are in `vizretarget::vector` and
//! `vizretarget::Enhancement`.

use super::args::{MarkSizeArg, VectorArgs};
use anyhow::Result;
use std::path::Path;
use std::sync::Arc;
use vizretarget::io::FrameMarks;
use vizretarget::io::{list_images, read_still_with, Input, InputKind};
use vizretarget::vector::read_layer;
use vizretarget::{EnhanceMask, Enhancement};
use vizretarget::{MarkSize, Options};

/// Whether any option of §5.3–5.4 is given.
pub fn any(args: &VectorArgs) -> bool {
    args.marks.is_some()
        || args.enhance.is_some()
        || !args.enhance_region.is_empty()
        || args.enhance_mask.is_some()
        || args.paint_out_marks
}

/// `options` with the enhancement and the way marks are drawn.
pub fn apply(
    args: &VectorArgs,
    mut options: Options,
    limits: &vizretarget::Limits,
) -> Result<Options> {
    let mask = match &args.enhance_mask {
        Some(path) => {
            let img = read_still_with(path, limits)?;
            Some(Arc::new(
                EnhanceMask::from_image(&img, args.enhance_mask_factor)
                    .map_err(super::library_error)?,
            ))
        }
        None => None,
    };
    options.enhance = Enhancement {
        per_level: args.enhance.unwrap_or([1.0; 3]),
        regions: args.enhance_region.clone(),
        mask,
    };
    options.vector.paint_out = args.paint_out_marks;
    options.vector.size = match args.mark_size {
        MarkSizeArg::Mesh => MarkSize::Mesh,
        MarkSizeArg::Keep => MarkSize::Keep,
    };
    Ok(options)
}

/// The marks of one picture (`--marks` FILE; a .jsonl gives its first line).
pub fn still_layer(args: &VectorArgs) -> Result<Option<vizretarget::VectorLayer>> {
    match &args.marks {
        Some(p) if p.is_dir() => super::usage!(
            "{}: a folder of marks goes with a folder of frames; for one picture give a JSON file",
            p.display()
        ),
        Some(p) => Ok(Some(read_layer(p)?)),
        None => Ok(None),
    }
}

/// Where each frame's marks come from: `--marks`, else sidecar JSON files beside the frames
/// of a folder input (when there are any). Says so on stderr unless `quiet`.
pub fn frame_marks(
    args: &VectorArgs,
    input_path: &Path,
    input: &Input,
    quiet: bool,
) -> Result<Option<FrameMarks>> {
    if let Some(p) = &args.marks {
        return Ok(Some(
            FrameMarks::open(p, input.names.clone()).map_err(super::library_error)?,
        ));
    }
    if input.kind == InputKind::Folder {
        if let Some(names) = &input.names {
            if FrameMarks::has_sidecars(input_path, &list_images(input_path)?) {
                if !quiet {
                    eprintln!(
                        "vizretarget: marks from the JSON files beside the frames in {}",
                        input_path.display()
                    );
                }
                return Ok(Some(FrameMarks::sidecars(input_path, names.clone())));
            }
        }
    }
    Ok(None)
}
