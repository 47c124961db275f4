//! Attractive/repulsive potential fields (Khatib 1986), in the form of Choset et al.,
//! *Principles of Robot Motion*, §4.1–4.2: a conic-then-parabolic attraction to the goal and
//! a repulsion from every obstacle within a distance Q*, descended with a fixed step. The sum
//! has local minima, so the descent can get trapped: it then reports
//! [`TraceStatus::Stalled`].

use std::time::Instant;

use harmonic_mesh::{Point, Vector};
use harmonic_trajectory::TraceStatus;

use crate::geometry::{check_point, check_polygon, check_positive};
use crate::{BaselineError, PlanResult};
use harmonic_mesh::geom::{closest_point_on_ring, polygon_contains};

/// Gains, thresholds and descent settings of [`PotentialField`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PotentialFieldOptions {
    /// Attractive gain ζ.
    pub zeta: f64,
    /// Distance d* to the goal where the attraction switches from parabolic (inside) to
    /// conic (outside).
    pub d_star: f64,
    /// Repulsive gain η.
    pub eta: f64,
    /// Distance Q* beyond which an obstacle does not repel.
    pub q_star: f64,
    /// Fixed step α of the descent `q ← q − α ∇U(q)`.
    pub step: f64,
    /// The goal counts as reached within this distance.
    pub goal_tolerance: f64,
    /// Give up after this many steps.
    pub max_steps: usize,
    /// The descent is stalled when |∇U| falls below this, or when it moved less than
    /// `goal_tolerance` over the last `stall_window` steps (circling a minimum).
    pub stall_gradient: f64,
    /// Steps over which progress is checked.
    pub stall_window: usize,
}

impl Default for PotentialFieldOptions {
    fn default() -> Self {
        PotentialFieldOptions {
            zeta: 1.0,
            d_star: 2.0,
            eta: 1.0,
            q_star: 1.0,
            step: 0.01,
            goal_tolerance: 0.05,
            max_steps: 100_000,
            stall_gradient: 1e-9,
            stall_window: 200,
        }
    }
}

/// An attractive/repulsive potential over a workspace with polygonal obstacles and a goal
/// point. The workspace boundary repels like an obstacle.
#[derive(Clone, Debug)]
pub struct PotentialField {
    workspace: Vec<Point>,
    obstacles: Vec<Vec<Point>>,
    goal: Point,
    options: PotentialFieldOptions,
}

impl PotentialField {
    /// Builds the field. Errors on polygons with fewer than three vertices, non-finite
    /// coordinates, non-positive gains, distances, step or tolerance, or a zero
    /// `stall_window`.
    ///
    /// ```
    /// use harmonic_baselines::{PotentialField, PotentialFieldOptions};
    /// use harmonic_mesh::Point;
    /// let ws = vec![Point::new(0.0, 0.0), Point::new(10.0, 0.0), Point::new(10.0, 10.0), Point::new(0.0, 10.0)];
    /// let field = PotentialField::new(&ws, &[], Point::new(8.0, 5.0), PotentialFieldOptions::default()).unwrap();
    /// let plan = field.plan(Point::new(2.0, 5.0));
    /// assert!(plan.status.reached_goal());
    /// ```
    pub fn new(
        workspace: &[Point],
        obstacles: &[Vec<Point>],
        goal: Point,
        options: PotentialFieldOptions,
    ) -> Result<Self, BaselineError> {
        check_polygon(|| "workspace".to_string(), workspace)?;
        for (i, o) in obstacles.iter().enumerate() {
            check_polygon(|| format!("obstacle {i}"), o)?;
        }
        check_point(|| "goal".to_string(), goal)?;
        let o = &options;
        for (name, v) in [
            ("zeta", o.zeta),
            ("d_star", o.d_star),
            ("eta", o.eta),
            ("q_star", o.q_star),
            ("step", o.step),
            ("goal_tolerance", o.goal_tolerance),
            ("stall_gradient", o.stall_gradient),
        ] {
            check_positive(name, v)?;
        }
        if o.stall_window == 0 {
            return Err(BaselineError::InvalidParameter {
                name: "stall_window",
                value: 0.0,
                reason: "must be at least 1 step",
            });
        }
        Ok(PotentialField {
            workspace: workspace.to_vec(),
            obstacles: obstacles.to_vec(),
            goal,
            options,
        })
    }

    /// Whether `p` lies in the workspace and outside every obstacle.
    pub fn is_free(&self, p: Point) -> bool {
        polygon_contains(&self.workspace, p)
            && !self.obstacles.iter().any(|o| polygon_contains(o, p))
    }

    /// The polygons that repel: the workspace boundary and every obstacle.
    fn repellers(&self) -> impl Iterator<Item = &[Point]> {
        std::iter::once(self.workspace.as_slice()).chain(self.obstacles.iter().map(Vec::as_slice))
    }

    /// The total potential `U = U_att + Σ U_rep,i` at `p` (infinite on an obstacle boundary).
    pub fn potential(&self, p: Point) -> f64 {
        let o = &self.options;
        let d = (p - self.goal).norm();
        let att = if d <= o.d_star {
            0.5 * o.zeta * d * d
        } else {
            o.d_star * o.zeta * d - 0.5 * o.zeta * o.d_star * o.d_star
        };
        let rep: f64 = self
            .repellers()
            .map(|poly| {
                let (_, dist) = closest_point_on_ring(poly, p).unwrap_or((p, f64::INFINITY));
                if dist <= o.q_star {
                    let s = 1.0 / dist - 1.0 / o.q_star;
                    0.5 * o.eta * s * s
                } else {
                    0.0
                }
            })
            .sum();
        att + rep
    }

    /// The gradient ∇U at `p`: `ζ(q − q_goal)` within d* of the goal, `d* ζ (q − q_goal)/d`
    /// beyond, plus `η (1/Q* − 1/D) (1/D²) ∇D` for each obstacle at distance `D ≤ Q*`,
    /// with `∇D = (q − c)/D` and `c` the obstacle's closest boundary point.
    pub fn gradient(&self, p: Point) -> Vector {
        let o = &self.options;
        let to_goal = p - self.goal;
        let d = to_goal.norm();
        let mut g = if d <= o.d_star {
            to_goal * o.zeta
        } else {
            to_goal * (o.d_star * o.zeta / d)
        };
        for poly in self.repellers() {
            let (c, dist) = closest_point_on_ring(poly, p).unwrap_or((p, f64::INFINITY));
            if dist <= o.q_star && dist > 0.0 {
                g += (p - c) * (o.eta * (1.0 / o.q_star - 1.0 / dist) / (dist * dist * dist));
            }
        }
        g
    }

    /// Descends `U` from `start` with the fixed step: `q ← q − α ∇U(q)`.
    pub fn plan(&self, start: Point) -> PlanResult {
        let clock = Instant::now();
        let o = &self.options;
        let mut points = vec![start];
        let status = if !polygon_contains(&self.workspace, start) {
            TraceStatus::OutsideWorkspace
        } else if !self.is_free(start) {
            TraceStatus::StartInObstacle
        } else {
            let mut q = start;
            let mut status = TraceStatus::MaxSteps;
            for k in 1..=o.max_steps {
                if (q - self.goal).norm() < o.goal_tolerance {
                    status = TraceStatus::ReachedGoal(0);
                    break;
                }
                let g = self.gradient(q);
                if g.norm() < o.stall_gradient {
                    status = TraceStatus::Stalled { at: q };
                    break;
                }
                let next = q - g * o.step;
                if !self.is_free(next) {
                    let dir = next - q;
                    status = TraceStatus::Collision {
                        at: Some([q.x, q.y, dir.y.atan2(dir.x)]),
                    };
                    break;
                }
                q = next;
                points.push(q);
                if k % o.stall_window == 0 {
                    let back = points[points.len() - 1 - o.stall_window];
                    if (q - back).norm() < o.goal_tolerance {
                        status = TraceStatus::Stalled { at: q };
                        break;
                    }
                }
            }
            status
        };
        PlanResult::new(points, status, clock.elapsed())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{GridHarmonic, Raster, SorOptions};
    use harmonic_trajectory::{SmoothOptions, trace_smooth};

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
        vec![
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ]
    }

    /// A U-shaped cup at x ∈ [4, 6], y ∈ [3, 7] opening toward the start (left), its back
    /// wall between the start and the goal.
    fn cup() -> Vec<Point> {
        vec![
            Point::new(4.0, 3.0),
            Point::new(6.0, 3.0),
            Point::new(6.0, 7.0),
            Point::new(4.0, 7.0),
            Point::new(4.0, 6.0),
            Point::new(5.5, 6.0),
            Point::new(5.5, 4.0),
            Point::new(4.0, 4.0),
        ]
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let field = PotentialField::new(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[cup()],
            Point::new(9.0, 5.0),
            PotentialFieldOptions::default(),
        )
        .unwrap();
        for p in [
            Point::new(3.5, 5.2),
            Point::new(8.0, 5.5),
            Point::new(2.0, 2.0),
        ] {
            let h = 1e-6;
            let fd = Vector::new(
                (field.potential(p + Vector::x() * h) - field.potential(p - Vector::x() * h))
                    / (2.0 * h),
                (field.potential(p + Vector::y() * h) - field.potential(p - Vector::y() * h))
                    / (2.0 * h),
            );
            let g = field.gradient(p);
            assert!(
                (g - fd).norm() < 1e-6 * (1.0 + g.norm()),
                "at {p}: {g} vs {fd}"
            );
        }
    }

    #[test]
    fn trapped_in_a_u_shaped_cup_where_the_harmonic_field_is_not() {
        let ws = rect(0.0, 0.0, 10.0, 10.0);
        // Off the symmetry axis y = 5, which leads the harmonic descent onto a saddle.
        let (start, goal) = (Point::new(1.0, 5.3), Point::new(9.0, 5.0));
        let field =
            PotentialField::new(&ws, &[cup()], goal, PotentialFieldOptions::default()).unwrap();
        let plan = field.plan(start);
        let TraceStatus::Stalled { at } = plan.status else {
            panic!("expected a stall, got {:?}", plan.status);
        };
        // Stuck inside the cup's mouth, short of its back wall.
        assert!(
            at.x > 3.0 && at.x < 5.5 && (at.y - 5.0).abs() < 0.5,
            "stalled at {at}"
        );

        // The grid harmonic field of the same scene leads around the cup.
        let goal_box = rect(8.8, 4.8, 9.2, 5.2);
        let raster = Raster::from_polygons(&ws, &[cup()], &[goal_box], 82).unwrap();
        let harmonic = GridHarmonic::solve(raster, &SorOptions::default()).unwrap();
        let path = trace_smooth(&harmonic, start, &SmoothOptions::for_scale(10.0)).unwrap();
        assert_eq!(path.status, TraceStatus::ReachedGoal(0));
    }

    #[test]
    fn rejects_bad_options() {
        let ws = rect(0.0, 0.0, 10.0, 10.0);
        let bad = PotentialFieldOptions {
            q_star: -1.0,
            ..PotentialFieldOptions::default()
        };
        assert!(matches!(
            PotentialField::new(&ws, &[], Point::new(5.0, 5.0), bad),
            Err(BaselineError::InvalidParameter { name: "q_star", .. })
        ));
        let field = PotentialField::new(
            &ws,
            &[cup()],
            Point::new(9.0, 5.0),
            PotentialFieldOptions::default(),
        )
        .unwrap();
        assert_eq!(
            field.plan(Point::new(5.8, 5.0)).status,
            TraceStatus::StartInObstacle
        );
        assert_eq!(
            field.plan(Point::new(11.0, 5.0)).status,
            TraceStatus::OutsideWorkspace
        );
    }
}
