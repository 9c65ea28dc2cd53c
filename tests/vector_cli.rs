//! `--marks` and `--enhance*` on the command line: marks drawn where they go, one-line errors
//! naming the file and line, exit codes, and sidecars found beside a folder of frames.

mod common;
use common::{assert_fails, run, stderr};

use std::path::Path;
use std::process::Output;

fn assert_ok(out: &Output) {
    assert_eq!(out.status.code(), Some(0), "stderr: {}", stderr(out));
}

/// A light background without marks.
fn background(dir: &Path, name: &str, w: u32, h: u32) {
    image::RgbImage::from_fn(w, h, |x, y| {
        if (x as i32 - 100).pow(2) + (y as i32 - 80).pow(2) < 60 * 60 {
            image::Rgb([204, 235, 197])
        } else {
            image::Rgb([236, 244, 250])
        }
    })
    .save(dir.join(name))
    .unwrap();
}

const DOTS: &str = r##"{"points": [
  {"id": "a", "x": 60, "y": 50, "r": 8, "fill": "#d7191c"},
  {"id": "b", "x": 240, "y": 120, "r": 8, "fill": "#2c7bb6"}
], "edges": [{"from": "a", "to": "b", "width": 2, "color": "#000000"}]}"##;

#[test]
fn marks_are_drawn_on_a_still_and_enhancement_keeps_the_size() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    background(d, "map.png", 300, 200);
    std::fs::write(d.join("dots.json"), DOTS).unwrap();
    let out = run(
        d,
        &[
            "map.png",
            "--marks",
            "dots.json",
            "--width",
            "150",
            "-o",
            "narrow.png",
        ],
    );
    assert_ok(&out);
    let img = image::open(d.join("narrow.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (150, 200));
    let red = img.pixels().filter(|p| p.0 == [215, 25, 28]).count();
    let blue = img.pixels().filter(|p| p.0 == [44, 123, 182]).count();
    assert!(red > 100 && blue > 100, "red {red}, blue {blue} px");
    // Same size, a region enlarged: the red dot grows, the canvas does not.
    let out = run(
        d,
        &[
            "map.png",
            "--marks",
            "dots.json",
            "--same-size",
            "--enhance-region",
            "20,10,90,80=1.6",
            "-o",
            "big.png",
        ],
    );
    assert_ok(&out);
    let big = image::open(d.join("big.png")).unwrap().to_rgb8();
    assert_eq!(big.dimensions(), (300, 200));
    let grown = big.pixels().filter(|p| p.0 == [215, 25, 28]).count();
    let plain = std::f64::consts::PI * 8.0 * 8.0;
    assert!(grown as f64 > 1.5 * plain, "{grown} px of red");
}

#[test]
fn bad_marks_and_options_fail_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    background(d, "map.png", 120, 80);
    std::fs::write(
        d.join("bad.json"),
        "{\n\"points\": [\n{\"x\": 1, \"y\": 2}\n]}",
    )
    .unwrap();
    let out = run(
        d,
        &[
            "map.png", "--marks", "bad.json", "--width", "60", "-o", "o.png",
        ],
    );
    assert_fails(&out, 1, &["bad.json", "missing field `r`", "line 3"]);
    let out = run(
        d,
        &[
            "map.png",
            "--marks",
            "nothere.json",
            "--width",
            "60",
            "-o",
            "o.png",
        ],
    );
    assert_fails(&out, 1, &["nothere.json"]);
    let out = run(
        d,
        &[
            "map.png",
            "--enhance-region",
            "1,2,3=1.5",
            "--width",
            "60",
            "-o",
            "o.png",
        ],
    );
    assert_fails(&out, 2, &["X,Y,W,H=FACTOR"]);
    let out = run(
        d,
        &[
            "map.png",
            "--enhance",
            "1,1,9",
            "--width",
            "60",
            "-o",
            "o.png",
        ],
    );
    assert_fails(&out, 2, &["out of range"]);
    let out = run(
        d,
        &[
            "map.png",
            "--enhance-mask",
            "map.png",
            "--enhance-mask-factor",
            "0",
            "--same-size",
            "-o",
            "o.png",
        ],
    );
    assert_fails(&out, 2, &["out of range"]);
    let out = run(
        d,
        &[
            "map.png", "--marks", "bad.json", "--method", "seam", "--width", "60", "-o", "o.png",
        ],
    );
    assert_fails(&out, 2, &["--method mesh"]);
    assert!(!d.join("o.png").exists());
}

#[test]
fn a_folder_of_frames_finds_its_sidecars_and_json_lines_must_cover_the_stream() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let frames = d.join("frames");
    std::fs::create_dir(&frames).unwrap();
    for i in 0..3 {
        background(&frames, &format!("f{i}.png"), 160, 100);
        std::fs::write(
            frames.join(format!("f{i}.json")),
            format!(
                "{{\"points\": [{{\"x\": {}, \"y\": 50, \"r\": 7, \"fill\": \"#d7191c\"}}]}}",
                30 + 40 * i
            ),
        )
        .unwrap();
    }
    let out = run(d, &["frames", "--width", "100", "-o", "out/", "-q"]);
    assert_ok(&out);
    for i in 0..3 {
        let img = image::open(d.join(format!("out/f{i}.png")))
            .unwrap()
            .to_rgb8();
        let red = img.pixels().filter(|p| p.0 == [215, 25, 28]).count();
        assert!(red > 60, "frame {i}: {red} px of red");
    }
    // Two lines for three frames: an error naming the file.
    std::fs::write(d.join("two.jsonl"), "{}\n{}\n").unwrap();
    let out = run(
        d,
        &[
            "frames",
            "--marks",
            "two.jsonl",
            "--width",
            "100",
            "-o",
            "out2/",
            "-q",
        ],
    );
    assert_fails(&out, 1, &["two.jsonl", "frame 3"]);
    // A folder of marks with one picture: explained.
    let out = run(
        d,
        &[
            "frames/f0.png",
            "--marks",
            "frames",
            "--width",
            "100",
            "-o",
            "one.png",
        ],
    );
    assert_fails(&out, 2, &["folder of marks"]);
}
