//! Graded costs shaping the field (`MapOptions::cost_weight`): a cell of cost c conducts
//! 1 / (1 + w·0.016·c) of a free cell's flow and absorbs w·`cost_absorption(c)` / (0.05 m)².
//!
//! - The bundled `meshes/costly_band.yaml` (a `scale` map: a block with a short route above it
//!   through a band of cost about 200, a longer one below): of seven starts down the left
//!   wall, fewer go through the band as the weight grows, none at weight 4; every start
//!   reaches the goal and the field has no interior local minimum.
//! - Seeded maps with random blocks and random cost blobs, weights from 0 to 8: the quadtree's
//!   system stays an M-matrix (the accurate solve accepts only those), no interior local
//!   minimum, every start on a clear cell connected to the goal reaches it, and no path
//!   crosses a blocked cell.
//! - Weight 0 plans exactly as the same map without costs, meshed alike.

use harmonic_fixtures::Rng;
use harmonic_planner::PlannerOptions;
use harmonic_planner::map::{Cell, MapMesher, MapOptions, OccupancyMap, UnknownCells};

fn bundled(name: &str) -> String {
    format!("{}/meshes/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn a_costly_band_turns_paths_away_as_the_weight_grows() {
    let map = OccupancyMap::load(bundled("costly_band.yaml")).expect("map");
    assert!(map.cost(80, 70) > 150, "the band has graded costs");
    let starts: Vec<[f64; 2]> = (1..=7).map(|k| [0.5, 0.5 * k as f64]).collect();
    let mut through = Vec::new();
    for w in [0.0, 1.0, 4.0] {
        let opts = MapOptions {
            cost_weight: w,
            ..MapOptions::default()
        };
        let planner = map
            .planner([7.5, 2.0], 0.0, &opts, &PlannerOptions::default())
            .expect("planner");
        let report = planner.plan_report(&starts);
        assert_eq!(report.potential.interior_local_minima, 0, "weight {w}");
        let mut above = 0;
        for p in &report.paths {
            assert!(p.status.reached_goal(), "weight {w}: {:?}", p.status);
            // Over the block (x 3..5 m, y 1..3 m) a path is either above or below it.
            let over: Vec<f64> = p
                .points
                .iter()
                .filter(|q| (3.0..=5.0).contains(&q[0]))
                .map(|q| q[1])
                .collect();
            if over.iter().all(|&y| y > 2.9) {
                above += 1;
            }
        }
        println!("weight {w}: {above} of 7 paths through the band");
        through.push(above);
    }
    assert!(through.windows(2).all(|w| w[1] <= w[0]), "{through:?}");
    assert!(through[0] >= 3, "{through:?}");
    assert_eq!(through[2], 0, "{through:?}");
}

/// A seeded grid: blocks of random size at `density`, cost blobs of random cost and radius.
fn random_map(seed: u64) -> OccupancyMap {
    let mut rng = Rng(seed);
    let (w, h) = (48 + rng.below(32), 40 + rng.below(24));
    let mut cells = vec![Cell::Free; w * h];
    let blocks = 6 + rng.below(10);
    for _ in 0..blocks {
        let (bw, bh) = (1 + rng.below(6), 1 + rng.below(6));
        let (x0, y0) = (rng.below(w - bw), rng.below(h - bh));
        for y in y0..y0 + bh {
            for x in x0..x0 + bw {
                cells[y * w + x] = Cell::Occupied;
            }
        }
    }
    let mut costs = vec![0u8; w * h];
    for _ in 0..4 + rng.below(6) {
        let (cx, cy) = (rng.below(w) as f64, rng.below(h) as f64);
        let r = 2.0 + 8.0 * rng.next_f64();
        let c = 1 + rng.below(252) as u8;
        for y in 0..h {
            for x in 0..w {
                if (x as f64 - cx).hypot(y as f64 - cy) <= r {
                    costs[y * w + x] = costs[y * w + x].max(c);
                }
            }
        }
    }
    OccupancyMap::from_cells(w, h, 0.1, [0.0, 0.0, 0.0], cells)
        .and_then(|m| m.with_costs(costs))
        .expect("map")
}

/// Whether the segment a–b stays on free cells (sampled at a hundredth of a cell).
fn on_free_cells(map: &OccupancyMap, a: [f64; 2], b: [f64; 2]) -> bool {
    let n = ((a[0] - b[0]).hypot(a[1] - b[1]) / (0.01 * map.resolution())).ceil() as usize + 1;
    (0..=n).all(|k| {
        let t = k as f64 / n as f64;
        let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        map.cell_at(p)
            .is_some_and(|(c, r)| !map.is_blocked(c, r, UnknownCells::Obstacle))
    })
}

#[test]
fn random_costs_keep_the_maximum_principle_and_completeness() {
    for seed in 1..=8u64 {
        let map = random_map(seed);
        let mut rng = Rng(1000 + seed);
        let free: Vec<(usize, usize)> = (0..map.height())
            .flat_map(|r| (0..map.width()).map(move |c| (c, r)))
            .filter(|&(c, r)| !map.is_blocked(c, r, UnknownCells::Obstacle))
            .collect();
        let pick = |rng: &mut Rng| {
            let (c, r) = free[rng.below(free.len())];
            map.cell_center(c, r)
        };
        let goal = pick(&mut rng);
        let starts: Vec<[f64; 2]> = (0..6).map(|_| pick(&mut rng)).collect();
        let weight = 8.0 * rng.next_f64();
        let opts = MapOptions {
            cost_weight: weight,
            ..MapOptions::default()
        };
        let planner = match map.planner(goal, 0.0, &opts, &PlannerOptions::default()) {
            Ok(p) => p,
            // A goal walled in by blocks is refused, as without costs.
            Err(e) => {
                println!("seed {seed}: {e}");
                continue;
            }
        };
        let report = planner.plan_report(&starts);
        assert_eq!(
            report.potential.interior_local_minima, 0,
            "seed {seed}, weight {weight}"
        );
        for p in &report.paths {
            let connected = !matches!(
                p.status,
                harmonic_planner::trajectory::TraceStatus::Unreachable
            );
            if !connected {
                continue;
            }
            assert!(
                p.status.reached_goal(),
                "seed {seed}, weight {weight:.2}, from {:?}: {:?}",
                p.start,
                p.status
            );
            for s in p.points.windows(2) {
                assert!(on_free_cells(&map, s[0], s[1]), "seed {seed}: {s:?}");
            }
        }
    }
}

/// A corridor 20 m long and 0.35 m wide whose every cell costs 252, at weight 8: each cell
/// absorbs so much that ψ falls about e^(−2300) from one end to the other, far below the
/// float range, and the solve goes on in extended exponents; the start at the far end (and
/// one beside the wall halfway) still reaches the goal point, on free cells.
#[test]
fn a_long_corridor_of_the_costliest_cells_still_plans_at_weight_eight() {
    let (w, h) = (404, 9);
    let mut cells = vec![Cell::Free; w * h];
    for c in 0..w {
        cells[c] = Cell::Occupied;
        cells[(h - 1) * w + c] = Cell::Occupied;
    }
    let costs: Vec<u8> = (0..w * h)
        .map(|i| if cells[i] == Cell::Free { 252 } else { 0 })
        .collect();
    let map = OccupancyMap::from_cells(w, h, 0.05, [0.0, 0.0, 0.0], cells)
        .and_then(|m| m.with_costs(costs))
        .expect("map");
    let opts = MapOptions {
        cost_weight: 8.0,
        ..MapOptions::default()
    };
    let planner = map
        .planner([0.2, 0.225], 0.0, &opts, &PlannerOptions::default())
        .expect("planner");
    let report = planner.plan_report(&[[20.0, 0.225], [10.0, 0.1]]);
    assert_eq!(report.potential.interior_local_minima, 0);
    assert!(
        report.potential.solved_by.contains("extended"),
        "{}",
        report.potential.solved_by
    );
    for p in &report.paths {
        assert!(
            p.status.reached_goal(),
            "from {:?}: {:?}",
            p.start,
            p.status
        );
        assert!((p.points.last().expect("a point")[0] - 0.2).abs() < 1e-9);
        for s in p.points.windows(2) {
            assert!(on_free_cells(&map, s[0], s[1]), "{s:?}");
        }
    }
}

#[test]
fn weight_zero_plans_as_the_map_without_costs() {
    let with = OccupancyMap::load(bundled("costly_band.yaml")).expect("map");
    let cells: Vec<Cell> = (0..with.height())
        .flat_map(|r| (0..with.width()).map(move |c| (c, r)))
        .map(|(c, r)| with.cell(c, r))
        .collect();
    let without =
        OccupancyMap::from_cells(with.width(), with.height(), 0.05, [0.0, 0.0, 0.0], cells)
            .expect("map");
    // A map with graded costs is meshed on its grid at every weight (the default mesher
    // picks the quadtree), so weight 0 there is the bare map's field on the quadtree.
    let weight0 = MapOptions {
        cost_weight: 0.0,
        ..MapOptions::default()
    };
    let quadtree = MapOptions {
        mesher: MapMesher::Quadtree,
        ..MapOptions::default()
    };
    let starts = [[0.5, 0.5], [0.5, 2.0], [0.5, 3.5]];
    let plan = |m: &OccupancyMap, opts: &MapOptions| {
        m.planner([7.5, 2.0], 0.0, opts, &PlannerOptions::default())
            .expect("planner")
            .plan_report(&starts)
    };
    let (a, b) = (plan(&with, &weight0), plan(&without, &quadtree));
    for (p, q) in a.paths.iter().zip(&b.paths) {
        assert!(
            (p.length - q.length).abs() < 1e-9,
            "{} vs {}",
            p.length,
            q.length
        );
    }
}

/// A weight below 0, above `MAX_COST_WEIGHT` or not a number is refused in one line naming
/// the option and the range; the largest weight still plans.
#[test]
fn cost_weights_out_of_range_are_refused() {
    let map = OccupancyMap::load(bundled("costly_band.yaml")).expect("map");
    let with = |w: f64| MapOptions {
        cost_weight: w,
        ..MapOptions::default()
    };
    for w in [-1.0, 1e7, f64::NAN, f64::INFINITY] {
        let Err(err) = map.planner([7.5, 2.0], 0.0, &with(w), &PlannerOptions::default()) else {
            panic!("weight {w} planned");
        };
        let message = err.to_string();
        assert!(
            message.contains("cost_weight") && message.contains("between 0 and 1e6"),
            "{message}"
        );
    }
    let planner = map
        .planner(
            [7.5, 2.0],
            0.0,
            &with(harmonic_planner::map::MAX_COST_WEIGHT),
            &PlannerOptions::default(),
        )
        .expect("the largest weight plans");
    assert!(planner.plan([0.5, 0.5]).status.reached_goal());
}
