//! Reach rate of the configuration-space planner on seeded scenes nobody tuned: polygon robots
//! (bars and triangles) among 3–8 circles and boxes with pose tolerances of 0.05–0.2, arms of
//! two and three links among circles with joint tolerances of 0.05–0.2 or end-effector
//! tolerances of 0.1–0.2 (`harmonic_fixtures::ConfigCase`). A start counts when a
//! conservative flood fill over configurations (with the exact clearance of
//! `harmonic_cspace::check`) connects it to the goal; it is reached when the path's last
//! configuration is within the goal's tolerance and every motion is collision-free.
//!
//! Per case: the planner's build time (mesh and solve) and the whole plan (build, then every
//! start traced, in parallel); per family, medians and maxima.
//!
//! ```text
//! cargo run --release --example cspace_reach [-- CASES [FIRST_SEED]]
//! cargo run --release --example cspace_reach -- scene SEED     # that case's scene file
//! ```

use std::collections::BTreeMap;
use std::time::Instant;

use harmonic_cspace::check::{check_path, exact_clearance};
use harmonic_fixtures::{ConfigCase, ConfigKind};
use harmonic_planner::AnyScene;
use harmonic_planner::cspace::ConfigPlanner;

/// What one case gave.
struct Outcome {
    connected: usize,
    reached: usize,
    missed: Vec<String>,
    tets: usize,
    build_ms: f64,
    plan_ms: f64,
    goal: String,
}

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
    println!(
        "| seed | robot | goal | tetrahedra | build ms | plan ms | connected | reached | missed |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut families: BTreeMap<String, Vec<Outcome>> = BTreeMap::new();
    for seed in first..first + cases {
        let case = case_of(seed);
        let o = run(&case);
        let robot = match case.kind {
            ConfigKind::Polygon => "polygon".to_string(),
            ConfigKind::Arm(n) => format!("{n}-link arm"),
        };
        println!(
            "| {seed} | {robot} | {} | {} | {:.0} | {:.0} | {} | {} | {} |",
            o.goal,
            o.tets,
            o.build_ms,
            o.plan_ms,
            o.connected,
            o.reached,
            o.missed.join("; ")
        );
        families.entry(robot).or_default().push(o);
    }
    println!(
        "\n| robot | scenes | connected starts | reached | tetrahedra (median, max) | build (median, max) | whole plan (median, max) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (robot, outcomes) in &families {
        let planned: Vec<&Outcome> = outcomes.iter().filter(|o| o.tets > 0).collect();
        let stat = |f: &dyn Fn(&Outcome) -> f64| {
            let mut v: Vec<f64> = planned.iter().map(|o| f(o)).collect();
            v.sort_by(f64::total_cmp);
            (
                v.get(v.len() / 2).copied().unwrap_or(0.0),
                v.last().copied().unwrap_or(0.0),
            )
        };
        let tets = stat(&|o| o.tets as f64 / 1e3);
        let build = stat(&|o| o.build_ms / 1e3);
        let plan = stat(&|o| o.plan_ms / 1e3);
        println!(
            "| {robot} | {} | {} | {} | {:.0} k, {:.0} k | {:.2} s, {:.2} s | {:.2} s, {:.2} s |",
            outcomes.len(),
            outcomes.iter().map(|o| o.connected).sum::<usize>(),
            outcomes.iter().map(|o| o.reached).sum::<usize>(),
            tets.0,
            tets.1,
            build.0,
            build.1,
            plan.0,
            plan.1
        );
    }
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

/// Builds the planner of `case`, plans every start, and checks the connected ones.
fn run(case: &ConfigCase) -> Outcome {
    let scene = match AnyScene::from_json(&case.json) {
        Ok(AnyScene::Config(s)) => s,
        other => panic!("{:?}", other.err()),
    };
    let goal = serde_json::to_string(&scene.goal).unwrap_or_default();
    let t = Instant::now();
    let planner = match ConfigPlanner::new(&scene) {
        Ok(p) => p,
        Err(e) => {
            return Outcome {
                connected: 0,
                reached: 0,
                missed: vec![e.to_string()],
                tets: 0,
                build_ms: 0.0,
                plan_ms: 0.0,
                goal,
            };
        }
    };
    let build_ms = t.elapsed().as_secs_f64() * 1e3;
    let paths = planner.plan_many(&case.starts);
    let plan_ms = t.elapsed().as_secs_f64() * 1e3;
    let space = planner.space();
    let clearance = |q: &[f64]| exact_clearance(space.robot(), space.world(), q);
    let in_goal = |q: &[f64]| space.goal_value(q) <= 0.0;
    let cells = if case.range.len() == 2 { 96 } else { 40 };
    let connected = case.connected_starts(cells, &clearance, &in_goal);
    let (mut n, mut reached, mut missed) = (0, 0, Vec::new());
    for ((start, &conn), p) in case.starts.iter().zip(&connected).zip(&paths) {
        if !conn {
            continue;
        }
        n += 1;
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
    Outcome {
        connected: n,
        reached,
        missed,
        tets: planner.slab().tetrahedra().len(),
        build_ms,
        plan_ms,
        goal,
    }
}
