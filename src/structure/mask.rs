//! Masks of bytes (1 marked, 0 not) as the line and glyph searches keep them, scanned a
//! machine word at a time.

/// The first position from `from` on that is on (1, `want`) or off (0), eight at a time: most
/// of a boundary (or a picture) is ground, and a byte at a time the scan was most of the line
/// and glyph searches.
pub(super) fn next_marked(on: &[u8], from: usize, want: bool) -> Option<usize> {
    const ONES: u64 = 0x0101_0101_0101_0101;
    let rest = on.get(from..)?;
    let mut chunks = rest.chunks_exact(8);
    for (k, c) in chunks.by_ref().enumerate() {
        let word = u64::from_le_bytes(c.try_into().expect("chunks of 8"));
        let hits = if want { word } else { !word & ONES };
        if hits != 0 {
            return Some(from + 8 * k + hits.trailing_zeros() as usize / 8);
        }
    }
    let tail = rest.len() - chunks.remainder().len();
    (chunks.remainder().iter())
        .position(|&o| (o != 0) == want)
        .map(|p| from + tail + p)
}
