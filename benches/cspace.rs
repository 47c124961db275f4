//! Configuration-space planners built from scratch (space, graded periodic mesh, goal carving,
//! assembly, planning solve, field): the bundled polygon robots and arms, and the slowest
//! 3-link arm of the seeded scenes `cargo run --release --example cspace_reach -- 24 25`
//! draws (seed 31, 800 k tetrahedra: `benches/scenes/arm3_seed31.json` as `-- scene 31`
//! writes it, starts included, some of which the draw put in collision; only the build is
//! timed).
//! The target for arms is at most 3 s each on a 2-core machine.
//!
//! `cargo bench --bench cspace`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_planner::{AnyScene, ConfigPlanner};

const SCENES: [&str; 5] = [
    "meshes/contract/polygon_example.json",
    "meshes/contract/arm_joints_example.json",
    "meshes/contract/arm_tip_example.json",
    "meshes/piano.json",
    "benches/scenes/arm3_seed31.json",
];

fn cspace(c: &mut Criterion) {
    let mut group = c.benchmark_group("cspace");
    group.sample_size(10);
    for name in SCENES {
        let path = format!("{}/{name}", env!("CARGO_MANIFEST_DIR"));
        let AnyScene::Config(scene) = AnyScene::from_file(&path).expect("bundled scene") else {
            panic!("{name} is not a configuration-space scene");
        };
        group.bench_function(format!("build/{name}"), |b| {
            b.iter(|| black_box(ConfigPlanner::new(&scene).expect("plans")))
        });
    }
    group.finish();
}

criterion_group!(benches, cspace);
criterion_main!(benches);
