//! # vizretarget
//!
//! Content-aware resizing of visualizations to any aspect ratio, after Li, Baciu, Wang and
//! Zhang, *Fast content-aware resizing of multi-layer information visualization via adaptive
//! triangulation*. A visual saliency map ([`Vsm`], §4) finds what matters; an adaptive Delaunay
//! [`Mesh`] (§5.1) is dense there and sparse on empty background; a linear energy (§5.2) solved
//! as one sparse system gives a [`Warp`] that keeps salient content in shape while empty space
//! absorbs the change; the renderer draws the warped frame.
//!
//! Read a chart, halve its width, write the result (the format is the one the name says;
//! a name saying another is refused):
//!
//! ```no_run
//! use vizretarget::io::{read_still, write_still, OutputFormat};
//! use vizretarget::{retarget, Options, Size};
//!
//! fn main() -> Result<(), vizretarget::Error> {
//!     let chart = read_still("chart.png".as_ref())?;
//!     let target = Size::new(chart.width() / 2, chart.height())?;
//!     let out = retarget(&chart, target, &Options::default())?;
//!     write_still(&out.image, "chart-narrow.png".as_ref(), OutputFormat::Png)?;
//!     Ok(())
//! }
//! ```
//!
//! An error returned from `main` prints as one line (`chart.png: No such file or directory
//! (os error 2)`): [`Error`]'s `Debug` is its `Display`. In memory, without files:
//!
//! ```
//! use vizretarget::{retarget, Image, Options, Size};
//! let img = Image::filled(Size::new(200, 100)?, [255, 255, 255, 255]);
//! let out = retarget(&img, Size::new(100, 100)?, &Options::default())?;
//! assert_eq!(out.image.size(), Size::new(100, 100)?);
//! # Ok::<(), vizretarget::Error>(())
//! ```
//!
//! The stages, in the order of the pipeline: the visual saliency map ([`Vsm`], §4), the
//! adaptive mesh ([`Mesh`], §5.1), the mesh resizing ([`Solver`] giving a [`Warp`], §5.2) and
//! the render ([`Renderer`]). Marks given as vectors ([`vector`], §5.3) are bound to the mesh
//! and redrawn crisp over the warped raster; an [`Enhancement`] (§5.4) enlarges chosen levels
//! or regions. [`Retargeter`] runs the stages in order, frame after frame; [`Pipeline`] runs
//! the same stages on threads between a source and a sink ([`io`], [`stream`]).
//!
//! Everything a user names is re-exported here; the modules that stay public are namespaces
//! of their own: [`io`] (reading and writing frames), [`stream`] (the traits a source or sink
//! implements, and the pipeline), [`vector`] (marks as vectors). With the `eval` feature (on
//! by default, through `binary`): [`baseline`] (the methods compared against), [`metrics`],
//! [`compare`] (the comparison sheet) and [`debug`] (pictures of the stages).

mod enhance;
mod error;
mod image;
mod limits;
mod mesh;
mod raster;
mod render;
mod retarget;
mod saliency;
mod simd;
mod size;
mod solve;
mod structure;
mod target;
mod tiles;

pub mod io;
pub mod stream;
pub mod vector;

#[cfg(feature = "eval")]
pub mod baseline;
#[cfg(feature = "eval")]
pub mod compare;
#[cfg(feature = "eval")]
pub mod debug;
#[cfg(feature = "eval")]
pub mod metrics;

#[cfg(feature = "eval")]
pub use baseline::{retarget_with, Method, MethodOutput};
pub use enhance::{EnhanceMask, EnhanceRegion, Enhancement};
pub use error::Error;
pub use image::{Image, ImageRef, Size, MAX_SIDE};
pub use limits::{parse_bytes, Limit, Limits, MemoryPlan};
pub use mesh::{Boundary, Mark, Mesh, MeshOptions, Role};
pub use render::{resize_linear, resize_mapped, AxisMap, CanvasMap, PanelMap, Renderer};
pub use retarget::{
    retarget, Analysis, Decision, Frame, FrameStats, Options, Retargeted, Retargeter, ReuseOptions,
    StageTimes, Status,
};
pub use saliency::{SaliencyLevel, Vsm, VsmBuilder};
pub use size::InvalidSize;
pub use solve::{EnergyParams, Locator, SolveStats, Solver, Warp};
pub use stream::{FrameSink, FrameSource, Pipeline, Repeat, RunSummary};
pub use structure::{AreaKind, Bands, DataArea, Line, Panel, Regions, Split, Structure, TextBlock};
pub use target::{InvalidTarget, Side, Target};
pub use vector::{MarkSize, VectorLayer, VectorOptions};
