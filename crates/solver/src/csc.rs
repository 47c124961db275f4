//! The symmetric sparse matrix type every solver of this crate takes.

use std::sync::Arc;

use crate::error::{SolverError, StructureIssue};

/// From this many stored entries [`SymmetricCsc::mul_vec`] splits its rows over rayon's pool
/// (an iterative solve's product; a 3-link arm's clamped system has about 1.9 M).
const PARALLEL_MUL_NNZ: usize = 400_000;

/// Rows per task of a parallel [`SymmetricCsc::mul_vec`].
const MUL_ROWS_PER_TASK: usize = 4096;

/// Symmetric sparse matrix in compressed sparse column form with the FULL pattern stored
/// (both triangles), row indices sorted and unique within each column.
///
/// The structure (and the symmetry of the pattern) is validated once by [`SymmetricCsc::try_new`];
/// the values may then be changed freely through [`SymmetricCsc::values_mut`] (for example new Robin
/// weights) without touching the pattern. The values are expected to be symmetric: the direct
/// solvers read the lower triangle, the iterative ones the whole matrix.
///
/// ```
/// use harmonic_solver::SymmetricCsc;
/// // [ 2 -1 ]
/// // [-1  2 ]
/// let a = SymmetricCsc::try_new(2, vec![0, 2, 4], vec![0, 1, 0, 1], vec![2.0, -1.0, -1.0, 2.0])?;
/// let mut y = [0.0; 2];
/// a.mul_vec(&[1.0, 1.0], &mut y);
/// assert_eq!(y, [1.0, 1.0]);
/// # Ok::<(), harmonic_solver::SolverError>(())
/// ```
///
/// The pattern is shared: clones and [`SymmetricCsc::zeros_like`] copy only the values, and
/// solvers that analysed a pattern recognise it without comparing it entry by entry.
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricCsc {
    n: usize,
    pattern: Arc<Pattern>,
    values: Vec<f64>,
}

/// Column pointers and row indices of a [`SymmetricCsc`].
#[derive(Debug, PartialEq)]
pub(crate) struct Pattern {
    pub(crate) col_ptr: Vec<usize>,
    pub(crate) row_idx: Vec<usize>,
}

impl SymmetricCsc {
    /// Builds the matrix after checking the structure: `col_ptr` has `n + 1` non-decreasing entries
    /// starting at 0 and ending at `row_idx.len() == values.len()`, row indices are `< n`, strictly
    /// increasing within each column, and every stored `(i, j)` has its mirror `(j, i)` stored.
    /// Values are not checked here (the solvers check them for finiteness).
    pub fn try_new(
        n: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> Result<Self, SolverError> {
        let bad = |column, issue| Err(SolverError::InvalidStructure { column, issue });
        let a = Self::try_from_symmetric_pattern(n, col_ptr, row_idx, values)?;
        if let Some((row, column)) = a.missing_mirror() {
            return bad(column, StructureIssue::MissingMirror { row });
        }
        Ok(a)
    }

    /// Like [`SymmetricCsc::try_new`], for a pattern symmetric by construction (built from
    /// undirected edges, as a finite element assembler does): every structural check except
    /// the search for each entry's mirror, which costs about as much as the rest together
    /// (40 ms at 3.5 M entries). Debug builds still check the mirror.
    pub fn try_from_symmetric_pattern(
        n: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> Result<Self, SolverError> {
        let bad = |column, issue| Err(SolverError::InvalidStructure { column, issue });
        if col_ptr.len() != n + 1 {
            return bad(
                0,
                StructureIssue::ColPtrLength {
                    expected: n + 1,
                    found: col_ptr.len(),
                },
            );
        }
        if col_ptr[0] != 0 {
            return bad(0, StructureIssue::ColPtrStart);
        }
        for j in 0..n {
            if col_ptr[j + 1] < col_ptr[j] {
                return bad(j, StructureIssue::ColPtrDecreasing);
            }
        }
        if col_ptr[n] != row_idx.len() || col_ptr[n] != values.len() {
            return bad(
                n,
                StructureIssue::NnzMismatch {
                    col_ptr_end: col_ptr[n],
                    row_idx_len: row_idx.len(),
                    values_len: values.len(),
                },
            );
        }
        for j in 0..n {
            let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            for (k, &i) in rows.iter().enumerate() {
                if i >= n {
                    return bad(j, StructureIssue::RowOutOfBounds { row: i });
                }
                if k > 0 && rows[k - 1] >= i {
                    return bad(j, StructureIssue::UnsortedOrDuplicate { row: i });
                }
            }
        }
        let a = Self {
            n,
            pattern: Arc::new(Pattern { col_ptr, row_idx }),
            values,
        };
        debug_assert_eq!(a.missing_mirror(), None, "pattern is not symmetric");
        Ok(a)
    }

    /// A matrix with `self`'s pattern (shared, not copied) and every value zero.
    ///
    /// ```
    /// use harmonic_solver::SymmetricCsc;
    /// let a = SymmetricCsc::try_new(2, vec![0, 2, 4], vec![0, 1, 0, 1], vec![2.0, -1.0, -1.0, 2.0])?;
    /// let z = SymmetricCsc::zeros_like(&a);
    /// assert!(z.shares_pattern(&a));
    /// assert_eq!(z.values(), &[0.0; 4]);
    /// # Ok::<(), harmonic_solver::SolverError>(())
    /// ```
    pub fn zeros_like(other: &SymmetricCsc) -> SymmetricCsc {
        SymmetricCsc {
            n: other.n,
            pattern: Arc::clone(&other.pattern),
            values: vec![0.0; other.nnz()],
        }
    }

    /// Whether `self` and `other` share one pattern object (as clones and
    /// [`SymmetricCsc::zeros_like`] do); equal patterns built separately do not.
    pub fn shares_pattern(&self, other: &SymmetricCsc) -> bool {
        Arc::ptr_eq(&self.pattern, &other.pattern)
    }

    /// The shared pattern.
    pub(crate) fn pattern(&self) -> &Arc<Pattern> {
        &self.pattern
    }

    /// Checks that `self` has the pattern `analysed` (recognised by pointer when shared,
    /// else compared); on a mismatch names the first column that differs.
    pub(crate) fn check_pattern(&self, analysed: &Arc<Pattern>) -> Result<(), SolverError> {
        if Arc::ptr_eq(&self.pattern, analysed) || *self.pattern == **analysed {
            return Ok(());
        }
        let (a, s) = (&self.pattern, analysed);
        let n = self.n.min(s.col_ptr.len() - 1);
        let column = (0..n)
            .find(|&j| {
                a.col_ptr[j + 1] != s.col_ptr[j + 1]
                    || a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]]
                        != s.row_idx[s.col_ptr[j]..s.col_ptr[j + 1]]
            })
            .unwrap_or(n);
        Err(SolverError::PatternMismatch { column })
    }

    /// The first stored `(row, column)` whose mirror is not stored, if any.
    fn missing_mirror(&self) -> Option<(usize, usize)> {
        let (col_ptr, row_idx) = (&self.pattern.col_ptr, &self.pattern.row_idx);
        (0..self.n).find_map(|j| {
            row_idx[col_ptr[j]..col_ptr[j + 1]]
                .iter()
                .find(|&&i| {
                    i != j
                        && row_idx[col_ptr[i]..col_ptr[i + 1]]
                            .binary_search(&j)
                            .is_err()
                })
                .map(|&i| (i, j))
        })
    }

    /// Number of rows (= columns).
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored entries (both triangles).
    pub fn nnz(&self) -> usize {
        self.pattern.row_idx.len()
    }

    /// Column pointers (`n + 1` entries).
    pub fn col_ptr(&self) -> &[usize] {
        &self.pattern.col_ptr
    }

    /// Row indices, column by column, sorted within each column.
    pub fn row_idx(&self) -> &[usize] {
        &self.pattern.row_idx
    }

    /// Values, parallel to [`SymmetricCsc::row_idx`].
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Mutable values (the pattern cannot change). Keep them symmetric.
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    /// Rows of column `j` and their values.
    pub fn column(&self, j: usize) -> (&[usize], &[f64]) {
        let p = &self.pattern;
        let r = p.col_ptr[j]..p.col_ptr[j + 1];
        (&p.row_idx[r.clone()], &self.values[r])
    }

    /// `y = A x`.
    ///
    /// # Panics
    /// If `x` or `y` does not have length `n` (a caller bug, not a data error).
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.n, "mul_vec: x has the wrong length");
        assert_eq!(y.len(), self.n, "mul_vec: y has the wrong length");
        // A is symmetric, so row i of A is column i: a gather loop (no scattered writes), each
        // row on its own, so rows split over rayon's pool give the same numbers.
        let p = &self.pattern;
        let rows = |first: usize, y: &mut [f64]| {
            for (i, yi) in (first..).zip(y.iter_mut()) {
                let r = p.col_ptr[i]..p.col_ptr[i + 1];
                let mut s = 0.0;
                for (&k, &v) in p.row_idx[r.clone()].iter().zip(&self.values[r]) {
                    s += v * x[k];
                }
                *yi = s;
            }
        };
        if self.values.len() >= PARALLEL_MUL_NNZ && rayon::current_num_threads() > 1 {
            use rayon::prelude::*;
            y.par_chunks_mut(MUL_ROWS_PER_TASK)
                .enumerate()
                .for_each(|(c, chunk)| rows(c * MUL_ROWS_PER_TASK, chunk));
        } else {
            rows(0, y);
        }
    }

    /// The diagonal (0 where no diagonal entry is stored).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n)
            .map(|j| {
                let (rows, vals) = self.column(j);
                rows.binary_search(&j).map_or(0.0, |k| vals[k])
            })
            .collect()
    }

    /// Index of the first non-finite value, if any.
    pub(crate) fn first_non_finite(&self) -> Option<usize> {
        self.values.iter().position(|v| !v.is_finite())
    }
}
