//! A folder of frames out: one PNG per frame, each written atomically (temporary file and
//! rename), so a reader watching the folder never sees half a picture.
//!
//! Names: `frame-00000.png`, `frame-00001.png`, ... by `frame_index`, or the name the source
//! recorded for the frame in [`FrameNames`] (a folder or a watched directory): the same name,
//! encoded as its extension says (`.png`, `.jpg`/`.jpeg` as JPEG, `.webp` as lossless WebP);
//! another extension (`.gif`) is replaced by `.png`.

use super::names::FrameNames;
use super::still::{encode_still, write_atomic, OutputFormat};
use crate::error::Error;
use crate::retarget::Retargeted;
use crate::stream::FrameSink;
use std::path::{Path, PathBuf};

/// Writes each frame as a file in a folder.
pub struct PngSeqSink {
    dir: PathBuf,
    names: Option<FrameNames>,
    last_written: Option<PathBuf>,
}

impl PngSeqSink {
    /// Writes into `dir`, creating it if missing (its parent must exist).
    pub fn create(dir: &Path, names: Option<FrameNames>) -> Result<Self, Error> {
        if !dir.is_dir() {
            std::fs::create_dir(dir).map_err(|e| Error::io(dir, e))?;
        }
        Ok(PngSeqSink {
            dir: dir.to_path_buf(),
            names,
            last_written: None,
        })
    }

    /// The file the last frame went to.
    pub fn last_written(&self) -> Option<&Path> {
        self.last_written.as_deref()
    }

    /// The file name and format for frame `frame_index`.
    pub fn file_for(&self, frame_index: u64) -> (String, OutputFormat) {
        let recorded = self.names.as_ref().and_then(|n| n.get(frame_index));
        match recorded {
            Some(name) => output_name(&name),
            None => (format!("frame-{frame_index:05}.png"), OutputFormat::Png),
        }
    }
}

/// The output name for an input file name: kept when PNG, JPEG or WebP, else given `.png`.
pub fn output_name(name: &str) -> (String, OutputFormat) {
    let path = Path::new(name);
    match OutputFormat::from_path(path) {
        Some(f) => (name.to_string(), f),
        None => {
            let stem = path
                .file_stem()
                .map_or_else(|| name.to_string(), |s| s.to_string_lossy().into_owned());
            (format!("{stem}.png"), OutputFormat::Png)
        }
    }
}

impl FrameSink for PngSeqSink {
    fn write_frame(&mut self, frame: &Retargeted) -> Result<(), Error> {
        let (name, format) = self.file_for(frame.frame_index);
        let path = self.dir.join(name);
        let bytes = encode_still(&frame.image, format).map_err(|e| match e {
            Error::Encode(m) => Error::decode(&path, format!("encoding failed: {m}")),
            e => e,
        })?;
        write_atomic(&path, &bytes)?;
        self.last_written = Some(path);
        Ok(())
    }

    fn finish(&mut self) -> Result<(), Error> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        assert_eq!(output_name("a.png"), ("a.png".into(), OutputFormat::Png));
        assert_eq!(output_name("b.JPG"), ("b.JPG".into(), OutputFormat::Jpeg));
        assert_eq!(output_name("c.webp"), ("c.webp".into(), OutputFormat::WebP));
        assert_eq!(output_name("d.gif"), ("d.png".into(), OutputFormat::Png));
        assert_eq!(
            output_name("noext"),
            ("noext.png".into(), OutputFormat::Png)
        );
    }
}
