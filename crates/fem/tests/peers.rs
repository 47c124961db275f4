//! Agreement with the Python (scikit-fem on Triangle) and FreeFEM peers on the reference scene
//! (docs/peers.md): φ at six sample points, Dirichlet and Robin cases.

use std::sync::Arc;

use harmonic_fem::{Assembler, AssemblyOptions, BoundaryCondition};
use harmonic_fem::{BoundaryConditions, Potential, offdiagonal_sign_violations, solve_potential};
use harmonic_fixtures::reference_mesh;
use harmonic_mesh::{Mesh, Point};
use serde_json::Value;

/// Case (b) of docs/peers.md: Robin ∂φ/∂n = 1 − φ (a = b = g = 1) on walls and obstacles,
/// φ = 0 on the goal. Case (a) is the default, Dirichlet φ = 1 on walls and obstacles.
fn robin() -> BoundaryConditions {
    BoundaryConditions::uniform(BoundaryCondition::Robin {
        a: 1.0,
        b: 1.0,
        g: 1.0,
    })
}

/// (points, [(peer name, φ at the points)]) from a peer sample file.
fn peer_samples(json: &str) -> (Vec<Point>, Vec<(String, Vec<f64>)>) {
    let v: Value = serde_json::from_str(json).expect("valid sample file");
    let points = v["points"]
        .as_array()
        .expect("points")
        .iter()
        .map(|p| Point::new(p[0].as_f64().expect("x"), p[1].as_f64().expect("y")))
        .collect();
    let peers = v["values"]
        .as_object()
        .expect("values")
        .iter()
        .map(|(name, entry)| {
            let phi = entry["phi"]
                .as_array()
                .expect("phi")
                .iter()
                .map(|x| x.as_f64().expect("number"))
                .collect();
            (name.clone(), phi)
        })
        .collect();
    (points, peers)
}

fn solve(mesh: &Arc<Mesh>, bcs: &BoundaryConditions) -> Potential {
    let system = Assembler::new(Arc::clone(mesh), bcs, AssemblyOptions::default())
        .expect("pattern")
        .assemble(bcs)
        .expect("assembly");
    assert_eq!(offdiagonal_sign_violations(&system), 0, "M-matrix");
    let p = solve_potential(Arc::clone(mesh), bcs).expect("solve");
    assert_eq!(p.interior_local_extrema(), 0, "discrete maximum principle");
    p
}

fn check(p: &Potential, points: &[Point], peer: &str, expected: &[f64], tol: f64) {
    let mut hint = None;
    for (q, &want) in points.iter().zip(expected) {
        let e = p.evaluate(*q, hint).expect("sample point in free space");
        hint = Some(e.triangle);
        eprintln!(
            "{peer:>40} ({:4}, {:4}): ours {:.12} peer {:.12} diff {:.2e}",
            q.x,
            q.y,
            e.phi,
            want,
            (e.phi - want).abs()
        );
        assert!(
            (e.phi - want).abs() <= tol,
            "at ({}, {}) φ = {} but {peer} has {want}",
            q.x,
            q.y,
            e.phi
        );
    }
}

#[test]
fn agrees_with_peers_at_30k_triangles() {
    let mesh = Arc::new(reference_mesh(0.0044));
    let n = mesh.triangles().len();
    assert!((25_000..40_000).contains(&n), "{n} triangles");
    for (file, bcs) in [
        (
            include_str!("data/reference_samples_dirichlet.json"),
            BoundaryConditions::default(),
        ),
        (include_str!("data/reference_samples_robin.json"), robin()),
    ] {
        let p = solve(&mesh, &bcs);
        let (points, peers) = peer_samples(file);
        for (name, phi) in &peers {
            check(&p, &points, name, phi, 2e-3);
        }
    }
}

/// The peers' ~1M-triangle values (docs/peers.md, "same points across mesh sizes"): Python on
/// Triangle (1008704 triangles) and FreeFEM buildmesh (1023290 triangles).
const DIRICHLET_1M: [[f64; 6]; 2] = [
    [
        0.999999773,
        1.000000000,
        0.999999161,
        0.999998318,
        0.875205544,
        0.999990960,
    ],
    [
        0.999999773,
        1.000000000,
        0.999999160,
        0.999998317,
        0.875222698,
        0.999990957,
    ],
];
const ROBIN_1M: [[f64; 6]; 2] = [
    [
        0.999618710,
        0.999993977,
        0.999088158,
        0.999314524,
        0.771218225,
        0.996835197,
    ],
    [
        0.999618726,
        0.999993978,
        0.999088295,
        0.999314602,
        0.771241885,
        0.996835432,
    ],
];

#[test]
#[ignore = "1M triangles: about 10 s in release; run with --ignored"]
fn agrees_with_peers_at_1m_triangles() {
    let mesh = Arc::new(reference_mesh(0.000132));
    eprintln!("{} triangles", mesh.triangles().len());
    let (points, _) = peer_samples(include_str!("data/reference_samples_dirichlet.json"));
    for (bcs, values) in [
        (BoundaryConditions::default(), DIRICHLET_1M),
        (robin(), ROBIN_1M),
    ] {
        let p = solve(&mesh, &bcs);
        for (name, phi) in ["python 1M", "freefem 1M"].iter().zip(values) {
            check(&p, &points, name, &phi, 5e-5);
        }
    }
}
