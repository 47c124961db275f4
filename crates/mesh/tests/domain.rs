//! Input validation (one test per error), merging with tag preservation, cutting at the
//! workspace boundary, robot radius, and clearance queries.

mod common;

use common::*;
use harmonic_fixtures::{p, rect, reference_disc};
use harmonic_mesh::{
    BoundaryTag, Bridges, Domain, DomainSpec, GoalShape, MeshError, MeshOptions, Part, Point, Shape,
};

fn square_with(obstacles: Vec<Shape>, goals: Vec<GoalShape>) -> DomainSpec {
    DomainSpec {
        workspace: rect(0.0, 0.0, 10.0, 10.0),
        obstacles,
        goals,
        robot_radius: 0.0,
    }
}

fn goal() -> Vec<GoalShape> {
    vec![GoalShape::Polygon(rect(8.0, 8.0, 9.0, 9.0))]
}

fn opts() -> MeshOptions {
    MeshOptions {
        max_area: Some(0.05),
        ..MeshOptions::default()
    }
}

fn err(spec: &DomainSpec) -> MeshError {
    Domain::new(spec, &opts()).expect_err("input must be rejected")
}

#[test]
fn self_intersection_names_obstacle_and_edges() {
    let bow = vec![
        p(4.0, 4.0),
        p(5.0, 4.0),
        p(5.0, 5.0),
        p(6.0, 5.0),
        p(6.0, 6.0),
        p(4.5, 3.0),
    ];
    let spec = square_with(
        vec![
            Shape::Polygon(rect(1.0, 1.0, 2.0, 2.0)),
            Shape::Polygon(rect(1.0, 5.0, 2.0, 6.0)),
            Shape::Polygon(rect(5.0, 7.0, 6.0, 7.5)),
            Shape::Polygon(bow),
        ],
        goal(),
    );
    let e = err(&spec);
    assert_eq!(
        e,
        MeshError::SelfIntersection {
            part: Part::Obstacle(3),
            edges: (0, 4)
        }
    );
    assert_eq!(
        e.to_string(),
        "obstacle 3: polygon self-intersects (edges 0 and 4)"
    );
    // A bow tie: edges 0 and 2 cross.
    let bow_tie = vec![p(4.0, 4.0), p(6.0, 6.0), p(6.0, 4.0), p(4.0, 6.0)];
    let e = err(&square_with(vec![Shape::Polygon(bow_tie)], goal()));
    assert_eq!(
        e.to_string(),
        "obstacle 0: polygon self-intersects (edges 0 and 2)"
    );
}

#[test]
fn each_invalid_input_has_its_error() {
    let nan = square_with(
        vec![Shape::Polygon(vec![
            p(1.0, 1.0),
            p(f64::NAN, 1.0),
            p(2.0, 2.0),
        ])],
        goal(),
    );
    assert_eq!(
        err(&nan),
        MeshError::NonFinite {
            part: Part::Obstacle(0),
            vertex: 1
        }
    );
    let inf_ws = DomainSpec {
        workspace: vec![p(0.0, 0.0), p(f64::INFINITY, 0.0), p(1.0, 1.0)],
        ..square_with(vec![], goal())
    };
    assert_eq!(
        err(&inf_ws),
        MeshError::NonFinite {
            part: Part::Workspace,
            vertex: 1
        }
    );
    let two = square_with(
        vec![],
        vec![GoalShape::Polygon(vec![
            p(1.0, 1.0),
            p(2.0, 2.0),
            p(1.0, 1.0),
        ])],
    );
    assert_eq!(
        err(&two),
        MeshError::TooFewVertices {
            part: Part::Goal(0),
            count: 2
        }
    );
    let flat = square_with(
        vec![Shape::Polygon(vec![p(1.0, 1.0), p(2.0, 2.0), p(3.0, 3.0)])],
        goal(),
    );
    assert_eq!(
        err(&flat),
        MeshError::ZeroArea {
            part: Part::Obstacle(0)
        }
    );
    let outside = square_with(
        vec![
            Shape::Polygon(rect(1.0, 1.0, 2.0, 2.0)),
            Shape::Polygon(rect(11.0, 1.0, 12.0, 2.0)),
        ],
        goal(),
    );
    assert_eq!(
        err(&outside),
        MeshError::OutsideWorkspace {
            part: Part::Obstacle(1)
        }
    );
    let goal_out = square_with(
        vec![],
        vec![
            GoalShape::Point(p(1.0, 1.0)),
            GoalShape::Circle {
                center: p(20.0, 1.0),
                radius: 1.0,
            },
        ],
    );
    assert_eq!(
        err(&goal_out),
        MeshError::OutsideWorkspace {
            part: Part::Goal(1)
        }
    );
    let in_obstacle = square_with(
        vec![
            Shape::Polygon(rect(1.0, 1.0, 2.0, 2.0)),
            Shape::Polygon(rect(5.0, 5.0, 8.0, 8.0)),
        ],
        vec![GoalShape::Circle {
            center: p(6.0, 6.0),
            radius: 0.5,
        }],
    );
    assert_eq!(
        err(&in_obstacle),
        MeshError::GoalInObstacle {
            goal: 0,
            obstacle: 1
        }
    );
    let bad_radius = square_with(
        vec![Shape::Circle {
            center: p(5.0, 5.0),
            radius: -1.0,
        }],
        goal(),
    );
    assert_eq!(
        err(&bad_radius),
        MeshError::InvalidRadius {
            part: Part::Obstacle(0),
            radius: -1.0
        }
    );
    let bad_robot = DomainSpec {
        robot_radius: f64::NAN,
        ..square_with(vec![], goal())
    };
    assert!(matches!(err(&bad_robot), MeshError::InvalidRobotRadius(r) if r.is_nan()));
    let huge_robot = DomainSpec {
        robot_radius: 6.0,
        ..square_with(vec![], goal())
    };
    assert_eq!(
        err(&huge_robot),
        MeshError::NoFreeSpace { robot_radius: 6.0 }
    );
    let covered = square_with(vec![Shape::Polygon(rect(-1.0, -1.0, 11.0, 11.0))], vec![]);
    assert_eq!(err(&covered), MeshError::NoFreeSpace { robot_radius: 0.0 });
    // The goal sits in a gap of 0.4 between two obstacles: a robot of radius 0.3 cannot get there.
    let gap = DomainSpec {
        robot_radius: 0.3,
        ..square_with(
            vec![
                Shape::Polygon(rect(0.0, 4.0, 10.0, 4.8)),
                Shape::Polygon(rect(0.0, 5.2, 10.0, 6.0)),
            ],
            vec![GoalShape::Point(p(5.0, 5.0))],
        )
    };
    assert_eq!(
        err(&gap),
        MeshError::GoalNotInFreeSpace {
            goal: 0,
            robot_radius: 0.3
        }
    );
    let sharp = MeshOptions {
        min_angle_deg: 34.0,
        ..opts()
    };
    assert!(matches!(
        Domain::new(&square_with(vec![], goal()), &sharp),
        Err(MeshError::InvalidOption {
            name: "min_angle_deg",
            ..
        })
    ));
    let neg_area = MeshOptions {
        max_area: Some(-1.0),
        ..opts()
    };
    assert!(matches!(
        Domain::new(&square_with(vec![], goal()), &neg_area),
        Err(MeshError::InvalidOption {
            name: "max_area",
            ..
        })
    ));
    // The budget is checked before any work is done.
    let d = Domain::new(&square_with(vec![], goal()), &opts()).unwrap();
    let tiny = MeshOptions {
        max_area: Some(1e-9),
        ..opts()
    };
    assert!(matches!(
        d.mesh(&tiny),
        Err(MeshError::TooManyTriangles {
            limit: 20_000_000,
            ..
        })
    ));
}

#[test]
fn merged_obstacles_keep_their_input_tags() {
    let o0 = rect(2.0, 2.0, 5.0, 4.0);
    let o1 = rect(4.0, 3.0, 6.0, 6.0); // overlaps o0
    let o2 = rect(5.0, 6.0, 7.0, 7.0); // touches o1 along y = 6 (x in 5..6)
    let o3 = rect(8.0, -1.0, 11.0, 2.0); // crosses the workspace corner
    let o4 = rect(2.0, 2.0, 5.0, 3.0); // inside o0 except the shared edges: hidden
    let spec = square_with(
        vec![
            Shape::Polygon(o0.clone()),
            Shape::Polygon(o1.clone()),
            Shape::Polygon(o2.clone()),
            Shape::Polygon(o3.clone()),
            Shape::Polygon(o4),
        ],
        vec![GoalShape::Polygon(rect(1.0, 8.0, 2.0, 9.0))],
    );
    let domain = Domain::new(&spec, &opts()).unwrap();
    // Exact area: 100 − (6 + 6 − 1) − 2 − 4 − goal 1.
    let exact = 100.0 - 11.0 - 2.0 - 4.0 - 1.0;
    assert!(
        (domain.free_area() - exact).abs() < 1e-12 * exact,
        "{}",
        domain.free_area()
    );
    assert_eq!(domain.obstacle_polygons().len(), 2);
    let merged = domain
        .obstacle_polygons()
        .iter()
        .find(|r| r.sources.len() > 1)
        .unwrap();
    assert_eq!(merged.sources, vec![0, 1, 2, 4]);
    let (mesh, report) = domain.mesh(&opts()).unwrap();
    assert!(report.refinement_complete);
    check_invariants(&mesh, exact, 1e-9).unwrap();
    let q = mesh.quality();
    assert_eq!((q.holes, q.components), (2, 1));
    let mut seen = std::collections::BTreeSet::new();
    for e in mesh.boundary_edges() {
        let [a, b] = e.vertices.map(|v| mesh.vertices()[v as usize]);
        seen.insert(e.tag);
        let ok = match e.tag {
            BoundaryTag::Wall => on_ring_edge(a, b, &spec.workspace),
            BoundaryTag::Obstacle(0) => on_ring_edge(a, b, &o0),
            BoundaryTag::Obstacle(1) => on_ring_edge(a, b, &o1),
            BoundaryTag::Obstacle(2) => on_ring_edge(a, b, &o2),
            BoundaryTag::Obstacle(3) => on_ring_edge(a, b, &o3),
            BoundaryTag::Goal(0) => on_ring_edge(a, b, &rect(1.0, 8.0, 2.0, 9.0)),
            t => panic!("unexpected tag {t}"),
        };
        assert!(ok, "{} edge {a} {b}", e.tag);
        // The edge of o0 at y = 2 is shared with the hidden o4: the lower index wins.
        assert_ne!(e.tag, BoundaryTag::Obstacle(4));
    }
    let expected: std::collections::BTreeSet<BoundaryTag> = [
        BoundaryTag::Wall,
        BoundaryTag::Obstacle(0),
        BoundaryTag::Obstacle(1),
        BoundaryTag::Obstacle(2),
        BoundaryTag::Obstacle(3),
        BoundaryTag::Goal(0),
    ]
    .into();
    assert_eq!(seen, expected);
    // The cut corner: edges along x = 8 (y in 0..2) and y = 2 (x in 8..10) belong to obstacle 3.
    let corner = mesh
        .boundary_edges()
        .iter()
        .filter(|e| e.tag == BoundaryTag::Obstacle(3))
        .count();
    assert!(corner >= 2);
}

#[test]
fn nested_obstacle_inside_a_ring_obstacle() {
    // A square ring obstacle (outer CCW, inner hole as a separate reversed polygon is not
    // allowed, so build the ring from two U shapes) with an island of free space inside.
    let left = vec![
        p(2.0, 2.0),
        p(5.0, 2.0),
        p(5.0, 3.0),
        p(3.0, 3.0),
        p(3.0, 7.0),
        p(5.0, 7.0),
        p(5.0, 8.0),
        p(2.0, 8.0),
    ];
    let right = vec![
        p(5.0, 2.0),
        p(8.0, 2.0),
        p(8.0, 8.0),
        p(5.0, 8.0),
        p(5.0, 7.0),
        p(7.0, 7.0),
        p(7.0, 3.0),
        p(5.0, 3.0),
    ];
    let spec = square_with(
        vec![
            Shape::Polygon(left),
            Shape::Polygon(right),
            Shape::Polygon(rect(4.5, 4.5, 5.5, 5.5)),
        ],
        vec![GoalShape::Polygon(rect(0.5, 0.5, 1.0, 1.0))],
    );
    let domain = Domain::new(&spec, &opts()).unwrap();
    let exact = 100.0 - 36.0 + 16.0 - 1.0 - 0.25;
    assert!((domain.free_area() - exact).abs() < 1e-12 * exact);
    let (mesh, _) = domain.mesh(&opts()).unwrap();
    check_invariants(&mesh, exact, 1e-9).unwrap();
    let q = mesh.quality();
    // Outer component (holes: the ring, the goal) and the island (hole: the small square).
    assert_eq!((q.components, q.holes), (2, 3), "{q:?}");
    assert!(domain.contains_free(p(4.0, 4.0)));
    assert!(!domain.contains_free(p(5.0, 5.0)));
    assert!(!domain.contains_free(p(2.5, 5.0)));
}

#[test]
fn robot_radius_inflates_obstacles_and_shrinks_walls() {
    let spec = DomainSpec {
        robot_radius: 0.25,
        ..square_with(
            vec![
                Shape::Polygon(rect(4.0, 4.0, 6.0, 6.0)),
                Shape::Circle {
                    center: p(2.0, 7.0),
                    radius: 0.5,
                },
            ],
            goal(),
        )
    };
    let domain = Domain::new(&spec, &opts()).unwrap();
    // Inflated square: 2x2 + 4·2·0.25 + π·0.25² (round corners, within chord error).
    let square = 4.0 + 2.0 + std::f64::consts::PI * 0.0625;
    // The disc is meshed as a regular n-gon with chords at most the target edge length.
    let n = (std::f64::consts::TAU * 0.75 / domain.target_edge_length())
        .ceil()
        .max(12.0);
    let disc = 0.5 * n * 0.75f64.powi(2) * (std::f64::consts::TAU / n).sin();
    let exact = 9.5 * 9.5 - square - disc - 1.0;
    assert!(
        (domain.free_area() - exact).abs() < 0.02,
        "{} vs {exact}",
        domain.free_area()
    );
    assert!(!domain.contains_free(p(0.1, 5.0)));
    assert!(!domain.contains_free(p(3.8, 5.0)));
    assert!(domain.contains_free(p(3.7, 5.0)));
    let (mesh, _) = domain.mesh(&opts()).unwrap();
    check_invariants(&mesh, domain.free_area(), 1e-9).unwrap();
    // Walls are tagged on the shrunk workspace, the inflated obstacles by their input index.
    for e in mesh.boundary_edges() {
        let [a, b] = e.vertices.map(|v| mesh.vertices()[v as usize]);
        let m = Point::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
        match e.tag {
            BoundaryTag::Wall => assert!(
                (m.x - 0.25).abs() < 1e-6
                    || (m.x - 9.75).abs() < 1e-6
                    || (m.y - 0.25).abs() < 1e-6
                    || (m.y - 9.75).abs() < 1e-6
            ),
            BoundaryTag::Obstacle(0) => assert!(m.x > 3.7 && m.x < 6.3 && m.y > 3.7 && m.y < 6.3),
            BoundaryTag::Obstacle(1) => assert!(((m - p(2.0, 7.0)).norm() - 0.75).abs() < 0.03),
            BoundaryTag::Goal(0) => {}
            t => panic!("{t}"),
        }
    }
}

#[test]
fn clearance_is_exact() {
    let domain = Domain::new(&reference_disc(), &opts()).unwrap();
    assert!((domain.distance_to_obstacles(p(1.0, 9.0)) - 1.0).abs() < 1e-12);
    assert!((domain.distance_to_obstacles(p(3.5, 5.0)) - 0.5).abs() < 1e-12);
    // The goal boundary does not count: (8.5, 1.8) is 0.15 from the goal, but 1.5 from the
    // right wall and the L-shaped obstacle.
    let d = domain.distance_to_obstacles(p(8.5, 1.8));
    assert!((d - 1.5).abs() < 1e-12, "{d}");
    assert_eq!(domain.segment_clearance(p(1.0, 5.0), p(4.0, 5.0)), 0.0);
    assert!((domain.segment_clearance(p(1.0, 1.0), p(1.0, 9.0)) - 1.0).abs() < 1e-12);
    assert!((domain.segment_clearance(p(2.5, 1.2), p(2.5, 1.7)) - 0.3).abs() < 1e-12);
    // Nearest feature is a corner: (3.5, 1.5) to (3, 2).
    let d = domain.segment_clearance(p(3.5, 1.0), p(3.5, 1.5));
    assert!((d - 0.5f64.sqrt()).abs() < 1e-12, "{d}");
    assert!(domain.contains_free(p(1.0, 1.0)));
    assert!(domain.contains_free(p(0.0, 5.0))); // on the wall: closed
    assert!(!domain.contains_free(p(2.5, 5.0)));
    assert!(!domain.contains_free(p(8.5, 1.5))); // inside the goal
    assert!(!domain.contains_free(p(-1.0, 5.0)));
}

/// Both ways of splitting bridges keep unknowns in a door narrower than the target edge:
/// refined again (every angle bound kept), or the midpoints kept as they are (fewer
/// vertices, angles down to about half the bound next to them); without splitting the door
/// is sealed.
#[test]
fn narrow_door_keeps_unknowns_across_it() {
    // A wall with a door 0.1 wide, a third of the target edge length (0.34).
    let spec = square_with(
        vec![
            Shape::Polygon(rect(0.0, 4.9, 4.95, 5.1)),
            Shape::Polygon(rect(5.05, 4.9, 10.0, 5.1)),
        ],
        vec![GoalShape::Point(p(5.0, 9.0))],
    );
    let domain = Domain::new(&spec, &opts()).unwrap();
    let mut vertices = Vec::new();
    for bridges in [Bridges::Refined, Bridges::Midpoints, Bridges::Kept] {
        let opts = MeshOptions { bridges, ..opts() };
        let (mesh, report) = domain.mesh(&opts).unwrap();
        check_invariants_with_bridges(&mesh, domain.free_area(), 1e-9, report.bridges_remaining)
            .unwrap();
        // Vertices strictly inside the door carry unknowns (are not on the boundary).
        let inside_door = mesh
            .vertices()
            .iter()
            .zip(mesh.vertex_tags())
            .filter(|(v, t)| t.is_none() && v.x > 4.95 && v.x < 5.05 && v.y > 4.9 && v.y < 5.1)
            .count();
        let min_angle = mesh.quality().min_angle_deg;
        match bridges {
            Bridges::Kept => {
                assert_eq!(report.bridges_split, 0);
                assert!(report.bridges_remaining > 0);
                assert_eq!(inside_door, 0, "the door is sealed");
            }
            _ => {
                assert!(report.bridges_split > 0);
                assert_eq!(report.bridges_remaining, 0);
                assert!(inside_door > 0, "{bridges:?}");
                let bound = if bridges == Bridges::Refined {
                    30.0
                } else {
                    15.0
                };
                assert!(min_angle >= bound - 1e-9, "{bridges:?}: {min_angle}°");
            }
        }
        // The door is a passage: one component.
        assert_eq!(mesh.component_count(), 1);
        vertices.push(mesh.vertices().len());
    }
    assert!(vertices[1] < vertices[0], "{vertices:?}");
}

#[test]
fn obstacles_touching_at_a_corner_and_along_the_wall() {
    // Two boxes meeting at one corner (a pinch vertex of free space), a box flush with the
    // wall (its wall-side edge disappears) and a triangle touching the wall at one vertex.
    let spec = square_with(
        vec![
            Shape::Polygon(rect(2.0, 2.0, 3.0, 3.0)),
            Shape::Polygon(rect(3.0, 3.0, 4.0, 4.0)),
            Shape::Polygon(rect(0.0, 6.0, 1.0, 7.0)),
            Shape::Polygon(vec![p(6.0, 0.0), p(7.0, 1.0), p(5.0, 1.0)]),
        ],
        goal(),
    );
    let domain = Domain::new(&spec, &opts()).unwrap();
    let exact = 100.0 - 1.0 - 1.0 - 1.0 - 1.0 - 1.0;
    assert!(
        (domain.free_area() - exact).abs() < 1e-12 * exact,
        "{}",
        domain.free_area()
    );
    let (mesh, report) = domain.mesh(&opts()).unwrap();
    assert!(report.refinement_complete);
    check_invariants_with_bridges(&mesh, exact, 1e-9, report.bridges_remaining).unwrap();
    assert_eq!(mesh.component_count(), 1);
    let q = mesh.quality();
    // Pinches at (3, 3) and (6, 0); holes: the two boxes (one figure-eight loop) and the goal.
    assert_eq!((q.pinch_vertices, q.holes), (2, 2), "{q:?}");
    for e in mesh.boundary_edges() {
        let [a, b] = e.vertices.map(|v| mesh.vertices()[v as usize]);
        let m = Point::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
        if m.x < 1e-9 && m.y > 6.0 && m.y < 7.0 {
            panic!("the flush box's wall edge is not free boundary: {m}");
        }
        if m.x > 1e-9 && m.x < 1.0 - 1e-9 && (m.y - 6.0).abs() < 1e-9 {
            assert_eq!(e.tag, BoundaryTag::Obstacle(2));
        }
    }
}

#[test]
fn obstacles_that_touch_nothing_are_holes_as_they_are_and_the_others_still_merge() {
    // An L-shaped workspace: [0, 10]² less [6, 10] × [6, 10].
    let workspace = vec![
        p(0.0, 0.0),
        p(10.0, 0.0),
        p(10.0, 6.0),
        p(6.0, 6.0),
        p(6.0, 10.0),
        p(0.0, 10.0),
    ];
    let alone = [rect(1.0, 1.0, 2.0, 2.0), rect(3.0, 1.0, 4.0, 2.0)];
    // A rounding error apart: snapped together and merged, not taken as they are.
    let near = [rect(1.0, 3.0, 2.0, 4.0), rect(2.0 + 1e-12, 3.0, 3.0, 4.0)];
    let overlapping = [rect(1.0, 6.0, 3.0, 7.0), rect(2.0, 6.5, 4.0, 8.0)];
    // Across the inner corner of the L: cut at the walls.
    let across = rect(5.0, 5.0, 7.0, 7.0);
    // Next to the goal, a rounding error off it.
    let by_goal = rect(8.0, 2.0 + 1e-13, 9.0, 3.0);
    let goal = rect(8.0, 1.0, 9.0, 2.0);
    let obstacles: Vec<Shape> = alone
        .iter()
        .chain(&near)
        .chain(&overlapping)
        .chain([&across, &by_goal])
        .map(|r| Shape::Polygon(r.clone()))
        .collect();
    let spec = DomainSpec {
        workspace: workspace.clone(),
        obstacles,
        goals: vec![GoalShape::Polygon(goal.clone())],
        robot_radius: 0.0,
    };
    let domain = Domain::new(&spec, &opts()).unwrap();
    // 84 − 1 − 1 − 2 − (2 + 3 − 0.5) − 3 (the part of `across` in the L) − 1 − goal 1.
    let exact = 84.0 - 2.0 - 2.0 - 4.5 - 3.0 - 1.0 - 1.0;
    assert!(
        (domain.free_area() - exact).abs() < 1e-9,
        "{}",
        domain.free_area()
    );
    let mut sources: Vec<Vec<u32>> = domain
        .obstacle_polygons()
        .iter()
        .map(|r| r.sources.clone())
        .collect();
    sources.sort();
    assert_eq!(
        sources,
        vec![vec![0], vec![1], vec![2, 3], vec![4, 5], vec![6], vec![7]]
    );
    for (i, ring) in alone.iter().enumerate() {
        let region = domain
            .obstacle_polygons()
            .iter()
            .find(|r| r.sources == [i as u32])
            .unwrap();
        assert_eq!(region.exterior.len(), 4);
        assert!(region.exterior.iter().all(|&q| on_ring_edge(q, q, ring)));
    }
    let (mesh, report) = domain.mesh(&opts()).unwrap();
    assert!(report.refinement_complete);
    check_invariants(&mesh, exact, 1e-9).unwrap();
    let q = mesh.quality();
    // Holes: the two alone, the merged pair, the overlapping pair, and the goal with
    // `by_goal` snapped onto it (`across` notches the walls).
    assert_eq!((q.components, q.holes), (1, 5), "{q:?}");
    let rings = [
        &alone[..],
        &near,
        &overlapping,
        &[across.clone(), by_goal.clone()],
    ]
    .concat();
    for e in mesh.boundary_edges() {
        let [a, b] = e.vertices.map(|v| mesh.vertices()[v as usize]);
        let ok = match e.tag {
            BoundaryTag::Wall => on_ring_edge(a, b, &workspace),
            BoundaryTag::Obstacle(i) => on_ring_edge(a, b, &rings[i as usize]),
            BoundaryTag::Goal(0) => on_ring_edge(a, b, &goal),
            t => panic!("unexpected tag {t}"),
        };
        assert!(ok, "{} edge {a} {b}", e.tag);
    }
    assert!(!domain.contains_free(p(1.5, 1.5)));
    assert!(domain.contains_free(p(2.5, 1.5)));
    assert!((domain.distance_to_obstacles(p(2.5, 1.5)) - 0.5).abs() < 1e-12);
}

proptest::proptest! {
    /// A polyline's clearance is the smallest of its segments' (the pruned search finds the
    /// same minimum, to the bit), on random walks across the reference domain, inside and
    /// outside free space, with steps from a millimetre to across the scene.
    #[test]
    fn polyline_clearance_is_the_smallest_segment_clearance(
        start in (0.0f64..10.0, 0.0f64..10.0),
        steps in proptest::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -4.0f64..1.0), 0..40),
    ) {
        let domain = Domain::new(&reference_disc(), &opts()).unwrap();
        let mut points = vec![p(start.0, start.1)];
        for (dx, dy, scale) in steps {
            let last = points[points.len() - 1];
            let s = 10f64.powf(scale);
            points.push(p(last.x + s * dx, last.y + s * dy));
        }
        let expected = match points.as_slice() {
            [only] => domain.segment_clearance(*only, *only),
            _ => points
                .windows(2)
                .map(|w| domain.segment_clearance(w[0], w[1]))
                .fold(f64::INFINITY, f64::min),
        };
        proptest::prop_assert_eq!(domain.polyline_clearance(&points), expected);
    }
}

#[test]
fn polyline_clearance_of_nothing_and_of_non_finite_points() {
    let domain = Domain::new(&reference_disc(), &opts()).unwrap();
    assert_eq!(domain.polyline_clearance(&[]), f64::INFINITY);
    assert!(
        domain
            .polyline_clearance(&[p(1.0, 1.0), p(f64::NAN, 1.0)])
            .is_nan()
    );
}
