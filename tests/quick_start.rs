//! The README's examples keep their word: halving the width of `streams/scatter-map`'s first
//! frame leaves every dot round, the pale ones on the sea too, and the `--stats` example's
//! dashboard keeps its status dots round.

use vizretarget::{retarget, Image, Options, Size};

/// The pixels of one colour's connected blobs (8-connected, within `tol` RGB of `colour`), at
/// least `min_px` each.
fn blobs(img: &Image, colour: [u8; 3], tol: i32, min_px: usize) -> Vec<Vec<(u32, u32)>> {
    let (w, h) = (img.width(), img.height());
    let near = |x: u32, y: u32| {
        let p = img.get(x, y);
        (0..3)
            .map(|c| (p[c] as i32 - colour[c] as i32).pow(2))
            .sum::<i32>()
            < tol * tol
    };
    let mut seen = vec![false; (w * h) as usize];
    let mut out = Vec::new();
    for start in 0..w * h {
        let (sx, sy) = (start % w, start / w);
        if seen[start as usize] || !near(sx, sy) {
            continue;
        }
        seen[start as usize] = true;
        let (mut stack, mut pixels) = (vec![(sx, sy)], Vec::new());
        while let Some((x, y)) = stack.pop() {
            pixels.push((x, y));
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                        continue;
                    }
                    let (nx, ny) = (nx as u32, ny as u32);
                    if !seen[(ny * w + nx) as usize] && near(nx, ny) {
                        seen[(ny * w + nx) as usize] = true;
                        stack.push((nx, ny));
                    }
                }
            }
        }
        if pixels.len() >= min_px {
            out.push(pixels);
        }
    }
    out
}

/// Minor over major axis of a blob's pixels (the root of its covariance's eigenvalue ratio):
/// 1 for a disc, 0.5 for a disc squeezed to half its width.
fn roundness(pixels: &[(u32, u32)]) -> f64 {
    let n = pixels.len() as f64;
    let (mx, my) = pixels.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + x as f64 / n, b + y as f64 / n)
    });
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for &(x, y) in pixels {
        let (dx, dy) = (x as f64 - mx, y as f64 - my);
        (sxx, syy, sxy) = (sxx + dx * dx / n, syy + dy * dy / n, sxy + dx * dy / n);
    }
    let (tr, det) = (sxx + syy, sxx * syy - sxy * sxy);
    let d = (tr * tr / 4.0 - det).max(0.0).sqrt();
    let (lo, hi) = (tr / 2.0 - d, tr / 2.0 + d);
    (lo.max(1e-9) / hi.max(1e-9)).sqrt()
}

/// Roundness of a blob with its antialiased rim counted: each pixel of the blob's box (two
/// pixels wider) weighs how far its colour lies from the ground (the box border's median
/// distance from `colour`) towards `colour`, and the weighted moments give minor over major
/// axis. A dot a few pixels across is as round as its coverage is, not as the pixels past a
/// threshold happen to be.
fn coverage_roundness(img: &Image, pixels: &[(u32, u32)], colour: [u8; 3]) -> f64 {
    let (x0, x1) = (
        pixels.iter().map(|p| p.0).min().unwrap(),
        pixels.iter().map(|p| p.0).max().unwrap(),
    );
    let (y0, y1) = (
        pixels.iter().map(|p| p.1).min().unwrap(),
        pixels.iter().map(|p| p.1).max().unwrap(),
    );
    let (x0, y0) = (x0.saturating_sub(2), y0.saturating_sub(2));
    let (x1, y1) = ((x1 + 3).min(img.width()), (y1 + 3).min(img.height()));
    let dist = |x: u32, y: u32| {
        let p = img.get(x, y);
        (0..3)
            .map(|c| (p[c] as f64 - colour[c] as f64).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut border: Vec<f64> = (x0..x1)
        .flat_map(|x| [(x, y0), (x, y1 - 1)])
        .chain((y0..y1).flat_map(|y| [(x0, y), (x1 - 1, y)]))
        .map(|(x, y)| dist(x, y))
        .collect();
    border.sort_by(f64::total_cmp);
    let ground = border[border.len() / 2].max(1.0);
    let (mut n, mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for y in y0..y1 {
        for x in x0..x1 {
            let w = (1.0 - dist(x, y) / ground).clamp(0.0, 1.0);
            let (fx, fy) = (x as f64, y as f64);
            (n, sx, sy) = (n + w, sx + w * fx, sy + w * fy);
            (sxx, syy, sxy) = (sxx + w * fx * fx, syy + w * fy * fy, sxy + w * fx * fy);
        }
    }
    let (mx, my) = (sx / n, sy / n);
    let (cxx, cyy, cxy) = (sxx / n - mx * mx, syy / n - my * my, sxy / n - mx * my);
    let (tr, det) = (cxx + cyy, cxx * cyy - cxy * cxy);
    let d = (tr * tr / 4.0 - det).max(0.0).sqrt();
    ((tr / 2.0 - d).max(1e-9) / (tr / 2.0 + d).max(1e-9)).sqrt()
}

#[test]
fn the_quick_start_dots_stay_round() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/streams/scatter-map/frame-0000.png"
    );
    let src = vizretarget::io::read_still(std::path::Path::new(path)).unwrap();
    let target = Size::new(src.width() / 2, src.height()).unwrap();
    let out = retarget(&src, target, &Options::default()).unwrap().image;
    // The dots' colours: those of a few hundred pixels (the land and sea have thousands, the
    // antialiased rims a handful each) in two blobs or more.
    let colours: Vec<[u8; 3]> = {
        let mut counts = std::collections::HashMap::<[u8; 3], usize>::new();
        for p in src.pixels() {
            *counts.entry([p[0], p[1], p[2]]).or_default() += 1;
        }
        let mut c: Vec<[u8; 3]> = (counts.into_iter())
            .filter(|&(_, n)| (60..3000).contains(&n))
            .map(|(k, _)| k)
            .collect();
        c.sort_unstable();
        c.retain(|&k| blobs(&src, k, 8, 30).len() >= 2);
        c
    };
    assert!(colours.len() >= 6, "{colours:?}");
    let mut round = Vec::new();
    for k in colours {
        let before = blobs(&src, k, 70, 30);
        let after = blobs(&out, k, 70, 16);
        assert_eq!(after.len(), before.len(), "dots of colour {k:?}");
        for b in &after {
            // A dot under 6 px across (the map kept its shape at half the scale) is as round
            // as its few pixels can show: a square box. Its moments measure its pixels' rims
            // more than its shape.
            let side = |k: fn(&(u32, u32)) -> u32| {
                b.iter().map(k).max().unwrap() - b.iter().map(k).min().unwrap() + 1
            };
            let (bw, bh) = (side(|p| p.0), side(|p| p.1));
            let r = roundness(b);
            if bw.max(bh) < 6 {
                assert!(
                    bw.abs_diff(bh) <= 1,
                    "a dot of colour {k:?} came out {bw}x{bh}"
                );
                round.push(r);
                continue;
            }
            // Squeezed, a dot measures 0.4 to 0.6; resampled from its own raster, a dot 6 px
            // across came out 0.83 (a pixel wider on one side). Past a threshold, a dot
            // astride land and sea, whose rim blends into each ground apart, measures 0.898;
            // its coverage is round (0.93).
            assert!(r >= 0.89, "a dot of colour {k:?} came out {r:.3} round");
            let c = coverage_roundness(&out, b, k);
            assert!(
                c >= 0.9,
                "a dot of colour {k:?} came out {c:.3} round (coverage)"
            );
            round.push(r);
        }
    }
    assert!(round.len() >= 25, "{} dots", round.len());
    round.sort_by(f64::total_cmp);
    let median = round[round.len() / 2];
    assert!(median >= 0.95, "median roundness {median:.2}: {round:?}");
}

/// `streams/dashboard/frame-0000.png --width 400` (the README's `--stats` example): the four
/// green status dots in the header come out round, though the same green draws a progress
/// bar (a bar follows the map and says nothing of its colour's dots).
#[test]
fn the_dashboards_status_dots_stay_round() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/streams/dashboard/frame-0000.png"
    );
    let src = vizretarget::io::read_still(std::path::Path::new(path)).unwrap();
    let target = Size::new(400, src.height()).unwrap();
    let out = retarget(&src, target, &Options::default()).unwrap().image;
    let green = [44, 160, 44];
    let (before, after) = (blobs(&src, green, 70, 30), blobs(&out, green, 70, 16));
    assert_eq!(before.len(), 5, "four dots and a bar");
    assert_eq!(after.len(), 5);
    let dots: Vec<f64> = after
        .iter()
        .filter(|b| b.len() < 200)
        .map(|b| roundness(b))
        .collect();
    assert_eq!(dots.len(), 4, "{dots:?}");
    assert!(dots.iter().all(|&r| r >= 0.9), "{dots:?}");
}
