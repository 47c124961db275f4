//! Nav2's maps beside NavFn, request by request: the first plan from the loaded occupancy
//! grid (map → mesh → assemble → solve → trace, where "mesh" is everything before assembly:
//! the clear cells and the quadtree, or the polygons, their booleans and the refined
//! Delaunay mesh), by the default mesher (`auto`: traced where its margin changes nothing a
//! path needs, else the quadtree; `--traced` or `--quadtree` to force one), where its time
//! goes, and a later start on the same planner (a trace only). Times are medians of 5 in-process runs (`--runs N` for N; 25 matches the
//! NavFn timings' protocol when NavFn is run beside it).
//!
//! Which solve each map gets: the planner's `SolveMethod::Auto` takes the accurate LDLᵀ up to
//! `AUTO_ACCURATE_MAX_UNKNOWNS` unknowns and Cholesky above. Beside it the example times both
//! on the map's system (numeric factorisation + solve, the analysis done once, best of 5;
//! Cholesky with rayon's pool as the planner runs it).
//!
//! ```text
//! HARMONIC_NAV2_MAPS=DIR cargo run --release --example map_stages -- [--traced | --quadtree [--snap off|CELLS]] [--runs N] [--json]
//! ```

use std::time::Instant;

use std::sync::Arc;

use harmonic_fixtures::{NAVFN_REQUESTS, NAVFN_ROBOT_RADIUS, nav2_maps_dir};
use harmonic_planner::fem::BoundaryConditions;
use harmonic_planner::fem::{
    AUTO_ACCURATE_MAX_UNKNOWNS, Assembler, AssemblyOptions, SolveMethod, Solver,
};
use harmonic_planner::map::{MapMesher, MapOptions, OccupancyMap, Snap};
use harmonic_planner::{Planner, PlannerOptions};
use serde::Serialize;

#[derive(Serialize)]
struct Row {
    map: &'static str,
    start: [f64; 2],
    triangles: usize,
    mesh_ms: f64,
    assemble_ms: f64,
    solve_ms: f64,
    trace_ms: f64,
    first_plan_ms: f64,
    later_start_ms: f64,
    navfn_ms: f64,
    status: String,
    length: f64,
    navfn_length: f64,
    unknowns: usize,
    method: String,
    accurate_ms: f64,
    cholesky_ms: f64,
}

/// The system's unknowns, the solve `SolveMethod::Auto` picks (and why), and the best of 5
/// numeric factorisations + solves of the map's system (walls φ = 1, goal φ = 0) on
/// `planner`'s mesh by the accurate LDLᵀ (NaN when the system is not an M-matrix) and by
/// Cholesky (each solver built, i.e. analysed, once beforehand).
fn solve_times(
    planner: &Planner,
    mesher: MapMesher,
) -> Result<(usize, String, f64, f64), Box<dyn std::error::Error>> {
    let bcs = BoundaryConditions::default();
    let mesh = Arc::new(planner.mesh().clone());
    let assembler = Assembler::new(mesh, &bcs, AssemblyOptions::default())?;
    let system = assembler.assemble(&bcs)?;
    let n = system.matrix().n();
    let method = match system.not_m_matrix() {
        Some(reason) => format!("Cholesky (not an M-matrix: {reason})"),
        // The map planner asks the quadtree's M-matrix for the accurate solve at any size.
        // (`Auto` took the quadtree where every angle is 45° or 90°.)
        None if mesher == MapMesher::Quadtree
            || (mesher == MapMesher::Auto
                && (planner.mesh().quality().min_angle_deg - 45.0).abs() < 1e-9) =>
        {
            "accurate".to_string()
        }
        None if n <= AUTO_ACCURATE_MAX_UNKNOWNS => "accurate".to_string(),
        None => "Cholesky, redone accurately if ψ spans over 1e12".to_string(),
    };
    let mut best = Vec::new();
    for method in [SolveMethod::Accurate, SolveMethod::Cholesky] {
        if method == SolveMethod::Accurate && system.not_m_matrix().is_some() {
            best.push(f64::NAN);
            continue;
        }
        let solver = Solver::with_method(&system, assembler.nested_dissection(), method)?;
        let mut times = Vec::new();
        for _ in 0..5 {
            let t = Instant::now();
            std::hint::black_box(solver.solve(&system)?);
            times.push(ms(t));
        }
        best.push(times.into_iter().fold(f64::INFINITY, f64::min));
    }
    Ok((n, method, best[0], best[1]))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let json = std::env::args().any(|a| a == "--json");
    let runs: usize = match std::env::args().skip_while(|a| a != "--runs").nth(1) {
        None => 5,
        Some(v) => v
            .parse::<usize>()
            .ok()
            .filter(|&n| n > 0)
            .ok_or("--runs takes a count from 1")?,
    };
    let opts = MapOptions {
        mesher: if std::env::args().any(|a| a == "--quadtree") {
            MapMesher::Quadtree
        } else if std::env::args().any(|a| a == "--traced") {
            MapMesher::Traced
        } else {
            MapMesher::Auto
        },
        snap: match std::env::args().skip_while(|a| a != "--snap").nth(1) {
            None => Snap::OpenFloor,
            Some(v) if v == "off" => Snap::Off,
            Some(v) => Snap::Blocks(v.parse()?),
        },
        ..MapOptions::default()
    };
    let Some(dir) = nav2_maps_dir() else {
        eprintln!(
            "set HARMONIC_NAV2_MAPS to a folder of Nav2's maps (depot.yaml, warehouse.yaml, ...)"
        );
        return Ok(());
    };
    let mut rows = Vec::new();
    for r in NAVFN_REQUESTS {
        let map = OccupancyMap::load(dir.join(format!("{}.yaml", r.map)))?;
        // Every run builds the same planner: keep the times, and the last planner only.
        let mut timed = Vec::new();
        let mut last = None;
        for _ in 0..runs {
            let t = Instant::now();
            let planner = map.planner(
                r.goal,
                NAVFN_ROBOT_RADIUS,
                &opts,
                &PlannerOptions::default(),
            )?;
            let t2 = Instant::now();
            let path = planner.plan(r.start);
            let trace_ms = ms(t2);
            timed.push((ms(t), trace_ms));
            last = Some((planner, path));
        }
        timed.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (first_plan_ms, trace_ms) = timed[runs / 2];
        let (planner, path) = last.ok_or("no run")?;
        let later = median(
            (0..runs)
                .map(|_| {
                    let t = Instant::now();
                    std::hint::black_box(planner.plan(r.start));
                    ms(t)
                })
                .collect(),
        );
        let tm = planner.timings();
        let (unknowns, method, accurate_ms, cholesky_ms) = solve_times(&planner, opts.mesher)?;
        rows.push(Row {
            map: r.map,
            start: r.start,
            triangles: planner.mesh().triangles().len(),
            mesh_ms: first_plan_ms - tm.assemble - tm.solve - trace_ms,
            assemble_ms: tm.assemble,
            solve_ms: tm.solve,
            trace_ms,
            first_plan_ms,
            later_start_ms: later,
            navfn_ms: r.navfn_ms,
            status: path.status.as_str().to_string(),
            length: path.length,
            navfn_length: r.navfn_length,
            unknowns,
            method,
            accurate_ms,
            cholesky_ms,
        });
    }
    if json {
        println!("{}", serde_json::json!({ "rows": rows }));
        return Ok(());
    }
    println!(
        "| map | start | triangles | first plan ms (mesh + assemble + solve + trace) | NavFn ms | ratio | later start ms | NavFn / later | status | length m (NavFn) |"
    );
    println!("|---|---|---:|---|---:|---:|---:|---:|---|---|");
    let solve_rows: Vec<String> = rows
        .iter()
        .map(|r| {
            format!(
                "| {} | {} | {} | {:.2} | {:.2} |",
                r.map, r.unknowns, r.method, r.accurate_ms, r.cholesky_ms
            )
        })
        .collect();
    for r in &rows {
        println!(
            "| {} | {}, {} | {} | {:.1} ({:.1} + {:.1} + {:.1} + {:.1}) | {} | {:.1}× | {:.2} | {:.0}× | {} | {:.2} ({:.2}) |",
            r.map,
            r.start[0],
            r.start[1],
            r.triangles,
            r.first_plan_ms,
            r.mesh_ms,
            r.assemble_ms,
            r.solve_ms,
            r.trace_ms,
            r.navfn_ms,
            r.first_plan_ms / r.navfn_ms,
            r.later_start_ms,
            r.navfn_ms / r.later_start_ms,
            r.status,
            r.length,
            r.navfn_length
        );
    }
    println!();
    println!("| map | unknowns | planner's solve | accurate ms | Cholesky ms |");
    println!("|---|---:|---|---:|---:|");
    let mut seen = Vec::new();
    for (r, line) in rows.iter().zip(&solve_rows) {
        if !seen.contains(&r.map) {
            seen.push(r.map);
            println!("{line}");
        }
    }
    Ok(())
}
