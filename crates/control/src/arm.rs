//! The redundant planar manipulator of Kim & Khosla's §5.2 (eqs. 52–58).
//!
//! Joint angles `q` (each relative to the previous link; the first to the x axis), links
//! `l₁ … l_n` from the base. Per period:
//!
//! - (52) the end effector's displacement `ΔX_e` is the flow at the end effector,
//!   normalised to the step `d_e`;
//! - (53) net motion `Δθ_p = J_e⁺ ΔX_e` (Moore–Penrose pseudoinverse of the 2 × n end-effector
//!   Jacobian);
//! - (54) null motion `Δθ_h = Σᵢ [J_ci (I − J_e⁺ J_e)]⁺ (ΔX_ci − J_ci J_e⁺ ΔX_e)`, in the null
//!   space of `J_e`: in the **obstacle operation** the secondary control points (closest link
//!   points within δ) pushed by φ_o (eq. 42); in the **potential operation** the end points of
//!   the inner links pulled by the same flow ("the motion of the end point of each link is
//!   determined by the potential on that point"; the requests solved together in the
//!   least-squares sense, [`follow_flow_null_motion`]), or nothing ([`NullMotion`]);
//! - (55) `Δθ = Δθ_p + Δθ_h`, and (56–58) `H = Δθ_max / ‖Δθ‖` scales both: a fixed energy per
//!   period.
//!
//! Jacobians and pseudoinverses are nalgebra's (SVD).

use harmonic_mesh::{Point, Vector};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::bar::Operation;
use crate::clearance::{Clearance, arm_clearance, arm_motion_clearance};
use crate::error::positive;
use crate::flow::{Flow, unit};
use crate::obstacles::{Contact, ObstaclePotential, Obstacles};
use crate::{ControlError, RunStatus};

/// A planar serial arm of revolute joints.
#[derive(Clone, Debug, PartialEq)]
pub struct Arm {
    base: Point,
    links: Vec<f64>,
}

/// Which elbow an inverse-kinematics solution takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Elbow {
    /// The second joint's angle positive (counter-clockwise bend).
    Up,
    /// Negative.
    Down,
}

impl Arm {
    /// An arm based at `base` with link lengths `links` (at least two, each positive and
    /// finite: a single link has no redundancy to speak of).
    pub fn new(base: Point, links: Vec<f64>) -> Result<Self, ControlError> {
        if links.len() < 2 {
            return Err(ControlError::InvalidArm {
                reason: format!("needs at least two links, got {}", links.len()),
            });
        }
        if let Some((k, l)) = links
            .iter()
            .enumerate()
            .find(|(_, l)| !(l.is_finite() && **l > 0.0))
        {
            return Err(ControlError::InvalidArm {
                reason: format!("link {k} has length {l}: must be positive and finite"),
            });
        }
        if !(base.x.is_finite() && base.y.is_finite()) {
            return Err(ControlError::InvalidArm {
                reason: "the base is not finite".into(),
            });
        }
        Ok(Arm { base, links })
    }

    /// The base.
    pub fn base(&self) -> Point {
        self.base
    }

    /// The link lengths.
    pub fn links(&self) -> &[f64] {
        &self.links
    }

    /// Degrees of freedom.
    pub fn dof(&self) -> usize {
        self.links.len()
    }

    /// The base, every joint and the end effector at `q` (`n + 1` points).
    pub fn points(&self, q: &[f64]) -> Vec<Point> {
        let mut pts = Vec::with_capacity(self.links.len() + 1);
        let mut p = self.base;
        let mut angle = 0.0;
        pts.push(p);
        for (l, a) in self.links.iter().zip(q) {
            angle += a;
            p += Vector::new(angle.cos(), angle.sin()) * *l;
            pts.push(p);
        }
        pts
    }

    /// The end effector at `q`.
    pub fn end_effector(&self, q: &[f64]) -> Point {
        self.points(q)[self.links.len()]
    }

    /// The summed length of links `j..`: how far a point beyond joint `j` can be from it.
    pub fn reach_from(&self, j: usize) -> f64 {
        self.links[j.min(self.links.len())..].iter().sum()
    }

    /// The 2 × n Jacobian of the point `c` fixed to link `link` (0-based) at `q`: column
    /// `j ≤ link` is `c − P_j` turned by +90°, columns past the link are zero.
    pub fn point_jacobian(&self, q: &[f64], link: usize, c: Point) -> DMatrix<f64> {
        let pts = self.points(q);
        let n = self.links.len();
        DMatrix::from_fn(2, n, |i, j| {
            if j > link {
                return 0.0;
            }
            let r = c - pts[j];
            if i == 0 { -r.y } else { r.x }
        })
    }

    /// The end-effector Jacobian `J_e` at `q`.
    pub fn jacobian(&self, q: &[f64]) -> DMatrix<f64> {
        let n = self.links.len();
        self.point_jacobian(q, n - 1, self.end_effector(q))
    }

    /// Joint angles of a three-link arm whose end effector is at `tip` with its third link at
    /// the absolute angle `last` (as the paper's start: "the initial angle between the third
    /// link and the x axis is 10 degrees"), the elbow as asked; `None` if out of reach.
    pub fn three_link_ik(&self, tip: Point, last: f64, elbow: Elbow) -> Option<[f64; 3]> {
        let [l1, l2, l3] = <[f64; 3]>::try_from(self.links.as_slice()).ok()?;
        let wrist = tip - Vector::new(last.cos(), last.sin()) * l3;
        let d = wrist - self.base;
        let r2 = d.norm_squared();
        let c2 = (r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
        if !(-1.0..=1.0).contains(&c2) {
            return None;
        }
        let s2 = match elbow {
            Elbow::Up => (1.0 - c2 * c2).sqrt(),
            Elbow::Down => -(1.0 - c2 * c2).sqrt(),
        };
        let q2 = s2.atan2(c2);
        let q1 = d.y.atan2(d.x) - (l2 * s2).atan2(l1 + l2 * c2);
        Some([q1, q2, last - q1 - q2])
    }
}

/// The null motion of the potential operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NullMotion {
    /// The end points of the inner links follow the flow (the paper's choice), solved
    /// together ([`follow_flow_null_motion`]).
    FollowFlow,
    /// None: the potential operation runs the net motion alone.
    None,
}

/// The controller's inputs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmParams {
    /// `d_e`, the end effector's displacement per period before (56) (m).
    pub d_e: f64,
    /// `Δθ_max` of eq. 56 (rad): the norm of every period's joint motion.
    pub d_theta_max: f64,
    /// δ, the minimum allowable distance (m).
    pub delta: f64,
    /// λ_c of φ_o (eq. 42); the default `2π δ d_e` pushes a secondary control point at δ by
    /// `d_e` (the paper gives none).
    pub obstacle_strength: f64,
    /// The potential operation's null motion.
    pub null_motion: NullMotion,
    /// Reached when the end effector is this close to the goal (m).
    pub goal_tolerance: f64,
    /// The step budget.
    pub max_steps: usize,
    /// The clearance is checked at samples no arm point moves more than this between (m).
    pub check_step: f64,
}

impl Default for ArmParams {
    fn default() -> Self {
        let (d_e, delta) = (0.1, 0.2);
        ArmParams {
            d_e,
            d_theta_max: 0.01,
            delta,
            obstacle_strength: 2.0 * std::f64::consts::PI * delta * d_e,
            null_motion: NullMotion::FollowFlow,
            goal_tolerance: 0.1,
            max_steps: 20_000,
            check_step: 0.01,
        }
    }
}

impl ArmParams {
    fn validate(&self) -> Result<(), ControlError> {
        positive("d_e", self.d_e)?;
        positive("d_theta_max", self.d_theta_max)?;
        positive("delta", self.delta)?;
        positive("obstacle_strength", self.obstacle_strength)?;
        positive("goal_tolerance", self.goal_tolerance)?;
        positive("check_step", self.check_step)
    }
}

/// One period's joint motion, split as eq. 55.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmStep {
    /// `Δθ_p` after (57).
    pub net: DVector<f64>,
    /// `Δθ_h` after (58).
    pub null: DVector<f64>,
    /// Which operation.
    pub operation: Operation,
    /// `H` of eq. 56.
    pub normalisation: f64,
}

impl ArmStep {
    /// `Δθ = Δθ_p + Δθ_h`.
    pub fn total(&self) -> DVector<f64> {
        &self.net + &self.null
    }
}

fn pinv(m: &DMatrix<f64>) -> DMatrix<f64> {
    let scale = m.amax().max(1.0);
    m.clone()
        .pseudo_inverse(1e-10 * scale)
        .unwrap_or_else(|_| DMatrix::zeros(m.ncols(), m.nrows()))
}

/// Eq. 54's term for one secondary control point `c` on `link`, wanting to move by `dx`:
/// `[J_c N]⁺ (ΔX_c − J_c Δθ_p)` with `N = I − J_e⁺ J_e`.
pub fn null_motion_term(
    arm: &Arm,
    q: &[f64],
    link: usize,
    c: Point,
    dx: Vector,
    null_projector: &DMatrix<f64>,
    net: &DVector<f64>,
) -> DVector<f64> {
    let jc = arm.point_jacobian(q, link, c);
    let want = DVector::from_column_slice(&[dx.x, dx.y]) - &jc * net;
    pinv(&(&jc * null_projector)) * want
}

/// The potential operation's null motion: the end points of the inner links pulled by the
/// flow there, each wanting `d_e` along it. The paper gives no formula for it; one request
/// is eq. 54's term, several are solved together in the least-squares sense,
/// `z = [Σ (J_ci N)ᵀ (J_ci N)]⁺ Σ (J_ci N)ᵀ (ΔX_ci − J_ci Δθ_p)` — summing each request's own
/// pseudoinverse instead (as eq. 54 does for the obstacle operation's few, nearby
/// secondary points) lets a point that can barely move in the null space dominate with a
/// huge, sign-flipping term: the arm chatters in place.
pub fn follow_flow_null_motion(
    arm: &Arm,
    q: &[f64],
    flow: &dyn Flow,
    d_e: f64,
    null_projector: &DMatrix<f64>,
    net: &DVector<f64>,
) -> DVector<f64> {
    let n = arm.dof();
    let pts = arm.points(q);
    let mut normal = DMatrix::<f64>::zeros(n, n);
    let mut rhs = DVector::<f64>::zeros(n);
    for (link, &p) in pts.iter().enumerate().take(n).skip(1) {
        // The end point of link `link − 1`, pulled by the flow there.
        let Some(d) = flow.velocity(p).and_then(unit) else {
            continue;
        };
        let jc = arm.point_jacobian(q, link - 1, p);
        let a = &jc * null_projector;
        let want = DVector::from_column_slice(&[d.x * d_e, d.y * d_e]) - &jc * net;
        normal += a.transpose() * &a;
        rhs += a.transpose() * want;
    }
    pinv(&normal) * rhs
}

/// One period of eqs. 52–58 at `q`: `end_velocity` is the flow at the end effector (or the
/// stagnation guard's direction), `contacts` the secondary control points. `None` if the
/// motion is zero (the flow has no direction there).
pub fn arm_step(
    arm: &Arm,
    q: &[f64],
    flow: &dyn Flow,
    end_velocity: Vector,
    contacts: &[Contact],
    params: &ArmParams,
) -> Option<ArmStep> {
    let n = arm.dof();
    let dxe = unit(end_velocity)? * params.d_e;
    let je = arm.jacobian(q);
    let je_pinv = pinv(&je);
    // (53)
    let net = &je_pinv * DVector::from_column_slice(&[dxe.x, dxe.y]);
    let projector = DMatrix::<f64>::identity(n, n) - &je_pinv * &je;
    let mut null = DVector::<f64>::zeros(n);
    let operation = if contacts.is_empty() {
        if params.null_motion == NullMotion::FollowFlow {
            null = follow_flow_null_motion(arm, q, flow, params.d_e, &projector, &net);
        }
        Operation::Potential
    } else {
        let phi_o = ObstaclePotential::from_contacts(contacts, params.obstacle_strength);
        for c in contacts {
            let push = phi_o.gradient(c.robot_point);
            null += null_motion_term(arm, q, c.segment, c.robot_point, push, &projector, &net);
        }
        Operation::Obstacle
    };
    // (55–58)
    let total = &net + &null;
    let norm = total.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return None;
    }
    let h = params.d_theta_max / norm;
    Some(ArmStep {
        net: net * h,
        null: null * h,
        operation,
        normalisation: h,
    })
}

/// A run of the arm controller.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ArmRun {
    /// How it ended.
    pub status: RunStatus,
    /// Periods run.
    pub steps: usize,
    /// The smallest distance of every link to every obstacle's exact polygon along the
    /// whole motion.
    pub min_distance: f64,
    /// The period of the smallest distance.
    pub min_distance_step: usize,
    /// δ.
    pub delta: f64,
    /// Periods in the obstacle operation.
    pub obstacle_periods: usize,
    /// Every joint configuration, the start first.
    pub joints: Vec<Vec<f64>>,
    /// The end effector's position at every period.
    pub end_effector: Vec<[f64; 2]>,
}

impl ArmRun {
    /// Whether the end effector reached the goal.
    pub fn reached(&self) -> bool {
        self.status == RunStatus::Reached
    }
}

/// Runs the arm controller on `flow` from joint angles `start` until the end effector
/// reaches `goal`.
pub fn run_arm(
    flow: &dyn Flow,
    obstacles: &Obstacles,
    arm: &Arm,
    start: &[f64],
    goal: Point,
    params: &ArmParams,
) -> Result<ArmRun, ControlError> {
    params.validate()?;
    if start.len() != arm.dof() {
        return Err(ControlError::InvalidArm {
            reason: format!(
                "the start has {} joint angles for {} links",
                start.len(),
                arm.dof()
            ),
        });
    }
    if let Some(bad) = start.iter().find(|a| !a.is_finite()) {
        return Err(ControlError::InvalidParameter {
            name: "start joint angle",
            value: *bad,
            reason: "must be finite",
        });
    }
    let first = arm_clearance(arm, obstacles, start);
    if let Some((d, obstacle)) = first
        && d <= 0.0
    {
        return Err(ControlError::StartInCollision {
            obstacle,
            distance: d,
        });
    }
    let mut q = start.to_vec();
    let mut clearance = Clearance::start(first.map(|x| x.0));
    let mut joints = vec![q.clone()];
    let mut tips = vec![arm.end_effector(&q)]
        .into_iter()
        .map(|p| [p.x, p.y])
        .collect::<Vec<_>>();
    let mut status = RunStatus::MaxSteps;
    let mut steps = 0;
    let mut obstacle_periods = 0;
    while steps < params.max_steps {
        let e = arm.end_effector(&q);
        if (e - goal).norm() <= params.goal_tolerance {
            status = RunStatus::Reached;
            break;
        }
        let Some(v) = flow.velocity(e) else {
            status = RunStatus::OutsideFlow { at: [e.x, e.y] };
            break;
        };
        let pts = arm.points(&q);
        let contacts: Vec<Contact> = pts
            .windows(2)
            .enumerate()
            .flat_map(|(k, w)| obstacles.contacts(w[0], w[1], params.delta, k))
            .collect();
        let Some(step) = arm_step(arm, &q, flow, v, &contacts, params) else {
            status = RunStatus::Stalled { at: [e.x, e.y] };
            break;
        };
        if step.operation == Operation::Obstacle {
            obstacle_periods += 1;
        }
        let dq = step.total();
        let next: Vec<f64> = q.iter().zip(dq.iter()).map(|(a, d)| a + d).collect();
        steps += 1;
        let along = arm_motion_clearance(arm, obstacles, &q, &next, params.check_step);
        clearance.update(along, steps);
        q = next;
        let tip = arm.end_effector(&q);
        joints.push(q.clone());
        tips.push([tip.x, tip.y]);
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
        && (arm.end_effector(&q) - goal).norm() <= params.goal_tolerance
    {
        status = RunStatus::Reached;
    }
    Ok(ArmRun {
        status,
        steps,
        min_distance: clearance.distance,
        min_distance_step: clearance.step,
        delta: params.delta,
        obstacle_periods,
        joints,
        end_effector: tips,
    })
}
