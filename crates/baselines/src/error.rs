//! Typed errors of the baseline planners.

/// Everything that can go wrong while building or querying a baseline planner.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BaselineError {
    /// A polygon has fewer than three vertices.
    #[error("{what}: a polygon needs at least 3 vertices, got {count}")]
    TooFewVertices {
        /// Which polygon (`workspace`, `obstacle 2`, `goal 0`).
        what: String,
        /// How many vertices it has.
        count: usize,
    },
    /// A coordinate or parameter is NaN or infinite.
    #[error("{what}: value {value} is not finite")]
    NonFinite {
        /// Which input holds the value.
        what: String,
        /// The offending value.
        value: f64,
    },
    /// A tuning parameter is out of its valid range.
    #[error("parameter {name} = {value} is invalid: {reason}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What the valid range is.
        reason: &'static str,
    },
    /// The grid is too coarse to hold anything but its wall ring.
    #[error("grid of {n}×{n} cells is too small: at least {min} cells a side are needed")]
    GridTooSmall {
        /// The requested cells per side.
        n: usize,
        /// The smallest accepted size.
        min: usize,
    },
    /// No goal region could be placed on the grid.
    #[error("no goal cell: goal {goal} lies outside the free cells of the grid")]
    NoGoalCell {
        /// Index of the goal region that could not be placed.
        goal: usize,
    },
    /// The scene has no goal region at all.
    #[error("the scene has no goal region")]
    NoGoal,
    /// A panel has zero length.
    #[error("panel {panel} has zero length")]
    ZeroLengthPanel {
        /// The panel's index.
        panel: usize,
    },
    /// The panel method's linear system for the source strengths is singular or gave
    /// non-finite strengths (coinciding or overlapping panels).
    #[error("the panel system is singular: {panels} panels, some coincide or overlap")]
    SingularPanels {
        /// How many panels the system had.
        panels: usize,
    },
    /// A sphere-world description is invalid.
    #[error("sphere world: {0}")]
    InvalidSphereWorld(String),
}
