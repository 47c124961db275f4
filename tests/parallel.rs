//! The planner's paths do not depend on how many threads solve the potential: the Cholesky
//! path (above `AUTO_ACCURATE_MAX_UNKNOWNS` unknowns) on one thread and on two.

use harmonic_planner::fem::Parallelism;
use harmonic_planner::{Planner, PlannerOptions, Scene};

#[test]
fn one_thread_and_two_give_the_same_paths() {
    let mut scene = Scene::from_file(harmonic_fixtures::mesh_file("reference.json")).unwrap();
    // About 130 k triangles: over 50 000 unknowns, so the solve is the (parallel) Cholesky.
    scene.mesh.max_area = Some(0.001);
    let build = |parallelism| {
        let options = PlannerOptions {
            parallelism,
            ..PlannerOptions::default()
        };
        Planner::with_options(&scene, &options).unwrap()
    };
    let sequential = build(Parallelism::Sequential);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let parallel = pool.install(|| {
        build(Parallelism::Rayon {
            from_unknowns: 0,
            dense_kernels: true,
        })
    });
    assert!(sequential.mesh().vertices().len() > 50_000);
    let starts = scene.starts.clone();
    assert!(!starts.is_empty());
    for start in starts {
        let (a, b) = (sequential.plan(start), parallel.plan(start));
        assert_eq!(a.status, b.status, "start {start:?}");
        let relative = (a.length - b.length).abs() / a.length.max(f64::MIN_POSITIVE);
        assert!(
            relative <= 1e-9,
            "start {start:?}: {} vs {} (relative {relative:e})",
            a.length,
            b.length
        );
    }
}
