//! Numerical robustness of the whole single-frame path (issue 8, item 6): degenerate content
//! (uniform colour, one-pixel-wide canvases, pure noise) and degenerate targets (1×1,
//! 16384×16, 16×16384, one pixel wide) must give a finite warp with no inverted triangle, an
//! output of exactly the target size, and pixels that come from the source — never a NaN
//! turned into a colour, never a panic.
//!
//! A NaN in a vertex position or a sampling weight shows in the pixels as a colour the source
//! does not have (a float-to-int cast of NaN gives 0), so every check here compares output
//! colours against the source's: a uniform source must come out exactly uniform, a noise
//! source drawn from a middle band of values must stay inside that band.

use proptest::prelude::*;
use vizretarget::Boundary;
use vizretarget::{retarget, Image, Options, Retargeted, Size};

/// A tiny deterministic RNG (xorshift64*), so a failing case is reproducible from its seed.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
}

/// Noise with every channel in `lo..=hi` (alpha opaque).
fn noise(size: Size, seed: u64, lo: u8, hi: u8) -> Image {
    let mut rng = XorShift(seed | 1);
    let mut img = Image::new(size);
    let span = (hi - lo) as u64 + 1;
    for p in img.pixels_mut() {
        let r = rng.next();
        *p = [
            lo + (r % span) as u8,
            lo + ((r >> 16) % span) as u8,
            lo + ((r >> 32) % span) as u8,
            255,
        ];
    }
    img
}

fn twice_signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Retargets with the analysis kept and checks the warp: every position finite and inside the
/// target, boundary vertices on their side, no triangle with non-positive signed area
/// (recomputed here in `f64`), output exactly the target size.
fn retarget_checked(img: &Image, target: Size) -> Result<Retargeted, String> {
    let options = Options::default().with_analysis(true);
    let out = retarget(img, target, &options)
        .map_err(|e| format!("{} -> {target}: retarget failed: {e}", img.size()))?;
    let at = |what: String| format!("{} -> {target}: {what}", img.size());
    if out.image.size() != target {
        return Err(at(format!("output is {}", out.image.size())));
    }
    let analysis = out.analysis.as_ref().ok_or("no analysis kept")?;
    let (mesh, warp) = (&analysis.mesh, &analysis.warp);
    let q = warp.positions();
    let (tw, th) = (target.width as f64, target.height as f64);
    for (i, (d, b)) in q.iter().zip(mesh.boundary()).enumerate() {
        if !d.x.is_finite() || !d.y.is_finite() {
            return Err(at(format!("vertex {i} has position {d}")));
        }
        let on_side = match b {
            Boundary::Left => d.x == 0.0,
            Boundary::Right => d.x == tw,
            Boundary::Top => d.y == 0.0,
            Boundary::Bottom => d.y == th,
            Boundary::Corner => (d.x == 0.0 || d.x == tw) && (d.y == 0.0 || d.y == th),
            Boundary::Interior => true,
        };
        let inside = (0.0..=tw).contains(&d.x) && (0.0..=th).contains(&d.y);
        if !on_side || !inside {
            return Err(at(format!("vertex {i} ({b:?}) at {d}")));
        }
    }
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = tri.map(|v| [q[v as usize].x, q[v as usize].y]);
        let a2 = twice_signed_area(a, b, c);
        if a2.is_nan() || a2 <= 0.0 {
            return Err(at(format!("triangle {t} has signed area {}", a2 / 2.0)));
        }
    }
    Ok(out)
}

/// Every output pixel equals `rgba`.
fn all_equal(out: &Image, rgba: [u8; 4]) -> Result<(), String> {
    match out.pixels().iter().position(|&p| p != rgba) {
        None => Ok(()),
        Some(i) => Err(format!(
            "pixel {i} of {} is {:?}, the uniform source is {rgba:?}",
            out.size(),
            out.pixels()[i]
        )),
    }
}

/// Every output channel within `lo..=hi` (with the linear filter's overshoot) and opaque.
fn within(out: &Image, lo: u8, hi: u8) -> Result<(), String> {
    // Catmull-Rom (the linear resize's filter) overshoots by at most its negative lobes'
    // weight, an eighth of the step along each axis, and the two axes compound (1.125² - 1):
    // under three tenths in all, a step of rounding on top.
    let over = ((hi - lo) as u32 * 3 / 10 + 1) as u8;
    let bad = |p: &[u8; 4]| {
        p[..3]
            .iter()
            .any(|&c| c < lo.saturating_sub(over) || c > hi.saturating_add(over))
            || p[3] != 255
    };
    match out.pixels().iter().position(bad) {
        None => Ok(()),
        Some(i) => Err(format!(
            "pixel {i} of {} is {:?}, the source's channels lie in {lo}..={hi}",
            out.size(),
            out.pixels()[i]
        )),
    }
}

/// Degenerate targets every case is tried at, beside its random one.
fn fixed_targets(src: Size) -> Vec<Size> {
    [
        (1, 1),
        (16384, 16),
        (16, 16384),
        (1, src.height),
        (src.width, 1),
    ]
    .into_iter()
    .map(|(w, h)| Size::new(w, h).unwrap())
    .collect()
}

fn side() -> impl Strategy<Value = u32> {
    prop_oneof![Just(1u32), Just(2), 3u32..=24, 25u32..=240]
}

fn target_side() -> impl Strategy<Value = u32> {
    prop_oneof![Just(1u32), 1u32..=8, 9u32..=600]
}

fn cases(default: u32) -> ProptestConfig {
    ProptestConfig {
        cases: default,
        max_shrink_time: 60_000,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("proptest-regressions"),
        )),
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(cases(48))]

    /// A uniform image (any colour, any alpha, any size down to 1×1) comes out exactly that
    /// colour at every target: nothing salient, nothing to invent.
    #[test]
    fn uniform_images_stay_uniform(
        w in side(), h in side(), rgba in prop::array::uniform4(any::<u8>()),
        tw in target_side(), th in target_side(),
    ) {
        let src = Size::new(w, h).unwrap();
        let img = Image::filled(src, rgba);
        let mut targets = fixed_targets(src);
        targets.push(Size::new(tw, th).unwrap());
        for target in targets {
            let out = retarget_checked(&img, target).map_err(TestCaseError::fail)?;
            all_equal(&out.image, rgba)
                .map_err(|e| TestCaseError::fail(format!("{src} -> {target}: {e}")))?;
        }
    }

    /// Pure noise (every pixel salient and different) from a middle band of values: the warp
    /// is valid and every output pixel is a blend of source pixels, so it stays in the band.
    #[test]
    fn noise_images_give_valid_warps_and_source_colours(
        w in side(), h in side(), seed in any::<u64>(),
        tw in target_side(), th in target_side(),
    ) {
        let (lo, hi) = (60, 190);
        let src = Size::new(w, h).unwrap();
        let img = noise(src, seed, lo, hi);
        let mut targets = fixed_targets(src);
        targets.push(Size::new(tw, th).unwrap());
        for target in targets {
            let out = retarget_checked(&img, target).map_err(TestCaseError::fail)?;
            within(&out.image, lo, hi)
                .map_err(|e| TestCaseError::fail(format!("{src} -> {target}: {e}")))?;
        }
    }

    /// One-pixel-wide and one-pixel-tall canvases with a few dark marks on white, to any
    /// target: valid warps, colours from the source's range.
    #[test]
    fn one_pixel_wide_images(
        long in 1u32..=500, vertical in any::<bool>(), seed in any::<u64>(),
        tw in target_side(), th in target_side(),
    ) {
        let src = if vertical { Size::new(1, long) } else { Size::new(long, 1) }.unwrap();
        let mut img = Image::filled(src, [250, 250, 250, 255]);
        let mut rng = XorShift(seed | 1);
        for p in img.pixels_mut() {
            if rng.next().is_multiple_of(7) {
                *p = [20, 40, 160, 255];
            }
        }
        let mut targets = fixed_targets(src);
        targets.push(Size::new(tw, th).unwrap());
        for target in targets {
            let out = retarget_checked(&img, target).map_err(TestCaseError::fail)?;
            within(&out.image, 20, 250)
                .map_err(|e| TestCaseError::fail(format!("{src} -> {target}: {e}")))?;
        }
    }
}

/// A larger noise image, where every lattice level is full and the solver has its most
/// unknowns, to the widest and tallest targets the library accepts.
#[test]
fn large_noise_to_extreme_strips() {
    let img = noise(Size::new(400, 300).unwrap(), 0x5eed, 60, 190);
    for (w, h) in [(16384, 16), (16, 16384), (1, 1), (4000, 3)] {
        let target = Size::new(w, h).unwrap();
        let out = retarget_checked(&img, target).unwrap_or_else(|e| panic!("{e}"));
        within(&out.image, 60, 190).unwrap_or_else(|e| panic!("{target}: {e}"));
    }
}

/// The stream core, whose reuse paths (region updates of the VSM, warm-started solves, kept
/// meshes) differ from a one-shot frame: degenerate frames in a row, uniform ↔ noise ↔ a
/// one-pixel line, at degenerate targets, each frame exactly what its content allows.
#[test]
fn degenerate_frames_in_a_stream() {
    use vizretarget::{Frame, Retargeter};
    let size = Size::new(96, 64).unwrap();
    let uniform = Image::filled(size, [200, 120, 40, 255]);
    let busy = noise(size, 77, 60, 190);
    let mut lined = uniform.clone();
    for x in 0..96 {
        lined.set(x, 30, [60, 60, 60, 255]);
    }
    let frames = [
        &uniform, &uniform, &busy, &busy, &uniform, &lined, &lined, &busy,
    ];
    for (w, h) in [(1, 1), (16384, 16), (16, 16384), (1, 64), (300, 1)] {
        let target = Size::new(w, h).unwrap();
        let mut r = Retargeter::new(target, Options::default()).unwrap();
        for (i, img) in frames.iter().enumerate() {
            r.send_frame(Frame::new((*img).clone(), i as u64)).unwrap();
            let out = r.receive_frame().expect("one frame out per frame in");
            assert_eq!(out.image.size(), target);
            let check = if std::ptr::eq(*img, &uniform) {
                all_equal(&out.image, [200, 120, 40, 255])
            } else if std::ptr::eq(*img, &busy) {
                within(&out.image, 60, 190)
            } else {
                within(&out.image, 40, 200)
            };
            check.unwrap_or_else(|e| panic!("frame {i} -> {target}: {e}"));
        }
    }
}
