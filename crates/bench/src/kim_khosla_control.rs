//! Kim & Khosla (1992), §5: their controllers for non-point robots ([`harmonic_control`])
//! run in their settings, on their published panel field and on our FEM potential — the same
//! controller on both fields, so the fields are compared on the same robot.
//!
//! - **The bar robot** (§5.1, setting (50)): start (1.2, 8.5, η = 0), goal (8, 2), δ = 0.2,
//!   around the reconstructed concave obstacle-1 ([`crate::kim_khosla`]). The paper gives
//!   neither the bar's length nor `d_max` and `Δη_max`: we take a 1 m bar, 0.05 m and 0.1 rad.
//!   The FEM field lives in the square [0, 10]² (walls and obstacle φ = 1, a goal disc of
//!   radius 0.2 m at (8, 2) φ = 0).
//! - **The arm** (§5.2, setting (51)): base (−2, 2), end effector from (−2, 8) with the third
//!   link at 10° to (5, 9) through the aperture of the reconstructed obstacle-2
//!   ([`crate::kim_khosla_arm`]), δ = 0.2. No link lengths in the paper: we take 4.5, 4 and
//!   3 m, the elbow bent clockwise, `d_e` = 0.1 m, `Δθ_max` = 0.01 rad. The FEM field lives in
//!   the box [−8, 10] × [−3, 14] (a goal disc of radius 0.2 m at (5, 9)).
//!
//! Every run reports the smallest distance of the whole robot to the exact obstacle polygons
//! along its whole motion (sampled so that no robot point moves more than 1 cm between
//! samples: 1e-3 of the 10 m scene).

use std::time::Instant;

use harmonic_baselines::{PanelField, StagnationSearch};
use harmonic_control::arm::{Elbow, run_arm};
use harmonic_control::bar::run_bar;
use harmonic_control::stagnation::{Turn, fem_stagnation_points};
use harmonic_control::svg::Picture;
use harmonic_control::{
    Arm, ArmParams, BarParams, BarRobot, FemFlow, Flow, NullMotion, Obstacles, RunStatus, Side,
    StagnationGuard,
};
use harmonic_mesh::Point;
use harmonic_planner::{Planner, Scene};
use serde::Serialize;

use crate::kim_khosla::{obstacle_1, setting_50};
use crate::kim_khosla_arm::{OBSTACLE_2_FITTED, field_51, start_goal_51};
use crate::paper::{KIM_KHOSLA_SETTING_50, KIM_KHOSLA_SETTING_51};

/// The reconstruction's inner corner, as fitted to Table 1.
pub const INNER_CORNER: [f64; 2] = [4.0, 6.0];
/// The FEM goal disc's radius in both settings (m).
pub const GOAL_RADIUS: f64 = 0.2;
/// The bar's length (m): our choice.
pub const BAR_LENGTH: f64 = 1.0;
/// The arm's link lengths (m): our choice.
pub const ARM_LINKS: [f64; 3] = [4.5, 4.0, 3.0];
/// The arm's base (setting (51)).
pub const ARM_BASE: [f64; 2] = [-2.0, 2.0];
/// The box the arm's FEM field lives in.
pub const ARM_BOX: [[f64; 2]; 2] = [[-8.0, -3.0], [10.0, 14.0]];
/// The stagnation guard's radius (m).
pub const GUARD_RADIUS: f64 = 0.5;

type Error = Box<dyn std::error::Error + Send + Sync>;

fn box_scene(
    name: &str,
    lo: [f64; 2],
    hi: [f64; 2],
    obstacles: &[Vec<Point>],
    goal: Point,
) -> Result<Scene, Error> {
    let polys: Vec<serde_json::Value> = obstacles
        .iter()
        .map(|o| serde_json::json!({"polygon": o.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>()}))
        .collect();
    let scene = serde_json::json!({
        "name": name,
        "workspace": [lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]],
        "obstacles": polys,
        "goal": {"circle": {"center": [goal.x, goal.y], "radius": GOAL_RADIUS}},
    });
    Ok(Scene::from_json(&scene.to_string())?)
}

/// The point-robot scene of the bar's FEM field (obstacle-1 in [0, 10]²).
pub fn bar_scene() -> Result<Scene, Error> {
    let s = KIM_KHOSLA_SETTING_50;
    box_scene(
        "Kim & Khosla 1992, Fig. 8 (reconstructed)",
        [0.0, 0.0],
        [10.0, 10.0],
        &[obstacle_1(Point::new(INNER_CORNER[0], INNER_CORNER[1]))],
        Point::new(s.goal[0], s.goal[1]),
    )
}

/// The point-robot scene of the arm's FEM field (obstacle-2 in [`ARM_BOX`]).
pub fn arm_scene() -> Result<Scene, Error> {
    let (_, goal) = start_goal_51();
    box_scene(
        "Kim & Khosla 1992, Fig. 10 (reconstructed)",
        ARM_BOX[0],
        ARM_BOX[1],
        &OBSTACLE_2_FITTED.polygons(),
        goal,
    )
}

/// One bar run, as the `bar_robot` example prints it.
#[derive(Clone, Debug, Serialize)]
pub struct BarRunReport {
    /// `"panel"` or `"fem"`.
    pub field: &'static str,
    /// Whether the leading point reached the goal.
    pub reached: bool,
    /// How it ended.
    #[serde(flatten)]
    pub status: RunStatus,
    /// Periods.
    pub steps: usize,
    /// The smallest distance of the whole bar to the obstacle along the whole motion (m).
    pub min_distance: f64,
    /// δ (m).
    pub delta: f64,
    /// The field's stagnation points (panel: eq. 41's search; FEM: discrete saddles).
    pub stagnation_points: Vec<[f64; 2]>,
    /// The closest the leading point came to each stagnation point (m).
    pub closest_approach: Vec<f64>,
    /// The turns the stagnation guard made.
    pub turns: Vec<Turn>,
    /// Periods in the obstacle operation.
    pub obstacle_periods: usize,
    /// Wall-clock time per period (µs), the field's evaluations included.
    pub microseconds_per_period: f64,
    /// Every pose `(x, y, η)`.
    pub poses: Vec<[f64; 3]>,
}

/// A run from the dividing streamline: the start 0.3 m upstream of the panel field's
/// stagnation point nearest the paper's (2.5, 6.5), heading along the flow.
#[derive(Clone, Debug, Serialize)]
pub struct StagnationDemo {
    /// The side the guard was told to take, or `None` for no guard.
    pub side: Option<Side>,
    /// The start pose.
    pub start: [f64; 3],
    /// The run.
    pub run: BarRunReport,
}

/// The bar robot in setting (50) on both fields.
#[derive(Clone, Debug, Serialize)]
pub struct BarRuns {
    /// The bar's length (m).
    pub bar_length: f64,
    /// `d_max` (m).
    pub d_max: f64,
    /// `Δη_max` (rad).
    pub d_eta_max: f64,
    /// The reconstructed obstacle.
    pub obstacle: Vec<[f64; 2]>,
    /// Triangles of the FEM field's mesh.
    pub fem_triangles: usize,
    /// The panel run, then the FEM run.
    pub runs: Vec<BarRunReport>,
    /// Runs from the dividing streamline of the panel field: without a guard, turning left,
    /// turning right.
    pub stagnation_demo: Vec<StagnationDemo>,
}

#[allow(clippy::too_many_arguments)]
fn bar_run(
    field: &'static str,
    flow: &dyn Flow,
    stagnation: &[Point],
    guard: Option<&StagnationGuard>,
    obstacles: &Obstacles,
    start: [f64; 3],
    goal: Point,
    params: &BarParams,
) -> Result<BarRunReport, Error> {
    let robot = BarRobot { length: BAR_LENGTH };
    let t0 = Instant::now();
    let r = run_bar(flow, obstacles, guard, &robot, start, goal, params)?;
    let per_period = t0.elapsed().as_secs_f64() * 1e6 / r.steps.max(1) as f64;
    let closest_approach = stagnation
        .iter()
        .map(|s| {
            r.poses
                .iter()
                .map(|p| (Point::new(p[0], p[1]) - s).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    Ok(BarRunReport {
        field,
        reached: r.reached(),
        status: r.status,
        steps: r.steps,
        min_distance: r.min_distance,
        delta: r.delta,
        stagnation_points: stagnation.iter().map(|p| [p.x, p.y]).collect(),
        closest_approach,
        turns: r.turns,
        obstacle_periods: r.obstacle_periods,
        microseconds_per_period: per_period,
        poses: r.poses,
    })
}

/// The bar controller in setting (50) on the panel field and the FEM field, the guard
/// turning to `side` at stagnation points, with the runs from the dividing streamline; the
/// FEM planner is returned for pictures.
pub fn bar_runs(side: Side) -> Result<(BarRuns, PanelField, Planner), Error> {
    let s = KIM_KHOSLA_SETTING_50;
    let (start, goal) = (
        Point::new(s.start[0], s.start[1]),
        Point::new(s.goal[0], s.goal[1]),
    );
    let polygon = obstacle_1(Point::new(INNER_CORNER[0], INNER_CORNER[1]));
    let obstacles = Obstacles::new(vec![polygon.clone()])?;
    let params = BarParams {
        delta: s.delta,
        ..BarParams::default()
    };
    let start_pose = [start.x, start.y, 0.0];

    let panel = PanelField::published(std::slice::from_ref(&polygon), start, goal, &setting_50())?;
    let panel_points: Vec<Point> = panel
        .stagnation_points(&StagnationSearch::default())
        .iter()
        .map(|p| p.at)
        .collect();
    let guard = StagnationGuard::new(&panel, &panel_points, GUARD_RADIUS, side);
    let panel_run = bar_run(
        "panel",
        &panel,
        &panel_points,
        Some(&guard),
        &obstacles,
        start_pose,
        goal,
        &params,
    )?;

    let planner = Planner::new(&bar_scene()?)?;
    let fem = FemFlow::new(planner.potential());
    let fem_points = fem_stagnation_points(planner.potential(), GUARD_RADIUS);
    let fem_guard = StagnationGuard::new(&fem, &fem_points, GUARD_RADIUS, side);
    let fem_params = BarParams {
        goal_tolerance: GOAL_RADIUS + params.d_max,
        ..params
    };
    let fem_run = bar_run(
        "fem",
        &fem,
        &fem_points,
        Some(&fem_guard),
        &obstacles,
        start_pose,
        goal,
        &fem_params,
    )?;

    // From the dividing streamline, 0.3 m upstream of the stagnation point nearest the
    // paper's, heading along the flow: without a guard, then each side.
    let paper = Point::new(2.5, 6.5);
    let mut stagnation_demo = Vec::new();
    if let Some(k) = (0..guard.saddles.len()).min_by(|&a, &b| {
        (guard.saddles[a].at - paper)
            .norm()
            .total_cmp(&(guard.saddles[b].at - paper).norm())
    }) && let Some(p) = guard.saddles[k].upstream(&panel, 0.3)
        && let Some(v) = Flow::velocity(&panel, p)
    {
        let demo_start = [p.x, p.y, v.y.atan2(v.x)];
        let demo_params = BarParams {
            max_steps: 2000,
            ..params
        };
        for demo_side in [None, Some(Side::Left), Some(Side::Right)] {
            let g =
                demo_side.map(|sd| StagnationGuard::new(&panel, &panel_points, GUARD_RADIUS, sd));
            let run = bar_run(
                "panel",
                &panel,
                &panel_points,
                g.as_ref(),
                &obstacles,
                demo_start,
                goal,
                &demo_params,
            )?;
            stagnation_demo.push(StagnationDemo {
                side: demo_side,
                start: demo_start,
                run,
            });
        }
    }
    let runs = BarRuns {
        bar_length: BAR_LENGTH,
        d_max: params.d_max,
        d_eta_max: params.d_eta_max,
        obstacle: polygon.iter().map(|p| [p.x, p.y]).collect(),
        fem_triangles: planner.mesh().triangles().len(),
        runs: vec![panel_run, fem_run],
        stagnation_demo,
    };
    Ok((runs, panel, planner))
}

/// The picture every run starts from: streamlines of `flow`, the obstacles, the primary
/// control point's trace (dashed).
fn run_picture(
    lo: Point,
    hi: Point,
    width: f64,
    flow: &dyn Flow,
    obstacles: &Obstacles,
    goal: Point,
    trace: &[Point],
) -> Picture {
    let mut pic = Picture::new(lo, hi, width);
    pic.streamlines(flow, 16, goal, GOAL_RADIUS);
    pic.obstacles(obstacles);
    pic.polyline(
        trace,
        r##"fill="none" stroke="#202124" stroke-width="1" stroke-dasharray="3 2""##,
    );
    pic
}

/// The caption of a run's picture.
fn run_caption(
    robot: &str,
    field: &str,
    reached: bool,
    steps: usize,
    min: f64,
    delta: f64,
) -> String {
    let outcome = if reached { "reached" } else { "not reached" };
    format!(
        "{robot}, {field} field: {outcome} in {steps} periods, min distance {min:.3} m (δ = {delta})"
    )
}

/// A bar run drawn: streamlines of `flow`, the obstacle, the bar every few periods, the
/// leading point's trace, the stagnation points (red) and the goal (green).
pub fn bar_svg(run: &BarRunReport, flow: &dyn Flow, obstacle: &[[f64; 2]]) -> String {
    let goal = Point::new(KIM_KHOSLA_SETTING_50.goal[0], KIM_KHOSLA_SETTING_50.goal[1]);
    let robot = BarRobot { length: BAR_LENGTH };
    let obstacles = Obstacles::new(vec![
        obstacle.iter().map(|p| Point::new(p[0], p[1])).collect(),
    ])
    .unwrap_or_default();
    let trace: Vec<Point> = run.poses.iter().map(|p| Point::new(p[0], p[1])).collect();
    let mut pic = run_picture(
        Point::new(0.0, 0.0),
        Point::new(10.0, 10.0),
        560.0,
        flow,
        &obstacles,
        goal,
        &trace,
    );
    let bodies: Vec<Vec<Point>> = run
        .poses
        .iter()
        .map(|&p| {
            let (a, b) = robot.ends(p);
            vec![b, a]
        })
        .collect();
    pic.robot_frames(&bodies, 16);
    for s in &run.stagnation_points {
        pic.cross(Point::new(s[0], s[1]), "#d93025");
    }
    pic.dot(goal, 5.0, "#188038");
    pic.caption(&run_caption(
        "bar robot",
        run.field,
        run.reached,
        run.steps,
        run.min_distance,
        run.delta,
    ));
    pic.finish()
}

/// One arm run, as the `manipulator` example prints it.
#[derive(Clone, Debug, Serialize)]
pub struct ArmRunReport {
    /// `"panel"` or `"fem"`.
    pub field: &'static str,
    /// Whether the end effector reached the goal.
    pub reached: bool,
    /// How it ended.
    #[serde(flatten)]
    pub status: RunStatus,
    /// Periods.
    pub steps: usize,
    /// The smallest distance of every link to every obstacle along the whole motion (m).
    pub min_distance: f64,
    /// The period of the smallest distance.
    pub min_distance_step: usize,
    /// δ (m).
    pub delta: f64,
    /// Periods in the obstacle operation.
    pub obstacle_periods: usize,
    /// Wall-clock time per period (µs).
    pub microseconds_per_period: f64,
    /// Every joint configuration (rad).
    pub joints: Vec<Vec<f64>>,
    /// The end effector at every period.
    pub end_effector: Vec<[f64; 2]>,
}

/// The arm in setting (51) on both fields.
#[derive(Clone, Debug, Serialize)]
pub struct ArmRuns {
    /// The base.
    pub base: [f64; 2],
    /// Link lengths (m).
    pub links: Vec<f64>,
    /// The start joint angles (rad).
    pub start_joints: [f64; 3],
    /// The potential operation's null motion.
    pub null_motion: NullMotion,
    /// `d_e` (m).
    pub d_e: f64,
    /// `Δθ_max` (rad).
    pub d_theta_max: f64,
    /// The reconstructed obstacles.
    pub obstacles: Vec<Vec<[f64; 2]>>,
    /// Triangles of the FEM field's mesh.
    pub fem_triangles: usize,
    /// The panel run, then the FEM run.
    pub runs: Vec<ArmRunReport>,
}

fn arm_run(
    field: &'static str,
    flow: &dyn Flow,
    obstacles: &Obstacles,
    arm: &Arm,
    start: &[f64],
    params: &ArmParams,
) -> Result<ArmRunReport, Error> {
    let (_, goal) = start_goal_51();
    let t0 = Instant::now();
    let r = run_arm(flow, obstacles, arm, start, goal, params)?;
    let per_period = t0.elapsed().as_secs_f64() * 1e6 / r.steps.max(1) as f64;
    Ok(ArmRunReport {
        field,
        reached: r.reached(),
        status: r.status,
        steps: r.steps,
        min_distance: r.min_distance,
        min_distance_step: r.min_distance_step,
        delta: r.delta,
        obstacle_periods: r.obstacle_periods,
        microseconds_per_period: per_period,
        joints: r.joints,
        end_effector: r.end_effector,
    })
}

/// The arm controller in setting (51) with links `links` on the panel field and the FEM
/// field; the FEM planner is returned for pictures.
pub fn arm_runs(
    links: &[f64],
    null_motion: NullMotion,
) -> Result<(ArmRuns, PanelField, Planner), Error> {
    let (tip, _) = start_goal_51();
    let polygons = OBSTACLE_2_FITTED.polygons();
    let obstacles = Obstacles::new(polygons.to_vec())?;
    let arm = Arm::new(Point::new(ARM_BASE[0], ARM_BASE[1]), links.to_vec())?;
    let start = arm
        .three_link_ik(tip, 10f64.to_radians(), Elbow::Down)
        .ok_or("the start (−2, 8) with the third link at 10° is out of the arm's reach")?;
    let params = ArmParams {
        delta: KIM_KHOSLA_SETTING_51.delta,
        null_motion,
        ..ArmParams::default()
    };
    let panel = field_51(&OBSTACLE_2_FITTED)?;
    let panel_run = arm_run("panel", &panel, &obstacles, &arm, &start, &params)?;
    let planner = Planner::new(&arm_scene()?)?;
    let fem = FemFlow::new(planner.potential());
    let fem_params = ArmParams {
        goal_tolerance: GOAL_RADIUS + params.d_e,
        ..params
    };
    let fem_run = arm_run("fem", &fem, &obstacles, &arm, &start, &fem_params)?;
    let runs = ArmRuns {
        base: ARM_BASE,
        links: links.to_vec(),
        start_joints: start,
        null_motion,
        d_e: params.d_e,
        d_theta_max: params.d_theta_max,
        obstacles: polygons
            .iter()
            .map(|o| o.iter().map(|p| [p.x, p.y]).collect())
            .collect(),
        fem_triangles: planner.mesh().triangles().len(),
        runs: vec![panel_run, fem_run],
    };
    Ok((runs, panel, planner))
}

/// An arm run drawn: streamlines, the obstacles, the arm every few periods, the end
/// effector's trace, the base and the goal.
pub fn arm_svg(run: &ArmRunReport, flow: &dyn Flow, runs: &ArmRuns) -> String {
    let (_, goal) = start_goal_51();
    let obstacles = Obstacles::new(
        runs.obstacles
            .iter()
            .map(|o| o.iter().map(|p| Point::new(p[0], p[1])).collect())
            .collect(),
    )
    .unwrap_or_default();
    let base = Point::new(runs.base[0], runs.base[1]);
    let Ok(arm) = Arm::new(base, runs.links.clone()) else {
        return String::new();
    };
    let trace: Vec<Point> = run
        .end_effector
        .iter()
        .map(|p| Point::new(p[0], p[1]))
        .collect();
    let mut pic = run_picture(
        Point::new(-8.0, -1.0),
        Point::new(8.0, 13.0),
        600.0,
        flow,
        &obstacles,
        goal,
        &trace,
    );
    let bodies: Vec<Vec<Point>> = run.joints.iter().map(|q| arm.points(q)).collect();
    pic.robot_frames(&bodies, 12);
    pic.dot(base, 5.0, "#202124");
    pic.dot(goal, 5.0, "#188038");
    pic.caption(&run_caption(
        "3-link arm",
        run.field,
        run.reached,
        run.steps,
        run.min_distance,
        run.delta,
    ));
    pic.finish()
}
