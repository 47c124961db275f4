//! Times `Domain::new` and `Domain::mesh` on the large inputs of issue #25 and prints the
//! figures: a circle of radius 1 sampled at N vertices in a 10 × 10 room (`detailed N`), or a
//! forest of N circles in 100 × 100 m (`forest N`).
//!
//! ```sh
//! cargo run --release -p harmonic-mesh --example large_inputs -- detailed 50000
//! cargo run --release -p harmonic-mesh --example large_inputs -- forest 3000 --poly /tmp/forest.poly
//! ```
//!
//! Options: `--max-area A` (default: the mesher's, free area / 20000), `--radius R` (of the
//! detailed circle, default 1), `--one-piece` (no halves), `--poly FILE` (write free space's
//! boundary as a Triangle `.poly`, to time `triangle -pq30a<A>` on the same boundary: the
//! area bound used is printed). The last line is preparation and meshing together, the
//! figure to set beside Triangle's.

use std::time::Instant;

use harmonic_mesh::{Domain, MeshOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let kind = args.first().map(String::as_str).unwrap_or("forest");
    let n: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(3000);
    let radius: f64 = value("--radius")
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(1.0);
    let spec = match kind {
        "detailed" => harmonic_fixtures::detailed_room(n, radius),
        "forest" => harmonic_fixtures::forest(n),
        other => return Err(format!("unknown input {other:?} (detailed or forest)").into()),
    };
    let opts = MeshOptions {
        max_area: value("--max-area").map(|s| s.parse()).transpose()?,
        halves_from: if args.iter().any(|a| a == "--one-piece") {
            usize::MAX
        } else {
            MeshOptions::default().halves_from
        },
        ..MeshOptions::default()
    };
    let t0 = Instant::now();
    let domain = Domain::new(&spec, &opts)?;
    let t1 = Instant::now();
    println!(
        "{kind} {n}: domain {:.3} s, {} ring vertices",
        (t1 - t0).as_secs_f64(),
        domain
            .free_rings()
            .iter()
            .map(|r| r.points.len())
            .sum::<usize>()
    );
    if let Some(path) = value("--poly") {
        std::fs::write(&path, harmonic_fixtures::free_space_poly(&domain))?;
        println!("boundary written to {path}");
    }
    let prepared = (t1 - t0).as_secs_f64();
    let t1 = Instant::now();
    match domain.mesh(&opts) {
        Ok((mesh, report)) => {
            let t2 = Instant::now();
            let q = mesh.quality();
            println!(
                "mesh {:.3} s: {} triangles (estimated {}), {} vertices, max_area {:.6}, min angle {:.2}, complete {}, seam {:?} (refined again: {} local, {} full)",
                (t2 - t1).as_secs_f64(),
                q.triangles,
                report.estimated_triangles,
                q.vertices,
                report.max_area,
                q.min_angle_deg,
                report.refinement_complete,
                report.seam,
                report.seam_refinements.local,
                report.seam_refinements.full
            );
            println!(
                "total (domain + mesh) {:.3} s",
                prepared + (t2 - t1).as_secs_f64()
            );
        }
        Err(e) => println!("refused after {:.3} s: {e}", t1.elapsed().as_secs_f64()),
    }
    Ok(())
}
