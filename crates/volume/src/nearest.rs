//! The nearest point of a tetrahedral mesh's boundary (through parry3d's triangle
//! projection).

use harmonic_types::TetMesh;

use crate::solid::{Point, Vector, pv};

/// The point of the mesh's boundary nearest to `p`, and the boundary face (index into
/// [`TetMesh::boundary_faces`]) it lies on; `None` without boundary faces.
/// A linear scan: for the occasional start that lies off the mesh.
pub fn nearest_boundary_point(mesh: &TetMesh, p: &Point) -> Option<(Point, usize)> {
    use parry3d_f64::query::PointQuery;
    use parry3d_f64::shape::Triangle;
    let mut best: Option<(f64, Point, usize)> = None;
    for (i, f) in mesh.boundary_faces().iter().enumerate() {
        let [a, b, c] = f.vertices.map(|v| mesh.vertices()[v as usize]);
        // No closer than the distance to the face's bounding box.
        let lo = a.inf(&b).inf(&c);
        let hi = a.sup(&b).sup(&c);
        let gap = (lo - p).sup(&(p - hi)).sup(&Vector::zeros()).norm_squared();
        if best.is_some_and(|(d, _, _)| gap >= d) {
            continue;
        }
        let t = Triangle::new(pv(&a), pv(&b), pv(&c));
        let q = t.project_local_point(pv(p), true).point;
        let q = Point::new(q.x, q.y, q.z);
        let d = (q - p).norm_squared();
        if best.is_none_or(|(bd, _, _)| d < bd) {
            best = Some((d, q, i));
        }
    }
    best.map(|(_, q, i)| (q, i))
}
