//! A folder of frames in: the PNG, JPEG and WebP files of a folder, in natural order of their
//! names (`frame2` before `frame10`), decoded one at a time as the pipeline asks.
//!
//! Files are recognised by their first bytes; other files (notes, thumbnails databases),
//! hidden files (names starting with `.`, such as the temporary files of atomic writers) and
//! sub-folders are ignored. Every frame must have the size of the first. Each frame's file
//! name is recorded in [`FrameNames`], for sinks that name outputs after inputs.

use super::names::FrameNames;
use super::natural::natural_cmp;
use super::sniff::{head_of, sniff, Magic};
use super::still::read_still_with;
use crate::error::Error;
use crate::image::Size;
use crate::limits::Limits;
use crate::retarget::Frame;
use crate::stream::FrameSource;
use std::path::{Path, PathBuf};

/// Frames from the image files of a folder.
pub struct DirSource {
    files: Vec<PathBuf>,
    next: usize,
    size: Option<(Size, PathBuf)>,
    names: FrameNames,
    limits: Limits,
}

/// The image files of `dir` (by content), hidden ones skipped, in natural order.
pub fn list_images(dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        let path = entry.path();
        // A file that vanishes while listing is simply not part of the snapshot.
        if !std::fs::metadata(&path).is_ok_and(|m| m.is_file()) {
            continue;
        }
        let Ok(head) = head_of(&path) else { continue };
        if matches!(
            sniff(&head),
            Some(Magic::Png | Magic::Jpeg | Magic::WebP | Magic::Gif)
        ) {
            files.push((name, path));
        }
    }
    files.sort_by(|a, b| natural_cmp(&a.0, &b.0));
    Ok(files.into_iter().map(|(_, p)| p).collect())
}

impl DirSource {
    /// Lists the image files of `dir` within the default [`Limits`]; see
    /// [`DirSource::open_with`].
    pub fn open(dir: &Path) -> Result<Self, Error> {
        DirSource::open_with(dir, &Limits::default())
    }

    /// Lists the image files of `dir`; [`Error::NoFrames`] if there are none, and a folder of
    /// more than [`Limits::max_frames`] is refused before any is decoded. Each file is checked
    /// against `limits` from its header.
    pub fn open_with(dir: &Path, limits: &Limits) -> Result<Self, Error> {
        let files = list_images(dir)?;
        if files.is_empty() {
            return Err(Error::NoFrames(dir.to_path_buf()));
        }
        limits.check_frame_count(dir, files.len() as u64, false)?;
        Ok(DirSource {
            files,
            next: 0,
            size: None,
            names: FrameNames::new(),
            limits: limits.clone(),
        })
    }

    /// The files, in the order they will be read.
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// The names of the frames read so far, by `frame_index`.
    pub fn names(&self) -> FrameNames {
        self.names.clone()
    }
}

impl FrameSource for DirSource {
    fn next_frame(&mut self) -> Result<Option<Frame>, Error> {
        let Some(path) = self.files.get(self.next).cloned() else {
            return Ok(None);
        };
        let index = self.next as u64;
        self.next += 1;
        let image = read_still_with(&path, &self.limits).map_err(|e| match e {
            Error::Io { path, source } if source.kind() == std::io::ErrorKind::NotFound => {
                Error::decode(
                    path,
                    "the file disappeared from the folder before it was read",
                )
            }
            other => other,
        })?;
        match &self.size {
            None => self.size = Some((image.size(), path.clone())),
            Some((s, first)) if *s != image.size() => {
                return Err(Error::decode(
                    &path,
                    format!(
                        "is {}, but the frames before it are {s} (like {}): every frame of a \
                         folder must have the same size",
                        image.size(),
                        first.file_name().unwrap_or_default().to_string_lossy()
                    ),
                ));
            }
            Some(_) => {}
        }
        self.names.insert_file(index, &path);
        Ok(Some(Frame::new(image, index)))
    }

    fn len_hint(&self) -> Option<usize> {
        Some(self.files.len() - self.next)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;

    fn save(path: &Path, w: u32) {
        let img = Image::filled(Size::new(w, 4).unwrap(), [9, 9, 9, 255]);
        super::super::still::write_still(&img, path, super::super::still::OutputFormat::Png)
            .unwrap();
    }

    #[test]
    fn natural_order_by_content_and_vanished_files_are_named() {
        let dir = tempfile::tempdir().unwrap();
        for n in ["f10.png", "f2.png", "f1.png", "f3"] {
            save(&dir.path().join(n), 4);
        }
        std::fs::write(dir.path().join("f0.png"), b"text, not a picture").unwrap();
        std::fs::write(dir.path().join(".f0.png"), b"hidden").unwrap();
        let mut src = DirSource::open(dir.path()).unwrap();
        let names: Vec<_> = src
            .files()
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["f1.png", "f2.png", "f3", "f10.png"]);
        assert_eq!(src.len_hint(), Some(4));
        let first = src.next_frame().unwrap().unwrap();
        assert_eq!(
            (first.frame_index, src.names().get(0).as_deref()),
            (0, Some("f1.png"))
        );
        std::fs::remove_file(dir.path().join("f2.png")).unwrap();
        let e = src.next_frame().unwrap_err().to_string();
        assert!(e.contains("f2.png") && e.contains("disappeared"), "{e}");
        assert_eq!(src.len_hint(), Some(2));
    }
}
