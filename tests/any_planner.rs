//! `AnyPlanner`, the planner of any scene file, gives the same paths as the planner of each
//! kind (plane, volume, polygon robot), refuses starts of the wrong dimension before building
//! anything, and writes VTU for every kind.

use harmonic_fixtures::paths::mesh_file;
use harmonic_planner::{
    AnyPlanner, AnyReport, AnyScene, ConfigPlanner, Planner, PlannerApi, PlannerOptions, Summary,
    VolumePlanner,
};

fn scene(name: &str) -> AnyScene {
    AnyScene::from_file(mesh_file(&format!("{name}.json"))).expect("bundled scene")
}

#[test]
fn any_planner_plans_as_each_kind_does() {
    for name in ["reference", "torus3d", "piano"] {
        let scene = scene(name);
        let starts = scene.starts();
        assert!(!starts.is_empty(), "{name}");
        scene
            .check_starts(&starts)
            .expect("the scene's own starts fit");
        let any = AnyPlanner::new(&scene, &PlannerOptions::default()).expect("builds");
        let report = any.report(&starts).expect("starts fit");
        assert!(!report.summary().is_empty());
        assert!(any.vtu().expect("vtu").starts_with("<?xml"), "{name}");
        let json = serde_json::to_value(&report).expect("serialises");
        let points = |j: &serde_json::Value| -> Vec<serde_json::Value> {
            j["paths"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| p["points"].clone())
                .collect()
        };
        // The same scene through its own planner.
        let direct = match (&scene, &report) {
            (AnyScene::Plane(s), AnyReport::Plane(_)) => {
                let p = Planner::new(s).unwrap();
                let s2: Vec<[f64; 2]> = starts.iter().map(|s| [s[0], s[1]]).collect();
                serde_json::to_value(PlannerApi::report(&p, &s2)).unwrap()
            }
            (AnyScene::Volume(s), AnyReport::Volume(_)) => {
                let p = VolumePlanner::new(s).unwrap();
                let s3: Vec<[f64; 3]> = starts.iter().map(|s| [s[0], s[1], s[2]]).collect();
                serde_json::to_value(PlannerApi::report(&p, &s3)).unwrap()
            }
            (AnyScene::Config(s), AnyReport::Config(_)) => {
                let p = ConfigPlanner::new(s).unwrap();
                serde_json::to_value(PlannerApi::report(&p, &starts)).unwrap()
            }
            _ => panic!("{name}: the report's kind differs from the scene's"),
        };
        assert_eq!(points(&json), points(&direct), "{name}");
    }
}

#[test]
fn starts_of_the_wrong_dimension_are_refused_by_name() {
    let cases = [
        ("reference", vec![1.0, 2.0, 3.0], "X,Y on a plane scene"),
        ("torus3d", vec![1.0, 2.0], "X,Y,Z on a volume scene"),
        ("piano", vec![1.0, 2.0], "3 numbers (X,Y,THETA)"),
    ];
    for (name, start, expected) in cases {
        let e = scene(name)
            .check_starts(std::slice::from_ref(&start))
            .unwrap_err();
        assert_eq!(e.start, start, "{name}");
        assert!(e.to_string().contains(expected), "{name}: {e}");
    }
}
