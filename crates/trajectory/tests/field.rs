use harmonic_fixtures::{Cell, Grid};
use harmonic_mesh::Point;
use harmonic_trajectory::{Field, Locate, P1Field, Segment, TraceError};

fn room() -> Grid {
    let mut g = Grid::new(10, 10, 1.0);
    g.mark(3.0, 3.0, 5.0, 7.0, Cell::Obstacle(0));
    g.mark(8.0, 8.0, 9.0, 9.0, Cell::Goal(0));
    g
}

#[test]
fn locate_classifies_free_goal_obstacle_outside() {
    let mesh = room().mesh();
    let psi = vec![0.0; mesh.vertices().len()];
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    for (p, hint) in [
        (Point::new(1.2, 1.3), None),
        (Point::new(9.5, 0.5), Some(0)),
    ] {
        let Locate::Inside(t) = f.locate(p, hint) else {
            panic!("{p} is free")
        };
        let [a, b, c] = mesh.triangle_points(t);
        let inside = |u: Point, v: Point| (v - u).perp(&(p - u)) >= 0.0;
        assert!(inside(a, b) && inside(b, c) && inside(c, a));
    }
    assert_eq!(f.locate(Point::new(4.0, 5.0), Some(0)), Locate::InObstacle);
    assert_eq!(f.locate(Point::new(8.5, 8.7), None), Locate::Goal(0));
    assert_eq!(
        f.locate(Point::new(-1.0, 5.0), None),
        Locate::OutsideWorkspace
    );
    assert_eq!(
        f.locate(Point::new(11.0, 5.0), None),
        Locate::OutsideWorkspace
    );
    assert_eq!(
        f.locate(Point::new(f64::NAN, 5.0), None),
        Locate::OutsideWorkspace
    );
}

#[test]
fn segments_stop_at_obstacles_and_enter_goals() {
    let mesh = room().mesh();
    let psi = vec![0.0; mesh.vertices().len()];
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let a = Point::new(1.5, 5.0);
    let Locate::Inside(t) = f.locate(a, None) else {
        panic!()
    };
    // Straight through the obstacle to free space beyond: blocked even though the end is free.
    assert_eq!(f.segment(t, a, Point::new(7.5, 5.0)), Segment::Blocked);
    // Around it: free.
    let end = Point::new(1.5, 9.5);
    let Segment::Inside(u) = f.segment(t, a, end) else {
        panic!("free segment")
    };
    assert_eq!(f.locate(end, Some(u)), Locate::Inside(u));
    // Into the goal.
    let b = Point::new(7.5, 7.5);
    let Locate::Inside(tb) = f.locate(b, None) else {
        panic!()
    };
    assert_eq!(f.segment(tb, b, Point::new(8.5, 8.5)), Segment::Goal(0));
    // Along a mesh edge and through a vertex exactly.
    let c = Point::new(1.0, 1.0);
    let Locate::Inside(tc) = f.locate(c, None) else {
        panic!()
    };
    assert!(matches!(
        f.segment(tc, c, Point::new(2.0, 2.0)),
        Segment::Inside(_)
    ));
    assert!(matches!(
        f.segment(tc, c, Point::new(1.0, 2.5)),
        Segment::Inside(_)
    ));
}

#[test]
fn constructors_check_lengths_and_gradient_sign() {
    let mesh = room().mesh();
    let short = vec![0.0; 3];
    assert!(matches!(
        P1Field::descending(&mesh, &short),
        Err(TraceError::LengthMismatch { what: "values", .. })
    ));
    let mut bad = vec![0.0; mesh.vertices().len()];
    bad[7] = f64::NAN;
    assert_eq!(
        P1Field::ascending(&mesh, &bad).unwrap_err(),
        TraceError::NotFinite {
            what: "values",
            index: 7
        }
    );
    // ψ = x: the ascending field's value is −x and its gradient (−1, 0).
    let psi: Vec<f64> = mesh.vertices().iter().map(|p| p.x).collect();
    let f = P1Field::ascending(&mesh, &psi).unwrap();
    let p = Point::new(2.3, 1.7);
    let Locate::Inside(t) = f.locate(p, None) else {
        panic!()
    };
    assert!((f.value(t, p) + 2.3).abs() < 1e-14);
    let g = f.gradient(t, p);
    assert!((g.x + 1.0).abs() < 1e-14 && g.y.abs() < 1e-14);
}
