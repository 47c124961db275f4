//! The planar geometric kernels ([`harmonic_types::geom`], re-exported here) and the two
//! the mesher adds on rings: Douglas–Peucker simplification ([`simplify_ring`]) and an
//! R-tree over segments for distance and inside queries.
//!
//! ```
//! use harmonic_mesh::geom::{polygon_contains, polygon_distance, segment_polygon_distance};
//! let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
//! assert!(polygon_contains(&square, [1.0, 1.0]));
//! assert_eq!(polygon_distance(&square, [1.0, 1.0]), 0.0);
//! assert_eq!(polygon_distance(&square, [3.0, 1.0]), 1.0);
//! assert_eq!(segment_polygon_distance([3.0, -1.0], [3.0, 3.0], &square), 1.0);
//! ```

mod index;
mod simplify;

pub use harmonic_types::geom::*;
pub(crate) use index::SegmentIndex;
pub use simplify::simplify_ring;
