//! The ME766 term paper: the blend k·φ_D + (1 − k)·φ_N swept over k on Garrido et al.'s
//! Figure 1 scene (their claim: k < 0.5 avoids the Dirichlet field's shallow gradients, and
//! paths graze obstacles as k → 0), and the parabolic relaxation's steps on 100 × 100
//! reconstructions of its workcells beside its iterations and beside Gauss–Seidel and SOR.
//!
//! ```text
//! cargo run --release -p harmonic-bench --example me766            # Markdown
//! cargo run --release -p harmonic-bench --example me766 -- --json  # {"blend": [...], "relaxation": [...]}
//! ```

use harmonic_bench::me766::{blend_sweep, me766_iterations};
use harmonic_planner::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let json = std::env::args().any(|a| a == "--json");
    let scene = Scene::from_file(harmonic_fixtures::mesh_file("garrido_fig1.json"))?;
    let starts = [[0.5, 0.8], [0.2, 0.8]];
    let ks = [0.0, 0.1, 0.25, 0.4, 0.5, 0.6, 0.75, 0.9, 1.0];
    let blend = blend_sweep(&scene, &starts, &ks)?;
    let relax = me766_iterations()?;
    if json {
        println!(
            "{}",
            serde_json::json!({ "blend": blend, "relaxation": relax })
        );
        return Ok(());
    }
    println!(
        "Blend k·φ_D + (1 − k)·φ_N on meshes/garrido_fig1.json, starts (0.5, 0.8) / (0.2, 0.8):\n"
    );
    println!("| k | length | min clearance | smallest abs grad phi | reached | interior minima |");
    println!("|---:|---|---|---|---|---:|");
    for r in &blend {
        println!(
            "| {} | {:.3} / {:.3} | {:.4} / {:.4} | {:.1e} / {:.1e} | {} / {} | {} |",
            r.k,
            r.length[0],
            r.length[1],
            r.clearance[0],
            r.clearance[1],
            r.min_gradient[0],
            r.min_gradient[1],
            r.reached[0],
            r.reached[1],
            r.interior_minima
        );
    }
    println!(
        "\nRelaxation to the paper's accuracies on the 100 × 100 reconstructions (steps = iterations):\n"
    );
    println!(
        "| problem | walls | sink | accuracy | paper iterations | parabolic r = 1/4 | parabolic r = 1/8 | Gauss–Seidel | SOR (optimal ω) |"
    );
    println!("|---:|---|---:|---:|---:|---:|---:|---:|---:|");
    let opt = |v: Option<usize>| v.map_or("—".to_string(), |v| v.to_string());
    for r in &relax {
        println!(
            "| {} | {} | {:e} | {:e} | {} | {} | {} | {} | {} |",
            r.problem,
            r.walls,
            r.sink,
            r.accuracy,
            r.paper_iterations,
            r.parabolic_steps,
            r.parabolic_steps_r_eighth,
            opt(r.gauss_seidel_sweeps),
            opt(r.sor_sweeps)
        );
    }
    Ok(())
}
