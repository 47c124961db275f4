//! Robustness on arbitrary (non-harmonic) P1 fields: whatever the values, the exact tracer
//! ends (goal, stall or budget), never leaves free space, never produces NaN, and never
//! climbs; the smooth tracer ends and never leaves free space.

mod common;

use common::GridQueries;
use harmonic_fixtures::{Cell, Grid};
use harmonic_mesh::Point;
use harmonic_trajectory::{
    CarOptions, ExactOptions, Field, Locate, P1Field, SmoothOptions, TraceStatus, drive,
    trace_exact, trace_smooth,
};
use proptest::prelude::*;

fn grid() -> Grid {
    let mut g = Grid::new(8, 8, 0.5);
    g.mark(1.5, 1.5, 2.5, 2.5, Cell::Obstacle(0));
    g.mark(3.0, 0.0, 3.5, 1.0, Cell::Goal(0));
    g
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn any_field_any_start(
        seed_values in proptest::collection::vec(-3i8..4, 81),
        sx in 0.0f64..4.0,
        sy in 0.0f64..4.0,
        snap in 0u8..3,
    ) {
        let g = grid();
        let mesh = g.mesh();
        // Small integers make exact ties (flat triangles, level edges) common.
        let psi: Vec<f64> = seed_values.iter().map(|&v| v as f64).collect();
        let f = P1Field::ascending(&mesh, &psi).unwrap();
        // Snap some starts to vertices and edges of the grid.
        let s = match snap {
            0 => Point::new(sx, sy),
            1 => Point::new((sx * 2.0).round() / 2.0, (sy * 2.0).round() / 2.0),
            _ => Point::new((sx * 2.0).round() / 2.0, sy),
        };
        let opts = ExactOptions { max_steps: 10_000, max_perturbations: 8 };
        let path = trace_exact(&f, s, &opts);
        prop_assert!(path.length.is_finite());
        prop_assert!(path.points.iter().all(|p| p.x.is_finite() && p.y.is_finite()));
        match path.status {
            TraceStatus::StartInObstacle => prop_assert!(matches!(g.cell_at(s), Some(Cell::Obstacle(_)))),
            TraceStatus::ReachedGoal(_) | TraceStatus::Stalled { .. } | TraceStatus::MaxSteps => {}
            other => prop_assert!(false, "unexpected status {:?}", other),
        }
        if path.status != TraceStatus::StartInObstacle {
            for w in path.points.windows(2) {
                prop_assert!(!g.segment_hits_obstacle(w[0], w[1]), "{} → {}", w[0], w[1]);
            }
            let mut prev = f64::INFINITY;
            let mut hint = None;
            for (i, p) in path.points.iter().enumerate() {
                let v = match f.locate(*p, hint) {
                    Locate::Inside(t) => { hint = Some(t); f.value(t, *p) }
                    Locate::Goal(_) if i + 1 == path.points.len() => continue,
                    other => { prop_assert!(false, "{} left free space: {:?}", p, other); unreachable!() }
                };
                prop_assert!(v <= prev + 1e-9, "climbs at point {}: {} → {}", i, prev, v);
                prev = v;
            }
            let mut sopts = SmoothOptions::for_scale(4.0);
            sopts.max_steps = 5_000;
            let smooth = trace_smooth(&f, s, &sopts).unwrap();
            prop_assert!(smooth.length.is_finite());
            for w in smooth.points.windows(2) {
                prop_assert!(!g.segment_hits_obstacle(w[0], w[1]), "smooth {} → {}", w[0], w[1]);
            }
            let mut copts = CarOptions::new(0.2, 0.6, 0.05);
            copts.max_steps = 2_000;
            copts.stall_steps = 100;
            let car = drive(&f, [s.x, s.y, sx + sy], &copts, None).unwrap();
            prop_assert!(car.length.is_finite() && car.max_curvature <= 0.6f64.tan() / 0.2 + 1e-9);
            for (i, p) in car.poses.iter().enumerate() {
                prop_assert!(p.iter().all(|c| c.is_finite()));
                let cell = g.cell_at(Point::new(p[0], p[1]));
                let last_in_goal = i + 1 == car.poses.len() && car.status.reached_goal();
                prop_assert!(cell == Some(Cell::Free) || last_in_goal || (p[0] == s.x && p[1] == s.y), "car pose {:?} in {:?}", p, cell);
            }
        }
    }
}
