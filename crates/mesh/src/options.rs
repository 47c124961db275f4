//! What a mesh is asked to be: [`MeshOptions`] (area and angle bounds, budget, prefill,
//! bridge splitting, two halves) and its local refinement, [`Grading`]. Both [`Domain::new`]
//! (circle discretisation) and [`Domain::mesh`] read them.
//!
//! [`Domain::new`]: crate::Domain::new
//! [`Domain::mesh`]: crate::Domain::mesh

use serde::{Deserialize, Serialize};

use crate::MeshError;

/// The fewest vertices refinement may add to a mesh, whatever its estimate (the vertex
/// budget is twice the estimated triangle count, and at least this). A gap between two
/// boundaries much narrower than the target edge — a box 0.6 mm off a wall of a 10 m room —
/// needs small triangles of its own that the estimate does not see; 10 000 were too few for
/// that one.
pub const MIN_VERTEX_BUDGET: usize = 20_000;

/// The largest minimum angle accepted: Delaunay refinement does not terminate reliably above it.
pub const MAX_MIN_ANGLE_DEG: f64 = 33.0;

/// Meshing parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MeshOptions {
    /// Largest triangle area; `None` chooses free area / 20000.
    pub max_area: Option<f64>,
    /// Smallest angle wanted in the refined mesh, in degrees (0 to 33; default 30). Input
    /// corners sharper than this stay as they are.
    pub min_angle_deg: f64,
    /// Budget: a mesh estimated to need more triangles is refused at once (default 20 M).
    pub max_triangles: usize,
    /// Seed the interior with a triangular lattice (triangle area 0.6 × `max_area`, boundary
    /// segments pre-split to the lattice spacing) and bulk-load it before refinement (default
    /// false). Interior triangles are then equilateral; the run time is about the same as
    /// plain refinement (spade's refinement pass over all faces dominates either way), and the
    /// pre-split corners need bridge splitting (and another refinement pass) more often.
    pub prefill: bool,
    /// Split every interior edge whose two end vertices lie on the boundary (a "bridge"):
    /// a bridge carries no unknown when the boundary is Dirichlet, and across a passage one
    /// triangle wide it seals the passage. Ears (a triangle with two boundary edges at a
    /// corner) are left alone: their third edge seals nothing. Up to 8 rounds;
    /// [`MeshReport::bridges_remaining`] counts what is left (sharp input corners). What
    /// follows a split is [`Bridges`]'s choice (default [`Bridges::Refined`]).
    ///
    /// [`MeshReport::bridges_remaining`]: crate::MeshReport::bridges_remaining
    pub bridges: Bridges,
    /// Smaller triangles near the goals and at obstacle corners (default `None`: the area
    /// bound is `max_area` everywhere). See [`Grading`].
    pub grading: Option<Grading>,
    /// Meshes estimated to have at least this many triangles are made as two halves on two
    /// threads of rayon's pool (one after the other in a pool of one thread: the same mesh),
    /// glued along a cut (default 250 000; `usize::MAX` never). Not with grading or prefill.
    pub halves_from: usize,
    /// Simplify detailed obstacle polygons before meshing: vertices are dropped while the
    /// simplified boundary stays within this distance (workspace units) of the original, and
    /// the simplified obstacle always contains the original one (a conservative
    /// simplification: free space only shrinks). `None` (default): polygons are meshed as
    /// given. The triangle-budget error suggests a value when one polygon's detail is what
    /// exceeds the budget.
    pub simplify: Option<f64>,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            max_area: None,
            min_angle_deg: 30.0,
            max_triangles: 20_000_000,
            prefill: false,
            bridges: Bridges::Refined,
            grading: None,
            halves_from: HALVES_FROM,
            simplify: None,
        }
    }
}

/// How [`MeshOptions::bridges`] splits the interior edges that join two boundary vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Bridges {
    /// Leave bridges as refinement made them.
    Kept,
    /// Split each at its midpoint and refine again (a pass over the whole mesh) where that
    /// spoils the angle or area bound, or puts an obtuse angle opposite a boundary edge.
    /// Every bound holds in the final mesh.
    #[default]
    Refined,
    /// Split each at its midpoint and keep the midpoints as they are. The faces around a
    /// midpoint may then break the angle bound (by about half: splitting an edge of a
    /// 20° mesh leaves angles of 10° and more on Nav2's maps) and may put an obtuse angle
    /// opposite a boundary edge, which couples two boundary vertices only: the matrix on
    /// the unknowns stays an M-matrix where the boundary is Dirichlet, as a map's walls
    /// are. A fifth to a quarter fewer triangles on small maps, and no second refinement.
    Midpoints,
}

/// A local area bound: finer triangles at goal boundaries and at obstacle corners, growing
/// back to the global `max_area` with the distance from them.
///
/// At distance `d` from the nearest goal boundary the target edge length is that of
/// `max_area` times `a + (1 − a)·min(d / radius, 1)` with `a = √near_goal` (it grows linearly
/// from the goal boundary and is the uniform one beyond `radius`); likewise with
/// `near_corners` around each obstacle corner (a vertex of an obstacle boundary where the
/// boundary turns by more than 35°, so the vertices of discretised circles do not count).
/// The local area bound is the square of the smaller factor times `max_area`.
///
/// Delaunay refinement (spade) only knows one area bound, so the grading is a second pass:
/// every free triangle larger than the local bound at its centroid gets its centroid
/// inserted, and refinement (same angle bound) runs again, until no triangle is too large
/// (at most 40 rounds; [`MeshReport::refinement_complete`] is false if any is left). The
/// minimum angle, boundary tags and bridge splitting are as without grading.
///
/// [`MeshReport::refinement_complete`]: crate::MeshReport::refinement_complete
///
/// ```
/// use harmonic_mesh::{Domain, DomainSpec, GoalShape, Grading, MeshOptions, Point};
///
/// let p = Point::new;
/// let spec = DomainSpec {
///     workspace: vec![p(0.0, 0.0), p(4.0, 0.0), p(4.0, 4.0), p(0.0, 4.0)],
///     obstacles: vec![],
///     goals: vec![GoalShape::Circle { center: p(3.0, 3.0), radius: 0.2 }],
///     robot_radius: 0.0,
/// };
/// let uniform = MeshOptions { max_area: Some(0.05), ..MeshOptions::default() };
/// let graded = MeshOptions {
///     grading: Some(Grading { near_goal: 0.05, near_corners: 1.0, radius: 1.0 }),
///     ..uniform.clone()
/// };
/// let domain = Domain::new(&spec, &graded)?;
/// let (coarse, _) = domain.mesh(&uniform)?;
/// let (fine, report) = domain.mesh(&graded)?;
/// assert!(report.refinement_complete);
/// assert!(fine.triangles().len() > coarse.triangles().len());
/// assert!(fine.quality().min_angle_deg >= 29.9);
/// # Ok::<(), harmonic_mesh::MeshError>(())
/// ```
///
/// In JSON the two factors may be left out (1: none); unknown fields are errors.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Grading {
    /// Area bound at the goal boundaries relative to `max_area`, in `(0, 1]` (1: no grading
    /// at goals). E.g. 0.1: triangles there are at most a tenth of `max_area`.
    #[serde(default = "no_grading")]
    pub near_goal: f64,
    /// Area bound at obstacle corners relative to `max_area`, in `(0, 1]` (1: none).
    #[serde(default = "no_grading")]
    pub near_corners: f64,
    /// Distance (workspace units) over which the edge length grows back to the uniform one;
    /// positive and finite.
    pub radius: f64,
}

/// The area factor that grades nothing.
fn no_grading() -> f64 {
    1.0
}

impl MeshOptions {
    /// Checks the ranges of the options.
    pub fn validate(&self) -> Result<(), MeshError> {
        if !(self.min_angle_deg.is_finite() && self.min_angle_deg >= 0.0) {
            return Err(MeshError::InvalidOption {
                name: "min_angle_deg",
                value: self.min_angle_deg,
                reason: "must be a finite angle of at least 0 degrees",
            });
        }
        if self.min_angle_deg > MAX_MIN_ANGLE_DEG {
            return Err(MeshError::InvalidOption {
                name: "min_angle_deg",
                value: self.min_angle_deg,
                reason: "must be at most 33 degrees (Delaunay refinement does not terminate above)",
            });
        }
        if let Some(a) = self.max_area
            && !(a.is_finite() && a > 0.0)
        {
            return Err(MeshError::InvalidOption {
                name: "max_area",
                value: a,
                reason: "must be positive and finite",
            });
        }
        if let Some(t) = self.simplify
            && !(t.is_finite() && t > 0.0)
        {
            return Err(MeshError::InvalidOption {
                name: "simplify",
                value: t,
                reason: "must be a positive and finite distance",
            });
        }
        if let Some(g) = &self.grading {
            for (name, value) in [
                ("grading.near_goal", g.near_goal),
                ("grading.near_corners", g.near_corners),
            ] {
                if !(value > 0.0 && value <= 1.0) {
                    return Err(MeshError::InvalidOption {
                        name,
                        value,
                        reason: "must be an area factor in (0, 1]",
                    });
                }
            }
            if !(g.radius.is_finite() && g.radius > 0.0) {
                return Err(MeshError::InvalidOption {
                    name: "grading.radius",
                    value: g.radius,
                    reason: "must be positive and finite",
                });
            }
        }
        if self.max_triangles == 0 {
            return Err(MeshError::InvalidOption {
                name: "max_triangles",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        Ok(())
    }
}

/// Estimated triangle count from which [`Domain::mesh`](crate::Domain::mesh) makes the mesh
/// in two halves.
const HALVES_FROM: usize = 250_000;
