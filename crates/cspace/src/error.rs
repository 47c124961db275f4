//! Errors of the configuration-space geometry and mesher.

use harmonic_volume::VolumeError;

/// Why a configuration space cannot be built or meshed.
#[derive(Debug, thiserror::Error)]
pub enum CspaceError {
    /// Bad input, named by its JSON path.
    #[error("{path}: {message}")]
    Invalid {
        /// The JSON path (`robot.polygon`, `obstacles[2].polygon`, `goal.tolerance`, …).
        path: String,
        /// What is wrong.
        message: String,
    },
    /// The lattice would not fit the budget (refused before any work).
    #[error(
        "the configuration-space lattice at spacing {spacing} would hold about {estimated} tetrahedra, more than the budget of {budget}; raise mesh.spacing"
    )]
    TooLarge {
        /// Estimated lattice tetrahedra.
        estimated: u64,
        /// The budget.
        budget: u64,
        /// The spacing asked for.
        spacing: f64,
    },
    /// No lattice vertex is free.
    #[error(
        "no free configuration at lattice spacing {spacing}: the robot collides everywhere (or refine mesh.spacing)"
    )]
    NoFreeSpace {
        /// The spacing.
        spacing: f64,
    },
    /// The goal region is too small for the lattice (or lies in collision).
    #[error(
        "the goal region has no face in the mesh at spacing {spacing}: it lies in collision or is smaller than the lattice; widen goal.tolerance or lower mesh.spacing"
    )]
    GoalNotMeshed {
        /// The spacing.
        spacing: f64,
    },
    /// The volume mesher failed.
    #[error(transparent)]
    Volume(#[from] VolumeError),
}
