//! A covering's field from its first copy's gradients ([`P1VolumeField::ascending_with_copies`])
//! is the field computed tetrahedron by tetrahedron, to rounding; a copy whose values differ
//! from its original's gets its own gradients.

use harmonic_trajectory::Field;
use harmonic_trajectory::volume::{P1VolumeField, VolumeFieldTopology};
use harmonic_volume::{BoundaryTag, Point, TetMesh};

/// Two copies of a 3³ Kuhn cube, the second moved by 1 along x (disjoint: each copy is a
/// component with a goal face), its tetrahedra after the first's.
fn two_copies() -> TetMesh {
    let tag = |p: &Point| {
        if p.z > 1.0 - 1e-12 {
            BoundaryTag::Goal(0)
        } else {
            BoundaryTag::Wall
        }
    };
    let one = harmonic_fixtures::kuhn_cube(3, &tag);
    let nv = one.vertices().len() as u32;
    let mut vertices = one.vertices().to_vec();
    vertices.extend(
        one.vertices()
            .iter()
            .map(|p| p + harmonic_volume::Vector::new(1.5, 0.0, 0.0)),
    );
    let mut tets = one.tetrahedra().to_vec();
    tets.extend(one.tetrahedra().iter().map(|t| t.map(|v| v + nv)));
    TetMesh::new(vertices, tets, &tag).expect("two disjoint cubes")
}

/// The smooth (recovered) gradient at the centroid of every tetrahedron.
fn gradients(field: &P1VolumeField<'_>, mesh: &TetMesh) -> Vec<harmonic_volume::Vector> {
    (0..mesh.tetrahedra().len() as u32)
        .map(|t| {
            let p = mesh.tet_points(t);
            let c = Point::from((p[0].coords + p[1].coords + p[2].coords + p[3].coords) / 4.0);
            field.gradient(t, c)
        })
        .collect()
}

/// The field from copies of the first `period` tetrahedra has the smooth gradients of the
/// field computed tetrahedron by tetrahedron.
fn same_field(mesh: &TetMesh, psi: &[f64], period: usize) {
    let each = P1VolumeField::ascending_with(mesh, VolumeFieldTopology::of(mesh), psi).unwrap();
    let copied =
        P1VolumeField::ascending_with_copies(mesh, VolumeFieldTopology::of(mesh), psi, period)
            .unwrap();
    for (a, b) in gradients(&each, mesh).iter().zip(gradients(&copied, mesh)) {
        assert!(
            (a - b).norm() <= 1e-12 * a.norm().max(1.0),
            "{a:?} vs {b:?}"
        );
    }
}

#[test]
fn copies_take_their_originals_gradients() {
    let mesh = two_copies();
    let nt = mesh.tetrahedra().len();
    let nv = mesh.vertices().len();
    // ψ the same at both copies of a vertex (copied, so equal to the bit).
    let first: Vec<f64> = mesh.vertices()[..nv / 2]
        .iter()
        .map(|p| (0.3 + p.z * p.z + 0.2 * p.y).exp() * (1.0 + p.x))
        .collect();
    let psi = [first.clone(), first].concat();
    same_field(&mesh, &psi, nt / 2);
    // A second copy with other values: its tetrahedra get their own gradients.
    let mut other = psi.clone();
    for v in other.iter_mut().skip(nv / 2) {
        *v *= 2.0;
    }
    same_field(&mesh, &other, nt / 2);
    // A copy size that does not divide the mesh is refused.
    assert!(
        P1VolumeField::ascending_with_copies(
            &mesh,
            VolumeFieldTopology::of(&mesh),
            &psi,
            nt / 2 + 1
        )
        .is_err()
    );
}
