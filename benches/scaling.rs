//! Thread scaling of a whole build (mesh, assemble, solve): the reference scene at 1 M
//! triangles and the 3D maze at 1 M tetrahedra, each in a rayon pool of 1 and of 2 threads
//! (the paths are the same at any count: `tests/parallel.rs`).
//!
//! Before timing, each case is built once and its peak resident memory printed (Linux:
//! `VmHWM` of `/proc/self/status`, reset through `/proc/self/clear_refs` before each case).
//!
//! `cargo bench --bench scaling` (about a minute per case on two cores)

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_planner::volume::VolumePlanner;
use harmonic_planner::{AnyScene, Planner, Scene};

fn mesh_file(name: &str) -> String {
    format!("{}/meshes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Resets the process's peak resident memory (Linux; elsewhere nothing happens).
fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// The process's peak resident memory since the last reset, in MB (Linux).
fn peak_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Builds once and prints the peak memory the build reached.
fn report_peak<T>(name: &str, build: impl FnOnce() -> T) {
    reset_peak();
    let built = build();
    match peak_mb() {
        Some(mb) => println!("peak memory, {name}: {mb:.0} MB"),
        None => println!("peak memory, {name}: not measured on this system"),
    }
    drop(built);
}

fn scaling(c: &mut Criterion) {
    let mut reference = Scene::from_file(mesh_file("reference.json")).expect("bundled scene");
    reference.mesh.max_area = Some(0.000132); // 994 k triangles
    let text = std::fs::read_to_string(mesh_file("maze3d.json")).expect("bundled scene");
    let Ok(AnyScene::Volume(mut maze)) = AnyScene::from_json(&text) else {
        panic!("maze3d.json is a volume scene")
    };
    maze.mesh.max_volume = Some(0.00065); // 1.00 M tetrahedra
    report_peak("reference_1M", || Planner::new(&reference).expect("plans"));
    report_peak("maze3d_1M_tets", || {
        VolumePlanner::new(&maze).expect("plans")
    });

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
