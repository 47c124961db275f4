//! The planner's paths do not depend on how many threads solve the potential: the Cholesky
//! path (`SolveMethod::Auto`'s above `AUTO_ACCURATE_MAX_UNKNOWNS` unknowns, asked for here)
//! and the multigrid route (the default from `AUTO_MULTIGRID_FROM` estimated triangles) on one
//! thread and on two.

use harmonic_planner::fem::{Parallelism, SolveMethod};
use harmonic_planner::{Planner, PlannerOptions, Scene};

#[test]
fn one_thread_and_two_give_the_same_paths() {
    let mut scene = Scene::from_file(harmonic_fixtures::mesh_file("reference.json")).unwrap();
    // About 130 k triangles: over 50 000 unknowns, where the Cholesky path runs in parallel,
    // and over `AUTO_MULTIGRID_FROM`, so the default is the multigrid route.
    scene.mesh.max_area = Some(0.001);
    for (multigrid, solve, solved_by) in [
        (Some(0), SolveMethod::Cholesky, "cholesky"),
        (None, SolveMethod::Auto, "multigrid"),
    ] {
        let build = |parallelism| {
            let options = PlannerOptions {
                parallelism,
                multigrid,
                solve,
                ..PlannerOptions::default()
            };
            Planner::with_options(&scene, &options).unwrap()
        };
        let sequential = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| build(Parallelism::Sequential));
        let parallel = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap()
            .install(|| {
                build(Parallelism::Rayon {
                    from_unknowns: 0,
                    dense_kernels: true,
                })
            });
        assert!(sequential.mesh().vertices().len() > 50_000);
        assert!(
            parallel.solved_by().starts_with(solved_by),
            "{}",
            parallel.solved_by()
        );
        let starts = scene.starts.clone();
        assert!(!starts.is_empty());
        for start in starts {
            let (a, b) = (sequential.plan(start), parallel.plan(start));
            assert_eq!(a.status, b.status, "start {start:?}");
            let relative = (a.length - b.length).abs() / a.length.max(f64::MIN_POSITIVE);
            assert!(
                relative <= 1e-9,
                "{solved_by}, start {start:?}: {} vs {} (relative {relative:e})",
                a.length,
                b.length
            );
        }
    }
}

/// Volumes and configuration spaces too: the stuffing, the face sort, the edge weights and
/// recovered gradients on every core, and the clamped solve tried beside the Galerkin one
/// give the same paths on one thread as on two (to 1e-9).
#[test]
fn volumes_and_configuration_spaces_plan_the_same_on_one_thread_and_two() {
    use harmonic_planner::AnyScene;
    use harmonic_planner::cspace::ConfigPlanner;
    use harmonic_planner::volume::VolumePlanner;
    let in_pool = |threads: usize, f: &(dyn Fn() -> Vec<Vec<f64>> + Sync)| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(f)
    };
    let flat = |points: Vec<Vec<f64>>| points.into_iter().flatten().collect::<Vec<f64>>();
    let same = |name: &str, a: Vec<f64>, b: Vec<f64>| {
        assert_eq!(a.len(), b.len(), "{name}");
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "{name}: paths differ by {worst:e}");
    };
    for name in ["torus3d.json", "maze3d.json"] {
        let text = std::fs::read_to_string(harmonic_fixtures::mesh_file(name)).unwrap();
        let Ok(AnyScene::Volume(scene)) = AnyScene::from_json(&text) else {
            panic!("{name} is a volume scene")
        };
        let paths = || {
            let planner = VolumePlanner::new(&scene).unwrap();
            scene
                .starts
                .iter()
                .flat_map(|&s| planner.plan(s).points)
                .map(|p| p.to_vec())
                .collect()
        };
        same(name, flat(in_pool(1, &paths)), flat(in_pool(2, &paths)));
    }
    for name in ["piano.json", "arm_aperture.json"] {
        let text = std::fs::read_to_string(harmonic_fixtures::mesh_file(name)).unwrap();
        let Ok(AnyScene::Config(scene)) = AnyScene::from_json(&text) else {
            panic!("{name} is a configuration-space scene")
        };
        let paths = || {
            let planner = ConfigPlanner::new(&scene).unwrap();
            scene
                .starts
                .iter()
                .flat_map(|s| planner.plan(s).configurations())
                .collect()
        };
        same(name, flat(in_pool(1, &paths)), flat(in_pool(2, &paths)));
    }
}

/// The `threads` option: a scene and a map planned on one thread and on two (the whole
/// build and `plan_many` in the planner's own pool) give the same paths to 1e-9, and zero
/// threads is refused in one line.
#[test]
fn the_threads_option_gives_the_same_paths_at_any_count() {
    use harmonic_planner::map::{MapOptions, OccupancyMap};
    let mut scene = Scene::from_file(harmonic_fixtures::mesh_file("reference.json")).unwrap();
    scene.mesh.max_area = Some(0.002);
    let options = |threads| PlannerOptions {
        threads: Some(threads),
        ..PlannerOptions::default()
    };
    let starts = scene.starts.clone();
    let one = Planner::with_options(&scene, &options(1)).unwrap();
    let two = Planner::with_options(&scene, &options(2)).unwrap();
    let (a, b) = (one.plan_many(&starts), two.plan_many(&starts));
    let map = OccupancyMap::load(harmonic_fixtures::mesh_file("costly_band.yaml")).unwrap();
    let map_starts = [[0.5, 0.5], [0.5, 2.0], [0.5, 3.5]];
    let on_map = |threads| {
        map.planner([7.5, 2.0], 0.0, &MapOptions::default(), &options(threads))
            .unwrap()
            .plan_many(&map_starts)
    };
    let (c, d) = (on_map(1), on_map(2));
    for (p, q) in a.iter().zip(&b).chain(c.iter().zip(&d)) {
        assert_eq!(p.status, q.status);
        assert!(p.status.reached_goal());
        assert!(
            (p.length - q.length).abs() <= 1e-9 * p.length,
            "{} vs {}",
            p.length,
            q.length
        );
    }
    let refused = Planner::with_options(&scene, &options(0)).unwrap_err();
    assert_eq!(
        refused.to_string(),
        "cannot plan on 0 threads: at least one thread is needed"
    );
}
