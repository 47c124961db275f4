//! The bar-shaped mobile robot of Kim & Khosla's §5.1 (eqs. 43–49).
//!
//! Configuration `(x, y, η)`: `(x, y)` the leading point (the primary control point), η the
//! angle between the bar and the x axis; the bar trails behind the leading point, from
//! `(x, y)` to `(x, y) − L (cos η, sin η)`.
//!
//! Per period, **potential operation** (no part of the bar within δ of an obstacle):
//!
//! - (43) `Δη = atan2(v, u) − η` with `(u, v)` the flow at the leading point;
//! - (44–45) `Δx = d_max cos(η + Δη)`, `Δy = d_max sin(η + Δη)`: the flow's direction at the
//!   fixed step `d_max` (the flow's speed grows near obstacles, its direction does not);
//! - (46–49) if `|Δη| > Δη_max`: `H = Δη_max / |Δη|` scales `Δx`, `Δy` and `Δη`.
//!
//! **Obstacle operation** (secondary control points within δ): the leading point moves as in
//! (44–45), and η is turned by φ_o (eq. 42) instead of the flow: "assuming the primary
//! control point is fixed", each secondary control point `s` pushed by `∇φ_o(s)` turns the bar
//! about the leading point by `(r × ∇φ_o(s)) / |r|²`, `r = s − (x, y)`; the sum is saturated by
//! (46–49) as before.

use harmonic_mesh::{Point, Vector};
use serde::Serialize;

use crate::clearance::{Clearance, bar_motion_clearance};
use crate::error::positive;
use crate::flow::{Flow, unit};
use crate::obstacles::{Contact, ObstaclePotential, Obstacles};
use crate::stagnation::{StagnationGuard, Turn};
use crate::{ControlError, RunStatus};

/// The bar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarRobot {
    /// Its length L (m).
    pub length: f64,
}

impl BarRobot {
    /// The bar's two end points at `pose`: the leading point, then the tail.
    pub fn ends(&self, pose: [f64; 3]) -> (Point, Point) {
        let p = Point::new(pose[0], pose[1]);
        (
            p,
            p - Vector::new(pose[2].cos(), pose[2].sin()) * self.length,
        )
    }
}

/// The controller's inputs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarParams {
    /// `d_max`, the largest displacement of the leading point per period (m).
    pub d_max: f64,
    /// `Δη_max`, the largest turn per period (rad).
    pub d_eta_max: f64,
    /// δ, the minimum allowable distance (m).
    pub delta: f64,
    /// λ_c, the strength of each obstacle point's source in φ_o (eq. 42). The paper gives
    /// none; the default `2π δ d_max / 1 s` pushes a secondary control point at δ by `d_max`
    /// per period.
    pub obstacle_strength: f64,
    /// The run has reached the goal when the leading point is this close to it (m).
    pub goal_tolerance: f64,
    /// The step budget.
    pub max_steps: usize,
    /// The clearance is checked along each period's motion at samples no body point moves
    /// more than this between (m).
    pub check_step: f64,
}

impl Default for BarParams {
    fn default() -> Self {
        let (d_max, delta) = (0.05, 0.2);
        BarParams {
            d_max,
            d_eta_max: 0.1,
            delta,
            obstacle_strength: 2.0 * std::f64::consts::PI * delta * d_max,
            goal_tolerance: 0.1,
            max_steps: 5000,
            check_step: 0.01,
        }
    }
}

impl BarParams {
    fn validate(&self) -> Result<(), ControlError> {
        positive("d_max", self.d_max)?;
        positive("d_eta_max", self.d_eta_max)?;
        positive("delta", self.delta)?;
        positive("obstacle_strength", self.obstacle_strength)?;
        positive("goal_tolerance", self.goal_tolerance)?;
        positive("check_step", self.check_step)
    }
}

/// Which operation a period ran.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Operation {
    /// No secondary control point: η follows the flow (eq. 43).
    Potential,
    /// Secondary control points: η turned by φ_o.
    Obstacle,
}

/// One period's displacement `(Δx, Δy, Δη)` and what produced it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarStep {
    /// `(Δx, Δy, Δη)` after (44–49).
    pub delta: [f64; 3],
    /// The operation.
    pub operation: Operation,
    /// `H` of eq. 46 (1 when no saturation).
    pub saturation: f64,
}

/// Wraps an angle into (−π, π].
pub fn wrap(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let r = a.rem_euclid(t);
    if r > std::f64::consts::PI { r - t } else { r }
}

/// One period of eqs. 43–49 for the bar at `pose` whose leading point moves along the
/// direction `heading` (the flow's, or the stagnation guard's), with the secondary control
/// points `contacts`.
pub fn bar_step(
    pose: [f64; 3],
    heading: Vector,
    contacts: &[Contact],
    params: &BarParams,
) -> BarStep {
    let eta = pose[2];
    let psi = heading.y.atan2(heading.x);
    let (operation, mut d_eta) = if contacts.is_empty() {
        (Operation::Potential, wrap(psi - eta))
    } else {
        let phi_o = ObstaclePotential::from_contacts(contacts, params.obstacle_strength);
        let p = Point::new(pose[0], pose[1]);
        let turn: f64 = contacts
            .iter()
            .map(|c| {
                let r = c.robot_point - p;
                let r2 = r.norm_squared();
                if r2 > 0.0 {
                    r.perp(&phi_o.gradient(c.robot_point)) / r2
                } else {
                    0.0
                }
            })
            .sum();
        (Operation::Obstacle, turn)
    };
    // (44–45): the step along the leading point's direction. In the potential operation
    // η + Δη is the flow's direction ψ itself.
    let mut dx = params.d_max * psi.cos();
    let mut dy = params.d_max * psi.sin();
    let mut h = 1.0;
    if d_eta.abs() > params.d_eta_max {
        // (46–49)
        h = params.d_eta_max / d_eta.abs();
        dx *= h;
        dy *= h;
        d_eta *= h;
    }
    BarStep {
        delta: [dx, dy, d_eta],
        operation,
        saturation: h,
    }
}

/// A run of the bar controller.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BarRun {
    /// How it ended.
    pub status: RunStatus,
    /// Periods run.
    pub steps: usize,
    /// The smallest distance of the whole bar to every obstacle's exact polygon along the
    /// whole motion (sampled, see [`BarParams::check_step`]).
    pub min_distance: f64,
    /// δ.
    pub delta: f64,
    /// Periods in the obstacle operation.
    pub obstacle_periods: usize,
    /// The turns at stagnation points.
    pub turns: Vec<Turn>,
    /// Every pose, the start first.
    pub poses: Vec<[f64; 3]>,
    /// Where the smallest distance occurred: the pose's period.
    pub min_distance_step: usize,
}

impl BarRun {
    /// Whether the leading point reached the goal.
    pub fn reached(&self) -> bool {
        self.status == RunStatus::Reached
    }
}

/// Runs the bar controller on `flow` from `start` to `goal`, steering around the
/// stagnation points of `guard` if given.
pub fn run_bar(
    flow: &dyn Flow,
    obstacles: &Obstacles,
    guard: Option<&StagnationGuard>,
    robot: &BarRobot,
    start: [f64; 3],
    goal: Point,
    params: &BarParams,
) -> Result<BarRun, ControlError> {
    params.validate()?;
    positive("bar length", robot.length)?;
    if start.iter().any(|c| !c.is_finite()) {
        return Err(ControlError::InvalidParameter {
            name: "start",
            value: start
                .iter()
                .copied()
                .find(|c| !c.is_finite())
                .unwrap_or(0.0),
            reason: "a start coordinate is not finite",
        });
    }
    let (a, b) = robot.ends(start);
    if let Some((d, obstacle)) = obstacles.segment_distance(a, b)
        && d <= 0.0
    {
        return Err(ControlError::StartInCollision {
            obstacle,
            distance: d,
        });
    }
    let mut pose = start;
    let mut poses = vec![pose];
    let mut clearance = Clearance::start(obstacles.segment_distance(a, b).map(|x| x.0));
    let mut turns = Vec::new();
    let mut obstacle_periods = 0;
    let mut status = RunStatus::MaxSteps;
    let mut steps = 0;
    while steps < params.max_steps {
        let p = Point::new(pose[0], pose[1]);
        if (p - goal).norm() <= params.goal_tolerance {
            status = RunStatus::Reached;
            break;
        }
        let Some(v) = flow.velocity(p) else {
            status = RunStatus::OutsideFlow { at: [p.x, p.y] };
            break;
        };
        let steered = guard.and_then(|g| g.steer(p, v).map(|(k, d)| (g, k, d)));
        let heading = match steered {
            Some((g, k, d)) => {
                if turns.last().is_none_or(|t: &Turn| {
                    t.stagnation_point != [g.saddles[k].at.x, g.saddles[k].at.y]
                }) {
                    turns.push(Turn {
                        step: steps,
                        stagnation_point: [g.saddles[k].at.x, g.saddles[k].at.y],
                        at: [p.x, p.y],
                        side: g.side,
                    });
                }
                d
            }
            None => match unit(v) {
                Some(d) => d,
                None => {
                    status = RunStatus::Stalled { at: [p.x, p.y] };
                    break;
                }
            },
        };
        let (a, b) = robot.ends(pose);
        let contacts = obstacles.contacts(a, b, params.delta, 0);
        let step = bar_step(pose, heading, &contacts, params);
        if step.operation == Operation::Obstacle {
            obstacle_periods += 1;
        }
        let next = [
            pose[0] + step.delta[0],
            pose[1] + step.delta[1],
            pose[2] + step.delta[2],
        ];
        steps += 1;
        let along = bar_motion_clearance(robot, obstacles, pose, next, params.check_step);
        clearance.update(along, steps);
        pose = next;
        poses.push(pose);
        if let Some((d, obstacle)) = along
            && d <= 0.0
        {
            status = RunStatus::Collided {
                step: steps,
                obstacle,
            };
            break;
        }
    }
    if status == RunStatus::MaxSteps
        && (Point::new(pose[0], pose[1]) - goal).norm() <= params.goal_tolerance
    {
        status = RunStatus::Reached;
    }
    Ok(BarRun {
        status,
        steps,
        min_distance: clearance.distance,
        delta: params.delta,
        obstacle_periods,
        turns,
        poses,
        min_distance_step: clearance.step,
    })
}
