//! Any scale, any offset: a scene is meshed in its unit frame (`harmonic_mesh::Frame`), so
//! the reference scene scaled by 1e-150 … 1e150 and moved away from the origin (up to a few
//! hundred times its size: beyond, its own coordinates no longer hold its twelve decimals)
//! gets the same mesh and plans the same paths, scaled.

use harmonic_planner::{Planner, Scene};

/// The scene with every length multiplied by `s` and every point moved by `o` afterwards.
fn scaled(scene: &Scene, s: f64, o: [f64; 2]) -> Scene {
    let p = |q: [f64; 2]| [q[0] * s + o[0], q[1] * s + o[1]];
    let region = |r: &harmonic_planner::scene::Region| {
        let mut r = r.clone();
        r.polygon = r.polygon.map(|v| v.into_iter().map(p).collect());
        if let Some(c) = r.circle.as_mut() {
            c.center = p(c.center);
            c.radius *= s;
        }
        r.point = r.point.map(p);
        r
    };
    let mut out = scene.clone();
    out.workspace = scene.workspace.iter().copied().map(p).collect();
    out.obstacles = scene.obstacles.iter().map(region).collect();
    out.goal.0 = scene.goal.0.iter().map(region).collect();
    out.starts = scene.starts.iter().copied().map(p).collect();
    out.mesh.max_area = scene.mesh.max_area.map(|a| a * s * s);
    out.robot.radius *= s;
    out
}

#[test]
fn the_reference_scene_plans_the_same_at_every_scale_and_offset() {
    let file = harmonic_fixtures::mesh_file("reference.json");
    let scene = Scene::from_file(&file).expect("reference scene");
    let base = Planner::new(&scene).expect("plans at scale 1");
    let starts = [[1.0, 9.0], [8.5, 1.5], [5.5, 6.0]];
    let expected = base.plan_report(&starts);
    for (s, o) in [
        (1e-150, [0.0, 0.0]),
        (1e-150, [3e-148, -7e-149]),
        (1e-6, [0.0, 0.0]),
        (1e-6, [3e-5, -2e-4]),
        (1.0, [1e3, -2e3]),
        (1e6, [-3e8, 0.0]),
        (1e150, [0.0, 0.0]),
        (1e150, [-2e153, 5e152]),
    ] {
        let moved = scaled(&scene, s, o);
        let planner =
            Planner::new(&moved).unwrap_or_else(|e| panic!("scale {s}, offset {o:?}: {e}"));
        let starts_here: Vec<[f64; 2]> = starts
            .iter()
            .map(|q| [q[0] * s + o[0], q[1] * s + o[1]])
            .collect();
        let report = planner.plan_report(&starts_here);
        // The same unit scene bit for bit, so the same mesh.
        assert_eq!(
            report.mesh.triangles, expected.mesh.triangles,
            "scale {s}, offset {o:?}"
        );
        for (a, b) in expected.paths.iter().zip(&report.paths) {
            assert_eq!(
                a.status, b.status,
                "scale {s}, offset {o:?}, start {:?}",
                a.start
            );
            let rel = (b.length / s - a.length).abs() / a.length.max(f64::MIN_POSITIVE);
            assert!(
                rel < 1e-6,
                "scale {s}, offset {o:?}, start {:?}: length {} vs {} (relative {rel:e})",
                a.start,
                b.length / s,
                a.length
            );
        }
    }
}

/// A scene whose mesh cannot be written in its own coordinates (triangle areas below f64's
/// normal range) is refused in one line that says so, not with the triangulator's words.
#[test]
fn a_scene_too_small_for_f64_is_refused_in_words() {
    let file = harmonic_fixtures::mesh_file("reference.json");
    let scene = Scene::from_file(&file).expect("reference scene");
    let tiny = scaled(&scene, 1e-160, [0.0, 0.0]);
    let Err(e) = Planner::new(&tiny) else {
        panic!("a scene of size 1e-159 was planned");
    };
    let e = e.to_string();
    assert!(e.contains("out of f64's range"), "{e}");
    assert!(!e.contains("TooSmall"), "{e}");
}
