//! The four solves of the tetrahedral system agree: the accurate M-matrix elimination,
//! faer's Cholesky, IC(0)-PCG and smoothed-aggregation multigrid-PCG, on a stuffed
//! box-minus-ball mesh with clamped weights.

use std::sync::Arc;

use harmonic_fem::BoundaryConditions;
use harmonic_fem::volume::{
    NegativeWeights, VolumeAssembler, VolumeAssemblyOptions, VolumeSolveMethod, solve_volume,
};
use harmonic_volume::{GoalRegion, MeshOptions, Part, Point, Solid, VolumeDomain};

#[test]
fn accurate_cholesky_pcg_and_multigrid_agree() {
    let domain = VolumeDomain::new(
        Solid::new_box(
            Part::Workspace,
            Point::new(0.0, 0.0, 0.0),
            Point::new(3.0, 2.0, 2.0),
        )
        .unwrap(),
        vec![Solid::new_sphere(Part::Obstacle(0), Point::new(1.5, 1.0, 1.0), 0.5).unwrap()],
        vec![GoalRegion::Point(Point::new(0.4, 0.4, 0.4))],
        0.0,
    )
    .unwrap();
    let (mesh, _) = domain.mesh(&MeshOptions::with_max_volume(0.0002)).unwrap();
    let mesh = Arc::new(mesh);
    let bcs = BoundaryConditions::default();
    let options = VolumeAssemblyOptions {
        negative_weights: NegativeWeights::Clamp,
    };
    let system = VolumeAssembler::with_options(mesh, &bcs, options)
        .unwrap()
        .assemble(&bcs)
        .unwrap();
    assert!(system.not_m_matrix().is_none());
    let (a, ra) = solve_volume(&system, VolumeSolveMethod::Accurate).unwrap();
    let (c, rc) = solve_volume(&system, VolumeSolveMethod::Cholesky).unwrap();
    let (p, rp) = solve_volume(&system, VolumeSolveMethod::Pcg).unwrap();
    let (m, rm) = solve_volume(&system, VolumeSolveMethod::Multigrid).unwrap();
    println!(
        "{} unknowns: accurate {:.3} s, Cholesky {:.3} s, PCG {:.3} s ({} iterations), multigrid {:.3} s ({} iterations)",
        system.matrix().n(),
        ra.seconds,
        rc.seconds,
        rp.seconds,
        rp.iterations,
        rm.seconds,
        rm.iterations
    );
    assert!(rp.iterations > 0);
    // The multigrid's iterations do not grow with the mesh (IC(0)'s do): a few tens at most.
    assert!(
        rm.iterations > 0 && rm.iterations <= 30,
        "{}",
        rm.iterations
    );
    let max = a.iter().copied().fold(0.0, f64::max);
    for i in 0..a.len() {
        assert!(
            (a[i] - c[i]).abs() <= 1e-10 * max,
            "vertex {i}: {} vs {}",
            a[i],
            c[i]
        );
        assert!(
            (a[i] - p[i]).abs() <= 1e-7 * max,
            "vertex {i}: {} vs {}",
            a[i],
            p[i]
        );
        assert!(
            (a[i] - m[i]).abs() <= 1e-7 * max,
            "vertex {i}: {} vs {}",
            a[i],
            m[i]
        );
    }
}

/// Costs of the three solves on the benchmark scene at a lattice spacing `H` (default 0.3):
/// `H=0.24 cargo test --release -p harmonic-fem --test volume_solvers -- --ignored --nocapture`.
#[test]
#[ignore]
fn solver_costs() {
    let h: f64 = std::env::var("H")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.3);
    let (workspace, hole) = harmonic_fixtures::torus_solids();
    let domain = VolumeDomain::new(
        workspace,
        vec![
            hole,
            Solid::new_sphere(Part::Obstacle(1), Point::new(2.0, 8.0, 5.0), 1.0).unwrap(),
        ],
        vec![GoalRegion::Point(Point::new(9.0, 9.0, 9.0))],
        0.1,
    )
    .unwrap();
    let (mesh, _) = domain
        .mesh(&MeshOptions::with_max_volume(h.powi(3) / 12.0))
        .unwrap();
    let tets = mesh.tetrahedra().len();
    let mesh = Arc::new(mesh);
    let bcs = BoundaryConditions::default();
    let options = VolumeAssemblyOptions {
        negative_weights: NegativeWeights::Clamp,
    };
    let system = VolumeAssembler::with_options(mesh, &bcs, options)
        .unwrap()
        .assemble(&bcs)
        .unwrap();
    println!(
        "h = {h}: {tets} tetrahedra, {} unknowns",
        system.matrix().n()
    );
    for method in [
        VolumeSolveMethod::Multigrid,
        VolumeSolveMethod::Pcg,
        VolumeSolveMethod::Cholesky,
        VolumeSolveMethod::Accurate,
    ] {
        let (_, r) = solve_volume(&system, method).unwrap();
        println!(
            "  {method:?}: {:.3} s ({} iterations)",
            r.seconds, r.iterations
        );
    }
}
