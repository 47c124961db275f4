//! Configuration-space planning end to end: the bundled polygon and arm scenes reach their
//! goals along motions that are collision-free against the exact polygons (checked at samples
//! no robot point moves more than 1e-3 × the scene size between), a robot that cannot pass
//! is `unreachable`, angles come out continuous across the period, and bad input is refused
//! with its JSON path.

use harmonic_cspace::ConfigClass;
use harmonic_cspace::check::exact_clearance;
use harmonic_planner::PlanError;
use harmonic_planner::cspace::{ConfigPlanner, ConfigScene, parse_config_scene};
use harmonic_planner::{AnyScene, SceneError};

fn load(path: &std::path::Path) -> ConfigScene {
    match AnyScene::from_file(path).expect("scene parses") {
        AnyScene::Config(s) => *s,
        _ => panic!("{} is not a configuration-space scene", path.display()),
    }
}

#[test]
fn bundled_config_scenes_reach_the_goal_collision_free() {
    let scenes = harmonic_fixtures::config_scenes();
    let names: Vec<String> = scenes
        .iter()
        .filter_map(|p| p.file_stem()?.to_str().map(String::from))
        .collect();
    for want in ["arm_aperture", "bar_kim_khosla", "piano"] {
        assert!(names.iter().any(|n| n == want), "{want} bundled: {names:?}");
    }
    for path in scenes {
        let scene = load(&path);
        let planner = ConfigPlanner::new(&scene).expect("plannable");
        assert_eq!(planner.potential().interior_local_extrema(), 0, "{path:?}");
        assert!(!scene.starts.is_empty());
        for start in &scene.starts {
            let p = planner.plan(start);
            assert!(
                p.status.reached_goal(),
                "{path:?} from {start:?}: {:?}",
                p.status
            );
            let configs = p.configurations();
            assert_eq!(&configs[0], start);
            // The last entry is in the goal region (its own function ≤ 0, to the mesh's chord).
            let last = configs.last().expect("entries");
            assert!(
                planner.space().goal_value(last) <= 1e-6,
                "{path:?}: ends outside the goal at {last:?}"
            );
            // Angles continuous: no jump of a wrapped angle between entries.
            for w in configs.windows(2) {
                for (a, b) in w[0].iter().zip(&w[1]) {
                    assert!((a - b).abs() < 1.0, "{path:?}: jump {a} → {b}");
                }
            }
            let clearance = planner.check(&p);
            assert!(
                clearance > 0.0,
                "{path:?}: a motion touches an obstacle (clearance {clearance})"
            );
        }
    }
}

const PIANO: &str = r#"{
    "workspace": [[0, 0], [8, 0], [8, 5], [0, 5]],
    "obstacles": [{"polygon": [[3.8, 0], [4.2, 0], [4.2, DOOR_LO], [3.8, DOOR_LO]]},
                  {"polygon": [[3.8, DOOR_HI], [4.2, DOOR_HI], [4.2, 5], [3.8, 5]]}],
    "robot": {"polygon": [[-0.9, -0.12], [0.9, -0.12], [0.9, 0.12], [-0.9, 0.12]]},
    "goal": {"pose": [6.5, 2.5, 1.5708], "tolerance": {"position": 0.35, "angle": 0.35}},
    "starts": [[1.5, 2.5, 1.5708]],
    "mesh": {"spacing": 0.2, "margin": 0.03}
}"#;

#[test]
fn a_bar_wider_than_the_door_is_unreachable_not_a_collision() {
    // The door is 0.2 wide, the bar 0.24 thick: no configuration passes.
    let text = PIANO.replace("DOOR_LO", "2.4").replace("DOOR_HI", "2.6");
    let scene = parse_config_scene(&text).expect("parses");
    let planner = ConfigPlanner::new(&scene).expect("plannable");
    let p = planner.plan(&[1.5, 2.5, std::f64::consts::FRAC_PI_2]);
    assert_eq!(p.status.as_str(), "unreachable", "{:?}", p.status);
    // A start in collision is reported as such.
    let p = planner.plan(&[4.0, 1.0, 0.0]);
    assert_eq!(p.status.as_str(), "start_in_obstacle");
}

#[test]
fn heading_crosses_the_period_continuously() {
    // Start at θ = 5.9, goal at θ = 0.4: the short way is across 2π; the path's θ must end
    // near 0.4 + 2π, not jump back to 0.4.
    let scene = parse_config_scene(
        r#"{
        "workspace": [[0, 0], [4, 0], [4, 3], [0, 3]],
        "robot": {"polygon": [[-0.5, -0.1], [0.5, -0.1], [0.5, 0.1], [-0.5, 0.1]]},
        "goal": {"pose": [3.0, 1.5, 0.4], "tolerance": {"position": 0.3, "angle": 0.3}},
        "mesh": {"spacing": 0.2, "margin": 0.02}
    }"#,
    )
    .expect("parses");
    let planner = ConfigPlanner::new(&scene).expect("plannable");
    let p = planner.plan(&[1.0, 1.5, 5.9]);
    assert!(p.status.reached_goal(), "{:?}", p.status);
    let poses = p.poses.as_ref().expect("poses");
    let end = poses.last().expect("entries")[2];
    assert!(
        (end - (0.4 + std::f64::consts::TAU)).abs() < 0.35,
        "θ ends at {end}"
    );
    assert!(planner.check(&p) > 0.0);
}

#[test]
fn a_two_link_arm_plans_in_its_joint_plane() {
    let scene = parse_config_scene(
        r#"{
        "workspace": [[-3, -3], [3, -3], [3, 3], [-3, 3]],
        "obstacles": [{"circle": {"center": [1.2, 1.2], "radius": 0.35}}],
        "robot": {"arm": {"base": [0, 0], "links": [1.3, 1.0],
                          "joint_limits": [[-3.14159, 3.14159], [-2.6, 2.6]]}},
        "goal": {"joints": [2.0, -0.5], "tolerance": 0.15},
        "starts": [[0.0, 0.3]],
        "mesh": {"spacing": 0.12, "margin": 0.02}
    }"#,
    )
    .expect("parses");
    let planner = ConfigPlanner::new(&scene).expect("plannable");
    let p = planner.plan(&[0.0, 0.3]);
    assert!(p.status.reached_goal(), "{:?}", p.status);
    let joints = p.joints.as_ref().expect("joints");
    assert!(joints.iter().all(|q| q.len() == 2));
    assert!(planner.check(&p) > 0.0);
}

/// A two-link arm in an empty room touches nothing anywhere: its configuration space is the
/// whole torus, bounded by nothing but the goal. The faces around the point farthest from
/// the goal are held at the walls' value, so the field has no interior extremum and every
/// start (wrapping either way round) reaches the goal, within its tolerance.
#[test]
fn an_arm_that_touches_nothing_anywhere_still_plans() {
    let scene = parse_config_scene(
        r#"{"workspace": [[-5, -5], [5, -5], [5, 5], [-5, 5]],
        "robot": {"arm": {"base": [0, 0], "links": [2.0, 1.0], "width": 0.02}},
        "goal": {"joints": [1.2, 0.0], "tolerance": 0.05},
        "starts": [[0.0, 0.0]]}"#,
    )
    .expect("parses");
    let planner = ConfigPlanner::new(&scene).expect("plannable");
    let starts = [
        vec![0.0, 0.0],
        vec![0.0, 0.3],
        vec![-2.0, 3.0],
        vec![3.0, 1.0],
        vec![-1.9, 3.0],
    ];
    let report = planner.plan_report(&starts);
    assert_eq!(report.potential.interior_local_minima, 0);
    for p in &report.paths {
        assert!(p.status.reached_goal(), "{:?}: {:?}", p.start, p.status);
        let end = p.joints.as_ref().and_then(|j| j.last()).expect("joints");
        let off = |q: f64, g: f64| {
            (q - g + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
        };
        assert!(
            off(end[0], 1.2).abs() <= 0.05 + 1e-9 && off(end[1], 0.0).abs() <= 0.05 + 1e-9,
            "{end:?}"
        );
    }
}

/// Three wrapping joints that can never meet (links 1, 3, 1), in an empty room: nothing
/// bounds the 3-torus, and no slab face lies near the point farthest from the goal. A ball
/// around that point is left out of the mesh and held at the walls' value, so every start
/// flows to the goal (one in the ball led straight out first) and ends within its tolerance.
#[test]
fn a_three_link_arm_that_touches_nothing_anywhere_still_plans() {
    let scene = parse_config_scene(
        r#"{"workspace": [[-10, -10], [10, -10], [10, 10], [-10, 10]],
        "robot": {"arm": {"base": [0, 0], "links": [1.0, 3.0, 1.0], "width": 0.02}},
        "goal": {"joints": [1.2, 0.0, 0.0], "tolerance": 0.1},
        "starts": [[0, 0, 0]], "mesh": {"spacing": 1.0}}"#,
    )
    .expect("parses");
    let planner = ConfigPlanner::new(&scene).expect("plannable");
    let starts = [
        vec![0.0, 0.0, 0.0],
        vec![-2.0, 3.0, 1.0],
        vec![3.0, -1.0, 2.5],
        vec![1.0, 2.0, -3.0],
        // The point farthest from the goal, the anti-goal's centre: led straight out of its
        // ball, then down the field.
        vec![
            1.2 + std::f64::consts::PI,
            std::f64::consts::PI,
            -std::f64::consts::PI,
        ],
    ];
    let report = planner.plan_report(&starts);
    assert_eq!(report.potential.interior_local_minima, 0);
    let off = |q: f64, g: f64| {
        (q - g + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    };
    for p in &report.paths {
        assert!(p.status.reached_goal(), "{:?}: {:?}", p.start, p.status);
        let end = p.joints.as_ref().and_then(|j| j.last()).expect("joints");
        let goal = [1.2, 0.0, 0.0];
        assert!(
            end.iter()
                .zip(goal)
                .all(|(&q, g)| off(q, g).abs() <= 0.1 + 1e-9),
            "{end:?}"
        );
        assert!(planner.check(p) > 0.0);
    }
}

fn error_of(text: &str) -> String {
    match parse_config_scene(text) {
        Err(e) => e.to_string(),
        Ok(scene) => match ConfigPlanner::new(&scene) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("accepted: {text}"),
        },
    }
}

#[test]
fn bad_robots_and_goals_name_their_json_path() {
    let base =
        r#"{"workspace": [[0, 0], [4, 0], [4, 4], [0, 4]], ROBOT, GOAL, "mesh": {"spacing": 0.4}}"#;
    let bar = r#""robot": {"polygon": [[-0.5, -0.1], [0.5, -0.1], [0.5, 0.1], [-0.5, 0.1]]}"#;
    let pose = r#""goal": {"pose": [3, 3, 0], "tolerance": {"position": 0.4, "angle": 0.5}}"#;
    let cases = [
        (
            base.replace(
                "ROBOT",
                r#""robot": {"polygon": [[0, 0], [1, 1], [1, 0], [0, 1]]}"#,
            )
            .replace("GOAL", pose),
            "robot.polygon",
        ),
        (
            base.replace(
                "ROBOT",
                r#""robot": {"arm": {"base": [2, 2], "links": [1, 1, 1, 1]}}"#,
            )
            .replace("GOAL", r#""goal": {"joints": [0, 0, 0, 0]}"#),
            "robot.arm.links",
        ),
        (
            base.replace(
                "ROBOT",
                r#""robot": {"arm": {"base": [2, 2], "links": [1, -1]}}"#,
            )
            .replace("GOAL", r#""goal": {"joints": [0, 0]}"#),
            "robot.arm.links[1]",
        ),
        (
            base.replace("ROBOT", bar)
                .replace("GOAL", r#""goal": {"joints": [0, 0, 0]}"#),
            "goal",
        ),
        (
            base.replace("ROBOT", bar)
                .replace("GOAL", r#""goal": {"pose": [3, 3, 0], "tolerance": 0.3}"#),
            "goal.tolerance",
        ),
        (
            base.replace("ROBOT", bar)
                .replace("GOAL", r#""goal": {"pose": [3, 3]}"#),
            "goal.pose",
        ),
        (
            base.replace(
                "ROBOT",
                r#""robot": {"polygon": [[0, 0], [1, 0], [0, 1]], "radius": 1}"#,
            )
            .replace("GOAL", pose),
            "robot",
        ),
    ];
    for (text, path) in cases {
        let e = error_of(&text);
        assert!(e.starts_with(path), "expected {path}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
}

#[test]
fn an_oversized_lattice_is_refused_before_any_work() {
    let text = PIANO
        .replace("DOOR_LO", "1.9")
        .replace("DOOR_HI", "3.1")
        .replace("\"spacing\": 0.2", "\"spacing\": 0.004");
    let scene = parse_config_scene(&text).expect("parses");
    let t = std::time::Instant::now();
    let e = ConfigPlanner::new(&scene).err().expect("refused");
    assert!(t.elapsed().as_secs_f64() < 1.0);
    assert!(matches!(e, PlanError::Cspace(_)), "{e}");
    let s = e.to_string();
    assert!(
        s.contains("tetrahedra") && s.contains("mesh.spacing") && !s.contains('\n'),
        "{s}"
    );
    let _ = SceneError::Invalid {
        path: String::new(),
        message: String::new(),
    };
}

#[test]
fn an_arm_that_must_fold_through_itself_is_unreachable() {
    // Links 2, 1.5 and 1.2; the elbow held between 2.4 and 2.7 rad keeps the second joint
    // 0.64–1.01 above the first link, so the last link pointing down crosses the first: from
    // q3 = −1 (pointing up) to q3 = 3.55 it must pass pointing down, through link 1.
    let scene = parse_config_scene(
        r#"{
        "workspace": [[-5, -5], [5, -5], [5, 5], [-5, 5]],
        "robot": {"arm": {"base": [0, 0], "links": [2.0, 1.5, 1.2], "width": 0.1,
                          "joint_limits": [[-3.14159, 3.14159], [2.4, 2.7], [-2.0, 3.6]]}},
        "goal": {"joints": [0.0, 2.55, 3.55], "tolerance": 0.05},
        "starts": [[0.0, 2.55, -1.0]]
    }"#,
    )
    .expect("parses");
    let planner = ConfigPlanner::new(&scene).expect("plannable");
    let space = planner.space();
    // Link 3 pointing straight down crosses link 1: a collision with itself.
    let folded = [0.0, 2.55, 3.0 * std::f64::consts::FRAC_PI_2 - 2.55];
    assert_eq!(space.classify(&folded), ConfigClass::Collision);
    assert_eq!(
        exact_clearance(space.robot(), space.world(), &folded),
        0.0,
        "the checker sees the links cross"
    );
    let p = planner.plan(&[0.0, 2.55, -1.0]);
    assert_eq!(p.status.as_str(), "unreachable", "{:?}", p.status);
}

/// A 2 × 0.3 m bar through a 0.8 m slot in a 0.4 m wall, meshed at a spacing fine enough for
/// the passage (0.12: 225 k unknowns). Behind the slot ψ falls to 1e-27, far below what the
/// iterative solves' residual resolves: their fields had 1 718 interior minima and both
/// starts stalled. The far field solved layer by layer has none, and both reach the goal.
#[test]
fn a_bar_through_a_slot_plans_where_psi_falls_far_below_the_residual() {
    let scene = parse_config_scene(
        r#"{"workspace": [[0, 0], [10, 0], [10, 10], [0, 10]],
        "obstacles": [{"polygon": [[4.8, 0], [5.2, 0], [5.2, 4.6], [4.8, 4.6]]},
                      {"polygon": [[4.8, 5.4], [5.2, 5.4], [5.2, 10], [4.8, 10]]}],
        "robot": {"polygon": [[-1.0, -0.15], [1.0, -0.15], [1.0, 0.15], [-1.0, 0.15]]},
        "goal": {"pose": [8.0, 5.0, 0.0], "tolerance": {"position": 0.2, "angle": 0.2}},
        "starts": [[2.0, 5.0, 0.0], [2.0, 3.0, 1.0]], "mesh": {"spacing": 0.12}}"#,
    )
    .expect("parses");
    let planner = ConfigPlanner::new(&scene).expect("plannable");
    let report = planner.plan_report(&scene.starts);
    assert_eq!(report.potential.interior_local_minima, 0);
    for p in &report.paths {
        assert!(p.status.reached_goal(), "{:?}: {:?}", p.start, p.status);
        assert!(planner.check(p) > 0.0);
        let end = p.poses.as_ref().and_then(|q| q.last()).expect("poses");
        assert!((end[0] - 8.0).hypot(end[1] - 5.0) <= 0.2 + 1e-9, "{end:?}");
    }
}

/// A 2 × 0.3 bar through a slot in a 0.4-thick wall, at the default spacing (0.42; nine
/// heading cells): after the 0.05 margin, a 0.8 slot leaves the bar's centre 0.2 of play
/// across it at heading 0 and less when tilted, a 1.0 slot 0.4: passages thinner than the
/// lattice, between two different contacts (the wall above and the wall below). Graded
/// where lattice edges join the two contacts over free space, and with no edge's coupling
/// lost to the clamping, they plan; before, slots of 0.75–0.8 were `unreachable` and the
/// 0.85–1.0 slots' starts stalled in a flat field (ψ = 0 behind the passage; at 0.85
/// because every lattice vertex in the passage was warped onto its walls).
#[test]
fn a_bar_through_a_slot_a_few_times_its_thickness_plans_at_the_default_spacing() {
    for slot in [0.75, 0.8, 0.85, 0.95, 1.0] {
        let (lo, hi) = (5.0 - slot / 2.0, 5.0 + slot / 2.0);
        let scene = parse_config_scene(&format!(
            r#"{{"workspace": [[0, 0], [10, 0], [10, 10], [0, 10]],
            "obstacles": [{{"polygon": [[4.8, 0], [5.2, 0], [5.2, {lo}], [4.8, {lo}]]}},
                          {{"polygon": [[4.8, {hi}], [5.2, {hi}], [5.2, 10], [4.8, 10]]}}],
            "robot": {{"polygon": [[-1.0, -0.15], [1.0, -0.15], [1.0, 0.15], [-1.0, 0.15]]}},
            "goal": {{"pose": [8.0, 5.0, 0.0], "tolerance": {{"position": 0.2, "angle": 0.2}}}},
            "starts": [[2.0, 5.0, 0.0], [2.0, 3.0, 1.0], [1.5, 8.0, 2.5]]}}"#
        ))
        .expect("parses");
        let planner = ConfigPlanner::new(&scene).expect("plannable");
        let report = planner.plan_report(&scene.starts);
        assert_eq!(report.potential.interior_local_minima, 0, "slot {slot}");
        for p in &report.paths {
            assert!(
                p.status.reached_goal(),
                "slot {slot}, {:?}: {:?}",
                p.start,
                p.status
            );
            assert!(planner.check(p) > 0.0, "slot {slot}: a motion collides");
            let end = p.poses.as_ref().and_then(|q| q.last()).expect("poses");
            assert!(
                planner.space().goal_value(&end[..]) <= 1e-6,
                "slot {slot}: ends outside the goal at {end:?}"
            );
        }
    }
}
