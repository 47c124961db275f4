//! Dynamic replanning: scans become obstacles, the local window plans around them, and in
//! randomised worlds with moving and unmapped obstacles the robot reaches the goal without
//! ever touching a true obstacle.

use harmonic_dynamic::{
    DynamicError, DynamicPlanner, LaserScan, LocalMapMode, LocalMapOptions, RunOptions,
    ScanOptions, World, WorldObstacle, cluster_points, inflated_hull, run, scan_obstacles,
};
use harmonic_mesh::geom::{polygon_contains, polygon_distance};
use harmonic_planner::Scene;

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<[f64; 2]> {
    vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
}

/// A 6 m × 4 m room with one mapped pillar; start on the left, goal on the right.
fn room() -> Scene {
    Scene::from_json(
        r#"{
        "workspace": [[0, 0], [6, 0], [6, 4], [0, 4]],
        "obstacles": [{"polygon": [[2.8, 3.0], [3.2, 3.0], [3.2, 4.0], [2.8, 4.0]]}],
        "goal": {"circle": {"center": [5.5, 2.0], "radius": 0.12}},
        "mesh": {"max_area": 0.02}
    }"#,
    )
    .expect("the test scene is valid")
}

fn small_window() -> LocalMapOptions {
    LocalMapOptions {
        size: 2.5,
        max_area: 0.02,
        ..LocalMapOptions::default()
    }
}

/// splitmix64: a small deterministic generator, so every run is reproducible by its seed.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

#[test]
fn clusters_split_at_the_gap_and_hulls_contain_discs_around_points() {
    let pts = [[0.0, 0.0], [0.25, 0.0], [0.5, 0.1], [3.0, 3.0], [3.1, 3.2]];
    let clusters = cluster_points(&pts, 0.3);
    assert_eq!(clusters.len(), 2);
    let sizes: Vec<usize> = clusters.iter().map(Vec::len).collect();
    assert!(sizes.contains(&3) && sizes.contains(&2), "{sizes:?}");
    // A gap just below the distance splits every point apart.
    assert_eq!(cluster_points(&pts[..3], 0.24).len(), 3);

    let hull = inflated_hull(&pts[..3], 0.1);
    for p in &pts[..3] {
        for k in 0..64 {
            let a = std::f64::consts::TAU * k as f64 / 64.0;
            let q = [p[0] + 0.0999 * a.cos(), p[1] + 0.0999 * a.sin()];
            assert!(polygon_contains(&hull, q), "{q:?} outside the hull");
        }
    }
    // ... and not much more: the octagons overshoot a disc by at most 8.3 %.
    assert!(polygon_distance(&hull, [0.25, 0.0 + 0.2]) > 0.0);
}

#[test]
fn scans_drop_what_the_map_explains_and_turn_the_rest_into_obstacles() {
    let scene = room();
    let planner = DynamicPlanner::new(&scene, small_window()).expect("planner");
    let box_ = rect(2.0, 1.8, 2.4, 2.2);
    let world = World::new(
        &scene,
        vec![WorldObstacle {
            polygon: box_.clone(),
            velocity: [0.0, 0.0],
            period: 0.0,
        }],
    );
    // Facing away (heading π) must not matter: points are in the robot frame.
    let scan = world.scan([1.0, 2.0, std::f64::consts::PI], 0.0, 360, 10.0);
    assert!(scan.points.len() > 300, "walls and the box are in range");
    for p in scan.world_points() {
        let on_map = planner.known_distance(p) < 1e-9;
        let on_box = polygon_distance(&box_, p) < 1e-9 && !polygon_contains(&box_, p)
            || polygon_distance(&box_, p) == 0.0;
        assert!(on_map || on_box, "{p:?} is on nothing");
    }
    let obstacles = scan_obstacles(
        &scan,
        |p| planner.known_distance(p),
        &ScanOptions::default(),
    );
    assert_eq!(obstacles.len(), 1, "only the unmapped box is left");
    // The sensed face of the box is covered with a margin; the robot is outside.
    for y in [1.85, 2.0, 2.15] {
        assert!(polygon_contains(&obstacles[0], [2.0, y]));
        assert!(polygon_contains(&obstacles[0], [1.95, y]));
    }
    assert!(!polygon_contains(&obstacles[0], [1.0, 2.0]));

    // A scan from a different pose in the robot frame: the same world points.
    let moved = LaserScan {
        pose: [1.0, 2.0, 0.0],
        points: world.scan([1.0, 2.0, 0.0], 0.0, 360, 10.0).points,
    };
    let (a, b) = (scan.world_points(), moved.world_points());
    assert_eq!(a.len(), b.len());
}

#[test]
fn local_goal_is_on_the_global_path_at_the_window_edge_and_replans_go_around() {
    let scene = room();
    let mut planner = DynamicPlanner::new(&scene, small_window()).expect("planner");
    let plan = planner.replan([0.5, 2.0]).expect("empty room");
    assert_eq!(plan.path.status.as_str(), "reached_goal");
    assert!(!plan.goal_in_window);
    // The window is [-0.75, 1.75]: the goal sits near its right edge, on the way to (5.5, 2).
    assert!(
        plan.local_goal[0] > 1.2 && plan.local_goal[0] < 1.75,
        "{:?}",
        plan.local_goal
    );
    assert!(
        (plan.local_goal[1] - 2.0).abs() < 0.3,
        "{:?}",
        plan.local_goal
    );

    // A wall across the straight line: the local path bends around it.
    let wall = rect(1.0, 1.5, 1.2, 2.5);
    planner.set_obstacle(3, wall.clone());
    let plan = planner.replan([0.5, 2.0]).expect("around the wall");
    assert_eq!(plan.path.status.as_str(), "reached_goal");
    assert!(
        plan.path
            .points
            .iter()
            .all(|&p| polygon_distance(&wall, p) > 0.0)
    );
    assert!(plan.path.points.iter().any(|p| (p[1] - 2.0).abs() > 0.5));
    // Removed again: straight on.
    assert!(planner.remove_obstacle(3));
    let plan = planner.replan([0.5, 2.0]).expect("empty room");
    assert!(plan.path.points.iter().all(|p| (p[1] - 2.0).abs() < 0.3));

    // Near the goal the real goal is used.
    let plan = planner.replan([4.8, 2.0]).expect("near the goal");
    assert!(plan.goal_in_window);
    assert_eq!(plan.path.status.as_str(), "reached_goal");
}

#[test]
fn a_kept_waypoint_never_moves_into_a_known_obstacle() {
    // Up and down the reference scene's corridor past a sensed box, 5 cm per replan. The kept
    // waypoint, nudged when it stopped being valid, once landed 0.19 m inside the obstacle
    // [5, 9] × [4, 5] (far from its boundary, so "clear" by distance alone) and the replan
    // failed with "goal 0 lies outside the workspace".
    let scene = Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/reference.json"
    ))
    .expect("reference scene");
    let mut planner = DynamicPlanner::new(&scene, LocalMapOptions::default()).expect("planner");
    planner.set_obstacle(0, rect(4.0, 4.6, 4.5, 5.1));
    let up: Vec<[f64; 2]> = (0..=20).map(|k| [3.7, 5.5 + 0.05 * k as f64]).collect();
    for robot in up.iter().chain(up.iter().rev()) {
        let plan = planner
            .replan(*robot)
            .unwrap_or_else(|e| panic!("{robot:?}: {e}"));
        assert_eq!(plan.path.status.as_str(), "reached_goal", "{robot:?}");
        let g = plan.local_goal;
        let domain = planner.global().domain();
        assert!(
            domain.contains_free(harmonic_planner::mesh::Point::new(g[0], g[1])),
            "{robot:?}: local goal {g:?} outside free space"
        );
    }
}

#[test]
fn bad_positions_and_options_are_errors() {
    let scene = room();
    let mut planner = DynamicPlanner::new(&scene, small_window()).expect("planner");
    assert!(matches!(
        planner.replan([7.0, 2.0]),
        Err(DynamicError::OutsideWorkspace { .. })
    ));
    // Inside the mapped pillar (which touches the wall, so it is cut out of the window).
    assert!(matches!(
        planner.replan([3.0, 3.5]),
        Err(DynamicError::OutsideWorkspace { .. } | DynamicError::NoGlobalPath { .. })
    ));
    let bad = LocalMapOptions {
        max_area: -1.0,
        ..small_window()
    };
    let err = DynamicPlanner::new(&scene, bad).err().expect("invalid");
    assert!(err.to_string().contains("max_area"), "{err}");
    // A lattice far too fine is refused before anything is allocated.
    let huge = LocalMapOptions {
        max_area: 1e-12,
        ..small_window()
    };
    let err = DynamicPlanner::new(&scene, huge).err().expect("invalid");
    assert!(err.to_string().contains("1000 × 1000"), "{err}");
}

/// Whatever a caller puts in as obstacles — non-finite coordinates, degenerate or
/// self-crossing rings, an obstacle over the robot or over the whole window — a replan is a
/// plan or an error, never a panic, in both local-map modes.
#[test]
fn odd_sensed_obstacles_give_a_plan_or_an_error() {
    let scene = room();
    let odd: Vec<Vec<[f64; 2]>> = vec![
        vec![[f64::NAN, 1.0], [2.0, 1.0], [2.0, 2.0]],
        vec![[1.0, f64::INFINITY], [2.0, 1.0], [2.0, 2.0]],
        vec![],
        vec![[1.0, 1.0]],
        vec![[1.0, 1.0], [1.5, 1.5]],
        vec![[1.0, 1.0], [1.0, 1.0], [1.0, 1.0]],
        // A bow tie.
        vec![[1.0, 1.0], [2.0, 2.0], [2.0, 1.0], [1.0, 2.0]],
        // Over the robot.
        rect(0.3, 1.8, 0.7, 2.2),
        // Over the whole window and beyond the workspace.
        rect(-5.0, -5.0, 10.0, 10.0),
        // Huge coordinates.
        vec![[1e300, 1e300], [-1e300, 1e300], [0.0, -1e300]],
    ];
    for mode in [LocalMapMode::Lattice, LocalMapMode::Remesh] {
        for ring in &odd {
            let options = LocalMapOptions {
                mode,
                ..small_window()
            };
            let mut planner = DynamicPlanner::new(&scene, options).expect("planner");
            planner.set_obstacle(0, ring.clone());
            if let Ok(plan) = planner.replan([0.5, 2.0]) {
                assert!(
                    plan.path.points.iter().flatten().all(|v| v.is_finite()),
                    "{mode:?} {ring:?}"
                );
            }
        }
    }
}

/// 100 random worlds: an unmapped box somewhere between start and goal and a box moving up and
/// down across the way. The robot must reach the goal and keep a positive distance to every
/// true obstacle at every step.
#[test]
fn hundred_random_runs_reach_the_goal_without_touching_anything() {
    let scene = room();
    let opts = RunOptions {
        beams: 90,
        range: 2.0,
        max_steps: 600,
        snapshot_every: 0,
        ..RunOptions::default()
    };
    let mut replans = 0;
    for seed in 0..100u64 {
        let mut rng = Rng(seed);
        let (cx, cy, w, h) = (
            rng.range(1.6, 4.4),
            rng.range(0.8, 2.6),
            rng.range(0.2, 0.6),
            rng.range(0.2, 0.6),
        );
        let (mx, speed) = (rng.range(1.5, 4.5), rng.range(0.1, 0.6));
        let world = World::new(
            &scene,
            vec![
                WorldObstacle {
                    polygon: rect(cx - w / 2.0, cy - h / 2.0, cx + w / 2.0, cy + h / 2.0),
                    velocity: [0.0, 0.0],
                    period: 0.0,
                },
                WorldObstacle {
                    polygon: rect(mx - 0.15, 0.2, mx + 0.15, 0.5),
                    velocity: [0.0, speed],
                    period: 2.0 * 3.2 / speed,
                },
            ],
        );
        let mut planner = DynamicPlanner::new(&scene, small_window()).expect("planner");
        let result = run(&mut planner, &world, [0.5, 2.0], &opts);
        assert!(
            result.reached,
            "seed {seed}: did not reach the goal in {} steps ({} failed replans, last: {:?})",
            result.trail.len() - 1,
            result.failed_replans,
            result.last_error
        );
        assert!(
            result.min_distance_to_obstacles > 0.0,
            "seed {seed}: touched an obstacle"
        );
        replans += result.replans;
    }
    assert!(replans > 100 * 20, "{replans} replans in 100 runs");
}
