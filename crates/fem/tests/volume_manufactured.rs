//! Manufactured harmonic solutions on tetrahedral meshes: observed convergence rates in L2
//! (≈ 2) and H1 (≈ 1) over refinements, with Dirichlet, Neumann and Robin data on different
//! faces. Run with `--nocapture` to see the errors and rates.

use std::sync::Arc;

use harmonic_fem::volume::{VolumeAssembler, VolumePotential, VolumeSolveMethod, solve_volume};
use harmonic_fem::{BoundaryCondition, BoundaryConditions};
use harmonic_volume::{
    BoundaryFace, BoundaryTag, GoalRegion, MeshOptions, Part, Point, Solid, SphereSolid, TetMesh,
    Vector, VolumeDomain,
};

/// The unit cube cut into n³ cubes of 6 Kuhn tetrahedra each; x = 0 is goal 0, x = 1 is
/// obstacle 0, the other faces are walls.
fn kuhn(n: usize) -> TetMesh {
    harmonic_fixtures::kuhn_cube(n, &|p: &Point| {
        if p.x < 1e-12 {
            BoundaryTag::Goal(0)
        } else if p.x > 1.0 - 1e-12 {
            BoundaryTag::Obstacle(0)
        } else {
            BoundaryTag::Wall
        }
    })
}

fn outward(mesh: &TetMesh, f: &BoundaryFace) -> Vector {
    let [a, b, c] = f.vertices.map(|v| mesh.vertices()[v as usize]);
    (b - a).cross(&(c - a)).normalize()
}

/// Errors ‖u − u_h‖_L2 and |u − u_h|_H1 by the 4-point (degree 2) rule per tetrahedron.
fn errors(
    p: &VolumePotential,
    u: &dyn Fn(&Point) -> f64,
    grad: &dyn Fn(&Point) -> Vector,
) -> (f64, f64) {
    let mesh = p.mesh();
    let phi = p.phi_at_vertices();
    let (a, b) = (0.585_410_196_624_968_5, 0.138_196_601_125_010_5);
    let (mut l2, mut h1) = (0.0, 0.0);
    for (t, tet) in mesh.tetrahedra().iter().enumerate() {
        let q = mesh.tet_points(t as u32);
        let vol = mesh.tet_volume(t as u32);
        let g = -p.tet_gradient_psi(t as u32);
        for m in 0..4 {
            let w: [f64; 4] = std::array::from_fn(|k| if k == m { a } else { b });
            let x = Point::from((0..4).map(|k| q[k].coords * w[k]).sum::<Vector>());
            let uh: f64 = (0..4).map(|k| w[k] * phi[tet[k] as usize]).sum();
            l2 += vol / 4.0 * (u(&x) - uh).powi(2);
            h1 += vol / 4.0 * (grad(&x) - g).norm_squared();
        }
    }
    (l2.sqrt(), h1.sqrt())
}

fn rates(label: &str, hs: &[f64], errs: &[(f64, f64)]) -> (f64, f64) {
    let mut worst = (f64::INFINITY, f64::INFINITY);
    for k in 0..hs.len() {
        if k == 0 {
            println!(
                "{label}: h = {:.4}  L2 {:.3e}  H1 {:.3e}",
                hs[k], errs[k].0, errs[k].1
            );
            continue;
        }
        let r = (hs[k - 1] / hs[k]).ln();
        let (r2, r1) = (
            (errs[k - 1].0 / errs[k].0).ln() / r,
            (errs[k - 1].1 / errs[k].1).ln() / r,
        );
        println!(
            "{label}: h = {:.4}  L2 {:.3e} (rate {r2:.2})  H1 {:.3e} (rate {r1:.2})",
            hs[k], errs[k].0, errs[k].1
        );
        worst = (worst.0.min(r2), worst.1.min(r1));
    }
    worst
}

#[test]
fn cube_with_dirichlet_neumann_and_robin_faces() {
    // u = x² − y² + xz is harmonic.
    let u = |p: &Point| p.x * p.x - p.y * p.y + p.x * p.z;
    let grad = |p: &Point| Vector::new(2.0 * p.x + p.z, -2.0 * p.y, p.x);
    let (ra, rb) = (1.0, 2.0);
    let bcs = BoundaryConditions {
        goals: BoundaryCondition::Dirichlet(0.0),
        obstacles: BoundaryCondition::Neumann(0.0),
        walls: BoundaryCondition::Robin {
            a: ra,
            b: rb,
            g: 0.0,
        },
        ..BoundaryConditions::default()
    };
    let mut hs = Vec::new();
    let mut errs = Vec::new();
    for n in [3, 6, 12, 18] {
        let mesh = Arc::new(kuhn(n));
        let data = |f: &BoundaryFace, p: &Point| match f.tag {
            BoundaryTag::Goal(_) => u(p),
            BoundaryTag::Obstacle(_) => grad(p).dot(&outward(&mesh, f)),
            BoundaryTag::Wall => ra * grad(p).dot(&outward(&mesh, f)) + rb * u(p),
        };
        let assembler = VolumeAssembler::new(Arc::clone(&mesh), &bcs).unwrap();
        let system = assembler.assemble_with(&bcs, Some(&data)).unwrap();
        assert_eq!(
            system.positive_offdiagonals(),
            0,
            "Kuhn cubes are non-obtuse"
        );
        let (psi, report) = solve_volume(&system, VolumeSolveMethod::Auto).unwrap();
        assert_eq!(report.method, VolumeSolveMethod::Accurate);
        let p = VolumePotential::new(Arc::clone(&mesh), psi, system.reference()).unwrap();
        hs.push(1.0 / n as f64);
        errs.push(errors(&p, &u, &grad));
    }
    let (l2, h1) = rates("Kuhn cube, D/N/R faces", &hs, &errs);
    assert!(l2 >= 1.8 && h1 >= 0.9, "rates L2 {l2}, H1 {h1}");
}

#[test]
fn stuffed_cube_around_a_ball_with_dirichlet_ball_and_robin_walls() {
    // u = e^z cos(x/√2) cos(y/√2) is harmonic.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let u = move |p: &Point| p.z.exp() * (s * p.x).cos() * (s * p.y).cos();
    let grad = move |p: &Point| {
        let e = p.z.exp();
        let (cx, cy) = ((s * p.x).cos(), (s * p.y).cos());
        let (sx, sy) = ((s * p.x).sin(), (s * p.y).sin());
        Vector::new(-s * e * sx * cy, -s * e * cx * sy, e * cx * cy)
    };
    let (ra, rb) = (1.0, 3.0);
    let bcs = BoundaryConditions {
        goals: BoundaryCondition::Dirichlet(0.0),
        walls: BoundaryCondition::Robin {
            a: ra,
            b: rb,
            g: 0.0,
        },
        ..BoundaryConditions::default()
    };
    let domain = VolumeDomain::new(
        Solid::new_box(
            Part::Workspace,
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 1.0, 1.0),
        )
        .unwrap(),
        vec![],
        vec![GoalRegion::Sphere(SphereSolid {
            center: Point::new(0.5, 0.5, 0.5),
            radius: 0.25,
        })],
        0.0,
    )
    .unwrap();
    let mut hs = Vec::new();
    let mut errs = Vec::new();
    for n in [6.0, 9.0, 13.5, 20.25] {
        let h: f64 = 1.0 / n;
        let (mesh, _) = domain
            .mesh(&MeshOptions::with_max_volume(h.powi(3) / 12.0))
            .unwrap();
        let mesh = Arc::new(mesh);
        let data = |f: &BoundaryFace, p: &Point| match f.tag {
            BoundaryTag::Wall => ra * grad(p).dot(&outward(&mesh, f)) + rb * u(p),
            _ => u(p),
        };
        let assembler = VolumeAssembler::new(Arc::clone(&mesh), &bcs).unwrap();
        let system = assembler.assemble_with(&bcs, Some(&data)).unwrap();
        let (psi, _) = solve_volume(&system, VolumeSolveMethod::Auto).unwrap();
        let p = VolumePotential::new(Arc::clone(&mesh), psi, system.reference()).unwrap();
        hs.push(h);
        errs.push(errors(&p, &u, &grad));
        println!(
            "  {} tetrahedra, {} positive off-diagonals",
            mesh.tetrahedra().len(),
            system.positive_offdiagonals()
        );
    }
    let (l2, h1) = rates("stuffed cube − ball, D ball / R walls", &hs, &errs);
    assert!(l2 >= 1.8 && h1 >= 0.9, "rates L2 {l2}, H1 {h1}");
}
