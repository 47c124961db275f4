//! `hp.VolumePlanner`: a volume scene (`"dimension": 3`) meshed into tetrahedra, assembled,
//! solved once, then queried with points of shape (n, 3).

use std::sync::Arc;

use harmonic_planner::VolumePlanner;
use harmonic_volume::Point;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::{built, guarded, scene_error};
use crate::paths::PyPath;
use crate::planner::{positive, timings_dict};
use crate::scene::PyScene;

/// A harmonic-potential planner for one volume scene (`"dimension": 3`).
///
/// `VolumePlanner(scene)` meshes free space into tetrahedra (isosurface stuffing), assembles
/// P1 on them and solves — once, with the GIL released. Points are arrays of shape (n, 3).
/// `max_volume` overrides the scene's `mesh.max_volume` (as `hplan --max-volume`).
#[pyclass(module = "harmonic_planner", name = "VolumePlanner", frozen)]
pub struct PyVolumePlanner {
    planner: Arc<VolumePlanner>,
    source: Option<String>,
}

impl PyVolumePlanner {
    /// As `Planner`'s: each point located afresh, large arrays in parallel without the GIL.
    fn map_points<const K: usize>(
        &self,
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        f: impl Fn(&VolumePlanner, &Point) -> Option<[f64; K]> + Sync + Send,
    ) -> PyResult<Vec<[f64; K]>> {
        arrays::map_points(py, points, &*self.planner, |pl, [x, y, z]| {
            f(pl, &Point::new(x, y, z))
        })
    }
}

#[pymethods]
impl PyVolumePlanner {
    #[new]
    #[pyo3(signature = (scene, *, max_volume = None))]
    fn new(py: Python<'_>, scene: &PyScene, max_volume: Option<f64>) -> PyResult<Self> {
        let mut volume = match &scene.scene {
            harmonic_planner::AnyScene::Volume(v) => (**v).clone(),
            harmonic_planner::AnyScene::Plane(_) | harmonic_planner::AnyScene::Config(_) => {
                return Err(scene_error(scene.located(
                    "VolumePlanner works on volume scenes (\"dimension\": 3); use Planner",
                )));
            }
        };
        if let Some(v) = positive("max_volume", max_volume)? {
            volume.mesh.max_volume = Some(v);
        }
        let source = scene.source.clone();
        let planner = built(py, &source, move || VolumePlanner::new(&volume))?;
        Ok(PyVolumePlanner {
            planner: Arc::new(planner),
            source,
        })
    }

    /// Plans a path from `start` (x, y, z); returns a `Path` whose points have shape (n, 3).
    fn plan(&self, start: &Bound<'_, PyAny>) -> PyResult<PyPath> {
        let start = arrays::finite(arrays::point::<3>(start, "start")?, "start")?;
        guarded(|| Ok(self.planner.plan(start).into()))
    }

    /// Plans from every row of `starts` (shape (n, 3)) in parallel, GIL released; a list of
    /// `Path` in the same order.
    fn plan_many(&self, py: Python<'_>, starts: &Bound<'_, PyAny>) -> PyResult<Vec<PyPath>> {
        crate::paths::plan_many(py, &self.planner, starts)
    }

    /// φ at every row of `points` (shape (m, 3)); shape (m,), NaN outside the mesh.
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

    /// ψ = c − φ at every row of `points`, accurate where it is tiny; shape (m,).
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

    /// ∇φ (constant per tetrahedron) at every row of `points`; shape (m, 3).
    fn gradient<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.map_points::<3>(py, points, |pl, p| {
            let g = pl.potential().evaluate(p, None).ok()?.grad_psi;
            Some([-g.x, -g.y, -g.z])
        })?;
        Ok(arrays::rows_f64(py, &v))
    }

    /// The tetrahedral mesh: `(vertices, tetrahedra)`, float64 (V, 3) and int64 (T, 4).
    fn mesh<'py>(&self, py: Python<'py>) -> (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>) {
        let mesh = self.planner.mesh();
        let vertices: Vec<[f64; 3]> = mesh.vertices().iter().map(|p| [p.x, p.y, p.z]).collect();
        (
            arrays::rows_f64(py, &vertices),
            arrays::rows_i64(py, mesh.tetrahedra()),
        )
    }

    /// φ at every mesh vertex, shape (V,).
    fn phi_at_vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::values(py, self.planner.potential().phi_at_vertices())
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
        let mesh = self.planner.mesh();
        format!(
            "VolumePlanner(source={}, vertices={}, tetrahedra={})",
            crate::planner::py_repr(&self.source),
            mesh.vertices().len(),
            mesh.tetrahedra().len()
        )
    }
}
