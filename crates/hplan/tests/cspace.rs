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

/// `hplan export` on a configuration-space scene writes its slab of one period with the
/// potential (as for a volume), and the JSON report names how ψ was solved: the same slab
/// as `plan --json` reports, ψ in [0, 1] (goal 1, walls 0), the goal's faces tagged.
#[test]
fn a_configuration_space_exports_its_slab_and_says_how_it_was_solved() {
    let file = scene("piano.json");
    let report = run_json(&["plan", &file, "--json"]);
    let solved_by = report["potential"]["solved_by"]
        .as_str()
        .expect("solved_by");
    assert!(
        ["accurate", "cholesky", "pcg"]
            .iter()
            .any(|m| solved_by.starts_with(m)),
        "{solved_by}"
    );
    assert_eq!(report["potential"]["interior_local_extrema"], 0);
    let out = std::env::temp_dir().join(format!("hplan-cspace-export-{}.json", std::process::id()));
    let run = hplan()
        .args(["export", &file, "--potential", out.to_str().expect("utf-8")])
        .output()
        .expect("export runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let export: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("export written"))
            .expect("export is JSON");
    let _ = std::fs::remove_file(&out);
    let tets = export["tetrahedra"].as_array().expect("tetrahedra");
    assert_eq!(
        Some(tets.len() as u64),
        report["mesh"]["tetrahedra"].as_u64()
    );
    let vertices = export["vertices"].as_array().expect("vertices").len();
    assert_eq!(Some(vertices as u64), report["mesh"]["vertices"].as_u64());
    let psi: Vec<f64> = export["psi"]
        .as_array()
        .expect("psi")
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect();
    assert_eq!(psi.len(), vertices);
    assert!(psi.iter().all(|&v| (-1e-12..=1.0 + 1e-12).contains(&v)));
    let faces = export["boundary_faces"].as_array().expect("boundary faces");
    assert!(
        faces
            .iter()
            .any(|f| f[3].as_str().is_some_and(|t| t.starts_with("goal")))
    );
}
