//! What can be wrong with mesh data handed to [`Mesh`](crate::Mesh) or
//! [`TetMesh`](crate::TetMesh).

/// The kind of element a mesh is made of, to name it in errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Element {
    /// A triangle of a planar mesh.
    Triangle,
    /// A tetrahedron of a volume mesh.
    Tetrahedron,
}

impl std::fmt::Display for Element {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Element::Triangle => "triangle",
            Element::Tetrahedron => "tetrahedron",
        })
    }
}

/// Inconsistent mesh data: each variant names the element, vertex, edge or face at fault.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MeshDataError {
    /// A vertex has a NaN or infinite coordinate.
    #[error("vertex {vertex} is not finite")]
    NonFiniteVertex {
        /// The vertex's index.
        vertex: usize,
    },
    /// An element refers to a vertex that does not exist.
    #[error("{element} {index} refers to vertex {vertex}, but there are {vertices} vertices")]
    VertexOutOfRange {
        /// Triangle or tetrahedron.
        element: Element,
        /// The element's index.
        index: usize,
        /// The vertex index it holds.
        vertex: u32,
        /// How many vertices there are.
        vertices: usize,
    },
    /// An element is clockwise (inverted) or degenerate: its signed area or volume is not
    /// positive.
    #[error(
        "{element} {index} {vertices:?} is not positively oriented (clockwise, inverted or degenerate)"
    )]
    NotPositive {
        /// Triangle or tetrahedron.
        element: Element,
        /// The element's index.
        index: usize,
        /// Its vertices (a triangle's fourth is `u32::MAX`).
        vertices: [u32; 4],
    },
    /// Two triangles use one edge in the same direction (they overlap or one is flipped).
    #[error("edge ({}, {}) is used twice in the same direction (near triangle {triangle})", edge[0], edge[1])]
    EdgeUsedTwice {
        /// The directed edge.
        edge: [u32; 2],
        /// One of the triangles.
        triangle: usize,
    },
    /// A face is shared by more than two tetrahedra.
    #[error("face {face:?} is shared by {count} tetrahedra")]
    FaceSharedTooOften {
        /// The face's sorted vertices.
        face: [u32; 3],
        /// How many tetrahedra share it.
        count: usize,
    },
    /// Neighbour lists given with the elements do not match them in number.
    #[error("{given} neighbour lists for {elements} {element}s")]
    NeighborCount {
        /// Triangle or tetrahedron.
        element: Element,
        /// How many neighbour lists were given.
        given: usize,
        /// How many elements there are.
        elements: usize,
    },
    /// A neighbour given across an edge does not have that edge.
    #[error("triangle {triangle}: neighbour {neighbor} across edge ({}, {}) does not share it", edge[0], edge[1])]
    NeighborMismatch {
        /// The triangle.
        triangle: usize,
        /// The neighbour it names.
        neighbor: u32,
        /// The edge.
        edge: [u32; 2],
    },
    /// A boundary edge has no tag among those given.
    #[error("boundary edge ({}, {}) of triangle {triangle} has no boundary tag", edge[0], edge[1])]
    UntaggedEdge {
        /// The edge.
        edge: [u32; 2],
        /// Its triangle.
        triangle: usize,
    },
    /// Tags were given for edges that are not boundary edges.
    #[error("{given} tagged edges given but the mesh has {boundary} boundary edges")]
    TagCount {
        /// How many tagged edges were given.
        given: usize,
        /// How many boundary edges the mesh has.
        boundary: usize,
    },
    /// More vertices or elements than the mesh's 32-bit indices hold.
    #[error("{vertices} vertices and {elements} {element}s: more than 32-bit indices hold")]
    TooLarge {
        /// Triangle or tetrahedron.
        element: Element,
        /// How many vertices.
        vertices: usize,
        /// How many elements.
        elements: usize,
    },
    /// A mesh hierarchy whose levels and parent lists do not match in number.
    #[error(
        "{levels} levels and {parents} parent lists: a hierarchy needs one level more than parent lists, and at least one"
    )]
    LevelCount {
        /// How many levels.
        levels: usize,
        /// How many parent lists.
        parents: usize,
    },
    /// A parent list of a mesh hierarchy without one entry per vertex of its level.
    #[error("level {level}: {given} parent pairs for {vertices} vertices")]
    ParentCount {
        /// The finer level.
        level: usize,
        /// How many parent pairs.
        given: usize,
        /// How many vertices it has.
        vertices: usize,
    },
}
