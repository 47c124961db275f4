//! Garrido et al. (2010), Table 1: the clearance of paths under Neumann, Robin and Dirichlet
//! conditions on walls and obstacles, relative to Dirichlet (d = d_i / d_D × 100 %).
//!
//! ```text
//! cargo run --release -p harmonic-bench --example bc_table            # Markdown
//! cargo run --release -p harmonic-bench --example bc_table -- --json  # {"rows": [...]}
//! cargo run --release -p harmonic-bench --example bc_table -- --scene meshes/garrido_fig1.json --max-area 0.0001
//! ```

use harmonic_bench::paper::GARRIDO_TABLE1_D;
use harmonic_bench::tables::{BcKind, PAPER_ROWS, bc_table, bc_table_literal};
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
    let reference = rows
        .iter()
        .find(|r| r.row.kind == BcKind::Dirichlet)
        .map(|r| r.clearance.clone())
        .ok_or("the table has a Dirichlet row")?;
    let literal = bc_table_literal(&scene, &starts, &PAPER_ROWS, &reference);
    if json {
        let rows: Vec<_> = rows
            .iter()
            .zip(&literal)
            .zip(GARRIDO_TABLE1_D)
            .map(|((r, l), paper)| {
                serde_json::json!({
                    "type": r.row.kind, "a": r.row.a, "b": r.row.b, "k": r.row.k,
                    "paper_d_05_08": paper[0], "paper_d_02_08": paper[1],
                    "literal_d_05_08": l.d[0], "literal_d_02_08": l.d[1],
                    "literal_no_path": l.no_path,
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
        "| condition | a | b | K | paper d (0.5, 0.8) % | ours | literal | paper d (0.2, 0.8) % | ours | literal | d_i (0.5, 0.8) | d_i (0.2, 0.8) | length | smallest abs grad phi | reached |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|");
    let lit = |d: Option<f64>| d.map_or("no path".to_string(), |d| format!("{d:.1}"));
    for ((r, l), paper) in rows.iter().zip(&literal).zip(GARRIDO_TABLE1_D) {
        println!(
            "| {} | {} | {} | {} | {} | {:.1} | {} | {} | {:.1} | {} | {:.4} | {:.4} | {:.3} / {:.3} | {:.1e} / {:.1e} | {} / {} |",
            r.row.kind,
            r.row.a,
            r.row.b,
            r.row.k,
            paper[0],
            r.d[0],
            lit(l.d[0]),
            paper[1],
            r.d[1],
            lit(l.d[1]),
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
