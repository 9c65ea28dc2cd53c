//! The sequential core: options, frames, and the retargeter that runs the stages in order.
//!
//! `send_frame` / `receive_frame` / `flush` follow rav1e's encoder API: the core is sequential
//! and deterministic, and threaded pipelines wrap the same stage functions.

use crate::enhance::Enhancement;
use crate::error::Error;
use crate::image::{Image, Size};
use crate::mesh::{Mesh, MeshOptions};
use crate::saliency::Vsm;
use crate::solve::{EnergyParams, SolveStats, Warp};
use crate::stream::stages::{MeshStage, RenderStage, SaliencyStage, SolveStage};
use crate::stream::{Decision, ReuseOptions};
use crate::vector::{Binding, RaisedVsm, VectorLayer, VectorOptions};
use std::collections::VecDeque;
use std::sync::Arc;
use std::time::Instant;

/// How to retarget. Plain data with defaults; checked once by [`Options::validate`].
#[derive(Clone, Debug)]
pub struct Options {
    /// The paper's `α`: the mesh budget is `w·h/α²` key points. Smaller is finer and slower.
    /// Allowed: 4 to 200; default 20. Under one affine map over the canvas (the default
    /// regions) the mesh shapes nothing drawn and takes α 200 whatever this says.
    pub alpha: f32,
    /// Energy tuning (see [`EnergyParams`]).
    pub energy: EnergyParams,
    /// Keep the VSM, mesh and warp of each frame in [`Retargeted::analysis`] (for pictures and
    /// metrics; costs memory).
    pub keep_analysis: bool,
    /// When a stream may reuse the previous frame's mesh and solution.
    pub reuse: ReuseOptions,
    /// Detect lines and text and keep them straight and rigid (on by default; off gives the
    /// paper's method alone).
    pub structure: bool,
    /// Which regions are data areas, warped by one axis-aligned affine map each (by default
    /// the whole canvas; needs [`Options::structure`]).
    pub regions: crate::structure::Regions,
    /// Vector marks for every frame that brings none of its own ([`Frame::marks`]): bound to
    /// the mesh and redrawn over the warped raster (§5.3, see [`crate::vector`]).
    pub marks: Option<Arc<VectorLayer>>,
    /// How vector marks are bound and drawn.
    pub vector: VectorOptions,
    /// Content enhancement (§5.4, see [`crate::enhance`]); the default changes nothing.
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
            regions: crate::structure::Regions::default(),
            marks: None,
            vector: VectorOptions::default(),
            enhance: Enhancement::default(),
        }
    }
}

impl Options {
    /// Sets which regions are data areas.
    pub fn with_regions(mut self, regions: crate::structure::Regions) -> Options {
        self.regions = regions;
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
    pub fn effective_regions(&self) -> crate::structure::Regions {
        use crate::structure::Regions;
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
        let e = &self.energy;
        let checks = [
            ("weight_power", e.weight_power, 0.0, 16.0),
            ("weight_floor", e.weight_floor, 1e-9, 1.0),
            ("prior_threshold", e.prior_threshold, 0.0, 1.0),
            ("prior_strength", e.prior_strength, 0.0, 1e6),
            ("smoothing", e.smoothing, 0.0, 1e6),
        ];
        for (name, v, lo, hi) in checks {
            if !(lo..=hi).contains(&v) {
                return Err(Error::InvalidOptions(format!(
                    "{name} {v} is out of range: allowed {lo} to {hi}"
                )));
            }
        }
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

/// One input frame.
#[derive(Clone, Debug)]
pub struct Frame {
    pub image: Image,
    /// Position in the stream, from 0.
    pub frame_index: u64,
    /// How long the frame is shown, in milliseconds, if the source says (GIF delays).
    pub duration_ms: Option<u32>,
    /// Vector marks of this frame (source coordinates); `None`: [`Options::marks`], if any.
    pub marks: Option<Arc<VectorLayer>>,
}

impl Frame {
    pub fn new(image: Image, frame_index: u64) -> Frame {
        Frame {
            image,
            frame_index,
            duration_ms: None,
            marks: None,
        }
    }

    /// This frame with its vector marks.
    pub fn with_marks(mut self, marks: VectorLayer) -> Frame {
        self.marks = Some(Arc::new(marks));
        self
    }
}

/// Milliseconds spent in each stage for one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    pub vsm_ms: f64,
    pub mesh_ms: f64,
    pub solve_ms: f64,
    pub render_ms: f64,
}

impl StageTimes {
    pub fn total_ms(&self) -> f64 {
        self.vsm_ms + self.mesh_ms + self.solve_ms + self.render_ms
    }
}

/// What happened to one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameStats {
    pub vertices: usize,
    pub triangles: usize,
    /// Free vertex coordinates (the paper's DOF).
    pub dof: usize,
    pub solve: SolveStats,
    pub times: StageTimes,
    /// What the reuse policy did with this frame.
    pub decision: Decision,
    /// Tiles whose key points were re-sampled ([`Decision::Update`]).
    pub updated_tiles: usize,
    /// Data areas found (one affine map each).
    pub data_areas: usize,
    /// Marks and text blocks drawn floating over the warp (a data area's, and a stream's
    /// marks that the kept mesh does not ring).
    pub floated: usize,
    /// Position in the stream.
    pub frame_index: u64,
}

/// The intermediate results of one frame, kept when [`Options::keep_analysis`] is set.
#[derive(Clone, Debug)]
pub struct Analysis {
    pub vsm: Arc<Vsm>,
    pub mesh: Arc<Mesh>,
    pub warp: Arc<Warp>,
}

/// One retargeted frame.
#[derive(Clone, Debug)]
pub struct Retargeted {
    pub image: Image,
    pub frame_index: u64,
    pub duration_ms: Option<u32>,
    pub stats: FrameStats,
    pub analysis: Option<Analysis>,
    /// The frame's vector marks as placed and drawn on [`Retargeted::image`] (output
    /// coordinates, same order as given; radii as drawn).
    pub marks: Option<Arc<VectorLayer>>,
}

/// Why [`Retargeter::receive_frame`] has no frame.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Status {
    /// Send more frames.
    NeedMoreData,
    /// Flushed and drained: the stream is over.
    Done,
}

/// Retargets frames to one target size, in order, reusing the previous frame's mesh and
/// solution while the saliency barely changes (see [`ReuseOptions`]).
pub struct Retargeter {
    target: Size,
    options: Options,
    saliency: SaliencyStage,
    mesh: MeshStage,
    solve: SolveStage,
    render: RenderStage,
    raised: RaisedVsm,
    ready: VecDeque<Retargeted>,
    flushed: bool,
}

impl Retargeter {
    /// A retargeter for `target` (checked: each side 1 to [`crate::MAX_SIDE`]).
    pub fn new(target: Size, options: Options) -> Result<Retargeter, Error> {
        Size::new(target.width, target.height)?;
        options.validate()?;
        Ok(Retargeter {
            target,
            saliency: SaliencyStage::new(options.reuse.clone()),
            mesh: MeshStage::new(
                MeshOptions {
                    alpha: options.alpha,
                    regions: options.effective_regions(),
                },
                options.reuse.clone(),
                options.structure,
            ),
            solve: SolveStage::new(options.energy.clone(), target)
                .with_enhancement(&options.enhance),
            render: RenderStage::default(),
            raised: RaisedVsm::default(),
            options,
            ready: VecDeque::new(),
            flushed: false,
        })
    }

    /// The target size.
    pub fn target(&self) -> Size {
        self.target
    }

    /// Processes a frame; its result is then available from [`Retargeter::receive_frame`].
    pub fn send_frame(&mut self, frame: Frame) -> Result<(), Error> {
        if self.flushed {
            return Err(Error::InvalidOptions("send_frame after flush".into()));
        }
        let out = self.process(frame)?;
        self.ready.push_back(out);
        Ok(())
    }

    /// The next retargeted frame, in input order.
    pub fn receive_frame(&mut self) -> Result<Retargeted, Status> {
        match self.ready.pop_front() {
            Some(f) => Ok(f),
            None if self.flushed => Err(Status::Done),
            None => Err(Status::NeedMoreData),
        }
    }

    /// Ends the stream: frames still queued stay receivable, then `receive_frame` says `Done`.
    pub fn flush(&mut self) {
        self.flushed = true;
    }

    fn process(&mut self, mut frame: Frame) -> Result<Retargeted, Error> {
        let mut times = StageTimes::default();
        let t0 = Instant::now();
        let whole = crate::vector::prepare_frame(
            &mut frame,
            self.options.marks.as_ref(),
            &self.options.vector,
        )?;
        // With vector marks, saliency and structure are those of the whole picture.
        let analysed = whole.as_ref().unwrap_or(&frame.image);
        let mut sal = self.saliency.run(analysed);
        sal.vsm = self.raised.apply(&sal.vsm, frame.marks.as_ref());
        let t1 = Instant::now();
        times.vsm_ms = ms(t0, t1);
        let bind = Binding::of(frame.marks.as_deref(), frame.image.size());
        let meshed = self
            .mesh
            .run_with_marks(&sal, analysed, &bind.points, &bind.rings);
        let t2 = Instant::now();
        times.mesh_ms = ms(t1, t2);
        let solved = self.solve.run(&sal.vsm, &meshed)?;
        let t3 = Instant::now();
        times.solve_ms = ms(t2, t3);
        let mut image = self.render.run(
            &frame.image,
            &sal.vsm,
            &meshed,
            &solved.warp,
            solved.decision,
            &sal.dirty,
        );
        let marks = frame.marks.as_ref().map(|m| {
            crate::vector::overlay(
                &mut image,
                m,
                &meshed.mesh,
                &solved.warp,
                &self.options.vector,
            )
        });
        times.render_ms = ms(t3, Instant::now());
        let region_tiles = meshed.region.count();
        Ok(finish(
            FrameParts {
                frame,
                image,
                vsm: sal.vsm,
                mesh: meshed.mesh,
                solved,
                region_tiles,
                times,
                marks,
                floated: self.render.floated(),
            },
            self.options.keep_analysis,
        ))
    }
}

/// Everything the stages produced for one frame.
pub(crate) struct FrameParts {
    pub frame: Frame,
    pub image: Image,
    pub vsm: Arc<Vsm>,
    pub mesh: Arc<Mesh>,
    pub solved: crate::stream::stages::Solved,
    pub region_tiles: usize,
    pub times: StageTimes,
    /// The vector marks as placed and drawn.
    pub marks: Option<Arc<VectorLayer>>,
    /// Marks and text blocks drawn floating over the warp.
    pub floated: usize,
}

/// The output record of one frame.
pub(crate) fn finish(parts: FrameParts, keep_analysis: bool) -> Retargeted {
    let FrameParts {
        frame,
        image,
        vsm,
        mesh,
        solved,
        region_tiles,
        times,
        marks,
        floated,
    } = parts;
    let stats = FrameStats {
        vertices: mesh.vertices().len(),
        triangles: mesh.triangles().len(),
        dof: mesh.dof(),
        solve: solved.stats,
        times,
        decision: solved.decision,
        updated_tiles: if solved.decision == Decision::Update {
            region_tiles
        } else {
            0
        },
        frame_index: frame.frame_index,
        data_areas: mesh.structure().map_or(0, |s| s.areas.len()),
        floated,
    };
    let analysis = keep_analysis.then_some(Analysis {
        vsm,
        mesh,
        warp: solved.warp,
    });
    Retargeted {
        image,
        frame_index: frame.frame_index,
        duration_ms: frame.duration_ms,
        stats,
        analysis,
        marks,
    }
}

fn ms(a: Instant, b: Instant) -> f64 {
    (b - a).as_secs_f64() * 1000.0
}

/// Retargets one still image to `target`.
pub fn retarget(image: &Image, target: Size, options: &Options) -> Result<Retargeted, Error> {
    let mut r = Retargeter::new(target, options.clone())?;
    r.send_frame(Frame::new(image.clone(), 0))?;
    r.flush();
    r.receive_frame().map_err(|_| Error::Aborted)
}
