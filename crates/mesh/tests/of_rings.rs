//! `Domain::of_rings`: free space given as rings. Random boxes as holes in a room, some
//! overlapping each other or the wall, some nested: either a typed error naming the rings
//! that meet or nest, or a domain whose mesh covers the room less the holes and the goal.

mod common;

use common::refined_or_budget_spent;
use harmonic_fixtures::rect;
use harmonic_mesh::{BoundaryTag, Domain, GoalShape, MeshError, MeshOptions, Part, Point};
use proptest::prelude::*;

/// Whether the holes lie inside the room and no two of them meet (by their boxes).
fn disjoint(room: &[Point], holes: &[Vec<Point>]) -> bool {
    let bbox = |r: &[Point]| {
        let (mut lo, mut hi) = (r[0], r[0]);
        for p in r {
            lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        (lo, hi)
    };
    let (rlo, rhi) = bbox(room);
    let boxes: Vec<_> = holes.iter().map(|h| bbox(h)).collect();
    boxes
        .iter()
        .all(|(lo, hi)| lo.x > rlo.x && lo.y > rlo.y && hi.x < rhi.x && hi.y < rhi.y)
        && boxes.iter().enumerate().all(|(i, a)| {
            boxes
                .iter()
                .skip(i + 1)
                .all(|b| a.1.x < b.0.x || b.1.x < a.0.x || a.1.y < b.0.y || b.1.y < a.0.y)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn random_rings_give_a_mesh_or_a_typed_error(
        boxes in proptest::collection::vec(
            (-0.5..9.5f64, -0.5..9.5f64, 0.1..3.0f64, 0.1..3.0f64), 0..8),
        goal in (0.2..9.8f64, 0.2..9.8f64),
    ) {
        let room = rect(0.0, 0.0, 10.0, 10.0);
        let holes: Vec<Vec<Point>> = boxes.iter().map(|&(x, y, w, h)| rect(x, y, x + w, y + h)).collect();
        let opts = MeshOptions { max_area: Some(0.2), ..MeshOptions::default() };
        let goals = [GoalShape::Point(Point::new(goal.0, goal.1))];
        match Domain::of_rings(&room, &holes, &goals, &opts) {
            Err(e) => {
                prop_assert!(
                    matches!(
                        e,
                        MeshError::RingsMeet { .. }
                            | MeshError::HoleInHole { .. }
                            | MeshError::OutsideWorkspace { part: Part::Obstacle(_) }
                            | MeshError::GoalNotInFreeSpace { .. }
                    ),
                    "unexpected error: {e}"
                );
                // Disjoint holes inside the room fail only on the goal.
                if disjoint(&room, &holes) {
                    prop_assert!(matches!(e, MeshError::GoalNotInFreeSpace { .. }), "{e}");
                }
            }
            Ok(domain) => {
                prop_assert!(disjoint(&room, &holes), "meeting rings were taken");
                let holes_area: f64 = boxes.iter().map(|b| b.2 * b.3).sum();
                // The room less the holes, less the goal's disc (of radius at most twice the
                // target edge).
                let free = 100.0 - holes_area;
                let disc = std::f64::consts::PI * (2.0 * domain.target_edge_length()).powi(2);
                let area = domain.free_area();
                prop_assert!(area < free && area > free - disc, "{area} vs {free}");
                let (mesh, report) = domain.mesh(&opts).expect("a valid domain meshes");
                refined_or_budget_spent(&report, &opts).map_err(TestCaseError::fail)?;
                let q = mesh.quality();
                prop_assert!((q.area - area).abs() <= 1e-9 * free, "{} vs {area}", q.area);
                prop_assert_eq!(q.non_delaunay_edges, 0);
                prop_assert!(mesh.boundary_edges().iter().any(|e| e.tag == BoundaryTag::Goal(0)));
            }
        }
    }
}
