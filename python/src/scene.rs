//! `hp.Scene`: a scene file of either kind (plane, or volume with `"dimension": 3`), read
//! from a file, a JSON string or a Python dict.

use std::path::PathBuf;

use harmonic_planner::{AnyScene, Scene};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;
use crate::errors::{guarded, scene_error};

/// A scene: workspace, obstacles, goal regions, boundary conditions, mesh options, robot.
///
/// Build one with `Scene.from_file(path)`, `Scene.from_json(text)` or `Scene.from_dict(d)`
/// (the format of the JSON files in `meshes/`). Plane scenes go to `Planner`; volume scenes
/// (`"dimension": 3`) to `VolumePlanner`. Invalid input raises `SceneError` with the same
/// message as `hplan`.
#[pyclass(module = "harmonic_planner", name = "Scene", frozen)]
#[derive(Clone)]
pub struct PyScene {
    pub(crate) scene: AnyScene,
    /// The file it was read from, if any: errors of planners built from it start with it.
    pub(crate) source: Option<String>,
}

impl PyScene {
    /// `message` prefixed with the scene's file, as `hplan` prints errors about a scene.
    pub(crate) fn located(&self, message: impl std::fmt::Display) -> String {
        match &self.source {
            Some(file) => format!("{file}: {message}"),
            None => message.to_string(),
        }
    }

    /// The plane scene, or a SceneError saying `what` needs one.
    pub(crate) fn plane(&self, what: &str) -> PyResult<Scene> {
        match &self.scene {
            AnyScene::Plane(s) => Ok((**s).clone()),
            AnyScene::Volume(_) => Err(scene_error(self.located(format!(
                "{what} works on plane scenes, not volumes (use VolumePlanner)"
            )))),
            AnyScene::Config(_) => Err(scene_error(self.located(format!(
                "{what} works on plane scenes, not on polygon or arm robots (use hplan plan)"
            )))),
        }
    }

    fn to_json_text(&self) -> PyResult<String> {
        let text = match &self.scene {
            AnyScene::Plane(s) => serde_json::to_string(s),
            AnyScene::Volume(s) => serde_json::to_string(s),
            AnyScene::Config(s) => serde_json::to_string(s),
        };
        text.map_err(|e| scene_error(e.to_string()))
    }
}

#[pymethods]
impl PyScene {
    /// Reads a scene file (plane or volume). Errors read `<path>: <error>`, as `hplan` says
    /// them.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<PyScene> {
        guarded(|| {
            let shown = path.display().to_string();
            let scene =
                AnyScene::from_file(&path).map_err(|e| scene_error(format!("{shown}: {e}")))?;
            Ok(PyScene {
                scene,
                source: Some(shown),
            })
        })
    }

    /// Parses a scene from JSON text. Errors name the field, line and column.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<PyScene> {
        guarded(|| {
            let scene = AnyScene::from_json(text).map_err(|e| scene_error(e.to_string()))?;
            Ok(PyScene {
                scene,
                source: None,
            })
        })
    }

    /// A scene from a dict (or any JSON-serialisable mapping) of the file format: it is
    /// serialised with `json.dumps(d, indent=1)`, so lines and columns in errors refer to
    /// that text; NaN and infinity are rejected.
    #[staticmethod]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyAny>) -> PyResult<PyScene> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("allow_nan", false)?;
        kwargs.set_item("indent", 1)?;
        let text: String = py
            .import("json")?
            .getattr("dumps")?
            .call((d,), Some(&kwargs))
            .map_err(|e| scene_error(format!("not a JSON document: {}", e.value(py))))?
            .extract()?;
        PyScene::from_json(&text)
    }

    /// The scene as JSON text (the file format, defaults filled in).
    fn to_json(&self) -> PyResult<String> {
        self.to_json_text()
    }

    /// The scene as a dict (`json.loads(scene.to_json())`).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?
            .getattr("loads")?
            .call1((self.to_json_text()?,))
    }

    /// 2 for a plane scene, 3 for a volume scene; for a configuration-space robot the size
    /// of its configuration (3 for a polygon robot's (x, y, θ), the joint count of an arm).
    #[getter]
    fn dimension(&self) -> u32 {
        match &self.scene {
            AnyScene::Plane(_) => 2,
            AnyScene::Volume(_) => 3,
            AnyScene::Config(s) => s.starts.first().map_or(3, |q| q.len() as u32),
        }
    }

    /// The scene's name, if it has one.
    #[getter]
    fn name(&self) -> Option<String> {
        match &self.scene {
            AnyScene::Plane(s) => s.name.clone(),
            AnyScene::Volume(s) => s.name.clone(),
            AnyScene::Config(s) => s.name.clone(),
        }
    }

    /// The file the scene was read from (None for from_json / from_dict).
    #[getter]
    fn source(&self) -> Option<String> {
        self.source.clone()
    }

    /// The scene's query points `"starts"`, an array of shape (n, 2), or (n, 3) for a volume.
    #[getter]
    fn starts<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        match &self.scene {
            AnyScene::Plane(s) => arrays::rows_f64(py, &s.starts).into_any(),
            AnyScene::Volume(s) => arrays::rows_f64(py, &s.starts).into_any(),
            AnyScene::Config(s) => numpy::PyArray2::from_vec2(py, &s.starts)
                .map(|a| a.into_any())
                .unwrap_or_else(|_| arrays::rows_f64::<3>(py, &[]).into_any()),
        }
    }

    fn __repr__(&self) -> String {
        let name = self
            .name()
            .map(|n| format!("{n:?}"))
            .unwrap_or("None".into());
        match &self.scene {
            AnyScene::Plane(s) => format!(
                "Scene(name={name}, dimension=2, obstacles={}, goals={})",
                s.obstacles.len(),
                s.goals().len()
            ),
            AnyScene::Volume(s) => format!(
                "Scene(name={name}, dimension=3, obstacles={})",
                s.obstacles.len()
            ),
            AnyScene::Config(s) => format!(
                "Scene(name={name}, configuration space, obstacles={})",
                s.obstacles.len()
            ),
        }
    }
}
