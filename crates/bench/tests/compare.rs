//! Issue #9's comparison harness: the attractive/repulsive baseline gets trapped where the
//! FEM harmonic planner does not, the visibility-graph shortest path is exact on hand-made
//! cases and never longer than a planner's collision-free path, and every FEM path the
//! harness produces on the bundled scenes is collision-free.

use harmonic_bench::compare::{
    Arena, CompareOptions, PlannerKind, VisibilityGraph, markdown_table,
};
use harmonic_planner::Scene;
use harmonic_planner::mesh::{Domain, DomainSpec, GoalShape, MeshOptions, Point, Shape};

fn bundled(name: &str) -> Scene {
    Scene::from_file(harmonic_fixtures::mesh_file(&format!("{name}.json"))).expect("bundled scene")
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
    vec![
        Point::new(x0, y0),
        Point::new(x1, y0),
        Point::new(x1, y1),
        Point::new(x0, y1),
    ]
}

/// A 10 × 10 room with a 2 × 2 block in the middle and a small square goal right of it.
fn block_room(robot_radius: f64) -> Domain {
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 10.0, 10.0),
        obstacles: vec![Shape::Polygon(rect(4.0, 4.0, 6.0, 6.0))],
        goals: vec![GoalShape::Polygon(rect(8.0, 4.9, 8.2, 5.1))],
        robot_radius,
    };
    Domain::new(&spec, &MeshOptions::default()).expect("valid domain")
}

#[test]
fn attractive_repulsive_is_trapped_in_the_concave_trap_where_fem_is_not() {
    let scene = bundled("concave_trap");
    let options = CompareOptions {
        planners: vec![
            PlannerKind::FemDirichlet,
            PlannerKind::FemRobin,
            PlannerKind::AttractiveRepulsive,
        ],
        ..CompareOptions::default()
    };
    let arena = Arena::new(&scene, &options).expect("arena");
    let start = scene.starts[0];
    for c in arena.contestants() {
        let run = arena.plan(c, start);
        match c.kind() {
            PlannerKind::AttractiveRepulsive => {
                assert!(run.stalled && !run.success, "APF from {start:?}: {run:?}");
                // Trapped inside the cup: it ends well away from the goal.
                let end = run.points.last().expect("a path");
                assert!((end - Point::new(17.0, 5.0)).norm() > 5.0, "{end:?}");
            }
            kind => assert!(
                run.success && !run.stalled && run.min_clearance > 0.0,
                "{kind:?} from {start:?}: {} clearance {}",
                run.status,
                run.min_clearance
            ),
        }
    }
}

#[test]
fn shortest_path_around_a_square_is_the_hand_computed_one() {
    let domain = block_room(0.0);
    let graph = VisibilityGraph::new(&domain);
    // The block's four corners are the only reflex corners (the room's are convex, the goal's
    // are goal points).
    assert_eq!(graph.corners().len(), 4);
    // Blocked: over the corners (4, 6) and (6, 6), along the block's top, down to the goal's
    // corner (8, 5.1).
    let path = graph.shortest_path(Point::new(2.0, 5.2)).expect("a path");
    let by_hand = 2f64.hypot(0.8) + 2.0 + 2f64.hypot(0.9);
    assert!(
        (path.length - by_hand).abs() < 1e-5,
        "{} vs {by_hand}",
        path.length
    );
    assert_eq!(path.points.len(), 4, "{:?}", path.points);
    assert!((path.points[1] - Point::new(4.0, 6.0)).norm() < 1e-5);
    assert!((path.points[2] - Point::new(6.0, 6.0)).norm() < 1e-5);
    assert!((path.points[3] - Point::new(8.0, 5.1)).norm() < 1e-9);
    // The mirror image below the block has the same length.
    let below = graph.shortest_path(Point::new(2.0, 4.8)).expect("a path");
    assert!((below.length - by_hand).abs() < 1e-5, "{}", below.length);
    assert!((below.points[1] - Point::new(4.0, 4.0)).norm() < 1e-5);
    // In plain view: straight to the closest point of the goal, the middle of its left edge.
    let direct = graph.shortest_path(Point::new(7.0, 5.0)).expect("a path");
    assert!((direct.length - 1.0).abs() < 1e-12, "{}", direct.length);
    assert_eq!(
        direct.points,
        vec![Point::new(7.0, 5.0), Point::new(8.0, 5.0)]
    );
    // Seen past the block's corner: to the goal's corner (8, 4.9).
    let past = graph.shortest_path(Point::new(2.0, 2.0)).expect("a path");
    assert!(
        (past.length - 6f64.hypot(2.9)).abs() < 1e-12,
        "{}",
        past.length
    );
    // No path from inside the block or outside the room.
    assert!(graph.shortest_path(Point::new(5.0, 5.0)).is_none());
    assert!(graph.shortest_path(Point::new(11.0, 5.0)).is_none());
}

#[test]
fn shortest_path_for_a_disc_robot_goes_around_the_inflated_block() {
    let point = VisibilityGraph::new(&block_room(0.0))
        .shortest_path(Point::new(2.0, 5.2))
        .expect("a path")
        .length;
    let domain = block_room(0.3);
    let path = VisibilityGraph::new(&domain)
        .shortest_path(Point::new(2.0, 5.2))
        .expect("a path");
    // Longer than the point robot's, and it keeps the robot's radius off the original block,
    // up to the chords of the inflated corners (polygons inscribed in the rounded ones).
    assert!(path.length > point + 0.1, "{} vs {point}", path.length);
    let block = rect(4.0, 4.0, 6.0, 6.0);
    for w in path.points.windows(2) {
        for k in 0..4 {
            let d = harmonic_mesh::geom::segment_segment_distance(
                w[0],
                w[1],
                block[k],
                block[(k + 1) % 4],
            );
            assert!(d > 0.3 * 0.98, "{w:?} is {d} from the block");
        }
    }
}

#[test]
fn shortest_path_is_never_longer_than_a_planners_collision_free_path() {
    let options = CompareOptions {
        grid_n: 128,
        starts_per_side: 4,
        ..CompareOptions::default()
    };
    let mut checked = 0;
    for name in ["reference", "concave_trap", "garrido_fig1"] {
        let arena = Arena::new(&bundled(name), &options).expect("arena");
        let comparison = arena.run(&arena.starts(options.starts_per_side));
        assert!(
            comparison.starts.len() >= 10,
            "{name}: {:?}",
            comparison.starts
        );
        for r in &comparison.results {
            for (run, shortest) in r.runs.iter().zip(&comparison.shortest) {
                if run.success {
                    assert!(
                        shortest.length <= run.length * (1.0 + 1e-9) + 1e-6,
                        "{name}, {:?} from {:?}: shortest {} > {}",
                        r.kind,
                        run.start,
                        shortest.length,
                        run.length
                    );
                    checked += 1;
                }
            }
        }
        // Every row has the JSON fields of the issue.
        for row in comparison.rows() {
            let json = serde_json::to_value(&row).expect("serialises");
            for key in [
                "scene",
                "planner",
                "success_rate",
                "mean_length_ratio",
                "min_clearance",
                "millis",
            ] {
                assert!(json.get(key).is_some(), "{key} missing in {json}");
            }
            if let Some(ratio) = row.mean_length_ratio {
                assert!(ratio >= 1.0 - 1e-9, "{row:?}");
            }
        }
    }
    assert!(checked > 50, "only {checked} successful runs checked");
}

#[test]
fn every_fem_path_in_the_harness_is_collision_free() {
    let options = CompareOptions {
        planners: vec![PlannerKind::FemDirichlet, PlannerKind::FemRobin],
        ..CompareOptions::default()
    };
    for name in [
        "reference",
        "maze",
        "office",
        "concave_trap",
        "clutter",
        "garrido_fig1",
    ] {
        let arena = Arena::new(&bundled(name), &options).expect("arena");
        let comparison = arena.run(&arena.starts(options.starts_per_side));
        assert!(!comparison.starts.is_empty());
        for r in &comparison.results {
            for run in &r.runs {
                assert!(
                    run.success && run.min_clearance > 0.0,
                    "{name}, {:?} from {:?}: {}, clearance {}",
                    r.kind,
                    run.start,
                    run.status,
                    run.min_clearance
                );
                // Every step, checked independently of the harness's own measure.
                for w in run.points.windows(2) {
                    assert!(arena.domain().segment_clearance(w[0], w[1]) > 0.0);
                }
            }
        }
        let table = markdown_table(&comparison.rows());
        assert_eq!(table.lines().count(), 2 + 2, "{table}");
    }
}

#[test]
fn navigation_function_runs_in_a_sphere_world_only() {
    let ring: Vec<String> = (0..48)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 48.0;
            format!("[{}, {}]", 10.0 * a.cos(), 10.0 * a.sin())
        })
        .collect();
    let scene = Scene::from_json(&format!(
        r#"{{
            "name": "sphere_world",
            "workspace": [{}],
            "obstacles": [{{"circle": {{"center": [0, 0], "radius": 2}}}},
                          {{"circle": {{"center": [3, 4], "radius": 1}}}}],
            "goal": {{"circle": {{"center": [6, 0], "radius": 0.3}}}},
            "starts": [[-6, 0.5]],
            "mesh": {{"max_area": 0.1}}
        }}"#,
        ring.join(", ")
    ))
    .expect("scene");
    let options = CompareOptions {
        planners: vec![PlannerKind::NavigationFunction, PlannerKind::FemDirichlet],
        ..CompareOptions::default()
    };
    let arena = Arena::new(&scene, &options).expect("arena");
    assert!(arena.notes().is_empty(), "{:?}", arena.notes());
    let comparison = arena.run(&[[-6.0, 0.5]]);
    for row in comparison.rows() {
        assert_eq!(row.success_rate, 1.0, "{row:?}");
    }
    // A square room is no sphere world: the planner is left out, with a note saying why.
    let arena = Arena::new(&bundled("concave_trap"), &options).expect("arena");
    assert_eq!(arena.contestants().len(), 1);
    assert!(
        arena.notes()[0].contains("sphere world"),
        "{:?}",
        arena.notes()
    );
}

#[test]
fn connollys_grid_field_reaches_the_goal_from_every_maze_start() {
    // ψ decays to ~1e-44 along the maze's corridors at n = 256. Stopped at an absolute
    // residual of 1e-13 (the old default), the relaxation left ~1e-15 of noise there and the
    // tracer stalled from 16 of these 24 starts, (2, 2) among them; the relative stopping
    // rule resolves every cell.
    let options = CompareOptions {
        planners: vec![PlannerKind::GridSor],
        ..CompareOptions::default()
    };
    let arena = Arena::new(&bundled("maze"), &options).expect("arena");
    let starts = arena.starts(options.starts_per_side);
    assert!(starts.contains(&[2.0, 2.0]), "{starts:?}");
    let comparison = arena.run(&starts);
    assert_eq!(comparison.starts.len(), 24);
    let runs = &comparison.results[0].runs;
    let failed: Vec<_> = runs
        .iter()
        .filter(|r| !r.success)
        .map(|r| (r.start, r.status))
        .collect();
    assert!(
        failed.is_empty(),
        "{} of 24 failed: {failed:?}",
        failed.len()
    );
    assert!(runs.iter().all(|r| r.min_clearance > 0.0 && !r.stalled));
}

#[test]
fn the_panel_system_solves_in_the_office_and_its_paths_are_collision_free() {
    // The office's partitions are flush with the outer walls and with each other. Panelled
    // polygon by polygon, the shared segments carried coinciding panels with opposite
    // normals and the system was singular from all 27 starts; panelling the boundary of free
    // space leaves no panel there.
    let options = CompareOptions {
        planners: vec![PlannerKind::Panel],
        ..CompareOptions::default()
    };
    let arena = Arena::new(&bundled("office"), &options).expect("arena");
    let comparison = arena.run(&arena.starts(options.starts_per_side));
    assert_eq!(comparison.starts.len(), 27);
    let runs = &comparison.results[0].runs;
    for run in runs {
        assert!(run.error.is_none(), "from {:?}: {:?}", run.start, run.error);
        assert!(
            run.min_clearance > 0.0,
            "from {:?}: {} touches an obstacle",
            run.start,
            run.status
        );
        for w in run.points.windows(2) {
            assert!(arena.domain().segment_clearance(w[0], w[1]) > 0.0);
        }
    }
    // Where the uniform stream presses the robot into a partition the planner stops short
    // of it; it still reaches the goal from the starts in and next to the goal's room.
    let reached = runs.iter().filter(|r| r.success).count();
    assert!(reached >= 10, "only {reached} of 27 reached the goal");
}
