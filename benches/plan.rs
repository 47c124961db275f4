//! The whole pipeline on the reference scene (about 31 k triangles): scene → mesh → assemble
//! → factor → solve, and one path query on the built planner.
//!
//! `cargo bench --bench plan`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_planner::{Planner, Scene};

fn plan(c: &mut Criterion) {
    let scene = Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/meshes/reference.json"
    ))
    .expect("bundled scene");
    let mut group = c.benchmark_group("plan");
    group.sample_size(20);
    group.bench_function("build/reference", |b| {
        b.iter(|| black_box(Planner::new(&scene).expect("plans")))
    });
    let planner = Planner::new(&scene).expect("plans");
    group.bench_function("query/reference_1_9", |b| {
        b.iter(|| black_box(planner.plan([1.0, 9.0])))
    });
    group.finish();
}

criterion_group!(benches, plan);
criterion_main!(benches);
