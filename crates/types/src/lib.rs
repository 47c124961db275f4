//! # harmonic-types
//!
//! The vocabulary every crate of the harmonic planner shares, and nothing else: points and
//! vectors of the plane and of space, the triangle mesh ([`Mesh`]) and the tetrahedral mesh
//! ([`TetMesh`]) that meshers produce and solvers and tracers read, the [`BoundaryTag`] of a
//! boundary edge or face, and the geometric kernels — one of each ([`geom`]).
//!
//! This crate has no mesher, no solver and no collision library in it: it depends on
//! nalgebra, serde, thiserror, rayon and `robust` only, so a crate that reads meshes (the
//! finite elements, the tracers) does not pull in spade, geo or parry.
//!
//! ```
//! use harmonic_types::{BoundaryTag, Mesh, Point, geom};
//!
//! // The unit square as two triangles, its bottom edge the goal.
//! let vertices = vec![
//!     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0),
//! ];
//! let boundary = [(0, 1, BoundaryTag::Goal(0)), (1, 2, BoundaryTag::Wall),
//!                 (2, 3, BoundaryTag::Wall), (3, 0, BoundaryTag::Wall)];
//! let mesh = Mesh::from_parts(vertices, vec![[0, 1, 2], [0, 2, 3]], &boundary)?;
//! assert_eq!(mesh.boundary_edges().len(), 4);
//! assert_eq!(mesh.locate(Point::new(0.75, 0.25), None), Some(0));
//! assert_eq!(geom::signed_area(mesh.vertices()), 1.0);
//! # Ok::<(), harmonic_types::MeshDataError>(())
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod error;
pub mod geom;
mod grouped;
mod hierarchy;
mod mesh;
mod tag;
mod tet_locate;
mod tet_mesh;

pub use error::{Element, MeshDataError};
pub use grouped::{Grouped, TetEdges, vertex_runs};
pub use hierarchy::MeshHierarchy;
pub use mesh::{BoundaryEdge, Mesh, NO_NEIGHBOR, QualityReport, map_in_two};
pub use tag::{BoundaryTag, Part, SEAM_PART};
pub use tet_mesh::{
    BoundaryFace, EDGES, FACES, TetMesh, check_tetrahedra, face_neighbors, face_neighbors_around,
    signed_volume,
};

/// A point of the plane.
pub type Point = nalgebra::Point2<f64>;
/// A vector of the plane.
pub type Vector = nalgebra::Vector2<f64>;
/// A point in space.
pub type Point3 = nalgebra::Point3<f64>;
/// A vector in space.
pub type Vector3 = nalgebra::Vector3<f64>;
