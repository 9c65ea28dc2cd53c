//! The reuse policy: compare a frame's VSM with the VSM the current mesh was built for, tile
//! by tile, and decide to reuse the mesh and solution, update them locally, or rebuild
//! ([`decide`], a pure function of what was built and the new saliency).

use crate::mesh::{find_marks, IncrementalMesh, Mark, Mesh};
use crate::saliency::{Vsm, DILATION_RADIUS};
use crate::structure::Regions;
use crate::tiles::TileMask;
use glam::DVec2;
use std::sync::Arc;

/// What the reuse policy decided for a frame.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum Decision {
    /// Mesh and solution built from scratch.
    #[default]
    Rebuild,
    /// Key points re-sampled in the changed tiles only; the rest of the solution kept.
    Update,
    /// Previous mesh and solution kept; only rendering.
    Reuse,
}

/// Thresholds of the reuse policy.
#[derive(Clone, Debug, PartialEq)]
pub struct ReuseOptions {
    /// Off: every frame is built from scratch (for comparison).
    pub enabled: bool,
    /// Side of the tiles changes are tracked in, in pixels.
    pub tile_px: u32,
    /// A tile whose mean absolute VSM change is below this is unchanged (VSM values are in
    /// `[0, 1]`; a 6-px dot moving inside a 32-px tile changes it by about 0.1).
    pub tile_threshold: f32,
    /// Above this share of changed tiles the mesh is rebuilt rather than updated.
    pub rebuild_fraction: f64,
}

impl Default for ReuseOptions {
    fn default() -> Self {
        ReuseOptions {
            enabled: true,
            tile_px: 32,
            tile_threshold: 0.02,
            rebuild_fraction: 0.3,
        }
    }
}

/// What the mesh stage built, and for what: all the reuse policy compares a frame with.
pub(crate) struct Built {
    pub inc: IncrementalMesh,
    pub mesh: Arc<Mesh>,
    /// The VSM the mesh was built for: the frame's own map, shared, until an update replaces
    /// tiles in a copy.
    pub reference: Arc<Vsm>,
    /// The VSM of the last frame meshed: a frame with the very same map changes nothing.
    pub last: Arc<Vsm>,
    /// The points the mesh was built to have as vertices, and the marks it was built to ring
    /// (vector marks, §5.3).
    pub points: Vec<DVec2>,
    pub rings: Vec<Mark>,
    /// The last frame's small marks that the mesh does not ring.
    pub floating: Arc<Vec<Mark>>,
}

/// A frame as the reuse policy sees it.
pub(crate) struct Incoming<'a> {
    pub vsm: &'a Arc<Vsm>,
    /// No previous frame of this size (see [`crate::retarget::stages::Saliency::fresh`]).
    pub fresh: bool,
    /// Points that must be vertices and marks to ring (vector marks), as for [`Built`].
    pub points: &'a [DVec2],
    pub rings: &'a [Mark],
}

/// What to do with the mesh for a frame.
#[derive(Debug, PartialEq)]
pub(crate) enum Plan {
    /// Build a mesh afresh.
    Rebuild,
    /// Keep the mesh and its solution. `marks`: the small marks found in the frame, to float
    /// where the mesh does not ring them; `None` for the very map of the last frame (the same
    /// floats).
    Reuse { marks: Option<Vec<Mark>> },
    /// Re-sample the key points of the tiles of `region`; `marks` as for `Reuse`.
    Update { region: TileMask, marks: Vec<Mark> },
}

/// The reuse policy for a frame: keep what was built while the saliency barely changes
/// (small marks moving or appearing do not count: they float over the kept warp), update it
/// tile by tile where it changed, rebuild when too much changed, a vector mark is touched, or
/// the picture is one affine map (whose mesh is cheap, and whose text found on an earlier
/// frame, floated over this one, would paste a label that moved or grew torn). `scratch` is a
/// buffer, its contents irrelevant.
pub(crate) fn decide(
    built: Option<&Built>,
    now: &Incoming,
    options: &ReuseOptions,
    regions: Regions,
    scratch: &mut Vec<bool>,
) -> Plan {
    let vsm = now.vsm;
    let Some(b) = built.filter(|b| {
        !now.fresh
            && options.enabled
            && b.mesh.size() == vsm.size()
            && b.points == now.points
            && b.rings == now.rings
    }) else {
        return Plan::Rebuild;
    };
    if Arc::ptr_eq(&b.last, vsm) {
        return Plan::Reuse { marks: None };
    }
    // Under one affine map a frame whose pixels changed (the saliency stage made it a new
    // map) is built afresh: its text and floats are found in its own pixels, so a frame
    // draws the same whether it came alone or after others. A measure of how much the map
    // changed would depend on which map is kept ([`crate::saliency::VsmBuilder`]'s whole
    // map, or the importance alone) and let a changed label be drawn as an earlier frame
    // found it.
    if regions == Regions::Affine {
        return Plan::Rebuild;
    }
    // Raster marks float only without vector marks (those steer the mesh themselves).
    let floats = now.points.is_empty() && now.rings.is_empty();
    let marks: Vec<Mark> = if floats {
        find_marks(vsm)
            .into_iter()
            .filter(|m| !b.inc.in_text(m.center))
            .collect()
    } else {
        Vec::new()
    };
    // Small marks, where the mesh rings them and where they are now, do not count as change.
    // Their saliency reaches beyond their box by the VSM's blur, Sobel and dilation.
    let ignore: Vec<[f64; 4]> = if floats {
        let reach = ((DILATION_RADIUS + 2) as u32 * vsm.scale() + 1) as f64;
        b.mesh
            .marks()
            .iter()
            .chain(&marks)
            .map(|m| {
                let [x0, y0, x1, y1] = m.bbox.map(|v| v as f64);
                [x0 - reach, y0 - reach, x1 + reach, y1 + reach]
            })
            .collect()
    } else {
        Vec::new()
    };
    let changed = changed_saliency(&b.reference, vsm, options, &ignore, scratch);
    let touches_vector_marks = || {
        now.points.iter().any(|&p| changed.contains(p))
            || now.rings.iter().any(|m| {
                let r = 1.5 * m.ring_radius;
                let c = m.center;
                changed.intersects(c.x - r, c.y - r, c.x + r, c.y + r)
            })
    };
    if changed.is_empty() {
        Plan::Reuse { marks: Some(marks) }
    } else if changed.fraction() > options.rebuild_fraction || touches_vector_marks() {
        Plan::Rebuild
    } else {
        Plan::Update {
            region: changed,
            marks,
        }
    }
}

/// Tiles (of `tile_px` image pixels) where `now` differs from `reference` by more than the
/// threshold, not counting map cells within the rectangles `ignore` (`[x0, y0, x1, y1]` in
/// image px: where small marks were and are, which float over the warp instead of re-meshing
/// it). Both maps must have the same size and scale. With `first_only`, the scan stops at the
/// first tile found: whether any changed is all the caller needs.
pub(crate) fn changed_saliency(
    reference: &Vsm,
    now: &Vsm,
    options: &ReuseOptions,
    ignore: &[[f64; 4]],
    scratch: &mut Vec<bool>,
) -> TileMask {
    let size = now.size();
    let mut mask = TileMask::new(size, options.tile_px);
    let s = now.scale();
    let grid = now.grid_size();
    let (gw, gh) = (grid.width as usize, grid.height as usize);
    let ignored = ignored_cells(ignore, s, gw, gh, scratch);
    let cells = (options.tile_px / s).max(1) as usize;
    let (a, b) = (reference.values(), now.values());
    for row in 0..mask.rows() as usize {
        let y0 = row * cells;
        let y1 = ((row + 1) * cells).min(gh);
        for col in 0..mask.cols() as usize {
            let x0 = col * cells;
            let x1 = ((col + 1) * cells).min(gw);
            if x0 >= x1 || y0 >= y1 {
                continue;
            }
            let mut sum = 0f32;
            for y in y0..y1 {
                let (ra, rb) = (&a[y * gw + x0..y * gw + x1], &b[y * gw + x0..y * gw + x1]);
                if ra == rb {
                    continue;
                }
                match ignored {
                    None => sum += ra.iter().zip(rb).map(|(p, q)| (p - q).abs()).sum::<f32>(),
                    Some(ig) => {
                        let skip = &ig[y * gw + x0..y * gw + x1];
                        sum += ra
                            .iter()
                            .zip(rb)
                            .zip(skip)
                            .filter(|(_, &k)| !k)
                            .map(|((p, q), _)| (p - q).abs())
                            .sum::<f32>();
                    }
                }
            }
            let mean = sum / ((x1 - x0) * (y1 - y0)) as f32;
            if mean > options.tile_threshold {
                mask.set(col as u32, row as u32);
            }
        }
    }
    mask
}

/// One flag per map cell (`gw × gh`, `s` px each) that meets a rectangle of `rects`, written
/// into `out`, or `None` without rectangles.
fn ignored_cells<'a>(
    rects: &[[f64; 4]],
    s: u32,
    gw: usize,
    gh: usize,
    out: &'a mut Vec<bool>,
) -> Option<&'a [bool]> {
    if rects.is_empty() {
        return None;
    }
    let s = s as f64;
    out.clear();
    out.resize(gw * gh, false);
    for &[x0, y0, x1, y1] in rects {
        let cx0 = (x0 / s).floor().max(0.0) as usize;
        let cy0 = (y0 / s).floor().max(0.0) as usize;
        let cx1 = ((x1 / s).ceil().max(0.0) as usize).min(gw);
        let cy1 = ((y1 / s).ceil().max(0.0) as usize).min(gh);
        for y in cy0..cy1 {
            out[y * gw + cx0..y * gw + cx1.max(cx0)].fill(true);
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Image, Size};
    use crate::mesh::MeshOptions;
    use crate::saliency::VsmBuilder;

    const SIZE: Size = Size {
        width: 320,
        height: 200,
    };

    /// A white picture with red dots of radius 6 at `dots` and a dark bar over `bar`.
    fn picture(dots: &[(f32, f32)], bar: Option<[u32; 4]>) -> Image {
        let mut img = Image::filled(SIZE, [255; 4]);
        for y in 0..SIZE.height {
            for x in 0..SIZE.width {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                if dots
                    .iter()
                    .any(|&(cx, cy)| (px - cx).powi(2) + (py - cy).powi(2) <= 36.0)
                {
                    img.set(x, y, [215, 25, 28, 255]);
                }
                if bar
                    .is_some_and(|[x0, y0, x1, y1]| (x0..x1).contains(&x) && (y0..y1).contains(&y))
                {
                    img.set(x, y, [40, 40, 120, 255]);
                }
            }
        }
        img
    }

    const DOTS: [(f32, f32); 3] = [(60.0, 50.0), (250.0, 150.0), (160.0, 100.0)];
    const BAR: [u32; 4] = [20, 120, 60, 190];

    fn vsm(img: &Image) -> Arc<Vsm> {
        Arc::new(VsmBuilder::new().build(img.as_ref()))
    }

    fn built(vsm: &Arc<Vsm>) -> Built {
        let options = MeshOptions {
            alpha: 20.0,
            regions: Regions::Free,
        };
        let (inc, mesh) = IncrementalMesh::build_with_marks(vsm, None, &[], &[], &options, 0);
        Built {
            inc,
            mesh: Arc::new(mesh),
            reference: vsm.clone(),
            last: vsm.clone(),
            points: Vec::new(),
            rings: Vec::new(),
            floating: Arc::default(),
        }
    }

    fn plan(b: Option<&Built>, vsm: &Arc<Vsm>, regions: Regions) -> Plan {
        let now = Incoming {
            vsm,
            fresh: false,
            points: &[],
            rings: &[],
        };
        decide(b, &now, &ReuseOptions::default(), regions, &mut Vec::new())
    }

    #[test]
    fn nothing_built_or_a_fresh_frame_or_reuse_off_rebuilds() {
        let v = vsm(&picture(&DOTS, Some(BAR)));
        let b = built(&v);
        assert_eq!(plan(None, &v, Regions::Free), Plan::Rebuild);
        let fresh = Incoming {
            vsm: &v,
            fresh: true,
            points: &[],
            rings: &[],
        };
        let off = ReuseOptions {
            enabled: false,
            ..ReuseOptions::default()
        };
        let mut scratch = Vec::new();
        let on = ReuseOptions::default();
        assert_eq!(
            decide(Some(&b), &fresh, &on, Regions::Free, &mut scratch),
            Plan::Rebuild
        );
        let now = Incoming {
            fresh: false,
            ..fresh
        };
        assert_eq!(
            decide(Some(&b), &now, &off, Regions::Free, &mut scratch),
            Plan::Rebuild
        );
        // Other vector marks than the mesh was built for.
        let points = [DVec2::new(100.0, 100.0)];
        let marked = Incoming {
            points: &points,
            ..now
        };
        assert_eq!(
            decide(Some(&b), &marked, &on, Regions::Free, &mut scratch),
            Plan::Rebuild
        );
    }

    #[test]
    fn the_same_map_is_reused_with_the_same_floats_and_an_equal_one_finds_them_again() {
        let img = picture(&DOTS, Some(BAR));
        let v = vsm(&img);
        let b = built(&v);
        assert_eq!(
            plan(Some(&b), &v, Regions::Free),
            Plan::Reuse { marks: None }
        );
        let again = vsm(&img);
        match plan(Some(&b), &again, Regions::Free) {
            Plan::Reuse { marks: Some(m) } => assert_eq!(m.len(), DOTS.len(), "{m:?}"),
            p => panic!("{p:?}"),
        }
    }

    #[test]
    fn a_small_mark_moving_does_not_count_as_change() {
        let b = built(&vsm(&picture(&DOTS, Some(BAR))));
        let moved = [DOTS[0], DOTS[1], (176.0, 100.0)];
        match plan(Some(&b), &vsm(&picture(&moved, Some(BAR))), Regions::Free) {
            Plan::Reuse { marks: Some(m) } => {
                assert!(m
                    .iter()
                    .any(|m| m.center.distance(DVec2::new(176.0, 100.0)) < 1.5))
            }
            p => panic!("{p:?}"),
        }
    }

    #[test]
    fn a_local_change_updates_its_tiles_and_rebuilds_under_one_affine_map() {
        let b = built(&vsm(&picture(&DOTS, Some(BAR))));
        let grown = vsm(&picture(&DOTS, Some([20, 120, 90, 190])));
        match plan(Some(&b), &grown, Regions::Free) {
            Plan::Update { region, .. } => {
                assert!(
                    region.contains(DVec2::new(75.0, 150.0)),
                    "the bar's new end"
                );
                assert!(!region.contains(DVec2::new(300.0, 20.0)), "far from it");
                assert!(region.fraction() <= ReuseOptions::default().rebuild_fraction);
            }
            p => panic!("{p:?}"),
        }
        assert_eq!(plan(Some(&b), &grown, Regions::Affine), Plan::Rebuild);
    }

    #[test]
    fn a_change_over_most_of_the_picture_rebuilds() {
        let b = built(&vsm(&picture(&DOTS, Some(BAR))));
        let other = vsm(&picture(&[], Some([0, 0, 300, 120])));
        assert_eq!(plan(Some(&b), &other, Regions::Free), Plan::Rebuild);
    }
}
