//! Writes generated MovingAI benchmark files (a maze of one-cell corridors and rooms joined
//! by one-cell doors, with scenarios whose optimal lengths come from an 8-connected A*
//! without corner cutting) and times that A* on them, the reference beside `hplan bench`:
//!
//! ```text
//! cargo run --release --example grid_bench -- OUT_DIR
//! cargo run --release -- bench OUT_DIR/maze.map.scen
//! cargo run --release -- bench OUT_DIR/rooms.map.scen
//! ```

use std::time::Instant;

use harmonic_fixtures::occupancy::{self, OccGrid, astar8, clear_cells, random_pairs};

fn write(dir: &std::path::Path, name: &str, grid: &OccGrid, seed: u64, n: usize) {
    let (w, h) = (grid.width, grid.height);
    let clear = clear_cells(grid, 0.0);
    let pairs = random_pairs(seed, &clear, w, h, n, 8.0);
    let mut rows = Vec::new();
    let mut times = Vec::new();
    for &(s, g) in &pairs {
        let t = Instant::now();
        let optimal = astar8(&clear, w, h, s, g).expect("pairs are connected");
        times.push(t.elapsed().as_secs_f64() * 1e3);
        rows.push((s, g, optimal));
    }
    let map = dir.join(format!("{name}.map"));
    std::fs::write(&map, grid.to_movingai()).expect("write the map");
    std::fs::write(
        dir.join(format!("{name}.map.scen")),
        grid.to_scen(&format!("{name}.map"), &rows),
    )
    .expect("write the scenarios");
    times.sort_by(f64::total_cmp);
    let total: f64 = times.iter().sum();
    println!(
        "{name}: {w} × {h}, {} scenarios; grid A* (8-connected, no corner cutting): median {:.3} ms, worst {:.3} ms, whole {:.3} s",
        rows.len(),
        times[times.len() / 2],
        times[times.len() - 1],
        total / 1e3
    );
}

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "grid_bench".into());
    let dir = std::path::PathBuf::from(dir);
    std::fs::create_dir_all(&dir).expect("create the output folder");
    write(&dir, "maze", &occupancy::maze(7, 255, 255, 1), 1, 40);
    write(&dir, "rooms", &occupancy::rooms(8, 256, 256, 1), 2, 40);
}
