//! Standard input told apart by content before a job is chosen, as image tools read `-`
//! (`convert - out.png`): a JPEG, WebP or GIF file is one picture (a GIF perhaps an
//! animation), and so is a PNG followed by the end of the input; several PNGs one after the
//! other, YUV4MPEG2 and anything else are a stream of frames.
//!
//! A PNG says nothing of what follows it, so the first one is read whole (its chunks walked up
//! to `IEND`, as [`super::PngStreamSource`] walks them) and one byte more is asked for: none
//! means one picture. A stream waits for its second frame to begin, no longer.

use super::gif_in::count_frames;
use super::pipe::{read_full, stdin_stream, STDIN_NAME};
use super::sniff::{sniff, Magic, SNIFF_LEN};
use super::still::{decode_still_with, max_piped_bytes, probe_bytes};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::limits::{human_bytes, Limits};
use std::io::{Cursor, Read};
use std::path::{Path, PathBuf};

/// What an input read through a pipe holds.
pub enum Peeked {
    /// One picture file, read whole.
    Picture(PictureFile),
    /// A stream of frames: this reader gives the bytes looked at, then the rest.
    Stream(Box<dyn Read + Send>),
}

/// One picture file read from a pipe: a PNG, JPEG or WebP, or a GIF of one frame or more.
pub struct PictureFile {
    bytes: Vec<u8>,
    name: PathBuf,
    frames: Option<u64>,
}

impl PictureFile {
    /// The name it goes by in messages (`stdin`).
    pub fn name(&self) -> &Path {
        &self.name
    }

    /// How many frames it holds: 1 but for an animated GIF; `None` for a GIF whose blocks
    /// cannot be walked to the end (reading it names what is wrong).
    pub fn frames(&self) -> Option<u64> {
        self.frames
    }

    /// Whether it is a GIF (its frames are read by [`super::GifSource`]).
    pub fn is_gif(&self) -> bool {
        sniff(&self.bytes) == Some(Magic::Gif)
    }

    /// Its size from the header, checked against `limits`, as [`super::probe_still`] gives it.
    pub fn probe(&self, limits: &Limits) -> Result<Size, Error> {
        probe_bytes(&self.bytes, &self.name, limits)
    }

    /// The picture (a GIF's first frame), as [`super::read_still_with`] reads a file.
    pub fn decode(&self, limits: &Limits) -> Result<Image, Error> {
        decode_still_with(&self.bytes, &self.name, limits)
    }

    /// The file's bytes.
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }
}

/// Peeks at standard input within `limits` ([`peek_input`]).
pub fn peek_stdin(limits: &Limits) -> Result<Peeked, Error> {
    peek_input(stdin_stream(), Path::new(STDIN_NAME), limits)
}

/// Reads from `reader` what it takes to tell one picture from a stream: the first bytes, then
/// a whole JPEG, WebP or GIF file, or the first PNG and one byte after it. At most as many
/// bytes as a still read from a pipe may hold (1 GiB, or the memory budget if smaller).
/// An empty input is a stream, whose reader says it is empty.
pub fn peek_input(
    mut reader: Box<dyn Read + Send>,
    name: &Path,
    limits: &Limits,
) -> Result<Peeked, Error> {
    let mut bytes = vec![0u8; SNIFF_LEN];
    let n = read_full(&mut reader, &mut bytes).map_err(|e| Error::io(name, e))?;
    bytes.truncate(n);
    let max = max_piped_bytes(limits);
    let picture = |bytes: Vec<u8>, frames| {
        Peeked::Picture(PictureFile {
            bytes,
            name: name.to_path_buf(),
            frames,
        })
    };
    match sniff(&bytes) {
        Some(Magic::Jpeg | Magic::WebP) => {
            read_rest(&mut reader, &mut bytes, max, name)?;
            Ok(picture(bytes, Some(1)))
        }
        Some(Magic::Gif) => {
            read_rest(&mut reader, &mut bytes, max, name)?;
            // All of them (the bytes are in memory): a limit is checked when they are read.
            let frames = count_frames(&bytes[..], None).map(|(n, _)| n);
            Ok(picture(bytes, frames))
        }
        Some(Magic::Png) => {
            if !read_png(&mut reader, &mut bytes, max, name)? {
                // Cut short: one picture, whose reader says where.
                return Ok(picture(bytes, Some(1)));
            }
            let mut next = [0u8; 1];
            if read_full(&mut reader, &mut next).map_err(|e| Error::io(name, e))? == 0 {
                return Ok(picture(bytes, Some(1)));
            }
            bytes.push(next[0]);
            Ok(Peeked::Stream(Box::new(Cursor::new(bytes).chain(reader))))
        }
        _ => Ok(Peeked::Stream(Box::new(Cursor::new(bytes).chain(reader)))),
    }
}

fn too_large(name: &Path, max: u64) -> Error {
    Error::decode(
        name,
        format!("input stream is larger than {}", human_bytes(max)),
    )
}

/// Appends the rest of `reader` to `bytes`, refusing more than `max` bytes in all.
fn read_rest(
    reader: &mut dyn Read,
    bytes: &mut Vec<u8>,
    max: u64,
    name: &Path,
) -> Result<(), Error> {
    let room = (max + 1).saturating_sub(bytes.len() as u64);
    reader
        .take(room)
        .read_to_end(bytes)
        .map_err(|e| Error::io(name, e))?;
    if bytes.len() as u64 > max {
        return Err(too_large(name, max));
    }
    Ok(())
}

/// Reads the PNG whose first bytes (up to its signature) are in `bytes`, chunk by chunk, up
/// to its `IEND` chunk: true if it is all there, false if the input ended first.
fn read_png(
    reader: &mut dyn Read,
    bytes: &mut Vec<u8>,
    max: u64,
    name: &Path,
) -> Result<bool, Error> {
    let mut take = |bytes: &mut Vec<u8>, n: u64| -> Result<bool, Error> {
        if bytes.len() as u64 + n > max {
            // In the words of the stream's reader, which would meet the same chunk.
            return Err(Error::decode(
                name,
                format!(
                    "PNG 0 is corrupt or larger than {} (a chunk claims {} bytes)",
                    human_bytes(max),
                    n.saturating_sub(4)
                ),
            ));
        }
        let got = (&mut *reader)
            .take(n)
            .read_to_end(bytes)
            .map_err(|e| Error::io(name, e))?;
        Ok(got as u64 == n)
    };
    // The chunk headers start after the 8-byte signature; the sniffed bytes hold part of the
    // first one.
    let mut at = 8;
    loop {
        let have = bytes.len().saturating_sub(at) as u64;
        if have < 8 && !take(bytes, 8 - have)? {
            return Ok(false);
        }
        let len = u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
        let is_end = &bytes[at + 4..at + 8] == b"IEND";
        // The chunk's data and CRC.
        if !take(bytes, len as u64 + 4)? {
            return Ok(false);
        }
        if is_end {
            return Ok(true);
        }
        at = bytes.len();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32) -> Vec<u8> {
        let img = image::RgbaImage::from_pixel(w, h, image::Rgba([10, 20, 30, 255]));
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    fn peek(bytes: Vec<u8>) -> Peeked {
        peek_input(
            Box::new(Cursor::new(bytes)),
            Path::new("stdin"),
            &Limits::default(),
        )
        .unwrap()
    }

    #[test]
    fn one_png_is_a_picture_and_two_are_a_stream() {
        let one = png(7, 5);
        let Peeked::Picture(p) = peek(one.clone()) else {
            panic!("one PNG is one picture");
        };
        assert_eq!(p.frames(), Some(1));
        assert_eq!(
            p.probe(&Limits::default()).unwrap(),
            Size::new(7, 5).unwrap()
        );
        assert_eq!(p.into_bytes(), one, "the whole file, nothing more");
        let two = [one.clone(), png(3, 3)].concat();
        let Peeked::Stream(mut r) = peek(two.clone()) else {
            panic!("two PNGs are a stream");
        };
        let mut back = Vec::new();
        r.read_to_end(&mut back).unwrap();
        assert_eq!(
            back, two,
            "the stream gives every byte, the peeked ones first"
        );
    }

    #[test]
    fn a_png_cut_short_is_a_picture_whose_reader_names_it() {
        let one = png(7, 5);
        let Peeked::Picture(p) = peek(one[..one.len() - 6].to_vec()) else {
            panic!("a picture");
        };
        assert!(p.decode(&Limits::default()).is_err());
    }

    #[test]
    fn other_inputs_are_streams() {
        for bytes in [b"YUV4MPEG2 W2 H2 F25:1\n".to_vec(), vec![1, 2, 3], vec![]] {
            let Peeked::Stream(mut r) = peek(bytes.clone()) else {
                panic!("{bytes:?} is a stream");
            };
            let mut back = Vec::new();
            r.read_to_end(&mut back).unwrap();
            assert_eq!(back, bytes);
        }
    }

    #[test]
    fn a_picture_past_the_memory_budget_is_refused() {
        let limits = Limits {
            memory_budget: Some(1000),
            ..Limits::default()
        };
        let mut jpeg = vec![0xFF, 0xD8, 0xFF, 0xE0];
        jpeg.resize(1 << 20, 0);
        let r = peek_input(Box::new(Cursor::new(jpeg)), Path::new("stdin"), &limits);
        let e = r.err().expect("refused").to_string();
        assert!(e.contains("stdin") && e.contains("larger than"), "{e}");
    }
}
