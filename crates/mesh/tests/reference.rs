mod common;

use common::*;
use harmonic_mesh::{BoundaryTag, Domain, MeshOptions};

#[test]
fn reference_scene_30k() {
    let spec = reference();
    let opts = MeshOptions {
        max_area: Some(0.0044),
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).expect("domain");
    let t0 = std::time::Instant::now();
    let (mesh, report) = domain.mesh(&opts).expect("mesh");
    let q = mesh.quality();
    eprintln!("{:?} {:?} {:?}", t0.elapsed(), report, q);
    assert!(report.refinement_complete);
    check_invariants(&mesh, domain.free_area(), 1e-12).unwrap();
    assert_eq!(q.holes, 6);
    assert!(q.min_angle_deg >= 30.0 - 1e-9, "{}", q.min_angle_deg);
    let _ = BoundaryTag::Wall;
}
