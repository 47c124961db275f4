//! Reach rate of the configuration-space planner on seeded scenes nobody tuned: polygon robots
//! (bars and triangles) among 3–8 circles and boxes with pose tolerances of 0.05–0.2, arms of
//! two and three links among circles with joint tolerances of 0.05–0.2 or end-effector
//! tolerances of 0.1–0.2 (`harmonic_fixtures::ConfigCase`). A start counts when a
//! conservative flood fill over configurations (with the exact clearance of
//! `harmonic_cspace::check`) connects it to the goal; it is reached when the path's last
//! configuration is within the goal's tolerance and every motion is collision-free.
//!
//! ```text
//! cargo run --release --example cspace_reach [-- CASES [FIRST_SEED]]
//! cargo run --release --example cspace_reach -- scene SEED     # that case's scene file
//! ```

use std::time::Instant;

use harmonic_cspace::check::{check_path, exact_clearance};
use harmonic_fixtures::{ConfigCase, ConfigKind};
use harmonic_planner::AnyScene;
use harmonic_planner::cspace::ConfigPlanner;

fn main() {
    // `-- scene SEED` prints that case's scene file instead.
    if std::env::args().nth(1).as_deref() == Some("scene") {
        let seed = std::env::args()
            .nth(2)
            .and_then(|a| a.parse().ok())
            .unwrap_or(1);
        println!("{}", case_of(seed).json);
        return;
    }
    let arg = |i: usize, default: u64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(default)
    };
    let cases = arg(1, 12);
    let first = arg(2, 1);
    println!("| seed | robot | goal | tetrahedra | build ms | connected | reached | missed |");
    println!("|---|---|---|---|---|---|---|---|");
    let (mut all_connected, mut all_reached) = (0, 0);
    for seed in first..first + cases {
        let case = case_of(seed);
        let (connected, reached, missed, tets, build, goal) = run(&case);
        all_connected += connected;
        all_reached += reached;
        let robot = match case.kind {
            ConfigKind::Polygon => "polygon".to_string(),
            ConfigKind::Arm(n) => format!("{n}-link arm"),
        };
        println!(
            "| {seed} | {robot} | {goal} | {tets} | {build:.0} | {connected} | {reached} | {} |",
            missed.join("; ")
        );
    }
    println!("\nreached {all_reached} of {all_connected} connected starts");
}

/// The case of a seed: polygon, 2-link joints, 3-link joints, 3-link tip in turn.
fn case_of(seed: u64) -> ConfigCase {
    match seed % 4 {
        0 => ConfigCase::polygon(seed, 8),
        1 => ConfigCase::arm(seed, 2, false, 8),
        2 => ConfigCase::arm(seed, 3, false, 8),
        _ => ConfigCase::arm(seed, 3, true, 8),
    }
}

/// Plans every start of `case`: (connected, reached, misses, tetrahedra, build ms, goal).
fn run(case: &ConfigCase) -> (usize, usize, Vec<String>, usize, f64, String) {
    let scene = match AnyScene::from_json(&case.json) {
        Ok(AnyScene::Config(s)) => s,
        other => panic!("{:?}", other.err()),
    };
    let goal_text = serde_json::to_string(&scene.goal).unwrap_or_default();
    let t = Instant::now();
    let planner = match ConfigPlanner::new(&scene) {
        Ok(p) => p,
        Err(e) => return (0, 0, vec![e.to_string()], 0, 0.0, goal_text),
    };
    let build = t.elapsed().as_secs_f64() * 1e3;
    let space = planner.space();
    let clearance = |q: &[f64]| exact_clearance(space.robot(), space.world(), q);
    let in_goal = |q: &[f64]| space.goal_value(q) <= 0.0;
    let cells = if case.range.len() == 2 { 96 } else { 40 };
    let connected = case.connected_starts(cells, &clearance, &in_goal);
    let (mut n, mut reached, mut missed) = (0, 0, Vec::new());
    for (start, &conn) in case.starts.iter().zip(&connected) {
        if !conn {
            continue;
        }
        n += 1;
        let p = planner.plan(start);
        let configs = p.configurations();
        let met = configs.last().is_some_and(|q| case.goal_met(q));
        let motion = check_path(space.robot(), space.world(), &configs, 1e-3);
        if p.status.reached_goal() && met && motion.min_clearance > 0.0 {
            reached += 1;
        } else {
            missed.push(format!(
                "{start:.2?}: {}, goal met {met}, motion clearance {:.2e}",
                p.status.as_str(),
                motion.min_clearance
            ));
        }
    }
    (
        n,
        reached,
        missed,
        planner.slab().tetrahedra().len(),
        build,
        goal_text,
    )
}
