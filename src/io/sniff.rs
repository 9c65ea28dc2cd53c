//! What a file or a stream holds, from its first bytes (never from its name).

/// Kinds of input recognised by their magic bytes.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Magic {
    /// `GIF87a` or `GIF89a`.
    Gif,
    /// The 8-byte PNG signature.
    Png,
    /// `FF D8 FF`.
    Jpeg,
    /// `RIFF....WEBP`.
    WebP,
    /// `YUV4MPEG2 `.
    Y4m,
}

/// How many leading bytes [`sniff`] looks at.
pub const SNIFF_LEN: usize = 12;

pub(crate) const PNG_SIGNATURE: &[u8; 8] = b"\x89PNG\r\n\x1a\n";

/// Recognises `head`, the first bytes of an input (up to `SNIFF_LEN`).
pub fn sniff(head: &[u8]) -> Option<Magic> {
    if head.starts_with(b"GIF87a") || head.starts_with(b"GIF89a") {
        Some(Magic::Gif)
    } else if head.starts_with(PNG_SIGNATURE) {
        Some(Magic::Png)
    } else if head.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some(Magic::Jpeg)
    } else if head.len() >= 12 && head.starts_with(b"RIFF") && &head[8..12] == b"WEBP" {
        Some(Magic::WebP)
    } else if head.starts_with(b"YUV4MPEG2") {
        Some(Magic::Y4m)
    } else {
        None
    }
}

/// Reads up to [`SNIFF_LEN`] bytes from the start of a file. A short file gives fewer bytes.
pub(crate) fn head_of(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let mut head = Vec::with_capacity(SNIFF_LEN);
    std::fs::File::open(path)?
        .take(SNIFF_LEN as u64)
        .read_to_end(&mut head)?;
    Ok(head)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn magic_bytes() {
        assert_eq!(sniff(b"GIF89a\x01\x00"), Some(Magic::Gif));
        assert_eq!(sniff(b"GIF87a"), Some(Magic::Gif));
        assert_eq!(sniff(b"\x89PNG\r\n\x1a\n\0\0\0\x0d"), Some(Magic::Png));
        assert_eq!(sniff(&[0xFF, 0xD8, 0xFF, 0xE0]), Some(Magic::Jpeg));
        assert_eq!(sniff(b"RIFF\0\0\0\0WEBPVP8 "), Some(Magic::WebP));
        assert_eq!(sniff(b"YUV4MPEG2 W1 H1"), Some(Magic::Y4m));
        assert_eq!(sniff(b"RIFF\0\0\0\0WAVE"), None);
        assert_eq!(sniff(b"GIF8"), None);
        assert_eq!(sniff(b""), None);
        assert_eq!(sniff(b"BM\0\0"), None);
    }
}
