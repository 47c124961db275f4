//! Python bindings of harmonic-planner: `import harmonic_planner as hp`.
//!
//! The native module is `harmonic_planner._native`; `python/harmonic_planner/__init__.py`
//! re-exports it and `_native.pyi` types it. Concepts by file: [`scene`] (`hp.Scene`),
//! [`planner`] (`hp.Planner`), [`workspace`] (`hp.Workspace`), [`volume`] (`hp.VolumePlanner`), [`cspace`]
//! (`hp.ConfigPlanner`), [`paths`] (`hp.Path`,
//! `hp.CarRun`), [`errors`] (`hp.SceneError`, the panic boundary), [`arrays`] (NumPy in and
//! out, shape checks).

use pyo3::prelude::*;

mod arrays;
mod cspace;
mod errors;
mod paths;
mod planner;
mod scene;
mod volume;
mod workspace;

/// Local-minimum-free robot path planning with harmonic potentials solved by P1 finite
/// elements (native part; use the `harmonic_planner` package).
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<errors::SceneError>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<planner::PyPlanner>()?;
    m.add_class::<volume::PyVolumePlanner>()?;
    m.add_class::<cspace::PyConfigPlanner>()?;
    m.add_class::<workspace::PyWorkspace>()?;
    m.add_class::<paths::PyPath>()?;
    m.add_class::<paths::PyCarRun>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(_panic_at_the_boundary, m)?)?;
    Ok(())
}

/// Panics inside the boundary on purpose, so the tests can check that a Rust panic becomes a
/// `SceneError` ("internal error: …") instead of unwinding into the interpreter.
#[pyfunction]
fn _panic_at_the_boundary() -> PyResult<()> {
    errors::guarded(|| panic!("a deliberate panic"))
}
