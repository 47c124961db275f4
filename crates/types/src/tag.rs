//! What a boundary edge (plane) or face (volume) lies on.

use serde::{Deserialize, Serialize};

/// What a boundary edge or face of free space lies on.
///
/// Obstacle and goal indices are the positions of the obstacle or goal in the input
/// (before overlapping obstacles were merged), so per-obstacle boundary conditions keep
/// their meaning.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum BoundaryTag {
    /// The outer boundary of the workspace.
    Wall,
    /// The boundary of input obstacle `i`.
    Obstacle(u32),
    /// The boundary of input goal region `j`.
    Goal(u32),
}

impl std::fmt::Display for BoundaryTag {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BoundaryTag::Wall => write!(f, "wall"),
            BoundaryTag::Obstacle(i) => write!(f, "obstacle {i}"),
            BoundaryTag::Goal(j) => write!(f, "goal {j}"),
        }
    }
}

/// The obstacle index given to the end faces of one period of a periodic mesh (a
/// configuration space's slab, `BoundaryTag::Obstacle(SEAM_PART)`): the finite elements give
/// that part the natural condition (no term) before folding the two ends into one.
pub const SEAM_PART: u32 = u32::MAX;

/// A part of a scene as its input lists it, used to say where an input error is: the
/// workspace, obstacle `i` or goal `j` (their positions in the input), in the plane and in
/// volumes alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Part {
    /// The workspace.
    Workspace,
    /// Input obstacle `i`.
    Obstacle(usize),
    /// Input goal `j`.
    Goal(usize),
}

impl std::fmt::Display for Part {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Part::Workspace => write!(f, "workspace"),
            Part::Obstacle(i) => write!(f, "obstacle {i}"),
            Part::Goal(j) => write!(f, "goal {j}"),
        }
    }
}
