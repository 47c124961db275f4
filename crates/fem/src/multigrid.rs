//! The potential on a uniformly refined mesh by multigrid-preconditioned conjugate
//! gradients: every level of a [`MeshHierarchy`] assembled on its own, the coarsest
//! factored, P1 interpolation between the levels.
//!
//! The work grows linearly with the triangles (the direct solve's grows faster), so this is
//! the fast solve for large meshes: the 1 M-triangle reference system in a fraction of the
//! Cholesky factorisation's time. It solves to a residual tolerance, so ψ is accurate to
//! about `rel_tol` of its largest value: enough where ψ is not many orders of magnitude below
//! it. Far from a goal in a long maze ψ underflows that scale, which is what the
//! entrywise-accurate solve ([`crate::SolveMethod::Accurate`]) is for.

use std::sync::Arc;

use rayon::prelude::*;

use harmonic_solver::{
    Cholesky, Multigrid, MultigridOptions, Ordering, Parallelism, PcgReport, Prolongation,
    SolverError, SymbolicCholesky,
};
use harmonic_types::{Mesh, MeshHierarchy};

use crate::potential::{Unsound, unsound};
use crate::{
    Assembler, AssemblyOptions, BoundaryConditions, FemError, LinearSystem, Potential, SolveMethod,
    SolveReport, Solver,
};

/// The relative residual [`MultilevelSystem::solve`] stops at by default: ψ to about 1e-10
/// of its largest value, below the discretisation error of any mesh that fits in memory.
pub const MULTIGRID_REL_TOL: f64 = 1e-10;

/// Iterations after which [`MultilevelSystem::solve`] gives up (it needs about ten).
const MULTIGRID_MAX_ITER: usize = 200;

/// The reduced system of every level of a hierarchy, finest last.
#[derive(Debug)]
pub struct MultilevelSystem {
    meshes: Vec<Arc<Mesh>>,
    parents: Vec<Vec<[u32; 2]>>,
    systems: Vec<LinearSystem>,
    /// The coarsest level's assembler (for its fill-reducing ordering).
    coarsest: Assembler,
    /// The coarsest level's factor, made while the finest level was assembled (taken by the
    /// first [`MultilevelSystem::multigrid`]; `None` for a hierarchy of one level, or where
    /// it failed: the cycle then factors, and reports the failure).
    coarsest_factor: std::sync::Mutex<Option<Cholesky>>,
}

impl MultilevelSystem {
    /// Assembles `bcs` on every level of `hierarchy` (the same conditions on each: the
    /// boundary tags are the same on every level).
    pub fn assemble(hierarchy: &MeshHierarchy, bcs: &BoundaryConditions) -> Result<Self, FemError> {
        let meshes = hierarchy.levels().to_vec();
        let assemble = |mesh: &Arc<Mesh>| -> Result<(Assembler, LinearSystem), FemError> {
            let assembler = Assembler::new(Arc::clone(mesh), bcs, AssemblyOptions::default())?;
            let system = assembler.assemble(bcs)?;
            Ok((assembler, system))
        };
        // The finest level is three quarters of the work: it goes to a second thread while
        // this one assembles the others.
        let (finest, coarser) = meshes.split_last().ok_or(FemError::LengthMismatch {
            what: "levels of the hierarchy",
            expected: 1,
            got: 0,
        })?;
        // The coarser side then factors the coarsest level, which the cycle needs first.
        let (finest, coarser) = rayon::join(
            || assemble(finest),
            || -> Result<_, FemError> {
                let levels = coarser
                    .iter()
                    .map(assemble)
                    .collect::<Result<Vec<_>, _>>()?;
                let factor = levels.first().and_then(|(assembler, system)| {
                    let coarse = system.matrix();
                    SymbolicCholesky::analyze(coarse, assembler.ordering())
                        .and_then(|s| s.factor(coarse))
                        .ok()
                });
                Ok((levels, factor))
            },
        );
        let (mut levels, coarsest_factor) = coarser?;
        levels.push(finest?);
        let mut coarsest = None;
        let mut systems = Vec::with_capacity(levels.len());
        for (assembler, system) in levels {
            systems.push(system);
            coarsest.get_or_insert(assembler);
        }
        let parents = (1..meshes.len())
            .map(|l| hierarchy.parents(l).to_vec())
            .collect();
        Ok(Self {
            meshes,
            parents,
            systems,
            coarsest_factor: std::sync::Mutex::new(coarsest_factor),
            coarsest: coarsest.ok_or(FemError::LengthMismatch {
                what: "levels of the hierarchy",
                expected: 1,
                got: 0,
            })?,
        })
    }

    /// The finest level's system.
    pub fn finest(&self) -> &LinearSystem {
        &self.systems[self.systems.len() - 1]
    }

    /// The finest mesh.
    pub fn finest_mesh(&self) -> &Arc<Mesh> {
        &self.meshes[self.meshes.len() - 1]
    }

    /// The V-cycle over the levels: the coarsest factored (in its fastest ordering), the
    /// interpolations between the levels' unknowns built from the vertices' parents
    /// (unknowns at Dirichlet vertices are left out: their correction is zero).
    pub fn multigrid(&self, opts: MultigridOptions) -> Result<Multigrid, FemError> {
        let interpolations = self
            .parents
            .par_iter()
            .enumerate()
            .map(|(l, parents)| interpolation(&self.systems[l], &self.systems[l + 1], parents))
            .collect::<Result<Vec<_>, _>>()?;
        let levels = self.systems[1..]
            .iter()
            .map(LinearSystem::matrix)
            .zip(interpolations)
            .collect();
        let coarse = self.systems[0].matrix();
        let made = self.coarsest_factor.lock().ok().and_then(|mut f| f.take());
        let factor = || match made {
            Some(f) => Ok(f),
            None => SymbolicCholesky::analyze(coarse, self.coarsest.ordering())?.factor(coarse),
        };
        Ok(Multigrid::with_coarsest_from(factor, levels, opts)?)
    }

    /// ψ on the finest mesh by conjugate gradients preconditioned with `multigrid` (built by
    /// [`MultilevelSystem::multigrid`]), to a relative residual of `rel_tol`.
    pub fn solve(
        &self,
        multigrid: &Multigrid,
        rel_tol: f64,
    ) -> Result<(Potential, PcgReport), FemError> {
        let fine = self.finest();
        let mut x = vec![0.0; fine.unknown_count()];
        let report = multigrid.solve(fine.rhs(), &mut x, rel_tol, MULTIGRID_MAX_ITER)?;
        let potential = Potential::new(
            Arc::clone(self.finest_mesh()),
            fine.expand(&x)?,
            fine.reference(),
        )?;
        Ok((potential, report))
    }
}

/// Why [`MultilevelSystem::checked_potential`] did not keep the multigrid ψ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MultigridRejection {
    /// The iteration stopped before its tolerance.
    NotConverged,
    /// ψ broke the maximum principle somewhere: it is resolved only to the residual's
    /// scale, and a maze's or a long corridor's ψ falls far below it.
    Unsound(Unsound),
}

/// How [`MultilevelSystem::checked_potential`] had ψ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MultilevelSolve {
    /// The multigrid ψ, kept: no negative value, no zero beside a positive one and no
    /// interior local extremum (the discrete maximum principle holds for it, so the tracer
    /// cannot stop short of a goal).
    Multigrid(PcgReport),
    /// The multigrid ψ failed the check, so the finest level was solved directly
    /// ([`SolveMethod::Auto`]: Cholesky, checked in its turn, else the accurate solve).
    Direct {
        /// Why the multigrid ψ was not kept.
        rejected: MultigridRejection,
        /// What the direct solve did.
        report: SolveReport,
    },
}

impl MultilevelSystem {
    /// The potential on the finest mesh, by multigrid when its ψ passes the check the
    /// tracer needs, else directly: the V-cycle over the levels and conjugate gradients to
    /// `rel_tol` ([`MultilevelSystem::solve`]), then the check — the iteration converged,
    /// and at the unknowns no ψ is negative, none is zero beside a positive one (underflow)
    /// and none is an interior local extremum. A ψ that falls
    /// below the residual's scale (a long maze, a corridor) fails it, and the finest level is
    /// factored instead (in `parallelism`), on the same mesh: the path is never worse for
    /// having tried the fast solve first.
    pub fn checked_potential(
        &self,
        rel_tol: f64,
        parallelism: Parallelism,
    ) -> Result<(Potential, MultilevelSolve), FemError> {
        let fine = self.finest();
        let cycle = self.multigrid(MultigridOptions::default())?;
        let rejected = match self.solve(&cycle, rel_tol) {
            Ok((potential, report)) => {
                match unsound(self.finest_mesh(), potential.psi(), fine.free_vertices()) {
                    None => return Ok((potential, MultilevelSolve::Multigrid(report))),
                    Some(why) => MultigridRejection::Unsound(why),
                }
            }
            Err(FemError::Solver(SolverError::NotConverged { .. })) => {
                MultigridRejection::NotConverged
            }
            Err(e) => return Err(e),
        };
        drop(cycle);
        let mesh = self.finest_mesh();
        let vertices = mesh.vertices();
        let coords = fine
            .free_vertices()
            .iter()
            .map(|&v| [vertices[v as usize].x, vertices[v as usize].y])
            .collect();
        let solver = Solver::with_parallelism(
            fine,
            Ordering::NestedDissection { coords },
            SolveMethod::Auto,
            parallelism,
        )?;
        let (potential, report) = solver.potential_with_report(Arc::clone(mesh), fine)?;
        Ok((potential, MultilevelSolve::Direct { rejected, report }))
    }
}

/// P1 interpolation from `below`'s unknowns to `here`'s: a vertex kept takes its coarse
/// value, an edge midpoint the mean of the edge's ends (Dirichlet ends contribute nothing).
fn interpolation(
    below: &LinearSystem,
    here: &LinearSystem,
    parents: &[[u32; 2]],
) -> Result<Prolongation, FemError> {
    let mut row_ptr = Vec::with_capacity(here.unknown_count() + 1);
    let mut columns = Vec::with_capacity(2 * here.unknown_count());
    let mut values = Vec::with_capacity(2 * here.unknown_count());
    row_ptr.push(0);
    for &v in here.free_vertices() {
        let [a, b] = parents
            .get(v as usize)
            .copied()
            .ok_or(FemError::LengthMismatch {
                what: "parents of the finer level's vertices",
                expected: v as usize + 1,
                got: parents.len(),
            })?;
        let ends: &[(u32, f64)] = if a == b {
            &[(a, 1.0)]
        } else {
            &[(a, 0.5), (b, 0.5)]
        };
        for &(p, w) in ends {
            if let Some(u) = below.unknown_of(p) {
                columns.push(u);
                values.push(w);
            }
        }
        row_ptr.push(columns.len());
    }
    Ok(Prolongation::try_new(
        below.unknown_count(),
        row_ptr,
        columns,
        values,
    )?)
}
