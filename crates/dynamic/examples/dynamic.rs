//! Dynamic replanning on the reference scene (Garrido et al. 2010, §6, Figure 10): a robot
//! goes from (1, 9) to the goal while one obstacle crosses its path back and forth and
//! another, not on the map, stands in the way; the laser sees them only within its range.
//! Every step the robot scans, turns the scan into obstacles, meshes and solves a 4 m × 4 m
//! window around itself and moves a step sized by the distance to the nearest sensed obstacle.
//!
//! ```text
//! cargo run --release --example dynamic -- [--scene meshes/reference.json] [--svg OUT.svg] [--json]
//! ```

use std::fmt::Write as _;
use std::process::ExitCode;

use clap::Parser;
use harmonic_dynamic::{
    DynamicPlanner, LocalMapMode, LocalMapOptions, Run, RunOptions, World, WorldObstacle,
};
use harmonic_planner::Scene;

#[derive(Parser)]
#[command(about = "A robot crossing the reference scene among moving and unmapped obstacles")]
struct Args {
    /// The known map.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/reference.json"))]
    scene: String,
    /// Write an SVG of the run.
    #[arg(long)]
    svg: Option<String>,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
    /// Side of the local window, m.
    #[arg(long, default_value_t = 4.0)]
    window: f64,
    /// Largest triangle area of the local mesh.
    #[arg(long, default_value_t = 0.005)]
    max_area: f64,
    /// Remesh the window at every replan instead of cutting the obstacles into the fixed
    /// lattice.
    #[arg(long)]
    remesh: bool,
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<[f64; 2]> {
    vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(ok) => ok,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let scene = Scene::from_file(&args.scene)?;
    let start = scene.starts.first().copied().unwrap_or([1.0, 9.0]);
    let opts = LocalMapOptions {
        size: args.window,
        max_area: args.max_area,
        mode: if args.remesh {
            LocalMapMode::Remesh
        } else {
            LocalMapMode::Lattice
        },
        ..LocalMapOptions::default()
    };
    let mut planner = DynamicPlanner::new(&scene, opts)?;
    let world = World::new(
        &scene,
        vec![
            // Crosses the corridor between the tall rectangle and the triangle, back and forth.
            WorldObstacle {
                polygon: rect(3.1, 6.15, 3.4, 6.45),
                velocity: [0.4, 0.0],
                period: 7.5,
            },
            // Not on the map: stands on the global path below the corridor.
            WorldObstacle {
                polygon: rect(4.0, 4.6, 4.5, 5.1),
                velocity: [0.0, 0.0],
                period: 0.0,
            },
        ],
    );
    let run_opts = RunOptions::default();
    let result = harmonic_dynamic::run(&mut planner, &world, start, &run_opts);
    let (median, p99) = result.replan_percentiles();
    if let Some(path) = &args.svg {
        std::fs::write(path, svg(&scene, &world, &result))?;
    }
    if args.json {
        let summary = serde_json::json!({
            "replans": result.replans,
            "remeshed": result.remeshed,
            "reached": result.reached,
            "min_distance_to_obstacles": result.min_distance_to_obstacles,
            "replan_ms_median": median,
            "replan_ms_p99": p99,
            "failed_replans": result.failed_replans,
            "steps": result.trail.len() - 1,
            "time_s": result.times.last().copied().unwrap_or(0.0),
            "triangles": [result.triangles.0, result.triangles.1],
            "stage_ms_mean": {
                "prepare": result.stage_ms.prepare / result.replans.max(1) as f64,
                "mesh": result.stage_ms.mesh / result.replans.max(1) as f64,
                "assemble": result.stage_ms.assemble / result.replans.max(1) as f64,
                "solve": result.stage_ms.solve / result.replans.max(1) as f64,
                "trace": result.stage_ms.trace / result.replans.max(1) as f64,
            },
        });
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!(
            "{}: {} replans ({} remeshed, {} failed), {} steps, {:.1} s simulated, local meshes of {}..{} triangles",
            if result.reached {
                "reached the goal"
            } else {
                "did NOT reach the goal"
            },
            result.replans,
            result.remeshed,
            result.failed_replans,
            result.trail.len() - 1,
            result.times.last().copied().unwrap_or(0.0),
            result.triangles.0,
            result.triangles.1,
        );
        println!(
            "smallest distance to the true obstacles: {:.4} m; replan median {median:.2} ms, p99 {p99:.2} ms",
            result.min_distance_to_obstacles
        );
        if let Some(e) = &result.last_error {
            println!("last failed replan: {e}");
        }
    }
    Ok(
        if result.reached && result.min_distance_to_obstacles > 0.0 {
            ExitCode::SUCCESS
        } else {
            ExitCode::FAILURE
        },
    )
}

/// The run as an SVG: the known map, the unknown obstacles over time (lighter when earlier),
/// and the robot's trail.
fn svg(scene: &Scene, world: &World, run: &Run) -> String {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &scene.workspace {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let width = 800.0;
    let scale = width / (hi[0] - lo[0]).max(1e-12);
    let height = (hi[1] - lo[1]) * scale;
    let xy = |p: [f64; 2]| ((p[0] - lo[0]) * scale, (hi[1] - p[1]) * scale);
    let ring = |pts: &[[f64; 2]]| {
        let mut d = String::new();
        for (i, &p) in pts.iter().enumerate() {
            let (x, y) = xy(p);
            let _ = write!(d, "{}{x:.2},{y:.2} ", if i == 0 { "M" } else { "L" });
        }
        d.push('Z');
        d
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.2} {height:.2}">"#
    );
    let _ = writeln!(
        s,
        r##"<path d="{}" fill="#fff" stroke="#222" stroke-width="2"/>"##,
        ring(&scene.workspace)
    );
    for o in &scene.obstacles {
        let pts = match (&o.polygon, &o.circle) {
            (Some(p), _) => p.clone(),
            (None, Some(c)) => (0..48)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / 48.0;
                    [
                        c.center[0] + c.radius * a.cos(),
                        c.center[1] + c.radius * a.sin(),
                    ]
                })
                .collect(),
            _ => continue,
        };
        let _ = writeln!(s, r##"<path d="{}" fill="#555"/>"##, ring(&pts));
    }
    for g in scene.goals() {
        if let Some(c) = g.circle {
            let (x, y) = xy(c.center);
            let _ = writeln!(
                s,
                r##"<circle cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="#2ca02c"/>"##,
                c.radius * scale
            );
        } else if let Some(p) = &g.polygon {
            let _ = writeln!(s, r##"<path d="{}" fill="#2ca02c"/>"##, ring(p));
        }
    }
    let t_end = run.times.last().copied().unwrap_or(0.0).max(1e-9);
    for (t, polys) in &run.snapshots {
        let opacity = 0.08 + 0.3 * (t / t_end);
        for (p, o) in polys.iter().zip(&world.obstacles) {
            let colour = if o.moves() { "#1f77b4" } else { "#ff7f0e" };
            let _ = writeln!(
                s,
                r##"<path d="{}" fill="{colour}" fill-opacity="{opacity:.3}" stroke="none"/>"##,
                ring(p)
            );
        }
    }
    for o in &world.obstacles {
        let colour = if o.moves() { "#1f77b4" } else { "#ff7f0e" };
        let _ = writeln!(
            s,
            r##"<path d="{}" fill="{colour}" stroke="#000" stroke-width="0.5"/>"##,
            ring(&o.at(t_end))
        );
    }
    let mut d = String::new();
    for (i, &p) in run.trail.iter().enumerate() {
        let (x, y) = xy(p);
        let _ = write!(d, "{}{x:.2},{y:.2} ", if i == 0 { "M" } else { "L" });
    }
    let _ = writeln!(
        s,
        r##"<path d="{d}" fill="none" stroke="#d62728" stroke-width="2"/>"##
    );
    let _ = writeln!(
        s,
        r##"<text x="8" y="18" font-family="sans-serif" font-size="14">{} replans, reached: {}, closest approach {:.3} m</text>"##,
        run.replans, run.reached, run.min_distance_to_obstacles
    );
    s.push_str("</svg>\n");
    s
}
