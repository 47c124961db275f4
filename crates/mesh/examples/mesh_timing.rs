//! Times `Domain::mesh` on the reference scene at a given maximum area and prints the
//! quality report: `cargo run -p harmonic-mesh --release --example mesh_timing -- 0.000132`.
//! Further arguments `prefill` (switch the lattice prefill on) and `no-bridges` (switch bridge
//! splitting off).

use harmonic_mesh::{Bridges, Domain, MeshOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let max_area: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(0.0044);
    let spec = harmonic_fixtures::reference_disc();
    let flags: Vec<String> = std::env::args().skip(2).collect();
    let opts = MeshOptions {
        max_area: Some(max_area),
        min_angle_deg: 30.0,
        prefill: flags.iter().any(|f| f == "prefill"),
        bridges: if flags.iter().any(|f| f == "no-bridges") {
            Bridges::Kept
        } else {
            Bridges::Refined
        },
        ..MeshOptions::default()
    };
    let t0 = std::time::Instant::now();
    let domain = Domain::new(&spec, &opts)?;
    let t1 = std::time::Instant::now();
    let (mesh, report) = domain.mesh(&opts)?;
    let t2 = std::time::Instant::now();
    let q = mesh.quality();
    println!(
        "max_area {max_area}: domain {:.4} s, mesh {:.4} s, {} triangles, {} vertices, min angle {:.3}, complete {}, non-Delaunay {}, obtuse boundary {}, bridges split {}",
        (t1 - t0).as_secs_f64(),
        (t2 - t1).as_secs_f64(),
        q.triangles,
        q.vertices,
        q.min_angle_deg,
        report.refinement_complete,
        q.non_delaunay_edges,
        q.obtuse_boundary_edges,
        report.bridges_split
    );
    Ok(())
}
