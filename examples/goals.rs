//! Any goal in milliseconds: the reference scene's walls factored once ([`Workspace`]), then
//! 20 random goals each answered by a blocked solve, against what a new goal costs without
//! it (a new mesh and a new factorisation: [`Planner::new`]) and checked against a fresh
//! factorisation with the same goal vertices held.
//!
//! ```text
//! cargo run --release --example goals -- [--json] [--goals N] [--max-area A]...
//! cargo run --release --example goals -- --map MAP.yaml --robot-radius R --start X,Y... [--json]
//! ```
//!
//! With `--map`, the occupancy map is loaded and traced once (around the first start), its
//! workspace built, then `--goals N` random free points are each answered with a field and a
//! path from one of the starts (in turn): `{"map": {"triangles", "workspace_ms",
//! "goals", "goals_ms", "per_goal_ms", "paths_reached"}}`, the time from the loaded grid.
//!
//! Prints one row per mesh size (by default about 30 k and 300 k triangles):
//! `{"rows": [{"triangles", "rebuild_ms", "per_goal_ms", "per_goal_blocked_ms",
//! "max_relative_difference", "paths", "paths_reached", "status_differences",
//! "max_length_difference"}]}` — `per_goal_ms` one goal at a
//! time, `per_goal_blocked_ms` all goals in one call, both including the gradient recovery
//! a planner needs; `rebuild_ms` the mean of three full builds with the goal in the mesh;
//! `max_relative_difference` the largest entrywise difference of ψ from the fresh solve, and
//! the paths from four starts per goal compared with the fresh planner's (status, length).

use std::time::Instant;

use harmonic_fixtures::{Rng, max_relative_difference};
use harmonic_planner::scene::{Goals, Region};
use harmonic_planner::{Goal, Planner, Point, Scene, Workspace};
use serde::Serialize;

#[derive(Serialize)]
struct Row {
    max_area: f64,
    triangles: usize,
    factor_ms: f64,
    rebuild_ms: f64,
    per_goal_ms: f64,
    per_goal_blocked_ms: f64,
    max_relative_difference: f64,
    paths: usize,
    paths_reached: usize,
    /// Paths whose status differs from the fresh planner's.
    status_differences: usize,
    /// Largest relative difference of a path's length from the fresh planner's.
    max_length_difference: f64,
}

/// `n` random points of free space, 5 cm or more from every wall and obstacle.
fn random_free_points(ws: &Workspace, n: usize, rng: &mut Rng) -> Vec<Point> {
    let (lo, hi) = ws.domain().bounding_box();
    let domain = ws.domain();
    rng.points_in(n, [lo.x, lo.y], [hi.x, hi.y], |p| {
        let p = Point::new(p[0], p[1]);
        domain.contains_free(p) && domain.distance_to_obstacles(p) > 0.05
    })
    .into_iter()
    .map(|p| Point::new(p[0], p[1]))
    .collect()
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

fn row(base: &Scene, max_area: f64, n_goals: usize) -> Result<Row, Box<dyn std::error::Error>> {
    let mut scene = base.clone();
    scene.mesh.max_area = Some(max_area);
    let ws = Workspace::new(&scene)?;
    let mut rng = Rng(2026);
    let goals = random_free_points(&ws, n_goals, &mut rng);
    let starts = random_free_points(&ws, 4, &mut rng);

    // One goal at a time.
    let t = Instant::now();
    let planners = goals
        .iter()
        .map(|&g| ws.planner(&Goal::point(g)))
        .collect::<Result<Vec<_>, _>>()?;
    let per_goal_ms = ms(t) / n_goals as f64;
    // All goals in one call (their columns in shared blocks).
    let t = Instant::now();
    let blocked = ws.planners(&goals.iter().map(|&g| Goal::point(g)).collect::<Vec<_>>())?;
    let per_goal_blocked_ms = ms(t) / n_goals as f64;

    let mut worst: f64 = 0.0;
    let (mut paths, mut reached, mut status_differences) = (0, 0, 0);
    let mut length_difference: f64 = 0.0;
    for ((g, one), many) in goals.iter().zip(&planners).zip(&blocked) {
        let fresh = ws.fresh_planner(&Goal::point(*g))?;
        for p in [one, many] {
            worst = worst.max(max_relative_difference(
                p.potential().psi(),
                fresh.potential().psi(),
            ));
        }
        for &s in &starts {
            let (a, b) = (one.plan(s), fresh.plan(s));
            paths += 1;
            if a.status.reached_goal() {
                reached += 1;
            }
            if a.status != b.status {
                status_differences += 1;
            }
            length_difference = length_difference.max((a.length - b.length).abs() / b.length);
        }
    }

    // What a new goal costs without the workspace: a planner built with the goal in its mesh.
    let t = Instant::now();
    let rebuilds = 3.min(n_goals);
    for g in &goals[..rebuilds] {
        let mut with_goal = scene.clone();
        with_goal.goal = Goals(vec![Region {
            point: Some([g.x, g.y]),
            ..Region::default()
        }]);
        Planner::new(&with_goal)?;
    }
    let rebuild_ms = ms(t) / rebuilds as f64;

    Ok(Row {
        max_area,
        triangles: ws.mesh().triangles().len(),
        factor_ms: ws.timings().factor,
        rebuild_ms,
        per_goal_ms,
        per_goal_blocked_ms,
        max_relative_difference: worst,
        paths,
        paths_reached: reached,
        status_differences,
        max_length_difference: length_difference,
    })
}

#[derive(Serialize)]
struct MapRow {
    triangles: usize,
    /// Tracing the map, meshing, assembling and factoring (once).
    workspace_ms: f64,
    goals: usize,
    /// Every goal's field and one path each.
    goals_ms: f64,
    per_goal_ms: f64,
    paths_reached: usize,
}

fn map_row(
    map: &str,
    robot_radius: f64,
    starts: &[[f64; 2]],
    n_goals: usize,
) -> Result<MapRow, Box<dyn std::error::Error>> {
    use harmonic_planner::map::{MapOptions, OccupancyMap};
    let first = *starts
        .first()
        .ok_or("--map needs at least one --start X,Y")?;
    let grid = OccupancyMap::load(map)?;
    let t = Instant::now();
    let ws = grid.workspace(
        first,
        robot_radius,
        &MapOptions::default(),
        &harmonic_planner::PlannerOptions::default(),
    )?;
    let workspace_ms = ms(t);
    let goals = random_free_points(&ws, n_goals, &mut Rng(2026));
    let t = Instant::now();
    let mut reached = 0;
    for (k, g) in goals.iter().enumerate() {
        let planner = ws.planner(&Goal::point(*g))?;
        if planner.plan(starts[k % starts.len()]).status.reached_goal() {
            reached += 1;
        }
    }
    let goals_ms = ms(t);
    Ok(MapRow {
        triangles: ws.mesh().triangles().len(),
        workspace_ms,
        goals: n_goals,
        goals_ms,
        per_goal_ms: goals_ms / n_goals as f64,
        paths_reached: reached,
    })
}

fn parse_point(s: &str) -> Result<[f64; 2], Box<dyn std::error::Error>> {
    let v: Vec<f64> = s.split(',').map(str::parse).collect::<Result<_, _>>()?;
    match v.as_slice() {
        &[x, y] if x.is_finite() && y.is_finite() => Ok([x, y]),
        _ => Err(format!("expected X,Y, got `{s}`").into()),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let json = args.iter().any(|a| a == "--json");
    let mut n_goals = 20;
    let mut areas = Vec::new();
    let (mut map, mut robot_radius, mut starts) = (None, 0.0, Vec::new());
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--json" => {}
            "--goals" => n_goals = value()?.parse()?,
            "--max-area" => areas.push(value()?.parse::<f64>()?),
            "--map" => map = Some(value()?.clone()),
            "--robot-radius" => robot_radius = value()?.parse()?,
            "--start" => starts.push(parse_point(value()?)?),
            other => return Err(format!("unknown argument `{other}`").into()),
        }
    }
    if n_goals == 0 {
        return Err("--goals must be at least 1".into());
    }
    if let Some(map) = map {
        let row = map_row(&map, robot_radius, &starts, n_goals)?;
        if json {
            println!("{}", serde_json::json!({ "map": row }));
        } else {
            println!(
                "{map}: {} triangles; workspace {:.0} ms once; {} goals with a path each in {:.0} ms ({:.1} ms per goal, {}/{} reached)",
                row.triangles,
                row.workspace_ms,
                row.goals,
                row.goals_ms,
                row.per_goal_ms,
                row.paths_reached,
                row.goals
            );
        }
        return Ok(());
    }
    if areas.is_empty() {
        // About 30 k and 300 k triangles on the reference scene.
        areas = vec![0.0045, 0.00045];
    }
    let scene = Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/meshes/reference.json"
    ))?;
    let rows = areas
        .iter()
        .map(|&a| row(&scene, a, n_goals))
        .collect::<Result<Vec<_>, _>>()?;
    if json {
        println!("{}", serde_json::json!({ "rows": rows }));
    } else {
        println!(
            "| triangles | factor ms | rebuild ms | per goal ms | per goal, blocked ms | ψ vs fresh | paths reached | length vs fresh |"
        );
        println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
        for r in &rows {
            println!(
                "| {} | {:.0} | {:.0} | {:.1} | {:.1} | {:.1e} | {}/{} | {:.1e} |",
                r.triangles,
                r.factor_ms,
                r.rebuild_ms,
                r.per_goal_ms,
                r.per_goal_blocked_ms,
                r.max_relative_difference,
                r.paths_reached,
                r.paths,
                r.max_length_difference
            );
        }
    }
    Ok(())
}
