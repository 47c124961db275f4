//! Rimon & Koditschek's navigation function for sphere worlds (*Exact robot navigation using
//! artificial potential functions*, IEEE T-RA 1992): in a disc world with disc obstacles,
//!
//! `φ(q) = γ(q) / (γ(q)^κ + β(q))^{1/κ}`, `γ = |q − q_goal|²`,
//! `β = β₀ Π βᵢ`, `β₀ = ρ₀² − |q − q₀|²`, `βᵢ = |q − qᵢ|² − ρᵢ²`.
//!
//! `φ` is 0 at the goal, 1 on every boundary, and for a large enough κ its only minimum is the
//! goal (the other critical points are saddles); for small κ spurious minima remain.

use std::time::Instant;

use harmonic_mesh::{Point, Vector};
use harmonic_trajectory::{Field, Locate, TraceStatus};

use crate::geometry::{check_point, check_positive};
use crate::{BaselineError, PlanResult};

/// A disc: the world (free space inside) or an obstacle (free space outside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disc {
    /// Centre.
    pub centre: Point,
    /// Radius (positive).
    pub radius: f64,
}

/// Descent settings of [`NavigationFunction::plan`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavigationOptions {
    /// Length of each step along `−∇φ / |∇φ|` (shortened near the goal).
    pub step: f64,
    /// The goal counts as reached within this distance.
    pub goal_tolerance: f64,
    /// Give up after this many steps.
    pub max_steps: usize,
    /// Stalled when the two terms of `∇φ` cancel to this relative precision (a critical
    /// point), or when the path moved less than `goal_tolerance` over `stall_window` steps.
    pub stall_tolerance: f64,
    /// Steps over which progress is checked.
    pub stall_window: usize,
}

impl NavigationOptions {
    /// Checks that the step, tolerances and window are positive.
    pub fn validate(&self) -> Result<(), BaselineError> {
        check_positive("step", self.step)?;
        check_positive("goal_tolerance", self.goal_tolerance)?;
        check_positive("stall_tolerance", self.stall_tolerance)?;
        if self.stall_window == 0 {
            return Err(BaselineError::InvalidParameter {
                name: "stall_window",
                value: 0.0,
                reason: "must be at least 1 step",
            });
        }
        Ok(())
    }
}

impl Default for NavigationOptions {
    fn default() -> Self {
        NavigationOptions {
            step: 0.02,
            goal_tolerance: 0.05,
            max_steps: 100_000,
            stall_tolerance: 1e-12,
            stall_window: 200,
        }
    }
}

/// A sphere-world navigation function with tuning parameter κ.
#[derive(Clone, Debug)]
pub struct NavigationFunction {
    world: Disc,
    obstacles: Vec<Disc>,
    goal: Point,
    kappa: f64,
}

impl NavigationFunction {
    /// Builds the navigation function.
    ///
    /// Errors if a radius or κ is not positive and finite (κ must be at least 1), an obstacle
    /// is not strictly inside the world or overlaps another, or the goal is not in free space.
    ///
    /// ```
    /// use harmonic_baselines::{Disc, NavigationFunction, NavigationOptions};
    /// use harmonic_mesh::Point;
    /// let world = Disc { centre: Point::origin(), radius: 10.0 };
    /// let rock = Disc { centre: Point::new(0.0, 0.0), radius: 2.0 };
    /// let nav = NavigationFunction::new(world, vec![rock], Point::new(6.0, 0.0), 6.0).unwrap();
    /// assert!(nav.value(Point::new(6.0, 0.0)) < 1e-12);
    /// let plan = nav.plan(Point::new(-6.0, 0.5), &NavigationOptions::default()).unwrap();
    /// assert!(plan.status.reached_goal());
    /// ```
    pub fn new(
        world: Disc,
        obstacles: Vec<Disc>,
        goal: Point,
        kappa: f64,
    ) -> Result<Self, BaselineError> {
        check_point(|| "goal".to_string(), goal)?;
        if !(kappa >= 1.0 && kappa.is_finite()) {
            return Err(BaselineError::InvalidParameter {
                name: "kappa",
                value: kappa,
                reason: "must be finite and at least 1",
            });
        }
        check_point(|| "world centre".to_string(), world.centre)?;
        check_positive("world radius", world.radius)?;
        for (i, o) in obstacles.iter().enumerate() {
            check_point(|| format!("obstacle {i} centre"), o.centre)?;
            check_positive("obstacle radius", o.radius)?;
            if (o.centre - world.centre).norm() + o.radius >= world.radius {
                return Err(BaselineError::InvalidSphereWorld(format!(
                    "obstacle {i} is not strictly inside the world disc"
                )));
            }
            for (j, p) in obstacles[..i].iter().enumerate() {
                if (o.centre - p.centre).norm() <= o.radius + p.radius {
                    return Err(BaselineError::InvalidSphereWorld(format!(
                        "obstacles {j} and {i} overlap"
                    )));
                }
            }
        }
        let nav = NavigationFunction {
            world,
            obstacles,
            goal,
            kappa,
        };
        if !nav.is_free(goal) {
            return Err(BaselineError::InvalidSphereWorld(
                "the goal is not in free space".to_string(),
            ));
        }
        Ok(nav)
    }

    /// Whether `p` lies strictly inside the world and outside every obstacle.
    pub fn is_free(&self, p: Point) -> bool {
        (p - self.world.centre).norm() < self.world.radius
            && self
                .obstacles
                .iter()
                .all(|o| (p - o.centre).norm() > o.radius)
    }

    /// `β` and `∇β` at `p`.
    fn beta(&self, p: Point) -> (f64, Vector) {
        let r0 = p - self.world.centre;
        let mut beta = self.world.radius * self.world.radius - r0.norm_squared();
        let mut grad = -2.0 * r0;
        for o in &self.obstacles {
            let r = p - o.centre;
            let bi = r.norm_squared() - o.radius * o.radius;
            // ∇(β bᵢ) = bᵢ ∇β + β ∇bᵢ
            grad = grad * bi + 2.0 * r * beta;
            beta *= bi;
        }
        (beta, grad)
    }

    /// `φ(p)` in [0, 1] (computed through logarithms, so large κ neither overflows nor
    /// underflows); 1 outside free space.
    pub fn value(&self, p: Point) -> f64 {
        match self.log_terms(p) {
            None => 1.0,
            // φ = (1 + β/γ^κ)^{−1/κ} = exp(−softplus(u)/κ)
            Some((u, _)) => (-softplus(u) / self.kappa).exp(),
        }
    }

    /// `u = ln β − κ ln γ` with `∇γ/γ − ∇β/(κβ)` (the direction of ∇φ), or `None` outside
    /// free space.
    fn log_terms(&self, p: Point) -> Option<(f64, Vector)> {
        let r = p - self.goal;
        let gamma = r.norm_squared();
        let (beta, grad_beta) = self.beta(p);
        if !self.is_free(p) || beta <= 0.0 {
            return None;
        }
        let u = beta.ln() - self.kappa * gamma.ln();
        Some((u, 2.0 * r / gamma - grad_beta / (self.kappa * beta)))
    }

    /// `ln(1 − φ)`: how far below its boundary value 1 the function is, in logarithms.
    /// For large κ, `1 − φ ≈ β/(κγ^κ)` is far below the float spacing near 1 (φ rounds to 1
    /// over most of the world), but its logarithm is an ordinary number. Takes
    /// `u = ln β − κ ln γ`.
    fn log_gap(&self, u: f64) -> f64 {
        if u < -30.0 {
            // softplus(u) ≈ e^u, 1 − φ ≈ e^u / κ
            u - self.kappa.ln()
        } else {
            (-(-softplus(u) / self.kappa).exp_m1()).ln()
        }
    }

    /// The navigation function as a [`Field`] for the shared tracer and car stepper: value
    /// `−ln(1 − φ)`, an increasing function of φ (same descent directions, same critical
    /// points) that keeps its precision where φ rounds to 1 for large κ; goal the disc of
    /// radius `goal_radius` around the goal.
    pub fn field(&self, goal_radius: f64) -> Result<NavigationField<'_>, BaselineError> {
        check_positive("goal_radius", goal_radius)?;
        Ok(NavigationField {
            nav: self,
            goal_radius,
        })
    }

    /// A positive multiple of `∇φ(p)`: `β∇γ − (γ/κ)∇β` (the factor
    /// `(γ^κ + β)^{−1−1/κ}` is dropped: it only rescales and under- or overflows for large
    /// κ), together with the magnitude of the larger of the two terms.
    fn gradient_direction(&self, p: Point) -> (Vector, f64) {
        let r = p - self.goal;
        let gamma = r.norm_squared();
        let (beta, grad_beta) = self.beta(p);
        let a = 2.0 * r * beta;
        let b = grad_beta * (gamma / self.kappa);
        (a - b, a.norm().max(b.norm()))
    }

    /// `∇φ(p)` (exact, may under- or overflow for large κ far from the goal).
    pub fn gradient(&self, p: Point) -> Vector {
        let gamma = (p - self.goal).norm_squared();
        let (beta, _) = self.beta(p);
        let (d, _) = self.gradient_direction(p);
        let s = gamma.powf(self.kappa) + beta;
        d * s.powf(-1.0 - 1.0 / self.kappa)
    }

    /// Descends `φ` from `start` in fixed-length steps along `−∇φ/|∇φ|`, halving a step that
    /// would leave free space (up to 20 times before reporting a collision).
    ///
    /// Errors if the options are invalid (see [`NavigationOptions::validate`]).
    pub fn plan(
        &self,
        start: Point,
        options: &NavigationOptions,
    ) -> Result<PlanResult, BaselineError> {
        options.validate()?;
        let clock = Instant::now();
        let o = options;
        let mut points = vec![start];
        let from_centre = (start - self.world.centre).norm();
        let status = if from_centre >= self.world.radius || from_centre.is_nan() {
            TraceStatus::OutsideWorkspace
        } else if !self.is_free(start) {
            TraceStatus::StartInObstacle
        } else {
            let mut q = start;
            let mut status = TraceStatus::MaxSteps;
            'steps: for k in 1..=o.max_steps {
                let dist = (q - self.goal).norm();
                if dist < o.goal_tolerance {
                    status = TraceStatus::ReachedGoal(0);
                    break;
                }
                let (d, scale) = self.gradient_direction(q);
                if d.norm() <= o.stall_tolerance * scale || !d.norm().is_finite() {
                    status = TraceStatus::Stalled { at: q };
                    break;
                }
                let dir = -d.normalize();
                let mut h = o.step.min(dist);
                let mut next = q + dir * h;
                let mut halvings = 0;
                while !self.is_free(next) {
                    halvings += 1;
                    if halvings > 20 {
                        status = TraceStatus::Collision {
                            at: Some([q.x, q.y, dir.y.atan2(dir.x)]),
                        };
                        break 'steps;
                    }
                    h *= 0.5;
                    next = q + dir * h;
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
        Ok(PlanResult::new(points, status, clock.elapsed()))
    }
}

/// `ln(1 + eˣ)` without overflow or loss for large |x|.
fn softplus(x: f64) -> f64 {
    x.max(0.0) + (-x.abs()).exp().ln_1p()
}

/// A [`NavigationFunction`] as a [`Field`] (see [`NavigationFunction::field`]); its only cell
/// is `()`.
#[derive(Clone, Copy, Debug)]
pub struct NavigationField<'a> {
    nav: &'a NavigationFunction,
    goal_radius: f64,
}

impl Field for NavigationField<'_> {
    type Point = Point;
    type Vector = Vector;
    type Cell = ();

    fn locate(&self, p: Point, _hint: Option<()>) -> Locate<()> {
        let w = self.nav.world;
        let from_centre = (p - w.centre).norm();
        if from_centre >= w.radius || from_centre.is_nan() {
            Locate::OutsideWorkspace
        } else if !self.nav.is_free(p) {
            Locate::InObstacle
        } else if (p - self.nav.goal).norm() < self.goal_radius {
            Locate::Goal(0)
        } else {
            Locate::Inside(())
        }
    }

    fn value(&self, _cell: (), p: Point) -> f64 {
        match self.nav.log_terms(p) {
            Some((u, _)) => -self.nav.log_gap(u),
            None => f64::INFINITY,
        }
    }

    /// `∇φ / (1 − φ) = φ (1 − s)/(1 − φ) (∇γ/γ − ∇β/(κβ))` with `1 − s = logistic(u)`, the
    /// ratio taken in logarithms.
    fn gradient(&self, _cell: (), p: Point) -> Vector {
        match self.nav.log_terms(p) {
            Some((u, dir)) => {
                let phi = (-softplus(u) / self.nav.kappa).exp();
                let log_one_minus_s = -softplus(-u);
                dir * (phi * (log_one_minus_s - self.nav.log_gap(u)).exp())
            }
            None => Vector::zeros(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> (Disc, Vec<Disc>) {
        (
            Disc {
                centre: Point::origin(),
                radius: 10.0,
            },
            vec![
                Disc {
                    centre: Point::new(0.0, 0.0),
                    radius: 2.5,
                },
                Disc {
                    centre: Point::new(3.0, 5.0),
                    radius: 1.5,
                },
                Disc {
                    centre: Point::new(-3.0, -5.0),
                    radius: 1.5,
                },
            ],
        )
    }

    #[test]
    fn gradient_matches_finite_differences_of_the_value() {
        let (w, obs) = world();
        let nav = NavigationFunction::new(w, obs, Point::new(6.0, 0.0), 3.0).unwrap();
        for p in [
            Point::new(-5.0, 1.0),
            Point::new(4.0, 3.0),
            Point::new(1.0, -4.0),
        ] {
            let h = 1e-6;
            let fd = Vector::new(
                (nav.value(p + Vector::x() * h) - nav.value(p - Vector::x() * h)) / (2.0 * h),
                (nav.value(p + Vector::y() * h) - nav.value(p - Vector::y() * h)) / (2.0 * h),
            );
            let g = nav.gradient(p);
            assert!(
                (g - fd).norm() < 1e-6 * (1.0 + g.norm()),
                "at {p}: {g} vs {fd}"
            );
        }
        assert_eq!(nav.value(Point::new(0.0, 2.5)), 1.0);
        assert!(nav.value(Point::new(10.0 - 1e-7, 0.0)) > 0.999);
    }

    #[test]
    fn large_kappa_reaches_the_goal_small_kappa_gets_stuck() {
        let (w, obs) = world();
        let goal = Point::new(6.0, 0.0);
        let opts = NavigationOptions::default();
        let starts = [
            Point::new(-6.0, 0.3),
            Point::new(-7.0, 4.0),
            Point::new(0.0, -8.0),
        ];
        let nav = NavigationFunction::new(w, obs.clone(), goal, 10.0).unwrap();
        for s in starts {
            let plan = nav.plan(s, &opts).unwrap();
            assert!(plan.status.reached_goal(), "from {s}: {:?}", plan.status);
            assert!(plan.points.iter().all(|&p| nav.is_free(p)));
        }
        // With κ = 1 the function keeps a spurious minimum behind the central obstacle.
        let weak = NavigationFunction::new(w, obs, goal, 1.0).unwrap();
        let plan = weak.plan(starts[0], &opts).unwrap();
        assert!(
            matches!(plan.status, TraceStatus::Stalled { .. }),
            "{:?}",
            plan.status
        );
    }

    #[test]
    fn the_shared_tracer_follows_the_navigation_function_for_large_kappa() {
        use harmonic_trajectory::{SmoothOptions, trace_smooth};
        let (w, obs) = world();
        // κ = 40: 1 − φ ~ 1e-77 far from the goal, so φ is 1 in floats there; the field's
        // value −ln(1 − φ) keeps a usable gradient.
        let nav = NavigationFunction::new(w, obs, Point::new(6.0, 0.0), 40.0).unwrap();
        let field = nav.field(0.05).unwrap();
        for p in [Point::new(-5.0, 1.0), Point::new(4.0, 3.0)] {
            let h = 1e-6;
            let fd = Vector::new(
                field.value((), p + Vector::x() * h) - field.value((), p - Vector::x() * h),
                field.value((), p + Vector::y() * h) - field.value((), p - Vector::y() * h),
            ) / (2.0 * h);
            let g = field.gradient((), p);
            assert_eq!(nav.value(p), 1.0);
            assert!(g.norm() > 1e-3, "{g}");
            assert!(
                (g - fd).norm() < 1e-5 * (1.0 + g.norm()),
                "at {p}: {g} vs {fd}"
            );
        }
        for start in [Point::new(-6.0, 0.3), Point::new(0.0, -8.0)] {
            let path = trace_smooth(&field, start, &SmoothOptions::for_scale(20.0)).unwrap();
            assert_eq!(path.status, TraceStatus::ReachedGoal(0), "from {start}");
            assert!(path.points.iter().all(|&p| nav.is_free(p)));
        }
    }

    #[test]
    fn rejects_invalid_worlds() {
        let (w, obs) = world();
        let goal = Point::new(6.0, 0.0);
        assert!(NavigationFunction::new(w, obs.clone(), goal, 0.5).is_err());
        assert!(NavigationFunction::new(w, obs.clone(), Point::new(0.0, 1.0), 2.0).is_err());
        let mut overlapping = obs.clone();
        overlapping.push(Disc {
            centre: Point::new(1.0, 0.0),
            radius: 2.0,
        });
        assert_eq!(
            NavigationFunction::new(w, overlapping, goal, 2.0).unwrap_err(),
            BaselineError::InvalidSphereWorld("obstacles 0 and 3 overlap".to_string())
        );
        let outside = vec![Disc {
            centre: Point::new(9.0, 0.0),
            radius: 2.0,
        }];
        assert!(NavigationFunction::new(w, outside, goal, 2.0).is_err());
        let nav = NavigationFunction::new(w, obs, goal, 2.0).unwrap();
        let no_window = NavigationOptions {
            stall_window: 0,
            ..NavigationOptions::default()
        };
        assert!(nav.plan(Point::new(-6.0, 0.0), &no_window).is_err());
        let plan = nav.plan(Point::new(f64::NAN, 0.0), &NavigationOptions::default());
        assert_eq!(plan.unwrap().status, TraceStatus::OutsideWorkspace);
    }
}
