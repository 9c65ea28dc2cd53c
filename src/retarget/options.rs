//! What a retargeter is asked to do: plain data with defaults, checked once when it is built.

use super::reuse::ReuseOptions;
use crate::enhance::Enhancement;
use crate::error::Error;
use crate::solve::EnergyParams;
use crate::structure::Regions;
use crate::vector::{VectorLayer, VectorOptions};
use std::sync::Arc;

/// How to retarget. Plain data with defaults; checked once by [`Options::validate`].
#[derive(Clone, Debug)]
pub struct Options {
    /// The paper's `α`: the mesh budget is `w·h/α²` key points. Smaller is finer and slower.
    /// Allowed: 4 to 200; default 20. Under one affine map over the canvas (the default
    /// regions) the mesh shapes nothing drawn and takes α 200 whatever this says.
    pub alpha: f32,
    /// Energy tuning (see [`EnergyParams`]).
    pub energy: EnergyParams,
    /// Keep the VSM, mesh and warp of each frame in [`crate::Retargeted::analysis`] (for pictures and
    /// metrics; costs memory).
    pub keep_analysis: bool,
    /// When a stream may reuse the previous frame's mesh and solution.
    pub reuse: ReuseOptions,
    /// Detect lines and text and keep them straight and rigid (on by default; off gives the
    /// paper's method alone).
    pub structure: bool,
    /// Which regions are data areas, warped by one axis-aligned affine map each (by default
    /// the whole canvas; needs [`Options::structure`]).
    pub regions: Regions,
    /// Under [`Regions::Affine`], fill the whole target where nothing on the canvas gives way
    /// (its map is then the linear resize's, with whatever floats over it), instead of
    /// drawing the picture at one scale, centred on its ground (the colour of most of its
    /// edge; a picture without one is not drawn so). Off by default: judged blind, readers
    /// preferred the picture at one scale to the squeezed one. Frames with vector marks
    /// always fill.
    pub fill: bool,
    /// Under [`Regions::Affine`], lay a chart out again as its author would for the target:
    /// the data areas found from axes, frames, grids and bars take the room that the parts
    /// around them (labels, legends, titles, gutters) leave, those parts keep their size,
    /// text over the plots floats at its size, an x axis' crowded tick labels are thinned,
    /// and round marks keep their size where no two would touch. On by default: judged
    /// blind (2026-12-07, two judges a set) above the previous default in 42 of 84 rankings
    /// of generated charts (27 below: histograms and heat maps) and in 14 of 18 on the real
    /// stills it changes; it still loses where a plot holds shapes that do not float (an
    /// UpSet matrix's dots). A picture without data areas is unchanged by it.
    pub layout: bool,
    /// Vector marks for every frame that brings none of its own ([`crate::Frame::marks`]): bound to
    /// the mesh and redrawn over the warped raster (§5.3, see [`crate::vector`]).
    pub marks: Option<Arc<VectorLayer>>,
    /// How vector marks are bound and drawn.
    pub vector: VectorOptions,
    /// Content enhancement (§5.4, see [`Enhancement`]); the default changes nothing.
    pub enhance: Enhancement,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            alpha: 20.0,
            energy: EnergyParams::default(),
            keep_analysis: false,
            reuse: ReuseOptions::default(),
            structure: true,
            regions: Regions::default(),
            fill: false,
            layout: true,
            marks: None,
            vector: VectorOptions::default(),
            enhance: Enhancement::default(),
        }
    }
}

impl Options {
    /// Sets which regions are data areas.
    pub fn with_regions(mut self, regions: Regions) -> Options {
        self.regions = regions;
        self
    }

    /// Sets whether the whole target is filled where nothing gives way ([`Options::fill`]).
    pub fn with_fill(mut self, fill: bool) -> Options {
        self.fill = fill;
        self
    }

    /// Sets whether a chart's plots take the room its parts leave ([`Options::layout`]).
    pub fn with_layout(mut self, layout: bool) -> Options {
        self.layout = layout;
        self
    }

    /// The regions used: [`Options::regions`] ([`Regions::Free`] without
    /// [`Options::structure`]), except that content enhancement and vector marks, which grow
    /// or hold marks against their surroundings, ask for the mesh where the canvas would
    /// otherwise be one affine map (under which nothing can grow): [`Regions::Affine`] with
    /// either becomes [`Regions::Auto`].
    ///
    /// [`Regions::Affine`]: crate::structure::Regions::Affine
    /// [`Regions::Auto`]: crate::structure::Regions::Auto
    /// [`Regions::Free`]: crate::structure::Regions::Free
    pub fn effective_regions(&self) -> Regions {
        match self.regions {
            // Without structure nothing is found: the paper's warp everywhere, at its α.
            _ if !self.structure => Regions::Free,
            Regions::Affine if !self.enhance.is_identity() || self.marks.is_some() => Regions::Auto,
            r => r,
        }
    }

    /// Sets `α`.
    pub fn with_alpha(mut self, alpha: f32) -> Options {
        self.alpha = alpha;
        self
    }

    /// Keeps each frame's VSM, mesh and warp.
    pub fn with_analysis(mut self, keep: bool) -> Options {
        self.keep_analysis = keep;
        self
    }

    /// Draws `marks` over every frame that brings none of its own.
    pub fn with_marks(mut self, marks: VectorLayer) -> Options {
        self.marks = Some(Arc::new(marks));
        self
    }

    /// Enhances content (§5.4).
    pub fn with_enhancement(mut self, enhance: Enhancement) -> Options {
        self.enhance = enhance;
        self
    }

    /// Checks every option, naming the value and the allowed range.
    pub fn validate(&self) -> Result<(), Error> {
        self.enhance.validate()?;
        if let Some(m) = &self.marks {
            m.validate()
                .map_err(|e| Error::InvalidOptions(format!("the marks: {e}")))?;
        }
        if !(4.0..=200.0).contains(&self.alpha) {
            return Err(Error::InvalidOptions(format!(
                "alpha {} is out of range: allowed 4 to 200",
                self.alpha
            )));
        }
        self.energy.validate()?;
        let r = &self.reuse;
        if !(4..=1024).contains(&r.tile_px) {
            return Err(Error::InvalidOptions(format!(
                "reuse tile {} px is out of range: allowed 4 to 1024",
                r.tile_px
            )));
        }
        for (name, v) in [
            ("tile threshold", r.tile_threshold as f64),
            ("rebuild fraction", r.rebuild_fraction),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(Error::InvalidOptions(format!(
                    "reuse {name} {v} is out of range: allowed 0 to 1"
                )));
            }
        }
        Ok(())
    }
}
