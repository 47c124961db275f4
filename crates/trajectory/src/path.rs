//! What a tracer or the car stepper returns: the path, how it ended, and its metrics.

use harmonic_types::Point;
use harmonic_types::geom::polyline_length;
use serde::{Serialize, Serializer};

/// How a path ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TraceStatus {
    /// The path reached goal region `j`.
    ReachedGoal(u32),
    /// No goal lies in the connected component of free space holding the start.
    Unreachable,
    /// The start lies inside an obstacle.
    StartInObstacle,
    /// The start lies outside the workspace.
    OutsideWorkspace,
    /// The path stopped making progress at `at` (a flat region or a discrete minimum that
    /// perturbations could not escape, or a car circling).
    Stalled {
        /// Where the path stopped.
        at: Point,
    },
    /// The step budget ran out before the goal was reached.
    MaxSteps,
    /// The car's footprint hit an obstacle (the collision predicate said so) at pose `at`.
    Collision {
        /// The last collision-free pose `[x, y, θ]`.
        at: [f64; 3],
    },
}

impl TraceStatus {
    /// The status as the scene contract's snake_case string (`"reached_goal"`, ...).
    ///
    /// ```
    /// use harmonic_trajectory::TraceStatus;
    /// assert_eq!(TraceStatus::ReachedGoal(0).as_str(), "reached_goal");
    /// assert_eq!(TraceStatus::MaxSteps.as_str(), "max_steps");
    /// ```
    pub fn as_str(&self) -> &'static str {
        match self {
            TraceStatus::ReachedGoal(_) => "reached_goal",
            TraceStatus::Unreachable => "unreachable",
            TraceStatus::StartInObstacle => "start_in_obstacle",
            TraceStatus::OutsideWorkspace => "outside_workspace",
            TraceStatus::Stalled { .. } => "stalled",
            TraceStatus::MaxSteps => "max_steps",
            TraceStatus::Collision { .. } => "collision",
        }
    }

    /// Whether the path reached a goal.
    pub fn reached_goal(&self) -> bool {
        matches!(self, TraceStatus::ReachedGoal(_))
    }
}

impl std::fmt::Display for TraceStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for TraceStatus {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

/// A path of a point robot through free space.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Path {
    /// The polyline from the start; serialised as `[[x, y], ...]`.
    #[serde(serialize_with = "serialize_points")]
    pub points: Vec<Point>,
    /// How the path ended.
    pub status: TraceStatus,
    /// The goal reached, if any (also in `status`; here for JSON readers).
    pub goal: Option<u32>,
    /// Total length of the polyline.
    pub length: f64,
    /// The smallest gradient magnitude |∇value| met along the path (`+∞` if none was met).
    pub min_gradient: f64,
    /// How many cells (triangles) the path entered after its first.
    pub triangles_crossed: usize,
}

impl Path {
    /// Builds a path from its points and status, computing its length and goal.
    pub fn new(
        points: Vec<Point>,
        status: TraceStatus,
        min_gradient: f64,
        triangles_crossed: usize,
    ) -> Self {
        let length = polyline_length(&points);
        let goal = match status {
            TraceStatus::ReachedGoal(j) => Some(j),
            _ => None,
        };
        Path {
            points,
            status,
            goal,
            length,
            min_gradient,
            triangles_crossed,
        }
    }
}

/// A path of a car-like robot: poses `[x, y, θ]` of the rear-axle midpoint.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CarPath {
    /// The poses from the start pose, one per step.
    pub poses: Vec<[f64; 3]>,
    /// How the path ended.
    pub status: TraceStatus,
    /// The goal reached, if any.
    pub goal: Option<u32>,
    /// Distance driven by the rear-axle midpoint (sum of arc lengths).
    pub length: f64,
    /// The smallest gradient magnitude |∇value| met at the front axle.
    pub min_gradient: f64,
    /// The largest |curvature| commanded (`tan δ / L`).
    pub max_curvature: f64,
}

fn serialize_points<S: Serializer>(points: &[Point], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(points.iter().map(|p| [p.x, p.y]))
}
