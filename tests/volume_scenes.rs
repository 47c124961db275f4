//! The bundled volume scenes parse with the scene contract's type, and the two small ones are
//! planned end to end: every start reaches the goal with both tracers, with no interior
//! extremum, in a maze whose far field falls to |∇φ| ≈ 1e-30.

use std::sync::Arc;

use harmonic_fem::volume::solve_volume_potential_with_report;
use harmonic_planner::scene::VolumeScene;
use harmonic_trajectory::volume::{ExactVolumeOptions, P1VolumeField, trace_exact_volume};
use harmonic_trajectory::{Locate, SmoothOptions, trace_smooth};
use harmonic_volume::{MeshOptions, Point, PointClass};

fn scene(name: &str) -> VolumeScene {
    let path = format!("{}/meshes/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn bundled_volume_scenes_parse_and_build() {
    for name in ["torus3d", "maze3d", "me766_3d"] {
        let spec = scene(name);
        let domain = spec.build().unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!spec.start_points().is_empty(), "{name}");
        let v = spec.max_volume(&domain).unwrap();
        assert!(v > 0.0, "{name}");
        for s in spec.start_points() {
            assert_eq!(
                domain.classify(&s, 0.01),
                PointClass::Free,
                "{name}: start {s}"
            );
        }
    }
}

#[test]
fn torus_and_maze_are_planned() {
    for name in ["torus3d", "maze3d"] {
        let spec = scene(name);
        let domain = spec.build().unwrap();
        let (mesh, report) = domain
            .mesh(&MeshOptions::with_max_volume(
                spec.max_volume(&domain).unwrap(),
            ))
            .unwrap();
        let mesh = Arc::new(mesh);
        let bcs = spec.conditions();
        let (potential, _, _) =
            solve_volume_potential_with_report(Arc::clone(&mesh), &bcs).unwrap();
        assert_eq!(potential.interior_local_extrema(), 0, "{name}");
        let r = report.point_goal_radius;
        let classify = |p: &Point| match domain.classify(p, r) {
            PointClass::Free => Locate::Inside(0),
            PointClass::Goal(j) => Locate::Goal(j),
            PointClass::Obstacle(_) => Locate::InObstacle,
            PointClass::OutsideWorkspace => Locate::OutsideWorkspace,
        };
        let field = P1VolumeField::ascending(&mesh, potential.psi())
            .unwrap()
            .with_outside(&classify);
        for s in spec.start_points() {
            let exact = trace_exact_volume(&field, s, &ExactVolumeOptions::default());
            assert!(
                exact.status.reached_goal(),
                "{name} from {s}: {:?}",
                exact.status
            );
            let smooth = trace_smooth(&field, s, &SmoothOptions::for_scale(10.0)).unwrap();
            assert!(
                smooth.status.reached_goal(),
                "{name} from {s}: {:?}",
                smooth.status
            );
            println!(
                "{name} from {s}: exact {:.3}, smooth {:.3}, min |∇| {:.2e}",
                exact.length, smooth.length, exact.min_gradient
            );
        }
    }
}
