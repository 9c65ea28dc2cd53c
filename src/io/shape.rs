//! What a path holds, to choose between one picture and a stream of frames: the command
//! line's choice and the Python package's `retarget_file`, told the same way (the package
//! had its own copy, which took a GIF it could not walk for one picture where the command
//! line reads a stream).

use super::gif_in::GifSource;
use super::sniff::{sniff, Magic};
use crate::error::Error;
use crate::limits::Limits;
use crate::stream::FrameSource;
use std::path::Path;

/// What a file or folder holds, told from a file's first bytes (never its name).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum PathShape {
    /// A PNG, JPEG or WebP file, or a GIF of one frame; also a file that cannot be read (the
    /// reading of the picture names what is wrong).
    Picture,
    /// A GIF of this many frames (more than one), counted by walking its blocks without
    /// decoding.
    Animation(u64),
    /// A folder of frames.
    Folder,
    /// A GIF whose blocks cannot be walked to the end: read as one picture if one is asked
    /// for (the reader names what is wrong), else as a stream, which keeps the frames
    /// before the fault.
    UnreadableGif,
}

/// What `path` holds; a GIF is opened within `limits`.
pub fn path_shape(path: &Path, limits: &Limits) -> Result<PathShape, Error> {
    if path.is_dir() {
        return Ok(PathShape::Folder);
    }
    let mut head = Vec::new();
    if let Ok(f) = std::fs::File::open(path) {
        use std::io::Read;
        let _ = f.take(16).read_to_end(&mut head);
    }
    if sniff(&head) != Some(Magic::Gif) {
        return Ok(PathShape::Picture);
    }
    let gif = GifSource::open_with(path, limits)?;
    Ok(match gif.len_hint() {
        Some(n) if n <= 1 => PathShape::Picture,
        Some(n) => PathShape::Animation(n as u64),
        None => PathShape::UnreadableGif,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn streams() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("streams")
    }

    #[test]
    fn files_by_their_bytes_folders_and_gifs_by_their_frames() {
        let limits = Limits::default();
        let shape = |p: &Path| path_shape(p, &limits).unwrap();
        assert_eq!(shape(&streams().join("graph")), PathShape::Folder);
        assert_eq!(
            shape(&streams().join("graph/frame-0000.png")),
            PathShape::Picture
        );
        let frames = std::fs::read_dir(streams().join("graph")).unwrap().count() as u64;
        assert_eq!(
            shape(&streams().join("graph.gif")),
            PathShape::Animation(frames)
        );
        let dir = std::env::temp_dir().join(format!("vizretarget-shape-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let gif = std::fs::read(streams().join("graph.gif")).unwrap();
        let cut = dir.join("cut.gif");
        std::fs::write(&cut, &gif[..gif.len() * 2 / 3]).unwrap();
        assert_eq!(shape(&cut), PathShape::UnreadableGif);
        // Named .gif, holding a PNG: the bytes decide.
        let png_named_gif = dir.join("png.gif");
        std::fs::copy(streams().join("graph/frame-0000.png"), &png_named_gif).unwrap();
        assert_eq!(shape(&png_named_gif), PathShape::Picture);
        assert_eq!(shape(&dir.join("missing.png")), PathShape::Picture);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
