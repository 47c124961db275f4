//! # harmonic-planner
//!
//! Local-minimum-free robot path planning with harmonic potentials solved by the finite
//! element method (Connolly et al. 1990; Garrido et al. 2010).
//!
//! A [`Scene`] (JSON: workspace polygon, obstacles, goal regions, boundary conditions) is
//! meshed by constrained Delaunay triangulation, Laplace's equation is solved on the mesh with
//! P1 finite elements, and paths follow the potential downhill to the goal. A harmonic
//! function has no local minima inside the domain, and on a Delaunay mesh the discrete
//! potential keeps that property, so no path gets stuck.
//!
//! The [`Planner`] builds everything once and answers many queries: [`Planner::plan`] for a
//! point (or disc) robot, [`Planner::car`] for a car-like robot. The stages live in their own
//! crates, re-exported here: [`mesh`] (triangulation), [`fem`] (assembly and potentials),
//! [`solver`] (sparse Cholesky and PCG) and [`trajectory`] (tracers, car stepper). Replanning
//! among moving obstacles is `harmonic-dynamic`, the comparison planners `harmonic-baselines`,
//! the command line `hplan`. A robot that is not a disc — a rigid polygon or a planar arm —
//! is planned in its configuration space by [`ConfigPlanner`] ([`cspace`]).
//!
//! Features: `map` (default) reads ROS map_server occupancy maps ([`map`]); without it the
//! crate needs no image decoder and no YAML parser.
//!
//! ```
//! use harmonic_planner::{Planner, Scene};
//! let scene = Scene::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/reference.json"))?;
//! let planner = Planner::new(&scene)?;
//! let path = planner.plan([1.0, 9.0]);
//! assert!(path.status.reached_goal());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod api;
pub mod cspace;
mod error;
pub mod inputs;
#[cfg(feature = "map")]
pub mod map;
pub mod planner;
pub mod render;
pub mod scene;
mod threads;
pub mod volume;
pub mod workspace;

pub use api::{AnyExport, AnyPlanner, AnyReport, PlannerApi, StartError, Summary, VtuError};
pub use cspace::{ConfigPlanner, ConfigScene};
pub use error::PlanError;
pub use harmonic_fem as fem;
pub use harmonic_mesh as mesh;
pub use harmonic_mesh::{Point, Vector};
pub use harmonic_solver as solver;
pub use harmonic_trajectory as trajectory;
pub use harmonic_types::{Point3, Vector3};
pub use planner::{
    AUTO_MULTIGRID_FROM, AUTO_MULTIGRID_REFINEMENTS, CarParams, CarReport, CarRun, Export,
    PlanReport, PlannedPath, Planner, PlannerOptions, Report, Stage, StartEntry, SvgOptions,
    Timings, poses_along,
};
pub use scene::{AnyScene, Scene, SceneError};
pub use volume::{VolumePlanner, VolumeScene};
pub use workspace::{
    Goal, GoalError, GoalRun, GoalTimings, GoalsReport, Workspace, WorkspaceTimings,
};
