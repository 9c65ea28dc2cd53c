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

/// `fuzz/artifacts/retarget_frame/crash-a0be12f3176d5ddef6bacc8dfad91a241ac9005b`: a 45x55
/// picture with marks mostly off it, retargeted to 1x1 with the structure read. A mark's
/// ring point 0.007 px above the canvas area's top edge made a sliver that the 1x1 target's
/// fixed-point grid collapses, in the linear resize too: it was counted as a fold. A fold is
/// a triangle the warp closes or turns over, not one no map onto the target can keep open.
#[test]
fn a_sliver_the_linear_grid_collapses_is_no_fold() {
    use vizretarget::vector::{PointMark, VectorLayer};
    use vizretarget::{Frame, Image, Options, Retargeter, Size};
    let mut img = Image::filled(Size::new(45, 55).unwrap(), [0, 162, 216, 255]);
    img.set(30, 35, [255; 4]);
    let mark = |x: f64, y: f64, radius: f64| PointMark {
        id: None,
        x,
        y,
        radius,
        fill: [200, 30, 30, 255],
        stroke: None,
    };
    let r = 255.0 / 16.0;
    let layer = VectorLayer {
        points: vec![
            mark(62.25, 63.75, r),
            mark(63.75, 63.75, r),
            mark(15.5, 0.0, r),
            mark(63.75, 63.75, 254.0 / 16.0),
            mark(46.25, 63.75, r),
            mark(63.75, 0.0, 165.0 / 16.0),
        ],
        ..VectorLayer::default()
    };
    let target = Size::new(1, 1).unwrap();
    let options = Options {
        structure: true,
        ..Options::default()
    }
    .with_alpha(4.0)
    .with_analysis(true);
    let mut r = Retargeter::new(target, options).unwrap();
    r.send_frame(Frame::new(img, 0).with_marks(layer)).unwrap();
    let out = r.receive_frame().unwrap();
    assert_eq!(out.image.size(), target);
    let a = out.analysis.as_ref().unwrap();
    assert_eq!(a.warp.folded_triangles(&a.mesh), 0);
}
