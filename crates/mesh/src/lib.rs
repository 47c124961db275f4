//! # harmonic-mesh
//!
//! Quality triangulations of a robot's free space: a workspace polygon with polygonal and
//! circular obstacles (holes) and goal regions, meshed by constrained Delaunay triangulation
//! (spade) and refined to a minimum angle and maximum area. Every boundary edge knows what it
//! lies on ([`BoundaryTag`]: wall, obstacle `i`, goal `j`), triangles know their neighbours,
//! and points can be located by walking.

mod mesh;

pub use mesh::{BoundaryEdge, BoundaryTag, Mesh, NO_NEIGHBOR, Point, Vector};

/// Everything that can go wrong while building a domain or a mesh.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// Mesh data handed to [`Mesh::from_parts`] (or read from a file) is inconsistent.
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
}

/// Twice the signed area of the triangle `a, b, c`: positive when counter-clockwise.
pub fn orient2d(a: Point, b: Point, c: Point) -> f64 {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}
