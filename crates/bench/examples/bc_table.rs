//! Garrido et al. (2010), Table 1: the clearance of paths under Neumann, Robin and Dirichlet
//! conditions on walls and obstacles, relative to Dirichlet (d = d_i / d_D × 100 %).
//!
//! ```text
//! cargo run --release --example bc_table            # Markdown
//! cargo run --release --example bc_table -- --json  # {"rows": [...]}
//! cargo run --release --example bc_table -- --scene meshes/garrido_fig1.json --max-area 0.0001
//! ```

use harmonic_bench::tables::{PAPER_ROWS, bc_table};
use harmonic_planner::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let json = args.iter().any(|a| a == "--json");
    let value_of = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
    };
    let path = value_of("--scene").map_or("meshes/garrido_fig1.json", String::as_str);
    let mut scene = Scene::from_file(path)?;
    if let Some(a) = value_of("--max-area") {
        scene.mesh.max_area = Some(a.parse()?);
    }
    let starts = [[0.5, 0.8], [0.2, 0.8]];
    let rows = bc_table(&scene, &starts, &PAPER_ROWS)?;
    if json {
        let rows: Vec<_> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "type": r.row.kind, "a": r.row.a, "b": r.row.b, "k": r.row.k,
                    "d_05_08": r.d[0], "d_02_08": r.d[1],
                    "clearance_05_08": r.clearance[0], "clearance_02_08": r.clearance[1],
                    "reached_05_08": r.reached[0], "reached_02_08": r.reached[1],
                    "length_05_08": r.length[0], "length_02_08": r.length[1],
                    "min_gradient_05_08": r.min_gradient[0], "min_gradient_02_08": r.min_gradient[1],
                })
            })
            .collect();
        println!("{}", serde_json::json!({ "rows": rows }));
        return Ok(());
    }
    println!(
        "Scene {path}; starts (0.5, 0.8) and (0.2, 0.8); goal φ = 0; walls and obstacles as below.\n"
    );
    println!(
        "| condition | a | b | K | d (0.5, 0.8) % | d (0.2, 0.8) % | d_i (0.5, 0.8) | d_i (0.2, 0.8) | length | smallest abs grad phi | reached |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {} | {} | {} | {:.1} | {:.1} | {:.4} | {:.4} | {:.3} / {:.3} | {:.1e} / {:.1e} | {} / {} |",
            r.row.kind,
            r.row.a,
            r.row.b,
            r.row.k,
            r.d[0],
            r.d[1],
            r.clearance[0],
            r.clearance[1],
            r.length[0],
            r.length[1],
            r.min_gradient[0],
            r.min_gradient[1],
            yes(r.reached[0]),
            yes(r.reached[1])
        );
    }
    Ok(())
}

fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}
