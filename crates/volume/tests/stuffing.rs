//! Isosurface stuffing on the bundled kinds of scene: volume, quality, tags, conservativeness.

use harmonic_volume::{
    BoundaryTag, GoalRegion, MeshOptions, Point, Solid, SolidRole, SphereSolid, VolumeDomain,
    VolumeError, quality,
};

fn torus(robot: f64) -> VolumeDomain {
    VolumeDomain::new(
        Solid::new_box(
            SolidRole::Workspace,
            Point::new(0.0, 0.0, 0.0),
            Point::new(10.0, 10.0, 10.0),
        )
        .unwrap(),
        vec![
            Solid::new_box(
                SolidRole::Obstacle(0),
                Point::new(3.0, 3.0, -1.0),
                Point::new(7.0, 7.0, 11.0),
            )
            .unwrap(),
        ],
        vec![GoalRegion::Sphere(SphereSolid {
            center: Point::new(9.0, 9.0, 9.0),
            radius: 0.6,
        })],
        robot,
    )
    .unwrap()
}

fn spheres() -> VolumeDomain {
    VolumeDomain::new(
        Solid::new_box(
            SolidRole::Workspace,
            Point::new(0.0, 0.0, 0.0),
            Point::new(4.0, 4.0, 4.0),
        )
        .unwrap(),
        vec![
            Solid::new_sphere(SolidRole::Obstacle(0), Point::new(1.5, 2.0, 2.0), 0.8).unwrap(),
            Solid::new_sphere(SolidRole::Obstacle(1), Point::new(2.6, 2.0, 2.0), 0.7).unwrap(),
            Solid::new_box(
                SolidRole::Obstacle(2),
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
