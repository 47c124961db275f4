//! The exact tracer on a linear field whose descent points into a wall: it runs straight to
//! the floor, then slides along it to the goal face — exactly, so the length is known.

use harmonic_trajectory::volume::{ExactVolumeOptions, P1VolumeField, trace_exact_volume};
use harmonic_volume::{BoundaryTag, Point, TetMesh};

/// The unit cube in n³ Kuhn cubes; the face x = 1 is the goal.
fn cube(n: usize) -> TetMesh {
    harmonic_fixtures::kuhn_cube(n, &|p: &Point| {
        if p.x > 1.0 - 1e-12 {
            BoundaryTag::Goal(0)
        } else {
            BoundaryTag::Wall
        }
    })
}

#[test]
fn descent_into_the_floor_slides_along_it_to_the_goal() {
    let mesh = cube(4);
    // φ = −x + 2z: −∇φ = (1, 0, −2) pushes into the floor z = 0.
    let phi: Vec<f64> = mesh.vertices().iter().map(|p| -p.x + 2.0 * p.z).collect();
    let field = P1VolumeField::descending(&mesh, &phi).unwrap();
    let start = Point::new(0.1, 0.5, 0.5);
    let path = trace_exact_volume(&field, start, &ExactVolumeOptions::default());
    assert!(path.status.reached_goal(), "{:?}", path.status);
    // Straight to the floor (Δz = 0.5, Δx = 0.25), then along it to x = 1.
    let want = (0.25f64.powi(2) + 0.5f64.powi(2)).sqrt() + 0.65;
    assert!(
        (path.length - want).abs() < 1e-9,
        "length {} vs {want}",
        path.length
    );
    let end = path.points.last().unwrap();
    assert!((end.x - 1.0).abs() < 1e-9 && end.z.abs() < 1e-9 && (end.y - 0.5).abs() < 1e-9);
    // φ decreases along the path.
    let values: Vec<f64> = path.points.iter().map(|p| -p.x + 2.0 * p.z).collect();
    assert!(values.windows(2).all(|w| w[1] <= w[0] + 1e-12));
}

#[test]
fn a_corner_is_followed_along_its_edge() {
    let mesh = cube(3);
    // −∇φ = (1, −1, −1): into the floor and the wall y = 0, so the path ends on their edge.
    let phi: Vec<f64> = mesh.vertices().iter().map(|p| -p.x + p.y + p.z).collect();
    let field = P1VolumeField::descending(&mesh, &phi).unwrap();
    let path = trace_exact_volume(
        &field,
        Point::new(0.2, 0.3, 0.3),
        &ExactVolumeOptions::default(),
    );
    assert!(path.status.reached_goal(), "{:?}", path.status);
    let end = path.points.last().unwrap();
    assert!(
        end.y.abs() < 1e-9 && end.z.abs() < 1e-9 && (end.x - 1.0).abs() < 1e-9,
        "{end}"
    );
    // Straight for Δ = 0.3 in each axis, then along the edge y = z = 0 from x = 0.5 to 1.
    let want = 0.3 * 3f64.sqrt() + 0.5;
    assert!(
        (path.length - want).abs() < 1e-9,
        "length {} vs {want}",
        path.length
    );
}

#[test]
fn a_topology_computed_beforehand_gives_the_same_field() {
    use harmonic_trajectory::volume::VolumeFieldTopology;
    let mesh = cube(3);
    let psi: Vec<f64> = mesh
        .vertices()
        .iter()
        .map(|p| p.x * p.x + 0.3 * p.y)
        .collect();
    let fresh = P1VolumeField::ascending(&mesh, &psi).unwrap();
    let beforehand =
        P1VolumeField::ascending_with(&mesh, VolumeFieldTopology::of(&mesh), &psi).unwrap();
    let start = Point::new(0.1, 0.4, 0.6);
    let opts = ExactVolumeOptions::default();
    let (a, b) = (
        trace_exact_volume(&fresh, start, &opts),
        trace_exact_volume(&beforehand, start, &opts),
    );
    assert!(a.status.reached_goal(), "{:?}", a.status);
    assert_eq!(a.points, b.points);
    // A topology of another mesh is refused, not read out of bounds.
    let other = VolumeFieldTopology::of(&cube(2));
    assert!(P1VolumeField::ascending_with(&mesh, other, &psi).is_err());
}
