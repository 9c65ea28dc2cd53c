//! Vector marks bound to the mesh (§5.3, "Vector adjustment").
//!
//! A visualization often exists as vectors as well as pixels: the dots of a scatterplot, the
//! nodes and edges of a graph. Given as a [`VectorLayer`] beside a frame, such marks are
//!
//! 1. **bound** to the mesh: the saliency map is computed on the whole visualization (the
//!    raster with the marks drawn in, as the paper does: a background alone would have its
//!    faint content normalized up to full saliency, and the map would fight the marks for
//!    room), and raised to 1 inside every point mark's and polyline's footprint; each point
//!    mark's centre becomes a mesh vertex, and a mark that stands alone gets a ring of key
//!    points just outside it (when the mesh is built), so that it
//!    sits in a fan of triangles of its own and keeps its shape and size, however many marks
//!    there are (the small marks the mesh finds in the raster share a ring budget: beyond it,
//!    a mark lies across large background triangles and does not grow with enhancement);
//! 2. **carried**: after the solve, a mark's new centre is where the deformed mesh takes it (the
//!    barycentric coordinates of the centre in its source triangle, applied to the same
//!    triangle's deformed vertices; a centre that is a vertex goes exactly where the vertex
//!    goes). Polylines and edges map each of their points the same way;
//! 3. **drawn** crisp and undistorted over the warped raster: a round mark stays round,
//!    antialiased. This is the paper's "hybrid": the raster keeps the context (a map, axes),
//!    the marks are redrawn on top.
//!
//! The layer as placed on the output is returned with each frame
//! ([`crate::Retargeted::marks`]), in the same order, so callers can hit-test or label it.
//!
//! # Size of a point mark
//! [`MarkSize::Mesh`] (the default): the radius is multiplied by the local scale of the warp
//! over the mark's disc, `√|det A|` of the affine map that best fits (least squares) where the
//! mesh carries 8 points on the disc's rim, clamped to `[0.1, 10]`. It is the scale the mesh
//! gives the mark's area, so the drawn mark keeps the size the raster around it gets: content
//! enhancement (§5.4) enlarges marks with their region; shrinking a crowded map shrinks them
//! with it, and they do not run into each other. [`MarkSize::Keep`] draws every radius as
//! given. Line widths (polylines, edges, a point's stroke) are kept in either case: they are
//! a weight, not a size.
//!
//! # Drawing
//! Straight (non-premultiplied) sRGB "over" blending, as browsers and SVG renderers do by
//! default, so colours match the tool that drew the visualization. Coverage is analytic: a
//! disc's pixel covers `clamp(r + ½ − d, 0, 1)` with `d` the distance of the pixel centre from
//! the mark's centre, a line's `clamp(w/2 + ½ − d, 0, 1)` with `d` the distance to the
//! polyline (round joins and caps; one coverage per polyline, so joints are not blended
//! twice). Order: polylines, then edges, then points (nodes cover the ends of their edges); a
//! point's stroke is centred on its rim, over its fill.
//!
//! # Marks already in the raster
//! By default the raster is used as it is ([`VectorOptions::paint_out`] off): right for a
//! background drawn without its marks (a map, axes) plus a layer of marks. When the same marks
//! are also in the raster, they would be drawn twice (a warped copy under a crisp one);
//! `paint_out` first fills each mark's source footprint (its disc or line band plus 1.5 px)
//! from the colours around it (onion-peel filling from the outside in, each pixel the mean of
//! its already known 8-neighbours: a flat background stays exactly flat).
//!
//! # The JSON format
//! One layer is one JSON object; every key is optional and unknown keys are an error (a typo
//! should not silently drop a mark). Coordinates are source-image pixels, `x` to the right and
//! `y` down, `(0, 0)` the top-left corner of the top-left pixel.
//!
//! ```json
//! {
//!   "points": [
//!     {"id": "paris", "x": 412.5, "y": 160, "r": 6, "fill": "#d7191c",
//!      "stroke": "#ffffff", "stroke_width": 1.5},
//!     {"x": 300, "y": 200, "r": 4, "fill": [44, 123, 182, 200]}
//!   ],
//!   "polylines": [
//!     {"points": [[10, 300], [120, 250], [240, 280]], "width": 2, "color": "#333333"}
//!   ],
//!   "edges": [
//!     {"from": "paris", "to": 1, "width": 1.5, "color": "#55555580"}
//!   ]
//! }
//! ```
//!
//! * `points`: `x`, `y` (required), `r` (or `radius`, required, ≥ 0), `fill` (default black),
//!   `stroke` (optional colour) and `stroke_width` (default 1 px), `id` (optional, unique).
//! * `polylines`: `points` (at least one `[x, y]`), `width` (default 1 px), `color` (or
//!   `colour`, default black).
//! * `edges`: `from` and `to` name two points, by `id` (a string) or by index in `points` (a
//!   number from 0); `width`, `color` as for polylines. An edge runs from centre to centre of
//!   its points wherever they are carried, so it follows its nodes.
//! * Colours: `"#rgb"`, `"#rrggbb"`, `"#rrggbbaa"`, or `[r, g, b]` / `[r, g, b, a]` with
//!   components 0 to 255.
//!
//! For a stream, either one file of **JSON Lines** (`.jsonl` or `.ndjson`: each non-blank
//! line is the layer of the next frame, in order; blank lines are skipped, `{}` is a frame
//! without marks; a stream with more frames than lines is an error naming the file, lines
//! beyond the last frame are ignored), or one **sidecar** per frame file: `frame-0001.json`
//! beside `frame-0001.png` (a frame without a sidecar has no marks). A plain `.json` file with
//! a stream is one layer for every frame. Errors name the file and, where there is one, the
//! line and column.
//!
//! Every number must be finite and within ±[`MAX_COORD`] (JSON has no `NaN` or `Infinity`;
//! the error says so when a writer emitted them), radii 0 or more, widths above 0. A mark
//! outside the canvas is accepted: it is carried by the affine map of the nearest triangle
//! ([`MeshMap::map`]) and drawn where it lands, so one far off the output is not drawn at all.

mod draw;
mod footprint;
mod json;
mod place;

pub(crate) use json::{is_json_lines, parse_line};
pub use json::{parse_layer, parse_layer_lines, read_layer};
pub use place::{place, MeshMap};

pub use footprint::paint_out;
pub(crate) use footprint::RaisedVsm;

use crate::image::{Image, Size};
use crate::mesh::{Mark, Mesh};
use crate::solve::Warp;
use glam::DVec2;
use std::sync::Arc;

/// A colour, straight (non-premultiplied) sRGB with alpha, each 0 to 255.
pub type Rgba = [u8; 4];

/// Marks given as vectors alongside a frame (see the module docs for the JSON format).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VectorLayer {
    /// Dots, nodes, symbols: drawn last.
    pub points: Vec<PointMark>,
    /// Free polylines (a trend line, a route): drawn first.
    pub polylines: Vec<Polyline>,
    /// Straight lines between two point marks (a graph's links): drawn between.
    pub edges: Vec<Edge>,
}

/// A round mark.
#[derive(Clone, Debug, PartialEq)]
pub struct PointMark {
    /// Optional name, unique within the layer (edges may refer to it).
    pub id: Option<String>,
    /// Centre, px.
    pub x: f64,
    pub y: f64,
    /// Radius, px (≥ 0).
    pub radius: f64,
    pub fill: Rgba,
    /// An outline centred on the rim.
    pub stroke: Option<Stroke>,
}

/// A point mark's outline.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Stroke {
    pub color: Rgba,
    /// Width, px (> 0).
    pub width: f64,
}

/// An open polyline.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// Its points `[x, y]`, px (at least one).
    pub points: Vec<[f64; 2]>,
    /// Width, px (> 0).
    pub width: f64,
    pub color: Rgba,
}

/// A straight line between two point marks, by their index in [`VectorLayer::points`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Edge {
    pub from: usize,
    pub to: usize,
    /// Width, px (> 0).
    pub width: f64,
    pub color: Rgba,
}

/// How large point marks are drawn (see the module docs).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum MarkSize {
    /// Radius times the local scale of the warp over the mark, clamped to `[0.1, 10]`.
    #[default]
    Mesh,
    /// Radius as given.
    Keep,
}

/// How vector marks are bound and drawn.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VectorOptions {
    /// Fill the marks' source footprints from the colours around them before anything else,
    /// for a raster that also shows the marks (default off: the raster is a background).
    pub paint_out: bool,
    /// How large point marks are drawn.
    pub size: MarkSize,
}

/// Largest coordinate, radius or width accepted, px: far beyond any canvas, small enough that
/// sums and squares stay exact enough and loops over bounding boxes stay bounded.
pub const MAX_COORD: f64 = 1.0e6;

/// A number for a message: as written when modest, in exponent form when huge (`1e300` is
/// 301 digits in `{}` form, a line no one reads).
fn num(v: f64) -> String {
    if v.is_finite() && v.abs() < 1e9 {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

impl VectorLayer {
    /// Whether the layer holds no marks.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty() && self.polylines.is_empty() && self.edges.is_empty()
    }

    /// Checks every number (finite, within ±[`MAX_COORD`], radii ≥ 0, widths > 0) and every
    /// edge's points; the message names the mark.
    pub fn validate(&self) -> Result<(), String> {
        let coord = |v: f64| v.is_finite() && v.abs() <= MAX_COORD;
        for (i, p) in self.points.iter().enumerate() {
            if !coord(p.x) || !coord(p.y) {
                return Err(format!(
                    "points[{i}]: centre ({}, {}) is not a finite coordinate within ±{MAX_COORD}",
                    num(p.x),
                    num(p.y)
                ));
            }
            if !(p.radius >= 0.0 && p.radius <= MAX_COORD) {
                return Err(format!(
                    "points[{i}]: radius {} is out of range: 0 to {MAX_COORD}",
                    num(p.radius)
                ));
            }
            if let Some(s) = &p.stroke {
                if !(s.width > 0.0 && s.width <= MAX_COORD) {
                    return Err(format!(
                        "points[{i}]: stroke width {} is out of range: above 0, up to {MAX_COORD}",
                        num(s.width)
                    ));
                }
            }
        }
        for (i, l) in self.polylines.iter().enumerate() {
            if l.points.is_empty() {
                return Err(format!("polylines[{i}]: has no points"));
            }
            if let Some(q) = l.points.iter().find(|q| !coord(q[0]) || !coord(q[1])) {
                return Err(format!(
                    "polylines[{i}]: point ({}, {}) is not a finite coordinate within ±{MAX_COORD}",
                    num(q[0]),
                    num(q[1])
                ));
            }
            if !(l.width > 0.0 && l.width <= MAX_COORD) {
                return Err(format!(
                    "polylines[{i}]: width {} is out of range: above 0, up to {MAX_COORD}",
                    num(l.width)
                ));
            }
        }
        for (i, e) in self.edges.iter().enumerate() {
            let n = self.points.len();
            if e.from >= n || e.to >= n {
                return Err(format!(
                    "edges[{i}]: joins points {} and {}, but there are {n} points",
                    e.from, e.to
                ));
            }
            if !(e.width > 0.0 && e.width <= MAX_COORD) {
                return Err(format!(
                    "edges[{i}]: width {} is out of range: above 0, up to {MAX_COORD}",
                    num(e.width)
                ));
            }
        }
        Ok(())
    }

    /// Draws the layer (in the image's own coordinates) onto `image`.
    pub fn draw(&self, image: &mut Image) {
        draw::draw_layer(image, self);
    }
}

/// Ring radius beyond a mark's rim (its stroke's outer edge), px: as for the small marks the
/// mesh finds itself.
const RING_MARGIN_PX: f64 = 1.5;
/// Marks with a larger ring are left to the lattice (a ring of 8 points would be a coarse
/// octagon around them; the raised saliency makes the lattice dense there instead).
const MAX_RING_RADIUS_PX: f64 = 40.0;

/// What the mesh must hold for a layer (§5.3): every point mark's centre as a vertex, and a
/// ring of key points just outside each point mark that stands alone (whose ring meets no
/// other's), so that it sits in a fan of triangles of its own, whatever the ring budget leaves
/// for the small marks found in the raster. Marks that overlap are left to the raster's mark
/// finder, which sees their raised footprint as one blob and rings it as a whole.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Binding {
    pub points: Vec<DVec2>,
    pub rings: Vec<Mark>,
}

impl Binding {
    pub fn of(layer: Option<&VectorLayer>, size: Size) -> Binding {
        let Some(layer) = layer else {
            return Binding::default();
        };
        let points: Vec<DVec2> = layer.points.iter().map(|p| DVec2::new(p.x, p.y)).collect();
        let (w, h) = (size.width as f64, size.height as f64);
        let ring =
            |p: &PointMark| p.radius + p.stroke.map_or(0.0, |s| s.width / 2.0) + RING_MARGIN_PX;
        // Sweep in x: a ring meets another only if their centres are within the two radii.
        let mut order: Vec<usize> = (0..points.len()).collect();
        order.sort_by(|&a, &b| points[a].x.total_cmp(&points[b].x));
        let max_ring = layer.points.iter().map(ring).fold(0.0, f64::max);
        let mut alone = vec![true; points.len()];
        for (k, &i) in order.iter().enumerate() {
            let ri = ring(&layer.points[i]);
            for &j in &order[k + 1..] {
                if points[j].x - points[i].x >= ri + max_ring {
                    break;
                }
                if points[i].distance(points[j]) < ri + ring(&layer.points[j]) {
                    alone[i] = false;
                    alone[j] = false;
                }
            }
        }
        let rings = layer
            .points
            .iter()
            .zip(&alone)
            .filter(|(p, &a)| {
                let r = ring(p);
                a && p.radius >= 1.0
                    && r <= MAX_RING_RADIUS_PX
                    && p.x > 0.0
                    && p.y > 0.0
                    && p.x < w
                    && p.y < h
            })
            .map(|(p, _)| {
                let r = ring(p);
                let clip = |v: f64, hi: f64| v.clamp(0.0, hi) as u32;
                Mark {
                    center: DVec2::new(p.x, p.y),
                    ring_radius: r,
                    bbox: [
                        clip(p.x - r, w),
                        clip(p.y - r, h),
                        clip(p.x + r, w),
                        clip(p.y + r, h),
                    ],
                    pixels: (std::f64::consts::PI * p.radius * p.radius).min(u32::MAX as f64)
                        as u32,
                }
            })
            .collect();
        Binding { points, rings }
    }
}

/// Places `layer` through the warp and draws it onto the rendered `image`; returns the layer
/// as placed.
pub(crate) fn overlay(
    image: &mut Image,
    layer: &VectorLayer,
    mesh: &Mesh,
    warp: &Warp,
    options: &VectorOptions,
) -> Arc<VectorLayer> {
    let placed = place(layer, mesh, warp, options.size);
    placed.draw(image);
    Arc::new(placed)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dot(x: f64, y: f64, radius: f64) -> PointMark {
        PointMark {
            id: None,
            x,
            y,
            radius,
            fill: [0, 0, 0, 255],
            stroke: None,
        }
    }

    /// Marks alone get rings; marks whose rings meet, tiny ones and ones on or off the
    /// border do not; every centre is a point to bind.
    #[test]
    fn binding_rings_marks_that_stand_alone() {
        let layer = VectorLayer {
            points: vec![
                dot(50.0, 50.0, 6.0),
                dot(100.0, 50.0, 6.0),
                dot(112.0, 50.0, 6.0),
                dot(150.0, 80.0, 0.5),
                dot(0.0, 30.0, 5.0),
                dot(250.0, 30.0, 5.0),
            ],
            ..VectorLayer::default()
        };
        let b = Binding::of(Some(&layer), Size::new(200, 100).unwrap());
        assert_eq!(b.points.len(), 6);
        assert_eq!(b.rings.len(), 1);
        assert_eq!(b.rings[0].center, DVec2::new(50.0, 50.0));
        assert_eq!(b.rings[0].ring_radius, 7.5);
        assert_eq!(
            Binding::of(None, Size::new(1, 1).unwrap()),
            Binding::default()
        );
    }

    #[test]
    fn validation_names_the_mark() {
        let mut l = VectorLayer {
            points: vec![dot(1.0, 2.0, 3.0)],
            ..VectorLayer::default()
        };
        assert!(l.validate().is_ok());
        l.edges.push(Edge {
            from: 0,
            to: 1,
            width: 1.0,
            color: [0; 4],
        });
        assert!(l.validate().unwrap_err().starts_with("edges[0]"));
        l.edges.clear();
        l.points[0].radius = f64::INFINITY;
        assert!(l.validate().unwrap_err().starts_with("points[0]"));
    }
}
