//! The obstacles as exact polygons, the secondary control points a robot segment has within
//! δ of them (§4), and the point-source potential φ_o of eq. 42 that pushes those points away.

use harmonic_mesh::geom::{closest_points_segment_segment, polygon_contains, ring_edges};
use harmonic_mesh::{Point, Vector};

use crate::ControlError;

/// The obstacle polygons (either orientation, implicitly closed).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Obstacles {
    polygons: Vec<Vec<Point>>,
}

/// A secondary control point and its obstacle point (§4): the closest pair of a robot
/// segment and one obstacle edge, within δ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The secondary control point, on the robot.
    pub robot_point: Point,
    /// The obstacle point, on the obstacle's boundary.
    pub obstacle_point: Point,
    /// Their distance (0: touching).
    pub distance: f64,
    /// The obstacle.
    pub obstacle: usize,
    /// The robot segment (a bar has one; an arm's link `k` is segment `k`).
    pub segment: usize,
}

impl Obstacles {
    /// Checked polygons: at least three vertices each, finite coordinates.
    pub fn new(polygons: Vec<Vec<Point>>) -> Result<Self, ControlError> {
        for (index, p) in polygons.iter().enumerate() {
            if p.len() < 3 {
                return Err(ControlError::InvalidObstacle {
                    index,
                    reason: "a polygon needs at least three vertices",
                });
            }
            if p.iter().any(|q| !q.x.is_finite() || !q.y.is_finite()) {
                return Err(ControlError::InvalidObstacle {
                    index,
                    reason: "a coordinate is not finite",
                });
            }
        }
        Ok(Obstacles { polygons })
    }

    /// The polygons.
    pub fn polygons(&self) -> &[Vec<Point>] {
        &self.polygons
    }

    /// The smallest distance from the segment `ab` to every obstacle (0 when it touches or
    /// lies inside one), with that obstacle; `None` without obstacles.
    pub fn segment_distance(&self, a: Point, b: Point) -> Option<(f64, usize)> {
        self.polygons
            .iter()
            .enumerate()
            .filter_map(|(i, poly)| {
                harmonic_mesh::geom::closest_points_segment_polygon(a, b, poly).map(|c| (c.2, i))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0))
    }

    /// The secondary control points of robot segment `segment` (`ab`) within `delta`: per
    /// obstacle, the closest pair with each edge, merged where the robot points lie within
    /// `delta` of one another (the closer pair kept) — so a segment beside a concave
    /// obstacle gets one point per side it approaches. A segment that lies inside an
    /// obstacle gets a contact of distance 0 at `a`.
    pub fn contacts(&self, a: Point, b: Point, delta: f64, segment: usize) -> Vec<Contact> {
        let mut out: Vec<Contact> = Vec::new();
        for (obstacle, poly) in self.polygons.iter().enumerate() {
            let first = out.len();
            if polygon_contains(poly, a) {
                out.push(Contact {
                    robot_point: a,
                    obstacle_point: a,
                    distance: 0.0,
                    obstacle,
                    segment,
                });
                continue;
            }
            for (c, d) in ring_edges(poly) {
                let (p, q, dist) = closest_points_segment_segment(a, b, c, d);
                if dist >= delta {
                    continue;
                }
                let found = Contact {
                    robot_point: p,
                    obstacle_point: q,
                    distance: dist,
                    obstacle,
                    segment,
                };
                match out[first..]
                    .iter_mut()
                    .find(|k| (k.robot_point - p).norm() < delta)
                {
                    Some(k) if k.distance > dist => *k = found,
                    Some(_) => {}
                    None => out.push(found),
                }
            }
        }
        out
    }
}

/// Eq. 42: `φ_o(x, y) = Σᵢ λ_c / (2π) · log R_ci`, one point source of strength `λ_c` at
/// each obstacle point. Its gradient pushes away from every obstacle point, as `1/R`.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstaclePotential {
    /// The obstacle points.
    pub sources: Vec<Point>,
    /// λ_c, the same for every source.
    pub strength: f64,
}

impl ObstaclePotential {
    /// The sources at the obstacle points of `contacts`.
    pub fn from_contacts(contacts: &[Contact], strength: f64) -> Self {
        ObstaclePotential {
            sources: contacts.iter().map(|c| c.obstacle_point).collect(),
            strength,
        }
    }

    /// φ_o at `p`.
    pub fn value(&self, p: Point) -> f64 {
        self.sources
            .iter()
            .map(|&s| self.strength / (2.0 * std::f64::consts::PI) * (p - s).norm().ln())
            .sum()
    }

    /// ∇φ_o at `p` (sources at `p` itself are left out: they have no direction).
    pub fn gradient(&self, p: Point) -> Vector {
        self.sources
            .iter()
            .filter_map(|&s| {
                let r = p - s;
                let r2 = r.norm_squared();
                (r2 > 0.0).then(|| r * (self.strength / (2.0 * std::f64::consts::PI * r2)))
            })
            .sum()
    }
}
