//! The local area bound of a [`Grading`]: distances to goal boundaries and obstacle corners.

use rstar::RTree;

use crate::geom::SegmentIndex;
use crate::options::Grading;
use crate::{BoundaryTag, Domain, Point};

/// A boundary vertex is an obstacle corner if the boundary turns there by more than this
/// (radians): 35°, above the 30° turns of the coarsest discretised circle (12 vertices).
const CORNER_TURN: f64 = 35.0 * std::f64::consts::PI / 180.0;

/// Local area bound `max_area · min(s_goal, s_corner)²`, each `s = a + (1 − a)·min(d / r, 1)`.
pub(crate) struct SizeField {
    max_area: f64,
    radius: f64,
    /// Goal boundary segments and `√near_goal` (none if there are no goals or no grading).
    goal: Option<(SegmentIndex, f64)>,
    /// Obstacle corners and `√near_corners`.
    corners: Option<(RTree<[f64; 2]>, f64)>,
    /// Triangles the grading adds on top of a uniform mesh, roughly (an overestimate where
    /// bands overlap): for the triangle budget.
    extra_triangles: f64,
}

/// Triangles per unit of `1 / max_area` area in a 30° refinement (as in `Domain::mesh`).
const TRIANGLES_PER_AREA: f64 = 1.6;

impl SizeField {
    pub(crate) fn new(domain: &Domain, max_area: f64, grading: &Grading) -> Self {
        let radius = grading.radius;
        let mut goal_segments = Vec::new();
        let mut corners = Vec::new();
        for ring in domain.unit_rings() {
            let n = ring.points.len();
            for k in 0..n {
                let (prev, p, next) = (
                    ring.points[(k + n - 1) % n],
                    ring.points[k],
                    ring.points[(k + 1) % n],
                );
                if matches!(ring.tags[k], BoundaryTag::Goal(_)) {
                    goal_segments.push((p, next, 0));
                }
                let obstacle = [ring.tags[(k + n - 1) % n], ring.tags[k]]
                    .iter()
                    .any(|t| matches!(t, BoundaryTag::Obstacle(_)));
                let (u, v) = (p - prev, next - p);
                let turn = (u.x * v.y - u.y * v.x).atan2(u.dot(&v)).abs();
                if obstacle && turn > CORNER_TURN {
                    corners.push([p.x, p.y]);
                }
            }
        }
        let a_goal = grading.near_goal.sqrt();
        let a_corner = grading.near_corners.sqrt();
        let perimeter: f64 = goal_segments.iter().map(|(p, q, _)| (q - p).norm()).sum();
        // ∫₀ʳ (1/s² − 1) dd = r (1/a − 1) per unit of goal boundary; around a point,
        // ∫₀ʳ 2πρ (1/s² − 1) dρ = 2πr² (ln(1/a) − 1 + a) / (1 − a)² − πr².
        let band = perimeter * radius * (1.0 / a_goal - 1.0);
        let disc = if a_corner < 1.0 {
            let pi = std::f64::consts::PI;
            (2.0 * pi * radius * radius * (-a_corner.ln() - 1.0 + a_corner)
                / (1.0 - a_corner).powi(2)
                - pi * radius * radius)
                .max(0.0)
        } else {
            0.0
        };
        // Never more than refining all of free space to the finer factor.
        let finest = grading.near_goal.min(grading.near_corners);
        let extra_triangles = (TRIANGLES_PER_AREA * (band + disc * corners.len() as f64)
            / max_area)
            .min(TRIANGLES_PER_AREA * domain.unit_free_area() * (1.0 / finest - 1.0) / max_area);
        SizeField {
            max_area,
            radius,
            goal: (a_goal < 1.0 && !goal_segments.is_empty())
                .then(|| (SegmentIndex::new(goal_segments), a_goal)),
            corners: (a_corner < 1.0 && !corners.is_empty())
                .then(|| (RTree::bulk_load(corners), a_corner)),
            extra_triangles,
        }
    }

    /// Roughly how many triangles the grading adds to a uniform mesh at `max_area`.
    pub(crate) fn extra_triangles(&self) -> f64 {
        self.extra_triangles
    }

    /// The largest triangle area wanted at `p`.
    pub(crate) fn area_at(&self, p: Point) -> f64 {
        let factor = |d: f64, a: f64| a + (1.0 - a) * (d / self.radius).min(1.0);
        let mut s: f64 = 1.0;
        if let Some((index, a)) = &self.goal {
            s = s.min(factor(index.distance(p), *a));
        }
        if let Some((tree, a)) = &self.corners
            && let Some(c) = tree.nearest_neighbor(&[p.x, p.y])
        {
            s = s.min(factor((Point::new(c[0], c[1]) - p).norm(), *a));
        }
        self.max_area * s * s
    }
}
