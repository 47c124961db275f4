//! A volume scene (`"dimension": 3`), field for field as in the scene format; its
//! conversion to a [`VolumeDomain`] and to the boundary conditions of the finite elements.
//!
//! ```
//! use harmonic_planner::scene::VolumeScene;
//! let spec: VolumeScene = serde_json::from_str(r#"{
//!     "name": "torus", "dimension": 3,
//!     "workspace": {"box": {"min": [0, 0, 0], "max": [10, 10, 10]}},
//!     "obstacles": [{"box": {"min": [3, 3, -1], "max": [7, 7, 11]}},
//!                   {"sphere": {"center": [2, 8, 5], "radius": 1.0}, "boundary": {"neumann": 0.0}}],
//!     "goal": {"sphere": {"center": [9, 9, 9], "radius": 0.3}},
//!     "starts": [[1, 1, 1]],
//!     "mesh": {"max_volume": 0.01}
//! }"#)?;
//! let domain = spec.build()?;
//! assert_eq!(domain.obstacles().len(), 2);
//! assert_eq!(spec.max_volume(&domain)?, 0.01);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use harmonic_fem::{BoundaryCondition, BoundaryConditions};
use harmonic_volume::{
    BoxSolid, GoalRegion, Part, Point, Solid, SphereSolid, VolumeDomain, VolumeError,
};
use serde::{Deserialize, Serialize};

use super::{BoundarySpec, RobotSpec, SceneError};

/// A box `{"min": [x, y, z], "max": [x, y, z]}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// The lowest corner.
    pub min: [f64; 3],
    /// The highest corner.
    pub max: [f64; 3],
}

/// A sphere `{"center": [x, y, z], "radius": r}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// The centre.
    pub center: [f64; 3],
    /// The radius.
    pub radius: f64,
}

/// A closed triangle surface `{"vertices": [[x, y, z], ...], "triangles": [[i, j, k], ...]}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    /// The vertices.
    pub vertices: Vec<[f64; 3]>,
    /// The triangles (either orientation, but consistent).
    pub triangles: Vec<[u32; 3]>,
}

/// The workspace: exactly one of `box` and `mesh`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkspaceSpec {
    /// A box workspace.
    #[serde(rename = "box", default, skip_serializing_if = "Option::is_none")]
    pub box_: Option<BoxSpec>,
    /// A closed surface workspace.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<SurfaceSpec>,
}

/// An obstacle: exactly one of `box`, `sphere` and `mesh`, and optionally its own boundary
/// condition.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// A box obstacle.
    #[serde(rename = "box", default, skip_serializing_if = "Option::is_none")]
    pub box_: Option<BoxSpec>,
    /// A ball obstacle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere: Option<SphereSpec>,
    /// A closed surface obstacle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<SurfaceSpec>,
    /// This obstacle's boundary condition (overrides `boundary.obstacles`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundary: Option<BoundaryCondition>,
}

/// A goal region: exactly one of `sphere`, `box` and `point`, and optionally its own
/// boundary condition.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoalSpec {
    /// A ball goal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere: Option<SphereSpec>,
    /// A box goal.
    #[serde(rename = "box", default, skip_serializing_if = "Option::is_none")]
    pub box_: Option<BoxSpec>,
    /// A point goal (a small ball sized from the mesh).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<[f64; 3]>,
    /// This goal's boundary condition (overrides `boundary.goal`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundary: Option<BoundaryCondition>,
}

/// One goal region or several.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum GoalsSpec {
    /// One region.
    One(GoalSpec),
    /// Several regions.
    Many(Vec<GoalSpec>),
}

impl GoalsSpec {
    /// The regions in order.
    pub fn regions(&self) -> &[GoalSpec] {
        match self {
            GoalsSpec::One(g) => std::slice::from_ref(g),
            GoalsSpec::Many(v) => v,
        }
    }
}

/// `mesh`: the largest tetrahedron volume.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VolumeMeshSpec {
    /// Largest tetrahedron volume (default: free volume / 200 000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_volume: Option<f64>,
}

/// A volume scene as written in a scene file with `"dimension": 3`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VolumeScene {
    /// The scene's name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Must be 3.
    pub dimension: u32,
    /// The workspace.
    pub workspace: WorkspaceSpec,
    /// The obstacles.
    #[serde(default)]
    pub obstacles: Vec<ObstacleSpec>,
    /// The goal region(s).
    pub goal: GoalsSpec,
    /// Query start points.
    #[serde(default)]
    pub starts: Vec<[f64; 3]>,
    /// Boundary conditions.
    #[serde(default)]
    pub boundary: BoundarySpec,
    /// Mesh options.
    #[serde(default)]
    pub mesh: VolumeMeshSpec,
    /// The robot.
    #[serde(default)]
    pub robot: RobotSpec,
}

fn point(p: [f64; 3]) -> Point {
    Point::new(p[0], p[1], p[2])
}

fn surface(role: Part, s: &SurfaceSpec) -> Result<Solid, VolumeError> {
    Solid::new_surface(
        role,
        s.vertices.iter().map(|&p| point(p)).collect(),
        s.triangles.clone(),
    )
}

impl VolumeScene {
    /// Validates the scene and builds its domain. Errors name the part (`obstacle 3: ...`).
    pub fn build(&self) -> Result<VolumeDomain, SceneError> {
        let invalid = |path: String, message: &str| SceneError::Invalid {
            path,
            message: message.to_string(),
        };
        if self.dimension != 3 {
            return Err(invalid(
                "dimension".into(),
                &format!("is {}, a volume scene needs 3", self.dimension),
            ));
        }
        if self.boundary.blend.is_some() {
            return Err(invalid(
                "boundary.blend".into(),
                "the Dirichlet–Neumann blend is planned in the plane only",
            ));
        }
        let ws = &self.workspace;
        let workspace = match (&ws.box_, &ws.mesh) {
            (Some(b), None) => Solid::new_box(Part::Workspace, point(b.min), point(b.max))?,
            (None, Some(m)) => surface(Part::Workspace, m)?,
            _ => {
                return Err(invalid(
                    "workspace".into(),
                    "give exactly one of \"box\" and \"mesh\"",
                ));
            }
        };
        let mut obstacles = Vec::with_capacity(self.obstacles.len());
        for (i, o) in self.obstacles.iter().enumerate() {
            let role = Part::Obstacle(i);
            obstacles.push(match (&o.box_, &o.sphere, &o.mesh) {
                (Some(b), None, None) => Solid::new_box(role, point(b.min), point(b.max))?,
                (None, Some(s), None) => Solid::new_sphere(role, point(s.center), s.radius)?,
                (None, None, Some(m)) => surface(role, m)?,
                _ => {
                    return Err(invalid(
                        format!("obstacles[{i}]"),
                        "give exactly one of \"box\", \"sphere\" and \"mesh\"",
                    ));
                }
            });
        }
        let mut goals = Vec::new();
        for (j, g) in self.goal.regions().iter().enumerate() {
            goals.push(match (&g.sphere, &g.box_, &g.point) {
                (Some(s), None, None) => GoalRegion::Sphere(SphereSolid {
                    center: point(s.center),
                    radius: s.radius,
                }),
                (None, Some(b), None) => GoalRegion::Box(BoxSolid {
                    min: point(b.min),
                    max: point(b.max),
                }),
                (None, None, Some(p)) => GoalRegion::Point(point(*p)),
                _ => {
                    return Err(invalid(
                        format!("goal[{j}]"),
                        "give exactly one of \"sphere\", \"box\" and \"point\"",
                    ));
                }
            });
        }
        Ok(VolumeDomain::new(
            workspace,
            obstacles,
            goals,
            self.robot.radius,
        )?)
    }

    /// `mesh.max_volume`, or free volume / 200 000 when it is not given.
    pub fn max_volume(&self, domain: &VolumeDomain) -> Result<f64, SceneError> {
        let v = match self.mesh.max_volume {
            Some(v) => v,
            None => {
                let free = domain.free_volume_estimate();
                if free <= 0.0 {
                    return Err(VolumeError::RobotTooBig {
                        radius: domain.robot_radius(),
                    }
                    .into());
                }
                free / 200_000.0
            }
        };
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(VolumeError::BadMaxVolume { value: v }.into())
        }
    }

    /// The start points.
    pub fn start_points(&self) -> Vec<Point> {
        self.starts.iter().map(|&p| point(p)).collect()
    }

    /// The scene's boundary conditions: `boundary.walls`, `boundary.obstacles` and
    /// `boundary.goal` (defaults Dirichlet 1, 1, 0) with the per-obstacle and per-goal
    /// overrides.
    ///
    /// ```
    /// use harmonic_planner::fem::BoundaryCondition;
    /// use harmonic_planner::scene::VolumeScene;
    /// let spec: VolumeScene = serde_json::from_str(r#"{"dimension": 3,
    ///     "workspace": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}},
    ///     "obstacles": [{"sphere": {"center": [0.5, 0.5, 0.5], "radius": 0.2}, "boundary": {"neumann": 0.0}}],
    ///     "goal": {"point": [0.1, 0.1, 0.1]},
    ///     "boundary": {"walls": {"robin": {"a": 1.0, "b": 2.0, "g": 2.0}}}}"#)?;
    /// let bcs = spec.conditions();
    /// assert_eq!(bcs.walls, BoundaryCondition::Robin { a: 1.0, b: 2.0, g: 2.0 });
    /// assert_eq!(bcs.obstacle_overrides[&0], BoundaryCondition::Neumann(0.0));
    /// assert_eq!(bcs.goals, BoundaryCondition::Dirichlet(0.0));
    /// # Ok::<(), serde_json::Error>(())
    /// ```
    pub fn conditions(&self) -> BoundaryConditions {
        self.boundary.conditions(
            self.obstacles.iter().map(|o| o.boundary),
            self.goal.regions().iter().map(|g| g.boundary),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_fields_and_bad_parts_are_refused() {
        let bad = r#"{"dimension": 3, "workspace": {"box": {"min": [0,0,0], "max": [1,1,1]}},
                      "goal": {"point": [0.5, 0.5, 0.5]}, "mesh": {"max_area": 0.1}}"#;
        assert!(serde_json::from_str::<VolumeScene>(bad).is_err());
        let two = r#"{"dimension": 3, "workspace": {"box": {"min": [0,0,0], "max": [1,1,1]}},
                      "obstacles": [{"box": {"min": [0,0,0], "max": [1,1,1]},
                                     "sphere": {"center": [0,0,0], "radius": 1}}],
                      "goal": {"point": [0.5, 0.5, 0.5]}}"#;
        let spec: VolumeScene = serde_json::from_str(two).unwrap();
        let e = spec.build().unwrap_err();
        assert!(e.to_string().contains("obstacles[0]"), "{e}");
        let inverted = r#"{"dimension": 3, "workspace": {"box": {"min": [0,0,0], "max": [1,1,1]}},
                      "obstacles": [{"sphere": {"center": [0,0,0], "radius": 1}},
                                    {"box": {"min": [0,2,0], "max": [1,1,1]}}],
                      "goal": [{"point": [0.5, 0.5, 0.5]}]}"#;
        let spec: VolumeScene = serde_json::from_str(inverted).unwrap();
        let e = spec.build().unwrap_err();
        assert_eq!(
            e.to_string(),
            "obstacle 1: box min 2 is not below max 1 on axis 1"
        );
    }
}
