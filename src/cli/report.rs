//! What a stream run tells its user: a progress bar (stderr is a terminal and the frame count
//! is known), optional lines per frame, a summary line, and `--stats-json`.

use indicatif::{ProgressBar, ProgressStyle};
use std::collections::HashSet;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use vizretarget::io::{output_name, FrameNames};
use vizretarget::stream::Progress;
use vizretarget::{Decision, FrameStats, RunSummary, Size};

/// Collects per-frame statistics and moves the progress bar.
pub struct Reporter {
    bar: Option<ProgressBar>,
    names: Option<FrameNames>,
    /// Print one line per frame: the per-frame --stats line, or for watch `name -> out`.
    per_frame: PerFrame,
    keep: bool,
    frames: Mutex<Vec<(FrameStats, Option<String>)>>,
    /// Frames whose output could not be written (watch goes on past them).
    failed: Option<Arc<Mutex<HashSet<u64>>>>,
    /// Frames done, and their milliseconds summed and at most (for watch's closing line).
    times: Mutex<(u64, f64, f64)>,
}

/// What to print for each frame.
pub enum PerFrame {
    Nothing,
    Stats,
    /// `name -> OUTDIR/name` (watch mode).
    Written(PathBuf),
}

impl Reporter {
    pub fn new(
        len: Option<usize>,
        quiet: bool,
        per_frame: PerFrame,
        names: Option<FrameNames>,
        keep_stats: bool,
    ) -> Reporter {
        let bar = match len {
            Some(n) if !quiet && std::io::stderr().is_terminal() && n > 1 => {
                let bar = ProgressBar::new(n as u64);
                if let Ok(style) = ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} frames, {elapsed} elapsed, {eta} left",
                ) {
                    bar.set_style(style);
                }
                Some(bar)
            }
            _ => None,
        };
        Reporter {
            bar,
            names,
            per_frame,
            keep: keep_stats,
            frames: Mutex::new(Vec::new()),
            failed: None,
            times: Mutex::new((0, 0.0, 0.0)),
        }
    }

    /// Frames in `failed` get no `name -> output` line, and `"written": false` in the JSON.
    pub fn with_failed_writes(mut self, failed: Arc<Mutex<HashSet<u64>>>) -> Reporter {
        self.failed = Some(failed);
        self
    }

    fn write_failed(&self, frame_index: u64) -> bool {
        self.failed.as_ref().is_some_and(|f| {
            f.lock()
                .unwrap_or_else(|e| e.into_inner())
                .contains(&frame_index)
        })
    }

    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }

    fn print(&self, line: String) {
        match &self.bar {
            Some(bar) => bar.suspend(|| eprintln!("{line}")),
            None => eprintln!("{line}"),
        }
    }

    /// The closing line of watch: snapshots arrive over minutes, so frames per second say
    /// little; how many were done and how long each took say what matters.
    pub fn snapshot_line(&self, interrupted: bool) -> String {
        let (n, sum, max) = *self.times.lock().unwrap_or_else(|e| e.into_inner());
        let each = if n == 0 {
            String::new()
        } else {
            format!("; {:.0} ms mean, {max:.0} ms max each", sum / n as f64)
        };
        format!(
            "vizretarget: {n} snapshot{} retargeted{each}{}",
            if n == 1 { "" } else { "s" },
            if interrupted { " (stopped)" } else { "" }
        )
    }

    /// Writes the statistics as JSON to `path` (atomically).
    pub fn write_json(&self, path: &Path, summary: Option<&RunSummary>) -> anyhow::Result<()> {
        let frames = self.frames.lock().unwrap_or_else(|e| e.into_inner());
        let mut s = String::from("{\n  \"frames\": [");
        for (i, (f, name)) in frames.iter().enumerate() {
            let t = &f.times;
            s.push_str(if i == 0 { "\n    " } else { ",\n    " });
            s.push_str(&format!("{{\"frame_index\": {}", f.frame_index));
            if let Some(n) = name {
                s.push_str(&format!(", \"name\": {}", json_string(n)));
            }
            if self.write_failed(f.frame_index) {
                s.push_str(", \"written\": false");
            }
            s.push_str(&format!(
                ", \"decision\": \"{}\", \"vertices\": {}, \"triangles\": {}, \"dof\": {}, \
                 \"ms\": {{\"vsm\": {}, \"mesh\": {}, \"solve\": {}, \"render\": {}, \"total\": {}}}}}",
                decision_name(f.decision),
                f.vertices,
                f.triangles,
                f.dof,
                json_number(t.vsm_ms),
                json_number(t.mesh_ms),
                json_number(t.solve_ms),
                json_number(t.render_ms),
                json_number(t.total_ms()),
            ));
        }
        s.push_str(if frames.is_empty() { "]" } else { "\n  ]" });
        if let Some(r) = summary {
            let secs = r.elapsed.as_secs_f64();
            s.push_str(&format!(
                ",\n  \"summary\": {{\"frames\": {}, \"seconds\": {}, \"fps\": {}, \"reused\": {}, \
                 \"updated\": {}, \"rebuilt\": {}, \"output_closed\": {}, \"cancelled\": {}}}",
                r.frames,
                json_number(secs),
                json_number(if secs > 0.0 { r.frames as f64 / secs } else { 0.0 }),
                r.reused,
                r.updated,
                r.rebuilt,
                r.output_closed,
                r.cancelled
            ));
        }
        s.push_str("\n}\n");
        vizretarget::io::write_atomic(path, s.as_bytes())?;
        Ok(())
    }
}

impl Progress for Reporter {
    fn frame_done(&self, stats: &FrameStats) {
        if let Some(bar) = &self.bar {
            bar.inc(1);
        }
        let name = self.names.as_ref().and_then(|n| n.get(stats.frame_index));
        let t = &stats.times;
        {
            let mut times = self.times.lock().unwrap_or_else(|e| e.into_inner());
            times.0 += 1;
            times.1 += t.total_ms();
            times.2 = times.2.max(t.total_ms());
        }
        match &self.per_frame {
            PerFrame::Nothing => {}
            PerFrame::Stats => self.print(format!(
                "frame {}{}: {}, {} vertices, {} triangles, DOF {}; vsm {:.1} ms, mesh {:.1} ms, \
                 solve {:.1} ms, render {:.1} ms",
                stats.frame_index,
                name.as_deref()
                    .map_or_else(String::new, |n| format!(" ({n})")),
                decision_name(stats.decision),
                stats.vertices,
                stats.triangles,
                stats.dof,
                t.vsm_ms,
                t.mesh_ms,
                t.solve_ms,
                t.render_ms
            )),
            PerFrame::Written(dir) => {
                if let Some(n) = name
                    .as_ref()
                    .filter(|_| !self.write_failed(stats.frame_index))
                {
                    self.print(format!(
                        "vizretarget: {n} -> {} ({}, {:.0} ms)",
                        dir.join(output_name(n).0).display(),
                        decision_name(stats.decision),
                        t.total_ms()
                    ));
                }
            }
        }
        if self.keep {
            self.frames
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push((stats.clone(), name));
        }
    }
}

pub fn decision_name(d: Decision) -> &'static str {
    match d {
        Decision::Rebuild => "rebuild",
        Decision::Update => "update",
        Decision::Reuse => "reuse",
    }
}

/// The one-line summary of a run.
pub fn summary_line(r: &RunSummary, from: Option<Size>, to: Size, linear: bool) -> String {
    let secs = r.elapsed.as_secs_f64();
    let n = r.frames.max(1) as f64;
    let t = &r.stage_ms;
    format!(
        "vizretarget: {} frame{}{} in {:.2} s ({:.1} fps); {}; per frame: vsm {:.1} ms, \
         mesh {:.1} ms, solve {:.1} ms, render {:.1} ms{}",
        r.frames,
        if r.frames == 1 { "" } else { "s" },
        from.map_or_else(|| format!(" -> {to}"), |f| format!(", {f} -> {to},")),
        secs,
        if secs > 0.0 {
            r.frames as f64 / secs
        } else {
            0.0
        },
        kept(r, linear),
        t.vsm_ms / n,
        t.mesh_ms / n,
        t.solve_ms / n,
        t.render_ms / n,
        if r.cancelled { " (interrupted)" } else { "" },
    )
}

/// What was kept from frame to frame, in the words of the mode in use. Under one linear map
/// per axis (`--regions affine`, the default) there is no mesh worth keeping: a frame whose
/// pixels did not change keeps the last map, any other is resampled afresh. With a mesh,
/// the reuse policy's three decisions.
fn kept(r: &RunSummary, linear: bool) -> String {
    let n = r.frames.max(1) as f64;
    let pct = |k: u64| 100.0 * k as f64 / n;
    if linear {
        format!(
            "one linear map per axis, no mesh kept: {:.0}% of frames unchanged, {:.0}% \
             resampled afresh",
            pct(r.reused),
            pct(r.updated + r.rebuilt)
        )
    } else {
        format!(
            "mesh reused {:.0}%, updated {:.0}%, rebuilt {:.0}%",
            pct(r.reused),
            pct(r.updated),
            pct(r.rebuilt)
        )
    }
}

fn json_number(x: f64) -> String {
    if x.is_finite() {
        format!("{:.3}", x)
    } else {
        "null".into()
    }
}

fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_says_what_reuse_means_in_the_mode_in_use() {
        let r = RunSummary {
            frames: 4,
            reused: 1,
            updated: 1,
            rebuilt: 2,
            ..RunSummary::default()
        };
        let to = Size::new(40, 30).unwrap();
        let linear = summary_line(&r, None, to, true);
        assert!(
            linear.contains("no mesh kept: 25% of frames unchanged, 75% resampled afresh"),
            "{linear}"
        );
        assert!(!linear.contains("rebuilt"), "{linear}");
        let mesh = summary_line(&r, None, to, false);
        assert!(
            mesh.contains("mesh reused 25%, updated 25%, rebuilt 50%"),
            "{mesh}"
        );
    }

    #[test]
    fn json_strings_are_escaped() {
        assert_eq!(json_string("a\"b\\c\n\u{1}é"), "\"a\\\"b\\\\c\\n\\u0001é\"");
        assert_eq!(json_number(f64::NAN), "null");
        assert_eq!(json_number(1.5), "1.500");
    }
}
