//! A scene whose robot is a polygon or an arm (the scene format's "Rigid robots and arms"):
//! its serde form, its configuration space (`build`) and its boundary conditions.

use harmonic_cspace::{
    Arm, ConfigGoal, ConfigSpace, EXTRUDE_PART, ObstacleInput, RigidRobot, Robot, World,
};
use harmonic_fem::{BoundaryCondition, BoundaryConditions};
use serde::{Deserialize, Serialize};

use super::{BoundarySpec, Region, SceneError, parse_json};
use crate::cspace::ANTIGOAL_PART;

/// The `"robot"` of a configuration-space scene: exactly one of `polygon` and `arm`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConfigRobotSpec {
    /// A rigid robot's body-frame polygon.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polygon: Option<Vec<[f64; 2]>>,
    /// A planar arm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arm: Option<ArmSpec>,
    /// A disc robot's radius: not allowed here (a disc is planned in the plane).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
}

/// A planar arm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArmSpec {
    /// The base `[x, y]`.
    pub base: [f64; 2],
    /// Two or three link lengths.
    pub links: Vec<f64>,
    /// Link width (absent or 0: segments).
    #[serde(default)]
    pub width: f64,
    /// `[lo, hi]` per joint, radians; absent: every joint turns freely.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_limits: Option<Vec<[f64; 2]>>,
}

/// A goal tolerance: a number, or `{"position": d, "angle": a}` for a pose.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ToleranceSpec {
    /// One number (radians for joints, a distance for an end-effector point).
    Number(f64),
    /// A pose's tolerances.
    Pose {
        /// Distance.
        position: f64,
        /// Radians.
        angle: f64,
    },
}

/// The goal of a configuration-space scene: exactly one of `pose`, `joints`,
/// `end_effector`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConfigGoalSpec {
    /// `[x, y, θ]` of a rigid robot.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pose: Option<[f64; 3]>,
    /// An arm's joint angles.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joints: Option<Vec<f64>>,
    /// A point for an arm's tip.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_effector: Option<[f64; 2]>,
    /// The tolerance (defaults: 2 lattice spacings, in the goal's units).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<ToleranceSpec>,
    /// The goal's boundary condition (default φ = 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundary: Option<BoundaryCondition>,
}

/// Mesh options of a configuration-space scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConfigMeshSpec {
    /// Lattice spacing in scaled configuration units (default: the scene size / 24).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
    /// Safety margin ε added around the robot (default: the scene size / 200).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
    /// Refuse lattices of more tetrahedra (default 3 M).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_tetrahedra: Option<u64>,
}

/// A scene whose robot is a polygon or an arm (the scene format's "Rigid robots and arms").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConfigScene {
    /// A name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The workspace polygon.
    pub workspace: Vec<[f64; 2]>,
    /// Obstacles: polygons or circles.
    #[serde(default)]
    pub obstacles: Vec<Region>,
    /// The robot.
    pub robot: ConfigRobotSpec,
    /// The goal.
    pub goal: ConfigGoalSpec,
    /// Start configurations.
    #[serde(default)]
    pub starts: Vec<Vec<f64>>,
    /// Boundary conditions (walls, obstacles, goal), as for plane scenes.
    #[serde(default)]
    pub boundary: BoundarySpec,
    /// Mesh options.
    #[serde(default)]
    pub mesh: ConfigMeshSpec,
}

/// Parses a configuration-space scene; errors name the JSON path, line and column.
pub fn parse_config_scene(text: &str) -> Result<ConfigScene, SceneError> {
    parse_json(text)
}

fn invalid(path: &str, message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        path: path.into(),
        message: message.into(),
    }
}

impl ConfigScene {
    /// The world, the robot and the goal, validated, and the mesh options.
    pub fn build(&self) -> Result<ConfigSpace, SceneError> {
        let mut obstacles = Vec::new();
        for (i, o) in self.obstacles.iter().enumerate() {
            match (&o.polygon, &o.circle, &o.point) {
                (Some(p), None, None) => obstacles.push(ObstacleInput::Polygon(p.clone())),
                (None, Some(c), None) => obstacles.push(ObstacleInput::Circle {
                    center: c.center,
                    radius: c.radius,
                }),
                _ => {
                    return Err(invalid(
                        &format!("obstacles[{i}]"),
                        "an obstacle is exactly one of \"polygon\" and \"circle\"",
                    ));
                }
            }
        }
        let world = World::new(&self.workspace, &obstacles)?;
        let robot = match (&self.robot.polygon, &self.robot.arm, self.robot.radius) {
            (Some(p), None, None) => Robot::Rigid(RigidRobot::new(p)?),
            (None, Some(a), None) => Robot::Arm(Arm::new(
                a.base,
                &a.links,
                a.width,
                a.joint_limits.as_deref(),
            )?),
            _ => {
                return Err(invalid(
                    "robot",
                    "a robot has exactly one of \"radius\", \"polygon\" and \"arm\"",
                ));
            }
        };
        let size = world.size();
        let spacing = self.mesh.spacing.unwrap_or(size / 24.0);
        let margin = self.mesh.margin.unwrap_or(size / 200.0);
        let g = &self.goal;
        let tol = g.tolerance;
        let goal = match (&g.pose, &g.joints, &g.end_effector) {
            (Some(pose), None, None) => {
                let (position, angle) = match tol {
                    Some(ToleranceSpec::Pose { position, angle }) => (position, angle),
                    Some(ToleranceSpec::Number(_)) => {
                        return Err(invalid(
                            "goal.tolerance",
                            "a pose's tolerance is {\"position\": d, \"angle\": a}",
                        ));
                    }
                    None => {
                        let rg = match &robot {
                            Robot::Rigid(r) => r.radius_of_gyration,
                            Robot::Arm(_) => 1.0,
                        };
                        (2.0 * spacing, 2.0 * spacing / rg)
                    }
                };
                ConfigGoal::Pose {
                    pose: *pose,
                    position,
                    angle,
                }
            }
            (None, Some(joints), None) => ConfigGoal::Joints {
                joints: joints.clone(),
                tolerance: number_tolerance(tol, 0.1)?,
            },
            (None, None, Some(point)) => ConfigGoal::EndEffector {
                point: *point,
                tolerance: number_tolerance(tol, 2.0 * spacing)?,
            },
            _ => {
                return Err(invalid(
                    "goal",
                    "a goal is exactly one of \"pose\", \"joints\" and \"end_effector\"",
                ));
            }
        };
        Ok(ConfigSpace::new(robot, world, goal, margin, spacing)?)
    }

    /// The boundary conditions: walls, obstacles (with per-obstacle overrides), the goal;
    /// joint limits are walls; a two-link arm's slab faces natural.
    pub fn boundary_conditions(&self) -> BoundaryConditions {
        // The goal's own condition, where it has one, holds for the goal as a whole.
        let boundary = BoundarySpec {
            goal: self.goal.boundary.or(self.boundary.goal),
            ..self.boundary
        };
        let mut bcs = boundary.conditions(self.obstacles.iter().map(|o| o.boundary), []);
        bcs.obstacle_overrides
            .insert(EXTRUDE_PART, BoundaryCondition::Neumann(0.0));
        bcs.obstacle_overrides.insert(ANTIGOAL_PART, bcs.walls);
        bcs
    }
}

fn number_tolerance(t: Option<ToleranceSpec>, default: f64) -> Result<f64, SceneError> {
    match t {
        None => Ok(default),
        Some(ToleranceSpec::Number(v)) => Ok(v),
        Some(ToleranceSpec::Pose { .. }) => Err(invalid(
            "goal.tolerance",
            "a joints or end_effector goal's tolerance is one number",
        )),
    }
}
