//! Command-line arguments. Parsing only: values are checked here so that a typo gets a clear
//! message before any work starts.

use clap::Parser;
use std::path::PathBuf;

/// Resize visualizations (charts, maps, graphs, dashboards) to another aspect ratio, keeping
/// marks round, and letting empty space absorb the change.
///
/// Examples:
///
///   vizretarget chart.png --size 400x600 -o chart-portrait.png
///
///   vizretarget map.png --width 640 -o map-narrow.png --stats
///
///   vizretarget graph.png --size 800x800 -o out.png --debug-dir debug/
#[derive(Parser, Debug)]
#[command(name = "vizretarget", version, about, long_about, max_term_width = 100)]
pub struct Cli {
    /// Input image: PNG, JPEG, WebP, or GIF (first frame). Recognised by content, not by name.
    pub input: PathBuf,

    /// Output image; the format follows the extension (.png, .jpg or .jpeg).
    #[arg(short, long, value_name = "OUTPUT")]
    pub output: PathBuf,

    /// Target size as WIDTHxHEIGHT, e.g. 400x600 (each side 1 to 16384).
    #[arg(short, long, value_name = "WxH", allow_hyphen_values = true,
          conflicts_with_all = ["width", "height"], value_parser = parse_size)]
    pub size: Option<(u32, u32)>,

    /// Target width; the height stays as in the input unless --height is given too.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub width: Option<u32>,

    /// Target height; the width stays as in the input unless --width is given too.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub height: Option<u32>,

    /// Mesh budget α: about w·h/α² key points. Smaller is finer and slower (4 to 200).
    #[arg(long, value_name = "N", default_value_t = 20.0)]
    pub alpha: f32,

    /// Write the method's intermediate pictures here: the saliency map (vsm.png), its levels
    /// (levels.png) and the mesh before and after the warp (mesh-before.png, mesh-after.png).
    #[arg(long, value_name = "DIR")]
    pub debug_dir: Option<PathBuf>,

    /// Print mesh size (vertices, DOF) and milliseconds per stage to stderr.
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
