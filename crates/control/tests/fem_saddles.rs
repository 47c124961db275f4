//! The discrete saddles of an FEM potential: a square obstacle in a square room with the
//! goal on the right has one saddle, on the symmetry axis behind the obstacle (where the
//! descent splits to pass it above or below).

use harmonic_control::stagnation::fem_stagnation_points;
use harmonic_planner::{Planner, Scene};

#[test]
fn a_symmetric_room_has_its_saddle_on_the_axis_behind_the_obstacle() {
    let scene = Scene::from_json(
        r#"{"workspace": [[0, 0], [10, 0], [10, 10], [0, 10]],
            "obstacles": [{"polygon": [[4, 4], [6, 4], [6, 6], [4, 6]]}],
            "goal": {"circle": {"center": [9, 5], "radius": 0.3}},
            "mesh": {"max_area": 0.02}}"#,
    )
    .expect("scene");
    let planner = Planner::new(&scene).expect("plans");
    let saddles = fem_stagnation_points(planner.potential(), 0.5);
    assert_eq!(saddles.len(), 1, "{saddles:?}");
    let s = saddles[0];
    assert!((s.y - 5.0).abs() < 0.3, "{s}");
    assert!(s.x > 0.0 && s.x < 4.0, "{s}");
}
