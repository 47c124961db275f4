//! Seeded cluttered volumes nobody tuned (`harmonic_fixtures::Clutter3d`): 5–40 balls and
//! boxes in a 10 m box, goal balls of radius 0.1–0.5 m — most smaller than the default
//! lattice's spacing — at the default `max_volume`, a point robot and a ball of radius 0.3.
//! Every start that a conservative voxel flood fill connects to a goal reaches a goal ball,
//! along segments that keep the robot's radius from every solid (sampled, exact distances
//! computed by the fixture, not by the planner). And with two goals, a start beside the small
//! one is led into it.

use harmonic_fixtures::Clutter3d;
use harmonic_planner::AnyScene;
use harmonic_planner::volume::{VolumePlanner, VolumeScene};

fn scene(c: &Clutter3d) -> VolumeScene {
    match AnyScene::from_json(&c.scene_json()) {
        Ok(AnyScene::Volume(s)) => *s,
        other => panic!("a volume scene: {:?}", other.err()),
    }
}

fn in_ball(p: [f64; 3], (c, r): ([f64; 3], f64)) -> bool {
    ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt() <= r + 1e-9
}

#[test]
fn every_connected_start_reaches_a_goal_clear_of_the_solids() {
    for seed in [101u64, 102, 103, 104, 105, 106] {
        let obstacles = [5, 40, 18, 27, 33, 12][(seed - 101) as usize];
        let robot = if seed.is_multiple_of(2) { 0.3 } else { 0.0 };
        let c = Clutter3d::random(
            seed,
            obstacles,
            1 + seed.is_multiple_of(3) as usize,
            8,
            robot,
        );
        let connected = c.connected_starts(0.125);
        let planner = VolumePlanner::new(&scene(&c)).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        let report = planner.plan_report(&c.starts);
        assert_eq!(report.potential.interior_local_minima, 0, "seed {seed}");
        let mut counted = 0;
        for (path, &conn) in report.paths.iter().zip(&connected) {
            if !conn {
                continue;
            }
            counted += 1;
            let tag = format!("seed {seed} from {:?}", path.start);
            assert!(path.status.reached_goal(), "{tag}: {:?}", path.status);
            let end = *path.points.last().expect("points");
            assert!(
                c.goals.iter().any(|&g| in_ball(end, g)),
                "{tag}: ends at {end:?}"
            );
            for w in path.points.windows(2) {
                for k in 0..=20 {
                    let t = k as f64 / 20.0;
                    let p = [0, 1, 2].map(|a| w[0][a] + t * (w[1][a] - w[0][a]));
                    assert!(
                        c.clearance(p) >= robot - 1e-9,
                        "{tag}: {p:?} is {} from a solid",
                        c.clearance(p)
                    );
                }
            }
        }
        assert!(counted >= 4, "seed {seed}: only {counted} connected starts");
    }
}

#[test]
fn a_start_beside_a_small_goal_reaches_it_not_the_far_large_one() {
    for (small, large) in [
        (([2.0, 2.0, 2.0], 0.1), ([8.0, 8.0, 8.0], 0.5)),
        (([7.5, 2.5, 5.0], 0.15), ([2.0, 8.0, 3.0], 0.5)),
    ] {
        let mut c = Clutter3d::random(7, 0, 0, 0, 0.0);
        c.goals = vec![large, small];
        c.starts = vec![
            [small.0[0] + 0.4, small.0[1], small.0[2]],
            [small.0[0], small.0[1] - 0.5, small.0[2] + 0.3],
            [large.0[0] - 1.0, large.0[1], large.0[2]],
        ];
        let planner = VolumePlanner::new(&scene(&c)).expect("plans");
        let report = planner.plan_report(&c.starts);
        for (k, path) in report.paths.iter().enumerate() {
            let want = if k < 2 { 1 } else { 0 };
            assert_eq!(
                path.goal,
                Some(want),
                "from {:?}: {:?}",
                path.start,
                path.status
            );
            let end = *path.points.last().expect("points");
            assert!(in_ball(end, c.goals[want as usize]), "ends at {end:?}");
        }
    }
}
