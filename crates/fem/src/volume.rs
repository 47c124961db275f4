//! P1 finite elements on tetrahedra ([`harmonic_volume::TetMesh`]): the same mathematics as
//! the 2D assembler — stiffness `K_ij = Σ_T V_T ∇λ_i·∇λ_j` assembled straight into compressed
//! sparse storage, Dirichlet lifting, Neumann load, lumped Robin mass — and the same ψ = c − φ
//! convention (see the crate docs). Boundary faces are tagged with the 2D
//! [`harmonic_mesh::BoundaryTag`], so [`crate::BoundaryConditions`] applies unchanged.
//!
//! The reduced matrix is an M-matrix exactly when every edge between unknowns has a
//! non-negative summed weight `−K_ij` (in 3D: when the cotangent-of-dihedral-angle sums are
//! non-negative). Isosurface-stuffed meshes are not always there (obtuse dihedral angles in
//! the clipped boundary layer), so [`VolumeSystem::positive_offdiagonals`] counts the
//! exceptions and [`VolumePotential::interior_local_extrema`] checks the discrete maximum
//! principle on the solution instead of assuming it; [`solve_volume_potential`] falls back on
//! the clamped stiffness ([`NegativeWeights::Clamp`], an M-matrix) when the Galerkin solution
//! has an interior extremum. [`VolumeSolveMethod::Auto`] uses the entrywise-accurate
//! M-matrix elimination ([`harmonic_solver::AccurateLdlt`]) on small M-matrix systems, faer's
//! Cholesky (AMD ordering) up to [`AUTO_CHOLESKY_MAX_UNKNOWNS`] unknowns and IC(0)-PCG above
//! (50.6k unknowns: PCG 0.16 s, Cholesky 3.9 s, accurate 69 s).
//!
//! A periodic mesh (a configuration space's angles, `harmonic_volume::PeriodicMesh`) is
//! solved on its slab of one period with the ends identified: [`identify_periodic`] folds the
//! assembled system, [`solve_periodic_for_planning`] is the planning solve on it.
//!
//! ```
//! use std::sync::Arc;
//! use harmonic_fem::BoundaryConditions;
//! use harmonic_fem::volume::solve_volume_potential;
//! use harmonic_volume::{GoalRegion, MeshOptions, Point, Solid, SolidRole, SphereSolid, VolumeDomain};
//!
//! let domain = VolumeDomain::new(
//!     Solid::new_box(SolidRole::Workspace, Point::new(0.0, 0.0, 0.0), Point::new(2.0, 2.0, 2.0))?,
//!     vec![],
//!     vec![GoalRegion::Sphere(SphereSolid { center: Point::new(1.0, 1.0, 1.0), radius: 0.4 })],
//!     0.0,
//! )?;
//! let (mesh, _) = domain.mesh(&MeshOptions::with_max_volume(0.002))?;
//! let potential = solve_volume_potential(Arc::new(mesh), &BoundaryConditions::default())?;
//! assert_eq!(potential.interior_local_extrema(), 0);
//! // Between the goal (φ = 0) and the walls (φ = 1).
//! let e = potential.evaluate(&Point::new(1.0, 1.0, 1.7), None)?;
//! assert!(e.phi > 0.2 && e.phi < 0.9);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod assemble;
mod periodic;
mod potential;
mod solve;

pub use assemble::{
    NegativeWeights, VolumeAssembler, VolumeAssemblyOptions, VolumeBoundaryData, VolumeSystem,
};
pub use periodic::{
    PeriodicSolveReport, identify_periodic, periodic_conditions, solve_periodic_for_planning,
};
pub use potential::{VolumeEvaluation, VolumePotential};
pub use solve::{
    AUTO_ACCURATE_MAX_UNKNOWNS_3D, AUTO_CHOLESKY_MAX_UNKNOWNS, FLAT_RATIO_3D,
    PLANNING_ACCURATE_MAX_UNKNOWNS, PLANNING_CHOLESKY_MAX_UNKNOWNS, PLANNING_PCG_TOL,
    VolumeSolveMethod, VolumeSolveReport, planning_method, solve_assembled_for_planning,
    solve_volume, solve_volume_potential, solve_volume_potential_with_report,
};

use crate::FemError;

/// Errors of the tetrahedral FEM.
#[derive(Debug, thiserror::Error)]
pub enum VolumeFemError {
    /// A boundary condition is invalid (names the part).
    #[error(transparent)]
    Condition(#[from] FemError),
    /// A connected piece of free space has neither a Dirichlet part nor a Robin part with
    /// `b/a > 0`.
    #[error(
        "only Neumann conditions on connected component {component} of free space (around ({x}, {y}, {z})): the potential is defined up to a constant; hold a part (e.g. the goal) by a Dirichlet condition or use Robin with b/a > 0"
    )]
    OnlyNeumann {
        /// The component (by tetrahedron adjacency).
        component: u32,
        /// A vertex of it.
        x: f64,
        /// A vertex of it.
        y: f64,
        /// A vertex of it.
        z: f64,
    },
    /// Every boundary value is the same and no flux enters.
    #[error(
        "nothing drives the flow: every Dirichlet value and Robin equilibrium g/b equals {value} and no Neumann or Robin flux enters, so the potential is the constant {value}; give the goal a different value"
    )]
    ConstantPotential {
        /// The single boundary value.
        value: f64,
    },
    /// Boundary data from a callback is not finite.
    #[error("boundary data on {part} at ({x}, {y}, {z}) is {value}, not a finite number")]
    NonFiniteData {
        /// The boundary part.
        part: String,
        /// Where.
        x: f64,
        /// Where.
        y: f64,
        /// Where.
        z: f64,
        /// The value.
        value: f64,
    },
    /// Conditions whose kind on a part differs from the assembler's.
    #[error(
        "boundary part {part} changed between Dirichlet and flux conditions; build a new VolumeAssembler"
    )]
    KindChanged {
        /// The part.
        part: String,
    },
    /// A system from another assembler.
    #[error("the linear system was not made by this assembler")]
    ForeignSystem,
    /// More stored entries than 32-bit positions hold.
    #[error("the matrix has {nnz} stored entries, more than this assembler indexes (u32)")]
    TooLarge {
        /// Stored entries.
        nnz: usize,
    },
    /// The accurate solve was asked for a system that is not an M-matrix.
    #[error("the accurate (M-matrix) solve does not apply: {0}")]
    NotMMatrix(String),
    /// PCG did not reach its tolerance.
    #[error("PCG stopped after {iterations} iterations at relative residual {residual:e}")]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// The relative residual reached.
        residual: f64,
    },
    /// A point outside the mesh.
    #[error("point ({x}, {y}, {z}) is outside the mesh (in an obstacle or beyond the walls)")]
    OutsideMesh {
        /// The point.
        x: f64,
        /// The point.
        y: f64,
        /// The point.
        z: f64,
    },
    /// A per-vertex slice of the wrong length.
    #[error("{what}: expected {expected} entries, got {got}")]
    LengthMismatch {
        /// What.
        what: &'static str,
        /// Expected.
        expected: usize,
        /// Got.
        got: usize,
    },
    /// A periodic identification that pairs an unknown with a prescribed vertex (or with
    /// no vertex): the slab's two ends do not match.
    #[error(
        "periodic mesh: vertex {vertex} is identified with vertex {image}, but not both are unknowns"
    )]
    PeriodicMismatch {
        /// The vertex.
        vertex: u32,
        /// What it is identified with.
        image: u32,
    },
    /// The sparse solver failed.
    #[error("linear solve failed: {0}")]
    Solver(#[from] harmonic_solver::SolverError),
}
