//! # harmonic-mesh
//!
//! Quality triangulations of a robot's free space: a workspace polygon with polygonal and
//! circular obstacles (holes) and goal regions, meshed by constrained Delaunay triangulation
//! (spade) and refined to a minimum angle and maximum area. Every boundary edge knows what it
//! lies on ([`BoundaryTag`]: wall, obstacle `i`, goal `j`), triangles know their neighbours,
//! and points can be located by walking.
//!
//! The pipeline is [`DomainSpec`] → [`Domain::new`] (validation, circle discretisation,
//! robot-radius offsetting, polygon booleans with geo/i_overlay, snapping, boundary tags) →
//! [`Domain::mesh`] (constrained Delaunay + Ruppert refinement, optional [`Grading`] towards
//! goals and obstacle corners, large meshes in two halves on two threads of rayon's pool,
//! glued along a cut — [`MeshOptions::halves_from`] —, Hilbert vertex order from
//! [`HILBERT_FROM`] vertices) → [`Mesh`] (adjacency, tags, components, point location,
//! quality report).
//!
//! ```
//! use harmonic_mesh::{Domain, DomainSpec, GoalShape, MeshOptions, Point, Shape};
//!
//! let spec = DomainSpec {
//!     workspace: vec![Point::new(0.0, 0.0), Point::new(4.0, 0.0), Point::new(4.0, 4.0), Point::new(0.0, 4.0)],
//!     obstacles: vec![Shape::Circle { center: Point::new(2.0, 2.0), radius: 0.5 }],
//!     goals: vec![GoalShape::Point(Point::new(3.5, 3.5))],
//!     robot_radius: 0.0,
//! };
//! let opts = MeshOptions { max_area: Some(0.05), ..MeshOptions::default() };
//! let domain = Domain::new(&spec, &opts)?;
//! let (mesh, report) = domain.mesh(&opts)?;
//! assert!(report.refinement_complete);
//! let q = mesh.quality();
//! assert!(q.min_angle_deg >= 29.9);
//! assert_eq!(q.holes, 2); // the obstacle and the goal
//! assert!(mesh.locate(Point::new(0.5, 0.5), None).is_some());
//! assert!(mesh.locate(Point::new(2.0, 2.0), None).is_none()); // inside the obstacle
//! # Ok::<(), harmonic_mesh::MeshError>(())
//! ```

#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod domain;
mod frame;
pub mod geom;
mod grading;
mod halves;
pub mod io;
mod options;
pub mod quadtree;
mod refine_uniform;
mod seam_refine;
mod touch;
mod triangulate;

pub use domain::{Domain, DomainSpec, GoalShape, Region, Shape, TaggedRing};
pub use frame::Frame;
pub use harmonic_types::{
    BoundaryEdge, BoundaryTag, Mesh, MeshDataError, MeshHierarchy, NO_NEIGHBOR, Part, Point,
    QualityReport, Vector,
};
pub use options::{Bridges, Grading, MAX_MIN_ANGLE_DEG, MIN_VERTEX_BUDGET, MeshOptions};
pub use refine_uniform::{RefineUniformly, Refinement, uniform_hierarchy};
pub use triangulate::{HILBERT_FROM, MeshReport, SeamRefinements};

/// Everything that can go wrong while building a domain or a mesh.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// Mesh data handed to [`Mesh::from_parts`] (or read from a file) is inconsistent.
    #[error("invalid mesh: {0}")]
    InvalidMesh(#[from] MeshDataError),
    /// A mesh to plan in, given as it is, has no closed boundary loop.
    #[error("the mesh has no closed boundary loop")]
    NoBoundaryLoop,
    /// A quadtree's block grid does not hold `width × height` blocks, or more than it can mesh.
    #[error(
        "a {width} × {height} block grid with {blocks} blocks: it needs width × height blocks, at most {max}"
    )]
    BlockGridSize {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
        /// How many blocks were given.
        blocks: usize,
        /// The most blocks a grid may hold.
        max: usize,
    },
    /// A quadtree's block grid has no free block: there is nothing to mesh.
    #[error("the block grid has no free block")]
    NoFreeBlock,
    /// A coordinate (or radius) is NaN or infinite.
    #[error("{part}: vertex {vertex} has a non-finite coordinate")]
    NonFinite {
        /// The input shape that holds the coordinate.
        part: Part,
        /// Index of the offending vertex in that shape's input list (0 for a circle).
        vertex: usize,
    },
    /// Fewer than three distinct vertices.
    #[error("{part}: polygon has {count} distinct vertices, at least 3 are needed")]
    TooFewVertices {
        /// The input polygon.
        part: Part,
        /// How many distinct vertices it has.
        count: usize,
    },
    /// Two non-adjacent edges of a polygon touch or cross (edge `k` runs from input vertex `k`).
    #[error("{part}: polygon self-intersects (edges {} and {})", edges.0, edges.1)]
    SelfIntersection {
        /// The input polygon.
        part: Part,
        /// The two edges (by input index of their first vertex) that touch or cross.
        edges: (usize, usize),
    },
    /// Two rings of free space given as rings ([`Domain::of_rings`]) touch or cross.
    #[error("{part} and {other} touch or cross: free space given as rings needs disjoint rings")]
    RingsMeet {
        /// One ring.
        part: Part,
        /// The other (the same part when a ring meets itself).
        other: Part,
    },
    /// A hole of free space given as rings ([`Domain::of_rings`]) lies inside another hole.
    #[error("{part}: lies inside {other}")]
    HoleInHole {
        /// The inner hole.
        part: Part,
        /// The hole around it.
        other: Part,
    },
    /// The polygon encloses no area (all its vertices are collinear).
    #[error("{part}: polygon has zero area (all vertices collinear)")]
    ZeroArea {
        /// The input polygon.
        part: Part,
    },
    /// A circle radius that is not positive and finite.
    #[error("{part}: circle radius {radius} must be positive and finite")]
    InvalidRadius {
        /// The circular obstacle or goal.
        part: Part,
        /// The radius given, in workspace units.
        radius: f64,
    },
    /// An obstacle or goal lies entirely outside the workspace.
    #[error("{part}: lies outside the workspace")]
    OutsideWorkspace {
        /// The obstacle or goal.
        part: Part,
    },
    /// A goal lies entirely inside obstacles (inflated by the robot radius, if any).
    #[error(
        "goal {goal}: lies inside obstacle {obstacle} (after inflating obstacles by the robot radius)"
    )]
    GoalInObstacle {
        /// Index of the goal in [`DomainSpec::goals`].
        goal: usize,
        /// Index of an obstacle covering it in [`DomainSpec::obstacles`].
        obstacle: usize,
    },
    /// The robot radius is negative or not finite.
    #[error("robot radius {0} must be finite and non-negative")]
    InvalidRobotRadius(f64),
    /// Nothing of the workspace is left once obstacles (and goals) are removed.
    #[error(
        "no free space is left: obstacles inflated by the robot radius {robot_radius} cover the workspace"
    )]
    NoFreeSpace {
        /// The robot radius the obstacles were inflated by, in workspace units.
        robot_radius: f64,
    },
    /// A goal does not touch the free space left for a robot of the given radius.
    #[error(
        "goal {goal}: not reachable by a robot of radius {robot_radius} (it touches no free space)"
    )]
    GoalNotInFreeSpace {
        /// Index of the goal in [`DomainSpec::goals`].
        goal: usize,
        /// The robot radius, in workspace units.
        robot_radius: f64,
    },
    /// An option has a value outside its allowed range.
    #[error("mesh option {name} = {value}: {reason}")]
    InvalidOption {
        /// The option's field name in [`MeshOptions`] (e.g. `grading.radius`).
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is required of it.
        reason: &'static str,
    },
    /// The requested mesh would exceed the triangle budget.
    #[error(
        "mesh would need about {estimated} triangles, more than the limit of {limit} (raise max_area or max_triangles)"
    )]
    TooManyTriangles {
        /// The triangle count estimated from the free area and `max_area`.
        estimated: usize,
        /// [`MeshOptions::max_triangles`].
        limit: usize,
    },
    /// The scene is so small or so large that its mesh cannot be written in its own
    /// coordinates (triangle areas below f64's normal range, or squared coordinates
    /// overflowing); meshing itself works in unit coordinates at any scale.
    #[error(
        "scene of size {size:e} is out of f64's range for its mesh: triangles of edge {edge:e} would have areas below 1e-304 or coordinates would overflow when squared (express the scene in other units)"
    )]
    ScaleOutOfRange {
        /// The workspace's larger side.
        size: f64,
        /// The smallest edge length expected in the mesh, in scene units.
        edge: f64,
    },
    /// The mesh would exceed the triangle budget mostly because of one obstacle's detail.
    #[error(
        "obstacle {obstacle} has {vertices} vertices: the mesh would need about {estimated} triangles, more than the limit of {limit} (set mesh.simplify to about {suggest:.2e} to coarsen it, or raise max_triangles)"
    )]
    TooDetailed {
        /// The obstacle (input index) whose boundary detail dominates the estimate.
        obstacle: usize,
        /// Its vertices on free space's boundary.
        vertices: usize,
        /// The estimated triangle count.
        estimated: usize,
        /// [`MeshOptions::max_triangles`].
        limit: usize,
        /// A `mesh.simplify` tolerance (scene units) that coarsens it to about the target
        /// edge length.
        suggest: f64,
    },
    /// The triangulation library failed on the (already validated) boundary.
    #[error("triangulation failed: {0}")]
    Triangulation(String),
    /// A file is wrong as a whole rather than on one line (a `.poly` whose segments do not
    /// close the outer boundary, a mesh file with no triangles).
    #[error("{file}: {message}")]
    Input {
        /// The file's path (or kind).
        file: String,
        /// What is wrong, naming the vertices, segments or lines concerned.
        message: String,
    },
    /// A triangle of an imported mesh has zero area.
    #[error("{file}: triangle {triangle} has zero area (its vertices are collinear)")]
    DegenerateTriangle {
        /// The mesh file.
        file: String,
        /// The triangle, numbered as in the file.
        triangle: usize,
    },
    /// An edge of an imported mesh is shared by more than two triangles, or two triangles
    /// overlap along it.
    #[error(
        "{file}: edge ({a}, {b}) is shared by {count} triangles or by two on the same side (the mesh is not a manifold)"
    )]
    NonManifoldEdge {
        /// The mesh file.
        file: String,
        /// One end, numbered as in the file.
        a: usize,
        /// The other end, numbered as in the file.
        b: usize,
        /// How many triangles use it.
        count: usize,
    },
    /// A vertex of an imported mesh that no triangle uses.
    #[error("{file}: vertex {vertex} is used by no triangle")]
    UnusedVertex {
        /// The mesh file.
        file: String,
        /// The vertex, numbered as in the file.
        vertex: usize,
    },
    /// An interior constraint given to [`Domain::with_constraints`] is unusable.
    #[error("constraint {what} {index}: {reason}")]
    Constraint {
        /// `segment` or `point`.
        what: &'static str,
        /// Its position in the list given.
        index: usize,
        /// What is wrong.
        reason: &'static str,
    },
    /// A Triangle `.node/.ele/.poly` file could not be read or written.
    #[error("{file}: line {line}: {message}")]
    Io {
        /// Which file: its path, or its kind (`.node`, `.ele`, `.poly`) when parsing text, or
        /// `marker` for a tag with no Triangle boundary marker.
        file: String,
        /// The line the problem is on (0 when it concerns the whole file).
        line: usize,
        /// What is wrong.
        message: String,
    },
}
