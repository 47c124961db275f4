//! Seeded configuration-space scenes nobody tuned (`harmonic_fixtures::ConfigCase`): a polygon
//! robot with a pose tolerance under 0.2, two- and three-link arms with joint tolerances of
//! 0.05–0.2 and an end-effector tolerance. Every start that a conservative flood fill over
//! configurations connects to the goal reaches it: the last configuration meets the goal as
//! the scene states it (checked by the fixture, the tip by its own forward kinematics), and
//! every motion is collision-free against the exact polygons.

use harmonic_cspace::check::{check_path, exact_clearance};
use harmonic_fixtures::ConfigCase;
use harmonic_planner::AnyScene;
use harmonic_planner::cspace::ConfigPlanner;

fn check(case: &ConfigCase, name: &str) {
    let scene = match AnyScene::from_json(&case.json) {
        Ok(AnyScene::Config(s)) => s,
        other => panic!("{name}: {:?}", other.err()),
    };
    let planner = ConfigPlanner::new(&scene).unwrap_or_else(|e| panic!("{name}: {e}"));
    let space = planner.space();
    let clearance = |q: &[f64]| exact_clearance(space.robot(), space.world(), q);
    let in_goal = |q: &[f64]| space.goal_value(q) <= 0.0;
    let cells = if case.range.len() == 2 { 96 } else { 40 };
    let connected = case.connected_starts(cells, &clearance, &in_goal);
    let mut counted = 0;
    for (start, &conn) in case.starts.iter().zip(&connected) {
        if !conn {
            continue;
        }
        counted += 1;
        let p = planner.plan(start);
        assert!(
            p.status.reached_goal(),
            "{name} from {start:?}: {:?}",
            p.status
        );
        let configs = p.configurations();
        let last = configs.last().expect("configurations");
        assert!(
            case.goal_met(last),
            "{name} from {start:?}: ends at {last:?}"
        );
        let motion = check_path(space.robot(), space.world(), &configs, 1e-3);
        assert!(
            motion.min_clearance > 0.0,
            "{name} from {start:?}: {motion:?}"
        );
    }
    assert!(counted >= 2, "{name}: only {counted} connected starts");
}

#[test]
fn polygon_robots_reach_small_pose_goals() {
    for seed in [4u64, 8] {
        check(&ConfigCase::polygon(seed, 8), &format!("polygon {seed}"));
    }
}

#[test]
fn two_link_arms_reach_small_joint_goals() {
    for seed in [1u64, 5] {
        check(
            &ConfigCase::arm(seed, 2, false, 8),
            &format!("2-link {seed}"),
        );
    }
}

#[test]
fn three_link_arms_reach_joint_and_tip_goals() {
    check(&ConfigCase::arm(2, 3, false, 8), "3-link joints 2");
    check(&ConfigCase::arm(7, 3, true, 8), "3-link tip 7");
}

/// Seed 10's goal lies beyond an obstacle's image in configuration space that is thinner than
/// the default spacing (the arm's tip grazing a small circle at full reach): stuffing leaves a
/// tetrahedron across it, and the traced motion would pass through the circle. The planner
/// checks every reached path against the exact geometry: that start is `collision`, naming
/// the circle, never `reached_goal`; every path it calls reached is collision-free.
#[test]
fn a_motion_through_an_unresolved_obstacle_is_a_collision_not_a_reach() {
    let case = ConfigCase::arm(10, 3, false, 8);
    let scene = match AnyScene::from_json(&case.json) {
        Ok(AnyScene::Config(s)) => s,
        other => panic!("{:?}", other.err()),
    };
    let planner = ConfigPlanner::new(&scene).expect("planner");
    let space = planner.space();
    let grazing = [-0.9979097541823152, 0.1985225262267134, -0.345714405724864];
    let mut collisions = 0;
    for start in &case.starts {
        let p = planner.plan(start);
        let motion = check_path(space.robot(), space.world(), &p.configurations(), 1e-3);
        if p.status.reached_goal() {
            assert!(motion.min_clearance > 0.0, "{start:?}: {motion:?}");
        }
        if p.status == harmonic_trajectory::volume::VolumeTraceStatus::Collision {
            collisions += 1;
            let why = p.blocked_by.clone().unwrap_or_default();
            assert!(why.contains("obstacle 0"), "{start:?}: {why}");
        }
        let same = start
            .iter()
            .zip(&grazing)
            .all(|(a, b)| (a - b).abs() < 1e-12);
        if same {
            assert_eq!(p.status.as_str(), "collision", "{start:?}");
        }
    }
    assert!(collisions >= 1);
}
