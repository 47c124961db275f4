//! `hp.Path` (a planned path, plane or volume) and `hp.CarRun` (a car's drive).

use std::sync::Arc;

use harmonic_planner::cspace::ConfigPlannedPath;
use harmonic_planner::trajectory::PathPoint;
use harmonic_planner::{CarRun, PlannedPath, PlannerApi};
use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::prelude::*;

use crate::arrays;
use crate::errors::guarded;

/// A planned path from `start` down the potential.
///
/// `status` is one of the command line's words: "reached_goal", "unreachable", "stalled",
/// "start_in_obstacle", "outside_workspace", "max_steps". `points` is an array of shape
/// (n, 2) — (n, 3) for a volume — from the start; on reaching the goal the last point lies on
/// the goal's boundary.
#[pyclass(module = "harmonic_planner", name = "Path", frozen)]
pub struct PyPath {
    start: Vec<f64>,
    status: &'static str,
    goal: Option<u32>,
    tracer: String,
    length: f64,
    min_clearance: f64,
    min_gradient: f64,
    dimension: usize,
    points: Vec<f64>,
    /// What a point is: `"plane"`, `"volume"`, `"pose"` (a polygon robot's `[x, y, θ]`) or
    /// `"joints"` (an arm's joint angles).
    space: &'static str,
}

impl PyPath {
    /// The path's points as configurations (rows).
    pub(crate) fn configurations(&self) -> Vec<Vec<f64>> {
        self.points
            .chunks_exact(self.dimension.max(1))
            .map(<[f64]>::to_vec)
            .collect()
    }
}

fn tracer_name(t: &impl serde::Serialize) -> String {
    match serde_json::to_value(t) {
        Ok(serde_json::Value::String(s)) => s,
        other => format!("{other:?}"),
    }
}

impl<P: PathPoint> From<PlannedPath<P>> for PyPath {
    /// A path of the plane or of a volume: its points flattened, `dimension` per row.
    fn from(p: PlannedPath<P>) -> PyPath {
        PyPath {
            start: p.start.as_ref().to_vec(),
            status: p.status.as_str(),
            goal: p.goal,
            tracer: tracer_name(&p.tracer),
            length: p.length,
            min_clearance: p.min_clearance,
            min_gradient: p.min_gradient,
            dimension: p.start.as_ref().len(),
            points: p.points.iter().flat_map(|q| q.as_ref().to_vec()).collect(),
            space: if p.start.as_ref().len() == 2 {
                "plane"
            } else {
                "volume"
            },
        }
    }
}

impl From<ConfigPlannedPath> for PyPath {
    /// A motion of a polygon robot or an arm: its configurations as the points.
    fn from(p: ConfigPlannedPath) -> PyPath {
        let configurations = p.configurations();
        PyPath {
            dimension: p.start.len(),
            points: configurations.into_iter().flatten().collect(),
            status: p.status.as_str(),
            goal: p.status.reached_goal().then_some(0),
            tracer: tracer_name(&p.tracer),
            length: p.length,
            min_clearance: p.min_clearance,
            min_gradient: p.min_gradient,
            space: if p.poses.is_some() { "pose" } else { "joints" },
            start: p.start,
        }
    }
}

/// Plans from every row of `starts` (shape (n, D), finite) in parallel with the GIL released:
/// `plan_many` of any planner whose starts are points.
pub(crate) fn plan_many<A, const D: usize>(
    py: Python<'_>,
    planner: &Arc<A>,
    starts: &Bound<'_, PyAny>,
) -> PyResult<Vec<PyPath>>
where
    A: PlannerApi<Start = [f64; D]> + Send + Sync,
    A::Path: Into<PyPath> + Send,
{
    let starts = arrays::points::<D>(starts, "starts")?;
    for &s in &starts {
        arrays::finite(s, "starts")?;
    }
    let planner = Arc::clone(planner);
    let paths = py.detach(move || guarded(|| Ok(PlannerApi::plan_many(&*planner, &starts))))?;
    Ok(paths.into_iter().map(Into::into).collect())
}

fn rows<'py>(py: Python<'py>, flat: &[f64], d: usize) -> Bound<'py, PyArray2<f64>> {
    let array = Array2::from_shape_vec((flat.len() / d, d), flat.to_vec()).expect("n × d values");
    PyArray2::from_owned_array(py, array)
}

#[pymethods]
impl PyPath {
    /// How the path ended: "reached_goal", "unreachable", "stalled", "start_in_obstacle",
    /// "outside_workspace" or "max_steps".
    #[getter]
    fn status(&self) -> &'static str {
        self.status
    }
    /// Whether the path reached a goal (status == "reached_goal").
    #[getter]
    fn reached_goal(&self) -> bool {
        self.status == "reached_goal"
    }
    /// The index of the goal region reached, or None.
    #[getter]
    fn goal(&self) -> Option<u32> {
        self.goal
    }
    /// Which tracer made the path: "smooth" (the default) or "exact" (the fallback).
    #[getter]
    fn tracer(&self) -> &str {
        &self.tracer
    }
    /// The query point, as given (a tuple of 2 or 3 floats).
    #[getter]
    fn start(&self) -> Vec<f64> {
        self.start.clone()
    }
    /// What a point of the path is: "plane" (x, y), "volume" (x, y, z), "pose" (a polygon
    /// robot's x, y, theta) or "joints" (an arm's joint angles).
    #[getter]
    fn space(&self) -> &'static str {
        self.space
    }
    /// The path's vertices, a new float64 array of shape (n, 2) — (n, 3) for a volume, (n,
    /// dof) of configurations for a polygon robot or an arm.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(py, &self.points, self.dimension)
    }
    /// Length of the polyline `points`, in scene units.
    #[getter]
    fn length(&self) -> f64 {
        self.length
    }
    /// Smallest distance from the path to a wall or an obstacle (exact geometry).
    #[getter]
    fn min_clearance(&self) -> f64 {
        self.min_clearance
    }
    /// Smallest |∇φ| met along the path (0 if none was met).
    #[getter]
    fn min_gradient(&self) -> f64 {
        self.min_gradient
    }
    /// A plane path as poses, a new float64 array of shape (n, 3) of [x, y, theta]: each
    /// point with the heading of the segment leaving it (the last, of the one arriving);
    /// `start_heading` replaces the first's and, on reaching the goal, `goal_heading` the
    /// last's (a pose goal). ValueError on a volume path.
    #[pyo3(signature = (start_heading=None, goal_heading=None))]
    fn poses<'py>(
        &self,
        py: Python<'py>,
        start_heading: Option<f64>,
        goal_heading: Option<f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        match self.space {
            "plane" => {}
            // A polygon robot's path is its poses.
            "pose" => return Ok(rows(py, &self.points, 3)),
            space => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "poses are for plane paths and polygon robots; this path is a {}",
                    if space == "joints" {
                        "motion of an arm's joints"
                    } else {
                        "volume's"
                    }
                )));
            }
        }
        let points: Vec<[f64; 2]> = self.points.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
        let goal_heading = goal_heading.filter(|_| self.status == "reached_goal");
        let poses = harmonic_planner::poses_along(&points, start_heading, goal_heading);
        let flat: Vec<f64> = poses.iter().flatten().copied().collect();
        Ok(rows(py, &flat, 3))
    }
    fn __len__(&self) -> usize {
        self.points.len() / self.dimension
    }
    fn __repr__(&self) -> String {
        format!(
            "Path(status={:?}, points={}, length={:.6}, min_clearance={:.6})",
            self.status,
            self.__len__(),
            self.length,
            self.min_clearance
        )
    }
}

/// A car-like robot's run along the potential: `poses` is an array of shape (n, 3) of
/// rear-axle midpoints and headings `[x, y, theta]` (radians).
///
/// `status` is one of "reached_goal", "stalled", "max_steps", "collision" (with
/// `check_footprint=True`), "start_in_obstacle", "outside_workspace", "unreachable".
#[pyclass(module = "harmonic_planner", name = "CarRun", frozen)]
pub struct PyCarRun {
    run: CarRun,
}

impl From<CarRun> for PyCarRun {
    fn from(run: CarRun) -> PyCarRun {
        PyCarRun { run }
    }
}

#[pymethods]
impl PyCarRun {
    /// How the run ended (the command line's words).
    #[getter]
    fn status(&self) -> &'static str {
        self.run.status.as_str()
    }
    /// Whether the car reached a goal.
    #[getter]
    fn reached_goal(&self) -> bool {
        self.run.status.reached_goal()
    }
    /// The index of the goal region reached, or None.
    #[getter]
    fn goal(&self) -> Option<u32> {
        self.run.goal
    }
    /// The start pose `[x, y, theta]`, as given.
    #[getter]
    fn start(&self) -> [f64; 3] {
        self.run.start
    }
    /// The poses `[x, y, theta]`, a new float64 array of shape (n, 3).
    #[getter]
    fn poses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::rows_f64(py, &self.run.poses)
    }
    /// Arc length driven.
    #[getter]
    fn length(&self) -> f64 {
        self.run.length
    }
    /// Smallest distance from the rear-axle track to a wall or an obstacle.
    #[getter]
    fn min_clearance(&self) -> f64 {
        self.run.min_clearance
    }
    /// Smallest |∇φ| met along the run.
    #[getter]
    fn min_gradient(&self) -> f64 {
        self.run.min_gradient
    }
    /// Largest curvature |κ| driven (at most tan(max_steer) / wheelbase).
    #[getter]
    fn max_curvature(&self) -> f64 {
        self.run.max_curvature
    }
    fn __len__(&self) -> usize {
        self.run.poses.len()
    }
    fn __repr__(&self) -> String {
        format!(
            "CarRun(status={:?}, poses={}, length={:.6})",
            self.status(),
            self.run.poses.len(),
            self.run.length
        )
    }
}
