//! Scenes shared by the integration tests (Rust equivalents of the bundled JSON scenes).
#![allow(dead_code)]

use harmonic_mesh::{BoundaryTag, DomainSpec, GoalShape, Mesh, Point, Shape};

pub fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

pub fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
    vec![p(x0, y0), p(x1, y0), p(x1, y1), p(x0, y1)]
}

/// meshes/reference.json: square [0,10]², five obstacles, goal disc (8.5, 1.5) r 0.15.
pub fn reference() -> DomainSpec {
    DomainSpec {
        workspace: rect(0.0, 0.0, 10.0, 10.0),
        obstacles: vec![
            Shape::Polygon(rect(2.0, 2.0, 3.0, 8.0)),
            Shape::Polygon(rect(5.0, 4.0, 9.0, 5.0)),
            Shape::Polygon(vec![p(4.0, 7.0), p(7.0, 7.0), p(6.0, 9.0)]),
            Shape::Polygon(vec![
                p(5.5, 1.0),
                p(7.0, 1.0),
                p(7.0, 3.0),
                p(6.5, 3.0),
                p(6.5, 1.5),
                p(5.5, 1.5),
            ]),
            Shape::Polygon(vec![
                p(3.6, 2.4),
                p(4.6, 2.2),
                p(4.9, 3.1),
                p(4.2, 3.7),
                p(3.5, 3.2),
            ]),
        ],
        goals: vec![GoalShape::Circle {
            center: p(8.5, 1.5),
            radius: 0.15,
        }],
        robot_radius: 0.0,
    }
}

/// Shoelace area of a polygon (positive if counter-clockwise).
pub fn area(poly: &[Point]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        * 0.5
}

/// Distance from p to segment ab.
pub fn seg_dist(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    (a + ab * t - p).norm()
}

/// Checks the invariants every mesh must satisfy, returning a description of the first failure.
pub fn check_invariants(mesh: &Mesh, expected_area: f64, rel_tol: f64) -> Result<(), String> {
    check_invariants_with_bridges(mesh, expected_area, rel_tol, 0)
}

/// Like [`check_invariants`], with `bridges` interior edges joining two boundary vertices allowed.
pub fn check_invariants_with_bridges(
    mesh: &Mesh,
    expected_area: f64,
    rel_tol: f64,
    bridges: usize,
) -> Result<(), String> {
    let q = mesh.quality();
    let rel = (q.area - expected_area).abs() / expected_area;
    if rel > rel_tol {
        return Err(format!(
            "area {} vs {} (rel {rel:e})",
            q.area, expected_area
        ));
    }
    // Euler per component: V - E + T = 1 - holes; summed: V - E + T = C - H (plus pinches).
    let v = mesh.vertices().len() as i64;
    let t = mesh.triangles().len() as i64;
    let nb = mesh.boundary_edges().len() as i64;
    let e = (3 * t + nb) / 2;
    if (3 * t + nb) % 2 != 0 {
        return Err("odd edge count".into());
    }
    // Vertices where the boundary touches itself count once per extra wedge of free space.
    let mut leaving = vec![0i64; mesh.vertices().len()];
    for b in mesh.boundary_edges() {
        leaving[b.vertices[0] as usize] += 1;
    }
    let pinch: i64 = leaving.iter().map(|&w| (w - 1).max(0)).sum();
    if pinch != q.pinch_vertices as i64 {
        return Err(format!(
            "{pinch} pinch wedges, report says {}",
            q.pinch_vertices
        ));
    }
    if v - e + t + pinch != q.components as i64 - q.holes as i64 {
        return Err(format!(
            "Euler: V-E+T+P = {} but C-H = {}",
            v - e + t + pinch,
            q.components as i64 - q.holes as i64
        ));
    }
    for (t, tri) in mesh.triangles().iter().enumerate() {
        if mesh.triangle_area(t as u32) <= 0.0 {
            return Err(format!("triangle {t} {tri:?} not CCW"));
        }
    }
    // No interior edge joins two boundary vertices, ears aside (split_boundary_bridges).
    let mut found = 0;
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
            let u = mesh.neighbors()[t][k];
            // An ear: the other two edges of the triangle are boundary edges.
            let ear = |s: usize, j: usize| {
                let n = mesh.neighbors()[s];
                n[(j + 1) % 3] == harmonic_mesh::NO_NEIGHBOR
                    && n[(j + 2) % 3] == harmonic_mesh::NO_NEIGHBOR
            };
            if u != harmonic_mesh::NO_NEIGHBOR
                && mesh.vertex_tags()[a].is_some()
                && mesh.vertex_tags()[b].is_some()
            {
                let j = mesh.neighbors()[u as usize]
                    .iter()
                    .position(|&x| x == t as u32)
                    .unwrap();
                if !ear(t, k) && !ear(u as usize, j) {
                    found += 1;
                }
            }
        }
    }
    // Each interior edge is seen from both sides.
    if found != 2 * bridges {
        return Err(format!(
            "{} interior edges join two boundary vertices, {bridges} reported",
            found / 2
        ));
    }
    let _ = BoundaryTag::Wall;
    Ok(())
}
