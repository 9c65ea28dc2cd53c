//! Stage 3: the mesh resizing (§5.2), skipped on reuse, local on update (warm-started from
//! the previous frame's solution).

use super::{ms, Meshed, WithMesh, WithWarp};
use crate::enhance::Enhancement;
use crate::error::Error;
use crate::image::Size;
use crate::mesh::Mesh;
use crate::raster::snap;
use crate::retarget::reuse::Decision;
use crate::saliency::Vsm;
use crate::solve::{EnergyParams, Locator, SalientFit, SolveStats, Solver, Warp};
use glam::DVec2;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;
use std::time::Instant;

/// How much harder than other re-sampled vertices a moved mark's centre is held where the
/// previous warp maps it.
const MARK_CENTRE_HOLD: f64 = 1000.0;

/// Stage 3: the solve, skipped on reuse, local on update.
pub(crate) struct SolveStage {
    solver: Solver,
    target: Size,
    prev: Option<(Arc<Mesh>, Arc<Warp>)>,
    salient_fit: SalientFit,
    /// Content enhancement (§5.4), when it changes anything.
    enhance: Option<Enhancement>,
}

/// What the solve stage hands on.
pub(crate) struct Solved {
    pub warp: Arc<Warp>,
    pub stats: SolveStats,
    /// The decision as carried out (an update whose local solve kept folds became a full
    /// solve: [`Decision::Rebuild`]).
    pub decision: Decision,
}

impl SolveStage {
    pub fn new(params: EnergyParams, target: Size) -> SolveStage {
        SolveStage {
            solver: Solver::new(params),
            target,
            prev: None,
            salient_fit: SalientFit::default(),
            enhance: None,
        }
    }

    /// With content enhancement: every solve is a full one with `δ` per triangle (a local
    /// update's solve has no `δ`).
    pub fn with_enhancement(mut self, enhance: &Enhancement) -> SolveStage {
        self.enhance = (!enhance.is_identity()).then(|| enhance.clone());
        self
    }

    /// The warp for a frame.
    pub fn run(&mut self, m: WithMesh) -> Result<WithWarp, Error> {
        let t = Instant::now();
        let solved = self.solve(&m.sal.vsm, &m.meshed)?;
        let mut times = m.times;
        times.solve_ms = ms(t);
        Ok(WithWarp {
            frame: m.frame,
            sal: m.sal,
            meshed: m.meshed,
            solved,
            times,
        })
    }

    /// The warp for a mesh: the previous one for a kept mesh, a linear map for a canvas taken
    /// whole, a local solve warm-started from the previous warp for an update, else a full
    /// solve.
    fn solve(&mut self, vsm: &Vsm, m: &Meshed) -> Result<Solved, Error> {
        let mesh = &m.mesh;
        if m.decision == Decision::Reuse {
            if let Some(kept) = self.kept(mesh) {
                return Ok(kept);
            }
        }
        // A canvas taken whole has one linear map: nothing to solve (its text floats).
        let canvas = mesh.structure().filter(|s| s.whole_canvas());
        let (warp, stats, decision) = match (&self.enhance, canvas) {
            (None, Some(s)) => {
                let stats = SolveStats {
                    text_blocks: s.text.len(),
                    ..SolveStats::default()
                };
                (Warp::linear(mesh, self.target), stats, Decision::Rebuild)
            }
            _ => match self.local(vsm, m)? {
                Some((warp, stats)) => (warp, stats, Decision::Update),
                // A full solve changes the whole frame, also when it stands in for an update
                // whose local solve kept folds.
                None => {
                    let (warp, stats) = self.full(vsm, mesh)?;
                    (warp, stats, Decision::Rebuild)
                }
            },
        };
        let warp = Arc::new(warp);
        self.prev = Some((mesh.clone(), warp.clone()));
        Ok(Solved {
            warp,
            stats,
            decision,
        })
    }

    /// The previous warp, if it was solved for this very mesh.
    fn kept(&self, mesh: &Arc<Mesh>) -> Option<Solved> {
        let (pm, pw) = self.prev.as_ref()?;
        Arc::ptr_eq(pm, mesh).then(|| Solved {
            warp: pw.clone(),
            stats: SolveStats {
                salient_scale: self.salient_fit.similar,
                salient_fit: self.salient_fit.free,
                ..SolveStats::default()
            },
            decision: Decision::Reuse,
        })
    }

    /// For a mesh updated tile by tile (and no enhancement, whose `δ` a local solve lacks): a
    /// solve of the re-sampled vertices only, the kept ones held where the previous warp put
    /// them; `None` when there is no previous warp or the local solve kept folds.
    fn local(&mut self, vsm: &Vsm, m: &Meshed) -> Result<Option<(Warp, SolveStats)>, Error> {
        if m.decision != Decision::Update || self.enhance.is_some() {
            return Ok(None);
        }
        let Some((pm, pw)) = &self.prev else {
            return Ok(None);
        };
        let mesh = &m.mesh;
        let held: HashMap<u64, DVec2> = pm
            .ids()
            .iter()
            .copied()
            .zip(pw.positions().iter().copied())
            .collect();
        let fixed: Vec<Option<DVec2>> = mesh.ids().iter().map(|id| held.get(id).copied()).collect();
        let anchors = anchors(mesh, &fixed, &pw.locator(pm));
        self.solver
            .solve_local(mesh, vsm, self.target, &fixed, &anchors, self.salient_fit)
    }

    /// The whole energy solved afresh (with `δ` per triangle under enhancement); the salient
    /// fit it found is kept for the frames that reuse its warp.
    fn full(&mut self, vsm: &Vsm, mesh: &Mesh) -> Result<(Warp, SolveStats), Error> {
        let (warp, stats) = match &self.enhance {
            Some(e) => {
                let delta = e.triangle_factors(mesh, vsm);
                let held = e.held(vsm);
                self.solver.solve_enhanced(
                    mesh,
                    held.as_ref().unwrap_or(vsm),
                    self.target,
                    &delta,
                )?
            }
            None => self.solver.solve(mesh, vsm, self.target)?,
        };
        self.salient_fit = SalientFit {
            free: stats.salient_fit,
            similar: stats.salient_scale,
        };
        Ok((warp, stats))
    }
}

/// Where each re-sampled vertex of `mesh` (not `fixed`) is pulled, and how hard: to where the
/// previous warp maps its source point. A moved mark's centre is held much harder: it then
/// lands where the old warp maps it, a smooth function of its position, and the mark moves in
/// the output by as many whole pixels as that says (no extra jumps from re-solving).
fn anchors(mesh: &Mesh, fixed: &[Option<DVec2>], previous: &Locator) -> Vec<Option<(DVec2, f64)>> {
    let centres: HashSet<(u64, u64)> = mesh
        .marks()
        .iter()
        .map(|m| (snap(m.center.x).to_bits(), snap(m.center.y).to_bits()))
        .collect();
    mesh.vertices()
        .iter()
        .zip(fixed)
        .map(|(&p, f)| {
            if f.is_some() {
                return None;
            }
            let k = if centres.contains(&(p.x.to_bits(), p.y.to_bits())) {
                MARK_CENTRE_HOLD
            } else {
                1.0
            };
            previous.map_inside(p).map(|q| (q, k))
        })
        .collect()
}
