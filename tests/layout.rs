//! The default layout (issue 37's first step): a chart laid out again for the target as its
//! author would, from pixels alone. Type keeps its size, one size per row of labels; an x
//! axis' crowded tick labels are thinned at even steps from the first, each left under its
//! tick; the plot stays one linear map; a picture with nothing around its plot is still drawn at one
//! scale on its ground; a stream keeps its layout.

use vizretarget::compare::draw_label;
use vizretarget::{retarget, Image, Options, Size};

mod common;
use common::draw::{disc, rect};

const INK: [u8; 4] = [40, 40, 40, 255];
const DOT: [u8; 4] = [214, 39, 40, 255];

/// Tick positions (x) of the chart of [`chart`].
const TICKS: [u32; 6] = [100, 220, 340, 460, 580, 700];
/// Where the x axis' labels' rows start, and their type size.
const LABEL_Y: f32 = 378.0;
const LABEL_PX: f32 = 20.0;

/// A scatter chart 760 × 420: y labels in the left margin, an L of axes, six x ticks with
/// labels under them ("10000" to "60000", wide enough to collide at half width), a title,
/// and dots inside.
fn chart() -> Image {
    let mut img = Image::filled(Size::new(760, 420).unwrap(), [255; 4]);
    draw_label(&mut img, 300.0, 6.0, 24.0, "Visitors by month");
    for (i, l) in ["300", "200", "100"].iter().enumerate() {
        draw_label(&mut img, 20.0, 60.0 + 100.0 * i as f32, LABEL_PX, l);
    }
    rect(&mut img, 80, 40, 82, 362, INK);
    rect(&mut img, 80, 360, 740, 362, INK);
    for (i, &t) in TICKS.iter().enumerate() {
        rect(&mut img, t, 362, t + 2, 368, INK);
        let text = format!("{}0000", i + 1);
        draw_label(&mut img, t as f32 - 28.0, LABEL_Y, LABEL_PX, &text);
    }
    for (i, (x, y)) in [
        (150.0, 300.0),
        (260.0, 120.0),
        (400.0, 200.0),
        (520.0, 90.0),
        (650.0, 250.0),
    ]
    .iter()
    .enumerate()
    {
        disc(&mut img, *x, *y, 6.0 + i as f32, DOT);
    }
    img
}

/// The runs `[first, last]` of columns holding dark ink in rows `y0..y1` of `img`.
fn ink_runs(img: &Image, rows: [u32; 2], gap: u32) -> Vec<[u32; 2]> {
    runs_darker(img, rows, gap, 110)
}

/// The runs of columns holding a pixel darker than `level` in rows `y0..y1` of `img`.
fn runs_darker(img: &Image, [y0, y1]: [u32; 2], gap: u32, level: u8) -> Vec<[u32; 2]> {
    let dark = |x: u32| (y0..y1).any(|y| img.get(x, y)[0] < level);
    let mut runs: Vec<[u32; 2]> = Vec::new();
    for x in 0..img.width() {
        if !dark(x) {
            continue;
        }
        match runs.last_mut() {
            Some(r) if x <= r[1] + gap => r[1] = x,
            _ => runs.push([x, x]),
        }
    }
    runs
}

/// The rows `[first, last]` holding dark ink in columns `x0..x1`, between rows `y0..y1`.
fn ink_rows(img: &Image, [x0, x1]: [u32; 2], [y0, y1]: [u32; 2]) -> Option<[u32; 2]> {
    let dark = |y: u32| (x0..x1).any(|x| img.get(x, y)[0] < 110);
    let first = (y0..y1).find(|&y| dark(y))?;
    let last = (y0..y1).rev().find(|&y| dark(y))?;
    Some([first, last])
}

/// Tick marks' columns in the output: dark runs in the rows just under the axis.
fn ticks(img: &Image) -> Vec<f64> {
    // A 2-px tick resampled at half scale is a grey column: lighter than type.
    runs_darker(img, [363, 367], 1, 200)
        .iter()
        .map(|r| (r[0] + r[1] + 1) as f64 / 2.0)
        .collect()
}

#[test]
fn an_x_axis_crowded_labels_are_thinned_and_keep_their_size_under_their_ticks() {
    let img = chart();
    let src_labels = ink_runs(&img, [LABEL_Y as u32, 404], 6);
    assert_eq!(src_labels.len(), 6, "{src_labels:?}");
    let src_width = src_labels[0][1] - src_labels[0][0] + 1;
    let src_rows = ink_rows(&img, [0, 760], [LABEL_Y as u32, 404]).unwrap();
    let target = Size::new(380, 420).unwrap();
    let out = retarget(&img, target, &Options::default()).unwrap();
    let out = out.image;
    let labels = ink_runs(&out, [LABEL_Y as u32 - 4, 410], 6);
    let ticks = ticks(&out);
    assert_eq!(ticks.len(), 6, "every tick is drawn: {ticks:?}");
    // Six labels of 56 px under ticks 60 px apart collide: every other one is dropped from
    // the first, as a locator steps (the last would leave an uneven last step: dropped).
    assert_eq!(labels.len(), 3, "thinned: {labels:?}");
    let centre = |r: &[u32; 2]| (r[0] + r[1] + 1) as f64 / 2.0;
    let near = |x: f64| ticks.iter().map(|t| (t - x).abs()).fold(f64::MAX, f64::min);
    for (l, k) in labels.iter().zip([0, 2, 4]) {
        assert!(
            (centre(l) - ticks[k]).abs() <= 1.5,
            "labels under every other tick from the first: {labels:?} {ticks:?}"
        );
    }
    for l in &labels {
        assert!(
            near(centre(l)) <= 1.5,
            "label {l:?} off its tick: {ticks:?}"
        );
        // One size for the row, the author's: as wide as in the source.
        let w = l[1] - l[0] + 1;
        assert!(
            w.abs_diff(src_width) <= 2,
            "label {w} px wide, source {src_width}"
        );
    }
    let rows = ink_rows(&out, [0, 380], [LABEL_Y as u32 - 4, 410]).unwrap();
    assert!(
        (rows[1] - rows[0]).abs_diff(src_rows[1] - src_rows[0]) <= 1,
        "type height kept: {rows:?} against {src_rows:?}"
    );
    // Without the layout, no label is dropped.
    let plain = retarget(&img, target, &Options::default().with_layout(false)).unwrap();
    let kept = ink_runs(&plain.image, [LABEL_Y as u32 - 4, 410], 1);
    assert!(kept.len() >= 6, "{kept:?}");
}

/// The plot is one linear map: the ticks, evenly spaced in the source, stay evenly spaced.
#[test]
fn the_plot_stays_one_linear_map() {
    let out = retarget(&chart(), Size::new(380, 420).unwrap(), &Options::default()).unwrap();
    let t = ticks(&out.image);
    assert_eq!(t.len(), 6);
    let steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let spread = steps.iter().cloned().fold(f64::MIN, f64::max)
        - steps.iter().cloned().fold(f64::MAX, f64::min);
    assert!(spread <= 1.0, "{steps:?}");
    assert_eq!(out.stats.fitted, None, "laid out, not letterboxed");
}

/// A dot keeps its size (the author's) where no other is near.
#[test]
fn round_marks_keep_their_size() {
    let img = chart();
    let out = retarget(&img, Size::new(380, 420).unwrap(), &Options::default()).unwrap();
    let red = |im: &Image| {
        (0..im.height())
            .flat_map(|y| (0..im.width()).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let p = im.get(x, y);
                p[0] > 180 && p[1] < 90
            })
            .count() as f64
    };
    let ratio = red(&out.image) / red(&img);
    assert!(ratio > 0.85, "dots kept {ratio} of their area");
}

/// A stream whose plot stands keeps its layout: a frame laid out in the stream is the same
/// as the first frame where nothing changed, and the plot's ticks do not move when a dot does.
#[test]
fn a_stream_keeps_its_layout() {
    let first = chart();
    let mut second = first.clone();
    disc(&mut second, 300.0, 320.0, 5.0, DOT);
    let target = Size::new(380, 420).unwrap();
    let mut r = vizretarget::Retargeter::new(target, Options::default()).unwrap();
    let mut outs = Vec::new();
    for (i, f) in [first.clone(), second, first].into_iter().enumerate() {
        r.send_frame(vizretarget::Frame::new(f, i as u64)).unwrap();
        outs.push(r.receive_frame().unwrap().image);
    }
    assert_eq!(ticks(&outs[0]), ticks(&outs[1]), "the plot did not move");
    assert!(outs[2] == outs[0], "the same frame, the same picture");
}

/// A stream whose scene changes (a folder of unrelated charts of one size run as one
/// stream) lays each scene out afresh: a frame after another chart is drawn as it is alone,
/// not in the panels and bands of the chart before it.
#[test]
fn a_new_scene_is_laid_out_afresh() {
    let mut single = Image::filled(Size::new(800, 600).unwrap(), [255; 4]);
    panel(&mut single, 0, 0, 800, 600);
    let target = Size::new(400, 600).unwrap();
    for pictures in [[dashboard(), single.clone()], [single.clone(), dashboard()]] {
        let alone = retarget(&pictures[1], target, &Options::default()).unwrap();
        let mut r = vizretarget::Retargeter::new(target, Options::default()).unwrap();
        let mut outs = Vec::new();
        for (i, f) in pictures.into_iter().enumerate() {
            r.send_frame(vizretarget::Frame::new(f, i as u64)).unwrap();
            outs.push(r.receive_frame().unwrap());
        }
        assert_eq!(outs[1].stats.panels, alone.stats.panels);
        assert!(outs[1].image == alone.image, "drawn as it is alone");
    }
}

/// A small chart in the rectangle at `(x0, y0)`, `w × h`: y labels in its left margin, an
/// L of axes, five x ticks with labels under them, and dots.
fn panel(img: &mut Image, x0: u32, y0: u32, w: u32, h: u32) {
    let (ax, ay) = (x0 + 60, y0 + h - 50);
    for (i, l) in ["30", "20", "10"].iter().enumerate() {
        let y = y0 + 20 + i as u32 * (ay - y0 - 40) / 2;
        draw_label(img, (x0 + 18) as f32, y as f32, LABEL_PX, l);
    }
    rect(img, ax, y0 + 10, ax + 2, ay + 2, INK);
    rect(img, ax, ay, x0 + w - 10, ay + 2, INK);
    let step = (w - 90) / 5;
    for i in 0..5 {
        let t = ax + 15 + i * step;
        rect(img, t, ay + 2, t + 2, ay + 8, INK);
        draw_label(
            img,
            t as f32 - 10.0,
            (ay + 16) as f32,
            LABEL_PX,
            &format!("{}", 2 * i + 2),
        );
    }
    for k in 0..4 {
        let (x, y) = (ax + 30 + k * (w - 110) / 4, y0 + 30 + (k * 37) % (h - 100));
        disc(img, x as f32, y as f32, 6.0, DOT);
    }
}

/// A dashboard: a wide chart over two narrow ones, apart by white gutters.
fn dashboard() -> Image {
    let mut img = Image::filled(Size::new(800, 600).unwrap(), [255; 4]);
    panel(&mut img, 0, 0, 800, 280);
    panel(&mut img, 0, 300, 390, 300);
    panel(&mut img, 410, 300, 390, 300);
    img
}

/// The panels of a dashboard each lay themselves out (a wide chart over two narrow ones
/// cannot share one map per axis): at half width the picture fills the target instead of
/// being drawn at one scale, every panel's y labels keep their type size, and each narrow
/// panel's plot stays one linear map.
#[test]
fn the_panels_of_a_dashboard_lay_themselves_out() {
    let img = dashboard();
    let target = Size::new(400, 600).unwrap();
    let out = retarget(&img, target, &Options::default()).unwrap();
    assert_eq!(out.stats.fitted, None, "laid out, not letterboxed");
    let out = out.image;
    // The y labels of the lower right panel ("30" at its top): their rows of ink.
    let src_rows = ink_rows(&img, [420, 470], [315, 345]).unwrap();
    let right = (200..400)
        .find(|&x| (300..600).any(|y| out.get(x, y)[0] < 110))
        .expect("the right panel's ink");
    let rows = ink_rows(&out, [right, right + 30], [305, 350]).expect("its top y label");
    assert!(
        (rows[1] - rows[0]).abs_diff(src_rows[1] - src_rows[0]) <= 1,
        "type height kept: {rows:?} against {src_rows:?}"
    );
    // Each lower panel's ticks stay evenly spaced (its plot one linear map).
    let ay = 600 - 50 + 4;
    for half in [[0u32, 200u32], [200, 400]] {
        let t: Vec<f64> = runs_darker(&out, [ay, ay + 3], 1, 200)
            .iter()
            .filter(|r| r[0] >= half[0] && r[1] < half[1])
            .map(|r| (r[0] + r[1] + 1) as f64 / 2.0)
            .collect();
        assert_eq!(t.len(), 5, "{half:?}: {t:?}");
        let steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        let spread = steps.iter().cloned().fold(f64::MIN, f64::max)
            - steps.iter().cloned().fold(f64::MAX, f64::min);
        assert!(spread <= 1.0, "{half:?}: {steps:?}");
    }
    // The old one map per axis for the whole picture could not lay it out.
    let plain = retarget(&img, target, &Options::default().with_layout(false)).unwrap();
    assert!(plain.stats.fitted.is_some());
}

const GROUND: [u8; 4] = [240, 240, 240, 255];
const BLUE: [u8; 4] = [31, 119, 180, 255];

/// A card on the page: a grey frame one pixel wide around a white fill.
fn card(img: &mut Image, r: [u32; 4]) {
    rect(img, r[0], r[1], r[2], r[3], [200, 200, 200, 255]);
    rect(img, r[0] + 1, r[1] + 1, r[2] - 1, r[3] - 1, [255; 4]);
}

/// A page of two cards on a grey ground, each a white box with a grey frame, a title at its
/// top and a body under it: a round blob (a map's, whose aspect is data) in the left card,
/// a block of bars in the right one.
fn cards() -> Image {
    let mut img = Image::filled(Size::new(800, 500).unwrap(), GROUND);
    for x0 in [10, 405] {
        card(&mut img, [x0, 10, x0 + 385, 490]);
    }
    draw_label(&mut img, 26.0, 22.0, LABEL_PX, "Sales by state");
    draw_label(&mut img, 421.0, 22.0, LABEL_PX, "Best sellers");
    disc(&mut img, 200.0, 270.0, 90.0, BLUE);
    for i in 0..5 {
        let y = 110 + i * 60;
        rect(&mut img, 440, y, 760 - 40 * i, y + 30, DOT);
    }
    img
}

/// A dashboard of cards lays each card out in its slot (a responsive page's reflow, not a
/// letterbox): at 60 % height every card fills its slot, its title keeps its type size, and
/// its body keeps one scale (the blob stays round), larger than the letterbox draws it.
#[test]
fn a_page_of_cards_lays_each_card_out_in_its_slot() {
    let img = cards();
    let target = Size::new(800, 300).unwrap();
    let out = retarget(&img, target, &Options::default()).unwrap();
    assert_eq!(out.stats.fitted, None, "laid out, not letterboxed");
    assert!(out.stats.panels >= 2, "{} panels", out.stats.panels);
    let out = out.image;
    // The cards reach the sides of the target (a letterbox leaves 160 px of ground there),
    // and the left card's frame runs from the top of its slot to the bottom.
    assert!(out.get(20, 150) != GROUND && out.get(780, 150) != GROUND);
    let framed = |y: u32| out.get(100, y) != GROUND;
    assert!(
        framed(12) && framed(288),
        "the card fills its slot's height"
    );
    // Its title keeps its height.
    let src = ink_rows(&img, [20, 200], [15, 60]).unwrap();
    let now = ink_rows(&out, [5, 200], [10, 50]).expect("the title's ink");
    assert!(
        (now[1] - now[0]).abs_diff(src[1] - src[0]) <= 1,
        "title height kept: {now:?} against {src:?}"
    );
    // The blob keeps one scale, as tall as it is wide, and more than the letterbox's 0.6.
    let blue = |x: u32, y: u32| {
        let p = out.get(x, y);
        p[2] > 150 && p[0] < 90
    };
    let cols: Vec<u32> = (0..400).filter(|&x| (0..300).any(|y| blue(x, y))).collect();
    let rows: Vec<u32> = (0..300).filter(|&y| (0..400).any(|x| blue(x, y))).collect();
    let (w, h) = (cols.len() as f64, rows.len() as f64);
    assert!((w / h - 1.0).abs() < 0.08, "blob {w} x {h}");
    assert!(w > 180.0 * 0.66, "blob {w} wide, letterboxed 108");
}

/// A page of two cards, the right one a chart: five grid lines evenly spaced (one broken
/// where a series crosses it), tick labels left of them and under the last.
fn cards_with_a_plot() -> Image {
    let mut img = Image::filled(Size::new(800, 500).unwrap(), GROUND);
    for x0 in [10, 405] {
        card(&mut img, [x0, 10, x0 + 385, 490]);
    }
    draw_label(&mut img, 26.0, 22.0, LABEL_PX, "Sales by state");
    draw_label(&mut img, 421.0, 22.0, LABEL_PX, "Visits");
    disc(&mut img, 200.0, 270.0, 90.0, BLUE);
    for (i, l) in ["100", "75", "50", "25", "0"].iter().enumerate() {
        let y = PLOT_GRID[i];
        rect(&mut img, 480, y, 760, y + 2, [190, 190, 190, 255]);
        draw_label(&mut img, 430.0, y as f32 - 10.0, LABEL_PX, l);
    }
    for (i, l) in ["Q1", "Q2", "Q3", "Q4"].iter().enumerate() {
        draw_label(&mut img, 500.0 + 80.0 * i as f32, 395.0, LABEL_PX, l);
    }
    // The series: a thick red stroke across the middle line.
    rect(&mut img, 600, 200, 612, 300, DOT);
    img
}

/// Rows of the grid lines of [`cards_with_a_plot`].
const PLOT_GRID: [u32; 5] = [100, 170, 240, 310, 380];

/// A card holding a plot (its grid inside the card's frame, which the picture's data areas
/// take for the plot) is laid out as its author would re-render it for a shorter screen:
/// the plot squeezed to the room the card leaves, its tick labels at their size.
#[test]
fn a_cards_plot_is_squeezed_and_its_labels_keep_their_size() {
    let img = cards_with_a_plot();
    let target = Size::new(800, 300).unwrap();
    let out = retarget(&img, target, &Options::default()).unwrap();
    assert_eq!(out.stats.fitted, None, "laid out, not letterboxed");
    assert!(out.stats.panels >= 2, "{} panels", out.stats.panels);
    let out = out.image;
    // The grid lines, down a column of the plot clear of the series (inside the card's
    // frame, whose lines stand at its slot's top and bottom).
    let grey = |p: [u8; 4]| p[0] > 150 && p[0] < 225 && p[0] == p[2];
    let mut lines: Vec<u32> = Vec::new();
    for y in 15..285 {
        if grey(out.get(720, y)) && lines.last().is_none_or(|&l| y > l + 2) {
            lines.push(y);
        }
    }
    assert_eq!(lines.len(), 5, "grid lines at {lines:?}");
    let spacing = (lines[4] - lines[0]) as f64 / 4.0;
    assert!(spacing < 0.7 * 70.0, "squeezed: spacing {spacing}");
    // Its width kept: the top line still spans the plot's 280 px.
    let width = (400..800).filter(|&x| grey(out.get(x, lines[0]))).count();
    assert!(width as f64 >= 0.9 * 280.0, "plot width {width}");
    // The tick labels left of the plot keep their height.
    let src = ink_rows(&img, [428, 478], [85, 108]).unwrap();
    for &y in &lines[..1] {
        let now = ink_rows(&out, [410, 478], [y.saturating_sub(14), y + 12]).expect("a label");
        assert!(
            (now[1] - now[0]).abs_diff(src[1] - src[0]) <= 1,
            "label height kept: {now:?} against {src:?}"
        );
    }
}

/// A page of two cards one over the other, the lower one's content set across its width (a
/// title running into its body's columns, a note from its body's end to the frame), so that
/// no blank column of its fill can take the room a shorter screen leaves beside its body.
fn stacked_cards() -> Image {
    let mut img = Image::filled(Size::new(600, 500).unwrap(), GROUND);
    for (y0, y1) in [(10, 240), (250, 490)] {
        card(&mut img, [10, y0, 590, y1]);
    }
    draw_label(&mut img, 26.0, 22.0, LABEL_PX, "Sales by region");
    rect(&mut img, 40, 60, 560, 220, BLUE);
    draw_label(
        &mut img,
        26.0,
        262.0,
        LABEL_PX,
        "Sales by state and by month",
    );
    disc(&mut img, 300.0, 390.0, 80.0, BLUE);
    draw_label(&mut img, 380.0, 460.0, LABEL_PX, "Source: survey of sales");
    img
}

/// Where a card's body keeps one scale in a slot wider than it needs, the room over goes
/// inside the card's frame: each frame stays at its slot's edges, in line with the card
/// over it, and the ground around the cards keeps its size.
#[test]
fn cards_frames_stay_at_their_slots_edges() {
    let img = stacked_cards();
    let target = Size::new(600, 300).unwrap();
    let out = retarget(&img, target, &Options::default()).unwrap();
    assert_eq!(out.stats.fitted, None, "laid out, not letterboxed");
    let out = out.image;
    // The first and last columns off the ground, along a row through each card's middle.
    let frame = |y: u32| {
        let off = |x: u32| out.get(x, y) != GROUND;
        let first = (0..600).find(|&x| off(x)).unwrap();
        let last = (0..600).rev().find(|&x| off(x)).unwrap();
        [first, last]
    };
    let (top, bottom) = (frame(60), frame(230));
    assert!(
        top[0].abs_diff(10) <= 1 && top[1].abs_diff(589) <= 1,
        "top frame {top:?}"
    );
    assert!(
        bottom[0].abs_diff(top[0]) <= 1 && bottom[1].abs_diff(top[1]) <= 1,
        "frames in line: {top:?} and {bottom:?}"
    );
}
