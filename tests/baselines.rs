//! The baselines behind `retarget_with`: exact output sizes, and the property that defines
//! each method (crop keeps the salient window, seam carving removes empty columns first, the
//! grid never folds, linear scaling maps positions proportionally).

use vizretarget::baseline::{resize_linear, Mapping};
use vizretarget::{retarget, retarget_with, Image, Method, Options, Size};

const WHITE: [u8; 4] = [255, 255, 255, 255];
const RED: [u8; 4] = [215, 25, 28, 255];
const BLUE: [u8; 4] = [44, 123, 182, 255];
const BLACK: [u8; 4] = [0, 0, 0, 255];

fn size(w: u32, h: u32) -> Size {
    Size::new(w, h).unwrap()
}

fn disc(img: &mut Image, cx: f32, cy: f32, r: f32, c: [u8; 4]) {
    for y in 0..img.height() {
        for x in 0..img.width() {
            let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
            if dx * dx + dy * dy <= r * r {
                img.set(x, y, c);
            }
        }
    }
}

fn rect(img: &mut Image, x0: u32, y0: u32, x1: u32, y1: u32, c: [u8; 4]) {
    for y in y0..y1 {
        for x in x0..x1 {
            img.set(x, y, c);
        }
    }
}

/// A small scatter: discs, a frame line and a pastel region.
fn scene(w: u32, h: u32) -> Image {
    let mut img = Image::filled(size(w, h), [250, 250, 250, 255]);
    rect(
        &mut img,
        w / 5,
        h / 4,
        w / 2,
        h * 3 / 4,
        [222, 235, 247, 255],
    );
    for x in 0..w {
        img.set(x, h.saturating_sub(6), [120, 120, 120, 255]);
    }
    let (wf, hf) = (w as f32, h as f32);
    disc(&mut img, 0.2 * wf, 0.3 * hf, 7.0, RED);
    disc(&mut img, 0.55 * wf, 0.5 * hf, 9.0, BLUE);
    disc(&mut img, 0.85 * wf, 0.7 * hf, 6.0, RED);
    img
}

fn count(img: &Image, c: [u8; 4]) -> usize {
    img.pixels().iter().filter(|&&p| p == c).count()
}

#[test]
fn every_method_gives_exactly_the_target_size() {
    let img = scene(160, 100);
    let targets = [
        (80, 100),  // narrower
        (260, 100), // wider
        (160, 50),  // shorter
        (160, 170), // taller
        (70, 180),  // both, opposite ways
        (330, 45),
    ];
    for method in Method::ALL {
        for (tw, th) in targets {
            let out = retarget_with(method, &img, size(tw, th), &Options::default())
                .unwrap_or_else(|e| panic!("{method} {tw}x{th}: {e}"));
            assert_eq!(out.image.size(), size(tw, th), "{method}");
            assert_eq!(out.method, method);
            assert_eq!(out.stats.vertices.is_some(), method.has_mesh(), "{method}");
        }
    }
}

#[test]
fn tiny_images_and_targets_do_not_fail() {
    let one = Image::filled(size(1, 1), RED);
    let thin = scene(40, 3);
    for method in Method::ALL {
        for (img, t) in [
            (&one, size(3, 2)),
            (&one, size(1, 1)),
            (&thin, size(1, 1)),
            (&thin, size(2, 9)),
        ] {
            let out = retarget_with(method, img, t, &Options::default())
                .unwrap_or_else(|e| panic!("{method} {} -> {t}: {e}", img.size()));
            assert_eq!(out.image.size(), t, "{method}");
        }
    }
}

#[test]
fn invalid_options_are_errors_for_every_method() {
    let img = scene(60, 40);
    let bad = Options::default().with_alpha(1.0);
    for method in Method::ALL {
        let err = retarget_with(method, &img, size(30, 40), &bad).unwrap_err();
        assert!(err.to_string().contains("alpha"), "{method}: {err}");
    }
}

#[test]
fn names_round_trip_and_unknown_names_list_the_choices() {
    for m in Method::ALL {
        assert_eq!(m.name().parse::<Method>().unwrap(), m);
        assert_eq!(m.to_string().to_uppercase().parse::<Method>().unwrap(), m);
    }
    assert_eq!(Method::default(), Method::Mesh);
    let err = "carve".parse::<Method>().unwrap_err().to_string();
    assert!(
        err.contains("carve") && err.contains("seam") && err.contains("linear"),
        "{err}"
    );
}

#[test]
fn mesh_is_the_crates_own_method() {
    let img = scene(160, 100);
    let t = size(90, 100);
    let a = retarget_with(Method::Mesh, &img, t, &Options::default()).unwrap();
    let b = retarget(&img, t, &Options::default()).unwrap();
    assert_eq!(a.image, b.image);
    assert_eq!(a.stats.vertices, Some(b.stats.vertices));
    assert_eq!(a.stats.dof, Some(b.stats.dof));
}

/// Left half red, right half blue: after scaling, the boundary is at the same relative place.
#[test]
fn linear_scaling_maps_positions_proportionally() {
    let mut img = Image::filled(size(200, 50), RED);
    rect(&mut img, 100, 0, 200, 50, BLUE);
    for (tw, th) in [(50, 50), (130, 20), (420, 90)] {
        let out = retarget_with(Method::Linear, &img, size(tw, th), &Options::default()).unwrap();
        let row = out.image.row(th / 2);
        let mid = tw as usize / 2;
        // Away from the boundary's filter footprint the colours are pure.
        assert!(row[..mid - 2].iter().all(|&p| p == RED), "{tw}x{th}");
        assert!(row[mid + 2..].iter().all(|&p| p == BLUE), "{tw}x{th}");
        assert!(
            matches!(out.mapping, Mapping::Affine { window } if window == [0.0, 0.0, 200.0, 50.0])
        );
    }
    // Same size is an exact copy.
    assert_eq!(resize_linear(img.as_ref(), img.size()), img);
}

/// A salient blob far right of centre: the crop's window must hold it, which a centre crop
/// would not.
#[test]
fn crop_keeps_an_off_centre_salient_blob() {
    let mut img = Image::filled(size(300, 100), WHITE);
    disc(&mut img, 255.0, 40.0, 12.0, RED);
    let blob = count(&img, RED);
    let out = retarget_with(Method::Crop, &img, size(100, 100), &Options::default()).unwrap();
    let Mapping::Affine { window } = out.mapping else {
        panic!("crop maps a window")
    };
    // The window is the target's shape at the cover scale (here: 100 px of 300, full height).
    assert_eq!(window[2] - window[0], 100.0);
    assert_eq!(window[3] - window[1], 100.0);
    assert!(
        window[0] <= 255.0 - 12.0 && window[2] >= 255.0 + 12.0,
        "{window:?}"
    );
    assert!(window[0] > 150.0, "a centre crop would miss the blob");
    // Scale 1: the blob is copied exactly.
    assert_eq!(count(&out.image, RED), blob);

    // Enlarging: the cover scale is 2 and the window half the image, still on the blob.
    let out = retarget_with(Method::Crop, &img, size(300, 200), &Options::default()).unwrap();
    let Mapping::Affine { window } = out.mapping else {
        panic!("crop maps a window")
    };
    assert_eq!(
        (window[2] - window[0], window[3] - window[1]),
        (150.0, 100.0)
    );
    assert!(window[0] <= 243.0 && window[2] >= 267.0, "{window:?}");
    assert_eq!(out.image.size(), size(300, 200));
}

/// An empty image is centre-cropped (ties go to the most central window).
#[test]
fn crop_of_an_empty_image_is_centred() {
    let img = Image::filled(size(300, 100), WHITE);
    let out = retarget_with(Method::Crop, &img, size(100, 100), &Options::default()).unwrap();
    let Mapping::Affine { window } = out.mapping else {
        panic!("crop maps a window")
    };
    assert_eq!(window, [100.0, 0.0, 200.0, 100.0]);
}

/// Connected components of pixels of colour `c`: bounding box and pixel count.
fn components(img: &Image, c: [u8; 4]) -> Vec<([u32; 4], usize)> {
    let (w, h) = (img.width(), img.height());
    let mut seen = vec![false; (w * h) as usize];
    let mut out = Vec::new();
    for y0 in 0..h {
        for x0 in 0..w {
            if seen[(y0 * w + x0) as usize] || img.get(x0, y0) != c {
                continue;
            }
            let mut stack = vec![(x0, y0)];
            seen[(y0 * w + x0) as usize] = true;
            let (mut bb, mut n) = ([x0, y0, x0, y0], 0);
            while let Some((x, y)) = stack.pop() {
                n += 1;
                bb = [bb[0].min(x), bb[1].min(y), bb[2].max(x), bb[3].max(y)];
                let nb = [
                    (x.wrapping_sub(1), y),
                    (x + 1, y),
                    (x, y.wrapping_sub(1)),
                    (x, y + 1),
                ];
                for (nx, ny) in nb {
                    if nx < w && ny < h && !seen[(ny * w + nx) as usize] && img.get(nx, ny) == c {
                        seen[(ny * w + nx) as usize] = true;
                        stack.push((nx, ny));
                    }
                }
            }
            out.push((bb, n));
        }
    }
    out
}

/// Two marks with empty space around and between them: narrowing by less than the empty
/// columns removes only empty pixels, so both marks survive pixel for pixel, closer together.
#[test]
fn seam_carving_removes_empty_columns_first() {
    let mut img = Image::filled(size(240, 80), WHITE);
    rect(&mut img, 40, 20, 52, 60, BLACK);
    disc(&mut img, 180.0, 40.0, 10.0, RED);
    let before = components(&img, RED);
    let out = retarget_with(Method::Seam, &img, size(140, 80), &Options::default()).unwrap();
    let o = &out.image;
    assert_eq!(o.size(), size(140, 80));
    // The bar: one component of exactly 12×40 pixels.
    let bars = components(o, BLACK);
    assert_eq!(bars.len(), 1, "{bars:?}");
    let ([x0, y0, x1, y1], n) = bars[0];
    assert_eq!((x1 - x0 + 1, y1 - y0 + 1, n), (12, 40, 480));
    assert_eq!((y0, y1), (20, 59), "rows are untouched by vertical seams");
    // The disc: same pixel count and the same shape, shifted.
    let discs = components(o, RED);
    assert_eq!(discs.len(), 1);
    let (bb, n) = discs[0];
    let (bb0, n0) = before[0];
    assert_eq!(n, n0);
    assert_eq!(
        (bb[2] - bb[0], bb[3] - bb[1]),
        (bb0[2] - bb0[0], bb0[3] - bb0[1])
    );
    let dx = bb0[0] - bb[0];
    for y in bb0[1]..=bb0[3] {
        for x in bb0[0]..=bb0[2] {
            assert_eq!(img.get(x, y) == RED, o.get(x - dx, y) == RED, "({x},{y})");
        }
    }
    // Only white was removed: every colour count but white's is unchanged.
    assert_eq!(count(o, BLACK), count(&img, BLACK));
    assert_eq!(count(o, WHITE), count(&img, WHITE) - 100 * 80);
}

/// Enlarging duplicates low-energy (empty) seams: the marks keep their pixels.
#[test]
fn seam_insertion_widens_empty_space() {
    let mut img = Image::filled(size(120, 60), WHITE);
    rect(&mut img, 30, 10, 40, 50, BLACK);
    rect(&mut img, 80, 10, 90, 50, BLACK);
    let out = retarget_with(Method::Seam, &img, size(200, 90), &Options::default()).unwrap();
    assert_eq!(out.image.size(), size(200, 90));
    let bars = components(&out.image, BLACK);
    assert_eq!(bars.len(), 2, "{bars:?}");
    for ([x0, _, x1, _], _) in bars {
        assert_eq!(x1 - x0 + 1, 10, "bar width kept");
    }
}

#[test]
fn grid_never_folds() {
    let img = scene(200, 120);
    for (tw, th) in [(40, 120), (200, 24), (600, 120), (60, 480), (1000, 30)] {
        let out = retarget_with(Method::Grid, &img, size(tw, th), &Options::default()).unwrap();
        let Mapping::Warp { mesh, warp } = &out.mapping else {
            panic!("grid maps through a mesh")
        };
        assert_eq!(warp.folded_triangles(mesh), 0, "{tw}x{th}");
        // A uniform lattice: every vertex on a regular grid of about α px.
        let v = mesh.vertices().len();
        assert_eq!(v, (200 / 20 + 1) * (120 / 20 + 1), "{tw}x{th}");
        assert_eq!(out.stats.vertices, Some(v));
    }
}
