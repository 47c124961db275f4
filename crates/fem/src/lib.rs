//! # harmonic-fem
//!
//! P1 (piecewise linear) finite elements for Laplace's equation on a triangulated free space,
//! the numerical core of the harmonic planner: stiffness by the cotangent formula assembled
//! straight into compressed sparse storage, Robin boundary mass and load, Neumann load and
//! Dirichlet lifting; the solution as a [`Potential`] with point values, element gradients,
//! recovered nodal gradients and an error indicator. For large meshes, [`MultilevelSystem`]
//! solves on a uniformly refined mesh by multigrid-preconditioned conjugate gradients, in
//! linear time.
//!
//! ## The ψ convention
//! Far from the goal a Dirichlet potential φ is within 1e-17 of the wall value, so a float φ
//! loses every digit there. This crate therefore solves for **ψ = c − φ**, where `c` is the
//! reference "high" value (the largest Dirichlet value or Robin equilibrium value `g/b`; 1 for
//! the defaults), and keeps ψ's relative precision however small it becomes. Each condition
//! is transformed exactly: Dirichlet `v` → ψ = c − v; Neumann `g` → ∂ψ/∂n = −g; Robin
//! `a∂φ/∂n + bφ = g` → `a∂ψ/∂n + bψ = b·c − g`. The robot ascends ψ (descends φ).
//!
//! ## Accurate far fields (issue #11)
//! ψ in f64 keeps its relative precision only if the solve does too. On a Delaunay mesh with
//! Dirichlet and lumped-Robin walls the reduced matrix is a diagonally dominant M-matrix, and
//! the assembler also records each row's excess (edge weights to prescribed vertices plus
//! Robin mass, a sum of non-negative terms — [`LinearSystem::excess`]). [`SolveMethod::Accurate`]
//! eliminates with the off-diagonal weights and these excesses as primary data
//! ([`harmonic_solver::AccurateLdlt`]), so every ψ has a small relative error down to 1e-300.
//! A Cholesky pivot `a_ii − Σ l² d` instead loses the excess when it is tiny against the
//! diagonal: on a 2-row strip with Robin walls `b/a = 1e-6` (ψ down to 1e-61) Cholesky is off by
//! 8e-9 relative, the accurate solve by 3e-14 (`tests/flat_fields.rs` at the workspace root).
//! Costs measured on the reference scene with nested dissection (first solve = analysis,
//! factorisation and solve; `cargo test --release --test flat_fields -- --ignored --nocapture
//! accurate_solve_cost`, two runs on the 2-core machine, 07 Dec 2026): 14 k unknowns 22–23 ms
//! Cholesky against 14–15 ms accurate; 73 k 92–124 ms against 88–114 ms; 148 k 214–256 ms
//! against 238 ms (0.93–1.11×); 296 k 0.46–0.55 s against 0.52–0.66 s (1.12–1.19×); 494 k
//! 1.01 s against 1.23 s. (Before the multifrontal elimination it was 0.27 s against 0.60 s
//! at 148 k.) A flat field above the threshold costs a Cholesky solve, the check and the
//! accurate solve. Hence the default [`SolveMethod::Auto`]: accurate up to
//! [`AUTO_ACCURATE_MAX_UNKNOWNS`] (150 k), above that Cholesky, redone accurately only when ψ
//! spans more than 1/[`AUTO_FLAT_RATIO`] and fails the maximum-principle check.
//!
//! ```
//! use std::sync::Arc;
//! use harmonic_fem::{
//!     Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions, SolveMethod, Solver,
//! };
//! use harmonic_mesh::{BoundaryTag, Mesh, Point};
//!
//! // A 40 × 1 strip of right triangles, goal on the left side, Robin walls ∂ψ/∂n + 50ψ = 0.
//! let n = 80u32;
//! let vertices = (0..=n)
//!     .flat_map(|i| [Point::new(0.5 * i as f64, 0.0), Point::new(0.5 * i as f64, 1.0)])
//!     .collect();
//! let triangles = (0..n)
//!     .flat_map(|i| [[2 * i, 2 * i + 2, 2 * i + 3], [2 * i, 2 * i + 3, 2 * i + 1]])
//!     .collect();
//! let mut boundary = vec![(1, 0, BoundaryTag::Goal(0)), (2 * n, 2 * n + 1, BoundaryTag::Wall)];
//! for i in 0..n {
//!     boundary.push((2 * i, 2 * i + 2, BoundaryTag::Wall));
//!     boundary.push((2 * i + 3, 2 * i + 1, BoundaryTag::Wall));
//! }
//! let mesh = Arc::new(Mesh::from_parts(vertices, triangles, &boundary)?);
//! let bcs = BoundaryConditions::uniform(BoundaryCondition::Robin { a: 1.0, b: 50.0, g: 50.0 });
//! let bcs = BoundaryConditions { goals: BoundaryCondition::Dirichlet(0.0), ..bcs };
//! let assembler = Assembler::new(mesh.clone(), &bcs, AssemblyOptions::default())?;
//! let system = assembler.assemble(&bcs)?;
//! assert!(system.not_m_matrix().is_none());
//! let solver = Solver::with_method(&system, assembler.nested_dissection(), SolveMethod::Accurate)?;
//! let potential = solver.potential(mesh, &system)?;
//! let bottom: Vec<f64> = potential.psi().iter().step_by(2).copied().collect();
//! // ψ falls by a factor of about 30 per column, to about 1e-118 at the far end, and keeps
//! // every digit: each column's ratio to the next stays the same.
//! let far = bottom[n as usize];
//! assert!(far > 0.0 && far < 1e-100);
//! let ratio = |i: usize| bottom[i] / bottom[i + 1];
//! assert!((ratio(10) - ratio(60)).abs() < 1e-10 * ratio(10));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Flow
//! [`Assembler::new`] computes the sparsity pattern and the Dirichlet map once for a mesh and
//! the *kinds* of its boundary conditions; [`Assembler::assemble`] fills values for any
//! conditions of the same kinds; [`Solver`] keeps the symbolic Cholesky factorisation so a
//! replan with new values only refactors numerically.
//!
//! ```
//! use std::sync::Arc;
//! use harmonic_fem::{BoundaryConditions, solve_potential};
//! use harmonic_mesh::{BoundaryTag, Mesh, Point};
//!
//! // A unit square in two triangles plus a centre vertex; the goal is the bottom side.
//! let vertices = vec![
//!     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0),
//!     Point::new(0.0, 1.0), Point::new(0.5, 0.5),
//! ];
//! let triangles = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
//! let boundary = [
//!     (0, 1, BoundaryTag::Goal(0)),
//!     (1, 2, BoundaryTag::Wall),
//!     (2, 3, BoundaryTag::Wall),
//!     (3, 0, BoundaryTag::Wall),
//! ];
//! let mesh = Arc::new(Mesh::from_parts(vertices, triangles, &boundary)?);
//! let potential = solve_potential(mesh, &BoundaryConditions::default())?;
//! // The centre vertex is the only unknown: the mean of its four neighbours 0, 0, 1, 1.
//! assert!((potential.phi_at_vertices()[4] - 0.5).abs() < 1e-12);
//! assert_eq!(potential.interior_local_extrema(), 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod assemble;
mod bc;
mod goals;
mod multigrid;
mod potential;
mod solve;
mod structured;
pub mod volume;

pub use assemble::{
    Assembler, AssemblyOptions, BoundaryData, LinearSystem, NATURAL_ORDER_BELOW, NotMMatrix,
    RobinMass, offdiagonal_sign_violations,
};
pub use bc::{BoundaryCondition, BoundaryConditions, ConditionKind};
pub use goals::{BLOCK_COLUMNS, GoalReport, GoalSolution, GoalSolver, MAX_GOAL_RIM};
pub use multigrid::{MULTIGRID_REL_TOL, MultigridRejection, MultilevelSolve, MultilevelSystem};
pub use potential::{
    Evaluation, LocalExtrema, Potential, Unsound, blend, interior_local_extrema,
    interior_local_extrema_except,
};
pub use solve::{
    AUTO_ACCURATE_MAX_UNKNOWNS, AUTO_FLAT_RATIO, EXTENDED_BELOW, SolveMethod, SolveReport, Solver,
    solve_potential,
};
pub use structured::{StructuredGrid, StructuredSystem, VertexRole};

/// Re-exported so callers can pick an ordering without depending on the solver crate.
pub use harmonic_solver::{MultigridOptions, Ordering, Parallelism, PcgReport, Wide};

/// A point named in an error: of the plane or of space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum At {
    /// `(x, y)`.
    Plane([f64; 2]),
    /// `(x, y, z)`.
    Space([f64; 3]),
}

impl At {
    /// The coordinates.
    pub fn coords(&self) -> &[f64] {
        match self {
            At::Plane(c) => c,
            At::Space(c) => c,
        }
    }
}

impl From<harmonic_types::Point> for At {
    fn from(p: harmonic_types::Point) -> At {
        At::Plane([p.x, p.y])
    }
}

impl From<harmonic_types::Point3> for At {
    fn from(p: harmonic_types::Point3) -> At {
        At::Space([p.x, p.y, p.z])
    }
}

impl std::fmt::Display for At {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            At::Plane([x, y]) => write!(f, "({x}, {y})"),
            At::Space([x, y, z]) => write!(f, "({x}, {y}, {z})"),
        }
    }
}

/// Everything that can go wrong while assembling, solving or evaluating, on triangles and on
/// tetrahedra.
#[derive(Debug, thiserror::Error)]
pub enum FemError {
    /// A conductivity (the coefficient k of ∇·(k∇φ) = 0) that is not a positive finite number.
    #[error("the conductivity of triangle {triangle} is {value}, not a positive finite number")]
    BadConductivity {
        /// The triangle.
        triangle: usize,
        /// The offending value.
        value: f64,
    },
    /// An absorption (the coefficient σ of −∇·(k∇φ) + σ(φ − c) = 0) that is negative, NaN or
    /// infinite.
    #[error("the absorption of triangle {triangle} is {value}, not a finite number ≥ 0")]
    BadAbsorption {
        /// The triangle.
        triangle: usize,
        /// The offending value.
        value: f64,
    },
    /// Conductivities given for a different number of triangles than the mesh has.
    #[error(
        "{got} coefficients (conductivities or absorptions) for a mesh of {expected} triangles"
    )]
    ConductivityCount {
        /// Triangles in the mesh.
        expected: usize,
        /// Values given.
        got: usize,
    },
    /// A boundary condition holds NaN or an infinity.
    #[error("boundary condition on {part}: {what} is {value}, not a finite number")]
    NonFinite {
        /// The boundary part ("walls", "obstacle 3", ...).
        part: String,
        /// Which number.
        what: String,
        /// The offending value.
        value: f64,
    },
    /// A Robin condition with `a = b = 0`.
    #[error("boundary condition on {part}: Robin a and b are both zero, so it says nothing")]
    RobinBothZero {
        /// The boundary part.
        part: String,
    },
    /// A Robin condition with `b/a < 0`, which makes the problem indefinite.
    #[error(
        "boundary condition on {part}: Robin b/a = {ratio} is negative; the problem would be indefinite (use b/a ≥ 0)"
    )]
    NegativeRobin {
        /// The boundary part.
        part: String,
        /// The ratio b/a.
        ratio: f64,
    },
    /// Boundary data from a [`BoundaryData`] callback is not finite.
    #[error("boundary data on {part} at {at} is {value}, not a finite number")]
    NonFiniteData {
        /// The boundary part.
        part: String,
        /// Where.
        at: At,
        /// The offending value.
        value: f64,
    },
    /// A connected piece of free space has neither a Dirichlet part nor a Robin part with
    /// `b/a > 0`.
    #[error(
        "only Neumann conditions on connected component {component} of free space (around {at}): the potential is defined up to a constant; hold a part (e.g. the goal) by a Dirichlet condition or use Robin with b/a > 0"
    )]
    OnlyNeumann {
        /// The component index (by triangle or tetrahedron adjacency).
        component: u32,
        /// A vertex of that component.
        at: At,
    },
    /// Every Dirichlet value and Robin equilibrium value is the same and no flux enters.
    #[error(
        "nothing drives the flow: every Dirichlet value and Robin equilibrium g/b equals {value} and no Neumann or Robin flux enters, so the potential is the constant {value}; give the goal a different value"
    )]
    ConstantPotential {
        /// The single boundary value.
        value: f64,
    },
    /// [`Assembler::assemble`] was given conditions whose kind on some part differs from the
    /// ones the assembler was built for.
    #[error(
        "boundary part {part} was {was:?} when the assembler was built but is {now:?} now; build a new Assembler"
    )]
    KindChanged {
        /// The boundary part.
        part: String,
        /// Kind at construction.
        was: ConditionKind,
        /// Kind now.
        now: ConditionKind,
    },
    /// [`Assembler::assemble_into`] was handed a system made by a different assembler.
    #[error("the linear system was not made by this assembler (different pattern)")]
    ForeignSystem,
    /// The mesh is too large for 32-bit positions in the sparse matrix.
    #[error("the matrix has {nnz} stored entries, more than this crate indexes (u32)")]
    TooLarge {
        /// The number of stored entries.
        nnz: usize,
    },
    /// Two things that must have the same length do not.
    #[error("{what}: expected length {expected}, got {got}")]
    LengthMismatch {
        /// What was checked.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
    /// A point lies outside the mesh.
    #[error("point {at} is outside the mesh (in an obstacle or beyond the walls)")]
    OutsideMesh {
        /// The point.
        at: At,
    },
    /// Two potentials on different meshes were combined.
    #[error("the potentials live on different meshes")]
    DifferentMeshes,
    /// A blending weight outside [0, 1].
    #[error("blending weight k = {k} must lie in [0, 1]")]
    BadWeight {
        /// The weight.
        k: f64,
    },
    /// The entrywise-accurate solve was asked for a system that is not an M-matrix with
    /// non-negative primary data.
    #[error("the accurate (M-matrix) solve does not apply: {0}")]
    NotMMatrix(NotMMatrix),
    /// [`GoalSolver::new`] needs the goal held by a Dirichlet value (its vertices are held
    /// at that level).
    #[error(
        "goals chosen later are held at a Dirichlet value: give the goal a Dirichlet condition"
    )]
    GoalNotDirichlet,
    /// [`GoalSolver::new`] was given a mesh that already has goal edges.
    #[error(
        "the mesh already has a goal; a goal solver needs a mesh without one (goals come later, as vertices)"
    )]
    GoalInMesh,
    /// Without a goal nothing holds the potential: every wall is Neumann.
    #[error(
        "the walls hold nothing (only Neumann conditions around {at}), so without a goal the system is singular and cannot be factored once for all goals; give the walls a Dirichlet or Robin (b/a > 0) part, or build the planner with its goal"
    )]
    WallsHoldNothing {
        /// A vertex of the unheld part.
        at: At,
    },
    /// A goal with no vertex.
    #[error("goal {goal} holds no mesh vertex")]
    EmptyGoal {
        /// The goal's index in the request.
        goal: usize,
    },
    /// A goal names a vertex whose value is already prescribed (on a Dirichlet wall) or
    /// that is not a vertex of the mesh's triangles.
    #[error("goal {goal}: vertex {vertex} is not free (on a Dirichlet wall, or not a mesh vertex)")]
    GoalVertexNotFree {
        /// The goal's index in the request.
        goal: usize,
        /// The vertex.
        vertex: u32,
    },
    /// A goal region whose rim needs more columns than allowed.
    #[error(
        "goal {goal} has {rim} vertices on its rim, more than {max}; use a smaller goal region"
    )]
    GoalTooLarge {
        /// The goal's index in the request.
        goal: usize,
        /// Its rim size.
        rim: usize,
        /// The limit ([`MAX_GOAL_RIM`]).
        max: usize,
    },
    /// The goal's small dense system could not be solved (non-finite fluxes).
    #[error("the goal's flux system is singular")]
    GoalSingular,
    /// PCG did not reach its tolerance.
    #[error("PCG stopped after {iterations} iterations at relative residual {residual:e}")]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// The relative residual reached.
        residual: f64,
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
