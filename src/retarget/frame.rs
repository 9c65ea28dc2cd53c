//! A frame going in, and what comes out of it: the retargeted picture with its statistics.

use super::reuse::Decision;
use crate::image::Image;
use crate::mesh::Mesh;
use crate::saliency::Vsm;
use crate::solve::{SolveStats, Warp};
use crate::vector::VectorLayer;
use std::sync::Arc;

/// One input frame.
#[derive(Clone, Debug)]
pub struct Frame {
    pub image: Image,
    /// Position in the stream, from 0.
    pub frame_index: u64,
    /// How long the frame is shown, in milliseconds, if the source says (GIF delays).
    pub duration_ms: Option<u32>,
    /// Vector marks of this frame (source coordinates); `None`: [`crate::Options::marks`], if any.
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
    /// Of those, tick labels thinned out (painted out, not drawn), as an axis' locator drops
    /// every other label where they would collide.
    pub dropped: usize,
    /// Panels laid out each in its own slot (a dashboard's, a figure's); 0 where the
    /// picture is laid out as one.
    pub panels: usize,
    /// Where the picture was drawn at one scale because nothing on its canvas gave way (see
    /// [`crate::Options::fill`]): the output rectangle `[x0, y0, x1, y1)` it fills, its ground
    /// around it. The analysis' warp still maps the canvas onto the whole target: a source
    /// point `(x, y)` of a `w × h` frame lies at `x0 + x·(x1 − x0)/w`, `y0 + y·(y1 − y0)/h`.
    pub fitted: Option<[u32; 4]>,
    /// Position in the stream.
    pub frame_index: u64,
}

/// The intermediate results of one frame, kept when [`crate::Options::keep_analysis`] is set.
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
