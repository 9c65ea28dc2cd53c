//! Command-line arguments. Parsing only: values are checked here so that a typo gets a clear
//! message before any work starts.

use clap::Parser;
use std::path::PathBuf;
use vizretarget::ReuseOptions;
pub use vizretarget::{Side, Target};

/// Help text after the options of `--help`: worked examples and exit codes.
const EXAMPLES: &str = "\
Examples (run from a clone of the repository: the inputs are its samples in streams/, the
outputs go to out/, which git ignores):
  Fit a landscape scatter map on a portrait phone screen:
    vizretarget streams/scatter-map/frame-0000.png --size 360x640 -o out/map-portrait.png

  Halve a dashboard's width, keep its height, print mesh size and timings:
    vizretarget streams/dashboard/frame-0000.png --width 320 -o out/dashboard-narrow.png --stats

  Make a graph square with a finer mesh, as JPEG, keeping pictures of each stage:
    vizretarget streams/graph/frame-0019.png --size 600x600 --alpha 12 -o out/graph-square.jpg \\
        --debug-dir out/debug/

Streams: every frame goes through one pipeline. A summary line ends each run: frames, fps,
what was kept from frame to frame (under the default --regions affine, how many frames were
unchanged and how many resampled afresh; with a mesh, the share of frames whose mesh was
reused, updated or rebuilt), ms per stage.
  vizretarget streams/dashboard.gif --size 360x640 -o out/dashboard-portrait.gif
      An animated GIF to a portrait GIF: delays and loop count kept.
  vizretarget streams/dashboard/ --width 400 -o out/narrow/ --stats-json out/stats.json
      A folder of PNG/JPEG frames, in natural order (frame2 before frame10), to a folder of
      PNGs with the same names, and per-frame statistics as JSON.
  ffmpeg -i streams/scatter-map.gif -f yuv4mpegpipe -pix_fmt yuv420p - \\
      | vizretarget - --size 720x720 -o out/square.gif
      Video piped in as YUV4MPEG2 (or as PNGs: -f image2pipe -c:v png -), recognised by
      content, written as a GIF. Keep -pix_fmt yuv420p: from a GIF or RGB source ffmpeg
      writes nothing to yuv4mpegpipe without it.
  ffmpeg -i streams/dashboard.gif -f rawvideo -pix_fmt rgba - \\
      | vizretarget - --input-format rgba --input-size 640x360 --fps 4 --size 360x360 -o - \\
      | ffmpeg -f yuv4mpegpipe -i - out/dashboard-square.mp4
      Raw frames in (they need --input-format and --input-size, and --fps: raw frames carry
      no rate, and YUV4MPEG2 out would otherwise say 25 fps), YUV4MPEG2 out (the default for
      a stream on stdout; also --output-format rgba, rgb24 or png).
  cat streams/graph/frame-0000.png | vizretarget - --size 50% -o - > out/small.png
      One picture on stdin (a PNG, JPEG, WebP or GIF file, by content; several PNGs are a
      stream) or to stdout is a PNG. Sizes may be percentages of the input's (50% for both
      sides, or --size 50%x100%) or one side (--size 400x keeps the height).
  vizretarget streams/graph.gif --width 50% -o /dev/null --stats
      Time a run without keeping its output.
  vizretarget watch streams/dashboard/ -o out/phone/ --size 360x640
      Retarget each dashboard snapshot in the folder, then each new or replaced one as it
      lands, into out/phone/ under the same name. Ctrl-C (or SIGTERM) stops.
  vizretarget completions bash > out/vizretarget.bash
      Shell completions (bash, zsh or fish) on stdout; put them where the shell looks, e.g.
      ~/.local/share/bash-completion/completions/vizretarget.

Vector marks and enhancement (the paper's 5.3 and 5.4):
  vizretarget streams/marks/map.png --marks streams/marks/dots.json --width 400 \\
      -o out/map-narrow.png
      The map is resized as a picture; the dots of dots.json are carried by the mesh and
      drawn crisp and round over it. dots.json: {\"points\": [{\"x\": 120, \"y\": 80, \"r\": 6,
      \"fill\": \"#d7191c\"}, ...], \"edges\": [{\"from\": 0, \"to\": 1, \"width\": 1.5}]}. Add
      --paint-out-marks when the picture shows the dots too.
  vizretarget streams/marks/map.png --same-size --enhance-region 300,60,300,150=1.5 \\
      -o out/enlarged.png
      Enlarge a crowded region by half without changing the canvas size.
  vizretarget streams/scatter-map/ --marks streams/marks/scatter-map.jsonl --paint-out-marks \\
      --enhance 1,1,1.3 --width 400 -o out/narrow.gif
      A stream with one line of marks per frame, painted out of the frames and drawn again;
      salient content 30 % larger on every frame.

Limits: an input is refused from its header, before any large allocation, when a frame has more
than --max-pixels pixels (default 40000000), a file or folder more than --max-frames frames
(default 100000; stdin has no frame limit unless given), or the run would need more than
--memory-limit (default 2.5G). The message names the option that raises the limit; 0 lifts it.
A stream that fails part way (a corrupt frame, a frame past the limit) keeps the frames before
it in the output and exits with 1.

Exit status: 0 done (also when the reader of stdout closes it early); 1 the input could not be
read or the output not written; 2 usage error (an option's value, or options and inputs that do
not go together, e.g. an animated GIF to one .png); 130 stopped by SIGINT (Ctrl-C), 143 by SIGTERM
(during a stream the first signal finishes the frames in flight and completes the output, a
second one quits at once).";

/// Help text after the options of `watch --help`.
const WATCH_HELP: &str = "\
Each PNG or JPEG snapshot that appears in DIR, or replaces one there, is retargeted once and
written into OUTDIR under the same name, atomically (a temporary file, then a rename): a reader
of OUTDIR never sees half a picture. A snapshot is read only when its writer is done (a
close-write event, or no change for --settle-ms), never half-written. Snapshots already in DIR
when watching starts are retargeted first, in natural order of their names. Hidden files and
other extensions are ignored. Faults are reported on stderr, one line naming the file, and
watching goes on: a snapshot that vanishes before it is read or cannot be decoded is skipped, one
without read permission until its permissions change, an output that cannot be written (OUTDIR
read-only) until its snapshot changes; a removed DIR is waited for and watched again when back.
Each snapshot gets its own target: a percentage, or the side not given, is taken from that
snapshot, so snapshots of different sizes keep their own height (--width) or width (--height).
One line per snapshot on stderr unless --quiet; at the end, how many were retargeted and how
long each took (mean and max ms).

Example (from a clone of the repository: its folder of sample frames, outputs in out/):
  vizretarget watch streams/graph/ -o out/graph-phone/ --size 360x640 \\
      --stats-json out/graph-phone.json

Exit status: 130 after SIGINT (Ctrl-C), 143 after SIGTERM (the snapshot in flight is finished
first), 1 if DIR cannot be watched or OUTDIR cannot be created, 2 usage error.";

/// Help text after the options of `compare --help`.
const COMPARE_HELP: &str = "\
The sheet shows, left to right and wrapping into rows on wide inputs: the original, mesh
(vizretarget), linear scaling, crop (the most salient window at the scale that covers the
target), grid (the same energy on a uniform grid, Wang et al. 2008), seam carving (forward
energy) and axis (axis-aligned deformation, Panozzo et al. 2012). Each panel is labelled with its method and size. Panels keep their relative sizes.

The table on stdout has one row per method: sal.mean, the mean saliency of the output's own
saliency map (the paper's Fig. 15); sal.carried, the same read as preserved energy (Avidan and
Shamir): the source's saliency of what each output pixel shows, averaged (linear scaling keeps
the source's mean); sal.kept, the output's total saliency over the source's;
distortion, how far salient content is from a similarity (0: only scaled; halving one axis
linearly: 0.47); sal.area, the output area of the source's salient pixels over their area (1:
marks kept at their size); vertices and DOF of mesh and grid; milliseconds per stage.

Example (from a clone of the repository: a sample frame, the sheet in out/):
  vizretarget compare streams/scatter-map/frame-0000.png --width 400 -o out/map-compare.png \\
      --mesh --metrics

Exit status: 0 done, 1 the input could not be read or the sheet not written, 2 usage error.";

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
/// never modified; the output is written only if the whole run succeeds. Streams of frames (an
/// animated GIF, a folder, stdin from ffmpeg, a watched folder) go through the same method, one
/// frame after the other.
#[derive(Parser, Debug)]
#[command(
    name = "vizretarget",
    version,
    override_usage = "vizretarget <INPUT> (--size WxH | --width N | --height N) -o <OUTPUT> [OPTIONS]\n  \
                      or:  vizretarget watch <DIR> -o <OUTDIR> (--size WxH | --width N | --height N) [OPTIONS]\n  \
                      or:  vizretarget compare <INPUT> (--size WxH | --width N | --height N) -o <SHEET.png> [--mesh] [--metrics] [--json]\n  \
                      or:  vizretarget completions <bash|zsh|fish>",
    after_long_help = EXAMPLES,
    max_term_width = 100,
    args_conflicts_with_subcommands = true,
    disable_help_subcommand = true,
    subcommand_negates_reqs = true
)]
#[command(group = clap::ArgGroup::new("target").args(["size", "width", "height", "same_size"]).required(true).multiple(true))]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,

    /// Input: a PNG, JPEG, WebP or GIF (animated or not), recognised by content, not by name; a
    /// folder of PNG/JPEG frames; or - for stdin (one picture as a file holds it, a PNG stream
    /// or YUV4MPEG2, recognised; raw frames with --input-format). Up to 16384 px on a side.
    #[arg(required = true)]
    pub input: Option<PathBuf>,

    /// Output; the extension picks the format: .png, .jpg, .jpeg or .webp (lossless) for one
    /// picture, .gif for an animation, .y4m for YUV4MPEG2; a folder (existing, or ending in /)
    /// for one PNG per frame (a single picture keeps its name: in.jpg -o out/ writes
    /// out/in.png); - for stdout (one picture as PNG, a stream as YUV4MPEG2: see
    /// --output-format), and so is a device such as /dev/null. An animated GIF or a folder of frames needs a .gif, a folder or -,
    /// not one picture. Replaces an existing file only when the run succeeds. The folder a
    /// file goes into must exist; a folder output ending in / is created if missing (its
    /// parent must exist).
    #[arg(short, long, value_name = "OUTPUT", required = true)]
    pub output: Option<PathBuf>,

    /// Target size as WIDTHxHEIGHT, each side in px (1 to 16384) or as a percentage of the
    /// input's, e.g. 400x600, 50%x100%; leave a side out to keep it as in the input: 400x,
    /// x300; one percentage scales both sides: 200%. Not together with --width or --height.
    #[arg(short, long, value_name = "WxH", allow_hyphen_values = true,
          conflicts_with_all = ["width", "height"], value_parser = parse_size)]
    pub size: Option<Target>,

    /// Target width in px (1 to 16384) or as a percentage of the input's, e.g. 400 or 50%; the
    /// height stays as in the input unless --height is given too.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub width: Option<Side>,

    /// Target height in px (1 to 16384) or as a percentage of the input's, e.g. 300 or 50%;
    /// the width stays as in the input unless --width is given too.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub height: Option<Side>,

    /// Keep the input's size: with --enhance, --enhance-region or --enhance-mask, enlarge
    /// what matters without resizing the canvas.
    #[arg(long, conflicts_with_all = ["size", "width", "height"])]
    pub same_size: bool,

    /// Mesh spacing α in px: the mesh gets about width·height/α² key points. Smaller follows
    /// small marks more closely but is slower; 4 to 200. Under the default --regions affine
    /// the mesh shapes nothing drawn and uses 200.
    #[arg(long, value_name = "N", default_value_t = 20.0, value_parser = parse_alpha)]
    pub alpha: f32,

    /// Which parts of a chart the warp may bend: affine (the default: the whole picture is
    /// one data area, resized by one map per axis so nothing read off a position or a length
    /// changes, with text bands and text on a flat ground kept at their size where they have
    /// room, and at one scale where nothing can give way, see --fill: judged blind on real
    /// charts, readers preferred this to the bending modes and to a plain resize); auto (data areas found from axes,
    /// frames, even grids and bars on a baseline keep one affine map each and their round
    /// marks one scale, margins, gutters and the space around text absorb the rest); free (no
    /// data areas: the paper's adaptive mesh bends wherever content allows, for node-link
    /// graphs whose nodes must stay round).
    #[arg(long, value_name = "REGIONS", value_enum, default_value_t = RegionsArg::Affine)]
    pub regions: RegionsArg,

    /// Under --regions affine, fill the whole target size even where nothing in the picture
    /// can give way (no text band to keep at its size, no blank margin): the picture is then
    /// squeezed along one axis as a plain resize squeezes it, with its round marks and text
    /// on a flat ground floated over it where they have room. By default such a picture is
    /// drawn at one scale, the smaller of the two, centred on its own ground (the colour of
    /// most of its edge; a picture without one, such as a gradient to the edge, fills):
    /// readers judging blind preferred that to the squeeze.
    #[arg(long)]
    pub fill: bool,

    /// Do not lay charts out again: by default (under --regions affine) a chart's plots (data
    /// areas found from axes, frames, grids, bars) take the room the parts around them leave,
    /// tick labels, axis titles, legends and titles keep their size, an x axis' crowded tick
    /// labels drop every other one from the first (steps kept even), and round marks keep
    /// their size where no two would touch, as the chart's author re-rendering it for the
    /// smaller screen would. With --no-layout only the text bands and blank margins give way. A picture
    /// without axes, frames, grids or bars (a map, a node-link graph) is the same either way.
    #[arg(long)]
    pub no_layout: bool,

    /// Resizing method, for one picture: mesh (vizretarget's adaptive mesh, the default);
    /// linear (plain scaling); crop (scale to cover, keep the most salient window); grid (the
    /// same deformation on a uniform grid, Wang et al. 2008); seam (seam carving with forward
    /// energy); axis (axis-aligned deformation, Panozzo et al. 2012: a scale per column and
    /// per row, so every line stays straight and whole). `vizretarget compare` shows them side
    /// by side. Streams use mesh.
    #[arg(long, value_name = "METHOD", value_enum, default_value_t = MethodArg::Mesh)]
    pub method: MethodArg,

    /// Also write the method's intermediate pictures into DIR (created if missing): the
    /// saliency map (vsm.png), its levels (levels.png), the lines and text blocks found
    /// (structure.png; as JSON in structure.json, with where the warp put each text block and
    /// its scale under "text_out", and the layout's spans and panels under "bands"), and two
    /// pictures of the mesh: over the input before the
    /// warp (mesh-before.png) and over the output after it (mesh-after.png). One picture
    /// only: refused for a stream.
    #[arg(long, value_name = "DIR")]
    pub debug_dir: Option<PathBuf>,

    /// Print mesh size (vertices, triangles, degrees of freedom) and milliseconds per stage to
    /// stderr (for a stream, one line per frame), with the data areas, the marks and text
    /// drawn floating, the tick labels thinned out and the panels laid out each in its slot.
    /// Off by default.
    #[arg(long)]
    pub stats: bool,

    #[command(flatten)]
    pub stream: StreamArgs,

    #[command(flatten)]
    pub vector: VectorArgs,

    #[command(flatten)]
    pub limits: LimitArgs,

    /// Most frames read from the input; 0: no limit. Default: 100000 for a file or folder (a
    /// GIF or folder with more is refused before any frame is decoded; other files stop with
    /// an error at the frame past the limit, after the frames before it); no limit on stdin,
    /// so a pipe from ffmpeg runs as long as it lasts.
    #[arg(long, value_name = "N", value_parser = parse_count, help_heading = "Limits")]
    pub max_frames: Option<u64>,
}

/// Bounds on what reading an input may cost (`--max-pixels`, `--memory-limit`). Inputs that
/// go past one are refused from their header, before the big allocations, with a message
/// naming the option.
#[derive(clap::Args, Debug, Default, Clone)]
#[command(next_help_heading = "Limits")]
pub struct LimitArgs {
    /// Most pixels in one input frame (width x height), checked from the file's header before
    /// decoding; 0: no limit but 16384 px a side. Default 40000000: 8K UHD (7680x4320) fits.
    #[arg(long, value_name = "N", value_parser = parse_count)]
    pub max_pixels: Option<u64>,

    /// Most memory a run may hold: decoded frames in flight, the method's working memory, the
    /// output's buffers; e.g. 512M, 2G, or bytes; 0: no limit. Default 2.5G: any picture
    /// within --max-pixels at a size up to its own, a stream up to about 24 megapixels a
    /// frame. A stream that would need more runs with fewer frames in flight if that fits,
    /// else it is refused before any work.
    #[arg(long, value_name = "SIZE", value_parser = parse_memory)]
    pub memory_limit: Option<u64>,
}

impl LimitArgs {
    /// The library's limits: defaults where no option is given, 0 as no limit, and
    /// `max_frames` as given (the caller decides its default).
    pub fn limits(&self, max_frames: Option<u64>) -> vizretarget::Limits {
        let off = |v: u64| (v != 0).then_some(v);
        let d = vizretarget::Limits::default();
        vizretarget::Limits {
            max_pixels: self.max_pixels.map_or(d.max_pixels, off),
            max_frames,
            memory_budget: self.memory_limit.map_or(d.memory_budget, off),
        }
    }
}

impl Cli {
    /// The target as given: `--size`, else `--width` and `--height`.
    pub fn target(&self) -> Target {
        Target::of(self.size, self.width, self.height)
    }

    /// The limits of a run reading `input` (`-`: stdin, which has no default frame limit).
    pub fn limits_for(&self, stdin: bool) -> vizretarget::Limits {
        let frames = match self.max_frames {
            Some(0) => None,
            Some(n) => Some(n),
            None if stdin => None,
            None => Some(vizretarget::Limits::DEFAULT_MAX_FRAMES),
        };
        self.limits.limits(frames)
    }
}

fn parse_count(s: &str) -> Result<u64, String> {
    s.trim()
        .replace('_', "")
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number (0: no limit)"))
}

fn parse_memory(s: &str) -> Result<u64, String> {
    vizretarget::parse_bytes(s)
}

/// Vector marks (§5.3) and content enhancement (§5.4).
#[derive(clap::Args, Debug, Default)]
pub struct VectorArgs {
    /// Marks given as vectors, bound to the mesh and redrawn crisp (round stays round) over
    /// the resized picture: a JSON file (one layer: for a stream, on every frame), a JSON
    /// Lines file (.jsonl: one line per frame, in order), or a folder of per-frame files
    /// (frame-0001.json for frame-0001.png). For a folder of frames, sidecars beside the
    /// frames are used without this option. The format: points {x, y, r, fill, stroke,
    /// stroke_width, id}, polylines {points, width, color}, edges {from, to, width, color}
    /// (README, "Vector marks and enhancement").
    #[arg(long, value_name = "FILE|DIR")]
    pub marks: Option<PathBuf>,

    /// The marks are also in the picture: fill their footprints from the colours around them
    /// first, so that each is drawn once.
    #[arg(long)]
    pub paint_out_marks: bool,

    /// Size of point marks: mesh (radius times the local scale the mesh gives the mark; they
    /// grow with --enhance) or keep (radius as given).
    #[arg(long, value_name = "RULE", value_enum, default_value_t = MarkSizeArg::Mesh)]
    pub mark_size: MarkSizeArg,

    /// Enlarge by saliency level: D1,D2,D3 are the factors of the background, context and
    /// salient levels (the paper's δ_k, Eq. 13), e.g. 1,1,1.4; each 0.25 to 4.
    #[arg(long, value_name = "D1,D2,D3", value_parser = parse_levels)]
    pub enhance: Option<[f64; 3]>,

    /// Enlarge a rectangle of the input, X,Y,W,H=FACTOR in input pixels, e.g.
    /// 120,80,300,200=1.5 (factor 0.25 to 4). Repeat for more; where they overlap, the last
    /// given wins. In a stream the rectangle stays where it is in the input and the mesh
    /// carries it.
    #[arg(long, value_name = "X,Y,W,H=F", value_parser = parse_region)]
    pub enhance_region: Vec<vizretarget::EnhanceRegion>,

    /// Enlarge where a grey picture is light: black leaves content as it is, white enlarges
    /// it by --enhance-mask-factor, grey in between (linear in the grey level, times alpha).
    /// Stretched over the frames if its size differs.
    #[arg(long, value_name = "MASK.png")]
    pub enhance_mask: Option<PathBuf>,

    /// The factor white stands for in --enhance-mask, 0.25 to 4.
    #[arg(long, value_name = "F", default_value_t = 1.5, requires = "enhance_mask",
          value_parser = parse_factor)]
    pub enhance_mask_factor: f64,
}

/// `--mark-size` values.
#[derive(clap::ValueEnum, Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum MarkSizeArg {
    #[default]
    Mesh,
    Keep,
}

fn parse_factor(s: &str) -> Result<f64, String> {
    let f: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    let (lo, hi) = vizretarget::Enhancement::FACTOR_RANGE;
    if !(lo..=hi).contains(&f) {
        return Err(format!("factor {f} is out of range: {lo} to {hi}"));
    }
    Ok(f)
}

fn parse_levels(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!(
            "'{s}' is not three factors D1,D2,D3 (background, context, salient), e.g. 1,1,1.4"
        ));
    }
    Ok([
        parse_factor(parts[0])?,
        parse_factor(parts[1])?,
        parse_factor(parts[2])?,
    ])
}

fn parse_region(s: &str) -> Result<vizretarget::EnhanceRegion, String> {
    let usage = || format!("'{s}' is not X,Y,W,H=FACTOR (e.g. 120,80,300,200=1.5)");
    let (rect, factor) = s.split_once('=').ok_or_else(usage)?;
    let v: Vec<f64> = rect
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| usage())?;
    if v.len() != 4 || v.iter().any(|x| !x.is_finite()) {
        return Err(usage());
    }
    if v[2] <= 0.0 || v[3] <= 0.0 {
        return Err(format!("'{s}': the width and height must be above 0"));
    }
    Ok(vizretarget::EnhanceRegion {
        x: v[0],
        y: v[1],
        width: v[2],
        height: v[3],
        factor: parse_factor(factor)?,
    })
}

/// Options of streams of frames.
#[derive(clap::Args, Debug, Default)]
pub struct StreamArgs {
    /// How to read stdin (or a file): auto recognises by content one picture (a PNG followed
    /// by the end of the input, a JPEG, WebP or GIF file), a PNG stream or YUV4MPEG2; png
    /// reads a PNG stream even of one PNG; rgba and rgb24 are raw frames as `ffmpeg -f rawvideo -pix_fmt rgba -` writes them and
    /// need --input-size.
    #[arg(long, value_name = "FORMAT", value_enum, default_value_t = InputArg::Auto)]
    pub input_format: InputArg,

    /// Frame size of raw input, WIDTHxHEIGHT in px.
    #[arg(long, value_name = "WxH", value_parser = parse_px_size)]
    pub input_size: Option<(u32, u32)>,

    /// What to write: auto decides by the output path (on stdout: one picture as PNG, as
    /// image tools do, and a stream as YUV4MPEG2); png-seq writes a folder; png on stdout is a
    /// stream of PNG files (`ffmpeg -f image2pipe -i -` reads it), y4m on stdout also for one
    /// picture.
    #[arg(long, value_name = "FORMAT", value_enum, default_value_t = OutputArg::Auto)]
    pub output_format: OutputArg,

    /// Frames per second of the output: GIF delays and the YUV4MPEG2 header. Default: the
    /// input's own timing (GIF delays, YUV4MPEG2 rate), else 10 fps for a GIF and 25 for
    /// YUV4MPEG2. 0.001 to 1000.
    #[arg(long, value_name = "FPS", value_parser = parse_fps)]
    pub fps: Option<f64>,

    /// Write per-frame statistics to FILE as JSON: frame index (and file name), reuse decision,
    /// vertices, triangles, DOF, milliseconds per stage; and the run's summary.
    #[arg(long, value_name = "FILE")]
    pub stats_json: Option<PathBuf>,

    /// No progress bar and no summary line on stderr (errors are still reported).
    #[arg(short, long)]
    pub quiet: bool,

    /// Build every frame from scratch: no reuse of the previous frame's mesh and solution
    /// (slower, and static content may shimmer; for comparison).
    #[arg(long, help_heading = "Reuse between frames")]
    pub no_reuse: bool,

    /// Side in px of the tiles saliency changes are tracked in: smaller tiles re-mesh less
    /// around a small moving mark, larger ones cost less to compare. 4 to 1024.
    #[arg(long, value_name = "PX", default_value_t = ReuseOptions::default().tile_px,
          value_parser = parse_tile_px, help_heading = "Reuse between frames")]
    pub reuse_tile: u32,

    /// Mean saliency change (0 to 1) above which a tile counts as changed; a 6-px dot moving
    /// in a 32-px tile changes it by about 0.1. Raise it to ignore noise and flicker.
    #[arg(long, value_name = "T", default_value_t = ReuseOptions::default().tile_threshold,
          value_parser = parse_unit_f32, help_heading = "Reuse between frames")]
    pub tile_threshold: f32,

    /// Share of changed tiles (0 to 1) above which the mesh is rebuilt rather than updated
    /// locally; no changed tile reuses mesh and solution as they are.
    #[arg(long, value_name = "F", default_value_t = ReuseOptions::default().rebuild_fraction,
          value_parser = parse_unit_f64, help_heading = "Reuse between frames")]
    pub rebuild_fraction: f64,
}

impl StreamArgs {
    /// The reuse policy these options ask for (checked by `Options::validate`).
    pub fn reuse(&self) -> ReuseOptions {
        ReuseOptions {
            enabled: !self.no_reuse,
            tile_px: self.reuse_tile,
            tile_threshold: self.tile_threshold,
            rebuild_fraction: self.rebuild_fraction,
        }
    }
}

/// Subcommands.
#[derive(clap::Subcommand, Debug)]
pub enum Command {
    /// Watch a folder of dashboard snapshots and retarget each new or replaced one into OUTDIR.
    #[command(
        override_usage = "vizretarget watch <DIR> -o <OUTDIR> (--size WxH | --width N | --height N) [OPTIONS]",
        after_long_help = WATCH_HELP
    )]
    #[command(group = clap::ArgGroup::new("target").args(["size", "width", "height"]).required(true).multiple(true))]
    Watch(WatchArgs),

    /// Write one sheet with the original and every method's output side by side, labelled, and
    /// print their measures (saliency preservation, distortion, salient area kept, mesh size,
    /// milliseconds per stage).
    #[command(
        override_usage = "vizretarget compare <INPUT> (--size WxH | --width N | --height N) -o <SHEET.png> [--mesh] [--metrics] [--json]",
        after_long_help = COMPARE_HELP
    )]
    #[command(group = clap::ArgGroup::new("target").args(["size", "width", "height"]).required(true).multiple(true))]
    Compare(CompareArgs),

    /// Print the completion script of a shell on stdout, e.g. `vizretarget completions bash >
    /// ~/.local/share/bash-completion/completions/vizretarget`.
    Completions {
        /// The shell: bash, zsh or fish.
        #[arg(value_enum)]
        shell: ShellArg,
    },
}

/// Shells `vizretarget completions` writes for.
#[derive(clap::ValueEnum, Copy, Clone, Debug, PartialEq, Eq)]
pub enum ShellArg {
    Bash,
    Zsh,
    Fish,
}

impl From<ShellArg> for clap_complete::Shell {
    fn from(s: ShellArg) -> clap_complete::Shell {
        match s {
            ShellArg::Bash => clap_complete::Shell::Bash,
            ShellArg::Zsh => clap_complete::Shell::Zsh,
            ShellArg::Fish => clap_complete::Shell::Fish,
        }
    }
}

/// Arguments of `vizretarget compare`.
#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// The picture to resize: PNG, JPEG, WebP or GIF (first frame).
    pub input: PathBuf,

    /// The sheet to write: .png, .jpg or .jpeg.
    #[arg(short, long, value_name = "SHEET")]
    pub output: PathBuf,

    /// Target size as WIDTHxHEIGHT, each side in px (1 to 16384) or a percentage of the
    /// input's (50%x100%); 400x or x300 keep the other side; 50% scales both sides.
    #[arg(short, long, value_name = "WxH", allow_hyphen_values = true,
          conflicts_with_all = ["width", "height"], value_parser = parse_size)]
    pub size: Option<Target>,

    /// Target width in px or a percentage (50%); the height stays as in the input unless
    /// --height is given.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub width: Option<Side>,

    /// Target height in px or a percentage (50%); the width stays as in the input unless
    /// --width is given.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub height: Option<Side>,

    /// Mesh spacing α in px (mesh, and the grid's cell), 4 to 200.
    #[arg(long, value_name = "N", default_value_t = 20.0, value_parser = parse_alpha)]
    pub alpha: f32,

    /// Draw the mesh over the mesh and grid outputs (and the source mesh over the original).
    #[arg(long)]
    pub mesh: bool,

    /// Add saliency mean and distortion under each panel's label.
    #[arg(long)]
    pub metrics: bool,

    /// Print the measures as JSON on stdout instead of a table.
    #[arg(long)]
    pub json: bool,

    #[command(flatten)]
    pub limits: LimitArgs,
}

/// `--regions` values.
#[derive(clap::ValueEnum, Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum RegionsArg {
    Auto,
    #[default]
    Affine,
    Free,
}

impl From<RegionsArg> for vizretarget::Regions {
    fn from(r: RegionsArg) -> vizretarget::Regions {
        match r {
            RegionsArg::Auto => vizretarget::Regions::Auto,
            RegionsArg::Affine => vizretarget::Regions::Affine,
            RegionsArg::Free => vizretarget::Regions::Free,
        }
    }
}

/// `--method` values.
#[derive(clap::ValueEnum, Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum MethodArg {
    #[default]
    Mesh,
    Linear,
    Crop,
    Grid,
    Seam,
    Axis,
}

impl From<MethodArg> for vizretarget::Method {
    fn from(m: MethodArg) -> vizretarget::Method {
        match m {
            MethodArg::Mesh => vizretarget::Method::Mesh,
            MethodArg::Linear => vizretarget::Method::Linear,
            MethodArg::Crop => vizretarget::Method::Crop,
            MethodArg::Grid => vizretarget::Method::Grid,
            MethodArg::Seam => vizretarget::Method::Seam,
            MethodArg::Axis => vizretarget::Method::Axis,
        }
    }
}

/// Arguments of `vizretarget watch`.
#[derive(clap::Args, Debug)]
pub struct WatchArgs {
    /// The folder to watch (not recursively).
    pub dir: PathBuf,

    /// The folder to write into (created if missing; not DIR itself).
    #[arg(short, long, value_name = "OUTDIR")]
    pub output: PathBuf,

    /// Target size as WIDTHxHEIGHT, each side in px (1 to 16384) or a percentage of each
    /// snapshot's (50%x100%); 400x or x300 keep the other side as in each snapshot; 50%
    /// scales both sides.
    #[arg(short, long, value_name = "WxH", allow_hyphen_values = true,
          conflicts_with_all = ["width", "height"], value_parser = parse_size)]
    pub size: Option<Target>,

    /// Target width in px or a percentage (50%); the height stays as in each snapshot unless
    /// --height is given.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub width: Option<Side>,

    /// Target height in px or a percentage (50%); the width stays as in each snapshot unless
    /// --width is given.
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_side)]
    pub height: Option<Side>,

    /// Mesh spacing α in px, 4 to 200.
    #[arg(long, value_name = "N", default_value_t = 20.0, value_parser = parse_alpha)]
    pub alpha: f32,

    /// Which parts of each snapshot the warp may bend (see `vizretarget --help`): affine
    /// (the default), auto or free.
    #[arg(long, value_name = "REGIONS", value_enum, default_value_t = RegionsArg::Affine)]
    pub regions: RegionsArg,

    /// Fill the whole target size where nothing gives way (see `vizretarget --help`).
    #[arg(long)]
    pub fill: bool,

    /// Do not lay charts out again for the target (see `vizretarget --help`).
    #[arg(long)]
    pub no_layout: bool,

    /// How long a snapshot must stay unchanged before it is read when its writer's close was
    /// not seen (files already there at the start; platforms without close-write events), in
    /// ms. On Linux a file still open for writing waits up to 10 times this.
    #[arg(long, value_name = "MS", default_value_t = 200)]
    pub settle_ms: u64,

    /// Write per-snapshot statistics (with file names) to FILE as JSON when watching stops.
    #[arg(long, value_name = "FILE")]
    pub stats_json: Option<PathBuf>,

    /// No line per snapshot on stderr (warnings are still reported).
    #[arg(short, long)]
    pub quiet: bool,

    #[command(flatten)]
    pub limits: LimitArgs,
}

/// `--input-format` values.
#[derive(clap::ValueEnum, Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum InputArg {
    #[default]
    Auto,
    Rgba,
    Rgb24,
    Y4m,
    /// Concatenated PNG files.
    Png,
}

/// `--output-format` values.
#[derive(clap::ValueEnum, Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum OutputArg {
    #[default]
    Auto,
    Gif,
    PngSeq,
    Png,
    Jpeg,
    Rgba,
    Rgb24,
    Y4m,
}

fn parse_fps(s: &str) -> Result<f64, String> {
    let f: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number of frames per second"))?;
    if !(0.001..=1000.0).contains(&f) {
        return Err(format!("{f} fps is out of range: 0.001 to 1000"));
    }
    Ok(f)
}

/// `--width N`, `--height N`: px or a percentage, read by the library ([`Side::parse`]).
fn parse_side(s: &str) -> Result<Side, String> {
    Side::parse(s).map_err(|e| e.0)
}

fn parse_px(s: &str) -> Result<u32, String> {
    Side::parse_px(s).map_err(|e| e.0)
}

/// `--size WxH`, or a lone percentage of both sides, read by the library ([`Target::parse`]).
fn parse_size(s: &str) -> Result<Target, String> {
    Target::parse(s).map_err(|e| e.0)
}

/// `WxH` in px, both sides (the size of raw frames).
fn parse_px_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT in px (e.g. 1280x720)"))?;
    Ok((parse_px(w)?, parse_px(h)?))
}

/// A number in `lo..=hi`, named `what` in the message.
fn number_in(s: &str, what: &str, lo: f64, hi: f64) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if !(lo..=hi).contains(&v) {
        return Err(format!("{what}{v} is out of range: {lo} to {hi}"));
    }
    Ok(v)
}

fn parse_alpha(s: &str) -> Result<f32, String> {
    number_in(s, "alpha ", 4.0, 200.0).map(|v| v as f32)
}

fn parse_tile_px(s: &str) -> Result<u32, String> {
    let v = number_in(s, "", 4.0, 1024.0)?;
    if v.fract() != 0.0 {
        return Err(format!("'{s}' is not a whole number of pixels"));
    }
    Ok(v as u32)
}

fn parse_unit_f32(s: &str) -> Result<f32, String> {
    number_in(s, "", 0.0, 1.0).map(|v| v as f32)
}

fn parse_unit_f64(s: &str) -> Result<f64, String> {
    number_in(s, "", 0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vizretarget::Size;

    #[test]
    fn sizes_parse_and_bad_ones_explain() {
        let px = |w, h| Target {
            width: Some(Side::Px(w)),
            height: Some(Side::Px(h)),
        };
        assert_eq!(parse_size("400x600"), Ok(px(400, 600)));
        assert_eq!(parse_size("16384X1"), Ok(px(16384, 1)));
        assert!(parse_size("0x10").unwrap_err().contains("out of range"));
        assert!(parse_size("-5x10").unwrap_err().contains("out of range"));
        assert!(parse_size("axb")
            .unwrap_err()
            .contains("not a whole number"));
        assert!(parse_size("400").unwrap_err().contains("WIDTHxHEIGHT"));
        assert!(parse_size("20000x10").unwrap_err().contains("out of range"));
        assert_eq!(parse_fps("29.97"), Ok(29.97));
        assert!(parse_fps("0").unwrap_err().contains("out of range"));
        assert!(parse_fps("x").unwrap_err().contains("not a number"));
    }

    #[test]
    fn percentages_and_one_side_resolve_per_input() {
        let from = Size::new(672, 480).unwrap();
        let t = parse_size("50%x100%").unwrap();
        assert_eq!(t.resolve(from).unwrap(), Size::new(336, 480).unwrap());
        assert_eq!(t.fixed(), None);
        let t = parse_size("400x").unwrap();
        assert_eq!(t.resolve(from).unwrap(), Size::new(400, 480).unwrap());
        let t = parse_size("x300").unwrap();
        assert_eq!(t.resolve(from).unwrap(), Size::new(672, 300).unwrap());
        assert_eq!(parse_side(" 12.5% "), Ok(Side::Percent(12.5)));
        // One percentage is both sides, as ImageMagick reads `-resize 200%`.
        let t = parse_size("200%").unwrap();
        assert_eq!(t.resolve(from).unwrap(), Size::new(1344, 960).unwrap());
        assert_eq!(
            parse_size("12.5%").unwrap().resolve(from).unwrap(),
            Size::new(84, 60).unwrap()
        );
        assert!(parse_size("0%").unwrap_err().contains("out of range"));
        for bad in ["0%", "-5%", "abc%", "1e9%", "NaN%", "%"] {
            let e = parse_side(bad).unwrap_err();
            assert!(e.contains(bad.trim()), "{bad}: {e}");
        }
        assert!(parse_size("x").unwrap_err().contains("neither side"));
        assert!(parse_side("").unwrap_err().contains("not a whole number"));
        let huge = Target::of(None, Some(Side::Percent(5000.0)), None);
        let e = huge.resolve(from).unwrap_err().to_string();
        assert!(
            e.contains("5000% of the input's width (672 px) is 33600 px"),
            "{e}"
        );
        assert!(parse_px_size("400x").is_err());
        assert!(parse_alpha("2")
            .unwrap_err()
            .contains("alpha 2 is out of range"));
        assert!(parse_unit_f32("2")
            .unwrap_err()
            .contains("out of range: 0 to 1"));
    }

    #[test]
    fn still_form_and_watch_subcommand_both_parse() {
        let c = Cli::try_parse_from(["v", "in.png", "-o", "o.png", "--width", "3"]).unwrap();
        assert!(c.command.is_none());
        assert_eq!(c.input.as_deref(), Some(std::path::Path::new("in.png")));
        let c = Cli::try_parse_from(["v", "watch", "d", "-o", "out", "--size", "3x4"]).unwrap();
        match c.command {
            Some(Command::Watch(w)) => {
                assert_eq!(w.size.and_then(|t| t.fixed()), Size::new(3, 4).ok())
            }
            other => panic!("{other:?}"),
        }
        assert!(
            Cli::try_parse_from(["v", "watch", "d", "-o", "out"]).is_err(),
            "needs a target"
        );
        let c =
            Cli::try_parse_from(["v", "compare", "i.png", "-o", "s.png", "--width", "9"]).unwrap();
        match c.command {
            Some(Command::Compare(a)) => {
                assert_eq!((a.width, a.mesh, a.json), (Some(Side::Px(9)), false, false))
            }
            other => panic!("{other:?}"),
        }
        assert!(
            Cli::try_parse_from(["v", "compare", "i.png", "-o", "s.png"]).is_err(),
            "needs a target"
        );
        let c = Cli::try_parse_from(["v", "completions", "zsh"]).unwrap();
        assert!(matches!(
            c.command,
            Some(Command::Completions {
                shell: ShellArg::Zsh
            })
        ));
        assert!(Cli::try_parse_from(["v", "completions", "tcsh"]).is_err());
        let c = Cli::try_parse_from([
            "v", "in.png", "-o", "o.png", "--width", "3", "--method", "seam",
        ])
        .unwrap();
        assert_eq!(c.method, MethodArg::Seam);
        assert!(Cli::try_parse_from([
            "v", "in.png", "-o", "o.png", "--width", "3", "--method", "blur"
        ])
        .is_err());
        assert!(
            Cli::try_parse_from(["v", "in.png", "-o", "o.png"]).is_err(),
            "needs a target"
        );
        assert!(
            Cli::try_parse_from(["v", "--width", "3", "-o", "o.png"]).is_err(),
            "needs input"
        );
    }

    #[test]
    fn command_is_well_formed() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
