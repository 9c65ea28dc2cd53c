//! The comparison sheet (the paper's Figs. 10 and 14): the original and every method's output
//! side by side on a neutral background, each labelled with the method and its size (and,
//! if asked, two measures from [`crate::metrics`]), optionally with the mesh drawn over mesh
//! and grid.
//!
//! Panels keep their true relative sizes: one display scale for the whole sheet, 1 unless a
//! panel would be wider than [`SheetOptions::max_width`] or taller than
//! [`SheetOptions::max_height`]. Panels fill rows left to right up to `max_width`.
//!
//! Labels are set in DejaVu Sans (a subset bundled in `assets/fonts/`, Bitstream Vera licence)
//! and rasterized by `ab_glyph`.

use crate::baseline::{retarget_with, Mapping, Method, MethodOutput};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::metrics::MetricsTable;
use crate::retarget::Options;
use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};

/// The bundled label font (see `assets/fonts/README.md`).
const FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans-subset.ttf");

/// How the sheet is laid out.
#[derive(Clone, Debug)]
pub struct SheetOptions {
    /// Draw the deformed mesh over mesh and grid outputs, and the mesh method's source mesh
    /// over the original.
    pub mesh_overlay: bool,
    /// Add a line with saliency mean and distortion under each label.
    pub metrics: bool,
    /// Widest sheet before panels wrap to a new row (and widest panel before the sheet is
    /// scaled down), in px.
    pub max_width: u32,
    /// Tallest panel before the sheet is scaled down, in px.
    pub max_height: u32,
    /// Label size in px.
    pub font_px: f32,
    pub background: [u8; 4],
}

impl Default for SheetOptions {
    fn default() -> Self {
        SheetOptions {
            mesh_overlay: false,
            metrics: false,
            max_width: 3200,
            max_height: 1600,
            font_px: 18.0,
            background: [236, 236, 236, 255],
        }
    }
}

/// Every method's output on one image, and their measures.
#[derive(Clone, Debug)]
pub struct Comparison {
    pub outputs: Vec<MethodOutput>,
    pub metrics: MetricsTable,
}

/// Runs every method of [`Method::ALL`] on `image` and measures them.
pub fn compare(image: &Image, target: Size, options: &Options) -> Result<Comparison, Error> {
    compare_methods(image, target, options, &Method::ALL)
}

/// Runs `methods` on `image` and measures them.
pub fn compare_methods(
    image: &Image,
    target: Size,
    options: &Options,
    methods: &[Method],
) -> Result<Comparison, Error> {
    let outputs = methods
        .iter()
        .map(|&m| retarget_with(m, image, target, options))
        .collect::<Result<Vec<_>, Error>>()?;
    let metrics = MetricsTable::measure(image, &outputs);
    Ok(Comparison { outputs, metrics })
}

impl Comparison {
    /// The sheet: `original` first, then every output.
    pub fn sheet(&self, original: &Image, options: &SheetOptions) -> Image {
        sheet(original, &self.outputs, Some(&self.metrics), options)
    }
}

/// One labelled panel.
struct Panel {
    image: Image,
    lines: Vec<String>,
}

const MARGIN: u32 = 16;
const GAP: u32 = 16;
const LABEL_GAP: u32 = 6;
const FRAME: [u8; 4] = [170, 170, 170, 255];
const INK: [u8; 3] = [30, 30, 30];

/// Lays out `original` and `outputs` with their labels (metrics lines only when `metrics` is
/// given and [`SheetOptions::metrics`] is set).
pub fn sheet(
    original: &Image,
    outputs: &[MethodOutput],
    metrics: Option<&MetricsTable>,
    options: &SheetOptions,
) -> Image {
    let mut panels = Vec::with_capacity(outputs.len() + 1);
    let mut original_image = original.clone();
    if options.mesh_overlay {
        if let Some(Mapping::Warp { mesh, .. }) = outputs
            .iter()
            .find(|o| o.method == Method::Mesh)
            .map(|o| &o.mapping)
        {
            original_image =
                crate::debug::mesh_overlay(original, mesh.vertices(), mesh.triangles());
        }
    }
    let mut first = vec![format!("original {}", size_label(original.size()))];
    if options.metrics {
        if let Some(t) = metrics {
            first.push(format!("sal.mean {:.3}", t.source_saliency_mean));
        }
    }
    panels.push(Panel {
        image: original_image,
        lines: first,
    });
    for o in outputs {
        let image = match (&o.mapping, options.mesh_overlay) {
            (Mapping::Warp { mesh, warp }, true) => {
                crate::debug::mesh_overlay(&o.image, warp.positions(), mesh.triangles())
            }
            _ => o.image.clone(),
        };
        let name = match o.method {
            Method::Mesh => "mesh (vizretarget)".to_string(),
            m => m.name().to_string(),
        };
        let mut lines = vec![format!("{name} {}", size_label(o.image.size()))];
        if options.metrics {
            if let Some(r) = metrics.and_then(|t| t.row(o.method)) {
                let d = r.distortion.map_or("-".into(), |d| format!("{d:.2}"));
                lines.push(format!("sal.mean {:.3} · dist {d}", r.saliency_mean));
            }
        }
        panels.push(Panel { image, lines });
    }
    layout(panels, options)
}

fn size_label(s: Size) -> String {
    format!("{}×{}", s.width, s.height)
}

/// Scales the panels to fit the sheet's bounds, sets them in rows and draws them with their
/// labels.
fn layout(panels: Vec<Panel>, options: &SheetOptions) -> Image {
    let labels = Labels::new(options.font_px);
    let max_width = options.max_width.max(64);
    let scale = display_scale(&panels, max_width, options.max_height);
    let panels = at_scale(panels, scale);
    // A panel's box is its image plus a 1-px frame, with the label above.
    let widths: Vec<u32> = panels.iter().map(|p| p.image.width() + 2).collect();
    let rows = even_rows(&widths, max_width);
    draw_sheet(&panels, &rows, &labels, options.background)
}

/// The label font at the sheet's size. Without a font there are no labels, and no room is
/// kept for them.
struct Labels {
    font: Option<FontRef<'static>>,
    px: f32,
    line_h: u32,
}

impl Labels {
    fn new(font_px: f32) -> Labels {
        let font = FontRef::try_from_slice(FONT).ok();
        let px = font_px.clamp(6.0, 200.0);
        let line_h = font
            .as_ref()
            .map_or(0, |f| f.as_scaled(PxScale::from(px)).height().ceil() as u32);
        Labels { font, px, line_h }
    }

    /// The height of `p`'s label, with the gap under it.
    fn height(&self, p: &Panel) -> u32 {
        p.lines.len() as u32 * self.line_h + LABEL_GAP
    }

    /// Draws `p`'s label with its top-left at `(x, y)`, clipped to the panel's box so that a
    /// long label does not run into the next panel.
    fn draw(&self, sheet: &mut Image, p: &Panel, x: u32, y: u32) {
        let Some(f) = &self.font else {
            return;
        };
        let x_end = x + p.image.width() + 2;
        for (k, line) in p.lines.iter().enumerate() {
            let top = (y + k as u32 * self.line_h) as f32;
            draw_text(sheet, f, self.px, x as f32, top, x_end, line);
        }
    }
}

/// One display scale for every panel, so that they keep their true relative sizes: 1 unless
/// the widest would not fit `max_width` or the tallest `max_height`.
fn display_scale(panels: &[Panel], max_width: u32, max_height: u32) -> f64 {
    let widest = panels.iter().map(|p| p.image.width()).max().unwrap_or(1);
    let tallest = panels.iter().map(|p| p.image.height()).max().unwrap_or(1);
    (1.0f64)
        .min((max_width - 2 * MARGIN - 2) as f64 / widest as f64)
        .min(max_height.max(16) as f64 / tallest as f64)
}

/// The panels at display `scale` (below 1 only: panels are never enlarged).
fn at_scale(panels: Vec<Panel>, scale: f64) -> Vec<Panel> {
    if scale >= 1.0 {
        return panels;
    }
    panels
        .into_iter()
        .map(|p| {
            let s = p.image.size();
            let size = Size {
                width: ((s.width as f64 * scale).round() as u32).max(1),
                height: ((s.height as f64 * scale).round() as u32).max(1),
            };
            Panel {
                image: crate::baseline::resize_linear(p.image.as_ref(), size),
                lines: p.lines,
            }
        })
        .collect()
}

/// Panels (by index) in rows of at most `limit` px, filled greedily left to right.
fn greedy_rows(widths: &[u32], limit: u32) -> Vec<Vec<usize>> {
    let mut rows: Vec<Vec<usize>> = vec![Vec::new()];
    let mut x = MARGIN;
    for (i, &w) in widths.iter().enumerate() {
        let row = rows.last_mut().expect("one row");
        if !row.is_empty() && x + w + MARGIN > limit {
            rows.push(vec![i]);
            x = MARGIN + w + GAP;
        } else {
            row.push(i);
            x += w + GAP;
        }
    }
    rows
}

/// As many rows as `max_width` needs, then as even as they go: the narrowest limit that still
/// fits in that many rows (so six panels make rows of three and three, not five and one).
fn even_rows(widths: &[u32], max_width: u32) -> Vec<Vec<usize>> {
    let mut rows = greedy_rows(widths, max_width);
    let total: u32 = widths.iter().sum::<u32>() + GAP * widths.len() as u32 + 2 * MARGIN;
    let mut limit = (total / rows.len() as u32).min(max_width);
    while limit < max_width {
        let r = greedy_rows(widths, limit);
        if r.len() <= rows.len() {
            rows = r;
            break;
        }
        limit += 16;
    }
    rows
}

/// The width of row `r`: its panels' boxes and the gaps between them.
fn row_width(panels: &[Panel], r: &[usize]) -> u32 {
    r.iter().map(|&i| panels[i].image.width() + 2).sum::<u32>()
        + GAP * (r.len() as u32).saturating_sub(1)
}

/// The height of row `r`: its tallest panel, label and frame included.
fn row_height(panels: &[Panel], r: &[usize], labels: &Labels) -> u32 {
    r.iter()
        .map(|&i| labels.height(&panels[i]) + panels[i].image.height() + 2)
        .max()
        .unwrap_or(0)
}

/// The sheet: `rows` of framed panels under their labels, within a margin.
fn draw_sheet(
    panels: &[Panel],
    rows: &[Vec<usize>],
    labels: &Labels,
    background: [u8; 4],
) -> Image {
    let width = rows.iter().map(|r| row_width(panels, r)).max().unwrap_or(0) + 2 * MARGIN;
    let height = rows
        .iter()
        .map(|r| row_height(panels, r, labels))
        .sum::<u32>()
        + GAP * (rows.len() as u32).saturating_sub(1)
        + 2 * MARGIN;
    let size = Size {
        width: width.max(1),
        height: height.max(1),
    };
    let mut sheet = Image::filled(size, background);
    let mut y = MARGIN;
    for r in rows {
        let mut x = MARGIN;
        for &i in r {
            let p = &panels[i];
            let (pw, ph) = (p.image.width(), p.image.height());
            labels.draw(&mut sheet, p, x, y);
            let top = y + labels.height(p);
            frame(&mut sheet, x, top, pw + 2, ph + 2);
            blit(&mut sheet, &p.image, x + 1, top + 1, background);
            x += pw + 2 + GAP;
        }
        y += row_height(panels, r, labels) + GAP;
    }
    sheet
}

/// A 1-px frame around the box `[x, x + w) × [y, y + h)`.
fn frame(img: &mut Image, x: u32, y: u32, w: u32, h: u32) {
    for i in x..x + w {
        img.set(i, y, FRAME);
        img.set(i, y + h - 1, FRAME);
    }
    for j in y..y + h {
        img.set(x, j, FRAME);
        img.set(x + w - 1, j, FRAME);
    }
}

/// Copies `src` to `(x, y)`, compositing transparent pixels over `bg`.
fn blit(dst: &mut Image, src: &Image, x: u32, y: u32, bg: [u8; 4]) {
    for sy in 0..src.height() {
        let row = &mut dst.row_mut(y + sy)[x as usize..(x + src.width()) as usize];
        for (d, &s) in row.iter_mut().zip(src.row(sy)) {
            let a = s[3] as u32;
            *d = if a == 255 {
                s
            } else {
                let mix = |c: u8, b: u8| ((c as u32 * a + b as u32 * (255 - a) + 127) / 255) as u8;
                [mix(s[0], bg[0]), mix(s[1], bg[1]), mix(s[2], bg[2]), 255]
            };
        }
    }
}

/// Draws `text` with its top at `y`, starting at `x`, clipped at `x_end`; anti-aliased.
fn draw_text(img: &mut Image, font: &FontRef<'_>, px: f32, x: f32, y: f32, x_end: u32, text: &str) {
    let scale = PxScale::from(px);
    let sf = font.as_scaled(scale);
    let baseline = y + sf.ascent();
    let mut caret = x;
    let mut prev = None;
    let (w, h) = (img.width().min(x_end) as i64, img.height() as i64);
    for c in text.chars() {
        let id = sf.glyph_id(c);
        if let Some(p) = prev {
            caret += sf.kern(p, id);
        }
        prev = Some(id);
        let glyph = id.with_scale_and_position(scale, point(caret, baseline));
        caret += sf.h_advance(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let b = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let (px, py) = (b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64);
            if px < 0 || py < 0 || px >= w || py >= h {
                return;
            }
            let a = coverage.clamp(0.0, 1.0);
            let d = img.get(px as u32, py as u32);
            let mix = |c: u8, ink: u8| (c as f32 * (1.0 - a) + ink as f32 * a + 0.5) as u8;
            img.set(
                px as u32,
                py as u32,
                [
                    mix(d[0], INK[0]),
                    mix(d[1], INK[1]),
                    mix(d[2], INK[2]),
                    d[3],
                ],
            );
        });
    }
}

/// Draws `text` in dark ink with the bundled font, its top-left at `(x, y)`, `px` high
/// (tests and examples use it to make visualizations with real text).
pub fn draw_label(img: &mut Image, x: f32, y: f32, px: f32, text: &str) {
    if let Ok(font) = FontRef::try_from_slice(FONT) {
        let x_end = img.width();
        draw_text(img, &font, px, x, y, x_end, text);
    }
}

/// Width of `text` in px at `px` with the bundled font (0 if it cannot be read).
pub fn text_width(text: &str, px: f32) -> f32 {
    let Ok(font) = FontRef::try_from_slice(FONT) else {
        return 0.0;
    };
    let sf = font.as_scaled(PxScale::from(px));
    let mut prev = None;
    let mut w = 0.0;
    for c in text.chars() {
        let id = sf.glyph_id(c);
        if let Some(p) = prev {
            w += sf.kern(p, id);
        }
        w += sf.h_advance(id);
        prev = Some(id);
    }
    w
}
