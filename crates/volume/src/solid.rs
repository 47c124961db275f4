//! Solids a volume scene is made of: axis-aligned boxes, spheres and closed triangle surfaces,
//! validated on construction, with signed distances (negative inside) and exact distances to
//! triangles (through parry3d) for checking a mesh against the true geometry.

use std::collections::HashMap;

use nalgebra::{Point3, Vector3};
use parry3d_f64::math::{Pose, Vector as PVector};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{Ball, Cuboid, Segment, Shape, TriMesh, TriMeshFlags, Triangle};

use crate::error::{Part, VolumeError};

/// A point in space.
pub type Point = Point3<f64>;
/// A vector in space.
pub type Vector = Vector3<f64>;

/// An axis-aligned box `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxSolid {
    /// The lowest corner.
    pub min: Point,
    /// The highest corner.
    pub max: Point,
}

/// A ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereSolid {
    /// The centre.
    pub center: Point,
    /// The radius (> 0).
    pub radius: f64,
}

/// A closed, manifold, consistently oriented triangle surface and the solid it bounds
/// (triangles are reoriented outward if they were given inward).
#[derive(Clone)]
pub struct TriSurface {
    vertices: Vec<Point>,
    triangles: Vec<[u32; 3]>,
    shape: TriMesh,
    bounds: (Point, Point),
}

impl std::fmt::Debug for TriSurface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TriSurface")
            .field("vertices", &self.vertices.len())
            .field("triangles", &self.triangles.len())
            .finish_non_exhaustive()
    }
}

pub(crate) fn pv(p: &Point) -> PVector {
    PVector::new(p.x, p.y, p.z)
}

fn finite(p: &Point) -> bool {
    p.iter().all(|c| c.is_finite())
}

impl TriSurface {
    /// Validates a triangle surface: finite vertices, indices in range, no degenerate
    /// triangle, every edge shared by exactly two triangles traversing it in opposite
    /// directions, no two triangles without a common vertex touching or crossing. `role`
    /// names the solid in errors.
    pub fn new(
        role: Part,
        vertices: Vec<Point>,
        mut triangles: Vec<[u32; 3]>,
    ) -> Result<Self, VolumeError> {
        if triangles.is_empty() {
            return Err(VolumeError::EmptySurface { solid: role });
        }
        if let Some(i) = vertices.iter().position(|p| !finite(p)) {
            return Err(VolumeError::NonFinite {
                solid: role,
                what: format!("vertex {i}"),
            });
        }
        let n = vertices.len();
        let mut directed: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            for &v in tri {
                if v as usize >= n {
                    return Err(VolumeError::BadVertexIndex {
                        solid: role,
                        triangle: t,
                        vertex: v,
                        count: n,
                    });
                }
            }
            let [a, b, c] = tri.map(|v| vertices[v as usize]);
            let area2 = (b - a).cross(&(c - a)).norm();
            let scale = (b - a).norm().max((c - a).norm()).max(f64::MIN_POSITIVE);
            if tri[0] == tri[1]
                || tri[1] == tri[2]
                || tri[0] == tri[2]
                || area2 <= 1e-14 * scale * scale
            {
                return Err(VolumeError::DegenerateTriangle {
                    solid: role,
                    triangle: t,
                });
            }
            for k in 0..3 {
                let e = (tri[k], tri[(k + 1) % 3]);
                if let Some(&first) = directed.get(&e) {
                    return Err(VolumeError::InconsistentOrientation {
                        solid: role,
                        edge: [e.0, e.1],
                        first,
                        second: t,
                    });
                }
                directed.insert(e, t);
            }
        }
        // Undirected counts: each directed edge once, so an edge with no reverse is open and
        // an undirected edge seen more than twice (a, b), (b, a), (a, b)... was caught above;
        // three triangles on one edge show up as a missing or duplicate direction.
        let mut undirected: HashMap<(u32, u32), usize> = HashMap::with_capacity(directed.len());
        for &(a, b) in directed.keys() {
            *undirected.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
        for (&(a, b), &t) in &directed {
            if !directed.contains_key(&(b, a)) {
                let count = undirected[&(a.min(b), a.max(b))];
                if count > 2 {
                    return Err(VolumeError::NonManifoldEdge {
                        solid: role,
                        edge: [a, b],
                        count,
                    });
                }
                return Err(VolumeError::OpenEdge {
                    solid: role,
                    edge: [a, b],
                    triangle: t,
                });
            }
        }
        // Outward orientation: positive enclosed volume.
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| vertices[v as usize].coords);
                a.dot(&b.cross(&c))
            })
            .sum();
        if volume < 0.0 {
            for t in &mut triangles {
                t.swap(1, 2);
            }
        }
        if let Some([a, b]) = crossing_triangles(&vertices, &triangles) {
            return Err(VolumeError::SelfIntersecting {
                solid: role,
                triangles: [a, b],
            });
        }
        let mut lo = vertices[0];
        let mut hi = vertices[0];
        for p in &vertices {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let shape = TriMesh::with_flags(
            vertices.iter().map(pv).collect(),
            triangles.clone(),
            TriMeshFlags::ORIENTED,
        )
        .map_err(|e| VolumeError::Surface {
            solid: role,
            message: e.to_string(),
        })?;
        Ok(TriSurface {
            vertices,
            triangles,
            shape,
            bounds: (lo, hi),
        })
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// The triangles, oriented outward.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    fn signed_distance(&self, p: &Point) -> f64 {
        let proj = self.shape.project_local_point(pv(p), false);
        let q = proj.point;
        let d = ((p.x - q.x).powi(2) + (p.y - q.y).powi(2) + (p.z - q.z).powi(2)).sqrt();
        if proj.is_inside { -d } else { d }
    }
}

/// Two triangles of a surface that touch or cross though they share no vertex, if any: a
/// sweep over their bounding boxes along x, then parry's exact triangle–triangle test.
fn crossing_triangles(vertices: &[Point], triangles: &[[u32; 3]]) -> Option<[usize; 2]> {
    let boxes: Vec<(Point, Point)> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| vertices[v as usize]);
            (a.inf(&b).inf(&c), a.sup(&b).sup(&c))
        })
        .collect();
    let mut order: Vec<usize> = (0..triangles.len()).collect();
    order.sort_by(|&i, &j| boxes[i].0.x.total_cmp(&boxes[j].0.x));
    let tri = |t: usize| {
        let [a, b, c] = triangles[t].map(|v| pv(&vertices[v as usize]));
        Triangle::new(a, b, c)
    };
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if boxes[j].0.x > boxes[i].1.x {
                break;
            }
            let overlap =
                (1..3).all(|a| boxes[j].0[a] <= boxes[i].1[a] && boxes[i].0[a] <= boxes[j].1[a]);
            if !overlap || triangles[i].iter().any(|v| triangles[j].contains(v)) {
                continue;
            }
            let touch = parry3d_f64::query::intersection_test(
                &Pose::IDENTITY,
                &tri(i),
                &Pose::IDENTITY,
                &tri(j),
            )
            .is_ok_and(|r| r.intersecting);
            if touch {
                return Some([i.min(j), i.max(j)]);
            }
        }
    }
    None
}

/// One solid of a volume scene.
#[derive(Clone, Debug)]
pub enum Solid {
    /// An axis-aligned box.
    Box(BoxSolid),
    /// A ball.
    Sphere(SphereSolid),
    /// A closed triangle surface.
    Surface(Box<TriSurface>),
}

impl Solid {
    /// A validated box (`min < max` on every axis, finite).
    pub fn new_box(role: Part, min: Point, max: Point) -> Result<Self, VolumeError> {
        if !finite(&min) || !finite(&max) {
            return Err(VolumeError::NonFinite {
                solid: role,
                what: "a box corner".into(),
            });
        }
        for axis in 0..3 {
            if min[axis] >= max[axis] {
                return Err(VolumeError::InvertedBox {
                    solid: role,
                    axis,
                    min: min[axis],
                    max: max[axis],
                });
            }
        }
        Ok(Solid::Box(BoxSolid { min, max }))
    }

    /// A validated sphere (finite centre, radius > 0).
    pub fn new_sphere(role: Part, center: Point, radius: f64) -> Result<Self, VolumeError> {
        if !finite(&center) || !radius.is_finite() {
            return Err(VolumeError::NonFinite {
                solid: role,
                what: "the sphere centre or radius".into(),
            });
        }
        if radius <= 0.0 {
            return Err(VolumeError::BadRadius {
                solid: role,
                radius,
            });
        }
        Ok(Solid::Sphere(SphereSolid { center, radius }))
    }

    /// A validated closed triangle surface (see [`TriSurface::new`]).
    pub fn new_surface(
        role: Part,
        vertices: Vec<Point>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self, VolumeError> {
        Ok(Solid::Surface(Box::new(TriSurface::new(
            role, vertices, triangles,
        )?)))
    }

    /// Signed distance to the solid's surface: negative inside. Exact for every kind.
    pub fn signed_distance(&self, p: &Point) -> f64 {
        match self {
            Solid::Box(b) => {
                let c = nalgebra::center(&b.min, &b.max);
                let half = (b.max - b.min) / 2.0;
                let q = (p - c).abs() - half;
                let outside = q.sup(&Vector::zeros()).norm();
                let inside = q.max().min(0.0);
                outside + inside
            }
            Solid::Sphere(s) => (p - s.center).norm() - s.radius,
            Solid::Surface(t) => t.signed_distance(p),
        }
    }

    /// The axis-aligned bounding box `(min, max)`.
    pub fn bounds(&self) -> (Point, Point) {
        match self {
            Solid::Box(b) => (b.min, b.max),
            Solid::Sphere(s) => {
                let r = Vector::repeat(s.radius);
                (s.center - r, s.center + r)
            }
            Solid::Surface(t) => t.bounds,
        }
    }

    /// The solid's volume (boxes and spheres exactly, surfaces by the divergence theorem).
    pub fn volume(&self) -> f64 {
        match self {
            Solid::Box(b) => (b.max - b.min).product(),
            Solid::Sphere(s) => 4.0 / 3.0 * std::f64::consts::PI * s.radius.powi(3),
            Solid::Surface(t) => {
                t.triangles
                    .iter()
                    .map(|tri| {
                        let [a, b, c] = tri.map(|v| t.vertices[v as usize].coords);
                        a.dot(&b.cross(&c))
                    })
                    .sum::<f64>()
                    / 6.0
            }
        }
    }

    /// The exact distance between the triangle `tri` and the solid (0 if they touch or
    /// intersect; for a surface solid also 0 when a corner of the triangle is inside it).
    pub fn distance_to_triangle(&self, tri: [Point; 3]) -> f64 {
        let t = Triangle::new(pv(&tri[0]), pv(&tri[1]), pv(&tri[2]));
        self.distance_to_shape(&t, &tri)
    }

    /// The exact distance between the segment `a`–`b` and the solid (0 if it touches or
    /// crosses it; for a surface solid also 0 when an end is inside it).
    pub fn distance_to_segment(&self, a: &Point, b: &Point) -> f64 {
        let s = Segment::new(pv(a), pv(b));
        self.distance_to_shape(&s, &[*a, *b])
    }

    /// The distance between `shape` (in world coordinates, with these `corners`) and the
    /// solid, by parry; where parry has no algorithm, the corners' distances (an upper bound).
    fn distance_to_shape(&self, shape: &dyn Shape, corners: &[Point]) -> f64 {
        let id = Pose::IDENTITY;
        let corner_bound = |d: &dyn Fn(&Point) -> f64| {
            corners
                .iter()
                .map(|p| d(p).max(0.0))
                .fold(f64::INFINITY, f64::min)
        };
        let (pose, solid): (Pose, Box<dyn Shape>) = match self {
            Solid::Box(b) => {
                let c = nalgebra::center(&b.min, &b.max);
                let h = (b.max - b.min) / 2.0;
                (
                    Pose::from_translation(pv(&c)),
                    Box::new(Cuboid::new(PVector::new(h.x, h.y, h.z))),
                )
            }
            Solid::Sphere(s) => (
                Pose::from_translation(pv(&s.center)),
                Box::new(Ball::new(s.radius)),
            ),
            Solid::Surface(s) => {
                if corners.iter().any(|p| s.signed_distance(p) <= 0.0) {
                    return 0.0;
                }
                return match parry3d_f64::query::distance(&id, shape, &id, &s.shape) {
                    Ok(d) => d.distance,
                    Err(_) => corner_bound(&|p| s.signed_distance(p)),
                };
            }
        };
        match parry3d_f64::query::distance(&id, shape, &pose, solid.as_ref()) {
            Ok(d) => d.distance,
            Err(_) => corner_bound(&|p| self.signed_distance(p)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> (Vec<Point>, Vec<[u32; 3]>) {
        (
            vec![
                Point::new(0.0, 0.0, 0.0),
                Point::new(1.0, 0.0, 0.0),
                Point::new(0.0, 1.0, 0.0),
                Point::new(0.0, 0.0, 1.0),
            ],
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
    }

    #[test]
    fn box_and_sphere_distances() {
        let b = Solid::new_box(
            Part::Obstacle(0),
            Point::new(0.0, 0.0, 0.0),
            Point::new(2.0, 2.0, 2.0),
        )
        .unwrap();
        assert!((b.signed_distance(&Point::new(1.0, 1.0, 1.0)) + 1.0).abs() < 1e-15);
        assert!((b.signed_distance(&Point::new(3.0, 3.0, 1.0)) - 2f64.sqrt()).abs() < 1e-15);
        let s = Solid::new_sphere(Part::Obstacle(1), Point::new(0.0, 0.0, 0.0), 1.0).unwrap();
        assert!((s.signed_distance(&Point::new(0.0, 3.0, 0.0)) - 2.0).abs() < 1e-15);
        let tri = [
            Point::new(4.0, 0.0, 0.0),
            Point::new(4.0, 1.0, 0.0),
            Point::new(4.0, 0.0, 1.0),
        ];
        assert!((b.distance_to_triangle(tri) - 2.0).abs() < 1e-9);
        assert!((s.distance_to_triangle(tri) - 3.0).abs() < 1e-9);
    }

    #[test]
    fn bad_solids_are_named() {
        let e = Solid::new_box(
            Part::Obstacle(2),
            Point::new(0.0, 1.0, 0.0),
            Point::new(1.0, 0.5, 1.0),
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "obstacle 2: box min 1 is not below max 0.5 on axis 1"
        );
        let e = Solid::new_sphere(Part::Goal(0), Point::new(0.0, 0.0, 0.0), 0.0).unwrap_err();
        assert!(matches!(e, VolumeError::BadRadius { .. }));
        let e = Solid::new_sphere(Part::Goal(0), Point::new(f64::NAN, 0.0, 0.0), 1.0).unwrap_err();
        assert!(matches!(e, VolumeError::NonFinite { .. }));
    }

    #[test]
    fn a_surface_crossing_itself_names_two_crossing_triangles() {
        // Two tetrahedra in one surface, the second poking through the first's faces.
        let (mut v, mut t) = tetra();
        let shift = |p: &Point| Point::new(p.x + 0.3, p.y + 0.3, p.z - 0.4);
        v.extend(tetra().0.iter().map(shift));
        t.extend(tetra().1.iter().map(|tri| tri.map(|i| i + 4)));
        let e = Solid::new_surface(Part::Obstacle(1), v, t.clone()).unwrap_err();
        let VolumeError::SelfIntersecting { triangles, .. } = e else {
            panic!("{e}");
        };
        assert!(triangles[0] < 4 && triangles[1] >= 4, "{triangles:?}");
        assert!(e.to_string().starts_with("obstacle 1: triangles "), "{e}");
        // Apart, the same two tetrahedra are one valid (two-piece) surface.
        let (mut v, _) = tetra();
        v.extend(tetra().0.iter().map(|p| Point::new(p.x + 3.0, p.y, p.z)));
        assert!(Solid::new_surface(Part::Obstacle(1), v, t).is_ok());
    }

    #[test]
    fn surfaces_are_validated_and_oriented() {
        let (v, t) = tetra();
        let s = Solid::new_surface(Part::Obstacle(0), v.clone(), t.clone()).unwrap();
        assert!((s.volume() - 1.0 / 6.0).abs() < 1e-15);
        assert!(s.signed_distance(&Point::new(0.1, 0.1, 0.1)) < 0.0);
        assert!((s.signed_distance(&Point::new(-1.0, 0.2, 0.2)) - 1.0).abs() < 1e-12);
        // Inward given: reoriented, same solid.
        let inward: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let s2 = Solid::new_surface(Part::Obstacle(0), v.clone(), inward).unwrap();
        assert!((s2.volume() - 1.0 / 6.0).abs() < 1e-15);
        assert!(s2.signed_distance(&Point::new(0.1, 0.1, 0.1)) < 0.0);
        // Open: drop a triangle.
        let e = Solid::new_surface(Part::Obstacle(3), v.clone(), t[..3].to_vec()).unwrap_err();
        assert!(
            matches!(
                e,
                VolumeError::OpenEdge {
                    solid: Part::Obstacle(3),
                    ..
                }
            ),
            "{e}"
        );
        // Inconsistent: flip one triangle.
        let mut bad = t.clone();
        bad[1] = [0, 3, 1];
        let e = Solid::new_surface(Part::Workspace, v.clone(), bad).unwrap_err();
        assert!(
            matches!(e, VolumeError::InconsistentOrientation { .. }),
            "{e}"
        );
        // Out-of-range index.
        let mut bad = t.clone();
        bad[0] = [0, 2, 9];
        let e = Solid::new_surface(Part::Workspace, v, bad).unwrap_err();
        assert!(
            matches!(e, VolumeError::BadVertexIndex { vertex: 9, .. }),
            "{e}"
        );
    }
}
