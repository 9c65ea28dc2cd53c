//! Bounds on what reading an input may cost: pixels per frame, frames per input, and the bytes
//! a whole run holds.
//!
//! Why: a 60-byte GIF can declare a 16384x16384 canvas (1 GiB of RGBA before its first frame
//! is drawn); a few megabytes of GIF hold a million one-pixel frames, each composited onto that
//! canvas and retargeted; a PNG's zlib stream inflates a thousandfold. So every source checks
//! its header against [`Limits`] before it allocates pixels, a GIF's frames are counted by
//! walking its blocks before any is decoded, other streams are counted as they are read, and a
//! run's memory is estimated from the frame and target sizes before any work
//! ([`Limits::plan_stream`], [`Limits::check_still`]).
//!
//! The estimates are linear in the input and output pixels, with per-pixel costs measured on
//! this code (peak RSS of runs from 1 to 33 megapixels, see the constants); they err on the
//! high side, as a budget should.

use crate::error::Error;
use crate::image::{Size, MAX_SIDE};
use std::path::{Path, PathBuf};

pub use crate::error::Limit;

/// How much an input may make the library allocate and do. `None` turns a bound off.
///
/// ```
/// use vizretarget::Limits;
/// let tight = Limits::default().with_max_pixels(Some(4_000_000)).with_max_frames(Some(500));
/// assert_eq!(tight.max_pixels, Some(4_000_000));
/// assert_eq!(Limits::default().max_frames, Some(Limits::DEFAULT_MAX_FRAMES));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Most pixels in one frame (width × height), checked from the header before decoding.
    /// Default [`Limits::DEFAULT_MAX_PIXELS`]. Each side is also bounded by [`MAX_SIDE`],
    /// whatever this says.
    pub max_pixels: Option<u64>,
    /// Most frames read from one input. Default [`Limits::DEFAULT_MAX_FRAMES`]. A GIF file or a
    /// folder with more is refused before its first frame is decoded; a stream (a pipe, a
    /// YUV4MPEG2 or raw file) is counted as it is read, and the frame past the limit ends the
    /// run with an error after the frames before it. An endless pipe wants `None`: the command
    /// line gives stdin no frame limit unless `--max-frames` is given.
    pub max_frames: Option<u64>,
    /// Most bytes a run may hold: decoded frames in flight, the method's working memory, the
    /// sink's buffers. Default [`Limits::DEFAULT_MEMORY_BUDGET`]. A stream that does not fit
    /// with one frame waiting between stages is run with none waiting (about half the frames
    /// in flight, a little slower); if that does not fit either it is refused.
    pub memory_budget: Option<u64>,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_pixels: Some(Limits::DEFAULT_MAX_PIXELS),
            max_frames: Some(Limits::DEFAULT_MAX_FRAMES),
            memory_budget: Some(Limits::DEFAULT_MEMORY_BUDGET),
        }
    }
}

impl Limits {
    /// 40 megapixels: 8K UHD (7680x4320, 33.2 MP) fits, and so do tall dashboards of the
    /// same area; a still this size peaked at 1.7 to 2.0 GB (7680x5200 to widths 1920 to
    /// 7680).
    pub const DEFAULT_MAX_PIXELS: u64 = 40_000_000;
    /// 100 000 frames: over an hour of 25 fps video, hours of any real GIF; a million-frame
    /// GIF (a few MB of one-pixel frames) is refused before decoding.
    pub const DEFAULT_MAX_FRAMES: u64 = 100_000;
    /// 2.5 GiB: every still within [`Limits::DEFAULT_MAX_PIXELS`] fits at any target up to
    /// its own size (estimated 2.35 GB at 40 MP), so the pixel limit is the one ordinary
    /// jobs meet; larger targets, `compare` and streams of more than about 24 MP a frame
    /// (6000x4000; above about 15 MP with fewer frames in flight) meet this one.
    pub const DEFAULT_MEMORY_BUDGET: u64 = 5 << 29;

    /// No bounds but [`MAX_SIDE`].
    pub fn unlimited() -> Limits {
        Limits {
            max_pixels: None,
            max_frames: None,
            memory_budget: None,
        }
    }

    pub fn with_max_pixels(mut self, max: Option<u64>) -> Limits {
        self.max_pixels = max;
        self
    }

    pub fn with_max_frames(mut self, max: Option<u64>) -> Limits {
        self.max_frames = max;
        self
    }

    pub fn with_memory_budget(mut self, bytes: Option<u64>) -> Limits {
        self.memory_budget = bytes;
        self
    }

    /// Checks a frame size read from a header: each side 1 to [`MAX_SIDE`] (a hard bound, not
    /// an option), then [`Limits::max_pixels`]. `what` says what declared it ("GIF", "PNG
    /// 3 of the stream", "frame 7") for the message.
    pub fn check_size(
        &self,
        name: &Path,
        what: &str,
        width: u64,
        height: u64,
    ) -> Result<Size, Error> {
        let side = |v: u64| (1..=MAX_SIDE as u64).contains(&v);
        if !side(width) || !side(height) {
            return Err(Error::decode(
                name,
                format!(
                    "{what} declares {width}x{height} px: out of range, each side must be 1 to \
                     {MAX_SIDE}"
                ),
            ));
        }
        self.check_pixels(name, what, width, height)?;
        Ok(Size::new(width as u32, height as u32)?)
    }

    /// Checks `width × height` against [`Limits::max_pixels`] (sides unchecked: a GIF frame's
    /// rectangle may lie partly off its canvas).
    pub fn check_pixels(
        &self,
        name: &Path,
        what: &str,
        width: u64,
        height: u64,
    ) -> Result<(), Error> {
        let px = width.saturating_mul(height);
        match self.max_pixels {
            Some(max) if px > max => Err(Error::LimitExceeded {
                path: name.to_path_buf(),
                limit: Limit::Pixels,
                needed: Some(px),
                message: format!(
                    "{what} declares {width}x{height} px ({px} pixels), above the limit of {max} \
                     pixels a frame"
                ),
            }),
            _ => Ok(()),
        }
    }

    /// Checks that an input holding `count` frames (`at_least`: the count stopped early, there
    /// are more) is within [`Limits::max_frames`].
    pub fn check_frame_count(&self, name: &Path, count: u64, at_least: bool) -> Result<(), Error> {
        match self.max_frames {
            Some(max) if count > max || (at_least && count >= max) => Err(Error::LimitExceeded {
                path: name.to_path_buf(),
                limit: Limit::Frames,
                needed: (!at_least).then_some(count),
                message: format!(
                    "holds {}{count} frames, above the limit of {max} frames",
                    if at_least { "more than " } else { "" },
                    count = if at_least { max } else { count },
                ),
            }),
            _ => Ok(()),
        }
    }

    /// Checks that frame `frame_index` (from 0) may still be read: the error when a stream
    /// goes past [`Limits::max_frames`].
    pub fn check_frame_index(&self, name: &Path, frame_index: u64) -> Result<(), Error> {
        match self.max_frames {
            Some(max) if frame_index >= max => Err(too_many_frames(name, max)),
            _ => Ok(()),
        }
    }

    /// How many bytes the decoders may allocate for one picture: the whole budget (the run's
    /// estimate is checked separately, before decoding, where the target size is known).
    pub(crate) fn decode_bytes(&self) -> Option<u64> {
        self.memory_budget
    }

    /// Checks the memory of one picture retargeted from `input` to `target` px (the still job;
    /// a caller of [`crate::retarget`] may ask it too); returns the estimate in bytes.
    pub fn check_still(&self, name: &Path, input: Size, target: Size) -> Result<u64, Error> {
        let bytes = still_bytes(input, target);
        self.check_bytes(name, bytes, || {
            format!("retargeting one {input} picture to {target}")
        })?;
        Ok(bytes)
    }

    /// Checks the memory of `vizretarget compare`: every method on one `input` picture, the
    /// outputs kept for the sheet.
    pub fn check_compare(&self, name: &Path, input: Size, target: Size) -> Result<u64, Error> {
        let bytes = compare_bytes(input, target);
        self.check_bytes(name, bytes, || {
            format!("comparing every method on one {input} picture at {target}")
        })?;
        Ok(bytes)
    }

    /// Plans a stream of `frame`-sized frames to `target` into a sink that holds
    /// `sink_bytes_per_px` bytes per output pixel (see [`crate::io::SinkFormat`]): one frame
    /// waiting between stages if that fits the budget, none if only that fits, else
    /// [`Error::LimitExceeded`].
    pub fn plan_stream(
        &self,
        name: &Path,
        frame: Size,
        target: Size,
        sink_bytes_per_px: u64,
    ) -> Result<MemoryPlan, Error> {
        let mut plan = MemoryPlan {
            name: name.to_path_buf(),
            budget: self.memory_budget,
            target,
            sink_bytes_per_px,
            channel_capacity: 1,
            frame,
            bytes: 0,
        };
        plan.bytes = plan.estimate(frame, 1);
        if self.memory_budget.is_none_or(|b| plan.bytes <= b) {
            return Ok(plan);
        }
        let lean = plan.estimate(frame, 0);
        self.check_bytes(name, lean, || {
            format!("retargeting a stream of {frame} frames to {target}")
        })?;
        plan.channel_capacity = 0;
        plan.bytes = lean;
        Ok(plan)
    }

    fn check_bytes(&self, name: &Path, bytes: u64, job: impl Fn() -> String) -> Result<(), Error> {
        match self.memory_budget {
            Some(budget) if bytes > budget => Err(Error::LimitExceeded {
                path: name.to_path_buf(),
                limit: Limit::Memory,
                needed: Some(bytes),
                message: format!(
                    "{} needs about {}, above the memory limit of {}",
                    job(),
                    human_bytes(bytes),
                    human_bytes(budget)
                ),
            }),
            _ => Ok(()),
        }
    }
}

/// The error of a stream that goes on past `max` frames.
pub(crate) fn too_many_frames(name: &Path, max: u64) -> Error {
    Error::LimitExceeded {
        path: name.to_path_buf(),
        limit: Limit::Frames,
        needed: None,
        message: format!("goes on past {max} frames, the limit (the frames before were read)"),
    }
}

/// How a stream run fits its memory budget: how many frames wait between stages, and what the
/// run is estimated to hold. Frames of another size are admitted one by one
/// ([`MemoryPlan::admit`]).
#[derive(Clone, Debug)]
pub struct MemoryPlan {
    name: PathBuf,
    budget: Option<u64>,
    target: Size,
    sink_bytes_per_px: u64,
    /// Frames waiting in each channel between two stages: 1, or 0 (handed over directly) when
    /// only that fits the budget.
    pub channel_capacity: usize,
    /// The frame size planned for.
    pub frame: Size,
    /// Estimated bytes the run holds at its peak.
    pub bytes: u64,
}

impl MemoryPlan {
    /// A plan without a budget, one frame waiting between stages: what [`crate::Pipeline::run`]
    /// uses.
    pub fn unbounded(frame: Size, target: Size) -> MemoryPlan {
        MemoryPlan {
            name: PathBuf::new(),
            budget: None,
            target,
            sink_bytes_per_px: 0,
            channel_capacity: 1,
            frame,
            bytes: 0,
        }
    }

    /// Checks a frame of `size` (a stream whose frames change size: a PNG stream, a watched
    /// folder) against the budget with the channels as planned.
    pub fn admit(&self, frame_index: u64, size: Size) -> Result<(), Error> {
        let Some(budget) = self.budget else {
            return Ok(());
        };
        if size.area() <= self.frame.area() {
            return Ok(());
        }
        let bytes = self.estimate(size, self.channel_capacity);
        if bytes <= budget {
            return Ok(());
        }
        Err(Error::LimitExceeded {
            path: self.name.clone(),
            limit: Limit::Memory,
            needed: Some(bytes),
            message: format!(
                "frame {frame_index} is {size}, larger than the frames before it: retargeting it \
                 to {} needs about {}, above the memory limit of {}",
                self.target,
                human_bytes(bytes),
                human_bytes(budget)
            ),
        })
    }

    fn estimate(&self, frame: Size, capacity: usize) -> u64 {
        stream_bytes(frame, self.target, capacity, self.sink_bytes_per_px)
    }
}

/// Bytes of the program itself, its threads and tables, before any picture.
const BASE_BYTES: u64 = 24 << 20;

/// A still job at its peak, per input pixel: the decoded RGBA (4 B), the decoder's own buffer
/// while converting (up to 4 B), the saliency map's Lab planes and filters (about 20 B at full
/// resolution), structure detection's luma and transposed copies, the renderer's mip levels
/// (about 5 B). Measured: 38-39 B per input pixel from 1 to 33 MP, up to 43 B at 40 MP
/// (7680x5200 to 3840x5200: 1.97 GB peak); 46 keeps the estimate above what was measured.
const STILL_PER_IN_PX: u64 = 46;
/// Per output pixel: the output picture and its encoded copy.
const STILL_PER_OUT_PX: u64 = 12;

/// Bytes of one still job.
pub fn still_bytes(input: Size, target: Size) -> u64 {
    BASE_BYTES + STILL_PER_IN_PX * input.area() as u64 + STILL_PER_OUT_PX * target.area() as u64
}

/// `compare` keeps the source, its saliency map and five outputs, and seam carving's energy
/// and index maps at the source size.
fn compare_bytes(input: Size, target: Size) -> u64 {
    BASE_BYTES
        + 2 * STILL_PER_IN_PX * input.area() as u64
        + 8 * STILL_PER_OUT_PX * target.area() as u64
}

/// Stage threads that each hold a frame while working: ingest, saliency, mesh, solve, render.
const STAGES: u64 = 5;
/// Channels between them (and the sink).
const CHANNELS: u64 = 5;
/// Per input pixel and frame in flight: the frame (4 B) and its saliency map (4 B when the
/// frame changed; shared when it did not).
const STREAM_PER_FRAME_IN_PX: u64 = 8;
/// Per input pixel, whatever the depth: the stages' scratch (saliency builder, the previous
/// frame and map for the reuse decision, the renderer's mip levels, decoding).
const STREAM_FIXED_PER_IN_PX: u64 = 36;
/// Per output pixel and frame in flight: the rendered frame.
const STREAM_PER_FRAME_OUT_PX: u64 = 4;

/// Bytes of a stream run of `frame` frames to `target` with `capacity` frames waiting in each
/// channel, into a sink holding `sink_bytes_per_px` per output pixel.
pub fn stream_bytes(frame: Size, target: Size, capacity: usize, sink_bytes_per_px: u64) -> u64 {
    let in_flight = STAGES + CHANNELS * capacity as u64;
    let (i, o) = (frame.area() as u64, target.area() as u64);
    BASE_BYTES
        + i * (STREAM_FIXED_PER_IN_PX + in_flight * STREAM_PER_FRAME_IN_PX)
        + o * (in_flight * STREAM_PER_FRAME_OUT_PX + sink_bytes_per_px)
}

/// `1.5 GiB`, `300 MiB`, `12 KiB`.
pub fn human_bytes(bytes: u64) -> String {
    const K: f64 = 1024.0;
    let b = bytes as f64;
    if b >= K * K * K {
        format!("{:.1} GiB", b / (K * K * K))
    } else if b >= K * K {
        format!("{:.0} MiB", b / (K * K))
    } else if b >= K {
        format!("{:.0} KiB", b / K)
    } else {
        format!("{bytes} bytes")
    }
}

/// Parses a byte size as people write it: `2G`, `512M`, `1.5GiB`, `300MB`, `65536`. Suffixes
/// are powers of 1024 (K, M, G, T, with or without `B`/`iB`).
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let value: f64 = num
        .parse()
        .map_err(|_| format!("'{s}' is not a size such as 512M, 2G or 1048576"))?;
    let shift = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 0,
        "k" | "kb" | "kib" => 10,
        "m" | "mb" | "mib" => 20,
        "g" | "gb" | "gib" => 30,
        "t" | "tb" | "tib" => 40,
        _ => return Err(format!("'{s}': unknown unit '{unit}' (use K, M, G or T)")),
    };
    let bytes = value * (1u64 << shift) as f64;
    if !bytes.is_finite() || bytes >= u64::MAX as f64 {
        return Err(format!("'{s}' is too large"));
    }
    Ok(bytes.round() as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn size(w: u32, h: u32) -> Size {
        Size::new(w, h).unwrap()
    }

    #[test]
    fn sizes_and_pixels_are_checked_with_the_side_first() {
        let l = Limits::default();
        let p = Path::new("x.gif");
        let e = l
            .check_size(p, "GIF", 65535, 65535)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("65535x65535") && e.contains("out of range"),
            "{e}"
        );
        let e = l.check_size(p, "GIF", 16000, 16000).unwrap_err();
        assert!(
            matches!(
                e,
                Error::LimitExceeded {
                    limit: Limit::Pixels,
                    ..
                }
            ),
            "{e}"
        );
        assert_eq!(
            l.check_size(p, "GIF", 7680, 4320).unwrap(),
            size(7680, 4320)
        );
        assert!(Limits::unlimited()
            .check_size(p, "GIF", 16384, 16384)
            .is_ok());
        assert!(l.check_size(p, "GIF", 0, 5).is_err());
    }

    #[test]
    fn frames_are_counted_against_the_limit() {
        let l = Limits::default().with_max_frames(Some(3));
        let p = Path::new("-");
        assert!(l.check_frame_count(p, 3, false).is_ok());
        let e = l.check_frame_count(p, 3, true).unwrap_err().to_string();
        assert!(e.contains("more than 3 frames"), "{e}");
        assert!(l.check_frame_index(p, 2).is_ok());
        assert!(l.check_frame_index(p, 3).is_err());
        assert!(Limits::unlimited()
            .check_frame_index(p, u64::MAX - 1)
            .is_ok());
    }

    #[test]
    fn a_stream_that_does_not_fit_runs_leaner_or_is_refused() {
        let (f, t) = (size(4000, 4000), size(3000, 4000));
        let roomy = Limits::default().with_memory_budget(Some(8 << 30));
        assert_eq!(
            roomy
                .plan_stream(Path::new("a"), f, t, 0)
                .unwrap()
                .channel_capacity,
            1
        );
        let full = stream_bytes(f, t, 1, 0);
        let lean = stream_bytes(f, t, 0, 0);
        assert!(lean < full);
        let mid = Limits::default().with_memory_budget(Some((full + lean) / 2));
        let plan = mid.plan_stream(Path::new("a"), f, t, 0).unwrap();
        assert_eq!((plan.channel_capacity, plan.bytes), (0, lean));
        let tight = Limits::default().with_memory_budget(Some(lean - 1));
        let e = tight.plan_stream(Path::new("a"), f, t, 0).unwrap_err();
        assert!(
            matches!(
                e,
                Error::LimitExceeded {
                    limit: Limit::Memory,
                    ..
                }
            ),
            "{e}"
        );
        // A later, larger frame is admitted only within the budget.
        let plan = mid
            .plan_stream(Path::new("a"), size(100, 100), t, 0)
            .unwrap();
        assert!(plan.admit(1, size(100, 100)).is_ok());
        assert!(plan.admit(2, f).is_err());
    }

    #[test]
    fn the_defaults_agree_and_estimates_stay_above_measured_peaks() {
        // A still the default pixel limit admits fits the default budget at its own size
        // (8000x5000 is 40 MP exactly), so the pixel limit is the one ordinary jobs meet.
        let l = Limits::default();
        let p = Path::new("a.png");
        let full = size(8000, 5000);
        assert!(l.check_size(p, "PNG", 8000, 5000).is_ok());
        assert!(l.check_still(p, full, full).is_ok());
        // Peak RSS measured (/usr/bin/time -v, release build) for 7680x5200 to 3840x5200:
        // 1 921 536 KiB. An estimate below it would let a budget be overrun.
        assert!(still_bytes(size(7680, 5200), size(3840, 5200)) > 1_921_536 * 1024);
        // And a stream of six 3000x2000 raw frames to 1500x2000 GIF: 500 680 KiB.
        let s = stream_bytes(size(3000, 2000), size(1500, 2000), 1, 12);
        assert!(s > 500_680 * 1024, "{s}");
    }

    #[test]
    fn byte_sizes_parse() {
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("2G"), Ok(2 << 30));
        assert_eq!(parse_bytes("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_bytes("65536"), Ok(65536));
        assert_eq!(parse_bytes(" 300 mb "), Ok(300 << 20));
        assert!(parse_bytes("lots").is_err());
        assert!(parse_bytes("5X").unwrap_err().contains("unknown unit"));
        assert!(parse_bytes("-1G").is_err());
        assert_eq!(human_bytes(3 << 29), "1.5 GiB");
        assert_eq!(human_bytes(300 << 20), "300 MiB");
    }
}
