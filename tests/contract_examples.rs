//! The scene format's own examples, planned exactly as written (`meshes/contract/`): a volume
//! with a goal ball smaller than the lattice, a polygon robot whose first start touches a
//! wall, an arm with a joint goal of tolerance 0.05 and one with an end-effector goal. Every
//! start reaches the goal; every path is checked here, by code that does not use the
//! planner's geometry, against the scene's exact solids or the robot's exact body, and its
//! end against the goal's stated tolerance; the potential has no interior local minimum.

use std::f64::consts::{PI, TAU};
use std::path::PathBuf;

use harmonic_cspace::check::check_path;
use harmonic_planner::cspace::ConfigPlanner;
use harmonic_planner::volume::VolumePlanner;
use harmonic_planner::{AnyScene, ConfigScene};

fn scene(name: &str) -> AnyScene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("meshes/contract")
        .join(name);
    AnyScene::from_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(TAU) - PI
}

#[test]
fn volume_example_reaches_its_small_goal_clear_of_every_solid() {
    let AnyScene::Volume(s) = scene("volume_example.json") else {
        panic!("a volume scene");
    };
    let planner = VolumePlanner::new(&s).expect("the contract's volume example plans");
    let report = planner.plan_report(&s.starts);
    assert_eq!(report.potential.interior_local_minima, 0);
    assert!(report.potential.max > report.potential.min);
    // The scene, by hand: the box through the workspace, the ball, the corner tetrahedron.
    let blocked = |p: [f64; 3]| {
        let in_box = (3.0..=7.0).contains(&p[0]) && (3.0..=7.0).contains(&p[1]);
        let in_ball =
            (p[0] - 2.0).powi(2) + (p[1] - 8.0).powi(2) + (p[2] - 5.0).powi(2) < 1.0 - 1e-12;
        let in_tet = p.iter().all(|&c| c > 1e-12) && p[0] + p[1] + p[2] < 1.0 - 1e-12;
        let outside = p.iter().any(|&c| !(-1e-12..=10.0 + 1e-12).contains(&c));
        in_box || in_ball || in_tet || outside
    };
    for path in &report.paths {
        assert!(
            path.status.reached_goal(),
            "{:?}: {:?}",
            path.start,
            path.status
        );
        let end = path.points.last().expect("points");
        let to_goal =
            ((end[0] - 9.0).powi(2) + (end[1] - 9.0).powi(2) + (end[2] - 9.0).powi(2)).sqrt();
        assert!(
            to_goal <= 0.3 + 1e-9,
            "ends {to_goal} from the goal's centre"
        );
        for w in path.points.windows(2) {
            let n = 200;
            for k in 0..=n {
                let t = k as f64 / n as f64;
                let p = [0, 1, 2].map(|a| w[0][a] + t * (w[1][a] - w[0][a]));
                assert!(
                    !blocked(p),
                    "{:?}: the path enters a solid at {p:?}",
                    path.start
                );
            }
        }
    }
}

/// The arm's tip: base at the origin, link i at the sum of the first i angles.
fn tip(links: &[f64], q: &[f64]) -> [f64; 2] {
    let (mut x, mut y, mut angle) = (0.0, 0.0, 0.0);
    for (l, a) in links.iter().zip(q) {
        angle += a;
        x += l * angle.cos();
        y += l * angle.sin();
    }
    [x, y]
}

fn plan_config(name: &str) -> (ConfigScene, ConfigPlanner, Vec<Vec<Vec<f64>>>) {
    let AnyScene::Config(s) = scene(name) else {
        panic!("{name}: a configuration-space scene");
    };
    let planner = ConfigPlanner::new(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
    let report = planner.plan_report(&s.starts);
    assert_eq!(report.potential.interior_local_minima, 0, "{name}");
    let mut paths = Vec::new();
    for p in &report.paths {
        assert!(
            p.status.reached_goal(),
            "{name} from {:?}: {:?}",
            p.start,
            p.status
        );
        let configs = p.configurations();
        assert_eq!(&configs[0], &p.start);
        // Overlapping nothing anywhere; touching only where the start itself touches.
        let all = check_path(
            planner.space().robot(),
            planner.space().world(),
            &configs,
            1e-3,
        );
        assert!(all.min_clearance >= 0.0, "{name}: {:?}", all);
        paths.push(configs);
    }
    (*s, planner, paths)
}

#[test]
fn polygon_example_reaches_the_pose_within_its_tolerance() {
    let (scene, planner, paths) = plan_config("polygon_example.json");
    let goal = scene.goal.pose.expect("a pose goal");
    for configs in &paths {
        let q = configs.last().expect("configurations");
        assert!((q[0] - goal[0]).hypot(q[1] - goal[1]) <= 0.2, "{q:?}");
        assert!(wrap(q[2] - goal[2]).abs() <= 0.2, "{q:?}");
        // After leaving the wall the first start touches, the robot keeps clear of everything.
        let rest = check_path(
            planner.space().robot(),
            planner.space().world(),
            &configs[1..],
            1e-3,
        );
        assert!(rest.min_clearance >= 0.0, "{rest:?}");
    }
    // The first start touches the wall x = 0 (the rectangle's back edge): led off it.
    assert_eq!(paths[0][0], vec![1.0, 1.5, 0.0]);
}

#[test]
fn arm_joints_example_ends_within_the_joint_tolerance() {
    let (_, _, paths) = plan_config("arm_joints_example.json");
    for configs in &paths {
        let q = configs.last().expect("configurations");
        for (a, g) in q.iter().zip([1.2, -0.4, 0.3]) {
            assert!(wrap(a - g).abs() <= 0.05, "{q:?}");
        }
    }
}

#[test]
fn arm_tip_example_ends_within_the_tip_tolerance() {
    let (_, _, paths) = plan_config("arm_tip_example.json");
    for configs in &paths {
        let q = configs.last().expect("configurations");
        let t = tip(&[2.0, 1.5, 1.0], q);
        assert!((t[0] + 1.5).hypot(t[1] - 3.0) <= 0.1, "tip {t:?} at {q:?}");
    }
}
