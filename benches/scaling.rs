//! Thread scaling of a whole build (mesh, assemble, solve): the reference scene at 1 M
//! triangles and the 3D maze at 1 M tetrahedra, each in a rayon pool of 1 and of 2 threads
//! (the paths are the same at any count: `tests/parallel.rs`).
//!
//! `cargo bench --bench scaling` (about a minute per case on two cores)

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_planner::volume::VolumePlanner;
use harmonic_planner::{AnyScene, Planner, Scene};

fn mesh_file(name: &str) -> String {
    format!("{}/meshes/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn scaling(c: &mut Criterion) {
    let mut reference = Scene::from_file(mesh_file("reference.json")).expect("bundled scene");
    reference.mesh.max_area = Some(0.000132); // 994 k triangles
    let text = std::fs::read_to_string(mesh_file("maze3d.json")).expect("bundled scene");
    let Ok(AnyScene::Volume(mut maze)) = AnyScene::from_json(&text) else {
        panic!("maze3d.json is a volume scene")
    };
    maze.mesh.max_volume = Some(0.00065); // 1.00 M tetrahedra

    let mut group = c.benchmark_group("scaling");
    group.sample_size(10);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        group.bench_function(format!("reference_1M/{threads}"), |b| {
            b.iter(|| pool.install(|| black_box(Planner::new(&reference).expect("plans"))))
        });
        group.bench_function(format!("maze3d_1M_tets/{threads}"), |b| {
            b.iter(|| pool.install(|| black_box(VolumePlanner::new(&maze).expect("plans"))))
        });
    }
    group.finish();
}

criterion_group!(benches, scaling);
criterion_main!(benches);
