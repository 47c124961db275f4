//! The scene file: the JSON contract of `docs/scene-format.md`, parsed with errors that say where.
//!
//! A scene names a workspace polygon, obstacles (polygons or circles), one or more goal
//! regions, optional start points, boundary conditions per boundary part, mesh options and the
//! robot's radius. Unknown fields are errors naming their path (`obstacles[2].polgon`).
//! A volume scene (`"dimension": 3`) is [`VolumeScene`]; a robot that is not a disc is a
//! configuration-space scene ([`crate::ConfigScene`]); [`AnyScene`] reads a file of any kind.

pub mod config;
mod plane;
mod volume;

pub use plane::{
    BlendSpec, BoundarySpec, Circle, Goals, MeshSpec, Obstacle, Region, RobotSpec, Scene,
};

pub use volume::{
    BoxSpec, GoalSpec, GoalsSpec, ObstacleSpec, SphereSpec, SurfaceSpec, VolumeMeshSpec,
    VolumeScene, WorkspaceSpec,
};

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
    /// A configuration-space scene's world, robot or goal is invalid (names the JSON path).
    #[error(transparent)]
    Config(#[from] harmonic_cspace::CspaceError),
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
    use harmonic_fem::BoundaryCondition;

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
