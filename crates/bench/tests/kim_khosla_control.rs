//! Kim & Khosla's controllers in their settings (50) and (51), on their panel field and on
//! our FEM field: both reach, and the whole robot stays off the exact obstacle polygons along
//! the whole motion — rechecked here independently of the controllers' own bookkeeping,
//! every motion between consecutive periods sampled so that no robot point moves more than
//! 1e-3 of the scene size.

use harmonic_bench::kim_khosla_control::{ARM_LINKS, BAR_LENGTH, arm_runs, bar_runs};
use harmonic_control::{Arm, NullMotion, Side};
use harmonic_mesh::Point;
use harmonic_mesh::geom::segment_polygon_distance;

fn polys(v: &[Vec<[f64; 2]>]) -> Vec<Vec<Point>> {
    v.iter()
        .map(|o| o.iter().map(|p| Point::new(p[0], p[1])).collect())
        .collect()
}

fn min_distance(segments: &[(Point, Point)], obstacles: &[Vec<Point>]) -> f64 {
    segments
        .iter()
        .flat_map(|&(a, b)| {
            obstacles
                .iter()
                .map(move |o| segment_polygon_distance(a, b, o))
        })
        .fold(f64::INFINITY, f64::min)
}

/// The smallest distance along linear interpolation between consecutive configurations,
/// `sweep(from, to)` bounding how far any robot point moves, `body(c)` the segments.
fn recheck(
    configs: &[Vec<f64>],
    obstacles: &[Vec<Point>],
    step: f64,
    sweep: impl Fn(&[f64], &[f64]) -> f64,
    body: impl Fn(&[f64]) -> Vec<(Point, Point)>,
) -> f64 {
    let mut best = min_distance(&body(&configs[0]), obstacles);
    for w in configs.windows(2) {
        let n = (sweep(&w[0], &w[1]) / step).ceil().max(1.0) as usize;
        for k in 1..=n {
            let t = k as f64 / n as f64;
            let c: Vec<f64> = w[0]
                .iter()
                .zip(&w[1])
                .map(|(a, b)| a + t * (b - a))
                .collect();
            best = best.min(min_distance(&body(&c), obstacles));
        }
    }
    best
}

#[test]
fn the_bar_reaches_the_goal_on_both_fields_clear_of_the_obstacle() {
    let (out, _, _) = bar_runs(Side::Left).expect("setting (50) runs");
    let obstacle = polys(std::slice::from_ref(&out.obstacle));
    assert_eq!(out.runs.len(), 2);
    assert_eq!((out.runs[0].field, out.runs[1].field), ("panel", "fem"));
    for r in &out.runs {
        assert!(r.reached, "{}: {:?}", r.field, r.status);
        assert!(r.min_distance > 0.0, "{}: {}", r.field, r.min_distance);
        assert!(!r.stagnation_points.is_empty(), "{}", r.field);
        let goal = Point::new(8.0, 2.0);
        let last = r.poses.last().unwrap();
        assert!((Point::new(last[0], last[1]) - goal).norm() < 0.3);
        let configs: Vec<Vec<f64>> = r.poses.iter().map(|p| p.to_vec()).collect();
        let d = recheck(
            &configs,
            &obstacle,
            1e-3 * 10.0,
            |a, b| (b[0] - a[0]).hypot(b[1] - a[1]) + BAR_LENGTH * (b[2] - a[2]).abs(),
            |c| {
                let p = Point::new(c[0], c[1]);
                vec![(
                    p,
                    p - harmonic_mesh::Vector::new(c[2].cos(), c[2].sin()) * BAR_LENGTH,
                )]
            },
        );
        assert!(d > 0.0, "{}: {d}", r.field);
        // The controller's own figure is this one, up to the sampling.
        assert!(
            (d - r.min_distance).abs() < 0.01,
            "{}: {d} vs {}",
            r.field,
            r.min_distance
        );
    }
    // The panel field's stagnation points lie in front of the inner corner, as the paper's
    // "around (2.5, 6.5)".
    for s in &out.runs[0].stagnation_points {
        assert!(
            (Point::new(s[0], s[1]) - Point::new(2.5, 6.5)).norm() < 1.0,
            "{s:?}"
        );
    }
    // From the dividing streamline the guard decides: left over the top of the L (y > 8),
    // right down its left side (x < 2); both reach, clear of it.
    let demo = &out.stagnation_demo;
    assert_eq!(demo.len(), 3);
    for d in demo {
        assert!(d.run.reached, "{:?}: {:?}", d.side, d.run.status);
        assert!(d.run.min_distance > 0.0);
    }
    let left = demo.iter().find(|d| d.side == Some(Side::Left)).unwrap();
    let right = demo.iter().find(|d| d.side == Some(Side::Right)).unwrap();
    assert_eq!(left.run.turns.len(), 1);
    assert_eq!(right.run.turns.len(), 1);
    assert!(left.run.poses.iter().any(|p| p[1] > 8.0));
    assert!(left.run.poses.iter().all(|p| p[0] > 2.0));
    assert!(right.run.poses.iter().any(|p| p[0] < 2.0));
    assert!(right.run.poses.iter().all(|p| p[1] < 8.0));
}

#[test]
fn the_arm_reaches_through_the_aperture_on_both_fields_without_touching() {
    let (out, _, _) = arm_runs(&ARM_LINKS, NullMotion::FollowFlow).expect("setting (51) runs");
    let obstacles = polys(&out.obstacles);
    let arm = Arm::new(Point::new(out.base[0], out.base[1]), out.links.clone()).unwrap();
    // The start is the paper's: the end effector at (−2, 8), the third link at 10°.
    let q0 = out.start_joints;
    let tip = arm.end_effector(&q0);
    assert!((tip - Point::new(-2.0, 8.0)).norm() < 1e-12);
    assert!(((q0[0] + q0[1] + q0[2]).to_degrees() - 10.0).abs() < 1e-9);
    for r in &out.runs {
        assert!(r.reached, "{}: {:?}", r.field, r.status);
        let last = *r.end_effector.last().unwrap();
        assert!((Point::new(last[0], last[1]) - Point::new(5.0, 9.0)).norm() < 0.31);
        let d = recheck(
            &r.joints,
            &obstacles,
            1e-3 * 17.0,
            |a, b| {
                (0..3)
                    .map(|j| (b[j] - a[j]).abs() * arm.reach_from(j))
                    .sum()
            },
            |c| {
                let p = arm.points(c);
                p.windows(2).map(|w| (w[0], w[1])).collect()
            },
        );
        assert!(d > 0.0, "{}: a link touches an obstacle ({d})", r.field);
        assert!(r.min_distance > 0.0);
    }
}
