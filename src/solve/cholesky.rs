//! A sparse symmetric system with a fixed pattern, solved by `faer`'s sparse Cholesky.
//!
//! The symbolic factorization (fill-reducing ordering and elimination structure) depends only on
//! the pattern, i.e. on the mesh topology and its boundary; it is computed once per pattern and
//! kept, and each numeric update (new weights, fold repair, a new frame on the same mesh) only
//! refactors numerically. We use faer's lower-level `SymbolicCholesky` / `factorize_numeric_llt`,
//! the same factorization that `SymbolicLlt::try_new` / `Llt::try_new_with_symbolic` wrap, so
//! that the factor values and the scratch memory are reused rather than allocated per update.

use crate::error::Error;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// `H u = b` with `H` stored as its upper triangle in compressed columns.
#[derive(Default)]
pub(crate) struct SparseSystem {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// For the k-th entry of the assembly order, its index in `values`.
    slots: Vec<u32>,
    symbolic: Option<SymbolicCholesky<usize>>,
    factor: Vec<f64>,
    mem: Option<MemBuffer>,
    /// `factor` holds the factorization of `factored_values` (perhaps not the current ones).
    has_factor: bool,
    factored_values: Vec<f64>,
    /// ... and those are the current values.
    factored: bool,
    columns: FactorColumns,
    update: UpdateScratch,
}

/// The factor's columns, whichever layout faer chose: column `j` holds its diagonal at
/// `diag[j]` of the factor's values and the rows `rows[start[j]..end[j]]` below it at the
/// values that follow (so in the simplicial layout, and within a supernode's dense block).
#[derive(Default)]
struct FactorColumns {
    diag: Vec<usize>,
    start: Vec<usize>,
    end: Vec<usize>,
    rows: Vec<usize>,
    /// Elimination tree: the first row below the diagonal (`usize::MAX` at a root).
    parent: Vec<usize>,
}

impl FactorColumns {
    fn of(symbolic: &SymbolicCholesky<usize>) -> FactorColumns {
        let mut c = FactorColumns::default();
        match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(l) => {
                // Rows sorted within a column, the diagonal first.
                let (cp, ri) = (l.col_ptr(), l.row_idx());
                c.rows.extend_from_slice(ri);
                for j in 0..l.ncols() {
                    c.diag.push(cp[j]);
                    c.start.push(cp[j] + 1);
                    c.end.push(cp[j + 1]);
                }
            }
            SymbolicCholeskyRaw::Supernodal(l) => {
                // A supernode is a dense column-major block: its columns' diagonal block, then
                // the rows of its pattern, the same for all its columns.
                let mut val = 0;
                for s in 0..l.n_supernodes() {
                    let (b, e) = (l.supernode_begin()[s], l.supernode_end()[s]);
                    let pattern = l.supernode(s).pattern();
                    let at = c.rows.len();
                    c.rows.extend(b..e);
                    c.rows.extend_from_slice(pattern);
                    let nrows = e - b + pattern.len();
                    for k in 0..e - b {
                        c.diag.push(val + k * nrows + k);
                        c.start.push(at + k + 1);
                        c.end.push(at + nrows);
                    }
                    val += nrows * (e - b);
                }
            }
        }
        c.parent = (0..c.diag.len())
            .map(|j| {
                c.rows[c.start[j]..c.end[j]]
                    .iter()
                    .copied()
                    .min()
                    .unwrap_or(usize::MAX)
            })
            .collect();
        c
    }
}

impl FactorColumns {
    /// `L Lᵀ + w wᵀ` into the factor values `lx`, for `w` (in the factor's order, zero before
    /// column `start`) whose non-zeros lie on the elimination tree's path from `start`: the
    /// path's columns only (Davis and Hager; CSparse's `cs_updown`). `w` is zero again after.
    /// `None` if a diagonal on the path becomes non-finite or not positive.
    fn rank_one_update(&self, lx: &mut [f64], w: &mut [f64], start: usize) -> Option<()> {
        let mut beta = 1.0f64;
        let mut j = start;
        while j != usize::MAX {
            let p = self.diag[j];
            let alpha = w[j] / lx[p];
            let beta2 = (beta * beta + alpha * alpha).sqrt();
            let delta = beta / beta2;
            let gamma = alpha / (beta2 * beta);
            lx[p] = delta * lx[p] + gamma * w[j];
            // A non-finite change reaches a diagonal on its path (every non-zero of the
            // update lies on it); the factor is then factorized again.
            if !(lx[p].is_finite() && lx[p] > 0.0) {
                return None;
            }
            w[j] = 0.0;
            beta = beta2;
            let rows = &self.rows[self.start[j]..self.end[j]];
            for (l, &i) in lx[p + 1..p + 1 + rows.len()].iter_mut().zip(rows) {
                let w1 = w[i];
                w[i] = w1 - alpha * *l;
                *l = delta * *l + gamma * w1;
            }
            j = self.parent[j];
        }
        Some(())
    }
}

/// Work memory of [`SparseSystem::update_factor`], kept between calls.
#[derive(Default)]
struct UpdateScratch {
    /// Per unknown, its position in `support` (`u32::MAX`: not in it).
    slot: Vec<u32>,
    /// Unknowns whose rows of `H` changed, in the factor's order.
    support: Vec<(usize, usize)>,
    /// The change restricted to `support`, dense, then its Cholesky factor.
    dense: Vec<f64>,
    /// The update vector, in the factor's order.
    w: Vec<f64>,
}

/// The values of `H` now and when it was last factored, in its compressed columns.
struct Change<'a> {
    col_ptr: &'a [usize],
    row_idx: &'a [usize],
    now: &'a [f64],
    was: &'a [f64],
}

impl Change<'_> {
    /// Number of unknowns.
    fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }
}

impl UpdateScratch {
    /// The unknowns whose rows of `H` changed, into `support` in the factor's order (`to_factor`
    /// maps an unknown to its column of the factor) and `slot`; `None` when there are more than
    /// [`MAX_UPDATE_SUPPORT`], for which a factorization is cheaper.
    fn gather_support(
        &mut self,
        change: &Change<'_>,
        to_factor: impl Fn(usize) -> usize,
    ) -> Option<()> {
        let n = change.n();
        self.slot.clear();
        self.slot.resize(n, u32::MAX);
        self.support.clear();
        for j in 0..n {
            for k in change.col_ptr[j]..change.col_ptr[j + 1] {
                if change.now[k] != change.was[k] {
                    for v in [change.row_idx[k], j] {
                        if self.slot[v] == u32::MAX {
                            if self.support.len() == MAX_UPDATE_SUPPORT {
                                return None;
                            }
                            self.slot[v] = 0;
                            self.support.push((to_factor(v), v));
                        }
                    }
                }
            }
        }
        self.support.sort_unstable();
        for (a, &(_, v)) in self.support.iter().enumerate() {
            self.slot[v] = a as u32;
        }
        Some(())
    }

    /// The change restricted to `support`, dense, lower triangle in the factor's order
    /// (column-major), into `dense`.
    fn densify(&mut self, change: &Change<'_>) {
        let m = self.support.len();
        self.dense.clear();
        self.dense.resize(m * m, 0.0);
        for j in 0..change.n() {
            let b = self.slot[j];
            if b == u32::MAX {
                continue;
            }
            for k in change.col_ptr[j]..change.col_ptr[j + 1] {
                let d = change.now[k] - change.was[k];
                if d != 0.0 {
                    let a = self.slot[change.row_idx[k]];
                    let (r, c) = (a.max(b) as usize, a.min(b) as usize);
                    self.dense[c * m + r] = d;
                }
            }
        }
    }

    /// `dense` becomes its Cholesky factor `G`. A negative pivot means a weight went down, a
    /// vanishing one with entries below it a change that is not semi-definite (an off-diagonal
    /// entry that changed alone): `None`, no update then. A vanishing pivot with nothing below
    /// it leaves a zero column (no update along it).
    fn factor_dense(&mut self) -> Option<()> {
        let m = self.support.len();
        let mut scale = 0.0f64;
        for v in &self.dense {
            scale = scale.max(v.abs());
        }
        let tiny = scale * 1e-13;
        let negligible = (tiny * scale).sqrt();
        for c in 0..m {
            let (head, tail) = self.dense.split_at_mut(c * m);
            let col = &mut tail[..m];
            for p in 0..c {
                let pc = &head[p * m..(p + 1) * m];
                let f = pc[c];
                if f != 0.0 {
                    for (x, &y) in col[c..].iter_mut().zip(&pc[c..]) {
                        *x -= f * y;
                    }
                }
            }
            let d = col[c];
            if d < -tiny * 1e3 {
                return None;
            }
            if d <= tiny {
                if col[c + 1..].iter().any(|x| x.abs() > negligible) {
                    return None;
                }
                col[c..].fill(0.0);
                continue;
            }
            let s = d.sqrt();
            col[c..].iter_mut().for_each(|x| *x /= s);
        }
        Some(())
    }

    /// One rank-one update of the factor values `lx` per non-zero column of `G`; how many, or
    /// `None` when one fails (the factor is then half updated and needs a factorization).
    fn rank_one_updates(&mut self, cols: &FactorColumns, lx: &mut [f64]) -> Option<usize> {
        let UpdateScratch {
            slot,
            support,
            dense,
            w,
        } = self;
        let m = support.len();
        w.clear();
        w.resize(slot.len(), 0.0);
        let mut updates = 0;
        for c in 0..m {
            let col = &dense[c * m..(c + 1) * m];
            if col[c] == 0.0 {
                continue;
            }
            for (&x, &(r, _)) in col[c..].iter().zip(&support[c..]) {
                w[r] = x;
            }
            cols.rank_one_update(lx, w, support[c].0)?;
            updates += 1;
        }
        Some(updates)
    }
}

/// How [`SparseSystem::solve_warm`] solved.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Solved {
    /// By rank-one updates of the last factorization, this many.
    Updated(usize),
    /// By a numeric factorization of the current values.
    Factored,
}

/// faer factorizes supernodally (dense blocks) where its flop count per factor entry is above
/// this share of its default threshold. The meshes' systems (a few thousand unknowns, fill
/// from the scale unknowns' coupling) sit just below the default, where the simplicial
/// factorization takes about twice the time of the supernodal one (`cargo bench --bench
/// paper_tables` shows it); a tenth of it puts them on the supernodal side.
const SUPERNODAL_THRESHOLD: SupernodalThreshold = SupernodalThreshold(0.1);

/// Unknowns whose rows may change for an update to be tried instead of a factorization: a
/// repair round boosts a few triangles (tens of unknowns), a text hold a few blocks. One
/// rank-one update walks one path of the elimination tree, 1/70 to 1/120 of a factorization's
/// time on these systems, and there are at most as many as unknowns that changed: up to 64,
/// the updates never cost much more than the factorization they replace.
const MAX_UPDATE_SUPPORT: usize = 64;

impl SparseSystem {
    /// Sets the pattern from the assembly order's `(row, col)` pairs (`row ≤ col`) and computes
    /// the symbolic factorization.
    pub fn set_pattern(&mut self, n: usize, pairs: &[(u32, u32)]) -> Result<(), Error> {
        self.set_pattern_with(n, pairs, SUPERNODAL_THRESHOLD)
    }

    fn set_pattern_with(
        &mut self,
        n: usize,
        pairs: &[(u32, u32)],
        supernodal: SupernodalThreshold,
    ) -> Result<(), Error> {
        // Nothing of the last pattern survives, even if this one fails.
        self.symbolic = None;
        self.has_factor = false;
        self.factored = false;
        // The assembly order sorted by (column, row): bucketed by column, then each column's
        // few entries sorted, which is linear in the pairs but for those short sorts (one
        // comparison sort of them all takes about three times as long on a mesh's pairs).
        let mut start = vec![0u32; n + 1];
        for &(_, j) in pairs {
            start[j as usize + 1] += 1;
        }
        for j in 0..n {
            start[j + 1] += start[j];
        }
        let mut order = vec![0u32; pairs.len()];
        let mut fill = start.clone();
        for (k, &(_, j)) in pairs.iter().enumerate() {
            order[fill[j as usize] as usize] = k as u32;
            fill[j as usize] += 1;
        }
        for j in 0..n {
            order[start[j] as usize..start[j + 1] as usize]
                .sort_unstable_by_key(|&k| pairs[k as usize].0);
        }
        self.n = n;
        self.col_ptr.clear();
        self.col_ptr.resize(n + 1, 0);
        self.row_idx.clear();
        self.slots.clear();
        self.slots.resize(pairs.len(), 0);
        let mut last: Option<(u32, u32)> = None;
        for &k in &order {
            let (i, j) = pairs[k as usize];
            if last != Some((i, j)) {
                self.row_idx.push(i as usize);
                self.col_ptr[j as usize + 1] += 1;
                last = Some((i, j));
            }
            self.slots[k as usize] = (self.row_idx.len() - 1) as u32;
        }
        for j in 0..n {
            self.col_ptr[j + 1] += self.col_ptr[j];
        }
        self.values.clear();
        self.values.resize(self.row_idx.len(), 0.0);
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let symbolic = factorize_symbolic_cholesky(
            sym,
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: supernodal,
                ..Default::default()
            },
        )
        .map_err(|e| Error::Solve(format!("symbolic factorization: {e:?}")))?;
        self.factor.clear();
        self.factor.resize(symbolic.len_val(), 0.0);
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        self.mem = Some(MemBuffer::try_new(req).map_err(|_| Error::Solve("out of memory".into()))?);
        self.columns = FactorColumns::of(&symbolic);
        self.symbolic = Some(symbolic);
        self.has_factor = false;
        self.factored = false;
        Ok(())
    }

    /// Number of unknowns.
    #[allow(dead_code)]
    pub fn n(&self) -> usize {
        self.n
    }

    /// Stored entries of the upper triangle.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Zeroes the values before a numeric assembly.
    pub fn clear_values(&mut self) {
        self.values.fill(0.0);
        self.factored = false;
    }

    /// Adds the value of the k-th entry of the assembly order.
    #[inline]
    pub fn add(&mut self, k: usize, v: f64) {
        self.values[self.slots[k] as usize] += v;
        self.factored = false;
    }

    /// Numeric Cholesky factorization of the current values.
    pub fn factorize(&mut self) -> Result<(), Error> {
        let symbolic = self
            .symbolic
            .as_ref()
            .ok_or_else(|| Error::Solve("no pattern".into()))?;
        let mem = self
            .mem
            .as_mut()
            .ok_or_else(|| Error::Solve("no pattern".into()))?;
        let sym = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let a = SparseColMatRef::new(sym, &self.values);
        // faer writes into the factor before it finds a pivot that is not positive.
        self.has_factor = false;
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.factor,
                a,
                Side::Upper,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(mem),
                Default::default(),
            )
            .map_err(|e| Error::Solve(format!("numeric factorization: {e:?}")))?;
        self.has_factor = true;
        self.factored = true;
        self.factored_values.clear();
        self.factored_values.extend_from_slice(&self.values);
        Ok(())
    }

    /// Solves in place (`rhs` becomes the solution), updating the last factorization where the
    /// values changed in a few rows only.
    ///
    /// A fold-repair round raises the weights of a few triangles and a text hold those of a few
    /// blocks: the new matrix is the factored one plus a positive semi-definite change on a few
    /// tens of unknowns. Its Cholesky factor `G` (dense on those unknowns, in the factor's
    /// order) gives `H' = L Lᵀ + Σ g gᵀ`, and each `g` is a rank-one update of `L` along one
    /// path of the elimination tree (Davis and Hager; CSparse's `cs_updown`): a few hundred
    /// columns each, where a factorization touches every column. Anything else (a change that
    /// lowers a weight, too many rows) factorizes the current values.
    pub fn solve_warm(&mut self, rhs: &mut [f64]) -> Result<Solved, Error> {
        let mut how = Solved::Factored;
        if !self.factored {
            match self.has_factor.then(|| self.update_factor()).flatten() {
                Some(updates) => {
                    self.factored = true;
                    how = Solved::Updated(updates);
                }
                None => self.factorize()?,
            }
        }
        self.solve(rhs)?;
        Ok(how)
    }

    /// Brings the factor from `factored_values` to `values` by rank-one updates; how many, or
    /// `None` (the factor then needs a factorization) where that does not apply.
    fn update_factor(&mut self) -> Option<usize> {
        let symbolic = self.symbolic.as_ref()?;
        let inv = symbolic.perm().map(|p| p.arrays().1);
        let change = Change {
            col_ptr: &self.col_ptr,
            row_idx: &self.row_idx,
            now: &self.values,
            was: &self.factored_values,
        };
        let u = &mut self.update;
        u.gather_support(&change, |i| inv.map_or(i, |inv| inv[i]))?;
        u.densify(&change);
        u.factor_dense()?;
        let updates = u.rank_one_updates(&self.columns, &mut self.factor)?;
        self.factored_values.copy_from_slice(&self.values);
        Some(updates)
    }

    /// Solves in place: `rhs` becomes the solution.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<(), Error> {
        if !self.factored {
            return Err(Error::Solve("solve before factorization".into()));
        }
        let symbolic = self
            .symbolic
            .as_ref()
            .ok_or_else(|| Error::Solve("no pattern".into()))?;
        let mem = self
            .mem
            .as_mut()
            .ok_or_else(|| Error::Solve("no pattern".into()))?;
        let llt = LltRef::<'_, usize, f64>::new(symbolic, &self.factor);
        let rhs_mat = MatMut::from_column_major_slice_mut(rhs, self.n, 1);
        llt.solve_in_place_with_conj(Conj::No, rhs_mat, Par::Seq, MemStack::new(mem));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_small_spd_system_with_repeated_entries() {
        // H = [[4, 1, 0], [1, 3, 1], [0, 1, 2]], entries given in pieces.
        let pairs = [(0, 0), (0, 1), (1, 1), (1, 2), (2, 2), (0, 0), (1, 1)];
        let vals = [3.0, 1.0, 2.0, 1.0, 2.0, 1.0, 1.0];
        let mut s = SparseSystem::default();
        s.set_pattern(3, &pairs).unwrap();
        assert_eq!(s.nnz(), 5);
        s.clear_values();
        for (k, &v) in vals.iter().enumerate() {
            s.add(k, v);
        }
        s.factorize().unwrap();
        let x = [1.0, -2.0, 0.5];
        let mut b = vec![
            4.0 * x[0] + x[1],
            x[0] + 3.0 * x[1] + x[2],
            x[1] + 2.0 * x[2],
        ];
        s.solve(&mut b).unwrap();
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-12, "{b:?}");
        }
    }

    /// A 12×12 grid's Laplacian plus a diagonal: its pairs (i ≤ j) and values.
    fn grid_system(extra: &[((u32, u32), f64)]) -> (Vec<(u32, u32)>, Vec<f64>) {
        let (side, mut pairs, mut vals) = (12u32, vec![], vec![]);
        for y in 0..side {
            for x in 0..side {
                let i = y * side + x;
                pairs.push((i, i));
                vals.push(0.1 + (i % 7) as f64 * 0.01);
                for j in [
                    (x + 1 < side).then(|| i + 1),
                    (y + 1 < side).then(|| i + side),
                ]
                .into_iter()
                .flatten()
                {
                    // (x_i − x_j)² with weight 1 + i/100.
                    let w = 1.0 + i as f64 / 100.0;
                    pairs.extend([(i, i), (j, j), (i, j)]);
                    vals.extend([w, w, -w]);
                }
            }
        }
        for &(pair, v) in extra {
            pairs.push(pair);
            vals.push(v);
        }
        (pairs, vals)
    }

    /// A system on the grid's pattern in the layout asked for.
    fn system(pairs: &[(u32, u32)], supernodal: bool) -> SparseSystem {
        let threshold = if supernodal {
            SupernodalThreshold::FORCE_SUPERNODAL
        } else {
            SupernodalThreshold::FORCE_SIMPLICIAL
        };
        let mut s = SparseSystem::default();
        s.set_pattern_with(144, pairs, threshold).unwrap();
        let raw = s.symbolic.as_ref().unwrap().raw();
        assert_eq!(
            matches!(raw, SymbolicCholeskyRaw::Supernodal(_)),
            supernodal
        );
        s
    }

    /// Assembles `vals` and solves for `b`.
    fn solve(s: &mut SparseSystem, vals: &[f64], b: &[f64]) -> Result<(Solved, Vec<f64>), Error> {
        s.clear_values();
        for (k, &v) in vals.iter().enumerate() {
            s.add(k, v);
        }
        let mut x = b.to_vec();
        s.solve_warm(&mut x).map(|how| (how, x))
    }

    /// `x` is what a fresh factorization of `vals` gives for `b`.
    fn assert_solves(x: &[f64], pairs: &[(u32, u32)], vals: &[f64], b: &[f64]) {
        let mut s = SparseSystem::default();
        s.set_pattern(144, pairs).unwrap();
        let (how, fresh) = solve(&mut s, vals, b).unwrap();
        assert_eq!(how, Solved::Factored);
        for (u, v) in x.iter().zip(&fresh) {
            assert!((u - v).abs() < 1e-10 * v.abs().max(1.0), "{u} vs {v}");
        }
    }

    /// Raising the weight of a few terms updates the factor instead of factorizing again, and
    /// gives the solution a fresh factorization gives; lowering one factorizes. In both of
    /// faer's layouts.
    #[test]
    fn a_few_raised_weights_update_the_factor() {
        // Terms whose weights change: (x_13 − x_14)², (x_13 − x_25)² and x_100².
        let extra = [
            ((13, 13), 0.0),
            ((14, 14), 0.0),
            ((13, 14), 0.0),
            ((13, 13), 0.0),
            ((25, 25), 0.0),
            ((13, 25), 0.0),
            ((100, 100), 0.0),
        ];
        let (pairs, vals0) = grid_system(&extra);
        let b: Vec<f64> = (0..144).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
        let k = vals0.len() - extra.len();
        for supernodal in [false, true] {
            let mut s = system(&pairs, supernodal);
            let mut vals = vals0.clone();
            assert_eq!(solve(&mut s, &vals, &b).unwrap().0, Solved::Factored);
            for (d, v) in [3.0, 3.0, -3.0, 0.5, 0.5, -0.5, 40.0]
                .iter()
                .zip(&mut vals[k..])
            {
                *v += d;
            }
            let (how, x) = solve(&mut s, &vals, &b).unwrap();
            assert!(matches!(how, Solved::Updated(3)), "{how:?}");
            assert_solves(&x, &pairs, &vals, &b);
            // Lowering a weight again needs a factorization.
            vals[k + 6] -= 20.0;
            let (how, x) = solve(&mut s, &vals, &b).unwrap();
            assert_eq!(how, Solved::Factored);
            assert_solves(&x, &pairs, &vals, &b);
        }
    }

    /// A change that is not positive semi-definite (an off-diagonal entry alone, or one
    /// beside an unchanged diagonal) is not an update: the solution is still the current
    /// system's.
    #[test]
    fn an_indefinite_change_factorizes() {
        let (pairs, vals0) = grid_system(&[((13, 14), 0.0), ((14, 14), 0.0)]);
        let b: Vec<f64> = (0..144).map(|i| (i % 5) as f64 - 2.0).collect();
        let k = vals0.len() - 2;
        for supernodal in [false, true] {
            // Off-diagonal alone; then off-diagonal with a raise of one diagonal only.
            for change in [[0.5, 0.0], [0.5, 2.0]] {
                let mut s = system(&pairs, supernodal);
                let mut vals = vals0.clone();
                solve(&mut s, &vals, &b).unwrap();
                vals[k] += change[0];
                vals[k + 1] += change[1];
                let (how, x) = solve(&mut s, &vals, &b).unwrap();
                assert_eq!(how, Solved::Factored, "{change:?}");
                assert_solves(&x, &pairs, &vals, &b);
            }
        }
    }

    /// A factorization that fails (a matrix that is not positive definite) leaves no factor
    /// for a later update to build on.
    #[test]
    fn a_failed_factorization_leaves_no_factor_to_update() {
        let (pairs, vals) = grid_system(&[((100, 100), 0.0)]);
        let k = vals.len() - 1;
        let b: Vec<f64> = (0..144).map(|i| (i % 3) as f64).collect();
        let mut s = SparseSystem::default();
        s.set_pattern(144, &pairs).unwrap();
        solve(&mut s, &vals, &b).unwrap();
        // Twice the matrix but for one unknown, whose pivot fails: the factor's columns before
        // it hold another matrix's values. That unknown is off the path an update from unknown
        // 100 walks, and after its start, so that the update would meet only positive pivots.
        let (fwd, inv) = s.symbolic.as_ref().unwrap().perm().unwrap().arrays();
        let start = inv[100];
        let mut on_path = [false; 144];
        let mut j = start;
        while j != usize::MAX {
            on_path[j] = true;
            j = s.columns.parent[j];
        }
        let fail = (start + 1..144).find(|&j| !on_path[j]).unwrap();
        let unknown = fwd[fail] as u32;
        let mut bad: Vec<f64> = vals.iter().map(|v| 2.0 * v).collect();
        bad[pairs.iter().position(|&p| p == (unknown, unknown)).unwrap()] -= 1e3;
        assert!(solve(&mut s, &bad, &b).is_err());
        let mut good = vals.clone();
        good[k] += 1.0;
        let (how, x) = solve(&mut s, &good, &b).unwrap();
        assert_eq!(how, Solved::Factored);
        assert_solves(&x, &pairs, &good, &b);
    }
}
