//! The plane scene: a workspace polygon, polygonal and circular obstacles, goal regions,
//! boundary conditions per part, mesh options and a disc robot; parsed with checks that name
//! the JSON path, and mapped to the mesher's geometry and options and to the FEM's boundary
//! conditions.

use std::fmt;

use harmonic_fem::{BoundaryCondition, BoundaryConditions};
use harmonic_mesh::{DomainSpec, GoalShape, Grading, MeshOptions, Point, Shape};
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};

use super::{SceneError, parse_json};

/// A scene: what to plan in, towards what, and how.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// A name for reports and pictures.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The outer boundary, a simple polygon in either orientation.
    pub workspace: Vec<[f64; 2]>,
    /// Obstacles, each a polygon or a circle, optionally with its own boundary condition.
    #[serde(default)]
    pub obstacles: Vec<Obstacle>,
    /// One goal region or several.
    pub goal: Goals,
    /// Query points for `hplan plan`.
    #[serde(default)]
    pub starts: Vec<[f64; 2]>,
    /// Boundary conditions of the walls, the obstacles and the goal.
    #[serde(default)]
    pub boundary: BoundarySpec,
    /// Mesh options; defaults are chosen from the scene's size.
    #[serde(default)]
    pub mesh: MeshSpec,
    /// The robot: a disc of the given radius (0 for a point robot).
    #[serde(default)]
    pub robot: RobotSpec,
}

/// Boundary conditions by part; missing parts take the defaults.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// The workspace boundary (default φ = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub walls: Option<BoundaryCondition>,
    /// Every obstacle without its own condition (default φ = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obstacles: Option<BoundaryCondition>,
    /// Every goal without its own condition (default φ = 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub goal: Option<BoundaryCondition>,
    /// The ME766 blend `k·φ_D + (1 − k)·φ_N` of a Dirichlet and a Neumann solve on the same
    /// mesh (walls and obstacles then take no condition of their own but a Dirichlet one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blend: Option<BlendSpec>,
}

impl BoundarySpec {
    /// The finite elements' conditions: `walls`, `obstacles` and `goal` (defaults Dirichlet
    /// 1, 1, 0), then each obstacle's and goal's own condition (`obstacles[i].boundary`,
    /// `goal[j].boundary`) where it has one. The one mapping of every kind of scene.
    pub fn conditions(
        &self,
        obstacles: impl IntoIterator<Item = Option<BoundaryCondition>>,
        goals: impl IntoIterator<Item = Option<BoundaryCondition>>,
    ) -> BoundaryConditions {
        let mut bcs = BoundaryConditions::default();
        if let Some(c) = self.walls {
            bcs.walls = c;
        }
        if let Some(c) = self.obstacles {
            bcs.obstacles = c;
        }
        if let Some(c) = self.goal {
            bcs.goals = c;
        }
        for (i, c) in obstacles.into_iter().enumerate() {
            if let Some(c) = c {
                bcs.obstacle_overrides.insert(i as u32, c);
            }
        }
        for (j, c) in goals.into_iter().enumerate() {
            if let Some(c) = c {
                bcs.goal_overrides.insert(j as u32, c);
            }
        }
        bcs
    }
}

/// `"blend": {"k": 0.3, "neumann": 1.0}`: the potential is `k·φ_D + (1 − k)·φ_N`, where
/// `φ_D` holds walls and obstacles at their Dirichlet value (`boundary.walls` /
/// `boundary.obstacles` if given, else 1) and `φ_N` lets the uniform inflow
/// `∂φ/∂n = neumann` through them, scaled so that its largest value is 1; both hold the
/// goals as `boundary.goal` says. `k = 1` is the Dirichlet field, `k = 0` the Neumann one.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlendSpec {
    /// The weight of the Dirichlet solve, in [0, 1].
    pub k: f64,
    /// The inflow `g > 0` of the Neumann solve (default 1).
    #[serde(default = "default_blend_inflow")]
    pub neumann: f64,
}

fn default_blend_inflow() -> f64 {
    1.0
}

/// Mesh options of a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// Largest triangle area.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_area: Option<f64>,
    /// Smallest angle refinement aims for, in degrees (at most 33).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_angle_deg: Option<f64>,
    /// Finer triangles near the goal and at obstacle corners (an extension of the scene
    /// format; absent: uniform). Checked here so errors name their JSON path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grading: Option<Grading>,
    /// Simplify detailed obstacle polygons to within this distance (scene units) before
    /// meshing, conservatively: each simplified obstacle contains the original. Absent:
    /// polygons are meshed as given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simplify: Option<f64>,
}

/// The robot's shape.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// Radius of a disc robot; obstacles are inflated and walls shrunk by it.
    #[serde(default)]
    pub radius: f64,
}

/// A circle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Circle {
    /// Centre `[x, y]`, in scene units.
    pub center: [f64; 2],
    /// Radius, positive, in scene units.
    pub radius: f64,
}

/// The shape of an obstacle or a goal region: exactly one of the fields is given.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Region {
    /// A simple polygon, its vertices `[x, y]` in either orientation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polygon: Option<Vec<[f64; 2]>>,
    /// A disc.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub circle: Option<Circle>,
    /// Only for goals: a point goal, meshed as a small circle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<[f64; 2]>,
    /// A boundary condition overriding the scene-wide one for this part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundary: Option<BoundaryCondition>,
}

/// An obstacle: a polygon or a circle.
pub type Obstacle = Region;

/// One goal region or several (`"goal": {...}` or `"goal": [{...}, ...]`).
#[derive(Clone, Debug, PartialEq)]
pub struct Goals(
    /// The goal regions, in file order: goal `j` of the boundary tags is `self.0[j]`.
    pub Vec<Region>,
);

impl Serialize for Goals {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0.as_slice() {
            [one] => one.serialize(s),
            many => many.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Goals {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct GoalsVisitor;
        impl<'de> Visitor<'de> for GoalsVisitor {
            type Value = Goals;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a goal region ({\"circle\"|\"polygon\"|\"point\": ...}) or an array of them",
                )
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Goals, A::Error> {
                let region = Region::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(Goals(vec![region]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Goals, A::Error> {
                let regions =
                    Vec::<Region>::deserialize(de::value::SeqAccessDeserializer::new(seq))?;
                Ok(Goals(regions))
            }
        }
        d.deserialize_any(GoalsVisitor)
    }
}

impl Scene {
    /// Parses a scene from JSON text and checks what the format alone can check (one shape
    /// per region, finite numbers, positive radii, mesh options in range).
    pub fn from_json(text: &str) -> Result<Scene, SceneError> {
        let scene: Scene = parse_json(text)?;
        scene.check()?;
        Ok(scene)
    }

    /// Reads and parses a scene file.
    pub fn from_file(path: impl AsRef<std::path::Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            file: path.display().to_string(),
            source,
        })?;
        Scene::from_json(&text)
    }

    /// The goal regions.
    pub fn goals(&self) -> &[Region] {
        &self.goal.0
    }

    fn check(&self) -> Result<(), SceneError> {
        let invalid = |path: String, message: String| Err(SceneError::Invalid { path, message });
        check_points("workspace", &self.workspace)?;
        for (i, o) in self.obstacles.iter().enumerate() {
            let path = format!("obstacles[{i}]");
            if o.point.is_some() {
                return invalid(
                    path,
                    "an obstacle is a \"polygon\" or a \"circle\", not a \"point\"".into(),
                );
            }
            check_region(&path, o)?;
        }
        if self.goal.0.is_empty() {
            return invalid("goal".into(), "at least one goal region is needed".into());
        }
        for (j, g) in self.goal.0.iter().enumerate() {
            let path = if self.goal.0.len() == 1 {
                "goal".to_string()
            } else {
                format!("goal[{j}]")
            };
            check_region(&path, g)?;
        }
        for (k, s) in self.starts.iter().enumerate() {
            check_points(&format!("starts[{k}]"), std::slice::from_ref(s))?;
        }
        for (part, c) in [
            ("walls", self.boundary.walls),
            ("obstacles", self.boundary.obstacles),
            ("goal", self.boundary.goal),
        ] {
            if let Some(c) = c {
                check_condition(&format!("boundary.{part}"), &c)?;
            }
        }
        if let Some(b) = self.boundary.blend {
            if !(0.0..=1.0).contains(&b.k) {
                return invalid(
                    "boundary.blend.k".into(),
                    format!("must lie in [0, 1], got {}", b.k),
                );
            }
            if !(b.neumann.is_finite() && b.neumann > 0.0) {
                return invalid(
                    "boundary.blend.neumann".into(),
                    format!(
                        "the Neumann inflow must be a positive number, got {}",
                        b.neumann
                    ),
                );
            }
            for (part, c) in [
                ("walls", self.boundary.walls),
                ("obstacles", self.boundary.obstacles),
            ] {
                if let Some(c) = c
                    && !matches!(c, BoundaryCondition::Dirichlet(_))
                {
                    return invalid(
                        format!("boundary.{part}"),
                        "with boundary.blend, walls and obstacles take a Dirichlet value only"
                            .into(),
                    );
                }
            }
            if let Some(i) = self.obstacles.iter().position(|o| o.boundary.is_some()) {
                return invalid(
                    format!("obstacles[{i}].boundary"),
                    "with boundary.blend, obstacles take no condition of their own".into(),
                );
            }
        }
        if let Some(a) = self.mesh.max_area
            && !(a.is_finite() && a > 0.0)
        {
            return invalid(
                "mesh.max_area".into(),
                format!("must be a positive number, got {a}"),
            );
        }
        if let Some(t) = self.mesh.simplify
            && !(t.is_finite() && t > 0.0)
        {
            return invalid(
                "mesh.simplify".into(),
                format!("must be a positive distance, got {t}"),
            );
        }
        if let Some(d) = self.mesh.min_angle_deg
            && !(d.is_finite() && (0.0..=33.0).contains(&d))
        {
            return invalid(
                "mesh.min_angle_deg".into(),
                format!(
                    "must be between 0 and 33 degrees (refinement does not terminate above 33), got {d}"
                ),
            );
        }
        if let Some(g) = self.mesh.grading {
            for (name, v) in [("near_goal", g.near_goal), ("near_corners", g.near_corners)] {
                if !(v.is_finite() && v > 0.0 && v <= 1.0) {
                    return invalid(
                        format!("mesh.grading.{name}"),
                        format!("must be in (0, 1], got {v}"),
                    );
                }
            }
            if !(g.radius.is_finite() && g.radius > 0.0) {
                return invalid(
                    "mesh.grading.radius".into(),
                    format!("must be a positive number, got {}", g.radius),
                );
            }
        }
        let r = self.robot.radius;
        if !(r.is_finite() && r >= 0.0) {
            return invalid(
                "robot.radius".into(),
                format!("must be zero or positive, got {r}"),
            );
        }
        Ok(())
    }
}

fn check_points(path: &str, points: &[[f64; 2]]) -> Result<(), SceneError> {
    for (k, p) in points.iter().enumerate() {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(SceneError::Invalid {
                path: format!("{path}[{k}]"),
                message: "coordinates must be finite numbers".into(),
            });
        }
    }
    Ok(())
}

fn check_region(path: &str, r: &Region) -> Result<(), SceneError> {
    let given = [r.polygon.is_some(), r.circle.is_some(), r.point.is_some()]
        .iter()
        .filter(|&&b| b)
        .count();
    if given != 1 {
        return Err(SceneError::Invalid {
            path: path.to_string(),
            message: format!(
                "give exactly one of \"polygon\", \"circle\" or \"point\" (found {given})"
            ),
        });
    }
    if let Some(p) = &r.polygon {
        check_points(&format!("{path}.polygon"), p)?;
    }
    if let Some(c) = &r.circle {
        check_points(
            &format!("{path}.circle.center"),
            std::slice::from_ref(&c.center),
        )?;
        if !(c.radius.is_finite() && c.radius > 0.0) {
            return Err(SceneError::Invalid {
                path: format!("{path}.circle.radius"),
                message: format!("must be a positive number, got {}", c.radius),
            });
        }
    }
    if let Some(p) = &r.point {
        check_points(&format!("{path}.point"), std::slice::from_ref(p))?;
    }
    if let Some(c) = &r.boundary {
        check_condition(&format!("{path}.boundary"), c)?;
    }
    Ok(())
}

fn check_condition(path: &str, c: &BoundaryCondition) -> Result<(), SceneError> {
    let finite = match *c {
        BoundaryCondition::Dirichlet(v) | BoundaryCondition::Neumann(v) => v.is_finite(),
        BoundaryCondition::Robin { a, b, g } => a.is_finite() && b.is_finite() && g.is_finite(),
    };
    if !finite {
        return Err(SceneError::Invalid {
            path: path.into(),
            message: "values must be finite".into(),
        });
    }
    if let BoundaryCondition::Robin { a, b, .. } = *c
        && a == 0.0
        && b == 0.0
    {
        return Err(SceneError::Invalid {
            path: path.into(),
            message: "Robin condition with a = b = 0 says nothing (a·∂φ/∂n + b·φ = g needs a or b nonzero)"
                .into(),
        });
    }
    Ok(())
}

fn point(p: [f64; 2]) -> Point {
    Point::new(p[0], p[1])
}

impl Scene {
    /// The geometry of the scene for the mesher.
    pub fn domain_spec(&self) -> DomainSpec {
        let shape = |r: &Region| match (&r.polygon, &r.circle) {
            (Some(p), _) => Shape::Polygon(p.iter().copied().map(point).collect()),
            (None, Some(c)) => Shape::Circle {
                center: point(c.center),
                radius: c.radius,
            },
            // `Scene::from_json` guarantees one shape per obstacle; an empty polygon is
            // reported by the mesher as too few vertices.
            (None, None) => Shape::Polygon(Vec::new()),
        };
        let goal = |r: &Region| match (&r.polygon, &r.circle, &r.point) {
            (Some(p), _, _) => GoalShape::Polygon(p.iter().copied().map(point).collect()),
            (None, Some(c), _) => GoalShape::Circle {
                center: point(c.center),
                radius: c.radius,
            },
            (None, None, Some(p)) => GoalShape::Point(point(*p)),
            (None, None, None) => GoalShape::Polygon(Vec::new()),
        };
        DomainSpec {
            workspace: self.workspace.iter().copied().map(point).collect(),
            obstacles: self.obstacles.iter().map(shape).collect(),
            goals: self.goals().iter().map(goal).collect(),
            robot_radius: self.robot.radius,
        }
    }

    /// The mesh options of the scene (defaults where it gives none).
    pub fn mesh_options(&self) -> MeshOptions {
        let mut opts = MeshOptions {
            max_area: self.mesh.max_area,
            grading: self.mesh.grading,
            simplify: self.mesh.simplify,
            ..MeshOptions::default()
        };
        if let Some(d) = self.mesh.min_angle_deg {
            opts.min_angle_deg = d;
        }
        opts
    }

    /// The boundary conditions of the scene, per part, with per-obstacle and per-goal overrides.
    pub fn boundary_conditions(&self) -> BoundaryConditions {
        self.boundary.conditions(
            self.obstacles.iter().map(|o| o.boundary),
            self.goals().iter().map(|g| g.boundary),
        )
    }

    /// With `boundary.blend`: its weight `k` and the conditions of its Dirichlet and Neumann
    /// solves.
    pub fn blend_conditions(&self) -> Option<(f64, BoundaryConditions, BoundaryConditions)> {
        let b = self.boundary.blend?;
        let mut dirichlet = self.boundary_conditions();
        if self.boundary.walls.is_none() {
            dirichlet.walls = BoundaryCondition::Dirichlet(1.0);
        }
        if self.boundary.obstacles.is_none() {
            dirichlet.obstacles = BoundaryCondition::Dirichlet(1.0);
        }
        let mut neumann = dirichlet.clone();
        neumann.walls = BoundaryCondition::Neumann(b.neumann);
        neumann.obstacles = BoundaryCondition::Neumann(b.neumann);
        Some((b.k, dirichlet, neumann))
    }
}
