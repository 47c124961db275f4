//! End-to-end checks on the bundled scenes: meshed by `harmonic_mesh::Domain`, ψ solved by
//! `harmonic_fem` with the scene's boundary conditions (and variants), followed by the exact
//! and smooth tracers and the car.

use std::sync::Arc;

use harmonic_fem::{BoundaryCondition, BoundaryConditions, Potential, solve_potential};
use harmonic_fixtures::{Rng, mesh_file, plane_scene};
use harmonic_mesh::{Domain, DomainSpec, GoalShape, Mesh, MeshOptions, Point, Shape};
use harmonic_trajectory::{
    CarOptions, ExactOptions, Field, Locate, P1Field, SmoothOptions, SmoothP1Field, TraceStatus,
    drive, max_pose_curvature, path_metrics, trace_exact, trace_smooth,
};
use serde_json::Value;

fn condition(v: &Value) -> BoundaryCondition {
    if let Some(d) = v.get("dirichlet") {
        BoundaryCondition::Dirichlet(d.as_f64().unwrap())
    } else if let Some(g) = v.get("neumann") {
        BoundaryCondition::Neumann(g.as_f64().unwrap())
    } else {
        let r = &v["robin"];
        let f = |k: &str| r[k].as_f64().unwrap();
        BoundaryCondition::Robin {
            a: f("a"),
            b: f("b"),
            g: f("g"),
        }
    }
}

/// The scene's boundary conditions (defaults where absent).
fn conditions(name: &str) -> BoundaryConditions {
    let path = mesh_file(&format!("{name}.json"));
    let s: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mut bcs = BoundaryConditions::default();
    let b = &s["boundary"];
    if let Some(v) = b.get("walls") {
        bcs.walls = condition(v);
    }
    if let Some(v) = b.get("obstacles") {
        bcs.obstacles = condition(v);
    }
    if let Some(v) = b.get("goal") {
        bcs.goals = condition(v);
    }
    bcs
}

fn setup(name: &str, bcs: &BoundaryConditions) -> (Domain, Potential) {
    let opts = MeshOptions {
        max_area: Some(0.01),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&plane_scene(name).spec, &opts).unwrap();
    let (mesh, _) = domain.mesh(&opts).unwrap();
    let potential = solve_potential(Arc::new(mesh), bcs).unwrap();
    (domain, potential)
}

fn random_free(domain: &Domain, rng: &mut Rng, n: usize, clearance: f64) -> Vec<Point> {
    let (lo, hi) = domain.bounding_box();
    let mut out = Vec::new();
    while out.len() < n {
        let p = Point::new(
            lo.x + rng.next_f64() * (hi.x - lo.x),
            lo.y + rng.next_f64() * (hi.y - lo.y),
        );
        if domain.contains_free(p) && domain.distance_to_obstacles(p) >= clearance {
            out.push(p);
        }
    }
    out
}

/// Every segment stays in free space: sampled points lie in the closed free set (up to
/// rounding on walls and obstacle boundaries). The path's
/// last point lies on the goal's boundary up to rounding, so it is checked 1e-9 back (unless
/// the last step has no length, as from a start on the goal's boundary: then it has no
/// direction to back off along, and its point was checked as the step's first).
fn assert_in_free_space(domain: &Domain, pts: &[Point], what: &str) {
    for (i, w) in pts.windows(2).enumerate() {
        for k in 0..=8 {
            let mut q = w[0] + (w[1] - w[0]) * (k as f64 / 8.0);
            if k == 8 && i + 2 == pts.len() && w[1] != w[0] {
                q = w[1] + (w[0] - w[1]).normalize() * 1e-9;
            }
            // Points on a wall or obstacle boundary count as free, up to rounding.
            let free = domain.contains_free(q) || domain.distance_to_obstacles(q) < 1e-12;
            assert!(free, "{what}: {} → {} leaves free space at {q}", w[0], w[1]);
        }
    }
}

/// 200 random free starts: exact and smooth traces reach the goal through free space, φ
/// decreases along the exact ones.
fn check_traces(domain: &Domain, potential: &Potential, seed: u64) {
    let mesh: &Mesh = potential.mesh();
    let psi = potential.psi();
    let exact_field = P1Field::ascending(mesh, psi).unwrap();
    let smooth_field =
        SmoothP1Field::ascending(mesh, psi, potential.nodal_gradients_psi()).unwrap();
    let sopts = SmoothOptions::for_scale(10.0);
    let mut rng = Rng(seed);
    for s in random_free(domain, &mut rng, 200, 0.0) {
        let exact = trace_exact(&exact_field, s, &ExactOptions::default());
        assert_eq!(exact.status, TraceStatus::ReachedGoal(0), "exact from {s}");
        assert!(exact.min_gradient > 0.0 && exact.min_gradient.is_finite());
        assert_in_free_space(domain, &exact.points, "exact");
        let mut prev = f64::INFINITY;
        let mut hint = None;
        for (i, p) in exact.points.iter().enumerate() {
            let t = match exact_field.locate(*p, hint) {
                Locate::Inside(t) => t,
                // The end point lies on the goal's boundary up to rounding.
                Locate::Goal(0) if i + 1 == exact.points.len() => continue,
                other => panic!("{p} off the mesh: {other:?}"),
            };
            hint = Some(t);
            let v = exact_field.value(t, *p);
            assert!(v <= prev + 1e-12, "φ rises along the exact path from {s}");
            prev = v;
        }
        let smooth = trace_smooth(&smooth_field, s, &sopts).unwrap();
        assert_eq!(
            smooth.status,
            TraceStatus::ReachedGoal(0),
            "smooth from {s}"
        );
        assert_in_free_space(domain, &smooth.points, "smooth");
        let m = path_metrics(&smooth.points, |a, b| domain.segment_clearance(a, b));
        assert!(m.min_clearance >= 0.0 && (m.length - smooth.length).abs() < 1e-9);
    }
}

/// The car from 200 random free poses with room to turn; returns the success rate.
fn check_car(domain: &Domain, potential: &Potential, seed: u64, name: &str) -> f64 {
    let mesh: &Mesh = potential.mesh();
    let f =
        SmoothP1Field::ascending(mesh, potential.psi(), potential.nodal_gradients_psi()).unwrap();
    let (l, dmax) = (0.2f64, 0.6f64);
    let kmax = dmax.tan() / l;
    let opts = CarOptions::new(l, dmax, 0.02);
    let mut rng = Rng(seed);
    let starts = random_free(domain, &mut rng, 200, l / dmax.tan());
    let mut failures = Vec::new();
    for s in &starts {
        let th = (rng.next_f64() * 2.0 - 1.0) * std::f64::consts::PI;
        let car = drive(&f, [s.x, s.y, th], &opts, None).unwrap();
        assert!(max_pose_curvature(&car.poses) <= kmax * (1.0 + 1e-6));
        assert!(car.max_curvature <= kmax * (1.0 + 1e-12));
        let pts: Vec<Point> = car.poses.iter().map(|p| Point::new(p[0], p[1])).collect();
        // The final pose may lie just inside the goal; the rest stays in free space.
        assert_in_free_space(domain, &pts[..pts.len() - 1], "car");
        if !car.status.reached_goal() {
            failures.push((*s, th, car.status));
        }
    }
    let rate = 1.0 - failures.len() as f64 / starts.len() as f64;
    eprintln!(
        "{name}: the car reaches the goal from {:.1} % of 200 random poses; failures: {failures:?}",
        100.0 * rate
    );
    rate
}

#[test]
fn reference_scene() {
    let (domain, potential) = setup("reference", &conditions("reference"));
    check_traces(&domain, &potential, 2024);
    assert!(check_car(&domain, &potential, 99, "reference") >= 0.95);
    // Starts outside free space.
    let f = P1Field::ascending(potential.mesh(), potential.psi()).unwrap();
    let o = ExactOptions::default();
    assert_eq!(
        trace_exact(&f, Point::new(2.5, 5.0), &o).status,
        TraceStatus::StartInObstacle
    );
    assert_eq!(
        trace_exact(&f, Point::new(-1.0, 5.0), &o).status,
        TraceStatus::OutsideWorkspace
    );
    assert_eq!(
        trace_exact(&f, Point::new(8.5, 1.5), &o).status,
        TraceStatus::ReachedGoal(0)
    );
}

#[test]
fn reference_robin_scene() {
    let (domain, potential) = setup("reference_robin", &conditions("reference_robin"));
    check_traces(&domain, &potential, 7);
    assert!(check_car(&domain, &potential, 8, "reference_robin") >= 0.95);
}

#[test]
fn reference_scene_with_insulated_walls() {
    // Neumann walls: the flow runs along the walls, so paths meet and slide along them.
    let bcs = BoundaryConditions {
        walls: BoundaryCondition::Neumann(0.0),
        ..BoundaryConditions::default()
    };
    let (domain, potential) = setup("reference", &bcs);
    check_traces(&domain, &potential, 31);
}

#[test]
fn sealed_room_is_unreachable() {
    // Four overlapping bars enclose the room [2, 4] × [2, 4]; the goal is outside it.
    let bar = |x0: f64, y0: f64, x1: f64, y1: f64| {
        Shape::Polygon(vec![
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ])
    };
    let spec = DomainSpec {
        workspace: vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ],
        obstacles: vec![
            bar(1.5, 1.5, 4.5, 2.0),
            bar(1.5, 4.0, 4.5, 4.5),
            bar(1.5, 1.5, 2.0, 4.5),
            bar(4.0, 1.5, 4.5, 4.5),
        ],
        goals: vec![GoalShape::Circle {
            center: Point::new(8.0, 8.0),
            radius: 0.3,
        }],
        robot_radius: 0.0,
    };
    let opts = MeshOptions {
        max_area: Some(0.02),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).unwrap();
    let (mesh, _) = domain.mesh(&opts).unwrap();
    assert!(mesh.component_count() >= 2);
    let potential = solve_potential(Arc::new(mesh), &BoundaryConditions::default()).unwrap();
    let mesh: &Mesh = potential.mesh();
    let exact = P1Field::ascending(mesh, potential.psi()).unwrap();
    let smooth =
        SmoothP1Field::ascending(mesh, potential.psi(), potential.nodal_gradients_psi()).unwrap();
    let inside = Point::new(3.0, 3.1);
    assert_eq!(
        trace_exact(&exact, inside, &ExactOptions::default()).status,
        TraceStatus::Unreachable
    );
    let s = trace_smooth(&smooth, inside, &SmoothOptions::for_scale(10.0)).unwrap();
    assert_eq!(s.status, TraceStatus::Unreachable);
    let car = drive(
        &smooth,
        [3.0, 3.1, 0.0],
        &CarOptions::new(0.2, 0.6, 0.02),
        None,
    )
    .unwrap();
    assert_eq!(car.status, TraceStatus::Unreachable);
    assert_eq!(serde_json::to_value(&car).unwrap()["status"], "unreachable");
    // Outside the room the goal is reached.
    let outside = trace_exact(&exact, Point::new(6.0, 2.0), &ExactOptions::default());
    assert_eq!(outside.status, TraceStatus::ReachedGoal(0));
    assert_eq!(
        trace_exact(&exact, Point::new(1.75, 3.0), &ExactOptions::default()).status,
        TraceStatus::StartInObstacle
    );
}

#[test]
fn starts_on_vertices_and_edges_of_an_unstructured_mesh() {
    let (domain, potential) = setup("reference", &conditions("reference"));
    let mesh: &Mesh = potential.mesh();
    let f = P1Field::ascending(mesh, potential.psi()).unwrap();
    let smooth =
        SmoothP1Field::ascending(mesh, potential.psi(), potential.nodal_gradients_psi()).unwrap();
    let mut rng = Rng(4242);
    let nv = mesh.vertices().len();
    let nt = mesh.triangles().len();
    let mut starts = Vec::new();
    for _ in 0..100 {
        starts.push(mesh.vertices()[(rng.next_f64() * nv as f64) as usize % nv]);
        let tri = mesh.triangles()[(rng.next_f64() * nt as f64) as usize % nt];
        let (a, b) = (
            mesh.vertices()[tri[0] as usize],
            mesh.vertices()[tri[1] as usize],
        );
        starts.push(a + (b - a) * 0.5);
    }
    for s in starts {
        let exact = trace_exact(&f, s, &ExactOptions::default());
        let tag = f.locate(s, None);
        if let Locate::Goal(_) = tag {
            // A vertex of the goal's boundary may round to just inside the goal.
            assert!(exact.status.reached_goal());
            continue;
        }
        assert_eq!(
            exact.status,
            TraceStatus::ReachedGoal(0),
            "exact from {s} ({tag:?})"
        );
        assert_in_free_space(&domain, &exact.points, "exact");
        let sm = trace_smooth(&smooth, s, &SmoothOptions::for_scale(10.0)).unwrap();
        assert_eq!(sm.status, TraceStatus::ReachedGoal(0), "smooth from {s}");
        assert_in_free_space(&domain, &sm.points, "smooth");
    }
}

#[test]
fn far_end_of_a_long_corridor_where_phi_is_exactly_the_wall_value() {
    // In a 30 × 1 corridor ψ decays like e^(−πx): 1e-40 at the far end, where the float φ =
    // 1 − ψ is exactly 1. The tracers follow ψ's direction there all the same.
    let len = 30.0;
    let spec = DomainSpec {
        workspace: vec![
            Point::new(0.0, 0.0),
            Point::new(len, 0.0),
            Point::new(len, 1.0),
            Point::new(0.0, 1.0),
        ],
        obstacles: vec![],
        goals: vec![GoalShape::Polygon(vec![
            Point::new(0.3, 0.3),
            Point::new(0.7, 0.3),
            Point::new(0.7, 0.7),
            Point::new(0.3, 0.7),
        ])],
        robot_radius: 0.0,
    };
    let opts = MeshOptions {
        max_area: Some(0.005),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).unwrap();
    let (mesh, _) = domain.mesh(&opts).unwrap();
    let potential = solve_potential(Arc::new(mesh), &BoundaryConditions::default()).unwrap();
    let mesh: &Mesh = potential.mesh();
    let exact = P1Field::ascending(mesh, potential.psi()).unwrap();
    let smooth =
        SmoothP1Field::ascending(mesh, potential.psi(), potential.nodal_gradients_psi()).unwrap();
    let far = Point::new(29.5, 0.5);
    assert!(potential.psi_at(far, None).unwrap() < 1e-35);
    assert_eq!(1.0 - potential.psi_at(far, None).unwrap(), 1.0);
    for x in [10.0, 20.0, 29.5] {
        let s = Point::new(x, 0.37);
        let e = trace_exact(&exact, s, &ExactOptions::default());
        assert_eq!(e.status, TraceStatus::ReachedGoal(0), "exact from {s}");
        assert_in_free_space(&domain, &e.points, "exact");
        let sm = trace_smooth(&smooth, s, &SmoothOptions::for_scale(len)).unwrap();
        assert_eq!(sm.status, TraceStatus::ReachedGoal(0), "smooth from {s}");
        let car = drive(
            &smooth,
            [x, 0.5, 0.0],
            &CarOptions::new(0.1, 0.6, 0.01),
            None,
        )
        .unwrap();
        assert_eq!(car.status, TraceStatus::ReachedGoal(0), "car from {s}");
        if x == 29.5 {
            assert!(e.min_gradient < 1e-35 && sm.min_gradient < 1e-35 && car.min_gradient < 1e-35);
        }
    }
}
