//! The ME766 blend k·φ_D + (1 − k)·φ_N from the scene file: for every k in [0, 1] it is the
//! convex combination of the two solves, discretely harmonic at every interior vertex (the
//! P1 stiffness rows vanish) and free of interior local minima.

use harmonic_planner::fem::interior_local_extrema;
use harmonic_planner::{Planner, Scene};

fn scene(k: f64) -> Scene {
    let json = format!(
        r#"{{"workspace": [[0,0],[4,0],[4,3],[0,3]],
            "obstacles": [{{"polygon": [[1,1],[2.5,1],[2.5,1.6],[1,1.6]]}},
                          {{"circle": {{"center": [3.0, 2.2], "radius": 0.3}}}}],
            "goal": {{"circle": {{"center": [3.5, 0.5], "radius": 0.2}}}},
            "boundary": {{"blend": {{"k": {k}, "neumann": 1.0}}}},
            "mesh": {{"max_area": 0.01}}}}"#
    );
    Scene::from_json(&json).expect("scene parses")
}

/// Σ_j K_ij φ_j at every interior vertex i, with K the P1 stiffness (cotangent weights).
fn interior_residual(planner: &Planner) -> f64 {
    let mesh = planner.mesh();
    let v = mesh.vertices();
    let phi: Vec<f64> = {
        let p = planner.potential();
        p.psi().iter().map(|s| p.reference() - s).collect()
    };
    let mut r = vec![0.0; v.len()];
    let mut scale = vec![0.0f64; v.len()];
    for t in mesh.triangles() {
        for e in 0..3 {
            let (a, b, c) = (
                t[e] as usize,
                t[(e + 1) % 3] as usize,
                t[(e + 2) % 3] as usize,
            );
            // cot of the angle at c, opposite edge ab.
            let (u, w) = (v[a] - v[c], v[b] - v[c]);
            let cot = u.dot(&w) / (u.x * w.y - u.y * w.x).abs();
            let k = 0.5 * cot;
            r[a] += k * (phi[a] - phi[b]);
            r[b] += k * (phi[b] - phi[a]);
            scale[a] += k.abs();
            scale[b] += k.abs();
        }
    }
    let mut boundary = vec![false; v.len()];
    for e in mesh.boundary_edges() {
        boundary[e.vertices[0] as usize] = true;
        boundary[e.vertices[1] as usize] = true;
    }
    (0..v.len())
        .filter(|&i| !boundary[i])
        .map(|i| r[i].abs() / scale[i].max(1e-300))
        .fold(0.0, f64::max)
}

#[test]
fn the_blend_is_harmonic_without_interior_minima_for_every_k() {
    let ends: Vec<Vec<f64>> = [0.0, 1.0]
        .iter()
        .map(|&k| {
            let p = Planner::new(&scene(k)).expect("plans");
            let pot = p.potential();
            pot.psi().iter().map(|s| pot.reference() - s).collect()
        })
        .collect();
    for k in [0.0, 0.2, 0.4, 0.5, 0.6, 0.8, 1.0] {
        let planner = Planner::new(&scene(k)).expect("plans");
        let residual = interior_residual(&planner);
        assert!(residual < 1e-9, "k = {k}: interior residual {residual}");
        let e = interior_local_extrema(planner.mesh(), planner.potential().psi());
        assert_eq!(e.minima, 0, "k = {k}");
        assert_eq!(e.maxima, 0, "k = {k}");
        // The convex combination of the two ends.
        let pot = planner.potential();
        for (i, s) in pot.psi().iter().enumerate() {
            let phi = pot.reference() - s;
            let want = k * ends[1][i] + (1.0 - k) * ends[0][i];
            assert!((phi - want).abs() < 1e-9, "k = {k}, vertex {i}");
        }
        let path = planner.plan([0.3, 2.7]);
        assert!(path.status.reached_goal(), "k = {k}: {:?}", path.status);
    }
}

#[test]
fn bad_blends_are_refused_with_their_path() {
    for (blend, what) in [
        (r#"{"k": 1.5}"#, "boundary.blend.k"),
        (r#"{"k": 0.5, "neumann": 0}"#, "boundary.blend.neumann"),
    ] {
        let json = format!(
            r#"{{"workspace": [[0,0],[4,0],[4,3],[0,3]], "goal": {{"point": [3.5, 0.5]}},
                "boundary": {{"blend": {blend}}}}}"#
        );
        let err = match Scene::from_json(&json) {
            Err(e) => e.to_string(),
            Ok(s) => match Planner::new(&s) {
                Err(e) => e.to_string(),
                Ok(_) => panic!("{blend} accepted"),
            },
        };
        assert!(err.contains(what), "{err}");
    }
    let json = r#"{"workspace": [[0,0],[4,0],[4,3],[0,3]], "goal": {"point": [3.5, 0.5]},
        "boundary": {"walls": {"neumann": 1.0}, "blend": {"k": 0.5}}}"#;
    assert!(
        Scene::from_json(json).is_err() || Planner::new(&Scene::from_json(json).unwrap()).is_err()
    );
}
