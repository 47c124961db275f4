//! The configuration-space geometry: parry2d's convex-part distances agree with the exact
//! polygon kernels of `harmonic_mesh::geom`, the radius of gyration is the textbook one,
//! the periodic mesh's two ends match face for face, and contacts name their pair of pieces.

use std::collections::HashMap;

use harmonic_cspace::check::exact_clearance;
use harmonic_cspace::{Arm, ConfigGoal, ConfigSpace, ObstacleInput, RigidRobot, Robot, World};
use harmonic_volume::{BoundaryTag, SEAM_PART};

fn world() -> World {
    World::new(
        &[[0.0, 0.0], [6.0, 0.0], [6.0, 5.0], [0.0, 5.0]],
        &obstacles(),
    )
    .expect("valid world")
}

fn obstacles() -> Vec<ObstacleInput> {
    vec![
        ObstacleInput::Polygon(vec![
            [2.0, 1.0],
            [4.0, 1.0],
            [4.0, 3.0],
            [3.5, 3.0],
            [3.5, 1.5],
            [2.5, 1.5],
            [2.5, 3.0],
            [2.0, 3.0],
        ]),
        ObstacleInput::Circle {
            center: [4.8, 4.0],
            radius: 0.4,
        },
    ]
}

/// A small deterministic generator (no dependency for a few numbers).
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

/// [`world`]'s obstacles in an L-shaped room: its two edges at the reflex corner have
/// workspace on both sides of their lines.
fn l_world() -> World {
    World::new(
        &[
            [0.0, 0.0],
            [6.0, 0.0],
            [6.0, 5.0],
            [3.0, 5.0],
            [3.0, 3.2],
            [0.0, 3.2],
        ],
        &obstacles(),
    )
    .expect("valid world")
}

#[test]
fn parry_distances_agree_with_the_exact_kernels() {
    // Convex rooms measure their walls as half-planes, the L's reflex edges as segments.
    parry_distances_agree_in(world(), [1.0, 4.0]);
    parry_distances_agree_in(l_world(), [1.5, 2.0]);
}

fn parry_distances_agree_in(world: World, base: [f64; 2]) {
    let l_shape = [
        [-0.5, -0.2],
        [0.6, -0.2],
        [0.6, 0.0],
        [0.0, 0.0],
        [0.0, 0.4],
        [-0.5, 0.4],
    ];
    let robots = [
        Robot::Rigid(RigidRobot::new(&l_shape).expect("valid")),
        Robot::Arm(Arm::new(base, &[1.2, 0.9, 0.6], 0.08, None).expect("valid")),
        Robot::Arm(Arm::new(base, &[1.2, 0.9], 0.0, None).expect("valid")),
    ];
    let mut rng = Lcg(7);
    for robot in robots {
        let goal = match &robot {
            Robot::Rigid(_) => ConfigGoal::Pose {
                pose: [5.0, 1.0, 0.0],
                position: 0.3,
                angle: 0.3,
            },
            Robot::Arm(_) => ConfigGoal::EndEffector {
                point: [2.0, 4.0],
                tolerance: 0.3,
            },
        };
        let space = ConfigSpace::new(robot.clone(), world.clone(), goal, 0.0, 0.3).expect("valid");
        let mut compared = 0;
        for _ in 0..400 {
            let q: Vec<f64> = match &robot {
                Robot::Rigid(_) => vec![6.0 * rng.next(), 5.0 * rng.next(), 7.0 * rng.next()],
                Robot::Arm(a) => (0..a.links.len()).map(|_| 7.0 * rng.next() - 3.5).collect(),
            };
            let (d, _) = space.clearance(&q);
            let exact = exact_clearance(&robot, space.world(), &q);
            if d > 0.0 {
                assert!((d - exact).abs() < 1e-9, "{q:?}: parry {d}, exact {exact}");
                compared += 1;
            } else {
                assert_eq!(exact, 0.0, "{q:?}: parry {d}");
            }
        }
        assert!(compared > 50);
    }
}

#[test]
fn radius_of_gyration_of_a_rectangle() {
    // A 2a × 2b rectangle about its centre: r² = (a² + b²)/3.
    let (a, b) = (0.9, 0.12);
    let r = RigidRobot::new(&[[-a, -b], [a, -b], [a, b], [-a, b]]).expect("valid");
    assert!((r.radius_of_gyration - ((a * a + b * b) / 3.0).sqrt()).abs() < 1e-12);
    assert!((r.max_radius - a.hypot(b)).abs() < 1e-12);
}

#[test]
fn the_two_ends_of_the_period_match_face_for_face() {
    let robot = Robot::Rigid(
        RigidRobot::new(&[[-0.7, -0.1], [0.7, -0.1], [0.7, 0.1], [-0.7, 0.1]]).expect("valid"),
    );
    let goal = ConfigGoal::Pose {
        pose: [5.2, 0.6, 0.0],
        position: 0.4,
        angle: 0.4,
    };
    let space = ConfigSpace::new(robot, world(), goal, 0.02, 0.25).expect("valid");
    let (mesh, report) = space.mesh(2_000_000).expect("meshes");
    assert_eq!(
        report.cells[2].map(|n| n as f64 * 0.25),
        Some(std::f64::consts::TAU * space.scale()[2])
    );
    // Every end face, its vertices replaced by the ones they are identified with, appears
    // exactly twice: once at θ = 0, once at θ = 2π.
    let mut count: HashMap<[u32; 3], usize> = HashMap::new();
    for f in mesh.slab.boundary_faces() {
        if f.tag == BoundaryTag::Obstacle(SEAM_PART) {
            let mut k = f.vertices.map(|v| mesh.images[v as usize]);
            k.sort_unstable();
            *count.entry(k).or_default() += 1;
        }
    }
    assert!(!count.is_empty());
    assert!(count.values().all(|&c| c == 2), "unmatched end faces");
    assert_eq!(report.seam_faces, 2 * count.len());
    // Three glued copies: three times the real faces, and one end of seam faces at each
    // extremity — the copies' inner ends are glued away.
    let real = mesh.slab.boundary_faces().len() - report.seam_faces;
    assert_eq!(
        mesh.covering.boundary_faces().len(),
        3 * real + report.seam_faces
    );
}

/// A contact names the two convex pieces it is measured between: a bar pushed into the wall
/// below a slot and one pushed into the wall above it are blocked through different pairs
/// (the configurations between them may be free), two bars in the same wall through the
/// same one; workspace edges are numbered before the obstacles' parts.
#[test]
fn contacts_name_the_pair_of_pieces_they_are_measured_between() {
    use harmonic_cspace::{Nearest, Pair};
    let world = World::new(
        &[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
        &[
            ObstacleInput::Polygon(vec![[4.8, 0.0], [5.2, 0.0], [5.2, 4.6], [4.8, 4.6]]),
            ObstacleInput::Polygon(vec![[4.8, 5.4], [5.2, 5.4], [5.2, 10.0], [4.8, 10.0]]),
        ],
    )
    .expect("valid world");
    let bar = RigidRobot::new(&[[-1.0, -0.15], [1.0, -0.15], [1.0, 0.15], [-1.0, 0.15]])
        .expect("valid bar");
    let at = |q: [f64; 3]| world.nearest_pair(&bar.placed(&q), bar.outline(&q)[0]);
    let below = at([5.0, 4.55, 0.0]);
    let above = at([5.0, 5.45, 0.0]);
    let below_too = at([4.5, 4.5, 0.0]);
    assert_eq!((below.0, below.1), (0.0, Nearest::Obstacle(0)));
    assert_eq!((above.0, above.1), (0.0, Nearest::Obstacle(1)));
    assert_eq!(below.2, Pair { robot: 0, world: 4 });
    assert_eq!(above.2, Pair { robot: 0, world: 5 });
    assert_eq!(below_too.2, below.2);
    // In the middle of the slot the bar is free by 0.25 to either wall.
    let middle = at([5.0, 5.0, 0.0]);
    assert!((middle.0 - 0.25).abs() < 1e-12, "{middle:?}");
    // Against the workspace's left edge (the fourth): a pair of its own.
    let left = at([0.9, 2.0, 0.0]);
    assert_eq!(
        (left.0, left.1, left.2),
        (0.0, Nearest::Wall, Pair { robot: 0, world: 3 })
    );
    // The pair does not change the clearance `clearance` reports.
    let q = [5.0, 4.55, 0.0];
    assert_eq!(
        world.clearance(&bar.placed(&q), bar.outline(&q)[0]),
        (below.0, below.1)
    );
}
