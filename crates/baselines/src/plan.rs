//! The result every baseline planner returns, so a harness can compare them.

use std::time::Duration;

use harmonic_mesh::Point;
use harmonic_trajectory::{Path, TraceStatus, polyline_length};
use serde::{Serialize, Serializer};

/// A planned path with how it ended, its length and what it cost to compute. Serialises as
/// `{"points": [[x, y], ...], "status": "reached_goal", "length": ..., "compute_time_ms": ...}`
/// like the `paths` entries of `hplan plan --json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlanResult {
    /// The polyline from the start.
    #[serde(serialize_with = "serialize_points")]
    pub points: Vec<Point>,
    /// How the path ended (the same statuses as the shared tracer's).
    pub status: TraceStatus,
    /// Length of the polyline.
    pub length: f64,
    /// Wall-clock time of the query that produced the path (precomputation, such as a grid
    /// solve or a brushfire, is reported by the planner separately).
    #[serde(rename = "compute_time_ms", serialize_with = "serialize_ms")]
    pub compute_time: Duration,
}

fn serialize_points<S: Serializer>(points: &[Point], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(points.iter().map(|p| [p.x, p.y]))
}

fn serialize_ms<S: Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64() * 1e3)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serialises_like_the_cli_paths() {
        let plan = PlanResult::new(
            vec![Point::new(0.0, 0.0), Point::new(3.0, 4.0)],
            TraceStatus::ReachedGoal(0),
            Duration::from_micros(1500),
        );
        assert_eq!(plan.length, 5.0);
        assert_eq!(
            serde_json::to_string(&plan).unwrap(),
            r#"{"points":[[0.0,0.0],[3.0,4.0]],"status":"reached_goal","length":5.0,"compute_time_ms":1.5}"#
        );
    }
}
