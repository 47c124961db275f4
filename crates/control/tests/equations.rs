//! The controllers on hand-built flows (a uniform stream, a single source, a saddle) move as
//! Kim & Khosla's equations say.

use approx::assert_relative_eq;
use harmonic_control::arm::{arm_step, follow_flow_null_motion, null_motion_term};
use harmonic_control::bar::{Operation, bar_step, run_bar, wrap};
use harmonic_control::{
    Arm, ArmParams, BarParams, BarRobot, ControlError, Flow, NullMotion, Obstacles, Side, Source,
    StagnationGuard, Uniform,
};
use harmonic_mesh::{Point, Vector};
use nalgebra::{DMatrix, DVector};

fn square(lo: [f64; 2], hi: [f64; 2]) -> Vec<Point> {
    vec![
        Point::new(lo[0], lo[1]),
        Point::new(hi[0], lo[1]),
        Point::new(hi[0], hi[1]),
        Point::new(lo[0], hi[1]),
    ]
}

#[test]
fn a_turn_larger_than_the_saturation_scales_every_displacement_by_h() {
    // (43): Δη = atan2(0, 1) − 0.5 = −0.5 > Δη_max = 0.1, so (46) H = 0.2 and (47–49)
    // scale the step along the flow, d_max (cos 0, sin 0), and Δη.
    let p = BarParams::default();
    let s = bar_step([0.0, 0.0, 0.5], Vector::new(1.0, 0.0), &[], &p);
    assert_eq!(s.operation, Operation::Potential);
    assert_relative_eq!(s.saturation, 0.2, epsilon = 1e-15);
    assert_relative_eq!(s.delta[0], 0.2 * p.d_max, epsilon = 1e-15);
    assert_relative_eq!(s.delta[1], 0.0, epsilon = 1e-15);
    assert_relative_eq!(s.delta[2], -0.1, epsilon = 1e-15);
}

#[test]
fn a_small_turn_is_taken_whole_and_the_step_is_d_max_along_the_flow() {
    let p = BarParams::default();
    let dir = Vector::new(3.0, 4.0); // ψ = atan2(4, 3)
    let eta = 0.9;
    let s = bar_step([1.0, 1.0, eta], dir * 7.0, &[], &p);
    let psi = 4f64.atan2(3.0);
    assert!((psi - eta).abs() < p.d_eta_max);
    assert_relative_eq!(s.saturation, 1.0);
    assert_relative_eq!(s.delta[2], psi - eta, epsilon = 1e-15);
    // (44–45): d_max cos(η + Δη), d_max sin(η + Δη), whatever the flow's speed.
    assert_relative_eq!(s.delta[0], p.d_max * 0.6, epsilon = 1e-15);
    assert_relative_eq!(s.delta[1], p.d_max * 0.8, epsilon = 1e-15);
}

#[test]
fn a_bar_beside_a_single_source_runs_straight_away_from_it_trailing_behind() {
    let source = Source {
        at: Point::new(0.0, 0.0),
        strength: 5.0,
    };
    let robot = BarRobot { length: 1.0 };
    let goal = Point::new(30.0, 30.0);
    let params = BarParams {
        max_steps: 200,
        ..BarParams::default()
    };
    // Leading point on the diagonal, the bar already along it: every step is radial.
    let run = run_bar(
        &source,
        &Obstacles::default(),
        None,
        &robot,
        [2.0, 2.0, std::f64::consts::FRAC_PI_4],
        goal,
        &params,
    )
    .expect("runs");
    for w in run.poses.windows(2) {
        let (a, b) = (Point::new(w[0][0], w[0][1]), Point::new(w[1][0], w[1][1]));
        assert_relative_eq!((b - a).norm(), params.d_max, epsilon = 1e-12);
        let radial = (a - source.at).normalize();
        assert_relative_eq!((b - a).normalize().dot(&radial), 1.0, epsilon = 1e-12);
        assert_relative_eq!(w[1][2], std::f64::consts::FRAC_PI_4, epsilon = 1e-12);
    }
    // Off the diagonal, the bar turns into the radial direction at Δη_max per period.
    let run = run_bar(
        &source,
        &Obstacles::default(),
        None,
        &robot,
        [2.0, 0.0, 1.5],
        goal,
        &params,
    )
    .expect("runs");
    let turns: Vec<f64> = run.poses.windows(2).map(|w| w[1][2] - w[0][2]).collect();
    assert_relative_eq!(turns[0], -params.d_eta_max, epsilon = 1e-12);
    let last = run.poses.last().unwrap();
    let radial = last[1].atan2(last[0]);
    assert!(wrap(last[2] - radial).abs() < 1e-3, "{last:?}");
}

#[test]
fn the_obstacle_operation_turns_the_tail_away_from_the_obstacle() {
    // A bar along +x led from (5, 0.25) with its tail 0.15 above a wall-like box's top
    // edge y = 0.1 near the tail: the secondary control point is the tail, and φ_o turns the
    // bar about the leading point so that the tail rises.
    let obstacles = Obstacles::new(vec![square([3.0, -1.0], [4.5, 0.1])]).unwrap();
    let robot = BarRobot { length: 2.0 };
    let pose = [5.0, 0.25, 0.0];
    let (a, b) = robot.ends(pose);
    let params = BarParams::default();
    let contacts = obstacles.contacts(a, b, params.delta, 0);
    assert!(!contacts.is_empty());
    let s = bar_step(pose, Vector::new(1.0, 0.0), &contacts, &params);
    assert_eq!(s.operation, Operation::Obstacle);
    // The tail is behind the leading point (−x): lifting it means turning clockwise.
    assert!(s.delta[2] < 0.0, "{:?}", s.delta);
    let next = [pose[0], pose[1], pose[2] + s.delta[2]];
    let d0 = obstacles.segment_distance(a, b).unwrap().0;
    let (a1, b1) = robot.ends(next);
    let d1 = obstacles.segment_distance(a1, b1).unwrap().0;
    assert!(d1 > d0, "{d0} → {d1}");
}

#[test]
fn a_concave_obstacle_gives_one_secondary_point_per_side_approached() {
    // A U open to the top; a segment lying across its mouth, just above both arms.
    let u = vec![
        Point::new(0.0, 0.0),
        Point::new(3.0, 0.0),
        Point::new(3.0, 2.0),
        Point::new(2.0, 2.0),
        Point::new(2.0, 1.0),
        Point::new(1.0, 1.0),
        Point::new(1.0, 2.0),
        Point::new(0.0, 2.0),
    ];
    let obstacles = Obstacles::new(vec![u]).unwrap();
    let c = obstacles.contacts(Point::new(0.5, 2.1), Point::new(2.5, 2.1), 0.2, 0);
    assert!(c.iter().any(|k| k.robot_point.x < 1.5), "{c:?}");
    assert!(c.iter().any(|k| k.robot_point.x > 1.5), "{c:?}");
    for k in &c {
        assert_relative_eq!(k.distance, 0.1, epsilon = 1e-12);
        assert_relative_eq!(
            (k.robot_point - k.obstacle_point).norm(),
            k.distance,
            epsilon = 1e-12
        );
    }
    // Away from the mouth, none.
    assert!(
        obstacles
            .contacts(Point::new(0.5, 2.5), Point::new(2.5, 2.5), 0.2, 0)
            .is_empty()
    );
}

fn arm() -> Arm {
    Arm::new(Point::new(0.0, 0.0), vec![2.0, 1.5, 1.0]).unwrap()
}

#[test]
fn the_net_motion_moves_the_end_effector_along_the_flow() {
    let arm = arm();
    let q = [0.3, 0.8, -0.4];
    let flow = Uniform(Vector::new(0.6, -0.8));
    let params = ArmParams {
        null_motion: NullMotion::None,
        ..ArmParams::default()
    };
    let step = arm_step(&arm, &q, &flow, flow.0, &[], &params).expect("a step");
    // (56): the joint motion has norm Δθ_max.
    assert_relative_eq!(step.total().norm(), params.d_theta_max, epsilon = 1e-14);
    // J_e Δθ = H ΔX_e: along the flow.
    let je = arm.jacobian(&q);
    let moved = &je * step.total();
    let dir = Vector::new(moved[0], moved[1]).normalize();
    assert_relative_eq!(dir.dot(&flow.0), 1.0, epsilon = 1e-12);
    // And for a finite step, to first order.
    let q1: Vec<f64> = q
        .iter()
        .zip(step.total().iter())
        .map(|(a, b)| a + b)
        .collect();
    let real = arm.end_effector(&q1) - arm.end_effector(&q);
    assert!((real.normalize().dot(&flow.0) - 1.0).abs() < 1e-3);
}

#[test]
fn the_null_motion_leaves_the_end_effector_still_to_first_order() {
    let arm = arm();
    let q = [0.3, 0.8, -0.4];
    let je = arm.jacobian(&q);
    let pinv = je.clone().pseudo_inverse(1e-12).unwrap();
    let projector = DMatrix::<f64>::identity(3, 3) - &pinv * &je;
    let net = &pinv * DVector::from_column_slice(&[0.05, 0.02]);
    // A secondary control point on the first link, pushed away from an obstacle below it.
    let c = arm.points(&q)[0] + (arm.points(&q)[1] - arm.points(&q)[0]) * 0.6;
    let dh = null_motion_term(&arm, &q, 0, c, Vector::new(0.0, 0.1), &projector, &net);
    assert!(dh.norm() > 1e-3, "the term is not trivial: {dh}");
    assert!(
        (&je * &dh).norm() < 1e-12 * dh.norm(),
        "J_e Δθ_h = {}",
        &je * &dh
    );
    // Second order: the end effector moves O(ε²) along ε Δθ_h.
    let dir = &dh / dh.norm();
    let moves: Vec<f64> = [1e-2, 1e-3]
        .iter()
        .map(|&eps| {
            let q1: Vec<f64> = q.iter().zip(dir.iter()).map(|(a, d)| a + eps * d).collect();
            (arm.end_effector(&q1) - arm.end_effector(&q)).norm()
        })
        .collect();
    assert!(moves[0] < 1e-2 * 5.0 * 1e-2, "{moves:?}");
    assert_relative_eq!(moves[0] / moves[1], 100.0, max_relative = 0.05);
    // It moves the secondary point up, as asked (the part of the request in the null space).
    let q1: Vec<f64> = q.iter().zip(dh.iter()).map(|(a, d)| a + 1e-3 * d).collect();
    let pts1 = arm.points(&q1);
    let c1 = pts1[0] + (pts1[1] - pts1[0]) * 0.6;
    assert!(c1.y > c.y);
    // The potential operation's null motion is in the null space too.
    let flow = Uniform(Vector::new(1.0, 0.3));
    let ff = follow_flow_null_motion(&arm, &q, &flow, 0.1, &projector, &net);
    assert!((&je * &ff).norm() < 1e-12 * ff.norm().max(1e-300));
}

#[test]
fn an_arm_in_a_single_source_pushes_its_end_effector_away_from_it() {
    let arm = arm();
    let q = [0.2, 0.6, 0.4];
    let e = arm.end_effector(&q);
    let source = Source {
        at: Point::new(e.x - 1.0, e.y - 0.5),
        strength: 3.0,
    };
    let v = source.velocity(e).unwrap();
    let step = arm_step(&arm, &q, &source, v, &[], &ArmParams::default()).expect("a step");
    let q1: Vec<f64> = q
        .iter()
        .zip(step.total().iter())
        .map(|(a, b)| a + b)
        .collect();
    let e1 = arm.end_effector(&q1);
    assert!((e1 - source.at).norm() > (e - source.at).norm());
}

/// v = (x, −y): a saddle at the origin, in along ±y, out along ±x.
struct SaddleFlow;
impl Flow for SaddleFlow {
    fn velocity(&self, p: Point) -> Option<Vector> {
        Some(Vector::new(p.x, -p.y))
    }
}

#[test]
fn the_guard_turns_to_the_chosen_side_along_the_outflow() {
    let origin = Point::new(0.0, 0.0);
    for (side, want) in [(Side::Left, 1.0), (Side::Right, -1.0)] {
        let g = StagnationGuard::new(&SaddleFlow, &[origin], 0.5, side);
        let axis = g.saddles[0].outflow.expect("an axis");
        assert_relative_eq!(axis.x.abs(), 1.0, epsilon = 1e-9);
        // Coming down the +y axis: left of the incoming (0, −1) is +x.
        let p = Point::new(0.0, 0.3);
        let (k, d) = g
            .steer(p, SaddleFlow.velocity(p).unwrap())
            .expect("steered");
        assert_eq!(k, 0);
        assert_relative_eq!(d.x, want, epsilon = 1e-9);
        // The upstream point is on the inflow axis, where the flow comes in.
        let up = g.saddles[0].upstream(&SaddleFlow, 0.3).unwrap();
        assert_relative_eq!(up.x, 0.0, epsilon = 1e-9);
        // Moving away from it along the outflow: no steering.
        let q = Point::new(0.3, 0.01);
        assert!(g.steer(q, SaddleFlow.velocity(q).unwrap()).is_none());
        // Out of the radius: none either.
        let far = Point::new(0.0, 2.0);
        assert!(g.steer(far, SaddleFlow.velocity(far).unwrap()).is_none());
    }
}

#[test]
fn the_guard_decides_the_side_where_the_flow_leaves_it_to_rounding() {
    // On the exact inflow axis the flow has no side: the bar reaches the saddle, turns back
    // and forth, and leaves along whichever side rounding (cos(−π/2) ≠ 0) favours. The
    // guard picks the side: left of the incoming −y is +x, toward the goal; right is −x,
    // away along the other outflow branch.
    let robot = BarRobot { length: 0.5 };
    let params = BarParams {
        max_steps: 400,
        ..BarParams::default()
    };
    let start = [0.0, 1.0, -std::f64::consts::FRAC_PI_2];
    let goal = Point::new(3.0, 0.0);
    let origin = [Point::new(0.0, 0.0)];
    let run = |side| {
        let g = StagnationGuard::new(&SaddleFlow, &origin, 0.5, side);
        run_bar(
            &SaddleFlow,
            &Obstacles::default(),
            Some(&g),
            &robot,
            start,
            goal,
            &params,
        )
        .unwrap()
    };
    let left = run(Side::Left);
    assert!(left.reached(), "{:?}", left.status);
    assert_eq!(left.turns.len(), 1);
    assert_eq!(left.turns[0].side, Side::Left);
    assert!(left.poses.iter().all(|p| p[0] >= -1e-9));
    let right = run(Side::Right);
    assert!(!right.reached());
    assert!(
        right.poses.last().unwrap()[0] < -2.0,
        "{:?}",
        right.poses.last()
    );
}

#[test]
fn bad_inputs_get_typed_errors() {
    let robot = BarRobot { length: 1.0 };
    let flow = Uniform(Vector::new(1.0, 0.0));
    let bad = BarParams {
        d_max: -1.0,
        ..BarParams::default()
    };
    let e = run_bar(
        &flow,
        &Obstacles::default(),
        None,
        &robot,
        [0.0; 3],
        Point::new(1.0, 0.0),
        &bad,
    )
    .unwrap_err();
    assert!(
        matches!(e, ControlError::InvalidParameter { name: "d_max", .. }),
        "{e}"
    );
    let box_ = Obstacles::new(vec![square([-1.0, -1.0], [1.0, 1.0])]).unwrap();
    let e = run_bar(
        &flow,
        &box_,
        None,
        &robot,
        [0.0; 3],
        Point::new(5.0, 0.0),
        &BarParams::default(),
    )
    .unwrap_err();
    assert!(
        matches!(e, ControlError::StartInCollision { obstacle: 0, .. }),
        "{e}"
    );
    assert!(Arm::new(Point::new(0.0, 0.0), vec![1.0]).is_err());
    assert!(Arm::new(Point::new(0.0, 0.0), vec![1.0, f64::NAN]).is_err());
    assert!(Obstacles::new(vec![vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0)]]).is_err());
    let e = harmonic_control::arm::run_arm(
        &flow,
        &Obstacles::default(),
        &arm(),
        &[0.0, 0.0],
        Point::new(1.0, 1.0),
        &ArmParams::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("2 joint angles for 3 links"), "{e}");
}
