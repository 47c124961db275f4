//! Corridors of any length (issue #19): a Dirichlet corridor of L widths has ψ ≈ e^(−πL/w),
//! past the double range beyond ≈ 230 widths. The bundled corridor of 1000 widths
//! (`meshes/corridor1000.json`, ψ ≈ 1e-1326 at the far end) and square spiral of ≈ 350 widths
//! (`meshes/spiral.json`, ψ ≈ 1e-474) are solved in extended-exponent arithmetic and planned
//! to the goal from both ends (the goal moved to the other end in a mirrored copy of each);
//! the car drives the spiral; the export and the pictures carry log₁₀ ψ.

use harmonic_planner::{CarParams, Planner, Scene, SvgOptions};
use serde_json::{Value, json};

fn scene_json(name: &str) -> Value {
    let path = format!("{}/meshes/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).expect("bundled scene");
    serde_json::from_str(&text).expect("JSON")
}

fn planner(scene: &Value) -> Planner {
    let scene = Scene::from_json(&scene.to_string()).expect("scene parses");
    Planner::new(&scene).expect("planner")
}

/// Plans from `start` and checks the path reaches the goal; returns its length.
fn reaches(planner: &Planner, start: [f64; 2]) -> f64 {
    let path = planner.plan(start);
    assert!(
        path.status.reached_goal(),
        "from {start:?}: {:?} after {} (tracer {})",
        path.status,
        path.length,
        path.tracer
    );
    assert!(path.min_clearance > 0.0, "from {start:?}");
    path.length
}

fn check_extended(planner: &Planner, below_log10: f64) {
    let potential = planner.potential();
    assert!(potential.is_extended());
    let report = planner.plan_report::<[f64; 2]>(&[]);
    let lowest = report
        .potential
        .min_log10_psi
        .expect("reported when extended");
    assert!(lowest < below_log10, "smallest log10 ψ {lowest}");
    assert_eq!(report.potential.interior_local_minima, 0);
}

#[test]
fn corridor_of_1000_widths_is_planned_from_both_ends() {
    let mut scene = scene_json("corridor1000");
    let there = planner(&scene);
    check_extended(&there, -1300.0);
    // From the far end (ψ ≈ 1e-1326) and from the middle; the path runs along the corridor.
    let length = reaches(&there, [999.5, 0.5]);
    assert!((998.0..1001.0).contains(&length), "{length}");
    reaches(&there, [500.0, 0.2]);
    // The exact tracer too.
    let exact = there.plan_exact([999.5, 0.5]);
    assert!(exact.status.reached_goal(), "{:?}", exact.status);
    // The goal at the other end.
    scene["goal"] = json!({"polygon": [[999.4, 0.3], [999.8, 0.3], [999.8, 0.7], [999.4, 0.7]]});
    let back = planner(&scene);
    check_extended(&back, -1300.0);
    let length = reaches(&back, [0.5, 0.5]);
    assert!((998.0..1001.0).contains(&length), "{length}");
}

#[test]
fn spiral_of_300_widths_is_planned_from_both_ends_and_driven() {
    let mut scene = scene_json("spiral");
    let inward = planner(&scene);
    check_extended(&inward, -400.0);
    let start = [0.625, 0.5];
    let length = reaches(&inward, start);
    assert!(length > 300.0, "{length}");
    // The car, with a wheelbase that fits the corridor (width 1).
    let params = CarParams {
        wheelbase: 0.3,
        max_steer: 35f64.to_radians(),
        step: 0.03,
        check_footprint: false,
    };
    let run = inward
        .car([start[0], start[1], std::f64::consts::FRAC_PI_2], &params)
        .unwrap();
    assert!(run.status.reached_goal(), "car: {:?}", run.status);
    // The goal at the outer end, the start at the centre.
    let centre = scene["goal"]["circle"]["center"].clone();
    scene["goal"] = json!({"circle": {"center": start, "radius": 0.3}});
    let outward = planner(&scene);
    check_extended(&outward, -400.0);
    let from = [centre[0].as_f64().unwrap(), centre[1].as_f64().unwrap()];
    let length = reaches(&outward, from);
    assert!(length > 300.0, "{length}");
}

#[test]
fn export_and_pictures_carry_log10_psi() {
    let planner = planner(&scene_json("spiral"));
    let export = planner.export();
    let n = export.vertices.len();
    assert_eq!(export.log10_psi.len(), n);
    // Somewhere ψ underflows as a float but its logarithm is known.
    let far = (0..n)
        .find(|&v| export.psi[v] == 0.0 && export.log10_psi[v].is_some())
        .expect("a vertex below the double range");
    let lg = export.log10_psi[far].unwrap();
    // The spiral's far end is about 1e-474 (the mesh moves it by a few decades).
    assert!(lg < -323.0 && lg > -520.0, "{lg}");
    // Where ψ is a float, log10_psi is its logarithm.
    for v in 0..n {
        if export.psi[v] > 1e-300 {
            let lg = export.log10_psi[v].unwrap();
            assert!((lg - export.psi[v].log10()).abs() < 1e-12, "vertex {v}");
        }
    }
    let vtu = planner.vtu();
    assert!(vtu.contains("Name=\"log10_psi\""));
    assert!(!vtu.contains("inf") && !vtu.contains("NaN"));
    let svg = planner.svg(&[], &[], &SvgOptions::default());
    assert!(svg.matches("<path").count() > 20, "isolines on log ψ");
}
