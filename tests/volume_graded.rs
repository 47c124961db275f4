//! What the uniform stuffing lattice lost and the graded one keeps: a window narrower than
//! the lattice in a wall (a ball robot passes it), and a plate thinner than the lattice (no
//! path may cross it). Paths are checked against the boxes by distances computed here.

use harmonic_planner::AnyScene;
use harmonic_planner::volume::VolumePlanner;

fn planner(json: &str) -> VolumePlanner {
    let AnyScene::Volume(scene) = AnyScene::from_json(json).expect("parses") else {
        panic!("a volume scene");
    };
    VolumePlanner::new(&scene).expect("plans")
}

/// Signed distance from `p` to the box `[lo, hi]` (negative inside).
fn box_distance(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    let q = [0, 1, 2].map(|a| (lo[a] - p[a]).max(p[a] - hi[a]));
    let out = q.iter().map(|c| c.max(0.0).powi(2)).sum::<f64>().sqrt();
    out + q[0].max(q[1]).max(q[2]).min(0.0)
}

#[test]
fn a_window_narrower_than_the_lattice_lets_the_robot_through() {
    // A wall at x = 5 with a 0.8 m square window; the robot's radius 0.3 leaves 0.2 m, less
    // than half the default lattice's spacing (about 0.39 m), which closed it.
    let boxes = [
        ([4.9, -1.0, -1.0], [5.1, 4.6, 11.0]),
        ([4.9, 5.4, -1.0], [5.1, 11.0, 11.0]),
        ([4.9, 4.6, -1.0], [5.1, 5.4, 4.6]),
        ([4.9, 4.6, 5.4], [5.1, 5.4, 11.0]),
    ];
    let obstacles: Vec<String> = boxes
        .iter()
        .map(|(lo, hi)| format!(r#"{{"box": {{"min": {lo:?}, "max": {hi:?}}}}}"#))
        .collect();
    let json = format!(
        r#"{{"dimension": 3, "workspace": {{"box": {{"min": [0, 0, 0], "max": [10, 10, 10]}}}},
        "obstacles": [{}], "robot": {{"radius": 0.3}},
        "goal": {{"sphere": {{"center": [9, 5, 5], "radius": 0.4}}}},
        "starts": [[1, 5, 5], [2, 2, 2], [1, 8, 9]]}}"#,
        obstacles.join(", ")
    );
    let planner = planner(&json);
    for start in [[1.0, 5.0, 5.0], [2.0, 2.0, 2.0], [1.0, 8.0, 9.0]] {
        let path = planner.plan(start);
        assert!(
            path.status.reached_goal(),
            "from {start:?}: {:?}",
            path.status
        );
        for w in path.points.windows(2) {
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let p = [0, 1, 2].map(|a| w[0][a] + t * (w[1][a] - w[0][a]));
                for (lo, hi) in &boxes {
                    assert!(
                        box_distance(p, *lo, *hi) >= 0.3 - 1e-9,
                        "{p:?} too near a box"
                    );
                }
            }
        }
    }
}

#[test]
fn a_plate_thinner_than_the_lattice_is_not_crossed() {
    // 0.08 m thick, across the whole workspace: the uniform lattice held no vertex in it, so
    // the plate vanished and paths went through it.
    let planner = planner(
        r#"{"dimension": 3, "workspace": {"box": {"min": [0, 0, 0], "max": [10, 10, 10]}},
        "obstacles": [{"box": {"min": [5.0, -1, -1], "max": [5.08, 11, 11]}}],
        "goal": {"sphere": {"center": [9, 5, 5], "radius": 0.4}}}"#,
    );
    for start in [[1.0, 5.0, 5.0], [2.0, 2.0, 2.0]] {
        let path = planner.plan(start);
        assert_eq!(path.status.as_str(), "unreachable", "from {start:?}");
    }
    // On the goal's side, a start still reaches it.
    assert!(planner.plan([8.0, 2.0, 3.0]).status.reached_goal());
}

/// A plate of 0.1 mm, thinner than the grading's floor: the mesh misses it and the field
/// leads through it. Every reached path is checked against the exact solids segment by
/// segment (parry's segment distances), so those starts are `collision`, naming the plate,
/// never `reached_goal`; a start beside the plate still reaches the goal.
#[test]
fn a_path_through_a_plate_thinner_than_any_mesh_is_a_collision() {
    let planner = planner(
        r#"{"dimension": 3, "workspace": {"box": {"min": [0, 0, 0], "max": [4, 4, 4]}},
        "obstacles": [{"box": {"min": [2.0, 1.4, 1.4], "max": [2.0001, 2.6, 2.6]}}],
        "goal": {"sphere": {"center": [3.5, 2, 2], "radius": 0.3}},
        "mesh": {"max_volume": 0.01}}"#,
    );
    for start in [[0.5, 2.0, 2.0], [0.8, 1.9, 2.1]] {
        let path = planner.plan(start);
        assert_eq!(path.status.as_str(), "collision", "from {start:?}");
        let why = path.blocked_by.clone().unwrap_or_default();
        assert!(why.contains("obstacle 0"), "from {start:?}: {why}");
        assert_eq!(path.min_clearance, 0.0);
    }
    assert!(planner.plan([3.2, 0.8, 1.0]).status.reached_goal());
}

/// A plate of 0.2 mm across a whole 10 m box is thinner than the grading's finest size too:
/// it is not refined for (over its 100 m² that took minutes and gigabytes), the mesh stays
/// the lattice's size, and the start behind it is a `collision` naming it.
#[test]
fn a_plate_thinner_than_the_finest_grading_is_not_refined_for() {
    let planner = planner(
        r#"{"dimension": 3, "workspace": {"box": {"min": [0, 0, 0], "max": [10, 10, 10]}},
        "obstacles": [{"box": {"min": [5, -1, -1], "max": [5.0002, 11, 11]}}],
        "goal": {"sphere": {"center": [8, 5, 5], "radius": 0.3}}}"#,
    );
    assert!(
        planner.mesh().tetrahedra().len() < 600_000,
        "{} tetrahedra",
        planner.mesh().tetrahedra().len()
    );
    let path = planner.plan([2.0, 5.0, 5.0]);
    assert_eq!(path.status.as_str(), "collision");
    assert!(
        path.blocked_by
            .clone()
            .unwrap_or_default()
            .contains("obstacle 0")
    );
    assert!(planner.plan([8.0, 2.0, 2.0]).status.reached_goal());
}
