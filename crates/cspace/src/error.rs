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
    /// The goal configuration collides.
    #[error(
        "the goal configuration collides with {with} (clearance {clearance:.4}, safety margin {margin}): move the goal into free space"
    )]
    GoalInCollision {
        /// What it collides with.
        with: String,
        /// The robot's distance to it (≤ the margin).
        clearance: f64,
        /// The safety margin.
        margin: f64,
    },
    /// The goal configuration is outside the joint limits.
    #[error("the goal configuration is outside the joint limits")]
    GoalOutsideLimits,
    /// No free configuration within the goal's tolerance was found.
    #[error(
        "no free configuration lies within the goal's tolerance: every one collides or breaks a joint limit; move the goal or widen goal.tolerance"
    )]
    GoalUnreachableRegion,
    /// Refinement toward the goal stopped at the budget.
    #[error(
        "the goal region could not be resolved within the budget of {budget} tetrahedra: raise mesh.max_tetrahedra or widen goal.tolerance"
    )]
    GoalNotResolved {
        /// The budget.
        budget: u64,
    },
    /// The volume mesher failed.
    #[error(transparent)]
    Volume(#[from] VolumeError),
}
