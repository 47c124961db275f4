//! What the `scene` fuzz target runs on every input (the scene also meshed in two halves), shared with the corpus replay in
//! `tests/robustness.rs` (which includes this file with `#[path]`), so CI replays the corpus
//! exactly as the fuzzer ran it.

use harmonic_planner::mesh::{Domain, MeshOptions};
use harmonic_planner::{Planner, Scene};

/// Triangle budget of one fuzz case: the area-driven part of the mesh is kept to roughly
/// 1.6 × this many triangles (Ruppert refinement at 30° makes about 1.6 triangles per
/// `max_area`). Small, so that an instrumented (ASan + coverage) build still runs several
/// cases a second on a shared machine; at 20 000 one case took over 20 s there.
pub const TRIANGLE_CAP: f64 = 2_000.0;

/// At most this many starts are planned per case.
pub const MAX_STARTS: usize = 8;

/// Coarsens the scene's mesh so it has at most about [`TRIANGLE_CAP`] triangles: `max_area`
/// becomes at least the workspace's bounding-box area / [`TRIANGLE_CAP`] (the free area is
/// never larger than the bounding box, so this bounds the area-driven part of the mesh at a
/// cost of one pass over the workspace vertices).
pub fn cap_mesh(scene: &mut Scene) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &scene.workspace {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let floor = (hi[0] - lo[0]) * (hi[1] - lo[1]) / TRIANGLE_CAP;
    if floor.is_finite() && floor > 0.0 {
        let given = scene.mesh.max_area.unwrap_or(0.0);
        scene.mesh.max_area = Some(given.max(floor));
    }
}

/// What happened to one input (for the replay test's messages).
#[derive(Debug, PartialEq, Eq)]
pub enum Outcome {
    /// `Scene::from_json` refused it.
    BadScene,
    /// `Planner::new` refused it.
    NotPlannable,
    /// Planned from this many starts.
    Planned(usize),
}

/// Parses `data` as a scene, caps its mesh, builds the planner and plans from its starts (the
/// first [`MAX_STARTS`], or the workspace's first vertex nudged inwards if it has none). Any
/// panic in here is a bug; errors are fine. Every planned path must be free of NaN.
pub fn run(data: &[u8]) -> Outcome {
    let Ok(text) = std::str::from_utf8(data) else {
        return Outcome::BadScene;
    };
    let Ok(mut scene) = Scene::from_json(text) else {
        return Outcome::BadScene;
    };
    cap_mesh(&mut scene);
    // The same free space in two halves glued along a cut (what meshes above 250 k
    // triangles go through): errors are fine, panics are not.
    let halves = MeshOptions {
        halves_from: 0,
        ..scene.mesh_options()
    };
    if let Ok(domain) = Domain::new(&scene.domain_spec(), &halves) {
        let _ = domain.mesh(&halves);
    }
    let Ok(planner) = Planner::new(&scene) else {
        return Outcome::NotPlannable;
    };
    let mut starts: Vec<[f64; 2]> = scene.starts.iter().take(MAX_STARTS).copied().collect();
    if starts.is_empty() {
        let w = &scene.workspace;
        let n = w.len() as f64;
        let c = w
            .iter()
            .fold([0.0, 0.0], |a, p| [a[0] + p[0] / n, a[1] + p[1] / n]);
        if let Some(first) = w.first() {
            starts.push([0.9 * first[0] + 0.1 * c[0], 0.9 * first[1] + 0.1 * c[1]]);
        }
    }
    let report = planner.plan_report(&starts);
    for path in &report.paths {
        assert!(
            path.length.is_finite()
                && path.min_clearance.is_finite()
                && path.min_gradient.is_finite()
                && path.points.iter().flatten().all(|v| v.is_finite()),
            "NaN or infinity in the path from {:?}: {path:?}",
            path.start
        );
    }
    // serde_json writes NaN and infinities as `null`, and no field of a report is optional
    // `null`, so a `null` anywhere is a non-finite number.
    let json = serde_json::to_string(&report).expect("a plan report serialises");
    assert!(
        !json.contains("null"),
        "non-finite number in the report: {json}"
    );
    Outcome::Planned(report.paths.len())
}
