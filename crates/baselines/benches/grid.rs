//! Grid baselines on the reference scene by grid size: red–black SOR to a residual of 1e-13,
//! Gauss–Seidel (small grids only: it needs O(n²) sweeps), and the wavefront brushfire.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use harmonic_baselines::{Connectivity, GridHarmonic, Raster, Relaxation, SorOptions, Wavefront};
use harmonic_fixtures::{ScenePolygons, reference_polygons};

fn raster(n: usize) -> Raster {
    let ScenePolygons {
        workspace: ws,
        obstacles,
        goals,
    } = reference_polygons();
    Raster::from_polygons(&ws, &obstacles, &goals, n).expect("the reference scene rasterises")
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("grid");
    group.sample_size(10);
    for n in [64, 128, 256, 512] {
        let r = raster(n);
        let sor = SorOptions::default();
        group.bench_with_input(BenchmarkId::new("sor", n), &r, |b, r| {
            b.iter(|| GridHarmonic::solve(r.clone(), &sor).expect("valid options"))
        });
        if n <= 64 {
            let gs = SorOptions {
                relaxation: Relaxation::GaussSeidel,
                ..sor
            };
            group.bench_with_input(BenchmarkId::new("gauss_seidel", n), &r, |b, r| {
                b.iter(|| GridHarmonic::solve(r.clone(), &gs).expect("valid options"))
            });
        }
        group.bench_with_input(BenchmarkId::new("wavefront8", n), &r, |b, r| {
            b.iter(|| Wavefront::new(r.clone(), Connectivity::Eight))
        });
        group.bench_with_input(BenchmarkId::new("rasterise", n), &n, |b, &n| {
            b.iter(|| raster(n))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
