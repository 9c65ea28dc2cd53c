//! Command-line arguments. Parsing only: values are checked here so that a typo gets a clear
//! message before any work starts.

use clap::Parser;
use std::path::PathBuf;

/// Help text after the options of `--help`: worked examples and exit codes.
const EXAMPLES: &str = "\
Examples:
  Fit a landscape scatter map on a portrait phone screen:
    vizretarget map.png --size 360x640 -o map-portrait.png

  Halve a dashboard's width, keep its height, print mesh size and timings:
    vizretarget dashboard.png --width 320 -o dashboard-narrow.png --stats

  Make a graph square with a finer mesh, as JPEG, keeping pictures of each stage:
    vizretarget graph.png --size 600x600 --alpha 12 -o graph-square.jpg --debug-dir debug/

Exit status: 0 done; 1 the input could not be read or the output not written; 2 usage error.";

/// Resize a visualization to another aspect ratio without squashing its marks.
///
/// vizretarget is for charts, maps, node-link graphs and dashboards designed for one screen that
/// must be shown on another: a phone, a portrait wall display, a thumbnail. Cropping drops
/// content and plain scaling squashes circles into ellipses and text into smudges. Instead,
/// vizretarget finds the salient content, covers the image with a triangle mesh that is dense
/// there and sparse on empty background, and deforms the mesh so that marks keep their shape
/// while empty or uniform areas absorb the change.
///
/// Give the target with --size WxH, or change one side with --width or --height. The input is
/// never modified; the output is written only if the whole run succeeds.
#[derive(Parser, Debug)]
#[command(
    name = "vizretarget",
    version,
    override_usage = "vizretarget <INPUT> (--size WxH | --width N | --height N) -o <OUTPUT> [OPTIONS]",
    after_long_help = EXAMPLES,
    max_term_width = 100
)]
#[command(group = clap::ArgGroup::new("target").args(["size", "width", "height"]).required(true).multiple(true))]
pub struct Cli {
    /// Input image: PNG, JPEG, WebP, or GIF (first frame), recognised by content, not by name.
    /// Up to 16384 px on a side.
    pub input: PathBuf,

    /// Output image; the extension picks the format: .png, .jpg or .jpeg. Replaces an existing
    /// file only when the run succeeds; the folder must exist.
    #[arg(short, long, value_name = "OUTPUT")]
    pub output: PathBuf,

    /// Target size as WIDTHxHEIGHT in px, e.g. 400x600; each side 1 to 16384. Not together with
    /// --width or --height.
    #[arg(short, long, value_name = "WxH", allow_hyphen_values = true,
          conflicts_with_all = ["width", "height"], value_parser = parse_size)]
    pub size: Option<(u32, u32)>,

    /// Target width in px, 1 to 16384; the height stays as in the input unless --height is
    /// given too.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub width: Option<u32>,

    /// Target height in px, 1 to 16384; the width stays as in the input unless --width is
    /// given too.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub height: Option<u32>,

    /// Mesh spacing α in px: the mesh gets about width·height/α² key points. Smaller follows
    /// small marks more closely but is slower; 4 to 200.
    #[arg(long, value_name = "N", default_value_t = 20.0)]
    pub alpha: f32,

    /// Also write the method's intermediate pictures into DIR (created if missing): the
    /// saliency map (vsm.png), its levels (levels.png) and the mesh before and after the warp
    /// (mesh-before.png, mesh-after.png).
    #[arg(long, value_name = "DIR")]
    pub debug_dir: Option<PathBuf>,

    /// Print mesh size (vertices, triangles, degrees of freedom) and milliseconds per stage to
    /// stderr. Off by default.
    #[arg(long)]
    pub stats: bool,
}

fn parse_side(s: &str) -> Result<u32, String> {
    let n: i64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number of pixels"))?;
    if n < 1 || n > vizretarget::MAX_SIDE as i64 {
        return Err(format!(
            "{n} px is out of range: each side must be 1 to {}",
            vizretarget::MAX_SIDE
        ));
    }
    Ok(n as u32)
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT (e.g. 400x600)"))?;
    Ok((parse_side(w)?, parse_side(h)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_bad_ones_explain() {
        assert_eq!(parse_size("400x600"), Ok((400, 600)));
        assert_eq!(parse_size("16384X1"), Ok((16384, 1)));
        assert!(parse_size("0x10").unwrap_err().contains("out of range"));
        assert!(parse_size("-5x10").unwrap_err().contains("out of range"));
        assert!(parse_size("axb")
            .unwrap_err()
            .contains("not a whole number"));
        assert!(parse_size("400").unwrap_err().contains("WIDTHxHEIGHT"));
        assert!(parse_size("20000x10").unwrap_err().contains("out of range"));
    }

    #[test]
    fn command_is_well_formed() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
