//! Why a planner could not be built: one [`PlanError`] for the plane, volumes and
//! configuration spaces, each variant the error of the stage that failed (scene, mesher,
//! assembly and solve, tracer), so a message names what is wrong and where.

use crate::planner::Stage;
use crate::scene::SceneError;

/// Why a planner (plane, volume or configuration space) could not be built.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// The scene is invalid (names the JSON path): a part given twice or not at all, solids
    /// that are not solids, a robot that does not fit.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// [`crate::PlannerOptions::threads`] could not be had.
    #[error("cannot plan on {threads} threads: {message}")]
    Threads {
        /// The threads asked for.
        threads: usize,
        /// Why not.
        message: String,
    },
    /// A plane scene's geometry is invalid or cannot be meshed.
    #[error(transparent)]
    Mesh(#[from] harmonic_mesh::MeshError),
    /// A volume (or a configuration space's slab) cannot be meshed.
    #[error(transparent)]
    Volume(#[from] harmonic_volume::VolumeError),
    /// A configuration space cannot be built or meshed.
    #[error(transparent)]
    Cspace(#[from] harmonic_cspace::CspaceError),
    /// The boundary conditions make no solvable problem, or the solve failed.
    #[error(transparent)]
    Fem(#[from] harmonic_fem::FemError),
    /// A tracer or car option is out of range, or the potential cannot be traced.
    #[error(transparent)]
    Trace(#[from] harmonic_trajectory::TraceError),
    /// A goal given to a [`crate::Workspace`] is not usable.
    #[error(transparent)]
    Goal(#[from] crate::workspace::GoalError),
    /// [`crate::PlannerOptions::cancel`] asked to stop, at the start of `stage`.
    #[error("cancelled before {stage:?}")]
    Cancelled {
        /// The stage that was about to start.
        stage: Stage,
    },
    /// [`crate::PlannerOptions::multigrid`] asked of a planner whose mesh is not a scene's own, or
    /// with the blended conditions.
    #[error(
        "multigrid (PlannerOptions::multigrid) needs a scene's own mesh and plain boundary conditions, not {what}"
    )]
    MultigridUnsupported {
        /// What the planner was built from instead.
        what: &'static str,
    },
    /// A configuration-space robot touches nothing in any configuration, every axis wraps
    /// around, and the goal got no face either: nothing bounds the space a potential could
    /// flow through (a space bounded by its goal alone gets an anti-goal instead).
    #[error(
        "the robot touches nothing in any configuration (no obstacle in reach, no joint limit, \
         no link that can meet another), so nothing but the goal bounds the configuration \
         space: add a joint limit or an obstacle"
    )]
    NothingToAvoid,
}
