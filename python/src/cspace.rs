//! `hp.ConfigPlanner`: a polygon robot (poses `[x, y, theta]`) or a planar arm (joint angles)
//! planned in its configuration space — meshed, solved once, then queried with
//! configurations.

use std::sync::Arc;

use harmonic_planner::{ConfigPlanner, PlannerApi};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::{built, guarded, scene_error};
use crate::paths::PyPath;
use crate::planner::timings_dict;
use crate::scene::PyScene;

/// A harmonic-potential planner for a polygon robot or an arm (a scene with `"robot":
/// {"polygon": …}` or `{"arm": …}`), in its configuration space.
///
/// `ConfigPlanner(scene)` meshes the free configurations (the robot's exact geometry against
/// the obstacles, the joint limits, the links against each other), assembles and solves —
/// once, with the GIL released. A start is a configuration: `[x, y, theta]` for a polygon,
/// the joint angles for an arm. A path's `points` are configurations, and every motion between
/// two of them has been checked against the robot's exact geometry.
#[pyclass(module = "harmonic_planner", name = "ConfigPlanner", frozen)]
pub struct PyConfigPlanner {
    planner: Arc<ConfigPlanner>,
    source: Option<String>,
}

impl PyConfigPlanner {
    /// `starts` as configurations of this robot's size (rows of an (n, dof) array).
    fn configurations(&self, starts: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec<f64>>> {
        fn rows<const D: usize>(starts: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec<f64>>> {
            arrays::points::<D>(starts, what)?
                .into_iter()
                .map(|q| Ok(arrays::finite(q, what)?.to_vec()))
                .collect()
        }
        match self.planner.space().dof() {
            2 => rows::<2>(starts, what),
            _ => rows::<3>(starts, what),
        }
    }

    fn start(&self, start: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
        fn one<const D: usize>(start: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
            Ok(arrays::finite(arrays::point::<D>(start, "start")?, "start")?.to_vec())
        }
        match self.planner.space().dof() {
            2 => one::<2>(start),
            _ => one::<3>(start),
        }
    }
}

#[pymethods]
impl PyConfigPlanner {
    #[new]
    fn new(py: Python<'_>, scene: &PyScene) -> PyResult<Self> {
        let config = match &scene.scene {
            harmonic_planner::AnyScene::Config(c) => (**c).clone(),
            harmonic_planner::AnyScene::Plane(_) | harmonic_planner::AnyScene::Volume(_) => {
                return Err(scene_error(scene.located(
                    "ConfigPlanner works on polygon and arm robots (\"robot\": {\"polygon\": …} or \
                     {\"arm\": …}); use Planner or VolumePlanner",
                )));
            }
        };
        let source = scene.source.clone();
        let planner = built(py, &source, move || ConfigPlanner::new(&config))?;
        Ok(PyConfigPlanner {
            planner: Arc::new(planner),
            source,
        })
    }

    /// Plans a motion from the configuration `start`; returns a `Path` whose `points` are
    /// configurations, shape (n, dof).
    fn plan(&self, start: &Bound<'_, PyAny>) -> PyResult<PyPath> {
        let start = self.start(start)?;
        guarded(|| Ok(self.planner.plan(&start).into()))
    }

    /// Plans from every row of `starts` (shape (n, dof)) in parallel, GIL released; a list of
    /// `Path` in the same order.
    fn plan_many(&self, py: Python<'_>, starts: &Bound<'_, PyAny>) -> PyResult<Vec<PyPath>> {
        let starts = self.configurations(starts, "starts")?;
        let planner = Arc::clone(&self.planner);
        let paths = py.detach(move || guarded(|| Ok(planner.plan_many(&starts))))?;
        Ok(paths.into_iter().map(PyPath::from).collect())
    }

    /// The report of `hplan plan --json` for `starts` (shape (n, dof)), as a JSON string:
    /// the mesh, the timings, the potential (`solved_by`, interior extrema) and the paths.
    fn report_json(&self, py: Python<'_>, starts: &Bound<'_, PyAny>) -> PyResult<String> {
        let starts = self.configurations(starts, "starts")?;
        let planner = Arc::clone(&self.planner);
        py.detach(move || {
            guarded(|| {
                serde_json::to_string(&PlannerApi::report(&*planner, &starts))
                    .map_err(|e| scene_error(e.to_string()))
            })
        })
    }

    /// The text summary `hplan plan` prints for `starts` (shape (n, dof)).
    fn summary(&self, py: Python<'_>, starts: &Bound<'_, PyAny>) -> PyResult<String> {
        let starts = self.configurations(starts, "starts")?;
        let planner = Arc::clone(&self.planner);
        py.detach(move || guarded(|| Ok(PlannerApi::report(&*planner, &starts).summary())))
    }

    /// The scene with the robot drawn along each path (SVG text).
    fn svg(&self, paths: Vec<PyRef<'_, PyPath>>) -> PyResult<String> {
        let paths: Vec<Vec<Vec<f64>>> = paths.iter().map(|p| p.configurations()).collect();
        guarded(|| Ok(self.planner.svg(&paths, None)))
    }

    /// Degrees of freedom: 3 for a polygon (x, y, theta), the number of joints for an arm.
    #[getter]
    fn dof(&self) -> usize {
        self.planner.space().dof()
    }

    /// `"pose"` (a polygon robot) or `"joints"` (an arm).
    #[getter]
    fn configuration(&self) -> &'static str {
        self.planner.configuration()
    }

    /// What produced ψ, as `hplan plan --json` says in `potential.solved_by` ("accurate",
    /// "cholesky", "multigrid", "pcg (clamped M-matrix)", …).
    #[getter]
    fn solved_by(&self) -> &'static str {
        self.planner.solved_by()
    }

    /// Wall-clock milliseconds of each build stage: {"mesh", "assemble", "solve"}.
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        timings_dict(py, self.planner.timings())
    }

    /// The file the scene came from, or None.
    #[getter]
    fn source(&self) -> Option<String> {
        self.source.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "ConfigPlanner(source={}, configuration={:?}, tetrahedra={})",
            crate::planner::py_repr(&self.source),
            self.configuration(),
            self.planner.slab().tetrahedra().len()
        )
    }
}
