//! Property tests over random scenes: boxes and circles in a square, disjoint or overlapping,
//! some crossing the wall, with a point goal. Either a typed error or a valid mesh; never a panic.

mod common;

use common::*;
use harmonic_fixtures::{p, rect};
use harmonic_mesh::{
    BoundaryTag, Domain, DomainSpec, GoalShape, MeshError, MeshOptions, Point, Shape,
};
use proptest::prelude::*;

#[derive(Clone, Debug)]
enum Obs {
    Box(f64, f64, f64, f64),
    Circle(f64, f64, f64),
}

fn obstacle() -> impl Strategy<Value = Obs> {
    prop_oneof![
        (-0.5..9.5f64, -0.5..9.5f64, 0.2..2.5f64, 0.2..2.5f64)
            .prop_map(|(x, y, w, h)| Obs::Box(x, y, w, h)),
        (0.0..10.0f64, 0.0..10.0f64, 0.1..1.2f64).prop_map(|(x, y, r)| Obs::Circle(x, y, r)),
    ]
}

/// Whether edge ab lies on the boundary of the input shape `o` (for circles: on the chord
/// polygon, so within the sagitta of the circle).
fn on_shape(a: Point, b: Point, o: &Obs, h: f64) -> bool {
    match *o {
        Obs::Box(x, y, w, hh) => on_ring_edge(a, b, &rect(x, y, x + w, y + hh)),
        Obs::Circle(x, y, r) => {
            let c = p(x, y);
            let sag = h * h / (8.0 * r) + 1e-9;
            [a, b, a + (b - a) * 0.5]
                .iter()
                .all(|&q| (q - c).norm() <= r + 1e-9 && (q - c).norm() >= r - sag)
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, .. ProptestConfig::default() })]

    #[test]
    fn random_scene_meshes_are_valid(obs in prop::collection::vec(obstacle(), 1..9), gx in 0.2..9.8f64, gy in 0.2..9.8f64, prefill in any::<bool>(), halves in any::<bool>()) {
        let spec = DomainSpec {
            workspace: rect(0.0, 0.0, 10.0, 10.0),
            obstacles: obs.iter().map(|o| match *o {
                Obs::Box(x, y, w, h) => Shape::Polygon(rect(x, y, x + w, y + h)),
                Obs::Circle(x, y, r) => Shape::Circle { center: p(x, y), radius: r },
            }).collect(),
            goals: vec![GoalShape::Point(p(gx, gy))],
            robot_radius: 0.0,
        };
        // `halves`: made in two halves glued along a cut wherever one exists.
        let halves_from = if halves { 0 } else { usize::MAX };
        let opts = MeshOptions { max_area: Some(0.05), prefill, halves_from, ..MeshOptions::default() };
        let domain = match Domain::new(&spec, &opts) {
            Ok(d) => d,
            Err(e) => {
                // Only these are legitimate for such scenes.
                prop_assert!(matches!(e, MeshError::GoalInObstacle { .. } | MeshError::OutsideWorkspace { .. } | MeshError::NoFreeSpace { .. }), "{e}");
                return Ok(());
            }
        };
        let (mesh, report) = domain.mesh(&opts).expect("mesh of a valid domain");
        refined_or_budget_spent(&report, &opts).map_err(TestCaseError::fail)?;
        check_invariants_with_bridges(&mesh, domain.free_area(), 1e-9, report.bridges_remaining).map_err(TestCaseError::fail)?;
        let q = mesh.quality();
        prop_assert!(q.triangles > 0);
        prop_assert_eq!(q.non_delaunay_edges, 0);
        let h = domain.target_edge_length();
        for e in mesh.boundary_edges() {
            let [a, b] = e.vertices.map(|v| mesh.vertices()[v as usize]);
            let ok = match e.tag {
                BoundaryTag::Wall => on_shape(a, b, &Obs::Box(0.0, 0.0, 10.0, 10.0), h),
                BoundaryTag::Obstacle(i) => on_shape(a, b, &obs[i as usize], h),
                BoundaryTag::Goal(0) => {
                    let d = (a - p(gx, gy)).norm();
                    d <= 2.0 * h + 1e-9
                }
                BoundaryTag::Goal(_) => false,
            };
            prop_assert!(ok, "{} edge {} {}", e.tag, a, b);
        }
        // Centroids are located in their own triangle and are in free space.
        for t in (0..mesh.triangles().len() as u32).step_by(7) {
            let [a, b, c] = mesh.triangle_points(t);
            let g = Point::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0);
            prop_assert_eq!(mesh.locate(g, Some(0)), Some(t));
            prop_assert!(domain.contains_free(g));
        }
    }
}
