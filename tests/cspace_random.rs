//! Seeded configuration-space scenes nobody tuned (`harmonic_fixtures::ConfigCase`): a polygon
//! robot with a pose tolerance under 0.2, two- and three-link arms with joint tolerances of
//! 0.05–0.2 and an end-effector tolerance. Every start that a conservative flood fill over
//! configurations connects to the goal reaches it: the last configuration meets the goal as
//! the scene states it (checked by the fixture, the tip by its own forward kinematics), and
//! every motion is collision-free against the exact polygons.

use harmonic_cspace::ConfigClass;
use harmonic_cspace::check::{check_path, exact_clearance};
use harmonic_fixtures::ConfigCase;
use harmonic_planner::AnyScene;
use harmonic_planner::cspace::ConfigPlanner;

/// Checks `case` and returns its planner.
fn check(case: &ConfigCase, name: &str) -> ConfigPlanner {
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
    planner
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
/// the default spacing (the arm's tip grazing a small circle at full reach). On the uniform
/// lattice a tetrahedron spanned it and one traced motion passed through the circle; the
/// lattice is now graded where its vertices miss such a sliver, and every start reaches the
/// goal without touching anything (checked on the exact geometry).
#[test]
fn a_sliver_of_collision_thinner_than_the_lattice_is_graded_and_avoided() {
    let case = ConfigCase::arm(10, 3, false, 8);
    let scene = match AnyScene::from_json(&case.json) {
        Ok(AnyScene::Config(s)) => s,
        other => panic!("{:?}", other.err()),
    };
    let planner = ConfigPlanner::new(&scene).expect("planner");
    let space = planner.space();
    let report = planner.plan_report(&case.starts);
    assert!(report.mesh.graded > 0, "{:?}", report.mesh);
    let grazing = [-0.9979097541823152, 0.1985225262267134, -0.345714405724864];
    let mut reached = 0;
    for start in &case.starts {
        let p = planner.plan(start);
        if !matches!(space.classify(start), ConfigClass::Free) {
            continue;
        }
        assert!(p.status.reached_goal(), "{start:?}: {}", p.status.as_str());
        let motion = check_path(space.robot(), space.world(), &p.configurations(), 1e-3);
        assert!(motion.min_clearance > 0.0, "{start:?}: {motion:?}");
        reached += usize::from(
            start
                .iter()
                .zip(&grazing)
                .all(|(a, b)| (a - b).abs() < 1e-12),
        );
    }
    assert_eq!(
        reached, 1,
        "the grazing start is among the free ones and reached"
    );
}

/// A circle of radius 0.01 on the arc a two-link arm's tip sweeps at full reach, under a
/// lattice of spacing 1: its image in configuration space is a sliver thinner than the
/// finest grading (a quarter spacing), and the straight start's motion passes through it.
/// The planner checks every reached path against the exact geometry. Built for a scene whose
/// starts include the straight one, it sees that motion meet the circle and meshes again,
/// graded finer around where it did: every start is then reached without touching
/// anything. Built for a scene without it, a later plan from the straight start is
/// `collision`, naming the circle, never `reached_goal`.
#[test]
fn a_motion_through_an_unresolved_obstacle_is_meshed_again_or_a_collision() {
    let scene = |starts: &str| {
        let json = format!(
            r#"{{"workspace": [[-5, -5], [5, -5], [5, 5], [-5, 5]],
            "robot": {{"arm": {{"base": [0.0, 0.0], "links": [2.0, 1.0], "width": 0.02}}}},
            "obstacles": [{{"circle": {{"center": [2.4760068, 1.6939274], "radius": 0.01}}}},
                          {{"circle": {{"center": [-2.2, -1.5], "radius": 0.5}}}}],
            "goal": {{"joints": [1.2, 0.0], "tolerance": 0.05}},
            "starts": {starts},
            "mesh": {{"spacing": 1.0, "margin": 0.01}}}}"#
        );
        match AnyScene::from_json(&json) {
            Ok(AnyScene::Config(s)) => s,
            other => panic!("{:?}", other.err()),
        }
    };
    let starts = [[0.0, 0.0], [0.0, 0.3], [0.0, -0.3]];
    let statuses = |planner: &ConfigPlanner| -> Vec<String> {
        let space = planner.space();
        starts
            .iter()
            .map(|start| {
                let p = planner.plan(start);
                let motion = check_path(space.robot(), space.world(), &p.configurations(), 1e-3);
                if p.status.reached_goal() {
                    assert!(motion.min_clearance > 0.0, "{start:?}: {motion:?}");
                } else {
                    let why = p.blocked_by.clone().unwrap_or_default();
                    assert!(why.contains("obstacle 0"), "{start:?}: {why}");
                }
                p.status.as_str().to_string()
            })
            .collect()
    };
    let once = ConfigPlanner::new(&scene("[[0.0, 0.3]]")).expect("planner");
    assert_eq!(once.plan_report(&[]).mesh.refined_near, 0);
    assert_eq!(
        statuses(&once),
        ["collision", "reached_goal", "reached_goal"]
    );
    let again =
        ConfigPlanner::new(&scene("[[0.0, 0.0], [0.0, 0.3], [0.0, -0.3]]")).expect("planner");
    assert!(again.plan_report(&[]).mesh.refined_near >= 1);
    assert_eq!(statuses(&again), ["reached_goal"; 3]);
}

/// Seed 707 of the held-out sweep (`examples/cspace_reach.rs`): a 3-link arm whose tip, at
/// full reach, grazes a circle of radius 0.23; two starts' motions entered the circle's
/// image in configuration space where the mesh's faces cut across its edge by more than the
/// margin (`collision` on the first build). Meshed again, graded finer around where they met
/// it, every connected start reaches the goal collision-free.
#[test]
fn an_image_the_mesh_cuts_across_is_meshed_again_finer() {
    let planner = check(&ConfigCase::arm(707, 3, true, 8), "3-link tip 707");
    let report = planner.plan_report(&[]);
    assert!(report.mesh.refined_near >= 1, "{:?}", report.mesh);
}
