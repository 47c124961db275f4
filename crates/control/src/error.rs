//! Typed errors of the controllers.

/// What went wrong setting up a controller run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ControlError {
    /// A parameter is out of its range.
    #[error("{name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        reason: &'static str,
    },
    /// The robot overlaps an obstacle in its start configuration.
    #[error("the robot's start configuration touches obstacle {obstacle} (distance {distance})")]
    StartInCollision {
        /// The obstacle.
        obstacle: usize,
        /// The distance (0: overlapping).
        distance: f64,
    },
    /// An obstacle polygon has fewer than three vertices or a non-finite coordinate.
    #[error("obstacle {index}: {reason}")]
    InvalidObstacle {
        /// The obstacle.
        index: usize,
        /// What is wrong.
        reason: &'static str,
    },
    /// An arm needs at least two links, each of positive finite length.
    #[error("arm: {reason}")]
    InvalidArm {
        /// What is wrong.
        reason: String,
    },
}

/// Checks that `value` is finite and positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<(), ControlError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ControlError::InvalidParameter {
            name,
            value,
            reason: "must be positive and finite",
        })
    }
}
