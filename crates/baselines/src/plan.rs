//! The result every baseline planner returns, so a harness can compare them.

use std::time::Duration;

use harmonic_mesh::Point;
use harmonic_trajectory::{Path, TraceStatus, polyline_length};

/// A planned path with how it ended, its length and what it cost to compute.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanResult {
    /// The polyline from the start.
    pub points: Vec<Point>,
    /// How the path ended (the same statuses as the shared tracer's).
    pub status: TraceStatus,
    /// Length of the polyline.
    pub length: f64,
    /// Wall-clock time of the query that produced the path (precomputation, such as a grid
    /// solve or a brushfire, is reported by the planner separately).
    pub compute_time: Duration,
}

impl PlanResult {
    /// Builds a result, computing the length.
    pub fn new(points: Vec<Point>, status: TraceStatus, compute_time: Duration) -> Self {
        let length = polyline_length(&points);
        PlanResult {
            points,
            status,
            length,
            compute_time,
        }
    }

    /// Wraps a path traced by the shared tracer (for field planners such as
    /// [`crate::GridHarmonic`]).
    pub fn from_path(path: Path, compute_time: Duration) -> Self {
        PlanResult {
            points: path.points,
            status: path.status,
            length: path.length,
            compute_time,
        }
    }
}
