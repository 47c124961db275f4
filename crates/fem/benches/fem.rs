//! Stage timings of the FEM pipeline on the reference scene (Dirichlet case) at about
//! 3k / 30k / 300k / 1M triangles: pattern (Assembler::new), assemble (values only, into an
//! existing system; also for the Robin case), symbolic analysis, numeric factorisation, triangular solves.
//!
//! The `multigrid/<size>` groups time the multigrid route at the same sizes: a mesh at 16×
//! the area refined twice (`MeshHierarchy`), every level assembled (`MultilevelSystem`),
//! the cycle's set-up and the conjugate-gradient solve.
//!
//! `cargo bench -p harmonic-fem --bench fem` (filter sizes with e.g. `-- 1M`).

use std::sync::Arc;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_fem::{
    Assembler, AssemblyOptions, BoundaryCondition, BoundaryConditions, MULTIGRID_REL_TOL,
    MultigridOptions, MultilevelSystem, Ordering,
};
use harmonic_fixtures::reference_mesh;
use harmonic_solver::SymbolicCholesky;

/// The peers' Robin case (docs/peers.md, case (b)): ∂φ/∂n = 1 − φ on walls and obstacles.
fn robin() -> BoundaryConditions {
    BoundaryConditions::uniform(BoundaryCondition::Robin {
        a: 1.0,
        b: 1.0,
        g: 1.0,
    })
}

const SIZES: [(&str, f64); 4] = [
    ("3k", 0.045),
    ("30k", 0.0044),
    ("300k", 0.00044),
    ("1M", 0.000132),
];

fn stages(c: &mut Criterion) {
    for (label, max_area) in SIZES {
        let mut group = c.benchmark_group(format!("fem/{label}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(3));
        // Mesh only once the group is selected (criterion filters by id).
        let mesh = Arc::new(reference_mesh(max_area));
        let bcs = BoundaryConditions::default();
        eprintln!(
            "{label}: {} triangles, {} vertices",
            mesh.triangles().len(),
            mesh.vertices().len()
        );
        group.bench_function("pattern", |b| {
            b.iter(|| Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()))
        });
        let assembler =
            Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("pattern");
        let mut system = assembler.assemble(&bcs).expect("assembly");
        group.bench_function("assemble", |b| {
            b.iter(|| assembler.assemble_into(&bcs, None, &mut system))
        });
        // Robin walls and obstacles: no Dirichlet walls, more unknowns, boundary mass and load.
        let robin = robin();
        let robin_assembler =
            Assembler::new(Arc::clone(&mesh), &robin, AssemblyOptions::default()).expect("pattern");
        let mut robin_system = robin_assembler.assemble(&robin).expect("assembly");
        group.bench_function("assemble_robin", |b| {
            b.iter(|| robin_assembler.assemble_into(&robin, None, &mut robin_system))
        });
        let a = system.matrix();
        let orderings = [
            ("amd", Ordering::Amd),
            (
                "nd",
                Ordering::NestedDissection {
                    coords: assembler.unknown_coordinates(),
                },
            ),
        ];
        for (name, ordering) in orderings {
            group.bench_function(format!("symbolic_{name}"), |b| {
                b.iter(|| SymbolicCholesky::analyze(a, ordering.clone()))
            });
            let symbolic = SymbolicCholesky::analyze(a, ordering).expect("symbolic");
            group.bench_function(format!("numeric_{name}"), |b| b.iter(|| symbolic.factor(a)));
            let factor = symbolic.factor(a).expect("numeric");
            group.bench_function(format!("solve_{name}"), |b| {
                b.iter(|| factor.solve(system.rhs()))
            });
        }
        group.finish();
    }
}

/// Uniform refinements per multigrid hierarchy (the coarse mesh has 1/16 of the triangles).
const REFINEMENTS: usize = 2;

fn multigrid(c: &mut Criterion) {
    for (label, max_area) in &SIZES[1..] {
        let mut group = c.benchmark_group(format!("multigrid/{label}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(3));
        let coarse_area = max_area * 4f64.powi(REFINEMENTS as i32);
        let coarse = reference_mesh(coarse_area);
        group.bench_function("refine", |b| {
            b.iter(|| harmonic_mesh::uniform_hierarchy(coarse.clone(), REFINEMENTS))
        });
        let hierarchy = harmonic_mesh::uniform_hierarchy(coarse, REFINEMENTS).expect("refine");
        let bcs = BoundaryConditions::default();
        group.bench_function("assemble", |b| {
            b.iter(|| MultilevelSystem::assemble(&hierarchy, &bcs))
        });
        let levels = MultilevelSystem::assemble(&hierarchy, &bcs).expect("assemble");
        group.bench_function("setup", |b| {
            b.iter(|| levels.multigrid(MultigridOptions::default()))
        });
        let cycle = levels
            .multigrid(MultigridOptions::default())
            .expect("multigrid");
        group.bench_function("solve", |b| {
            b.iter(|| levels.solve(&cycle, MULTIGRID_REL_TOL))
        });
        group.finish();
    }
}

criterion_group!(benches, stages, multigrid);
criterion_main!(benches);
