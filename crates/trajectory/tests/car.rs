mod common;

use common::{GridQueries, laplace_psi, nodal_gradients};
use harmonic_fixtures::{Cell, Grid, Rng};
use harmonic_mesh::Point;
use harmonic_trajectory::{
    CarOptions, CarSpeed, CarTarget, Collision, Footprint, P1Field, SmoothP1Field, TraceError,
    TraceStatus, drive, max_pose_curvature,
};

fn scene() -> Grid {
    let mut g = Grid::new(40, 40, 0.25);
    g.mark(3.0, 1.0, 4.0, 4.9, Cell::Obstacle(0));
    g.mark(3.0, 5.1, 4.0, 9.0, Cell::Obstacle(1));
    g.mark(6.0, 3.0, 7.0, 7.0, Cell::Obstacle(2));
    g.mark(8.5, 4.5, 9.0, 5.5, Cell::Goal(0));
    g
}

#[test]
fn cars_reach_the_goal_from_random_poses_within_the_curvature_limit() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 3000);
    let grads = nodal_gradients(&mesh, &psi);
    let f = SmoothP1Field::ascending(&mesh, &psi, &grads).unwrap();
    let (l, dmax) = (0.2, 0.6);
    let kmax = f64::tan(dmax) / l;
    let opts = CarOptions::new(l, dmax, 0.02);
    let mut rng = Rng(777);
    // Free poses: the car has room to turn (its smallest turning radius L / tan δmax) before
    // meeting a wall or obstacle; closer in and facing one, a forward-only car cannot avoid it.
    let r_min = l / f64::tan(dmax);
    let starts: Vec<Point> = g
        .random_free(&mut rng, 2000)
        .into_iter()
        .filter(|p| g.clearance(*p) >= r_min)
        .take(200)
        .collect();
    assert_eq!(starts.len(), 200);
    let mut reached = 0;
    let mut failures = Vec::new();
    for s in &starts {
        let th = rng.next_f64() * std::f64::consts::TAU - std::f64::consts::PI;
        let car = drive(&f, [s.x, s.y, th], &opts, None).unwrap();
        assert!(car.max_curvature <= kmax * (1.0 + 1e-12));
        assert!(
            max_pose_curvature(&car.poses) <= kmax * (1.0 + 1e-6),
            "start {s}"
        );
        for w in car.poses.windows(2) {
            let (a, b) = (Point::new(w[0][0], w[0][1]), Point::new(w[1][0], w[1][1]));
            assert!(
                !g.segment_hits_obstacle(a, b),
                "car from {s} crosses an obstacle at {a}"
            );
        }
        if car.status.reached_goal() {
            reached += 1;
        } else {
            failures.push((*s, th, car.status));
        }
    }
    let rate = reached as f64 / starts.len() as f64;
    eprintln!("car success rate {rate:.3}; failures: {failures:?}");
    assert!(rate >= 0.95, "rate {rate}: {failures:?}");
}

#[test]
fn footprint_collisions_targets_and_speed_options() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 3000);
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    // A wide car facing obstacle 0 from close by: its footprint hits it.
    let collides = |c: &[Point; 4]| c.iter().any(|p| g.cell_at(*p) != Some(Cell::Free));
    let col = Collision {
        footprint: Footprint {
            rear: 0.1,
            front: 0.5,
            half_width: 0.3,
        },
        collides: &collides,
    };
    let car = drive(
        &f,
        [2.3, 2.0, 0.0],
        &CarOptions::new(0.3, 0.3, 0.05),
        Some(&col),
    )
    .unwrap();
    match car.status {
        TraceStatus::Collision { at: Some(at) } => assert!(!collides(&col.footprint.corners(at))),
        other => panic!("{other:?}"),
    }
    for p in &car.poses {
        assert!(!collides(&col.footprint.corners(*p)));
    }
    // A target with a tolerance ends the drive early.
    let mut opts = CarOptions::new(0.2, 0.6, 0.02);
    let full = drive(&f, [7.5, 8.5, 0.0], &opts, None).unwrap();
    assert_eq!(full.status, TraceStatus::ReachedGoal(0));
    let mid = full.poses[full.poses.len() / 2];
    let center = Point::new(mid[0] + 0.01, mid[1]);
    opts.target = Some(CarTarget {
        center,
        tolerance: 0.05,
        goal: 7,
    });
    let car = drive(&f, [7.5, 8.5, 0.0], &opts, None).unwrap();
    assert_eq!(car.status, TraceStatus::ReachedGoal(7));
    assert!(car.poses.len() < full.poses.len());
    let last = car.poses.last().unwrap();
    assert!((Point::new(last[0], last[1]) - center).norm() <= 0.05);
    // Arc length proportional to the gradient.
    let mut opts = CarOptions::new(0.2, 0.6, 0.05);
    opts.speed = CarSpeed::ProportionalToGradient {
        gain: 0.05,
        min_step: 0.005,
    };
    let car = drive(&f, [1.0, 1.0, 0.0], &opts, None).unwrap();
    assert_eq!(car.status, TraceStatus::ReachedGoal(0));
    let steps: Vec<f64> = car
        .poses
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .collect();
    let (lo, hi) = steps
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &s| (a.min(s), b.max(s)));
    assert!(
        lo < hi * 0.9 && hi <= 0.05 + 1e-12,
        "steps vary with |∇ψ|: {lo} .. {hi}"
    );
    // Invalid options and starts.
    assert!(matches!(
        drive(&f, [1.0, 1.0, 0.0], &CarOptions::new(0.2, 2.0, 0.02), None),
        Err(TraceError::InvalidOption {
            name: "max_steer",
            ..
        })
    ));
    let car = drive(&f, [3.5, 2.0, 0.0], &CarOptions::new(0.2, 0.6, 0.02), None).unwrap();
    assert_eq!(car.status, TraceStatus::StartInObstacle);
}
