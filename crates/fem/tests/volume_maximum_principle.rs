//! The discrete maximum principle on isosurface-stuffed meshes of random scenes of boxes and
//! spheres: the solution has no interior local extremum, and the positive off-diagonal
//! entries of the reduced stiffness (which stuffing does not rule out) are counted.

use std::sync::Arc;

use harmonic_fem::FemError;
use harmonic_fem::volume::{
    NegativeWeights, VolumeAssembler, VolumeAssemblyOptions, VolumePotential, VolumeSolveMethod,
    planning_method, solve_volume, solve_volume_potential_with_report,
};
use harmonic_fem::{BoundaryCondition, BoundaryConditions};
use harmonic_volume::{
    GoalRegion, MeshOptions, Part, Point, Solid, SphereSolid, VolumeDomain, quality,
};

/// A small deterministic generator (64-bit LCG, top bits).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn random_scene(rng: &mut Lcg) -> VolumeDomain {
    let mut obstacles = Vec::new();
    let count = 2 + (rng.next() * 4.0) as usize;
    for i in 0..count {
        let role = Part::Obstacle(i);
        let c = Point::new(
            rng.range(0.5, 3.5),
            rng.range(0.5, 3.5),
            rng.range(0.5, 3.5),
        );
        if rng.next() < 0.5 {
            obstacles.push(Solid::new_sphere(role, c, rng.range(0.3, 0.8)).unwrap());
        } else {
            let h = nalgebra::Vector3::new(
                rng.range(0.2, 0.9),
                rng.range(0.2, 0.9),
                rng.range(0.2, 0.9),
            );
            obstacles.push(Solid::new_box(role, c - h, c + h).unwrap());
        }
    }
    VolumeDomain::new(
        Solid::new_box(
            Part::Workspace,
            Point::new(0.0, 0.0, 0.0),
            Point::new(4.0, 4.0, 4.0),
        )
        .unwrap(),
        obstacles,
        vec![GoalRegion::Sphere(SphereSolid {
            center: Point::new(rng.range(0.3, 3.7), rng.range(0.3, 3.7), 0.4),
            radius: 0.3,
        })],
        0.0,
    )
    .unwrap()
}

#[test]
fn no_interior_extrema_on_random_scenes() {
    let mut rng = Lcg(0x005e_ed3d);
    let conditions = [
        BoundaryConditions::default(),
        BoundaryConditions::uniform(BoundaryCondition::Robin {
            a: 1.0,
            b: 5.0,
            g: 5.0,
        }),
        BoundaryConditions {
            obstacles: BoundaryCondition::Neumann(0.0),
            ..BoundaryConditions::default()
        },
    ];
    let mut total_positive = 0;
    for scene in 0..6 {
        let domain = random_scene(&mut rng);
        let (mesh, _) = domain
            .mesh(&MeshOptions::with_max_volume(0.3f64.powi(3) / 12.0))
            .unwrap();
        let q = quality(&mesh);
        let mesh = Arc::new(mesh);
        for bcs in &conditions {
            let options = VolumeAssemblyOptions {
                negative_weights: NegativeWeights::Clamp,
            };
            let assembler = VolumeAssembler::with_options(Arc::clone(&mesh), bcs, options).unwrap();
            let system = match assembler.assemble(bcs) {
                Ok(s) => s,
                // A pocket enclosed by Neumann obstacles: refused, as it must be.
                Err(FemError::OnlyNeumann { .. }) => {
                    assert_eq!(bcs.obstacles, BoundaryCondition::Neumann(0.0));
                    println!("scene {scene}: a pocket sealed by Neumann obstacles is refused");
                    continue;
                }
                Err(e) => panic!("scene {scene}: {e}"),
            };
            // A direct solve: the claim is about the M-matrix's solution, which an iterative
            // solve only approximates (to a residual of 1e-10, noise where ψ is smaller).
            let (psi, report) =
                solve_volume(&system, planning_method(system.matrix().n())).unwrap();
            let p = VolumePotential::new(Arc::clone(&mesh), psi, system.reference()).unwrap();
            println!(
                "scene {scene}: {} tets, dihedral {:.1}°..{:.1}°, {} of {} edges with negative weight ({} clamped), {} positive off-diagonals, solved by {:?}, {} interior extrema",
                q.tetrahedra,
                q.min_dihedral_deg,
                q.max_dihedral_deg,
                q.negative_weight_edges,
                q.edges,
                system.clamped_edges(),
                system.positive_offdiagonals(),
                report.method,
                p.interior_local_extrema()
            );
            total_positive += system.positive_offdiagonals();
            assert_eq!(
                system.positive_offdiagonals(),
                0,
                "clamping leaves an M-matrix"
            );
            assert_eq!(p.interior_local_extrema(), 0, "scene {scene}");
            // The planning entry point: Galerkin first, clamped if that had an extremum.
            let (auto, _, clamped) =
                solve_volume_potential_with_report(Arc::clone(&mesh), bcs).unwrap();
            assert_eq!(auto.interior_local_extrema(), 0, "scene {scene}");
            println!("  planning solve: clamped stiffness needed: {clamped}");
            // ψ within its boundary range (maximum principle for the values too).
            let (lo, hi) = p
                .psi()
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            assert!(
                lo >= -1e-9 && hi <= system.reference() + 1e-9,
                "ψ in [{lo}, {hi}]"
            );
        }
    }
    println!("positive off-diagonals in all: {total_positive}");
}

/// Without the clamp the Galerkin stiffness of a stuffed mesh has positive off-diagonals and
/// the maximum principle can fail: the check above is not vacuous.
#[test]
fn the_galerkin_stiffness_of_stuffed_meshes_is_not_an_m_matrix() {
    let mut rng = Lcg(0x005e_ed3d);
    let domain = random_scene(&mut rng);
    let (mesh, _) = domain
        .mesh(&MeshOptions::with_max_volume(0.3f64.powi(3) / 12.0))
        .unwrap();
    let mesh = Arc::new(mesh);
    let bcs = BoundaryConditions::default();
    let options = VolumeAssemblyOptions {
        negative_weights: NegativeWeights::Keep,
    };
    let assembler = VolumeAssembler::with_options(Arc::clone(&mesh), &bcs, options).unwrap();
    let system = assembler.assemble(&bcs).unwrap();
    let (psi, report) = solve_volume(&system, VolumeSolveMethod::Auto).unwrap();
    let p = VolumePotential::new(Arc::clone(&mesh), psi, system.reference()).unwrap();
    println!(
        "Galerkin: {} positive off-diagonals, {:?}, {} interior extrema",
        system.positive_offdiagonals(),
        report.method,
        p.interior_local_extrema()
    );
    assert!(system.positive_offdiagonals() > 0);
    assert!(system.not_m_matrix().is_some());
    assert_eq!(report.method, VolumeSolveMethod::Cholesky);
}
