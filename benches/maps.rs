//! Nav2's occupancy maps against NavFn: for each of NavFn's measured requests, the first plan
//! from the loaded grid (mesh the map by its default mesher, assemble, factor, solve, trace
//! one path), and a later start on the built planner (a trace only). NavFn recomputes its
//! navigation function on every request; its times are printed beside ours.
//!
//! `HARMONIC_NAV2_MAPS=DIR cargo bench --bench maps` (skipped with a message without the maps)

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_fixtures::{NAVFN_REQUESTS, NAVFN_ROBOT_RADIUS, nav2_maps_dir};
use harmonic_planner::PlannerOptions;
use harmonic_planner::map::{MapOptions, OccupancyMap};

fn maps(c: &mut Criterion) {
    let Some(dir) = nav2_maps_dir() else {
        eprintln!("maps bench skipped: set HARMONIC_NAV2_MAPS to a folder of Nav2's maps");
        return;
    };
    let mut group = c.benchmark_group("maps");
    group.sample_size(10);
    for r in NAVFN_REQUESTS {
        let map = OccupancyMap::load(dir.join(format!("{}.yaml", r.map))).expect("map loads");
        let name = format!("{}_{}_{}", r.map, r.start[0], r.start[1]);
        let first = || {
            let planner = map
                .planner(
                    r.goal,
                    NAVFN_ROBOT_RADIUS,
                    &MapOptions::default(),
                    &PlannerOptions::default(),
                )
                .expect("planner");
            let path = planner.plan(r.start);
            (planner, path)
        };
        let (planner, path) = first();
        eprintln!(
            "{name}: NavFn {} ms per request; ours {} triangles, {} {:.2} m (NavFn {:.2} m)",
            r.navfn_ms,
            planner.mesh().triangles().len(),
            path.status,
            path.length,
            r.navfn_length
        );
        group.bench_function(format!("first_plan/{name}"), |b| {
            b.iter(|| black_box(first()))
        });
        group.bench_function(format!("later_start/{name}"), |b| {
            b.iter(|| black_box(planner.plan(r.start)))
        });
    }
    group.finish();
}

criterion_group!(benches, maps);
criterion_main!(benches);
