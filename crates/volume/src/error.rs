//! Everything that can go wrong while validating solids, meshing a volume or writing files.

pub use harmonic_types::Part;

/// Errors of this crate. Each names what is wrong and where.
#[derive(Debug, thiserror::Error)]
pub enum VolumeError {
    /// A number of the input is NaN or infinite.
    #[error("{solid}: {what} is not a finite number")]
    NonFinite {
        /// The solid.
        solid: Part,
        /// Which number ("box min", "vertex 3", ...).
        what: String,
    },
    /// A box with `min > max` on some axis (or of zero extent).
    #[error("{solid}: box min {min} is not below max {max} on axis {axis}")]
    InvertedBox {
        /// The solid.
        solid: Part,
        /// 0, 1 or 2 for x, y, z.
        axis: usize,
        /// The box's min on that axis.
        min: f64,
        /// The box's max on that axis.
        max: f64,
    },
    /// A sphere radius ≤ 0.
    #[error("{solid}: sphere radius {radius} must be positive")]
    BadRadius {
        /// The solid.
        solid: Part,
        /// The radius given.
        radius: f64,
    },
    /// A triangle surface with no triangles.
    #[error("{solid}: the triangle surface has no triangles")]
    EmptySurface {
        /// The solid.
        solid: Part,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "{solid}: triangle {triangle} refers to vertex {vertex}, but there are {count} vertices"
    )]
    BadVertexIndex {
        /// The solid.
        solid: Part,
        /// The triangle.
        triangle: usize,
        /// The bad index.
        vertex: u32,
        /// The number of vertices.
        count: usize,
    },
    /// A triangle with a repeated vertex or zero area.
    #[error("{solid}: triangle {triangle} is degenerate (repeated vertex or zero area)")]
    DegenerateTriangle {
        /// The solid.
        solid: Part,
        /// The triangle.
        triangle: usize,
    },
    /// Two triangles without a common vertex touch or cross: the surface intersects itself.
    #[error(
        "{solid}: triangles {} and {} cross each other: the surface intersects itself",
        triangles[0],
        triangles[1]
    )]
    SelfIntersecting {
        /// The solid.
        solid: Part,
        /// The two triangles.
        triangles: [usize; 2],
    },
    /// An edge used by one triangle only: the surface is not closed.
    #[error("{solid}: edge ({}, {}) belongs to one triangle only (triangle {triangle}): the surface is not closed", edge[0], edge[1])]
    OpenEdge {
        /// The solid.
        solid: Part,
        /// The edge's vertices.
        edge: [u32; 2],
        /// The one triangle using it.
        triangle: usize,
    },
    /// An edge used by more than two triangles.
    #[error("{solid}: edge ({}, {}) belongs to {count} triangles: the surface is not manifold", edge[0], edge[1])]
    NonManifoldEdge {
        /// The solid.
        solid: Part,
        /// The edge's vertices.
        edge: [u32; 2],
        /// How many triangles use it.
        count: usize,
    },
    /// Two triangles traverse a shared edge in the same direction.
    #[error("{solid}: triangles {first} and {second} traverse edge ({}, {}) in the same direction: the surface is not consistently oriented", edge[0], edge[1])]
    InconsistentOrientation {
        /// The solid.
        solid: Part,
        /// The directed edge.
        edge: [u32; 2],
        /// One triangle.
        first: usize,
        /// The other.
        second: usize,
    },
    /// parry3d refused the surface.
    #[error("{solid}: the triangle surface was refused: {message}")]
    Surface {
        /// The solid.
        solid: Part,
        /// parry3d's message.
        message: String,
    },
    /// A robot radius that is negative or not finite.
    #[error("robot radius {radius} must be a finite number ≥ 0")]
    BadRobotRadius {
        /// The radius.
        radius: f64,
    },
    /// The robot does not fit: shrinking the workspace by its radius leaves nothing.
    #[error("the workspace shrunk by the robot radius {radius} is empty")]
    EmptyWorkspace {
        /// The robot radius.
        radius: f64,
    },
    /// A goal lies in an obstacle grown by the robot's radius.
    #[error(
        "goal {goal} lies in obstacle {obstacle} (grown by the robot radius {radius}): move it into free space"
    )]
    GoalInObstacle {
        /// The goal.
        goal: usize,
        /// The obstacle.
        obstacle: usize,
        /// The robot's radius.
        radius: f64,
    },
    /// A goal lies outside the workspace shrunk by the robot's radius.
    #[error(
        "goal {goal} lies outside the workspace (shrunk by the robot radius {radius}): move it inside"
    )]
    GoalOutsideWorkspace {
        /// The goal.
        goal: usize,
        /// The robot's radius.
        radius: f64,
    },
    /// Refinement toward a goal stopped at the tetrahedron budget before the goal held a
    /// whole tetrahedron.
    #[error(
        "goal {goal} could not be resolved within the budget of {budget} tetrahedra: raise mesh.max_tetrahedra or widen the goal"
    )]
    GoalNotResolved {
        /// The goal.
        goal: usize,
        /// The tetrahedron budget.
        budget: u64,
    },
    /// The robot's radius leaves no free space (sampled on a 48³ grid).
    #[error(
        "robot.radius {radius} leaves no free space: the obstacles grown by it and the workspace shrunk by it cover everything; use a smaller robot or set mesh.max_volume to look closer"
    )]
    RobotTooBig {
        /// The robot's radius.
        radius: f64,
    },
    /// No goal was given.
    #[error("the scene has no goal region")]
    NoGoal,
    /// `mesh.max_volume` not a positive finite number.
    #[error("mesh.max_volume = {value} must be a positive finite number")]
    BadMaxVolume {
        /// The value.
        value: f64,
    },
    /// The mesh would exceed the tetrahedron budget.
    #[error(
        "the mesh would have about {estimated} tetrahedra, more than the budget of {budget}; raise mesh.max_volume"
    )]
    TooManyTetrahedra {
        /// The estimate (from the lattice size).
        estimated: u64,
        /// The budget.
        budget: u64,
    },
    /// Meshing produced no tetrahedra: free space is empty at this resolution.
    #[error(
        "free space is empty at lattice spacing {spacing} (obstacles cover the workspace, or it is thinner than the mesh)"
    )]
    NoFreeSpace {
        /// The lattice spacing used.
        spacing: f64,
    },
    /// A tetrahedral mesh given by parts is invalid.
    #[error("invalid tetrahedral mesh: {0}")]
    InvalidMesh(#[from] harmonic_types::MeshDataError),
    /// Data written beside a mesh (VTK point data) does not have one entry per vertex.
    #[error("point data `{name}` has {entries} entries for {vertices} vertices")]
    PointDataLength {
        /// The data's name.
        name: String,
        /// How many entries it has.
        entries: usize,
        /// How many vertices the mesh has.
        vertices: usize,
    },
    /// A periodic lattice with fewer than 3 cells along a periodic axis (a tetrahedron would
    /// meet its own copy).
    #[error("a periodic axis needs at least 3 lattice cells, got {cells}")]
    PeriodicCells {
        /// The cells along that axis.
        cells: usize,
    },
    /// Writing a file failed.
    #[error("writing {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The underlying error.
        source: std::io::Error,
    },
}

impl VolumeError {
    /// The same error about goal `j` (goal errors are built before the goal is known).
    pub(crate) fn for_goal(self, j: usize) -> Self {
        match self {
            VolumeError::GoalInObstacle {
                obstacle, radius, ..
            } => VolumeError::GoalInObstacle {
                goal: j,
                obstacle,
                radius,
            },
            VolumeError::GoalOutsideWorkspace { radius, .. } => {
                VolumeError::GoalOutsideWorkspace { goal: j, radius }
            }
            VolumeError::GoalNotResolved { budget, .. } => {
                VolumeError::GoalNotResolved { goal: j, budget }
            }
            e => e,
        }
    }
}
