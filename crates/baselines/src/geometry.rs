//! Small polygon queries shared by the analytic planners.

use harmonic_mesh::{Point, Vector};

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

/// Whether `p` lies inside `poly` (even–odd rule; either orientation).
pub(crate) fn contains(poly: &[Point], p: Point) -> bool {
    let mut inside = false;
    for (k, a) in poly.iter().enumerate() {
        let b = poly[(k + 1) % poly.len()];
        if (a.y <= p.y) != (b.y <= p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The point of segment `a b` closest to `p`.
pub(crate) fn closest_on_segment(p: Point, a: Point, b: Point) -> Point {
    let ab: Vector = b - a;
    let len2 = ab.norm_squared();
    if len2 == 0.0 {
        return a;
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    a + ab * t
}

/// The point of the boundary of `poly` closest to `p`, and its distance.
pub(crate) fn closest_on_boundary(poly: &[Point], p: Point) -> (Point, f64) {
    let mut best = (poly[0], f64::INFINITY);
    for (k, a) in poly.iter().enumerate() {
        let c = closest_on_segment(p, *a, poly[(k + 1) % poly.len()]);
        let d = (p - c).norm();
        if d < best.1 {
            best = (c, d);
        }
    }
    best
}
