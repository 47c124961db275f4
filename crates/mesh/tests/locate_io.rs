//! Point location against brute force, Triangle file round trips and serde.

use harmonic_fixtures::{Rng, p, reference_disc};
use harmonic_mesh::{Domain, Mesh, MeshOptions, Point, io};

fn reference_mesh(max_area: f64) -> (Domain, Mesh) {
    let opts = MeshOptions {
        max_area: Some(max_area),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&reference_disc(), &opts).unwrap();
    let (mesh, _) = domain.mesh(&opts).unwrap();
    (domain, mesh)
}

/// A probe point for point location: a mesh vertex (`kind` 0), the midpoint of a triangle's
/// edge (1), or a point of a box slightly larger than the reference scene (otherwise).
fn probe_point(mesh: &Mesh, rng: &mut Rng, kind: usize) -> Point {
    match kind {
        0 => mesh.vertices()[(rng.next_f64() * mesh.vertices().len() as f64) as usize],
        1 => {
            let t = mesh.triangles()[(rng.next_f64() * mesh.triangles().len() as f64) as usize];
            let (a, b) = (
                mesh.vertices()[t[0] as usize],
                mesh.vertices()[t[1] as usize],
            );
            a + (b - a) * 0.5
        }
        _ => Point::new(rng.next_f64() * 10.4 - 0.2, rng.next_f64() * 10.4 - 0.2),
    }
}

#[test]
fn locate_agrees_with_brute_force() {
    let (domain, mesh) = reference_mesh(0.02);
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut hint = None;
    let mut inside = 0;
    for i in 0..10_000 {
        // Points over a slightly larger box, plus some exactly on mesh vertices and edges.
        let q = probe_point(&mesh, &mut rng, i % 10);
        let brute: Vec<u32> = (0..mesh.triangles().len() as u32)
            .filter(|&t| mesh.triangle_contains(t, q))
            .collect();
        for h in [None, hint, Some(0)] {
            let got = mesh.locate(q, h);
            match got {
                Some(t) => assert!(brute.contains(&t), "{q} in {t}, brute {brute:?}"),
                None => assert!(brute.is_empty(), "{q} missed, brute {brute:?}"),
            }
        }
        // Inside free space exactly when a triangle contains the point (away from edges).
        if brute.is_empty() {
            assert!(
                !domain.contains_free(q)
                    || domain.distance_to_obstacles(q) < 1e-9
                    || (q - p(8.5, 1.5)).norm() < 0.16,
                "{q}"
            );
        } else {
            inside += 1;
            assert!(domain.contains_free(q), "{q}");
        }
        hint = mesh.locate(q, hint).or(hint);
    }
    assert!(inside > 7000);
    assert_eq!(mesh.locate(Point::new(f64::NAN, 1.0), None), None);
    assert_eq!(mesh.locate(p(2.5, 5.0), Some(u32::MAX)), None);
}

/// The first locations a mesh answers without a hint scan every triangle; later ones use the
/// bucket grid. Both give the same triangle, on vertices and edges too.
#[test]
fn scanned_and_grid_locations_agree() {
    let (_, mesh) = reference_mesh(0.05);
    let warmed = mesh.clone();
    for _ in 0..16 {
        warmed.locate(p(-1.0, -1.0), None);
    }
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for i in 0..400 {
        let q = probe_point(&mesh, &mut rng, i % 4);
        let scanned = mesh.clone().locate(q, None);
        assert_eq!(scanned, warmed.locate(q, None), "{q}");
    }
}

#[test]
fn triangle_files_round_trip() {
    let (_, mesh) = reference_mesh(0.045);
    let node = io::to_node(&mesh).unwrap();
    let ele = io::to_ele(&mesh);
    let poly = io::to_poly(&mesh).unwrap();
    let back = io::from_triangle(&node, &ele, Some(&poly)).unwrap();
    assert_eq!(back.vertices(), mesh.vertices());
    assert_eq!(back.triangles(), mesh.triangles());
    assert_eq!(back.boundary_edges(), mesh.boundary_edges());
    // Without the .poly the tags come from vertex markers; the goal is still found.
    let back = io::from_triangle(&node, &ele, None).unwrap();
    assert_eq!(back.boundary_edges().len(), mesh.boundary_edges().len());
    // Files on disk, 1-based input with comments as Triangle writes it.
    let dir = std::env::temp_dir().join(format!("hm_io_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = dir.join("ref");
    io::write_files(&mesh, &base).unwrap();
    let again = io::read_files(&base).unwrap();
    assert_eq!(again.triangles(), mesh.triangles());
    std::fs::remove_dir_all(&dir).unwrap();
    let one_based = "# a triangle\n3 2 0 1\n1 0 0 1\n2 1 0 1\n3 0 1 1000000\n";
    let ele1 = "1 3 0\n1 1 3 2\n"; // clockwise on purpose
    let m = io::from_triangle(one_based, ele1, None).unwrap();
    assert_eq!(m.triangles().len(), 1);
    assert!(m.triangle_area(0) > 0.0);
}

#[test]
fn triangle_files_errors_name_file_and_line() {
    let e = io::from_triangle("3 2 0 0\n0 0 0\n1 1 x\n", "", None).unwrap_err();
    assert_eq!(
        e.to_string(),
        ".node: line 3: field 3 (\"x\") is not a number"
    );
    let e =
        io::from_triangle("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n", "1 3 0\n0 0 1 7\n", None).unwrap_err();
    assert_eq!(e.to_string(), ".ele: line 2: vertex 7 does not exist");
    let e =
        io::from_triangle("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n", "1 3 0\n0 0 1 2\n", None).unwrap_err();
    assert!(e.to_string().contains("no segment or vertex marker"), "{e}");
    assert_eq!(io::tag_of_marker(0), None);
    for tag in [
        harmonic_mesh::BoundaryTag::Wall,
        harmonic_mesh::BoundaryTag::Obstacle(7),
        harmonic_mesh::BoundaryTag::Goal(2),
    ] {
        assert_eq!(io::tag_of_marker(io::marker_of(tag).unwrap()), Some(tag));
    }
}

#[test]
fn serde_round_trip() {
    let (_, mesh) = reference_mesh(0.045);
    let json = serde_json::to_string(&mesh).unwrap();
    let back: Mesh = serde_json::from_str(&json).unwrap();
    // serde_json parses floats to within one ulp (exact with its float_roundtrip feature).
    for (a, b) in back.vertices().iter().zip(mesh.vertices()) {
        assert!((a - b).norm() <= 1e-15 * 10.0);
    }
    assert_eq!(back.boundary_edges(), mesh.boundary_edges());
    assert_eq!(
        back.locate(p(1.0, 1.0), None),
        mesh.locate(p(1.0, 1.0), None)
    );
    let spec = reference_disc();
    let json = serde_json::to_string(&spec).unwrap();
    assert_eq!(
        serde_json::from_str::<harmonic_mesh::DomainSpec>(&json).unwrap(),
        spec
    );
    let opts: MeshOptions = serde_json::from_str(r#"{"max_area": 0.01}"#).unwrap();
    assert_eq!(opts.min_angle_deg, 30.0);
}
