//! Times `Domain::mesh` on the reference scene at a given maximum area and prints the
//! quality report: `cargo run -p harmonic-mesh --release --example mesh_timing -- 0.000132`.
//! Further arguments `prefill` (switch the lattice prefill on) and `no-bridges` (switch bridge
//! splitting off).

use harmonic_mesh::{Domain, DomainSpec, GoalShape, MeshOptions, Point, Shape};

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
    vec![p(x0, y0), p(x1, y0), p(x1, y1), p(x0, y1)]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let max_area: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(0.0044);
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 10.0, 10.0),
        obstacles: vec![
            Shape::Polygon(rect(2.0, 2.0, 3.0, 8.0)),
            Shape::Polygon(rect(5.0, 4.0, 9.0, 5.0)),
            Shape::Polygon(vec![p(4.0, 7.0), p(7.0, 7.0), p(6.0, 9.0)]),
            Shape::Polygon(vec![
                p(5.5, 1.0),
                p(7.0, 1.0),
                p(7.0, 3.0),
                p(6.5, 3.0),
                p(6.5, 1.5),
                p(5.5, 1.5),
            ]),
            Shape::Polygon(vec![
                p(3.6, 2.4),
                p(4.6, 2.2),
                p(4.9, 3.1),
                p(4.2, 3.7),
                p(3.5, 3.2),
            ]),
        ],
        goals: vec![GoalShape::Circle {
            center: p(8.5, 1.5),
            radius: 0.15,
        }],
        robot_radius: 0.0,
    };
    let flags: Vec<String> = std::env::args().skip(2).collect();
    let opts = MeshOptions {
        max_area: Some(max_area),
        min_angle_deg: 30.0,
        prefill: flags.iter().any(|f| f == "prefill"),
        split_boundary_bridges: !flags.iter().any(|f| f == "no-bridges"),
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
