//! Runs every polygon-scene baseline on the reference scene from the peers' start and sample
//! points and prints one Markdown row per planner and start: status, path length, time.
//!
//! `cargo run --release -p harmonic-baselines --example compare [-- N]` (grid size, default 256)

use std::time::Instant;

use harmonic_baselines::{
    Connectivity, GridHarmonic, PanelOptions, PanelPlanner, PlanResult, PotentialField,
    PotentialFieldOptions, Raster, SorOptions, Wavefront,
};
use harmonic_fixtures::{REFERENCE_GOAL_CENTER, ScenePolygons, reference_polygons};
use harmonic_mesh::Point;
use harmonic_trajectory::{SmoothOptions, trace_smooth};

fn row(planner: &str, start: Point, plan: &PlanResult, setup_ms: f64) {
    println!(
        "| {planner} | ({}, {}) | {} | {:.3} | {:.2} | {:.2} |",
        start.x,
        start.y,
        plan.status,
        plan.length,
        setup_ms,
        plan.compute_time.as_secs_f64() * 1e3
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = match std::env::args().nth(1) {
        Some(a) => a.parse()?,
        None => 256,
    };
    let ScenePolygons {
        workspace: ws,
        obstacles,
        goals,
    } = reference_polygons();
    let goal = Point::from(REFERENCE_GOAL_CENTER);
    let starts = [
        Point::new(1.0, 9.0),
        Point::new(1.0, 1.0),
        Point::new(4.0, 5.0),
        Point::new(9.0, 9.0),
        Point::new(8.0, 3.0),
        Point::new(3.5, 1.0),
    ];
    println!("| planner | start | status | length | setup ms | query ms |");
    println!("|---|---|---|---|---|---|");

    let clock = Instant::now();
    let raster = Raster::from_polygons(&ws, &obstacles, &goals, n)?;
    let raster_ms = clock.elapsed().as_secs_f64() * 1e3;

    let field = GridHarmonic::solve(raster.clone(), &SorOptions::default())?;
    let sor_ms = raster_ms + field.report().time.as_secs_f64() * 1e3;
    let wave = Wavefront::new(raster, Connectivity::Eight);
    let wave_ms = raster_ms + wave.build_time().as_secs_f64() * 1e3;
    let pf = PotentialField::new(&ws, &obstacles, goal, PotentialFieldOptions::default())?;
    let panel = PanelPlanner::new(&ws, &obstacles, goal, PanelOptions::default())?;
    for start in starts {
        let clock = Instant::now();
        let path = trace_smooth(&field, start, &SmoothOptions::for_scale(10.0))?;
        row(
            &format!("grid harmonic SOR n={n}"),
            start,
            &PlanResult::from_path(path, clock.elapsed()),
            sor_ms,
        );
        row(
            &format!("wavefront 8 n={n}"),
            start,
            &wave.plan(start),
            wave_ms,
        );
        row("attractive/repulsive", start, &pf.plan(start), 0.0);
        row("panel method", start, &panel.plan(start)?, 0.0);
    }
    Ok(())
}
