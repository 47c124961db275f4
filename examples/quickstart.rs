//! The library in a few lines: read a scene, build the planner once, plan from several starts.
//!
//! ```text
//! cargo run --release --example quickstart -- meshes/reference.json
//! ```

use harmonic_planner::{Planner, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let file = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "meshes/reference.json".into());
    let scene = Scene::from_file(&file)?;

    // Mesh, assemble and factor once...
    let planner = Planner::new(&scene)?;
    let mesh = planner.mesh();
    println!(
        "{file}: {} triangles, {} vertices",
        mesh.triangles().len(),
        mesh.vertices().len()
    );

    // ...then answer many queries from the same potential.
    let starts = [[1.0, 9.0], [1.0, 1.0], [9.0, 9.0], [4.0, 5.0]];
    for path in planner.plan_many(&starts) {
        println!(
            "from {:?}: {} after {:.2} m, {} points, closest approach to an obstacle {:.3} m",
            path.start,
            path.status,
            path.length,
            path.points.len(),
            path.min_clearance
        );
    }

    // The potential itself: φ at any point, exact to the float range near the walls through ψ.
    let phi = planner
        .potential()
        .phi_at(harmonic_planner::Point::new(8.0, 3.0), None)?;
    println!("φ(8, 3) = {phi:.9}");
    Ok(())
}
