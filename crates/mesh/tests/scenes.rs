//! The bundled scenes (meshes/*.json): each meshes with its own `mesh` settings into a valid,
//! Delaunay, 30° mesh in which every start can reach the goal.
//!
//! Scene parsing belongs to the facade; `harmonic_fixtures::plane_scene` reads only the
//! geometry fields.

mod common;

use common::*;
use harmonic_fixtures::{plane_scene, reference};
use harmonic_mesh::{BoundaryTag, Domain, DomainSpec, MeshOptions, MeshReport, Point};

fn load(name: &str) -> (DomainSpec, MeshOptions, Vec<Point>) {
    let scene = plane_scene(name);
    (scene.spec, scene.options, scene.starts)
}

/// `cut`: whether a cut for two halves exists (none meets 50 scattered obstacles steeply
/// enough everywhere).
fn check_scene(name: &str, max_triangles: usize, cut: bool) {
    let (spec, opts, starts) = load(name);
    check_mesh(name, &spec, &opts, &starts, max_triangles);
    // The same scene made in two halves glued along a cut (as large meshes are).
    let halves = MeshOptions {
        halves_from: 0,
        ..opts
    };
    let report = check_mesh(name, &spec, &halves, &starts, max_triangles);
    assert_eq!(report.seam.is_some(), cut, "{name}: {:?}", report.seam);
}

fn check_mesh(
    name: &str,
    spec: &DomainSpec,
    opts: &MeshOptions,
    starts: &[Point],
    max_triangles: usize,
) -> MeshReport {
    let domain = Domain::new(spec, opts).unwrap();
    let (mesh, report) = domain.mesh(opts).unwrap();
    let q = mesh.quality();
    eprintln!("{name}: {q:?}");
    assert!(report.refinement_complete, "{name}");
    check_invariants(&mesh, domain.free_area(), 1e-9).unwrap();
    assert!(
        q.triangles <= max_triangles,
        "{name}: {} triangles",
        q.triangles
    );
    assert!(
        q.min_angle_deg >= opts.min_angle_deg - 1e-9,
        "{name}: {q:?}"
    );
    assert_eq!(q.non_delaunay_edges, 0, "{name}");
    assert_eq!(q.obtuse_boundary_edges, 0, "{name}");
    // Every start lies in free space, in a component that touches the goal.
    let goal_components: Vec<u32> = mesh
        .boundary_edges()
        .iter()
        .filter(|e| matches!(e.tag, BoundaryTag::Goal(_)))
        .map(|e| mesh.triangle_components()[e.triangle as usize])
        .collect();
    assert!(!starts.is_empty());
    for &s in starts {
        assert!(domain.contains_free(s), "{name}: start {s}");
        let t = mesh
            .locate(s, None)
            .unwrap_or_else(|| panic!("{name}: start {s} not located"));
        assert!(
            goal_components.contains(&mesh.triangle_components()[t as usize]),
            "{name}: start {s} cannot reach the goal"
        );
        assert!(
            domain.distance_to_obstacles(s) > 0.2,
            "{name}: start {s} too close to an obstacle"
        );
    }
    report
}

#[test]
fn maze() {
    check_scene("maze", 40_000, true);
}

#[test]
fn office() {
    check_scene("office", 40_000, true);
}

#[test]
fn concave_trap() {
    check_scene("concave_trap", 40_000, true);
}

#[test]
fn clutter() {
    let (spec, _, _) = load("clutter");
    assert!(spec.obstacles.len() >= 45);
    check_scene("clutter", 40_000, false);
}

#[test]
fn reference_json_matches_the_rust_reference_scene() {
    let (spec, opts, _) = load("reference");
    assert_eq!(spec.workspace, reference().workspace);
    assert_eq!(spec.obstacles, reference().obstacles);
    check_scene("reference", 40_000, true);
    assert_eq!(opts.max_area, Some(0.0044));
}
