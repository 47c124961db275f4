mod common;

use common::{GridQueries, laplace_psi};
use harmonic_fixtures::{Cell, Grid, Rng};
use harmonic_mesh::Point;
use harmonic_trajectory::{ExactOptions, Field, Locate, P1Field, Path, TraceStatus, trace_exact};

/// A 10 × 10 room (cells of 0.25): two obstacles with a narrow gap between them, a goal on
/// the right, and a small room in the top-left corner sealed off by an obstacle.
fn scene() -> Grid {
    let mut g = Grid::new(40, 40, 0.25);
    g.mark(3.0, 1.0, 4.0, 4.9, Cell::Obstacle(0));
    g.mark(3.0, 5.1, 4.0, 9.0, Cell::Obstacle(1));
    g.mark(6.0, 3.0, 7.0, 7.0, Cell::Obstacle(2));
    g.mark(8.5, 4.5, 9.0, 5.5, Cell::Goal(0));
    // Sealed room: walls of obstacle 3 around [0, 1.5] × [8.5, 10].
    g.mark(0.0, 8.0, 1.75, 8.25, Cell::Obstacle(3));
    g.mark(1.5, 8.0, 1.75, 10.0, Cell::Obstacle(3));
    g
}

fn in_sealed_room(p: Point) -> bool {
    p.x < 1.5 && p.y > 8.25
}

/// Checks a path's geometry and the monotone decrease of the field along it.
fn check_path(g: &Grid, f: &P1Field<'_>, path: &Path) {
    for w in path.points.windows(2) {
        assert!(
            !g.segment_hits_obstacle(w[0], w[1]),
            "segment {} → {} crosses an obstacle",
            w[0],
            w[1]
        );
    }
    let mut prev = f64::INFINITY;
    let mut hint = None;
    for (i, &p) in path.points.iter().enumerate() {
        let v = match f.locate(p, hint) {
            Locate::Inside(t) => {
                hint = Some(t);
                f.value(t, p)
            }
            other => panic!("path point {i} {p} is not in free space: {other:?}"),
        };
        assert!(v <= prev + 1e-12, "value rises at point {i}: {prev} → {v}");
        assert!(v.is_finite());
        prev = v;
    }
    assert!(path.length.is_finite() && path.min_gradient > 0.0);
}

#[test]
fn random_starts_reach_the_goal_or_are_unreachable() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 3000);
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let starts = g.random_free(&mut rng, 200);
    let mut unreachable = 0;
    for s in starts {
        let path = trace_exact(&f, s, &ExactOptions::default());
        if in_sealed_room(s) {
            assert_eq!(path.status, TraceStatus::Unreachable, "start {s}");
            unreachable += 1;
            continue;
        }
        assert_eq!(path.status, TraceStatus::ReachedGoal(0), "start {s}");
        assert_eq!(path.goal, Some(0));
        assert!(path.cells_crossed > 0 || path.points.len() <= 3);
        check_path(&g, &f, &path);
        // The last point lies on the goal's boundary.
        let end = *path.points.last().unwrap();
        assert!(
            (8.5..=9.0).contains(&end.x) && (4.5..=5.5).contains(&end.y),
            "end {end}"
        );
    }
    assert!(
        unreachable > 0,
        "some random starts fall in the sealed room"
    );
}

#[test]
fn starts_outside_free_space() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 10);
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let o = ExactOptions::default();
    assert_eq!(
        trace_exact(&f, Point::new(3.5, 2.0), &o).status,
        TraceStatus::StartInObstacle
    );
    assert_eq!(
        trace_exact(&f, Point::new(12.0, 2.0), &o).status,
        TraceStatus::OutsideWorkspace
    );
    assert_eq!(
        trace_exact(&f, Point::new(8.7, 5.0), &o).status,
        TraceStatus::ReachedGoal(0)
    );
    let json = serde_json::to_value(trace_exact(&f, Point::new(3.5, 2.0), &o)).unwrap();
    assert_eq!(json["status"], "start_in_obstacle");
    assert_eq!(json["points"], serde_json::json!([[3.5, 2.0]]));
}

/// A 4 × 4 grid (cells of 1) whose top-right cell is the goal and ψ = x + y − 3|x − y|:
/// a valley along the diagonal y = x, which is made of mesh edges.
fn valley() -> (Grid, Vec<f64>) {
    let mut g = Grid::new(4, 4, 1.0);
    g.mark(3.0, 3.0, 4.0, 4.0, Cell::Goal(0));
    let mesh = g.mesh();
    let psi = mesh
        .vertices()
        .iter()
        .map(|p| p.x + p.y - 3.0 * (p.x - p.y).abs())
        .collect();
    (g, psi)
}

#[test]
fn slides_along_an_interior_edge() {
    let (g, psi) = valley();
    let mesh = g.mesh();
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let path = trace_exact(&f, Point::new(1.6, 0.5), &ExactOptions::default());
    assert_eq!(path.status, TraceStatus::ReachedGoal(0));
    check_path(&g, &f, &path);
    // After meeting the valley the path runs along it to the goal corner (3, 3).
    let on_diag: Vec<_> = path
        .points
        .iter()
        .filter(|p| (p.x - p.y).abs() < 1e-12)
        .collect();
    assert!(on_diag.len() >= 2, "{:?}", path.points);
    assert_eq!(*path.points.last().unwrap(), Point::new(3.0, 3.0));
}

#[test]
fn starts_exactly_on_an_edge_or_a_vertex() {
    let (g, psi) = valley();
    let mesh = g.mesh();
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let o = ExactOptions::default();
    for s in [
        Point::new(1.5, 1.5), // on the valley edge
        Point::new(1.0, 1.0), // on a valley vertex
        Point::new(2.0, 0.5), // on a vertical edge off the valley
        Point::new(2.0, 1.0), // on a vertex off the valley
        Point::new(0.0, 2.0), // on a wall vertex
        Point::new(0.0, 0.5), // on a wall edge
    ] {
        let path = trace_exact(&f, s, &o);
        assert_eq!(
            path.status,
            TraceStatus::ReachedGoal(0),
            "start {s}: {:?}",
            path.points
        );
        check_path(&g, &f, &path);
        assert_eq!(*path.points.last().unwrap(), Point::new(3.0, 3.0));
    }
}

#[test]
fn enters_and_leaves_vertices_exactly() {
    // ψ = x + y on a 4 × 4 grid with the top-right cell as goal: from (0.5, 0.5) the descent
    // runs along the diagonal through the vertices (1, 1) and (2, 2).
    let mut g = Grid::new(4, 4, 1.0);
    g.mark(3.0, 3.0, 4.0, 4.0, Cell::Goal(0));
    let mesh = g.mesh();
    let psi: Vec<f64> = mesh.vertices().iter().map(|p| p.x + p.y).collect();
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let path = trace_exact(&f, Point::new(0.5, 0.5), &ExactOptions::default());
    assert_eq!(path.status, TraceStatus::ReachedGoal(0));
    assert!(path.points.contains(&Point::new(1.0, 1.0)));
    assert!(path.points.contains(&Point::new(2.0, 2.0)));
    assert!((path.length - 2.5 * 2f64.sqrt()).abs() < 1e-12);
    check_path(&g, &f, &path);
}

#[test]
fn slides_along_a_wall() {
    // ψ = x + 0.5 y on a 4 × 8 strip, goal above the top-right cell: the ascent pushes into
    // the right wall and slides up along it.
    let mut g = Grid::new(4, 8, 1.0);
    g.mark(3.0, 7.0, 4.0, 8.0, Cell::Goal(0));
    let mesh = g.mesh();
    let psi: Vec<f64> = mesh.vertices().iter().map(|p| p.x + 0.5 * p.y).collect();
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let path = trace_exact(&f, Point::new(0.3, 0.2), &ExactOptions::default());
    assert_eq!(
        path.status,
        TraceStatus::ReachedGoal(0),
        "{:?}",
        path.points
    );
    assert!(path.points.iter().all(|p| p.x <= 4.0));
    let on_wall = path.points.iter().filter(|p| p.x == 4.0).count();
    assert!(on_wall >= 3, "{:?}", path.points);
    check_path(&g, &f, &path);
}

#[test]
fn saddle_between_two_obstacles_is_escaped() {
    // Goal cells at both the left and right ends of a symmetric corridor with two obstacles
    // pinching its middle: a start on the axis of symmetry sits on the saddle ridge. The
    // mesh and ψ are mirror-symmetric in x about x = 5, and the start x = 5 lies on it.
    let mut g = Grid::new(20, 10, 0.5);
    g.mark(4.0, 0.0, 6.0, 1.9, Cell::Obstacle(0));
    g.mark(4.0, 3.1, 6.0, 5.0, Cell::Obstacle(1));
    g.mark(0.0, 2.0, 0.5, 3.0, Cell::Goal(0));
    g.mark(9.5, 2.0, 10.0, 3.0, Cell::Goal(1));
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 4000);
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    for s in [
        Point::new(5.0, 2.5),
        Point::new(5.0, 2.25),
        Point::new(5.0, 2.0),
    ] {
        let path = trace_exact(&f, s, &ExactOptions::default());
        assert!(path.status.reached_goal(), "start {s}: {:?}", path.status);
        check_path(&g, &f, &path);
    }
}

#[test]
fn plateaus_are_escaped_nearby_and_stall_far_away() {
    // ψ = max(x − 7, 0): flat on x ≤ 7. Near the slope a perturbation finds lower ground;
    // deep in the plateau nothing lower is in reach and the path stalls.
    let mut g = Grid::new(12, 4, 1.0);
    g.mark(11.0, 0.0, 12.0, 4.0, Cell::Goal(0));
    let mesh = g.mesh();
    let psi: Vec<f64> = mesh
        .vertices()
        .iter()
        .map(|p| (p.x - 7.0).max(0.0))
        .collect();
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let near = trace_exact(&f, Point::new(6.8, 1.3), &ExactOptions::default());
    assert_eq!(near.status, TraceStatus::ReachedGoal(0));
    check_path(&g, &f, &near);
    let far = trace_exact(&f, Point::new(0.4, 1.3), &ExactOptions::default());
    assert!(
        matches!(far.status, TraceStatus::Stalled { .. }),
        "{:?}",
        far.status
    );
    let capped = trace_exact(
        &f,
        Point::new(6.8, 1.3),
        &ExactOptions {
            max_steps: 2,
            max_perturbations: 4,
        },
    );
    assert_eq!(capped.status, TraceStatus::MaxSteps);
}

#[test]
fn values_far_below_the_squared_norm_underflow() {
    // ψ scaled by 1e-250: gradients near 1e-250, whose squared norm underflows to zero.
    // Nothing may treat them as flat.
    let g = scene();
    let mesh = g.mesh();
    let psi: Vec<f64> = laplace_psi(&mesh, 3000)
        .iter()
        .map(|v| v * 1e-250)
        .collect();
    let grads = common::nodal_gradients(&mesh, &psi);
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let smooth = harmonic_trajectory::SmoothP1Field::ascending(&mesh, &psi, &grads).unwrap();
    for s in [
        Point::new(1.0, 2.0),
        Point::new(9.5, 9.5),
        Point::new(5.0, 5.0),
    ] {
        let e = trace_exact(&f, s, &ExactOptions::default());
        assert_eq!(e.status, TraceStatus::ReachedGoal(0), "exact from {s}");
        assert!(e.min_gradient > 0.0 && e.min_gradient < 1e-240);
        let sm = harmonic_trajectory::trace_smooth(&smooth, s, &Default::default()).unwrap();
        assert_eq!(sm.status, TraceStatus::ReachedGoal(0), "smooth from {s}");
        let car = harmonic_trajectory::drive(
            &smooth,
            [s.x, s.y, 0.0],
            &harmonic_trajectory::CarOptions::new(0.2, 0.6, 0.02),
            None,
        )
        .unwrap();
        assert_eq!(car.status, TraceStatus::ReachedGoal(0), "car from {s}");
    }
}
