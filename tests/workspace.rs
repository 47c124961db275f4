//! A workspace factored once answers any goal: the same field as a fresh solve of the same
//! held vertices, the same paths, every path reaching and ending on its goal point.

use harmonic_fixtures::{Rng, max_relative_difference, mesh_file};
use harmonic_planner::trajectory::TraceStatus;
use harmonic_planner::{Goal, PlanError, Planner, Point, Scene, Workspace};

fn reference(max_area: f64) -> Scene {
    let mut scene = Scene::from_file(mesh_file("reference.json")).expect("bundled scene");
    scene.mesh.max_area = Some(max_area);
    scene
}

/// `n` random points of free space (at least `margin` from every wall and obstacle).
fn random_free_points(workspace: &Workspace, n: usize, seed: u64, margin: f64) -> Vec<Point> {
    let domain = workspace.domain();
    Rng(seed)
        .points_in(n, [0.0, 0.0], [10.0, 10.0], |p| {
            let p = Point::new(p[0], p[1]);
            domain.contains_free(p) && domain.distance_to_obstacles(p) > margin
        })
        .into_iter()
        .map(|p| Point::new(p[0], p[1]))
        .collect()
}

#[test]
fn twenty_random_goals_match_fresh_solves_and_every_path_reaches_its_goal() {
    let workspace = Workspace::new(&reference(0.02)).expect("builds");
    let goals = random_free_points(&workspace, 20, 7, 0.05);
    let starts = random_free_points(&workspace, 4, 11, 0.05);
    let planners = workspace
        .planners(&goals.iter().map(|&g| Goal::point(g)).collect::<Vec<_>>())
        .expect("solves");
    for (goal, planner) in goals.iter().zip(&planners) {
        let fresh = workspace.fresh_planner(&Goal::point(*goal)).expect("fresh");
        let d = max_relative_difference(planner.potential().psi(), fresh.potential().psi());
        assert!(d <= 1e-9, "goal {goal:?}: ψ differs by {d:e}");
        let report = planner.goal_report().expect("a workspace planner");
        assert!(report.entrywise_accurate, "{report:?}");
        for &s in &starts {
            let (a, b) = (planner.plan(s), fresh.plan(s));
            assert_eq!(
                a.status,
                TraceStatus::ReachedGoal(0),
                "from {s:?} to {goal:?}"
            );
            assert_eq!(a.status, b.status);
            // ψ agrees to ~1e-14; the smooth tracer's step control may amplify that a little.
            assert!(
                (a.length - b.length).abs() <= 1e-4 * b.length,
                "from {s:?} to {goal:?}: {} vs {}",
                a.length,
                b.length
            );
            assert_eq!(*a.points.last().expect("points"), [goal.x, goal.y]);
            assert!(
                a.min_clearance > 0.0,
                "from {s:?} to {goal:?}: touches an obstacle"
            );
        }
        assert_eq!(
            planner.plan_report(&starts).potential.interior_local_minima,
            0
        );
    }
}

#[test]
fn a_workspace_goal_gives_about_the_path_of_a_planner_built_with_that_goal() {
    let scene = reference(0.02);
    let workspace = Workspace::new(&scene).expect("builds");
    let goal = Point::new(8.5, 1.5);
    let ours = workspace.planner(&Goal::point(goal)).expect("solves");
    // The bundled scene's goal is a disc of radius 0.15 at the same point.
    let built = Planner::new(&scene).expect("builds");
    for s in [[1.0, 9.0], [1.0, 1.0], [9.0, 9.0]] {
        let (a, b) = (ours.plan(s), built.plan(s));
        assert!(a.status.reached_goal() && b.status.reached_goal());
        // The disc's boundary is 0.15 short of its centre.
        let gap = a.length - (b.length + 0.15);
        assert!(
            gap.abs() < 0.05 * b.length,
            "from {s:?}: {} vs {}",
            a.length,
            b.length
        );
    }
}

#[test]
fn a_goal_set_sends_each_start_to_a_goal_of_the_set() {
    let workspace = Workspace::new(&reference(0.05)).expect("builds");
    let goals = [
        Point::new(1.0, 1.0),
        Point::new(9.0, 9.0),
        Point::new(8.5, 1.5),
    ];
    let set: Vec<Goal> = goals.iter().map(|&g| Goal::point(g)).collect();
    let planner = workspace.planner_for_any(&set).expect("solves");
    // Starts right beside each goal go to it.
    for (j, g) in goals.iter().enumerate() {
        let s = [g.x + 0.2, g.y + 0.1];
        let path = planner.plan(s);
        assert_eq!(
            path.status,
            TraceStatus::ReachedGoal(j as u32),
            "from {s:?}"
        );
        assert_eq!(*path.points.last().expect("points"), [g.x, g.y]);
    }
}

#[test]
fn a_goal_region_of_vertices_and_a_radius_are_held_whole() {
    let workspace = Workspace::new(&reference(0.05)).expect("builds");
    let centre = Point::new(1.0, 9.0);
    let disc = Goal::Point {
        at: centre,
        radius: 0.4,
    };
    let held = workspace.goal_vertices(&disc, 0).expect("vertices");
    assert!(held.len() > 5, "{} vertices", held.len());
    let planner = workspace
        .planner(&Goal::Vertices(held.clone()))
        .expect("solves");
    let report = planner.goal_report().expect("report");
    assert_eq!(report.held, held.len());
    assert!(
        report.columns < report.held,
        "the region's inside needs no column"
    );
    let path = planner.plan([9.0, 9.0]);
    assert!(path.status.reached_goal());
    let end = path.points.last().expect("points");
    assert!((Point::new(end[0], end[1]) - centre).norm() <= 0.4 + 1e-12);
}

#[test]
fn bad_goals_and_scenes_get_clear_errors() {
    let workspace = Workspace::new(&reference(0.2)).expect("builds");
    let in_obstacle = workspace
        .planner(&Goal::point([2.5, 5.0]))
        .expect_err("in an obstacle");
    assert!(
        in_obstacle.to_string().contains("not in the free space"),
        "{in_obstacle}"
    );
    let nan = workspace
        .planner(&Goal::point([f64::NAN, 1.0]))
        .expect_err("NaN");
    assert!(nan.to_string().contains("finite"), "{nan}");
    let beyond = workspace
        .planner(&Goal::Vertices(vec![u32::MAX]))
        .expect_err("no such vertex");
    assert!(beyond.to_string().contains("not a vertex"), "{beyond}");
    assert!(workspace.planner_for_any(&[]).is_err());

    let mut neumann = reference(0.2);
    neumann.boundary.walls = Some(harmonic_planner::fem::BoundaryCondition::Neumann(0.0));
    neumann.boundary.obstacles = Some(harmonic_planner::fem::BoundaryCondition::Neumann(0.0));
    let err = Workspace::new(&neumann).expect_err("walls hold nothing");
    assert!(matches!(err, PlanError::Fem(_)), "{err}");
    assert!(err.to_string().contains("hold nothing"), "{err}");
}
