//! FEM against Connolly's grid planner (SOR) at comparable resolution on the unit-square
//! scene of `meshes/garrido_fig1.json`: the grid is N × N, the mesh has triangles of at most
//! the cell's area. The FEM side is mesh + assemble + factor + solve; the SOR side is
//! rasterise + relax to a normalised residual of 1e-13 (the baseline's default).
//!
//! `cargo bench --bench fem_vs_sor`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_baselines::{GridHarmonic, Raster, SorOptions};
use harmonic_planner::mesh::Domain;
use harmonic_planner::scene::Region;
use harmonic_planner::{Planner, Scene};

fn scene() -> Scene {
    let mut scene = Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/garrido_fig1.json"
    ))
    .expect("bundled scene");
    scene.goal.0 = vec![Region {
        polygon: Some(vec![[0.7, 0.1], [0.8, 0.1], [0.8, 0.2], [0.7, 0.2]]),
        ..Region::default()
    }];
    scene
}

fn fem_vs_sor(c: &mut Criterion) {
    let scene = scene();
    let domain = Domain::new(&scene.domain_spec(), &scene.mesh_options()).expect("valid scene");
    let mut group = c.benchmark_group("fem_vs_sor");
    group.sample_size(10);
    for n in [50usize, 100, 200] {
        group.bench_function(format!("sor/{n}"), |b| {
            b.iter(|| {
                let raster = Raster::from_domain(&domain, n).expect("raster");
                let options = SorOptions::default();
                black_box(GridHarmonic::solve(raster, &options).expect("sor converges"))
            })
        });
        let mut s = scene.clone();
        s.mesh.max_area = Some(1.0 / (n * n) as f64);
        group.bench_function(format!("fem/{n}"), |b| {
            b.iter(|| black_box(Planner::new(&s).expect("plans")))
        });
    }
    group.finish();
}

criterion_group!(benches, fem_vs_sor);
criterion_main!(benches);
