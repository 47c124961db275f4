//! Planning on a uniformly refined mesh solved by multigrid (`PlannerOptions::multigrid`):
//! the same paths as the direct solve to a fraction of a percent, and a clear refusal where
//! it does not apply.

use harmonic_planner::{PlanError, Planner, PlannerOptions, Scene, Workspace};

fn reference(max_area: f64) -> Scene {
    let mut scene = Scene::from_file(harmonic_fixtures::mesh_file("reference.json")).unwrap();
    scene.mesh.max_area = Some(max_area);
    scene
}

fn multigrid(k: usize) -> PlannerOptions {
    PlannerOptions {
        multigrid: Some(k),
        ..PlannerOptions::default()
    }
}

/// Every start of `scene` reaches the goal on both planners, with clearance, along paths
/// whose lengths agree to 0.5 %.
fn same_paths(scene: &Scene, direct: &Planner, other: &Planner) {
    assert!(!scene.starts.is_empty());
    for &start in &scene.starts {
        let (a, b) = (direct.plan(start), other.plan(start));
        assert!(
            a.status.reached_goal() && b.status.reached_goal(),
            "{start:?}"
        );
        assert!(b.min_clearance > 0.0, "{start:?}: {}", b.min_clearance);
        let relative = (a.length - b.length).abs() / a.length;
        assert!(
            relative <= 5e-3,
            "start {start:?}: {} vs {} m",
            a.length,
            b.length
        );
    }
}

#[test]
fn multigrid_paths_match_the_direct_ones() {
    let scene = reference(0.004);
    let direct = Planner::new(&scene).unwrap();
    let refined = Planner::with_options(&scene, &multigrid(2)).unwrap();
    // Sixteen times the coarse mesh: close to the direct mesh's size.
    let (n_direct, n_refined) = (
        direct.mesh().triangles().len() as f64,
        refined.mesh().triangles().len() as f64,
    );
    assert!(
        (0.7..1.3).contains(&(n_refined / n_direct)),
        "{n_refined} vs {n_direct} triangles"
    );
    assert_eq!(refined.mesh().quality().non_delaunay_edges, 0);
    same_paths(&scene, &direct, &refined);
}

#[test]
fn multigrid_is_refused_where_there_is_no_scene_mesh_to_refine() {
    let scene = reference(0.05);
    let mesh = Planner::new(&scene).unwrap().mesh().clone();
    let err = Planner::from_mesh(mesh, &multigrid(1)).unwrap_err();
    assert!(
        matches!(err, PlanError::MultigridUnsupported { .. }),
        "{err}"
    );
    let err = Workspace::with_options(&scene, &multigrid(1)).unwrap_err();
    assert!(
        matches!(err, PlanError::MultigridUnsupported { .. }),
        "{err}"
    );
    // Zero refinements is the direct solve.
    assert!(Planner::with_options(&scene, &multigrid(0)).is_ok());
}

/// From `AUTO_MULTIGRID_FROM` estimated triangles a planner with default options takes the
/// multigrid route, checked; below it, and with `multigrid: Some(0)`, the direct solve on
/// the scene's own mesh. The two paths agree to 0.5 %.
#[test]
fn large_scenes_take_the_multigrid_route_by_default() {
    let scene = reference(0.001);
    let auto = Planner::new(&scene).unwrap();
    let direct = Planner::with_options(&scene, &multigrid(0)).unwrap();
    assert!(
        auto.mesh().triangles().len() >= harmonic_planner::AUTO_MULTIGRID_FROM,
        "{} triangles",
        auto.mesh().triangles().len()
    );
    assert_eq!(
        auto.solved_by(),
        "multigrid (checked: no interior extremum)"
    );
    assert!(
        !direct.solved_by().contains("multigrid"),
        "{}",
        direct.solved_by()
    );
    same_paths(&scene, &direct, &auto);
    // The bundled scene's own size stays on the direct route.
    let small = Planner::new(&reference(0.004)).unwrap();
    assert!(
        !small.solved_by().contains("multigrid"),
        "{}",
        small.solved_by()
    );
}

/// The spiral's ψ falls past the double range, far below a multigrid ψ's residual scale:
/// the check rejects the multigrid ψ and the finest level is solved directly (in the
/// extended exponent), so the multigrid route still reaches the goal, along the direct
/// route's path to 0.5 %.
#[test]
fn a_multigrid_psi_that_fails_its_check_is_solved_directly_on_the_same_mesh() {
    let scene = Scene::from_file(harmonic_fixtures::mesh_file("spiral.json")).unwrap();
    let refined = Planner::with_options(&scene, &multigrid(2)).unwrap();
    let direct = Planner::new(&scene).unwrap();
    assert!(
        refined
            .solved_by()
            .contains("the multigrid ψ failed its check"),
        "{}",
        refined.solved_by()
    );
    same_paths(&scene, &direct, &refined);
}
