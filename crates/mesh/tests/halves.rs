//! Meshes made in two halves glued along a cut (`MeshOptions::halves_from`): the cut may run
//! through obstacle corners and along obstacle edges, and the glued mesh must satisfy every
//! invariant of a mesh made in one piece.

mod common;

use common::*;
use harmonic_fixtures::{p, rect};
use harmonic_mesh::geom::ring_distance;
use harmonic_mesh::{BoundaryTag, Domain, DomainSpec, GoalShape, MeshOptions, Shape};

/// What every glued mesh meets as a mesh in one piece does: the invariants, one component,
/// the angle bound and the M-matrix conditions (no non-Delaunay edge, no obtuse angle
/// opposite a boundary edge).
fn assert_like_one_piece(
    mesh: &harmonic_mesh::Mesh,
    domain: &Domain,
) -> harmonic_mesh::QualityReport {
    check_invariants(mesh, domain.free_area(), 1e-9).expect("invariants");
    let q = mesh.quality();
    assert_eq!(q.components, 1, "{q:?}");
    assert!(q.min_angle_deg >= 30.0 - 1e-9, "{q:?}");
    assert_eq!(q.non_delaunay_edges, 0, "{q:?}");
    assert_eq!(q.obtuse_boundary_edges, 0, "{q:?}");
    q
}

fn check(spec: &DomainSpec, expected_seam: (usize, f64)) {
    let opts = MeshOptions {
        max_area: Some(0.01),
        halves_from: 0,
        ..MeshOptions::default()
    };
    let domain = Domain::new(spec, &opts).expect("domain");
    let (mesh, report) = domain.mesh(&opts).expect("mesh");
    assert_eq!(report.seam, Some(expected_seam));
    assert!(report.refinement_complete);
    assert_like_one_piece(&mesh, &domain);
    // No boundary edge lies on the glued stretches of the cut: every one is on an input ring.
    for e in mesh.boundary_edges() {
        let [a, b] = e.vertices.map(|v| mesh.vertices()[v as usize]);
        let m = (a + b.coords) * 0.5;
        let on_ring = |ring: &[harmonic_mesh::Point]| ring_distance(ring, m) < 1e-9;
        let ok = match e.tag {
            BoundaryTag::Wall => on_ring(&spec.workspace),
            BoundaryTag::Obstacle(i) => match &spec.obstacles[i as usize] {
                Shape::Polygon(p) => on_ring(p),
                Shape::Circle { .. } => true,
            },
            BoundaryTag::Goal(_) => true,
        };
        assert!(ok, "{:?} edge {a} {b} is not on its ring", e.tag);
    }
    // The same mesh in one piece has about as many triangles.
    let whole = MeshOptions {
        halves_from: usize::MAX,
        ..opts
    };
    let (one, _) = domain.mesh(&whole).expect("mesh");
    let (a, b) = (mesh.triangles().len() as f64, one.triangles().len() as f64);
    assert!((a / b - 1.0).abs() < 0.03, "{a} vs {b}");
}

#[test]
fn a_cut_through_an_obstacle_corner() {
    // x = 4 splits free space equally and touches the diamond's corner (4, 2), whose edges
    // leave it at 63° to the cut. (The room's larger side is 10 and its corner the origin, so
    // the unit frame is the identity and the power-of-two cut candidates are the scene's.)
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 8.0, 10.0),
        obstacles: vec![
            Shape::Polygon(vec![p(4.0, 2.0), p(5.0, 1.5), p(6.0, 2.0), p(5.0, 2.5)]),
            Shape::Polygon(rect(1.0, 5.0, 2.0, 6.0)),
        ],
        goals: vec![GoalShape::Circle {
            center: p(7.0, 7.0),
            radius: 0.3,
        }],
        robot_radius: 0.0,
    };
    check(&spec, (0, 4.0));
}

#[test]
fn a_cut_along_obstacle_edges_and_across_obstacles() {
    // x = 4 runs along the right edge of [2, 4] × [4, 6] and across [3.5, 4.5] × [1, 2], and
    // splits free space evenly (so it beats a cut through the median, which is not exact).
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 8.0, 10.0),
        obstacles: vec![
            Shape::Polygon(rect(2.0, 4.0, 4.0, 6.0)),
            Shape::Polygon(rect(3.5, 1.0, 4.5, 2.0)),
            Shape::Polygon(rect(5.0, 6.0, 7.0, 8.0)),
        ],
        goals: vec![GoalShape::Circle {
            center: p(7.0, 1.0),
            radius: 0.3,
        }],
        robot_radius: 0.0,
    };
    check(&spec, (0, 4.0));
}

#[test]
fn a_cut_through_the_median_of_free_space() {
    // Every exact cut (x or y at 0 or ±2^k) leaves more than 67 % of free space on one side:
    // x = 4 and x = 8 are beyond 70 %, y = 1 and y = 2 leave 32.5 % / 67.5 % (the obstacles
    // take free space near the bottom, top and left wall). The cut goes through the median of
    // free area, off every vertex.
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 10.0, 3.0),
        obstacles: vec![
            Shape::Polygon(rect(0.5, 0.2, 3.5, 0.8)),
            Shape::Polygon(rect(0.5, 2.2, 3.5, 2.8)),
            Shape::Polygon(rect(1.0, 1.2, 3.0, 1.8)),
        ],
        goals: vec![GoalShape::Circle {
            center: p(9.5, 1.5),
            radius: 0.2,
        }],
        robot_radius: 0.0,
    };
    let opts = MeshOptions {
        max_area: Some(0.01),
        halves_from: 0,
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).expect("domain");
    let (mesh, report) = domain.mesh(&opts).expect("mesh");
    let (axis, at) = report.seam.expect("made in two halves");
    let exact = at == 0.0 || at.abs().log2().fract() == 0.0;
    assert!(!exact, "axis {axis} at {at}");
    // The low side of the cut holds half the free area, up to the nudge off the vertices.
    let low: f64 = (0..mesh.triangles().len() as u32)
        .filter(|&t| {
            let [a, b, c] = mesh.triangle_points(t);
            (a[axis] + b[axis] + c[axis]) / 3.0 < at
        })
        .map(|t| mesh.triangle_area(t))
        .sum();
    let fraction = low / domain.free_area();
    assert!(
        (fraction - 0.5).abs() < 0.03,
        "axis {axis} at {at}: {fraction}"
    );
    assert_like_one_piece(&mesh, &domain);
}

#[test]
fn no_cut_meets_an_obstacle_at_a_shallow_angle() {
    // Both x = 4 and y = 4 would meet the triangle's edges at 27°: the mesh is made in one
    // piece.
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 8.0, 8.0),
        obstacles: vec![Shape::Polygon(vec![p(3.0, 3.0), p(5.0, 4.0), p(4.0, 6.0)])],
        goals: vec![GoalShape::Circle {
            center: p(7.0, 7.0),
            radius: 0.3,
        }],
        robot_radius: 0.0,
    };
    let opts = MeshOptions {
        max_area: Some(0.01),
        halves_from: 0,
        ..MeshOptions::default()
    };
    let (_, report) = Domain::new(&spec, &opts)
        .and_then(|d| d.mesh(&opts))
        .expect("mesh");
    assert_eq!(report.seam, None);
}

#[test]
fn a_horizontal_cut_along_the_top_of_an_obstacle() {
    // y = 4 is the top edge of [3, 5] × [2, 4] (free space above it: the high side's) and
    // splits free space evenly.
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 10.0, 8.0),
        obstacles: vec![
            Shape::Polygon(rect(3.0, 2.0, 5.0, 4.0)),
            Shape::Polygon(rect(1.0, 5.0, 3.0, 7.0)),
        ],
        goals: vec![GoalShape::Circle {
            center: p(6.0, 7.0),
            radius: 0.3,
        }],
        robot_radius: 0.0,
    };
    check(&spec, (1, 4.0));
}

#[test]
fn halves_taking_each_others_cut_vertices_are_refined_locally_or_in_full() {
    // Forests of circles: refinement splits seam edges on both sides, so the halves
    // exchange cut vertices and are refined around them. With 500 circles the faces there
    // are clear of the circles and the refinement is local; with 300 the local steps come
    // to something they leave to spade (a bad face at a circle, or an encroached circle
    // edge) and spade's full pass runs. Either way the glued mesh meets every bound a mesh in one
    // piece meets.
    for (n, local) in [(500, true), (300, false)] {
        let spec = harmonic_fixtures::forest(n);
        let opts = MeshOptions {
            halves_from: 0,
            ..MeshOptions::default()
        };
        let domain = Domain::new(&spec, &opts).expect("domain");
        let (mesh, report) = domain.mesh(&opts).expect("mesh");
        assert!(report.seam.is_some(), "{n}: {report:?}");
        assert!(report.refinement_complete);
        let again = report.seam_refinements;
        if local {
            assert!(again.local > 0 && again.full == 0, "{n}: {report:?}");
        } else {
            assert!(again.full > 0, "{n}: {report:?}");
        }
        let q = assert_like_one_piece(&mesh, &domain);
        assert!(
            q.max_triangle_area <= report.max_area * (1.0 + 1e-9),
            "{n}: {q:?}"
        );
    }
}

/// The halves run on rayon's pool: in a pool of one thread one after the other, in a pool of
/// two side by side, and the glued mesh is the same either way.
#[test]
fn the_halves_give_the_same_mesh_in_a_pool_of_one_thread_and_of_two() {
    let spec = DomainSpec {
        workspace: rect(0.0, 0.0, 8.0, 10.0),
        obstacles: vec![
            Shape::Polygon(vec![p(4.0, 2.0), p(5.0, 1.5), p(6.0, 2.0), p(5.0, 2.5)]),
            Shape::Circle {
                center: p(2.0, 7.0),
                radius: 0.7,
            },
        ],
        goals: vec![GoalShape::Circle {
            center: p(7.0, 7.0),
            radius: 0.3,
        }],
        robot_radius: 0.1,
    };
    let opts = MeshOptions {
        max_area: Some(0.01),
        halves_from: 0,
        ..MeshOptions::default()
    };
    let domain = Domain::new(&spec, &opts).expect("domain");
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| domain.mesh(&opts).expect("mesh"))
    };
    let (one, report) = in_pool(1);
    let (two, _) = in_pool(2);
    assert!(report.seam.is_some(), "made in halves: {report:?}");
    assert_eq!(one.vertices(), two.vertices());
    assert_eq!(one.triangles(), two.triangles());
}
