//! Solving the reduced system with a reusable symbolic Cholesky factorisation.

use std::sync::Arc;

use harmonic_mesh::Mesh;
use harmonic_solver::{Ordering, SymbolicCholesky};

use crate::FemError;
use crate::assemble::{Assembler, AssemblyOptions, LinearSystem};
use crate::bc::BoundaryConditions;
use crate::potential::Potential;

/// A sparse Cholesky solver for the systems of one [`Assembler`]: the symbolic analysis
/// (ordering, elimination tree, pattern of the factor) is done once by [`Solver::new`];
/// [`Solver::solve`] factors numerically and solves, so new boundary values cost only the
/// numeric part.
pub struct Solver {
    /// `None` when there are no unknowns (every vertex prescribed).
    symbolic: Option<SymbolicCholesky>,
    n: usize,
    nnz: usize,
}

impl std::fmt::Debug for Solver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solver")
            .field("unknowns", &self.n)
            .field("nnz", &self.nnz)
            .finish_non_exhaustive()
    }
}

impl Solver {
    /// Analyses the pattern of `system`'s matrix with `ordering`:
    /// [`Assembler::nested_dissection`] is the fastest on meshes (see the `fem` bench);
    /// `Ordering::Amd` needs no coordinates.
    pub fn new(system: &LinearSystem, ordering: Ordering) -> Result<Self, FemError> {
        let a = system.matrix();
        let symbolic = if a.n() == 0 {
            None
        } else {
            Some(SymbolicCholesky::analyze(a, ordering)?)
        };
        Ok(Solver {
            symbolic,
            n: a.n(),
            nnz: a.nnz(),
        })
    }

    /// Factors `system`'s matrix and solves; returns ψ at every mesh vertex.
    pub fn solve(&self, system: &LinearSystem) -> Result<Vec<f64>, FemError> {
        let a = system.matrix();
        if a.n() != self.n || a.nnz() != self.nnz {
            return Err(FemError::ForeignSystem);
        }
        let x = match &self.symbolic {
            None => Vec::new(),
            Some(symbolic) => symbolic.factor(a)?.solve(system.rhs())?,
        };
        system.expand(&x)
    }

    /// Solves `system` and wraps the result as a [`Potential`] on `mesh` (the mesh the system
    /// was assembled on).
    pub fn potential(&self, mesh: Arc<Mesh>, system: &LinearSystem) -> Result<Potential, FemError> {
        Potential::new(mesh, self.solve(system)?, system.reference())
    }
}

/// One-shot convenience: assemble (lumped Robin mass), analyse with nested dissection
/// ([`Assembler::nested_dissection`]), factor and solve.
/// For repeated solves on one mesh keep the [`Assembler`] and [`Solver`] instead.
pub fn solve_potential(mesh: Arc<Mesh>, bcs: &BoundaryConditions) -> Result<Potential, FemError> {
    let assembler = Assembler::new(Arc::clone(&mesh), bcs, AssemblyOptions::default())?;
    let system = assembler.assemble(bcs)?;
    let solver = Solver::new(&system, assembler.nested_dissection())?;
    solver.potential(mesh, &system)
}
