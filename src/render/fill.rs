//! Filling masked pixels from their surroundings, for pixels whose content is drawn elsewhere
//! (vector marks drawn crisp over the result, raster marks floating over a kept warp).

use crate::image::Image;

/// Fills every pixel listed in `todo` (and set in `masked`, one flag per pixel of `image`) from
/// the colours around it: onion-peel, from the outside in, each pixel the mean of its
/// 8-neighbours already known. A mark on a flat background leaves exactly that background.
/// `masked` comes back with the filled pixels cleared.
pub(crate) fn fill_from_surroundings(image: &mut Image, masked: &mut [bool], mut todo: Vec<u32>) {
    let (w, h) = (image.width() as usize, image.height() as usize);
    let mut fill: Vec<(u32, [u8; 4])> = Vec::new();
    while !todo.is_empty() {
        fill.clear();
        let px = image.pixels();
        for &i in &todo {
            let (x, y) = (i as usize % w, i as usize / w);
            let mut sum = [0u32; 4];
            let mut n = 0u32;
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                        continue;
                    }
                    let j = ny as usize * w + nx as usize;
                    if !masked[j] {
                        for (s, &c) in sum.iter_mut().zip(&px[j]) {
                            *s += c as u32;
                        }
                        n += 1;
                    }
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
        todo.retain(|&i| masked[i as usize]);
    }
}
