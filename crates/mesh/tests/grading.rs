//! Optional grading (issue #2): finer triangles at the goal boundary and at obstacle corners,
//! growing back to `max_area` over `radius`, with the quality guarantees of plain refinement.

mod common;

use common::check_invariants_with_bridges;
use harmonic_fixtures::{p, reference_disc};
use harmonic_mesh::{Domain, Grading, Mesh, MeshError, MeshOptions, Point};

const MAX_AREA: f64 = 0.02;
/// The reference scene's goal disc.
const GOAL: (f64, f64, f64) = (8.5, 1.5, 0.15);

fn options(grading: Option<Grading>) -> MeshOptions {
    MeshOptions {
        max_area: Some(MAX_AREA),
        grading,
        ..MeshOptions::default()
    }
}

fn mesh_of(opts: &MeshOptions) -> (Domain, Mesh) {
    let domain = Domain::new(&reference_disc(), opts).expect("valid scene");
    let (mesh, report) = domain.mesh(opts).expect("meshes");
    assert!(report.refinement_complete, "{report:?}");
    check_invariants_with_bridges(&mesh, domain.free_area(), 1e-9, report.bridges_remaining)
        .unwrap_or_else(|e| panic!("{e}"));
    let q = mesh.quality();
    assert!(q.min_angle_deg >= 30.0 - 1e-9, "{q:?}");
    assert_eq!(q.non_delaunay_edges, 0, "{q:?}");
    (domain, mesh)
}

/// Mean area of the triangles whose centroid satisfies `pick`.
fn mean_area(mesh: &Mesh, pick: impl Fn(Point) -> bool) -> (f64, usize) {
    let mut sum = 0.0;
    let mut n = 0;
    for t in 0..mesh.triangles().len() as u32 {
        let [a, b, c] = mesh.triangle_points(t);
        let m = p((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0);
        if pick(m) {
            sum += mesh.triangle_area(t);
            n += 1;
        }
    }
    (sum / n.max(1) as f64, n)
}

fn goal_distance(m: Point) -> f64 {
    (m - p(GOAL.0, GOAL.1)).norm() - GOAL.2
}

#[test]
fn triangles_at_the_goal_are_smaller_by_about_the_factor() {
    let radius = 1.5;
    let grading = Grading {
        near_goal: 0.1,
        near_corners: 1.0,
        radius,
    };
    let (_, mesh) = mesh_of(&options(Some(grading)));
    let (near, n_near) = mean_area(&mesh, |m| goal_distance(m) < 0.05);
    // Far from the goal, and from the walls and obstacles (boundary layers are finer).
    let (domain, _) = mesh_of(&options(None));
    let (far, n_far) = mean_area(&mesh, |m| {
        goal_distance(m) > radius + 0.5 && domain.distance_to_obstacles(m) > 0.5
    });
    assert!(n_near >= 20 && n_far >= 200, "{n_near} {n_far}");
    let ratio = near / far;
    assert!(
        (0.05..0.2).contains(&ratio),
        "near {near} far {far}: {ratio}"
    );
    // Between the two, the size grows with the distance.
    let (mid, _) = mean_area(&mesh, |m| (0.6..0.9).contains(&goal_distance(m)));
    assert!(near < mid && mid < far, "{near} {mid} {far}");
}

#[test]
fn graded_mesh_is_far_smaller_than_a_uniform_fine_one() {
    let grading = Grading {
        near_goal: 0.1,
        near_corners: 0.1,
        radius: 1.0,
    };
    let (_, graded) = mesh_of(&options(Some(grading)));
    let (_, coarse) = mesh_of(&options(None));
    let fine = MeshOptions {
        max_area: Some(0.1 * MAX_AREA),
        ..MeshOptions::default()
    };
    let (_, fine) = mesh_of(&fine);
    let (g, c, f) = (
        graded.triangles().len(),
        coarse.triangles().len(),
        fine.triangles().len(),
    );
    assert!(
        g > c && 3 * g < f,
        "graded {g}, uniform coarse {c}, uniform fine {f}"
    );
}

#[test]
fn triangles_at_obstacle_corners_are_smaller() {
    let grading = Grading {
        near_goal: 1.0,
        near_corners: 0.05,
        radius: 1.0,
    };
    let (domain, mesh) = mesh_of(&options(Some(grading)));
    let (_, plain) = mesh_of(&options(None));
    let (far, _) = mean_area(&plain, |m| domain.distance_to_obstacles(m) > 0.5);
    // Corner (3, 8) of the first obstacle, and (6.5, 1.5), the inner corner of the fourth
    // (an L): at most (√0.05 + (1 − √0.05)·0.15)² ≈ 0.12 of `max_area` within 0.15.
    for corner in [p(3.0, 8.0), p(6.5, 1.5)] {
        let (graded, n) = mean_area(&mesh, |m| (m - corner).norm() < 0.15);
        assert!(
            n >= 10 && graded < 0.2 * far,
            "{corner}: {graded} vs {far} ({n})"
        );
    }
    // The goal is not graded.
    let at_goal = |m: Point| goal_distance(m) < 0.05;
    let (graded, _) = mean_area(&mesh, at_goal);
    let (uniform, _) = mean_area(&plain, at_goal);
    assert!(graded > 0.5 * uniform, "{graded} vs {uniform}");
}

#[test]
fn unit_factors_leave_the_mesh_as_without_grading() {
    let grading = Grading {
        near_goal: 1.0,
        near_corners: 1.0,
        radius: 2.0,
    };
    let (_, graded) = mesh_of(&options(Some(grading)));
    let (_, plain) = mesh_of(&options(None));
    assert_eq!(graded.vertices(), plain.vertices());
    assert_eq!(graded.triangles(), plain.triangles());
}

#[test]
fn a_radius_larger_than_the_scene_refines_everything_to_the_goal_factor() {
    let grading = Grading {
        near_goal: 0.25,
        near_corners: 1.0,
        radius: 1e6,
    };
    let (_, mesh) = mesh_of(&options(Some(grading)));
    let (_, uniform) = mesh_of(&MeshOptions {
        max_area: Some(0.25 * MAX_AREA),
        ..MeshOptions::default()
    });
    // The bound is 0.25 × max_area to within 1e-5 all over the scene, so the mesh is about
    // as fine as a uniform one at that size (the budget estimate does not explode either).
    let largest = (0..mesh.triangles().len() as u32)
        .map(|t| mesh.triangle_area(t))
        .fold(0.0, f64::max);
    assert!(largest <= 0.25 * MAX_AREA * (1.0 + 1e-4), "{largest}");
    let (g, u) = (mesh.triangles().len(), uniform.triangles().len());
    assert!(
        g as f64 > 0.8 * u as f64 && (g as f64) < 1.5 * u as f64,
        "{g} vs {u}"
    );
}

#[test]
fn bad_grading_options_are_refused() {
    let spec = reference_disc();
    for (grading, name) in [
        ((0.0, 0.5, 1.0), "grading.near_goal"),
        ((f64::NAN, 0.5, 1.0), "grading.near_goal"),
        ((0.5, 1.5, 1.0), "grading.near_corners"),
        ((0.5, 0.5, 0.0), "grading.radius"),
        ((0.5, 0.5, f64::INFINITY), "grading.radius"),
    ] {
        let opts = options(Some(Grading {
            near_goal: grading.0,
            near_corners: grading.1,
            radius: grading.2,
        }));
        match Domain::new(&spec, &opts) {
            Err(MeshError::InvalidOption { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{grading:?}: {other:?}"),
        }
    }
    // A grading needing more triangles than the budget fails at once.
    let opts = MeshOptions {
        max_triangles: 100_000,
        ..options(Some(Grading {
            near_goal: 1e-6,
            near_corners: 1.0,
            radius: 5.0,
        }))
    };
    let domain = Domain::new(&spec, &opts).expect("valid");
    assert!(matches!(
        domain.mesh(&opts),
        Err(MeshError::TooManyTriangles { .. })
    ));
}
