//! Garrido et al. (2010), Table 2: FEM against Connolly's grid planner solved by SOR.
//!
//! Same workspace (the unit square of `meshes/garrido_fig1.json`, its goal widened to a
//! 0.1 × 0.1 square so that even the 10 × 10 grid has a goal cell), same boundary values
//! (walls and obstacles φ = 1, goal φ = 0). For each N the grid is N × N (red-black SOR with
//! the optimal ω, stopped when the normalised residual is below 1e-13: at 1e-10 the far field
//! keeps cells without a lower neighbour and slightly negative ψ) and the FEM mesh has triangles of at most the grid cell's area
//! (max_area = 1/N²). Both are compared with a fine FEM reference (max_area 5e-7, about 2 M
//! triangles) by the largest error of φ at six sample points in free space.
//!
//! ```text
//! cargo run --release -p harmonic-bench --example fem_vs_sor             # Markdown
//! cargo run --release -p harmonic-bench --example fem_vs_sor -- --json   # {"rows": [...]}
//! cargo run --release -p harmonic-bench --example fem_vs_sor -- --max-n 200   # skip the largest grids
//! ```

use std::time::Instant;

use harmonic_baselines::{GridHarmonic, Raster, SorOptions};
use harmonic_bench::paper::{GARRIDO_TABLE2_MACHINE, garrido_table2};
use harmonic_planner::mesh::Domain;
use harmonic_planner::scene::Region;
use harmonic_planner::{Planner, Point, Scene};

const SAMPLES: [[f64; 2]; 6] = [
    [0.5, 0.8],
    [0.2, 0.8],
    [0.9, 0.9],
    [0.1, 0.45],
    [0.6, 0.3],
    [0.92, 0.2],
];
const REFERENCE_MAX_AREA: f64 = 5e-7;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let json = args.iter().any(|a| a == "--json");
    let max_n: usize = match args.iter().position(|a| a == "--max-n") {
        Some(i) => args.get(i + 1).ok_or("--max-n needs a number")?.parse()?,
        None => 1000,
    };
    let mut scene = Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../meshes/garrido_fig1.json"
    ))?;
    scene.goal.0 = vec![Region {
        polygon: Some(vec![[0.7, 0.1], [0.8, 0.1], [0.8, 0.2], [0.7, 0.2]]),
        ..Region::default()
    }];

    let reference = {
        let mut s = scene.clone();
        s.mesh.max_area = Some(REFERENCE_MAX_AREA);
        let planner = Planner::new(&s)?;
        SAMPLES
            .iter()
            .map(|&[x, y]| planner.potential().phi_at(Point::new(x, y), None))
            .collect::<Result<Vec<f64>, _>>()?
    };

    let domain = Domain::new(&scene.domain_spec(), &scene.mesh_options())?;
    let mut rows = Vec::new();
    for n in [10usize, 20, 50, 100, 200, 500, 1000]
        .into_iter()
        .filter(|&n| n <= max_n)
    {
        // SOR on the grid: rasterise + relax.
        let t = Instant::now();
        let raster = Raster::from_domain(&domain, n)?;
        let options = SorOptions::default();
        let grid = GridHarmonic::solve(raster, &options)?;
        let sor_seconds = t.elapsed().as_secs_f64();
        let sor_error = max_error(&reference, |p| {
            grid.value_and_gradient(p).map(|(v, _)| 1.0 + v)
        });

        // FEM of comparable resolution: mesh + assemble + solve.
        let mut s = scene.clone();
        s.mesh.max_area = Some(1.0 / (n * n) as f64);
        let t = Instant::now();
        let planner = Planner::new(&s)?;
        let fem_seconds = t.elapsed().as_secs_f64();
        let fem_error = max_error(&reference, |p| planner.potential().phi_at(p, None).ok());

        let paper = garrido_table2(n);
        rows.push(serde_json::json!({
            "n": n,
            "paper_sor_seconds": paper.map(|c| c.sor),
            "paper_fem_seconds": paper.map(|c| c.fem),
            "sor_iterations": grid.report().iterations,
            "sor_seconds": sor_seconds,
            "sor_error": sor_error,
            "sor_converged": grid.report().converged,
            "fem_triangles": planner.mesh().triangles().len(),
            "fem_seconds": fem_seconds,
            "fem_error": fem_error,
        }));
    }

    if json {
        println!(
            "{}",
            serde_json::json!({
                "rows": rows,
                "reference_max_area": REFERENCE_MAX_AREA,
                "samples": SAMPLES,
                "paper_machine": GARRIDO_TABLE2_MACHINE,
            })
        );
        return Ok(());
    }
    println!(
        "FEM vs SOR on the unit-square scene; error = max |φ − φ_ref| at {} sample points, reference FEM max_area {REFERENCE_MAX_AREA:e}.\n",
        SAMPLES.len()
    );
    println!(
        "| N | paper SOR s | paper FEM s | SOR sweeps | SOR s | SOR error | FEM triangles | FEM s | FEM error | FEM s ÷ SOR s |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in &rows {
        let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
        let paper = |k: &str| r[k].as_f64().map_or("—".to_string(), |s| format!("{s:.4}"));
        println!(
            "| {} | {} | {} | {} | {:.4} | {:.2e} | {} | {:.4} | {:.2e} | {:.3} |",
            r["n"],
            paper("paper_sor_seconds"),
            paper("paper_fem_seconds"),
            r["sor_iterations"],
            f("sor_seconds"),
            f("sor_error"),
            r["fem_triangles"],
            f("fem_seconds"),
            f("fem_error"),
            f("fem_seconds") / f("sor_seconds")
        );
    }
    println!(
        "\nThe paper's seconds are from {GARRIDO_TABLE2_MACHINE}, Garrido et al. (2010), Table 2."
    );
    println!("\nTime to reach an accuracy (the fastest row whose error is at most the target):\n");
    println!("| target error | SOR s (N) | FEM s (N) |");
    println!("|---:|---:|---:|");
    for target in [3e-2, 1e-2, 3e-3, 1e-3, 3e-4] {
        let best = |err: &str, secs: &str| {
            rows.iter()
                .filter(|r| r[err].as_f64().is_some_and(|e| e <= target))
                .map(|r| {
                    (
                        r[secs].as_f64().unwrap_or(f64::NAN),
                        r["n"].as_u64().unwrap_or(0),
                    )
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map_or("not reached".to_string(), |(s, n)| format!("{s:.4} ({n})"))
        };
        println!(
            "| {target:.0e} | {} | {} |",
            best("sor_error", "sor_seconds"),
            best("fem_error", "fem_seconds")
        );
    }
    Ok(())
}

/// Largest |φ(p) − φ_ref(p)| over the samples; infinity if the field is undefined at one.
fn max_error(reference: &[f64], phi: impl Fn(Point) -> Option<f64>) -> f64 {
    SAMPLES
        .iter()
        .zip(reference)
        .map(|(&[x, y], r)| phi(Point::new(x, y)).map_or(f64::INFINITY, |v| (v - r).abs()))
        .fold(0.0, f64::max)
}
