//! `hplan plan --goal X,Y [--start X,Y]... --goal X,Y ...`: several goals on one mesh and one
//! factorisation, each with the starts that follow it.

mod common;

use common::{hplan, run_json};
use harmonic_fixtures::mesh_file;
use serde_json::Value;

fn point(v: &Value) -> [f64; 2] {
    [v[0].as_f64().expect("x"), v[1].as_f64().expect("y")]
}

#[test]
fn each_goal_gets_the_starts_after_it_and_every_path_ends_on_its_goal() {
    let scene = mesh_file("reference.json");
    let report = run_json(&[
        "plan",
        scene.to_str().expect("utf-8"),
        "--start",
        "4,5.5",
        "--goal",
        "8.5,1.5",
        "--start",
        "1,9",
        "--goal",
        "1,1",
        "--start",
        "9,9",
        "--start",
        "0.5,5",
        "--json",
    ]);
    assert_eq!(report["method"], "accurate");
    assert!(report["timings_ms"]["factor"].as_f64().expect("factor") > 0.0);
    let goals = report["goals"].as_array().expect("goals");
    assert_eq!(goals.len(), 2);
    // (4, 5.5) stood before the first goal: every goal gets it.
    let expected = [
        vec![[4.0, 5.5], [1.0, 9.0]],
        vec![[4.0, 5.5], [9.0, 9.0], [0.5, 5.0]],
    ];
    for (g, starts) in goals.iter().zip(expected) {
        let paths = g["paths"].as_array().expect("paths");
        let got: Vec<[f64; 2]> = paths.iter().map(|p| point(&p["start"])).collect();
        assert_eq!(got, starts, "{g}");
        assert_eq!(g["potential"]["interior_local_minima"], 0);
        assert!(g["held_vertices"].as_u64().expect("held") >= 1);
        for p in paths {
            assert_eq!(p["status"], "reached_goal", "{p}");
            let pts = p["points"].as_array().expect("points");
            assert_eq!(point(pts.last().expect("end")), point(&g["goal"]), "{p}");
            assert!(p["min_clearance"].as_f64().expect("clearance") > 0.0);
        }
    }
}

#[test]
fn several_goals_on_a_map_and_one_goal_on_a_scene_file() {
    let map = mesh_file("warehouse_map.yaml");
    let report = run_json(&[
        "plan",
        "--map",
        map.to_str().expect("utf-8"),
        "--robot-radius",
        "0.2",
        "--goal",
        "16.5,1.5",
        "--goal",
        "3.0,4.0",
        "--start",
        "16.5,1.5",
        "--json",
    ]);
    let goals = report["goals"].as_array().expect("goals");
    assert_eq!(goals.len(), 2);
    assert_eq!(
        goals[1]["paths"][0]["status"], "reached_goal",
        "{}",
        goals[1]
    );

    // Goals are independent: one off the map reports its error and fails none of the others,
    // one in the closed closet plans (its own free space), and a start outside that is
    // unreachable from it.
    let report = run_json(&[
        "plan",
        "--map",
        map.to_str().expect("utf-8"),
        "--robot-radius",
        "0.2",
        "--goal",
        "100,100",
        "--start",
        "3.0,4.0",
        "--goal",
        "16.4,11.8",
        "--start",
        "3.0,4.0",
        "--goal",
        "3.0,4.0",
        "--start",
        "16.5,1.5",
        "--json",
    ]);
    let goals = report["goals"].as_array().expect("goals");
    assert_eq!(goals.len(), 3);
    let error = goals[0]["error"]
        .as_str()
        .expect("the refused goal's error");
    assert!(error.contains("outside the map"), "{error}");
    assert_eq!(
        goals[1]["paths"][0]["status"], "unreachable",
        "{}",
        goals[1]
    );
    let path = &goals[2]["paths"][0];
    assert_eq!(path["status"], "reached_goal", "{path}");
    let pts = path["points"].as_array().expect("points");
    assert_eq!(point(pts.last().expect("end")), [3.0, 4.0]);

    // One --goal on a scene file replaces the scene's goal: an ordinary report.
    let scene = mesh_file("reference.json");
    let one = run_json(&[
        "plan",
        scene.to_str().expect("utf-8"),
        "--goal",
        "1,1",
        "--start",
        "9,9",
        "--json",
    ]);
    let path = &one["paths"][0];
    assert_eq!(path["status"], "reached_goal");
    let end = point(
        path["points"]
            .as_array()
            .expect("points")
            .last()
            .expect("end"),
    );
    // A point goal in a scene is meshed as a small disc (twice the target edge length).
    assert!(
        (end[0] - 1.0).hypot(end[1] - 1.0) < 0.25,
        "ends near (1, 1): {end:?}"
    );
}

#[test]
fn a_goal_in_an_obstacle_is_one_line_naming_it() {
    let scene = mesh_file("reference.json");
    let out = hplan()
        .args(["plan", scene.to_str().expect("utf-8")])
        .args(["--goal", "1,1", "--goal", "2.5,5", "--json"])
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("(2.5, 5) is not in the free space"), "{err}");
    assert!(out.stdout.is_empty());
}

#[test]
fn a_pose_goal_on_a_map_gives_poses_whose_last_carries_its_heading() {
    let map = mesh_file("warehouse_map.yaml");
    let report = run_json(&[
        "plan",
        "--map",
        map.to_str().expect("utf-8"),
        "--robot-radius",
        "0.2",
        "--goal",
        "16.5,1.5,1.25",
        "--start",
        "3.0,4.0,-0.5",
        "--start",
        "7.0,12.0",
        "--json",
    ]);
    for (k, path) in report["paths"]
        .as_array()
        .expect("paths")
        .iter()
        .enumerate()
    {
        assert_eq!(path["status"], "reached_goal", "{path}");
        let points = path["points"].as_array().expect("points");
        let poses = path["poses"].as_array().expect("poses");
        assert_eq!(points.len(), poses.len());
        let pose = |v: &Value| -> [f64; 3] { [0, 1, 2].map(|i| v[i].as_f64().expect("a number")) };
        let last = pose(poses.last().expect("a pose"));
        assert_eq!(last, [16.5, 1.5, 1.25]);
        let first = pose(&poses[0]);
        if k == 0 {
            assert_eq!(first[2], -0.5, "the start's heading");
        }
        // In between, each pose heads along the segment that leaves it.
        for w in poses.windows(2).skip(1).take(poses.len().saturating_sub(3)) {
            let (a, b) = (pose(&w[0]), pose(&w[1]));
            if (b[0] - a[0]).hypot(b[1] - a[1]) > 1e-12 {
                let along = (b[1] - a[1]).atan2(b[0] - a[0]);
                assert!((along - a[2]).abs() < 1e-12, "{a:?} → {b:?}");
            }
        }
    }
    // A pose goal is for maps.
    let out = hplan()
        .args(["plan", mesh_file("reference.json").to_str().expect("utf-8")])
        .args(["--goal", "1,1,0"])
        .output()
        .expect("runs");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("a pose goal) is for maps"));
}
