//! Graded costs on Nav2's maps: paths at cost weight 0 and at another weight (default 1) on
//! the costmap Nav2 builds for a 0.22 m robot (inflation 0.7 m, cost scaling 3), planned for
//! a point (the costmap's 253 cells are where the centre may not go, as in Nav2), compared
//! on the grid: each path's narrowest clearance to a blocked cell (exact, the whole path) and
//! its mean cost.
//!
//! ```sh
//! cargo run --release --example cost_weight -- MAPS_DIR [--weight W] [--seeds N]
//! ```
//!
//! `MAPS_DIR` holds Nav2's maps (`depot.yaml`, …). The pairs: NavFn's 18 requests, then for
//! each seed 1..=N three random goals and five random starts on each map's clear cells.

use harmonic_fixtures::Rng;
use harmonic_fixtures::maps::{NAVFN_REQUESTS, mean_cost_along, nav2_inflated_costs};
use harmonic_fixtures::occupancy::polyline_clearance;
use harmonic_planner::map::{Cell, MapOptions, OccupancyMap};

/// A map with Nav2's inflated costmap: the planner's map and the costs.
struct Costmap {
    map: OccupancyMap,
    costs: Vec<u8>,
    blocked: Vec<bool>,
}

impl Costmap {
    fn load(dir: &str, name: &str) -> Costmap {
        let bare = OccupancyMap::load(format!("{dir}/{name}.yaml")).expect("map");
        let (w, h) = (bare.width(), bare.height());
        let cells: Vec<u8> = (0..h)
            .flat_map(|r| (0..w).map(move |c| (c, r)))
            .map(|(c, r)| match bare.cell(c, r) {
                Cell::Free => 0,
                Cell::Occupied => 254,
                Cell::Unknown => 255,
            })
            .collect();
        let costs = nav2_inflated_costs(&cells, w, h, bare.resolution());
        // As the C interface reads a costmap: 253 and up blocked, 1–252 graded.
        let occupancy = costs
            .iter()
            .map(|&c| match c {
                255 => Cell::Unknown,
                253.. => Cell::Occupied,
                _ => Cell::Free,
            })
            .collect();
        let graded = costs.iter().map(|&c| if c < 253 { c } else { 0 }).collect();
        let map = OccupancyMap::from_cells(w, h, bare.resolution(), bare.origin(), occupancy)
            .and_then(|m| m.with_costs(graded))
            .expect("costmap");
        let blocked = costs.iter().map(|&c| c >= 253).collect();
        Costmap {
            map,
            costs,
            blocked,
        }
    }

    fn in_cells(&self, points: &[[f64; 2]]) -> Vec<[f64; 2]> {
        let (res, o) = (self.map.resolution(), self.map.origin());
        points
            .iter()
            .map(|p| [(p[0] - o[0]) / res, (p[1] - o[1]) / res])
            .collect()
    }

    /// (narrowest clearance in metres, mean cost) of a path.
    fn measure(&self, points: &[[f64; 2]]) -> (f64, f64) {
        let (w, h, res) = (self.map.width(), self.map.height(), self.map.resolution());
        let cells = self.in_cells(points);
        (
            res * polyline_clearance(&self.blocked, w, h, &cells),
            mean_cost_along(&self.costs, w, h, &cells, 0.01 / res),
        )
    }
}

#[derive(Default)]
struct Tally {
    pairs: usize,
    unreached: usize,
    narrower: usize,
    worst: f64,
    costlier: usize,
    cost: [f64; 2],
    build_ms: [f64; 2],
}

impl Tally {
    fn print(&self, what: &str, weight: f64) {
        println!(
            "{what}: {} pairs, {} unreached; at weight {weight}: narrower by more than 1 mm on {} (by at most {:.4} m), costlier on {}, mean cost {:.2} -> {:.2}",
            self.pairs,
            self.unreached,
            self.narrower,
            self.worst,
            self.costlier,
            self.cost[0] / self.pairs.max(1) as f64,
            self.cost[1] / self.pairs.max(1) as f64
        );
        println!(
            "  planners built in {:.0} ms at weight 0, {:.0} ms at weight {weight}, all together",
            self.build_ms[0], self.build_ms[1]
        );
    }
}

/// Plans `starts` to `goal` at weights 0 and `weight`, prints one line per start and tallies.
fn compare(
    cm: &Costmap,
    name: &str,
    goal: [f64; 2],
    starts: &[[f64; 2]],
    weight: f64,
    tally: &mut Tally,
) {
    let mut build_ms = [0.0; 2];
    let planners: Vec<_> = [0.0, weight]
        .iter()
        .zip(&mut build_ms)
        .map(|(&w, ms)| {
            let opts = MapOptions {
                cost_weight: w,
                ..MapOptions::default()
            };
            let t = std::time::Instant::now();
            let p = cm.map.planner(goal, 0.0, &opts, &Default::default());
            *ms = t.elapsed().as_secs_f64() * 1e3;
            p.expect("planner")
        })
        .collect();
    tally.build_ms[0] += build_ms[0];
    tally.build_ms[1] += build_ms[1];
    println!(
        "{name}, goal {goal:?}: planner built in {:.1} ms at weight 0, {:.1} ms at weight {weight}",
        build_ms[0], build_ms[1]
    );
    for &s in starts {
        let (a, b) = (planners[0].plan(s), planners[1].plan(s));
        if !a.status.reached_goal() || !b.status.reached_goal() {
            tally.unreached += 1;
            println!(
                "  {name} {s:?} -> {goal:?}: {:?} / {:?}",
                a.status, b.status
            );
            continue;
        }
        let (n0, m0) = cm.measure(&a.points);
        let (n1, m1) = cm.measure(&b.points);
        println!(
            "  {name} {s:?} -> {goal:?}: {:.2} m, narrowest {n0:.4} m, mean cost {m0:.3} | {:.2} m, narrowest {n1:.4} m, mean cost {m1:.3}",
            a.length, b.length
        );
        tally.pairs += 1;
        if n1 < n0 - 1e-3 {
            tally.narrower += 1;
            tally.worst = tally.worst.max(n0 - n1);
        }
        tally.costlier += usize::from(m1 > m0 + 1e-9);
        tally.cost[0] += m0;
        tally.cost[1] += m1;
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let dir = args
        .next()
        .expect("usage: cost_weight MAPS_DIR [--weight W] [--seeds N]");
    let (mut weight, mut seeds) = (1.0, 3u64);
    while let Some(a) = args.next() {
        let v = args.next().expect("a value");
        match a.as_str() {
            "--weight" => weight = v.parse().expect("--weight W"),
            "--seeds" => seeds = v.parse().expect("--seeds N"),
            other => panic!("unknown option {other}"),
        }
    }
    let names: Vec<&str> = {
        let mut n: Vec<&str> = NAVFN_REQUESTS.iter().map(|r| r.map).collect();
        n.dedup();
        n
    };
    let maps: Vec<Costmap> = names.iter().map(|n| Costmap::load(&dir, n)).collect();
    let mut fixed = Tally::default();
    for (name, cm) in names.iter().zip(&maps) {
        let requests: Vec<_> = NAVFN_REQUESTS.iter().filter(|r| r.map == *name).collect();
        let starts: Vec<[f64; 2]> = requests.iter().map(|r| r.start).collect();
        compare(cm, name, requests[0].goal, &starts, weight, &mut fixed);
    }
    let mut random = Tally::default();
    for seed in 1..=seeds {
        let mut rng = Rng(seed);
        for (name, cm) in names.iter().zip(&maps) {
            let clear: Vec<usize> = (0..cm.costs.len()).filter(|&i| cm.costs[i] < 253).collect();
            let (w, res, o) = (cm.map.width(), cm.map.resolution(), cm.map.origin());
            let mut draw = || {
                let i = clear[rng.below(clear.len())];
                [
                    o[0] + ((i % w) as f64 + 0.5) * res,
                    o[1] + ((i / w) as f64 + 0.5) * res,
                ]
            };
            for _ in 0..3 {
                let goal = draw();
                let starts: Vec<[f64; 2]> = (0..5).map(|_| draw()).collect();
                compare(cm, name, goal, &starts, weight, &mut random);
            }
        }
    }
    fixed.print("NavFn's 18 requests", weight);
    random.print(&format!("random pairs, seeds 1..={seeds}"), weight);
}
