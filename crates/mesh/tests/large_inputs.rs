//! Detailed and numerous obstacles: preparation that scales, the budget that sees boundary
//! detail, and `MeshOptions::simplify`. The large cases (a 200 000-vertex polygon, a forest
//! of 3000 circles) are `#[ignore]`d: run them with
//! `cargo test --release -p harmonic-mesh --test large_inputs -- --ignored --nocapture`.

use std::time::Instant;

use harmonic_fixtures::{p, rect};
use harmonic_mesh::{Domain, DomainSpec, GoalShape, MeshError, MeshOptions, Point, Shape};

/// A circle of radius `r` about `c` sampled at `n` vertices (a traced or CAD outline).
fn sampled_circle(c: Point, r: f64, n: usize) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            p(c.x + r * t.cos(), c.y + r * t.sin())
        })
        .collect()
}

fn room_with(obstacle: Vec<Point>) -> DomainSpec {
    DomainSpec {
        workspace: rect(0.0, 0.0, 10.0, 10.0),
        obstacles: vec![Shape::Polygon(obstacle)],
        goals: vec![GoalShape::Circle {
            center: p(9.0, 9.0),
            radius: 0.3,
        }],
        robot_radius: 0.0,
    }
}

/// The forest: `n` circles of radius 0.4–0.8 on a jittered grid in a 100 × 100 m square.
pub fn forest(n: usize) -> DomainSpec {
    let side = (n as f64).sqrt().ceil() as usize;
    let cell = 100.0 / side as f64;
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut rnd = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let obstacles = (0..n)
        .map(|k| {
            let (i, j) = (k % side, k / side);
            let r = 0.1 * cell * (1.0 + rnd());
            let cx = (i as f64 + 0.5 + 0.3 * (rnd() - 0.5)) * cell;
            let cy = (j as f64 + 0.5 + 0.3 * (rnd() - 0.5)) * cell;
            Shape::Circle {
                center: p(cx, cy),
                radius: r,
            }
        })
        .collect();
    DomainSpec {
        workspace: rect(-1.0, -1.0, 101.0, 101.0),
        obstacles,
        goals: vec![GoalShape::Point(p(100.5, 100.5))],
        robot_radius: 0.0,
    }
}

#[test]
fn simplify_keeps_the_original_inside_and_drops_vertices() {
    let fine = sampled_circle(p(5.0, 5.0), 2.0, 4000);
    let spec = room_with(fine.clone());
    let opts = MeshOptions {
        max_area: Some(0.05),
        simplify: Some(0.01),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).expect("domain");
    let hole: usize = domain
        .obstacle_polygons()
        .iter()
        .map(|r| r.exterior.len())
        .sum();
    assert!(hole < 400, "{hole} vertices left of 4000");
    // Every original vertex is outside free space (or on its boundary): the simplified
    // obstacle contains the original.
    for q in &fine {
        assert!(
            !domain.contains_free(*q) || domain.distance_to_obstacles(*q) < 1e-9,
            "{q:?} is in free space"
        );
    }
    // And the boundary moved out by at most about the tolerance.
    let (mesh, _) = domain.mesh(&opts).expect("mesh");
    let nearest = mesh
        .vertices()
        .iter()
        .map(|v| (v - p(5.0, 5.0)).norm())
        .fold(f64::INFINITY, f64::min);
    assert!((2.0 - 1e-9..=2.0 + 0.011).contains(&nearest), "{nearest}");
}

#[test]
fn a_too_detailed_obstacle_is_refused_naming_it_and_suggesting_simplify() {
    let spec = room_with(sampled_circle(p(5.0, 5.0), 2.0, 20_000));
    let opts = MeshOptions {
        max_area: Some(0.05),
        max_triangles: 20_000,
        ..MeshOptions::default()
    };
    let t = Instant::now();
    let Err(e) = Domain::new(&spec, &opts).and_then(|d| d.mesh(&opts)) else {
        panic!("a too detailed obstacle was meshed");
    };
    assert!(t.elapsed().as_secs_f64() < 5.0);
    assert!(
        matches!(e, MeshError::TooDetailed { obstacle: 0, .. }),
        "{e:?}"
    );
    let line = e.to_string();
    assert!(
        line.contains("obstacle 0") && line.contains("20000 vertices"),
        "{line}"
    );
    assert!(line.contains("mesh.simplify"), "{line}");
    assert!(!line.contains('\n'), "{line}");
}

/// A 200 000-vertex polygon: prepared in O(n log n) and meshed, or refused at once.
#[test]
#[ignore = "large: run with --ignored to see the figures"]
fn a_200k_vertex_polygon_meshes_in_seconds() {
    let spec = room_with(sampled_circle(p(5.0, 5.0), 2.0, 200_000));
    let opts = MeshOptions::default();
    let t = Instant::now();
    let domain = Domain::new(&spec, &opts).expect("domain");
    let prepared = t.elapsed().as_secs_f64();
    let (mesh, report) = domain.mesh(&opts).expect("mesh");
    let total = t.elapsed().as_secs_f64();
    println!(
        "200k-vertex polygon: domain {prepared:.2} s, mesh {:.2} s, {} triangles (estimated {})",
        total - prepared,
        mesh.triangles().len(),
        report.estimated_triangles
    );
    assert!(total < 30.0);
}

/// 3000 circles in 100 × 100 m.
#[test]
#[ignore = "large: run with --ignored to see the figures"]
fn a_forest_of_3000_circles_meshes_in_seconds() {
    let spec = forest(3000);
    let opts = MeshOptions::default();
    let t = Instant::now();
    let domain = Domain::new(&spec, &opts).expect("domain");
    let prepared = t.elapsed().as_secs_f64();
    let (mesh, report) = domain.mesh(&opts).expect("mesh");
    let total = t.elapsed().as_secs_f64();
    println!(
        "3000 circles: domain {prepared:.2} s, mesh {:.2} s, {} triangles, {} input vertices, max_area {}",
        total - prepared,
        mesh.triangles().len(),
        report.input_vertices,
        report.max_area
    );
    if let Ok(path) = std::env::var("FOREST_POLY") {
        std::fs::write(&path, boundary_poly(&domain)).expect("write .poly");
        println!("boundary written to {path}");
    }
}

/// Free space's boundary as a Triangle `.poly` (vertices, segments, a hole point at the
/// centroid of each hole ring: the forest's holes are convex).
fn boundary_poly(domain: &Domain) -> String {
    use std::fmt::Write;
    let rings = domain.free_rings();
    let n: usize = rings.iter().map(|r| r.points.len()).sum();
    let mut out = format!("{n} 2 0 0\n");
    let mut k = 0;
    for r in rings {
        for q in &r.points {
            k += 1;
            let _ = writeln!(out, "{k} {:.17e} {:.17e}", q.x, q.y);
        }
    }
    let _ = writeln!(out, "{n} 0");
    let (mut s, mut base) = (0, 0);
    for r in rings {
        let m = r.points.len();
        for i in 0..m {
            s += 1;
            let _ = writeln!(out, "{s} {} {}", base + i + 1, base + (i + 1) % m + 1);
        }
        base += m;
    }
    let holes: Vec<Point> = rings
        .iter()
        .filter(|r| {
            let m = r.points.len();
            (0..m)
                .map(|i| {
                    let (a, b) = (r.points[i], r.points[(i + 1) % m]);
                    a.x * b.y - b.x * a.y
                })
                .sum::<f64>()
                < 0.0
        })
        .map(|r| {
            let c = r
                .points
                .iter()
                .fold(p(0.0, 0.0), |a, q| p(a.x + q.x, a.y + q.y));
            p(c.x / r.points.len() as f64, c.y / r.points.len() as f64)
        })
        .collect();
    let _ = writeln!(out, "{}", holes.len());
    for (i, h) in holes.iter().enumerate() {
        let _ = writeln!(out, "{} {:.17e} {:.17e}", i + 1, h.x, h.y);
    }
    out
}
