//! The one exception type of the module, and the boundary that keeps Rust panics out of
//! Python.

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

pyo3::create_exception!(
    harmonic_planner,
    SceneError,
    PyValueError,
    "Bad input: an unreadable or invalid scene or map, a scene that cannot be meshed or solved, \
     an option out of range, or an array of the wrong shape. The message is the command line's \
     (`hplan: <message>`) without the `hplan: ` prefix: `<file>: <error>` for files, the error \
     alone otherwise. A subclass of ValueError."
);

/// A [`SceneError`] with `message`.
pub fn scene_error(message: impl Into<String>) -> PyErr {
    SceneError::new_err(message.into())
}

/// Runs `f`, turning a panic into a [`SceneError`] ("internal error: …") so that no panic
/// unwinds into the interpreter. Planners are immutable after they are built, so one that
/// was in use when a query panicked is still whole and usable afterwards.
pub fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            Err(scene_error(format!("internal error: {what}")))
        }
    }
}

/// Builds something heavy with `build` outside the GIL and inside the panic boundary; its
/// error becomes a [`SceneError`] saying `<file>: <error>` when the input came from `source`.
pub fn built<T: Send, E: std::fmt::Display>(
    py: Python<'_>,
    source: &Option<String>,
    build: impl FnOnce() -> Result<T, E> + Send,
) -> PyResult<T> {
    let shown = source.clone();
    py.detach(move || {
        guarded(|| {
            build().map_err(|e| {
                scene_error(match &shown {
                    Some(file) => format!("{file}: {e}"),
                    None => e.to_string(),
                })
            })
        })
    })
}
