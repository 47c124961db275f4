//! Sparse symmetric positive definite solves for the harmonic planner, behind one small API and
//! with no mesh types.
//!
//! * [`SymmetricCsc`]: the matrix (full symmetric pattern, validated once).
//! * Direct: [`SymbolicCholesky::analyze`] (fill-reducing [`Ordering`] + faer's supernodal symbolic
//!   factorisation, done once per pattern), [`SymbolicCholesky::factor`] (numeric `L Lᵀ`, redone
//!   whenever only the values change), [`Cholesky::solve`]; [`solve_direct`] does all three.
//! * Iterative: [`pcg`] with [`Preconditioner::Jacobi`] or [`Preconditioner::IncompleteCholesky`],
//!   for systems whose factor will not fit in memory; [`pcg_with`] with a [`Precondition`] of
//!   the caller's, such as [`Multigrid`]: a V-cycle over levels the caller gives (the matrices
//!   of a mesh and its uniform refinements, with the [`Prolongation`]s between them), whose
//!   iteration count does not grow with the mesh (7–8 to a relative residual of 1e-10 on the
//!   reference scene from 6 k to 1 M triangles), or levels built from the matrix alone by
//!   smoothed aggregation ([`Multigrid::aggregation`], [`AggregationOptions`]: 18 iterations
//!   on 891 k unknowns of a stuffed tetrahedral mesh).
//! * Accurate: [`AccurateLdlt`] factors an [`MMatrix`] given by its off-diagonal magnitudes and
//!   row excesses with no subtractive cancellation, so solutions spanning 1e-300..1 keep their
//!   relative accuracy entrywise (issue #11, the far-from-goal potential). [`WideLdlt`] is the
//!   same elimination in [`Wide`] numbers (an `f64` mantissa with a separate exponent), for
//!   solutions past the double range (issue #19: ψ ≈ 1e-1364 in a corridor of 1000 widths).
//! * [`gallery`]: FEM-like test matrices.
//!
//! Threads: [`SymbolicCholesky::analyze_with`] takes a [`Parallelism`]. By default systems of
//! [`PARALLEL_MIN_UNKNOWNS`] unknowns and more use rayon's pool for the nested-dissection
//! ordering, which dissects the halves of its large pieces on two threads (the same
//! numbering); faer's numeric Cholesky and solves stay on the calling thread, which measured
//! faster on two cores (see [`Parallelism`]; `dense_kernels: true` puts them on the pool, the
//! same factor to rounding). [`Multigrid`] puts the products and the Gauss–Seidel sweeps of
//! levels from [`PARALLEL_MIN_UNKNOWNS`] unknowns on the pool, and its aggregation the
//! prolongation's rows and the Galerkin product. Smaller systems,
//! [`Parallelism::Sequential`] and every other solver here run on the calling thread.
//!
//! # Which ordering
//!
//! For FEM systems pass [`Ordering::NestedDissection`] with the coordinates of the unknowns' mesh
//! vertices: on 2D meshes it factors faster than [`Ordering::Amd`] (the default, which needs no
//! coordinates). Measured on the 7-point triangulated-grid Laplacian with 499 849 unknowns and
//! 3.49 M stored entries (`cargo run -p harmonic-solver --release --example orderings -- 707`,
//! best of 3 per stage, on a shared 2-core machine at load average 6, so wall times are
//! pessimistic; CPU time is that of the fastest run):
//!
//! | ordering | len(L) | symbolic | numeric | solve | total wall | total CPU |
//! |----------|--------|----------|---------|-------|------------|-----------|
//! | AMD      | 37.6 M | 0.47 s   | 0.74 s  | 0.10 s | 1.32 s    | 0.97 s    |
//! | ND       | 36.9 M | 0.27 s   | 0.60 s  | 0.12 s | 1.00 s    | 0.72 s    |
//!
//! With the unknowns numbered randomly (as an unstructured mesh numbers them; `SHUFFLE=1`), ND
//! is unaffected while AMD's analysis slows down (150k unknowns: 0.65 s vs 1.05 s in total).
//!
//! IC(0)-PCG needs 574 iterations (≈ 11 s) on the same system to reach 1e-10: it is the fallback
//! for systems whose factor does not fit in memory, not a competitor. [`AccurateLdlt`] is
//! multifrontal (dense fronts, subtrees on the thread pool, the same factor at any thread
//! count): with the same example on 2 threads, ordering + factor + solve took 0.023 s at 15 k
//! unknowns, 0.23 s at 116 k and 1.60 s at 500 k, beside faer's Cholesky's 0.029 s (AMD),
//! 0.26 s and 1.39 s (nested dissection); the simplicial elimination it replaced was ≈ 4×
//! slower than faer at 150 k and ≈ 15× at 500 k.
//!
//! ```
//! use harmonic_solver::{gallery, solve_direct};
//! let (a, _coords) = gallery::triangulated_grid_laplacian(10, 10);
//! let b = vec![1.0; a.n()];
//! let x = solve_direct(&a, &b)?;
//! let mut ax = vec![0.0; a.n()];
//! a.mul_vec(&x, &mut ax);
//! assert!(ax.iter().zip(&b).all(|(l, r)| (l - r).abs() < 1e-12));
//! # Ok::<(), harmonic_solver::SolverError>(())
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod aggregation;
mod csc;
mod direct;
mod error;
pub mod gallery;
mod kept_order;
mod mmatrix;
mod multigrid;
mod ordering;
mod parallel;
mod pcg;
mod wide;
mod wide_ldlt;

pub use aggregation::AggregationOptions;
pub use csc::SymmetricCsc;
pub use direct::{Cholesky, SymbolicCholesky, solve_direct};
pub use error::{SolverError, StructureIssue};
pub use kept_order::KeptOrder;
pub use mmatrix::{AccurateLdlt, LdltAnalysis, MMatrix};
pub use multigrid::{Multigrid, MultigridOptions, Prolongation};
pub use ordering::Ordering;
pub use parallel::{PARALLEL_MIN_UNKNOWNS, Parallelism};
pub use pcg::{PcgOptions, PcgReport, Precondition, Preconditioner, pcg, pcg_with};
pub use wide::Wide;
pub use wide_ldlt::WideLdlt;
