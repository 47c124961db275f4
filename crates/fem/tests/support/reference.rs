//! The reference scene of the peer comparison (`meshes/reference.json`, docs/peers.md): the
//! square [0, 10]² with five obstacles and a 16-gon goal of radius 0.15 at (8.5, 1.5).
//! Shared by the peer tests and the `fem` bench.

use harmonic_fem::{BoundaryCondition, BoundaryConditions};
use harmonic_mesh::{Domain, DomainSpec, GoalShape, Mesh, MeshOptions, Point, Shape};

fn polygon(points: &[[f64; 2]]) -> Vec<Point> {
    points.iter().map(|p| Point::new(p[0], p[1])).collect()
}

/// The scene's domain (obstacles in input order: tall_rect, long_rect, triangle, L_shape,
/// pentagon).
pub fn reference_spec() -> DomainSpec {
    let goal: Vec<Point> = (0..16)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 16.0;
            Point::new(8.5 + 0.15 * a.cos(), 1.5 + 0.15 * a.sin())
        })
        .collect();
    DomainSpec {
        workspace: polygon(&[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]),
        obstacles: vec![
            Shape::Polygon(polygon(&[[2.0, 2.0], [3.0, 2.0], [3.0, 8.0], [2.0, 8.0]])),
            Shape::Polygon(polygon(&[[5.0, 4.0], [9.0, 4.0], [9.0, 5.0], [5.0, 5.0]])),
            Shape::Polygon(polygon(&[[4.0, 7.0], [7.0, 7.0], [6.0, 9.0]])),
            Shape::Polygon(polygon(&[
                [5.5, 1.0],
                [7.0, 1.0],
                [7.0, 3.0],
                [6.5, 3.0],
                [6.5, 1.5],
                [5.5, 1.5],
            ])),
            Shape::Polygon(polygon(&[
                [3.6, 2.4],
                [4.6, 2.2],
                [4.9, 3.1],
                [4.2, 3.7],
                [3.5, 3.2],
            ])),
        ],
        goals: vec![GoalShape::Polygon(goal)],
        robot_radius: 0.0,
    }
}

/// The reference scene meshed with `max_area` and a 30° minimum angle.
pub fn reference_mesh(max_area: f64) -> Mesh {
    let opts = MeshOptions {
        max_area: Some(max_area),
        min_angle_deg: 30.0,
        ..MeshOptions::default()
    };
    let domain = Domain::new(&reference_spec(), &opts).expect("the reference scene is valid");
    domain.mesh(&opts).expect("the reference scene meshes").0
}

/// Case (a): Dirichlet φ = 1 on walls and obstacles, 0 on the goal (the defaults).
pub fn dirichlet() -> BoundaryConditions {
    BoundaryConditions::default()
}

/// Case (b): Robin ∂φ/∂n = 1 − φ (a = b = g = 1) on walls and obstacles, φ = 0 on the goal.
pub fn robin() -> BoundaryConditions {
    BoundaryConditions::uniform(BoundaryCondition::Robin {
        a: 1.0,
        b: 1.0,
        g: 1.0,
    })
}
