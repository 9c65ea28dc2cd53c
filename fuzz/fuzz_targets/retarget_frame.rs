//! The whole single-frame path on a small structured picture (rectangles, dots, lines, a
//! sprinkle of noise) and a target from 1x1 to 5x each side; then a few frames of a stream
//! through the sequential core, with the content moving.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use vizretarget::vector::{PointMark, VectorLayer};
use vizretarget::{Frame, Image, Options, Retargeted, Retargeter, Size, Status};

#[derive(Arbitrary, Debug)]
enum Shape {
    Rect {
        x: u8,
        y: u8,
        w: u8,
        h: u8,
        rgba: [u8; 4],
    },
    Dot {
        x: u8,
        y: u8,
        r: u8,
        rgba: [u8; 4],
    },
    Line {
        x0: u8,
        y0: u8,
        x1: u8,
        y1: u8,
        rgba: [u8; 4],
    },
}

#[derive(Arbitrary, Debug)]
struct Input {
    w: u8,
    h: u8,
    background: [u8; 4],
    shapes: Vec<Shape>,
    /// (pixel index, grey) pairs.
    noise: Vec<(u16, u8)>,
    target_w: u16,
    target_h: u16,
    alpha: u8,
    structure: bool,
    /// Vector marks: (x, y, radius) in quarter pixels.
    marks: Vec<(u8, u8, u8)>,
    /// Further frames of a stream: each moves the shapes by (dx, dy).
    moves: Vec<(i8, i8)>,
}

fn draw(input: &Input, size: Size, dx: i32, dy: i32) -> Image {
    let (w, h) = (size.width as i32, size.height as i32);
    let mut img = Image::filled(size, input.background);
    let mut put = |x: i32, y: i32, c: [u8; 4]| {
        if (0..w).contains(&x) && (0..h).contains(&y) {
            img.set(x as u32, y as u32, c);
        }
    };
    for s in input.shapes.iter().take(12) {
        match *s {
            Shape::Rect {
                x,
                y,
                w: rw,
                h: rh,
                rgba,
            } => {
                let (x, y) = (x as i32 % w + dx, y as i32 % h + dy);
                for yy in y..y + 1 + rh as i32 % 24 {
                    for xx in x..x + 1 + rw as i32 % 24 {
                        put(xx, yy, rgba);
                    }
                }
            }
            Shape::Dot { x, y, r, rgba } => {
                let (cx, cy, r) = (x as i32 % w + dx, y as i32 % h + dy, r as i32 % 6);
                for yy in cy - r..=cy + r {
                    for xx in cx - r..=cx + r {
                        if (xx - cx).pow(2) + (yy - cy).pow(2) <= r * r {
                            put(xx, yy, rgba);
                        }
                    }
                }
            }
            Shape::Line {
                x0,
                y0,
                x1,
                y1,
                rgba,
            } => {
                let (x0, y0) = (x0 as i32 % w + dx, y0 as i32 % h + dy);
                let (x1, y1) = (x1 as i32 % w + dx, y1 as i32 % h + dy);
                let n = (x1 - x0).abs().max((y1 - y0).abs()).max(1);
                for k in 0..=n {
                    put(x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n, rgba);
                }
            }
        }
    }
    let area = size.area();
    for &(i, g) in input.noise.iter().take(64) {
        let i = i as usize % area;
        img.pixels_mut()[i] = [g, g, g, 255];
    }
    img
}

fn check(out: &Retargeted, target: Size) {
    assert_eq!(out.image.size(), target, "output has the target size");
    assert_eq!(out.image.pixels().len(), target.area());
    let a = out.analysis.as_ref().expect("analysis kept");
    assert_eq!(a.warp.target(), target);
    for p in a.warp.positions() {
        assert!(p.x.is_finite() && p.y.is_finite(), "vertex at {p:?}");
        assert!(
            p.x >= 0.0 && p.y >= 0.0 && p.x <= target.width as f64 && p.y <= target.height as f64,
            "vertex {p:?} outside {target}"
        );
    }
    assert!(a.warp.scales().iter().flatten().all(|s| s.is_finite()));
    assert_eq!(a.warp.folded_triangles(&a.mesh), 0, "no folded triangle");
    if let Some(m) = &out.marks {
        for p in &m.points {
            assert!(p.x.is_finite() && p.y.is_finite() && p.radius.is_finite());
        }
    }
}

fuzz_target!(|input: Input| {
    let size = Size::new(1 + input.w as u32 % 64, 1 + input.h as u32 % 64).unwrap();
    let target = Size::new(
        1 + input.target_w as u32 % (5 * size.width),
        1 + input.target_h as u32 % (5 * size.height),
    )
    .unwrap();
    let options = Options {
        structure: input.structure,
        ..Options::default()
    }
    .with_alpha(4.0 + (input.alpha % 197) as f32)
    .with_analysis(true);
    let layer = VectorLayer {
        points: input
            .marks
            .iter()
            .take(6)
            .map(|&(x, y, r)| PointMark {
                id: None,
                x: x as f64 / 4.0,
                y: y as f64 / 4.0,
                radius: r as f64 / 16.0,
                fill: [200, 30, 30, 255],
                stroke: None,
            })
            .collect(),
        ..VectorLayer::default()
    };
    let marks = (!layer.is_empty()).then_some(layer);

    let mut r = Retargeter::new(target, options).unwrap();
    let frames = 1 + input.moves.len().min(3);
    for i in 0..frames {
        let (dx, dy) = match i {
            0 => (0, 0),
            _ => (
                input.moves[i - 1].0 as i32 % 8,
                input.moves[i - 1].1 as i32 % 8,
            ),
        };
        let mut frame = Frame::new(draw(&input, size, dx, dy), i as u64);
        if let Some(m) = &marks {
            frame = frame.with_marks(m.clone());
        }
        r.send_frame(frame).expect("a valid frame retargets");
        let out = r.receive_frame().expect("one frame out per frame in");
        assert_eq!(out.frame_index, i as u64);
        check(&out, target);
    }
    r.flush();
    assert_eq!(r.receive_frame().unwrap_err(), Status::Done);
});
