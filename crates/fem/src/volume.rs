//! P1 finite elements on tetrahedra (`harmonic_volume::TetMesh`): the same mathematics as
//! the 2D assembler — stiffness `K_ij = Σ_T V_T ∇λ_i·∇λ_j` assembled straight into compressed
//! sparse storage, Dirichlet lifting, Neumann load, lumped Robin mass — and the same ψ = c − φ
//! convention (see the crate docs). Boundary faces are tagged with the 2D
//! `harmonic_mesh::BoundaryTag`, so `crate::BoundaryConditions` applies unchanged.
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
//! use harmonic_volume::{GoalRegion, MeshOptions, Point, Solid, Part, SphereSolid, VolumeDomain};
//!
//! let domain = VolumeDomain::new(
//!     Solid::new_box(Part::Workspace, Point::new(0.0, 0.0, 0.0), Point::new(2.0, 2.0, 2.0))?,
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
    CLAMP_KEEP, NegativeWeights, VolumeAssembler, VolumeAssemblyOptions, VolumeBoundaryData,
    VolumeSystem,
};
pub use periodic::{
    PeriodicSolveReport, assemble_periodic_for_planning, identify_periodic, periodic_conditions,
    solve_folded_for_planning, solve_periodic_for_planning,
};
pub use potential::{VolumeEvaluation, VolumePotential};
pub use solve::{
    AUTO_ACCURATE_MAX_UNKNOWNS_3D, AUTO_CHOLESKY_MAX_UNKNOWNS, FLAT_RATIO_3D,
    PLANNING_ACCURATE_MAX_UNKNOWNS, PLANNING_CHOLESKY_MAX_UNKNOWNS, PLANNING_PCG_TOL,
    VolumeSolveMethod, VolumeSolveReport, planning_method, solve_assembled_for_planning,
    solve_volume, solve_volume_potential, solve_volume_potential_with_report,
};

use crate::FemError;
