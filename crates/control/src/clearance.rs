//! The check of a run against the exact obstacle polygons: the whole body (every segment of
//! the bar or of every link) along the whole motion, each period's motion sampled so that no
//! body point moves more than a given step between samples (configurations interpolated
//! linearly, as the controller moves them).

use harmonic_mesh::Point;

use crate::arm::Arm;
use crate::bar::BarRobot;
use crate::obstacles::Obstacles;

/// The smallest distance seen so far and the period it was seen in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearance {
    /// The distance (infinity without obstacles).
    pub distance: f64,
    /// The period (0: the start).
    pub step: usize,
}

impl Clearance {
    /// From the start configuration's distance.
    pub fn start(distance: Option<f64>) -> Self {
        Clearance {
            distance: distance.unwrap_or(f64::INFINITY),
            step: 0,
        }
    }

    /// Takes a period's smallest distance.
    pub fn update(&mut self, along: Option<(f64, usize)>, step: usize) {
        if let Some((d, _)) = along
            && d < self.distance
        {
            self.distance = d;
            self.step = step;
        }
    }
}

/// Samples `1..=n` of the straight move between two configurations, with `n` so that no
/// body point moves more than `check_step` between samples given that the fastest one moves
/// `sweep` in all.
fn samples(sweep: f64, check_step: f64) -> usize {
    ((sweep / check_step).ceil() as usize).clamp(1, 100_000)
}

/// The smallest distance of the bar to every obstacle along the straight move `from → to`
/// in `(x, y, η)` (the end included, the start not: it was the previous end), with the
/// obstacle.
pub fn bar_motion_clearance(
    robot: &BarRobot,
    obstacles: &Obstacles,
    from: [f64; 3],
    to: [f64; 3],
    check_step: f64,
) -> Option<(f64, usize)> {
    // A bar point at distance s ≤ L behind the leading point moves at most
    // |Δ(x, y)| + L |Δη|.
    let sweep = (to[0] - from[0]).hypot(to[1] - from[1]) + robot.length * (to[2] - from[2]).abs();
    let n = samples(sweep, check_step);
    (1..=n)
        .filter_map(|k| {
            let t = k as f64 / n as f64;
            let pose = [0, 1, 2].map(|i| from[i] + t * (to[i] - from[i]));
            let (a, b) = robot.ends(pose);
            obstacles.segment_distance(a, b)
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
}

/// The smallest distance of every link of `arm` to every obstacle at `joints`.
pub fn arm_clearance(arm: &Arm, obstacles: &Obstacles, joints: &[f64]) -> Option<(f64, usize)> {
    let pts: Vec<Point> = arm.points(joints);
    pts.windows(2)
        .filter_map(|w| obstacles.segment_distance(w[0], w[1]))
        .min_by(|x, y| x.0.total_cmp(&y.0))
}

/// The smallest distance of every link to every obstacle along the straight move
/// `from → to` in joint space (the end included).
pub fn arm_motion_clearance(
    arm: &Arm,
    obstacles: &Obstacles,
    from: &[f64],
    to: &[f64],
    check_step: f64,
) -> Option<(f64, usize)> {
    // Joint j turns everything after it: a point at distance ≤ Σ_{k ≥ j} l_k from joint j.
    let sweep: f64 = (0..from.len())
        .map(|j| (to[j] - from[j]).abs() * arm.reach_from(j))
        .sum();
    let n = samples(sweep, check_step);
    (1..=n)
        .filter_map(|k| {
            let t = k as f64 / n as f64;
            let q: Vec<f64> = from.iter().zip(to).map(|(a, b)| a + t * (b - a)).collect();
            arm_clearance(arm, obstacles, &q)
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
}
