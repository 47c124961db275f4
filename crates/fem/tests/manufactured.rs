//! Convergence against manufactured harmonic solutions, with Dirichlet, Neumann and Robin
//! conditions on different parts of a square with a square hole.

mod common;

use std::sync::Arc;

use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions, Ordering, Potential, Solver,
};
use harmonic_mesh::{BoundaryEdge, Mesh, Point, Vector};

/// An exact harmonic function and its gradient.
struct Exact {
    u: fn(Point) -> f64,
    grad: fn(Point) -> Vector,
}

const EXP_SIN: Exact = Exact {
    u: |p| p.x.exp() * p.y.sin(),
    grad: |p| Vector::new(p.x.exp() * p.y.sin(), p.x.exp() * p.y.cos()),
};

/// Re((x + iy)^3) = x³ − 3xy².
const CUBIC: Exact = Exact {
    u: |p| p.x.powi(3) - 3.0 * p.x * p.y * p.y,
    grad: |p| Vector::new(3.0 * p.x * p.x - 3.0 * p.y * p.y, -6.0 * p.x * p.y),
};

/// Degree-5 7-point rule on the reference triangle: (barycentric coords, weight summing to 1).
fn quadrature() -> Vec<([f64; 3], f64)> {
    let a1 = 0.059_715_871_789_769_82;
    let b1 = 0.470_142_064_105_115_1;
    let a2 = 0.797_426_985_353_087_3;
    let b2 = 0.101_286_507_323_456_3;
    let w0 = 0.225;
    let w1 = 0.132_394_152_788_506_2;
    let w2 = 0.125_939_180_544_827_2;
    vec![
        ([1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0], w0),
        ([a1, b1, b1], w1),
        ([b1, a1, b1], w1),
        ([b1, b1, a1], w1),
        ([a2, b2, b2], w2),
        ([b2, a2, b2], w2),
        ([b2, b2, a2], w2),
    ]
}

/// (L2 error of φ, H1 semi-norm error of φ).
fn errors(potential: &Potential, exact: &Exact) -> (f64, f64) {
    let mesh = potential.mesh();
    let phi = potential.phi_at_vertices();
    let rule = quadrature();
    let (mut l2, mut h1) = (0.0, 0.0);
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let pts = mesh.triangle_points(t as u32);
        let area = mesh.triangle_area(t as u32);
        // ∇φ_h = −∇ψ_h.
        let grad_h = -potential.triangle_gradient_psi(t as u32);
        for (l, w) in &rule {
            let p = Point::from(pts[0].coords * l[0] + pts[1].coords * l[1] + pts[2].coords * l[2]);
            let uh: f64 = (0..3).map(|k| l[k] * phi[tri[k] as usize]).sum();
            l2 += w * area * ((exact.u)(p) - uh).powi(2);
            h1 += w * area * ((exact.grad)(p) - grad_h).norm_squared();
        }
    }
    (l2.sqrt(), h1.sqrt())
}

/// Left side Dirichlet (goal 0), hole Neumann (obstacle 0), other sides Robin (walls), all
/// data from the exact solution.
fn solve_mixed(mesh: Arc<Mesh>, exact: &'static Exact, (a, b): (f64, f64)) -> Potential {
    let bcs = BoundaryConditions {
        walls: BoundaryCondition::Robin { a, b, g: 0.0 },
        obstacles: BoundaryCondition::Neumann(0.0),
        goals: BoundaryCondition::Dirichlet(0.0),
        ..BoundaryConditions::default()
    };
    let data = |e: &BoundaryEdge, p: Point| -> f64 {
        let [va, vb] = e.vertices;
        let d = mesh.vertices()[vb as usize] - mesh.vertices()[va as usize];
        let n = Vector::new(d.y, -d.x) / d.norm();
        let u = (exact.u)(p);
        let dudn = (exact.grad)(p).dot(&n);
        match bcs.for_tag(e.tag) {
            BoundaryCondition::Dirichlet(_) => u,
            BoundaryCondition::Neumann(_) => dudn,
            BoundaryCondition::Robin { a, b, .. } => a * dudn + b * u,
        }
    };
    let assembler =
        Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("assembler");
    let system = assembler.assemble_with(&bcs, &data).expect("assembly");
    let solver = Solver::new(&system, Ordering::Amd).expect("symbolic");
    solver.potential(Arc::clone(&mesh), &system).expect("solve")
}

fn rates(exact: &'static Exact, x0: f64, y0: f64, robin: (f64, f64)) -> (Vec<f64>, Vec<f64>) {
    let mut errs = Vec::new();
    for n in [8, 16, 32, 64, 128] {
        let mesh = Arc::new(common::square_with_hole(n, x0, y0, common::three_part_tags));
        let p = solve_mixed(mesh, exact, robin);
        errs.push(errors(&p, exact));
    }
    let l2: Vec<f64> = errs.windows(2).map(|w| (w[0].0 / w[1].0).log2()).collect();
    let h1: Vec<f64> = errs.windows(2).map(|w| (w[0].1 / w[1].1).log2()).collect();
    eprintln!("errors {errs:?}\nL2 rates {l2:?}\nH1 rates {h1:?}");
    (l2, h1)
}

#[test]
fn exp_sin_converges_at_optimal_rates() {
    let (l2, h1) = rates(&EXP_SIN, 0.0, 0.0, (1.0, 2.0));
    assert!(l2.iter().all(|&r| r >= 1.9), "L2 rates {l2:?}");
    assert!(h1.iter().all(|&r| r >= 0.95), "H1 rates {h1:?}");
}

#[test]
fn cubic_converges_at_optimal_rates() {
    let (l2, h1) = rates(&CUBIC, -1.0, -0.5, (0.5, 1.0));
    assert!(l2.iter().all(|&r| r >= 1.9), "L2 rates {l2:?}");
    assert!(h1.iter().all(|&r| r >= 0.95), "H1 rates {h1:?}");
}

/// The area-weighted recovered nodal gradient is more accurate than the element gradients:
/// its RMS error at interior vertices converges faster than the O(h) element gradient error.
#[test]
fn recovered_gradient_beats_element_gradient() {
    let mut errs = Vec::new();
    for n in [16, 32, 64] {
        let mesh = Arc::new(common::square_with_hole(
            n,
            0.0,
            0.0,
            common::three_part_tags,
        ));
        let p = solve_mixed(Arc::clone(&mesh), &EXP_SIN, (1.0, 2.0));
        let g = p.nodal_gradients_psi();
        let (mut sum, mut count) = (0.0, 0);
        for (v, &q) in mesh.vertices().iter().enumerate() {
            if mesh.vertex_tags()[v].is_none() {
                sum += (g[v] + (EXP_SIN.grad)(q)).norm_squared();
                count += 1;
            }
        }
        let rms_recovered = (sum / count as f64).sqrt();
        let (_, h1) = errors(&p, &EXP_SIN);
        let area: f64 = (0..mesh.triangles().len() as u32)
            .map(|t| mesh.triangle_area(t))
            .sum();
        errs.push((rms_recovered, h1 / area.sqrt()));
    }
    let rates: Vec<f64> = errs.windows(2).map(|w| (w[0].0 / w[1].0).log2()).collect();
    eprintln!("(recovered RMS, element RMS) {errs:?}, recovered rates {rates:?}");
    assert!(errs.iter().all(|(r, e)| r < e), "{errs:?}");
    assert!(rates.iter().all(|&r| r >= 1.4), "{rates:?}");
}

/// The same on unstructured Delaunay meshes from `Domain::mesh`: outer walls Robin, a square
/// obstacle Neumann, a square goal Dirichlet; h taken as 1/√(triangles).
#[test]
fn converges_on_unstructured_meshes() {
    use harmonic_mesh::{Domain, DomainSpec, GoalShape, MeshOptions, Shape};
    let square = |x0: f64, y0: f64, x1: f64, y1: f64| {
        vec![
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ]
    };
    let spec = DomainSpec {
        workspace: square(0.0, 0.0, 2.0, 2.0),
        obstacles: vec![Shape::Polygon(square(0.4, 0.5, 0.9, 1.5))],
        goals: vec![GoalShape::Polygon(square(1.3, 0.8, 1.7, 1.2))],
        robot_radius: 0.0,
    };
    for exact in [&EXP_SIN, &CUBIC] {
        let mut rows = Vec::new();
        for max_area in [0.02, 0.005, 0.00125, 0.0003125, 0.000078125] {
            let opts = MeshOptions {
                max_area: Some(max_area),
                ..MeshOptions::default()
            };
            let domain = Domain::new(&spec, &opts).expect("domain");
            let mesh = Arc::new(domain.mesh(&opts).expect("mesh").0);
            let n = mesh.triangles().len() as f64;
            let p = solve_mixed(mesh, exact, (1.0, 2.0));
            assert_eq!(p.interior_local_extrema(), 0);
            let (l2, h1) = errors(&p, exact);
            rows.push((n, l2, h1));
        }
        let rate = |w: &[(f64, f64, f64)], e: fn(&(f64, f64, f64)) -> f64| {
            (e(&w[0]) / e(&w[1])).ln() / (w[1].0 / w[0].0).sqrt().ln()
        };
        let l2: Vec<f64> = rows.windows(2).map(|w| rate(w, |r| r.1)).collect();
        let h1: Vec<f64> = rows.windows(2).map(|w| rate(w, |r| r.2)).collect();
        eprintln!("(triangles, L2, H1) {rows:?}\nL2 rates {l2:?}\nH1 rates {h1:?}");
        assert!(l2.iter().all(|&r| r >= 1.9), "L2 rates {l2:?}");
        assert!(h1.iter().all(|&r| r >= 0.95), "H1 rates {h1:?}");
    }
}
