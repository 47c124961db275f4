//! Meshing (isosurface stuffing + the exact clearance check), assembly and solve on a volume
//! scene with a box hole, a ball and a goal ball, at about 100k tetrahedra; set
//! `VOLUME_BENCH_1M=1` to add the same at about 1M tetrahedra.
//!
//! ```text
//! cargo bench -p harmonic-volume --bench volume
//! VOLUME_BENCH_1M=1 cargo bench -p harmonic-volume --bench volume
//! ```

use std::sync::Arc;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_fem::BoundaryConditions;
use harmonic_fem::volume::{VolumeAssembler, VolumeSolveMethod, solve_volume};
use harmonic_volume::{GoalRegion, MeshOptions, Part, Point, Solid, SphereSolid, VolumeDomain};

fn scene() -> VolumeDomain {
    VolumeDomain::new(
        Solid::new_box(
            Part::Workspace,
            Point::new(0.0, 0.0, 0.0),
            Point::new(10.0, 10.0, 10.0),
        )
        .expect("valid box"),
        vec![
            Solid::new_box(
                Part::Obstacle(0),
                Point::new(3.0, 3.0, -1.0),
                Point::new(7.0, 7.0, 11.0),
            )
            .expect("valid box"),
            Solid::new_sphere(Part::Obstacle(1), Point::new(2.0, 8.0, 5.0), 1.0)
                .expect("valid ball"),
        ],
        vec![GoalRegion::Sphere(SphereSolid {
            center: Point::new(9.0, 9.0, 9.0),
            radius: 0.5,
        })],
        0.1,
    )
    .expect("valid scene")
}

fn bench_size(c: &mut Criterion, label: &str, max_volume: f64) {
    let domain = scene();
    let opts = MeshOptions::with_max_volume(max_volume);
    let (mesh, report) = domain.mesh(&opts).expect("meshes");
    let tets = mesh.tetrahedra().len();
    let mesh = Arc::new(mesh);
    let bcs = BoundaryConditions::default();
    let assembler = VolumeAssembler::new(Arc::clone(&mesh), &bcs).expect("pattern");
    let system = assembler.assemble(&bcs).expect("assembly");
    eprintln!(
        "{label}: {tets} tetrahedra, {} vertices, {} unknowns, {} passes",
        mesh.vertices().len(),
        system.matrix().n(),
        report.passes
    );
    let mut group = c.benchmark_group(label);
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    group.bench_function("mesh", |b| b.iter(|| domain.mesh(&opts).expect("meshes")));
    group.bench_function("assembler_new", |b| {
        b.iter(|| VolumeAssembler::new(Arc::clone(&mesh), &bcs).expect("pattern"))
    });
    group.bench_function("assemble", |b| {
        b.iter(|| assembler.assemble(&bcs).expect("assembly"))
    });
    group.bench_function("solve_auto", |b| {
        b.iter(|| solve_volume(&system, VolumeSolveMethod::Auto).expect("solve"))
    });
    group.finish();
}

fn benches(c: &mut Criterion) {
    // h = 0.47: about 100k tetrahedra (h = 0.24 gives 742k).
    bench_size(c, "volume_100k", 0.47f64.powi(3) / 12.0);
    if std::env::var_os("VOLUME_BENCH_1M").is_some() {
        bench_size(c, "volume_1m", 0.217f64.powi(3) / 12.0);
    }
}

criterion_group!(volume, benches);
criterion_main!(volume);
