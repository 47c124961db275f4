//! Isosurface stuffing on the bundled kinds of scene: volume, quality, tags, conservativeness.

use harmonic_volume::{
    BoundaryTag, GoalRegion, MeshOptions, Part, Point, Solid, SphereSolid, VolumeDomain,
    VolumeError, quality,
};

fn torus(robot: f64) -> VolumeDomain {
    harmonic_fixtures::torus_domain(
        GoalRegion::Sphere(SphereSolid {
            center: Point::new(9.0, 9.0, 9.0),
            radius: 0.6,
        }),
        robot,
    )
}

fn spheres() -> VolumeDomain {
    VolumeDomain::new(
        Solid::new_box(
            Part::Workspace,
            Point::new(0.0, 0.0, 0.0),
            Point::new(4.0, 4.0, 4.0),
        )
        .unwrap(),
        vec![
            Solid::new_sphere(Part::Obstacle(0), Point::new(1.5, 2.0, 2.0), 0.8).unwrap(),
            Solid::new_sphere(Part::Obstacle(1), Point::new(2.6, 2.0, 2.0), 0.7).unwrap(),
            Solid::new_box(
                Part::Obstacle(2),
                Point::new(3.3, -1.0, 0.3),
                Point::new(5.0, 1.13, 1.7),
            )
            .unwrap(),
        ],
        vec![GoalRegion::Point(Point::new(0.5, 0.5, 3.5))],
        0.1,
    )
    .unwrap()
}

#[test]
fn torus_box_aligned_with_the_lattice_is_exact() {
    let domain = torus(0.0);
    // h = 0.5: the hole's faces lie on lattice planes.
    let (mesh, report) = domain
        .mesh(&MeshOptions::with_max_volume(0.125 / 12.0))
        .unwrap();
    let q = quality(&mesh);
    println!("torus: {report:?}\n{q:?}");
    assert_eq!(report.passes, 1, "no margin needed");
    let ball = 4.0 / 3.0 * std::f64::consts::PI * 0.6f64.powi(3);
    let exact = 1000.0 - 160.0 - ball;
    assert!(
        (mesh.volume() - exact).abs() < 0.3 * ball,
        "volume {} vs {exact}",
        mesh.volume()
    );
    assert!(
        q.min_dihedral_deg > 9.0 && q.max_dihedral_deg < 166.0,
        "{q:?}"
    );
    let area = |tag: BoundaryTag| -> f64 {
        mesh.boundary_faces()
            .iter()
            .filter(|f| f.tag == tag)
            .map(|f| {
                let [a, b, c] = f.vertices.map(|v| mesh.vertices()[v as usize]);
                (b - a).cross(&(c - a)).norm() / 2.0
            })
            .sum()
    };
    // Walls: 6 faces of 100 minus the two 4×4 holes; obstacle: 4 sides of 4×10.
    assert!(
        (area(BoundaryTag::Wall) - 568.0).abs() < 1e-9,
        "{}",
        area(BoundaryTag::Wall)
    );
    assert!((area(BoundaryTag::Obstacle(0)) - 160.0).abs() < 1e-9);
    let sphere_area = 4.0 * std::f64::consts::PI * 0.36;
    assert!((area(BoundaryTag::Goal(0)) - sphere_area).abs() < 0.35 * sphere_area);
}

#[test]
fn curved_and_unaligned_obstacles_are_meshed_conservatively() {
    let domain = spheres();
    let (mesh, report) = domain.mesh(&MeshOptions::with_max_volume(0.002)).unwrap();
    let q = quality(&mesh);
    println!("spheres: {report:?}\n{q:?}");
    assert!(report.clearance_deficit <= 1e-10, "{report:?}");
    assert!(
        report.margin > 0.0 && report.margin < 0.5 * report.spacing,
        "{report:?}"
    );
    assert!(
        q.min_dihedral_deg > 5.0 && q.max_dihedral_deg < 175.0,
        "{q:?}"
    );
    // Every vertex keeps the robot's clearance from every obstacle and wall.
    for p in mesh.vertices() {
        for o in domain.obstacles() {
            assert!(o.signed_distance(p) >= 0.1 - 1e-9);
        }
        assert!(-domain.workspace().signed_distance(p) >= 0.1 - 1e-9);
    }
    // All three obstacles and the point goal show up as tagged faces.
    for tag in [
        BoundaryTag::Obstacle(0),
        BoundaryTag::Obstacle(1),
        BoundaryTag::Obstacle(2),
        BoundaryTag::Goal(0),
        BoundaryTag::Wall,
    ] {
        assert!(mesh.boundary_faces().iter().any(|f| f.tag == tag), "{tag}");
    }
}

#[test]
fn budget_is_refused_in_one_line_before_meshing() {
    let domain = torus(0.0);
    let mut opts = MeshOptions::with_max_volume(1e-6);
    opts.max_tetrahedra = 1_000_000;
    let e = domain.mesh(&opts).unwrap_err();
    assert!(matches!(e, VolumeError::TooManyTetrahedra { .. }));
    assert!(!e.to_string().contains('\n'));
    let e = domain
        .mesh(&MeshOptions::with_max_volume(-1.0))
        .unwrap_err();
    assert!(matches!(e, VolumeError::BadMaxVolume { .. }));
}

#[test]
fn point_location_finds_every_centroid() {
    let domain = torus(0.0);
    let (mesh, _) = domain
        .mesh(&MeshOptions::with_max_volume(1.0 / 12.0))
        .unwrap();
    for t in (0..mesh.tetrahedra().len() as u32).step_by(7) {
        let p = mesh.tet_points(t);
        let c = Point::from((p[0].coords + p[1].coords + p[2].coords + p[3].coords) / 4.0);
        assert_eq!(mesh.locate(&c, None), Some(t));
        assert_eq!(mesh.locate(&c, Some(0)), Some(t));
    }
    assert_eq!(mesh.locate(&Point::new(5.0, 5.0, 5.0), None), None);
}

/// A configuration-space-like domain known only through an inside test (±1, no distances):
/// a solid torus (tube radius 0.5 around a circle of radius 1.5). Cut points come from
/// bisection; the mesh's volume approaches 2π²Rr².
struct InsideOnlyTorus;

impl harmonic_volume::ImplicitDomain for InsideOnlyTorus {
    fn value(&self, p: &Point) -> f64 {
        let q = ((p.x * p.x + p.y * p.y).sqrt() - 1.5).hypot(p.z);
        if q < 0.5 { -1.0 } else { 1.0 }
    }
    fn tag(&self, _p: &Point) -> BoundaryTag {
        BoundaryTag::Obstacle(0)
    }
    fn bounds(&self) -> (Point, Point) {
        (Point::new(-2.0, -2.0, -0.5), Point::new(2.0, 2.0, 0.5))
    }
}

#[test]
fn an_inside_test_alone_is_enough_to_mesh() {
    use harmonic_volume::{StuffingOptions, TetMesh, stuff};
    let exact = 2.0 * std::f64::consts::PI.powi(2) * 1.5 * 0.25;
    let mut errors = Vec::new();
    for h in [0.2, 0.1] {
        let s = stuff(
            &InsideOnlyTorus,
            &StuffingOptions {
                spacing: h,
                max_tetrahedra: 10_000_000,
            },
        )
        .unwrap();
        let mesh = TetMesh::new(s.vertices, s.tetrahedra, &|_| BoundaryTag::Obstacle(0)).unwrap();
        let q = quality(&mesh);
        let err = (mesh.volume() - exact).abs() / exact;
        println!(
            "inside-only torus, h = {h}: {} tets, volume error {err:.2e}, {q:?}",
            q.tetrahedra
        );
        assert!(q.min_dihedral_deg > 5.0 && q.max_dihedral_deg < 175.0);
        // Closed: every boundary face's edges are shared by two boundary faces.
        let mut edges = std::collections::HashMap::new();
        for f in mesh.boundary_faces() {
            for k in 0..3 {
                let (a, b) = (f.vertices[k], f.vertices[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        assert!(
            edges.values().all(|&c| c == 2),
            "the boundary is a closed surface"
        );
        errors.push(err);
    }
    // Chords of a convex-ish surface: second order in h.
    assert!(
        errors[1] < 0.4 * errors[0] && errors[1] < 0.01,
        "{errors:?}"
    );
}

#[test]
fn triangle_surface_obstacles_are_meshed_around_with_clearance() {
    // An octahedron of "radius" 1 around (2, 2, 2), given inward-oriented (it is reoriented).
    let c = Point::new(2.0, 2.0, 2.0);
    let v = vec![
        c + harmonic_volume::Vector::x(),
        c - harmonic_volume::Vector::x(),
        c + harmonic_volume::Vector::y(),
        c - harmonic_volume::Vector::y(),
        c + harmonic_volume::Vector::z(),
        c - harmonic_volume::Vector::z(),
    ];
    let t = vec![
        [0, 4, 2],
        [2, 4, 1],
        [1, 4, 3],
        [3, 4, 0],
        [0, 2, 5],
        [2, 1, 5],
        [1, 3, 5],
        [3, 0, 5],
    ];
    let octahedron = Solid::new_surface(Part::Obstacle(0), v, t).unwrap();
    assert!((octahedron.volume() - 4.0 / 3.0).abs() < 1e-12);
    let domain = VolumeDomain::new(
        Solid::new_box(
            Part::Workspace,
            Point::new(0.0, 0.0, 0.0),
            Point::new(4.0, 4.0, 4.0),
        )
        .unwrap(),
        vec![octahedron],
        vec![GoalRegion::Point(Point::new(0.5, 0.5, 0.5))],
        0.1,
    )
    .unwrap();
    let (mesh, report) = domain.mesh(&MeshOptions::with_max_volume(0.002)).unwrap();
    println!("octahedron: {report:?}");
    assert!(report.clearance_deficit <= 1e-10, "{report:?}");
    assert!(
        mesh.boundary_faces()
            .iter()
            .any(|f| f.tag == BoundaryTag::Obstacle(0))
    );
    for p in mesh.vertices() {
        assert!(
            domain.obstacles()[0].signed_distance(p) >= 0.1 - 1e-9,
            "{p}"
        );
    }
    // The free volume: the box shrunk by 0.1 (3.8³) minus the octahedron inflated by 0.1 plus
    // the margin (surface 4√3 ≈ 6.9 times about 0.19) and the goal ball.
    let shrunk = 3.8f64.powi(3) - 4.0 / 3.0;
    assert!(mesh.volume() < shrunk, "{}", mesh.volume());
    assert!(mesh.volume() > shrunk - 2.0, "{}", mesh.volume());
}

#[test]
fn the_reported_dihedral_extremes_are_those_of_every_angle() {
    use harmonic_volume::{dihedral_range, tet_angles_and_weights};
    // A graded mesh (a point goal among curved obstacles): angles from sharp to obtuse.
    let (mesh, _) = spheres().mesh(&MeshOptions::with_max_volume(0.01)).unwrap();
    let (mut lo, mut hi, mut obtuse) = (f64::INFINITY, 0.0f64, 0);
    for t in 0..mesh.tetrahedra().len() as u32 {
        let (angles, _) = tet_angles_and_weights(&mesh, t);
        let deg = angles.map(f64::to_degrees);
        lo = deg.iter().copied().fold(lo, f64::min);
        hi = deg.iter().copied().fold(hi, f64::max);
        obtuse += usize::from(deg.iter().any(|&d| d > 90.0 + 1e-9));
    }
    let q = quality(&mesh);
    assert_eq!(dihedral_range(&mesh), [lo, hi]);
    assert_eq!([q.min_dihedral_deg, q.max_dihedral_deg], [lo, hi]);
    assert_eq!(q.obtuse_tetrahedra, obtuse);
    assert!(
        obtuse > 0 && lo < 60.0,
        "a mesh that exercises both ends: {q:?}"
    );
}
