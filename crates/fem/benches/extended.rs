//! The cost of the extended-exponent accurate solve (`WideLdlt`, issue #19) against the
//! ordinary accurate solve (`AccurateLdlt`) on the same system: the reference scene's
//! Dirichlet system at about 30k and 300k triangles, nested dissection, numeric factorisation
//! plus triangular solves (the ordering and symbolic analysis are shared: the FEM solver
//! builds the extended factor on the ordinary one's elimination order and pattern).
//!
//! `cargo bench -p harmonic-fem --bench extended` (filter sizes with e.g. `-- 300k`).

use std::sync::Arc;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_fem::{Assembler, AssemblyOptions, BoundaryConditions};
use harmonic_fixtures::reference_mesh;
use harmonic_solver::{AccurateLdlt, WideLdlt};

const SIZES: [(&str, f64); 2] = [("30k", 0.0044), ("300k", 0.00044)];

fn extended(c: &mut Criterion) {
    for (label, max_area) in SIZES {
        let mut group = c.benchmark_group(format!("extended/{label}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_millis(500));
        group.measurement_time(Duration::from_secs(5));
        let mesh = Arc::new(reference_mesh(max_area));
        let bcs = BoundaryConditions::default();
        let assembler =
            Assembler::new(Arc::clone(&mesh), &bcs, AssemblyOptions::default()).expect("pattern");
        let system = assembler.assemble(&bcs).expect("assembly");
        let m = system.m_matrix().expect("an M-matrix");
        eprintln!(
            "{label}: {} triangles, {} unknowns",
            mesh.triangles().len(),
            m.n()
        );
        let mut accurate = AccurateLdlt::factor(&m, assembler.nested_dissection()).expect("factor");
        eprintln!("{label}: {} entries in L", accurate.factor_nnz());
        group.bench_function("accurate_factor_solve", |b| {
            b.iter(|| {
                accurate.refactor(&m).expect("refactor");
                accurate.solve(system.rhs()).expect("solve")
            })
        });
        group.bench_function("wide_factor_solve", |b| {
            b.iter(|| {
                WideLdlt::factor_like(&accurate, &m)
                    .expect("factor")
                    .solve(system.rhs())
                    .expect("solve")
            })
        });
    }
}

criterion_group!(benches, extended);
criterion_main!(benches);
