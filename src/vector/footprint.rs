//! Where marks lie in the source: raised saliency under them (§5.3: a bound mark is content the
//! mesh must keep), and, when the raster also shows them, painting them out.

use super::VectorLayer;
use crate::image::Image;
use crate::saliency::Vsm;
use glam::DVec2;
use std::sync::Arc;

/// Margin around a mark that counts as its footprint (its antialiased rim), px.
const RAISE_MARGIN_PX: f64 = 1.0;
/// Margin painted out around a mark that is also in the raster (its rim, and a little of the
/// raster's own antialiasing), px.
const PAINT_MARGIN_PX: f64 = 1.5;

/// Distance from `p` to the segment `ab`.
pub(crate) fn dist_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

/// One shape of a footprint: a disc or a band around a segment, with its half-width.
#[derive(Copy, Clone)]
struct Shape {
    a: DVec2,
    b: DVec2,
    half: f64,
}

impl Shape {
    fn bbox(&self) -> [f64; 4] {
        [
            self.a.x.min(self.b.x) - self.half,
            self.a.y.min(self.b.y) - self.half,
            self.a.x.max(self.b.x) + self.half,
            self.a.y.max(self.b.y) + self.half,
        ]
    }
    fn contains(&self, p: DVec2) -> bool {
        dist_to_segment(p, self.a, self.b) <= self.half
    }
}

/// The shapes of a layer's footprint, each grown by `margin`: point marks (disc and stroke),
/// polylines, and edges when `edges` is set.
fn shapes(layer: &VectorLayer, margin: f64, edges: bool) -> Vec<Shape> {
    let mut out = Vec::new();
    for p in &layer.points {
        let c = DVec2::new(p.x, p.y);
        let stroke = p.stroke.map_or(0.0, |s| s.width / 2.0);
        out.push(Shape {
            a: c,
            b: c,
            half: p.radius + stroke + margin,
        });
    }
    for l in &layer.polylines {
        let pts: Vec<DVec2> = l.points.iter().map(|q| DVec2::new(q[0], q[1])).collect();
        let half = l.width / 2.0 + margin;
        if pts.len() == 1 {
            out.push(Shape {
                a: pts[0],
                b: pts[0],
                half,
            });
        }
        for w in pts.windows(2) {
            out.push(Shape {
                a: w[0],
                b: w[1],
                half,
            });
        }
    }
    if edges {
        for e in &layer.edges {
            let (Some(a), Some(b)) = (layer.points.get(e.from), layer.points.get(e.to)) else {
                continue;
            };
            out.push(Shape {
                a: DVec2::new(a.x, a.y),
                b: DVec2::new(b.x, b.y),
                half: e.width / 2.0 + margin,
            });
        }
    }
    out
}

/// Visits the cells (`cell` px square, `cols` × `rows` of them) whose centre lies in `shape`.
fn cells_in(shape: &Shape, cell: f64, cols: usize, rows: usize, mut f: impl FnMut(usize)) {
    let [x0, y0, x1, y1] = shape.bbox();
    let lo = |v: f64, n: usize| ((v / cell - 0.5).floor().max(0.0) as usize).min(n);
    let hi = |v: f64, n: usize| ((v / cell + 0.5).ceil().max(0.0) as usize).min(n);
    for gy in lo(y0, rows)..hi(y1, rows) {
        for gx in lo(x0, cols)..hi(x1, cols) {
            let c = DVec2::new((gx as f64 + 0.5) * cell, (gy as f64 + 0.5) * cell);
            if shape.contains(c) {
                f(gy * cols + gx);
            }
        }
    }
}

/// `vsm` with values, importance and edges raised to 1 in the footprint of every point mark
/// and polyline of `layer` (graph edges are connectors: they may stretch, so they are not
/// raised).
pub(crate) fn raise(vsm: &mut Vsm, layer: &VectorLayer) {
    let grid = vsm.grid_size();
    let (cols, rows) = (grid.width as usize, grid.height as usize);
    let cell = vsm.scale() as f64;
    let (values, importance, edges) = vsm.planes_mut();
    for s in shapes(layer, RAISE_MARGIN_PX, false) {
        cells_in(&s, cell, cols, rows, |i| {
            values[i] = 1.0;
            importance[i] = 1.0;
            edges[i] = 1.0;
        });
    }
}

/// Keeps the raised VSM of the last frame, so that a static layer over a static raster gives
/// the same map (the same `Arc`) and the stream's reuse policy sees no change.
#[derive(Default)]
pub(crate) struct RaisedVsm {
    last: Option<(Arc<Vsm>, Arc<VectorLayer>, Arc<Vsm>)>,
}

impl RaisedVsm {
    /// `vsm` raised under `layer` (`vsm` itself when there are no marks).
    pub fn apply(&mut self, vsm: &Arc<Vsm>, layer: Option<&Arc<VectorLayer>>) -> Arc<Vsm> {
        let Some(layer) = layer.filter(|l| !l.is_empty()) else {
            return vsm.clone();
        };
        if let Some((v, l, out)) = &self.last {
            if Arc::ptr_eq(v, vsm) && (Arc::ptr_eq(l, layer) || **l == **layer) {
                return out.clone();
            }
        }
        let mut raised = (**vsm).clone();
        raise(&mut raised, layer);
        let out = Arc::new(raised);
        self.last = Some((vsm.clone(), layer.clone(), out.clone()));
        out
    }
}

/// Fills the source footprint of every mark of `layer` (discs, polylines, edges, grown by
/// 1.5 px) from the colours around it: onion-peel, from the outside in, each pixel the mean of
/// its 8-neighbours already known. A mark on a flat background leaves exactly that background.
pub fn paint_out(image: &mut Image, layer: &VectorLayer) {
    let (w, h) = (image.width() as usize, image.height() as usize);
    let mut masked = vec![false; w * h];
    let mut todo: Vec<u32> = Vec::new();
    for s in shapes(layer, PAINT_MARGIN_PX, true) {
        cells_in(&s, 1.0, w, h, |i| {
            if !masked[i] {
                masked[i] = true;
                todo.push(i as u32);
            }
        });
    }
    crate::render::fill_from_surroundings(image, &mut masked, todo);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Size;
    use crate::vector::{PointMark, Polyline};

    fn dot(x: f64, y: f64, r: f64) -> PointMark {
        PointMark {
            id: None,
            x,
            y,
            radius: r,
            fill: [200, 0, 0, 255],
            stroke: None,
        }
    }

    #[test]
    fn painting_out_restores_a_flat_background() {
        let size = Size::new(60, 40).unwrap();
        let bg = [236, 244, 250, 255];
        let mut img = Image::filled(size, bg);
        let layer = VectorLayer {
            points: vec![dot(20.0, 20.0, 6.0), dot(0.0, 0.0, 4.0)],
            polylines: vec![Polyline {
                points: vec![[30.0, 5.0], [55.0, 35.0]],
                width: 2.0,
                color: [0, 0, 0, 255],
            }],
            edges: vec![],
        };
        layer.draw(&mut img);
        assert!(img.pixels().iter().any(|p| *p != bg));
        paint_out(&mut img, &layer);
        assert!(img.pixels().iter().all(|p| *p == bg));
    }

    #[test]
    fn raising_covers_the_disc_and_nothing_far() {
        let size = Size::new(64, 48).unwrap();
        let mut vsm = Vsm::from_values(size, vec![0.0; size.area()]).unwrap();
        raise(
            &mut vsm,
            &VectorLayer {
                points: vec![dot(30.5, 20.5, 5.0)],
                ..VectorLayer::default()
            },
        );
        assert_eq!(vsm.get(30, 20), 1.0);
        assert_eq!(vsm.get(35, 20), 1.0);
        assert_eq!(vsm.get(38, 20), 0.0);
        assert_eq!(vsm.importance()[20 * 64 + 26], 1.0);
    }
}
