//! The reference scene (meshes/reference.json) at the bench sizes: topology, exact area,
//! angles, the M-matrix conditions and boundary tags.

mod common;

use common::*;
use harmonic_fixtures::{area, p, reference_disc};
use harmonic_mesh::geom::polyline_length;
use harmonic_mesh::{BoundaryTag, Domain, MeshOptions, Point};

/// Free area from the inputs: 100 − obstacles − the 12-gon goal (r = 0.15).
fn exact_free_area(goal_sides: usize) -> f64 {
    let spec = reference_disc();
    let mut a = 100.0;
    for o in &spec.obstacles {
        if let harmonic_mesh::Shape::Polygon(pts) = o {
            a -= area(pts).abs();
        }
    }
    let n = goal_sides as f64;
    a - 0.5 * n * 0.15f64.powi(2) * (std::f64::consts::TAU / n).sin()
}

fn check_tags_on_inputs(mesh: &harmonic_mesh::Mesh) {
    let spec = reference_disc();
    for e in mesh.boundary_edges() {
        let [a, b] = e.vertices.map(|v| mesh.vertices()[v as usize]);
        let on = |poly: &[Point]| on_ring_edge(a, b, poly);
        match e.tag {
            BoundaryTag::Wall => assert!(on(&spec.workspace), "wall edge {a} {b}"),
            BoundaryTag::Obstacle(i) => match &spec.obstacles[i as usize] {
                harmonic_mesh::Shape::Polygon(p) => assert!(on(p), "obstacle {i} edge {a} {b}"),
                harmonic_mesh::Shape::Circle { .. } => unreachable!(),
            },
            BoundaryTag::Goal(0) => {
                let c = p(8.5, 1.5);
                for q in [a, b] {
                    let r = (q - c).norm();
                    assert!(
                        r <= 0.15 + 1e-12
                            && r >= 0.15 * (std::f64::consts::PI / 12.0).cos() - 1e-12
                    );
                }
            }
            BoundaryTag::Goal(j) => panic!("unexpected goal {j}"),
        }
    }
}

fn run(max_area: f64, prefill: bool) {
    run_with(MeshOptions {
        max_area: Some(max_area),
        prefill,
        ..MeshOptions::default()
    });
}

fn run_with(opts: MeshOptions) {
    let spec = reference_disc();
    let max_area = opts.max_area.expect("an area bound");
    let domain = Domain::new(&spec, &opts).expect("domain");
    let exact = exact_free_area(12);
    assert!((domain.free_area() - exact).abs() < 1e-12 * exact);
    let (mesh, report) = domain.mesh(&opts).expect("mesh");
    assert!(report.refinement_complete);
    check_invariants(&mesh, exact, 1e-9).expect("invariants");
    let q = mesh.quality();
    assert_eq!(q.holes, 6, "{q:?}");
    assert_eq!(q.components, 1);
    assert!(q.min_angle_deg >= 30.0 - 1e-9, "{q:?}");
    assert_eq!(q.non_delaunay_edges, 0, "{q:?}");
    assert_eq!(q.obtuse_boundary_edges, 0, "{q:?}");
    let max_tri = (0..mesh.triangles().len() as u32)
        .map(|t| mesh.triangle_area(t))
        .fold(0.0, f64::max);
    assert!(max_tri <= max_area * (1.0 + 1e-12));
    check_tags_on_inputs(&mesh);
    // Every tag is present: wall, five obstacles, the goal.
    let mut tags: Vec<BoundaryTag> = mesh.boundary_edges().iter().map(|e| e.tag).collect();
    tags.sort();
    tags.dedup();
    assert_eq!(tags.len(), 7, "{tags:?}");
}

#[test]
fn reference_3k_with_and_without_prefill() {
    run(0.045, true);
    run(0.045, false);
}

#[test]
fn reference_30k_with_and_without_prefill() {
    run(0.0044, true);
    run(0.0044, false);
}

#[test]
fn reference_in_two_halves() {
    for max_area in [0.045, 0.0044] {
        let opts = MeshOptions {
            max_area: Some(max_area),
            halves_from: 0,
            ..MeshOptions::default()
        };
        run_with(opts.clone());
        let domain = Domain::new(&reference_disc(), &opts).expect("domain");
        let (halves, report) = domain.mesh(&opts).expect("mesh");
        // A cut near the middle of free space.
        let (axis, at) = report.seam.expect("made in two halves");
        assert!(axis <= 1 && at > 3.0 && at < 7.0, "{axis} {at}");
        // About as many triangles as in one piece.
        let whole = MeshOptions {
            halves_from: usize::MAX,
            ..opts
        };
        let (one, report) = domain.mesh(&whole).expect("mesh");
        assert_eq!(report.seam, None);
        let (a, b) = (
            halves.triangles().len() as f64,
            one.triangles().len() as f64,
        );
        assert!((a / b - 1.0).abs() < 0.02, "{a} vs {b}");
    }
}

#[test]
fn triangle_counts_are_close_to_triangle() {
    // Triangle (pq30a0.0044) gives 30236 triangles; we aim for the same density.
    let opts = MeshOptions {
        max_area: Some(0.0044),
        ..MeshOptions::default()
    };
    for prefill in [true, false] {
        let opts = MeshOptions {
            prefill,
            ..opts.clone()
        };
        let (mesh, _) = Domain::new(&reference_disc(), &opts)
            .unwrap()
            .mesh(&opts)
            .unwrap();
        let n = mesh.triangles().len() as f64;
        assert!((n / 30236.0 - 1.0).abs() < 0.1, "{n}");
    }
}

#[test]
fn vertices_are_in_hilbert_order() {
    // Consecutive vertices are close: the mean distance between vertex i and i+1 is a small
    // multiple of the edge length (a random order would give about a third of the domain).
    let opts = MeshOptions {
        max_area: Some(0.0044),
        ..MeshOptions::default()
    };
    let (mesh, _) = Domain::new(&reference_disc(), &opts)
        .unwrap()
        .mesh(&opts)
        .unwrap();
    let v = mesh.vertices();
    let mean = polyline_length(v) / (v.len() - 1) as f64;
    assert!(mean < 0.3, "mean step {mean}");
}
