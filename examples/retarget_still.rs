//! The library API for one still image, start to end.
//!
//! Draws a 480x240 scatterplot in memory (a few coloured dots on white), retargets it to half
//! its width, and saves the result as PNG:
//!
//! ```text
//! cargo run --release --example retarget_still             # writes to the temp folder
//! cargo run --release --example retarget_still -- out.png  # writes out.png
//! ```
//!
//! Under the default options the picture keeps its shape: the dots are drawn at one scale, the
//! one that fits the new width (about 0.6 here: the white margins around them give way),
//! centred on their white ground, so they stay round. A plain resize to the same size would
//! squash them into ellipses half as wide as they are tall.

use std::path::PathBuf;
use vizretarget::io::{write_still, OutputFormat};
use vizretarget::{retarget, Image, Options, Size};

fn main() -> Result<(), vizretarget::Error> {
    // 1. An input image. `Image` is straight RGBA8, rows top to bottom.
    let size = Size::new(480, 240)?;
    let mut image = Image::filled(size, [255, 255, 255, 255]);
    let dots = [
        (70, 60, 14, [228, 26, 28, 255]),
        (160, 170, 10, [55, 126, 184, 255]),
        (250, 90, 18, [77, 175, 74, 255]),
        (330, 180, 8, [152, 78, 163, 255]),
        (410, 70, 12, [255, 127, 0, 255]),
    ];
    for (cx, cy, r, colour) in dots {
        for y in cy - r..=cy + r {
            for x in cx - r..=cx + r {
                if (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r {
                    image.set(x as u32, y as u32, colour);
                }
            }
        }
    }

    // 2. Retarget. `Options::default()` is the command line's default (`--regions affine`:
    //    one map per axis, with the margins giving way); `with_regions(Regions::Free)` is the
    //    paper's mesh everywhere. `Size::new` refuses zero and sides above
    //    `vizretarget::MAX_SIDE`.
    let target = Size::new(size.width / 2, size.height)?;
    let out = retarget(&image, target, &Options::default())?;
    let s = &out.stats;
    println!(
        "{} -> {}: {} vertices, {} triangles, {:.1} ms",
        size,
        out.image.size(),
        s.vertices,
        s.triangles,
        s.times.total_ms()
    );

    // 3. Save. `write_still` encodes in memory and replaces the file atomically.
    let path = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("retarget_still.png"));
    write_still(&out.image, &path, OutputFormat::Png)?;
    println!("wrote {}", path.display());
    Ok(())
}
