//! Geometric multigrid: V-cycles over nested levels, as the preconditioner of conjugate
//! gradients.
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
use crate::pcg::{PcgReport, Precondition, iterate_with, zero_rhs};

/// The interpolation from a coarse level's unknowns to a finer level's, by rows: fine
/// unknown `i` is `Σ values[k] · coarse[columns[k]]` over `k` in `row_ptr[i]..row_ptr[i+1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Prolongation {
    coarse: usize,
    rows: SparseRows,
}

/// Sparse rows: row `i` is `columns[k]`, `values[k]` for `k` in `row_ptr[i]..row_ptr[i + 1]`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SparseRows {
    pub(crate) row_ptr: Vec<usize>,
    pub(crate) columns: Vec<u32>,
    pub(crate) values: Vec<f64>,
}

impl SparseRows {
    /// Row `i`'s columns and values.
    pub(crate) fn row(&self, i: usize) -> (&[u32], &[f64]) {
        let r = self.row_ptr[i]..self.row_ptr[i + 1];
        (&self.columns[r.clone()], &self.values[r])
    }
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
            rows: SparseRows {
                row_ptr,
                columns,
                values,
            },
        })
    }

    /// Unknowns of the fine level (rows).
    pub fn fine_len(&self) -> usize {
        self.rows.row_ptr.len() - 1
    }

    /// Unknowns of the coarse level (columns).
    pub fn coarse_len(&self) -> usize {
        self.coarse
    }

    /// Row `i`: the coarse unknowns fine unknown `i` interpolates from, and their weights.
    pub(crate) fn row(&self, i: usize) -> (&[u32], &[f64]) {
        self.rows.row(i)
    }

    /// `Pᵀ` by rows (a coarse unknown's fine unknowns, sorted).
    pub(crate) fn transpose(&self) -> SparseRows {
        let SparseRows {
            row_ptr: p_ptr,
            columns: p_columns,
            values: p_values,
        } = &self.rows;
        let mut count = vec![0usize; self.coarse + 1];
        for &c in p_columns {
            count[c as usize + 1] += 1;
        }
        for c in 0..self.coarse {
            count[c + 1] += count[c];
        }
        let row_ptr = count.clone();
        let mut columns = vec![0u32; p_columns.len()];
        let mut values = vec![0.0; p_values.len()];
        for (i, w) in p_ptr.windows(2).enumerate() {
            for k in w[0]..w[1] {
                let slot = &mut count[p_columns[k] as usize];
                columns[*slot] = i as u32;
                values[*slot] = p_values[k];
                *slot += 1;
            }
        }
        SparseRows {
            row_ptr,
            columns,
            values,
        }
    }

    /// `coarse = Pᵀ fine` (the restriction of a residual), by the rows of `transposed` (this
    /// prolongation's [`Prolongation::transpose`]): each coarse value sums its fine terms in
    /// increasing fine order, as a scatter over the fine rows would, so the numbers do not
    /// depend on how the rows are split; large levels on rayon's pool.
    fn restrict(&self, transposed: &SparseRows, fine: &[f64], coarse: &mut [f64]) {
        let rows = |first: usize, out: &mut [f64]| {
            for (k, c) in out.iter_mut().enumerate() {
                let (columns, values) = transposed.row(first + k);
                *c = columns
                    .iter()
                    .zip(values)
                    .fold(0.0, |s, (&i, &v)| s + v * fine[i as usize]);
            }
        };
        split_rows(coarse, fine.len(), rows);
    }

    /// `fine += P coarse` (a coarse correction added); large levels on rayon's pool.
    fn add_prolonged(&self, coarse: &[f64], fine: &mut [f64]) {
        let rows = |first: usize, out: &mut [f64]| {
            for (k, f) in out.iter_mut().enumerate() {
                let (columns, values) = self.rows.row(first + k);
                let s: f64 = columns
                    .iter()
                    .zip(values)
                    .map(|(&c, &v)| v * coarse[c as usize])
                    .sum();
                *f += s;
            }
        };
        let n = self.fine_len();
        split_rows(&mut fine[..n], n, rows);
    }
}

/// Runs `rows(first, out)` over `out` (rows `first..first + out.len()`), in one piece, or
/// where the level (of `level_len` unknowns) is large enough for its sweeps to be split,
/// in one piece per thread on rayon's pool. Each row is computed alike either way.
fn split_rows(out: &mut [f64], level_len: usize, rows: impl Fn(usize, &mut [f64]) + Sync) {
    if level_len >= crate::PARALLEL_MIN_UNKNOWNS && rayon::current_num_threads() > 1 {
        use rayon::prelude::*;
        let size = out.len().div_ceil(rayon::current_num_threads()).max(1);
        out.par_chunks_mut(size)
            .enumerate()
            .for_each(|(c, o)| rows(c * size, o));
    } else {
        rows(0, out);
    }
}

/// Options of a [`Multigrid`] cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MultigridOptions {
    /// Gauss–Seidel sweeps before and after each coarse correction, at least one (0 is
    /// taken as 1). Default 2: 7–8 iterations on the reference scene against 11–13 with one
    /// sweep, for the same time or less.
    pub sweeps: usize,
}

impl Default for MultigridOptions {
    fn default() -> Self {
        Self { sweeps: 2 }
    }
}

/// One level above the coarsest: its matrix by rows and the prolongation from the level
/// below.
#[derive(Debug)]
struct Level {
    a: Rows,
    from_below: Prolongation,
    /// `from_below`'s transpose, for restricting by rows.
    to_below: SparseRows,
}

/// A symmetric matrix by rows for the cycle: the off-diagonal entries with 32-bit column
/// indices and the diagonal apart. The cycle is bound by memory traffic, so the smoother
/// reads its entries in single precision (8 bytes an entry where [`SymmetricCsc`] takes 16):
/// the rounded matrix is still symmetric, so the cycle is still a fixed symmetric operator,
/// and a preconditioner needs no more than that. Products with `A` (the residuals the cycle
/// restricts, and conjugate gradients' own) use the double-precision entries.
#[derive(Debug)]
struct Rows {
    row_ptr: Vec<u32>,
    /// Per row, the end of its entries left of the diagonal (columns are sorted).
    lower_end: Vec<u32>,
    columns: Vec<u32>,
    values: Vec<f64>,
    /// `values` rounded to single precision, for the sweeps.
    smoothing: Vec<f32>,
    diagonal: Vec<f64>,
    inv_diagonal: Vec<f64>,
}

impl Rows {
    /// The rows of `a` (its columns: the pattern is symmetric). Errors on a non-finite value,
    /// a diagonal entry that is not positive, or more entries than 32-bit indices reach.
    fn of(a: &SymmetricCsc) -> Result<Self, SolverError> {
        if let Some(index) = a.first_non_finite() {
            return Err(SolverError::NonFinite {
                what: "matrix values",
                index,
            });
        }
        if a.nnz() > u32::MAX as usize {
            return Err(SolverError::DimensionMismatch {
                what: "entries of a multigrid level (32-bit indices)",
                expected: u32::MAX as usize,
                found: a.nnz(),
            });
        }
        use rayon::prelude::*;
        let n = a.n();
        // Per row, its entries off the diagonal; the rows' places from their running sum.
        let off: Vec<u32> = (0..n)
            .into_par_iter()
            .map(|i| {
                let (cols, _) = a.column(i);
                (cols.len() - cols.iter().filter(|&&j| j == i).count()) as u32
            })
            .collect();
        let mut row_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0u32);
        for &k in &off {
            row_ptr.push(row_ptr[row_ptr.len() - 1] + k);
        }
        let total = row_ptr[n] as usize;
        let mut rows = Rows {
            row_ptr,
            lower_end: vec![0; n],
            smoothing: Vec::new(),
            columns: vec![0; total],
            values: vec![0.0; total],
            diagonal: vec![0.0; n],
            inv_diagonal: vec![0.0; n],
        };
        // Runs of rows, each with its own part of every array, copied on every core; the
        // first row (in order) that fails is the error.
        const RUN: usize = 4096;
        let mut runs = Vec::with_capacity(n.div_ceil(RUN));
        {
            let (mut columns, mut values) = (&mut rows.columns[..], &mut rows.values[..]);
            let mut lower_end = &mut rows.lower_end[..];
            let (mut diagonal, mut inv) = (&mut rows.diagonal[..], &mut rows.inv_diagonal[..]);
            let mut first = 0;
            while first < n {
                let last = (first + RUN).min(n);
                let len = (rows.row_ptr[last] - rows.row_ptr[first]) as usize;
                let (c, rest_c) = columns.split_at_mut(len);
                let (v, rest_v) = values.split_at_mut(len);
                let (l, rest_l) = lower_end.split_at_mut(last - first);
                let (d, rest_d) = diagonal.split_at_mut(last - first);
                let (w, rest_w) = inv.split_at_mut(last - first);
                runs.push((first, c, v, l, d, w));
                (columns, values, lower_end, diagonal, inv) =
                    (rest_c, rest_v, rest_l, rest_d, rest_w);
                first = last;
            }
        }
        let row_ptr = &rows.row_ptr;
        let failed = runs
            .into_par_iter()
            .filter_map(|(first, columns, values, lower_end, diagonal, inv)| {
                let base = row_ptr[first] as usize;
                for r in 0..diagonal.len() {
                    let i = first + r;
                    let mut at = row_ptr[i] as usize - base;
                    lower_end[r] = row_ptr[i + 1];
                    let (cols, vals) = a.column(i);
                    for (&j, &v) in cols.iter().zip(vals) {
                        if j == i {
                            diagonal[r] = v;
                            lower_end[r] = (base + at) as u32;
                        } else {
                            columns[at] = j as u32;
                            values[at] = v;
                            at += 1;
                        }
                    }
                    // No stored diagonal is a zero one, refused here.
                    let d = diagonal[r];
                    if d <= 0.0 {
                        return Some(if d == 0.0 {
                            SolverError::Singular { column: i }
                        } else {
                            SolverError::NotPositiveDefinite { column: i }
                        });
                    }
                    inv[r] = 1.0 / d;
                }
                None
            })
            .find_first(|_| true);
        if let Some(e) = failed {
            return Err(e);
        }
        rows.smoothing = rows.values.par_iter().map(|&v| v as f32).collect();
        Ok(rows)
    }

    fn n(&self) -> usize {
        self.diagonal.len()
    }

    /// `Σ_j a_ij x_j` over the off-diagonal entries of row `i`.
    #[inline]
    fn off_diagonal_dot(&self, i: usize, x: &[f64]) -> f64 {
        let (s, e) = (self.row_ptr[i] as usize, self.row_ptr[i + 1] as usize);
        let mut acc = 0.0;
        for (&j, &v) in self.columns[s..e].iter().zip(&self.values[s..e]) {
            acc += v * x[j as usize];
        }
        acc
    }

    /// `out = b − A x`, or `out = A x` with `b = None`; large levels on rayon's pool.
    fn residual(&self, b: Option<&[f64]>, x: &[f64], out: &mut [f64]) {
        let row = |i: usize| self.diagonal[i] * x[i] + self.off_diagonal_dot(i, x);
        let chunk = |start: usize, out: &mut [f64]| match b {
            Some(b) => {
                for (k, o) in out.iter_mut().enumerate() {
                    *o = b[start + k] - row(start + k);
                }
            }
            None => {
                for (k, o) in out.iter_mut().enumerate() {
                    *o = row(start + k);
                }
            }
        };
        split_rows(out, self.n(), chunk);
    }

    /// Whether this level's products and sweeps are split over rayon's pool.
    fn parallel(&self) -> bool {
        self.n() >= crate::PARALLEL_MIN_UNKNOWNS && rayon::current_num_threads() > 1
    }

    /// One Gauss–Seidel sweep on `A x = b`, in place. Large levels sweep their two halves of
    /// rows at once on two threads, each reading the other half's values from before the
    /// sweep (hybrid Gauss–Seidel: Gauss–Seidel within a half, Jacobi between them). It is
    /// still a fixed linear smoother, and the backward sweep is its transpose, so the cycle
    /// stays symmetric. The unknowns are numbered along the mesh (a Hilbert order), so the
    /// halves are two regions that meet along a short seam.
    ///
    /// `from_zero` says `x` is zero: a forward sweep then reads only the entries left of the
    /// diagonal (the others multiply zeros).
    fn gauss_seidel(&self, b: &[f64], x: &mut [f64], sweep: Sweep, before: &mut [f64]) {
        let n = self.n();
        if !self.parallel() {
            self.sweep_rows(0, b, x, None, sweep);
            return;
        }
        let mid = n / 2;
        if sweep == Sweep::ForwardFromZero {
            // Nothing to read across the seam: the other half's values are zero.
            let (lo, hi) = x.split_at_mut(mid);
            rayon::join(
                || self.sweep_rows(0, b, lo, None, sweep),
                || self.sweep_rows(mid, b, hi, None, sweep),
            );
            return;
        }
        before.copy_from_slice(x);
        let before = &*before;
        let (lo, hi) = x.split_at_mut(mid);
        rayon::join(
            || self.sweep_rows(0, b, lo, Some(before), sweep),
            || self.sweep_rows(mid, b, hi, Some(before), sweep),
        );
    }

    /// A Gauss–Seidel sweep over rows `first..first + own.len()`, whose values are `own`.
    /// With `before` (all of `x` before the sweep, for a sweep on two threads) the other rows'
    /// values are read from it; without, `own` is the whole vector (`first = 0`), or the
    /// sweep starts from zero and the other rows are zero.
    ///
    /// Each row's sum is split at the diagonal: the entries on the side not yet swept read
    /// values from before the sweep and do not wait for the row just relaxed, which breaks
    /// the chain of dependent rows (one row's sum no longer waits on the previous row's
    /// result for all its terms) and runs about twice as fast as one sum per row.
    fn sweep_rows(
        &self,
        first: usize,
        b: &[f64],
        own: &mut [f64],
        before: Option<&[f64]>,
        sweep: Sweep,
    ) {
        let end = first + own.len();
        let (rows, cols, vals) = (&self.row_ptr, &self.columns, &self.smoothing);
        // Σ a_ij x_j over entries k0..k1, x_j from `x` at j - offset.
        let dot = |k0: usize, k1: usize, x: &[f64], offset: usize| -> f64 {
            cols[k0..k1]
                .iter()
                .zip(&vals[k0..k1])
                .map(|(&j, &v)| f64::from(v) * x[j as usize - offset])
                .sum()
        };
        // The same where some columns may lie outside this block: those read `other(j)`.
        let mixed = |k0: usize, k1: usize, own: &[f64], other: &dyn Fn(usize) -> f64| -> f64 {
            cols[k0..k1]
                .iter()
                .zip(&vals[k0..k1])
                .map(|(&j, &v)| {
                    let j = j as usize;
                    f64::from(v)
                        * if j >= first && j < end {
                            own[j - first]
                        } else {
                            other(j)
                        }
                })
                .sum()
        };
        let zero = |_: usize| 0.0;
        let old = |j: usize| before.map_or(0.0, |x| x[j]);
        for step in 0..own.len() {
            let local = match sweep {
                Sweep::Backward => own.len() - 1 - step,
                _ => step,
            };
            let i = first + local;
            let (s, m, e) = (
                rows[i] as usize,
                self.lower_end[i] as usize,
                rows[i + 1] as usize,
            );
            let sum = match (sweep, before) {
                // Left of the diagonal: values of this sweep (this block's) or zero.
                (Sweep::ForwardFromZero, _) if first == 0 => dot(s, m, own, 0),
                (Sweep::ForwardFromZero, _) => mixed(s, m, own, &zero),
                // One thread: everything from `own`, the whole vector, still in two sums.
                (_, None) => dot(m, e, own, 0) + dot(s, m, own, 0),
                // Two threads, forward: right of the diagonal not yet swept (before);
                // left of it this block's new values, or another block's old ones.
                (Sweep::Forward, Some(x)) => {
                    dot(m, e, x, 0)
                        + if first == 0 {
                            dot(s, m, own, 0)
                        } else {
                            mixed(s, m, own, &old)
                        }
                }
                // Backward mirrors it.
                (Sweep::Backward, Some(x)) => {
                    dot(s, m, x, 0)
                        + if end == self.n() {
                            dot(m, e, own, first)
                        } else {
                            mixed(m, e, own, &old)
                        }
                }
            };
            own[local] = (b[i] - sum) * self.inv_diagonal[i];
        }
    }
}

/// Work vectors of one level above the coarsest: its residual and the right-hand side and
/// solution of the level below.
struct Scratch {
    r: Vec<f64>,
    /// The level's solution before a sweep (read across the seam of a two-thread sweep).
    before: Vec<f64>,
    below_b: Vec<f64>,
    below_x: Vec<f64>,
}

/// A multigrid V-cycle over a coarsest level solved directly and finer levels smoothed by
/// Gauss–Seidel; a [`Precondition`] for [`crate::pcg_with`] (forward sweeps, the coarse
/// correction, backward sweeps: a symmetric operator).
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
        levels: Vec<(&SymmetricCsc, Prolongation)>,
        opts: MultigridOptions,
    ) -> Result<Self, SolverError> {
        Self::with_coarsest_from(|| Ok(coarsest), levels, opts)
    }

    /// [`Multigrid::new`] with the coarsest level's factor made by `factor` beside the
    /// levels' row copies (on rayon's pool): the factorisation and the finest level's copy
    /// are each a few tens of milliseconds on a million unknowns, and neither needs the
    /// other.
    pub fn with_coarsest_from(
        factor: impl FnOnce() -> Result<Cholesky, SolverError> + Send,
        levels: Vec<(&SymmetricCsc, Prolongation)>,
        opts: MultigridOptions,
    ) -> Result<Self, SolverError> {
        for (a, from_below) in &levels {
            if from_below.fine_len() != a.n() {
                return Err(SolverError::DimensionMismatch {
                    what: "prolongation rows (unknowns of the level)",
                    expected: a.n(),
                    found: from_below.fine_len(),
                });
            }
        }
        let (coarsest, built) = rayon::join(factor, || {
            use rayon::prelude::*;
            // The row copies are independent (the finest is most of the work).
            levels
                .into_par_iter()
                .map(|(a, from_below)| {
                    Ok(Level {
                        a: Rows::of(a)?,
                        to_below: from_below.transpose(),
                        from_below,
                    })
                })
                .collect::<Result<Vec<_>, SolverError>>()
        });
        let (coarsest, built) = (coarsest?, built?);
        let mut below = coarsest.symbolic().n();
        for level in &built {
            if level.from_below.coarse_len() != below {
                return Err(SolverError::DimensionMismatch {
                    what: "prolongation columns (unknowns of the level below)",
                    expected: below,
                    found: level.from_below.coarse_len(),
                });
            }
            below = level.a.n();
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
        let n = self.n();
        for (what, v) in [("right-hand side", b), ("initial guess", &*x)] {
            if v.len() != n {
                return Err(SolverError::DimensionMismatch {
                    what,
                    expected: n,
                    found: v.len(),
                });
            }
            if let Some(index) = v.iter().position(|v| !v.is_finite()) {
                return Err(SolverError::NonFinite { what, index });
            }
        }
        let Some(level) = self.levels.last() else {
            x.copy_from_slice(b);
            self.coarsest.solve_in_place(x)?;
            return Ok(PcgReport {
                iterations: 0,
                rel_residual: 0.0,
            });
        };
        if let Some(zero) = zero_rhs(b, x) {
            return Ok(zero);
        }
        let with_scratch = WithScratch {
            multigrid: self,
            scratch: std::cell::RefCell::new(self.scratch()),
        };
        iterate_with(
            |v, av| level.a.residual(None, v, av),
            b,
            x,
            &with_scratch,
            rel_tol,
            max_iter,
        )
    }

    /// Work vectors for one cycle, coarse to fine.
    fn scratch(&self) -> Vec<Scratch> {
        let mut below = self.coarsest.symbolic().n();
        self.levels
            .iter()
            .map(|level| {
                let s = Scratch {
                    r: vec![0.0; level.a.n()],
                    before: vec![0.0; if level.a.parallel() { level.a.n() } else { 0 }],
                    below_b: vec![0.0; below],
                    below_x: vec![0.0; below],
                };
                below = level.a.n();
                s
            })
            .collect()
    }

    /// One V-cycle for the right-hand side `b` of the level `scratch.len()` (0 = the
    /// coarsest), into `x`.
    fn cycle(&self, b: &[f64], x: &mut [f64], scratch: &mut [Scratch]) {
        let Some((mine, below)) = scratch.split_last_mut() else {
            x.copy_from_slice(b);
            // The factor's solve checks sizes only, which match by construction.
            if self.coarsest.solve_in_place(x).is_err() {
                x.fill(0.0);
            }
            return;
        };
        let level = &self.levels[below.len()];
        x.fill(0.0);
        let sweeps = self.opts.sweeps.max(1);
        for sweep in 0..sweeps {
            let kind = if sweep == 0 {
                Sweep::ForwardFromZero
            } else {
                Sweep::Forward
            };
            level.a.gauss_seidel(b, x, kind, &mut mine.before);
        }
        level.a.residual(Some(b), x, &mut mine.r);
        level
            .from_below
            .restrict(&level.to_below, &mine.r, &mut mine.below_b);
        self.cycle(&mine.below_b, &mut mine.below_x, below);
        level.from_below.add_prolonged(&mine.below_x, x);
        for _ in 0..sweeps {
            level
                .a
                .gauss_seidel(b, x, Sweep::Backward, &mut mine.before);
        }
    }
}

impl Precondition for Multigrid {
    /// One V-cycle (allocating its work vectors; [`Multigrid::solve`] allocates them once).
    fn precondition(&self, r: &[f64], z: &mut [f64]) {
        self.cycle(r, z, &mut self.scratch());
    }
}

/// The cycle with work vectors kept across the iterations of one solve.
struct WithScratch<'a> {
    multigrid: &'a Multigrid,
    scratch: std::cell::RefCell<Vec<Scratch>>,
}

impl Precondition for WithScratch<'_> {
    fn precondition(&self, r: &[f64], z: &mut [f64]) {
        self.multigrid.cycle(r, z, &mut self.scratch.borrow_mut());
    }
}

/// The direction of a Gauss–Seidel sweep.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Sweep {
    /// Forward from `x = 0`.
    ForwardFromZero,
    Forward,
    Backward,
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

    /// The transfers of a level large enough to be split over threads give, on two threads,
    /// the very numbers one thread gives and a scatter over the fine rows gives.
    #[test]
    fn transfers_split_over_threads_give_the_same_numbers() {
        let n = crate::PARALLEL_MIN_UNKNOWNS;
        let p = interpolation_1d(n);
        let pt = p.transpose();
        let fine: Vec<f64> = (0..p.fine_len())
            .map(|i| (i as f64 * 0.731).sin())
            .collect();
        let coarse: Vec<f64> = (0..n).map(|i| (i as f64 * 1.37).cos()).collect();
        let mut scattered = vec![0.0; n];
        for (i, &r) in fine.iter().enumerate() {
            let (columns, values) = p.row(i);
            for (&c, &v) in columns.iter().zip(values) {
                scattered[c as usize] += v * r;
            }
        }
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut restricted = vec![f64::NAN; n];
                p.restrict(&pt, &fine, &mut restricted);
                let mut prolonged = fine.clone();
                p.add_prolonged(&coarse, &mut prolonged);
                (restricted, prolonged)
            })
        };
        let (one, two) = (run(1), run(2));
        assert_eq!(one.0, scattered);
        assert_eq!(two.0, scattered);
        assert_eq!(one.1, two.1);
        assert!((one.1[1] - (fine[1] + coarse[0])).abs() < 1e-15);
    }

    fn hierarchy(levels: usize) -> Multigrid {
        hierarchy_with(levels, MultigridOptions::default())
    }

    fn hierarchy_with(levels: usize, opts: MultigridOptions) -> Multigrid {
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
        let levels = finer.iter().map(|(a, p)| (a, p.clone())).collect();
        Multigrid::new(factor, levels, opts).unwrap()
    }

    #[test]
    fn zero_sweeps_are_one() {
        let solve = |sweeps| {
            let mg = hierarchy_with(5, MultigridOptions { sweeps });
            let b = vec![1.0; mg.n()];
            let mut x = vec![0.0; mg.n()];
            mg.solve(&b, &mut x, 1e-10, 100).unwrap().iterations
        };
        assert_eq!(solve(0), solve(1));
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
        // 15, 63 and 511 unknowns: the same handful of iterations.
        assert!(counts.iter().all(|&c| c <= 12), "{counts:?}");
        assert!(counts[2] <= counts[0] + 3, "{counts:?}");
    }

    #[test]
    fn the_cycle_is_symmetric() {
        // <M r1, r2> = <r1, M r2>, which conjugate gradients rely on; 14 levels reach
        // 65 535 unknowns, where the sweeps run on two threads when there are two.
        for levels in [3, 14] {
            cycle_is_symmetric(hierarchy(levels));
        }
    }

    #[test]
    fn large_levels_converge_as_fast() {
        // The two-thread sweep (from 50 000 unknowns) loses little against the one-thread one.
        let mg = hierarchy(14);
        let n = mg.n();
        assert!(n >= crate::PARALLEL_MIN_UNKNOWNS, "{n}");
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut x = vec![0.0; n];
        let report = mg.solve(&b, &mut x, 1e-10, 100).unwrap();
        assert!(report.iterations <= 12, "{report:?}");
        let mut r = vec![0.0; n];
        mg.levels[mg.levels.len() - 1]
            .a
            .residual(Some(&b), &x, &mut r);
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(norm(&r) <= 1e-10 * norm(&b) * (1.0 + 1e-6));
    }

    fn cycle_is_symmetric(mg: Multigrid) {
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
        let fine = laplacian_1d(15);
        let err = Multigrid::new(
            factor,
            vec![(&fine, interpolation_1d(7))],
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
