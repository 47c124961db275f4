//! Every baseline on the peers' reference scene from its six sample points: the harmonic
//! planners (grid SOR + shared tracer, panels) and the wavefront reach the goal without
//! leaving free space; the attractive/repulsive field gets trapped from the start (1, 9).

use harmonic_baselines::{
    Cell, Connectivity, GridHarmonic, PanelOptions, PanelPlanner, PotentialField,
    PotentialFieldOptions, Raster, SorOptions, Wavefront,
};
use harmonic_mesh::Point;
use harmonic_trajectory::{SmoothOptions, TraceStatus, trace_smooth};

#[path = "../benches/support/reference_scene.rs"]
mod reference_scene;

const STARTS: [[f64; 2]; 6] = [
    [1.0, 1.0],
    [1.0, 9.0],
    [4.0, 5.0],
    [9.0, 9.0],
    [8.0, 3.0],
    [3.5, 1.0],
];

fn inside(poly: &[Point], p: Point) -> bool {
    let mut c = false;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
            c = !c;
        }
    }
    c
}

#[test]
fn harmonic_baselines_and_wavefront_reach_the_goal() {
    let (ws, obstacles, goals) = reference_scene::reference();
    let free = |p: Point| inside(&ws, p) && !obstacles.iter().any(|o| inside(o, p));
    let raster = Raster::from_polygons(&ws, &obstacles, &goals, 128).unwrap();
    let field = GridHarmonic::solve(raster.clone(), &SorOptions::default()).unwrap();
    assert_eq!(field.flat_cells(), 0);
    let wave = Wavefront::new(raster, Connectivity::Eight);
    let panel = PanelPlanner::new(
        &ws,
        &obstacles,
        Point::new(8.5, 1.5),
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
        let straight = (Point::new(8.5, 1.5) - start).norm() - 0.15;
        for len in [traced.length, w.length, p.length] {
            assert!(len >= straight - 0.1, "from {start}: {len} < {straight}");
        }
    }
}

#[test]
fn attractive_repulsive_field_is_trapped_from_the_far_corner() {
    let (ws, obstacles, _) = reference_scene::reference();
    let pf = PotentialField::new(
        &ws,
        &obstacles,
        Point::new(8.5, 1.5),
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
