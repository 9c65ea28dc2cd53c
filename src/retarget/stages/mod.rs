//! The four stages of the method, each a stateful call `run(&mut self, msg) -> Result<next>`
//! that remembers what it needs of the previous frame:
//!
//! [`Frame`] → [`SaliencyStage`] → [`WithVsm`] → [`MeshStage`] → [`WithMesh`] →
//! [`SolveStage`] → [`WithWarp`] → [`RenderStage`] → [`Retargeted`].
//!
//! [`crate::Retargeter`] chains the calls on one thread; [`crate::Pipeline`] runs each stage on
//! its own thread. Same calls, same frames: nothing of a frame's handling lives outside them.

mod mesh;
mod render;
mod saliency;
mod solve;

pub(crate) use mesh::{MeshStage, Meshed};
pub(crate) use render::{laid_out, RenderStage};
pub(crate) use saliency::{Saliency, SaliencyStage};
pub(crate) use solve::{SolveStage, Solved};

use super::frame::{Frame, Retargeted, StageTimes};
use super::options::Options;
use crate::error::Error;
use crate::image::{Image, Size};
use crate::mesh::MeshOptions;
use std::time::Instant;

/// A frame with its saliency.
pub(crate) struct WithVsm {
    pub frame: Frame,
    pub sal: Saliency,
    /// The raster with the frame's vector marks drawn in, when it has any: what the VSM and
    /// the structure are computed on.
    pub whole: Option<Image>,
    pub times: StageTimes,
}

/// A frame with its saliency and mesh.
pub(crate) struct WithMesh {
    pub frame: Frame,
    pub sal: Saliency,
    pub meshed: Meshed,
    pub times: StageTimes,
}

/// A frame with its saliency, mesh and warp.
pub(crate) struct WithWarp {
    pub frame: Frame,
    pub sal: Saliency,
    pub meshed: Meshed,
    pub solved: Solved,
    pub times: StageTimes,
}

/// The four stages for one target and set of options (checked beforehand).
pub(crate) struct Stages {
    pub saliency: SaliencyStage,
    pub mesh: MeshStage,
    pub solve: SolveStage,
    pub render: RenderStage,
}

impl Stages {
    pub fn new(target: Size, options: &Options) -> Stages {
        Stages {
            saliency: SaliencyStage::new(options),
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
            render: RenderStage::new(options),
        }
    }

    /// One frame through all four stages, in order.
    pub fn run(&mut self, frame: Frame) -> Result<Retargeted, Error> {
        let m = self.saliency.run(frame)?;
        let m = self.mesh.run(m)?;
        let m = self.solve.run(m)?;
        self.render.run(m)
    }
}

/// Milliseconds since `t`.
fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1000.0
}
