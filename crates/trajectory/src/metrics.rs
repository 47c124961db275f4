//! Path metrics: length, clearance and discrete curvature.

use harmonic_types::Point;
use serde::Serialize;

use harmonic_types::geom::polyline_length;

/// Geometric measures of a path.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PathMetrics {
    /// Total length.
    pub length: f64,
    /// The smallest distance from the path to an obstacle or wall.
    pub min_clearance: f64,
    /// The largest discrete curvature (see [`max_curvature`]).
    pub max_curvature: f64,
}

/// Measures a polyline. `segment_clearance(a, b)` gives the distance from the segment
/// `a → b` to the nearest obstacle or wall (the facade passes the domain's).
///
/// ```
/// use harmonic_mesh::Point;
/// use harmonic_trajectory::path_metrics;
/// let pts = [Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0)];
/// // Clearance: distance to the line y = −1, smallest at a segment's lower end.
/// let m = path_metrics(&pts, |a, b| a.y.min(b.y) + 1.0);
/// assert_eq!(m.length, 2.0);
/// assert_eq!(m.min_clearance, 1.0);
/// assert!((m.max_curvature - 2f64.sqrt()).abs() < 1e-12);
/// ```
pub fn path_metrics(
    points: &[Point],
    segment_clearance: impl Fn(Point, Point) -> f64,
) -> PathMetrics {
    let min_clearance = match points {
        [] => f64::INFINITY,
        [p] => segment_clearance(*p, *p),
        _ => points
            .windows(2)
            .map(|w| segment_clearance(w[0], w[1]))
            .fold(f64::INFINITY, f64::min),
    };
    PathMetrics {
        length: polyline_length(points),
        min_clearance,
        max_curvature: max_curvature(points),
    }
}

/// The largest Menger curvature `4 · area / (|ab| |bc| |ca|)` (one over the radius of the
/// circle through three consecutive points) along a polyline; repeated points are skipped.
pub fn max_curvature(points: &[Point]) -> f64 {
    let mut pts: Vec<Point> = Vec::with_capacity(points.len());
    for &p in points {
        if pts.last() != Some(&p) {
            pts.push(p);
        }
    }
    pts.windows(3)
        .map(|w| {
            let (a, b, c) = (w[0], w[1], w[2]);
            let cross = (b - a).perp(&(c - a)).abs();
            let denom = (b - a).norm() * (c - b).norm() * (c - a).norm();
            if denom > 0.0 {
                2.0 * cross / denom
            } else {
                0.0
            }
        })
        .fold(0.0, f64::max)
}

/// The largest curvature between consecutive car poses `[x, y, θ]`: for a circular arc
/// turning by Δθ over a chord c it is `2 sin(|Δθ| / 2) / c` (exact for the car stepper's arcs).
pub fn max_pose_curvature(poses: &[[f64; 3]]) -> f64 {
    poses
        .windows(2)
        .map(|w| {
            let dth = (w[1][2] - w[0][2] + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            let chord = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
            if chord > 0.0 {
                2.0 * (0.5 * dth.abs()).sin() / chord
            } else {
                0.0
            }
        })
        .fold(0.0, f64::max)
}
