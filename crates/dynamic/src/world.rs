//! The simulated world: the known map plus moving and unmapped obstacles, a simulated laser,
//! and the sense–plan–move loop with the distance to the true obstacles checked at every step.

use harmonic_mesh::{Point, geom};
use serde::Serialize;

use harmonic_planner::scene::Scene;

use crate::{
    DynamicPlanner, LaserScan, LocalMapMode, ReplanTimings, ScanOptions, dist, region_polygon,
    scan_obstacles,
};

/// An obstacle of the simulated world that the known map does not have: static (zero
/// velocity) or moving.
#[derive(Clone, Debug, Serialize)]
pub struct WorldObstacle {
    /// The polygon at time 0.
    pub polygon: Vec<[f64; 2]>,
    /// Velocity, m/s.
    pub velocity: [f64; 2],
    /// 0: moves on forever; otherwise it turns back every `period / 2` seconds, returning to
    /// where it started every `period`.
    pub period: f64,
}

impl WorldObstacle {
    /// Whether the obstacle moves.
    pub fn moves(&self) -> bool {
        self.velocity != [0.0, 0.0]
    }

    /// The polygon at time `t`.
    pub fn at(&self, t: f64) -> Vec<[f64; 2]> {
        let s = if self.period > 0.0 {
            let h = 0.5 * self.period;
            h - (t.rem_euclid(self.period) - h).abs()
        } else {
            t
        };
        let (dx, dy) = (self.velocity[0] * s, self.velocity[1] * s);
        self.polygon
            .iter()
            .map(|p| [p[0] + dx, p[1] + dy])
            .collect()
    }
}

/// The simulated world: the known map's walls and obstacles, plus obstacles it does not know.
pub struct World {
    known_segments: Vec<([f64; 2], [f64; 2])>,
    /// Obstacles not in the known map, seen only by the laser.
    pub obstacles: Vec<WorldObstacle>,
}

/// The edges of a closed ring.
fn ring_segments(ring: &[[f64; 2]]) -> impl Iterator<Item = ([f64; 2], [f64; 2])> + '_ {
    (0..ring.len()).map(move |i| (ring[i], ring[(i + 1) % ring.len()]))
}

/// Where the ray `o + s·d` (s ≥ 0) first meets the segment `ab`, as `s`.
fn ray_hit(o: [f64; 2], d: [f64; 2], a: [f64; 2], b: [f64; 2]) -> Option<f64> {
    let e = [b[0] - a[0], b[1] - a[1]];
    let den = d[0] * e[1] - d[1] * e[0];
    if den.abs() < 1e-300 {
        return None;
    }
    let w = [a[0] - o[0], a[1] - o[1]];
    let s = (w[0] * e[1] - w[1] * e[0]) / den;
    let u = (w[0] * d[1] - w[1] * d[0]) / den;
    (s >= 0.0 && (0.0..=1.0).contains(&u)).then_some(s)
}

impl World {
    /// A world made of the known map of `scene` and the unknown `obstacles`.
    pub fn new(scene: &Scene, obstacles: Vec<WorldObstacle>) -> World {
        let mut known_segments: Vec<_> = ring_segments(&scene.workspace).collect();
        for o in &scene.obstacles {
            if let Some(ring) = region_polygon(o, 64) {
                known_segments.extend(ring_segments(&ring));
            }
        }
        World {
            known_segments,
            obstacles,
        }
    }

    /// A laser scan from `pose` at time `t`: `beams` rays evenly spread over a full turn,
    /// each returning its first hit closer than `range` (in the robot frame).
    pub fn scan(&self, pose: [f64; 3], t: f64, beams: usize, range: f64) -> LaserScan {
        let moving: Vec<Vec<[f64; 2]>> = self.obstacles.iter().map(|o| o.at(t)).collect();
        let o = [pose[0], pose[1]];
        let mut points = Vec::with_capacity(beams);
        for k in 0..beams {
            let local = std::f64::consts::TAU * k as f64 / beams as f64;
            let (s, c) = (pose[2] + local).sin_cos();
            let d = [c, s];
            let hit = self
                .known_segments
                .iter()
                .copied()
                .chain(moving.iter().flat_map(|r| ring_segments(r)))
                .filter_map(|(a, b)| ray_hit(o, d, a, b))
                .fold(f64::INFINITY, f64::min);
            if hit < range {
                let (ls, lc) = local.sin_cos();
                points.push([hit * lc, hit * ls]);
            }
        }
        LaserScan { pose, points }
    }

    /// Distance from `p` to the unknown obstacles at time `t` (0 inside one); `moving_only`
    /// restricts it to the moving ones.
    pub fn distance(&self, p: [f64; 2], t: f64, moving_only: bool) -> f64 {
        self.obstacles
            .iter()
            .filter(|o| !moving_only || o.moves())
            .map(|o| geom::polygon_distance(&o.at(t), p))
            .fold(f64::INFINITY, f64::min)
    }
}

/// The loop's settings.
#[derive(Clone, Copy, Debug)]
pub struct RunOptions {
    /// Laser rays per scan (default 180).
    pub beams: usize,
    /// Laser range (default 3 m).
    pub range: f64,
    /// Robot speed, m/s (default 1); obstacles must not be faster.
    pub speed: f64,
    /// Longest step (default 0.1 m).
    pub max_step: f64,
    /// Shortest step (default 0.002 m).
    pub min_step: f64,
    /// A step is this fraction of the distance to the nearest sensed obstacle (default 0.25).
    pub step_fraction: f64,
    /// Time the robot waits when it has no path, s (default 0.02).
    pub wait: f64,
    /// Steps before giving up (default 2000).
    pub max_steps: usize,
    /// Record the unknown obstacles every this many steps (default 10; 0: never).
    pub snapshot_every: usize,
    /// How scans become obstacles.
    pub scan: ScanOptions,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            beams: 180,
            range: 3.0,
            speed: 1.0,
            max_step: 0.1,
            min_step: 0.002,
            step_fraction: 0.25,
            wait: 0.02,
            max_steps: 2000,
            snapshot_every: 10,
            scan: ScanOptions::default(),
        }
    }
}

/// What happened in a run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Run {
    /// Whether the robot reached the goal.
    pub reached: bool,
    /// Successful replans.
    pub replans: usize,
    /// Of those, replans that remeshed the window (the lattice could not serve them, or
    /// [`LocalMapMode::Remesh`] was asked for).
    pub remeshed: usize,
    /// Replans that failed (the robot waited); the last error's message.
    pub failed_replans: usize,
    /// The last failure, if any.
    pub last_error: Option<String>,
    /// Robot positions, one per step.
    pub trail: Vec<[f64; 2]>,
    /// Simulated time at each trail point, s.
    pub times: Vec<f64>,
    /// Smallest distance from the robot to the true obstacles (known map, walls and unknown
    /// obstacles at their positions of the moment) over all steps and the segments between.
    pub min_distance_to_obstacles: f64,
    /// Wall-clock time of each replan, ms.
    pub replan_ms: Vec<f64>,
    /// Stage times summed over the run.
    pub stage_ms: ReplanTimings,
    /// `(time, unknown obstacles then)` every [`RunOptions::snapshot_every`] steps.
    pub snapshots: Vec<(f64, Vec<Vec<[f64; 2]>>)>,
    /// Local mesh sizes, smallest and largest.
    pub triangles: (usize, usize),
}

/// Walks `points` from the first one for an arc length `step`; returns where it stops. It
/// stops early at a cusp, a vertex where the path turns back by more than a right angle (as a
/// local path does where the flow converges on a lattice vertex and the trace steps off it
/// to a lower neighbour): a robot halts to turn there, and a step run on through the cusp
/// would end about where it began, replan after replan.
fn advance(points: &[[f64; 2]], step: f64) -> [f64; 2] {
    let mut left = step;
    let mut previous: Option<[f64; 2]> = None;
    for w in points.windows(2) {
        let d = [w[1][0] - w[0][0], w[1][1] - w[0][1]];
        let l = dist(w[0], w[1]);
        if l == 0.0 {
            continue;
        }
        if previous.is_some_and(|p| p[0] * d[0] + p[1] * d[1] < 0.0) {
            return w[0];
        }
        if l >= left {
            let s = left / l;
            return [w[0][0] + s * d[0], w[0][1] + s * d[1]];
        }
        left -= l;
        previous = Some(d);
    }
    points.last().copied().unwrap_or([f64::NAN, f64::NAN])
}

/// The paper's Figure 10 loop: from `start`, scan, turn the scan into obstacles, replan,
/// move a step along the local path sized by the distance to the nearest sensed obstacle,
/// let the world's obstacles move for the step's duration, repeat until the goal is reached
/// or [`RunOptions::max_steps`] steps.
pub fn run(planner: &mut DynamicPlanner, world: &World, start: [f64; 2], opts: &RunOptions) -> Run {
    let mut out = Run {
        min_distance_to_obstacles: f64::INFINITY,
        triangles: (usize::MAX, 0),
        ..Run::default()
    };
    let true_distance = |planner: &DynamicPlanner, p: [f64; 2], t: f64| {
        planner.known_distance(p).min(world.distance(p, t, false))
    };
    let (mut pos, mut heading, mut t) = (start, 0.0f64, 0.0f64);
    out.trail.push(pos);
    out.times.push(t);
    out.min_distance_to_obstacles = true_distance(planner, pos, t);
    for step_no in 0..opts.max_steps {
        if opts.snapshot_every > 0 && step_no % opts.snapshot_every == 0 {
            out.snapshots
                .push((t, world.obstacles.iter().map(|o| o.at(t)).collect()));
        }
        let scan = world.scan([pos[0], pos[1], heading], t, opts.beams, opts.range);
        let sensed = scan_obstacles(&scan, |p| planner.known_distance(p), &opts.scan);
        let nearest = sensed
            .iter()
            .map(|ring| geom::polygon_distance(ring, pos))
            .fold(f64::INFINITY, f64::min);
        planner.set_obstacles(sensed);
        let plan = match planner.replan(pos) {
            Ok(plan) if plan.path.status.reached_goal() && plan.path.points.len() >= 2 => plan,
            other => {
                out.failed_replans += 1;
                out.last_error = Some(match other {
                    Ok(plan) => format!("local path {}", plan.path.status),
                    Err(e) => e.to_string(),
                });
                t += opts.wait;
                let d = true_distance(planner, pos, t);
                out.min_distance_to_obstacles = out.min_distance_to_obstacles.min(d);
                continue;
            }
        };
        out.replans += 1;
        out.remeshed += usize::from(plan.method == LocalMapMode::Remesh);
        out.replan_ms.push(plan.timings.total);
        for (sum, v) in [
            (&mut out.stage_ms.prepare, plan.timings.prepare),
            (&mut out.stage_ms.mesh, plan.timings.mesh),
            (&mut out.stage_ms.assemble, plan.timings.assemble),
            (&mut out.stage_ms.solve, plan.timings.solve),
            (&mut out.stage_ms.trace, plan.timings.trace),
            (&mut out.stage_ms.total, plan.timings.total),
        ] {
            *sum += v;
        }
        out.triangles.0 = out.triangles.0.min(plan.triangles);
        out.triangles.1 = out.triangles.1.max(plan.triangles);

        let step = (opts.step_fraction * nearest).clamp(opts.min_step, opts.max_step);
        let remaining = geom::polyline_length(&plan.path.points);
        let final_leg = plan.goal_in_window && remaining <= step;
        let next = if final_leg {
            plan.path.points[plan.path.points.len() - 1]
        } else {
            advance(&plan.path.points, step)
        };
        let moved = dist(pos, next);
        // The segment against the static map, then the end point against everything.
        let seg = planner
            .global()
            .domain()
            .segment_clearance(Point::new(pos[0], pos[1]), Point::new(next[0], next[1]));
        if moved > 0.0 {
            heading = (next[1] - pos[1]).atan2(next[0] - pos[0]);
        }
        t += moved / opts.speed;
        pos = next;
        let d = true_distance(planner, pos, t).min(seg);
        out.min_distance_to_obstacles = out.min_distance_to_obstacles.min(d);
        out.trail.push(pos);
        out.times.push(t);
        if final_leg {
            out.reached = true;
            break;
        }
    }
    if out.replans == 0 {
        out.triangles = (0, 0);
    }
    out
}

impl Run {
    /// The median and the 99th percentile of the replan times, ms (0 without replans).
    pub fn replan_percentiles(&self) -> (f64, f64) {
        let mut v = self.replan_ms.clone();
        if v.is_empty() {
            return (0.0, 0.0);
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
        (at(0.5), at(0.99))
    }
}

#[cfg(test)]
mod tests {
    use super::advance;

    #[test]
    fn a_step_stops_at_a_cusp_and_runs_on_through_ordinary_bends() {
        // Out 0.02 to a vertex, then back 0.1 along the same line: a step of 0.045 stops on
        // the vertex instead of ending 0.005 from where it began.
        let cusp = [[0.0, 0.0], [0.02, 0.0], [-0.08, 0.0]];
        assert_eq!(advance(&cusp, 0.045), [0.02, 0.0]);
        // A right-angle bend is walked through.
        let bend = [[0.0, 0.0], [0.02, 0.0], [0.02, 0.1]];
        let p = advance(&bend, 0.045);
        assert!(
            (p[0] - 0.02).abs() < 1e-15 && (p[1] - 0.025).abs() < 1e-15,
            "{p:?}"
        );
        // A step shorter than the first segment never reaches the cusp.
        let p = advance(&cusp, 0.01);
        assert!((p[0] - 0.01).abs() < 1e-15 && p[1] == 0.0, "{p:?}");
    }
}
