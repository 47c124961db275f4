//! Triangle `.poly` files as free space: the bundled `meshes/triangle/*.poly`, bad files
//! (one clear line each), and, when `HARMONIC_TRIANGLE_DATA` names a directory of them,
//! Triangle's own sample files (the PyPI `triangle` package ships them in `triangle/data`).

use std::path::{Path, PathBuf};

use harmonic_fixtures::mesh_file;
use harmonic_mesh::io::poly::{Pslg, PslgFreeSpace};
use harmonic_mesh::{Domain, DomainSpec, Mesh, MeshError, MeshOptions, Point, Shape};

fn area(ring: &[Point]) -> f64 {
    harmonic_mesh::geom::signed_area(ring)
}

/// Meshes the free space of a `.poly` and checks the mesh against it: its area is the
/// workspace's less the holes', every constraint segment is covered by mesh edges, every
/// constraint point is a vertex, and the mesh is Delaunay with no obtuse boundary angle.
fn mesh_of(free: &PslgFreeSpace, max_area: f64, min_angle: f64) -> Mesh {
    let spec = DomainSpec {
        workspace: free.workspace.clone(),
        obstacles: free.holes.iter().cloned().map(Shape::Polygon).collect(),
        goals: vec![],
        robot_radius: 0.0,
    };
    let opts = MeshOptions {
        max_area: Some(max_area),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts)
        .and_then(|d| d.with_constraints(&free.constraint_segments, &free.constraint_points))
        .expect("domain");
    let (mesh, report) = domain.mesh(&opts).expect("mesh");
    assert!(report.refinement_complete);
    let q = mesh.quality();
    let expected = area(&free.workspace) + free.holes.iter().map(|h| area(h)).sum::<f64>();
    assert!(
        (q.area - expected).abs() <= 1e-9 * expected,
        "mesh area {} vs free area {expected}",
        q.area
    );
    assert_eq!(q.non_delaunay_edges, 0);
    assert_eq!(q.obtuse_boundary_edges, 0);
    assert!(q.min_angle_deg > min_angle, "min angle {}", q.min_angle_deg);
    assert_eq!(q.holes, free.holes.len());
    // Constraint segments are unions of mesh edges.
    let mut edges = std::collections::HashSet::new();
    for t in mesh.triangles() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    for &[a, b] in &free.constraint_segments {
        let on = |p: Point| {
            let (d, e) = (b - a, p - a);
            (d.x * e.y - d.y * e.x).abs() <= 1e-12 * d.norm_squared()
                && (-1e-12..=1.0 + 1e-12).contains(&(e.dot(&d) / d.norm_squared()))
        };
        let covered: f64 = edges
            .iter()
            .map(|&(i, j)| (mesh.vertices()[i as usize], mesh.vertices()[j as usize]))
            .filter(|&(p, q)| on(p) && on(q))
            .map(|(p, q)| (q - p).norm())
            .sum();
        assert!(
            ((covered - (b - a).norm()) / (b - a).norm()).abs() < 1e-9,
            "constraint {a} {b}: {covered} of {} covered",
            (b - a).norm()
        );
    }
    // (Vertices come back from the unit frame within rounding.)
    let size = free
        .workspace
        .iter()
        .map(|p| p.coords.amax())
        .fold(0.0, f64::max);
    for p in &free.constraint_points {
        let d = mesh
            .vertices()
            .iter()
            .map(|v| (v - p).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(d <= 1e-12 * size, "constraint point {p} kept ({d})");
    }
    mesh
}

fn bundled(name: &str) -> PslgFreeSpace {
    Pslg::read(&mesh_file(&format!("triangle/{name}")))
        .and_then(|p| p.free_space())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn two_hexagonal_holes() {
    let free = bundled("two_hex.poly");
    assert_eq!(free.workspace.len(), 24);
    assert!(area(&free.workspace) > 0.0);
    assert_eq!(free.holes.len(), 2);
    assert!(free.holes.iter().all(|h| h.len() == 6 && area(h) < 0.0));
    assert!(free.constraint_segments.is_empty() && free.constraint_points.is_empty());
    mesh_of(&free, 0.005, 28.0);
}

#[test]
fn interior_segments_and_points_are_constraints() {
    let free = bundled("slits.poly");
    // The outer L (its top edge split at the hanging slit's end), the triangle hole, the
    // free slit, the slit hanging from the wall, the lone vertex.
    assert_eq!(free.workspace.len(), 7);
    assert_eq!(free.holes.len(), 1);
    assert_eq!(free.constraint_segments.len(), 2);
    assert_eq!(free.constraint_points, vec![Point::new(0.6, 0.2)]);
    mesh_of(&free, 0.01, 28.0);
}

#[test]
fn a_closed_interior_ring_is_a_constraint_not_a_hole() {
    // layers.poly has no vertices: they come from layers.node.
    let pslg = Pslg::read(&mesh_file("triangle/layers.poly")).expect("read");
    assert_eq!(pslg.vertices.len(), 11);
    assert_eq!(pslg.regions.len(), 2);
    assert_eq!(pslg.regions[0].max_area, Some(0.01));
    let free = pslg.free_space().expect("free space");
    assert_eq!(free.holes.len(), 1);
    assert_eq!(free.constraint_segments.len(), 4);
    // Both sides of the inner ring are meshed (spade's own outer-face search would drop
    // its inside).
    mesh_of(&free, 0.005, 28.0);
}

fn error_of(text: &str) -> String {
    match Pslg::parse(text, "bad.poly", None).and_then(|p| p.free_space()) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => {
            let line = e.to_string();
            assert!(!line.contains('\n'), "one line: {line}");
            assert!(line.starts_with("bad.poly: "), "{line}");
            line
        }
    }
}

const SQUARE: &str = "\
4 2 0 0
1 0 0
2 4 0
3 4 4
4 0 4
4 0
1 1 2
2 2 3
3 3 4
4 4 1
";

#[test]
fn bad_files_get_one_clear_line() {
    // A square with a side missing: segment 1 ends at vertex 1, which nothing continues.
    let open = SQUARE.replace("4 0\n1 1 2\n", "3 0\n");
    let e = error_of(&open);
    assert!(e.contains("outer boundary is not closed"), "{e}");
    assert!(e.contains("vertex 2") || e.contains("vertex 1"), "{e}");
    // The gap of an outer boundary around a closed inner ring.
    let leaky = "8 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 1 1\n6 2 1\n7 2 2\n8 1 2\n\
                 7 0\n1 1 2\n2 2 3\n3 3 4\n4 5 6\n5 6 7\n6 7 8\n7 8 5\n0\n";
    let e = error_of(leaky);
    assert!(e.contains("outer boundary is not closed"), "{e}");
    // A hole in no ring removes everything.
    let e = error_of(&format!("{SQUARE}1\n1 2 2\n"));
    assert!(e.contains("hole 1") && e.contains("no closed ring"), "{e}");
    assert!(e.contains("line 12"), "{e}");
    // A hole outside.
    let e = error_of(&format!("{SQUARE}1\n1 9 9\n"));
    assert!(e.contains("outside the outer boundary"), "{e}");
    // An index out of range, named with its line.
    let e = error_of(&SQUARE.replace("4 4 1\n", "4 4 9\n"));
    assert!(e.contains("line 10") && e.contains("vertex 9"), "{e}");
    // A malformed line.
    let e = error_of(&SQUARE.replace("3 4 4\n", "3 4 x\n"));
    assert!(e.contains("line 4") && e.contains("not a number"), "{e}");
    // Crossing segments.
    let e = error_of(
        &SQUARE
            .replace("4 0\n1 1 2\n", "6 0\n1 1 2\n")
            .replace("4 4 1\n", "4 4 1\n5 1 3\n6 2 4\n"),
    );
    assert!(e.contains("crosses"), "{e}");
    // No vertices and no .node file.
    let e = error_of("0 2 0 0\n0 0\n");
    assert!(e.contains("no .node"), "{e}");
}

#[test]
fn comments_and_zero_based_indices_are_read() {
    let text = "# a comment line\n4 2 0 1 # trailing\n0 0 0 1\n1 4 0 1\n2 4 4 1\n3 0 4 1\n\
                4 1\n0 0 1 5\n1 1 2 5\n2 2 3 5\n3 3 0 5\n0\n";
    let pslg = Pslg::parse(text, "c.poly", None).expect("parse");
    assert_eq!(pslg.first_index, 0);
    assert_eq!(pslg.segments[0].marker, 5);
    let free = pslg.free_space().expect("free");
    assert!((area(&free.workspace) - 16.0).abs() < 1e-12);
}

/// Triangle's sample files, when `HARMONIC_TRIANGLE_DATA` names their directory.
fn triangle_data() -> Option<PathBuf> {
    match std::env::var_os("HARMONIC_TRIANGLE_DATA") {
        Some(d) if Path::new(&d).is_dir() => Some(PathBuf::from(d)),
        _ => {
            eprintln!(
                "skipped: set HARMONIC_TRIANGLE_DATA to the triangle/data directory of the PyPI `triangle` package to run this test on Triangle's sample files"
            );
            None
        }
    }
}

#[test]
fn triangle_sample_files() {
    let Some(dir) = triangle_data() else { return };
    for (name, holes, max_area) in [
        ("A.poly", 1, 0.0005),
        ("double_hex.poly", 2, 0.001),
        ("double_hex2.poly", 2, 0.001),
        ("double_hex3.poly", 2, 0.001),
        ("face.poly", 3, 50.0),
        ("la.poly", 0, 0.05),
        ("square_circle_hole.poly", 1, 0.001),
    ] {
        let free = Pslg::read(&dir.join(name))
            .and_then(|p| p.free_space())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(free.holes.len(), holes, "{name}");
        let mesh = mesh_of(&free, max_area, 0.0);
        eprintln!(
            "{name}: {} triangles, min angle {:.1}°",
            mesh.triangles().len(),
            mesh.quality().min_angle_deg
        );
    }
    // box.poly closes only its inner square: its outer box has one segment (Triangle meshes
    // its convex hull with -c); here that is an open outer boundary.
    let e = Pslg::read(&dir.join("box.poly"))
        .and_then(|p| p.free_space())
        .expect_err("box.poly has an open outer boundary");
    assert!(matches!(e, MeshError::Input { .. }), "{e}");
    assert!(e.to_string().contains("not closed"), "{e}");
}
