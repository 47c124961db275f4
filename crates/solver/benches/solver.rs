//! Stage-by-stage benchmarks on triangulated-grid P1 Laplacians (7-point pattern, Dirichlet
//! boundary eliminated) of about 1.5k, 15k, 150k and 500k unknowns: symbolic analysis, numeric
//! factorisation and solve for AMD and geometric nested dissection, and IC(0)-PCG (up to 150k;
//! the 500k PCG figure comes from `examples/orderings.rs`, one run takes ~10 s).
//!
//! `cargo bench -p harmonic-solver --bench solver` (filter e.g. `-- 499849`).

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harmonic_solver::{Ordering, PcgOptions, Preconditioner, SymbolicCholesky, gallery, pcg};

const SIDES: [usize; 4] = [39, 122, 387, 707];

fn direct(c: &mut Criterion) {
    for side in SIDES {
        let (a, coords) = gallery::triangulated_grid_laplacian(side, side);
        let n = a.n();
        let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
        let mut group = c.benchmark_group(format!("cholesky/{n}"));
        group.sample_size(10);
        for (name, ord) in [
            ("amd", Ordering::Amd),
            (
                "nd",
                Ordering::NestedDissection {
                    coords: coords.clone(),
                },
            ),
        ] {
            group.bench_function(BenchmarkId::new("symbolic", name), |bench| {
                bench.iter(|| SymbolicCholesky::analyze(black_box(&a), ord.clone()).unwrap())
            });
            let symbolic = SymbolicCholesky::analyze(&a, ord.clone()).unwrap();
            group.bench_function(BenchmarkId::new("numeric", name), |bench| {
                bench.iter(|| symbolic.factor(black_box(&a)).unwrap())
            });
            let chol = symbolic.factor(&a).unwrap();
            let mut x = b.clone();
            group.bench_function(BenchmarkId::new("solve", name), |bench| {
                bench.iter(|| {
                    x.copy_from_slice(&b);
                    chol.solve_in_place(black_box(&mut x)).unwrap()
                })
            });
            group.bench_function(BenchmarkId::new("total", name), |bench| {
                bench.iter(|| {
                    SymbolicCholesky::analyze(black_box(&a), ord.clone())
                        .unwrap()
                        .factor(&a)
                        .unwrap()
                        .solve(&b)
                        .unwrap()
                })
            });
        }
        if n <= 200_000 {
            let opts = PcgOptions {
                preconditioner: Preconditioner::IncompleteCholesky,
                rel_tol: 1e-10,
                max_iter: 10_000,
            };
            let mut x = vec![0.0; n];
            group.bench_function("pcg_ic0", |bench| {
                bench.iter(|| {
                    x.fill(0.0);
                    pcg(black_box(&a), &b, &mut x, &opts).unwrap()
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, direct);
criterion_main!(benches);
