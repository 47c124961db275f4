//! The scene file: the JSON contract of `docs/scene-format.md`, parsed with errors that say where.
//!
//! A scene names a workspace polygon, obstacles (polygons or circles), one or more goal
//! regions, optional start points, boundary conditions per boundary part, mesh options and the
//! robot's radius. Unknown fields are errors naming their path (`obstacles[2].polgon`).
//! A volume scene (`"dimension": 3`) is [`VolumeScene`]; a robot that is not a disc is a
//! configuration-space scene ([`crate::ConfigScene`]); [`AnyScene`] reads a file of any kind.

use std::fmt;

mod volume;

pub use volume::{
    BoxSpec, GoalSpec, GoalsSpec, ObstacleSpec, SphereSpec, SurfaceSpec, VolumeMeshSpec,
    VolumeScene, WorkspaceSpec,
};

use harmonic_fem::{BoundaryCondition, BoundaryConditions};
use harmonic_mesh::Grading;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};

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

/// Why a scene could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The text is not valid JSON, or does not match the scene format.
    #[error("{path}line {line}, column {column}: {message}")]
    Parse {
        /// Where in the document (`obstacles[2].circle.radius: `), empty at the top level.
        path: String,
        /// Line of the first mismatch, counted from 1.
        line: usize,
        /// Column of the first mismatch in that line, counted from 1.
        column: usize,
        /// What is wrong, as serde_json says it (without its own position).
        message: String,
    },
    /// The JSON is well formed but describes an impossible scene.
    #[error("{path}: {message}")]
    Invalid {
        /// The JSON path of the offending value (`obstacles[1]`, `goal`,
        /// `obstacles[0].circle.radius`).
        path: String,
        /// What is wrong with it.
        message: String,
    },
    /// A volume scene's solids are invalid (`obstacle 1: box min 2 is not below max 1 on
    /// axis 1`), or its robot leaves no free space.
    #[error(transparent)]
    Volume(#[from] harmonic_volume::VolumeError),
    /// The file could not be read.
    #[error("cannot read {file}: {source}")]
    Io {
        /// The path of the file, as given.
        file: String,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
}

/// Deserialises a JSON object, naming the field, line and column of the first mismatch.
pub(crate) fn parse_json<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, SceneError> {
    check_is_object(text)?;
    let mut de = serde_json::Deserializer::from_str(text);
    let value: T = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let path = if path == "." || path.is_empty() {
            String::new()
        } else {
            format!("{path}: ")
        };
        let message = strip_position(&inner.to_string());
        SceneError::Parse {
            path,
            line: inner.line(),
            column: inner.column(),
            message,
        }
    })?;
    de.end().map_err(|e| SceneError::Parse {
        path: String::new(),
        line: e.line(),
        column: e.column(),
        message: strip_position(&e.to_string()),
    })?;
    Ok(value)
}

/// A scene file of either kind: a plane scene, or a volume (`"dimension": 3`).
#[derive(Clone, Debug)]
pub enum AnyScene {
    /// A workspace polygon with obstacles (the default).
    Plane(Box<Scene>),
    /// A volume scene.
    Volume(Box<VolumeScene>),
    /// A robot that is not a disc (`"robot"` has a `"polygon"` or an `"arm"`), planned in
    /// its configuration space.
    Config(Box<crate::cspace::ConfigScene>),
}

impl AnyScene {
    /// Parses any kind of scene: `"dimension": 3` selects a volume, a `"robot"` with a
    /// `"polygon"` or an `"arm"` a configuration-space scene, otherwise a plane scene.
    pub fn from_json(text: &str) -> Result<AnyScene, SceneError> {
        #[derive(serde::Deserialize)]
        struct Dimension {
            dimension: Option<serde_json::Value>,
            robot: Option<serde_json::Value>,
        }
        // Only an object is probed: serde would read `[1, 2]` as a struct (dimension 1), and
        // anything that is not an object gets the plane parser's "a scene is a JSON object".
        let probe = text
            .trim_start()
            .starts_with('{')
            .then(|| serde_json::from_str::<Dimension>(text).ok())
            .flatten();
        let config = probe
            .as_ref()
            .and_then(|d| d.robot.as_ref())
            .and_then(|r| r.as_object())
            .is_some_and(|r| r.contains_key("polygon") || r.contains_key("arm"));
        let dimension = probe.and_then(|d| d.dimension);
        if config && dimension.is_none() {
            return Ok(AnyScene::Config(Box::new(parse_json(text)?)));
        }
        match dimension {
            None => Ok(AnyScene::Plane(Box::new(Scene::from_json(text)?))),
            Some(d) if d.as_u64() == Some(2) => {
                // The plane format has no "dimension" field: accept an explicit 2.
                let mut value: serde_json::Value =
                    serde_json::from_str(text).map_err(|e| SceneError::Parse {
                        path: String::new(),
                        line: e.line(),
                        column: e.column(),
                        message: strip_position(&e.to_string()),
                    })?;
                if let Some(o) = value.as_object_mut() {
                    o.remove("dimension");
                }
                Ok(AnyScene::Plane(Box::new(Scene::from_json(
                    &value.to_string(),
                )?)))
            }
            Some(d) if d.as_u64() == Some(3) => Ok(AnyScene::Volume(Box::new(parse_json(text)?))),
            Some(d) => Err(SceneError::Invalid {
                path: "dimension".into(),
                message: format!("must be 2 or 3, not {d}"),
            }),
        }
    }

    /// Reads and parses a scene file of either kind.
    pub fn from_file(path: impl AsRef<std::path::Path>) -> Result<AnyScene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            file: path.display().to_string(),
            source,
        })?;
        AnyScene::from_json(&text)
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

/// serde would read a JSON array positionally into a struct; a scene must be an object.
fn check_is_object(text: &str) -> Result<(), SceneError> {
    let Some((offset, first)) = text.char_indices().find(|(_, c)| !c.is_whitespace()) else {
        return Err(SceneError::Parse {
            path: String::new(),
            line: 1,
            column: 0,
            message:
                "the file is empty; a scene is a JSON object {\"workspace\": ..., \"goal\": ...}"
                    .into(),
        });
    };
    if first == '{' {
        return Ok(());
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = offset - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    Err(SceneError::Parse {
        path: String::new(),
        line,
        column,
        message: format!(
            "a scene is a JSON object {{\"workspace\": ..., \"goal\": ...}}, found `{first}`"
        ),
    })
}

/// serde_json appends " at line L column C"; we report the position separately.
fn strip_position(msg: &str) -> String {
    match msg.rfind(" at line ") {
        Some(i) => msg[..i].to_string(),
        None => msg.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const REFERENCE: &str = include_str!("../../meshes/reference.json");

    #[test]
    fn parses_the_reference_scene() {
        let s = Scene::from_json(REFERENCE).expect("reference scene parses");
        assert_eq!(s.obstacles.len(), 5);
        assert_eq!(s.goals().len(), 1);
        assert_eq!(s.starts, vec![[1.0, 9.0]]);
        assert_eq!(s.boundary.walls, Some(BoundaryCondition::Dirichlet(1.0)));
        assert_eq!(s.mesh.max_area, Some(0.0044));
    }

    #[test]
    fn parses_the_contract_example() {
        let text = r#"{
          "name": "reference",
          "workspace": [[0, 0], [10, 0], [10, 10], [0, 10]],
          "obstacles": [
            {"polygon": [[2, 2], [3, 2], [3, 8], [2, 8]]},
            {"circle": {"center": [6.5, 6.5], "radius": 0.6}, "boundary": {"dirichlet": 1.0}}
          ],
          "goal": {"circle": {"center": [8.5, 1.5], "radius": 0.15}},
          "starts": [[1, 9], [0.5, 8.0]],
          "boundary": {
            "walls":     {"robin": {"a": 1.0, "b": 10.0, "g": 10.0}},
            "obstacles": {"dirichlet": 1.0},
            "goal":      {"dirichlet": 0.0}
          },
          "mesh": {"max_area": 0.01, "min_angle_deg": 28.0},
          "robot": {"radius": 0.0}
        }"#;
        let s = Scene::from_json(text).expect("contract example parses");
        assert_eq!(
            s.boundary.walls,
            Some(BoundaryCondition::Robin {
                a: 1.0,
                b: 10.0,
                g: 10.0
            })
        );
        assert_eq!(s.obstacles[1].circle.map(|c| c.radius), Some(0.6));
        assert_eq!(
            s.obstacles[1].boundary,
            Some(BoundaryCondition::Dirichlet(1.0))
        );
        // Round trip through serde keeps the scene.
        let again =
            Scene::from_json(&serde_json::to_string(&s).expect("serialises")).expect("reparses");
        assert_eq!(again, s);
    }

    #[test]
    fn several_goals_and_point_goals() {
        let text = r#"{"workspace": [[0,0],[4,0],[4,4],[0,4]],
                       "goal": [{"point": [1, 1]}, {"polygon": [[3,3],[3.5,3],[3.5,3.5]]}]}"#;
        let s = Scene::from_json(text).expect("parses");
        assert_eq!(s.goals().len(), 2);
        assert_eq!(s.goals()[0].point, Some([1.0, 1.0]));
    }

    fn error_of(text: &str) -> String {
        Scene::from_json(text)
            .expect_err("must be rejected")
            .to_string()
    }

    #[test]
    fn grading_reaches_the_mesher_and_refines_near_the_goal() {
        let text = |grading: &str| {
            format!(
                r#"{{"workspace": [[0,0],[4,0],[4,4],[0,4]], "goal": {{"circle": {{"center": [3, 3], "radius": 0.2}}}},
                    "mesh": {{"max_area": 0.05{grading}}}}}"#
            )
        };
        let uniform = Scene::from_json(&text("")).expect("parses");
        let graded = Scene::from_json(&text(r#", "grading": {"near_goal": 0.05, "radius": 1}"#))
            .expect("parses");
        assert_eq!(
            graded.mesh_options().grading.map(|g| g.near_goal),
            Some(0.05)
        );
        let count = |scene: &Scene| {
            crate::Planner::new(scene)
                .expect("plans")
                .mesh()
                .triangles()
                .len()
        };
        assert!(count(&graded) > count(&uniform) + 100);
    }

    #[test]
    fn unknown_fields_name_their_path() {
        let e = error_of(
            r#"{"workspace": [[0,0],[1,0],[1,1]], "goal": {"point": [0.5,0.2]},
                "obstacles": [{"polygon": [[0,0],[1,0],[1,1]]}, {"polgon": []}]}"#,
        );
        assert!(e.contains("obstacles[1]"), "{e}");
        assert!(e.contains("polgon"), "{e}");
        assert!(e.contains("line 2"), "{e}");
    }

    #[test]
    fn malformed_json_has_line_and_column() {
        let e = error_of(
            "{\n  \"workspace\": [[0,0],[1,0],[1,1]],\n  \"goal\": {\"point\": [0.5,0.2]\n",
        );
        assert!(e.contains("line 4"), "{e}");
        let e = error_of("");
        assert!(e.contains("line 1, column 0"), "{e}");
        let e = error_of("[1, 2]");
        assert!(
            e.contains("a scene is a JSON object") && e.contains("line 1, column 1"),
            "{e}"
        );
        let e = error_of("\n  42");
        assert!(e.contains("line 2, column 3"), "{e}");
    }

    #[test]
    fn bad_values_are_named() {
        let base = |extra: &str| {
            format!(
                r#"{{"workspace": [[0,0],[1,0],[1,1]], "goal": {{"point": [0.5,0.2]}} {extra}}}"#
            )
        };
        assert!(error_of(&base(r#", "robot": {"radius": -1}"#)).contains("robot.radius"));
        assert!(error_of(&base(r#", "mesh": {"min_angle_deg": 40}"#)).contains("33"));
        assert!(error_of(&base(r#", "mesh": {"max_area": 0}"#)).contains("mesh.max_area"));
        let e = error_of(&base(
            r#", "mesh": {"grading": {"near_goal": 0, "radius": 1}}"#,
        ));
        assert!(e.contains("mesh.grading.near_goal"), "{e}");
        let e = error_of(&base(r#", "mesh": {"grading": {"radius": -1}}"#));
        assert!(e.contains("mesh.grading.radius"), "{e}");
        let e = error_of(&base(
            r#", "mesh": {"grading": {"radius": 1, "near_gaol": 0.1}}"#,
        ));
        assert!(e.contains("near_gaol"), "{e}");
        let e = error_of(&base(
            r#", "boundary": {"walls": {"robin": {"a": 0, "b": 0, "g": 1}}}"#,
        ));
        assert!(
            e.contains("boundary.walls") && e.contains("a = b = 0"),
            "{e}"
        );
        let e = error_of(&base(
            r#", "obstacles": [{"circle": {"center": [0.5, 0.5], "radius": 0}}]"#,
        ));
        assert!(e.contains("obstacles[0].circle.radius"), "{e}");
        let e = error_of(&base(r#", "obstacles": [{}]"#));
        assert!(e.contains("exactly one"), "{e}");
        let e = error_of(r#"{"workspace": [[0,0],[1,0],[1e400,1]], "goal": {"point": [0.5,0.2]}}"#);
        assert!(e.contains("workspace"), "{e}");
        let e = error_of(r#"{"workspace": [[0,0],[1,0],["a",1]], "goal": {"point": [0.5,0.2]}}"#);
        assert!(e.contains("workspace[2][0]"), "{e}");
    }
}
