//! Solving the reduced system: a sparse Cholesky factorisation with reusable symbolic analysis,
//! or the entrywise-accurate M-matrix LDLᵀ that keeps ψ's relative precision down to 1e-300.

use std::sync::{Arc, Mutex};

use harmonic_mesh::Mesh;
use harmonic_solver::{AccurateLdlt, Ordering, SymbolicCholesky};

use crate::FemError;
use crate::assemble::{Assembler, AssemblyOptions, LinearSystem, NotMMatrix};
use crate::bc::BoundaryConditions;
use crate::potential::Potential;

/// Up to this many unknowns [`SolveMethod::Auto`] uses the accurate solve outright: there it
/// costs about as much as the Cholesky factorisation (see the crate docs for the figures).
pub const AUTO_ACCURATE_MAX_UNKNOWNS: usize = 50_000;

/// Above [`AUTO_ACCURATE_MAX_UNKNOWNS`], [`SolveMethod::Auto`] redoes a Cholesky solution
/// with the accurate solve when the smallest ψ at an unknown is below this fraction of the
/// largest (or not positive): there a Cholesky ψ may have lost its relative precision.
pub const AUTO_FLAT_RATIO: f64 = 1e-12;

/// How [`Solver`] solves the reduced system.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SolveMethod {
    /// faer's supernodal Cholesky: the fastest on large meshes; ψ is accurate relative to
    /// its largest value (normwise), so values far below it may lose their digits.
    Cholesky,
    /// The GTH-style LDLᵀ of the M-matrix given by its off-diagonal magnitudes and row
    /// excesses ([`LinearSystem::m_matrix`]): every ψ to a small *relative* error however small
    /// (down to the underflow threshold). Needs a Delaunay mesh and lumped Robin mass, else
    /// [`FemError::NotMMatrix`]. Simplicial, so slower than Cholesky on large meshes.
    Accurate,
    /// Accurate up to [`AUTO_ACCURATE_MAX_UNKNOWNS`] unknowns (no slower than Cholesky there);
    /// above, Cholesky, redone accurately if ψ spans more than 1/[`AUTO_FLAT_RATIO`].
    /// Falls back to Cholesky when the system is not an M-matrix (reported by
    /// [`Solver::solve_with_report`]).
    #[default]
    Auto,
}

/// What a solve actually did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveReport {
    /// The factorisation whose solution was returned: `Cholesky` or `Accurate`.
    pub method: SolveMethod,
    /// Set when [`SolveMethod::Auto`] could not use the accurate solve because the system is
    /// not an M-matrix, so the Cholesky solution (normwise accurate only) was returned.
    pub fell_back: Option<NotMMatrix>,
}

/// A sparse solver for the systems of one [`Assembler`]. The ordering and symbolic analysis
/// are done once; each [`solve`](Solver::solve) only factors numerically, so new boundary
/// values cost only the numeric part.
pub struct Solver {
    method: SolveMethod,
    /// Ordering for the accurate factorisation, which is built on first use.
    ordering: Ordering,
    /// `None` when there are no unknowns or the Cholesky path is never needed.
    symbolic: Option<SymbolicCholesky>,
    accurate: Mutex<Option<AccurateLdlt>>,
    n: usize,
    nnz: usize,
}

impl std::fmt::Debug for Solver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solver")
            .field("method", &self.method)
            .field("unknowns", &self.n)
            .field("nnz", &self.nnz)
            .finish_non_exhaustive()
    }
}

impl Solver {
    /// [`Solver::with_method`] with [`SolveMethod::Auto`].
    pub fn new(system: &LinearSystem, ordering: Ordering) -> Result<Self, FemError> {
        Self::with_method(system, ordering, SolveMethod::Auto)
    }

    /// Prepares to solve systems with `system`'s pattern by `method`, with `ordering`
    /// ([`Assembler::nested_dissection`] is the fastest on meshes; `Ordering::Amd` needs no
    /// coordinates). For [`SolveMethod::Accurate`] fails with [`FemError::NotMMatrix`] if
    /// `system` is not an M-matrix.
    pub fn with_method(
        system: &LinearSystem,
        ordering: Ordering,
        method: SolveMethod,
    ) -> Result<Self, FemError> {
        let a = system.matrix();
        let needs_cholesky = match method {
            SolveMethod::Cholesky => true,
            SolveMethod::Accurate => {
                if let Some(reason) = system.not_m_matrix() {
                    return Err(FemError::NotMMatrix(reason));
                }
                false
            }
            SolveMethod::Auto => {
                a.n() > AUTO_ACCURATE_MAX_UNKNOWNS || system.not_m_matrix().is_some()
            }
        };
        let symbolic = if a.n() > 0 && needs_cholesky {
            Some(SymbolicCholesky::analyze(a, ordering.clone())?)
        } else {
            None
        };
        Ok(Solver {
            method,
            ordering,
            symbolic,
            accurate: Mutex::new(None),
            n: a.n(),
            nnz: a.nnz(),
        })
    }

    /// The method this solver was built with.
    pub fn method(&self) -> SolveMethod {
        self.method
    }

    /// Factors `system`'s matrix and solves; returns ψ at every mesh vertex.
    pub fn solve(&self, system: &LinearSystem) -> Result<Vec<f64>, FemError> {
        Ok(self.solve_with_report(system)?.0)
    }

    /// [`solve`](Self::solve), also saying which factorisation produced ψ.
    pub fn solve_with_report(
        &self,
        system: &LinearSystem,
    ) -> Result<(Vec<f64>, SolveReport), FemError> {
        let a = system.matrix();
        if a.n() != self.n || a.nnz() != self.nnz {
            return Err(FemError::ForeignSystem);
        }
        let report = |method, fell_back| SolveReport { method, fell_back };
        if self.n == 0 {
            return Ok((system.expand(&[])?, report(self.method, None)));
        }
        let (x, report) = match self.method {
            SolveMethod::Cholesky => (self.cholesky(system)?, report(SolveMethod::Cholesky, None)),
            SolveMethod::Accurate => (self.accurate(system)?, report(SolveMethod::Accurate, None)),
            SolveMethod::Auto => match system.not_m_matrix() {
                Some(reason) => (
                    self.cholesky(system)?,
                    report(SolveMethod::Cholesky, Some(reason)),
                ),
                None if self.n <= AUTO_ACCURATE_MAX_UNKNOWNS => {
                    (self.accurate(system)?, report(SolveMethod::Accurate, None))
                }
                None => {
                    let x = self.cholesky(system)?;
                    let max = x.iter().copied().fold(0.0, f64::max);
                    let min = x.iter().copied().fold(f64::INFINITY, f64::min);
                    if min > AUTO_FLAT_RATIO * max {
                        (x, report(SolveMethod::Cholesky, None))
                    } else {
                        (self.accurate(system)?, report(SolveMethod::Accurate, None))
                    }
                }
            },
        };
        Ok((system.expand(&x)?, report))
    }

    fn cholesky(&self, system: &LinearSystem) -> Result<Vec<f64>, FemError> {
        let symbolic = self
            .symbolic
            .as_ref()
            .expect("the symbolic Cholesky is analysed whenever the Cholesky path can run");
        Ok(symbolic.factor(system.matrix())?.solve(system.rhs())?)
    }

    fn accurate(&self, system: &LinearSystem) -> Result<Vec<f64>, FemError> {
        let m = system.m_matrix()?;
        // A poisoned lock only means another solve panicked; the factor is refactored anyway.
        let mut guard = self
            .accurate
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        match guard.as_mut() {
            Some(factor) => factor.refactor(&m)?,
            None => *guard = Some(AccurateLdlt::factor(&m, self.ordering.clone())?),
        }
        let factor = guard.as_ref().expect("factored just above");
        Ok(factor.solve(system.rhs())?)
    }

    /// Solves `system` and wraps the result as a [`Potential`] on `mesh` (the mesh the system
    /// was assembled on).
    pub fn potential(&self, mesh: Arc<Mesh>, system: &LinearSystem) -> Result<Potential, FemError> {
        Potential::new(mesh, self.solve(system)?, system.reference())
    }
}

/// One-shot convenience: assemble (lumped Robin mass), analyse with nested dissection
/// ([`Assembler::nested_dissection`]), factor and solve ([`SolveMethod::Auto`]).
/// For repeated solves on one mesh keep the [`Assembler`] and [`Solver`] instead.
pub fn solve_potential(mesh: Arc<Mesh>, bcs: &BoundaryConditions) -> Result<Potential, FemError> {
    let assembler = Assembler::new(Arc::clone(&mesh), bcs, AssemblyOptions::default())?;
    let system = assembler.assemble(bcs)?;
    let solver = Solver::new(&system, assembler.nested_dissection())?;
    solver.potential(mesh, &system)
}
