mod common;

use common::{GridQueries, laplace_psi, nodal_gradients};
use harmonic_fixtures::{Cell, Grid, Rng};
use harmonic_mesh::Point;
use harmonic_trajectory::{
    Field, P1Field, Path, SmoothOptions, SmoothP1Field, TraceError, TraceStatus, trace_smooth,
};

fn scene() -> Grid {
    let mut g = Grid::new(40, 40, 0.25);
    g.mark(3.0, 1.0, 4.0, 4.9, Cell::Obstacle(0));
    g.mark(3.0, 5.1, 4.0, 9.0, Cell::Obstacle(1));
    g.mark(6.0, 3.0, 7.0, 7.0, Cell::Obstacle(2));
    g.mark(8.5, 4.5, 9.0, 5.5, Cell::Goal(0));
    g.mark(0.0, 8.0, 1.75, 8.25, Cell::Obstacle(3));
    g.mark(1.5, 8.0, 1.75, 10.0, Cell::Obstacle(3));
    g
}

fn check(g: &Grid, path: &Path, start: Point) {
    if start.x < 1.5 && start.y > 8.25 {
        assert_eq!(path.status, TraceStatus::Unreachable, "start {start}");
        return;
    }
    assert_eq!(path.status, TraceStatus::ReachedGoal(0), "start {start}");
    for w in path.points.windows(2) {
        assert!(
            !g.segment_hits_obstacle(w[0], w[1]),
            "{} → {} crosses an obstacle",
            w[0],
            w[1]
        );
    }
    let end = *path.points.last().unwrap();
    assert!(
        (8.5 - 1e-9..=9.0 + 1e-9).contains(&end.x) && (4.5 - 1e-9..=5.5 + 1e-9).contains(&end.y),
        "end {end}"
    );
    assert!(path.length.is_finite() && path.min_gradient > 0.0);
}

#[test]
fn random_starts_reach_the_goal_smoothly() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 3000);
    let grads = nodal_gradients(&mesh, &psi);
    let smooth = SmoothP1Field::ascending(&mesh, &psi, &grads).unwrap();
    let p1 = P1Field::ascending(&mesh, &psi).unwrap();
    let opts = SmoothOptions::for_scale(10.0);
    let mut rng = Rng(12345);
    for s in g.random_free(&mut rng, 200) {
        check(&g, &trace_smooth(&smooth, s, &opts).unwrap(), s);
        check(&g, &trace_smooth(&p1, s, &opts).unwrap(), s);
    }
}

#[test]
fn smooth_paths_are_smooth_and_close_to_the_exact_ones() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 3000);
    let grads = nodal_gradients(&mesh, &psi);
    let smooth = SmoothP1Field::ascending(&mesh, &psi, &grads).unwrap();
    let s = Point::new(1.0, 2.0);
    let path = trace_smooth(&smooth, s, &SmoothOptions::for_scale(10.0)).unwrap();
    assert_eq!(path.status, TraceStatus::ReachedGoal(0));
    let exact = harmonic_trajectory::trace_exact(smooth.p1(), s, &Default::default());
    assert!(
        (path.length - exact.length).abs() < 0.1 * exact.length,
        "{} vs {}",
        path.length,
        exact.length
    );
    // The value decreases along the smooth path too (recovered gradients are close to the
    // P1 ones on this mesh), apart from tiny wiggles.
    let mut prev = f64::INFINITY;
    let mut hint = None;
    for p in &path.points[..path.points.len() - 1] {
        let harmonic_trajectory::Locate::Inside(t) = smooth.locate(*p, hint) else {
            panic!()
        };
        hint = Some(t);
        let v = smooth.value(t, *p);
        assert!(v <= prev + 1e-6, "{v} after {prev}");
        prev = v;
    }
}

#[test]
fn options_are_checked() {
    let mut o = SmoothOptions::for_scale(1.0);
    o.tolerance = -1.0;
    assert!(matches!(
        o.validate(),
        Err(TraceError::InvalidOption {
            name: "tolerance",
            ..
        })
    ));
    o = SmoothOptions::for_scale(1.0);
    o.min_step = 10.0;
    assert!(o.validate().is_err());
    let g = scene();
    let mesh = g.mesh();
    let psi = vec![0.0; mesh.vertices().len()];
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    assert!(trace_smooth(&f, Point::new(1.0, 1.0), &o).is_err());
    // A flat field stalls instead of wandering.
    let path = trace_smooth(&f, Point::new(1.0, 1.0), &SmoothOptions::for_scale(10.0)).unwrap();
    assert!(matches!(path.status, TraceStatus::Stalled { .. }));
}

#[test]
fn smooth_paths_slide_along_walls() {
    // ψ = x + 0.5 y on a 4 × 8 strip, goal above the top-right cell: the ascent pushes into
    // the right wall; steps into it are refused and the exact fallback slides along it.
    let mut g = Grid::new(4, 8, 1.0);
    g.mark(3.0, 7.0, 4.0, 8.0, Cell::Goal(0));
    let mesh = g.mesh();
    let psi: Vec<f64> = mesh.vertices().iter().map(|p| p.x + 0.5 * p.y).collect();
    let grads = nodal_gradients(&mesh, &psi);
    let smooth = SmoothP1Field::ascending(&mesh, &psi, &grads).unwrap();
    let p1 = P1Field::ascending(&mesh, &psi).unwrap();
    for path in [
        trace_smooth(
            &smooth,
            Point::new(0.3, 0.2),
            &SmoothOptions::for_scale(8.0),
        )
        .unwrap(),
        trace_smooth(&p1, Point::new(0.3, 0.2), &SmoothOptions::for_scale(8.0)).unwrap(),
    ] {
        assert_eq!(
            path.status,
            TraceStatus::ReachedGoal(0),
            "{:?}",
            path.points
        );
        assert!(path.points.iter().all(|p| p.x <= 4.0 && p.y <= 7.0 + 1e-9));
        assert!(path.points.iter().filter(|p| p.x == 4.0).count() >= 2);
        assert!(path.points.len() < 2000, "{} points", path.points.len());
    }
}
