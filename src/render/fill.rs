//! Filling masked pixels from their surroundings, for pixels whose content is drawn elsewhere
//! (vector marks drawn crisp over the result, raster marks floating over a kept warp).

use crate::image::Image;

/// Fills every pixel listed in `todo` (exactly the pixels set in `masked`, one flag per
/// pixel of `image`) from the colours around it: onion-peel, from the outside in, each pixel
/// the mean of its 8-neighbours already known. A mark on a flat background leaves exactly that
/// background. `masked` comes back with the filled pixels cleared.
///
/// Each peel after the first looks only at the masked neighbours of the pixels the last one
/// filled: no other pixel gained a known neighbour. (Looking at all that were left made a
/// disc of radius r cost r times its area.)
pub(crate) fn fill_from_surroundings(image: &mut Image, masked: &mut [bool], mut todo: Vec<u32>) {
    let (w, h) = (image.width() as usize, image.height() as usize);
    // The 8-neighbours of pixel `i` inside the image, into `out`; how many. Inside the
    // frame, by fixed offsets.
    let around = move |i: u32, out: &mut [usize; 8]| -> usize {
        let i = i as usize;
        let (x, y) = (i % w, i / w);
        if x > 0 && y > 0 && x + 1 < w && y + 1 < h {
            *out = [
                i - w - 1,
                i - w,
                i - w + 1,
                i - 1,
                i + 1,
                i + w - 1,
                i + w,
                i + w + 1,
            ];
            return 8;
        }
        let mut n = 0;
        for ny in y.saturating_sub(1)..(y + 2).min(h) {
            for nx in x.saturating_sub(1)..(x + 2).min(w) {
                if (nx, ny) != (x, y) {
                    out[n] = ny * w + nx;
                    n += 1;
                }
            }
        }
        n
    };
    let mut near = [0usize; 8];
    let mut fill: Vec<(u32, [u8; 4])> = Vec::new();
    while !todo.is_empty() {
        fill.clear();
        let px = image.pixels();
        for &i in &todo {
            let mut sum = [0u32; 4];
            let mut n = 0u32;
            let k = around(i, &mut near);
            for &j in &near[..k] {
                if !masked[j] {
                    for (s, &c) in sum.iter_mut().zip(&px[j]) {
                        *s += c as u32;
                    }
                    n += 1;
                }
            }
            if n > 0 {
                fill.push((i, sum.map(|s| ((s + n / 2) / n) as u8)));
            }
        }
        if fill.is_empty() {
            break; // nothing known around what is left (the mask covers the whole frame)
        }
        let px = image.pixels_mut();
        for &(i, c) in &fill {
            px[i as usize] = c;
            masked[i as usize] = false;
        }
        todo.clear();
        for &(i, _) in &fill {
            let k = around(i, &mut near);
            todo.extend(near[..k].iter().filter(|&&j| masked[j]).map(|&j| j as u32));
        }
        todo.sort_unstable();
        todo.dedup();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Size;

    /// The onion peel as its definition reads: every round, every pixel left.
    fn peel_every_pixel(image: &mut Image, masked: &mut [bool]) {
        let (w, h) = (image.width() as i64, image.height() as i64);
        loop {
            let px = image.pixels().to_vec();
            let mut fill = Vec::new();
            for i in (0..masked.len()).filter(|&i| masked[i]) {
                let (x, y) = (i as i64 % w, i as i64 / w);
                let (mut sum, mut n) = ([0u32; 4], 0u32);
                for (dx, dy) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))) {
                    let (nx, ny) = (x + dx, y + dy);
                    let j = (ny * w + nx) as usize;
                    if (dx, dy) != (0, 0)
                        && (0..w).contains(&nx)
                        && (0..h).contains(&ny)
                        && !masked[j]
                    {
                        (0..4).for_each(|c| sum[c] += px[j][c] as u32);
                        n += 1;
                    }
                }
                if n > 0 {
                    fill.push((i, sum.map(|s| ((s + n / 2) / n) as u8)));
                }
            }
            if fill.is_empty() {
                return;
            }
            for (i, c) in fill {
                image.pixels_mut()[i] = c;
                masked[i] = false;
            }
        }
    }

    /// Blobs of every shape, at the edges too, on noise: the same pixels as every pixel
    /// peeled every round; a mask over the whole picture leaves it as it was.
    #[test]
    fn peeling_the_frontier_is_peeling_every_pixel() {
        let size = Size::new(61, 37).unwrap();
        for seed in 1..6u32 {
            let img = Image::from_pixels(size, crate::image::noise_pixels(61 * 37, seed)).unwrap();
            let noise = crate::image::noise_pixels(61 * 37, seed + 100);
            let mut masked: Vec<bool> = (0..61 * 37)
                .map(|i| {
                    let (x, y) = ((i % 61) as f64, (i / 61) as f64);
                    let disc = (x - 20.0).powi(2) + (y - 15.0).powi(2) < 90.0;
                    let corner = x + y < 6.0;
                    disc || corner || noise[i][0] < 40
                })
                .collect();
            let todo: Vec<u32> = (0..masked.len() as u32)
                .filter(|&i| masked[i as usize])
                .collect();
            let (mut want, mut want_mask) = (img.clone(), masked.clone());
            peel_every_pixel(&mut want, &mut want_mask);
            let mut got = img.clone();
            fill_from_surroundings(&mut got, &mut masked, todo);
            assert!(got == want, "seed {seed}");
            assert!(masked.iter().all(|&m| !m));
        }
        let img = Image::from_pixels(size, crate::image::noise_pixels(61 * 37, 9)).unwrap();
        let (mut got, mut all) = (img.clone(), vec![true; 61 * 37]);
        fill_from_surroundings(&mut got, &mut all, (0..61 * 37).collect());
        assert!(got == img && all.iter().all(|&m| m));
    }
}
