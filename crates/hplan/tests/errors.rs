//! The command line's errors: every bad flag value and usage error fails with one line on
//! stderr, exit non-zero, nothing on stdout, no panic; and `hplan plan --map` end to end.

use std::path::PathBuf;

mod common;

use common::hplan;

fn root() -> PathBuf {
    harmonic_fixtures::repo_root()
}

fn warehouse_yaml() -> PathBuf {
    harmonic_fixtures::mesh_file("warehouse_map.yaml")
}

fn hplan_fails_with_one_line(args: &[&str], fragment: &str) -> Result<(), String> {
    let out = hplan().args(args).output().expect("hplan runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let ok = !out.status.success()
        && !stderr.contains("panicked")
        && stderr.trim_end().lines().count() == 1
        && stderr.to_lowercase().contains(&fragment.to_lowercase())
        && out.stdout.is_empty();
    if ok {
        Ok(())
    } else {
        Err(format!(
            "hplan {args:?}: exit {:?}, wanted one line with `{fragment}`, got:\n{stderr}",
            out.status.code()
        ))
    }
}

fn reference() -> String {
    root()
        .join("meshes/reference.json")
        .to_str()
        .expect("utf-8 path")
        .to_string()
}

/// Options checked after argument parsing fail with one line.
#[test]
fn bad_flag_values_fail_with_one_line() {
    let s = reference();
    let dir = root().join("meshes");
    let cases: &[(&[&str], &str)] = &[
        (
            &["car", &s, "--pose", "1,1,0", "--max-steer", "120"],
            "max_steer",
        ),
        (&["plan", dir.to_str().expect("utf-8")], "cannot read"),
        (&["export", &s], "--potential"),
    ];
    let wrong: Vec<String> = cases
        .iter()
        .filter_map(|(args, fragment)| hplan_fails_with_one_line(args, fragment).err())
        .collect();
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Errors found by the argument parser (unknown flags, missing arguments, values its
/// `value_parser`s refuse) also fail with one line.
#[test]
fn usage_errors_fail_with_one_line() {
    let s = reference();
    let cases: &[(&[&str], &str)] = &[
        (&["plan", &s, "--bogus"], "--bogus"),
        (&["plan", &s, "--start", "1e999,0"], "not a finite number"),
        (&["plan", &s, "--start", "1,2,3"], "expected X,Y"),
        (&["car", &s, "--pose", "1,2"], "expected X,Y,THETA"),
        (&["plan"], "required"),
        (&["frobnicate"], "frobnicate"),
        (
            &["car", &s, "--pose", "1,1,0", "--wheelbase", "-1"],
            "wheelbase",
        ),
    ];
    let wrong: Vec<String> = cases
        .iter()
        .filter_map(|(args, fragment)| hplan_fails_with_one_line(args, fragment).err())
        .collect();
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn the_command_line_plans_on_a_map() {
    // The warehouse with a start in an aisle and one in the closed closet, by a mesher.
    let plan = |mesher: &str| -> serde_json::Value {
        let out = hplan()
            .args(["plan", "--map"])
            .arg(warehouse_yaml())
            .args(["--goal", "16.5,1.5", "--robot-radius", "0.2", "--json"])
            .args([
                "--mesher",
                mesher,
                "--start",
                "3.0,4.0",
                "--start",
                "16.4,11.8",
            ])
            .output()
            .expect("runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        let paths = report["paths"].as_array().expect("paths");
        assert_eq!(paths[0]["status"], "reached_goal", "{mesher}");
        assert_ne!(paths[1]["status"], "reached_goal", "{mesher}");
        report
    };
    plan("traced");
    // The quadtree mesher: the same statuses, right isosceles triangles (45° smallest angle).
    let report = plan("quadtree");
    let min_angle = report["mesh"]["min_angle_deg"].as_f64().expect("angle");
    assert!((min_angle - 45.0).abs() < 1e-6, "{min_angle}");

    let fails = |args: &[&str], needle: &str| {
        let out = hplan()
            .current_dir(root())
            .args(args)
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(err.contains(needle), "{args:?}: {err}");
    };
    fails(&["plan", "--json"], "required");
    fails(
        &[
            "plan",
            "meshes/reference.json",
            "--map",
            "meshes/warehouse_map.yaml",
        ],
        "cannot be used with",
    );
    fails(&["plan", "--map", "meshes/warehouse_map.yaml"], "--goal");
    fails(
        &[
            "plan",
            "--map",
            "meshes/warehouse_map.yaml",
            "--goal",
            "16.5,1.5",
            "--robot-radius",
            "2",
            "--mesher",
            "quadtree",
        ],
        "closer than the robot radius 2",
    );
    fails(
        &["plan", "meshes/reference.json", "--mesher", "quadtree"],
        "--map",
    );
    fails(
        &[
            "plan",
            "--map",
            "meshes/warehouse_map.yaml",
            "--goal",
            "0.0,2.5",
        ],
        "occupied",
    );
    fails(
        &["plan", "meshes/torus3d.json", "--goal", "1,1"],
        "volume scene names its goal",
    );
}

/// A reader that goes away early (`hplan plan … --json | head -c 100`) ends the output
/// quietly: no panic, exit 0.
#[test]
fn a_closed_pipe_is_not_a_panic() {
    use std::process::{Command as Std, Stdio};
    let bin = assert_cmd::cargo::cargo_bin("hplan");
    let mut child = Std::new(bin)
        .args(["plan"])
        .arg(harmonic_fixtures::mesh_file("maze.json"))
        .arg("--json")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("hplan starts");
    // Close our end of stdout before hplan writes anything.
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("hplan ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        out.status.success(),
        "exit {:?}: {stderr}",
        out.status.code()
    );
}

/// clap's "required arguments were not provided:" runs on into the argument it names.
#[test]
fn a_missing_argument_is_named_on_the_same_line() {
    let out = hplan()
        .args(["plan", "--map"])
        .arg(warehouse_yaml())
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("not provided: --goal"),
        "one line naming --goal: {err}"
    );
}

#[test]
fn multigrid_plans_a_scene_and_is_refused_elsewhere() {
    let reference = reference();
    let report = common::run_json(&[
        "plan",
        &reference,
        "--max-area",
        "0.004",
        "--multigrid",
        "2",
        "--json",
    ]);
    let paths = report["paths"].as_array().expect("paths");
    assert!(!paths.is_empty());
    assert!(
        paths.iter().all(|p| p["status"] == "reached_goal"),
        "{paths:?}"
    );
    assert_eq!(report["mesh"]["refinement_complete"], true);

    let map = warehouse_yaml();
    let map = map.to_str().expect("utf-8 path");
    let maze3d = harmonic_fixtures::mesh_file("maze3d.json");
    let maze3d = maze3d.to_str().expect("utf-8 path");
    let cases: [(&[&str], &str); 4] = [
        (
            &[
                "plan",
                "--map",
                map,
                "--goal",
                "16.5,1.5",
                "--multigrid",
                "2",
            ],
            "cannot be used with",
        ),
        (&["plan", &reference, "--multigrid", "9"], "not in 0..=8"),
        (
            &["plan", maze3d, "--multigrid", "1"],
            "--multigrid is for plane scenes",
        ),
        (
            &[
                "plan",
                &reference,
                "--multigrid",
                "1",
                "--goal",
                "8.5,1.5",
                "--goal",
                "1,9",
            ],
            "--multigrid plans for one goal",
        ),
    ];
    for (args, fragment) in cases {
        hplan_fails_with_one_line(args, fragment).unwrap();
    }
}
