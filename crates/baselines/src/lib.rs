//! # harmonic-baselines
//!
//! The comparison planners of the seed papers, so the finite-element harmonic planner can be
//! measured against them on the same scenes, the same tracer and the same metrics.
//!
//! - [`grid_harmonic`]: Connolly, Burns & Weiss (1990), *Path planning using Laplace's
//!   equation*: the 5-point Laplacian on an occupancy grid ([`Raster`]), relaxed by
//!   Gauss–Seidel or red–black SOR, followed by bilinear interpolation.

mod error;
pub mod grid_harmonic;
mod raster;

pub use error::BaselineError;
pub use grid_harmonic::{GridHarmonic, Relaxation, SolveReport, SorOptions, StopRule, Unknown};
pub use raster::{Cell, MIN_GRID, Raster};
