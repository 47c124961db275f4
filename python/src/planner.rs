//! `hp.Planner`: a plane scene meshed, assembled and factored once, then queried.

use std::path::PathBuf;
use std::sync::Arc;

use harmonic_planner::map::{MapOptions, OccupancyMap};
use harmonic_planner::{CarParams, Planner, PlannerOptions, Point, Scene, Timings};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::{built, guarded, scene_error};
use crate::paths::{PyCarRun, PyPath};
use crate::scene::PyScene;

/// A harmonic-potential planner for one plane scene.
///
/// `Planner(scene)` validates and meshes the scene, assembles the finite element system and
/// factors and solves it — once (the GIL is released meanwhile); every query afterwards
/// (`plan`, `plan_many`, `potential`, `psi`, `gradient`, `drive`) reuses that solution.
/// `max_area` overrides the scene's `mesh.max_area` (as `hplan --max-area`). `multigrid=K`
/// (0 to 8) meshes at 4^K times that area, refines the mesh uniformly K times and solves by
/// multigrid-preconditioned conjugate gradients, checked (no negative ψ, no underflow, no
/// interior extremum) and else solved directly on the same mesh (as `hplan --multigrid`);
/// 0 factors the scene's own mesh. By default (`None`) K = 2 from 100 000 estimated
/// triangles and 0 below.
///
/// A planner is immutable: an error in one query leaves it usable for the next.
#[pyclass(module = "harmonic_planner", name = "Planner", frozen)]
pub struct PyPlanner {
    planner: Arc<Planner>,
    /// The file the scene (or map) came from, for error messages.
    source: Option<String>,
}

/// `--max-area`'s check.
pub(crate) fn positive(name: &str, v: Option<f64>) -> PyResult<Option<f64>> {
    match v {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(scene_error(format!(
            "{name} must be a positive number, got {v}"
        ))),
        v => Ok(v),
    }
}

pub(crate) fn timings_dict<'py>(py: Python<'py>, t: Timings) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("mesh", t.mesh)?;
    d.set_item("assemble", t.assemble)?;
    d.set_item("solve", t.solve)?;
    Ok(d)
}

impl PyPlanner {
    /// Wraps a built planner (one from a `Workspace`).
    pub(crate) fn from_planner(planner: Planner, source: Option<String>) -> PyPlanner {
        PyPlanner {
            planner: Arc::new(planner),
            source,
        }
    }

    fn build(
        py: Python<'_>,
        scene: Scene,
        source: Option<String>,
        multigrid: Option<usize>,
        threads: Option<usize>,
    ) -> PyResult<PyPlanner> {
        let options = PlannerOptions {
            multigrid,
            threads,
            ..PlannerOptions::default()
        };
        let planner = built(py, &source, move || Planner::with_options(&scene, &options))?;
        Ok(PyPlanner {
            planner: Arc::new(planner),
            source,
        })
    }

    /// Evaluates `f` at every point (NaN where it returns None). Each point is located
    /// afresh (the mesh's bucket grid is O(1); walking from the previous point's triangle
    /// only pays for polylines). Large arrays are split across threads with the GIL released.
    fn map_points<const K: usize>(
        &self,
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        f: impl Fn(&Planner, Point) -> Option<[f64; K]> + Sync + Send,
    ) -> PyResult<Vec<[f64; K]>> {
        arrays::map_points(py, points, &*self.planner, |pl, [x, y]| {
            f(pl, Point::new(x, y))
        })
    }
}

#[pymethods]
impl PyPlanner {
    #[new]
    #[pyo3(signature = (scene, *, max_area = None, multigrid = None, threads = None))]
    fn new(
        py: Python<'_>,
        scene: &PyScene,
        max_area: Option<f64>,
        multigrid: Option<usize>,
        threads: Option<usize>,
    ) -> PyResult<PyPlanner> {
        let mut plane = scene.plane("Planner")?;
        if let Some(a) = positive("max_area", max_area)? {
            plane.mesh.max_area = Some(a);
        }
        if let Some(k) = multigrid.filter(|&k| k > 8) {
            return Err(scene_error(format!(
                "multigrid must be 0 to 8 refinements, got {k}"
            )));
        }
        PyPlanner::build(py, plane, scene.source.clone(), multigrid, threads)
    }

    /// A planner on a ROS map_server occupancy map (`map.yaml` with its PGM/PNG image)
    /// towards `goal` (world coordinates) for a disc robot of `robot_radius`, as
    /// `hplan plan --map MAP.yaml --goal X,Y --robot-radius R` builds it (the map's default
    /// mesher, `auto`).
    /// Occupied cells (and unknown ones) are obstacles. A `scale` or `raw` map's graded
    /// costs shape the field by `cost_weight` (`--cost-weight`: a cell of cost c conducts
    /// 1 / (1 + w·0.016·c) of a free cell's flow and the costliest cells absorb; 0 plans
    /// them as free cells). The GIL is
    /// released while the map is read and the planner built.
    #[staticmethod]
    #[pyo3(signature = (yaml, goal, robot_radius = 0.0, *, max_area = None, cost_weight = 1.0, threads = None))]
    fn from_map(
        py: Python<'_>,
        yaml: PathBuf,
        goal: &Bound<'_, PyAny>,
        robot_radius: f64,
        max_area: Option<f64>,
        cost_weight: f64,
        threads: Option<usize>,
    ) -> PyResult<PyPlanner> {
        let goal = arrays::finite(arrays::point::<2>(goal, "goal")?, "goal")?;
        let opts = MapOptions {
            max_area: positive("max_area", max_area)?,
            cost_weight,
            ..MapOptions::default()
        };
        let planner = py.detach(|| {
            guarded(|| {
                OccupancyMap::load(&yaml)
                    .and_then(|m| {
                        let options = PlannerOptions {
                            threads,
                            ..PlannerOptions::default()
                        };
                        m.planner(goal, robot_radius, &opts, &options)
                    })
                    .map_err(|e| scene_error(e.to_string()))
            })
        })?;
        Ok(PyPlanner {
            planner: Arc::new(planner),
            source: Some(yaml.display().to_string()),
        })
    }

    /// Plans a path from `start` (x, y) down the potential to the goal: the smooth tracer,
    /// and where it stalls the exact one. Returns a `Path`; an unreachable or blocked start
    /// is a status, not an error.
    fn plan(&self, start: &Bound<'_, PyAny>) -> PyResult<PyPath> {
        let start = arrays::finite(arrays::point::<2>(start, "start")?, "start")?;
        guarded(|| Ok(self.planner.plan(start).into()))
    }

    /// The exact tracer's path from `start` (straight within each triangle, φ strictly
    /// decreasing along it).
    fn plan_exact(&self, start: &Bound<'_, PyAny>) -> PyResult<PyPath> {
        let start = arrays::finite(arrays::point::<2>(start, "start")?, "start")?;
        guarded(|| Ok(self.planner.plan_exact(start).into()))
    }

    /// Plans from every row of `starts` (shape (n, 2)) in parallel (rayon, GIL released);
    /// returns a list of `Path` in the same order.
    fn plan_many(&self, py: Python<'_>, starts: &Bound<'_, PyAny>) -> PyResult<Vec<PyPath>> {
        crate::paths::plan_many(py, &self.planner, starts)
    }

    /// φ at every row of `points` (shape (m, 2)), interpolated linearly on the mesh; an
    /// array of shape (m,), NaN outside free space (inside obstacles, outside the workspace).
    fn potential<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = self.map_points::<1>(py, points, |pl, p| {
            Some([pl.potential().evaluate(p, None).ok()?.phi])
        })?;
        Ok(arrays::values(py, v.into_iter().map(|[x]| x).collect()))
    }

    /// ψ = c − φ at every row of `points` (c: the walls' value, `reference`), interpolated
    /// from ψ's own nodal values, so it keeps its relative accuracy where φ ≈ c (far from the
    /// goal, ψ can be 1e-12 while φ rounds to c). Shape (m,), NaN outside free space.
    fn psi<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = self.map_points::<1>(py, points, |pl, p| {
            Some([pl.potential().evaluate(p, None).ok()?.psi])
        })?;
        Ok(arrays::values(py, v.into_iter().map(|[x]| x).collect()))
    }

    /// ∇φ at every row of `points` (shape (m, 2)): the P1 gradient, constant on each
    /// triangle, or with `smooth=True` the recovered (area-averaged nodal, interpolated)
    /// gradient the smooth tracer follows. Shape (m, 2), NaN outside free space.
    #[pyo3(signature = (points, *, smooth = false))]
    fn gradient<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        smooth: bool,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.map_points::<2>(py, points, move |pl, p| {
            let pot = pl.potential();
            let t = pot.locate(p, None).ok()?;
            let g = if smooth {
                pot.recovered_gradient_psi_at(p, Some(t)).ok()?
            } else {
                pot.triangle_gradient_psi(t)
            };
            // ∇φ = −∇ψ.
            Some([-g.x, -g.y])
        })?;
        Ok(arrays::rows_f64(py, &v))
    }

    /// The mesh of free space: `(vertices, triangles)`, float64 of shape (V, 2) and int64 of
    /// shape (T, 3) (counter-clockwise vertex indices), e.g. for `matplotlib.tri.Triangulation`.
    fn mesh<'py>(&self, py: Python<'py>) -> (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>) {
        let mesh = self.planner.mesh();
        let vertices: Vec<[f64; 2]> = mesh.vertices().iter().map(|p| [p.x, p.y]).collect();
        (
            arrays::rows_f64(py, &vertices),
            arrays::rows_i64(py, mesh.triangles()),
        )
    }

    /// φ at every mesh vertex, shape (V,) (same order as `mesh()[0]`).
    fn phi_at_vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::values(py, self.planner.potential().phi_at_vertices())
    }

    /// ψ = c − φ at every mesh vertex, shape (V,).
    fn psi_at_vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::values(py, self.planner.potential().psi().to_vec())
    }

    /// The walls' value c of φ (ψ = c − φ).
    #[getter]
    fn reference(&self) -> f64 {
        self.planner.potential().reference()
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

    /// The file the scene or map came from, or None.
    #[getter]
    fn source(&self) -> Option<String> {
        self.source.clone()
    }

    /// Drives a car-like robot (front-wheel steering, bicycle model) from `pose`
    /// (x, y, theta: rear-axle midpoint and heading in radians) along the potential, as
    /// `hplan car`. Defaults as the command line's: `wheelbase` 2 % of the scene's size,
    /// `max_steer_deg` 35, `step` a tenth of the default wheelbase. `check_footprint` checks a
    /// 1.25 L × 0.6 L rectangle against the obstacles every step. Returns a `CarRun`.
    #[pyo3(signature = (pose, *, wheelbase = None, max_steer_deg = 35.0, step = None, check_footprint = false))]
    fn drive(
        &self,
        pose: &Bound<'_, PyAny>,
        wheelbase: Option<f64>,
        max_steer_deg: f64,
        step: Option<f64>,
        check_footprint: bool,
    ) -> PyResult<PyCarRun> {
        let pose = arrays::finite(arrays::point::<3>(pose, "pose")?, "pose")?;
        guarded(|| {
            let mut params = CarParams::for_scene(&self.planner);
            if let Some(l) = wheelbase {
                params.wheelbase = l;
            }
            if let Some(s) = step {
                params.step = s;
            }
            params.max_steer = max_steer_deg.to_radians();
            params.check_footprint = check_footprint;
            params.validate().map_err(|e| scene_error(e.to_string()))?;
            let run = self
                .planner
                .car(pose, &params)
                .map_err(|e| scene_error(e.to_string()))?;
            Ok(run.into())
        })
    }

    fn __repr__(&self) -> String {
        let mesh = self.planner.mesh();
        format!(
            "Planner(source={}, vertices={}, triangles={})",
            py_repr(&self.source),
            mesh.vertices().len(),
            mesh.triangles().len()
        )
    }
}

/// An optional file name as Python would show it: `'file'` or `None`.
pub(crate) fn py_repr(source: &Option<String>) -> String {
    match source {
        Some(s) => format!("'{}'", s.replace('\\', "\\\\").replace('\'', "\\'")),
        None => "None".into(),
    }
}
