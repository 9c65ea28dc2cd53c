//! The mark-layer parser (JSON and JSON Lines), then what a parsed layer goes through: drawn,
//! painted out, bound to the mesh, carried by the warp and redrawn on a small frame.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vizretarget::vector::{parse_layer, parse_layer_lines, MarkSize, VectorLayer, VectorOptions};
use vizretarget::{Frame, Image, Options, Retargeter, Size};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(layers) = parse_layer_lines(text) {
        for l in &layers {
            assert_eq!(l.validate(), Ok(()), "a parsed line is valid");
        }
    }
    let Ok(layer) = parse_layer(text) else {
        return;
    };
    assert_eq!(layer.validate(), Ok(()), "a parsed layer is valid");
    let mut canvas = Image::filled(Size::new(24, 16).unwrap(), [250, 250, 250, 255]);
    layer.draw(&mut canvas);
    // Bounded work per input: the mesh and solve on a few dozen marks at most.
    if layer.points.len() + layer.polylines.len() + layer.edges.len() > 48 {
        return;
    }
    retarget_with(&layer, data.len());
});

fn retarget_with(layer: &VectorLayer, seed: usize) {
    let size = Size::new(40, 30).unwrap();
    let mut img = Image::filled(size, [255, 255, 255, 255]);
    for y in 10..20 {
        for x in 5..12 {
            img.set(x, y, [30, 60, 200, 255]);
        }
    }
    let target = Size::new(1 + (seed * 7) as u32 % 80, 1 + (seed * 13) as u32 % 60).unwrap();
    let options = Options {
        vector: VectorOptions {
            paint_out: seed.is_multiple_of(2),
            size: if seed.is_multiple_of(3) {
                MarkSize::Keep
            } else {
                MarkSize::Mesh
            },
        },
        ..Options::default()
    }
    .with_analysis(true);
    let mut r = Retargeter::new(target, options).unwrap();
    r.send_frame(Frame::new(img, 0).with_marks(layer.clone()))
        .expect("a valid layer on a valid frame retargets");
    let out = r.receive_frame().unwrap();
    assert_eq!(out.image.size(), target);
    let placed = out.marks.expect("the frame's marks come back placed");
    assert_eq!(placed.points.len(), layer.points.len());
    assert_eq!(placed.polylines.len(), layer.polylines.len());
    assert_eq!(placed.edges.len(), layer.edges.len());
    for p in &placed.points {
        assert!(
            p.x.is_finite() && p.y.is_finite() && p.radius.is_finite(),
            "{p:?}"
        );
    }
    let a = out.analysis.unwrap();
    assert_eq!(a.warp.folded_triangles(&a.mesh), 0);
}
