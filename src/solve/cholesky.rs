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
    SymmetricOrdering,
};
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
    factored: bool,
}

impl SparseSystem {
    /// Sets the pattern from the assembly order's `(row, col)` pairs (`row ≤ col`) and computes
    /// the symbolic factorization.
    pub fn set_pattern(&mut self, n: usize, pairs: &[(u32, u32)]) -> Result<(), Error> {
        let mut order: Vec<u32> = (0..pairs.len() as u32).collect();
        order.sort_unstable_by_key(|&k| {
            let (i, j) = pairs[k as usize];
            (j, i)
        });
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
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| Error::Solve(format!("symbolic factorization: {e:?}")))?;
        self.factor.clear();
        self.factor.resize(symbolic.len_val(), 0.0);
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        self.mem = Some(MemBuffer::try_new(req).map_err(|_| Error::Solve("out of memory".into()))?);
        self.symbolic = Some(symbolic);
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
        self.factored = true;
        Ok(())
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
}
