//! Inputs other tools make: Triangle's `.poly` files (planar straight line graphs) as scenes,
//! and meshes made by Triangle (`.node/.ele`) or gmsh (`.msh`) planned on as they are.
//!
//! A `.poly` becomes a [`PolyScene`]: its outer boundary the workspace, the regions around
//! its hole points obstacles, its other segments and vertices constraints the mesh must hold
//! ([`harmonic_mesh::io::poly`]); the goal is a point. A mesh made elsewhere is read into an
//! [`ImportedMesh`] (validated, boundary edges with their markers or physical groups) and
//! planned on by [`mesh_planner`], the goal either a boundary tag (those edges held at
//! φ = 0, every other boundary edge at φ = 1) or a point (held at the vertices of its
//! triangle, as [`crate::Workspace`] does).
//!
//! ```
//! use harmonic_planner::inputs::{MeshGoal, PolyScene, mesh_planner, read_mesh};
//! use harmonic_planner::PlannerOptions;
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
//! // A Triangle .poly with two hexagonal holes, the goal a point.
//! let poly = PolyScene::read(&root.join("meshes/triangle/two_hex.poly"), [3.8, 1.8])?;
//! let planner = poly.planner(&PlannerOptions::default())?;
//! assert!(planner.plan([0.2, 0.2]).status.reached_goal());
//! // A gmsh mesh, the goal its physical group "exit".
//! let mesh = read_mesh(&root.join("meshes/gmsh/room.msh"))?;
//! let planner = mesh_planner(&mesh, &MeshGoal::Tag("exit".into()), &PlannerOptions::default())?;
//! assert!(planner.plan([0.3, 1.0]).status.reached_goal());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::Path;

use harmonic_mesh::io::poly::Pslg;
pub use harmonic_mesh::io::{ImportedMesh, poly::PslgFreeSpace};

use crate::planner::{PlanError, Planner, PlannerOptions};
use crate::scene::{Goals, Region, Scene};
use crate::workspace::{Goal, Workspace};
use crate::{Point, scene};

/// A Triangle `.poly` file as a scene: its free space's outer boundary and holes, its
/// interior constraints, and a goal point.
#[derive(Clone, Debug, PartialEq)]
pub struct PolyScene {
    /// The scene: workspace, obstacles (the holes), the goal point; default conditions and
    /// mesh options.
    pub scene: Scene,
    /// Segments inside free space the mesh holds as edges.
    pub constraint_segments: Vec<[Point; 2]>,
    /// Vertices inside free space the mesh holds.
    pub constraint_points: Vec<Point>,
}

fn ring(points: &[Point]) -> Vec<[f64; 2]> {
    points.iter().map(|p| [p.x, p.y]).collect()
}

impl PolyScene {
    /// Reads `FILE.poly` (and `FILE.node` if the `.poly` lists no vertices) with the goal
    /// point `goal`.
    pub fn read(path: &Path, goal: [f64; 2]) -> Result<PolyScene, PlanError> {
        let free = Pslg::read(path)?.free_space()?;
        Ok(PolyScene::of(&free, goal))
    }

    /// The scene of a `.poly`'s free space with the goal point `goal`.
    pub fn of(free: &PslgFreeSpace, goal: [f64; 2]) -> PolyScene {
        let scene = Scene {
            name: None,
            workspace: ring(&free.workspace),
            obstacles: free
                .holes
                .iter()
                .map(|h| Region {
                    polygon: Some(ring(h)),
                    ..Region::default()
                })
                .collect(),
            goal: Goals(vec![Region {
                point: Some(goal),
                ..Region::default()
            }]),
            starts: Vec::new(),
            boundary: scene::BoundarySpec::default(),
            mesh: scene::MeshSpec::default(),
            robot: scene::RobotSpec::default(),
        };
        PolyScene {
            scene,
            constraint_segments: free.constraint_segments.clone(),
            constraint_points: free.constraint_points.clone(),
        }
    }

    /// Meshes (with the constraints), solves and returns the planner.
    pub fn planner(&self, options: &PlannerOptions) -> Result<Planner, PlanError> {
        Planner::with_constraints(
            &self.scene,
            &self.constraint_segments,
            &self.constraint_points,
            options,
        )
    }
}

/// Reads a mesh made elsewhere: a gmsh `.msh` file (by its extension), else Triangle's
/// `BASE.node` and `BASE.ele` (with `BASE.poly` or `BASE.edge` for boundary markers, if
/// there); `path` may be `BASE` or any of those files.
pub fn read_mesh(path: &Path) -> Result<ImportedMesh, PlanError> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("msh") => Ok(harmonic_mesh::io::msh::read_msh(path)?),
        Some("node" | "ele" | "poly" | "edge") => Ok(harmonic_mesh::io::read_triangle_mesh(
            &path.with_extension(""),
        )?),
        _ => Ok(harmonic_mesh::io::read_triangle_mesh(path)?),
    }
}

/// Where the goal of a mesh made elsewhere is.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshGoal {
    /// The boundary edges of this marker or physical group (a number, or a gmsh physical
    /// name).
    Tag(String),
    /// A point of the mesh (held at the free vertices of its triangle).
    Point([f64; 2]),
}

/// A planner on `mesh` for `goal`: the same assembly, solve and tracers as a scene's.
pub fn mesh_planner(
    mesh: &ImportedMesh,
    goal: &MeshGoal,
    options: &PlannerOptions,
) -> Result<Planner, PlanError> {
    match goal {
        MeshGoal::Tag(tag) => {
            let marker = mesh.marker(tag)?;
            Planner::from_mesh(mesh.to_mesh(Some(marker))?, options)
        }
        MeshGoal::Point(p) => {
            let workspace = Workspace::from_mesh(mesh.to_mesh(None)?, options)?;
            workspace.planner(&Goal::point(*p))
        }
    }
}
