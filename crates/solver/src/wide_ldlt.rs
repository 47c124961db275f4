//! [`WideLdlt`]: the accurate M-matrix LDLᵀ of [`crate::AccurateLdlt`] carried out in
//! [`Wide`] numbers (an `f64` mantissa with its own exponent), for solutions that leave the
//! double range.
//!
//! The GTH-style elimination only adds and multiplies non-negative numbers (Schur complement
//! magnitudes `w_ij ← w_ij + w_ik w_jk / d_k`, excesses `s_i ← s_i + w_ik s_k / d_k`, pivots
//! `d_k = s_k + Σ_j w_jk`), and so do the triangular solves of a right-hand side `b ≥ 0`; with
//! the range restriction removed the entrywise relative error bound holds however small the
//! entries get. In double precision, fill entries between separators far apart along a long
//! corridor (≈ e^(−πℓ/w)) underflow, and so does the solution: ψ = e^(−πL/w) is 1e-1364 at
//! 1000 widths. The arithmetic is several times slower than `f64`, so the FEM solver uses this
//! only when the ordinary accurate solve has underflowed.

use std::sync::Arc;

use crate::csc::Pattern;
use crate::error::SolverError;
use crate::mmatrix::{AccurateLdlt, LdltAnalysis, MMatrix, numeric};
use crate::ordering::Ordering;
use crate::wide::Wide;

/// Entrywise-accurate `A = L D Lᵀ` of an [`MMatrix`] in extended-exponent arithmetic.
///
/// ```
/// use harmonic_solver::{MMatrix, Ordering, SymmetricCsc, WideLdlt};
/// // A chain of 3000 unit conductances grounded at every node by ε = 0.5 and fed at node 0:
/// // x decays by λ ≈ 0.5 per node, so x[2999] ≈ 1e-903.
/// let n = 3000;
/// let (mut col_ptr, mut rows) = (vec![0], vec![]);
/// for j in 0..n {
///     if j > 0 { rows.push(j - 1); }
///     if j + 1 < n { rows.push(j + 1); }
///     col_ptr.push(rows.len());
/// }
/// let w = SymmetricCsc::try_new(n, col_ptr, rows.clone(), vec![1.0; rows.len()])?;
/// let m = MMatrix::try_new(w, vec![0.5; n])?;
/// let mut b = vec![0.0; n];
/// b[0] = 1.0;
/// let x = WideLdlt::factor(&m, Ordering::Amd)?.solve(&b)?;
/// assert!(x[n - 1].log10() < -900.0 && !x[n - 1].is_zero());
/// # Ok::<(), harmonic_solver::SolverError>(())
/// ```
#[derive(Debug, Clone)]
pub struct WideLdlt {
    /// `perm[new] = old`.
    perm: Vec<usize>,
    /// `inv[old] = new`.
    inv: Vec<usize>,
    /// Pattern of the factored matrix's off-diagonals, to check refactorisations.
    w_pattern: Arc<Pattern>,
    /// Columns of `−L` (permuted numbering, rows sorted).
    col_ptr: Vec<usize>,
    row_idx: Vec<u32>,
    l: Vec<Wide>,
    /// Pivots `d_j > 0`.
    d: Vec<Wide>,
}

impl WideLdlt {
    /// Factors `m` with the given fill-reducing ordering.
    ///
    /// Fails with [`SolverError::Singular`] when a pivot is zero (a connected block of
    /// unknowns with no excess anywhere; the column named belongs to it).
    pub fn factor(m: &MMatrix, ordering: Ordering) -> Result<Self, SolverError> {
        let a = LdltAnalysis::of(m.offdiag(), ordering)?;
        Self::numeric(
            m,
            a.perm,
            a.inv,
            Arc::clone(m.offdiag().pattern()),
            a.col_ptr,
            a.row_idx,
        )
    }

    /// Factors `m` on the elimination order and pattern of `L` of an ordinary accurate factor
    /// (of a matrix with the same off-diagonal pattern): no ordering or symbolic work is redone.
    pub fn factor_like(like: &AccurateLdlt, m: &MMatrix) -> Result<Self, SolverError> {
        let (perm, inv, pattern, col_ptr, row_idx) = like.structure();
        m.offdiag().check_pattern(pattern)?;
        Self::numeric(
            m,
            perm.to_vec(),
            inv.to_vec(),
            Arc::clone(pattern),
            col_ptr.to_vec(),
            row_idx.to_vec(),
        )
    }

    /// The elimination of `AccurateLdlt` (the same multifrontal code, the same order of
    /// operations), in [`Wide`] numbers.
    fn numeric(
        m: &MMatrix,
        perm: Vec<usize>,
        inv: Vec<usize>,
        w_pattern: Arc<Pattern>,
        col_ptr: Vec<usize>,
        row_idx: Vec<u32>,
    ) -> Result<Self, SolverError> {
        let (l, d) = numeric::<Wide>(m, &perm, &inv, &col_ptr, &row_idx)?;
        Ok(WideLdlt {
            perm,
            inv,
            w_pattern,
            col_ptr,
            row_idx,
            l,
            d,
        })
    }

    /// Refactors for new values of an M-matrix with the same off-diagonal pattern, reusing the
    /// ordering and the pattern of `L`. On error `self` is unchanged.
    pub fn refactor(&mut self, m: &MMatrix) -> Result<(), SolverError> {
        m.offdiag().check_pattern(&self.w_pattern)?;
        *self = Self::numeric(
            m,
            self.perm.clone(),
            self.inv.clone(),
            Arc::clone(&self.w_pattern),
            self.col_ptr.clone(),
            self.row_idx.clone(),
        )?;
        Ok(())
    }

    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.d.len()
    }

    /// The elimination order used: `perm[new] = old`.
    pub fn permutation(&self) -> &[usize] {
        &self.perm
    }

    /// Solves `A x = b`. Entrywise accurate when `b ≥ 0` (then `x ≥ 0`), with no lower limit
    /// on the size of the entries; any finite `b` is accepted.
    pub fn solve(&self, b: &[f64]) -> Result<Vec<Wide>, SolverError> {
        let n = self.n();
        if b.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "right-hand side",
                expected: n,
                found: b.len(),
            });
        }
        if let Some(index) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "right-hand side",
                index,
            });
        }
        let mut y: Vec<Wide> = self
            .perm
            .iter()
            .map(|&old| Wide::from_f64(b[old]))
            .collect();
        let column = |j: usize| {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            self.row_idx[range.clone()].iter().zip(&self.l[range])
        };
        for j in 0..n {
            let yj = y[j];
            if yj.is_zero() {
                continue;
            }
            for (&i, &lij) in column(j) {
                y[i as usize] += lij * yj;
            }
        }
        for j in (0..n).rev() {
            let mut acc = y[j] / self.d[j];
            for (&i, &lij) in column(j) {
                acc += lij * y[i as usize];
            }
            y[j] = acc;
        }
        let mut x = vec![Wide::ZERO; n];
        for (new, &old) in self.perm.iter().enumerate() {
            x[old] = y[new];
        }
        Ok(x)
    }
}
