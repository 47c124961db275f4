//! Reach rate of the volume planner on seeded cluttered volumes that nobody tuned: a 10 m box
//! with 5–40 balls and boxes, one or two goal balls of radius 0.1–0.5 m, the default
//! `max_volume`, a point robot and a ball of radius 0.3. A start counts when a conservative
//! voxel flood fill (0.1 m voxels, `harmonic_fixtures::Clutter3d`) connects it to a goal; it
//! is reached when the planner's path ends in a goal ball.
//!
//! ```text
//! cargo run --release --example volume_reach [-- CASES [FIRST_SEED]]
//! ```

use std::time::Instant;

use harmonic_fixtures::Clutter3d;
use harmonic_planner::AnyScene;
use harmonic_planner::volume::VolumePlanner;

fn main() {
    let arg = |i: usize, default: u64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(default)
    };
    let cases = arg(1, 24);
    let first = arg(2, 1);
    println!(
        "| seed | obstacles | goals | robot | tetrahedra | build ms | connected | reached | missed |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let (mut connected_all, mut reached_all) = (0, 0);
    for seed in first..first + cases {
        let obstacles = 5 + (seed as usize * 7) % 36;
        let goals = 1 + seed.is_multiple_of(3) as usize;
        let robot = if seed.is_multiple_of(2) { 0.3 } else { 0.0 };
        let c = Clutter3d::random(seed, obstacles, goals, 12, robot);
        let connected = c.connected_starts(0.1);
        let scene = match AnyScene::from_json(&c.scene_json()) {
            Ok(AnyScene::Volume(s)) => s,
            other => panic!("seed {seed}: {:?}", other.err()),
        };
        let t = Instant::now();
        let planner = match VolumePlanner::new(&scene) {
            Ok(p) => p,
            Err(e) => {
                println!(
                    "| {seed} | {obstacles} | {goals} | {robot} | – | – | {} | 0 | {e} |",
                    connected.iter().filter(|&&b| b).count()
                );
                continue;
            }
        };
        let build = t.elapsed().as_secs_f64() * 1e3;
        let mut n_conn = 0;
        let mut n_reached = 0;
        let mut misses = Vec::new();
        for (start, &conn) in c.starts.iter().zip(&connected) {
            if !conn {
                continue;
            }
            n_conn += 1;
            let p = planner.plan(*start);
            let end = p.points.last().copied().unwrap_or(*start);
            let in_goal = c.goals.iter().any(|&(g, r)| {
                ((end[0] - g[0]).powi(2) + (end[1] - g[1]).powi(2) + (end[2] - g[2]).powi(2)).sqrt()
                    <= r + 1e-9
            });
            if p.status.reached_goal() && in_goal {
                n_reached += 1;
            } else {
                misses.push(format!("{start:.2?}: {}", p.status.as_str()));
            }
        }
        connected_all += n_conn;
        reached_all += n_reached;
        println!(
            "| {seed} | {obstacles} | {goals} | {robot} | {} | {build:.0} | {n_conn} | {n_reached} | {} |",
            planner.mesh().tetrahedra().len(),
            misses.join("; ")
        );
    }
    println!("\nreached {reached_all} of {connected_all} connected starts");
}
