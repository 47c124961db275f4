//! Input vertices a rounding error away from another input's edge or vertex (issue #8, the
//! fuzz finding `found_spade_locate_panic_near_wall_vertex.json`): `Domain::new` snaps them
//! onto it, so the booleans see an exact touch and cut the obstacle out of the workspace as
//! they do for flush obstacles, instead of leaving a sliver no refinement can resolve.

mod common;

use common::check_invariants_with_bridges;
use harmonic_fixtures::{area, p, rect};
use harmonic_mesh::{BoundaryTag, Domain, DomainSpec, GoalShape, Mesh, MeshOptions, Point, Shape};

fn opts() -> MeshOptions {
    MeshOptions {
        max_area: Some(0.05),
        ..MeshOptions::default()
    }
}

/// Meshes `spec`, checks the mesh invariants against the area of the workspace minus
/// `removed` (exact obstacle and goal polygon areas) and returns the domain and mesh.
fn mesh_checked(spec: &DomainSpec, removed: f64) -> (Domain, Mesh) {
    let domain = Domain::new(spec, &opts()).expect("valid scene");
    let goal_area: f64 = domain
        .goal_polygons()
        .iter()
        .map(|g| area(&g.exterior))
        .sum();
    let exact = area(&spec.workspace).abs() - removed - goal_area;
    assert!(
        (domain.free_area() - exact).abs() <= 1e-9 * exact,
        "free area {} vs {exact}",
        domain.free_area()
    );
    let (mesh, report) = domain.mesh(&opts()).expect("meshes");
    assert!(report.refinement_complete, "{report:?}");
    check_invariants_with_bridges(&mesh, exact, 1e-9, report.bridges_remaining)
        .unwrap_or_else(|e| panic!("{e}"));
    (domain, mesh)
}

/// Whether `q` is a vertex of some free-space ring with the given tag on an edge at it.
fn ring_vertex_with_tag(domain: &Domain, q: Point, tag: BoundaryTag) -> bool {
    domain.free_rings().iter().any(|r| {
        let n = r.points.len();
        (0..n).any(|k| r.points[k] == q && (r.tags[k] == tag || r.tags[(k + n - 1) % n] == tag))
    })
}

fn fuzz_obstacle(y: f64) -> Vec<Point> {
    vec![
        p(8.0, 2.2),
        p(12.5, y),
        p(11.5, 7.5),
        p(8.0, 7.5),
        p(8.0, 6.9),
        p(10.9, 6.9),
        p(10.9, 3.1),
        p(8.0, 3.1),
    ]
}

fn fuzz_scene(y: f64) -> DomainSpec {
    DomainSpec {
        workspace: rect(0.0, 0.0, 20.0, 10.0),
        obstacles: vec![Shape::Polygon(fuzz_obstacle(y))],
        goals: vec![GoalShape::Circle {
            center: p(18.0, 9.0),
            radius: 0.4,
        }],
        robot_radius: 0.0,
    }
}

#[test]
fn the_fuzz_finding_meshes_with_the_obstacle_touching_the_wall() {
    for y in [2.1e-16, 1e-13, -1e-13, 1e-10] {
        let spec = fuzz_scene(y);
        let (domain, mesh) = mesh_checked(&spec, area(&fuzz_obstacle(0.0)));
        // The corner sits exactly on the wall, as a vertex of both.
        let corner = p(12.5, 0.0);
        assert!(
            ring_vertex_with_tag(&domain, corner, BoundaryTag::Wall),
            "y = {y}"
        );
        assert!(ring_vertex_with_tag(
            &domain,
            corner,
            BoundaryTag::Obstacle(0)
        ));
        let v = mesh
            .vertices()
            .iter()
            .position(|&q| q == corner)
            .expect("the touching corner is a mesh vertex");
        let tags: Vec<BoundaryTag> = mesh
            .boundary_edges()
            .iter()
            .filter(|e| e.vertices.contains(&(v as u32)))
            .map(|e| e.tag)
            .collect();
        assert!(tags.contains(&BoundaryTag::Wall) && tags.contains(&BoundaryTag::Obstacle(0)));
        // Inside the obstacle's wedge at the corner: no triangle; either side of it: free.
        assert!(mesh.locate(p(12.49, 0.01), None).is_none());
        assert!(mesh.locate(p(12.6, 0.01), None).is_some());
        assert!(mesh.locate(p(12.4, 0.01), None).is_some());
        assert_eq!(mesh.component_count(), 1);
    }
}

#[test]
fn a_vertex_just_off_a_slanted_wall_is_moved_onto_it() {
    let workspace = vec![p(0.0, 0.0), p(20.0, 5.0), p(20.0, 15.0), p(0.0, 10.0)];
    for d in [1e-13, -1e-13, 2e-16] {
        // The wall is y = x / 4; the corner (12, 3 + d) is within |d| of it.
        let obstacle = vec![p(12.0, 3.0 + d), p(14.0, 8.0), p(10.0, 8.0)];
        let spec = DomainSpec {
            workspace: workspace.clone(),
            obstacles: vec![Shape::Polygon(obstacle.clone())],
            goals: vec![GoalShape::Circle {
                center: p(18.0, 12.0),
                radius: 0.4,
            }],
            robot_radius: 0.0,
        };
        let (domain, mesh) = mesh_checked(&spec, area(&obstacle));
        // The moved corner is a vertex of the wall and of the obstacle, within |d| of where
        // it was.
        let shared = domain
            .free_rings()
            .iter()
            .flat_map(|r| r.points.iter().copied())
            .filter(|&q| (q - p(12.0, 3.0)).norm() <= 2.0 * d.abs())
            .collect::<Vec<_>>();
        assert!(!shared.is_empty(), "d = {d}");
        for q in shared {
            assert!(ring_vertex_with_tag(&domain, q, BoundaryTag::Wall), "{q:?}");
            assert!(ring_vertex_with_tag(&domain, q, BoundaryTag::Obstacle(0)));
        }
        assert_eq!(mesh.component_count(), 1);
    }
}

#[test]
fn a_vertex_just_off_another_obstacles_edge_touches_it() {
    // Obstacle 1's corner is within 1e-13 of obstacle 0's slanted bottom edge
    // (5, 3)–(9, 4), from outside or from inside.
    for d in [1e-13, -1e-13] {
        let a = vec![p(5.0, 3.0), p(9.0, 4.0), p(9.0, 6.0), p(5.0, 6.0)];
        let b = vec![p(7.0, 3.5 - d), p(8.0, 1.0), p(9.0, 2.0)];
        let spec = DomainSpec {
            workspace: rect(0.0, 0.0, 20.0, 10.0),
            obstacles: vec![Shape::Polygon(a.clone()), Shape::Polygon(b.clone())],
            goals: vec![GoalShape::Point(p(18.0, 9.0))],
            robot_radius: 0.0,
        };
        let (domain, mesh) = mesh_checked(&spec, area(&a) + area(&b));
        // The corner moved onto the edge (by at most |d|) and is a vertex of both.
        let shared: Vec<Point> = domain
            .free_rings()
            .iter()
            .flat_map(|r| r.points.iter().copied())
            .filter(|&q| (q - p(7.0, 3.5)).norm() <= 2.0 * d.abs())
            .collect();
        assert!(!shared.is_empty(), "d = {d}");
        for q in shared {
            assert!(ring_vertex_with_tag(&domain, q, BoundaryTag::Obstacle(0)));
            assert!(ring_vertex_with_tag(&domain, q, BoundaryTag::Obstacle(1)));
        }
        let tags = |t| mesh.boundary_edges().iter().any(|e| e.tag == t);
        assert!(tags(BoundaryTag::Obstacle(0)) && tags(BoundaryTag::Obstacle(1)));
    }
}

#[test]
fn nearly_coincident_corners_of_two_obstacles_become_one() {
    let a = rect(5.0, 5.0, 6.0, 6.0);
    let b = vec![p(6.0 + 1e-13, 6.0 - 3e-14), p(7.0, 6.5), p(6.5, 7.0)];
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 20.0, 10.0),
        obstacles: vec![Shape::Polygon(a.clone()), Shape::Polygon(b.clone())],
        goals: vec![GoalShape::Point(p(18.0, 9.0))],
        robot_radius: 0.0,
    };
    let (domain, mesh) = mesh_checked(&spec, area(&a) + area(&b));
    let corner = p(6.0, 6.0);
    assert!(ring_vertex_with_tag(
        &domain,
        corner,
        BoundaryTag::Obstacle(0)
    ));
    assert!(ring_vertex_with_tag(
        &domain,
        corner,
        BoundaryTag::Obstacle(1)
    ));
    // No vertex of the mesh is a hair away from the corner.
    assert!(
        mesh.vertices()
            .iter()
            .all(|&q| q == corner || (q - corner).norm() > 1e-6)
    );
}

#[test]
fn a_vertex_clearly_off_the_wall_is_left_where_it_is() {
    // 1e-6 is far above the snapping tolerance (1e-9 × the scene's size): a real, if narrow,
    // gap, meshed as such.
    let spec = fuzz_scene(1e-6);
    let (domain, mesh) = mesh_checked(&spec, area(&fuzz_obstacle(1e-6)));
    assert!(ring_vertex_with_tag(
        &domain,
        p(12.5, 1e-6),
        BoundaryTag::Obstacle(0)
    ));
    assert!(
        domain.free_rings()[0]
            .points
            .iter()
            .all(|q| q.y != 0.0 || q.x != 12.5)
    );
    // The gap under the corner is free space.
    assert!(mesh.locate(p(12.5, 5e-7), None).is_some());
}

#[test]
fn an_inflated_obstacle_a_rounding_error_off_the_shrunk_wall_meshes() {
    // With a robot radius, the inflated obstacle's bottom and the shrunk wall are both at
    // about y = 0.25 (each computed by a buffer).
    for d in [0.0, 1e-13] {
        let obstacle = vec![p(4.0, 0.5 + d), p(6.0, 0.5), p(6.0, 2.0), p(4.0, 2.0)];
        let spec = DomainSpec {
            workspace: rect(0.0, 0.0, 10.0, 10.0),
            obstacles: vec![Shape::Polygon(obstacle)],
            goals: vec![GoalShape::Point(p(8.0, 8.0))],
            robot_radius: 0.25,
        };
        let domain = Domain::new(&spec, &opts()).expect("valid scene");
        let (mesh, report) = domain.mesh(&opts()).expect("meshes");
        assert!(report.refinement_complete, "{report:?}");
        check_invariants_with_bridges(&mesh, domain.free_area(), 1e-9, report.bridges_remaining)
            .unwrap_or_else(|e| panic!("d = {d}: {e}"));
        assert!(mesh.quality().triangles < 10_000);
    }
}

mod random {
    //! Random scenes where obstacle corners land a rounding error away from a wall (straight
    //! or slanted) or from an earlier obstacle's edge: a typed input error or a valid mesh,
    //! never a triangulation failure.

    use super::common::check_invariants_with_bridges;
    use harmonic_fixtures::p;
    use harmonic_mesh::{Domain, DomainSpec, GoalShape, MeshError, MeshOptions, Point, Shape};
    use proptest::prelude::*;

    /// A triangle obstacle with its first corner `d` off the segment `ab` at parameter `t`
    /// (outwards from `ab`'s left side when `d` < 0), reaching `depth` into the left side.
    fn corner_near(a: Point, b: Point, t: f64, d: f64, depth: f64, width: f64) -> Vec<Point> {
        let u = (b - a).normalize();
        let n = p(-u.y, u.x) - p(0.0, 0.0);
        let c = a + (b - a) * t + n * d;
        vec![
            c,
            c + n * depth + u * width,
            c + n * depth - u * (0.7 * width),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        #[test]
        fn corners_a_rounding_error_off_other_boundaries_mesh(
            slant in 0.0..3.0f64,
            picks in proptest::collection::vec(
                (0usize..4, 0.1..0.9f64, prop_oneof![Just(0.0), Just(2e-16), Just(-3e-16),
                    Just(1e-13), Just(-1e-13), Just(1e-10), Just(-1e-10)],
                 0.5..2.0f64, 0.5..2.0f64),
                1..4),
        ) {
            // A workspace with a slanted bottom wall.
            let workspace = vec![p(0.0, 0.0), p(20.0, slant), p(20.0, 10.0), p(0.0, 10.0)];
            let mut obstacles: Vec<Vec<Point>> = Vec::new();
            for (i, &(side, t, d, depth, width)) in picks.iter().enumerate() {
                // Near a wall (sides 0..3 of the workspace, counter-clockwise so the inside is
                // on the left), or near the first edge of the previous obstacle (its outside
                // is on the right of a counter-clockwise ring: walk it backwards).
                let (a, b) = if i > 0 && side == 3 {
                    let prev = &obstacles[i - 1];
                    (prev[1], prev[0])
                } else {
                    (workspace[side], workspace[(side + 1) % 4])
                };
                obstacles.push(corner_near(a, b, t, d, depth, width));
            }
            let spec = DomainSpec {
                workspace,
                obstacles: obstacles.into_iter().map(Shape::Polygon).collect(),
                goals: vec![GoalShape::Point(p(10.0, 5.0))],
                robot_radius: 0.0,
            };
            let opts = MeshOptions { max_area: Some(0.3), ..MeshOptions::default() };
            let domain = match Domain::new(&spec, &opts) {
                Ok(d) => d,
                // The goal may end up inside an obstacle, an obstacle outside, etc.
                Err(MeshError::Triangulation(m)) => {
                    return Err(TestCaseError::fail(format!("domain: {m}")))
                }
                Err(_) => return Ok(()),
            };
            match domain.mesh(&opts) {
                Ok((mesh, report)) => {
                    check_invariants_with_bridges(
                        &mesh,
                        domain.free_area(),
                        1e-9,
                        report.bridges_remaining,
                    )
                    .map_err(TestCaseError::fail)?;
                }
                Err(e) => return Err(TestCaseError::fail(format!("{e}"))),
            }
        }
    }
}
