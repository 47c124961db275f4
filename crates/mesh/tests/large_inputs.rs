//! Detailed and numerous obstacles: preparation that scales, the budget that sees boundary
//! detail, and `MeshOptions::simplify`. The large cases (a 200 000-vertex polygon, a forest
//! of 3000 circles) are `#[ignore]`d: run them with
//! `cargo test --release -p harmonic-mesh --test large_inputs -- --ignored --nocapture`.

use std::time::Instant;

use harmonic_fixtures::{detailed_room, forest, free_space_poly, p, room_with, sampled_circle};
use harmonic_mesh::{Domain, MeshError, MeshOptions};

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

/// The triangles short boundary edges force are in the estimate: the 200 000-vertex circle
/// of radius 1 needs about 1.8 M triangles at the default area bound (1.6 per `max_area` of
/// free space would be 32 k), so a budget of 1 M refuses it before triangulating, naming the
/// obstacle, its vertex count and a `mesh.simplify` value in one line; with that value it
/// fits.
#[test]
fn a_200k_vertex_circle_over_the_budget_is_refused_before_meshing() {
    let spec = detailed_room(200_000, 1.0);
    let opts = MeshOptions {
        max_triangles: 1_000_000,
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).expect("domain");
    let Err(e) = domain.mesh(&opts) else {
        panic!("a 1.8 M-triangle mesh was made within a budget of 1 M");
    };
    let MeshError::TooDetailed {
        obstacle,
        vertices,
        estimated,
        suggest,
        ..
    } = e
    else {
        panic!("{e:?}");
    };
    assert_eq!((obstacle, vertices), (0, 200_000));
    assert!((1_500_000..2_500_000).contains(&estimated), "{estimated}");
    let line = e.to_string();
    assert!(
        line.contains("obstacle 0 has 200000 vertices") && line.contains("mesh.simplify"),
        "{line}"
    );
    assert!(!line.contains('\n'), "{line}");
    let simplified = MeshOptions {
        simplify: Some(suggest),
        ..opts
    };
    let domain = Domain::new(&spec, &simplified).expect("domain");
    let (mesh, report) = domain
        .mesh(&simplified)
        .expect("the suggested simplification fits");
    assert!(report.refinement_complete);
    assert!(
        mesh.triangles().len() < 100_000,
        "{}",
        mesh.triangles().len()
    );
}

/// The estimate follows what refinement makes around short edges (within 30 %), whether the
/// edges are 1/200 of the target edge length (a finely sampled circle) or 1/7 (a forest of
/// small discs).
#[test]
fn the_estimate_counts_the_triangles_short_edges_force() {
    for (name, spec) in [
        ("20 000-vertex circle", detailed_room(20_000, 1.0)),
        ("forest of 400", forest(400)),
    ] {
        let opts = MeshOptions::default();
        let (mesh, report) = Domain::new(&spec, &opts)
            .and_then(|d| d.mesh(&opts))
            .expect("mesh");
        let ratio = report.estimated_triangles as f64 / mesh.triangles().len() as f64;
        assert!(
            (0.9..1.3).contains(&ratio),
            "{name}: estimated {}, made {}",
            report.estimated_triangles,
            mesh.triangles().len()
        );
    }
}

/// A 200 000-vertex polygon: prepared in O(n log n) and meshed, or refused at once.
#[test]
#[ignore = "large: run with --ignored to see the figures"]
fn a_200k_vertex_polygon_meshes_in_seconds() {
    let spec = detailed_room(200_000, 1.0);
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
        std::fs::write(&path, free_space_poly(&domain)).expect("write .poly");
        println!("boundary written to {path}");
    }
}
