//! Text held at exactly its size: then it is copied crisp, where a few per cent short of it
//! is resampled and blurs.
//!
//! After the repair rounds, a text block that the solve brought near the scale it is pulled to
//! is held there much more firmly and the system solved again. In stages: first every block
//! near its target, then small type a little further from it (small glyphs are the first to
//! become illegible when resampled, a large title reads well a third smaller). Where a stage
//! leaves folds, the blocks it held across the squeeze from them are released and it tries
//! again; a stage that cannot settle is undone, and the stages before it stand.

use super::boundary::FIXED;
use super::{Solution, SolveStats, Solver};
use crate::error::Error;
use crate::image::Size;
use crate::mesh::Mesh;

/// A text block that a solve brought to at least this share of its target scale is then held
/// at the target ([`TEXT_HOLD`] times as firmly). Text at exactly its size is copied crisp,
/// a few per cent short of it is resampled and blurs; a block this near its target costs the
/// layout little to be held at it.
const PROMOTE: f64 = 0.85;
/// How much more firmly than [`super::EnergyParams::text_strength`] a held block keeps its
/// scale: enough that the solve settles at the target instead of a few per cent short of it.
const TEXT_HOLD: f64 = 100.0;
/// Small type (glyphs of [`SMALL_GLYPH_PX`] or less) is held from this share of its target
/// on, once the rest is held. At 0.75 a 12-px legend already reads 9 px tall, about the least
/// OCR (or a reader) makes out; a 20-px title still reads at 0.65, so larger type need not be
/// held from that far.
const PROMOTE_SMALL: f64 = 0.75;
/// Glyph height of small type: legends and tick labels (about 12 px on the charts this is
/// made for), not titles, which read well smaller.
const SMALL_GLYPH_PX: u32 = 13;

/// Which text [`Solver::hold_text`] holds.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum HoldStage {
    /// Every block near its target.
    All,
    /// Small type further from it.
    Small,
}

/// Solves with held text before a hold stage is given up. Each after the first has released
/// the blocks across the squeeze from the folds the last one left, so a few of them either
/// settle or show that the stage has no room.
const HOLD_ATTEMPTS: usize = 3;

impl Solver {
    /// Holds text near its target at it, stage by stage, while the solution `sol` has no
    /// folds; counts the blocks held into `stats`.
    pub(super) fn hold_text_in_stages(
        &mut self,
        mesh: &Mesh,
        target: Size,
        sol: &mut Solution,
        stats: &mut SolveStats,
    ) -> Result<(), Error> {
        for stage in [HoldStage::All, HoldStage::Small] {
            if !sol.folded.is_empty() {
                break;
            }
            self.hold_stage(mesh, target, stage, sol, stats)?;
        }
        stats.text_held = self.text_hold.iter().filter(|&&h| h > 1.0).count();
        Ok(())
    }

    /// One stage: holds its blocks and solves, releasing where folds remain, up to
    /// [`HOLD_ATTEMPTS`] times; where that does not settle, the solution before the stage
    /// stands.
    fn hold_stage(
        &mut self,
        mesh: &Mesh,
        target: Size,
        stage: HoldStage,
        sol: &mut Solution,
        stats: &mut SolveStats,
    ) -> Result<(), Error> {
        // What stands if this stage cannot settle: taken before it holds anything.
        let earlier = self.text_hold.clone();
        if self.hold_text(mesh, stage) == 0 {
            return Ok(());
        }
        // Holding changes the holds only: the rest of what stands is as it was.
        let before = (sol.clone(), self.rhs.clone(), self.boost.clone());
        for _ in 0..HOLD_ATTEMPTS {
            *sol = self.numeric_solve(mesh)?;
            self.repair_rounds(mesh, sol, stats)?;
            if sol.folded.is_empty() {
                return Ok(());
            }
            // Where folds remain, the held blocks across the squeeze from them go back to
            // their usual firmness.
            if !self.release_text_at(mesh, target, &sol.folded, &earlier) {
                break;
            }
        }
        // No room after all.
        (*sol, self.rhs, self.boost) = before;
        self.text_hold = earlier;
        Ok(())
    }

    /// Releases the blocks this stage held (not held in `earlier`) that lie across the
    /// squeeze from a folded triangle (the same rows where the width shrinks, the same columns
    /// where the height does), or all of this stage's if none does; whether any was held.
    fn release_text_at(
        &mut self,
        mesh: &Mesh,
        target: Size,
        folded: &[usize],
        earlier: &[f64],
    ) -> bool {
        let Some(st) = mesh.structure() else {
            return false;
        };
        let (rows, cols) = (
            target.width < mesh.size().width,
            target.height < mesh.size().height,
        );
        let spans: Vec<[f64; 4]> = folded
            .iter()
            .map(|&t| {
                let p = mesh.triangle_points(t);
                let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
                [lo.x, lo.y, hi.x, hi.y]
            })
            .collect();
        let mut released = false;
        for ((b, hold), &was) in st.text.iter().zip(self.text_hold.iter_mut()).zip(earlier) {
            if was > 1.0 {
                continue; // held by an earlier stage, which settled
            }
            let across = spans.iter().any(|f| {
                (rows && (b.y0 as f64) < f[3] && (b.y1 as f64) > f[1])
                    || (cols && (b.x0 as f64) < f[2] && (b.x1 as f64) > f[0])
            });
            if across && *hold > 1.0 {
                *hold = 1.0;
                released = true;
            }
        }
        if !released {
            for (hold, &was) in self.text_hold.iter_mut().zip(earlier) {
                if was <= 1.0 && *hold > 1.0 {
                    *hold = 1.0;
                    released = true;
                }
            }
        }
        released
    }

    /// Holds every text block of `stage` that the last solve (in `rhs`) brought near its
    /// target and that is not held yet; how many.
    fn hold_text(&mut self, mesh: &Mesh, stage: HoldStage) -> usize {
        let mut held = 0;
        for (k, b) in self.layout.blocks.iter().enumerate() {
            if b[2] == FIXED {
                continue;
            }
            let target = self.text_targets.get(k).copied().unwrap_or(1.0);
            if self.text_hold[k] > 1.0 {
                continue;
            }
            let promote = match stage {
                HoldStage::All => PROMOTE,
                HoldStage::Small => {
                    let glyph = mesh.structure().and_then(|st| st.text.get(k));
                    if glyph.is_none_or(|t| t.line_height > SMALL_GLYPH_PX) {
                        continue;
                    }
                    PROMOTE_SMALL
                }
            };
            if self.rhs[b[2] as usize] >= promote * target {
                self.text_hold[k] = TEXT_HOLD;
                held += 1;
            }
        }
        held
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::mesh::MeshOptions;
    use crate::saliency::VsmBuilder;
    use crate::solve::boundary::Layout;
    use crate::structure::{Structure, TextBlock};

    /// The first stage holds any block the solve brought to [`PROMOTE`] of its target, the
    /// second small type from [`PROMOTE_SMALL`] on; larger type that far short, or any type
    /// further, is left to the energy.
    #[test]
    fn stages_hold_blocks_by_how_near_their_target_and_their_size() {
        let size = Size::new(400, 300).unwrap();
        let vsm = VsmBuilder::new().build(Image::filled(size, [255; 4]).as_ref());
        // (glyph height, the share of its target the solve brought a block to)
        let cases = [(12, 0.9), (12, 0.8), (20, 0.8), (12, 0.7), (20, 0.9)];
        let text = (0..cases.len() as u32)
            .map(|k| TextBlock {
                x0: 40 + 20 * k,
                y0: 20 + 55 * k,
                x1: 200,
                y1: 20 + 55 * k + cases[k as usize].0,
                line_height: cases[k as usize].0,
                sideways: false,
            })
            .collect();
        let st = Structure {
            text,
            ..Structure::default()
        };
        let mesh = Mesh::build_with(&vsm, &st, &MeshOptions::default());
        let mut solver = Solver {
            layout: Layout::new(&mesh, size),
            text_targets: vec![0.5; cases.len()],
            text_hold: vec![1.0; cases.len()],
            ..Solver::default()
        };
        solver.rhs = vec![0.0; solver.layout.n];
        for (k, &(_, share)) in cases.iter().enumerate() {
            let s = solver.layout.blocks[k][2];
            assert_ne!(s, FIXED, "block {k} has a scale of its own");
            solver.rhs[s as usize] = share * 0.5;
        }
        assert_eq!(solver.hold_text(&mesh, HoldStage::All), 2);
        assert_eq!(solver.hold_text(&mesh, HoldStage::Small), 1);
        let held: Vec<bool> = solver.text_hold.iter().map(|&h| h == TEXT_HOLD).collect();
        assert_eq!(held, [true, true, false, false, true]);
    }
}
