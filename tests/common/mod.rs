//! Helpers the watcher tests share.

/// A small chart as PNG bytes: its dot position and band colour depend on `i`.
pub fn snapshot(i: usize) -> Vec<u8> {
    let img = image::RgbImage::from_fn(96, 64, |x, y| {
        let (dx, dy) = (x as i32 - 20 - (i % 50) as i32, y as i32 - 36);
        if y < 8 {
            image::Rgb([(i * 37 % 256) as u8, (i * 91 % 256) as u8, 120])
        } else if dx * dx + dy * dy <= 36 {
            image::Rgb([214, 39, 40])
        } else if x == 4 || y == 60 {
            image::Rgb([90, 90, 90])
        } else {
            image::Rgb([255, 255, 255])
        }
    });
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}
