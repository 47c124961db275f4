//! `hp.Workspace`: a plane scene (or map) meshed and its walls factored once; a planner for
//! any goal afterwards, by a few triangular solves.

use std::path::PathBuf;
use std::sync::Arc;

use harmonic_planner::map::{MapOptions, OccupancyMap};
use harmonic_planner::{Goal, PlannerOptions, Point, Scene, Workspace};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::{built, guarded, scene_error};
use crate::planner::{PyPlanner, positive};
use crate::scene::PyScene;

/// A plane scene's free space meshed without its goals and its walls' system factored once.
///
/// `Workspace(scene)` does the heavy part (the GIL is released meanwhile); then
/// `planner(goal)` gives a `Planner` for any goal point in a few milliseconds, the same
/// queries as a planner built with that goal (`plan`, `plan_many`, `potential`, ...), its
/// paths ending exactly on the goal. `planners(goals)` solves several goals together;
/// `planner_for_any(goals)` makes one field whose goal is the set.
#[pyclass(module = "harmonic_planner", name = "Workspace", frozen)]
pub struct PyWorkspace {
    workspace: Arc<Workspace>,
    source: Option<String>,
}

fn goal_of(goal: &Bound<'_, PyAny>, radius: f64) -> PyResult<Goal> {
    let p = arrays::point::<2>(goal, "goal")?;
    if !(p.iter().all(|v| v.is_finite()) && radius.is_finite() && radius >= 0.0) {
        return Err(scene_error(format!(
            "goal {p:?} with radius {radius}: coordinates must be finite and the radius ≥ 0"
        )));
    }
    Ok(Goal::Point {
        at: Point::new(p[0], p[1]),
        radius,
    })
}

impl PyWorkspace {
    fn build(py: Python<'_>, scene: Scene, source: Option<String>) -> PyResult<PyWorkspace> {
        let workspace = built(py, &source, move || Workspace::new(&scene))?;
        Ok(PyWorkspace {
            workspace: Arc::new(workspace),
            source,
        })
    }

    fn wrap(&self, planner: harmonic_planner::Planner) -> PyPlanner {
        PyPlanner::from_planner(planner, self.source.clone())
    }
}

#[pymethods]
impl PyWorkspace {
    #[new]
    #[pyo3(signature = (scene, *, max_area = None))]
    fn new(py: Python<'_>, scene: &PyScene, max_area: Option<f64>) -> PyResult<PyWorkspace> {
        let mut plane = scene.plane("Workspace")?;
        if let Some(a) = positive("max_area", max_area)? {
            plane.mesh.max_area = Some(a);
        }
        PyWorkspace::build(py, plane, scene.source.clone())
    }

    /// A workspace on a ROS map_server occupancy map: the free area holding `around` (world
    /// coordinates) is traced, as `hplan plan --map MAP.yaml --goal ... --goal ...` does.
    #[staticmethod]
    #[pyo3(signature = (yaml, around, robot_radius = 0.0, *, max_area = None))]
    fn from_map(
        py: Python<'_>,
        yaml: PathBuf,
        around: &Bound<'_, PyAny>,
        robot_radius: f64,
        max_area: Option<f64>,
    ) -> PyResult<PyWorkspace> {
        let around = arrays::point::<2>(around, "around")?;
        if !around.iter().all(|v| v.is_finite()) {
            return Err(scene_error(format!(
                "around: coordinates must be finite numbers, got {around:?}"
            )));
        }
        let opts = MapOptions {
            max_area: positive("max_area", max_area)?,
            ..MapOptions::default()
        };
        let workspace = py.detach(|| {
            guarded(|| {
                OccupancyMap::load(&yaml)
                    .and_then(|m| {
                        m.workspace(around, robot_radius, &opts, &PlannerOptions::default())
                    })
                    .map_err(|e| scene_error(e.to_string()))
            })
        })?;
        Ok(PyWorkspace {
            workspace: Arc::new(workspace),
            source: Some(yaml.display().to_string()),
        })
    }

    /// A planner towards `goal` (x, y): the free vertices of its triangle held, and those
    /// within `radius`. Raises SceneError for a goal outside free space.
    #[pyo3(signature = (goal, *, radius = 0.0))]
    fn planner(&self, py: Python<'_>, goal: &Bound<'_, PyAny>, radius: f64) -> PyResult<PyPlanner> {
        let goal = goal_of(goal, radius)?;
        let ws = &self.workspace;
        let planner =
            py.detach(|| guarded(|| ws.planner(&goal).map_err(|e| scene_error(e.to_string()))))?;
        Ok(self.wrap(planner))
    }

    /// One planner per goal (an (n, 2) array of points), their fields solved together.
    fn planners(&self, py: Python<'_>, goals: &Bound<'_, PyAny>) -> PyResult<Vec<PyPlanner>> {
        let goals: Vec<Goal> = arrays::points::<2>(goals, "goals")?
            .into_iter()
            .map(Goal::point)
            .collect();
        let ws = &self.workspace;
        let planners =
            py.detach(|| guarded(|| ws.planners(&goals).map_err(|e| scene_error(e.to_string()))))?;
        Ok(planners.into_iter().map(|p| self.wrap(p)).collect())
    }

    /// One planner whose goal is the whole set of points: a path ends on whichever goal the
    /// field leads it to (`Path.goal` is its index).
    fn planner_for_any(&self, py: Python<'_>, goals: &Bound<'_, PyAny>) -> PyResult<PyPlanner> {
        let goals: Vec<Goal> = arrays::points::<2>(goals, "goals")?
            .into_iter()
            .map(Goal::point)
            .collect();
        let ws = &self.workspace;
        let planner = py.detach(|| {
            guarded(|| {
                ws.planner_for_any(&goals)
                    .map_err(|e| scene_error(e.to_string()))
            })
        })?;
        Ok(self.wrap(planner))
    }

    /// Milliseconds spent meshing, assembling and factoring (once for every goal).
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = self.workspace.timings();
        let d = PyDict::new(py);
        d.set_item("mesh", t.mesh)?;
        d.set_item("assemble", t.assemble)?;
        d.set_item("factor", t.factor)?;
        Ok(d)
    }

    /// The number of triangles of the mesh.
    #[getter]
    fn triangles(&self) -> usize {
        self.workspace.mesh().triangles().len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Workspace({} triangles{})",
            self.workspace.mesh().triangles().len(),
            self.source
                .as_ref()
                .map(|s| format!(", from {s}"))
                .unwrap_or_default()
        )
    }
}
