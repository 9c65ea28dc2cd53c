//! The metrics (their definitions on cases with known answers, and mesh against linear on a
//! scatter) and the comparison sheet (layout, labels set with the font, mesh overlay).

use vizretarget::baseline::Mapping;
use vizretarget::compare::{compare, compare_methods, sheet, text_width, SheetOptions};
use vizretarget::metrics::{measure, MetricsTable};
use vizretarget::{retarget_with, Image, Method, Options, Regions, Size};

const WHITE: [u8; 4] = [255, 255, 255, 255];
const RED: [u8; 4] = [215, 25, 28, 255];
const BLUE: [u8; 4] = [44, 123, 182, 255];

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

/// Discs spread over a white canvas, a few px of margin each side.
fn scatter(w: u32, h: u32, n: u32) -> Image {
    let mut img = Image::filled(size(w, h), WHITE);
    let mut k = 0u32;
    for j in 0..n {
        for i in 0..n {
            let cx = (i as f32 + 0.5) * w as f32 / n as f32;
            let cy = (j as f32 + 0.5) * h as f32 / n as f32;
            disc(
                &mut img,
                cx,
                cy,
                6.0 + (k % 3) as f32,
                if k.is_multiple_of(2) { RED } else { BLUE },
            );
            k += 1;
        }
    }
    img
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// Linear scaling to half the width: a constant Jacobian diag(0.5, 1), so the distortion is
/// |0.5 − 1|/√2 / 0.75 and the salient area halves, exactly.
#[test]
fn linear_half_width_has_the_analytic_measures() {
    let img = scatter(240, 160, 4);
    let out = retarget_with(Method::Linear, &img, size(120, 160), &Options::default()).unwrap();
    let m = measure(&img, &out);
    let want = 0.5 / 2f64.sqrt() / 0.75;
    assert!(close(m.distortion.unwrap(), want, 1e-12), "{m:?}");
    assert!(close(m.salient_area_kept.unwrap(), 0.5, 1e-12), "{m:?}");
    assert!(m.vertices.is_none() && m.dof.is_none());
    // Every source pixel spread over the same share of the output: the source's mean.
    let src_mean = compare_methods(&img, size(120, 160), &Options::default(), &[Method::Linear])
        .unwrap()
        .metrics
        .source_saliency_mean;
    assert!(
        src_mean > 0.01 && close(m.saliency_carried, src_mean, 1e-9),
        "{m:?} {src_mean}"
    );
    // Uniform scaling has no distortion, and keeps the area by the square of the scale.
    let out = retarget_with(Method::Linear, &img, size(120, 80), &Options::default()).unwrap();
    let m = measure(&img, &out);
    assert!(close(m.distortion.unwrap(), 0.0, 1e-12));
    assert!(close(m.salient_area_kept.unwrap(), 0.25, 1e-12));
}

/// A crop at scale 1 that holds every mark keeps all salient area, undistorted, and all the
/// saliency there was (the window holds every salient pixel; the empty rest adds nothing).
#[test]
fn crop_holding_all_marks_keeps_everything() {
    let mut img = Image::filled(size(300, 100), WHITE);
    disc(&mut img, 200.0, 50.0, 10.0, RED);
    disc(&mut img, 240.0, 30.0, 8.0, BLUE);
    let out = retarget_with(Method::Crop, &img, size(120, 100), &Options::default()).unwrap();
    let m = measure(&img, &out);
    assert_eq!(m.distortion, Some(0.0));
    assert!(close(m.salient_area_kept.unwrap(), 1.0, 1e-12), "{m:?}");
    assert!(close(m.saliency_kept, 1.0, 0.05), "{m:?}");
}

/// The same size through the mesh is the identity: no distortion, all area kept (the paper's
/// warp, which has a mesh to measure; the default's one linear map is checked below).
#[test]
fn mesh_at_the_same_size_measures_as_the_identity() {
    let img = scatter(200, 120, 3);
    let options = Options::default().with_regions(Regions::Free);
    let out = retarget_with(Method::Mesh, &img, img.size(), &options).unwrap();
    let m = measure(&img, &out);
    assert!(m.distortion.unwrap() < 1e-3, "{m:?}");
    assert!(close(m.salient_area_kept.unwrap(), 1.0, 1e-3), "{m:?}");
    assert!(close(m.saliency_kept, 1.0, 1e-6), "{m:?}");
    let src_mean = compare_methods(&img, img.size(), &options, &[Method::Mesh])
        .unwrap()
        .metrics
        .source_saliency_mean;
    assert!(
        close(m.saliency_carried, src_mean, 1e-3 * src_mean),
        "{m:?}"
    );
    assert!(m.vertices.unwrap() > 4 && m.dof.unwrap() > 0);
}

/// The default takes the canvas whole: its mesh is the canvas's two triangles, nothing is
/// solved, and it is measured as the linear map it is (at half width: a similarity deviation
/// of a linear squeeze, all salient content kept at half its area).
#[test]
fn the_default_measures_as_one_linear_map() {
    let img = scatter(200, 120, 3);
    let out = retarget_with(Method::Mesh, &img, size(100, 120), &Options::default()).unwrap();
    assert!(matches!(out.mapping, Mapping::Affine { .. }));
    assert_eq!(
        (out.stats.vertices, out.stats.triangles, out.stats.dof),
        (Some(4), Some(2), Some(0))
    );
    let m = measure(&img, &out);
    let linear = measure(
        &img,
        &retarget_with(Method::Linear, &img, size(100, 120), &Options::default()).unwrap(),
    );
    assert_eq!(m.distortion, linear.distortion);
    assert_eq!(m.salient_area_kept, linear.salient_area_kept);
    assert!(m.distortion.unwrap() > 0.1, "{m:?}");
}

/// Where nothing gives way the default draws the picture at one scale on its ground: it is
/// measured as that map (no distortion, salient content kept at the scale's area), not as the
/// squeeze it no longer draws.
#[test]
fn a_picture_drawn_at_one_scale_measures_as_one() {
    let mut img = Image::filled(size(200, 100), WHITE);
    for x in 0..200 {
        img.set(x, 0, [40, 40, 40, 255]);
        img.set(x, 99, [40, 40, 40, 255]);
    }
    for y in 0..100 {
        img.set(0, y, [40, 40, 40, 255]);
        img.set(199, y, [40, 40, 40, 255]);
    }
    disc(&mut img, 100.0, 50.0, 20.0, RED);
    let out = retarget_with(Method::Mesh, &img, size(100, 100), &Options::default()).unwrap();
    let Mapping::Affine { window } = out.mapping else {
        panic!("measured as one map")
    };
    assert_eq!(window, [0.0, -50.0, 200.0, 150.0]);
    let m = measure(&img, &out);
    assert!(m.distortion.unwrap() < 1e-12, "{m:?}");
    assert!(close(m.salient_area_kept.unwrap(), 0.25, 1e-9), "{m:?}");
}

/// Seam carving that removes only empty columns keeps every salient pixel, undistorted.
#[test]
fn seam_carving_through_empty_space_keeps_the_marks() {
    let mut img = Image::filled(size(300, 80), WHITE);
    disc(&mut img, 60.0, 40.0, 9.0, RED);
    disc(&mut img, 240.0, 40.0, 9.0, BLUE);
    let out = retarget_with(Method::Seam, &img, size(200, 80), &Options::default()).unwrap();
    let m = measure(&img, &out);
    assert!(close(m.salient_area_kept.unwrap(), 1.0, 1e-12), "{m:?}");
    assert!(m.distortion.unwrap() < 0.05, "{m:?}");
}

/// On a scatter halved in width, the mesh keeps the discs near their size and round; linear
/// scaling halves and squashes them.
#[test]
fn mesh_beats_linear_on_a_scatter() {
    let img = scatter(480, 240, 5);
    let c = compare_methods(
        &img,
        size(240, 240),
        &Options::default().with_regions(Regions::Auto),
        &[Method::Mesh, Method::Linear, Method::Grid],
    )
    .unwrap();
    let mesh = c.metrics.row(Method::Mesh).unwrap();
    let linear = c.metrics.row(Method::Linear).unwrap();
    assert!(
        mesh.salient_area_kept.unwrap() > 0.8 && linear.salient_area_kept.unwrap() < 0.55,
        "{}",
        c.metrics
    );
    assert!(
        mesh.distortion.unwrap() < 0.5 * linear.distortion.unwrap(),
        "{}",
        c.metrics
    );
    assert!(mesh.saliency_kept > linear.saliency_kept, "{}", c.metrics);
    assert!(mesh.saliency_mean > linear.saliency_mean, "{}", c.metrics);
    assert!(
        mesh.saliency_carried > 1.2 * linear.saliency_carried,
        "{}",
        c.metrics
    );
}

/// A scatter made wider at the same height: the mesh grows its discs as one piece (round,
/// larger: the canvas has room for them), where linear scaling stretches them into ellipses.
/// Kept at their size, their area would stay near 1 and the output would show less saliency
/// per pixel than linear scaling; grown by the mean of the axes' scales, it shows as much.
#[test]
fn mesh_grows_marks_round_when_the_canvas_grows() {
    let img = scatter(240, 160, 4);
    let c = compare_methods(
        &img,
        size(380, 160),
        &Options::default().with_regions(Regions::Auto),
        &[Method::Mesh, Method::Linear],
    )
    .unwrap();
    let mesh = c.metrics.row(Method::Mesh).unwrap();
    let linear = c.metrics.row(Method::Linear).unwrap();
    let area = mesh.salient_area_kept.unwrap();
    assert!(area > 1.35 && area < 1.8, "{}", c.metrics);
    assert!(mesh.distortion.unwrap() < 0.1, "{}", c.metrics);
    assert!(linear.distortion.unwrap() > 0.2, "{}", c.metrics);
    assert!(
        mesh.saliency_carried > 0.97 * linear.saliency_carried,
        "{}",
        c.metrics
    );
}

#[test]
fn table_prints_aligned_and_serializes() {
    let img = scatter(160, 100, 3);
    let c = compare(&img, size(90, 100), &Options::default()).unwrap();
    let text = c.metrics.to_string();
    let lines: Vec<&str> = text.lines().collect();
    // A title, a header and one row per method, in order.
    assert_eq!(lines.len(), 2 + Method::ALL.len(), "{text}");
    assert!(lines[1].starts_with("method") && lines[1].contains("DOF"));
    let width = lines[1].len();
    for (line, m) in lines[2..].iter().zip(Method::ALL) {
        assert!(line.starts_with(m.name()), "{line}");
        assert_eq!(line.len(), width, "aligned:\n{text}");
    }
    let json: serde_json::Value = serde_json::from_str(&c.metrics.to_json().to_string()).unwrap();
    let rows = json["rows"].as_array().unwrap();
    assert_eq!(rows.len(), Method::ALL.len());
    assert_eq!(rows[0]["method"], "mesh");
    assert!(rows[0]["vertices"].as_u64().unwrap() > 0);
    assert!(rows[4]["vertices"].is_null(), "seam has no mesh");
    assert_eq!(json["target"]["width"], 90);
    for r in rows {
        assert!(r["saliency_mean"].as_f64().unwrap() >= 0.0);
        assert!(r["ms"]["total"].as_f64().unwrap() >= 0.0);
    }
    assert_eq!(
        MetricsTable::measure(&img, &c.outputs).rows.len(),
        Method::ALL.len()
    );
}

/// Where the original's pixels appear in the sheet (top-left corner), found by matching its
/// first row.
fn find(sheet: &Image, img: &Image) -> Option<(u32, u32)> {
    let (w, h) = (img.width(), img.height());
    for y in 0..=sheet.height().saturating_sub(h) {
        for x in 0..=sheet.width().saturating_sub(w) {
            if sheet.row(y)[x as usize..(x + w) as usize] == *img.row(0)
                && (0..h).all(|j| sheet.row(y + j)[x as usize..(x + w) as usize] == *img.row(j))
            {
                return Some((x, y));
            }
        }
    }
    None
}

#[test]
fn sheet_shows_every_panel_with_a_set_label() {
    let img = scatter(160, 100, 3);
    let c = compare(&img, size(90, 100), &Options::default()).unwrap();
    let opts = SheetOptions::default();
    let s = c.sheet(&img, &opts);
    // The original and every output appear pixel for pixel (no scaling at this size).
    let (ox, oy) = find(&s, &img).expect("original on the sheet");
    for o in &c.outputs {
        assert!(find(&s, &o.image).is_some(), "{} on the sheet", o.method);
    }
    // Corners are background.
    assert_eq!(s.get(0, 0), opts.background);
    assert_eq!(s.get(s.width() - 1, s.height() - 1), opts.background);
    // The label above the original: dark ink with anti-aliased (intermediate) edges, over
    // about the width the font gives the text, and nothing right of it.
    let label_w = text_width("original 160×100", opts.font_px).ceil() as u32;
    assert!(label_w > 80 && label_w < 200, "{label_w}");
    let (mut dark, mut grey, mut right) = (0, 0, 0);
    let mut last_ink = 0;
    for y in 0..oy.saturating_sub(2) {
        for x in ox..ox + img.width() + 2 {
            let p = s.get(x, y);
            if p == opts.background {
                continue;
            }
            if p[0] < 80 {
                dark += 1;
            } else {
                grey += 1;
            }
            last_ink = last_ink.max(x);
            if x > ox + label_w + 2 {
                right += 1;
            }
        }
    }
    assert!(dark > 50 && grey > 50, "dark {dark} grey {grey}");
    assert_eq!(right, 0, "ink right of the label's advance width");
    assert!(last_ink + 6 >= ox + label_w, "{last_ink} vs {label_w}");
}

#[test]
fn mesh_overlay_marks_only_mesh_panels_and_rows_wrap() {
    let img = scatter(160, 100, 3);
    let c = compare(&img, size(90, 100), &Options::default()).unwrap();
    let plain = sheet(&img, &c.outputs, None, &SheetOptions::default());
    let overlay = sheet(
        &img,
        &c.outputs,
        None,
        &SheetOptions {
            mesh_overlay: true,
            ..SheetOptions::default()
        },
    );
    assert_eq!(plain.size(), overlay.size());
    for o in &c.outputs {
        let shown = find(&overlay, &o.image).is_some();
        assert_eq!(
            shown,
            !matches!(o.mapping, Mapping::Warp { .. }),
            "{} drawn {} overlay",
            o.method,
            if shown { "without" } else { "with" }
        );
    }
    // Narrow sheets wrap into rows: taller and narrower.
    let narrow = sheet(
        &img,
        &c.outputs,
        None,
        &SheetOptions {
            max_width: 400,
            ..SheetOptions::default()
        },
    );
    assert!(narrow.width() <= 400 && narrow.height() > 2 * plain.height());
    assert!(find(&narrow, &img).is_some(), "still unscaled");
    // A panel wider than the sheet allows scales the whole sheet down.
    let tiny = sheet(
        &img,
        &c.outputs,
        None,
        &SheetOptions {
            max_width: 120,
            ..SheetOptions::default()
        },
    );
    assert!(tiny.width() <= 120, "{}", tiny.width());
}

/// The command line: `compare` and `--method` (skipped when the binary is not built, as with
/// `--no-default-features`).
mod cli {
    use super::*;
    use std::process::{Command, Output};
    use vizretarget::io::{read_still, write_still, OutputFormat};

    fn run(dir: &std::path::Path, args: &[&str]) -> Option<Output> {
        let bin = option_env!("CARGO_BIN_EXE_vizretarget")?;
        Some(
            Command::new(bin)
                .args(args)
                .current_dir(dir)
                .output()
                .expect("the binary runs"),
        )
    }

    fn setup() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        write_still(
            &scatter(240, 120, 3),
            &dir.path().join("in.png"),
            OutputFormat::Png,
        )
        .unwrap();
        dir
    }

    #[test]
    fn compare_writes_the_sheet_and_prints_the_table() {
        let dir = setup();
        let args = [
            "compare",
            "in.png",
            "--width",
            "120",
            "-o",
            "sheet.png",
            "--mesh",
        ];
        let Some(out) = run(dir.path(), &args) else {
            return;
        };
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        for m in Method::ALL {
            assert!(
                text.lines().any(|l| l.starts_with(m.name())),
                "{m} row:\n{text}"
            );
        }
        let sheet = read_still(&dir.path().join("sheet.png")).unwrap();
        assert!(sheet.width() > 240 + 5 * 120 / 2 && sheet.height() > 120);

        let args = [
            "compare", "in.png", "--size", "120x120", "-o", "s.jpg", "--json",
        ];
        let out = run(dir.path(), &args).unwrap();
        assert!(out.status.success());
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(json["rows"].as_array().unwrap().len(), Method::ALL.len());
        assert_eq!(json["target"]["height"], 120);
        assert!(dir.path().join("s.jpg").is_file());
    }

    #[test]
    fn method_picks_the_baseline_for_a_still() {
        let dir = setup();
        for m in ["linear", "crop", "grid", "seam", "mesh"] {
            let name = format!("{m}.png");
            let args = ["in.png", "--size", "100x150", "-o", &name, "--method", m];
            let Some(out) = run(dir.path(), &args) else {
                return;
            };
            assert!(
                out.status.success(),
                "{m}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let img = read_still(&dir.path().join(&name)).unwrap();
            assert_eq!(img.size(), size(100, 150), "{m}");
        }
        // Linear through the CLI is the library's linear output.
        let lib = retarget_with(
            Method::Linear,
            &read_still(&dir.path().join("in.png")).unwrap(),
            size(100, 150),
            &Options::default(),
        )
        .unwrap();
        assert_eq!(
            read_still(&dir.path().join("linear.png")).unwrap(),
            lib.image
        );
    }

    #[test]
    fn bad_uses_fail_on_one_line() {
        let dir = setup();
        let cases: [(&[&str], i32, &str); 4] = [
            (&["compare", "in.png", "-o", "s.png"], 2, "required"),
            (
                &["compare", "in.png", "--width", "9", "-o", "s.gif"],
                2,
                "one picture",
            ),
            (
                &["compare", "missing.png", "--width", "9", "-o", "s.png"],
                1,
                "missing.png",
            ),
            (
                &[
                    "in.png", "--width", "9", "-o", "out.gif", "--method", "seam",
                ],
                2,
                "streams",
            ),
        ];
        for (args, code, word) in cases {
            let Some(out) = run(dir.path(), args) else {
                return;
            };
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
            assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
            assert!(err.contains(word), "{args:?}: {err}");
            assert!(!err.contains("panicked"));
        }
        assert!(!dir.path().join("s.png").exists() && !dir.path().join("s.gif").exists());
    }
}
