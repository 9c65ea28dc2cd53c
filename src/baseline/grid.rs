//! The uniform-grid baseline: scale-and-stretch (Wang et al. 2008, the paper's ref. [1]) on a
//! regular lattice of `α`-px cells, with the same VSM, energy, solver, fold repair and renderer
//! as the mesh. Only the mesh differs, which is what the paper's Table 1 compares.

use super::{ms_since, MethodOutput};
use crate::error::Error;
use crate::image::{Image, Size};
use crate::mesh::Mesh;
use crate::retarget::{Options, StageTimes};
use crate::saliency::VsmBuilder;
use crate::solve::Solver;
use std::time::Instant;

pub(super) fn run(image: &Image, target: Size, options: &Options) -> Result<MethodOutput, Error> {
    let mut times = StageTimes::default();
    let t = Instant::now();
    let vsm = VsmBuilder::new().build(image.as_ref());
    times.vsm_ms = ms_since(t);
    let t = Instant::now();
    let mesh = Mesh::lattice(image.size(), options.alpha as f64);
    times.mesh_ms = ms_since(t);
    let t = Instant::now();
    let (warp, solve) = Solver::new(options.energy.clone()).solve(&mesh, &vsm, target)?;
    times.solve_ms = ms_since(t);
    Ok(super::lattice_output(
        super::Method::Grid,
        image,
        mesh,
        warp,
        vsm,
        times,
        solve.folds_first_solve,
    ))
}
