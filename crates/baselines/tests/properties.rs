//! Property tests: rasterisation against a direct point-in-polygon test (`harmonic_mesh::geom`'s
//! even-odd rule, independent of the raster's scanline fill), and the discrete maximum
//! principle of the grid harmonic field on random scenes.

use harmonic_baselines::{Cell, Connectivity, GridHarmonic, Raster, SorOptions, Wavefront};
use harmonic_mesh::Point;
use harmonic_mesh::geom::polygon_contains;
use proptest::prelude::*;

fn square(s: f64) -> Vec<Point> {
    vec![
        Point::new(0.0, 0.0),
        Point::new(s, 0.0),
        Point::new(s, s),
        Point::new(0.0, s),
    ]
}

/// A star-shaped (possibly non-convex) polygon around `c` with the given radii.
fn star(c: (f64, f64), radii: &[f64]) -> Vec<Point> {
    radii
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let a = std::f64::consts::TAU * k as f64 / radii.len() as f64;
            Point::new(c.0 + r * a.cos(), c.1 + r * a.sin())
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn raster_matches_point_in_polygon(
        c in (3.0f64..7.0, 3.0f64..7.0),
        radii in prop::collection::vec(0.5f64..2.5, 3..9),
        n in 8usize..40,
    ) {
        let obstacle = star(c, &radii);
        let goal = star((9.0, 9.0), &[0.6; 4]);
        let r = Raster::from_polygons(&square(10.0), std::slice::from_ref(&obstacle), std::slice::from_ref(&goal), n)
            .unwrap();
        for (k, cell) in r.cells().iter().enumerate() {
            let p = r.centre(k);
            let (i, j) = (k % n, k / n);
            let ring = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            let expected = if ring {
                Cell::Wall
            } else if polygon_contains(&goal, p) {
                Cell::Goal(0)
            } else if polygon_contains(&obstacle, p) {
                Cell::Obstacle(0)
            } else {
                Cell::Free
            };
            // A small goal may also be given the cell holding its centre.
            let goal_fallback = *cell == Cell::Goal(0) && r.index_of(Point::new(9.0, 9.0)) == Some(k);
            prop_assert!(*cell == expected || goal_fallback, "cell {k} at {p}: {cell:?} vs {expected:?}");
        }
    }

    #[test]
    fn grid_field_obeys_the_maximum_principle(
        boxes in prop::collection::vec((0.5f64..8.0, 0.5f64..8.0, 0.3f64..2.0, 0.3f64..2.0), 1..5),
        gx in 1.0f64..9.0,
        gy in 1.0f64..9.0,
    ) {
        let obstacles: Vec<Vec<Point>> = boxes
            .iter()
            .map(|&(x, y, w, h)| {
                vec![Point::new(x, y), Point::new(x + w, y), Point::new(x + w, y + h), Point::new(x, y + h)]
            })
            .collect();
        let goal = star((gx, gy), &[0.3; 6]);
        let raster = Raster::from_polygons(&square(10.0), &obstacles, &[goal], 32).unwrap();
        let f = GridHarmonic::solve(raster, &SorOptions::default()).unwrap();
        prop_assert!(f.report().converged);
        prop_assert!(f.values().iter().all(|v| (0.0..=1.0).contains(v)));
        prop_assert_eq!(f.flat_cells(), 0);
        // The wavefront reaches exactly the cells the harmonic field can lead to the goal.
        let wave = Wavefront::new(f.raster().clone(), Connectivity::Four);
        for (k, cell) in f.raster().cells().iter().enumerate() {
            if *cell == Cell::Free {
                let reached = wave.distances()[k] != harmonic_baselines::UNREACHED;
                prop_assert_eq!(reached, f.values()[k] > 0.0, "cell {}", k);
            }
        }
    }
}
