//! Marks for each frame of a stream: one layer for all, JSON Lines (one line per frame), or a
//! sidecar file per frame file; and a [`FrameSource`] that hands them on with the frames.

use super::FrameNames;
use crate::error::Error;
use crate::retarget::Frame;
use crate::stream::{FrameSource, Repeat};
use crate::vector::{is_json_lines, parse_line, read_layer, VectorLayer};
use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where each frame's marks come from.
pub struct FrameMarks {
    kind: Kind,
}

enum Kind {
    /// The same layer for every frame.
    Same(Arc<VectorLayer>),
    /// JSON Lines, read as the frames come.
    Lines {
        path: PathBuf,
        reader: Box<dyn BufRead + Send>,
        /// Lines read so far (the number of the last one read).
        line: usize,
        /// Layers handed out so far (the frame the next non-blank line is for).
        next_frame: u64,
    },
    /// `<stem>.json` in `dir` for the frame file `<stem>.<ext>`.
    Sidecars { dir: PathBuf, names: FrameNames },
}

impl FrameMarks {
    /// `layer` on every frame.
    pub fn same(layer: VectorLayer) -> FrameMarks {
        FrameMarks {
            kind: Kind::Same(Arc::new(layer)),
        }
    }

    /// One layer per non-blank line of the JSON Lines file `path`, frame 0 first. A frame
    /// after the last line is an error naming the file; lines after the last frame are not
    /// read.
    pub fn json_lines(path: &Path) -> Result<FrameMarks, Error> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        Ok(FrameMarks {
            kind: Kind::Lines {
                path: path.to_path_buf(),
                reader: Box::new(std::io::BufReader::new(file)),
                line: 0,
                next_frame: 0,
            },
        })
    }

    /// Sidecars: the marks of the frame read from file `NAME.png` (its name as `names`
    /// records it) are in `dir/NAME.json`; a frame without one has no marks.
    pub fn sidecars(dir: &Path, names: FrameNames) -> FrameMarks {
        FrameMarks {
            kind: Kind::Sidecars {
                dir: dir.to_path_buf(),
                names,
            },
        }
    }

    /// From a path as a user gives it: a folder of sidecars (needs the frames' `names`), a
    /// JSON Lines file (`.jsonl`, `.ndjson`), or one JSON layer for every frame.
    pub fn open(path: &Path, names: Option<FrameNames>) -> Result<FrameMarks, Error> {
        if path.is_dir() {
            return match names {
                Some(names) => Ok(FrameMarks::sidecars(path, names)),
                None => Err(Error::InvalidOptions(format!(
                    "{}: a folder of marks (one JSON file per frame file) needs a folder of \
                     frames as input; give a .jsonl file (one line per frame) instead",
                    path.display()
                ))),
            };
        }
        if is_json_lines(path) {
            return FrameMarks::json_lines(path);
        }
        Ok(FrameMarks::same(read_layer(path)?))
    }

    /// Whether `dir` holds a sidecar for any of the frame files `files`.
    pub fn has_sidecars(dir: &Path, files: &[PathBuf]) -> bool {
        files
            .iter()
            .any(|f| sidecar(dir, f).is_some_and(|s| s.is_file()))
    }

    /// The marks of frame `frame_index` (frames are asked for in order).
    pub fn for_frame(&mut self, frame_index: u64) -> Result<Option<Arc<VectorLayer>>, Error> {
        match &mut self.kind {
            Kind::Same(l) => Ok(Some(l.clone())),
            Kind::Sidecars { dir, names } => {
                let Some(name) = names.get(frame_index) else {
                    return Ok(None);
                };
                match sidecar(dir, Path::new(&name)) {
                    Some(p) if p.is_file() => Ok(Some(Arc::new(read_layer(&p)?))),
                    _ => Ok(None),
                }
            }
            Kind::Lines {
                path,
                reader,
                line,
                next_frame,
            } => {
                let mut buf = Vec::new();
                loop {
                    buf.clear();
                    let n = reader
                        .read_until(b'\n', &mut buf)
                        .map_err(|e| Error::io(path.as_path(), e))?;
                    if n == 0 {
                        return Err(Error::decode(
                            path.as_path(),
                            format!(
                                "has marks for {next_frame} frame(s) (one non-blank line each), \
                                 but the stream has a frame {}: give one line per frame ({{}} \
                                 for a frame without marks)",
                                frame_index + 1
                            ),
                        ));
                    }
                    *line += 1;
                    let text = std::str::from_utf8(&buf).map_err(|_| {
                        Error::decode(path.as_path(), format!("line {line}: is not UTF-8 text"))
                    })?;
                    if text.trim().is_empty() {
                        continue;
                    }
                    let this = *next_frame;
                    *next_frame += 1;
                    if this < frame_index {
                        continue; // a frame the source skipped
                    }
                    return parse_line(text.trim_end(), *line)
                        .map(|l| Some(Arc::new(l)))
                        .map_err(|m| Error::decode(path.as_path(), m));
                }
            }
        }
    }
}

/// `dir/<stem of file>.json`.
fn sidecar(dir: &Path, file: &Path) -> Option<PathBuf> {
    let stem = file.file_stem()?;
    let mut name = stem.to_os_string();
    name.push(".json");
    Some(dir.join(name))
}

/// A source whose frames carry their marks ([`crate::Frame::marks`]).
pub struct MarkedSource {
    inner: Box<dyn FrameSource>,
    marks: FrameMarks,
}

impl MarkedSource {
    pub fn new(inner: Box<dyn FrameSource>, marks: FrameMarks) -> MarkedSource {
        MarkedSource { inner, marks }
    }
}

impl FrameSource for MarkedSource {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        let Some(mut frame) = self.inner.next_frame()? else {
            return Ok(None);
        };
        if let Some(l) = self.marks.for_frame(frame.frame_index)? {
            frame.marks = Some(l);
        }
        Ok(Some(frame))
    }
    fn len_hint(&self) -> Option<usize> {
        self.inner.len_hint()
    }
    fn repeat(&self) -> Option<Repeat> {
        self.inner.repeat()
    }
}
