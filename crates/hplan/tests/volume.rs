//! `hplan` on volume scenes (`"dimension": 3`): the bundled small volumes plan from every
//! start to the goal, the paths stay out of the exact solids, the export has no strict
//! interior local minimum, and bad volume scenes fail with one line.

mod common;

use common::{hplan, run_json};
use serde_json::Value;

/// Signed distance to an axis-aligned box (negative inside).
fn box_distance(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    let q: Vec<f64> = (0..3)
        .map(|k| (p[k] - 0.5 * (lo[k] + hi[k])).abs() - 0.5 * (hi[k] - lo[k]))
        .collect();
    let outside = q.iter().map(|v| v.max(0.0).powi(2)).sum::<f64>().sqrt();
    outside + q.iter().copied().fold(f64::NEG_INFINITY, f64::max).min(0.0)
}

fn triple(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("[x, y, z]");
    [0, 1, 2].map(|k| a[k].as_f64().expect("a number"))
}

/// An axis-aligned box as its (min, max) corners.
type Aabb = ([f64; 3], [f64; 3]);

/// The box workspace of a scene file and its box obstacles.
fn boxes(scene: &Value) -> ([f64; 3], [f64; 3], Vec<Aabb>) {
    let ws = &scene["workspace"]["box"];
    let obstacles = scene["obstacles"]
        .as_array()
        .map(|v| v.as_slice())
        .unwrap_or_default()
        .iter()
        .filter_map(|o| o.get("box"))
        .map(|b| (triple(&b["min"]), triple(&b["max"])))
        .collect();
    (triple(&ws["min"]), triple(&ws["max"]), obstacles)
}

#[test]
fn small_bundled_volumes_reach_the_goal_and_stay_out_of_the_solids() {
    for name in ["torus3d.json", "maze3d.json"] {
        let file = harmonic_fixtures::mesh_file(name);
        let scene: Value =
            serde_json::from_str(&std::fs::read_to_string(&file).expect("scene")).expect("json");
        let (lo, hi, obstacles) = boxes(&scene);
        let radius = scene["robot"]["radius"].as_f64().unwrap_or(0.0);
        assert!(!obstacles.is_empty(), "{name}: box obstacles");
        let path = file.to_str().expect("utf-8");
        let report = run_json(&["plan", path, "--json"]);
        assert!(report["mesh"]["tetrahedra"].as_u64().expect("count") > 1000);
        assert_eq!(report["potential"]["interior_local_extrema"], 0, "{name}");
        let paths = report["paths"].as_array().expect("paths");
        assert_eq!(
            paths.len(),
            scene["starts"].as_array().expect("starts").len()
        );
        for p in paths {
            assert_eq!(p["status"], "reached_goal", "{name}: {}", p["start"]);
            let points: Vec<[f64; 3]> = p["points"]
                .as_array()
                .expect("points")
                .iter()
                .map(triple)
                .collect();
            // Every point of every segment, sampled at 1/50 of its length, keeps the robot's
            // radius from every box obstacle and from the workspace's walls.
            for w in points.windows(2) {
                for s in 0..=50 {
                    let t = f64::from(s) / 50.0;
                    let q = [0, 1, 2].map(|k| w[0][k] + t * (w[1][k] - w[0][k]));
                    let wall = -box_distance(q, lo, hi);
                    assert!(wall >= radius - 1e-9, "{name}: {q:?} {wall} from the walls");
                    for &(a, b) in &obstacles {
                        let d = box_distance(q, a, b);
                        assert!(d >= radius - 1e-9, "{name}: {q:?} {d} from {a:?}–{b:?}");
                    }
                }
            }
        }
    }
}

#[test]
fn a_volume_export_has_tetrahedra_and_no_interior_minimum() {
    let dir = std::env::temp_dir().join(format!("hplan-volume-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let out = dir.join("torus.json");
    let vtu = dir.join("torus.vtu");
    let file = harmonic_fixtures::mesh_file("torus3d.json");
    hplan()
        .args(["export"])
        .arg(&file)
        .arg("--potential")
        .arg(&out)
        .arg("--vtk")
        .arg(&vtu)
        .assert()
        .success();
    let export: Value =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("written")).expect("json");
    let tets = export["tetrahedra"].as_array().expect("tetrahedra");
    let psi: Vec<f64> = export["psi"]
        .as_array()
        .expect("psi")
        .iter()
        .map(|v| v.as_f64().expect("number"))
        .collect();
    let n = psi.len();
    // A vertex on a boundary face is not interior.
    let mut boundary = vec![false; n];
    for f in export["boundary_faces"].as_array().expect("faces") {
        for k in 0..3 {
            boundary[f[k].as_u64().expect("index") as usize] = true;
        }
    }
    // Recount strict local minima of φ (maxima of ψ) over edge neighbours.
    let mut dominated = vec![false; n];
    for t in tets {
        let v: Vec<usize> = (0..4)
            .map(|k| t[k].as_u64().expect("index") as usize)
            .collect();
        for a in 0..4 {
            for b in 0..4 {
                if a != b && psi[v[b]] >= psi[v[a]] {
                    dominated[v[a]] = true;
                }
            }
        }
    }
    let minima = (0..n).filter(|&v| !boundary[v] && !dominated[v]).count();
    assert_eq!(minima, 0);
    let vtu = std::fs::read_to_string(&vtu).expect("vtu written");
    assert!(vtu.contains("<UnstructuredGrid>") && vtu.contains("psi"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_volume_input_fails_with_one_line() {
    let dir = std::env::temp_dir().join(format!("hplan-badvol-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let cases = [
        (
            r#"{"dimension": 3, "workspace": {"box": {"min": [0, 0, 0], "max": [-1, 1, 1]}},
                "goal": {"point": [0.5, 0.5, 0.5]}}"#,
            "workspace",
        ),
        (
            r#"{"dimension": 3, "workspace": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}},
                "obstacles": [{"sphere": {"center": [0.5, 0.5, 0.5], "radius": -1}}],
                "goal": {"point": [0.1, 0.1, 0.1]}}"#,
            "obstacle",
        ),
        (
            r#"{"dimension": 4, "workspace": [[0, 0], [1, 0], [1, 1]], "goal": {"point": [0.5, 0.5]}}"#,
            "dimension",
        ),
        (
            r#"{"dimension": 3, "workspace": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}},
                "goal": {"point": [0.5, 0.5, 0.5]}, "bogus": 1}"#,
            "bogus",
        ),
    ];
    for (i, (text, fragment)) in cases.iter().enumerate() {
        let file = dir.join(format!("bad{i}.json"));
        std::fs::write(&file, text).expect("write");
        let out = hplan().arg("plan").arg(&file).output().expect("runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{text} planned");
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(fragment), "wanted `{fragment}` in: {err}");
    }
    // A plane start on a volume and a volume flag on a plane scene are named.
    let torus = harmonic_fixtures::mesh_file("torus3d.json");
    let out = hplan()
        .arg("plan")
        .arg(&torus)
        .args(["--start", "1,1"])
        .output()
        .expect("runs");
    assert!(String::from_utf8_lossy(&out.stderr).contains("X,Y,Z"));
    let reference = harmonic_fixtures::mesh_file("reference.json");
    let out = hplan()
        .arg("plan")
        .arg(&reference)
        .args(["--max-volume", "0.1"])
        .output()
        .expect("runs");
    assert!(String::from_utf8_lossy(&out.stderr).contains("--max-area"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Agreement with an outside solver: scikit-fem's own P1 Laplacian on our tetrahedra, with our
/// boundary values held, gives our interior φ to rounding (`tests/peers/skfem_volume.py`).
/// Runs where a Python with scikit-fem is found (`HARMONIC_PEER_PYTHON`, else `python3`);
/// CI installs it. Elsewhere it says it skipped.
#[test]
fn scikit_fem_solves_the_same_system_on_our_tetrahedra() {
    let python = std::env::var("HARMONIC_PEER_PYTHON").unwrap_or_else(|_| "python3".into());
    let has_skfem = std::process::Command::new(&python)
        .args(["-c", "import skfem"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_skfem {
        eprintln!("skipped: no scikit-fem for {python} (set HARMONIC_PEER_PYTHON)");
        return;
    }
    let dir = std::env::temp_dir().join(format!("hplan-skfem-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let export = dir.join("torus.json");
    hplan()
        .arg("export")
        .arg(harmonic_fixtures::mesh_file("torus3d.json"))
        .arg("--potential")
        .arg(&export)
        .assert()
        .success();
    let script = harmonic_fixtures::repo_root().join("tests/peers/skfem_volume.py");
    let out = std::process::Command::new(&python)
        .arg(script)
        .arg(&export)
        .output()
        .expect("the peer script runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let result: Value = serde_json::from_slice(&out.stdout).expect("one JSON line");
    let max = result["max_abs_diff"].as_f64().expect("max_abs_diff");
    assert!(result["interior"].as_u64().expect("interior") > 1000);
    assert!(max < 1e-10, "scikit-fem differs by {max}: {result}");
    eprintln!("scikit-fem {}: max |Δφ| {max:.2e}", result["skfem"]);
    let _ = std::fs::remove_dir_all(&dir);
}
