//! End-to-end checks on the bundled scenes, meshed by `harmonic_mesh::Domain`, with ψ from a
//! small Laplace solve (SOR on the P1 stiffness matrix) in the test itself.

mod common;

use common::{Rng, laplace_psi, nodal_gradients};
use harmonic_mesh::{Domain, DomainSpec, GoalShape, Mesh, MeshOptions, Point, Shape};
use harmonic_trajectory::{
    CarOptions, ExactOptions, Field, Locate, P1Field, SmoothOptions, SmoothP1Field, TraceStatus,
    drive, max_pose_curvature, path_metrics, trace_exact, trace_smooth,
};
use serde_json::Value;

fn pt(v: &Value) -> Point {
    Point::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap())
}

fn ring(v: &Value) -> Vec<Point> {
    v.as_array().unwrap().iter().map(pt).collect()
}

/// Reads the geometry of a bundled scene file (the facade owns the full format).
fn load(name: &str) -> DomainSpec {
    let path = format!("{}/../../meshes/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let s: Value = serde_json::from_str(&text).unwrap();
    let shape = |o: &Value| {
        if let Some(p) = o.get("polygon") {
            Shape::Polygon(ring(p))
        } else {
            let c = &o["circle"];
            Shape::Circle {
                center: pt(&c["center"]),
                radius: c["radius"].as_f64().unwrap(),
            }
        }
    };
    let goal = |o: &Value| {
        if let Some(p) = o.get("polygon") {
            GoalShape::Polygon(ring(p))
        } else if let Some(p) = o.get("point") {
            GoalShape::Point(pt(p))
        } else {
            let c = &o["circle"];
            GoalShape::Circle {
                center: pt(&c["center"]),
                radius: c["radius"].as_f64().unwrap(),
            }
        }
    };
    let goals = match &s["goal"] {
        Value::Array(a) => a.iter().map(goal).collect(),
        g => vec![goal(g)],
    };
    DomainSpec {
        workspace: ring(&s["workspace"]),
        obstacles: s["obstacles"]
            .as_array()
            .unwrap()
            .iter()
            .map(shape)
            .collect(),
        goals,
        robot_radius: 0.0,
    }
}

fn setup(name: &str) -> (Domain, Mesh, Vec<f64>) {
    let opts = MeshOptions {
        max_area: Some(0.01),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&load(name), &opts).unwrap();
    let (mesh, _) = domain.mesh(&opts).unwrap();
    let psi = laplace_psi(&mesh, 3000);
    (domain, mesh, psi)
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

/// Every segment stays in free space: sampled points lie in the closed free set. The path's
/// last point lies on the goal's boundary up to rounding, so it is checked 1e-9 back.
fn assert_in_free_space(domain: &Domain, pts: &[Point], what: &str) {
    for (i, w) in pts.windows(2).enumerate() {
        for k in 0..=8 {
            let mut q = w[0] + (w[1] - w[0]) * (k as f64 / 8.0);
            if k == 8 && i + 2 == pts.len() {
                q = w[1] + (w[0] - w[1]).normalize() * 1e-9;
            }
            assert!(
                domain.contains_free(q),
                "{what}: {} → {} leaves free space at {q}",
                w[0],
                w[1]
            );
        }
    }
}

#[test]
fn reference_scene_traces() {
    let (domain, mesh, psi) = setup("reference");
    let grads = nodal_gradients(&mesh, &psi);
    let exact_field = P1Field::ascending(&mesh, &psi).unwrap();
    let smooth_field = SmoothP1Field::ascending(&mesh, &psi, &grads).unwrap();
    let sopts = SmoothOptions::for_scale(10.0);
    let mut rng = Rng(2024);
    for s in random_free(&domain, &mut rng, 200, 0.0) {
        let exact = trace_exact(&exact_field, s, &ExactOptions::default());
        assert_eq!(exact.status, TraceStatus::ReachedGoal(0), "exact from {s}");
        assert_in_free_space(&domain, &exact.points, "exact");
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
        assert_in_free_space(&domain, &smooth.points, "smooth");
        let m = path_metrics(&smooth.points, |a, b| domain.segment_clearance(a, b));
        assert!(m.min_clearance >= 0.0 && (m.length - smooth.length).abs() < 1e-9);
    }
    // Starts outside free space.
    let o = ExactOptions::default();
    assert_eq!(
        trace_exact(&exact_field, Point::new(2.5, 5.0), &o).status,
        TraceStatus::StartInObstacle
    );
    assert_eq!(
        trace_exact(&exact_field, Point::new(-1.0, 5.0), &o).status,
        TraceStatus::OutsideWorkspace
    );
    assert_eq!(
        trace_exact(&exact_field, Point::new(8.5, 1.5), &o).status,
        TraceStatus::ReachedGoal(0)
    );
}

#[test]
fn reference_scene_car() {
    let (domain, mesh, psi) = setup("reference");
    let grads = nodal_gradients(&mesh, &psi);
    let f = SmoothP1Field::ascending(&mesh, &psi, &grads).unwrap();
    let (l, dmax) = (0.2f64, 0.6f64);
    let kmax = dmax.tan() / l;
    let opts = CarOptions::new(l, dmax, 0.02);
    let mut rng = Rng(99);
    let starts = random_free(&domain, &mut rng, 200, l / dmax.tan());
    let mut failures = Vec::new();
    for s in &starts {
        let th = (rng.next_f64() * 2.0 - 1.0) * std::f64::consts::PI;
        let car = drive(&f, [s.x, s.y, th], &opts, None).unwrap();
        assert!(max_pose_curvature(&car.poses) <= kmax * (1.0 + 1e-6));
        let pts: Vec<Point> = car.poses.iter().map(|p| Point::new(p[0], p[1])).collect();
        // The final pose may lie just inside the goal; the rest stays in free space.
        assert_in_free_space(&domain, &pts[..pts.len() - 1], "car");
        if !car.status.reached_goal() {
            failures.push((*s, th, car.status));
        }
    }
    let rate = 1.0 - failures.len() as f64 / starts.len() as f64;
    eprintln!(
        "reference scene: car reaches the goal from {:.1} % of 200 random poses; failures: {failures:?}",
        100.0 * rate
    );
    assert!(rate >= 0.95, "rate {rate}: {failures:?}");
}
