//! What the input holds, to choose a job: one picture, an animated GIF, or a stream of frames.
//! A file by its first bytes; stdin by what arrives on it ([`vizretarget::io::peek_stdin`]): a
//! PNG followed by the end of the input, a JPEG, WebP or GIF file is one picture (or one
//! animation), as image tools read `-`; several PNGs or YUV4MPEG2 are a stream.

use super::args::{Cli, InputArg};
use super::library_error;
use anyhow::Result;
use std::path::{Path, PathBuf};
use vizretarget::io::{is_std, path_shape, peek_stdin, PathShape, Peeked, PictureFile, STDIN_NAME};

/// How the input is named in messages: `stdin` for `-`.
pub fn name(input: &Path) -> &Path {
    if is_std(input) {
        Path::new(STDIN_NAME)
    } else {
        input
    }
}

/// The picture stdin held, if it held one.
pub fn picture(peeked: Option<Peeked>) -> Option<PictureFile> {
    match peeked {
        Some(Peeked::Picture(p)) => Some(p),
        _ => None,
    }
}

/// What an input holds, to choose between the still job and the stream job.
pub enum Shape {
    /// One picture: a PNG, JPEG or WebP file, or a GIF file of one frame (on stdin too).
    Picture,
    /// A GIF file of this many frames (more than one), on stdin too.
    Animation(u64),
    /// A folder, or on stdin several PNGs, YUV4MPEG2 or raw frames: frames, however many.
    Stream,
    /// A GIF file whose blocks cannot be walked to the end: read as one picture if one is
    /// asked for (the reader names what is wrong), else as a stream, which keeps the frames
    /// before the fault.
    UnreadableGif,
}

impl Shape {
    /// What `input` holds, and for stdin what was read of it to tell (the job goes on from
    /// there). Stdin is peeked at only when its format is found by content.
    pub fn of(cli: &Cli, input: &Path) -> Result<(Shape, Option<Peeked>)> {
        if is_std(input) && cli.stream.input_format == InputArg::Auto {
            let peeked = peek_stdin(&cli.limits_for(true)).map_err(library_error)?;
            let shape = match &peeked {
                Peeked::Picture(p) => match p.frames() {
                    Some(0 | 1) => Shape::Picture,
                    Some(n) => Shape::Animation(n),
                    None => Shape::UnreadableGif,
                },
                Peeked::Stream(_) => Shape::Stream,
            };
            return Ok((shape, Some(peeked)));
        }
        Ok((Shape::of_path(input, &cli.limits_for(false))?, None))
    }

    fn of_path(input: &Path, limits: &vizretarget::Limits) -> Result<Shape> {
        if is_std(input) {
            return Ok(Shape::Stream);
        }
        Ok(match path_shape(input, limits).map_err(library_error)? {
            PathShape::Picture => Shape::Picture,
            PathShape::Animation(n) => Shape::Animation(n),
            PathShape::Folder => Shape::Stream,
            PathShape::UnreadableGif => Shape::UnreadableGif,
        })
    }
}

/// The name of one picture written into a folder: the input's stem, as PNG.
pub fn picture_name(input: &Path) -> PathBuf {
    let stem = input
        .file_stem()
        .map_or_else(|| "picture".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from(format!("{stem}.png"))
}
