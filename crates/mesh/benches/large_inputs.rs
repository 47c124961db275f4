//! Preparing and meshing the large inputs of the mesher's scaling work: a forest of 3000
//! circles in 100 × 100 m (in two halves on two threads, as by default, and in one piece)
//! and a circle sampled at 50 000 vertices in a 10 × 10 room. Set Triangle beside the forest
//! on the same boundary: `cargo run --release -p harmonic-mesh --example large_inputs --
//! forest 3000 --poly forest.poly` writes it, and `triangle -pq30a0.485331` meshes it.
//!
//! `cargo bench -p harmonic-mesh --bench large_inputs`

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_mesh::{Domain, DomainSpec, MeshOptions};
use std::hint::black_box;

fn prepare_and_mesh(spec: &DomainSpec, opts: &MeshOptions) -> usize {
    let domain = Domain::new(black_box(spec), opts).expect("valid scene");
    let (mesh, _) = domain.mesh(opts).expect("mesh");
    mesh.triangles().len()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("large_inputs");
    group.sample_size(10);
    let forest = harmonic_fixtures::forest(3000);
    let halves = MeshOptions::default();
    let one_piece = MeshOptions {
        halves_from: usize::MAX,
        ..MeshOptions::default()
    };
    group.bench_function("forest_3000", |b| {
        b.iter(|| prepare_and_mesh(&forest, &halves))
    });
    group.bench_function("forest_3000_one_piece", |b| {
        b.iter(|| prepare_and_mesh(&forest, &one_piece))
    });
    let detailed = harmonic_fixtures::detailed_room(50_000, 1.0);
    group.bench_function("detailed_50000", |b| {
        b.iter(|| prepare_and_mesh(&detailed, &halves))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
