//! Inputs the fuzz targets (`fuzz/`, issue 8) crashed on, kept byte for byte. Each artifact
//! starts as its target's input does: for the stream targets a first byte saying how many of
//! the following bytes steer the chopped reads (0 here: none), then the stream itself.

use vizretarget::io::Y4mSource;
use vizretarget::{Error, FrameSource};

/// The stream inside a stream-target artifact (see `fuzz/src/lib.rs`, `split_chops`).
fn stream(artifact: &[u8]) -> &[u8] {
    let (&n, rest) = artifact.split_first().unwrap();
    &rest[(n as usize % 16).min(rest.len())..]
}

/// Every frame of a Y4M stream, or the first error (opening or reading), never a panic.
fn read_y4m(bytes: &[u8]) -> Result<usize, Error> {
    let mut src = Y4mSource::new(bytes, "stdin")?;
    let mut n = 0;
    while src.next_frame()?.is_some() {
        n += 1;
    }
    Ok(n)
}

/// `fuzz/artifacts/y4m_reader/crash-8e3a5471af9b870fc8be424058dea43488158f08`: a header
/// parameter starting with a non-UTF-8 byte (0xEB). The header was decoded lossily and each
/// token split after its first byte, inside the 3-byte U+FFFD: "byte index 1 is not a char
/// boundary". Now the header is parsed as bytes; this one lacks W and H, which is the error.
#[test]
fn y4m_header_token_with_non_utf8_first_byte() {
    const CRASH: &[u8] = b"\x00YUV4MPEG2 \xebQ\xeb\xeb\xeb\x8f\x80\x9f\xbf\x9f\x80t\x80i\x80i\x80\
FRAME\n\xeb\xeb\xeb\xebV\xeb\xeb\xeb\xebV\xeb\xeb\xeb\xebV\xeb\xeb\xeb\xebV\x15\x14\x14\x0e\x80\
\x8f\x8f\x8f\x8f\x80\x80wwww\x80";
    assert_eq!(CRASH.len(), 70);
    let err = read_y4m(stream(CRASH)).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("width (W) or height (H)"), "{msg}");
    assert!(!msg.contains('\n'), "one line: {msg}");
}

/// The same fault where it matters: non-UTF-8 bytes in a comment are ignored, in a value they
/// make that value invalid, and an unknown colour space is named on one line.
#[test]
fn y4m_header_non_utf8_parameters() {
    let mut ok = b"YUV4MPEG2 W2 H1 X\xe9t\xe9 C444 \xff\n".to_vec();
    ok.extend_from_slice(b"FRAME\n");
    ok.extend_from_slice(&[16, 235, 128, 128, 128, 128]);
    assert_eq!(read_y4m(&ok).unwrap(), 1);

    let err = read_y4m(b"YUV4MPEG2 W\xe92 H1\n").unwrap_err().to_string();
    assert!(err.contains("width (W) or height (H)"), "{err}");

    let err = read_y4m(b"YUV4MPEG2 W2 H1 C4\xe92\x07\n")
        .unwrap_err()
        .to_string();
    assert!(err.contains("unsupported YUV4MPEG2 colour space"), "{err}");
    assert!(
        !err.contains('\n') && !err.contains('\u{7}'),
        "one line: {err:?}"
    );
}
