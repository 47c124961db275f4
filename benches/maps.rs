//! Nav2's occupancy maps against NavFn: for each of NavFn's measured requests, the first plan
//! from the loaded grid (mesh the map by its default mesher, assemble, factor, solve, trace
//! one path), and a later start on the built planner (a trace only). NavFn recomputes its
//! navigation function on every request; its times are printed beside ours.
//!
//! `HARMONIC_NAV2_MAPS=DIR cargo bench --bench maps` (the Nav2 part skipped with a message
//! without the maps). The `grids` group needs nothing: generated maps of every family a
//! grid-search user brings (a 255² maze of one-cell corridors, 256² rooms joined by one-cell
//! doors, 256² streets, 30 % random blocks, the 400-cell one-cell spiral, an office at 5 cm
//! for a 0.22 m robot, and that office inside a 2048² map of unknown cells, as SLAM leaves
//! a map), a point robot (the office: 0.22 m) between two far cells.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use harmonic_fixtures::occupancy::{self, Occ, OccGrid, clear_cells, random_pairs};
use harmonic_fixtures::{NAVFN_REQUESTS, NAVFN_ROBOT_RADIUS, nav2_maps_dir};
use harmonic_planner::PlannerOptions;
use harmonic_planner::map::{Cell, MapOptions, OccupancyMap};

/// First plan and later start on generated maps of every family.
fn grids(c: &mut Criterion) {
    let mut group = c.benchmark_group("grids");
    group.sample_size(10);
    let families = [
        ("maze_255", occupancy::maze(7, 255, 255, 1), 1.0, 0.0),
        ("rooms_256", occupancy::rooms(8, 256, 256, 1), 1.0, 0.0),
        ("streets_256", occupancy::streets(9, 256, 256), 1.0, 0.0),
        (
            "random_30_128",
            occupancy::random_blocks(10, 128, 128, 0.3),
            1.0,
            0.0,
        ),
        ("spiral_400", occupancy::spiral(400), 1.0, 0.0),
        (
            "office_5cm",
            occupancy::office(11),
            occupancy::OFFICE_RESOLUTION,
            occupancy::OFFICE_ROBOT_RADIUS,
        ),
        (
            "office_5cm_in_2048_unknown",
            in_unknown(&occupancy::office(11), 2048, [900, 700]),
            occupancy::OFFICE_RESOLUTION,
            occupancy::OFFICE_ROBOT_RADIUS,
        ),
    ];
    for (name, grid, res, radius) in families {
        let map = map_of(&grid, res);
        let clear = clear_cells(&grid, radius / res);
        let Some(&(s, g)) = random_pairs(1, &clear, grid.width, grid.height, 1, 8.0).first() else {
            eprintln!("{name}: no pair drawn");
            continue;
        };
        let (start, goal) = (map.cell_center(s.0, s.1), map.cell_center(g.0, g.1));
        let first = || {
            let planner = map
                .planner(
                    goal,
                    radius,
                    &MapOptions::default(),
                    &PlannerOptions::default(),
                )
                .expect("planner");
            let path = planner.plan(start);
            (planner, path)
        };
        let (planner, path) = first();
        eprintln!(
            "{name}: {} triangles, {} {:.2}",
            planner.mesh().triangles().len(),
            path.status,
            path.length
        );
        group.bench_function(format!("first_plan/{name}"), |b| {
            b.iter(|| black_box(first()))
        });
        group.bench_function(format!("later_start/{name}"), |b| {
            b.iter(|| black_box(planner.plan(start)))
        });
    }
    group.finish();
}

/// `grid` put into a `size`² grid of unknown cells, its cell (0, 0) at `at`.
fn in_unknown(grid: &OccGrid, size: usize, at: [usize; 2]) -> OccGrid {
    let mut big = OccGrid::new(size, size, Occ::Unknown);
    for j in 0..grid.height {
        for i in 0..grid.width {
            big.set(at[0] + i, at[1] + j, grid.cells[j * grid.width + i]);
        }
    }
    big
}

fn map_of(grid: &OccGrid, resolution: f64) -> OccupancyMap {
    let cells = grid
        .cells
        .iter()
        .map(|c| match c {
            Occ::Free => Cell::Free,
            Occ::Occupied => Cell::Occupied,
            Occ::Unknown => Cell::Unknown,
        })
        .collect();
    OccupancyMap::from_cells(grid.width, grid.height, resolution, [0.0; 3], cells).expect("map")
}

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

criterion_group!(benches, maps, grids);
criterion_main!(benches);
