//! Direct solves: faer's sparse (supernodal) Cholesky with the symbolic analysis kept for reuse.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky as FaerSymbolic, SymbolicCholeskyRaw,
    SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Side, Spec};

use crate::csc::{Pattern, SymmetricCsc};
use crate::error::SolverError;
use crate::ordering::{Ordering, nested_dissection};
use crate::parallel::Parallelism;

#[derive(Debug)]
struct SymbolicInner {
    faer: FaerSymbolic<usize>,
    /// `perm[new] = old`: the fill-reducing ordering, to report errors in the caller's numbering.
    perm: Vec<usize>,
    /// The analysed pattern (shared with the matrix, not copied).
    pattern: Arc<Pattern>,
    /// Threads for the ordering, the numeric factorisations and the solves.
    parallelism: Parallelism,
}

/// Symbolic Cholesky analysis of a sparsity pattern: the fill-reducing ordering and faer's
/// supernodal (or simplicial, for very sparse factors) structure. Analyse once, then
/// [`factor`](SymbolicCholesky::factor) every matrix with the same pattern (new Robin weights,
/// new Dirichlet values) without redoing it. Cloning is cheap (shared [`Arc`]).
///
/// ```
/// use harmonic_solver::{gallery, Ordering, SymbolicCholesky};
/// let (mut a, coords) = gallery::triangulated_grid_laplacian(20, 20);
/// let symbolic = SymbolicCholesky::analyze(&a, Ordering::NestedDissection { coords })?;
/// let b = vec![1.0; a.n()];
/// let x1 = symbolic.factor(&a)?.solve(&b)?;
/// // New values, same pattern: only the numeric factorisation is redone.
/// for v in a.values_mut() { *v *= 2.0; }
/// let x2 = symbolic.factor(&a)?.solve(&b)?;
/// assert!((x1[7] - 2.0 * x2[7]).abs() < 1e-12 * x1[7].abs());
/// # Ok::<(), harmonic_solver::SolverError>(())
/// ```
#[derive(Debug, Clone)]
pub struct SymbolicCholesky {
    inner: Arc<SymbolicInner>,
}

impl SymbolicCholesky {
    /// Computes the ordering and the symbolic factorisation of `a`'s pattern (values unused),
    /// for factorisations with the default [`Parallelism`] (rayon's pool on large systems).
    pub fn analyze(a: &SymmetricCsc, ordering: Ordering) -> Result<Self, SolverError> {
        Self::analyze_with(a, ordering, Parallelism::default())
    }

    /// [`analyze`](Self::analyze), with the threads the ordering, every
    /// [`factor`](Self::factor) and every solve of its factors may use.
    pub fn analyze_with(
        a: &SymmetricCsc,
        ordering: Ordering,
        parallelism: Parallelism,
    ) -> Result<Self, SolverError> {
        let n = a.n();
        let perm: Vec<usize> = match &ordering {
            Ordering::Amd => Vec::new(),
            Ordering::Natural => (0..n).collect(),
            Ordering::NestedDissection { coords } => nested_dissection(a, coords, parallelism)?,
        };
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, a.col_ptr(), None, a.row_idx());
        let faer = if perm.is_empty() {
            factorize_symbolic_cholesky(
                pattern,
                Side::Lower,
                SymmetricOrdering::Amd,
                CholeskySymbolicParams::default(),
            )
        } else {
            let mut inv = vec![0; n];
            for (new, &old) in perm.iter().enumerate() {
                inv[old] = new;
            }
            let p = faer::perm::PermRef::new_checked(&perm, &inv, n);
            factorize_symbolic_cholesky(
                pattern,
                Side::Lower,
                SymmetricOrdering::Custom(p),
                CholeskySymbolicParams::default(),
            )
        }
        .map_err(|e| SolverError::Backend(format!("symbolic Cholesky: {e:?}")))?;
        let perm = match faer.perm() {
            Some(p) => p.arrays().0.to_vec(),
            None => (0..n).collect(),
        };
        Ok(Self {
            inner: Arc::new(SymbolicInner {
                faer,
                perm,
                pattern: Arc::clone(a.pattern()),
                parallelism,
            }),
        })
    }

    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.inner.pattern.col_ptr.len() - 1
    }

    /// The threads its factorisations and solves may use.
    pub fn parallelism(&self) -> Parallelism {
        self.inner.parallelism
    }

    /// Number of stored values of the Cholesky factor (a measure of fill; supernodal storage
    /// counts the dense blocks).
    pub fn factor_len(&self) -> usize {
        self.inner.faer.len_val()
    }

    /// The fill-reducing permutation, `perm[new] = old`.
    pub fn permutation(&self) -> &[usize] {
        &self.inner.perm
    }

    /// Numeric Cholesky factorisation `A = L Lᵀ` of `a`, which must have the analysed pattern.
    pub fn factor(&self, a: &SymmetricCsc) -> Result<Cholesky, SolverError> {
        let mut chol = Cholesky {
            symbolic: self.clone(),
            l_values: Vec::new(),
            valid: false,
        };
        chol.refactor(a)?;
        Ok(chol)
    }
}

/// Numeric Cholesky factor `A = L Lᵀ`, ready to solve.
#[derive(Debug, Clone)]
pub struct Cholesky {
    symbolic: SymbolicCholesky,
    l_values: Vec<f64>,
    /// False after a failed refactor: the values are garbage until the next success.
    valid: bool,
}

impl Cholesky {
    /// The symbolic analysis this factor was computed with.
    pub fn symbolic(&self) -> &SymbolicCholesky {
        &self.symbolic
    }

    /// Recomputes the factor in place for new values of `a` (same pattern), reusing the storage.
    /// On error the factor is left unusable for solving until a later refactor succeeds.
    pub fn refactor(&mut self, a: &SymmetricCsc) -> Result<(), SolverError> {
        a.check_pattern(&self.symbolic.inner.pattern)?;
        if let Some(index) = a.first_non_finite() {
            return Err(SolverError::NonFinite {
                what: "matrix values",
                index,
            });
        }
        let inner = &self.symbolic.inner;
        let n = a.n();
        // An empty column means a zero row and column: singular, whatever the ordering.
        if let Some(column) = (0..n).find(|&j| a.col_ptr()[j] == a.col_ptr()[j + 1]) {
            self.valid = false;
            return Err(SolverError::Singular { column });
        }
        let mat = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, a.col_ptr(), None, a.row_idx()),
            a.values(),
        );
        if self.l_values.len() != inner.faer.len_val() {
            // A fresh zeroed allocation (the OS supplies zero pages); faer overwrites it all, so a
            // refactor reuses the buffer as is rather than paying for a second zero fill.
            self.l_values = vec![0.0; inner.faer.len_val()];
        }
        self.valid = false;
        let par = inner.parallelism.faer(n);
        let req = inner
            .faer
            .factorize_numeric_llt_scratch::<f64>(par, Spec::default());
        let mut mem = MemBuffer::try_new(req).map_err(|_| {
            SolverError::Backend("out of memory for factorisation workspace".into())
        })?;
        let result = inner.faer.factorize_numeric_llt(
            &mut self.l_values,
            mat,
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Spec::default(),
        );
        match result {
            Ok(_) => {
                self.valid = true;
                Ok(())
            }
            Err(LltError::NonPositivePivot { index }) => {
                // faer 0.24 reports the simplicial pivot 1-based and the supernodal one 0-based.
                let pivot = match inner.faer.raw() {
                    SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
                    SymbolicCholeskyRaw::Supernodal(_) => index,
                };
                let column = inner.perm[pivot.min(n.saturating_sub(1))];
                Err(SolverError::NotPositiveDefinite { column })
            }
        }
    }

    /// Solves `A x = b`.
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>, SolverError> {
        let mut x = b.to_vec();
        self.solve_in_place(&mut x)?;
        Ok(x)
    }

    /// Solves `A x = b` in place: `x` holds `b` on entry and the solution on return.
    pub fn solve_in_place(&self, x: &mut [f64]) -> Result<(), SolverError> {
        let inner = &self.symbolic.inner;
        let n = self.symbolic.n();
        if x.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "right-hand side",
                expected: n,
                found: x.len(),
            });
        }
        if !self.valid {
            return Err(SolverError::StaleFactor);
        }
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "right-hand side",
                index,
            });
        }
        let par = inner.parallelism.faer(n);
        let req: StackReq = inner.faer.solve_in_place_scratch::<f64>(1, par);
        let mut mem = MemBuffer::try_new(req)
            .map_err(|_| SolverError::Backend("out of memory for solve workspace".into()))?;
        LltRef::new(&inner.faer, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            par,
            MemStack::new(&mut mem),
        );
        Ok(())
    }

    /// Solves `A X = B` for a block of `k` right-hand sides in place, laid out row-major as
    /// for [`crate::AccurateLdlt::solve_block_in_place`] (`x[i * k + c]`: unknown `i` of
    /// column `c`).
    pub fn solve_block_in_place(&self, x: &mut [f64], k: usize) -> Result<(), SolverError> {
        let inner = &self.symbolic.inner;
        let n = self.symbolic.n();
        if k == 0 {
            return Ok(());
        }
        if Some(x.len()) != n.checked_mul(k) {
            return Err(SolverError::DimensionMismatch {
                what: "right-hand side block (n × k, row-major)",
                expected: n.saturating_mul(k),
                found: x.len(),
            });
        }
        if !self.valid {
            return Err(SolverError::StaleFactor);
        }
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "right-hand side block",
                index,
            });
        }
        let par = inner.parallelism.faer(n);
        let req: StackReq = inner.faer.solve_in_place_scratch::<f64>(k, par);
        let mut mem = MemBuffer::try_new(req)
            .map_err(|_| SolverError::Backend("out of memory for solve workspace".into()))?;
        LltRef::new(&inner.faer, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_row_major_slice_mut(x, n, k),
            par,
            MemStack::new(&mut mem),
        );
        Ok(())
    }
}

/// Convenience: analyse with [`Ordering::Amd`], factor and solve `A x = b` once.
///
/// ```
/// use harmonic_solver::{solve_direct, SymmetricCsc};
/// let a = SymmetricCsc::try_new(2, vec![0, 2, 4], vec![0, 1, 0, 1], vec![2.0, -1.0, -1.0, 2.0])?;
/// let x = solve_direct(&a, &[1.0, 1.0])?;
/// assert!((x[0] - 1.0).abs() < 1e-14 && (x[1] - 1.0).abs() < 1e-14);
/// # Ok::<(), harmonic_solver::SolverError>(())
/// ```
pub fn solve_direct(a: &SymmetricCsc, b: &[f64]) -> Result<Vec<f64>, SolverError> {
    if b.len() != a.n() {
        return Err(SolverError::DimensionMismatch {
            what: "right-hand side",
            expected: a.n(),
            found: b.len(),
        });
    }
    SymbolicCholesky::analyze(a, Ordering::default())?
        .factor(a)?
        .solve(b)
}
