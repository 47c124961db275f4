//! The peers' reference workload (`meshes/reference.json`, docs/peers.md): the square
//! [0, 10]², five obstacles and a goal disc of radius 0.15 at (8.5, 1.5) as a 16-gon.

use harmonic_mesh::Point;

fn poly(v: &[[f64; 2]]) -> Vec<Point> {
    v.iter().map(|p| Point::new(p[0], p[1])).collect()
}

/// `(workspace, obstacles, goals)` of the reference scene.
pub fn reference() -> (Vec<Point>, Vec<Vec<Point>>, Vec<Vec<Point>>) {
    let workspace = poly(&[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]);
    let obstacles = vec![
        poly(&[[2.0, 2.0], [3.0, 2.0], [3.0, 8.0], [2.0, 8.0]]),
        poly(&[[5.0, 4.0], [9.0, 4.0], [9.0, 5.0], [5.0, 5.0]]),
        poly(&[[4.0, 7.0], [7.0, 7.0], [6.0, 9.0]]),
        poly(&[
            [5.5, 1.0],
            [7.0, 1.0],
            [7.0, 3.0],
            [6.5, 3.0],
            [6.5, 1.5],
            [5.5, 1.5],
        ]),
        poly(&[[3.6, 2.4], [4.6, 2.2], [4.9, 3.1], [4.2, 3.7], [3.5, 3.2]]),
    ];
    let goal = (0..16)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 16.0;
            Point::new(8.5 + 0.15 * a.cos(), 1.5 + 0.15 * a.sin())
        })
        .collect();
    (workspace, obstacles, vec![goal])
}
