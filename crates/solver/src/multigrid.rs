//! Geometric multigrid: V-cycles over nested levels, as the preconditioner of conjugate
//! gradients ([`crate::pcg_with`]).
//!
//! The levels are the caller's: one matrix per level (a coarse mesh and its uniform
//! refinements, each discretised on its own) and the prolongations between them (P1
//! interpolation: a fine unknown at a coarse vertex takes its value, one at an edge midpoint
//! the mean of the edge's two ends). One V-cycle, from the finest level down:
//!
//! 1. `ν` forward Gauss–Seidel sweeps on `A x = b` from `x = 0`;
//! 2. the residual restricted to the next level by `Pᵀ`, the cycle run there (the coarsest
//!    level is solved by its Cholesky factor), the correction prolonged by `P` and added;
//! 3. `ν` backward Gauss–Seidel sweeps.
//!
//! Backward after forward makes the cycle a symmetric positive definite operator, so
//! conjugate gradients can use it; on P1 Laplace problems it reduces the error by a fixed
//! factor per iteration whatever the number of levels, so the work grows linearly with the
//! unknowns.

use crate::csc::SymmetricCsc;
use crate::direct::Cholesky;
use crate::error::{SolverError, StructureIssue};
use crate::pcg::{PcgReport, Precondition, pcg_with};

/// The interpolation from a coarse level's unknowns to a finer level's, by rows: fine
/// unknown `i` is `Σ values[k] · coarse[columns[k]]` over `k` in `row_ptr[i]..row_ptr[i+1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Prolongation {
    coarse: usize,
    row_ptr: Vec<usize>,
    columns: Vec<u32>,
    values: Vec<f64>,
}

impl Prolongation {
    /// Checks and keeps the rows: `row_ptr` starts at 0, never decreases and ends at the
    /// length of `columns` and `values`; columns are below `coarse`; values are finite.
    /// Errors name the fine unknown (as the structure's "column") where the rows go wrong.
    pub fn try_new(
        coarse: usize,
        row_ptr: Vec<usize>,
        columns: Vec<u32>,
        values: Vec<f64>,
    ) -> Result<Self, SolverError> {
        let bad = |column, issue| Err(SolverError::InvalidStructure { column, issue });
        if row_ptr.first() != Some(&0) {
            return bad(0, StructureIssue::ColPtrStart);
        }
        if let Some(i) = row_ptr.windows(2).position(|w| w[1] < w[0]) {
            return bad(i, StructureIssue::ColPtrDecreasing);
        }
        let end = row_ptr.last().copied().unwrap_or(0);
        if end != columns.len() || end != values.len() {
            return bad(
                row_ptr.len().saturating_sub(2),
                StructureIssue::NnzMismatch {
                    col_ptr_end: end,
                    row_idx_len: columns.len(),
                    values_len: values.len(),
                },
            );
        }
        for (i, w) in row_ptr.windows(2).enumerate() {
            if let Some(&c) = columns[w[0]..w[1]].iter().find(|&&c| c as usize >= coarse) {
                return bad(i, StructureIssue::RowOutOfBounds { row: c as usize });
            }
        }
        if let Some(index) = values.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "prolongation",
                index,
            });
        }
        Ok(Self {
            coarse,
            row_ptr,
            columns,
            values,
        })
    }

    /// Unknowns of the fine level (rows).
    pub fn fine_len(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// Unknowns of the coarse level (columns).
    pub fn coarse_len(&self) -> usize {
        self.coarse
    }

    /// `coarse = Pᵀ fine` (the restriction of a residual).
    fn restrict(&self, fine: &[f64], coarse: &mut [f64]) {
        coarse.fill(0.0);
        for (i, w) in self.row_ptr.windows(2).enumerate() {
            let r = fine[i];
            for k in w[0]..w[1] {
                coarse[self.columns[k] as usize] += self.values[k] * r;
            }
        }
    }

    /// `fine += P coarse` (a coarse correction added).
    fn add_prolonged(&self, coarse: &[f64], fine: &mut [f64]) {
        for (i, w) in self.row_ptr.windows(2).enumerate() {
            let mut s = 0.0;
            for k in w[0]..w[1] {
                s += self.values[k] * coarse[self.columns[k] as usize];
            }
            fine[i] += s;
        }
    }
}

/// Options of a [`Multigrid`] cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MultigridOptions {
    /// Gauss–Seidel sweeps before and after each coarse correction (default 1).
    pub sweeps: usize,
}

impl Default for MultigridOptions {
    fn default() -> Self {
        Self { sweeps: 2 }
    }
}

/// One level above the coarsest: its matrix and the prolongation from the level below.
#[derive(Debug)]
struct Level {
    a: SymmetricCsc,
    inv_diag: Vec<f64>,
    from_below: Prolongation,
}

/// A multigrid V-cycle over a coarsest level solved directly and finer levels smoothed by
/// Gauss–Seidel; a [`Precondition`] for [`pcg_with`] (see the [module](self) notes).
#[derive(Debug)]
pub struct Multigrid {
    coarsest: Cholesky,
    levels: Vec<Level>,
    opts: MultigridOptions,
}

impl Multigrid {
    /// The cycle over `coarsest` (the factor of the coarsest level's matrix) and `levels`,
    /// ordered from coarse to fine, each the level's matrix with the prolongation from the
    /// level below it into it.
    ///
    /// Errors if a prolongation's sizes do not match the levels it joins, a matrix holds a
    /// non-finite value, or a diagonal entry is not positive (the smoother divides by it).
    pub fn new(
        coarsest: Cholesky,
        levels: Vec<(SymmetricCsc, Prolongation)>,
        opts: MultigridOptions,
    ) -> Result<Self, SolverError> {
        let mut below = coarsest.symbolic().n();
        let mut built = Vec::with_capacity(levels.len());
        for (a, from_below) in levels {
            if from_below.coarse_len() != below {
                return Err(SolverError::DimensionMismatch {
                    what: "prolongation columns (unknowns of the level below)",
                    expected: below,
                    found: from_below.coarse_len(),
                });
            }
            if from_below.fine_len() != a.n() {
                return Err(SolverError::DimensionMismatch {
                    what: "prolongation rows (unknowns of the level)",
                    expected: a.n(),
                    found: from_below.fine_len(),
                });
            }
            if let Some(index) = a.first_non_finite() {
                return Err(SolverError::NonFinite {
                    what: "matrix values",
                    index,
                });
            }
            let diag = a.diagonal();
            if let Some(column) = diag.iter().position(|&d| d <= 0.0) {
                return Err(if diag[column] == 0.0 {
                    SolverError::Singular { column }
                } else {
                    SolverError::NotPositiveDefinite { column }
                });
            }
            below = a.n();
            built.push(Level {
                inv_diag: diag.iter().map(|d| 1.0 / d).collect(),
                a,
                from_below,
            });
        }
        Ok(Self {
            coarsest,
            levels: built,
            opts,
        })
    }

    /// Levels, the coarsest included.
    pub fn level_count(&self) -> usize {
        self.levels.len() + 1
    }

    /// Unknowns of the finest level.
    pub fn n(&self) -> usize {
        self.levels
            .last()
            .map_or(self.coarsest.symbolic().n(), |l| l.a.n())
    }

    /// Solves the finest level's system `A x = b` by conjugate gradients preconditioned
    /// with one V-cycle per iteration, from the `x` given, to ‖b − Ax‖₂ ≤ `rel_tol` · ‖b‖₂.
    pub fn solve(
        &self,
        b: &[f64],
        x: &mut [f64],
        rel_tol: f64,
        max_iter: usize,
    ) -> Result<PcgReport, SolverError> {
        match self.levels.last() {
            Some(finest) => pcg_with(&finest.a, b, x, self, rel_tol, max_iter),
            None => {
                let solved = self.coarsest.solve(b)?;
                x.copy_from_slice(&solved);
                Ok(PcgReport {
                    iterations: 0,
                    rel_residual: 0.0,
                })
            }
        }
    }

    /// One V-cycle from level `l` (0 = the coarsest) for the right-hand side `b`, into `x`.
    fn cycle(&self, l: usize, b: &[f64], x: &mut [f64]) {
        if l == 0 {
            x.copy_from_slice(b);
            // The factor's solve checks sizes only, which match by construction.
            if self.coarsest.solve_in_place(x).is_err() {
                x.fill(0.0);
            }
            return;
        }
        let level = &self.levels[l - 1];
        x.fill(0.0);
        for _ in 0..self.opts.sweeps {
            gauss_seidel(&level.a, &level.inv_diag, b, x, Sweep::Forward);
        }
        let mut r = vec![0.0; b.len()];
        level.a.mul_vec(x, &mut r);
        for (ri, bi) in r.iter_mut().zip(b) {
            *ri = bi - *ri;
        }
        let below = level.from_below.coarse_len();
        let mut rc = vec![0.0; below];
        level.from_below.restrict(&r, &mut rc);
        let mut xc = vec![0.0; below];
        self.cycle(l - 1, &rc, &mut xc);
        level.from_below.add_prolonged(&xc, x);
        for _ in 0..self.opts.sweeps {
            gauss_seidel(&level.a, &level.inv_diag, b, x, Sweep::Backward);
        }
    }
}

impl Precondition for Multigrid {
    fn precondition(&self, r: &[f64], z: &mut [f64]) {
        self.cycle(self.levels.len(), r, z);
    }
}

/// The direction of a Gauss–Seidel sweep.
#[derive(Clone, Copy)]
enum Sweep {
    Forward,
    Backward,
}

/// One Gauss–Seidel sweep on `A x = b`, in place. The matrix stores its full pattern, so
/// column `i` is row `i`.
fn gauss_seidel(a: &SymmetricCsc, inv_diag: &[f64], b: &[f64], x: &mut [f64], sweep: Sweep) {
    let relax = |i: usize, x: &mut [f64]| {
        let (rows, vals) = a.column(i);
        let mut s = b[i];
        for (&j, &v) in rows.iter().zip(vals) {
            s -= v * x[j];
        }
        // The loop took the diagonal term too: add it back.
        x[i] += s * inv_diag[i];
    };
    match sweep {
        Sweep::Forward => (0..a.n()).for_each(|i| relax(i, x)),
        Sweep::Backward => (0..a.n()).rev().for_each(|i| relax(i, x)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Ordering, SymbolicCholesky, gallery};

    /// The 1D Laplacian on `n` interior points of a uniform grid.
    fn laplacian_1d(n: usize) -> SymmetricCsc {
        let (mut col_ptr, mut rows, mut vals) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for (i, v) in [(j.wrapping_sub(1), -1.0), (j, 2.0), (j + 1, -1.0)] {
                if i < n {
                    rows.push(i);
                    vals.push(v);
                }
            }
            col_ptr.push(rows.len());
        }
        SymmetricCsc::try_new(n, col_ptr, rows, vals).unwrap()
    }

    /// Linear interpolation from `n` interior points to `2n + 1`.
    fn interpolation_1d(n: usize) -> Prolongation {
        let (mut row_ptr, mut cols, mut vals) = (vec![0], Vec::new(), Vec::new());
        for i in 0..2 * n + 1 {
            if i % 2 == 1 {
                cols.push((i / 2) as u32);
                vals.push(1.0);
            } else {
                for c in [i / 2, (i / 2).wrapping_sub(1)] {
                    if c < n {
                        cols.push(c as u32);
                        vals.push(0.5);
                    }
                }
            }
            row_ptr.push(cols.len());
        }
        Prolongation::try_new(n, row_ptr, cols, vals).unwrap()
    }

    fn hierarchy(levels: usize) -> Multigrid {
        let mut n = 7;
        let coarse = laplacian_1d(n);
        let factor = SymbolicCholesky::analyze(&coarse, Ordering::Natural)
            .and_then(|s| s.factor(&coarse))
            .unwrap();
        let mut finer = Vec::new();
        for _ in 1..levels {
            let p = interpolation_1d(n);
            n = 2 * n + 1;
            // Rediscretised: the 1D stiffness on a grid twice as fine is twice as large.
            let mut a = laplacian_1d(n);
            let scale = (n + 1) as f64 / 8.0;
            a.values_mut().iter_mut().for_each(|v| *v *= scale);
            finer.push((a, p));
        }
        Multigrid::new(factor, finer, MultigridOptions::default()).unwrap()
    }

    #[test]
    fn iterations_do_not_grow_with_the_levels() {
        let mut counts = Vec::new();
        for levels in [2, 4, 7] {
            let mg = hierarchy(levels);
            let n = mg.n();
            let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
            let mut x = vec![0.0; n];
            let report = mg.solve(&b, &mut x, 1e-10, 100).unwrap();
            assert!(report.rel_residual <= 1e-10);
            counts.push(report.iterations);
        }
        // 63, 255 and 1023 unknowns: the same handful of iterations.
        assert!(counts.iter().all(|&c| c <= 12), "{counts:?}");
        assert!(counts[2] <= counts[0] + 3, "{counts:?}");
    }

    #[test]
    fn the_cycle_is_symmetric() {
        // <M r1, r2> = <r1, M r2>, which conjugate gradients rely on.
        let mg = hierarchy(3);
        let n = mg.n();
        let r1: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let r2: Vec<f64> = (0..n).map(|i| (i as f64 * 1.13).cos()).collect();
        let (mut z1, mut z2) = (vec![0.0; n], vec![0.0; n]);
        mg.precondition(&r1, &mut z1);
        mg.precondition(&r2, &mut z2);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let (left, right) = (dot(&z1, &r2), dot(&r1, &z2));
        assert!(
            (left - right).abs() <= 1e-12 * left.abs().max(1.0),
            "{left} {right}"
        );
    }

    #[test]
    fn mismatched_levels_are_refused() {
        let (a, _) = gallery::triangulated_grid_laplacian(5, 5);
        let factor = SymbolicCholesky::analyze(&a, Ordering::Natural)
            .and_then(|s| s.factor(&a))
            .unwrap();
        // A prolongation from 7 coarse unknowns, but the coarsest level has a.n().
        let err = Multigrid::new(
            factor,
            vec![(laplacian_1d(15), interpolation_1d(7))],
            MultigridOptions::default(),
        )
        .unwrap_err();
        assert!(
            matches!(err, SolverError::DimensionMismatch { .. }),
            "{err}"
        );
        assert!(matches!(
            Prolongation::try_new(3, vec![0, 1], vec![3], vec![1.0]),
            Err(SolverError::InvalidStructure {
                issue: StructureIssue::RowOutOfBounds { row: 3 },
                ..
            })
        ));
        assert!(matches!(
            Prolongation::try_new(3, vec![0, 1], vec![0], vec![f64::NAN]),
            Err(SolverError::NonFinite { .. })
        ));
    }
}
