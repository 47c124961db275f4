//! How small can the safety margin ε be? For each bundled polygon or arm scene, plan with
//! decreasing ε and check every motion between consecutive path entries against the exact
//! polygons (samples no robot point moves more than 1e-3 × the scene size between); print
//! the smallest clearance met, and per scene the smallest ε whose motions all stay clear.
//! Also the mesh size and the time per stage at the scene's own ε.
//!
//! ```text
//! cargo run --release --example cspace_margin
//! ```

use harmonic_planner::AnyScene;
use harmonic_planner::cspace::{ConfigPlanner, ConfigScene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    println!(
        "{:<16} {:>7} {:>8} {:>9} {:>8} {:>9} {:>9} {:>9} {:>8}",
        "scene", "ε", "reached", "clearance", "tets", "unknowns", "mesh ms", "solve ms", "trace ms"
    );
    for path in files {
        let Ok(AnyScene::Config(scene)) = AnyScene::from_file(&path) else {
            continue;
        };
        let scene: ConfigScene = *scene;
        let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("?");
        let own = scene.mesh.margin.unwrap_or(0.0);
        let mut margins = vec![own, 0.02, 0.01, 0.005, 0.002, 0.001, 0.0];
        margins.retain(|&m| m <= own);
        margins.dedup();
        let mut smallest = None;
        for m in margins {
            let mut s = scene.clone();
            s.mesh.margin = Some(m);
            let planner = match ConfigPlanner::new(&s) {
                Ok(p) => p,
                Err(e) => {
                    println!("{name:<16} {m:>7} error: {e}");
                    continue;
                }
            };
            let report = planner.plan_report(&s.starts);
            let reached = report.paths.iter().all(|p| p.status.reached_goal());
            let clearance = report
                .paths
                .iter()
                .map(|p| planner.check(p))
                .fold(f64::INFINITY, f64::min);
            let t = report.timings_ms;
            println!(
                "{name:<16} {m:>7} {:>8} {clearance:>9.5} {:>8} {:>9} {:>9.0} {:>9.0} {:>8.0}",
                reached, report.mesh.tetrahedra, report.mesh.unknowns, t.mesh, t.solve, t.trace
            );
            if reached && clearance > 0.0 {
                smallest = Some(m);
            }
        }
        println!("{name:<16} smallest ε with every motion clear: {smallest:?}");
    }
    Ok(())
}
