//! # harmonic-baselines
//!
//! The comparison planners of the seed papers, so the finite-element harmonic planner can be
//! measured against them on the same scenes, the same tracer and the same metrics.
//!
//! - [`grid_harmonic`]: Connolly, Burns & Weiss (ICRA 1990), *Path planning using Laplace's
//!   equation*: the 5-point Laplacian on an occupancy grid ([`Raster`], from polygons or from
//!   a [`harmonic_mesh::Domain`]), relaxed by Gauss–Seidel or red–black SOR (optimal ω by
//!   default), Dirichlet or Robin/Neumann outer walls, iterated on ψ = 1 − φ like the FEM
//!   solver until every cell's residual is small against its own value (by default: ψ
//!   decays exponentially along corridors, and an absolute tolerance leaves the far cells
//!   flat), followed by bilinear interpolation. [`GridHarmonic`] implements the shared
//!   [`harmonic_trajectory::Field`] trait, so the same tracer follows it, and reports
//!   Connolly's flat-cell count.
//! - [`integer_relaxation`]: Connolly et al.'s own procedure (§4): Gauss–Seidel in k-bit
//!   integers until no node changes, the flat-region count, and a left shift of every value
//!   by c bits while flat regions remain ([`IntegerRelaxation`]).
//! - [`parabolic`]: the ME766 term paper's relaxation: the heat equation stepped explicitly
//!   to its steady state, with the stability bound `Δt/h² ≤ 1/4` ([`Parabolic`]).
//! - [`wavefront`]: the wavefront planner (Choset et al., *Principles of Robot Motion*, §4.5):
//!   a brushfire of move counts from the goal over the grid, 4- or 8-connected, and descent to
//!   the lowest neighbour.
//! - [`potential_field`]: Khatib's attractive/repulsive potentials (*Real-time obstacle
//!   avoidance for manipulators and mobile robots*, IJRR 1986) in the form of Choset
//!   et al., §4.1–4.2 (conic/parabolic attraction with threshold d*, repulsion within Q* of
//!   each obstacle polygon), descended with a fixed step; they can get trapped in local
//!   minima, which the descent reports as `Stalled`.
//! - [`panel`]: Kim & Khosla (1992), *Real-time obstacle avoidance using harmonic potential
//!   functions*: uniform stream + goal sink + constant-strength source panels on the
//!   boundary of free space (obstacles and walls, merged where they touch), strengths from the linear system `P λ = q` for prescribed normal
//!   velocities, and the closed-form panel velocity field and potential; a query's flow is
//!   also a [`harmonic_trajectory::Field`] ([`PanelFlow`]).
//! - [`navigation`]: Rimon & Koditschek (1992), *Exact robot navigation using artificial
//!   potential functions*: the sphere-world navigation function
//!   `φ = γ / (γ^κ + β)^{1/κ}` with tunable κ, descended along its gradient, or followed by
//!   the shared tracer as a [`NavigationField`] (value `ln φ`, which does not underflow).
//!
//! Planners that produce paths directly return a [`PlanResult`] (points, status, length,
//! compute time), with the same [`harmonic_trajectory::TraceStatus`] as the shared tracer.
//!
//! ```
//! use harmonic_baselines::{Connectivity, GridHarmonic, Raster, SorOptions, Wavefront};
//! use harmonic_mesh::Point;
//! use harmonic_trajectory::{SmoothOptions, trace_smooth};
//! let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
//!     vec![Point::new(x0, y0), Point::new(x1, y0), Point::new(x1, y1), Point::new(x0, y1)]
//! };
//! let raster = Raster::from_polygons(
//!     &rect(0.0, 0.0, 10.0, 10.0),
//!     &[rect(2.0, 2.0, 3.0, 8.0)],
//!     &[rect(8.0, 1.0, 9.0, 2.0)],
//!     64,
//! )?;
//! // Connolly's planner: relax, then follow the field with the shared tracer.
//! let field = GridHarmonic::solve(raster.clone(), &SorOptions::default())?;
//! assert!(field.report().converged && field.flat_cells() == 0);
//! let path = trace_smooth(&field, Point::new(1.0, 9.0), &SmoothOptions::for_scale(10.0))?;
//! assert!(path.status.reached_goal());
//! // The wavefront planner on the same grid.
//! let plan = Wavefront::new(raster, Connectivity::Eight).plan(Point::new(1.0, 9.0));
//! assert!(plan.status.reached_goal());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod error;
mod geometry;
pub mod grid_harmonic;
pub mod integer_relaxation;
pub mod navigation;
pub mod panel;
pub mod panel_published;
pub mod parabolic;
mod plan;
pub mod potential_field;
mod raster;
pub mod wavefront;

pub use error::BaselineError;
pub use grid_harmonic::{
    GridHarmonic, Relaxation, SolveReport, SorOptions, StopRule, Unknown, WallCondition,
};
pub use integer_relaxation::{
    IntegerOptions, IntegerOutcome, IntegerPass, IntegerRelaxation, MAX_BITS,
};
pub use navigation::{Disc, NavigationField, NavigationFunction, NavigationOptions};
pub use panel::{Panel, PanelField, PanelFlow, PanelOptions, PanelPlanner, PanelVariant};
pub use panel_published::{
    ObstacleStrength, PublishedSetting, Remedied, Remedy, RemedyOutcome, RemedyRound,
    StagnationPoint, StagnationSearch, StrengthCheck,
};
pub use parabolic::{Parabolic, ParabolicOptions, ParabolicOutcome, ParabolicWalls, STABLE_R};
pub use plan::PlanResult;
pub use potential_field::{PotentialField, PotentialFieldOptions};
pub use raster::{Cell, Connectivity, MIN_GRID, Raster, UNREACHED};
pub use wavefront::Wavefront;
