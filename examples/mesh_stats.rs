//! Meshes a scene and prints one JSON line of mesh statistics: counts, angles, area, holes,
//! components, and the two conditions under which the P1 stiffness matrix is an M-matrix
//! (interior edges violating the Delaunay condition, boundary edges with an obtuse opposite
//! angle).
//!
//! ```text
//! cargo run --release --example mesh_stats -- meshes/reference.json [--max-area A] [--min-angle D]
//! ```

use std::time::Instant;

use harmonic_planner::Scene;
use harmonic_planner::mesh::Domain;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args
        .first()
        .filter(|a| !a.starts_with("--"))
        .ok_or("usage: mesh_stats SCENE.json [--max-area A] [--min-angle D]")?;
    let value_of = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
    };
    let mut scene = Scene::from_file(path)?;
    if let Some(a) = value_of("--max-area") {
        scene.mesh.max_area = Some(a.parse()?);
    }
    if let Some(d) = value_of("--min-angle") {
        scene.mesh.min_angle_deg = Some(d.parse()?);
    }
    let t = Instant::now();
    let opts = scene.mesh_options();
    let domain = Domain::new(&scene.domain_spec(), &opts)?;
    let (mesh, report) = domain.mesh(&opts)?;
    let millis = t.elapsed().as_secs_f64() * 1e3;
    let q = mesh.quality();
    println!(
        "{}",
        serde_json::json!({
            "vertices": q.vertices,
            "triangles": q.triangles,
            "min_angle_deg": q.min_angle_deg,
            "max_angle_deg": q.max_angle_deg,
            "area": q.area,
            "holes": q.holes,
            "components": q.components,
            "non_delaunay_edges": q.non_delaunay_edges,
            "obtuse_boundary_edges": q.obtuse_boundary_edges,
            "refinement_complete": report.refinement_complete,
            "millis": millis,
        })
    );
    Ok(())
}
