//! Meshing the reference scene at the peers' sizes (Triangle `pq30a<A>`: 3k, 30k, 300k, 1M
//! triangles for A = 0.045, 0.0044, 0.00044, 0.000132), with and without the lattice prefill;
//! 300k and 1M (made in two halves on two threads by default) also in one piece.
//!
//! `cargo bench -p harmonic-mesh --bench mesh`

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_mesh::{Domain, MeshOptions};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let spec = harmonic_fixtures::reference_disc();
    let sizes = [
        ("3k", 0.045),
        ("30k", 0.0044),
        ("300k", 0.00044),
        ("1M", 0.000132),
    ];
    let mut group = c.benchmark_group("mesh");
    group.sample_size(10);
    for (name, max_area) in sizes {
        for prefill in [false, true] {
            let opts = MeshOptions {
                max_area: Some(max_area),
                prefill,
                ..MeshOptions::default()
            };
            let id = format!("{name}{}", if prefill { "_lattice" } else { "" });
            group.bench_function(id, |b| {
                b.iter(|| {
                    let domain = Domain::new(black_box(&spec), &opts).expect("valid scene");
                    domain.mesh(&opts).expect("mesh")
                })
            });
        }
        if max_area < 0.001 {
            let opts = MeshOptions {
                max_area: Some(max_area),
                halves_from: usize::MAX,
                ..MeshOptions::default()
            };
            group.bench_function(format!("{name}_one_piece"), |b| {
                b.iter(|| {
                    let domain = Domain::new(black_box(&spec), &opts).expect("valid scene");
                    domain.mesh(&opts).expect("mesh")
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
