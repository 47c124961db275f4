//! Input checks shared by the analytic planners (their polygon kernels are
//! `harmonic_mesh::geom`'s).

use harmonic_mesh::Point;

use crate::BaselineError;

/// Checks that a polygon has at least three finite vertices; `what` names it in the error.
pub(crate) fn check_polygon(
    what: impl Fn() -> String,
    poly: &[Point],
) -> Result<(), BaselineError> {
    if poly.len() < 3 {
        return Err(BaselineError::TooFewVertices {
            what: what(),
            count: poly.len(),
        });
    }
    for p in poly {
        check_point(&what, *p)?;
    }
    Ok(())
}

/// Checks that a point is finite; `what` names it in the error.
pub(crate) fn check_point(what: impl Fn() -> String, p: Point) -> Result<(), BaselineError> {
    for v in [p.x, p.y] {
        if !v.is_finite() {
            return Err(BaselineError::NonFinite {
                what: what(),
                value: v,
            });
        }
    }
    Ok(())
}

/// Checks that a parameter is finite and positive.
pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<(), BaselineError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(BaselineError::InvalidParameter {
            name,
            value,
            reason: "must be positive and finite",
        })
    }
}
