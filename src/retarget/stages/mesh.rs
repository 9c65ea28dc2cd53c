//! Stage 2: the reuse decision ([`crate::retarget::reuse::decide`]) and the mesh (§5.1):
//! built, updated tile by tile, or kept.

use super::{ms, WithMesh, WithVsm};
use crate::error::Error;
use crate::image::Image;
use crate::mesh::{IncrementalMesh, Mark, Mesh, MeshOptions};
use crate::retarget::reuse::{decide, Built, Decision, Incoming, Plan, ReuseOptions};
use crate::saliency::Vsm;
use crate::structure::{Scene, Structure};
use crate::tiles::TileMask;
use crate::vector::Binding;
use glam::DVec2;
use std::sync::Arc;
use std::time::Instant;

/// Stage 2: the mesh, and what it was built for.
pub(crate) struct MeshStage {
    options: MeshOptions,
    /// Detect lines and text and build the mesh around them.
    structure: bool,
    reuse: ReuseOptions,
    built: Option<Built>,
    /// The id the next new vertex gets (ids stay unique across rebuilds, so a stream's later
    /// stages can tell a kept vertex from a new one).
    next_id: u64,
    /// Scratch of the reuse decision.
    scratch: Vec<bool>,
    /// The scene of the last canvas taken whole: a stream keeps what stays of its text bands
    /// ([`Bands::kept`]) while the scene stands, so that its plot does not move.
    scene: Option<Scene>,
}

/// What the mesh stage hands on.
pub(crate) struct Meshed {
    pub mesh: Arc<Mesh>,
    pub decision: Decision,
    /// The tiles whose key points were re-sampled (for [`Decision::Update`]).
    pub region: TileMask,
    /// Small marks of this frame that the mesh does not ring (they moved or appeared since
    /// it was built): drawn at their own size over the warp ([`crate::render::Floating`]).
    pub floating: Arc<Vec<Mark>>,
}

impl MeshStage {
    pub fn new(options: MeshOptions, reuse: ReuseOptions, structure: bool) -> MeshStage {
        MeshStage {
            options,
            structure,
            reuse,
            built: None,
            next_id: 0,
            scratch: Vec::new(),
            scene: None,
        }
    }

    /// The mesh for a frame, with its vector marks' centres as vertices and rings around
    /// those that stand alone (§5.3).
    pub fn run(&mut self, m: WithVsm) -> Result<WithMesh, Error> {
        let t = Instant::now();
        let bind = Binding::of(m.frame.marks.as_deref(), m.frame.image.size());
        let analysed = m.whole.as_ref().unwrap_or(&m.frame.image);
        let meshed = self.mesh_for(&m.sal.vsm, m.sal.fresh, analysed, &bind);
        let mut times = m.times;
        times.mesh_ms = ms(t);
        Ok(WithMesh {
            frame: m.frame,
            sal: m.sal,
            meshed,
            times,
        })
    }

    /// Carries out the reuse policy's plan for `vsm`: other points or rings than the current
    /// mesh's, or a local update touching a point, rebuild.
    fn mesh_for(&mut self, vsm: &Arc<Vsm>, fresh: bool, image: &Image, bind: &Binding) -> Meshed {
        let now = Incoming {
            vsm,
            fresh,
            points: &bind.points,
            rings: &bind.rings,
        };
        let plan = decide(
            self.built.as_ref(),
            &now,
            &self.reuse,
            self.options.regions,
            &mut self.scratch,
        );
        let unchanged = TileMask::new(vsm.size(), self.reuse.tile_px);
        let (built, decision, region) = match (plan, self.built.as_mut()) {
            (Plan::Reuse { marks }, Some(b)) => {
                if let Some(marks) = marks {
                    b.floating = Arc::new(unringed(marks, &b.mesh));
                }
                b.last = vsm.clone();
                (b, Decision::Reuse, unchanged)
            }
            (Plan::Update { region, marks }, Some(b)) => {
                let mesh = Arc::new(b.inc.update(vsm, &self.options, &region));
                self.next_id = b.inc.next_id();
                Arc::make_mut(&mut b.reference).copy_tiles_from(vsm, &region);
                b.floating = Arc::new(unringed(marks, &mesh));
                b.mesh = mesh;
                b.last = vsm.clone();
                (b, Decision::Update, region)
            }
            _ => {
                let fresh = self.build(vsm, image, bind);
                let b = self.built.insert(fresh);
                (b, Decision::Rebuild, unchanged)
            }
        };
        Meshed {
            mesh: built.mesh.clone(),
            decision,
            region,
            floating: built.floating.clone(),
        }
    }

    /// A mesh built afresh for `vsm` (and, with structure on, the lines and text of `image`).
    fn build(&mut self, vsm: &Arc<Vsm>, image: &Image, bind: &Binding) -> Built {
        let (points, rings) = (&bind.points, &bind.rings);
        let mut structure = self
            .structure
            .then(|| Structure::detect_with(image.as_ref(), self.options.regions));
        if let Some(s) = structure.as_mut().filter(|s| s.whole_canvas()) {
            let now = std::mem::take(&mut s.bands);
            s.bands = Scene::keep(&mut self.scene, image.size(), &s.text, now);
        }
        let (inc, mesh) = match structure {
            Some(s) if s.whole_canvas() && points.is_empty() && rings.is_empty() => {
                IncrementalMesh::canvas(vsm.size(), &s, self.next_id)
            }
            s => IncrementalMesh::build_with_marks(
                vsm,
                s.as_ref(),
                points,
                rings,
                &self.options,
                self.next_id,
            ),
        };
        self.next_id = inc.next_id();
        Built {
            inc,
            mesh: Arc::new(mesh),
            reference: vsm.clone(),
            last: vsm.clone(),
            points: points.clone(),
            rings: rings.clone(),
            floating: Arc::default(),
        }
    }
}

/// The marks of `current` that no mark of `mesh` rings: a mark whose box lies inside the ring
/// of one of the mesh's marks, centred within a pixel and a half of it, is still carried by
/// that ring's fan (the fan covers the whole ring).
fn unringed(current: Vec<Mark>, mesh: &Mesh) -> Vec<Mark> {
    current
        .into_iter()
        .filter(|c| {
            !mesh.marks().iter().any(|m| {
                let [x0, y0, x1, y1] = c.bbox.map(|v| v as f64);
                let r2 = m.ring_radius * m.ring_radius;
                m.center.distance(c.center) <= 1.5
                    && [(x0, y0), (x1, y0), (x0, y1), (x1, y1)]
                        .iter()
                        .all(|&(x, y)| DVec2::new(x, y).distance_squared(m.center) <= r2)
            })
        })
        .collect()
}
