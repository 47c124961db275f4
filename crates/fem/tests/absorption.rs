//! The absorption term (`Assembler::with_absorption`): −∇·∇φ + σ(φ − c) = 0, lumped.
//!
//! - Assembly: only the diagonal and the row excess change, by σ_t |t| / 3 per triangle.
//! - A manufactured solution on a strip: ψ = sinh(√σ (L − x)) / sinh(√σ L), nodal error
//!   falling at second order.
//! - Maximum principle on seeded random absorptions: ψ has no interior local maximum, and
//!   absorbing only ever lowers ψ (the comparison principle: ψ_σ ≤ ψ_0 at every vertex).
//! - Bad values are typed errors.

mod common;

use std::sync::Arc;

use common::{square_with_hole, three_part_tags};
use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions, FemError, LinearSystem,
    Ordering, Solver,
};
use harmonic_fixtures::{Grid, Rng, Side};
use harmonic_mesh::{BoundaryTag, Mesh};

fn assemble(mesh: &Arc<Mesh>, bcs: &BoundaryConditions, sigma: Option<Vec<f64>>) -> LinearSystem {
    let mut a =
        Assembler::new(Arc::clone(mesh), bcs, AssemblyOptions::default()).expect("assembler");
    if let Some(s) = sigma {
        a = a.with_absorption(s).expect("absorption");
    }
    a.assemble(bcs).expect("assemble")
}

fn psi(mesh: &Arc<Mesh>, bcs: &BoundaryConditions, sigma: Option<Vec<f64>>) -> Vec<f64> {
    let system = assemble(mesh, bcs, sigma);
    let solver = Solver::new(&system, Ordering::Amd).expect("factor");
    solver
        .potential(Arc::clone(mesh), &system)
        .expect("solve")
        .psi()
        .to_vec()
}

#[test]
fn absorption_adds_the_lumped_mass_to_the_diagonal_and_the_excess_only() {
    let mesh = Arc::new(square_with_hole(8, 0.0, 0.0, three_part_tags));
    let bcs = BoundaryConditions::default();
    let mut rng = Rng(3);
    let sigma: Vec<f64> = (0..mesh.triangles().len())
        .map(|_| 5.0 * rng.next_f64())
        .collect();
    let (bare, absorbing) = (
        assemble(&mesh, &bcs, None),
        assemble(&mesh, &bcs, Some(sigma.clone())),
    );
    let mut lumped = vec![0.0; mesh.vertices().len()];
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for &v in tri {
            lumped[v as usize] += sigma[t] * mesh.triangle_area(t as u32) / 3.0;
        }
    }
    let (d0, d1) = (bare.matrix().diagonal(), absorbing.matrix().diagonal());
    for (u, &v) in bare.free_vertices().iter().enumerate() {
        let want = lumped[v as usize];
        assert!(
            (d1[u] - d0[u] - want).abs() < 1e-12,
            "diagonal of unknown {u}"
        );
        assert!(
            (absorbing.excess()[u] - bare.excess()[u] - want).abs() < 1e-12,
            "excess {u}"
        );
    }
    // Off the diagonal, and on the right-hand side, nothing moves.
    let (a0, a1) = (bare.matrix(), absorbing.matrix());
    for j in 0..a0.n() {
        for p in a0.col_ptr()[j]..a0.col_ptr()[j + 1] {
            if a0.row_idx()[p] != j {
                assert_eq!(a0.values()[p], a1.values()[p]);
            }
        }
    }
    assert_eq!(bare.rhs(), absorbing.rhs());
    assert!(absorbing.not_m_matrix().is_none());
}

/// The strip [0, 4] × [0, 1]: goal (φ = 0) on the left, wall (φ = 1) on the right, no flux
/// across top and bottom, σ = 4: ψ = 1 − φ = sinh(2 (4 − x)) / sinh(8).
#[test]
fn a_manufactured_strip_converges_at_second_order() {
    let (len, sigma) = (4.0f64, 4.0f64);
    let exact = |x: f64| ((sigma.sqrt()) * (len - x)).sinh() / (sigma.sqrt() * len).sinh();
    let bcs = BoundaryConditions {
        obstacles: BoundaryCondition::Neumann(0.0),
        ..BoundaryConditions::default()
    };
    let mut errors = Vec::new();
    for per_unit in [4usize, 8, 16, 32] {
        let h = 1.0 / per_unit as f64;
        let mesh = Arc::new(
            Grid::new(4 * per_unit, per_unit, h)
                .parts(|side| match side {
                    Side::Left => BoundaryTag::Goal(0),
                    Side::Right => BoundaryTag::Wall,
                    Side::Top | Side::Bottom => BoundaryTag::Obstacle(0),
                })
                .mesh(),
        );
        let s = vec![sigma; mesh.triangles().len()];
        let psi = psi(&mesh, &bcs, Some(s));
        let err = mesh
            .vertices()
            .iter()
            .zip(&psi)
            .map(|(p, &v)| (v - exact(p.x)).abs())
            .fold(0.0, f64::max);
        errors.push(err);
    }
    let rates: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    println!("nodal errors {errors:?}, observed rates {rates:?}");
    assert!(errors[3] < 2e-3, "{errors:?}");
    assert!(rates[1..].iter().all(|&r| r > 1.8), "rates {rates:?}");
}

#[test]
fn random_absorptions_keep_the_maximum_principle_and_only_lower_psi() {
    let mesh = Arc::new(square_with_hole(16, 0.0, 0.0, three_part_tags));
    let bcs = BoundaryConditions::default();
    let harmonic = psi(&mesh, &bcs, None);
    let assembler =
        Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("assembler");
    let free = assembler.empty_system().free_vertices().to_vec();
    let mut neighbours = vec![Vec::new(); mesh.vertices().len()];
    for tri in mesh.triangles() {
        for k in 0..3 {
            neighbours[tri[k] as usize].push(tri[(k + 1) % 3]);
            neighbours[tri[k] as usize].push(tri[(k + 2) % 3]);
        }
    }
    for seed in 0..8 {
        let mut rng = Rng(seed);
        // Zero on most triangles, up to 10⁴ (ψ falling e-fold in 0.01) on a few.
        let sigma: Vec<f64> = (0..mesh.triangles().len())
            .map(|_| {
                if rng.below(3) == 0 {
                    10f64.powf(4.0 * rng.next_f64())
                } else {
                    0.0
                }
            })
            .collect();
        let absorbed = psi(&mesh, &bcs, Some(sigma));
        for &v in &free {
            let v = v as usize;
            assert!(
                absorbed[v] <= harmonic[v] * (1.0 + 1e-12),
                "seed {seed}: vertex {v} rose"
            );
            assert!(absorbed[v] > 0.0, "seed {seed}: vertex {v}");
            assert!(
                neighbours[v]
                    .iter()
                    .any(|&n| absorbed[n as usize] >= absorbed[v]),
                "seed {seed}: vertex {v} is an interior local maximum"
            );
        }
    }
}

#[test]
fn bad_absorptions_are_typed_errors() {
    let mesh = Arc::new(square_with_hole(4, 0.0, 0.0, three_part_tags));
    let bcs = BoundaryConditions::default();
    let n = mesh.triangles().len();
    let assembler =
        || Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("assembler");
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        let mut s = vec![0.0; n];
        s[2] = bad;
        let err = assembler().with_absorption(s).expect_err("refused");
        assert!(
            matches!(err, FemError::BadAbsorption { triangle: 2, .. }),
            "{err}"
        );
        assert!(err.to_string().contains("triangle 2"), "{err}");
    }
    let err = assembler()
        .with_absorption(vec![0.0; n + 1])
        .expect_err("refused");
    assert!(matches!(err, FemError::ConductivityCount { .. }), "{err}");
}
