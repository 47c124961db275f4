//! Exact collision checks of motions, independent of the mesher's geometry: the robot's
//! outlines against the obstacle polygons, discs and workspace edges with the planar kernels
//! of `harmonic_mesh::geom` (segment–segment and segment–polygon distances, even–odd
//! containment), at samples close enough that no robot point moves more than a given step
//! between two of them.

use harmonic_mesh::geom::{
    polygon_contains, polygon_distance, segment_polygon_distance, segment_segment_distance,
};

use crate::geometry::World;
use crate::robot::Robot;

fn pt(p: [f64; 2]) -> harmonic_mesh::Point {
    harmonic_mesh::Point::new(p[0], p[1])
}

fn edges(outline: &[[f64; 2]]) -> Vec<([f64; 2], [f64; 2])> {
    if outline.len() == 2 {
        return vec![(outline[0], outline[1])];
    }
    (0..outline.len())
        .map(|i| (outline[i], outline[(i + 1) % outline.len()]))
        .collect()
}

/// The exact distance between two outlines (segments or convex polygons): 0 when they
/// cross or one holds a corner of the other.
fn outline_distance(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let inside = |p: &[[f64; 2]], q: [f64; 2]| p.len() > 2 && polygon_contains(p, q);
    if a.iter().any(|&p| inside(b, p)) || b.iter().any(|&p| inside(a, p)) {
        return 0.0;
    }
    let mut best = f64::INFINITY;
    for &(p, q) in &edges(a) {
        for &(r, s) in &edges(b) {
            best = best.min(segment_segment_distance(pt(p), pt(q), pt(r), pt(s)));
        }
    }
    best
}

/// The exact distance from the robot at `q` to the nearest obstacle or wall, or between two
/// of an arm's links that are not neighbours; 0 when it touches or overlaps one or leaves
/// the workspace.
pub fn exact_clearance(robot: &Robot, world: &World, q: &[f64]) -> f64 {
    let mut best = f64::INFINITY;
    let outlines = robot.outlines(q);
    if matches!(robot, Robot::Arm(_)) {
        for i in 0..outlines.len() {
            for j in i + 2..outlines.len() {
                best = best.min(outline_distance(&outlines[i], &outlines[j]));
            }
        }
    }
    for outline in outlines {
        let es = edges(&outline);
        let solid = outline.len() > 2;
        if outline
            .iter()
            .any(|p| !polygon_contains(&world.workspace, *p))
        {
            return 0.0;
        }
        for &(a, b) in &es {
            for i in 0..world.workspace.len() {
                let (c, d) = (
                    world.workspace[i],
                    world.workspace[(i + 1) % world.workspace.len()],
                );
                best = best.min(segment_segment_distance(pt(a), pt(b), pt(c), pt(d)));
            }
        }
        for o in &world.obstacles {
            if let Some(ring) = &o.ring {
                for &(a, b) in &es {
                    best = best.min(segment_polygon_distance(a, b, ring));
                }
                if solid {
                    for i in 0..ring.len() {
                        best = best.min(segment_polygon_distance(
                            ring[i],
                            ring[(i + 1) % ring.len()],
                            &outline,
                        ));
                    }
                }
            }
            if let Some((c, r)) = o.disc {
                let d = if solid {
                    polygon_distance(&outline, c)
                } else {
                    harmonic_mesh::geom::point_segment_distance(c, outline[0], outline[1])
                };
                best = best.min((d - r).max(0.0));
            }
        }
    }
    best.max(0.0)
}

/// The outcome of [`check_motion`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionCheck {
    /// The smallest exact clearance met.
    pub min_clearance: f64,
    /// Configurations checked.
    pub samples: usize,
}

/// Checks the straight motion `a → b` in configuration space at samples such that no robot
/// point moves more than `step` between two (both ends included).
pub fn check_motion(robot: &Robot, world: &World, a: &[f64], b: &[f64], step: f64) -> MotionCheck {
    let n = ((robot.sweep_bound(a, b) / step).ceil() as usize).max(1);
    let mut min_clearance = f64::INFINITY;
    let mut q = a.to_vec();
    for k in 0..=n {
        let t = k as f64 / n as f64;
        for i in 0..a.len() {
            q[i] = a[i] + t * (b[i] - a[i]);
        }
        min_clearance = min_clearance.min(exact_clearance(robot, world, &q));
    }
    MotionCheck {
        min_clearance,
        samples: n + 1,
    }
}

/// Checks every motion of a path (consecutive entries); the smallest clearance and the
/// samples used.
pub fn check_path(robot: &Robot, world: &World, path: &[Vec<f64>], step: f64) -> MotionCheck {
    let mut out = MotionCheck {
        min_clearance: f64::INFINITY,
        samples: 0,
    };
    if path.len() == 1 {
        out.min_clearance = exact_clearance(robot, world, &path[0]);
        out.samples = 1;
    }
    for w in path.windows(2) {
        let c = check_motion(robot, world, &w[0], &w[1], step);
        out.min_clearance = out.min_clearance.min(c.min_clearance);
        out.samples += c.samples;
    }
    out
}
