//! `hplan plan` on polygon and arm robots: the bundled configuration-space scenes reach the
//! goal with `poses` / `joints` in the JSON, `--svg` draws the robot along its motion, and
//! starts of the wrong size fail in one line.

mod common;

use common::{hplan, run_json};

fn scene(name: &str) -> String {
    harmonic_fixtures::mesh_file(name)
        .to_str()
        .expect("utf-8 path")
        .to_string()
}

#[test]
fn piano_bar_and_arm_reach_the_goal_from_the_command_line() {
    for (name, key, dof) in [
        ("piano.json", "poses", 3),
        ("bar_kim_khosla.json", "poses", 3),
        ("arm_aperture.json", "joints", 3),
    ] {
        let report = run_json(&["plan", &scene(name), "--json"]);
        let path = &report["paths"][0];
        assert_eq!(path["status"], "reached_goal", "{name}");
        let entries = path[key].as_array().expect("configurations");
        assert!(entries.len() > 2, "{name}");
        assert!(
            entries
                .iter()
                .all(|e| e.as_array().is_some_and(|q| q.len() == dof))
        );
        assert!(path.get("points").is_none());
        assert!(path["length"].as_f64().is_some_and(|l| l > 0.0));
        assert!(report["mesh"]["tetrahedra"].as_u64().is_some_and(|t| t > 0));
    }
}

#[test]
fn svg_draws_the_robot_along_its_motion() {
    let out = std::env::temp_dir().join(format!("hplan-piano-{}.svg", std::process::id()));
    let status = hplan()
        .args([
            "plan",
            &scene("piano.json"),
            "--svg",
            out.to_str().expect("utf-8"),
        ])
        .output()
        .expect("runs");
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let svg = std::fs::read_to_string(&out).expect("written");
    let _ = std::fs::remove_file(&out);
    assert!(svg.starts_with("<svg"));
    // The robot drawn at 14 poses, plus the two obstacles and the workspace.
    assert!(svg.matches("<polygon").count() >= 14 + 3);
}

#[test]
fn a_start_of_the_wrong_size_fails_in_one_line() {
    let out = hplan()
        .args(["plan", &scene("piano.json"), "--start", "1,2"])
        .output()
        .expect("runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("X,Y,THETA"), "{err}");
}
