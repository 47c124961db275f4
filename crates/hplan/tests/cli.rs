//! End-to-end tests of `hplan` against the contract of docs/scene-format.md: every bundled scene
//! plans, the JSON fields are present and consistent with an independent recount, and every
//! bad scene fails with one clear line.

use std::path::PathBuf;

mod common;

use common::{hplan, run_json};
use serde_json::Value;

fn scenes() -> Vec<PathBuf> {
    let v = harmonic_fixtures::plane_scenes();
    assert!(v.len() >= 6, "expected the bundled scenes, found {v:?}");
    v
}

type Seg = ([f64; 2], [f64; 2]);

fn seg_seg_distance((p1, p2): Seg, (q1, q2): Seg) -> f64 {
    use harmonic_planner::mesh::geom::segment_segment_distance;
    segment_segment_distance(p1.into(), p2.into(), q1.into(), q2.into())
}

fn ring_segments(points: &[Value]) -> Vec<Seg> {
    let pts: Vec<[f64; 2]> = points
        .iter()
        .map(|p| [p[0].as_f64().expect("x"), p[1].as_f64().expect("y")])
        .collect();
    (0..pts.len())
        .map(|i| (pts[i], pts[(i + 1) % pts.len()]))
        .collect()
}

/// Walls and polygonal obstacles of a scene, straight from its JSON, and the largest chord
/// error of its circles (the mesher replaces circles by inscribed polygons).
fn exact_boundary(scene: &Value) -> (Vec<Seg>, Vec<([f64; 2], f64)>) {
    let mut segs = ring_segments(scene["workspace"].as_array().expect("workspace"));
    let mut circles = Vec::new();
    for o in scene["obstacles"].as_array().into_iter().flatten() {
        if let Some(p) = o["polygon"].as_array() {
            segs.extend(ring_segments(p));
        } else {
            let c = &o["circle"];
            circles.push((
                [
                    c["center"][0].as_f64().expect("cx"),
                    c["center"][1].as_f64().expect("cy"),
                ],
                c["radius"].as_f64().expect("r"),
            ));
        }
    }
    (segs, circles)
}

#[test]
fn every_bundled_scene_plans_and_its_report_is_consistent() {
    for scene_path in scenes() {
        let path = scene_path.to_str().expect("utf-8 path");
        let scene: Value =
            serde_json::from_str(&std::fs::read_to_string(&scene_path).expect("readable"))
                .expect("JSON");
        let report = run_json(&["plan", path, "--json"]);
        for key in ["vertices", "triangles", "min_angle_deg"] {
            assert!(report["mesh"][key].is_number(), "{path}: mesh.{key}");
        }
        for key in ["mesh", "assemble", "solve", "trace"] {
            assert!(
                report["timings_ms"][key].as_f64().is_some_and(|t| t >= 0.0),
                "{path}: timings_ms.{key}"
            );
        }
        assert_eq!(report["potential"]["interior_local_minima"], 0, "{path}");

        // Independent recount of interior local minima from the exported potential.
        let out = std::env::temp_dir().join(format!(
            "hplan-export-{}-{}.json",
            std::process::id(),
            scene_path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("scene")
        ));
        let status = hplan()
            .args(["export", path, "--potential", out.to_str().expect("utf-8")])
            .output()
            .expect("export runs");
        assert!(
            status.status.success(),
            "{}",
            String::from_utf8_lossy(&status.stderr)
        );
        let export: Value =
            serde_json::from_str(&std::fs::read_to_string(&out).expect("export written"))
                .expect("JSON");
        let _ = std::fs::remove_file(&out);
        let values: Vec<f64> = export["values"]
            .as_array()
            .expect("values")
            .iter()
            .map(|v| v.as_f64().expect("num"))
            .collect();
        let tris = export["triangles"].as_array().expect("triangles");
        assert_eq!(
            tris.len(),
            report["mesh"]["triangles"].as_u64().expect("count") as usize
        );
        let mut on_boundary = vec![false; values.len()];
        for e in export["boundary_edges"].as_array().expect("boundary edges") {
            on_boundary[e[0].as_u64().expect("i") as usize] = true;
            on_boundary[e[1].as_u64().expect("j") as usize] = true;
            let tag = e[2].as_str().expect("tag");
            assert!(
                tag == "wall" || tag.starts_with("obstacle:") || tag.starts_with("goal:"),
                "{tag}"
            );
        }
        let psi: Vec<f64> = export["psi"]
            .as_array()
            .expect("psi")
            .iter()
            .map(|v| v.as_f64().expect("num"))
            .collect();
        let mut has_lower_or_equal = vec![false; values.len()];
        for t in tris {
            let t: Vec<usize> = t
                .as_array()
                .expect("tri")
                .iter()
                .map(|v| v.as_u64().expect("idx") as usize)
                .collect();
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                // Compare ψ: φ rounds to the wall value where ψ is tiny.
                if psi[b] >= psi[a] {
                    has_lower_or_equal[a] = true;
                }
                if psi[a] >= psi[b] {
                    has_lower_or_equal[b] = true;
                }
            }
        }
        let recount = (0..values.len())
            .filter(|&v| !on_boundary[v] && !has_lower_or_equal[v])
            .count();
        assert_eq!(
            recount as u64,
            report["potential"]["interior_local_minima"]
                .as_u64()
                .expect("count"),
            "{path}"
        );

        // Paths: statuses from the contract; clearance equals an independent exact distance.
        let (segs, circles) = exact_boundary(&scene);
        let radius = scene["robot"]["radius"].as_f64().unwrap_or(0.0);
        let chord = circles.iter().map(|c| c.1).fold(0.0, f64::max) * 0.01 + 1e-9;
        for p in report["paths"].as_array().expect("paths") {
            let status = p["status"].as_str().expect("status");
            assert!(
                [
                    "reached_goal",
                    "unreachable",
                    "stalled",
                    "start_in_obstacle",
                    "outside_workspace",
                    "max_steps"
                ]
                .contains(&status),
                "{path}: {status}"
            );
            assert_eq!(
                status, "reached_goal",
                "{path}: bundled starts all reach the goal: {p}"
            );
            let pts: Vec<[f64; 2]> = p["points"]
                .as_array()
                .expect("points")
                .iter()
                .map(|q| [q[0].as_f64().expect("x"), q[1].as_f64().expect("y")])
                .collect();
            let mut exact = f64::INFINITY;
            for w in pts.windows(2) {
                for s in &segs {
                    exact = exact.min(seg_seg_distance((w[0], w[1]), *s));
                }
                for &(c, r) in &circles {
                    let d = seg_seg_distance((w[0], w[1]), (c, c)) - r;
                    exact = exact.min(d.max(0.0));
                }
            }
            let reported = p["min_clearance"].as_f64().expect("clearance");
            assert!(
                exact > radius,
                "{path}: the path touches an obstacle (clearance {exact})"
            );
            if radius == 0.0 {
                assert!(
                    (reported - exact).abs() <= chord.max(1e-9 * exact.max(1.0)),
                    "{path}: reported clearance {reported} but the exact distance is {exact}"
                );
            }
            let length: f64 = pts
                .windows(2)
                .map(|w| ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt())
                .sum();
            assert!(
                (length - p["length"].as_f64().expect("length")).abs() < 1e-9 * length.max(1.0)
            );
        }
    }
}

#[test]
fn svg_and_vtk_are_written() {
    let dir = std::env::temp_dir();
    let svg = dir.join(format!("hplan-{}.svg", std::process::id()));
    let vtu = dir.join(format!("hplan-{}.vtu", std::process::id()));
    let scene = harmonic_fixtures::mesh_file("reference.json");
    hplan()
        .args([
            "plan",
            scene.to_str().expect("utf-8"),
            "--svg",
            svg.to_str().expect("utf-8"),
        ])
        .args([
            "--vtk",
            vtu.to_str().expect("utf-8"),
            "--mesh",
            "--start",
            "1,1",
            "--start",
            "9,9",
        ])
        .assert()
        .success();
    let text = std::fs::read_to_string(&svg).expect("svg written");
    assert!(text.starts_with("<svg") && text.contains("<path"));
    let text = std::fs::read_to_string(&vtu).expect("vtu written");
    assert!(text.contains("UnstructuredGrid") && text.contains("Name=\"phi\""));
    let _ = std::fs::remove_file(svg);
    let _ = std::fs::remove_file(vtu);
}

#[test]
fn car_reports_poses() {
    let scene = harmonic_fixtures::mesh_file("reference.json");
    let report = run_json(&[
        "car",
        scene.to_str().expect("utf-8"),
        "--pose",
        "1,9,0",
        "--json",
    ]);
    let p = &report["paths"][0];
    assert_eq!(p["status"], "reached_goal", "{p}");
    let poses = p["poses"].as_array().expect("poses");
    assert!(poses.len() > 10 && poses[0].as_array().expect("pose").len() == 3);
}

#[test]
fn starts_outside_or_in_obstacles_are_statuses_not_errors() {
    let scene = harmonic_fixtures::mesh_file("reference.json");
    let report = run_json(&[
        "plan",
        scene.to_str().expect("utf-8"),
        "--json",
        "--start",
        "2.5,5",
        "--start",
        "-3,4",
    ]);
    assert_eq!(report["paths"][0]["status"], "start_in_obstacle");
    assert_eq!(report["paths"][1]["status"], "outside_workspace");
}

#[test]
fn bad_scenes_fail_with_one_clear_line() {
    let dir = harmonic_fixtures::repo_root().join("tests/bad_scenes");
    let expected = std::fs::read_to_string(dir.join("EXPECTED")).expect("EXPECTED exists");
    let mut checked = 0;
    for line in expected
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let (file, fragment) = line.split_once(": ").expect("file: fragment");
        let out = hplan()
            .args(["plan", dir.join(file).to_str().expect("utf-8"), "--json"])
            .output()
            .expect("hplan runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{file}: should fail");
        assert!(!stderr.contains("panicked"), "{file}: panicked: {stderr}");
        assert_eq!(
            stderr.trim_end().lines().count(),
            1,
            "{file}: one line, got {stderr}"
        );
        assert!(
            stderr.to_lowercase().contains(&fragment.to_lowercase()),
            "{file}: expected `{fragment}` in `{stderr}`"
        );
        assert!(out.stdout.is_empty(), "{file}: nothing on stdout");
        checked += 1;
    }
    assert!(checked >= 20, "{checked}");
}

#[test]
fn bad_flags_fail_clearly() {
    let scene = harmonic_fixtures::mesh_file("reference.json");
    let out = hplan()
        .args(["plan", scene.to_str().expect("utf-8"), "--start", "1,nan"])
        .output()
        .expect("runs");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a finite number"));
    let out = hplan()
        .args(["plan", "/no/such/scene.json"])
        .output()
        .expect("runs");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read"));
}
