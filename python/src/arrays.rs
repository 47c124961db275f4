//! NumPy in and out: any array-like of floats in (lists, tuples, arrays of any numeric
//! dtype), with its shape checked and named in the error; float64 / int64 arrays out.

use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::errors::{guarded, scene_error};

/// `obj` as a float64 array (`numpy.asarray(obj, dtype=float64)`), or a [`SceneError`]
/// saying what `what` should have been.
///
/// [`SceneError`]: crate::errors::SceneError
fn as_f64_array<'py>(
    obj: &Bound<'py, PyAny>,
    what: &str,
    expected: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let array = np
        .getattr("asarray")?
        .call1((obj, np.getattr("float64")?))
        .map_err(|e| {
            scene_error(format!(
                "{what}: expected an array of shape {expected} of numbers ({})",
                e.value(py)
            ))
        })?;
    array
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| scene_error(format!("{what}: expected an array of shape {expected}")))
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// An `(m, D)` array of points as `m` rows of `D` coordinates. `what` names the argument in
/// the error (`points`, `starts`).
pub fn points<const D: usize>(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f64; D]>> {
    let expected = format!("(m, {D})");
    let array = as_f64_array(obj, what, &expected)?;
    let shape = array.shape().to_vec();
    if shape.len() != 2 || shape[1] != D {
        return Err(scene_error(format!(
            "{what}: expected an array of shape {expected}, got shape {}",
            shape_text(&shape)
        )));
    }
    let readonly = array.readonly();
    let view = readonly.as_array();
    Ok(view
        .outer_iter()
        .map(|row| std::array::from_fn(|k| row[k]))
        .collect())
}

/// One point of `D` coordinates (a sequence or an array of shape `(D,)`).
pub fn point<const D: usize>(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; D]> {
    let expected = format!("({D},)");
    let array = as_f64_array(obj, what, &expected)?;
    let shape = array.shape().to_vec();
    if shape != [D] {
        return Err(scene_error(format!(
            "{what}: expected an array of shape {expected}, got shape {}",
            shape_text(&shape)
        )));
    }
    let readonly = array.readonly();
    let view = readonly.as_array();
    Ok(std::array::from_fn(|k| view[[k]]))
}

/// Rows of `D` values as a float64 array of shape `(n, D)`.
pub fn rows_f64<'py, const D: usize>(
    py: Python<'py>,
    rows: &[[f64; D]],
) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    let array = Array2::from_shape_vec((rows.len(), D), flat).expect("n rows of D values");
    PyArray2::from_owned_array(py, array)
}

/// Rows of `D` indices as an int64 array of shape `(n, D)`.
pub fn rows_i64<'py, const D: usize>(
    py: Python<'py>,
    rows: &[[u32; D]],
) -> Bound<'py, PyArray2<i64>> {
    let flat: Vec<i64> = rows.iter().flatten().map(|&i| i64::from(i)).collect();
    let array = Array2::from_shape_vec((rows.len(), D), flat).expect("n rows of D indices");
    PyArray2::from_owned_array(py, array)
}

/// A float64 array of shape `(n,)`.
pub fn values<'py>(py: Python<'py>, values: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, values)
}

/// `p` if every coordinate is a finite number, else a [`SceneError`] naming `what`.
///
/// [`SceneError`]: crate::errors::SceneError
pub(crate) fn finite<const D: usize>(p: [f64; D], what: &str) -> PyResult<[f64; D]> {
    if p.iter().all(|v| v.is_finite()) {
        Ok(p)
    } else {
        Err(scene_error(format!(
            "{what}: coordinates must be finite numbers, got {p:?}"
        )))
    }
}

/// Arrays of at least this many points are evaluated in parallel.
pub(crate) const PARALLEL_FROM: usize = 4096;

/// `f(of, row)` at every row of `points` (shape (m, D)), a row of NaN where `f` has no value
/// (outside free space); in parallel with the GIL released from [`PARALLEL_FROM`] rows.
pub(crate) fn map_points<T: Sync, const D: usize, const K: usize>(
    py: Python<'_>,
    points: &Bound<'_, PyAny>,
    of: &T,
    f: impl Fn(&T, [f64; D]) -> Option<[f64; K]> + Sync + Send,
) -> PyResult<Vec<[f64; K]>> {
    let points = self::points::<D>(points, "points")?;
    let one = |p: &[f64; D]| f(of, *p).unwrap_or([f64::NAN; K]);
    if points.len() < PARALLEL_FROM {
        return guarded(|| Ok(points.iter().map(one).collect()));
    }
    py.detach(|| guarded(|| Ok(points.par_iter().map(one).collect())))
}
