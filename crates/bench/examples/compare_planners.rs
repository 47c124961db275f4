//! Issue #9: every planner on every bundled scene, from a grid of starts plus the scene's own
//! starts — success rate, local-minimum traps, path length relative to the shortest
//! collision-free path (visibility graph + Dijkstra), smallest clearance, build and query time.
//!
//! ```text
//! cargo run --release --example compare_planners                  # Markdown table
//! cargo run --release --example compare_planners -- --json        # {"rows": [...]}
//! cargo run --release --example compare_planners -- --svg-dir out # one SVG per scene
//! ```

use std::path::PathBuf;

use clap::Parser;
use harmonic_bench::compare::{Arena, CompareOptions, Row, markdown_table};
use harmonic_planner::Scene;

/// Compare the FEM harmonic planner with the baselines on the bundled scenes.
#[derive(Parser)]
struct Args {
    /// Print `{"rows": [...]}` instead of the Markdown table.
    #[arg(long)]
    json: bool,
    /// Write `<scene>.svg` with every planner's paths into this directory.
    #[arg(long)]
    svg_dir: Option<PathBuf>,
    /// Cells per side of the grid planners' raster.
    #[arg(long, default_value_t = 256)]
    grid: usize,
    /// Starts per side of the grid of starts.
    #[arg(long, default_value_t = 5)]
    starts: usize,
    /// Scene files (default: the bundled scenes; reference_robin is left out, it is the
    /// reference scene with Robin walls, which the harness runs anyway).
    scenes: Vec<PathBuf>,
}

const BUNDLED: [&str; 6] = [
    "reference",
    "maze",
    "office",
    "concave_trap",
    "clutter",
    "garrido_fig1",
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let files: Vec<PathBuf> = if args.scenes.is_empty() {
        BUNDLED
            .iter()
            .map(|s| harmonic_fixtures::mesh_file(&format!("{s}.json")))
            .collect()
    } else {
        args.scenes.clone()
    };
    let options = CompareOptions {
        grid_n: args.grid,
        starts_per_side: args.starts,
        ..CompareOptions::default()
    };
    if let Some(dir) = &args.svg_dir {
        std::fs::create_dir_all(dir)?;
    }
    let mut rows: Vec<Row> = Vec::new();
    let mut notes = Vec::new();
    for file in &files {
        let mut scene = Scene::from_file(file)?;
        if scene.name.is_none() {
            scene.name = file.file_stem().map(|s| s.to_string_lossy().into_owned());
        }
        let arena = Arena::new(&scene, &options)?;
        let starts = arena.starts(options.starts_per_side);
        let comparison = arena.run(&starts);
        eprintln!(
            "{}: {} starts ({} without a path left out)",
            arena.name(),
            comparison.starts.len(),
            starts.len() - comparison.starts.len()
        );
        if let Some(dir) = &args.svg_dir {
            let out = dir.join(format!("{}.svg", arena.name()));
            std::fs::write(&out, comparison.svg(900.0))?;
            eprintln!("wrote {}", out.display());
        }
        rows.extend(comparison.rows());
        notes.extend(comparison.notes.iter().cloned());
    }
    if args.json {
        #[derive(serde::Serialize)]
        struct Output<'a> {
            rows: &'a [Row],
        }
        println!("{}", serde_json::to_string(&Output { rows: &rows })?);
    } else {
        print!("{}", markdown_table(&rows));
        if !notes.is_empty() {
            println!();
            for note in notes {
                println!("- {note}");
            }
        }
    }
    Ok(())
}
