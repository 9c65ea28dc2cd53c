//! The methods vizretarget is compared with, behind one interface: [`retarget_with`].
//!
//! * [`Method::Mesh`]: the crate's own method (the paper's adaptive mesh), [`crate::retarget`];
//! * [`Method::Linear`]: plain scaling with area filtering (the paper's Fig. 10b);
//! * [`Method::Crop`]: uniform scaling to cover the target, then the window with the most
//!   VSM saliency (Fig. 14b);
//! * [`Method::Grid`]: the uniform-grid scale-and-stretch deformation of Wang et al. 2008, the
//!   paper's ref. \[1\] and its Table 1 rival, on the same energy and solver as the mesh;
//! * [`Method::Axis`]: axis-aligned deformation (Panozzo et al. 2012): one scale per column
//!   and per row, so lines stay straight and unbroken;
//! * [`Method::Seam`]: seam carving (Avidan and Shamir 2007) with forward energy (Rubinstein et
//!   al. 2008), the usual content-aware tool.
//!
//! Every method returns exactly the target size, with how each output pixel relates to the
//! source ([`Mapping`]) so that [`crate::metrics`] can judge them all by the same rules.

mod axis;
mod crop;
mod grid;
mod linear;
mod seam;

use crate::error::Error;
use crate::image::{Image, Size};
use crate::mesh::Mesh;
use crate::retarget::{retarget, Options, StageTimes};
use crate::saliency::Vsm;
use crate::solve::Warp;
use std::sync::Arc;

pub use seam::OriginMap;

/// A resizing method.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum Method {
    /// The adaptive triangle mesh of the paper (this crate's method).
    #[default]
    Mesh,
    /// Linear scaling (bilinear, area-filtered where it shrinks).
    Linear,
    /// Uniform scaling to cover the target, then the most salient window.
    Crop,
    /// Scale-and-stretch on a uniform grid (Wang et al. 2008), same energy and solver.
    Grid,
    /// Seam carving with forward energy, removing or inserting seams, width then height.
    Seam,
    /// Axis-aligned deformation (Panozzo et al. 2012): a scale per grid column and per row.
    Axis,
}

impl Method {
    /// Every method, the crate's first.
    pub const ALL: [Method; 6] = [
        Method::Mesh,
        Method::Linear,
        Method::Crop,
        Method::Grid,
        Method::Seam,
        Method::Axis,
    ];

    /// The lower-case name used on the command line and in tables.
    pub const fn name(self) -> &'static str {
        match self {
            Method::Mesh => "mesh",
            Method::Linear => "linear",
            Method::Crop => "crop",
            Method::Grid => "grid",
            Method::Seam => "seam",
            Method::Axis => "axis",
        }
    }

    /// Whether the method deforms a triangle mesh (and so has vertices and DOF).
    pub const fn has_mesh(self) -> bool {
        matches!(self, Method::Mesh | Method::Grid | Method::Axis)
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Method {
    type Err = Error;

    fn from_str(s: &str) -> Result<Method, Error> {
        Method::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                Error::InvalidOptions(format!(
                    "unknown method {s:?}: allowed mesh, linear, crop, grid, seam, axis"
                ))
            })
    }
}

/// How the output's pixels relate to the source's, for the metrics.
#[derive(Clone, Debug)]
pub enum Mapping {
    /// A triangle mesh over the source and its deformed positions (mesh, grid).
    Warp { mesh: Arc<Mesh>, warp: Arc<Warp> },
    /// The source rectangle `[x0, x1) × [y0, y1)` (pixels, possibly fractional) scaled to the
    /// whole output: the whole image for linear scaling, the kept window for cropping.
    Affine { window: [f64; 4] },
    /// For each output pixel, where in the source it came from (seam carving).
    Origins(Arc<OriginMap>),
}

/// Size and cost of one run.
///
/// `times` keeps the pipeline's four columns for every method: `vsm_ms` the saliency map (0
/// for linear), `mesh_ms` building the mesh or grid, `solve_ms` the method's own search (the
/// mesh or grid solve, the crop's window search, the seams' dynamic programming and removal or
/// insertion), `render_ms` drawing the output (the warp, or the crop's scaling).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MethodStats {
    /// Mesh vertices (mesh and grid only).
    pub vertices: Option<usize>,
    /// Mesh triangles (mesh and grid only).
    pub triangles: Option<usize>,
    /// Free vertex coordinates, the paper's DOF (mesh and grid only).
    pub dof: Option<usize>,
    /// Folded triangles straight after the first solve (mesh and grid only; none reach the
    /// output).
    pub folds_first_solve: Option<usize>,
    pub times: StageTimes,
}

/// One method's result.
#[derive(Clone, Debug)]
pub struct MethodOutput {
    pub method: Method,
    /// Exactly the target size.
    pub image: Image,
    pub stats: MethodStats,
    /// How output pixels relate to the source.
    pub mapping: Mapping,
    /// The source's VSM, where the method computed one (all but linear).
    pub vsm: Option<Arc<Vsm>>,
}

/// Resizes `image` to `target` with `method`. [`Method::Mesh`] is [`crate::retarget`]; the
/// others are the baselines above. `options` are validated for every method; `alpha` and the
/// energy also set the grid (cells of `alpha` px, the same budget `w·h/α²` the mesh samples
/// from, which is the scale of the paper's grid counts in Table 1).
pub fn retarget_with(
    method: Method,
    image: &Image,
    target: Size,
    options: &Options,
) -> Result<MethodOutput, Error> {
    let target = Size::new(target.width, target.height)?;
    options.validate()?;
    match method {
        Method::Mesh => mesh_method(image, target, options),
        Method::Linear => Ok(linear::run(image, target)),
        Method::Crop => Ok(crop::run(image, target)),
        Method::Grid => grid::run(image, target, options),
        Method::Seam => Ok(seam::run(image, target)),
        Method::Axis => axis::run(image, target, options),
    }
}

fn mesh_method(image: &Image, target: Size, options: &Options) -> Result<MethodOutput, Error> {
    let out = retarget(image, target, &options.clone().with_analysis(true))?;
    let analysis = out.analysis.ok_or(Error::Internal(
        "the retargeter kept no analysis although asked to".into(),
    ))?;
    let t = out.image.size();
    Ok(MethodOutput {
        method: Method::Mesh,
        image: out.image,
        stats: MethodStats {
            vertices: Some(out.stats.vertices),
            triangles: Some(out.stats.triangles),
            dof: Some(out.stats.dof),
            folds_first_solve: Some(out.stats.solve.folds_first_solve),
            times: out.stats.times,
        },
        // A canvas taken whole is resampled as a plain resize: measured as that map (its
        // mesh is the two triangles of the canvas, too coarse to tell salient ones apart).
        // Drawn at one scale into `fitted`, the window that fills the output reaches past
        // the source by the ground around it.
        mapping: if analysis
            .mesh
            .structure()
            .is_some_and(crate::structure::Structure::whole_canvas)
        {
            let s = image.size();
            let (w, h) = (s.width as f64, s.height as f64);
            let window = match out.stats.fitted {
                Some([x0, y0, x1, y1]) => {
                    let (sx, sy) = ((x1 - x0) as f64 / w, (y1 - y0) as f64 / h);
                    let (x0, y0) = (x0 as f64 / sx, y0 as f64 / sy);
                    [
                        -x0,
                        -y0,
                        t.width as f64 / sx - x0,
                        t.height as f64 / sy - y0,
                    ]
                }
                None => [0.0, 0.0, w, h],
            };
            Mapping::Affine { window }
        } else {
            Mapping::Warp {
                mesh: analysis.mesh,
                warp: analysis.warp,
            }
        },
        vsm: Some(analysis.vsm),
    })
}

/// `src` scaled to `target`, each axis on its own, through the crate's renderer (bilinear, area
/// filtered where it shrinks): the linear baseline's resampler.
pub fn resize_linear(src: crate::image::ImageRef<'_>, target: Size) -> Image {
    linear::resize(src, target)
}

/// Renders `image` through `mesh` and `warp` (timed into `times.render_ms`) and packs the
/// result of a method that deforms a lattice (grid, axis).
fn lattice_output(
    method: Method,
    image: &Image,
    mesh: Mesh,
    warp: Warp,
    vsm: Vsm,
    mut times: StageTimes,
    folds_first_solve: usize,
) -> MethodOutput {
    let t = std::time::Instant::now();
    let mut out = Image::new(warp.target());
    crate::render::Renderer::new().render(image.as_ref(), &mesh, &warp, &mut out);
    times.render_ms = ms_since(t);
    MethodOutput {
        method,
        image: out,
        stats: MethodStats {
            vertices: Some(mesh.vertices().len()),
            triangles: Some(mesh.triangles().len()),
            dof: Some(mesh.dof()),
            folds_first_solve: Some(folds_first_solve),
            times,
        },
        mapping: Mapping::Warp {
            mesh: Arc::new(mesh),
            warp: Arc::new(warp),
        },
        vsm: Some(Arc::new(vsm)),
    }
}

/// Milliseconds since `t`.
fn ms_since(t: std::time::Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
