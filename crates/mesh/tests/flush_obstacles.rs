//! An obstacle flush with the workspace boundary, next to another obstacle: the boolean
//! operations return it as a hole sharing an edge with the exterior, which once made every
//! face look like a hole and the mesh empty.

use harmonic_mesh::{BoundaryTag, Domain, DomainSpec, GoalShape, MeshOptions, Point, Shape};

#[test]
fn obstacle_flush_with_the_wall_is_cut_out_not_a_hole() {
    let p = Point::new;
    let spec = DomainSpec {
        workspace: vec![p(0.0, 4.0), p(0.0, 1.5), p(2.5, 1.5), p(2.5, 4.0)],
        obstacles: vec![
            Shape::Polygon(vec![p(0.8, 3.0), p(1.2, 3.0), p(1.2, 4.0), p(0.8, 4.0)]),
            Shape::Polygon(vec![p(1.4, 2.4), p(1.8, 2.4), p(1.8, 2.8), p(1.4, 2.8)]),
        ],
        goals: vec![GoalShape::Polygon(vec![
            p(2.1, 1.7),
            p(2.3, 1.7),
            p(2.3, 1.9),
            p(2.1, 1.9),
        ])],
        robot_radius: 0.0,
    };
    let opts = MeshOptions {
        max_area: Some(0.02),
        min_angle_deg: 25.0,
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).expect("valid scene");
    let exact = 2.5 * 2.5 - 0.4 - 0.16 - 0.04;
    assert!(
        (domain.free_area() - exact).abs() < 1e-12,
        "{}",
        domain.free_area()
    );
    let (mesh, _) = domain.mesh(&opts).expect("meshes");
    let q = mesh.quality();
    assert!(q.triangles > 100, "{q:?}");
    assert!((q.area - exact).abs() < 1e-9, "{q:?}");
    assert_eq!(q.components, 1);
    let notch = mesh
        .boundary_edges()
        .iter()
        .filter(|e| e.tag == BoundaryTag::Obstacle(0))
        .count();
    assert!(notch >= 3, "the notch's three sides are obstacle 0's edges");
}
