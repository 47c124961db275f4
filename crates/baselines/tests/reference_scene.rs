//! Every baseline on the peers' reference scene from its six sample points: the harmonic
//! planners (grid SOR + shared tracer, panels) and the wavefront reach the goal without
//! leaving free space; the attractive/repulsive field gets trapped from the start (1, 9).

use harmonic_baselines::{
    Cell, Connectivity, GridHarmonic, PanelOptions, PanelPlanner, PotentialField,
    PotentialFieldOptions, Raster, SorOptions, Wavefront,
};
use harmonic_fixtures::{
    REFERENCE_GOAL_CENTER, REFERENCE_GOAL_RADIUS, ScenePolygons, reference_polygons,
};
use harmonic_mesh::Point;
use harmonic_mesh::geom::polygon_contains;
use harmonic_trajectory::{SmoothOptions, TraceStatus, trace_smooth};

const STARTS: [[f64; 2]; 6] = [
    [1.0, 1.0],
    [1.0, 9.0],
    [4.0, 5.0],
    [9.0, 9.0],
    [8.0, 3.0],
    [3.5, 1.0],
];

#[test]
fn harmonic_baselines_and_wavefront_reach_the_goal() {
    let ScenePolygons {
        workspace: ws,
        obstacles,
        goals,
    } = reference_polygons();
    let free =
        |p: Point| polygon_contains(&ws, p) && !obstacles.iter().any(|o| polygon_contains(o, p));
    let raster = Raster::from_polygons(&ws, &obstacles, &goals, 128).unwrap();
    let field = GridHarmonic::solve(raster.clone(), &SorOptions::default()).unwrap();
    assert_eq!(field.flat_cells(), 0);
    let wave = Wavefront::new(raster, Connectivity::Eight);
    let panel = PanelPlanner::new(
        &ws,
        &obstacles,
        Point::from(REFERENCE_GOAL_CENTER),
        PanelOptions::default(),
    )
    .unwrap();
    for [x, y] in STARTS {
        let start = Point::new(x, y);
        let traced = trace_smooth(&field, start, &SmoothOptions::for_scale(10.0)).unwrap();
        assert_eq!(
            traced.status,
            TraceStatus::ReachedGoal(0),
            "grid from {start}"
        );
        assert!(
            traced.points.iter().all(|&p| free(p)),
            "grid path from {start}"
        );
        let w = wave.plan(start);
        assert!(w.status.reached_goal(), "wavefront from {start}");
        assert!(
            w.points[1..]
                .iter()
                .all(|&p| wave.raster().cell_at(p).is_some_and(Cell::is_traversable))
        );
        let p = panel.plan(start).unwrap();
        assert!(
            p.status.reached_goal(),
            "panels from {start}: {:?}",
            p.status
        );
        assert!(p.points.iter().all(|&q| free(q)), "panel path from {start}");
        // Every path is at least as long as the straight line to the goal disc.
        let straight = (Point::from(REFERENCE_GOAL_CENTER) - start).norm() - REFERENCE_GOAL_RADIUS;
        for len in [traced.length, w.length, p.length] {
            assert!(len >= straight - 0.1, "from {start}: {len} < {straight}");
        }
    }
}

#[test]
fn attractive_repulsive_field_is_trapped_from_the_far_corner() {
    let ScenePolygons {
        workspace: ws,
        obstacles,
        ..
    } = reference_polygons();
    let pf = PotentialField::new(
        &ws,
        &obstacles,
        Point::from(REFERENCE_GOAL_CENTER),
        PotentialFieldOptions::default(),
    )
    .unwrap();
    assert!(matches!(
        pf.plan(Point::new(1.0, 9.0)).status,
        TraceStatus::Stalled { .. }
    ));
    // With nothing in the way it does reach the goal.
    assert!(pf.plan(Point::new(8.0, 3.0)).status.reached_goal());
}
