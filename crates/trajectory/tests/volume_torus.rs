//! Connolly's toroidal free space in 3D: the cube [0, 10]³ with the box [3, 7]² × [−1, 11]
//! through it, a ball robot, a goal ball. Both tracers reach the goal from the two named
//! starts and from 50 random free starts, and every path segment keeps the robot's clearance
//! from the EXACT solids (analytic distances, not the mesh).

use std::sync::Arc;

use harmonic_fem::BoundaryConditions;
use harmonic_fem::volume::solve_volume_potential_with_report;
use harmonic_trajectory::volume::{ExactVolumeOptions, P1VolumeField, trace_exact_volume};
use harmonic_trajectory::{Locate, Path, SmoothOptions, trace_smooth};
use harmonic_volume::{GoalRegion, MeshOptions, Point, PointClass, SphereSolid, VolumeDomain};

const R: f64 = 0.25;

fn torus() -> VolumeDomain {
    harmonic_fixtures::torus_domain(
        GoalRegion::Sphere(SphereSolid {
            center: Point::new(5.0, 1.5, 5.0),
            radius: 0.8,
        }),
        R,
    )
}

/// Signed distance of a point to the obstacle box (exact, analytic).
fn box_distance(p: &Point) -> f64 {
    let (lo, hi) = ([3.0, 3.0, -1.0], [7.0, 7.0, 11.0]);
    let mut outside = 0.0f64;
    let mut inside = f64::NEG_INFINITY;
    for a in 0..3 {
        let c = (lo[a] + hi[a]) / 2.0;
        let q = (p[a] - c).abs() - (hi[a] - lo[a]) / 2.0;
        outside += q.max(0.0).powi(2);
        inside = inside.max(q.min(0.0));
    }
    outside.sqrt() + inside
}

/// The smallest distance from the segment to the box: the signed distance of a convex set is
/// convex along a line, so golden-section search finds its minimum.
fn segment_box_distance(a: &Point, b: &Point) -> f64 {
    let f = |s: f64| box_distance(&(a + (b - a) * s));
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(x1) < f(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    f(0.5 * (lo + hi)).min(f(0.0)).min(f(1.0))
}

fn check_clearance(path: &Path<Point>, label: &str) {
    for (i, w) in path.points.windows(2).enumerate() {
        let d = segment_box_distance(&w[0], &w[1]);
        assert!(
            d >= R - 1e-9,
            "{label}: segment {i} comes within {d} of the obstacle"
        );
    }
    for p in &path.points {
        for a in 0..3 {
            // The workspace is convex, so checking the segment ends checks the segments.
            assert!(
                p[a] >= R - 1e-9 && p[a] <= 10.0 - R + 1e-9,
                "{label}: {p} leaves the workspace"
            );
        }
    }
}

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn torus_paths_reach_the_goal_and_keep_clear_of_the_exact_solids() {
    let domain = torus();
    let (mesh, report) = domain
        .mesh(&MeshOptions::with_max_volume(0.5f64.powi(3) / 12.0))
        .unwrap();
    println!("mesh: {} tets, {report:?}", mesh.tetrahedra().len());
    let mesh = Arc::new(mesh);
    let (potential, solve, clamped) =
        solve_volume_potential_with_report(Arc::clone(&mesh), &BoundaryConditions::default())
            .unwrap();
    println!(
        "solve: {solve:?}, clamped: {clamped}, extrema {}",
        potential.interior_local_extrema()
    );
    assert_eq!(potential.interior_local_extrema(), 0);
    let goal_radius = report.point_goal_radius;
    let classify = move |p: &Point| match domain.classify(p, goal_radius) {
        PointClass::Free => Locate::Inside(0),
        PointClass::Goal(j) => Locate::Goal(j),
        PointClass::Obstacle(_) => Locate::InObstacle,
        PointClass::OutsideWorkspace => Locate::OutsideWorkspace,
    };
    let field = P1VolumeField::ascending(&mesh, potential.psi())
        .unwrap()
        .with_outside(&classify);
    let exact = ExactVolumeOptions::default();
    let smooth = SmoothOptions::for_scale(10.0);
    // The named starts: one across the hole from the goal, one in a corner.
    let mut starts = vec![Point::new(5.0, 8.5, 5.0), Point::new(1.0, 9.0, 1.0)];
    let mut rng = Lcg(42);
    let check = torus();
    while starts.len() < 52 {
        let p = Point::new(10.0 * rng.next(), 10.0 * rng.next(), 10.0 * rng.next());
        // Free, and clear of the mesher's safety margin.
        if box_distance(&p) > R + 0.3
            && (0..3).all(|a| p[a] > R + 0.05 && p[a] < 10.0 - R - 0.05)
            && check.classify(&p, goal_radius) == PointClass::Free
        {
            starts.push(p);
        }
    }
    let (mut exact_len, mut smooth_len) = (0.0, 0.0);
    for (i, &s) in starts.iter().enumerate() {
        let path = trace_exact_volume(&field, s, &exact);
        assert!(
            path.status.reached_goal(),
            "exact from {s} (start {i}): {:?}",
            path.status
        );
        check_clearance(&path, &format!("exact from start {i}"));
        let path2 = trace_smooth(&field, s, &smooth).unwrap();
        assert!(
            path2.status.reached_goal(),
            "smooth from {s} (start {i}): {:?}",
            path2.status
        );
        check_clearance(&path2, &format!("smooth from start {i}"));
        if i < 2 {
            println!(
                "start {s}: exact {:.3} ({} moves), smooth {:.3} ({} steps)",
                path.length, path.cells_crossed, path2.length, path2.cells_crossed
            );
        }
        exact_len += path.length;
        smooth_len += path2.length;
        // Both descend to the same goal from the same start along similar routes.
        assert!(
            (path.length - path2.length).abs() < 0.2 * path.length + 0.5,
            "start {i}"
        );
    }
    println!(
        "mean lengths: exact {:.3}, smooth {:.3}",
        exact_len / 52.0,
        smooth_len / 52.0
    );
    // Starts in the obstacle and outside the workspace are named.
    assert_eq!(
        trace_exact_volume(&field, Point::new(5.0, 5.0, 5.0), &exact)
            .status
            .as_str(),
        "start_in_obstacle"
    );
    assert_eq!(
        trace_exact_volume(&field, Point::new(11.0, 5.0, 5.0), &exact)
            .status
            .as_str(),
        "outside_workspace"
    );
}
