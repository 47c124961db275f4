//! The non-holonomic car stepper of Garrido et al. (2010, §7).
//!
//! The car's state is the pose `(x, y, θ)` of its rear-axle midpoint. Each step reads the
//! field's descent direction `−∇value` at the front-axle midpoint `(x + L cos θ, y + L sin θ)`,
//! turns the front wheels toward it (steering angle δ = the angle between the heading and
//! that direction, clamped to ±δmax), and rotates the car about the instantaneous centre of
//! rotation where the rear- and front-wheel normals meet (radius `L / tan δ` from the rear
//! axle; straight ahead when δ = 0), driving an arc of length `s`.

use harmonic_types::{Point, Vector};

use crate::field::magnitude;
use crate::{CarPath, Field, Locate, Segment, TraceError, TraceStatus};

/// How long each step's arc is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CarSpeed {
    /// Every arc is [`CarOptions::step`] long.
    Constant,
    /// The arc is `gain · |∇value|` at the front axle, clamped to `[min_step, step]`.
    ProportionalToGradient {
        /// Arc length per unit of gradient magnitude.
        gain: f64,
        /// The shortest arc.
        min_step: f64,
    },
}

/// A target pose region: the drive ends when the rear axle comes within `tolerance` of
/// `center`, reported as reaching goal `goal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CarTarget {
    /// The goal point.
    pub center: Point,
    /// How close the rear axle must come.
    pub tolerance: f64,
    /// The goal index to report.
    pub goal: u32,
}

/// The car's rectangular footprint, relative to the rear-axle midpoint and heading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// How far the body reaches behind the rear axle.
    pub rear: f64,
    /// How far the body reaches ahead of the rear axle.
    pub front: f64,
    /// Half the body's width.
    pub half_width: f64,
}

impl Footprint {
    /// The footprint's corners at `pose`, counter-clockwise from rear-right.
    pub fn corners(&self, pose: [f64; 3]) -> [Point; 4] {
        let [x, y, th] = pose;
        let (s, c) = th.sin_cos();
        let at = |f: f64, l: f64| Point::new(x + f * c - l * s, y + f * s + l * c);
        [
            at(-self.rear, -self.half_width),
            at(self.front, -self.half_width),
            at(self.front, self.half_width),
            at(-self.rear, self.half_width),
        ]
    }
}

/// A footprint and the predicate that says whether it collides (true = collision).
pub struct Collision<'c> {
    /// The car's footprint.
    pub footprint: Footprint,
    /// Whether the footprint with these corners overlaps an obstacle or leaves the workspace.
    pub collides: &'c dyn Fn(&[Point; 4]) -> bool,
}

/// Options of the car stepper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CarOptions {
    /// Distance `L` between the rear and front axles.
    pub wheelbase: f64,
    /// Steering limit δmax in radians, in (0, π/2).
    pub max_steer: f64,
    /// Arc length per step (the largest one with [`CarSpeed::ProportionalToGradient`]).
    pub step: f64,
    /// How the arc length is chosen.
    pub speed: CarSpeed,
    /// An optional target point with a tolerance.
    pub target: Option<CarTarget>,
    /// Largest number of steps.
    pub max_steps: usize,
    /// The drive ends `Stalled` after this many steps without lowering the field's value at
    /// the rear axle (the car circles).
    pub stall_steps: usize,
}

impl CarOptions {
    /// Constant-speed options for wheelbase `L`, steering limit `max_steer` (radians) and
    /// arc length `step`, with room for 100 000 steps and a 400-step stall window.
    pub fn new(wheelbase: f64, max_steer: f64, step: f64) -> Self {
        CarOptions {
            wheelbase,
            max_steer,
            step,
            speed: CarSpeed::Constant,
            target: None,
            max_steps: 100_000,
            stall_steps: 400,
        }
    }

    /// Checks the options' ranges.
    pub fn validate(&self) -> Result<(), TraceError> {
        let bad = |name, value, reason| {
            Err(TraceError::InvalidOption {
                name,
                value,
                reason,
            })
        };
        if !(self.wheelbase > 0.0 && self.wheelbase.is_finite()) {
            return bad("wheelbase", self.wheelbase, "must be positive and finite");
        }
        if !(self.max_steer > 0.0 && self.max_steer < std::f64::consts::FRAC_PI_2) {
            return bad("max_steer", self.max_steer, "must lie in (0, π/2) radians");
        }
        if !(self.step > 0.0 && self.step.is_finite()) {
            return bad("step", self.step, "must be positive and finite");
        }
        if let CarSpeed::ProportionalToGradient { gain, min_step } = self.speed {
            if !(gain > 0.0 && gain.is_finite()) {
                return bad("gain", gain, "must be positive and finite");
            }
            if !(min_step > 0.0 && min_step <= self.step) {
                return bad("min_step", min_step, "must lie in (0, step]");
            }
        }
        if let Some(t) = self.target
            && !(t.tolerance >= 0.0
                && t.tolerance.is_finite()
                && t.center.coords.iter().all(|c| c.is_finite()))
        {
            return bad(
                "target.tolerance",
                t.tolerance,
                "must be finite and non-negative, with a finite centre",
            );
        }
        Ok(())
    }
}

/// Wraps an angle to (−π, π].
fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(std::f64::consts::TAU);
    if r > std::f64::consts::PI {
        r - std::f64::consts::TAU
    } else {
        r
    }
}

/// The pose after driving an arc of length `s` with curvature `kappa` from `pose`.
fn arc(pose: [f64; 3], kappa: f64, s: f64) -> [f64; 3] {
    let [x, y, th] = pose;
    if kappa.abs() * s < 1e-9 {
        // Straight (second-order accurate in the tiny turn).
        let mid = th + 0.5 * kappa * s;
        return [x + s * mid.cos(), y + s * mid.sin(), th + kappa * s];
    }
    let th2 = th + kappa * s;
    [
        x + (th2.sin() - th.sin()) / kappa,
        y - (th2.cos() - th.cos()) / kappa,
        th2,
    ]
}

/// Where the rear axle's arc ends.
enum ArcEnd<C> {
    /// In free space, in this cell, at this pose.
    Free(C, [f64; 3]),
    /// In goal `j`, at this pose, after this arc length.
    Goal(u32, [f64; 3], f64),
    /// The arc leaves free space.
    Blocked,
}

/// Follows the rear axle's arc (curvature `kappa`, length `s`) from `pose` through free space,
/// in chords of at most 0.1 rad.
fn follow_arc<F: Field<Point = Point, Vector = Vector>>(
    field: &F,
    cell: F::Cell,
    pose: [f64; 3],
    kappa: f64,
    s: f64,
) -> ArcEnd<F::Cell> {
    let pieces = ((kappa.abs() * s / 0.1).ceil() as usize).clamp(1, 64);
    let mut from = Point::new(pose[0], pose[1]);
    let mut c = cell;
    let mut q = pose;
    for i in 1..=pieces {
        let len = s * i as f64 / pieces as f64;
        q = arc(pose, kappa, len);
        let qp = Point::new(q[0], q[1]);
        match field.segment(c, from, qp) {
            Segment::Inside(u) => c = u,
            Segment::Goal(j) => return ArcEnd::Goal(j, q, len),
            Segment::Blocked => return ArcEnd::Blocked,
        }
        from = qp;
    }
    ArcEnd::Free(c, q)
}

/// Drives a car from `start = [x, y, θ]` (rear-axle midpoint and heading) down the field.
///
/// Ends `ReachedGoal(j)` when the rear axle's motion enters goal `j`, when the front-axle
/// midpoint lies in goal `j`, or within the target's tolerance; `Stalled` when the value at
/// the rear axle stops decreasing for `stall_steps` steps (the car circles);
/// `Collision` when the rear axle's arc would leave free space (or `collision` says the
/// footprint hits something) even at full lock either way: a commanded arc that is blocked is
/// replaced by the sharpest turn toward, then away from, the field direction. Errors only for
/// invalid options.
///
/// ```
/// use harmonic_mesh::{BoundaryTag, Mesh, Point};
/// use harmonic_trajectory::{CarOptions, P1Field, TraceStatus, drive};
/// // A 1 × 4 corridor with the goal across its top; ψ = y increases toward it.
/// let mesh = Mesh::from_parts(
///     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 4.0), Point::new(0.0, 4.0)],
///     vec![[0, 1, 2], [0, 2, 3]],
///     &[(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Wall),
///       (2, 3, BoundaryTag::Goal(0)), (3, 0, BoundaryTag::Wall)],
/// )?;
/// let psi = [0.0, 0.0, 4.0, 4.0];
/// let field = P1Field::ascending(&mesh, &psi)?;
/// // Heading east, the car turns north toward the goal.
/// let opts = CarOptions::new(0.1, 0.6, 0.01);
/// let car = drive(&field, [0.3, 0.5, 0.0], &opts, None)?;
/// assert_eq!(car.status, TraceStatus::ReachedGoal(0));
/// assert!(car.max_curvature <= 0.6f64.tan() / 0.1 + 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn drive<F: Field<Point = Point, Vector = Vector>>(
    field: &F,
    start: [f64; 3],
    opts: &CarOptions,
    collision: Option<&Collision<'_>>,
) -> Result<CarPath, TraceError> {
    opts.validate()?;
    let finish = |poses: Vec<[f64; 3]>, status, length, min_gradient, max_curvature| {
        let goal = match status {
            TraceStatus::ReachedGoal(j) => Some(j),
            _ => None,
        };
        CarPath {
            poses,
            status,
            goal,
            length,
            min_gradient,
            max_curvature,
        }
    };
    let rear = Point::new(start[0], start[1]);
    if !start[2].is_finite() {
        return Err(TraceError::InvalidOption {
            name: "start heading",
            value: start[2],
            reason: "must be finite",
        });
    }
    let mut cell = match field.locate(rear, None) {
        Locate::Inside(c) => c,
        Locate::Goal(j) => {
            return Ok(finish(
                vec![start],
                TraceStatus::ReachedGoal(j),
                0.0,
                f64::INFINITY,
                0.0,
            ));
        }
        Locate::InObstacle => {
            return Ok(finish(
                vec![start],
                TraceStatus::StartInObstacle,
                0.0,
                f64::INFINITY,
                0.0,
            ));
        }
        Locate::OutsideWorkspace => {
            return Ok(finish(
                vec![start],
                TraceStatus::OutsideWorkspace,
                0.0,
                f64::INFINITY,
                0.0,
            ));
        }
    };
    if !field.goal_reachable(cell) {
        return Ok(finish(
            vec![start],
            TraceStatus::Unreachable,
            0.0,
            f64::INFINITY,
            0.0,
        ));
    }
    if let Some(c) = collision
        && (c.collides)(&c.footprint.corners(start))
    {
        return Ok(finish(
            vec![start],
            TraceStatus::Collision { at: Some(start) },
            0.0,
            f64::INFINITY,
            0.0,
        ));
    }
    let l = opts.wheelbase;
    let kappa_max = opts.max_steer.tan() / l;
    let mut pose = start;
    let mut poses = vec![start];
    let mut length = 0.0;
    let mut min_gradient = f64::INFINITY;
    let mut max_curvature: f64 = 0.0;
    let mut front_cell = cell;
    let mut best = field.value(cell, rear);
    let mut since_best = 0;
    for _ in 0..opts.max_steps {
        let [x, y, th] = pose;
        let here = Point::new(x, y);
        if let Some(t) = opts.target
            && (here - t.center).norm() <= t.tolerance
        {
            return Ok(finish(
                poses,
                TraceStatus::ReachedGoal(t.goal),
                length,
                min_gradient,
                max_curvature,
            ));
        }
        // The field at the front axle (at the rear axle when the front overhangs a wall).
        let front = Point::new(x + l * th.cos(), y + l * th.sin());
        let g = match field.segment(cell, here, front) {
            Segment::Inside(c) => {
                front_cell = c;
                field.gradient(c, front)
            }
            Segment::Goal(j) => {
                return Ok(finish(
                    poses,
                    TraceStatus::ReachedGoal(j),
                    length,
                    min_gradient,
                    max_curvature,
                ));
            }
            Segment::Blocked => match field.locate(front, Some(front_cell)) {
                Locate::Inside(c) => {
                    front_cell = c;
                    field.gradient(c, front)
                }
                _ => field.gradient(cell, here),
            },
        };
        let gn = magnitude(g);
        if !(gn > 0.0 && gn.is_finite()) {
            return Ok(finish(
                poses,
                TraceStatus::Stalled { at: here },
                length,
                min_gradient,
                max_curvature,
            ));
        }
        min_gradient = min_gradient.min(gn);
        let d: Vector = -g;
        let delta = wrap(d.y.atan2(d.x) - th).clamp(-opts.max_steer, opts.max_steer);
        let kappa = (delta.tan() / l).clamp(-kappa_max, kappa_max);
        let s = match opts.speed {
            CarSpeed::Constant => opts.step,
            CarSpeed::ProportionalToGradient { gain, min_step } => {
                (gain * gn).clamp(min_step, opts.step)
            }
        };
        // The commanded arc; if it (or the footprint at its end) would hit something, the
        // sharpest turns toward and away from the field direction.
        let side = if kappa != 0.0 { kappa.signum() } else { 1.0 };
        let mut chosen = None;
        for k in [kappa, side * kappa_max, -side * kappa_max] {
            match follow_arc(field, cell, pose, k, s) {
                ArcEnd::Goal(j, q, len) => {
                    poses.push(q);
                    length += len;
                    max_curvature = max_curvature.max(k.abs());
                    return Ok(finish(
                        poses,
                        TraceStatus::ReachedGoal(j),
                        length,
                        min_gradient,
                        max_curvature,
                    ));
                }
                ArcEnd::Free(c, next) => {
                    let hits =
                        collision.is_some_and(|col| (col.collides)(&col.footprint.corners(next)));
                    if !hits {
                        chosen = Some((c, next, k));
                        break;
                    }
                }
                ArcEnd::Blocked => {}
            }
        }
        let Some((c, next, kappa)) = chosen else {
            return Ok(finish(
                poses,
                TraceStatus::Collision { at: Some(pose) },
                length,
                min_gradient,
                max_curvature,
            ));
        };
        let from = Point::new(next[0], next[1]);
        cell = c;
        pose = [next[0], next[1], wrap(next[2])];
        poses.push(pose);
        length += s;
        max_curvature = max_curvature.max(kappa.abs());
        let v = field.value(cell, from);
        if v < best {
            best = v;
            since_best = 0;
        } else {
            since_best += 1;
            if since_best > opts.stall_steps {
                return Ok(finish(
                    poses,
                    TraceStatus::Stalled { at: from },
                    length,
                    min_gradient,
                    max_curvature,
                ));
            }
        }
    }
    Ok(finish(
        poses,
        TraceStatus::MaxSteps,
        length,
        min_gradient,
        max_curvature,
    ))
}
