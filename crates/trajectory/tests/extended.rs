//! Fields of a ψ past the double range (issue #19): the same potential scaled by 2^-3000 (no
//! f64 holds it) is followed by the smooth tracer, the exact tracer and the car to the goal,
//! along paths close to those of the unscaled potential; a flat extended field stalls.

mod common;

use common::{GridQueries, laplace_psi, nodal_gradients};
use harmonic_fixtures::{Cell, Grid, Rng};
use harmonic_mesh::{Point, Vector};
use harmonic_trajectory::{
    CarOptions, ExactOptions, Field, Locate, P1Field, Path, SmoothOptions, SmoothP1Field,
    TraceStatus, drive, trace_exact, trace_smooth,
};

fn scene() -> Grid {
    let mut g = Grid::new(40, 40, 0.25);
    g.mark(3.0, 1.0, 4.0, 4.9, Cell::Obstacle(0));
    g.mark(3.0, 5.1, 4.0, 9.0, Cell::Obstacle(1));
    g.mark(6.0, 3.0, 7.0, 7.0, Cell::Obstacle(2));
    g.mark(8.5, 4.5, 9.0, 5.5, Cell::Goal(0));
    g
}

/// The shift: ψ · 2^SHIFT is about 1e-903 here.
const SHIFT: i32 = -3000;

fn check(g: &Grid, path: &Path, start: Point) {
    assert_eq!(path.status, TraceStatus::ReachedGoal(0), "start {start}");
    for w in path.points.windows(2) {
        assert!(!g.segment_hits_obstacle(w[0], w[1]), "{} → {}", w[0], w[1]);
    }
}

#[test]
fn scaled_far_below_the_double_range_paths_are_the_same() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 3000);
    let grads = nodal_gradients(&mesh, &psi);
    let exponents = vec![SHIFT; psi.len()];
    // Mantissas need not be normalised; gradients get exponents of their own.
    let plain = SmoothP1Field::ascending(&mesh, &psi, &grads).unwrap();
    let wide =
        SmoothP1Field::ascending_extended(&mesh, &psi, &exponents, &grads, &exponents).unwrap();
    assert!(wide.p1().is_extended() && !plain.p1().is_extended());
    let opts = SmoothOptions::for_scale(10.0);
    let mut rng = Rng(777);
    for s in g.random_free(&mut rng, 60) {
        let a = trace_smooth(&plain, s, &opts).unwrap();
        let b = trace_smooth(&wide, s, &opts).unwrap();
        check(&g, &b, s);
        assert!(
            (a.length - b.length).abs() <= 1e-3 * a.length,
            "smooth from {s}: {} vs {}",
            a.length,
            b.length
        );
        let a = trace_exact(plain.p1(), s, &ExactOptions::default());
        let b = trace_exact(wide.p1(), s, &ExactOptions::default());
        check(&g, &b, s);
        assert!(
            (a.length - b.length).abs() <= 0.05 * a.length,
            "exact from {s}: {} vs {}",
            a.length,
            b.length
        );
    }
}

#[test]
fn extended_values_decrease_toward_the_goal_and_gradients_point_uphill_in_psi() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 3000);
    let grads = nodal_gradients(&mesh, &psi);
    let exponents = vec![SHIFT; psi.len()];
    let wide =
        SmoothP1Field::ascending_extended(&mesh, &psi, &exponents, &grads, &exponents).unwrap();
    let plain = P1Field::ascending(&mesh, &psi).unwrap();
    let (near, far) = (Point::new(8.0, 5.0), Point::new(0.5, 0.5));
    let (Locate::Inside(tn), Locate::Inside(tf)) =
        (wide.locate(near, None), wide.locate(far, None))
    else {
        panic!("both inside")
    };
    // −ln ψ: the value is −ln(ψ_plain) + 3000 ln 2, lower near the goal.
    let v = wide.value(tn, near);
    let expected = -(plain.value(tn, near).abs().ln()) - SHIFT as f64 * std::f64::consts::LN_2;
    assert!(
        (v - expected).abs() < 1e-9 * expected.abs(),
        "{v} vs {expected}"
    );
    assert!(wide.value(tn, near) < wide.value(tf, far));
    // The P1 gradient points the same way as the unscaled one.
    for t in [tn, tf] {
        let a: Vector = plain.triangle_gradient(t);
        let b: Vector = wide.p1().triangle_gradient(t);
        let cos = a.dot(&b) / (a.norm() * b.norm());
        assert!(cos > 1.0 - 1e-12, "triangle {t}: cos {cos}");
    }
}

#[test]
fn the_car_drives_on_an_extended_field() {
    let g = scene();
    let mesh = g.mesh();
    let psi = laplace_psi(&mesh, 3000);
    let grads = nodal_gradients(&mesh, &psi);
    let exponents = vec![SHIFT; psi.len()];
    let wide =
        SmoothP1Field::ascending_extended(&mesh, &psi, &exponents, &grads, &exponents).unwrap();
    let run = drive(
        &wide,
        [1.0, 1.0, 0.0],
        &CarOptions::new(0.2, 35f64.to_radians(), 0.02),
        None,
    )
    .unwrap();
    assert_eq!(run.status, TraceStatus::ReachedGoal(0));
}

#[test]
fn a_flat_extended_field_stalls() {
    let g = scene();
    let mesh = g.mesh();
    let m = vec![1.0; mesh.vertices().len()];
    let e = vec![-5000; m.len()];
    let zero = vec![Vector::zeros(); m.len()];
    let f = SmoothP1Field::ascending_extended(&mesh, &m, &e, &zero, &e).unwrap();
    let path = trace_smooth(&f, Point::new(1.0, 1.0), &SmoothOptions::for_scale(10.0)).unwrap();
    assert!(
        matches!(path.status, TraceStatus::Stalled { .. }),
        "{:?}",
        path.status
    );
    // Slices of the wrong length are refused.
    assert!(P1Field::ascending_extended(&mesh, &m, &e[1..]).is_err());
}
