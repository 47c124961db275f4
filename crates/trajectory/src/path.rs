//! What a tracer or the car stepper returns: the path, how it ended, and its metrics — in
//! the plane (`Path`, `TraceStatus`) and in a volume or configuration space
//! (`Path<Point3>`, `TraceStatus<Point3>`): one vocabulary for every dimension.

use harmonic_types::{Point, Point3};
use serde::{Serialize, Serializer};

/// A point a path is made of: a point of the plane or of space.
pub trait PathPoint: Copy + std::fmt::Debug + PartialEq + Send + Sync {
    /// Its coordinates as an array (`[f64; 2]`, `[f64; 3]`), as reports keep them.
    type Array: Copy + std::fmt::Debug + PartialEq + Serialize + Send + Sync + AsRef<[f64]>;
    /// Its coordinates, as the JSON writes them (`[x, y]`, `[x, y, z]`).
    fn coords(&self) -> &[f64];
    /// Its coordinates as an array.
    fn array(&self) -> Self::Array;
    /// The distance to `other`.
    fn distance(&self, other: &Self) -> f64;
}

impl PathPoint for Point {
    type Array = [f64; 2];
    fn coords(&self) -> &[f64] {
        self.coords.as_slice()
    }
    fn array(&self) -> [f64; 2] {
        [self.x, self.y]
    }
    fn distance(&self, other: &Self) -> f64 {
        (other - self).norm()
    }
}

impl PathPoint for Point3 {
    type Array = [f64; 3];
    fn coords(&self) -> &[f64] {
        self.coords.as_slice()
    }
    fn array(&self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
    fn distance(&self, other: &Self) -> f64 {
        (other - self).norm()
    }
}

/// How a path ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TraceStatus<P = Point> {
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
        at: P,
    },
    /// The step budget ran out before the goal was reached.
    MaxSteps,
    /// The robot hit an obstacle: a car's footprint or a baseline's step (the collision
    /// predicate said so), or a check of the traced motions against the exact geometry (set
    /// by the planners that check, not by the tracers).
    Collision {
        /// The last collision-free pose `[x, y, θ]` of a planar robot, where it is known.
        at: Option<[f64; 3]>,
    },
}

impl<P> TraceStatus<P> {
    /// The status as the scene contract's snake_case string (`"reached_goal"`, ...).
    ///
    /// ```
    /// use harmonic_trajectory::TraceStatus;
    /// let (reached, out): (TraceStatus, TraceStatus) = (TraceStatus::ReachedGoal(0), TraceStatus::MaxSteps);
    /// assert_eq!(reached.as_str(), "reached_goal");
    /// assert_eq!(out.as_str(), "max_steps");
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

impl<P> std::fmt::Display for TraceStatus<P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl<P> Serialize for TraceStatus<P> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

/// A path of a point robot through free space (a plane's, a volume's, a configuration
/// space's).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(bound = "")]
pub struct Path<P: PathPoint = Point> {
    /// The polyline from the start; serialised as `[[x, y], ...]` or `[[x, y, z], ...]`.
    #[serde(serialize_with = "serialize_points")]
    pub points: Vec<P>,
    /// How the path ended.
    pub status: TraceStatus<P>,
    /// The goal reached, if any (also in `status`; here for JSON readers).
    pub goal: Option<u32>,
    /// Total length of the polyline.
    pub length: f64,
    /// The smallest gradient magnitude |∇value| met along the path (`+∞` if none was met).
    pub min_gradient: f64,
    /// How many cells (triangles, tetrahedra) the path entered after its first.
    pub cells_crossed: usize,
}

impl<P: PathPoint> Path<P> {
    /// Builds a path from its points and status, computing its length and goal.
    pub fn new(
        points: Vec<P>,
        status: TraceStatus<P>,
        min_gradient: f64,
        cells_crossed: usize,
    ) -> Self {
        let length = points.windows(2).map(|w| w[0].distance(&w[1])).sum();
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
            cells_crossed,
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

fn serialize_points<P: PathPoint, S: Serializer>(points: &[P], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(points.iter().map(PathPoint::coords))
}
