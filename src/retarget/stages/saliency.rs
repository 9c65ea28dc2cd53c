//! Stage 1: the visual saliency map (§4), recomputed only where pixels changed.

use super::{ms, WithVsm};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::retarget::frame::{Frame, StageTimes};
use crate::retarget::options::Options;
use crate::retarget::reuse::ReuseOptions;
use crate::saliency::{Rect, Vsm, VsmBuilder};
use crate::structure::Regions;
use crate::tiles::{take_changed_tiles, TileMask};
use crate::vector::{paint_out, RaisedVsm, VectorLayer, VectorOptions};
use std::sync::Arc;
use std::time::Instant;

/// Above this share of changed tiles the VSM is recomputed whole (with fresh normalization).
const FULL_VSM_FRACTION: f64 = 0.5;

/// Stage 1: the VSM, recomputed only where pixels changed.
pub(crate) struct SaliencyStage {
    builder: VsmBuilder,
    prev: Option<Image>,
    vsm: Option<Arc<Vsm>>,
    reuse: ReuseOptions,
    /// Vector marks for frames that bring none, and how they are drawn.
    marks: Option<Arc<VectorLayer>>,
    vector: VectorOptions,
    /// The VSM raised under vector marks (§5.3).
    raised: RaisedVsm,
    /// Maps of earlier frames, whose planes a new map reuses once the later stages have
    /// dropped them.
    spare: Vec<Arc<Vsm>>,
    /// Frames resampled as one canvas ([`Regions::Affine`], no analysis kept) get the
    /// importance alone ([`VsmBuilder::build_importance_into`]): nothing downstream reads
    /// more of their map.
    importance_only: bool,
    /// The current map is the importance alone.
    current_importance_only: bool,
    /// A changed frame's map is built whole, never region by region (under
    /// [`Regions::Affine`], where each changed frame is resampled afresh): a map held to an
    /// earlier frame's constants would make what floats depend on the frames before.
    whole_maps: bool,
}

/// Earlier maps kept for their planes: the later stages hold a frame's map for a frame or
/// two (the mesh stage keeps the last one it meshed).
const SPARE_MAPS: usize = 4;

/// What the saliency stage hands on.
pub(crate) struct Saliency {
    pub vsm: Arc<Vsm>,
    /// Tiles whose pixels differ from the previous frame (all tiles for a first frame).
    pub dirty: TileMask,
    /// No previous frame of this size: everything downstream starts over.
    pub fresh: bool,
}

impl SaliencyStage {
    pub fn new(options: &Options) -> SaliencyStage {
        SaliencyStage {
            builder: VsmBuilder::new(),
            prev: None,
            vsm: None,
            reuse: options.reuse.clone(),
            marks: options.marks.clone(),
            vector: options.vector.clone(),
            raised: RaisedVsm::default(),
            spare: Vec::new(),
            importance_only: options.effective_regions() == Regions::Affine
                && !options.keep_analysis,
            current_importance_only: false,
            whole_maps: options.effective_regions() == Regions::Affine,
        }
    }

    /// A map whose planes no later stage holds any more (empty if none is free yet).
    fn recycled(&mut self, size: Size) -> Vsm {
        // Held by this stage alone: no other stage can take a new reference to it.
        let free = self.spare.iter().rposition(|a| Arc::strong_count(a) == 1);
        free.and_then(|i| Arc::try_unwrap(self.spare.remove(i)).ok())
            .unwrap_or_else(|| Vsm::empty(size))
    }

    /// The frame's saliency: of the whole visualization when it has vector marks (drawn into
    /// the raster for it), raised under the marks.
    pub fn run(&mut self, mut frame: Frame) -> Result<WithVsm, Error> {
        let t = Instant::now();
        let whole = prepare_frame(&mut frame, self.marks.as_ref(), &self.vector)?;
        // A frame with vector marks is meshed around them (§5.3), whatever the regions.
        let importance_only = self.importance_only
            && whole.is_none()
            && crate::structure::takes_canvas_whole(frame.image.size());
        let mut sal = self.vsm_of(whole.as_ref().unwrap_or(&frame.image), importance_only);
        sal.vsm = self.raised.apply(&sal.vsm, frame.marks.as_ref());
        Ok(WithVsm {
            frame,
            sal,
            whole,
            times: StageTimes {
                vsm_ms: ms(t),
                ..StageTimes::default()
            },
        })
    }

    /// The VSM of `image` (its importance alone with `importance_only`), recomputed only in
    /// the tiles that differ from the previous frame (whole for the importance alone, which
    /// has no constants to hold a region to the rest).
    fn vsm_of(&mut self, image: &Image, importance_only: bool) -> Saliency {
        let size = image.size();
        let same = self.reuse.enabled
            && self.prev.as_ref().is_some_and(|p| p.size() == size)
            && self.vsm.is_some()
            && self.current_importance_only == importance_only;
        self.current_importance_only = importance_only;
        let out = if !same {
            let mut vsm = self.recycled(size);
            self.build(image, &mut vsm, importance_only);
            let vsm = Arc::new(vsm);
            let mut dirty = TileMask::new(size, self.reuse.tile_px);
            for r in 0..dirty.rows() {
                for c in 0..dirty.cols() {
                    dirty.set(c, r);
                }
            }
            Saliency {
                vsm,
                dirty,
                fresh: true,
            }
        } else {
            // The previous frame becomes this one as it is compared with it.
            let prev = self.prev.as_mut().expect("checked");
            let dirty = take_changed_tiles(prev, image, self.reuse.tile_px);
            let current = self.vsm.clone().expect("checked");
            let vsm = if dirty.is_empty() {
                current.clone()
            } else if self.whole_maps || dirty.fraction() > FULL_VSM_FRACTION {
                let mut v = self.recycled(size);
                self.build(image, &mut v, importance_only);
                Arc::new(v)
            } else {
                let mut v = self.recycled(size);
                v.clone_from(&current);
                for [x0, y0, x1, y1] in dirty.rects(size) {
                    self.builder
                        .update_region(image.as_ref(), &mut v, Rect { x0, y0, x1, y1 });
                }
                Arc::new(v)
            };
            Saliency {
                vsm,
                dirty,
                fresh: false,
            }
        };
        if let Some(old) = self.vsm.replace(out.vsm.clone()) {
            if !Arc::ptr_eq(&old, &out.vsm) {
                if self.spare.len() == SPARE_MAPS {
                    self.spare.remove(0);
                }
                self.spare.push(old);
            }
        }
        if !same {
            match &mut self.prev {
                Some(p) if p.size() == size => p.pixels_mut().copy_from_slice(image.pixels()),
                p => *p = Some(image.clone()),
            }
        }
        out
    }
}

impl SaliencyStage {
    /// The whole map of `image` into `vsm`, or its importance alone.
    fn build(&mut self, image: &Image, vsm: &mut Vsm, importance_only: bool) {
        if importance_only {
            self.builder.build_importance_into(image.as_ref(), vsm);
        } else {
            self.builder.build_into(image.as_ref(), vsm);
        }
    }
}

/// The layer that applies to a frame: its own, else the options' one for every frame;
/// checked, and the raster painted out under it if asked. Returns the picture to analyse
/// (saliency, structure) when there are marks: the raster with the marks drawn in at their
/// source places, i.e. the whole visualization, as the paper computes its saliency map
/// (§5.3). Its normalization then matches the same picture given as pixels: a background
/// alone would have its own faint content stretched to full saliency. The error names the
/// frame.
fn prepare_frame(
    frame: &mut Frame,
    marks: Option<&Arc<VectorLayer>>,
    options: &VectorOptions,
) -> Result<Option<Image>, Error> {
    if frame.marks.is_none() {
        frame.marks = marks.cloned();
    }
    let Some(layer) = frame.marks.as_ref().filter(|l| !l.is_empty()) else {
        return Ok(None);
    };
    layer.validate().map_err(|m| {
        Error::InvalidOptions(format!("the marks of frame {}: {m}", frame.frame_index))
    })?;
    if options.paint_out {
        paint_out(&mut frame.image, layer);
    }
    let mut whole = frame.image.clone();
    layer.draw(&mut whole);
    Ok(Some(whole))
}
