//! Bad input never panics and is refused with the right typed error (issue #8).
//!
//! - every scene in `tests/bad_scenes/` fails with the error variant that names its real
//!   defect (not an incidental one further down the pipeline);
//! - per-path problems (a start outside, inside an obstacle or in a sealed pocket) are path
//!   statuses, not errors;
//! - malformed Triangle `.node/.ele/.poly` files are refused with a line number;
//! - the fuzz corpus (`fuzz/corpus/scene/`) replays without a panic, with the fuzz target's
//!   own code and mesh cap (`fuzz/src/lib.rs`).

use std::panic::catch_unwind;
use std::path::Path;

use harmonic_planner::fem::FemError;
use harmonic_planner::mesh::{MeshError, Part, io};
use harmonic_planner::{PlanError, Planner, Scene, SceneError};

#[path = "../fuzz/src/lib.rs"]
mod fuzz_case;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// What reading and planning a scene file gave: the scene error or the planner error.
#[derive(Debug)]
enum Failure {
    Scene(SceneError),
    Plan(PlanError),
    Planned,
}

fn attempt(text: &str) -> Failure {
    match Scene::from_json(text) {
        Err(e) => Failure::Scene(e),
        Ok(scene) => match Planner::new(&scene) {
            Err(e) => Failure::Plan(e),
            Ok(_) => Failure::Planned,
        },
    }
}

fn bad_scene(file: &str) -> Failure {
    let path = root().join("tests/bad_scenes").join(file);
    match Scene::from_file(&path) {
        Err(e) => Failure::Scene(e),
        Ok(scene) => match Planner::new(&scene) {
            Err(e) => Failure::Plan(e),
            Ok(_) => Failure::Planned,
        },
    }
}

fn invalid_at(f: &Failure, want_path: &str, fragment: &str) -> bool {
    matches!(f, Failure::Scene(SceneError::Invalid { path, message })
        if path == want_path && message.contains(fragment))
}

fn parse_error_at(f: &Failure, want_path: &str, fragment: &str) -> bool {
    matches!(f, Failure::Scene(SceneError::Parse { path, message, .. })
        if path.starts_with(want_path) && message.contains(fragment))
}

fn mesh_error(f: &Failure) -> Option<&MeshError> {
    match f {
        Failure::Plan(PlanError::Mesh(e)) => Some(e),
        _ => None,
    }
}

fn fem_error(f: &Failure) -> Option<&FemError> {
    match f {
        Failure::Plan(PlanError::Fem(e)) => Some(e),
        _ => None,
    }
}

/// Each bad scene with a check of the exact error it must produce.
#[test]
fn every_bad_scene_fails_for_its_own_reason() {
    type Check = fn(&Failure) -> bool;
    let table: &[(&str, Check)] = &[
        ("malformed_json.json", |f| {
            matches!(f, Failure::Scene(SceneError::Parse { line: 5, message, .. })
                if message.contains("EOF"))
        }),
        ("empty_file.json", |f| {
            matches!(f, Failure::Scene(SceneError::Parse { line: 1, column: 0, message, .. })
                if message.contains("empty"))
        }),
        ("not_an_object.json", |f| {
            matches!(f, Failure::Scene(SceneError::Parse { line: 1, column: 1, message, .. })
                if message.contains("a scene is a JSON object"))
        }),
        ("wrong_type.json", |f| {
            parse_error_at(f, "workspace", "invalid type: string \"square\"")
        }),
        ("unknown_field.json", |f| {
            parse_error_at(f, "", "unknown field `obstacels`")
        }),
        ("overflowing_number.json", |f| {
            parse_error_at(f, "obstacles[0].polygon[2][1]", "number out of range")
        }),
        ("too_few_vertices.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::TooFewVertices {
                    part: Part::Workspace,
                    count: 2
                })
            )
        }),
        ("self_intersecting_workspace.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::SelfIntersection {
                    part: Part::Workspace,
                    ..
                })
            )
        }),
        ("self_intersecting_obstacle.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::SelfIntersection {
                    part: Part::Obstacle(0),
                    ..
                })
            )
        }),
        ("zero_area_obstacle.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::ZeroArea {
                    part: Part::Obstacle(0)
                })
            )
        }),
        ("only_duplicate_vertices.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::TooFewVertices {
                    part: Part::Obstacle(0),
                    count: 1
                })
            )
        }),
        ("negative_radius.json", |f| {
            invalid_at(f, "obstacles[0].circle.radius", "positive")
        }),
        ("zero_radius.json", |f| {
            invalid_at(f, "obstacles[0].circle.radius", "positive")
        }),
        ("negative_robot_radius.json", |f| {
            invalid_at(f, "robot.radius", "zero or positive")
        }),
        ("obstacle_outside.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::OutsideWorkspace {
                    part: Part::Obstacle(0)
                })
            )
        }),
        ("goal_outside.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::OutsideWorkspace {
                    part: Part::Goal(0)
                })
            )
        }),
        ("goal_inside_obstacle.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::GoalInObstacle {
                    goal: 0,
                    obstacle: 0
                })
            )
        }),
        ("robot_too_large.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::NoFreeSpace { robot_radius }) if *robot_radius == 6.0
            )
        }),
        ("degenerate_robin.json", |f| {
            invalid_at(f, "boundary.walls", "a = b = 0")
        }),
        ("only_neumann.json", |f| {
            matches!(fem_error(f), Some(FemError::OnlyNeumann { .. }))
        }),
        (
            "nothing_drives_the_flow.json",
            |f| matches!(fem_error(f), Some(FemError::ConstantPotential { value }) if *value == 0.0),
        ),
        ("min_angle_too_large.json", |f| {
            invalid_at(f, "mesh.min_angle_deg", "33")
        }),
        ("vertex_budget.json", |f| {
            matches!(mesh_error(f), Some(MeshError::TooManyTriangles { .. }))
        }),
        ("zero_area_workspace.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::ZeroArea {
                    part: Part::Workspace
                })
            )
        }),
        ("duplicate_workspace_vertices.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::TooFewVertices {
                    part: Part::Workspace,
                    count: 2
                })
            )
        }),
        ("trailing_characters.json", |f| {
            matches!(f, Failure::Scene(SceneError::Parse { line: 2, message, .. })
                if message.contains("trailing characters"))
        }),
        (
            "nan_literal.json",
            |f| matches!(f, Failure::Scene(SceneError::Parse { path, .. }) if path.starts_with("workspace")),
        ),
        ("empty_goal_list.json", |f| {
            invalid_at(f, "goal", "at least one goal")
        }),
        ("obstacle_is_a_point.json", |f| {
            invalid_at(f, "obstacles[1]", "not a \"point\"")
        }),
        ("two_shapes_in_one_region.json", |f| {
            invalid_at(f, "obstacles[0]", "found 2")
        }),
        ("second_goal_outside.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::OutsideWorkspace {
                    part: Part::Goal(1)
                })
            )
        }),
        ("second_goal_in_circle_obstacle.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::GoalInObstacle {
                    goal: 1,
                    obstacle: 2
                })
            )
        }),
        ("self_intersecting_third_obstacle.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::SelfIntersection {
                    part: Part::Obstacle(2),
                    ..
                })
            )
        }),
        ("negative_max_area.json", |f| {
            invalid_at(f, "mesh.max_area", "positive")
        }),
        ("start_not_finite.json", |f| {
            parse_error_at(f, "starts[1][0]", "number out of range")
        }),
        ("robin_overflow.json", |f| {
            parse_error_at(f, "boundary.walls.robin.g", "number out of range")
        }),
        ("obstacle_robin_both_zero.json", |f| {
            invalid_at(f, "obstacles[0].boundary", "a = b = 0")
        }),
        (
            "negative_robin.json",
            |f| matches!(fem_error(f), Some(FemError::NegativeRobin { part, .. }) if part.contains("wall")),
        ),
        ("unknown_condition.json", |f| {
            parse_error_at(f, "boundary.goal", "unknown variant `drichlet`")
        }),
        ("goal_too_narrow_for_robot.json", |f| {
            matches!(
                mesh_error(f),
                Some(MeshError::GoalNotInFreeSpace { goal: 0, .. })
            )
        }),
    ];
    let dir = root().join("tests/bad_scenes");
    let mut listed: Vec<&str> = table.iter().map(|(f, _)| *f).collect();
    listed.sort_unstable();
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .expect("tests/bad_scenes exists")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".json"))
        .collect();
    on_disk.sort_unstable();
    assert_eq!(
        listed, on_disk,
        "every bad scene has a check here, and every check a file"
    );
    let mut wrong = Vec::new();
    for (file, check) in table {
        let f = catch_unwind(|| bad_scene(file)).unwrap_or_else(|_| panic!("{file}: panicked"));
        if !check(&f) {
            wrong.push(format!("{file}: got {f:?}"));
        }
    }
    assert!(wrong.is_empty(), "wrong errors:\n{}", wrong.join("\n"));
}

#[test]
fn a_file_that_is_not_utf8_is_an_io_error_naming_the_file() {
    let path = std::env::temp_dir().join(format!("hplan-robust-{}.json", std::process::id()));
    std::fs::write(&path, [0x7b, 0xff, 0xfe, 0x7d]).expect("temp file written");
    let e = Scene::from_file(&path).expect_err("not UTF-8");
    let _ = std::fs::remove_file(&path);
    assert!(
        matches!(&e, SceneError::Io { file, .. } if file.ends_with(".json")),
        "{e:?}"
    );
    let e = Scene::from_file(root().join("no/such/scene.json")).expect_err("missing");
    assert!(e.to_string().contains("no/such/scene.json"), "{e}");
}

const SQUARE: &str = r#""workspace": [[0,0],[10,0],[10,10],[0,10]]"#;

/// A frame of four overlapping bars (merged into one obstacle with a hole) seals a pocket.
const FRAME: &str = r#""obstacles": [
    {"polygon": [[3,3],[7,3],[7,3.5],[3,3.5]]},
    {"polygon": [[6.5,3],[7,3],[7,7],[6.5,7]]},
    {"polygon": [[3,6.5],[7,6.5],[7,7],[3,7]]},
    {"polygon": [[3,3],[3.5,3],[3.5,7],[3,7]]}]"#;

#[test]
fn bad_starts_are_statuses_not_errors() {
    let text = format!(
        r#"{{{SQUARE}, {FRAME}, "goal": {{"circle": {{"center": [9, 1], "radius": 0.3}}}},
            "mesh": {{"max_area": 0.05}}}}"#
    );
    let scene = Scene::from_json(&text).expect("the scene is valid");
    let planner = Planner::new(&scene).expect("a sealed pocket is not an error");
    assert!(
        planner.mesh().component_count() >= 2,
        "the pocket is its own component"
    );
    let cases = [
        ([1.0, 9.0], "reached_goal"),
        ([5.0, 5.0], "unreachable"),
        ([3.2, 5.0], "start_in_obstacle"),
        ([-1.0, 5.0], "outside_workspace"),
        ([20.0, 20.0], "outside_workspace"),
    ];
    for (start, want) in cases {
        for path in [planner.plan(start), planner.plan_exact(start)] {
            assert_eq!(
                path.status.as_str(),
                want,
                "from {start:?} ({})",
                path.tracer
            );
            assert!(path.length.is_finite() && path.min_clearance.is_finite());
            assert!(path.points.iter().flatten().all(|v| v.is_finite()));
        }
    }
    let json = serde_json::to_string(&planner.plan_report(&cases.map(|c| c.0)))
        .expect("the report serialises");
    assert!(!json.contains("null"), "non-finite number in {json}");
}

/// Found by tests/properties.rs: a start outside the workspace, beside (not in) an obstacle
/// that reaches over the wall, is reported as `start_in_obstacle`.
/// `harmonic_trajectory::field` `classify_outside` casts a ray to the right and takes the tag
/// of the first boundary edge it meets; there the obstacle has replaced the wall.
#[test]
#[ignore = "harmonic-trajectory classify_outside: outside start beside an obstacle over the wall; see report"]
fn start_outside_beside_an_obstacle_over_the_wall_is_outside() {
    let text = format!(
        r#"{{{SQUARE}, "obstacles": [{{"polygon": [[1.7420848154505768, 3.2193008342579827],
            [1.2416123616265027, 4.215687202016823], [-0.541440555532336, 2.5424136515861635]]}}],
            "goal": {{"circle": {{"center": [0.7, 0.7], "radius": 0.2}}}}, "mesh": {{"max_area": 0.08}}}}"#
    );
    let scene = Scene::from_json(&text).expect("valid");
    let planner = Planner::new(&scene).expect("plans");
    let start = [-0.47063641634060016, 2.87149896653013];
    assert_eq!(planner.plan(start).status.as_str(), "outside_workspace");
    assert_eq!(
        planner.plan_exact(start).status.as_str(),
        "outside_workspace"
    );
}

#[test]
fn a_sealed_pocket_with_neumann_walls_is_named() {
    // Inside the frame only Neumann conditions hold: that piece of free space has no
    // reference value, and the error says which piece.
    let text = format!(
        r#"{{{SQUARE}, {FRAME}, "goal": {{"circle": {{"center": [9, 1], "radius": 0.3}}}},
            "boundary": {{"obstacles": {{"neumann": 0}}}}, "mesh": {{"max_area": 0.05}}}}"#
    );
    let f = attempt(&text);
    match fem_error(&f) {
        Some(FemError::OnlyNeumann { at, .. }) => assert!(
            at.coords().iter().all(|c| (3.5..=6.5).contains(c)),
            "the error points into the pocket: {at}"
        ),
        _ => panic!("expected OnlyNeumann for the pocket, got {f:?}"),
    }
}

fn triangle_error(node: &str, ele: &str, poly: Option<&str>) -> (String, usize, String) {
    match catch_unwind(|| io::from_triangle(node, ele, poly)) {
        Err(_) => panic!("from_triangle panicked on\n{node}\n--\n{ele}\n--\n{poly:?}"),
        Ok(Ok(_)) => panic!("accepted a bad mesh:\n{node}\n--\n{ele}\n--\n{poly:?}"),
        Ok(Err(MeshError::Io {
            file,
            line,
            message,
        })) => (file, line, message),
        Ok(Err(e)) => (String::new(), 0, e.to_string()),
    }
}

const NODE: &str = "4 2 0 1\n0 0 0 1\n1 1 0 1\n2 1 1 1\n3 0 1 1\n";
const ELE: &str = "2 3 0\n0 0 1 2\n1 0 2 3\n";

#[test]
fn good_triangle_files_read() {
    let mesh = io::from_triangle(NODE, ELE, None).expect("a valid unit square");
    assert_eq!(mesh.triangles().len(), 2);
    assert_eq!(mesh.boundary_edges().len(), 4);
}

/// `.node`, `.ele`, optional `.poly` contents, then the file, line and message fragment
/// of the error they must give.
type TriangleCase<'a> = (&'a str, &'a str, Option<&'a str>, &'a str, usize, &'a str);

#[test]
fn bad_triangle_files_are_refused_with_file_and_line() {
    let cases: &[TriangleCase] = &[
        ("", ELE, None, ".node", 0, "empty file"),
        ("# only a comment\n", ELE, None, ".node", 0, "empty file"),
        ("four 2 0 1\n", ELE, None, ".node", 1, "not a number"),
        (
            "4 2 0 1\n0 0 0 1\n1 1 0 1\n",
            ELE,
            None,
            ".node",
            1,
            "expected 4 vertices, found 2",
        ),
        (
            "4 2 0 1\n0 0 0 1\n1 1 0 1\n5 1 1 1\n3 0 1 1\n",
            ELE,
            None,
            ".node",
            4,
            "vertex number 5, expected 2",
        ),
        (
            "4 2 0 1\n0 0 0 1\n1 1 0 1\n2 inf 1 1\n3 0 1 1\n",
            ELE,
            None,
            ".node",
            4,
            "non-finite",
        ),
        (
            "4 2 0 1\n0 0 0 1\n1 1 0 1\n2 NaN 1 1\n3 0 1 1\n",
            ELE,
            None,
            ".node",
            4,
            "non-finite",
        ),
        (
            "4 2 0 1\n0 0 0 1\n1 1 0 1\n2 1 1\n3 0 1 1\n",
            ELE,
            None,
            ".node",
            4,
            "missing field 4",
        ),
        (NODE, "", None, ".ele", 0, "empty file"),
        (
            NODE,
            "2 3 0\n0 0 1 2\n",
            None,
            ".ele",
            1,
            "expected 2 triangles, found 1",
        ),
        (NODE, "1 3 0\n0 0 1 9\n", None, ".ele", 2, "vertex 9"),
        (NODE, "1 3 0\n0 0 1 -2\n", None, ".ele", 2, "not a number"),
        (
            NODE,
            ELE,
            Some("0 2 0 1\n1 1\n0 0 7 1\n0\n"),
            ".poly",
            3,
            "missing vertex",
        ),
        (
            NODE,
            ELE,
            Some("0 2 0 1\n3 1\n0 0 1 1\n"),
            ".poly",
            2,
            "expected 3 segments, found 1",
        ),
        (
            NODE,
            ELE,
            Some("2 2 0 0\n0 0 0\n1 1 0\n"),
            ".poly",
            1,
            "2 vertices, the .node file has 4",
        ),
    ];
    let mut wrong = Vec::new();
    for (node, ele, poly, file, line, fragment) in cases {
        let (f, l, m) = triangle_error(node, ele, *poly);
        if !(f == *file && l == *line && m.contains(fragment)) {
            wrong.push(format!(
                "wanted {file}:{line}: …{fragment}…, got {f}:{l}: {m}"
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn inconsistent_triangle_meshes_are_refused() {
    // Structurally valid files describing a bad mesh: the mesh constructor refuses them.
    let cases: &[(&str, &str)] = &[
        // A triangle with a repeated vertex.
        (NODE, "1 3 0\n0 0 0 2\n"),
        // Three collinear vertices.
        ("3 2 0 1\n0 0 0 1\n1 1 0 1\n2 2 0 1\n", "1 3 0\n0 0 1 2\n"),
        // Three triangles on one edge (non-manifold).
        (
            "5 2 0 1\n0 0 0 1\n1 1 0 1\n2 0 1 1\n3 1 1 1\n4 0.5 -1 1\n",
            "3 3 0\n0 0 1 2\n1 0 1 3\n2 0 1 4\n",
        ),
    ];
    for (node, ele) in cases {
        let (_, _, m) = triangle_error(node, ele, None);
        assert!(!m.is_empty(), "{node}\n{ele}");
    }
}

/// A count in a header is trusted for `Vec::with_capacity` before any data is read.
#[test]
fn huge_counts_in_headers_are_refused() {
    let (_, line, m) = triangle_error("1000000000000000000 2 0 0\n0 0 0\n", ELE, None);
    assert!(line == 1 && m.contains("expected"), "{m}");
    let (_, line, m) = triangle_error(NODE, "1000000000000000000 3 0\n0 0 1 2\n", None);
    assert!(line == 1 && m.contains("expected"), "{m}");
}

/// CI replays the fuzz corpus (seeds, and inputs the fuzzer found, kept as regressions)
/// through the fuzz target's own code: no input may panic.
#[test]
fn the_fuzz_corpus_replays_without_a_panic() {
    let files = harmonic_fixtures::fuzz_corpus("scene");
    assert!(files.len() >= 30, "seed corpus present: {}", files.len());
    let (outcomes, panicked) = harmonic_fixtures::replay(&files, fuzz_case::run);
    assert!(panicked.is_empty(), "panicked:\n{}", panicked.join("\n"));
    let planned = outcomes
        .iter()
        .filter(|o| matches!(o, fuzz_case::Outcome::Planned(_)))
        .count();
    assert!(planned >= 7, "the bundled scenes plan: {planned}");
}

/// The three inputs the `scene` target flagged as slow (`fuzz/corpus/scene/found_slow_*`,
/// up to 32 s under AddressSanitizer): two reference variants with a goal polygon whose
/// vertices jump thousands of units outside the workspace, and a 1.4° sliver workspace.
/// Their time went to refinement rounds that each could add the whole vertex budget again
/// (the halves' cut rounds times the bridge rounds on the first two, the bridge rounds on
/// the sliver: 146 k triangles for a 23-triangle estimate). The budget now bounds the
/// vertices of all rounds of a piece together, so each finishes with a mesh of at most the
/// input plus the budget's vertices per piece, and plans (or is refused with a typed error).
#[test]
fn the_slow_fuzz_inputs_stay_within_the_vertex_budget() {
    use harmonic_planner::mesh::{Domain, MeshOptions};
    let dir = root().join("fuzz/corpus/scene");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("fuzz/corpus/scene exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("found_slow_"))
        })
        .collect();
    files.sort();
    assert_eq!(files.len(), 3, "{files:?}");
    for file in &files {
        let text = std::fs::read_to_string(file).expect("readable");
        let mut scene = Scene::from_json(&text).expect("a valid scene");
        fuzz_case::cap_mesh(&mut scene);
        for halves_from in [0, usize::MAX] {
            let opts = MeshOptions {
                halves_from,
                ..scene.mesh_options()
            };
            let domain = Domain::new(&scene.domain_spec(), &opts).expect("a valid domain");
            let (mesh, report) = domain.mesh(&opts).expect("meshes");
            // The budget's floor is `MIN_VERTEX_BUDGET` added vertices (a piece of a mesh in
            // halves has half of it; the cut exchange adds the other half's cut vertices).
            let bound = report.input_vertices + 2 * harmonic_planner::mesh::MIN_VERTEX_BUDGET;
            assert!(
                mesh.vertices().len() <= bound,
                "{}: {} vertices, more than {bound} (halves_from {halves_from})",
                file.display(),
                mesh.vertices().len()
            );
        }
        assert!(
            matches!(
                fuzz_case::run(text.as_bytes()),
                fuzz_case::Outcome::Planned(_) | fuzz_case::Outcome::NotPlannable
            ),
            "{}",
            file.display()
        );
    }
}

/// The fuzzer's `found_spade_locate_panic_near_wall_vertex.json`: an obstacle corner 2e-16
/// above the wall y = 0. It used to fail with a misleading "invalid mesh" error (spade's
/// refinement panicked on the sliver); the corner is now snapped onto the wall, the obstacle
/// touches it, and the scene plans at its own mesh size.
#[test]
fn an_obstacle_corner_a_rounding_error_off_the_wall_plans() {
    let path = root().join("fuzz/corpus/scene/found_spade_locate_panic_near_wall_vertex.json");
    let scene = Scene::from_file(&path).expect("a valid scene");
    let planner = Planner::new(&scene).expect("plans");
    for &start in &scene.starts {
        let path = planner.plan(start);
        assert_eq!(
            path.status.as_str(),
            "reached_goal",
            "from {start:?}: {path:?}"
        );
        assert!(path.min_clearance > 0.0, "from {start:?}");
    }
}

/// The cap keeps a fuzz case small whatever `max_area` the scene asks for.
#[test]
fn the_fuzz_cap_bounds_the_mesh() {
    let mut scene = Scene::from_json(&format!(
        r#"{{{SQUARE}, "goal": {{"point": [9, 9]}}, "mesh": {{"max_area": 1e-9}}}}"#
    ))
    .expect("valid");
    fuzz_case::cap_mesh(&mut scene);
    assert_eq!(scene.mesh.max_area, Some(100.0 / fuzz_case::TRIANGLE_CAP));
    let planner = Planner::new(&scene).expect("plans");
    let n = planner.mesh().triangles().len() as f64;
    assert!(n < 2.0 * fuzz_case::TRIANGLE_CAP, "{n} triangles");
    // A coarser mesh than the cap is left alone.
    let mut coarse = scene.clone();
    coarse.mesh.max_area = Some(1.0);
    fuzz_case::cap_mesh(&mut coarse);
    assert_eq!(coarse.mesh.max_area, Some(1.0));
}
