//! Small marks: dots, legend symbols, short labels, found as connected blobs of high importance.
//!
//! A lattice, however fine, cuts a 6-px dot across triangles that are mostly empty; their mean
//! saliency is low, they give way, and the dot turns into an ellipse. A ring of key points just
//! outside each small mark (plus its centre) puts it into a fan of triangles that are all mark,
//! so it keeps its shape. Lattice points near the ring are dropped (they would cut the fan).
//!
//! Blobs use the undilated importance `S_m`, not the VSM: the VSM's dilated edges join a dot to
//! the map outline next to it, and a blob that long is no longer a small mark.

use crate::saliency::Vsm;
use glam::DVec2;

/// Importance above which a pixel belongs to a mark.
const MARK_IMPORTANCE: f32 = 0.5;
/// Blobs smaller than this (bounding box side, px) are specks or anti-aliasing.
const MIN_SIDE_PX: u32 = 3;
/// Blobs larger than this are regions, handled by the lattice.
pub(crate) const MAX_SIDE_PX: u32 = 60;
/// Ring radius beyond the blob's circumscribed circle, px.
const RING_MARGIN_PX: f64 = 1.5;

/// A small mark and the ring of key points around it.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Mark {
    /// Centre of the bounding box, source pixels.
    pub center: DVec2,
    /// Radius of the ring of key points around it.
    pub ring_radius: f64,
    /// Bounding box `[x0, y0, x1, y1]`, exclusive end.
    pub bbox: [u32; 4],
    /// Pixels in the blob.
    pub pixels: u32,
}

/// Finds small marks in `vsm`, merging blobs whose rings would overlap.
pub(crate) fn find_marks(vsm: &Vsm) -> Vec<Mark> {
    let grid = vsm.grid_size();
    let s = vsm.scale();
    let (w, h) = (grid.width as usize, grid.height as usize);
    // Size limits in map cells.
    let max_side = MAX_SIDE_PX.div_ceil(s);
    let imp = vsm.importance();
    let mut seen = vec![false; w * h];
    let mut stack: Vec<u32> = Vec::new();
    let mut blobs: Vec<Mark> = Vec::new();
    for start in 0..w * h {
        if seen[start] || imp[start] < MARK_IMPORTANCE {
            continue;
        }
        seen[start] = true;
        stack.push(start as u32);
        let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0u32, 0u32);
        let mut pixels = 0u32;
        let mut too_big = false;
        while let Some(i) = stack.pop() {
            let (x, y) = (i as usize % w, i as usize / w);
            pixels += 1;
            x0 = x0.min(x as u32);
            y0 = y0.min(y as u32);
            x1 = x1.max(x as u32 + 1);
            y1 = y1.max(y as u32 + 1);
            too_big |= x1 - x0 > max_side || y1 - y0 > max_side;
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                        continue;
                    }
                    let j = ny as usize * w + nx as usize;
                    if !seen[j] && imp[j] >= MARK_IMPORTANCE {
                        seen[j] = true;
                        stack.push(j as u32);
                    }
                }
            }
        }
        // A region too big for a ring (an axis, a bar, a block of text) is the lattice's job.
        if !too_big {
            // Back to image pixels.
            let bbox = [
                x0 * s,
                y0 * s,
                (x1 * s).min(vsm.size().width),
                (y1 * s).min(vsm.size().height),
            ];
            blobs.push(mark_of(bbox, pixels * s * s));
        }
    }
    let merged = merge_overlapping(blobs);
    merged
        .into_iter()
        .filter(|m| {
            let (bw, bh) = (m.bbox[2] - m.bbox[0], m.bbox[3] - m.bbox[1]);
            m.pixels > 0 && bw.max(bh) >= MIN_SIDE_PX && bw.max(bh) <= MAX_SIDE_PX
        })
        .collect()
}

fn mark_of(bbox: [u32; 4], pixels: u32) -> Mark {
    let [x0, y0, x1, y1] = bbox;
    let center = DVec2::new((x0 + x1) as f64 / 2.0, (y0 + y1) as f64 / 2.0);
    let half_diag = 0.5 * (((x1 - x0) as f64).powi(2) + ((y1 - y0) as f64).powi(2)).sqrt();
    Mark {
        center,
        ring_radius: half_diag + RING_MARGIN_PX,
        bbox,
        pixels,
    }
}

/// Merges blobs whose rings overlap until none do; a merge that grows too big is marked with
/// `pixels == 0` and stays too big.
fn merge_overlapping(mut blobs: Vec<Mark>) -> Vec<Mark> {
    const CELL: f64 = 64.0;
    loop {
        let mut merged_any = false;
        // Spatial hash of blob indices by ring bounding box.
        let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> = Default::default();
        for (i, b) in blobs.iter().enumerate() {
            for (cx, cy) in cells(b, CELL) {
                grid.entry((cx, cy)).or_default().push(i);
            }
        }
        let mut parent: Vec<usize> = (0..blobs.len()).collect();
        fn find(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for list in grid.values() {
            for (k, &i) in list.iter().enumerate() {
                for &j in &list[k + 1..] {
                    let (a, b) = (&blobs[i], &blobs[j]);
                    // A group already too big for a ring (`pixels == 0`) takes no more: its
                    // grown ring would swallow every mark around it, one merge at a time.
                    if a.pixels > 0
                        && b.pixels > 0
                        && a.center.distance(b.center) < a.ring_radius + b.ring_radius
                    {
                        let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                        if ri != rj {
                            parent[ri.max(rj)] = ri.min(rj);
                            merged_any = true;
                        }
                    }
                }
            }
        }
        if !merged_any {
            return blobs;
        }
        let mut groups: Vec<Option<Mark>> = vec![None; blobs.len()];
        for (i, &b) in blobs.iter().enumerate() {
            let r = find(&mut parent, i);
            groups[r] = Some(match groups[r] {
                None => b,
                Some(g) => {
                    let bbox = [
                        g.bbox[0].min(b.bbox[0]),
                        g.bbox[1].min(b.bbox[1]),
                        g.bbox[2].max(b.bbox[2]),
                        g.bbox[3].max(b.bbox[3]),
                    ];
                    let pixels = if g.pixels == 0 || b.pixels == 0 {
                        0
                    } else {
                        g.pixels + b.pixels
                    };
                    let side = (bbox[2] - bbox[0]).max(bbox[3] - bbox[1]);
                    mark_of(bbox, if side > MAX_SIDE_PX { 0 } else { pixels })
                }
            });
        }
        blobs = groups.into_iter().flatten().collect();
    }
}

fn cells(b: &Mark, cell: f64) -> impl Iterator<Item = (i64, i64)> {
    let r = b.ring_radius;
    let (x0, x1) = (
        ((b.center.x - r) / cell).floor() as i64,
        ((b.center.x + r) / cell).floor() as i64,
    );
    let (y0, y1) = (
        ((b.center.y - r) / cell).floor() as i64,
        ((b.center.y + r) / cell).floor() as i64,
    );
    (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| (x, y)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Image, Size};
    use crate::saliency::VsmBuilder;

    fn dot(img: &mut Image, cx: f32, cy: f32, r: f32, c: [u8; 4]) {
        for y in 0..img.height() {
            for x in 0..img.width() {
                let (dx, dy) = (x as f32 + 0.5 - cx, y as f32 + 0.5 - cy);
                if dx * dx + dy * dy <= r * r {
                    img.set(x, y, c);
                }
            }
        }
    }

    #[test]
    fn a_lone_small_dot_is_a_mark() {
        let mut img = Image::filled(Size::new(300, 200).unwrap(), [255; 4]);
        dot(&mut img, 150.0, 100.0, 3.0, [44, 123, 182, 255]);
        let vsm = VsmBuilder::new().build(img.as_ref());
        let marks = find_marks(&vsm);
        assert_eq!(marks.len(), 1, "{marks:?}");
        assert!(marks[0].center.distance(DVec2::new(150.0, 100.0)) < 1.0);
        assert!(marks[0].ring_radius > 3.0 && marks[0].ring_radius < 8.0);
    }

    #[test]
    fn close_dots_merge_and_big_regions_are_not_marks() {
        let mut img = Image::filled(Size::new(300, 200).unwrap(), [255; 4]);
        dot(&mut img, 50.0, 50.0, 4.0, [215, 25, 28, 255]);
        dot(&mut img, 60.0, 50.0, 4.0, [215, 25, 28, 255]);
        for y in 100..190 {
            for x in 150..290 {
                img.set(x, y, [26, 150, 65, 255]);
            }
        }
        // Two dots whose merged box exceeds the size limit are no mark either.
        for i in 0..8 {
            dot(
                &mut img,
                20.0 + 9.0 * i as f32,
                150.0,
                4.0,
                [215, 25, 28, 255],
            );
        }
        let vsm = VsmBuilder::new().build(img.as_ref());
        let marks = find_marks(&vsm);
        assert_eq!(marks.len(), 1, "{marks:?}");
        assert!(marks[0].center.distance(DVec2::new(55.0, 50.0)) < 1.0);
    }
}
